//! Specs that draw instances from the named suites (`[instance.suite]`, `[[suite]]`, the
//! built-in `suite:NAME` experiments): they parse, expand, widen the bounds a material needs,
//! build their data as `brdf_published::suite::generate` does, run a few trials, and refuse
//! bad names and values with errors naming the file, the line and the key.

use brdf_best_known::prepare::prepare;
use brdf_experiment::instance::build;
use brdf_experiment::progress::ProgressMode;
use brdf_experiment::run::{RunOptions, SlsExecutor, run_locked};
use brdf_experiment::spec::{Source, Spec};
use brdf_io::Channel;
use brdf_model::LobeKind;
use brdf_published::suite::{Noise, SUITE_NAMES, Sampling, generate, suite};
use std::path::Path;

fn parse(text: &str) -> Result<Spec, String> {
    Spec::parse(text, "suites.toml", "suites", Path::new(".")).map_err(|e| e.to_string())
}

const HEAD: &str = "seed = 1\ntrials = 2\n\n[budget]\nevaluations = 3e5\n\n";
const AED: &str = "\n[[algorithm]]\nkind = \"aed\"\n";

/// A spec with one `[instance.suite]` whose table holds `keys`.
fn instance_spec(keys: &str) -> String {
    format!(
        "{HEAD}[[instance]]\nname = \"gold\"\ntargets = [{{ relative = 0.01 }}]\n\
         [instance.suite]\n{keys}\n{AED}"
    )
}

/// A spec with one `[[suite]]` table holding `keys`.
fn suite_spec(keys: &str) -> String {
    format!("{HEAD}[[suite]]\ntargets = [{{ relative = 0.01 }}]\n{keys}\n{AED}")
}

fn error(text: &str) -> String {
    match parse(text) {
        Ok(_) => panic!("accepted:\n{text}"),
        Err(e) => e,
    }
}

#[test]
fn a_suite_instance_is_the_published_material_sampled_as_asked() {
    let s = parse(&instance_spec(
        "suite = \"ngan-ward\"\nmaterial = \"gold-metallic-paint\"\nsampling = \"merl\"\n\
         samples = 2000\nnoise = 0.02\nsigma = 0.001\nseed = 7\nchannel = \"red\"",
    ))
    .unwrap();
    let i = &s.instances[0];
    let material = suite("ngan-ward")
        .unwrap()
        .material("gold-metallic-paint", Channel::Red)
        .unwrap();
    let Source::Synthetic {
        params,
        samples,
        sigma,
        seed,
        suite: Some(su),
        ..
    } = &i.source
    else {
        panic!("not a suite source: {:?}", i.source);
    };
    assert_eq!(*params, material.params);
    assert_eq!((*samples, *sigma, *seed), (2000, 0.001, 7));
    assert_eq!(
        (su.sampling, su.noise, su.channel),
        (Sampling::Merl, 0.02, Channel::Red)
    );
    // The model: the suite's family, one isotropic lobe (as published), no bounds widened.
    assert_eq!(i.model.family.name(), "ward");
    assert_eq!(i.model.kinds, [LobeKind::Isotropic]);
    assert!(i.model.bounds.is_empty());
    // The data is the published crate's generation, bit for bit.
    let built = build(i).unwrap();
    let noise = Noise {
        relative: 0.02,
        absolute: 0.001,
    };
    let want = generate(&material.params, Sampling::Merl, 2000, noise, 7).unwrap();
    assert_eq!(*built.data, want);
    // The canonical form records where the data is from.
    let c = s.canonical().to_string();
    for part in [
        "\"suite\":{\"channel\":\"red\",\"material\":\"gold-metallic-paint\",\"noise\":0.02,\"sampling\":\"merl\",\"suite\":\"ngan-ward\"}",
        "\"family\":\"ward\"",
    ] {
        assert!(c.contains(part), "{part} not in {c}");
    }
    // Defaults: merl sampling of 10000 cells, 1% relative noise, seed 1, green.
    let d = parse(&instance_spec(
        "suite = \"ngan-ggx\"\nmaterial = \"gold-paint\"",
    ))
    .unwrap();
    let Source::Synthetic {
        samples,
        sigma,
        seed,
        suite: Some(su),
        ..
    } = &d.instances[0].source
    else {
        panic!()
    };
    assert_eq!((*samples, *sigma, *seed), (10_000, 0.0, 1));
    assert_eq!(
        (su.sampling, su.noise, su.channel),
        (Sampling::Merl, 0.01, Channel::Green)
    );
    assert_eq!(d.instances[0].model.family.name(), "ggx");
    let desc = d.describe(1);
    assert!(
        desc.contains(
            "suite ngan-ggx material gold-paint (green channel, merl sampling, 10000 samples"
        ),
        "{desc}"
    );
}

