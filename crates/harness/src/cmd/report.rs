//! `brdf-sls report`: one self-contained HTML page of one or more results folders.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use brdf_analysis::folder::Folder;

use super::{input_error, note, say};
use crate::cli::ReportArgs;

/// `brdf-sls report`.
pub fn report(a: ReportArgs) -> Result<()> {
    let folders = a
        .dirs
        .iter()
        .map(|d| read_folder(d))
        .collect::<Result<Vec<_>>>()?;
    let out = a
        .out
        .unwrap_or_else(|| folder_of(&a.dirs[0]).join("report.html"));
    write_report_page(&folders, &out)?;
    say!("wrote {}", out.display());
    Ok(())
}

/// Reads a results folder; a path that is not one is bad input (exit status 2).
pub fn read_folder(path: &Path) -> Result<Folder> {
    let folder = Folder::read(path).map_err(|e| {
        if e.is_input_error() {
            input_error(e.to_string())
        } else {
            anyhow::Error::new(e).context(format!("reading results in {}", path.display()))
        }
    })?;
    for n in &folder.notes {
        note!("{}: note: {n}", path.display());
    }
    Ok(folder)
}

/// The folder a results path names (the parent of a trials.jsonl file).
pub fn folder_of(path: &Path) -> PathBuf {
    if path.is_dir() {
        return path.to_path_buf();
    }
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// Builds the report page of `folders` and writes it to `out` atomically.
pub fn write_report_page(folders: &[Folder], out: &Path) -> Result<()> {
    let analyses: Vec<_> = folders.iter().map(Folder::analysis).collect();
    let pairs: Vec<_> = folders.iter().zip(&analyses).collect();
    write_report_page_of(&pairs, out)
}

/// Builds the report page of folders with their analyses (computed once, e.g. by a run) and
/// writes it to `out` atomically.
pub fn write_report_page_of(
    folders: &[(&Folder, &brdf_analysis::analysis::Analysis)],
    out: &Path,
) -> Result<()> {
    let page = brdf_analysis::html::report_page_of(folders, &page_dir(out))
        .context("building the report page")?;
    write_page(out, &page)
}

/// The folder a page is written into (links on it are relative to it).
fn page_dir(out: &Path) -> PathBuf {
    match out.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// Writes a page atomically (a reader never sees half of it).
pub fn write_page(out: &Path, page: &str) -> Result<()> {
    brdf_experiment::store::write_atomic(out, page.as_bytes())
        .with_context(|| format!("writing {}", out.display()))
}
