//! The conversions of Ngan et al.'s Ward and Ashikhmin-Shirley fits: computed by hand, against
//! bbm's formulas (as docs/published-fits.md gives them) evaluated here independently at many
//! directions, and the materials outside the families' bounds (none).

use brdf_io::Channel;
use brdf_published::{
    ConvertError, FitFile, NganAshikhminShirley, NganWard, bounds_violations, read_fits,
};
use std::f64::consts::PI;
use std::path::PathBuf;

fn load(name: &str) -> FitFile {
    let dir =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../experiments/data/published-fits");
    read_fits(dir.join(name)).unwrap_or_else(|e| panic!("{e}"))
}

const CHANNELS: [Channel; 3] = [Channel::Red, Channel::Green, Channel::Blue];

/// SplitMix64, so the test needs no RNG API.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
    /// Uniform on the upper hemisphere (by solid angle), `z >= zmin`.
    fn hemisphere(&mut self, zmin: f64) -> [f64; 3] {
        let z = zmin + (1.0 - zmin) * self.next();
        let phi = 2.0 * PI * self.next();
        let r = (1.0 - z * z).sqrt();
        [r * phi.cos(), r * phi.sin(), z]
    }
}

fn normalise(a: [f64; 3]) -> [f64; 3] {
    let l = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
    [a[0] / l, a[1] / l, a[2] / l]
}

/// Direction pairs: half uniform on the hemisphere, half near the mirror direction of `u`
/// (nudged by about `width` radians), where the lobe dominates the constant term.
fn directions(rng: &mut Rng, width: f64, count: usize) -> Vec<([f64; 3], [f64; 3])> {
    let mut out = Vec::with_capacity(count);
    while out.len() < count {
        let u = rng.hemisphere(0.02);
        if out.len() % 2 == 0 {
            out.push((u, rng.hemisphere(0.0)));
            continue;
        }
        let j = |r: &mut Rng| width * (r.next() - 0.5);
        let v = normalise([-u[0] + j(rng), -u[1] + j(rng), u[2] + j(rng)]);
        if v[2] > 0.0 {
            out.push((u, v));
        }
    }
    out
}

/// Relative difference; values below 1e-290 count as 0 (the families cut `exp` below -700,
/// black-obsidian's red channel has no constant term, and no fit sees such a value).
fn rel(a: f64, b: f64) -> f64 {
    if a == b || a.abs().max(b.abs()) < 1e-290 {
        0.0
    } else {
        (a - b).abs() / a.abs().max(b.abs())
    }
}

/// bbm's Ngan Ward, as docs/published-fits.md writes it: `tan^2(theta_h)` from the
/// unnormalised `H = u + v`.
fn bbm_ward(w: &NganWard, k: usize, u: [f64; 3], v: [f64; 3]) -> f64 {
    let h = [u[0] + v[0], u[1] + v[1], u[2] + v[2]];
    let tan2 = (h[0] * h[0] + h[1] * h[1]) / (h[2] * h[2]);
    let a2 = w.alpha[k] * w.alpha[k];
    w.kd[k] / PI + w.ks[k] * (-tan2 / a2).exp() / (4.0 * PI * a2 * (u[2] * v[2]).sqrt())
}

/// bbm's Ngan Ashikhmin-Shirley: `albedo (n + 1)/(8 pi) (n.h)^n F(u.h) / ((u.h) max(uz, vz))`.
///
/// `u.h` is taken as the mean `(u.h + v.h) / 2`: the two are equal for unit vectors, but `u`
/// and `v` are unit only to rounding (`|u|^2 - 1` up to about 2e-16), and then they differ by
/// `(|u|^2 - |v|^2) / (2 |u + v|)`, which near the grazing back-scatter configuration (`u.h`
/// small) is far above rounding: at colonial-maple-223 (green, `n` = 63.3),
/// `u = [-0.98906, 0.14616, 0.02012]`, `v = [0.98853, -0.15101, 0.00249]` (`u.h` = 0.0116), the
/// lobe with `u.h` alone is 3.9e-13 above its double-double value at the normalised directions
/// and with `v.h` alone 7.9e-13 below, while the mean (which is `|u + v| / 2`, as the family
/// computes it) is within 5e-15 and the family within 2e-15.
fn bbm_as(a: &NganAshikhminShirley, k: usize, u: [f64; 3], v: [f64; 3]) -> f64 {
    let h = normalise([u[0] + v[0], u[1] + v[1], u[2] + v[2]]);
    let dot = |w: [f64; 3]| w[0] * h[0] + w[1] * h[1] + w[2] * h[2];
    let uh = 0.5 * (dot(u) + dot(v));
    let n = a.n[k];
    let f = a.f0[k] + (1.0 - a.f0[k]) * (1.0 - uh).powi(5);
    a.kd[k] / PI + a.ks[k] * (n + 1.0) / (8.0 * PI) * h[2].powf(n) * f / (uh * u[2].max(v[2]))
}