#[test]
fn a_suite_table_expands_into_one_instance_per_material() {
    let all = parse(&suite_spec(
        "suite = \"ngan-lafortune\"\nsampling = \"cornell\"",
    ))
    .unwrap();
    assert_eq!(all.instances.len(), 86);
    assert_eq!(all.instances[0].name, "blue-acrylic");
    let inside = parse(&suite_spec(
        "suite = \"ngan-lafortune\"\nmaterials = \"in-bounds\"",
    ))
    .unwrap();
    assert_eq!(inside.instances.len(), 81);
    assert!(inside.instances.iter().all(|i| i.model.bounds.is_empty()));
    // The five with n > 10000 fit with lobe1.n widened to [0, 20000]; the others keep Table 1.
    let widened: Vec<&str> = all
        .instances
        .iter()
        .filter(|i| !i.model.bounds.is_empty())
        .map(|i| {
            assert_eq!(i.model.bounds["lobe1.n"], [0.0, 20000.0]);
            i.name.as_str()
        })
        .collect();
    assert_eq!(
        widened,
        [
            "brass",
            "hematite",
            "steel",
            "tungsten-carbide",
            "specular-violet-phenolic"
        ]
    );
    // A list (in the order given), a prefix, shared targets and model options.
    let listed = parse(&suite_spec(
        "suite = \"ngan-cook-torrance\"\nmaterials = [\"steel\", \"alum-bronze\"]\n\
         prefix = \"ct-\"\nsamples = 2000\n[suite.model]\nkind = \"anisotropic\"",
    ))
    .unwrap();
    let names: Vec<&str> = listed.instances.iter().map(|i| i.name.as_str()).collect();
    assert_eq!(names, ["ct-steel", "ct-alum-bronze"]);
    for i in &listed.instances {
        assert_eq!(i.model.kinds, [LobeKind::Anisotropic]);
        assert_eq!(i.relative_targets, [0.01]);
    }
    // A seeded sample of k materials: reproducible, k of them.
    let sample = |seed: u64| {
        let s = parse(&suite_spec(&format!(
            "suite = \"ngan-ward\"\nmaterials = {{ sample = 4, seed = {seed} }}"
        )))
        .unwrap();
        s.instance_names()
    };
    assert_eq!(sample(3).len(), 4);
    assert_eq!(sample(3), sample(3));
    assert_ne!(sample(3), sample(4));
    // [[instance]] and [[suite]] together, instances first.
    let both = format!(
        "{HEAD}[[instance]]\nname = \"t\"\ntargets = [0.1]\n[instance.synthetic]\nparams = \"tuning\"\n\n\
         [[suite]]\nsuite = \"ngan-ward\"\nmaterials = [\"steel\"]\ntargets = [0.1]\n{AED}"
    );
    assert_eq!(parse(&both).unwrap().instance_names(), ["t", "steel"]);
}

