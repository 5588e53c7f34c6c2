//! Integration tests: a reduced stress run end to end, and the detectors themselves.

use brdf_model::{DataSet, Evaluator, Layout, LobeKind, named_params, synthetic};
use brdf_stress::{Sizes, StressOptions, kernels, run};

/// A reduced run (every section, small sizes): every check passes (the two defects it found
/// first, a spurious Jacobian overflow in brdf-model and a false relative-function convergence
/// on numerically dead lobes in bounded-lm, are fixed), the report renders, and its JSON
/// round-trips through serde_json.
/// Progress lines of the reduced run (a plain `fn` can only reach a static).
static PROGRESS: std::sync::Mutex<Vec<String>> = std::sync::Mutex::new(Vec::new());

fn record_progress(line: &str) {
    PROGRESS.lock().unwrap().push(line.to_string());
}

#[test]
fn reduced_run_passes_and_reports() {
    let data = synthetic(&named_params("tuning").unwrap(), 200, 0.01, 3);
    let opts = StressOptions {
        quick: true,
        data: vec![brdf_stress::NamedData {
            name: "tiny synthetic".into(),
            data,
        }],
        seed: 7,
        threads: Some(2),
        sizes: Some(Sizes {
            batches: 96,
            subsamples: 2,
            bootstrap: 8,
            starts: 2,
            synthetic_samples: 300,
        }),
        progress: Some(record_progress),
    };
    let report = run(&opts).unwrap();
    // One line per check group, in order, each with its time and the elapsed time.
    let lines = PROGRESS.lock().unwrap().clone();
    let groups = ["kernels", "NIST", "MGH", "BRDF hostile", "diagnostics"];
    assert_eq!(lines.len(), groups.len(), "{lines:?}");
    for (line, group) in lines.iter().zip(groups) {
        assert!(line.starts_with(&format!("stress: {group}")), "{line}");
        assert!(line.contains(" s elapsed)"), "{line}");
    }
    let failed: Vec<String> = report
        .failures()
        .iter()
        .map(|c| format!("{}: {}", c.name, c.measured))
        .collect();
    assert!(failed.is_empty(), "{failed:#?}");
    assert!(report.passed());
    assert_eq!(report.suite.failures().count(), 0);
    // Every kernel the CPU has, plus the libm yardstick, was measured, and the overflow path
    // was reached.
    assert_eq!(
        report.kernels.kernels.len(),
        brdf_model::Kernel::available().len() + 1
    );
    for k in &report.kernels.kernels {
        assert!(k.values > 1000, "{}: {}", k.kernel, k.values);
        assert!(k.overflow_batches > 0);
    }
    assert_eq!(report.suite.nist_total, 54);
    assert!(report.diagnostics.len() >= 3);
    let md = report.to_markdown();
    assert!(md.contains("## 1. Kernel accuracy") && md.contains("## 3. Fit diagnostics"));
    let json: serde_json::Value = serde_json::from_str(&report.to_json().unwrap()).unwrap();
    assert!(json["kernels"]["kernels"][0]["ulps_histogram"].is_array());
}

/// A value off by 1e-12 relative (about 4500 ulps), a NaN and a spurious +inf are all caught,
/// while the evaluator's own values pass.
#[test]
fn a_wrong_kernel_value_is_detected() {
    let layout = Layout::builder(&[LobeKind::Anisotropic, LobeKind::Isotropic])
        .build()
        .unwrap();
    let mut p = named_params("tuning").unwrap();
    p.lobes.push(brdf_model::Lobe::isotropic(0.4, 0.6, 5.0));
    let x = layout.encode(&p);
    let mut data = synthetic(&p, 300, 0.0, 11);
    // Residuals against zero data are the model values.
    let zero: Vec<f64> = vec![0.0; data.len()];
    data = DataSet::from_columns([
        data.u_x().to_vec(),
        data.u_y().to_vec(),
        data.u_z().to_vec(),
        data.v_x().to_vec(),
        data.v_y().to_vec(),
        data.v_z().to_vec(),
        zero,
    ])
    .unwrap();
    let mut ev = Evaluator::new(&layout);
    let mut f = vec![0.0; data.len()];
    assert!(ev.residuals(&x, &layout.prepare(&data), &mut f));
    let good = kernels::judge(&layout, &x, &data, &f);
    assert_eq!(good.class_mismatches, 0);
    assert!(good.max_normalised <= 1.0, "{good:?}");
    let i = (0..f.len()).max_by(|&a, &b| f[a].total_cmp(&f[b])).unwrap();
    let mut bad = f.clone();
    bad[i] *= 1.0 + 1e-12;
    let j = kernels::judge(&layout, &x, &data, &bad);
    assert!(j.max_normalised > 1.0 && j.max_ulps > 1000.0, "{j:?}");
    let mut bad = f.clone();
    bad[3] = f64::NAN;
    assert_eq!(kernels::judge(&layout, &x, &data, &bad).class_mismatches, 1);
    let mut bad = f;
    bad[5] = f64::INFINITY;
    assert_eq!(kernels::judge(&layout, &x, &data, &bad).class_mismatches, 1);
}

/// The identifiability warning appears for in-plane data through the public API.
#[test]
fn in_plane_data_warn_through_the_public_api() {
    let p = named_params("tuning").unwrap();
    let mut data = DataSet::new();
    for i in 0..200 {
        let ti = 0.01 + 1.4 * (i % 20) as f64 / 20.0;
        let to = -1.4 + 2.8 * (i / 20) as f64 / 10.0;
        let (u, v) = ([ti.sin(), 0.0, ti.cos()], [to.sin(), 0.0, to.cos()]);
        data.push(u, v, p.value(u, v));
    }
    let layout = Layout::builder(&[LobeKind::Anisotropic]).build().unwrap();
    let x = layout.encode(&p);
    let d = brdf_stress::diagnose(
        &layout,
        &data,
        &x,
        &brdf_stress::DiagnoseOptions {
            bootstrap: 4,
            ..Default::default()
        },
    )
    .unwrap();
    assert!(
        d.warnings.iter().any(|w| w.contains("Cx and Cy")),
        "{:?}",
        d.warnings
    );
    assert!(d.condition_number.is_infinite() || d.condition_number > 1e8);
    assert_eq!(d.sensitivity.len(), 3);
    assert!(d.bootstrap.is_some());
}
