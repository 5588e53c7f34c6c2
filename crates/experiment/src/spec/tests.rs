//! Tests of reading specs: parsing, expansion, errors naming key and line, fingerprints.

use super::*;

/// A spec with every key of the format (commented ones are the alternatives).
const EVERY_KEY: &str = r#"
name = "tuning-aed-sweep"      # optional; default: the spec file's stem
description = "free text"      # optional
seed = 1                       # master seed (trial seeds are derived from it)
trials = 50                    # trials per (instance, configuration)
threads = 2                    # optional default for --threads (default: all CPUs)
kernel = "auto"                # evaluation kernel: auto | avx512 | avx2 | portable | scalar

[budget]                       # at least one limit
cpu_seconds = 10.0             # CPU-time cutoff per trial (worker thread clock)
evaluations = 2e9              # optional sample-evaluation cutoff per trial

[[instance]]                   # one or more
name = "tuning"
targets = [0.11, 0.115, 0.12]  # trials run to the lowest; the others come from the traces
#                              # an entry { relative = 0.01 } is 1% above the best-known RMSE
[instance.synthetic]           # either synthetic ...
params = "tuning"              # "tuning", "cross", "paper-bluepaint", "pbrt-bluepaint", or
                               # { kd = 0.15, lobes = [{ cx = -1, cy = 0.8, cz = 0.96, n = 20, pan_deg = 45 }] }
samples = 10000                # default 10000
sigma = 0.1                    # Gaussian noise; default 0
seed = 7                       # instance seed; default 1
# [instance.file]              # ... or a data file
# path = "data/krylon_blue.brdf"   # relative to this spec file
# format = "cornell"           # cornell | csv | merl (default: from the extension)
# wavelength = 550             # Cornell: nm (default 550)
# channel = "green"            # MERL: red | green | blue (default green)
# max_value = 1.0              # drop values above (the paper used 1)
# drop_negative = false        # default false (noisy data has negative values)
# drop_below_horizon = true    # default true
[instance.model]               # the model shape to fit (all optional)
lobes = 1                      # default: the synthetic params' lobe count, else 1
kind = "anisotropic"           # or "isotropic" (Cxy, Cz, n; no pan)
# kinds = ["anisotropic", "isotropic"]   # per lobe, overrides lobes/kind
exponent = "log1p"             # optimiser coordinate of n: "log1p" (default) or "raw"
starts = "coordinate"          # exponent in random starts: "coordinate" (default: uniform in
                               # the coordinate above), "uniform" (in n), "log-uniform"
fixed = { "lobe1.pan" = 45.0 } # parameters held fixed
bounds = { "lobe1.n" = [0.0, 200.0] }   # bounds overriding Table 1

[[algorithm]]                  # one or more
label = "AED"                  # default: the kind in capitals
kind = "aed"                   # aed | aers | rpls | ds | sa | sals | avg | asa (sls::AlgorithmConfig)
phi = 1.4                      # any parameter of that algorithm; missing = paper default
descent = "default"            # the descents' solver: default | gauss-newton | n2fb (the
                               # paper's PORT N2FB configuration); not sweepable
[algorithm.sweep]              # optional: one configuration per value (cartesian product)
rho0 = [10, 25, 50]            # a list, or
# phi = { from = 1.0, to = 2.0, steps = 5, scale = "linear" }   # linear | log; integer
#                              # endpoints give integer values

[plots]                        # optional
draw = ["rtd", "rtd-evaluations", "sweep", "trace", "scatter", "error-time", "ecdf"]
formats = ["png", "svg"]
trace_trials = 3               # trials per configuration in the trace plot
error_range = [0.11, 0.2]      # target range of the error-time and ECDF plots
error_steps = 25

[stats]                        # optional
bootstrap = 1000               # bootstrap resamples for the ERT
"#;

const MINI: &str = r#"
name = "mini"
seed = 3
trials = 4

[budget]
cpu_seconds = 0.5

[[instance]]
name = "tuning"
targets = [0.12, 0.11]
[instance.synthetic]
params = "tuning"
samples = 500
sigma = 0.1

[[algorithm]]
label = "AED"
kind = "aed"
phi = 1.4
[algorithm.sweep]
rho0 = [10, 25]

[[algorithm]]
kind = "rpls"
"#;