#[test]
fn hand_computed_conversions() {
    let close = |a: f64, b: f64| assert!((a - b).abs() <= 1e-15 * b.abs(), "{a} vs {b}");
    // ngan_ward.fit, alum-bronze: Lambertian [0.0851, 0.0586, 0.0294], albedo [0.0484, 0.0274,
    // 0.0135], roughness 0.0357. Green: kd = 0.0586 / pi = 0.0186529593303701, ks = 0.0274,
    // ax = ay = 0.0357, pan 0.
    let file = load("ngan_ward.fit");
    let w = NganWard::from_fit(file.get("alum-bronze").unwrap()).unwrap();
    let p = w.to_params_default();
    assert_eq!(p.family().name(), "ward");
    close(p.shared()[0], 0.018_652_959_330_370_134);
    assert_eq!(p.lobe(0), &[0.0274, 0.0357, 0.0357, 0.0][..]);
    // hematite, red: kd = 0.0317 / pi, ks = 0.0849, alpha = 0.00576 (the sharpest fit).
    let h = NganWard::from_fit(file.get("hematite").unwrap())
        .unwrap()
        .to_params(Channel::Red);
    close(h.shared()[0], 0.0317 / PI);
    assert_eq!(h.lobe(0), &[0.0849, 0.00576, 0.00576, 0.0][..]);
    // ngan_ashikhminshirley.fit, alum-bronze: Lambertian [0.0877, 0.0598, 0.0297], albedo
    // [0.108, 0.0637, 0.0337], fresnelReflectance 0.249, sharpness 1350. Green: kd = 0.0598 /
    // pi = 0.0190349311937907, ks = 0.0637, nu = nv = 1350, f0 = 0.249, pan 0.
    let file = load("ngan_ashikhminshirley.fit");
    let a = NganAshikhminShirley::from_fit(file.get("alum-bronze").unwrap()).unwrap();
    let p = a.to_params_default();
    assert_eq!(p.family().name(), "ashikhmin-shirley");
    close(p.shared()[0], 0.019_034_931_193_790_683);
    assert_eq!(p.lobe(0), &[0.0637, 1350.0, 1350.0, 0.249, 0.0][..]);
    // A fit of another model is refused with the model named.
    let e = NganWard::from_fit(file.get("pvc").unwrap()).unwrap_err();
    assert!(matches!(e, ConvertError::WrongModel { .. }), "{e}");
    assert!(e.to_string().contains("NganAshikhminShirley"), "{e}");
}

