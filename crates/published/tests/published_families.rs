//! The conversions of Ngan et al.'s Cook-Torrance and Blinn-Phong fits into the
//! `cook-torrance` and `blinn-phong` families (by hand, against bbm's formulas as
//! docs/published-fits.md documents them evaluated independently here, and against the
//! families' bounds), and the accuracy of the approximate Beckmann-to-GGX roughness.

// Expected values are mpmath's digits as printed, some beyond f64's precision.
#![allow(clippy::excessive_precision)]

#[path = "../../model/tests/quadrature/mod.rs"]
mod quadrature;

use brdf_io::Channel;
use brdf_model::{Params, uniform_hemisphere};
use brdf_published::{
    ConvertError, FitFile, GGX_PER_BECKMANN, NganBlinnPhong, NganCookTorrance, bounds_violations,
    ggx_alpha_from_beckmann, read_fits,
};
use rand::{RngExt, SeedableRng};
use rand_pcg::Pcg64Mcg;
use std::f64::consts::PI;
use std::path::PathBuf;

fn load(name: &str) -> FitFile {
    let dir =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../experiments/data/published-fits");
    read_fits(dir.join(name)).unwrap_or_else(|e| panic!("{e}"))
}

const CHANNELS: [Channel; 3] = [Channel::Red, Channel::Green, Channel::Blue];

fn rel(a: f64, b: f64) -> f64 {
    if a == b {
        0.0
    } else {
        (a - b).abs() / a.abs().max(b.abs())
    }
}

/// Hand-computed conversions (mpmath at 30 digits): Cook-Torrance `kd = Kd / pi`,
/// `ks = 4 albedo / pi`; Blinn-Phong `kd = Kd / pi`, `ks = 4 albedo (n + 2) / (n + 8)`.
#[test]
fn hand_computed_conversions() {
    let ct = load("ngan_cooktorrance.fit");
    // alum-bronze, green: Kd = 0.0602, albedo = 0.0698, eta = 0.203, roughness = 0.0367:
    // kd = 0.0602 / pi = 0.0191622551482641984, ks = 0.2792 / pi = 0.0888721202225143555.
    // colonial-maple-223, red (the largest albedo): Kd = 0.101, albedo = 0.981, eta = 0.00173,
    // roughness = 0.166: kd = 0.0321492985045628578, ks = 3.924 / pi = 1.2490479933851946.
    let cases = [
        (
            "alum-bronze",
            Channel::Green,
            0.019_162_255_148_264_198,
            0.088_872_120_222_514_356,
            0.0367,
            0.203,
        ),
        (
            "colonial-maple-223",
            Channel::Red,
            0.032_149_298_504_562_858,
            1.249_047_993_385_194_6,
            0.166,
            0.00173,
        ),
    ];
    let ab = NganCookTorrance::from_fit(ct.get("alum-bronze").unwrap()).unwrap();
    assert_eq!(ab.to_params_default(), ab.to_params(Channel::Green));
    let bab =
        NganBlinnPhong::from_fit(load("ngan_blinnphong.fit").get("alum-bronze").unwrap()).unwrap();
    assert_eq!(bab.to_params_default(), bab.to_params(Channel::Green));
    for (material, channel, kd, ks, m, f0) in cases {
        let p = NganCookTorrance::from_fit(ct.get(material).unwrap())
            .unwrap()
            .to_params(channel);
        assert_eq!(p.family().name(), "cook-torrance");
        assert!(
            rel(p.shared()[0], kd) <= 1e-15,
            "{material}: kd {}",
            p.shared()[0]
        );
        assert_eq!(p.lobe_count(), 1);
        let l = p.lobe(0);
        assert!(rel(l[0], ks) <= 1e-15, "{material}: ks {}", l[0]);
        assert_eq!((l[1], l[2], l[3], l[4]), (m, m, f0, 0.0), "{material}");
    }
    let bp = load("ngan_blinnphong.fit");
    // alum-bronze, green: Kd = 0.0597, albedo = 0.00818, n = 1290:
    // kd = 0.0190031002051723031, ks = 4 * 0.00818 * 1292 / 1298 = 0.0325687519260400616.
    // specular-violet-phenolic, green (the largest n): Kd = 0.0167, albedo = 0.000602,
    // n = 121000: kd = 0.00531577509926930421, ks = 4 * 0.000602 * 121002 / 121008
    // = 0.00240788060293534312.
    // colonial-maple-223, blue: Kd = 0.00942, albedo = 0.00509, n = 62.7:
    // kd = 0.00299847912785130813, ks = 4 * 0.00509 * 64.7 / 70.7 = 0.0186321357850070721.
    // polyurethane-foam, red: albedo 0 gives ks = 0 (n = 1.45).
    let cases = [
        (
            "alum-bronze",
            Channel::Green,
            0.019_003_100_205_172_303,
            0.032_568_751_926_040_062,
            1290.0,
        ),
        (
            "specular-violet-phenolic",
            Channel::Green,
            0.005_315_775_099_269_304_2,
            0.002_407_880_602_935_343_1,
            121000.0,
        ),
        (
            "colonial-maple-223",
            Channel::Blue,
            0.002_998_479_127_851_308_1,
            0.018_632_135_785_007_072,
            62.7,
        ),
        ("polyurethane-foam", Channel::Red, 0.0876 / PI, 0.0, 1.45),
    ];
    for (material, channel, kd, ks, n) in cases {
        let p = NganBlinnPhong::from_fit(bp.get(material).unwrap())
            .unwrap()
            .to_params(channel);
        assert_eq!(p.family().name(), "blinn-phong");
        assert!(
            rel(p.shared()[0], kd) <= 1e-15,
            "{material}: kd {}",
            p.shared()[0]
        );
        let l = p.lobe(0);
        assert!(rel(l[0], ks) <= 1e-15, "{material}: ks {}", l[0]);
        assert_eq!(l[1], n, "{material}");
    }
}

