//! CPU time of the three QRs of `benches/qr.rs`, interleaved in one run (round-robin repetitions,
//! thread CPU time, medians): robust to a machine shared with other builds, where criterion's
//! wall-clock times are not.
//!
//! `cargo run --release -p bounded-lm --example qr_timing -- [--reps 200]`

#[path = "../tests/faer_ref/mod.rs"]
mod faer_ref;

use bounded_lm::qr::{householder_qr, tall_qr, tall_qr_scratch_len};
use cpu_time::ThreadTime;
use std::hint::black_box;

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let reps: usize = args
        .iter()
        .position(|a| a == "--reps")
        .map_or(200, |i| args[i + 1].parse().expect("--reps N"));
    println!("| rows x cols | in-place us | tall us | faer us | in-place / tall | faer / tall |");
    println!("|---|---|---|---|---|---|");
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
        let (mut r, mut c) = (vec![0.0; p * p], vec![0.0; p]);
        let (mut qr, mut rq) = (vec![0.0; m * p], vec![0.0; m]);
        let mut scratch = vec![0.0; tall_qr_scratch_len(p)];
        let mut faer = faer_ref::FaerQr::new(m, p);
        // Enough calls per timing that one takes about 100 us of CPU or more.
        let inner = (200_000 / (m * p)).max(1);
        let mut times = [vec![], vec![], vec![]];
        for _ in 0..reps {
            for (v, t) in times.iter_mut().enumerate() {
                let start = ThreadTime::now();
                for _ in 0..inner {
                    match v {
                        0 => {
                            // The solver's small-problem path: scaled copy, QR in place, R out.
                            for j in 0..p {
                                for (q, &x) in qr[j * m..(j + 1) * m].iter_mut().zip(&a[j * m..]) {
                                    *q = x * scale[j];
                                }
                            }
                            rq.copy_from_slice(&rhs);
                            householder_qr(black_box(&mut qr), m, p, &mut rq);
                            for j in 0..p {
                                r[j * p..j * p + p].copy_from_slice(&qr[j * m..j * m + p]);
                            }
                            c.copy_from_slice(&rq[..p]);
                        }
                        1 => tall_qr(
                            black_box(&a),
                            m,
                            p,
                            &scale,
                            &rhs,
                            &mut r,
                            &mut c,
                            &mut scratch,
                        ),
                        _ => faer.factor(black_box(&a), &scale, &rhs, &mut r, &mut c),
                    }
                    black_box(&r);
                }
                t.push(start.elapsed().as_secs_f64() * 1e6 / inner as f64);
            }
        }
        let [t0, t1, t2] = times.map(|mut t| median(&mut t));
        println!(
            "| {m} x {p} | {t0:.2} | {t1:.2} | {t2:.2} | {:.2} | {:.2} |",
            t0 / t1,
            t2 / t1
        );
    }
}
