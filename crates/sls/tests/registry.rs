//! The registry keeps the built-in configurations' serialised text byte for byte: the JSON and
//! TOML below were written by the closed `enum AlgorithmConfig` (serde tag `kind`) that the
//! registry replaced, and spec fingerprints and stored trials depend on them.

use sls::registry::{self, Algorithm, RegistryError};
use sls::{AlgorithmConfig, AsaConfig, ConfigError, Perturbation, SaConfig, Search, Stop};

/// The configurations whose text was recorded: every kind's default, then an SA with the
/// optional and enum fields set and the paper's tuned ASA.
fn recorded_configs() -> Vec<AlgorithmConfig> {
    let mut all: Vec<AlgorithmConfig> = ["aed", "aers", "rpls", "ds", "sa", "sals", "avg", "asa"]
        .iter()
        .map(|k| AlgorithmConfig::default_for(k).unwrap())
        .collect();
    all.push(AlgorithmConfig::new(SaConfig {
        constant_acceptance: Some(0.125),
        perturbation: Perturbation::Optimiser,
        ..SaConfig::default()
    }));
    all.push(AlgorithmConfig::new(AsaConfig::paper_tuned()));
    all
}

/// `serde_json::to_string` of [`recorded_configs`] by the enum.
const RECORDED_JSON: [&str; 10] = [
    r#"{"kind":"aed","phi":1.4,"rho0":25,"descent_iterations":10,"descent_evaluations":200,"stall_limit":0}"#,
    r#"{"kind":"aers","phi":1.0,"rho0":25,"descent_iterations":10,"descent_evaluations":200,"stall_limit":0}"#,
    r#"{"kind":"rpls","descent_iterations":150,"descent_evaluations":200}"#,
    r#"{"kind":"ds","rtol":0.08,"initial_step":0.1,"restart":true,"max_steps":5000}"#,
    r#"{"kind":"sa","t_start":1.0,"t_stop":0.3,"temperatures":50,"iterations":200,"r":1.0,"constant_acceptance":null,"perturbation":"paper","sample_size":0}"#,
    r#"{"kind":"sals","first":{"t_start":0.5,"t_stop":0.05,"temperatures":10,"iterations":40,"r":1.0,"constant_acceptance":null,"perturbation":"paper","sample_size":0},"later":{"t_start":0.05,"t_stop":0.005,"temperatures":3,"iterations":40,"r":1.0,"constant_acceptance":null,"perturbation":"paper","sample_size":0},"descent_sample_size":0,"descent_iterations":150,"descent_evaluations":200,"stagnation_rounds":3}"#,
    r#"{"kind":"avg","sa":{"t_start":1.0,"t_stop":0.3,"temperatures":50,"iterations":200,"r":1.0,"constant_acceptance":null,"perturbation":"paper","sample_size":0},"descent_sample_size":0,"descent_iterations":150,"descent_evaluations":200,"restart_tolerance":0.001}"#,
    r#"{"kind":"asa","temperature_ratio_scale":0.00001,"cost_parameter_scale_ratio":1.0,"acceptance_frequency_modulus":100,"generated_frequency_modulus":10000,"temperature_anneal_scale":100.0,"initial_parameter_temperature":1.0,"number_cost_samples":5,"accepted_to_generated_ratio":1e-6,"delta_x":0.001,"limit_acceptances":10000,"limit_generated":99999}"#,
    r#"{"kind":"sa","t_start":1.0,"t_stop":0.3,"temperatures":50,"iterations":200,"r":1.0,"constant_acceptance":0.125,"perturbation":"optimiser","sample_size":0}"#,
    r#"{"kind":"asa","temperature_ratio_scale":0.00005,"cost_parameter_scale_ratio":0.9,"acceptance_frequency_modulus":25,"generated_frequency_modulus":5000,"temperature_anneal_scale":100.0,"initial_parameter_temperature":1.0,"number_cost_samples":5,"accepted_to_generated_ratio":1e-6,"delta_x":0.001,"limit_acceptances":10000,"limit_generated":99999}"#,
];

