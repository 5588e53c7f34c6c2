//! Synthetic instances: seeded, uniform by solid angle, with the asked noise.

use brdf_model::{Reflectance, named_params, synthetic};

#[test]
fn synthetic_is_seeded_and_uniform() {
    let p = named_params("tuning").unwrap();
    let a = synthetic(&p, 20000, 0.1, 7);
    assert_eq!(a, synthetic(&p, 20000, 0.1, 7));
    assert_ne!(a, synthetic(&p, 20000, 0.1, 8));
    // cos theta is uniform in [0, 1]: mean 1/2, and the noise has the asked sigma.
    let mean_z = a.u_z().iter().sum::<f64>() / a.len() as f64;
    assert!((mean_z - 0.5).abs() < 0.01, "{mean_z}");
    let rmse = p.rmse_on(&a);
    assert!((rmse - 0.1).abs() < 0.003, "{rmse}");
    let clean = synthetic(&p, 100, 0.0, 7);
    assert_eq!(p.rmse_on(&clean), 0.0);
    for i in 0..a.len() {
        let u = a.u(i);
        assert!(u[2] >= 0.0 && ((u[0] * u[0] + u[1] * u[1] + u[2] * u[2]) - 1.0).abs() < 1e-12);
    }
}