/// Ngan's Cook-Torrance as bbm evaluates it (docs/published-fits.md), written here in the
/// documented order: `h = normalize(u + v)`, `tan^2 = (hx^2 + hy^2) / hz^2`,
/// `D = exp(-tan^2 / m^2) / (pi m^2 hz^4)`, `G = min(1, 2 hz uz / (u.h), 2 hz vz / (v.h))`,
/// `F = F0 + (1 - F0)(1 - c)^5` with `c = (u.h + v.h) / 2`, and
/// `Kd / pi + albedo D G F / (pi uz vz)`.
fn ngan_ct(l: &NganCookTorrance, k: usize, u: [f64; 3], v: [f64; 3]) -> f64 {
    let (kd, albedo, f0, m) = (l.kd[k], l.albedo[k], l.f0[k], l.m[k]);
    let s = [u[0] + v[0], u[1] + v[1], u[2] + v[2]];
    let len = (s[0] * s[0] + s[1] * s[1] + s[2] * s[2]).sqrt();
    let h = [s[0] / len, s[1] / len, s[2] / len];
    let tan2 = (h[0] * h[0] + h[1] * h[1]) / (h[2] * h[2]);
    let d = (-tan2 / (m * m)).exp() / (PI * m * m * h[2].powi(4));
    let uh = u[0] * h[0] + u[1] * h[1] + u[2] * h[2];
    let vh = v[0] * h[0] + v[1] * h[1] + v[2] * h[2];
    let g = (2.0 * h[2] * u[2] / uh)
        .min(2.0 * h[2] * v[2] / vh)
        .min(1.0);
    let c = (uh + vh) / 2.0;
    let f = f0 + (1.0 - f0) * (1.0 - c).powi(5);
    kd / PI + albedo * d * g * f / (PI * u[2] * v[2])
}

