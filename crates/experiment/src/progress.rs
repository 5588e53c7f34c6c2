//! Progress reporting: indicatif bars on a terminal, occasional plain lines otherwise.
//!
//! Bars are used when stderr is a terminal and `CI` is not `true`; otherwise one plain line is
//! printed to stderr at most every 10 seconds (and at the end), so logs stay short.

use std::io::{IsTerminal, Write};
use std::sync::Mutex;
use std::time::{Duration, Instant};

use indicatif::{MultiProgress, ProgressBar, ProgressDrawTarget, ProgressStyle};

/// How progress is shown.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ProgressMode {
    /// Bars on a terminal, plain lines otherwise (see the module docs).
    Auto,
    /// Always bars.
    Bars,
    /// Always plain lines.
    Plain,
    /// Nothing.
    Quiet,
}

crate::choice::named_choices!(ProgressMode {
    Auto => "auto",
    Bars => "bars",
    Plain => "plain",
    Quiet => "quiet",
});

impl ProgressMode {
    /// Resolves `Auto` for the current process.
    pub fn resolve(self) -> ProgressMode {
        match self {
            ProgressMode::Auto => {
                let ci = std::env::var("CI").is_ok_and(|v| v == "true" || v == "1");
                if std::io::stderr().is_terminal() && !ci {
                    ProgressMode::Bars
                } else {
                    ProgressMode::Plain
                }
            }
            m => m,
        }
    }
}

struct State {
    done: Vec<u64>,
    ok: Vec<u64>,
    total_done: u64,
    total_ok: u64,
    last_line: Instant,
}

/// Progress of a run: trials done / total, rate, ETA, successes, per configuration.
pub struct Progress {
    mode: ProgressMode,
    labels: Vec<String>,
    totals: Vec<u64>,
    total: u64,
    start_done: u64,
    started: Instant,
    state: Mutex<State>,
    main: Option<ProgressBar>,
    bars: Vec<ProgressBar>,
    _multi: Option<MultiProgress>,
}

/// At most this many per-configuration bars (beyond it only the main bar is shown).
const MAX_BARS: usize = 16;

impl Progress {
    /// Progress over configurations `labels` with `totals[i]` trials each, of which `done[i]`
    /// (with `ok[i]` successes) are already finished.
    pub fn new(
        mode: ProgressMode,
        labels: &[String],
        totals: &[u64],
        done: &[u64],
        ok: &[u64],
    ) -> Self {
        let mode = mode.resolve();
        // Labels come from the spec: escaped before any bar or line shows them.
        let safe_labels: Vec<String> = labels
            .iter()
            .map(|l| crate::terminal::safe(l).into_owned())
            .collect();
        let labels = &safe_labels[..];
        let total: u64 = totals.iter().sum();
        let start_done: u64 = done.iter().sum();
        let total_ok: u64 = ok.iter().sum();
        let mut main = None;
        let mut bars = Vec::new();
        let mut multi = None;
        if mode == ProgressMode::Bars {
            let m = MultiProgress::with_draw_target(ProgressDrawTarget::stderr_with_hz(4));
            let style = ProgressStyle::with_template(
                "[{elapsed_precise}] {bar:30.cyan/blue} {pos}/{len} trials, {per_sec}, ETA {eta} {msg}",
            )
            .unwrap_or_else(|_| ProgressStyle::default_bar())
            .progress_chars("=> ");
            let pb = m.add(ProgressBar::new(total));
            pb.set_style(style);
            pb.set_position(start_done);
            pb.set_message(format!("| {total_ok} reached the target"));
            // Rate and ETA should reflect this session only.
            pb.reset_eta();
            main = Some(pb);
            if labels.len() <= MAX_BARS {
                let width = labels.iter().map(|l| l.len()).max().unwrap_or(8);
                let style = ProgressStyle::with_template(&format!(
                    "  {{prefix:<{width}}} {{bar:20.green/white}} {{pos}}/{{len}} {{msg}}"
                ))
                .unwrap_or_else(|_| ProgressStyle::default_bar())
                .progress_chars("=> ");
                for (i, l) in labels.iter().enumerate() {
                    let b = m.add(ProgressBar::new(totals[i]));
                    b.set_style(style.clone());
                    b.set_prefix(l.clone());
                    b.set_position(done[i]);
                    b.set_message(format!("ok {}", ok[i]));
                    bars.push(b);
                }
            }
            multi = Some(m);
        }
        Progress {
            mode,
            labels: safe_labels.clone(),
            totals: totals.to_vec(),
            total,
            start_done,
            started: Instant::now(),
            state: Mutex::new(State {
                done: done.to_vec(),
                ok: ok.to_vec(),
                total_done: start_done,
                total_ok,
                last_line: Instant::now(),
            }),
            main,
            bars,
            _multi: multi,
        }
    }

    /// Records a finished trial of configuration `config`.
    pub fn trial_done(&self, config: usize, success: bool) {
        let mut s = self.state.lock().unwrap_or_else(|e| e.into_inner());
        s.done[config] += 1;
        s.ok[config] += u64::from(success);
        s.total_done += 1;
        s.total_ok += u64::from(success);
        match self.mode {
            ProgressMode::Bars => {
                if let Some(m) = &self.main {
                    m.inc(1);
                    m.set_message(format!("| {} reached the target", s.total_ok));
                }
                if let Some(b) = self.bars.get(config) {
                    b.inc(1);
                    b.set_message(format!("ok {}", s.ok[config]));
                }
            }
            ProgressMode::Plain
                if s.last_line.elapsed() >= Duration::from_secs(10)
                    || s.total_done == self.total =>
            {
                s.last_line = Instant::now();
                // A closed stderr must not stop the run: progress is only a courtesy.
                let _ = writeln!(std::io::stderr().lock(), "{}", self.line(&s));
            }
            _ => {}
        }
    }

    fn line(&self, s: &State) -> String {
        let el = self.started.elapsed().as_secs_f64();
        let new = s.total_done - self.start_done;
        let rate = if el > 0.0 { new as f64 / el } else { 0.0 };
        let eta = if rate > 0.0 {
            format!(
                ", ETA {}",
                crate::duration::human_seconds((self.total - s.total_done) as f64 / rate)
            )
        } else {
            String::new()
        };
        let per: Vec<String> = self
            .labels
            .iter()
            .enumerate()
            .map(|(i, l)| format!("{l} {}/{} ok {}", s.done[i], self.totals[i], s.ok[i]))
            .collect();
        format!(
            "[{}] {}/{} trials ({rate:.2}/s{eta}), {} reached the target | {}",
            crate::duration::human_seconds(el),
            s.total_done,
            self.total,
            s.total_ok,
            per.join("; ")
        )
    }

    /// Ends the display.
    pub fn finish(&self) {
        for b in &self.bars {
            b.finish();
        }
        if let Some(m) = &self.main {
            m.finish();
        }
    }
}