fn parse(text: &str) -> Result<Spec, SpecError> {
    Spec::parse(text, "t.toml", "t", Path::new("/base"))
}

#[test]
fn parses_and_expands() {
    let s = parse(MINI).unwrap();
    assert_eq!(s.name, "mini");
    assert_eq!(s.instances[0].targets, vec![0.11, 0.12]);
    assert_eq!(s.instances[0].model.kinds, vec![LobeKind::Anisotropic]);
    let labels = s.config_labels();
    assert_eq!(labels, vec!["AED rho0=10", "AED rho0=25", "RPLS"]);
    let aed = s.configurations[0]
        .algorithm
        .downcast_ref::<sls::AedConfig>();
    assert_eq!(aed.map(|c| (c.rho0, c.phi)), Some((10, 1.4)));
    assert_eq!(s.configurations[1].swept, vec![("rho0".to_string(), 25.0)]);
    assert_eq!(s.trials_plan().len(), 12);
    let plan = s.describe(2);
    assert!(plan.contains("12 trials"), "{plan}");
    assert!(plan.contains("6.0 s CPU"), "{plan}");
}

#[test]
fn every_key_example_parses() {
    // One spec using every key of the format (docs/experiment-format.md) at once.
    let s = parse(EVERY_KEY).unwrap_or_else(|e| panic!("{e}\n{EVERY_KEY}"));
    assert_eq!(s.name, "tuning-aed-sweep");
    assert_eq!(
        s.config_labels(),
        vec!["AED rho0=10", "AED rho0=25", "AED rho0=50"]
    );
    assert_eq!(s.instances[0].model.fixed.get("lobe1.pan"), Some(&45.0));
    assert_eq!(s.budget.sample_evaluations, Some(2_000_000_000));
}

#[test]
fn default_experiment_parses() {
    let s = Spec::default_experiment();
    assert!(s.configurations.len() >= 3);
}

#[test]
fn range_sweeps_linear_log_integer() {
    let text = MINI.replace(
        "rho0 = [10, 25]",
        "phi = { from = 1.0, to = 2.0, steps = 3 }\nrho0 = { from = 10, to = 1000, steps = 3, scale = \"log\" }",
    );
    let s = parse(&text).unwrap();
    let labels = s.config_labels();
    assert_eq!(labels.len(), 10, "{labels:?}");
    assert_eq!(labels[0], "AED phi=1 rho0=10");
    assert_eq!(labels[1], "AED phi=1 rho0=100");
    assert_eq!(labels[4], "AED phi=1.5 rho0=100");
    assert_eq!(labels[8], "AED phi=2 rho0=1000");
    assert_eq!(format_value(1.2), "1.2");
    assert_eq!(format_value(0.0123456), "0.01235");
    assert_eq!(format_value(25.0), "25");
}

fn err(text: &str) -> String {
    parse(text).unwrap_err().to_string()
}

#[test]
fn unknown_keys_name_key_and_line() {
    // Top level: toml's own error names the key and the line.
    let e = err(&MINI.replace("trials = 4", "trials = 4\ntrails = 5"));
    assert!(e.contains("trails") && e.contains("line 5"), "{e}");
    // Inside an instance.
    let e = err(&MINI.replace("sigma = 0.1", "sigma = 0.1\nnoise = 2"));
    assert!(e.contains("noise") && e.contains("line 16"), "{e}");
    // Inside an algorithm (deserialised by sls): the key's own line.
    let e = err(&MINI.replace("phi = 1.4", "phi = 1.4\nphy = 2.0"));
    assert!(e.contains("phy") && e.contains("t.toml:21:"), "{e}");
}