#[test]
fn suite_specs_run_a_few_trials() {
    let text = format!(
        "{HEAD}[[instance]]\nname = \"gold\"\ntargets = [{{ relative = 0.01 }}]\n\
         [instance.suite]\nsuite = \"ngan-ward\"\nmaterial = \"gold-metallic-paint\"\n\
         samples = 2000\n\n\
         [[suite]]\nsuite = \"ngan-lafortune\"\nmaterials = [\"hematite\", \"alum-bronze\"]\n\
         prefix = \"lf-\"\nsampling = \"uniform\"\nsamples = 2000\n\
         targets = [{{ relative = 0.01 }}]\n{AED}\n[[algorithm]]\nkind = \"rpls\"\n"
    );
    let spec = parse(&text).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let prepared = prepare(spec, dir.path()).unwrap();
    assert!(
        prepared
            .spec
            .instances
            .iter()
            .all(|i| i.best_known.is_some())
    );
    let exec =
        SlsExecutor::from_built(&prepared.spec, &prepared.built, brdf_model::Kernel::Auto).unwrap();
    let options = RunOptions {
        threads: 1,
        fresh: false,
        progress: ProgressMode::Quiet,
        limit: None,
    };
    let out = run_locked(&prepared.spec, None, prepared.folder, &options, &exec).unwrap();
    assert_eq!(out.records.len(), 2 * 3 * 2);
    for r in &out.records {
        assert!(r.result.best_rmse.is_finite(), "{}", r.key);
    }
}

#[test]
fn built_in_suite_experiments() {
    for name in SUITE_NAMES {
        let s = Spec::suite_experiment(name).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(s.name, format!("suite-{name}"));
        assert_eq!(s.instances.len(), 86, "{name}");
        assert_eq!(s.config_labels(), ["AED", "RPLS"]);
        assert_eq!(s.trials, 10);
        assert_eq!(s.budget.cpu_seconds, Some(1.0));
        let d = s.description.as_deref().unwrap();
        assert!(
            d.contains("86 materials") && d.contains("merl sampling"),
            "{d}"
        );
        assert!(s.instances.iter().all(|i| i.relative_targets == [0.01]));
        // The stored text reparses to the same experiment (plot and stats read it back).
        let again = Spec::parse(&s.text, "stored", "x", Path::new(".")).unwrap();
        assert_eq!(again.fingerprint(), s.fingerprint());
    }
    let ggx = Spec::suite_experiment("ngan-ggx").unwrap();
    assert!(ggx.description.unwrap().contains("APPROXIMATION"));
    for bad in ["", "ngan-nope"] {
        let e = Spec::suite_experiment(bad).unwrap_err().to_string();
        assert!(e.starts_with(&format!("suite:{bad}:")), "{e}");
        for n in SUITE_NAMES {
            assert!(e.contains(n), "{e}");
        }
    }
}

