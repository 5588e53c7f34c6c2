//! Tests of the fit: the polish, the dead-lobe report, widened bounds, refusals.

use super::*;

/// The Lafortune model with `lobes` anisotropic lobes in log1p coordinates, nothing fixed.
fn anisotropic_lafortune(lobes: usize) -> ModelSpec {
    model_spec(
        Surface::Cli,
        FamilyRef::lafortune(),
        lobes,
        LobeKind::Anisotropic,
        ExponentCoord::Log1p,
        [],
    )
    .unwrap()
}

fn request(seed: u64) -> FitRequest {
    FitRequest {
        model: anisotropic_lafortune(1),
        algorithm: algorithm_config(
            Surface::Cli,
            "aed",
            [("phi".to_string(), toml::Value::Float(1.2))],
        )
        .unwrap(),
        seed,
        cpu_seconds: 30.0,
        target: 0.02,
        kernel: Kernel::Auto,
        descent: sls::DescentModel::Default,
        polish: true,
        progress: FitProgress::Quiet,
        surface: Surface::Cli,
    }
}

fn data() -> Arc<DataSet> {
    let p = brdf_model::named_params("tuning").unwrap();
    Arc::new(brdf_model::synthetic(&p, 500, 0.0, 4))
}

#[test]
fn the_same_seed_gives_the_same_fit() {
    let a = fit(data(), &request(7), None).unwrap();
    let b = fit(data(), &request(7), None).unwrap();
    assert_eq!(a.result.stop, StopReason::Target);
    assert!(a.rmse <= 0.02);
    assert_eq!(a.result.without_clock(), b.result.without_clock());
    assert_eq!(a.params, b.params);
}

#[test]
fn a_raised_interrupt_ends_the_fit() {
    let flag = Arc::new(AtomicBool::new(true));
    let e = fit(data(), &request(7), Some(flag)).unwrap_err();
    assert!(matches!(e, FitError::Interrupted), "{e}");
}

#[test]
fn bad_requests_say_which_flag() {
    let phix = || [("phix".to_string(), toml::Value::Integer(1))];
    let e = algorithm_config(Surface::Cli, "aed", phix());
    assert!(
        e.unwrap_err()
            .to_string()
            .starts_with("--algorithm/--set: unknown field `phix`")
    );
    let e = model_spec(
        Surface::Cli,
        FamilyRef::lafortune(),
        0,
        LobeKind::Isotropic,
        ExponentCoord::Raw,
        [],
    );
    assert_eq!(e.unwrap_err().to_string(), "--lobes 0: expected 1 to 64");
    assert_eq!(
        check_budget(Surface::Cli, 0.0, 0.0)
            .unwrap_err()
            .to_string(),
        "--cpu-seconds 0: expected a positive number"
    );
    assert!(
        check_budget(Surface::Cli, 1.0, -1.0)
            .unwrap_err()
            .is_input_error()
    );
    let mut r = request(1);
    r.model.fixed.insert("lobe2.n".into(), 1.0);
    assert!(fit(data(), &r, None).unwrap_err().is_input_error());
    let twice = [("kd".to_string(), 0.1), ("kd".to_string(), 0.2)];
    let e = model_spec(
        Surface::Cli,
        FamilyRef::lafortune(),
        1,
        LobeKind::Isotropic,
        ExponentCoord::Raw,
        twice,
    )
    .unwrap_err();
    assert_eq!(
        e.to_string(),
        "--fix kd: given twice (0.1 and 0.2); fix each parameter once"
    );
    let fs = FileSpec {
        path: "x.csv".into(),
        format: None,
        wavelength: None,
        channel: None,
        param_out: None,
        max_value: Some(f64::NAN),
        drop_negative: false,
        drop_below_horizon: true,
    };
    let e = load_data(&fs).unwrap_err();
    assert!(
        e.to_string()
            .starts_with("--max-value NaN: expected a finite number"),
        "{e}"
    );
}

/// The search stops where its budget ends; the polish descends from there until a
/// full-data descent gains nothing, so one more descent finds nothing to gain.
#[test]
fn the_polished_fit_is_at_rest() {
    let p = brdf_model::named_params("cross").unwrap();
    let data = Arc::new(brdf_model::synthetic(&p, 2000, 0.05, 3));
    let mut r = request(1);
    r.model = anisotropic_lafortune(2);
    r.target = 0.0;
    r.cpu_seconds = 0.3;
    let fit = fit(data.clone(), &r, None).unwrap();
    let polish = fit.polish.unwrap();
    assert!(polish.rmse_after <= polish.rmse_before, "{polish:?}");
    assert!((fit.rmse - polish.rmse_after).abs() <= 1e-12 * fit.rmse);
    let objective = sls::BrdfObjective::new(data, fit.layout.clone());
    for robust in [false, true] {
        let gain = one_more_descent_gain(&objective, &fit.x, robust);
        assert!(gain < 1e-10, "one more descent gained {gain:e} relative");
    }
}