#[test]
fn bad_values_name_key_and_line() {
    let e = err(&MINI.replace("phi = 1.4", "phi = \"fast\""));
    assert!(e.contains("`phi`") && e.contains("t.toml:20:"), "{e}");
    let e = err(&MINI.replace("phi = 1.4", "phi = 0.5"));
    assert!(e.contains("`phi`") && e.contains("t.toml:20:"), "{e}");
    let e = err(&MINI.replace("rho0 = [10, 25]", "rho0 = [10, 0]"));
    assert!(e.contains("rho0") && e.contains("t.toml:22:"), "{e}");
    let e = err(&MINI.replace("kind = \"rpls\"", "kind = \"magic\""));
    assert!(e.contains("magic") && e.contains("t.toml:25:"), "{e}");
    let e = err(&MINI.replace("params = \"tuning\"", "params = \"tunning\""));
    assert!(e.contains("tunning") && e.contains("t.toml:13:"), "{e}");
    let e = err(&MINI.replace("cpu_seconds = 0.5", "cpu_seconds = -1"));
    assert!(e.contains("cpu_seconds"), "{e}");
    let e = err(&MINI.replace("samples = 500", "samples = \"many\""));
    assert!(e.contains("samples") && e.contains("line 14"), "{e}");
    let e = err(&MINI.replace(
        "[[algorithm]]\nkind = \"rpls\"",
        "[[algorithm]]\nkind = \"aed\"\nlabel = \"AED rho0=10\"",
    ));
    assert!(e.contains("duplicate configuration label"), "{e}");
    let e = err(&MINI.replace(
        "sigma = 0.1",
        "sigma = 0.1\n[instance.model]\nfixed = { \"lobe1.foo\" = 1.0 }",
    ));
    assert!(e.contains("lobe1.foo") && e.contains("t.toml:17:"), "{e}");
}

#[test]
fn relative_targets_parse_and_bad_ones_name_the_key() {
    let s = parse(&MINI.replace(
        "targets = [0.12, 0.11]",
        "targets = [{ relative = 0.05 }, 0.12, { relative = 0.01 }]",
    ))
    .unwrap();
    let i = &s.instances[0];
    assert_eq!(i.relative_targets, vec![0.01, 0.05]);
    assert_eq!(i.absolute_targets, vec![0.12]);
    assert!(s.has_unresolved_targets());
    // The fingerprint holds the relative value as written.
    assert_ne!(s.fingerprint(), parse(MINI).unwrap().fingerprint());
    for (entry, needle) in [
        (
            "{ relative = -0.01 }",
            "`targets[0].relative` must be a finite fraction",
        ),
        (
            "{ relative = 0.01, absolute = 0.1 }",
            "`targets[0]`: `relative` and `absolute`",
        ),
        (
            "{ relative = \"1%\" }",
            "`targets[0].relative` must be a number",
        ),
        ("{ relatve = 0.01 }", "`targets[0]`: unknown key `relatve`"),
        ("{}", "`targets[0]`: empty table"),
        ("\"0.1\"", "`targets[0]` must be a number or a table"),
        (
            "{ absolute = -1 }",
            "`targets[0].absolute` must be a finite RMSE",
        ),
    ] {
        let e = err(&MINI.replace("targets = [0.12, 0.11]", &format!("targets = [{entry}]")));
        assert!(
            e.contains(needle) && e.contains("t.toml:11:"),
            "{entry}: {e}"
        );
    }
    let tuned = format!(
        "{}\n[tune]\ntrain = [\"tuning\"]\ntest = [\"tuning\"]\nbudget = 100\ncost = \"evaluations\"\n[[tune.parameter]]\nname = \"phi\"\ntype = \"real\"\nrange = [1.0, 2.0]\n",
        MINI.replace("targets = [0.12, 0.11]", "targets = [{ relative = 0.01 }]")
    );
    assert!(err(&tuned).contains("relative targets are not supported with [tune]"));
}

#[test]
fn starts_are_validated_and_the_default_keeps_the_fingerprint() {
    let with = |model: &str| {
        parse(&MINI.replace(
            "sigma = 0.1",
            &format!("sigma = 0.1\n[instance.model]\n{model}"),
        ))
    };
    let base = with("exponent = \"log1p\"").unwrap();
    let same = with("exponent = \"log1p\"\nstarts = \"log-uniform\"").unwrap();
    let uniform = with("exponent = \"log1p\"\nstarts = \"uniform\"").unwrap();
    assert_eq!(base.fingerprint(), same.fingerprint());
    assert_eq!(base.fingerprint(), parse(MINI).unwrap().fingerprint());
    assert_ne!(base.fingerprint(), uniform.fingerprint());
    assert_eq!(uniform.instances[0].model.starts, sls::StartDist::Uniform);
    let raw = with("exponent = \"raw\"\nstarts = \"uniform\"").unwrap();
    assert_eq!(raw.instances[0].model.starts, sls::StartDist::Coordinate);
    let e = with("starts = \"gaussian\"").unwrap_err().to_string();
    assert!(e.contains("gaussian") && e.contains("starts"), "{e}");
}