/// Ngan's Blinn-Phong in the half-vector reading (docs/published-fits.md):
/// `Kd / pi + albedo (n + 2) / (2 pi) max(0, n.h)^n`.
fn ngan_bp(l: &NganBlinnPhong, k: usize, u: [f64; 3], v: [f64; 3]) -> f64 {
    let s = [u[0] + v[0], u[1] + v[1], u[2] + v[2]];
    let hz = s[2] / (s[0] * s[0] + s[1] * s[1] + s[2] * s[2]).sqrt();
    let n = l.n[k];
    l.kd[k] / PI + l.albedo[k] * (n + 2.0) / (2.0 * PI) * hz.max(0.0).powf(n)
}

fn normalise(a: [f64; 3]) -> [f64; 3] {
    let l = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
    [a[0] / l, a[1] / l, a[2] / l]
}

/// Direction pairs: half uniform on the hemisphere, half near the mirror direction of `u`
/// (nudged by about `width` radians), where the lobe dominates the constant term.
fn directions(width: f64, rng: &mut Pcg64Mcg, count: usize) -> Vec<([f64; 3], [f64; 3])> {
    let mut out = Vec::with_capacity(count);
    while out.len() < count {
        let u = uniform_hemisphere(rng);
        if u[2] < 0.02 {
            continue;
        }
        if out.len() % 2 == 0 {
            out.push((u, uniform_hemisphere(rng)));
            continue;
        }
        let j: [f64; 3] = std::array::from_fn(|_| width * (rng.random::<f64>() - 0.5));
        let v = normalise([-u[0] + j[0], -u[1] + j[1], u[2] + j[2]]);
        if v[2] > 0.0 {
            out.push((u, v));
        }
    }
    out
}

/// Every material and channel against Ngan's form at 400 direction pairs each (half near the
/// peak). Cook-Torrance: measured (2026-12-07) at most 3.3e-13 relative, near the grazing
/// mirror direction, where bbm's separate `u.h` and `v.h` differ from the kernel's `|u + v| /
/// 2` by `eps / (1 + u.v)` because the `f64` directions are unit only to rounding; the
/// tolerance is 1e-12. Blinn-Phong: `powf` of a rounded `n.h` carries about `n` ulps (the
/// kernel's `ln(n.h)` is more accurate): measured at most 1.2 `n` ulps; the tolerance is 1e-13
/// or 2 `n` ulps.
#[test]
fn conversions_match_ngans_forms_at_random_directions() {
    let mut rng = Pcg64Mcg::seed_from_u64(2005);
    let (mut worst_ct, mut worst_bp, mut peak) = (0.0f64, 0.0f64, 0);
    for fit in &load("ngan_cooktorrance.fit").fits {
        let l = NganCookTorrance::from_fit(fit).unwrap();
        for (k, channel) in CHANNELS.into_iter().enumerate() {
            let p = l.to_params(channel);
            for (u, v) in directions(3.0 * l.m[k], &mut rng, 400) {
                let (ours, theirs) = (p.value(u, v), ngan_ct(&l, k, u, v));
                assert!(ours.is_finite() && theirs.is_finite(), "{}", l.material);
                let e = rel(ours, theirs);
                worst_ct = worst_ct.max(e);
                assert!(e <= 1e-12, "{} ({k}): {ours} vs {theirs}", l.material);
                if ours > 10.0 * l.kd[k] / PI {
                    peak += 1;
                }
            }
        }
    }
    for fit in &load("ngan_blinnphong.fit").fits {
        let l = NganBlinnPhong::from_fit(fit).unwrap();
        for (k, channel) in CHANNELS.into_iter().enumerate() {
            let p = l.to_params(channel);
            let n = l.n[k];
            for (u, v) in directions(4.0 / (n + 1.0).sqrt(), &mut rng, 400) {
                let (ours, theirs) = (p.value(u, v), ngan_bp(&l, k, u, v));
                let e = rel(ours, theirs);
                worst_bp = worst_bp.max(e / (n.max(1.0) * f64::EPSILON));
                assert!(
                    e <= 1e-13 || e <= 2.0 * n * f64::EPSILON,
                    "{} ({k}, n = {n}): {ours} vs {theirs}",
                    l.material
                );
            }
        }
    }
    eprintln!(
        "Cook-Torrance: largest relative difference {worst_ct:.1e} ({peak} evaluations where \
         the lobe is 9x the constant term or more); Blinn-Phong: {worst_bp:.2} n ulps"
    );
    assert!(peak > 10_000, "{peak}");
}

