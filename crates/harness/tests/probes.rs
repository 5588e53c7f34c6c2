//! Probes from outside: special files (FIFOs, links to them) given as specs, results files,
//! results folders and output files; absurd thread counts and budgets; a locked folder; stale
//! temporaries; edited results. Every probe must end quickly with a clear error naming the
//! file or key (exit status 2 for bad input, 1 for a folder in use), or do the right thing;
//! never hang, exhaust memory, or replace what it should not. `scripts/fuzz-long.sh` runs
//! these probes too. No probe touches a real device node: FIFOs stand in for them.
#![cfg(unix)]

#[path = "../../experiment/tests/common/mod.rs"]
mod common;

mod support;
use std::os::unix::fs::{FileTypeExt, symlink};
use std::path::Path;
use std::process::{Command, Output, Stdio};
use std::time::Duration;
use support::PROBE_SPEC as SPEC;

/// Runs the binary in `dir`, killing it (and failing) after 60 s: a probe that hangs on a
/// FIFO or reads without end fails instead of blocking the suite. The output is collected by
/// another thread while waiting, so a long output cannot fill the pipe and stall the child.
fn brdf_sls(dir: &Path, args: &[&str]) -> Output {
    let child = Command::new(env!("CARGO_BIN_EXE_brdf-sls"))
        .args(args)
        .current_dir(dir)
        .env("CI", "true")
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let pid = child.id().to_string();
    let (send, receive) = std::sync::mpsc::channel();
    std::thread::spawn(move || send.send(child.wait_with_output()));
    match receive.recv_timeout(Duration::from_secs(60)) {
        Ok(output) => output.unwrap(),
        Err(_) => {
            let _ = Command::new("kill").args(["-9", &pid]).status();
            panic!("brdf-sls {args:?} did not end within 60 s");
        }
    }
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Asserts exit status `code` and an error message holding every one of `parts`.
fn assert_refused(o: &Output, code: i32, parts: &[&str]) {
    let err = stderr(o);
    assert_eq!(o.status.code(), Some(code), "{err}");
    for p in parts {
        assert!(err.contains(p), "expected `{p}` in: {err}");
    }
}

fn mkfifo(path: &Path) {
    let made = Command::new("mkfifo").arg(path).status().unwrap();
    assert!(made.success(), "mkfifo {}", path.display());
}

/// A temporary folder with `probe.toml` and its finished run in `done/`.
fn with_a_run() -> tempfile::TempDir {
    let tmp = tempfile::tempdir().unwrap();
    std::fs::write(tmp.path().join("probe.toml"), SPEC).unwrap();
    let o = brdf_sls(
        tmp.path(),
        &["run", "probe.toml", "--out", "done", "--no-plots"],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    tmp
}

#[test]
fn a_fifo_or_a_link_to_one_as_a_spec_is_refused_naming_it() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    mkfifo(&dir.join("fifo.toml"));
    symlink("fifo.toml", dir.join("link.toml")).unwrap();
    for spec in ["fifo.toml", "link.toml"] {
        for args in [
            vec!["check", spec],
            vec!["run", spec, "--out", "out"],
            vec!["stats", spec, "--out", "out"],
        ] {
            let o = brdf_sls(dir, &args);
            assert_refused(&o, 2, &[spec, "is a FIFO, not a regular file"]);
        }
    }
}

#[test]
fn every_command_refuses_a_results_file_that_links_to_a_fifo() {
    let tmp = with_a_run();
    let dir = tmp.path();
    std::fs::create_dir(dir.join("bad")).unwrap();
    mkfifo(&dir.join("fifo"));
    symlink("../fifo", dir.join("bad/trials.jsonl")).unwrap();
    let file = "bad/trials.jsonl";
    let expected = "is a FIFO, not a regular file; expected a results file";
    for args in [
        vec!["stats", "bad"],
        vec!["plot", "bad"],
        vec!["export", "--format", "ioh", "bad"],
        vec!["merge", "merged", "done", "bad"],
        vec!["run", "probe.toml", "--out", "bad", "--no-plots"],
    ] {
        let o = brdf_sls(dir, &args);
        assert_refused(&o, 2, &[file, expected]);
    }
    // The link and its FIFO are left as they were.
    let meta = std::fs::symlink_metadata(dir.join(file)).unwrap();
    assert!(meta.file_type().is_symlink());
    assert!(
        std::fs::metadata(dir.join("fifo"))
            .unwrap()
            .file_type()
            .is_fifo()
    );
}

#[test]
fn an_out_folder_that_is_not_a_folder_is_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    std::fs::write(dir.join("probe.toml"), SPEC).unwrap();
    mkfifo(&dir.join("fifo"));
    symlink("fifo", dir.join("link")).unwrap();
    std::fs::write(dir.join("file"), "").unwrap();
    for (out, kind) in [
        ("fifo", "a FIFO"),
        ("link", "a FIFO"),
        ("file", "a regular file"),
    ] {
        let o = brdf_sls(dir, &["run", "probe.toml", "--out", out]);
        assert_refused(
            &o,
            2,
            &[&format!("--out {out}: is {kind}, not a directory")],
        );
    }
    let o = brdf_sls(dir, &["run", "probe.toml", "--out", "done", "--no-plots"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let o = brdf_sls(dir, &["export", "--format", "ioh", "done", "--out", "link"]);
    assert_refused(&o, 2, &["--out link: is a FIFO, not a directory"]);
    let o = brdf_sls(dir, &["merge", "fifo", "done"]);
    assert_refused(&o, 2, &["fifo: is a FIFO, not a directory"]);
    assert!(
        std::fs::metadata(dir.join("fifo"))
            .unwrap()
            .file_type()
            .is_fifo()
    );
}

#[test]
fn an_output_file_is_written_through_its_link_and_a_fifo_is_never_replaced() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    std::fs::write(dir.join("real.csv"), "old").unwrap();
    symlink("real.csv", dir.join("link.csv")).unwrap();
    let generate = ["gen", "--params", "tuning", "--samples", "10", "--out"];
    let o = brdf_sls(dir, &[&generate[..], &["link.csv"]].concat());
    assert!(o.status.success(), "{}", stderr(&o));
    let link = std::fs::symlink_metadata(dir.join("link.csv")).unwrap();
    assert!(link.file_type().is_symlink(), "the link was replaced");
    let written = std::fs::read_to_string(dir.join("real.csv")).unwrap();
    assert!(written.lines().count() > 10, "{written}");

    mkfifo(&dir.join("fifo.csv"));
    let o = brdf_sls(dir, &[&generate[..], &["fifo.csv"]].concat());
    assert_refused(&o, 2, &["fifo.csv", "is a FIFO", "refusing to replace it"]);
    let meta = std::fs::symlink_metadata(dir.join("fifo.csv")).unwrap();
    assert!(meta.file_type().is_fifo(), "the FIFO was replaced");
}

#[test]
fn absurd_thread_counts_are_refused_and_useless_threads_are_not_started() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    std::fs::write(dir.join("probe.toml"), SPEC).unwrap();
    for cmd in ["run", "check"] {
        let o = brdf_sls(dir, &[cmd, "probe.toml", "--threads", "10001"]);
        assert_refused(&o, 2, &["--threads must be from 1 to 1024, found 10001"]);
    }
    std::fs::write(dir.join("many.toml"), format!("threads = 5000\n{SPEC}")).unwrap();
    let o = brdf_sls(dir, &["check", "many.toml"]);
    assert_refused(&o, 2, &["many.toml", "`threads` must be from 1 to 1024"]);

    // 3 trials: 64 threads would idle.
    let o = brdf_sls(dir, &["run", "probe.toml", "--threads", "64", "--no-plots"]);
    let err = stderr(&o);
    assert!(o.status.success(), "{err}");
    assert!(err.contains("not the 64 asked for"), "{err}");
    assert!(!err.contains("64 worker thread(s)"), "{err}");
}

