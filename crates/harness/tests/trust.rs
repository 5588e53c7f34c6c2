//! Issue 45's third round of probes on results folders: a packed file with a torn last line,
//! pages and statistics written only where the user said, terminal escapes in labels, and
//! edited results files. Each test failed before its fix.
#![cfg(unix)]

mod support;
use std::path::Path;
use std::process::{Command, Output, Stdio};
use support::PROBE_SPEC as SPEC;

fn brdf_sls(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_brdf-sls"))
        .args(args)
        .current_dir(dir)
        .env("CI", "true")
        .stdin(Stdio::null())
        .output()
        .unwrap()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn all_text(o: &Output) -> String {
    format!("{}{}", String::from_utf8_lossy(&o.stdout), stderr(o))
}

/// Asserts exit status `code` and an error message holding every one of `parts`.
fn assert_refused(o: &Output, code: i32, parts: &[&str]) {
    let err = stderr(o);
    assert_eq!(o.status.code(), Some(code), "{err}");
    for p in parts {
        assert!(err.contains(p), "expected `{p}` in: {err}");
    }
}

/// A temporary folder with `probe.toml` (`spec`) and its finished run in `done/`.
fn with_a_run_of(spec: &str) -> tempfile::TempDir {
    let tmp = tempfile::tempdir().unwrap();
    std::fs::write(tmp.path().join("probe.toml"), spec).unwrap();
    let o = brdf_sls(
        tmp.path(),
        &["run", "probe.toml", "--out", "done", "--no-plots"],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    tmp
}

fn with_a_run() -> tempfile::TempDir {
    with_a_run_of(SPEC)
}

fn gzip(bytes: &[u8]) -> Vec<u8> {
    let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
    std::io::Write::write_all(&mut gz, bytes).unwrap();
    gz.finish().unwrap()
}

/// Item 4: `gzip` of a results file whose last line is torn, as the only results file. The
/// next `run` unpacked it, cut the torn line and went on; every later `run`, `stats` and
/// `export` then exited 2 ("holds both ..."). Now every command reads the folder.
#[test]
fn a_packed_file_with_a_torn_last_line_does_not_wedge_the_folder() {
    let tmp = with_a_run();
    let dir = tmp.path();
    let done = dir.join("done");
    let mut bytes = std::fs::read(done.join("trials.jsonl")).unwrap();
    // Drop the last trial line and put half of it back: a torn last line.
    let text = String::from_utf8(bytes.clone()).unwrap();
    let last = text.trim_end().rsplit('\n').next().unwrap().to_string();
    bytes.truncate(bytes.len() - last.len() - 1);
    bytes.extend_from_slice(&last.as_bytes()[..last.len() / 2]);
    std::fs::write(done.join("trials.jsonl.gz"), gzip(&bytes)).unwrap();
    std::fs::remove_file(done.join("trials.jsonl")).unwrap();
    for args in [
        vec!["run", "probe.toml", "--out", "done", "--no-plots"],
        vec!["run", "probe.toml", "--out", "done", "--no-plots"],
        vec!["stats", "done"],
        vec!["export", "--format", "ioh", "done"],
    ] {
        let o = brdf_sls(dir, &args);
        assert_eq!(o.status.code(), Some(0), "{args:?}: {}", stderr(&o));
    }
}

/// Item 9: pages and statistics go where the user said, and never into a folder a run holds.
#[test]
fn pages_are_written_only_where_the_user_said() {
    let tmp = with_a_run();
    let dir = tmp.path();
    let done = dir.join("done");
    {
        let _held = brdf_experiment::store::DirLock::acquire(&done).unwrap();
        for args in [vec!["report", "done"], vec!["compare", "done", "done"]] {
            let o = brdf_sls(dir, &args);
            assert_refused(&o, 1, &["done is in use by another brdf-sls process"]);
        }
        assert!(!done.join("report.html").exists());
        assert!(!done.join("compare.html").exists());
        // Elsewhere is fine.
        let o = brdf_sls(dir, &["report", "done", "--out", "page.html"]);
        assert!(o.status.success(), "{}", stderr(&o));
    }
    // `stats D --out O` and `plot D --out O` write into O and leave D alone.
    let before = std::fs::read(done.join("stats.csv")).unwrap();
    std::fs::remove_file(done.join("stats.csv")).unwrap();
    let o = brdf_sls(dir, &["stats", "done", "--out", "elsewhere"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(dir.join("elsewhere/stats.csv").exists());
    assert!(
        !done.join("stats.csv").exists(),
        "stats rewrote the results folder"
    );
    let o = brdf_sls(dir, &["plot", "done", "--out", "plots-here"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(dir.join("plots-here/plots").is_dir());
    assert!(
        !done.join("plots").exists(),
        "plot wrote into the results folder"
    );
    std::fs::write(done.join("stats.csv"), before).unwrap();

    // `report A B` without --out would replace A's own page.
    let o = brdf_sls(dir, &["report", "done"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let page = std::fs::read(done.join("report.html")).unwrap();
    let o = brdf_sls(dir, &["report", "done", "done"]);
    assert_refused(&o, 2, &["needs --out FILE", "report.html"]);
    assert_eq!(std::fs::read(done.join("report.html")).unwrap(), page);
}

/// Item 10: a label holding a terminal escape (clear the screen) was printed raw by `check`,
/// `run`, `stats` and `compare`; it is printed escaped now (pages escape it as HTML already).
#[test]
fn labels_with_terminal_escapes_are_printed_escaped() {
    let spec = SPEC.replace(
        "kind = \"aed\"",
        "kind = \"aed\"\nlabel = \"AED\\u001B[2J\\r\\u009Bx\"",
    );
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    std::fs::write(dir.join("probe.toml"), spec).unwrap();
    for args in [
        vec!["check", "probe.toml"],
        vec!["run", "probe.toml", "--out", "done", "--no-plots"],
        vec!["stats", "done"],
        vec!["stats", "done", "--print-only"],
        vec!["compare", "done", "done"],
    ] {
        let o = brdf_sls(dir, &args);
        assert_eq!(o.status.code(), Some(0), "{args:?}: {}", stderr(&o));
        let text = all_text(&o);
        assert!(
            !text
                .chars()
                .any(|c| c == '\u{1b}' || c == '\r' || c == '\u{9b}'),
            "{args:?} printed a control character: {text:?}"
        );
        if args[0] != "run" {
            assert!(text.contains("AED\\u{1b}[2J"), "{args:?}: {text}");
        }
    }
}

/// `done`'s results with `edit` applied to the first trial line, written to `dir/edited`;
/// returns that line's 1-based number.
fn edit_first_trial(dir: &Path, edit: impl Fn(&mut serde_json::Value)) -> usize {
    let text = std::fs::read_to_string(dir.join("done/trials.jsonl")).unwrap();
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    let at = lines
        .iter()
        .position(|l| l.contains("\"type\":\"trial\""))
        .unwrap();
    let mut v: serde_json::Value = serde_json::from_str(&lines[at]).unwrap();
    edit(&mut v);
    lines[at] = v.to_string();
    std::fs::create_dir_all(dir.join("edited")).unwrap();
    std::fs::write(dir.join("edited/trials.jsonl"), lines.join("\n") + "\n").unwrap();
    at + 1
}

/// Item 11: an edited seed or target, or a negative time, in a results file was accepted by
/// every command but a resume; each is refused now, naming the file, the line and the key.
#[test]
fn edited_seeds_targets_and_negative_times_are_refused_naming_file_line_and_key() {
    let tmp = with_a_run();
    let dir = tmp.path();
    let commands: [&[&str]; 5] = [
        &["stats", "edited", "--print-only"],
        &["report", "edited", "--out", "page.html"],
        &["compare", "done", "edited", "--out", "page.html"],
        &["export", "--format", "ioh", "edited", "--out", "ioh"],
        &["merge", "merged", "edited"],
    ];
    let line = edit_first_trial(dir, |v| {
        let seed = v["seed"].as_u64().unwrap();
        v["seed"] = (seed ^ 1).into();
    });
    let at = format!("edited/trials.jsonl:{line}");
    // `run` too: resuming checks seeds (exit 2, as the Python package's InputError).
    let run: &[&str] = &["run", "probe.toml", "--out", "edited", "--no-plots"];
    for args in commands.iter().chain([&run]) {
        let o = brdf_sls(dir, args);
        assert_refused(&o, 2, &[&at, "has seed", "the plan's seed"]);
    }
    let line = edit_first_trial(dir, |v| v["target"] = 0.5.into());
    let at = format!("edited/trials.jsonl:{line}");
    // merge checks seeds only (a relative target needs the best-known RMSE); a resume checks
    // targets too.
    for args in commands[..4].iter().chain([&run]) {
        let o = brdf_sls(dir, args);
        assert_refused(&o, 2, &[&at, "has target 0.5", "the plan's target"]);
    }
    let line = edit_first_trial(dir, |v| {
        v["result"]["ended_at"]["cpu_seconds"] = (-1.0).into()
    });
    let at = format!("edited/trials.jsonl:{line}");
    for args in commands
        .iter()
        .chain([&["run", "probe.toml", "--out", "edited", "--no-plots"][..]].iter())
    {
        let o = brdf_sls(dir, args);
        assert_refused(
            &o,
            2,
            &[&at, "`result.ended_at.cpu_seconds` is -1", "at least 0"],
        );
    }
    assert!(!dir.join("merged/trials.jsonl").exists());
}

/// Item 8: `gen --out` through a dangling link created the link target's missing folders
/// wherever it pointed; links inside a results folder (`stats.json`, `report.html`, `plots/`)
/// were written through, outside the folder. Both are refused now and nothing is written.
#[test]
fn links_never_lead_writes_outside_where_the_user_said() {
    use std::os::unix::fs::symlink;
    let tmp = with_a_run();
    let dir = tmp.path();
    symlink("elsewhere/deep/x.csv", dir.join("dangling.csv")).unwrap();
    let o = brdf_sls(
        dir,
        &[
            "gen",
            "--params",
            "tuning",
            "--samples",
            "10",
            "--out",
            "dangling.csv",
        ],
    );
    assert_refused(&o, 2, &["dangling.csv", "whose folder does not exist"]);
    assert!(
        !dir.join("elsewhere").exists(),
        "gen created folders elsewhere"
    );

    let done = dir.join("done");
    std::fs::write(dir.join("victim.txt"), "mine").unwrap();
    std::fs::create_dir(dir.join("victim-dir")).unwrap();
    let cases: [(&str, &str, &[&str]); 3] = [
        ("stats.json", "../victim.txt", &["stats", "done"]),
        ("report.html", "../victim.txt", &["report", "done"]),
        ("plots", "../victim-dir", &["plot", "done"]),
    ];
    for (name, to, args) in cases {
        let at = done.join(name);
        let _ = std::fs::remove_file(&at);
        let _ = std::fs::remove_dir_all(&at);
        symlink(to, &at).unwrap();
        let o = brdf_sls(dir, args);
        assert_refused(&o, 2, &[name, "is a symbolic link", "remove the link"]);
        std::fs::remove_file(&at).unwrap();
    }
    assert_eq!(
        std::fs::read_to_string(dir.join("victim.txt")).unwrap(),
        "mine"
    );
    assert_eq!(
        std::fs::read_dir(dir.join("victim-dir")).unwrap().count(),
        0
    );
    // A link inside plots/ is refused too.
    std::fs::create_dir_all(done.join("plots")).unwrap();
    symlink("../../victim.txt", done.join("plots/x.png")).unwrap();
    let o = brdf_sls(dir, &["plot", "done"]);
    assert_refused(&o, 2, &["x.png", "is a symbolic link"]);
    assert_eq!(
        std::fs::read_to_string(dir.join("victim.txt")).unwrap(),
        "mine"
    );
}

/// Item 5: results files were read whole (a 2 GB `trials.jsonl` took 4.2 GB) up to 8 GiB.
/// They are parsed as they are read now, and refused past the documented 4 GiB at once,
/// before reading (a sparse file: no disk space used).
#[test]
fn a_results_file_past_the_documented_limit_is_refused_before_reading() {
    let tmp = with_a_run();
    let dir = tmp.path();
    std::fs::create_dir(dir.join("huge")).unwrap();
    let text = std::fs::read(dir.join("done/trials.jsonl")).unwrap();
    let file = std::fs::File::create(dir.join("huge/trials.jsonl")).unwrap();
    std::io::Write::write_all(&mut &file, &text).unwrap();
    file.set_len(brdf_experiment::store::MAX_RESULTS_BYTES + 1)
        .unwrap();
    for args in [
        vec!["stats", "huge", "--print-only"],
        vec!["report", "huge", "--out", "page.html"],
        vec!["export", "--format", "ioh", "huge", "--out", "ioh"],
    ] {
        let o = brdf_sls(dir, &args);
        assert_refused(&o, 2, &["huge/trials.jsonl", "4294967296"]);
    }
}

/// Item 23 (papercuts): `trials = 0` was refused without its line; a run that failed before
/// writing results (a data file that is gone) left an empty folder holding only `.lock`.
#[test]
fn papercuts_trials_line_and_no_empty_folder_after_a_failed_run() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    std::fs::write(
        dir.join("zero.toml"),
        SPEC.replace("trials = 3", "trials = 0"),
    )
    .unwrap();
    let o = brdf_sls(dir, &["check", "zero.toml"]);
    assert_refused(&o, 2, &["zero.toml:4: `trials` must be at least 1"]);

    let gone = format!(
        "{SPEC}\n[[instance]]\nname = \"gone\"\ntargets = [0.1]\n[instance.file]\npath = \"gone.csv\"\n"
    );
    std::fs::write(dir.join("gone.toml"), gone).unwrap();
    let o = brdf_sls(dir, &["run", "gone.toml", "--out", "new", "--no-plots"]);
    assert!(!o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("gone.csv"), "{}", stderr(&o));
    assert!(
        !dir.join("new").exists(),
        "a failed run left its folder behind"
    );
    // An existing folder stays, without a stray lock file.
    std::fs::create_dir(dir.join("old")).unwrap();
    let o = brdf_sls(dir, &["run", "gone.toml", "--out", "old", "--no-plots"]);
    assert!(!o.status.success(), "{}", stderr(&o));
    assert!(dir.join("old").is_dir());
    assert!(
        !dir.join("old/.lock").exists(),
        "a failed run left .lock behind"
    );
}

/// Item 23: a results folder that may not be written (a read-only working folder) says to use
/// --out, for `run`, `stats`, `plot` and `report`. Root ignores permissions, so the test is
/// skipped where a file can be created in a folder of mode 0555 (CI runs as root: the
/// message's formatting has a unit test in the harness, `with_out_hint`).
#[test]
fn a_read_only_results_folder_says_to_use_out() {
    use std::os::unix::fs::PermissionsExt;
    let tmp = with_a_run();
    let dir = tmp.path();
    let mode = |p: &Path, m: u32| {
        std::fs::set_permissions(p, std::fs::Permissions::from_mode(m)).unwrap();
    };
    // `done` holds results (and its .lock): no new file may be made in it.
    let _ = std::fs::remove_file(dir.join("done/.lock"));
    mode(&dir.join("done"), 0o555);
    let root = std::fs::write(dir.join("done/probe"), "").is_ok();
    if !root {
        for args in [
            &["stats", "done"][..],
            &["plot", "done"],
            &["report", "done"],
            &["run", "probe.toml", "--out", "done", "--no-plots"],
        ] {
            let o = brdf_sls(dir, args);
            assert_refused(&o, 1, &["use --out DIR to write elsewhere"]);
        }
        // A read-only working folder: the default results folder cannot be created.
        mode(dir, 0o555);
        let o = brdf_sls(dir, &["run", "probe.toml", "--no-plots"]);
        mode(dir, 0o755);
        assert_refused(&o, 1, &["use --out DIR to write elsewhere"]);
    }
    mode(&dir.join("done"), 0o755);
}
