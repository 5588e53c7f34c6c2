//! The shape parameters' coordinate, measured: for a model family, synthetic instances made from
//! converted published fits, AED and RPLS in the family's log coordinate and in raw units, with
//! success counts and median sample-evaluations to a target 1% above the best RMSE found.
//!
//! ```text
//! cargo run --release -p sls --example family_coords -- FAMILY [--seeds 30] [--cutoff 1.5]
//!     [--materials a,b,c] [--algorithms aed,rpls] [--instance-seed 1] [--samples 10000]
//! ```
//!
//! `FAMILY` is `cook-torrance` (Ngan's Cook-Torrance fits, `NganCookTorrance::to_params`),
//! `blinn-phong` (Ngan's Blinn-Phong fits, `NganBlinnPhong::to_params`) or `ggx` (Ngan's
//! Cook-Torrance fits as GGX lobes of the same width, `NganCookTorrance::to_ggx_params`), green
//! channel, one isotropic lobe. Each material gives one instance: `--samples` direction pairs
//! uniform by solid angle, noise sigma 1% of the mean noiseless value (`synthetic`, seed
//! `--instance-seed`). The best RMSE is the smaller of the full-data descents from the true
//! parameters in the two coordinates; the target is 1.01 times it. Each algorithm runs `--seeds`
//! seeded trials (seeds 1..=N, one thread, CPU cutoff `--cutoff` seconds) in each coordinate:
//! `log` is the family's default ([`brdf_model::ExponentCoord::Log1p`]: `ln m` for a roughness,
//! `ln(1 + p)` for an exponent), `raw` the parameter itself; random starts are uniform in the
//! coordinate the search sees (`StartDist::Coordinate`), so `raw` also means uniform starts.
//! Censored trials count as +inf in the medians. The machine's load changes CPU times, not
//! sample-evaluations: compare those and the success counts. The last column is the two-sided
//! p-value of a Mann-Whitney U test of the two coordinates' sample-evaluations (censored trials
//! ranked last); the summary counts the materials on which each coordinate's median is lower.

use brdf_io::Channel;
use brdf_model::{DataSet, ExponentCoord, Layout, LobeKind, Params, family, synthetic};
use brdf_published::{NganBlinnPhong, NganCookTorrance, read_fits};
use sls::{
    AlgorithmConfig, BrdfObjective, Budget, DescentLimits, Rows, Search, TrialContext, run_trial,
};
use std::path::PathBuf;
use std::sync::Arc;

struct Args {
    family: String,
    seeds: u64,
    cutoff: f64,
    materials: Vec<String>,
    algorithms: Vec<String>,
    instance_seed: u64,
    samples: usize,
}

/// The materials at the 10th, 30th, 50th, 70th and 90th percentiles of the roughness of Ngan's
/// 86 Cook-Torrance fits (`m` = 0.00718, 0.0157, 0.0782, 0.214, 0.442; their Blinn-Phong
/// exponents are 31700, 20000, 215, 36.8 and 25.2).
const MATERIALS: [&str; 5] = [
    "chrome-steel",
    "red-specular-plastic",
    "purple-paint",
    "gold-paint",
    "red-fabric",
];

fn parse() -> Result<Args, String> {
    let mut it = std::env::args().skip(1);
    let family = it
        .next()
        .ok_or("usage: family_coords FAMILY [--seeds N] ...")?;
    let mut a = Args {
        family,
        seeds: 30,
        cutoff: 1.5,
        materials: MATERIALS.iter().map(|s| s.to_string()).collect(),
        algorithms: vec!["aed".into(), "rpls".into()],
        instance_seed: 1,
        samples: 10_000,
    };
    while let Some(flag) = it.next() {
        let value = it.next().ok_or(format!("{flag} needs a value"))?;
        let bad = |e: &dyn std::fmt::Display| format!("{flag} {value}: {e}");
        match flag.as_str() {
            "--seeds" => a.seeds = value.parse().map_err(|e| bad(&e))?,
            "--cutoff" => a.cutoff = value.parse().map_err(|e| bad(&e))?,
            "--instance-seed" => a.instance_seed = value.parse().map_err(|e| bad(&e))?,
            "--samples" => a.samples = value.parse().map_err(|e| bad(&e))?,
            "--materials" => a.materials = value.split(',').map(String::from).collect(),
            "--algorithms" => a.algorithms = value.split(',').map(String::from).collect(),
            _ => return Err(format!("unknown flag {flag}")),
        }
    }
    Ok(a)
}