/// `toml::to_string` of [`recorded_configs`] by the enum.
const RECORDED_TOML: [&str; 10] = [
    r#"kind = "aed"
phi = 1.4
rho0 = 25
descent_iterations = 10
descent_evaluations = 200
stall_limit = 0
"#,
    r#"kind = "aers"
phi = 1.0
rho0 = 25
descent_iterations = 10
descent_evaluations = 200
stall_limit = 0
"#,
    r#"kind = "rpls"
descent_iterations = 150
descent_evaluations = 200
"#,
    r#"kind = "ds"
rtol = 0.08
initial_step = 0.1
restart = true
max_steps = 5000
"#,
    r#"kind = "sa"
t_start = 1.0
t_stop = 0.3
temperatures = 50
iterations = 200
r = 1.0
perturbation = "paper"
sample_size = 0
"#,
    r#"kind = "sals"
descent_sample_size = 0
descent_iterations = 150
descent_evaluations = 200
stagnation_rounds = 3

[first]
t_start = 0.5
t_stop = 0.05
temperatures = 10
iterations = 40
r = 1.0
perturbation = "paper"
sample_size = 0

[later]
t_start = 0.05
t_stop = 0.005
temperatures = 3
iterations = 40
r = 1.0
perturbation = "paper"
sample_size = 0
"#,
    r#"kind = "avg"
descent_sample_size = 0
descent_iterations = 150
descent_evaluations = 200
restart_tolerance = 0.001

[sa]
t_start = 1.0
t_stop = 0.3
temperatures = 50
iterations = 200
r = 1.0
perturbation = "paper"
sample_size = 0
"#,
    r#"kind = "asa"
temperature_ratio_scale = 0.00001
cost_parameter_scale_ratio = 1.0
acceptance_frequency_modulus = 100
generated_frequency_modulus = 10000
temperature_anneal_scale = 100.0
initial_parameter_temperature = 1.0
number_cost_samples = 5
accepted_to_generated_ratio = 0.000001
delta_x = 0.001
limit_acceptances = 10000
limit_generated = 99999
"#,
    r#"kind = "sa"
t_start = 1.0
t_stop = 0.3
temperatures = 50
iterations = 200
r = 1.0
constant_acceptance = 0.125
perturbation = "optimiser"
sample_size = 0
"#,
    r#"kind = "asa"
temperature_ratio_scale = 0.00005
cost_parameter_scale_ratio = 0.9
acceptance_frequency_modulus = 25
generated_frequency_modulus = 5000
temperature_anneal_scale = 100.0
initial_parameter_temperature = 1.0
number_cost_samples = 5
accepted_to_generated_ratio = 0.000001
delta_x = 0.001
limit_acceptances = 10000
limit_generated = 99999
"#,
];

#[test]
fn built_ins_serialise_as_the_enum_did() {
    for (config, (json, toml_text)) in recorded_configs()
        .iter()
        .zip(RECORDED_JSON.iter().zip(RECORDED_TOML))
    {
        assert_eq!(serde_json::to_string(config).unwrap(), *json);
        assert_eq!(toml::to_string(config).unwrap(), toml_text);
    }
}

#[test]
fn built_ins_read_back_from_the_recorded_text() {
    for (config, (json, toml_text)) in recorded_configs()
        .iter()
        .zip(RECORDED_JSON.iter().zip(RECORDED_TOML))
    {
        let from_json: AlgorithmConfig = serde_json::from_str(json).unwrap();
        let from_toml: AlgorithmConfig = toml::from_str(toml_text).unwrap();
        assert_eq!(&from_json, config);
        assert_eq!(&from_toml, config);
    }
}

