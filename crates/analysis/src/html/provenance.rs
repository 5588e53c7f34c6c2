//! Where results come from: program version and commit, kernel, machine, dates, shards and
//! sessions, as recorded in a results file's header and session lines.

use super::{date, escape, key_values, table};
use crate::folder::Folder;
use brdf_experiment::machine::MachineInfo;

/// A machine in one line: CPU model, logical CPUs, threads, OS, host.
pub fn machine_text(m: &MachineInfo) -> String {
    let host = m
        .hostname
        .as_deref()
        .map(|h| format!(", host {h}"))
        .unwrap_or_default();
    format!(
        "{}, {} logical CPUs, {} worker thread(s), {}{host}",
        m.cpu_model, m.logical_cpus, m.threads, m.os
    )
}

/// The distinct non-empty values in order of first appearance, joined by ", " (escaped).
fn distinct<'a>(values: impl Iterator<Item = &'a str>) -> String {
    let mut seen: Vec<&str> = Vec::new();
    for v in values.filter(|v| !v.is_empty()) {
        if !seen.contains(&v) {
            seen.push(v);
        }
    }
    if seen.is_empty() {
        "not recorded".into()
    } else {
        escape(&seen.join(", "))
    }
}

/// The provenance table of a folder (key, value).
pub fn summary(f: &Folder) -> String {
    let h = &f.contents.header;
    let s = &f.contents.sessions;
    let (present, planned) = f.progress();
    let versions = distinct(
        std::iter::once(h.program_version.as_str())
            .chain(s.iter().map(|x| x.program_version.as_str())),
    );
    let kernels =
        distinct(std::iter::once(h.kernel.as_str()).chain(s.iter().map(|x| x.kernel.as_str())));
    let machines: Vec<String> = std::iter::once(&h.machine)
        .chain(s.iter().map(|x| &x.machine))
        .map(machine_text)
        .collect();
    let last = s.iter().map(|x| x.started_unix).max();
    let hashes: Vec<String> = h
        .data_hashes
        .iter()
        .map(|(k, v)| format!("{k}: {v}"))
        .collect();
    key_values(&[
        ("results", escape(&f.dir.display().to_string())),
        ("experiment", escape(&h.experiment)),
        ("spec fingerprint", escape(&h.fingerprint)),
        ("program version (commit)", versions),
        ("evaluation kernel", kernels),
        ("machine", distinct(machines.iter().map(String::as_str))),
        ("created", date(h.created_unix)),
        (
            "last session started",
            last.map_or_else(|| "-".into(), date),
        ),
        ("sessions", s.len().to_string()),
        (
            "shard",
            h.shard
                .as_ref()
                .map_or_else(|| "whole plan".into(), |x| escape(&x.to_string())),
        ),
        ("trials present / planned", format!("{present} / {planned}")),
        (
            "instance data hashes",
            distinct(hashes.iter().map(String::as_str)),
        ),
    ])
}

/// One row per session: start, trials already present, kernel, program version, machine.
pub fn sessions(f: &Folder) -> String {
    let rows: Vec<Vec<String>> = f
        .contents
        .sessions
        .iter()
        .map(|s| {
            vec![
                date(s.started_unix),
                s.trials_present.to_string(),
                escape(&s.kernel),
                escape(&s.program_version),
                escape(&machine_text(&s.machine)),
            ]
        })
        .collect();
    if rows.is_empty() {
        return String::new();
    }
    table(
        "sessions",
        &[
            "session started",
            "trials present at start",
            "kernel",
            "program version",
            "machine",
        ],
        &rows,
    )
}