#[test]
fn stats_and_plot_refuse_a_folder_a_run_holds() {
    let tmp = with_a_run();
    let done = tmp.path().join("done");
    {
        let _held = brdf_experiment::store::DirLock::acquire(&done).unwrap();
        for cmd in ["stats", "plot"] {
            let before = std::fs::read(done.join("stats.csv")).unwrap();
            let o = brdf_sls(tmp.path(), &[cmd, "done"]);
            assert_refused(&o, 1, &["done is in use by another brdf-sls process"]);
            assert_eq!(std::fs::read(done.join("stats.csv")).unwrap(), before);
        }
        // Printing only writes nothing, so it needs no lock.
        let o = brdf_sls(tmp.path(), &["stats", "done", "--print-only"]);
        assert!(o.status.success(), "{}", stderr(&o));
    }
}

#[test]
fn stats_removes_the_temporaries_of_killed_writers_only() {
    let tmp = with_a_run();
    let done = tmp.path().join("done");
    // PIDs above the kernel's largest (2^22) never run; our own test process does.
    let stale = done.join(".stats.csv.tmp-999999999");
    let live = done.join(format!(".stats.csv.tmp-{}", std::process::id()));
    std::fs::write(&stale, "half").unwrap();
    std::fs::write(&live, "half").unwrap();
    let o = brdf_sls(tmp.path(), &["stats", "done"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!stale.exists(), "a dead writer's temporary was kept");
    assert!(live.exists(), "a live writer's temporary was removed");
}

fn gzip(bytes: &[u8]) -> Vec<u8> {
    let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
    std::io::Write::write_all(&mut gz, bytes).unwrap();
    gz.finish().unwrap()
}

/// Both files: fine when the plain one starts with the packed one's content (a run unpacked
/// it and went on), refused when the packed one holds results the plain one lacks.
#[test]
fn a_folder_with_both_plain_and_packed_results_is_refused_unless_one_extends_the_other() {
    let tmp = with_a_run();
    let done = tmp.path().join("done");
    let full = std::fs::read(done.join("trials.jsonl")).unwrap();
    // The header and the first session line: no trials.
    let head_len = full
        .iter()
        .enumerate()
        .filter(|(_, b)| **b == b'\n')
        .nth(1)
        .unwrap()
        .0
        + 1;
    std::fs::write(done.join("trials.jsonl.gz"), gzip(&full[..head_len])).unwrap();
    let o = brdf_sls(tmp.path(), &["stats", "done"]);
    assert!(o.status.success(), "{}", stderr(&o));

    std::fs::write(done.join("trials.jsonl.gz"), gzip(&full)).unwrap();
    std::fs::write(done.join("trials.jsonl"), &full[..head_len]).unwrap();
    for args in [
        vec!["stats", "done"],
        vec!["run", "probe.toml", "--out", "done", "--no-plots"],
    ] {
        let o = brdf_sls(tmp.path(), &args);
        assert_refused(
            &o,
            2,
            &["done holds both trials.jsonl and trials.jsonl.gz", "remove"],
        );
    }
}

#[test]
fn a_stored_trial_with_an_edited_seed_is_refused_naming_its_line() {
    let tmp = with_a_run();
    let path = tmp.path().join("done/trials.jsonl");
    let text = std::fs::read_to_string(&path).unwrap();
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    let at = lines
        .iter()
        .position(|l| l.contains("\"type\":\"trial\""))
        .unwrap();
    let mut v: serde_json::Value = serde_json::from_str(&lines[at]).unwrap();
    let seed = v["seed"].as_u64().unwrap();
    v["seed"] = serde_json::json!(seed ^ 1);
    lines[at] = v.to_string();
    std::fs::write(&path, lines.join("\n") + "\n").unwrap();
    let o = brdf_sls(
        tmp.path(),
        &["run", "probe.toml", "--out", "done", "--no-plots"],
    );
    let line = format!("done/trials.jsonl:{}", at + 1);
    assert_refused(&o, 2, &[&line, &format!("has seed {}", seed ^ 1)]);
}

/// Spec values that were accepted silently, each refused naming its key.
#[test]
fn out_of_range_budget_and_sample_counts_are_refused_naming_the_key() {
    let tmp = tempfile::tempdir().unwrap();
    let check = |text: String| {
        std::fs::write(tmp.path().join("probe.toml"), text).unwrap();
        brdf_sls(tmp.path(), &["check", "probe.toml"])
    };
    let o = check(SPEC.replace("evaluations = 20000", "cpu_seconds = 1e300"));
    assert_refused(
        &o,
        2,
        &["probe.toml:", "`budget.cpu_seconds`", "at most 1e7"],
    );
    let o = check(SPEC.replace("evaluations = 20000", "cpu_seconds = 1e7"));
    assert!(o.status.success(), "{}", stderr(&o));

    let o = check(SPEC.replace("samples = 200", "samples = 1"));
    assert_refused(&o, 2, &["probe.toml:", "`synthetic.samples`"]);
    // The least count the message states is accepted, one fewer is not.
    let e = stderr(&o);
    let least: usize = e
        .split("parameters + 1 (")
        .nth(1)
        .and_then(|r| r.split(')').next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no count in: {e}"));
    assert!(least > 2, "{e}");
    let o = check(SPEC.replace("samples = 200", &format!("samples = {least}")));
    assert!(o.status.success(), "{}", stderr(&o));
    let o = check(SPEC.replace("samples = 200", &format!("samples = {}", least - 1)));
    assert_refused(&o, 2, &["`synthetic.samples`"]);
}

#[test]
fn a_long_sweep_over_a_narrow_range_gets_distinct_labels() {
    let tmp = tempfile::tempdir().unwrap();
    let text =
        format!("{SPEC}[algorithm.sweep]\nphi = {{ from = 1.4, to = 1.4001, steps = 10000 }}\n");
    std::fs::write(tmp.path().join("probe.toml"), text).unwrap();
    let o = brdf_sls(tmp.path(), &["check", "probe.toml"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(
        out.contains("configurations (10000)"),
        "{}",
        &out[..out.len().min(2000)]
    );
    let lines: Vec<&str> = out.lines().collect();
    let first = lines
        .iter()
        .position(|l| l.starts_with("configurations"))
        .unwrap()
        + 1;
    assert!(
        lines[first].trim_start().starts_with("AED phi=1.4 "),
        "{}",
        lines[first]
    );
    assert!(
        lines[first + 1]
            .trim_start()
            .starts_with("AED phi=1.40000001 "),
        "{}",
        lines[first + 1]
    );
}

#[test]
fn a_huge_label_and_huge_numbers_fail_cleanly_or_parse() {
    for (from, to) in [
        ("kind = \"aed\"", "kind = \"aed\"\nlabel = \"AAAA\""),
        ("trials = 3", "trials = 4000000000"),
        ("samples = 200", "samples = 9223372036854775807"),
    ] {
        let text = SPEC.replace(from, &to.replace("AAAA", &"L".repeat(70_000)));
        let parsed =
            brdf_experiment::spec::Spec::parse(&text, "probe.toml", "probe", Path::new("."));
        if let Ok(spec) = parsed {
            let _ = spec.describe(2);
        }
    }
}

/// The tiny experiment run into `dir/a` (no plots): 4 trials of 3 configurations.
fn tiny_run(dir: &Path) {
    std::fs::write(dir.join("tiny.toml"), common::TINY).unwrap();
    let o = brdf_sls(
        dir,
        &[
            "run",
            "tiny.toml",
            "--out",
            "a",
            "--threads",
            "2",
            "--no-plots",
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
}

/// `dir/a`'s results with `edit` applied to every line (as JSON), written to `dir/name`.
fn edited(dir: &Path, name: &str, edit: impl Fn(&mut serde_json::Value)) {
    let text = std::fs::read_to_string(dir.join("a/trials.jsonl")).unwrap();
    let mut out = String::new();
    for line in text.lines() {
        let mut v: serde_json::Value = serde_json::from_str(line).unwrap();
        edit(&mut v);
        out.push_str(&serde_json::to_string(&v).unwrap());
        out.push('\n');
    }
    std::fs::create_dir_all(dir.join(name)).unwrap();
    std::fs::write(dir.join(name).join("trials.jsonl"), out).unwrap();
}

/// Every `cpu_seconds` under `v` set to `x`.
fn set_cpu_seconds(v: &mut serde_json::Value, x: f64) {
    match v {
        serde_json::Value::Object(m) => {
            if m.contains_key("cpu_seconds") && m.contains_key("evaluations") {
                m.insert("cpu_seconds".into(), x.into());
            }
            m.values_mut().for_each(|c| set_cpu_seconds(c, x));
        }
        serde_json::Value::Array(a) => a.iter_mut().for_each(|c| set_cpu_seconds(c, x)),
        _ => {}
    }
}

/// Results files are input. A header created "at" 10^12 s or u64::MAX s (past the year 9999)
/// panicked `report` and `compare` when they printed the date; times of 1e305 s and more, or
/// subnormal ones (one trace point at 1e300 was enough), sent the log axes of `report`,
/// `compare` and `plot` into endless tick loops. Each must now end at once with its page.
#[test]
fn absurd_dates_and_times_in_results_neither_panic_nor_hang() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    tiny_run(dir);
    for created in [1_000_000_000_000u64, u64::MAX] {
        edited(dir, "dated", |v| {
            if v["type"] == "header" {
                v["created_unix"] = created.into();
            }
            if v["type"] == "session" {
                v["started_unix"] = created.into();
            }
        });
        let o = brdf_sls(dir, &["report", "dated", "--out", "dated.html"]);
        assert_eq!(o.status.code(), Some(0), "{created}: {}", stderr(&o));
        let page = std::fs::read_to_string(dir.join("dated.html")).unwrap();
        assert!(page.contains(&created.to_string()), "{created}");
        let o = brdf_sls(dir, &["compare", "a", "dated", "--out", "dated-c.html"]);
        assert_eq!(o.status.code(), Some(0), "{created}: {}", stderr(&o));
    }
    let one_point = |v: &mut serde_json::Value| {
        if v["key"] == "tuning/RPLS/0" {
            let trace = v["result"]["trace"].as_array_mut().unwrap();
            trace.last_mut().unwrap()["at"]["cpu_seconds"] = 1e300.into();
        }
    };
    edited(dir, "point", one_point);
    edited(dir, "huge", |v| set_cpu_seconds(v, 1e305));
    edited(dir, "subnormal", |v| set_cpu_seconds(v, 5e-324));
    for name in ["point", "huge", "subnormal"] {
        let o = brdf_sls(dir, &["plot", name]);
        assert_eq!(o.status.code(), Some(0), "plot {name}: {}", stderr(&o));
        let html = format!("{name}.html");
        let o = brdf_sls(dir, &["report", name, "--out", &html]);
        assert_eq!(o.status.code(), Some(0), "report {name}: {}", stderr(&o));
        let o = brdf_sls(
            dir,
            &["compare", "a", name, "--measure", "cpu", "--out", &html],
        );
        // The CPU times differ by a factor of 1e300: B slower or faster, never a panic.
        assert!(
            matches!(o.status.code(), Some(0 | 3)),
            "compare {name}: {:?} {}",
            o.status.code(),
            stderr(&o)
        );
    }
}
