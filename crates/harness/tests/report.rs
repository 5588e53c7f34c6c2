//! `brdf-sls report`, `compare`, `completions` and `man`, and BRDF_SLS_THREADS, through the
//! binary on a tiny experiment run twice.

#[path = "../../experiment/tests/common/mod.rs"]
mod common;

use std::path::Path;
use std::process::{Command, Output};

use brdf_analysis::html::wellformed;

fn brdf_sls(args: &[&str], cwd: &Path, env: &[(&str, &str)]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_brdf-sls"))
        .args(args)
        .current_dir(cwd)
        .env("CI", "true")
        .env_remove("BRDF_SLS_THREADS")
        .envs(env.iter().copied())
        .output()
        .unwrap()
}

fn text(o: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

/// Runs `args` and asserts the exit status.
fn expect(code: i32, args: &[&str], cwd: &Path) -> String {
    let o = brdf_sls(args, cwd, &[]);
    assert_eq!(o.status.code(), Some(code), "{args:?}: {}", text(&o));
    text(&o)
}

/// The tiny spec with 4 trials: 3 configurations on one instance, an evaluation budget, so
/// a second run with other kernel reaches the same targets at nearly the same counts.
fn tiny(dir: &Path) {
    std::fs::write(dir.join("tiny.toml"), common::TINY).unwrap();
}

/// Multiplies every recorded time (CPU seconds and sample-evaluations) of a results folder by
/// `factor`, as a much slower build would record them.
fn slow_down(dir: &Path, factor: u64) {
    let path = dir.join("trials.jsonl");
    let text = std::fs::read_to_string(&path).unwrap();
    let mut out = String::new();
    for line in text.lines() {
        let mut v: serde_json::Value = serde_json::from_str(line).unwrap();
        if let Some(r) = v.get_mut("result") {
            scale_stamps(r, factor);
        }
        out.push_str(&v.to_string());
        out.push('\n');
    }
    std::fs::write(&path, out).unwrap();
}

fn scale_stamps(v: &mut serde_json::Value, factor: u64) {
    match v {
        serde_json::Value::Object(m) => {
            if let Some(c) = m.get("cpu_seconds").and_then(|c| c.as_f64()) {
                m.insert("cpu_seconds".into(), (c * factor as f64).into());
            }
            for key in [
                "residual_rows",
                "jacobian_rows",
                "rmse_rows",
                "rmse_rows_computed",
            ] {
                if let Some(n) = m.get(key).and_then(|n| n.as_u64()) {
                    m.insert(key.into(), (n * factor).into());
                }
            }
            m.values_mut().for_each(|x| scale_stamps(x, factor));
        }
        serde_json::Value::Array(a) => a.iter_mut().for_each(|x| scale_stamps(x, factor)),
        _ => {}
    }
}

#[test]
fn run_report_and_compare_end_to_end() {
    let d = tempfile::tempdir().unwrap();
    let dir = d.path();
    tiny(dir);
    let run_a = ["run", "tiny.toml", "--out", "a", "--threads", "2"];
    expect(0, &run_a, dir);
    let page = std::fs::read_to_string(dir.join("a/report.html")).unwrap();
    wellformed::check(&page).unwrap();
    for want in [
        "Experiment and plan",
        "Provenance",
        "Instance tuning",
        "Success, median and ERT",
        "Pairwise tests",
        "Best fit",
        "same BRDF has other parameter sets",
        "RTD in CPU seconds - tuning, target RMSE 0.105",
        "sample-evaluations to reach RMSE",
        "Run time vs target error",
        "AED: ERT and median vs phi",
    ] {
        assert!(page.contains(want), "report.html lacks {want}");
    }
    assert!(!page.contains("Partial results"));
    // The answer first: the summary (with its sentence) before the plan and provenance, and
    // the views and explanations the reader needs.
    let at = |s: &str| {
        page.find(s)
            .unwrap_or_else(|| panic!("report.html lacks {s}"))
    };
    assert!(at("<table class=\"summary\">") < at("<h3>Experiment and plan</h3>"));
    assert!(at("<ul class=\"verdicts\">") < at("<h3>Provenance</h3>"));
    for want in [
        "lowest ERT",
        "How to read this page",
        "Kaplan-Meier",
        "Best RMSE by budget - tuning",
        "<ul class=\"legend\">",
        "data-key=\"RPLS\"",
        "<a href=\"stats.csv\">stats.csv</a>",
        "<details class=\"toc\">",
        "<details class=\"tests\">",
    ] {
        at(want);
    }
    assert!(!page.contains("<script"), "the page needs no script");
    assert!(!page.contains("http://") || !page.contains("src=\"http"));

    let run_b = [
        "run",
        "tiny.toml",
        "--out",
        "b",
        "--no-plots",
        "--kernel",
        "portable",
    ];
    expect(0, &run_b, dir);
    assert!(
        !dir.join("b/report.html").exists(),
        "--no-plots writes no page"
    );

    // Both folders on one page.
    expect(0, &["report", "a", "b", "--out", "both.html"], dir);
    let both = std::fs::read_to_string(dir.join("both.html")).unwrap();
    wellformed::check(&both).unwrap();
    assert_eq!(both.matches("<h2>tiny (").count(), 2);

    // Same spec, other kernel: comparable, nothing slower.
    let t = expect(0, &["compare", "a", "b"], dir);
    let lines: Vec<&str> = t.lines().filter(|l| l.starts_with("tuning")).collect();
    assert_eq!(lines.len(), 6, "3 configurations x 2 targets:\n{t}");
    assert!(
        lines
            .iter()
            .all(|l| l.contains("no significant difference")),
        "{t}"
    );
    let cpage = std::fs::read_to_string(dir.join("b/compare.html")).unwrap();
    wellformed::check(&cpage).unwrap();
    assert!(cpage.contains("A (solid) vs B (dashed)"));

    // B ten times slower: exit status 3, the verdict's own (alpha raised: 4 trials per side
    // are few); 1 stays for failures such as a page that cannot be written.
    copy_dir(&dir.join("b"), &dir.join("slow"));
    slow_down(&dir.join("slow"), 10);
    let t = expect(
        3,
        &["compare", "a", "slow", "--alpha", "0.5", "--out", "s.html"],
        dir,
    );
    assert!(
        t.contains("slower") && t.contains("significantly slower in slow"),
        "{t}"
    );
    expect(
        0,
        &["compare", "slow", "a", "--alpha", "0.5", "--out", "s.html"],
        dir,
    );
    // A page that cannot be written (its folder is a file): a failure, 1.
    let t = expect(
        1,
        &["compare", "a", "b", "--out", "a/report.html/c.html"],
        dir,
    );
    assert!(t.contains("Not a directory"), "{t}");

    // A different budget: nothing comparable, bad input, the reason printed.
    let other = common::TINY.replace("evaluations = 400000", "evaluations = 300000");
    std::fs::write(dir.join("other.toml"), other).unwrap();
    expect(
        0,
        &[
            "run",
            "other.toml",
            "--out",
            "c",
            "--limit",
            "3",
            "--no-plots",
        ],
        dir,
    );
    let t = expect(2, &["compare", "a", "c", "--out", "c.html"], dir);
    assert!(t.contains("not comparable: different budget/cutoff"), "{t}");
    let t = expect(0, &["report", "c", "--out", "c-report.html"], dir);
    assert!(t.contains("partial results"), "{t}");
    let page = std::fs::read_to_string(dir.join("c-report.html")).unwrap();
    assert!(page.contains("Partial results: 3 of 12 trials present"));
}

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap() {
        let e = e.unwrap();
        if e.file_type().unwrap().is_file() {
            std::fs::copy(e.path(), to.join(e.file_name())).unwrap();
        }
    }
}

