//! `brdf-sls check suite:` and `run suite:`: a suite name where a spec path is expected; an
//! unknown or missing name is bad input (exit 2) listing the suites. (The built-in suite
//! experiments themselves are tested in crates/experiment/tests/suites.rs.)

use std::process::Command;

#[test]
fn an_unknown_or_missing_suite_lists_the_suites() {
    let dir = tempfile::tempdir().unwrap();
    for args in [
        ["check", "suite:"],
        ["check", "suite:ngan-nope"],
        ["run", "suite:ngan-nope"],
    ] {
        let o = Command::new(env!("CARGO_BIN_EXE_brdf-sls"))
            .args(args)
            .current_dir(dir.path())
            .env("CI", "true")
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        for name in [
            "ngan-lafortune",
            "ngan-cook-torrance",
            "ngan-blinn-phong",
            "ngan-ward",
            "ngan-ashikhmin-shirley",
            "ngan-ggx",
        ] {
            assert!(err.contains(name), "{args:?}: {err}");
        }
        assert!(!dir.path().join("runs").exists(), "{args:?} wrote nothing");
    }
}