#[test]
fn an_unknown_kind_names_the_registered_kinds() {
    let err = serde_json::from_str::<AlgorithmConfig>(r#"{"kind": "tabu", "phi": 2}"#)
        .unwrap_err()
        .to_string();
    assert!(err.contains("unknown algorithm kind `tabu`"), "{err}");
    assert!(
        err.contains("`aed`, `aers`, `rpls`, `ds`, `sa`, `sals`, `avg`, `asa`"),
        "{err}"
    );
    let err = toml::from_str::<AlgorithmConfig>("kind = \"tabu\"").unwrap_err();
    assert!(
        err.message().contains("unknown algorithm kind `tabu`"),
        "{err}"
    );
}

#[test]
fn a_missing_or_malformed_kind_and_unknown_fields_are_rejected() {
    let missing = serde_json::from_str::<AlgorithmConfig>(r#"{"phi": 2}"#).unwrap_err();
    assert!(
        missing.to_string().contains("missing field `kind`"),
        "{missing}"
    );
    let number = serde_json::from_str::<AlgorithmConfig>(r#"{"kind": 3}"#).unwrap_err();
    assert!(
        number
            .to_string()
            .contains("`kind` must be a string, found an integer")
    );
    let unknown = serde_json::from_str::<AlgorithmConfig>(r#"{"kind": "aed", "ph": 2}"#)
        .unwrap_err()
        .to_string();
    assert!(unknown.contains("unknown field `ph`"), "{unknown}");
    let wrong_type = serde_json::from_str::<AlgorithmConfig>(r#"{"kind": "aed", "rho0": -1}"#);
    assert!(wrong_type.is_err());
}

#[test]
fn an_integer_for_a_real_field_is_read_as_before() {
    let config: AlgorithmConfig = toml::from_str("kind = \"aed\"\nphi = 2").unwrap();
    assert_eq!(config.downcast_ref::<sls::AedConfig>().unwrap().phi, 2.0);
}

/// A registered algorithm for the tests below: evaluates random picks.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
struct Picker {
    batch: usize,
}

impl Algorithm for Picker {
    const KIND: &'static str = "test-picker";
    fn validate(&self) -> Result<(), ConfigError> {
        Ok(())
    }
    fn run(&self, search: &mut dyn Search) -> Result<(), Stop> {
        let mut x = vec![0.0; search.dim()];
        loop {
            search.random_pick(&mut x);
            search.evaluate(&x)?;
        }
    }
}

/// Shares the kind of a built-in.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
struct FakeAed {}

impl Algorithm for FakeAed {
    const KIND: &'static str = "aed";
    fn validate(&self) -> Result<(), ConfigError> {
        Ok(())
    }
    fn run(&self, _: &mut dyn Search) -> Result<(), Stop> {
        Ok(())
    }
}

/// Not a usable tag.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
struct BadKind {}

impl Algorithm for BadKind {
    const KIND: &'static str = "Bad Kind";
    fn validate(&self) -> Result<(), ConfigError> {
        Ok(())
    }
    fn run(&self, _: &mut dyn Search) -> Result<(), Stop> {
        Ok(())
    }
}

#[test]
fn registration_adds_a_kind_once() {
    registry::register::<Picker>().unwrap();
    assert!(registry::kinds().contains(&"test-picker"));
    let config: AlgorithmConfig = toml::from_str("kind = \"test-picker\"\nbatch = 3").unwrap();
    assert_eq!(config.downcast_ref::<Picker>(), Some(&Picker { batch: 3 }));
    assert_eq!(
        config,
        AlgorithmConfig::default_for("test-picker")
            .map(|mut c| {
                c.downcast_mut::<Picker>().unwrap().batch = 3;
                c
            })
            .unwrap()
    );
    assert_eq!(
        serde_json::to_string(&config).unwrap(),
        r#"{"kind":"test-picker","batch":3}"#
    );
    let again = registry::register::<Picker>().unwrap_err();
    assert!(matches!(
        again,
        RegistryError::Duplicate {
            kind: "test-picker",
            ..
        }
    ));
    assert!(again.to_string().contains("already registered"), "{again}");
    let taken = registry::register::<FakeAed>().unwrap_err();
    assert!(matches!(
        taken,
        RegistryError::Duplicate { kind: "aed", .. }
    ));
    // The built-in is still what `aed` reads as.
    let aed: AlgorithmConfig = serde_json::from_str(r#"{"kind": "aed"}"#).unwrap();
    assert!(aed.downcast_ref::<sls::AedConfig>().is_some());
    let bad = registry::register::<BadKind>().unwrap_err();
    assert_eq!(bad, RegistryError::InvalidKind { kind: "Bad Kind" });
}

#[test]
fn configurations_of_different_kinds_differ() {
    let picker = AlgorithmConfig::new(Picker::default());
    assert_ne!(picker, AlgorithmConfig::default_for("rpls").unwrap());
    assert_eq!(picker.clone(), picker);
    assert_eq!(format!("{picker:?}"), "Picker { batch: 0 }");
}
