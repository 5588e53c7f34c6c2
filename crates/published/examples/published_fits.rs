//! Prints the generated tables of `docs/published-fits.md`: every published fit file's
//! parameter ranges and flagged values, the Lafortune conversion's statistics and the
//! lobe-shape check (`brdf_published::report_markdown`).
//!
//! `cargo run -p brdf-model --example published_fits [DIR]`; DIR defaults to
//! `experiments/data/published-fits` of this repository.

use std::path::PathBuf;

fn main() {
    let dir = std::env::args_os()
        .nth(1)
        .map(PathBuf::from)
        .unwrap_or_else(|| {
            PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../experiments/data/published-fits")
        });
    match brdf_published::report_markdown(&dir) {
        Ok(text) => print!("{text}"),
        Err(e) => {
            eprintln!("error: {e}");
            std::process::exit(1);
        }
    }
}
