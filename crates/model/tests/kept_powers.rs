//! The powers a residual evaluation keeps for the Jacobian at the same point
//! (`Evaluator::residuals` on 256 or more samples, every kernel but scalar): the Jacobian that reuses
//! them is bit for bit the one computed from scratch, and they are never used for another
//! point, another data set or other samples in the same buffer; Jacobians after an
//! evaluation that overflowed are right too.

use brdf_model::{
    DataSet, Evaluator, FamilyRef, Kernel, Layout, LobeKind, Samples, named_params, synthetic,
};

/// The Lafortune family's samples of `data` (what every layout here evaluates).
fn prepare(data: &DataSet) -> Samples {
    FamilyRef::lafortune().prepare(data)
}

fn layouts() -> Vec<Layout> {
    [
        vec![LobeKind::Anisotropic],
        vec![LobeKind::Isotropic],
        vec![LobeKind::Anisotropic, LobeKind::Isotropic],
    ]
    .iter()
    .map(|k| Layout::builder(k).build().unwrap())
    .collect()
}

fn kernels() -> Vec<Kernel> {
    [
        Kernel::Avx512,
        Kernel::Avx2,
        Kernel::Portable,
        Kernel::Scalar,
    ]
    .into_iter()
    .filter(|k| k.resolve().is_ok())
    .collect()
}

/// Residuals and Jacobian at `x` from an evaluator that never saw another point.
fn fresh(layout: &Layout, kernel: Kernel, x: &[f64], data: &Samples) -> (bool, Vec<u64>) {
    let mut ev = Evaluator::with_kernel(layout, kernel).unwrap();
    let mut r = vec![0.0; data.len()];
    let mut jac = vec![0.0; data.len() * layout.dim()];
    let ok = ev.residuals_and_jacobian(x, data, &mut r, &mut jac);
    (ok, r.iter().chain(&jac).map(|v| v.to_bits()).collect())
}

fn jacobian_of(ev: &mut Evaluator, x: &[f64], data: &Samples) -> (bool, Vec<u64>) {
    let mut r = vec![0.0; data.len()];
    let mut jac = vec![0.0; data.len() * ev.layout().dim()];
    let ok = ev.residuals_and_jacobian(x, data, &mut r, &mut jac);
    (ok, r.iter().chain(&jac).map(|v| v.to_bits()).collect())
}

fn point(layout: &Layout) -> Vec<f64> {
    let lobes = layout.kinds().len();
    let name = if lobes == 1 { "tuning" } else { "cross" };
    let mut p = named_params(name).unwrap();
    p.lobes.truncate(lobes);
    layout.encode(&p)
}

#[test]
fn a_jacobian_reusing_the_powers_equals_one_from_scratch() {
    let data = prepare(&synthetic(&named_params("cross").unwrap(), 1000, 0.1, 5));
    for layout in layouts() {
        for kernel in kernels() {
            let x = point(&layout);
            let mut ev = Evaluator::with_kernel(&layout, kernel).unwrap();
            let mut r = vec![0.0; data.len()];
            assert!(ev.residuals(&x, &data, &mut r));
            let reused = jacobian_of(&mut ev, &x, &data);
            assert!(reused.0);
            assert_eq!(reused, fresh(&layout, kernel, &x, &data), "{kernel}");
        }
    }
}

#[test]
fn kept_powers_never_serve_another_point_or_other_samples() {
    let all = prepare(&synthetic(&named_params("cross").unwrap(), 1200, 0.1, 9));
    let layout = &layouts()[2];
    let x = point(layout);
    for kernel in kernels() {
        let mut ev = Evaluator::with_kernel(layout, kernel).unwrap();
        let mut sub = Samples::empty(layout.family().name(), 0);
        let mut r = vec![0.0; 600];
        // Other samples in the same buffer (same length, same allocation).
        all.gather_into(&(0..600).collect::<Vec<u32>>(), &mut sub);
        assert!(ev.residuals(&x, &sub, &mut r));
        all.gather_into(&(600..1200).collect::<Vec<u32>>(), &mut sub);
        assert_eq!(
            jacobian_of(&mut ev, &x, &sub),
            fresh(layout, kernel, &x, &sub)
        );
        // A point one ulp away.
        assert!(ev.residuals(&x, &sub, &mut r));
        let mut y = x.clone();
        y[1] = f64::from_bits(y[1].to_bits() + 1);
        assert_eq!(
            jacobian_of(&mut ev, &y, &sub),
            fresh(layout, kernel, &y, &sub)
        );
        // A different data set of the same length.
        let other = prepare(&synthetic(&named_params("cross").unwrap(), 600, 0.1, 10));
        assert!(ev.residuals(&x, &sub, &mut r));
        assert_eq!(
            jacobian_of(&mut ev, &x, &other),
            fresh(layout, kernel, &x, &other)
        );
        // A clone has the same samples: reusing is right there, and must agree too.
        let copy = sub.clone();
        assert!(ev.residuals(&x, &sub, &mut r));
        assert_eq!(
            jacobian_of(&mut ev, &x, &copy),
            fresh(layout, kernel, &x, &copy)
        );
    }
}

#[test]
fn jacobians_after_a_failed_evaluation_are_right() {
    let data = prepare(&synthetic(&named_params("tuning").unwrap(), 800, 0.1, 3));
    let layout = Layout::builder(&[LobeKind::Isotropic]).build().unwrap();
    for kernel in kernels() {
        let mut ev = Evaluator::with_kernel(&layout, kernel).unwrap();
        let good = point(&layout);
        let mut r = vec![0.0; data.len()];
        assert!(ev.residuals(&good, &data, &mut r));
        // Huge Cxy and n: d > 1 somewhere, d^n overflows.
        let mut bad = good.clone();
        bad[1] = 1e4;
        bad[3] = layout.upper()[3];
        assert!(
            !ev.residuals(&bad, &data, &mut r),
            "{kernel}: expected overflow"
        );
        assert_eq!(
            jacobian_of(&mut ev, &bad, &data),
            fresh(&layout, kernel, &bad, &data)
        );
        assert_eq!(
            jacobian_of(&mut ev, &good, &data),
            fresh(&layout, kernel, &good, &data)
        );
    }
}