#[test]
fn fingerprint_ignores_trials_but_not_seed() {
    let a = parse(MINI).unwrap();
    let b = parse(&MINI.replace("trials = 4", "trials = 9")).unwrap();
    let c = parse(&MINI.replace("seed = 3", "seed = 4")).unwrap();
    // Spelling out a default does not change the fingerprint.
    let d = parse(&MINI.replace("phi = 1.4", "phi = 1.4\ndescent_evaluations = 200")).unwrap();
    assert_eq!(a.fingerprint(), b.fingerprint());
    assert_ne!(a.fingerprint(), c.fingerprint());
    assert_eq!(a.fingerprint(), d.fingerprint());
}

#[test]
fn descent_is_read_per_entry_and_fingerprinted_only_when_not_default() {
    let plain = parse(MINI).unwrap();
    assert!(
        plain
            .configurations
            .iter()
            .all(|c| c.descent == sls::DescentModel::Default)
    );
    let spelled = parse(&MINI.replace("phi = 1.4", "phi = 1.4\ndescent = \"default\"")).unwrap();
    assert_eq!(plain.fingerprint(), spelled.fingerprint());
    let n2fb = parse(&MINI.replace("phi = 1.4", "phi = 1.4\ndescent = \"n2fb\"")).unwrap();
    assert_ne!(plain.fingerprint(), n2fb.fingerprint());
    // Every swept configuration of the entry gets it; the other entry keeps the default.
    let descents: Vec<_> = n2fb.configurations.iter().map(|c| c.descent).collect();
    use sls::DescentModel::{Default, N2fb};
    assert_eq!(descents, [N2fb, N2fb, Default]);
    assert!(
        n2fb.describe(1).contains("descent=n2fb"),
        "{}",
        n2fb.describe(1)
    );
}

#[test]
fn bad_descent_names_line_and_choices() {
    let e = err(&MINI.replace("phi = 1.4", "phi = 1.4\ndescent = \"port\""));
    assert!(
        e.contains("t.toml:21:") && e.contains("`port`") && e.contains("`n2fb`"),
        "{e}"
    );
    let e = err(&MINI.replace("phi = 1.4", "phi = 1.4\ndescent = 2"));
    assert!(
        e.contains("t.toml:21:") && e.contains("must be a string"),
        "{e}"
    );
}

