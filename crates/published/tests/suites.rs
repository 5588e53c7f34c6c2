//! The named suites (`brdf_published::suite`): every material converts and lies inside its
//! family's bounds or is listed (and included only with a stated wider bound); each sampling
//! pattern's geometry (counts, angle ranges, the Cornell files' pairs, MERL's cells and their
//! reciprocity); seeded generation is reproducible and its noise is what it says; material
//! selections; errors for bad names; `docs/suites.md`'s generated listing is current.

use brdf_io::{Channel, Format, MerlBrdf};
use brdf_model::Filters;
use brdf_published::suite::{
    CORNELL_PAIRS, Inclusion, MERL_CELLS, Noise, Pair, SUITE_NAMES, Sampling, Selection,
    SuiteError, cornell_pairs, generate, listing_markdown, merl_cell, suite, suites,
};
use std::path::PathBuf;

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn angle_deg(a: [f64; 3], b: [f64; 3]) -> f64 {
    let d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    d.clamp(-1.0, 1.0).acos().to_degrees()
}

/// The half vector's angle from the normal, in degrees.
fn theta_h(u: [f64; 3], v: [f64; 3]) -> f64 {
    let h = [u[0] + v[0], u[1] + v[1], u[2] + v[2]];
    h[0].hypot(h[1]).atan2(h[2]).to_degrees()
}