/// Every material, every channel, inside both families' bounds: no material is out of range.
#[test]
fn every_material_is_inside_the_bounds() {
    for fit in &load("ngan_cooktorrance.fit").fits {
        let l = NganCookTorrance::from_fit(fit).unwrap();
        for c in CHANNELS {
            let v = bounds_violations(&l.to_params(c));
            assert!(v.is_empty(), "{} ({c:?}): {v:?}", l.material);
            l.to_params(c).validate().unwrap();
        }
    }
    for fit in &load("ngan_blinnphong.fit").fits {
        let l = NganBlinnPhong::from_fit(fit).unwrap();
        for c in CHANNELS {
            let v = bounds_violations(&l.to_params(c));
            assert!(v.is_empty(), "{} ({c:?}): {v:?}", l.material);
        }
    }
    // The list itself works: a roughness and an exponent pushed out of the box.
    let bp = load("ngan_blinnphong.fit");
    let mut p = NganBlinnPhong::from_fit(bp.get("hematite").unwrap())
        .unwrap()
        .to_params(Channel::Green);
    p.lobe_mut(0)[1] = 2e6;
    let v = bounds_violations(&p);
    assert_eq!(v.len(), 1);
    assert_eq!(v[0].to_string(), "lobe1.p = 2000000 outside [0, 1000000]");
}

#[test]
fn conversions_refuse_other_models_and_bad_values() {
    let ward = load("ngan_ward.fit");
    let fit = &ward.fits[0];
    assert!(matches!(
        NganCookTorrance::from_fit(fit),
        Err(ConvertError::WrongModel { .. })
    ));
    assert!(matches!(
        NganBlinnPhong::from_fit(fit),
        Err(ConvertError::WrongModel { .. })
    ));
    let ct = load("ngan_cooktorrance.fit");
    let mut bad = ct.fits[0].clone();
    bad.params.retain(|p| p.name != "roughness");
    let e = NganCookTorrance::from_fit(&bad).unwrap_err().to_string();
    assert!(e.contains("no `roughness` parameter"), "{e}");
    let mut bad = ct.fits[0].clone();
    for p in &mut bad.params {
        if p.name == "roughness" {
            p.rgb = [0.0; 3];
        }
    }
    let e = NganCookTorrance::from_fit(&bad).unwrap_err().to_string();
    assert!(
        e.contains("roughness[red] = 0: expected a value > 0"),
        "{e}"
    );
}