#[test]
fn bad_input_to_report_and_compare_exits_2_naming_it() {
    let d = tempfile::tempdir().unwrap();
    let t = expect(2, &["report", "nowhere"], d.path());
    assert!(t.contains("nowhere: no results here"), "{t}");
    let t = expect(2, &["compare", "x", "y", "--alpha", "2"], d.path());
    assert!(t.contains("--alpha must be between 0 and 1"), "{t}");
    let t = expect(2, &["compare", "x", "y"], d.path());
    assert!(t.contains("x: no results here"), "{t}");
    expect(2, &["report"], d.path());
}

#[test]
fn completions_for_every_shell_mention_compare() {
    let d = tempfile::tempdir().unwrap();
    for shell in ["bash", "zsh", "fish", "powershell"] {
        let t = expect(0, &["completions", shell], d.path());
        assert!(t.len() > 1000, "{shell}: {t}");
        assert!(t.contains("compare") && t.contains("min-effect"), "{shell}");
    }
    expect(2, &["completions", "tcsh"], d.path());
}

#[test]
fn the_man_page_renders() {
    let d = tempfile::tempdir().unwrap();
    let t = expect(0, &["man"], d.path());
    assert!(t.starts_with(".ie") || t.contains(".TH brdf-sls 1"), "{t}");
    assert!(
        t.contains("BRDF_SLS_THREADS") && t.contains("compare"),
        "{t}"
    );
    let t = expect(0, &["man", "--out", "man"], d.path());
    assert!(t.contains("wrote brdf-sls.1"), "{t}");
    let page = std::fs::read_to_string(d.path().join("man/brdf-sls-compare.1")).unwrap();
    assert!(page.contains("min\\-effect"), "{page}");
}

#[test]
fn brdf_sls_threads_sets_the_default_thread_count() {
    let d = tempfile::tempdir().unwrap();
    tiny(d.path());
    let args = ["run", "tiny.toml", "--limit", "1", "--no-plots"];
    let o = brdf_sls(&args, d.path(), &[("BRDF_SLS_THREADS", "3")]);
    assert!(o.status.success(), "{}", text(&o));
    // One trial to run: the pool is capped at it, and the note names the 3 the variable asked for.
    assert!(text(&o).contains("not the 3 asked for"), "{}", text(&o));
    // The flag wins over the variable.
    let o = brdf_sls(
        &[
            "run",
            "tiny.toml",
            "--limit",
            "1",
            "--no-plots",
            "--threads",
            "1",
        ],
        d.path(),
        &[("BRDF_SLS_THREADS", "3")],
    );
    assert!(text(&o).contains("1 worker thread(s)"), "{}", text(&o));
    let o = brdf_sls(&args, d.path(), &[("BRDF_SLS_THREADS", "many")]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(text(&o).contains("many"), "{}", text(&o));
    let t = expect(0, &["run", "--help"], d.path());
    assert!(t.contains("BRDF_SLS_THREADS"), "{t}");
}
