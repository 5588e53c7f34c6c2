//! `brdf-sls report`: one self-contained HTML page of one or more results folders.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use brdf_analysis::folder::Folder;

use super::{bail_input, input_error, note, say};
use crate::cli::ReportArgs;

/// `brdf-sls report`.
pub fn report(a: ReportArgs) -> Result<()> {
    let folders = a
        .dirs
        .iter()
        .map(|d| read_folder(d))
        .collect::<Result<Vec<_>>>()?;
    if a.dirs.len() > 1 && a.out.is_none() {
        bail_input!(
            "a report of {} folders needs --out FILE (it would replace {}'s own report.html)",
            a.dirs.len(),
            a.dirs[0].display()
        );
    }
    let out = a
        .out
        .unwrap_or_else(|| folder_of(&a.dirs[0]).join("report.html"));
    let _lock = lock_page_folder(&out)?;
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

/// The lock of the folder `page` is written into, when that folder holds results
/// ([`lock_if_results`]).
pub fn lock_page_folder(page: &Path) -> Result<Option<brdf_experiment::store::DirLock>> {
    let lock = lock_if_results(&page_dir(page))
        .with_context(|| format!("not writing {}", page.display()))?;
    if lock.is_some()
        && let Some(name) = page.file_name().and_then(|n| n.to_str())
    {
        // A page inside a results folder is not written through a link there.
        brdf_graphics::target::refuse_links_in(&page_dir(page), &[name])?;
    }
    Ok(lock)
}

/// The lock of `dir` when it holds results: a run holds it while it writes trials (and
/// rewrites its statistics and pages when it ends), so a file written there now would show a
/// partial run and race with the run's own. Refused with the holder's PID
/// ([`brdf_experiment::store::StoreError::Locked`], exit status 1); a folder without results
/// takes no lock.
pub fn lock_if_results(dir: &Path) -> Result<Option<brdf_experiment::store::DirLock>> {
    use brdf_experiment::store::{DirLock, PACKED_TRIALS_FILE, TRIALS_FILE};
    let holds_results = [TRIALS_FILE, PACKED_TRIALS_FILE]
        .iter()
        .any(|f| std::fs::symlink_metadata(dir.join(f)).is_ok());
    if !holds_results {
        return Ok(None);
    }
    Ok(Some(DirLock::acquire(dir)?))
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
