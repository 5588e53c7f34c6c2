//! The published fits (`experiments/data/published-fits/`): every file parses, the reader's
//! errors and limits, the conversion of Ngan et al.'s Lafortune fits (by hand, against Ngan's
//! normalised form evaluated directly, and against the Table 1 box), the data's SHA-256 sums
//! against the folder's README, and `docs/published-fits.md`'s generated tables.

use brdf_io::Channel;
use brdf_model::BrdfParams;
use brdf_published::{
    ConvertError, FIT_FILES, FitError, FitFile, MAX_FIT_BYTES, MAX_FIT_DEPTH, MAX_FIT_ITEMS,
    MAX_FIT_LINE_BYTES, NganLafortune, parse_fits, read_fits, report_markdown, table1_violations,
};
use std::f64::consts::PI;
use std::path::PathBuf;

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn data_dir() -> PathBuf {
    repo().join("experiments/data/published-fits")
}

fn load(name: &str) -> FitFile {
    read_fits(data_dir().join(name)).unwrap_or_else(|e| panic!("{e}"))
}

fn ngan_lafortune(material: &str) -> NganLafortune {
    let file = load("ngan_lafortune.fit");
    let fit = file
        .get(material)
        .unwrap_or_else(|| panic!("no {material}"));
    NganLafortune::from_fit(fit).unwrap()
}

const CHANNELS: [Channel; 3] = [Channel::Red, Channel::Green, Channel::Blue];

#[test]
fn every_published_file_parses_with_its_model_and_materials() {
    let expected = [
        ("ngan_lafortune.fit", "NganLafortune", 86),
        ("ngan_ward.fit", "NganWard", 86),
        ("ngan_wardduer.fit", "NganWardDuer", 86),
        ("ngan_blinnphong.fit", "NganBlinnPhong", 86),
        ("ngan_cooktorrance.fit", "NganCookTorrance", 86),
        ("ngan_ashikhminshirley.fit", "NganAshikhminShirley", 86),
        ("ngan_he.fit", "NganHe", 86),
        ("low_cooktorrance_E1.fit", "LowCookTorrance", 100),
        ("low_cooktorrance_E2.fit", "LowCookTorrance", 100),
        ("low_ashikhminshirley_E1.fit", "LowAshikhminShirley", 100),
        ("low_ashikhminshirley_E2.fit", "LowAshikhminShirley", 100),
        ("low_lowmicrofacet_E2.fit", "LowMicrofacetFit", 100),
        ("low_lowsmooth_E2.fit", "LowSmooth", 100),
        ("bagher_sgd.fit", "Bagher", 100),
    ];
    assert_eq!(expected.map(|e| e.0), FIT_FILES);
    let ngan_materials: Vec<String> = load("ngan_lafortune.fit")
        .fits
        .iter()
        .map(|f| f.material.clone())
        .collect();
    let low_materials: Vec<String> = load("low_cooktorrance_E1.fit")
        .fits
        .iter()
        .map(|f| f.material.clone())
        .collect();
    for (name, model, count) in expected {
        let file = load(name);
        assert_eq!(file.fits.len(), count, "{name}");
        assert!(!file.comments.is_empty(), "{name}: no header");
        let mut params: Option<Vec<&str>> = None;
        for f in &file.fits {
            assert_eq!(f.model, model, "{name}: {}", f.material);
            assert!(f.diffuse.is_some(), "{name}: {}", f.material);
            // Every line of a file has the same parameters in the same order.
            let names: Vec<&str> = f.params.iter().map(|p| p.name.as_str()).collect();
            match &params {
                None => params = Some(names),
                Some(p) => assert_eq!(*p, names, "{name}: {}", f.material),
            }
            for p in &f.params {
                assert!(
                    p.rgb.iter().all(|v| v.is_finite()),
                    "{name}: {}",
                    f.material
                );
            }
        }
        // The Ngan files cover the same 86 materials, Löw's and Bagher's the same 100.
        let materials: Vec<String> = file.fits.iter().map(|f| f.material.clone()).collect();
        let reference = if count == 86 {
            &ngan_materials
        } else {
            &low_materials
        };
        let (mut a, mut b) = (materials.clone(), reference.clone());
        a.sort();
        b.sort();
        assert_eq!(a, b, "{name}");
    }
    // Spot checks against the text of the files.
    let laf = load("ngan_lafortune.fit");
    let ab = laf.get("alum-bronze").unwrap();
    assert_eq!(ab.line, 7);
    assert_eq!(ab.diffuse, Some([0.0923, 0.0625, 0.0311]));
    assert_eq!(ab.rgb("albedo"), Some([0.322, 0.193, 0.105]));
    assert_eq!(ab.value("Cxy", Channel::Blue), Some(-0.579));
    assert!(ab.param("Cz").unwrap().shared);
    assert!(!ab.param("albedo").unwrap().shared);
    let bagher = load("bagher_sgd.fit");
    let bf = bagher.get("black-fabric").unwrap();
    assert_eq!(bf.rgb("eta.0"), Some([1.0; 3]));
    assert_eq!(bf.rgb("eta.1"), Some([0.0; 3]));
    assert_eq!(
        bagher.get("black-obsidian").unwrap().rgb("c"),
        Some([1.31522e+49, 9.46657e+50, 1.03557e+47])
    );
}