#[test]
fn relative_paths_resolve_against_spec_dir() {
    let text = MINI.replace(
        "[instance.synthetic]\nparams = \"tuning\"\nsamples = 500\nsigma = 0.1",
        "[instance.file]\npath = \"data/x.brdf\"\nmax_value = 1.0",
    );
    let s = parse(&text).unwrap();
    match &s.instances[0].source {
        Source::File { resolved, spec } => {
            assert_eq!(resolved, Path::new("/base/data/x.brdf"));
            assert_eq!(spec.max_value, Some(1.0));
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn sizes_and_values_are_checked_before_any_work() {
    let with_synthetic =
        |extra: &str| MINI.replace("sigma = 0.1", &format!("sigma = 0.1\n{extra}"));
    for (text, needle) in [
        (MINI.replace("samples = 500", "samples = 9223372036854775807"), "samples"),
        (with_synthetic("[instance.model]\nlobes = 9223372036854775807"), "model.lobes"),
        (MINI.replace("rho0 = [10, 25]", "rho0 = { from = 1, to = 9, steps = 4000000000 }"), "steps"),
        (format!("{MINI}\n[stats]\nbootstrap = 1000000000\n"), "bootstrap"),
        (MINI.replace("sigma = 0.1", "sigma = 1e300"), "sigma"),
        (MINI.replace("sigma = 0.1", "sigma = nan"), "sigma"),
        (MINI.replace("params = \"tuning\"", "params = { kd = nan, lobes = [] }"), "kd"),
        (
            MINI.replace(
                "params = \"tuning\"",
                "params = { kd = 0.1, lobes = [{ cx = inf, cy = 0.8, cz = 0.96, n = 20, pan_deg = 45 }] }",
            ),
            "cx",
        ),
        (
            MINI.replace(
                "params = \"tuning\"",
                "params = { kd = 0.1, lobes = [{ cx = 1, cy = 0.8, cz = 5, n = 20, pan_deg = 45 }] }",
            ),
            "cz",
        ),
        (with_synthetic("[instance.model]\nbounds = { \"lobe1.n\" = [0.0, 1.0, 2.0] }"), "bounds"),
        (MINI.replace("rho0 = [10, 25]", "rho0 = [10, \"many\"]"), "rho0"),
        (MINI.replace("trials = 4", "trials = 4000000000"), "plan"),
        (MINI.replace("targets = [0.12, 0.11]", "targets = [nan]"), "targets"),
        (MINI.replace("cpu_seconds = 0.5", "cpu_seconds = inf"), "cpu_seconds"),
    ] {
        let started = std::time::Instant::now();
        let e = match parse(&text) {
            Ok(_) => panic!("`{needle}` case accepted:\n{text}"),
            Err(e) => e.to_string(),
        };
        assert!(e.contains(needle), "expected an error naming `{needle}`, got: {e}");
        assert!(started.elapsed().as_secs_f64() < 1.0, "{needle}: too slow");
    }
}

/// A model whose every parameter is fixed has nothing to fit: a trial would evaluate no
/// candidate and store no RMSE. `check` and `run` refuse it here, naming the `fixed` line.
#[test]
fn a_model_with_nothing_free_is_refused() {
    let fixed = "[instance.model]\nkind = \"isotropic\"\nfixed = { kd = 0.1, \"lobe1.cxy\" = -1.0, \
                 \"lobe1.cz\" = 1.0, \"lobe1.n\" = 20.0 }";
    let e = err(&MINI.replace("sigma = 0.1", &format!("sigma = 0.1\n{fixed}")));
    assert!(
        e.contains("every parameter is fixed (all 4): nothing to fit") && e.contains("t.toml:18"),
        "{e}"
    );
    // One parameter left free is a fit.
    let one_free = fixed.replace("kd = 0.1, ", "");
    assert!(parse(&MINI.replace("sigma = 0.1", &format!("sigma = 0.1\n{one_free}"))).is_ok());
}

/// Issue 45, item 17: measured metals need exponents beyond Table 1's 10,000. Table 1's box
/// stays the default; `model.bounds` widens an exponent's (the truth of a synthetic instance is
/// then checked against the widened bound), the bounds enter the fingerprint, and anything
/// else beyond the box is refused with the bound named.
#[test]
fn model_bounds_widen_an_exponent_beyond_table_1() {
    let steel = |bounds: &str| {
        MINI.replace(
            "params = \"tuning\"\nsamples = 500\nsigma = 0.1",
            &format!(
                "params = {{ kd = 0.01, lobes = [{{ cx = -1, cy = -1, cz = 1, n = 16600, \
                 pan_deg = 0 }}] }}\nsamples = 500\nsigma = 0.0\n[instance.model]\n\
                 kind = \"isotropic\"\n{bounds}"
            ),
        )
    };
    let e = err(&steel(""));
    assert!(
        e.contains("lobe1.n = 16600: expected a finite value in [0, 10000]")
            && e.contains("`model.bounds`"),
        "{e}"
    );
    let wide = parse(&steel("bounds = { \"lobe1.n\" = [0, 20000] }")).unwrap();
    let inst = &wide.instances[0];
    assert_eq!(inst.model.bounds["lobe1.n"], [0.0, 20000.0]);
    let built = crate::instance::build(inst).unwrap();
    assert_eq!(
        built.layout.physical_bounds("lobe1.n"),
        Some((0.0, 20000.0))
    );
    // The bounds are part of the canonical form: another box is another experiment.
    let other = parse(&steel("bounds = { \"lobe1.n\" = [0, 30000] }")).unwrap();
    assert_ne!(wide.fingerprint(), other.fingerprint());
    for (bounds, says) in [
        (
            "bounds = { \"lobe1.n\" = [0, 2e6] }",
            "reach beyond [0, 1e6], the widest an exponent's bounds may be",
        ),
        (
            "bounds = { \"lobe1.n\" = [0, 20000], kd = [0, 2] }",
            "bounds [0, 2] for `kd` reach beyond its box [0, 1]",
        ),
    ] {
        let e = err(&steel(bounds));
        assert!(e.contains(says) && e.contains("t.toml:"), "{bounds}: {e}");
    }
}
