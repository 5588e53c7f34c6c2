//! Every experiment shipped in experiments/ parses, and its data files exist.

use std::path::Path;

use brdf_experiment::spec::{Source, Spec};

#[test]
fn shipped_experiments_are_valid() {
    // experiments/baselines.toml has algorithms written in Python: read, as `check` reads them.
    brdf_experiment::python_kind::register_schema();
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../experiments");
    let mut n = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|e| e != "toml") {
            continue;
        }
        let spec = Spec::from_file(&path).unwrap_or_else(|e| panic!("{e}"));
        for i in &spec.instances {
            if let Source::File { resolved, .. } = &i.source {
                assert!(
                    resolved.exists(),
                    "{}: {}",
                    path.display(),
                    resolved.display()
                );
                brdf_experiment::instance::build(i).unwrap();
            }
        }
        assert!(!spec.describe(2).is_empty());
        n += 1;
    }
    assert!(n >= 4, "found {n} experiments");
    // The crate's embedded copy of the default is the user-facing file, byte for byte.
    let on_disk = std::fs::read_to_string(dir.join("default.toml")).unwrap();
    assert_eq!(on_disk, brdf_experiment::spec::DEFAULT_SPEC);
}
