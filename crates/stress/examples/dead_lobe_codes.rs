//! Codes of bounded-lm's presets on 25-sample subsamples of the tuning instance, looking for
//! success codes (3 to 5) on a dead lobe (issue 45.16, docs/solver.md):
//! `cargo run -p brdf-stress --release --example dead_lobe_codes -- SEEDS SUBSAMPLES`.
//!
//! For each data seed (the 10,000-sample noiseless tuning instance drawn with it) it draws
//! SUBSAMPLES subsamples and starts, solves each with the default, `n2fb()`, `search()`, the
//! default without the dead-column hold and `n2fb().for_search()`, and prints a `RESTART` line
//! for every default or `n2fb()` end with a success code and a numerically dead column: the
//! presets restarted from that point, and `J^T r` there (a dead lobe whose gradient is not
//! exactly 0 could still be revived, so its success code is premature). Environment: `ISO=1`
//! isotropic lobes, `LOBES=K`, `RAW=1` raw exponent coordinate, `UNIFORM=1` starts uniform in
//! the box (else mid-box jittered by `JITTER`, default 0.05 of each width, as the stress
//! suite's), `SIGMA` noise, `M` subsample size (25), `ALL=1` every case.
use bounded_lm::{Options, Problem, Report, SolveError, Solver};
use brdf_model::{DataSet, Evaluator, Layout, LobeKind, Samples, named_params, synthetic};
use brdf_stress::diagnose::BrdfFit;
use rand::{RngExt, SeedableRng};
use rand_pcg::Pcg64;

/// One solve of the fit of `la` to `samples` from `x` (left at the end point) with `o`.
fn solve(la: &Layout, samples: &Samples, x: &mut [f64], o: &Options) -> Result<Report, SolveError> {
    let mut ev = Evaluator::new(la);
    let mut fit = BrdfFit {
        ev: &mut ev,
        data: samples,
    };
    Solver::new().solve(&mut fit, x, la.lower(), la.upper(), o)
}

/// An argument or variable that does not parse ends the probe with its usage (exit 2).
fn parsed<T: std::str::FromStr>(what: &str, text: &str) -> T {
    text.parse().unwrap_or_else(|_| {
        eprintln!("{what} = {text:?} does not parse; usage: dead_lobe_codes [SEEDS [SUBSAMPLES]]");
        std::process::exit(2)
    })
}

