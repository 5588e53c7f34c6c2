//! Progress of a fit on standard error: an objective that passes every call through to the
//! one it wraps and, at most once a second, prints the lowest full-data RMSE it has seen.
//!
//! The search cannot tell it from the wrapped objective (same values, same random draws), so a
//! fit with progress gives the same result as one without. It sees a full-data RMSE where it
//! is computed: [`Objective::rmse`], a completed [`Objective::rmse_below`], and the residuals
//! of a descent over the full data.

use std::sync::Mutex;
use std::time::{Duration, Instant};

use sls::{Objective, Rows, SearchRng};

/// How a fit shows its progress.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum FitProgress {
    /// Nothing (the default, and the Python package's).
    #[default]
    Quiet,
    /// One line a second.
    Lines,
    /// One line rewritten in place (a terminal), cleared at the end.
    Line,
}

/// What has been seen and when it was last shown.
struct Seen {
    best: f64,
    started: Instant,
    shown: Instant,
}

/// `inner`, printing the lowest RMSE seen each second in the style `mode` says.
pub(crate) struct Watched<'a, O> {
    inner: &'a O,
    mode: FitProgress,
    budget: f64,
    seen: Mutex<Seen>,
}

/// The wrapped workspace and whether the selected rows are the full data.
pub(crate) struct WatchedWork<W> {
    inner: W,
    full: bool,
}

impl<'a, O: Objective> Watched<'a, O> {
    /// Watches `inner` for a fit with a budget of `budget` CPU seconds.
    pub fn new(inner: &'a O, mode: FitProgress, budget: f64) -> Self {
        let now = Instant::now();
        Watched {
            inner,
            mode,
            budget,
            seen: Mutex::new(Seen {
                best: f64::INFINITY,
                started: now,
                shown: now,
            }),
        }
    }

    /// Notes a full-data RMSE, if any; prints when a second has passed since the last line
    /// (checked on every call: a search may spend seconds on subsamples alone).
    fn saw(&self, rmse: Option<f64>) {
        let Ok(mut seen) = self.seen.lock() else {
            return;
        };
        if let Some(rmse) = rmse.filter(|&r| r < seen.best) {
            seen.best = rmse;
        }
        if seen.shown.elapsed() < Duration::from_secs(1) || !seen.best.is_finite() {
            return;
        }
        seen.shown = Instant::now();
        let line = format!(
            "fit: best RMSE so far {:.9} after {:.0} s (budget {} CPU s)",
            seen.best,
            seen.started.elapsed().as_secs_f64(),
            self.budget
        );
        match self.mode {
            FitProgress::Quiet => {}
            FitProgress::Lines => eprintln!("{line}"),
            FitProgress::Line => eprint!("\r{line}\x1b[K"),
        }
    }

    /// Clears the in-place line, if one was drawn.
    pub fn finish(&self) {
        if self.mode == FitProgress::Line {
            eprint!("\r\x1b[K");
        }
    }
}

impl<O: Objective> Objective for Watched<'_, O> {
    type Workspace = WatchedWork<O::Workspace>;

    fn workspace(&self) -> Self::Workspace {
        WatchedWork {
            inner: self.inner.workspace(),
            full: false,
        }
    }
    fn dim(&self) -> usize {
        self.inner.dim()
    }
    fn lower(&self) -> &[f64] {
        self.inner.lower()
    }
    fn upper(&self) -> &[f64] {
        self.inner.upper()
    }
    fn sample_count(&self) -> usize {
        self.inner.sample_count()
    }
    fn random_pick(&self, rng: &mut SearchRng, x: &mut [f64]) {
        self.inner.random_pick(rng, x);
    }
    fn rmse(&self, ws: &mut Self::Workspace, x: &[f64]) -> f64 {
        let rmse = self.inner.rmse(&mut ws.inner, x);
        self.saw(Some(rmse));
        rmse
    }
    fn rmse_below(&self, ws: &mut Self::Workspace, x: &[f64], bound: f64) -> (Option<f64>, usize) {
        let (rmse, rows) = self.inner.rmse_below(&mut ws.inner, x, bound);
        self.saw(rmse);
        (rmse, rows)
    }
    fn select(&self, ws: &mut Self::Workspace, rows: Rows, rng: &mut SearchRng) -> usize {
        let m = self.inner.select(&mut ws.inner, rows, rng);
        ws.full = m == self.inner.sample_count();
        m
    }
    fn residuals(&self, ws: &mut Self::Workspace, x: &[f64], r: &mut [f64]) -> bool {
        let ok = self.inner.residuals(&mut ws.inner, x, r);
        let full = ok && ws.full && !r.is_empty();
        self.saw(full.then(|| (r.iter().map(|v| v * v).sum::<f64>() / r.len() as f64).sqrt()));
        ok
    }
    fn jacobian(&self, ws: &mut Self::Workspace, x: &[f64], jac: &mut [f64]) -> bool {
        let ok = self.inner.jacobian(&mut ws.inner, x, jac);
        self.saw(None);
        ok
    }
    fn natural_value(&self, i: usize, x: f64) -> f64 {
        self.inner.natural_value(i, x)
    }
    fn optimiser_value(&self, i: usize, v: f64) -> f64 {
        self.inner.optimiser_value(i, v)
    }
}