/// The true parameters of `material` for `family`, from the published fits.
fn truth(family_name: &str, material: &str) -> Result<Params, String> {
    let dir =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../experiments/data/published-fits");
    let file = |name: &str| read_fits(dir.join(name)).map_err(|e| e.to_string());
    let missing = || format!("no material {material}");
    let g = Channel::Green;
    match family_name {
        "cook-torrance" | "ggx" => {
            let f = file("ngan_cooktorrance.fit")?;
            let fit = f.get(material).ok_or_else(missing)?;
            let ct = NganCookTorrance::from_fit(fit).map_err(|e| e.to_string())?;
            Ok(if family_name == "ggx" {
                ct.to_ggx_params(g)
            } else {
                ct.to_params(g)
            })
        }
        "blinn-phong" => {
            let f = file("ngan_blinnphong.fit")?;
            let fit = f.get(material).ok_or_else(missing)?;
            let bp = NganBlinnPhong::from_fit(fit).map_err(|e| e.to_string())?;
            Ok(bp.to_params(g))
        }
        other => Err(format!(
            "family {other}: expected cook-torrance, blinn-phong or ggx"
        )),
    }
}

/// The shape parameter's value in `p` (the second field of the lobe: `m`, `p` or `alpha`).
fn shape(p: &Params) -> f64 {
    p.lobe(0)[1]
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        (v[n / 2 - 1] + v[n / 2]) / 2.0
    }
}

/// The two-sided p-value of the Mann-Whitney U test that `a` and `b` come from the same
/// distribution (normal approximation with the tie correction and a continuity correction;
/// censored trials are +inf, tied with each other and above every finished trial).
fn mann_whitney(a: &[f64], b: &[f64]) -> f64 {
    let (n1, n2) = (a.len() as f64, b.len() as f64);
    let mut all: Vec<(f64, bool)> = a.iter().map(|&v| (v, true)).collect();
    all.extend(b.iter().map(|&v| (v, false)));
    all.sort_by(|x, y| x.0.total_cmp(&y.0));
    let n = all.len();
    let (mut rank_a, mut ties, mut i) = (0.0, 0.0, 0);
    while i < n {
        let mut j = i;
        while j + 1 < n && all[j + 1].0 == all[i].0 {
            j += 1;
        }
        let t = (j - i + 1) as f64;
        let mid = (i + j) as f64 / 2.0 + 1.0;
        rank_a += mid * all[i..=j].iter().filter(|x| x.1).count() as f64;
        ties += t * t * t - t;
        i = j + 1;
    }
    let nf = n as f64;
    let u = rank_a - n1 * (n1 + 1.0) / 2.0;
    let var = n1 * n2 / 12.0 * ((nf + 1.0) - ties / (nf * (nf - 1.0)));
    if var <= 0.0 {
        return 1.0;
    }
    let z = ((u - n1 * n2 / 2.0).abs() - 0.5).max(0.0) / var.sqrt();
    erfc(z / std::f64::consts::SQRT_2)
}

/// The complementary error function for `x >= 0` (Numerical Recipes' `erfcc`, relative error
/// below 1.2e-7: plenty for a p-value).
fn erfc(x: f64) -> f64 {
    let t = 1.0 / (1.0 + 0.5 * x);
    let c = [
        -1.265_512_23,
        1.000_023_68,
        0.374_091_96,
        0.096_784_18,
        -0.186_288_06,
        0.278_868_07,
        -1.135_203_98,
        1.488_515_87,
        -0.822_152_23,
        0.170_872_77,
    ];
    let poly = c.iter().rev().fold(0.0, |acc, &k| acc * t + k);
    t * (-x * x + poly).exp()
}

fn fmt(v: f64, scale: f64) -> String {
    if v.is_finite() {
        format!("{:.0}", v * scale)
    } else {
        "censored".into()
    }
}

/// RMSE after a full-data descent from the true parameters, in coordinate `coord`.
fn polished(objective: &BrdfObjective, truth: &Params) -> f64 {
    let mut x = objective.layout().encode(truth.clone());
    let mut ctx = TrialContext::new(objective, 0, Budget::default(), 0.0);
    let _ = ctx.descend(&mut x, Rows::Full, DescentLimits::default());
    ctx.evaluate(&x).unwrap_or(f64::INFINITY)
}