fn main() {
    let args: Vec<u64> = std::env::args()
        .skip(1)
        .map(|a| parsed("argument", &a))
        .collect();
    let (seeds, subs) = (
        args.first().copied().unwrap_or(10),
        args.get(1).copied().unwrap_or(10),
    );
    let tuning = named_params("tuning").expect("a built-in parameter set");
    let env = |k: &str| std::env::var(k).ok();
    let kind = if env("ISO").is_some() {
        LobeKind::Isotropic
    } else {
        LobeKind::Anisotropic
    };
    let lobes = env("LOBES").map_or(1, |v| parsed("LOBES", &v));
    let mut b = Layout::builder(&vec![kind; lobes]);
    if env("RAW").is_some() {
        b = b.exponent_coord(brdf_model::ExponentCoord::Raw);
    }
    let la = b.build().unwrap_or_else(|e| {
        eprintln!("LOBES = {lobes}: {e}");
        std::process::exit(2)
    });
    let jitter: f64 = env("JITTER").map_or(0.05, |v| parsed("JITTER", &v));
    let sigma: f64 = env("SIGMA").map_or(0.0, |v| parsed("SIGMA", &v));
    let uniform = env("UNIFORM").is_some();
    let m: usize = env("M").map_or(25, |v| parsed("M", &v));
    println!(
        "names {:?} lo {:?} hi {:?}",
        la.free_names(),
        la.lower(),
        la.upper()
    );
    let mut presets: Vec<(&str, Options)> = vec![
        ("default", Options::default()),
        ("n2fb", Options::n2fb()),
        ("search", Options::search()),
    ];
    let mut nohold = Options::default();
    nohold.safeguards.hold_dead_columns = false;
    presets.push(("nohold", nohold));
    let mut n2fb_search = Options::n2fb().for_search();
    n2fb_search.limits = Options::default().limits;
    presets.push(("n2fb-search", n2fb_search));
    for seed in 0..seeds {
        let full = synthetic(&tuning, 10000, sigma, seed);
        let mut rng = Pcg64::seed_from_u64(seed);
        let mut sampler = brdf_model::Subsampler::new(full.len());
        let mut sub = DataSet::new();
        for k in 0..subs {
            let rows = sampler.draw(m, &mut rng).to_vec();
            full.gather_into(&rows, &mut sub);
            let start: Vec<f64> = la
                .lower()
                .iter()
                .zip(la.upper())
                .map(|(&l, &h)| {
                    if uniform {
                        l + (h - l) * rng.random::<f64>()
                    } else {
                        0.5 * (l + h) + jitter * (h - l) * (2.0 * rng.random::<f64>() - 1.0)
                    }
                })
                .collect();
            let samples = la.prepare(&sub);
            let mut res = Vec::new();
            for (name, o) in &presets {
                let mut x = start.clone();
                let rep = solve(&la, &samples, &mut x, o);
                let (mm, pp) = (samples.len(), la.dim());
                let mut jac = vec![0.0; mm * pp];
                let mut ev = Evaluator::new(&la);
                let mut fit = BrdfFit {
                    ev: &mut ev,
                    data: &samples,
                };
                let ok = fit.jacobian(&x, &mut jac);
                let norms: Vec<f64> = (0..pp)
                    .map(|j| {
                        jac[j * mm..(j + 1) * mm]
                            .iter()
                            .fold(0.0f64, |a, v| a.max(v.abs()))
                    })
                    .collect();
                let mx = norms.iter().cloned().fold(0.0, f64::max);
                let dead = ok && norms.iter().any(|&n| n <= f64::EPSILON * mx);
                match rep {
                    Ok(r) => res.push((*name, r.outcome.code(), r.f, r.iterations, x, dead)),
                    Err(e) => println!("{seed} {k} {name} err {e}"),
                }
            }
            for r in res
                .iter()
                .filter(|r| (r.0 == "default" || r.0 == "n2fb") && (3..=5).contains(&r.1) && r.5)
            {
                let mut line = format!(
                    "RESTART seed {seed} sub {k} {} code {} f {:.6e}:",
                    r.0, r.1, r.2
                );
                for (name, o) in &presets {
                    let mut x = r.4.clone();
                    if let Ok(rep) = solve(&la, &samples, &mut x, o) {
                        line += &format!(" {name} {} {:.6e}", rep.outcome.code(), rep.f);
                    }
                }
                // True gradient of each coordinate at the end point.
                let (mm, pp) = (samples.len(), la.dim());
                let mut jac = vec![0.0; mm * pp];
                let mut rr = vec![0.0; mm];
                let mut ev = Evaluator::new(&la);
                let mut fit = BrdfFit {
                    ev: &mut ev,
                    data: &samples,
                };
                fit.residuals(&r.4, &mut rr);
                fit.jacobian(&r.4, &mut jac);
                let g: Vec<String> = (0..pp)
                    .map(|j| {
                        format!(
                            "{:.1e}",
                            jac[j * mm..(j + 1) * mm]
                                .iter()
                                .zip(&rr)
                                .map(|(a, b)| a * b)
                                .sum::<f64>()
                        )
                    })
                    .collect();
                line += &format!(" g {:?}", g);
                println!("{line}");
            }
            let best = res.iter().map(|r| r.2).fold(f64::INFINITY, f64::min);
            let flag = res.iter().any(|r| {
                (r.0 == "default" || r.0 == "n2fb")
                    && (3..=5).contains(&r.1)
                    && r.5
                    && r.2 > best * 1.01 + 1e-20
            });
            if flag || std::env::var("ALL").is_ok() {
                println!(
                    "seed {seed} sub {k}{}",
                    if flag { "  <== premature" } else { "" }
                );
                println!("  start {:?}", start);
                for r in &res {
                    println!(
                        "  {:12} code {:2} f {:.6e} it {:3} dead {} x {:?}",
                        r.0, r.1, r.2, r.3, r.5, r.4
                    );
                }
            }
        }
    }
}