/// The relative gain of one more full-data descent from `x`, with the searches' solver
/// settings or (`robust`) the library's robust preset.
fn one_more_descent_gain(objective: &sls::BrdfObjective, x: &[f64], robust: bool) -> f64 {
    let budget = sls::Budget {
        cpu_seconds: None,
        sample_evaluations: Some(u64::MAX),
    };
    let mut cx = TrialContext::new(objective, 0, budget, f64::NEG_INFINITY);
    if robust {
        brdf_best_known::polish::use_robust_solver(&mut cx);
    }
    let mut x = x.to_vec();
    let before = cx.evaluate(&x).unwrap();
    let limits = sls::DescentLimits::default();
    cx.descend(&mut x, sls::Rows::Full, limits).unwrap();
    (before - cx.evaluate(&x).unwrap()) / before
}

/// Issue 45, item 14: on noisy cross data (two lobes, sigma 0.1, seed 2) a 1 CPU s search
/// (seed 2) left one lobe dead at this point. The old polish (the searches' solver settings,
/// stop on the first descent without gain) ended where it started, at RMSE 0.1173880771,
/// after two descents: N2FB's short singular test ends each after one iteration. The robust
/// preset reaches 0.1173340852 (as `--diagnose`'s refit), and the polish stops only where
/// the solver says the point is at rest.
#[test]
fn the_polish_ends_where_the_robust_solver_rests() {
    let p = brdf_model::named_params("cross").unwrap();
    let data = Arc::new(brdf_model::synthetic(&p, 10000, 0.1, 2));
    let layout = brdf_model::Layout::builder(&[LobeKind::Anisotropic; 2])
        .build()
        .unwrap();
    let stuck = brdf_model::BrdfParams {
        kd: 0.16437487608013898,
        lobes: vec![
            brdf_model::Lobe {
                cx: 0.8160035438444018,
                cy: -0.9961479772216264,
                cz: 0.9714325795795584,
                n: 21.69737621619952,
                pan_deg: 45.58350892913821,
            },
            brdf_model::Lobe {
                cx: 0.2666299890040651,
                cy: -0.6967513194276912,
                cz: -1.5,
                n: 1661.1383828818568,
                pan_deg: -51.05870980303395,
            },
        ],
    };
    let objective = sls::BrdfObjective::new(data, layout.clone());
    let result = TrialResult {
        stop: StopReason::CpuBudget,
        reached_at: None,
        ended_at: sls::Stamp::default(),
        best_rmse: 0.1173880771,
        best_x: layout.encode(stuck),
        trace: vec![],
        counters: vec![],
        failure: None,
    };
    let (x, p) = polish(&objective, &result, None).unwrap();
    assert!((p.rmse_before - 0.1173880771).abs() < 1e-9, "{p:?}");
    assert!(p.rmse_after < 0.11733409, "{p:?}");
    assert!(p.rest.at_rest, "{p:?}");
    let gain = one_more_descent_gain(&objective, &x, true);
    assert!(
        gain < 1e-12,
        "one more robust descent gained {gain:e} relative"
    );
    // Its second lobe (cz = -1.5: d < 0 on every sample) is dead, the first is not.
    let used = brdf_best_known::lobe_use::lobe_use(&layout.decode(&x), objective.data());
    assert!(!used[0].dead && used[1].dead, "{used:?}");
}

