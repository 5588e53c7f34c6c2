//! Searches each family for the direction pairs and parameters where its kernel is least
//! accurate, and compares the errors with the value check's condition term of section 1b
//! (`brdf_stress::families::CONDITION_FACTOR`): the relative error of the libm kernel
//! (`Params::value`; the vector kernels give the same numbers in section 1b) against the
//! double-double reference, and that error over `eps kappa` and over the check's bound.
//!
//! ```sh
//! cargo run -p brdf-stress --release --example families_condition -- [DRAWS]
//! ```
//!
//! Two kinds of draws per family (`DRAWS` each, default 300,000): *broad*, parameters
//! log-uniform in the box, a half vector of slope log-uniform in [1e-4, 100] at a random
//! azimuth, `u` tilted from it by up to 1.5 and `v` its mirror image about it; and
//! *adversarial*, a sharp axis (roughness 0.001, or exponent 1e6) and a wide one (roughness
//! 1.25 to 2.5, or exponent 0.3 to 1.3), the half vector's slopes along the two axes chosen so
//! that the exponent's two parts sum to at most 575 (values above 1e-250) and mixed by a random
//! pan, `u` tilted by up to 0.3: where the rotated slope along the sharp axis is a small
//! difference of large terms (not for Blinn-Phong, whose lobe has no rotation).

use brdf_model::{Params, family};
use brdf_stress::dd::DD;
use brdf_stress::families::{CONDITION_FACTOR, FamilyReference, VALUE_TOLERANCE, references};
use rand::{RngExt, SeedableRng};
use rand_pcg::Pcg64;

/// Largest relative error, largest error over `eps kappa` (errors above 1e-14), largest error
/// over the check's bound.
#[derive(Default)]
struct Worst {
    relative: f64,
    per_kappa: f64,
    normalised: f64,
    draws: usize,
}

fn main() {
    let draws: usize = std::env::args()
        .nth(1)
        .map_or(300_000, |a| a.parse().expect("an integer"));
    println!(
        "| family | draws | max relative error | max error / (eps kappa) | max error / bound |\n\
         |---|---|---|---|---|"
    );
    for r in references() {
        // Blinn-Phong's lobe is isotropic, with no rotation to cancel: broad draws only.
        let kinds: &[bool] = if r.name == "blinn-phong" {
            &[false]
        } else {
            &[false, true]
        };
        for &adversarial in kinds {
            let w = search(&r, draws, adversarial);
            println!(
                "| {} ({}) | {} | {:.2e} | {:.2} | {:.3} |",
                r.name,
                if adversarial { "adversarial" } else { "broad" },
                w.draws,
                w.relative,
                w.per_kappa,
                w.normalised
            );
        }
    }
}

/// The lobe's fields from a roughness pair (exponent families: `n = 2 / m^2`, capped at 1e6).
fn fields(name: &str, mx: f64, my: f64, pan: f64, f0: f64) -> Vec<f64> {
    let n = |m: f64| (2.0 / (m * m)).min(1e6);
    match name {
        "ward" | "ward-gmd" => vec![1.0, mx.min(1.0), my.min(1.0), pan],
        "ashikhmin-shirley" => vec![1.0, n(mx), n(my), f0, pan],
        "blinn-phong" => vec![1.0, n(mx)],
        _ => vec![1.0, mx, my, f0, pan],
    }
}

fn search(r: &FamilyReference, draws: usize, adversarial: bool) -> Worst {
    let fam = family(r.name).expect("a family");
    let mut rng = Pcg64::seed_from_u64(if adversarial { 2 } else { 1 });
    let mut w = Worst::default();
    let log_uniform = |x: f64, lo: f64, hi: f64| (lo.ln() + x * (hi.ln() - lo.ln())).exp();
    for _ in 0..draws {
        let pan = 90.0 * (2.0 * rng.random::<f64>() - 1.0);
        let f0 = rng.random::<f64>();
        let (mx, my, sx, sy, tilt);
        if adversarial {
            (mx, my) = (0.001, 2.5 * (0.5 + 0.5 * rng.random::<f64>()));
            let qx = 575.0 * rng.random::<f64>();
            let qy = (575.0 - qx) * rng.random::<f64>();
            let sign = if rng.random::<bool>() { 1.0 } else { -1.0 };
            let (px, py) = (sign * mx * qx.sqrt(), my * qy.sqrt());
            // The slopes in the unrotated frame: x = c x' - s y', y = s x' + c y'.
            let (s, c) = pan.to_radians().sin_cos();
            (sx, sy) = (c * px - s * py, s * px + c * py);
            tilt = 0.3 * rng.random::<f64>();
        } else {
            (mx, my) = (
                log_uniform(rng.random(), 0.001, 2.5),
                log_uniform(rng.random(), 0.001, 2.5),
            );
            let slope = log_uniform(rng.random(), 1e-4, 100.0);
            let phi = std::f64::consts::TAU * rng.random::<f64>();
            (sx, sy) = (slope * phi.cos(), slope * phi.sin());
            tilt = log_uniform(rng.random(), 1e-6, 1.5);
        }
        let l = (sx * sx + sy * sy + 1.0).sqrt();
        let h = [sx / l, sy / l, 1.0 / l];
        let phi = std::f64::consts::TAU * rng.random::<f64>();
        let unit = |a: [f64; 3]| {
            let n = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
            a.map(|c| c / n)
        };
        let u = unit([h[0] + tilt * phi.cos(), h[1] + tilt * phi.sin(), h[2]]);
        let uh = u[0] * h[0] + u[1] * h[1] + u[2] * h[2];
        let v = unit([0, 1, 2].map(|k| 2.0 * uh * h[k] - u[k]));
        if u[2] <= 0.0 || v[2] <= 0.0 {
            continue;
        }
        let f = fields(r.name, mx, my, pan, f0);
        let p = Params::new(fam.clone(), vec![0.0], vec![f.clone()]).expect("fields in the box");
        let fd: Vec<DD> = f.iter().map(|&x| DD::new(x)).collect();
        let reference = (r.lobe)(&fd, u, v).to_f64();
        if !(reference >= 1e-250 && reference.is_finite()) {
            continue;
        }
        w.draws += 1;
        let kappa = (r.condition)(&f, u, v);
        let e = (p.value(u, v) - reference).abs() / reference;
        w.relative = w.relative.max(e);
        if e > 1e-14 {
            w.per_kappa = w.per_kappa.max(e / (f64::EPSILON * kappa));
        }
        let bound = VALUE_TOLERANCE + CONDITION_FACTOR * f64::EPSILON * kappa;
        w.normalised = w.normalised.max(e / bound);
    }
    w
}
