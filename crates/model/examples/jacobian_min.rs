//! The Jacobian's cost per lobe-sample for every kernel this CPU can run, as the *minimum* over
//! many short batches: on a shared machine a median still moves by 20% from run to run, while
//! the fastest batch of many is rarely disturbed. Alternating two builds of this example
//! resolved a 9 to 15% change that `cpu_throughput`'s medians could not (docs/performance.md).
//!
//! ```text
//! cargo run --release -p brdf-model --example jacobian_min
//! ```
//!
//! Prints, for one and two anisotropic lobes on 10000 samples (the tuning and cross instances),
//! `jac` (values and Jacobian from scratch) and `step` (values, then values and Jacobian at the
//! same point, reusing the kept powers, as a descent's accepted step does), in wall-clock ns
//! per lobe-sample: the fastest of 40 batches of 20 calls.

use brdf_model::{Evaluator, Kernel, Layout, LobeKind, Samples, named_params, synthetic};
use std::hint::black_box;
use std::io::Write;
use std::time::Instant;

const SAMPLES: usize = 10_000;
const BATCHES: usize = 40;
const CALLS: usize = 20;

/// The fastest of [`BATCHES`] batches of [`CALLS`] calls of `f`, in ns per call and `per`.
fn fastest_batch(per: f64, mut f: impl FnMut()) -> f64 {
    (0..BATCHES)
        .map(|_| {
            let start = Instant::now();
            for _ in 0..CALLS {
                f();
            }
            start.elapsed().as_nanos() as f64 / (CALLS as f64 * per)
        })
        .fold(f64::INFINITY, f64::min)
}

/// Writes one kernel's line for `lobes` lobes.
fn measure(
    out: &mut impl Write,
    kernel: Kernel,
    layout: &Layout,
    x: &[f64],
    data: &Samples,
    lobes: usize,
) -> std::io::Result<()> {
    let mut ev = Evaluator::with_kernel(layout, kernel).expect("an available kernel");
    let mut r = vec![0.0; SAMPLES];
    let mut jac = vec![0.0; SAMPLES * layout.dim()];
    let per = (SAMPLES * lobes) as f64;
    let val_ns = fastest_batch(per, || {
        ev.forget_powers();
        black_box(ev.residuals(black_box(x), data, &mut r));
    });
    let jac_ns = fastest_batch(per, || {
        ev.forget_powers();
        black_box(ev.residuals_and_jacobian(black_box(x), data, &mut r, &mut jac));
    });
    let step_ns = fastest_batch(per, || {
        black_box(ev.residuals(black_box(x), data, &mut r));
        black_box(ev.residuals_and_jacobian(black_box(x), data, &mut r, &mut jac));
    });
    let name = format!("{kernel:?}");
    writeln!(
        out,
        "{lobes} lobe(s) {name:>8}: values {val_ns:6.3}  jac {jac_ns:6.3}  step {step_ns:6.3}"
    )
}

fn main() {
    // A closed pipe (`| head`) ends the output quietly; other write errors are reported.
    if let Err(e) = run(&mut std::io::stdout().lock())
        && e.kind() != std::io::ErrorKind::BrokenPipe
    {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
}

fn run(out: &mut impl Write) -> std::io::Result<()> {
    for (lobes, name) in [(1usize, "tuning"), (2, "cross")] {
        let params = named_params(name).expect("a built-in instance");
        let data = synthetic(&params, SAMPLES, 0.1, 42);
        let layout = Layout::builder(&vec![LobeKind::Anisotropic; lobes])
            .build()
            .expect("a valid layout");
        let x = layout.encode(&params);
        let samples = layout.prepare(&data);
        for kernel in Kernel::available()
            .into_iter()
            .rev()
            .filter(|&k| k != Kernel::Scalar)
        {
            measure(out, kernel, &layout, &x, &samples, lobes)?;
        }
    }
    Ok(())
}