/// Issue 45, item 17: a sharp lobe (n = 16,600, as Ngan et al.'s fits of steel reach)
/// sampled near the mirror direction. In Table 1's box the fit stops at n = 10,000; with
/// `--bounds lobe1.n=0,20000` it finds the exponent.
#[test]
fn bounds_widen_an_exponent_beyond_table_1() {
    use rand::{RngExt, SeedableRng};
    let truth = brdf_model::BrdfParams {
        kd: 0.05,
        lobes: vec![brdf_model::Lobe::isotropic(-1.0, 1.0, 16600.0)],
    };
    let mut rng = rand_pcg::Pcg64::seed_from_u64(5);
    let mut data = DataSet::new();
    for _ in 0..400 {
        let u = brdf_model::uniform_hemisphere(&mut rng);
        let (a, b) = (0.02 * rng.random::<f64>(), 0.02 * rng.random::<f64>());
        let v = [-u[0] + a, -u[1] + b, u[2]];
        let nv = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        let v = [v[0] / nv, v[1] / nv, v[2] / nv];
        data.push(u, v, truth.value(u, v));
    }
    let data = Arc::new(data);
    let iso = |bounds: Vec<(String, [f64; 2])>| {
        let spec = model_spec(
            Surface::Cli,
            FamilyRef::lafortune(),
            1,
            LobeKind::Isotropic,
            ExponentCoord::Log1p,
            [],
        )
        .unwrap();
        with_bounds(Surface::Cli, spec, bounds)
    };
    let mut r = request(1);
    r.algorithm = algorithm_config(Surface::Cli, "rpls", []).unwrap();
    r.cpu_seconds = 2.0;
    r.target = 1e-9;
    r.model = iso(vec![]).unwrap();
    let boxed = fit(data.clone(), &r, None).unwrap();
    let at_bound = boxed.params.get("lobe1.n").unwrap();
    assert!((at_bound / 10000.0 - 1.0).abs() < 1e-12, "n = {at_bound}");
    r.model = iso(vec![("lobe1.n".into(), [0.0, 20000.0])]).unwrap();
    let wide = fit(data, &r, None).unwrap();
    let n = wide.params.get("lobe1.n").unwrap();
    assert!(
        (n / 16600.0 - 1.0).abs() < 1e-6,
        "n = {n}, RMSE {}",
        wide.rmse
    );
    assert!(
        wide.rmse < 1e-3 * boxed.rmse,
        "{} vs {}",
        wide.rmse,
        boxed.rmse
    );
    // Beyond the widest exponent, or another parameter beyond its box: refused, naming
    // the flag and the bound; a parameter given twice too.
    let e = iso(vec![("lobe1.n".into(), [0.0, 2e6])]).unwrap_err();
    assert!(
        e.to_string()
            .starts_with("--bounds lobe1.n=0,2000000: bounds [0, 2000000]")
            && e.to_string().contains("[0, 1e6]"),
        "{e}"
    );
    let e = iso(vec![("kd".into(), [0.0, 2.0])]).unwrap_err();
    assert!(e.to_string().contains("its box [0, 1]"), "{e}");
    let twice = vec![
        ("lobe1.n".into(), [0.0, 2e4]),
        ("lobe1.n".into(), [0.0, 3e4]),
    ];
    assert!(iso(twice).unwrap_err().to_string().contains("given twice"));
}

/// Issue 45, item 11: a repeated setting, a budget above the spec's limit and fewer
/// samples than the free parameters + 1 were accepted (the last two ran until killed or
/// fitted an undetermined model).
#[test]
fn repeated_settings_endless_budgets_and_tiny_data_are_refused() {
    let phi = |v: f64| ("phi".to_string(), toml::Value::Float(v));
    let e = algorithm_config(Surface::Cli, "aed", [phi(1.4), phi(2.0)]).unwrap_err();
    assert_eq!(
        e.to_string(),
        "--algorithm/--set: `phi` given twice (1.4 and 2.0); set each setting once"
    );
    let kind = ("kind".to_string(), toml::Value::String("rpls".into()));
    let e = algorithm_config(Surface::Cli, "aed", [kind]).unwrap_err();
    assert!(e.to_string().starts_with("--set kind="), "{e}");
    let e = check_budget(Surface::Cli, 1e300, 0.0).unwrap_err();
    assert_eq!(
        e.to_string(),
        "--cpu-seconds 1e300: at most 1e7 CPU seconds (MAX_CPU_SECONDS, the limit of a \
         spec's `budget.cpu_seconds`)"
    );
    assert!(check_budget(Surface::Cli, 1e7, 0.0).is_ok());
    let p = brdf_model::named_params("tuning").unwrap();
    let mut r = request(1);
    r.cpu_seconds = 0.1;
    for (n, ok) in [(1, false), (6, false), (7, true)] {
        let data = Arc::new(brdf_model::synthetic(&p, n, 0.0, 4));
        match fit(data, &r, None) {
            Ok(_) => assert!(ok, "{n} samples accepted"),
            Err(e) => {
                assert!(!ok, "{n} samples: {e}");
                assert!(e.is_input_error());
                assert!(
                    e.to_string().contains(&format!(
                        "has {n} sample(s); a fit of 6 free parameters needs at least 7"
                    )),
                    "{e}"
                );
            }
        }
    }
}

