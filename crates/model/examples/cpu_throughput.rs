//! Per-thread CPU time per lobe-sample of the evaluator (Linux: reads
//! `/proc/thread-self/schedstat`), less sensitive than wall-clock benchmarks to other processes
//! sharing the cores. `cargo run --release -p brdf-model --example cpu_throughput`
//! prints the median over repetitions of ns per lobe-sample for each variant.

use brdf_model::{Evaluator, Kernel, Layout, LobeKind, named_params, synthetic};
use std::hint::black_box;

fn cpu_ns() -> Option<u64> {
    let s = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    s.split_whitespace().next()?.parse().ok()
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    const M: usize = 10_000;
    if cpu_ns().is_none() {
        eprintln!("no /proc/thread-self/schedstat: this example needs Linux");
        return;
    }
    for (lobes, name) in [(1usize, "tuning"), (2, "cross")] {
        let params = named_params(name).unwrap();
        let data = synthetic(&params, M, 0.1, 42);
        let layout = Layout::builder(&vec![LobeKind::Anisotropic; lobes])
            .build()
            .unwrap();
        let x = layout.encode(&params);
        let samples = layout.prepare(&data);
        let mut r = vec![0.0; M];
        let mut jac = vec![0.0; M * layout.dim()];
        let per = (M * lobes) as f64;
        // The thread's CPU clock advances in scheduler ticks (a few ms): time batches of calls
        // long enough (~0.2 s) that the tick is negligible.
        let measure = |f: &mut dyn FnMut()| {
            let start = std::time::Instant::now();
            f();
            let one = start.elapsed().as_secs_f64().max(1e-7);
            let reps = ((0.2 / one) as usize).clamp(1, 1_000_000);
            let mut t = Vec::new();
            for _ in 0..7 {
                let a = cpu_ns().unwrap_or(0);
                for _ in 0..reps {
                    f();
                }
                let b = cpu_ns().unwrap_or(0);
                t.push((b - a) as f64 / (reps as f64 * per));
            }
            median(t)
        };
        let scalar = measure(&mut || {
            for (i, ri) in r.iter_mut().enumerate() {
                *ri = black_box(&params).value(data.u(i), data.v(i)) - data.value(i);
            }
        });
        println!("{lobes} lobe(s) values   scalar-powf: {scalar:6.2} ns/lobe-sample");
        for kernel in Kernel::available()
            .into_iter()
            .rev()
            .filter(|&k| k != Kernel::Scalar)
        {
            let mut ev = Evaluator::with_kernel(&layout, kernel).expect("an available kernel");
            let label = format!("{kernel:?}");
            let v = measure(&mut || {
                black_box(ev.residuals(black_box(&x), &samples, &mut r));
            });
            let j = measure(&mut || {
                ev.forget_powers();
                black_box(ev.residuals_and_jacobian(black_box(&x), &samples, &mut r, &mut jac));
            });
            // A full-data RMSE (the searches' checks), which needs no Jacobian.
            let ss = measure(&mut || {
                black_box(ev.sum_squares(black_box(&x), &samples));
            });
            // What a descent's accepted step asks: values, then the Jacobian at that point.
            let step = measure(&mut || {
                black_box(ev.residuals(black_box(&x), &samples, &mut r));
                black_box(ev.residuals_and_jacobian(black_box(&x), &samples, &mut r, &mut jac));
            });
            println!(
                "{lobes} lobe(s) {label:>8}: values {v:6.2} ns/lobe-sample ({:.1}x scalar), values+jacobian {j:6.2}, values then values+jacobian at the same point {step:6.2}, sum of squares {ss:6.2}",
                scalar / v
            );
        }
    }
}
