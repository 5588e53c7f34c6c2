//! The Python package's version is the command line's: `brdf_sls.__version__` is the extension
//! crate's `CARGO_PKG_VERSION`, and maturin takes the wheel's version from the same
//! `crates/py/Cargo.toml` (the crate is outside the workspace, so it cannot inherit it).

use std::path::Path;

fn read_toml(relative: &str) -> toml::Table {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(relative);
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    text.parse()
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

#[test]
fn the_python_crate_has_the_command_line_version() {
    let py = read_toml("../py/Cargo.toml");
    let version = py["package"]["version"].as_str().unwrap();
    assert_eq!(version, env!("CARGO_PKG_VERSION"), "crates/py/Cargo.toml");
}

#[test]
fn the_wheel_takes_its_version_from_the_crate() {
    let project = read_toml("../py/pyproject.toml");
    let project = project["project"].as_table().unwrap();
    assert!(
        !project.contains_key("version"),
        "pyproject.toml sets a version of its own"
    );
    let dynamic = project["dynamic"].as_array().unwrap();
    assert!(dynamic.iter().any(|v| v.as_str() == Some("version")));
}
