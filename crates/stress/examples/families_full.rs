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
//! `SEED` as given to `brdf_stress::families::run` (default 7), `TOP` located cases per family
//! and kind (default 3), `KERNEL` the kernel whose cases are printed (default: the first
//! available, the widest vector kernel; `all` for every kernel).

use brdf_stress::families::{TracedError, trace};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let arg = |i: usize, d: u64| args.get(i).map_or(d, |a| a.parse().expect("an integer"));
    let (batches, seed, top) = (arg(0, 3000) as usize, arg(1, 7), arg(2, 3) as usize);
    let kernel = args.get(3).cloned();
    let t = std::time::Instant::now();
    let traces = trace(batches, seed, top);
    println!(
        "section 1b: {batches} batches per family, seed {seed} ({:.1} s)\n",
        t.elapsed().as_secs_f64()
    );
    println!("| family | kernel | max value error | max Jacobian error |\n|---|---|---|---|");
    for f in &traces {
        let v = f.values.first().map_or(0.0, |e| e.error);
        let j = f.jacobians.first().map_or(0.0, |e| e.error);
        println!("| {} | {} | {v:.2e} | {j:.2e} |", f.family, f.kernel);
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
        "{what} error {:.3e}{column}: batch {} regime {:?} kinds {:?}\n  x = {:?}\n  {}\n  \
         u = {:?}\n  v = {:?}\n  kernel {:e} reference {:e} scale {:e}",
        e.error,
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