fn main() {
    let args = match parse() {
        Ok(a) => a,
        Err(e) => {
            eprintln!("{e}");
            std::process::exit(2);
        }
    };
    let fam = match family(&args.family) {
        Ok(f) => f,
        Err(e) => {
            eprintln!("{e}");
            std::process::exit(2);
        }
    };
    let budget = Budget {
        cpu_seconds: Some(args.cutoff),
        sample_evaluations: None,
    };
    let coords = [("log", ExponentCoord::Log1p), ("raw", ExponentCoord::Raw)];
    println!(
        "family {}, {} samples, sigma 1% of the mean value, instance seed {}, {} seeds, cutoff {} CPU s",
        fam.name(),
        args.samples,
        args.instance_seed,
        args.seeds,
        args.cutoff
    );
    println!(
        "\n| material | shape | best RMSE | algorithm | coordinate | reached | median evals | median CPU ms | best RMSE of the trials | p (log vs raw) |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|");
    let mut totals: Vec<(String, &str, u64, Vec<f64>)> = Vec::new();
    // Per algorithm: materials where log's median evaluations are lower, higher.
    let mut wins: Vec<(String, usize, usize)> = Vec::new();
    for material in &args.materials {
        let truth = match truth(fam.name(), material) {
            Ok(t) => t,
            Err(e) => {
                eprintln!("{e}");
                std::process::exit(2);
            }
        };
        let clean = synthetic(&truth, args.samples, 0.0, args.instance_seed);
        let mean = clean.values().iter().sum::<f64>() / clean.len() as f64;
        let data: Arc<DataSet> = Arc::new(synthetic(
            &truth,
            args.samples,
            0.01 * mean,
            args.instance_seed,
        ));
        let objectives: Vec<BrdfObjective> = coords
            .iter()
            .map(|&(_, c)| {
                let layout = Layout::builder_for(&fam, &[LobeKind::Isotropic])
                    .and_then(|b| b.exponent_coord(c).build())
                    .expect("an isotropic layout");
                BrdfObjective::new(data.clone(), layout)
            })
            .collect();
        let best = objectives
            .iter()
            .map(|o| polished(o, &truth))
            .fold(f64::INFINITY, f64::min);
        let target = 1.01 * best;
        for alg in &args.algorithms {
            let Some(config) = AlgorithmConfig::default_for(alg) else {
                eprintln!("unknown algorithm {alg}");
                std::process::exit(2);
            };
            let mut runs: Vec<Vec<f64>> = Vec::new();
            for ((name, _), objective) in coords.iter().zip(&objectives) {
                let (mut evals, mut cpu, mut reached) = (Vec::new(), Vec::new(), 0);
                let mut found = f64::INFINITY;
                for seed in 1..=args.seeds {
                    let r = run_trial(objective, &config, seed, budget, target);
                    found = found.min(r.best_rmse);
                    match r.reached_at {
                        Some(at) => {
                            reached += 1;
                            evals.push(at.evaluations.total() as f64);
                            cpu.push(at.cpu_seconds);
                        }
                        None => {
                            evals.push(f64::INFINITY);
                            cpu.push(f64::INFINITY);
                        }
                    }
                }
                let p = match runs.first() {
                    Some(log) => format!("{:.3}", mann_whitney(log, &evals)),
                    None => "-".into(),
                };
                println!(
                    "| {material} | {:.4} | {best:.6} | {alg} | {name} | {reached}/{} | {} | {} | {found:.6} | {p} |",
                    shape(&truth),
                    args.seeds,
                    fmt(median(evals.clone()), 1.0),
                    fmt(median(cpu), 1e3),
                );
                runs.push(evals.clone());
                match totals.iter_mut().find(|t| t.0 == *alg && t.1 == *name) {
                    Some(t) => {
                        t.2 += reached;
                        t.3.extend(evals);
                    }
                    None => totals.push((alg.clone(), name, reached, evals)),
                }
            }
            let (log, raw) = (median(runs[0].clone()), median(runs[1].clone()));
            let w = match wins.iter_mut().find(|w| w.0 == *alg) {
                Some(w) => w,
                None => {
                    wins.push((alg.clone(), 0, 0));
                    wins.last_mut().expect("just pushed")
                }
            };
            w.1 += usize::from(log < raw);
            w.2 += usize::from(raw < log);
        }
    }
    println!(
        "\n| algorithm | coordinate | reached (all materials) | median evals (all trials) | materials with fewer median evals |"
    );
    println!("|---|---|---|---|---|");
    for (alg, name, reached, evals) in totals {
        let n = evals.len();
        let w = wins
            .iter()
            .find(|w| w.0 == alg)
            .map_or(0, |w| if name == "log" { w.1 } else { w.2 });
        println!(
            "| {alg} | {name} | {reached}/{n} | {} | {w} of {} |",
            fmt(median(evals), 1.0),
            args.materials.len()
        );
    }
}
