//! The solver's kernels (`bounded_lm::set_kernel`) change speed, never a result: whole solves
//! with every kernel this CPU runs give the same reports and points bit for bit, on Jacobians
//! below and above `qr::TALL_QR_MIN_ROWS` rows (the in-place and the blocked QR), with row
//! counts that leave partial blocks and tails.
//!
//! One test function: the kernel is process-wide, so the kernels are tried in sequence.

mod common;

use bounded_lm::{Kernel, Options, Solver, kernel, qr::TALL_QR_MIN_ROWS, set_kernel};
use common::expsum::ExpSum;

/// Outcome code, iterations, evaluation counts, and the bits of `f` and of the final point.
type Fingerprint = (u8, usize, usize, usize, u64, Vec<u64>);

fn solve(m: usize, p: usize, start: &[f64]) -> Fingerprint {
    let mut problem = ExpSum::new(m, p);
    let mut x = start.to_vec();
    let (lower, upper) = (vec![-10.0; p], vec![10.0; p]);
    let r = Solver::new()
        .solve(&mut problem, &mut x, &lower, &upper, &Options::default())
        .expect("a valid problem");
    (
        r.outcome.code(),
        r.iterations,
        r.residual_evaluations,
        r.jacobian_evaluations,
        r.f.to_bits(),
        x.iter().map(|v| v.to_bits()).collect(),
    )
}

fn all_solves() -> Vec<Fingerprint> {
    let starts: [&[f64]; 3] = [
        &[1.0, 0.3, 1.0, 1.5, 1.0, 4.0],
        &[0.5, 1.0, 0.5, 3.0, 0.2, 8.0],
        &[3.0, 0.1, -1.0, 0.7, 2.0, 2.5],
    ];
    let mut out = Vec::new();
    for m in [40, TALL_QR_MIN_ROWS, 1001, 2003] {
        for start in starts {
            out.push(solve(m, 6, start));
        }
        out.push(solve(m, 4, &starts[0][..4]));
    }
    out
}

#[test]
fn every_kernel_gives_the_same_solves_bit_for_bit() {
    assert_eq!(
        kernel(),
        Kernel::best(),
        "the default is the fastest kernel"
    );
    set_kernel(Kernel::Portable).unwrap();
    let reference = all_solves();
    assert!(reference.iter().any(|f| f.1 > 3), "the solves iterate");
    for k in Kernel::available() {
        let used = set_kernel(k).unwrap();
        assert_eq!(kernel(), used);
        let expected = if k == Kernel::Scalar {
            Kernel::Portable
        } else {
            k
        };
        assert_eq!(used, expected);
        assert_eq!(all_solves(), reference, "kernel {k}");
    }
    set_kernel(Kernel::Auto).unwrap();
}