/// Issue 45, item 12: a model with every parameter fixed ran a search that evaluated no
/// candidate and exited 1 saying the data values were too large.
#[test]
fn nothing_free_is_refused_up_front() {
    let mut r = request(1);
    r.model = model_spec(
        Surface::Cli,
        FamilyRef::lafortune(),
        1,
        LobeKind::Isotropic,
        ExponentCoord::Log1p,
        [
            ("kd".to_string(), 0.1),
            ("lobe1.cxy".to_string(), -1.0),
            ("lobe1.cz".to_string(), 1.0),
            ("lobe1.n".to_string(), 20.0),
        ],
    )
    .unwrap();
    let e = fit(data(), &r, None).unwrap_err();
    assert!(e.is_input_error(), "{e}");
    assert!(
        e.to_string()
            .starts_with("every parameter is fixed (all 4): nothing to fit"),
        "{e}"
    );
}

#[test]
fn no_candidate_says_why() {
    let huge = DataSet::from_columns([
        vec![0.0; 50],
        vec![0.0; 50],
        vec![1.0; 50],
        vec![0.3; 50],
        vec![0.0; 50],
        vec![0.95; 50],
        vec![1e300; 50],
    ])
    .unwrap();
    let mut r = request(1);
    r.cpu_seconds = 0.5;
    let e = fit(Arc::new(huge), &r, None).unwrap_err().to_string();
    assert!(e.contains("every candidate's RMSE overflowed"), "{e}");
    r.cpu_seconds = 1e-9;
    r.model = anisotropic_lafortune(64);
    let e = fit(data(), &r, None).unwrap_err().to_string();
    assert!(e.contains("ended before the first evaluation"), "{e}");
    assert!(
        e.contains("500 samples with 321 free parameters took"),
        "{e}"
    );
}

#[test]
fn a_read_error_names_the_file_once() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("missing.csv");
    let fs = FileSpec {
        path: path.clone(),
        format: None,
        wavelength: None,
        channel: None,
        param_out: None,
        max_value: None,
        drop_negative: false,
        drop_below_horizon: true,
    };
    let m = load_data(&fs).unwrap_err().to_string();
    let shown = path.display().to_string();
    assert!(m.starts_with(&format!("reading {shown}: ")), "{m}");
    assert_eq!(m.matches(&shown).count(), 1, "{m}");
}

#[test]
fn python_callers_read_their_keyword_arguments() {
    let py = Surface::Python;
    let e = algorithm_config(py, "aed", [("phix".to_string(), toml::Value::Integer(1))]);
    assert!(
        e.unwrap_err()
            .to_string()
            .starts_with("algorithm/settings: unknown field `phix`")
    );
    let e = model_spec(
        py,
        FamilyRef::lafortune(),
        0,
        LobeKind::Isotropic,
        ExponentCoord::Raw,
        [],
    );
    assert_eq!(e.unwrap_err().to_string(), "lobes=0: expected 1 to 64");
    assert_eq!(
        check_budget(py, 0.0, 0.0).unwrap_err().to_string(),
        "cpu_seconds=0: expected a positive number"
    );
    assert_eq!(
        check_budget(py, 1.0, -1.0).unwrap_err().to_string(),
        "target=-1: expected >= 0"
    );
}

/// Issue 45, item 15: on the noisy cross data (2 lobes, sigma 0.1, seed 2) the default
/// algorithm reaches the optimum with both lobes alive for every seed of 1-20, where AED as in
/// the paper left a lobe dead in 9 of 20 (the measurement in [`DEFAULT_ALGORITHM`]'s docs).
#[test]
fn the_default_algorithm_keeps_both_lobes_of_the_cross_data() {
    let p = brdf_model::named_params("cross").unwrap();
    let data = Arc::new(brdf_model::synthetic(&p, 10000, 0.1, 2));
    let mut dead = Vec::new();
    for seed in 1..=20 {
        let mut r = request(seed);
        r.model = anisotropic_lafortune(2);
        r.algorithm = algorithm_config(Surface::Cli, DEFAULT_ALGORITHM, []).unwrap();
        r.cpu_seconds = 2.0;
        r.target = 0.0998;
        let out = fit(data.clone(), &r, None).unwrap();
        if !(out.rmse < 0.0998 && out.dead_lobes().is_empty()) {
            dead.push((seed, out.rmse, out.dead_lobes()));
        }
    }
    assert!(dead.is_empty(), "seeds, RMSE and dead lobes: {dead:?}");
}