/// The approximate GGX roughness: `alpha = m sqrt(ln 2 / (sqrt 2 - 1))` puts both
/// distributions at half their peak (up to the common `cos^-4`) at the same angle, and that
/// is all it matches. Measured here (2026-12-07):
/// - the distributions alone differ by a total-variation distance of 0.321 (the share of
///   microfacet normals that would have to move) at every `m` from 0.005 to 1, and by 0.41
///   (relative L2 distance of `D`, weight `n.h`) for `m <= 0.1`, rising to 0.68 at `m = 1`;
/// - Ngan's 86 Cook-Torrance fits (green) against the GGX lobes so converted (same `kd`, `ks`,
///   `f0`), on 10,000 direction pairs uniform by solid angle (a synthetic instance): RMSE of
///   the difference relative to the RMS of the Cook-Torrance BRDF from 0.056 to 3.24, median
///   0.977. Most of that is the masking (the V-cavity's `G / (4 uz vz)` grows as `1 / (uz vz)`
///   near the grazing mirror direction, Smith's stays bounded); the distributions' tails and
///   the narrow peaks that the uniform sample misses do the rest.
///
/// So it makes GGX lobes of realistic widths for test instances, not GGX fits of the materials.
#[test]
fn ggx_from_beckmann_accuracy() {
    let c = (2f64.ln() / (2f64.sqrt() - 1.0)).sqrt();
    assert!(rel(GGX_PER_BECKMANN, c) <= 2e-16);
    assert_eq!(ggx_alpha_from_beckmann(0.5), 0.5 * GGX_PER_BECKMANN);
    // Half the peak at tan^2 = m^2 ln 2, for both.
    for m in [0.01f64, 0.3, 1.0] {
        let a = ggx_alpha_from_beckmann(m);
        let t2 = m * m * 2f64.ln();
        let beckmann = (-t2 / (m * m)).exp();
        let ggx = (1.0 + t2 / (a * a)).powi(-2);
        assert!(
            (beckmann - 0.5).abs() < 1e-15 && (ggx - 0.5).abs() < 1e-15,
            "{ggx}"
        );
    }
    // The distributions alone.
    for m in [0.005f64, 0.01, 0.05, 0.1, 0.3, 0.6, 1.0] {
        let a = ggx_alpha_from_beckmann(m);
        let db = |h: [f64; 3]| {
            let t2 = (h[0] * h[0] + h[1] * h[1]) / (h[2] * h[2]);
            (-t2 / (m * m)).exp() / (PI * m * m * h[2].powi(4))
        };
        let dg = |h: [f64; 3]| {
            let t2 = (h[0] * h[0] + h[1] * h[1]) / (h[2] * h[2]);
            1.0 / (PI * a * a * h[2].powi(4) * (1.0 + t2 / (a * a)).powi(2))
        };
        let tv = quadrature::hemisphere(m, 4, |h| (dg(h) - db(h)).abs() * h[2]) / 2.0;
        let l2 = (quadrature::hemisphere(m, 4, |h| (dg(h) - db(h)).powi(2) * h[2])
            / quadrature::hemisphere(m, 4, |h| db(h).powi(2) * h[2]))
        .sqrt();
        eprintln!("m = {m}: total variation {tv:.4}, relative L2 {l2:.4}");
        assert!((tv - 0.321).abs() < 0.001, "m = {m}: {tv}");
        if m <= 0.1 {
            assert!((l2 - 0.408).abs() < 0.002, "m = {m}: {l2}");
        }
    }
    // The BRDFs over a synthetic instance's directions.
    let mut rng = Pcg64Mcg::seed_from_u64(1);
    let pairs: Vec<([f64; 3], [f64; 3])> = (0..10_000)
        .map(|_| (uniform_hemisphere(&mut rng), uniform_hemisphere(&mut rng)))
        .collect();
    let relative_rmse = |a: &Params, b: &Params| {
        let (mut se, mut ss) = (0.0, 0.0);
        for &(u, v) in &pairs {
            let (x, y) = (a.value(u, v), b.value(u, v));
            se += (x - y) * (x - y);
            ss += x * x;
        }
        (se / ss).sqrt()
    };
    let mut errors: Vec<f64> = load("ngan_cooktorrance.fit")
        .fits
        .iter()
        .map(|fit| {
            let l = NganCookTorrance::from_fit(fit).unwrap();
            relative_rmse(
                &l.to_params(Channel::Green),
                &l.to_ggx_params(Channel::Green),
            )
        })
        .collect();
    errors.sort_by(f64::total_cmp);
    let median = (errors[42] + errors[43]) / 2.0;
    eprintln!(
        "Cook-Torrance against GGX (alpha = 1.29 m), relative RMSE: min {:.3}, median {median:.3}, max {:.3}",
        errors[0], errors[85]
    );
    assert!((errors[0] - 0.056).abs() < 0.001 && (errors[85] - 3.24).abs() < 0.01);
    assert!((median - 0.977).abs() < 0.001, "{median}");
}