fn unit(a: [f64; 3]) -> bool {
    ((a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt() - 1.0).abs() < 1e-14
}

#[test]
fn every_suite_has_86_materials_inside_its_bounds_or_listed() {
    assert_eq!(suites().len(), SUITE_NAMES.len());
    for (s, name) in suites().iter().zip(SUITE_NAMES) {
        assert_eq!(s.name(), name);
        assert_eq!(s.family().name(), s.family_name());
        for channel in Channel::ALL {
            let all = s.materials(channel).unwrap_or_else(|e| panic!("{e}"));
            assert_eq!(all.len(), 86, "{name} {channel}");
            let mut outside = Vec::new();
            for m in &all {
                assert_eq!(m.params.family().name(), s.family_name());
                // Inside the family's bounds, or inside them once the suite's widened.
                let widened = |n: &str| {
                    s.widened_bounds()
                        .iter()
                        .find(|w| w.0 == n)
                        .map(|w| (w.1, w.2))
                };
                m.params
                    .validate_within(widened)
                    .unwrap_or_else(|e| panic!("{name} {}: {e}", m.name));
                match m.inclusion(s) {
                    Inclusion::Inside => assert!(m.violations.is_empty()),
                    Inclusion::Widened(w) => {
                        assert_eq!(w, vec![("lobe1.n".to_string(), [0.0, 20000.0])]);
                        outside.push(m.name.clone());
                    }
                    Inclusion::Excluded(why) => panic!("{name} {}: excluded: {why}", m.name),
                }
            }
            if name == "ngan-lafortune" {
                // Only n leaves Table 1, for the same five materials in every channel (n is
                // shared by the channels).
                assert_eq!(
                    outside,
                    [
                        "brass",
                        "hematite",
                        "steel",
                        "tungsten-carbide",
                        "specular-violet-phenolic"
                    ],
                    "{channel}"
                );
                for m in all.iter().filter(|m| !m.violations.is_empty()) {
                    assert!(
                        m.violations
                            .iter()
                            .all(|v| v.name == "lobe1.n" && v.value > 10000.0)
                    );
                }
            } else {
                assert!(outside.is_empty(), "{name} {channel}: {outside:?}");
            }
        }
    }
    // The same 86 MERL materials in every suite.
    let names = |s: &str| -> Vec<String> {
        let m = suite(s).unwrap().materials(Channel::Green).unwrap();
        m.into_iter().map(|m| m.name).collect()
    };
    for s in SUITE_NAMES {
        assert_eq!(names(s), names("ngan-ward"), "{s}");
    }
}

#[test]
fn ggx_suite_is_the_documented_approximation() {
    let s = suite("ngan-ggx").unwrap();
    assert!(s.description().contains("APPROXIMATION"));
    assert!(s.description().contains("0.98"));
    let ct = suite("ngan-cook-torrance").unwrap();
    let a = s.material("gold-paint", Channel::Green).unwrap();
    let b = ct.material("gold-paint", Channel::Green).unwrap();
    assert_eq!(a.params.get("kd"), b.params.get("kd"));
    assert_eq!(a.params.get("lobe1.ks"), b.params.get("lobe1.ks"));
    assert_eq!(a.params.get("lobe1.f0"), b.params.get("lobe1.f0"));
    let ratio = a.params.get("lobe1.ax").unwrap() / b.params.get("lobe1.mx").unwrap();
    assert!((ratio - brdf_published::GGX_PER_BECKMANN).abs() < 1e-15);
}

#[test]
fn cornell_pattern_is_the_measured_files_geometry() {
    let pairs = cornell_pairs();
    assert_eq!(pairs.len(), CORNELL_PAIRS);
    let mut incident: Vec<i64> = pairs
        .iter()
        .map(|(u, _)| angle_deg(*u, [0.0, 0.0, 1.0]).round() as i64)
        .collect();
    incident.dedup();
    assert_eq!(incident, [10, 20, 30, 40, 50, 60, 70, 80]);
    for (u, v) in &pairs {
        assert!(unit(*u) && unit(*v));
        assert!(u[1] == 0.0 && u[0] > 0.0, "incident in the plane phi = 0");
        assert!(v[1] <= 1e-12, "exitant on the half circle phi in [-180, 0]");
        assert!(v[2] > 0.18 && angle_deg(*v, [0.0, 0.0, 1.0]) < 79.1);
        assert!(angle_deg(*u, *v) >= 17.0);
    }
    // The files' pairs, to their 6 decimals: all of them, and one more in the pattern.
    for file in ["krylon_blue.brdf", "acryl_blue.brdf"] {
        let path = repo().join("experiments/data").join(file);
        let (data, _) = brdf_io::read(
            &path,
            &Format::Cornell {
                wavelength_nm: 550.0,
            },
            &Filters::default(),
        )
        .unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(data.len(), 1439, "{file}");
        let close = |a: [f64; 3], b: [f64; 3]| a.iter().zip(b).all(|(x, y)| (x - y).abs() < 2e-6);
        let mut matched = vec![false; pairs.len()];
        for i in 0..data.len() {
            let k = pairs
                .iter()
                .position(|(u, v)| close(*u, data.u(i)) && close(*v, data.v(i)))
                .unwrap_or_else(|| panic!("{file}: pair {i} is not in the pattern"));
            assert!(!matched[k], "{file}: pair {i} twice");
            matched[k] = true;
        }
        let extra: Vec<_> = (0..pairs.len()).filter(|&k| !matched[k]).collect();
        assert_eq!(extra.len(), 1, "{file}");
        let (u, v) = pairs[extra[0]];
        assert_eq!(angle_deg(u, [0.0, 0.0, 1.0]).round(), 80.0);
        assert!((angle_deg(v, [0.0, 0.0, 1.0]) - 79.047).abs() < 1e-3);
        assert!((v[1].atan2(v[0]).to_degrees() + 175.0).abs() < 1e-9);
    }
    // A subset is seeded, distinct and in grid order.
    let a = Sampling::Cornell.directions(500, 7).unwrap();
    assert_eq!(a, Sampling::Cornell.directions(500, 7).unwrap());
    assert_ne!(a, Sampling::Cornell.directions(500, 8).unwrap());
    let idx: Vec<usize> = a
        .iter()
        .map(|p| pairs.iter().position(|q| q == p).unwrap())
        .collect();
    assert!(idx.windows(2).all(|w| w[0] < w[1]));
    assert_eq!(Sampling::Cornell.directions(1440, 3).unwrap(), pairs);
}

#[test]
fn merl_pattern_draws_distinct_cells_that_are_their_own_reciprocal() {
    // The count of cells above the horizon.
    let kept = (0..90 * 90 * 180)
        .filter(|&i| merl_cell(i).is_some())
        .count();
    assert_eq!(kept, MERL_CELLS);
    assert!(merl_cell(90 * 90 * 180).is_none());
    let table = MerlBrdf {
        dims: (90, 90, 180),
        table: Vec::new(),
    };
    let dirs = Sampling::Merl.directions(10_000, 1).unwrap();
    assert_eq!(dirs.len(), 10_000);
    let mut cells = Vec::new();
    let mut theta_h_max: f64 = 0.0;
    let mut phi_d_seen = [false; 180];
    for &(u, v) in &dirs {
        assert!(unit(u) && unit(v) && u[2] > 0.0 && v[2] > 0.0);
        let cell = table.index(u, v);
        // Reciprocity: (v, u) is the same cell of MERL's folded table.
        assert_eq!(table.index(v, u), cell);
        assert_eq!(merl_cell(cell), Some((u, v)), "the cell's own centre");
        cells.push(cell);
        theta_h_max = theta_h_max.max(theta_h(u, v));
        phi_d_seen[cell % 180] = true;
    }
    assert!(
        cells.windows(2).all(|w| w[0] < w[1]),
        "distinct, in grid order"
    );
    assert!(theta_h_max > 80.0 && theta_h_max < 90.0);
    assert!(phi_d_seen.iter().all(|&s| s), "every phi_d column drawn");
    // MERL's square-root grid: the first theta_h cell is (0.5/90)^2 90 degrees.
    let (u, v) = merl_cell(0).unwrap();
    let first = theta_h(u, v);
    assert!((first - 0.25 / 8100.0 * 90.0).abs() < 1e-12, "{first}");
    assert_eq!(dirs, Sampling::Merl.directions(10_000, 1).unwrap());
    assert_ne!(dirs, Sampling::Merl.directions(10_000, 2).unwrap());
}

#[test]
fn uniform_pattern_is_uniform_by_solid_angle_and_symmetric() {
    let dirs = Sampling::Uniform.directions(20_000, 5).unwrap();
    let n = dirs.len() as f64;
    let mean = |f: &dyn Fn(&Pair) -> f64| dirs.iter().map(f).sum::<f64>() / n;
    // Uniform by solid angle: cos theta uniform in [0, 1], mean 1/2, for u and v alike.
    for m in [mean(&|p| p.0[2]), mean(&|p| p.1[2])] {
        assert!((m - 0.5).abs() < 0.01, "{m}");
    }
    assert!(mean(&|p| p.0[2] - p.1[2]).abs() < 0.01);
    assert!(
        dirs.iter()
            .all(|(u, v)| unit(*u) && unit(*v) && u[2] >= 0.0 && v[2] >= 0.0)
    );
}

#[test]
fn generation_is_seeded_and_its_noise_is_relative_and_absolute() {
    let s = suite("ngan-ward").unwrap();
    let m = s.material("gold-metallic-paint", Channel::Green).unwrap();
    let none = Noise {
        relative: 0.0,
        absolute: 0.0,
    };
    for sampling in Sampling::ALL {
        let clean = generate(&m.params, sampling, 1000, none, 4).unwrap();
        let dirs = sampling.directions(1000, 4).unwrap();
        for (i, (u, v)) in dirs.iter().enumerate() {
            assert_eq!(
                (clean.u(i), clean.v(i)),
                (*u, *v),
                "{sampling}: directions first"
            );
            assert_eq!(clean.value(i), m.params.value(*u, *v));
        }
        let rel = Noise {
            relative: 0.05,
            absolute: 0.0,
        };
        let a = generate(&m.params, sampling, 1000, rel, 4).unwrap();
        assert_eq!(a, generate(&m.params, sampling, 1000, rel, 4).unwrap());
        assert_ne!(a, generate(&m.params, sampling, 1000, rel, 5).unwrap());
        let z: Vec<f64> = (0..a.len())
            .map(|i| (a.value(i) - clean.value(i)) / clean.value(i))
            .collect();
        let sd = (z.iter().map(|z| z * z).sum::<f64>() / z.len() as f64).sqrt();
        assert!((sd - 0.05).abs() < 0.005, "{sampling}: relative sd {sd}");
        let abs = Noise {
            relative: 0.0,
            absolute: 0.2,
        };
        let b = generate(&m.params, sampling, 1000, abs, 4).unwrap();
        let sd = ((0..b.len())
            .map(|i| (b.value(i) - clean.value(i)).powi(2))
            .sum::<f64>()
            / b.len() as f64)
            .sqrt();
        assert!((sd - 0.2).abs() < 0.02, "{sampling}: absolute sd {sd}");
    }
    // A widened Lafortune material generates finite values at every pattern.
    let lf = suite("ngan-lafortune").unwrap();
    let hematite = lf.material("hematite", Channel::Green).unwrap();
    assert!(matches!(hematite.inclusion(lf), Inclusion::Widened(_)));
    let noise = Noise {
        relative: 0.01,
        absolute: 0.0,
    };
    for sampling in Sampling::ALL {
        let d = generate(&hematite.params, sampling, 1440, noise, 1).unwrap();
        assert!(d.values().iter().all(|y| y.is_finite()));
    }
}

#[test]
fn selections() {
    let s = suite("ngan-lafortune").unwrap();
    let g = Channel::Green;
    assert_eq!(s.select(&Selection::All, g).unwrap().len(), 86);
    assert_eq!(s.select(&Selection::InBounds, g).unwrap().len(), 81);
    let names = vec!["steel".to_string(), "alum-bronze".to_string()];
    let picked = s.select(&Selection::Names(names), g).unwrap();
    assert_eq!(picked[0].name, "steel");
    assert_eq!(picked[1].name, "alum-bronze");
    let sample = Selection::Sample { count: 5, seed: 3 };
    let a = s.select(&sample, g).unwrap();
    assert_eq!(a.len(), 5);
    assert_eq!(a, s.select(&sample, g).unwrap());
    let b = s
        .select(&Selection::Sample { count: 5, seed: 4 }, g)
        .unwrap();
    assert_ne!(a, b);
    let all: Vec<String> = s
        .materials(g)
        .unwrap()
        .into_iter()
        .map(|m| m.name)
        .collect();
    let pos: Vec<usize> = a
        .iter()
        .map(|m| all.iter().position(|n| *n == m.name).unwrap())
        .collect();
    assert!(pos.windows(2).all(|w| w[0] < w[1]), "file order, distinct");
    assert_eq!(
        s.select(&Selection::Sample { count: 86, seed: 1 }, g)
            .unwrap()
            .len(),
        86
    );
    for count in [0, 87] {
        let e = s
            .select(&Selection::Sample { count, seed: 1 }, g)
            .unwrap_err();
        assert!(matches!(e, SuiteError::MaterialCount { .. }), "{e}");
    }
}

#[test]
fn bad_names_are_errors_listing_the_valid_ones() {
    let e = suite("ngan-nope").unwrap_err().to_string();
    for n in SUITE_NAMES {
        assert!(e.contains(n), "{e}");
    }
    let e = suite("ngan-ward")
        .unwrap()
        .material("gold", Channel::Green)
        .unwrap_err()
        .to_string();
    assert!(e.contains("no material `gold`"), "{e}");
    assert!(
        e.contains("gold-metallic-paint") && e.contains("alum-bronze"),
        "{e}"
    );
    let e = Sampling::from_name("grid").unwrap_err().to_string();
    assert!(e.contains("cornell, merl, uniform"), "{e}");
    for (sampling, n) in [
        (Sampling::Cornell, 1441),
        (Sampling::Merl, MERL_CELLS + 1),
        (Sampling::Uniform, 0),
    ] {
        let e = sampling.directions(n, 1).unwrap_err();
        assert!(matches!(e, SuiteError::SampleCount { .. }), "{e}");
    }
    let m = suite("ngan-ward")
        .unwrap()
        .material("steel", Channel::Red)
        .unwrap();
    for (relative, absolute) in [(-0.1, 0.0), (f64::NAN, 0.0), (0.0, 1e4), (11.0, 0.0)] {
        let noise = Noise { relative, absolute };
        let e = generate(&m.params, Sampling::Uniform, 10, noise, 1).unwrap_err();
        assert!(matches!(e, SuiteError::Noise { .. }), "{e}");
    }
}

#[test]
fn docs_suites_listing_is_current() {
    let doc = std::fs::read_to_string(repo().join("docs/suites.md")).unwrap();
    let (begin, end) = ("<!-- generated: begin -->\n", "<!-- generated: end -->");
    let start = doc.find(begin).expect("a generated part") + begin.len();
    let stop = doc.find(end).expect("the end of the generated part");
    let want = listing_markdown(Channel::Green).unwrap();
    assert!(
        doc[start..stop] == want,
        "docs/suites.md is out of date: replace its generated part with the output of \
         `cargo run -p brdf-published --example suites`"
    );
}
