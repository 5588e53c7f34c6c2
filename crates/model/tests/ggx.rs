//! GGX: the normalisation of its distribution by quadrature, through the kernels' own code.

mod quadrature;

use brdf_model::lobes::{FusedMath, Libm, LobeShape, MAX_COLUMNS, PlainMath};
use brdf_model::models::geometry::{H, ONE_MINUS_UH, U, V};
use brdf_model::models::ggx::Ggx;

/// `D(h)` as the lobe computes it: with `u = v = n` in the masking columns (`G1(u)/uz =
/// G1(v)/vz = 1`), `u.h = 1` (`F = f0`), `ks = 4` and `f0 = 1` the lobe `ks D F G1 G1 / (4 uz
/// vz)` is `D(h)`, whatever `h` the half-vector columns hold.
/// `math`: 0 libm, 1 the portable kernel's, 2 the AVX kernels' (fused multiply-adds).
fn d_of<const ANISO: bool>(fields: &[f64; 5], h: [f64; 3], math: usize) -> f64 {
    let c = Ggx::coef(fields, ANISO);
    let mut s = [0.0; MAX_COLUMNS];
    s[U + 2] = 1.0;
    s[V + 2] = 1.0;
    s[H..H + 3].copy_from_slice(&h);
    s[ONE_MINUS_UH] = 0.0;
    match math {
        0 => Ggx::value::<Libm, ANISO>(&c, &s),
        1 => Ggx::value::<PlainMath, ANISO>(&c, &s),
        _ => Ggx::value::<FusedMath, ANISO>(&c, &s),
    }
}

/// `int D(h) (n.h) dw_h = 1` over the hemisphere, isotropic and anisotropic (`ay = ax / 3`,
/// pan 30 degrees), at roughness 0.05, 0.3, 1 and 2, with the libm and both fast
/// arithmetics. 32-point Gauss-Legendre on panels in `theta` (ends at `atan(a 2^k)`), 1024
/// azimuths. Measured (2026-12-07): every integral within 1.6e-15 of 1 (isotropic at most
/// 1.1e-15, anisotropic 1.6e-15); the tolerance is 1e-12.
#[test]
fn distribution_is_normalised() {
    for a in [0.05f64, 0.3, 1.0, 2.0] {
        for (aniso, fields) in [
            (false, [4.0, a, a, 1.0, 0.0]),
            (true, [4.0, a, a / 3.0, 1.0, 30.0]),
        ] {
            for math in 0..3 {
                let width = fields[1].min(fields[2]);
                let integral = quadrature::hemisphere(width, 1024, |h| {
                    let d = if aniso {
                        d_of::<true>(&fields, h, math)
                    } else {
                        d_of::<false>(&fields, h, math)
                    };
                    d * h[2]
                });
                eprintln!(
                    "ggx a = {a}, aniso {aniso}, math {math}: {integral:.16} ({:.1e})",
                    integral - 1.0
                );
                assert!(
                    (integral - 1.0).abs() <= 1e-12,
                    "a = {a}, aniso {aniso}, math {math}: {integral}"
                );
            }
        }
    }
}