#[test]
fn bad_suite_keys_name_the_file_line_and_key() {
    let cases: &[(String, &str, &[&str])] = &[
        (
            instance_spec("suite = \"ngan-wrd\"\nmaterial = \"gold-metallic-paint\""),
            "suites.toml:11:",
            &[
                "`suite.suite`",
                "unknown suite `ngan-wrd`",
                "ngan-ward",
                "ngan-ggx",
            ],
        ),
        (
            instance_spec("suite = \"ngan-ward\"\nmaterial = \"gold\""),
            "suites.toml:12:",
            &[
                "`suite.material`",
                "no material `gold`",
                "gold-metallic-paint",
            ],
        ),
        (
            instance_spec("suite = \"ngan-ward\"\nmaterial = \"steel\"\nsampling = \"grid\""),
            "suites.toml:13:",
            &["`suite.sampling`", "cornell, merl, uniform"],
        ),
        (
            instance_spec(
                "suite = \"ngan-ward\"\nmaterial = \"steel\"\nsampling = \"cornell\"\nsamples = 1441",
            ),
            "suites.toml:14:",
            &["`suite.samples`", "1 to 1440"],
        ),
        (
            instance_spec("suite = \"ngan-ward\"\nmaterial = \"steel\"\nnoise = -0.1"),
            "suites.toml:13:",
            &["`suite.noise`", "[0, 10]"],
        ),
        (
            instance_spec("suite = \"ngan-ward\"\nmaterial = \"steel\"\nsamples = 2"),
            "suites.toml:8:",
            &["`suite.samples` must be at least"],
        ),
        (
            instance_spec("suite = \"ngan-ward\"\nmaterial = \"steel\"\nmaterials = 1"),
            "line 13",
            &["unknown field `materials`", "`material`", "`sampling`"],
        ),
        (
            instance_spec(
                "suite = \"ngan-lafortune\"\nmaterial = \"hematite\"\n\
                 [instance.model]\nbounds = { \"lobe1.n\" = [0, 12000] }",
            ),
            "suites.toml:14:",
            &[
                "material `hematite` has lobe1.n = 16600",
                "`model.bounds.\"lobe1.n\"`",
            ],
        ),
        (
            suite_spec("suite = \"ngan-nope\""),
            "suites.toml:9:",
            &[
                "[[suite]] 1: `suite`",
                "unknown suite `ngan-nope`",
                "ngan-lafortune",
            ],
        ),
        (
            suite_spec("suite = \"ngan-ward\"\nmaterials = [\"steel\", \"stel\"]"),
            "suites.toml:10:",
            &[
                "[[suite]] 1: `materials`",
                "no material `stel`",
                "alum-bronze",
            ],
        ),
        (
            suite_spec("suite = \"ngan-ward\"\nmaterials = \"some\""),
            "suites.toml:10:",
            &["`materials` must be \"all\", \"in-bounds\""],
        ),
        (
            suite_spec("suite = \"ngan-ward\"\nmaterials = { sample = 90 }"),
            "suites.toml:10:",
            &["a sample of 90 materials; expected 1 to 86"],
        ),
        (
            suite_spec("suite = \"ngan-ward\"\nmaterials = { count = 9 }"),
            "suites.toml:10:",
            &["unknown key `count`"],
        ),
        (
            suite_spec("suite = \"ngan-ward\"\nprefix = \"a/\""),
            "suites.toml:7:",
            &["[[suite]] 1: `prefix` must contain no '/'"],
        ),
        (
            suite_spec("suite = \"ngan-ward\"\nmaterial = \"steel\""),
            "line 10",
            &["unknown field `material`", "`materials`", "`prefix`"],
        ),
        (
            format!(
                "{}\n[[suite]]\nsuite = \"ngan-ward\"\nmaterials = [\"gold-metallic-paint\"]\ntargets = [0.1]\n",
                instance_spec("suite = \"ngan-ward\"\nmaterial = \"steel\"")
                    .replace("name = \"gold\"", "name = \"gold-metallic-paint\"")
            ),
            "suites.toml:",
            &["instance `gold-metallic-paint`: duplicate name", "`prefix`"],
        ),
        (
            format!(
                "{HEAD}[[instance]]\nname = \"x\"\ntargets = [0.1]\n[instance.synthetic]\nparams = \"tuning\"\n\
                 [instance.suite]\nsuite = \"ngan-ward\"\nmaterial = \"steel\"\n{AED}"
            ),
            "suites.toml:8:",
            &["exactly one of [instance.synthetic], [instance.file] or [instance.suite]"],
        ),
        (
            format!("{HEAD}{AED}"),
            "suites.toml:",
            &["at least one [[instance]] or [[suite]]"],
        ),
    ];
    for (text, at, parts) in cases {
        let e = error(text);
        assert!(e.contains(at), "expected `{at}` in: {e}\n{text}");
        for p in *parts {
            assert!(e.contains(p), "expected `{p}` in: {e}\n{text}");
        }
    }
}