/// Every material and channel against bbm's formula at 400 direction pairs (half near the
/// peak). Ward: within `1e-13 + 4 x eps` relative, `x = tan^2(theta_h) / alpha^2` (the
/// exponent's own rounding, about `x eps`, up to 1.6e-13 at `x = 700`). Ashikhmin-
/// Shirley: bbm's `hz^n` rounds `hz` before raising it to `n` (up to 78200), which costs about
/// `n` ulps, so the bound is `1e-13 + 2 n eps`; the family's `exp(n ln hz)` from the
/// half vector's components is the more accurate of the two.
#[test]
fn conversions_match_bbms_formulas_at_random_directions() {
    let mut rng = Rng(0x5eed_2005);
    let (mut worst_ward, mut worst_as, mut peak) = (0.0f64, 0.0f64, 0);
    let (mut raw_ward, mut raw_as) = (0.0f64, 0.0f64);
    let file = load("ngan_ward.fit");
    assert_eq!(file.fits.len(), 86);
    for fit in &file.fits {
        let w = NganWard::from_fit(fit).unwrap();
        for (k, channel) in CHANNELS.into_iter().enumerate() {
            let p = w.to_params(channel);
            for (u, v) in directions(&mut rng, 2.0 * w.alpha[k], 400) {
                let (ours, theirs) = (p.value(u, v), bbm_ward(&w, k, u, v));
                let e = rel(ours, theirs);
                let hv = [u[0] + v[0], u[1] + v[1], u[2] + v[2]];
                let x = (hv[0] * hv[0] + hv[1] * hv[1]) / (hv[2] * hv[2] * w.alpha[k] * w.alpha[k]);
                let bound = 1e-13 + 4.0 * f64::EPSILON * x;
                worst_ward = worst_ward.max(e / bound);
                raw_ward = raw_ward.max(e);
                assert!(
                    e <= bound,
                    "{} ({k}): {ours} vs {theirs}, {e:e} at u = {u:?}, v = {v:?}",
                    w.material
                );
                if ours > 10.0 * w.kd[k] / PI {
                    peak += 1;
                }
            }
        }
    }
    let file = load("ngan_ashikhminshirley.fit");
    assert_eq!(file.fits.len(), 86);
    for fit in &file.fits {
        let a = NganAshikhminShirley::from_fit(fit).unwrap();
        for (k, channel) in CHANNELS.into_iter().enumerate() {
            let p = a.to_params(channel);
            let width = 2.0 * (2.0 / a.n[k].max(1.0)).sqrt();
            for (u, v) in directions(&mut rng, width, 400) {
                let (ours, theirs) = (p.value(u, v), bbm_as(&a, k, u, v));
                let e = rel(ours, theirs);
                worst_as = worst_as.max(e / (1e-13 + 2.0 * a.n[k] * f64::EPSILON));
                raw_as = raw_as.max(e);
                assert!(
                    e <= 1e-13 + 2.0 * a.n[k] * f64::EPSILON,
                    "{} ({k}, n = {}): {ours} vs {theirs}, {e:e} at u = {u:?}, v = {v:?}",
                    a.material,
                    a.n[k]
                );
                if ours > 10.0 * a.kd[k] / PI {
                    peak += 1;
                }
            }
        }
    }
    eprintln!(
        "Ward: worst {raw_ward:e}, {worst_ward:.3} of its bound; Ashikhmin-Shirley: worst \
         {raw_as:e}, {worst_as:.3} of its bound; {peak} evaluations where the lobe is 10x the constant term or more"
    );
    assert!(peak > 20_000, "{peak}");
}

/// The materials outside the families' bounds, in any channel: none. Ward: ks 0.00145 to
/// 0.279 (bound [0, 1]), alpha 0.00576 to 0.5 ([0.001, 1]); Ashikhmin-Shirley: ks 0.00207 to
/// 0.773 ([0, 1]), f0 0.0123 to 0.999 ([0, 1]), n 0.5 to 78200 ([0, 1e6]); kd at most
/// 0.41 / pi.
#[test]
fn materials_outside_the_families_bounds() {
    let mut outside = Vec::new();
    for fit in &load("ngan_ward.fit").fits {
        let w = NganWard::from_fit(fit).unwrap();
        for c in CHANNELS {
            let v = bounds_violations(&w.to_params(c));
            if !v.is_empty() {
                outside.push(format!("{} {c:?}: {v:?}", fit.material));
            }
            w.to_params(c).validate().unwrap();
        }
    }
    for fit in &load("ngan_ashikhminshirley.fit").fits {
        let a = NganAshikhminShirley::from_fit(fit).unwrap();
        for c in CHANNELS {
            let v = bounds_violations(&a.to_params(c));
            if !v.is_empty() {
                outside.push(format!("{} {c:?}: {v:?}", fit.material));
            }
            a.to_params(c).validate().unwrap();
        }
    }
    assert_eq!(outside, Vec::<String>::new());
    // The check itself reports a value outside the bounds.
    let mut p = NganWard::from_fit(load("ngan_ward.fit").get("pvc").unwrap())
        .unwrap()
        .to_params_default();
    p.lobe_mut(0)[1] = 2.0;
    let v = bounds_violations(&p);
    assert_eq!(v.len(), 1);
    assert_eq!(v[0].to_string(), "lobe1.ax = 2 outside [0.001, 1]");
}