fn parse_err(text: &str) -> String {
    match parse_fits(text, "t.fit") {
        Ok(f) => panic!("accepted {text:?}: {f:?}"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn parse_errors_name_file_line_column_and_expectation() {
    let good = "m = Aggregate(Lambertian(albedo = [0.1, 0.2, 0.3]), M(a = 1.0, b = [1, 2, 3]))";
    let f = parse_fits(format!("# head\n\n{good}\r\n  # c2\n").as_str(), "t.fit").unwrap();
    assert_eq!(f.comments, ["head", "c2"]);
    assert_eq!(f.fits[0].line, 3);
    // A lone model without Aggregate or Lambertian is accepted.
    let lone = parse_fits("x = M(a = 2)", "t.fit").unwrap();
    assert_eq!(lone.fits[0].diffuse, None);
    assert_eq!(lone.fits[0].rgb("a"), Some([2.0; 3]));

    let cases: [(&str, &str); 22] = [
        (
            "m Aggregate(M())",
            "t.fit:1:1: expected `material = Model(...)` or a `#` comment, found no `=`",
        ),
        (
            " = M(a = 1)",
            "t.fit:1:2: expected a material name before `=`, found nothing",
        ),
        (
            "a b = M(a = 1)",
            "t.fit:1:2: expected a material name of letters",
        ),
        (
            "m = M(a = 1",
            "t.fit:1:12: expected `,` or `)`, found the end of the line",
        ),
        (
            "m = M(a = 1))",
            "t.fit:1:13: expected the end of the line after the model, found `)`",
        ),
        (
            "m = M(a = 1e400)",
            "t.fit:1:11: expected a finite number, found `1e400`",
        ),
        (
            "m = M(a = nan)",
            "t.fit:1:14: expected `(` after the model name `nan`",
        ),
        (
            "m = M(a = 1.2.3)",
            "t.fit:1:11: expected a number, found `1.2.3`",
        ),
        (
            "m = M(a = [1, 2])",
            "t.fit:1:11: expected `a`: a number or a list of 3 numbers",
        ),
        (
            "m = M(a = [1, 2, [3]])",
            "t.fit:1:18: expected `a`: a number or a list of 3",
        ),
        (
            "m = M(a = [[1, 2, 3], 4])",
            "expected `a.1`: a number or a list of 3 numbers",
        ),
        (
            "m = M(1)",
            "t.fit:1:7: expected a named parameter `name = value` of M",
        ),
        (
            "m = M(a = 1, a = 2)",
            "t.fit:1:18: expected each parameter of M once, found `a` again",
        ),
        (
            "m = Aggregate(M(a = 1), N(b = 2))",
            "t.fit:1:25: expected one specular model",
        ),
        (
            "m = Aggregate(Lambertian(albedo = [1, 2, 3]))",
            "expected a specular model besides",
        ),
        (
            "m = Aggregate(Lambertian(x = [1, 2, 3]), M(a = 1))",
            "`Lambertian(albedo = [r, g, b])`",
        ),
        (
            "m = Aggregate(x = M(a = 1))",
            "t.fit:1:19: expected a model as an argument of Aggregate",
        ),
        (
            "m = Aggregate(1)",
            "t.fit:1:15: expected a model as an argument of Aggregate",
        ),
        (
            "m = 3",
            "t.fit:1:5: expected a model call such as `Aggregate(...)`",
        ),
        (
            "m = M(a = $)",
            "t.fit:1:11: expected a number, a list `[...]` or a model call",
        ),
        (
            "m = M(a = 1)\nm = M(a = 2)",
            "t.fit:2:1: expected a material not given before",
        ),
        (
            "m = M(é = 1)",
            "t.fit:1:7: expected a number, a list `[...]` or a model call, found the character 'é'",
        ),
    ];
    for (text, want) in cases {
        let e = parse_err(text);
        assert!(e.contains(want), "{text:?}: {e}");
    }
}

#[test]
fn limits_are_enforced() {
    let deep = format!(
        "m = M(a = {}1{})",
        "[".repeat(MAX_FIT_DEPTH),
        "]".repeat(MAX_FIT_DEPTH)
    );
    assert!(parse_err(&deep).contains("(MAX_FIT_DEPTH)"));
    let items = vec!["1"; MAX_FIT_ITEMS + 1].join(", ");
    assert!(parse_err(&format!("m = M(a = [{items}])")).contains("(MAX_FIT_ITEMS)"));
    let args: Vec<String> = (0..=MAX_FIT_ITEMS).map(|i| format!("p{i} = 1")).collect();
    assert!(parse_err(&format!("m = M({})", args.join(", "))).contains("(MAX_FIT_ITEMS)"));
    let long = format!("# {}", "x".repeat(MAX_FIT_LINE_BYTES));
    assert!(parse_err(&long).contains("t.fit:1: expected at most 65536 bytes per line"));
    let name = "n".repeat(300);
    assert!(parse_err(&format!("{name} = M(a = 1)")).contains("(MAX_FIT_NAME_BYTES)"));
    assert!(parse_err(&format!("m = {name}(a = 1)")).contains("(MAX_FIT_NAME_BYTES)"));
    let big = "#\n".repeat(MAX_FIT_BYTES as usize / 2 + 1);
    assert!(parse_err(&big).contains("(MAX_FIT_BYTES)"));
    let lines: String = (0..=brdf_published::MAX_FIT_MATERIALS)
        .map(|i| format!("m{i} = M(a = 1)\n"))
        .collect();
    assert!(parse_err(&lines).contains("(MAX_FIT_MATERIALS)"));

    // Files: missing, not UTF-8, too long.
    let dir = tempfile::tempdir().unwrap();
    let missing = read_fits(dir.path().join("none.fit")).unwrap_err();
    assert!(matches!(missing, FitError::Io { .. }), "{missing}");
    let bad = dir.path().join("bad.fit");
    std::fs::write(&bad, b"# ok\nm = M(a = \xff)\n").unwrap();
    let e = read_fits(&bad).unwrap_err().to_string();
    assert!(
        e.ends_with("bad.fit:2:11: expected UTF-8 text, found the byte 0xff"),
        "{e}"
    );
    let huge = dir.path().join("huge.fit");
    std::fs::write(&huge, vec![b'#'; MAX_FIT_BYTES as usize + 1]).unwrap();
    let e = read_fits(&huge).unwrap_err().to_string();
    assert!(
        e.ends_with("huge.fit:0: expected at most 4194304 bytes (MAX_FIT_BYTES), found more"),
        "{e}"
    );
}

#[test]
fn mangled_lines_never_panic() {
    let text = std::fs::read_to_string(data_dir().join("bagher_sgd.fit")).unwrap();
    let line = text.lines().nth(2).unwrap();
    let mut accepted = 0;
    let cuts: Vec<usize> = line.char_indices().map(|(i, _)| i).collect();
    for &i in &cuts {
        if parse_fits(&line[..i], "t.fit").is_ok() {
            accepted += 1;
        }
        for c in [
            '(', ')', '[', ']', ',', '=', ' ', 'x', '1', '.', '-', '#', 'é',
        ] {
            let mut s = line.to_string();
            let end = i + s[i..].chars().next().map_or(0, char::len_utf8);
            s.replace_range(i..end, &c.to_string());
            let _ = parse_fits(&s, "t.fit");
        }
    }
    assert!(accepted <= 1, "{accepted} truncations accepted");
}

/// Hand-computed conversions (green channel unless said otherwise), digits from `bc -l`:
/// `kd = Kd / pi`, `a = ks (n + 2) / (2 pi)`, `s = a^(1/n) / max(|Cxy|, |Cz|)`,
/// `Cx = Cy = Cxy s`, `Cz' = Cz s`.
#[test]
fn hand_computed_conversions() {
    // (material, channel, kd, cxy, cz, n), each within 1e-13 relative.
    let cases = [
        // alum-bronze, green: Kd = 0.0625, ks = 0.193, Cxy = -0.579, Cz = 0.574, n = 630.
        // kd = 0.0625 / 3.14159265358979 = 0.0198943678864869;
        // a = 0.193 * 632 / 6.28318530717959 = 121.976 / 6.28318530717959 = 19.4130833385770;
        // a^(1/630) = exp(ln(19.4130833385770) / 630) = exp(2.96594 / 630) = 1.00471895210819;
        // s = 1.00471895210819 / 0.579 = 1.73526589310568 (|Cxy| > |Cz|);
        // Cx = -0.579 s = -1.00471895210819; Cz' = 0.574 s = 0.996042622642658.
        (
            "alum-bronze",
            Channel::Green,
            0.019894367886486917,
            -1.004718952108187,
            0.9960426226426584,
            630.0,
        ),
        // blue-fabric, green (a grazing lobe): Kd = 0.0184, ks = 0.0576, Cxy = -0.707,
        // Cz = 1.23e-10, n = 3.63.
        // kd = 0.0184 / pi = 0.00585690190578175;
        // a = 0.0576 * 5.63 / (2 pi) = 0.324288 / 6.28318530717959 = 0.0516120381853846;
        // a^(1/3.63) = exp(ln(0.0516120381853846) / 3.63) = exp(-2.96394 / 3.63)
        //            = 0.441963040996947;
        // s = 0.441963040996947 / 0.707 = 0.625124527577011;
        // Cx = -0.441963040996947; Cz' = 1.23e-10 s = 7.68903168919724e-11.
        (
            "blue-fabric",
            Channel::Green,
            0.0058569019057817484,
            -0.441963040996947,
            7.68903168919724e-11,
            3.63,
        ),
        // hematite, green (n > 10000): Kd = 0.0261, ks = 0.0698, Cxy = -0.577, Cz = 0.577,
        // n = 16600.
        // kd = 0.0261 / pi = 0.00830788802939694;
        // a = 0.0698 * 16602 / (2 pi) = 1158.8196 / 6.28318530717959 = 184.431867491773;
        // a^(1/16600) = exp(5.21727 / 16600) = 1.00031434337826;
        // s = 1.00031434337826 / 0.577 = 1.73364704225002;
        // Cx = -1.00031434337826; Cz' = 1.00031434337826.
        (
            "hematite",
            Channel::Green,
            0.008307888029396936,
            -1.000314343378263,
            1.000314343378263,
            16600.0,
        ),
        // pvc, red (ks > 1): Kd = 0.0383, ks = 1.07, Cxy = -0.584, Cz = 0.564, n = 450.
        // kd = 0.0383 / pi = 0.0121912686408392;
        // a = 1.07 * 452 / (2 pi) = 483.64 / 6.28318530717959 = 76.9736966769643;
        // a^(1/450) = exp(4.34346 / 450) = 1.00969887384684;
        // s = 1.00969887384684 / 0.584 = 1.72893642781994;
        // Cx = -1.00969887384684; Cz' = 0.564 s = 0.975120145290445.
        (
            "pvc",
            Channel::Red,
            0.012191268640839183,
            -1.0096988738468437,
            0.9751201452904449,
            450.0,
        ),
    ];
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-13 * b.abs();
    for (material, channel, kd, cxy, cz, n) in cases {
        let p = ngan_lafortune(material).to_params(channel);
        assert!(close(p.kd, kd), "{material}: kd {} vs {kd}", p.kd);
        let l = p.lobes[0];
        assert_eq!(p.lobes.len(), 1);
        assert!(close(l.cx, cxy) && close(l.cy, cxy), "{material}: {l:?}");
        assert!(close(l.cz, cz), "{material}: cz {} vs {cz}", l.cz);
        assert_eq!((l.n, l.pan_deg), (n, 0.0));
    }
    // The default channel is green.
    let ab = ngan_lafortune("alum-bronze");
    assert_eq!(ab.to_params_default(), ab.to_params(Channel::Green));
}

/// Ngan's normalised Lafortune as bbm's `ngan.h` and `lafortune.h` evaluate it, written here
/// independently of the conversion: `Kd / pi + ks (n + 2) / (2 pi) max(0, d)^n /
/// max(Cz^2, Cxy^2)^(n/2)` with `d = Cxy (ux vx + uy vy) + Cz uz vz`. The powers are grouped
/// as `(d / m)^n` with `m = sqrt(max(Cz^2, Cxy^2))`, because `m^n` underflows for large `n`
/// (0.577^n is below the smallest double from n = 1360 on; `literal` below is bbm's order).
fn ngan_value(l: &NganLafortune, k: usize, u: [f64; 3], v: [f64; 3]) -> f64 {
    let (kd, ks, cxy, cz, n) = (l.kd[k], l.ks[k], l.cxy[k], l.cz[k], l.n[k]);
    let d = cxy * (u[0] * v[0] + u[1] * v[1]) + cz * (u[2] * v[2]);
    let m = (cz * cz).max(cxy * cxy).sqrt();
    let lobe = if d > 0.0 {
        ks * (n + 2.0) / (2.0 * PI) * (d / m).powf(n)
    } else {
        0.0
    };
    kd / PI + lobe
}

fn ngan_literal(l: &NganLafortune, k: usize, u: [f64; 3], v: [f64; 3]) -> f64 {
    let (kd, ks, cxy, cz, n) = (l.kd[k], l.ks[k], l.cxy[k], l.cz[k], l.n[k]);
    let d = cxy * (u[0] * v[0] + u[1] * v[1]) + cz * (u[2] * v[2]);
    kd / PI
        + ks * d.max(0.0).powf(n) * (n + 2.0) * (0.5 / PI) / (cz * cz).max(cxy * cxy).powf(n * 0.5)
}

/// SplitMix64: a small deterministic generator, so the test needs no RNG API.
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

/// Direction pairs: half uniform on the hemisphere, half near the lobe's peak (the outgoing
/// direction along `(Cxy ux, Cxy uy, Cz uz)`, nudged by about `1/sqrt(n)` radians), where the
/// lobe dominates the constant term.
fn directions(
    l: &NganLafortune,
    k: usize,
    rng: &mut Rng,
    count: usize,
) -> Vec<([f64; 3], [f64; 3])> {
    let mut out = Vec::with_capacity(count);
    while out.len() < count {
        let u = rng.hemisphere(0.02);
        if out.len() % 2 == 0 {
            out.push((u, rng.hemisphere(0.0)));
            continue;
        }
        let peak = normalise([l.cxy[k] * u[0], l.cxy[k] * u[1], l.cz[k] * u[2] + 0.05]);
        let w = 2.0 / l.n[k].sqrt();
        let jitter = [
            w * (rng.next() - 0.5),
            w * (rng.next() - 0.5),
            w * (rng.next() - 0.5),
        ];
        let v = normalise([
            peak[0] + jitter[0],
            peak[1] + jitter[1],
            peak[2] + jitter[2],
        ]);
        if v[2] > 0.0 {
            out.push((u, v));
        }
    }
    out
}

fn rel(a: f64, b: f64) -> f64 {
    if a == b {
        0.0
    } else {
        (a - b).abs() / a.abs().max(b.abs())
    }
}

#[test]
fn conversion_matches_ngans_normalised_form_at_random_directions() {
    let file = load("ngan_lafortune.fit");
    let mut rng = Rng(0x5eed_2005);
    let mut worst_small = 0.0f64; // n <= 1000
    let mut worst_scaled = 0.0f64; // error / (n eps), all n
    let mut near_peak_checked = 0;
    let mut worst = (0.0f64, String::new(), 0.0f64); // (error, material, n)
    let mut within_1e12 = 0; // materials whose every evaluation is within 1e-12
    for fit in &file.fits {
        let l = NganLafortune::from_fit(fit).unwrap();
        let mut material_worst = 0.0f64;
        for (k, channel) in CHANNELS.into_iter().enumerate() {
            let p: BrdfParams = l.to_params(channel);
            let n = l.n[k];
            for (u, v) in directions(&l, k, &mut rng, 400) {
                let ours = p.value(u, v);
                let theirs = ngan_value(&l, k, u, v);
                assert!(
                    ours.is_finite() && theirs.is_finite(),
                    "{}: {ours} {theirs}",
                    l.material
                );
                let e = rel(ours, theirs);
                material_worst = material_worst.max(e);
                if e > worst.0 {
                    worst = (e, l.material.clone(), n);
                }
                // The exponent amplifies rounding: the converted coefficients (and d) carry
                // half an ulp each, which `x^n` turns into about n/2 ulps, so no set of f64
                // parameters can do better than about n eps. Below n = 1000 that is under
                // 1e-12 (checked); above, the error is bounded by 4 n eps.
                if n <= 1000.0 {
                    worst_small = worst_small.max(e);
                    assert!(
                        e <= 1e-12,
                        "{} ({k}): {ours} vs {theirs}, rel {e:e}",
                        l.material
                    );
                }
                let scaled = e / (n.max(1.0) * f64::EPSILON);
                worst_scaled = worst_scaled.max(scaled);
                assert!(
                    e <= 1e-12 || scaled <= 4.0,
                    "{} ({k}, n = {n}): {ours} vs {theirs}, rel {e:e} = {scaled} n eps",
                    l.material
                );
                if ours > 10.0 * l.kd[k] / PI {
                    near_peak_checked += 1;
                }
                // bbm's literal order of operations, where it does not underflow.
                let lit = ngan_literal(&l, k, u, v);
                if (l.cz[k] * l.cz[k]).max(l.cxy[k] * l.cxy[k]).powf(n * 0.5) > 1e-290 {
                    assert!(
                        rel(lit, theirs) <= 1e-12 || rel(lit, theirs) / (n * f64::EPSILON) <= 4.0
                    );
                }
            }
        }
        if material_worst <= 1e-12 {
            within_1e12 += 1;
        }
    }
    eprintln!(
        "worst relative error: {worst_small:e} for n <= 1000; {:e} overall ({}, n = {}), \
         {worst_scaled:.2} n eps; {within_1e12} of {} materials within 1e-12 everywhere; \
         {near_peak_checked} evaluations where the lobe is 9x the constant term or more",
        worst.0,
        worst.1,
        worst.2,
        file.fits.len()
    );
    assert!(near_peak_checked > 10_000, "{near_peak_checked}");
}

#[test]
fn materials_outside_the_table1_box() {
    // Green channel (the default): the five fits with n > 10000, nothing else; 81 of 86 inside.
    let file = load("ngan_lafortune.fit");
    let mut outside = Vec::new();
    for fit in &file.fits {
        let l = NganLafortune::from_fit(fit).unwrap();
        let v = table1_violations(&l.to_params_default());
        if !v.is_empty() {
            let why: Vec<String> = v.iter().map(ToString::to_string).collect();
            eprintln!("{}: {}", fit.material, why.join(", "));
            outside.push((fit.material.as_str(), v));
        }
        // In every channel the C's are within [-1.5, 1.5] and kd within [0, 1]: only n can
        // leave the box.
        for c in CHANNELS {
            for b in table1_violations(&l.to_params(c)) {
                assert_eq!(b.name, "lobe1.n", "{} ({c:?}): {b}", fit.material);
            }
        }
    }
    let names: Vec<&str> = outside.iter().map(|(m, _)| *m).collect();
    assert_eq!(
        names,
        [
            "brass",
            "hematite",
            "steel",
            "tungsten-carbide",
            "specular-violet-phenolic"
        ]
    );
    assert_eq!(file.fits.len() - outside.len(), 81);
    for (m, v) in &outside {
        assert_eq!(v.len(), 1, "{m}");
        assert_eq!(v[0].name, "lobe1.n");
        assert!(v[0].value > 10000.0);
    }
    // validate() agrees on the first violation.
    let hem = ngan_lafortune("hematite").to_params_default();
    assert!(
        hem.validate()
            .unwrap_err()
            .to_string()
            .starts_with("lobe1.n = 16600")
    );
    ngan_lafortune("alum-bronze")
        .to_params_default()
        .validate()
        .unwrap();
}

#[test]
fn conversion_refuses_what_it_cannot_represent() {
    let ward = load("ngan_ward.fit");
    let e = NganLafortune::from_fit(&ward.fits[0]).unwrap_err();
    assert!(matches!(e, ConvertError::WrongModel { .. }));
    assert_eq!(
        e.to_string(),
        "blue-acrylic (line 3): model `NganWard`: expected `NganLafortune`"
    );
    let one = |params: &str| {
        let text = format!("m = NganLafortune({params})");
        let file = parse_fits(&text, "t.fit").unwrap();
        NganLafortune::from_fit(&file.fits[0]).map(|l| l.to_params_default())
    };
    let ok = one("albedo = [0, 0, 0], Cxy = -1, Cz = 1, sharpness = 5").unwrap();
    assert_eq!(ok.kd, 0.0); // no Lambertian term
    assert_eq!(ok.value([0.0, 0.0, 1.0], [0.0, 0.0, 1.0]), 0.0); // ks = 0: a zero lobe
    let e = one("albedo = 1, Cz = 1, sharpness = 5")
        .unwrap_err()
        .to_string();
    assert_eq!(e, "m (line 1): no `Cxy` parameter: expected the lobe's Cxy");
    let e = one("albedo = [1, -1, 1], Cxy = -1, Cz = 1, sharpness = 5").unwrap_err();
    assert_eq!(
        e.to_string(),
        "m (line 1): albedo[green] = -1: expected a finite value >= 0"
    );
    let e = one("albedo = 1, Cxy = -1, Cz = 1, sharpness = 0").unwrap_err();
    assert!(
        e.to_string()
            .contains("sharpness[red] = 0: expected a finite value > 0")
    );
    let e = one("albedo = 1, Cxy = 0, Cz = 0, sharpness = 2").unwrap_err();
    assert!(e.to_string().contains("expected Cxy or Cz not 0"));
}

/// SHA-256 (FIPS 180-4), enough to check the data against the README's sums.
fn sha256(data: &[u8]) -> String {
    const K: [u32; 64] = [
        0x428a2f98, 0x71374491, 0xb5c0fbcf, 0xe9b5dba5, 0x3956c25b, 0x59f111f1, 0x923f82a4,
        0xab1c5ed5, 0xd807aa98, 0x12835b01, 0x243185be, 0x550c7dc3, 0x72be5d74, 0x80deb1fe,
        0x9bdc06a7, 0xc19bf174, 0xe49b69c1, 0xefbe4786, 0x0fc19dc6, 0x240ca1cc, 0x2de92c6f,
        0x4a7484aa, 0x5cb0a9dc, 0x76f988da, 0x983e5152, 0xa831c66d, 0xb00327c8, 0xbf597fc7,
        0xc6e00bf3, 0xd5a79147, 0x06ca6351, 0x14292967, 0x27b70a85, 0x2e1b2138, 0x4d2c6dfc,
        0x53380d13, 0x650a7354, 0x766a0abb, 0x81c2c92e, 0x92722c85, 0xa2bfe8a1, 0xa81a664b,
        0xc24b8b70, 0xc76c51a3, 0xd192e819, 0xd6990624, 0xf40e3585, 0x106aa070, 0x19a4c116,
        0x1e376c08, 0x2748774c, 0x34b0bcb5, 0x391c0cb3, 0x4ed8aa4a, 0x5b9cca4f, 0x682e6ff3,
        0x748f82ee, 0x78a5636f, 0x84c87814, 0x8cc70208, 0x90befffa, 0xa4506ceb, 0xbef9a3f7,
        0xc67178f2,
    ];
    let mut h: [u32; 8] = [
        0x6a09e667, 0xbb67ae85, 0x3c6ef372, 0xa54ff53a, 0x510e527f, 0x9b05688c, 0x1f83d9ab,
        0x5be0cd19,
    ];
    let mut msg = data.to_vec();
    msg.push(0x80);
    while msg.len() % 64 != 56 {
        msg.push(0);
    }
    msg.extend_from_slice(&((data.len() as u64) * 8).to_be_bytes());
    for block in msg.chunks(64) {
        let mut w = [0u32; 64];
        for (i, c) in block.chunks(4).enumerate() {
            w[i] = u32::from_be_bytes([c[0], c[1], c[2], c[3]]);
        }
        for i in 16..64 {
            let s0 = w[i - 15].rotate_right(7) ^ w[i - 15].rotate_right(18) ^ (w[i - 15] >> 3);
            let s1 = w[i - 2].rotate_right(17) ^ w[i - 2].rotate_right(19) ^ (w[i - 2] >> 10);
            w[i] = w[i - 16]
                .wrapping_add(s0)
                .wrapping_add(w[i - 7])
                .wrapping_add(s1);
        }
        let mut s = h;
        for i in 0..64 {
            let e = s[4];
            let a = s[0];
            let t1 = s[7]
                .wrapping_add(e.rotate_right(6) ^ e.rotate_right(11) ^ e.rotate_right(25))
                .wrapping_add((e & s[5]) ^ (!e & s[6]))
                .wrapping_add(K[i])
                .wrapping_add(w[i]);
            let t2 = (a.rotate_right(2) ^ a.rotate_right(13) ^ a.rotate_right(22))
                .wrapping_add((a & s[1]) ^ (a & s[2]) ^ (s[1] & s[2]));
            s = [
                t1.wrapping_add(t2),
                a,
                s[1],
                s[2],
                s[3].wrapping_add(t1),
                s[4],
                s[5],
                s[6],
            ];
        }
        for (x, y) in h.iter_mut().zip(s) {
            *x = x.wrapping_add(y);
        }
    }
    h.iter().map(|x| format!("{x:08x}")).collect()
}

#[test]
fn data_files_match_the_readme_sums() {
    assert_eq!(
        sha256(b"abc"),
        "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"
    );
    let readme = std::fs::read_to_string(data_dir().join("README.md")).unwrap();
    let mut listed = Vec::new();
    for line in readme.lines() {
        let cells: Vec<&str> = line.split('|').map(str::trim).collect();
        // | `file` | bytes | `sha256` |
        let is_data =
            cells.len() == 5 && (cells[1].ends_with(".fit`") || cells[1] == "`LICENSE-bbm`");
        if is_data {
            let name = cells[1].trim_matches('`');
            let sum = cells[3].trim_matches('`');
            let bytes = std::fs::read(data_dir().join(name)).unwrap();
            assert_eq!(cells[2], bytes.len().to_string(), "{name}");
            assert_eq!(sha256(&bytes), sum, "{name}");
            listed.push(name.to_string());
        }
    }
    let mut expected: Vec<String> = FIT_FILES.iter().map(|s| s.to_string()).collect();
    expected.push("LICENSE-bbm".into());
    listed.sort();
    expected.sort();
    assert_eq!(listed, expected);
}

#[test]
fn docs_tables_are_current() {
    let doc = std::fs::read_to_string(repo().join("docs/published-fits.md")).unwrap();
    let begin = "<!-- generated: begin -->\n";
    let end = "<!-- generated: end -->";
    let start = doc.find(begin).expect("no begin marker") + begin.len();
    let stop = doc.find(end).expect("no end marker");
    let now = report_markdown(&data_dir()).unwrap();
    assert!(
        doc[start..stop] == now,
        "docs/published-fits.md is out of date: replace its generated part with the output of \
         `cargo run -p brdf-model --example published_fits`"
    );
}
