//! Runs section 1b of the stress report (every model family beside Lafortune against its
//! double-double reference) with a given batch count and seed, and prints per family and
//! kernel the largest value and Jacobian errors with where they occur: the regime, the layout,
//! the point `x` with its physical fields, the Jacobian column and the direction pair.
//!
//! ```sh
//! cargo run -p brdf-stress --release --example families_full -- [BATCHES] [SEED] [TOP] [KERNEL]
//! ```
//!
//! `BATCHES` per family (default 3000, the full stress run's: `Sizes::full().batches / 20`),
//! `SEED` as given to `brdf_stress::families::run` (default 7; `stress:N` for the seed the
//! stress command with `--seed N` passes, `derive_seed(N, 4, 0)`), `TOP` located cases per family and kind (default 3), `KERNEL`
//! the kernel whose cases are printed (default: the first available, the widest vector
//! kernel; `all` for every kernel). The value cases are the largest errors over their bound
//! (1e-12 of the value plus the condition term), the Jacobian cases the largest errors
//! relative to their column's scale.

use brdf_stress::families::{TracedError, trace};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let arg = |i: usize, d: u64| args.get(i).map_or(d, |a| a.parse().expect("an integer"));
    // `stress:N`: the seed the stress command with `--seed N` gives section 1b.
    let seed = match args.get(1).and_then(|a| a.strip_prefix("stress:")) {
        Some(n) => brdf_stress::derive_seed(n.parse().expect("an integer"), 4, 0),
        None => arg(1, 7),
    };
    let (batches, top) = (arg(0, 3000) as usize, arg(2, 3) as usize);
    let kernel = args.get(3).cloned();
    let t = std::time::Instant::now();
    let traces = trace(batches, seed, top);
    println!(
        "section 1b: {batches} batches per family, seed {seed} ({:.1} s)\n",
        t.elapsed().as_secs_f64()
    );
    println!(
        "| family | kernel | max value error | value error / bound | max Jacobian error |\n\
         |---|---|---|---|---|"
    );
    for f in &traces {
        let worst = |l: &[TracedError], key: fn(&TracedError) -> f64| {
            l.iter().map(key).fold(0.0f64, f64::max)
        };
        println!(
            "| {} | {} | {:.2e} | {:.3} | {:.2e} |",
            f.family,
            f.kernel,
            f.max_value_error,
            worst(&f.values, |e| e.normalised),
            worst(&f.jacobians, |e| e.error)
        );
    }
    let first = traces.first().map(|f| f.kernel.clone()).unwrap_or_default();
    let wanted = kernel.unwrap_or(first);
    for f in traces
        .iter()
        .filter(|f| wanted == "all" || f.kernel == wanted)
    {
        println!("\n## {} ({})", f.family, f.kernel);
        for (what, list) in [("value", &f.values), ("Jacobian", &f.jacobians)] {
            for e in list.iter() {
                print_case(what, e);
            }
        }
    }
}

fn print_case(what: &str, e: &TracedError) {
    let column = e
        .column
        .as_ref()
        .map_or(String::new(), |c| format!(" column {c}"));
    println!(
        "{what} error {:.3e} ({:.3} of the bound; condition term {:.2e}){column}: batch {} \
         regime {:?} kinds {:?}\n  x = {:?}\n  {}\n  u = {:?}\n  v = {:?}\n  kernel {:e} \
         reference {:e} scale {:e}",
        e.error,
        e.normalised,
        e.condition,
        e.batch,
        e.regime,
        e.kinds,
        e.x,
        e.params,
        e.u,
        e.v,
        e.kernel,
        e.reference,
        e.scale
    );
}
