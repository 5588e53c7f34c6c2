//! The QR of the scaled Jacobian at the sizes the searches use, three ways in one run: the
//! solver's in-place Householder QR (with the scaled copy of `J` and of `r` it needs),
//! the blocked [`bounded_lm::qr::tall_qr`], and faer's `qr_in_place` with preallocated scratch
//! (plus applying `Q^T` to `r`). 10000 x 7 is RPLS's full-data Jacobian on the tuning instance
//! (one lobe and diffuse), 10000 x 13 two lobes, 25 and 400 rows the subsample descents.
//!
//! `cargo bench -p bounded-lm --bench qr -- --warm-up-time 1 --measurement-time 3`

#[path = "../tests/faer_ref/mod.rs"]
mod faer_ref;

use bounded_lm::qr::{householder_qr, tall_qr, tall_qr_scratch_len};
use criterion::{Criterion, criterion_group, criterion_main};
use std::hint::black_box;

/// What the solver did before `tall_qr`: scaled copy of `J`, copy of `r`, in-place QR, `R` out.
struct InPlace {
    qr: Vec<f64>,
    rq: Vec<f64>,
}

impl InPlace {
    #[allow(clippy::too_many_arguments)]
    fn factor(
        &mut self,
        a: &[f64],
        m: usize,
        p: usize,
        s: &[f64],
        rhs: &[f64],
        r: &mut [f64],
        c: &mut [f64],
    ) {
        for j in 0..p {
            for (q, &v) in self.qr[j * m..(j + 1) * m]
                .iter_mut()
                .zip(&a[j * m..(j + 1) * m])
            {
                *q = v * s[j];
            }
        }
        self.rq.copy_from_slice(rhs);
        householder_qr(&mut self.qr, m, p, &mut self.rq);
        for j in 0..p {
            for i in 0..p {
                r[j * p + i] = if i <= j && i < m {
                    self.qr[j * m + i]
                } else {
                    0.0
                };
            }
            c[j] = self.rq[j];
        }
    }
}

fn bench_qr(c: &mut Criterion) {
    let mut group = c.benchmark_group("qr");
    for (m, p) in [
        (10_000usize, 7usize),
        (10_000, 13),
        (400, 7),
        (25, 7),
        (25, 13),
    ] {
        let a = faer_ref::Rng(1).fill(m * p);
        let rhs = faer_ref::Rng(2).fill(m);
        let scale: Vec<f64> = (0..p).map(|j| 1.0 / (1.0 + j as f64)).collect();
        let (mut r, mut cv) = (vec![0.0; p * p], vec![0.0; p]);
        let mut inplace = InPlace {
            qr: vec![0.0; m * p],
            rq: vec![0.0; m],
        };
        let mut scratch = vec![0.0; tall_qr_scratch_len(p)];
        let mut faer = faer_ref::FaerQr::new(m, p);
        group.bench_function(format!("{m}x{p}/inplace"), |b| {
            b.iter(|| inplace.factor(black_box(&a), m, p, &scale, &rhs, &mut r, &mut cv))
        });
        group.bench_function(format!("{m}x{p}/tall"), |b| {
            b.iter(|| {
                tall_qr(
                    black_box(&a),
                    m,
                    p,
                    &scale,
                    &rhs,
                    &mut r,
                    &mut cv,
                    &mut scratch,
                )
            })
        });
        group.bench_function(format!("{m}x{p}/faer"), |b| {
            b.iter(|| faer.factor(black_box(&a), &scale, &rhs, &mut r, &mut cv))
        });
    }
    group.finish();
}

criterion_group!(benches, bench_qr);
criterion_main!(benches);
