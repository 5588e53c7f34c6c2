//! Throughput of values and values+Jacobian over 10000 samples for 1 and 2 anisotropic lobes
//! (all parameters free). Divide the time per iteration by `10000 * lobes` for ns per
//! lobe-sample (criterion's "elements" are lobe-samples).
//!
//! Variants: `scalar-powf` is a plain loop over `BrdfParams::value` (rotation + `powf`), and
//! for the Jacobian a plain loop with the same formulas using `powf`; then the evaluator with
//! each compiled copy of its loops the CPU supports (`Portable`, `Avx2`, `Avx512`; the
//! evaluator picks the last one by default).
//!
//! Wall-clock numbers are noisy on a shared machine; `examples/cpu_throughput.rs` measures the
//! same loops in thread CPU time.

use brdf_model::{
    BrdfParams, DataSet, Evaluator, Kernel, Layout, LobeKind, named_params, synthetic,
};
use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use std::hint::black_box;

const M: usize = 10_000;

fn scalar_values(p: &BrdfParams, d: &DataSet, r: &mut [f64]) {
    for (i, ri) in r.iter_mut().enumerate() {
        *ri = p.value(d.u(i), d.v(i)) - d.value(i);
    }
}

/// Straightforward scalar value + Jacobian (Raw n, pan in degrees), `powf` per sample.
fn scalar_jacobian(p: &BrdfParams, d: &DataSet, r: &mut [f64], jac: &mut [f64]) {
    let m = d.len();
    for i in 0..m {
        let (u, v) = (d.u(i), d.v(i));
        r[i] = p.kd - d.value(i);
        jac[i] = 1.0;
        for (k, l) in p.lobes.iter().enumerate() {
            let (s, c) = l.pan_deg.to_radians().sin_cos();
            let (ux, uy) = (c * u[0] + s * u[1], -s * u[0] + c * u[1]);
            let (vx, vy) = (c * v[0] + s * v[1], -s * v[0] + c * v[1]);
            let (a, b, z) = (ux * vx, uy * vy, u[2] * v[2]);
            let dd = l.cx * a + l.cy * b + l.cz * z;
            let base = 1 + 5 * k;
            if dd > 0.0 {
                let f = dd.powf(l.n);
                let g = l.n * dd.powf(l.n - 1.0);
                r[i] += f;
                // d/dpan of a and b (per degree).
                let da = (-s * u[0] + c * u[1]) * vx + ux * (-s * v[0] + c * v[1]);
                let db = (-c * u[0] - s * u[1]) * vy + uy * (-c * v[0] - s * v[1]);
                jac[base * m + i] = g * a;
                jac[(base + 1) * m + i] = g * b;
                jac[(base + 2) * m + i] = g * z;
                jac[(base + 3) * m + i] = f * dd.ln();
                jac[(base + 4) * m + i] =
                    g * (l.cx * da + l.cy * db) * std::f64::consts::PI / 180.0;
            } else {
                for q in 0..5 {
                    jac[(base + q) * m + i] = 0.0;
                }
            }
        }
    }
}

fn bench(c: &mut Criterion) {
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

        let mut g = c.benchmark_group(format!("values/{lobes}-lobe"));
        g.throughput(Throughput::Elements((M * lobes) as u64));
        g.bench_function("scalar-powf", |b| {
            b.iter(|| scalar_values(black_box(&params), &data, &mut r))
        });
        for kernel in Kernel::available()
            .into_iter()
            .rev()
            .filter(|&k| k != Kernel::Scalar)
        {
            let mut ev = Evaluator::with_kernel(&layout, kernel).expect("an available kernel");
            g.bench_function(format!("{kernel:?}"), |b| {
                b.iter(|| assert!(ev.residuals(black_box(&x), &samples, &mut r)))
            });
        }
        g.finish();

        let mut g = c.benchmark_group(format!("values+jacobian/{lobes}-lobe"));
        g.throughput(Throughput::Elements((M * lobes) as u64));
        g.bench_function("scalar-powf", |b| {
            b.iter(|| scalar_jacobian(black_box(&params), &data, &mut r, &mut jac))
        });
        for kernel in Kernel::available()
            .into_iter()
            .rev()
            .filter(|&k| k != Kernel::Scalar)
        {
            let mut ev = Evaluator::with_kernel(&layout, kernel).expect("an available kernel");
            g.bench_function(format!("{kernel:?}"), |b| {
                b.iter(|| {
                    assert!(ev.residuals_and_jacobian(black_box(&x), &samples, &mut r, &mut jac))
                })
            });
        }
        g.finish();
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
