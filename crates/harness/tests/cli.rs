//! The `brdf-sls` binary: every command runs and fails cleanly on bad input.

#[path = "../../experiment/tests/common/mod.rs"]
mod common;

mod support;
use support::{brdf_sls, text};

use std::path::Path;
use std::process::{Command, Output};

#[test]
fn help_on_every_command() {
    let dir = tempfile::tempdir().unwrap();
    for cmd in [
        "run", "check", "plot", "stats", "fit", "gen", "eval", "info", "render", "polar", "bench",
    ] {
        let o = brdf_sls(&[cmd, "--help"], dir.path());
        assert!(o.status.success(), "{cmd}: {}", text(&o));
        assert!(text(&o).contains("Usage"), "{cmd}");
    }
}

#[test]
fn check_run_plot_stats() {
    let dir = tempfile::tempdir().unwrap();
    let spec = dir.path().join("tiny.toml");
    std::fs::write(&spec, common::TINY.replace("trials = 4", "trials = 2")).unwrap();
    let o = brdf_sls(&["check", "tiny.toml", "--threads", "2"], dir.path());
    assert!(o.status.success(), "{}", text(&o));
    let t = text(&o);
    assert!(
        t.contains("3 configuration(s) x 2 trials = 6 trials"),
        "{t}"
    );
    assert!(t.contains("AED phi=1.2"), "{t}");
    // Issue 45, item 18: check states how many samples the best-known fit's lobes cover.
    assert!(
        t.contains("best-known fit's lobe1 on ") && t.contains(" samples (a lobe is on a sample"),
        "{t}"
    );

    let o = brdf_sls(
        &["run", "tiny.toml", "--threads", "2", "--no-plots"],
        dir.path(),
    );
    assert!(o.status.success(), "{}", text(&o));
    let t = text(&o);
    assert!(t.contains("target RMSE 0.105") && t.contains("RPLS"), "{t}");
    assert!(dir.path().join("runs/tiny/trials.jsonl").exists());
    assert!(!dir.path().join("runs/tiny/plots").exists());

    // Re-plot from the results directory alone (spec read from the header).
    let o = brdf_sls(&["plot", "runs/tiny"], dir.path());
    assert!(o.status.success(), "{}", text(&o));
    assert!(dir.path().join("runs/tiny/plots/tuning-trace.png").exists());
    let o = brdf_sls(&["stats", "tiny.toml"], dir.path());
    assert!(o.status.success(), "{}", text(&o));
    // `stats` writes no plots, but the summary still lists those `plot` drew.
    let summary = std::fs::read_to_string(dir.path().join("runs/tiny/summary.json")).unwrap();
    assert!(summary.contains("plots/tuning-trace.png"), "{summary}");
    // A folder that does not exist is bad input named as such.
    let o = brdf_sls(&["stats", "no-such-folder"], dir.path());
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    let t = text(&o);
    assert!(t.contains("no-such-folder: no such file or folder"), "{t}");

    // A changed spec is refused with advice.
    std::fs::write(&spec, common::TINY.replace("seed = 11", "seed = 99")).unwrap();
    let o = brdf_sls(&["run", "tiny.toml", "--progress", "quiet"], dir.path());
    // Bad input (exit status 2), not a failure while running.
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    let t = text(&o);
    assert!(t.contains("different spec") && t.contains("--fresh"), "{t}");

    // A bad spec names the key and line.
    std::fs::write(
        &spec,
        common::TINY.replace("trials = 4", "trials = 4\ntrails = 1"),
    )
    .unwrap();
    let o = brdf_sls(&["check", "tiny.toml"], dir.path());
    assert!(!o.status.success());
    let t = text(&o);
    assert!(t.contains("trails") && t.contains("line 5"), "{t}");
}

#[test]
fn gen_info_eval_fit() {
    let dir = tempfile::tempdir().unwrap();
    let o = brdf_sls(
        &[
            "gen",
            "--params",
            "tuning",
            "--samples",
            "300",
            "--sigma",
            "0",
            "--out",
            "t.csv",
        ],
        dir.path(),
    );
    assert!(o.status.success(), "{}", text(&o));
    let o = brdf_sls(&["info", "t.csv"], dir.path());
    assert!(o.status.success(), "{}", text(&o));
    let t = text(&o);
    assert!(t.contains("samples: 300") && t.contains("theta"), "{t}");

    // Noise-free data: the generating parameters fit exactly.
    let o = brdf_sls(&["eval", "t.csv", "--params", "tuning"], dir.path());
    assert!(o.status.success(), "{}", text(&o));
    assert!(text(&o).contains("RMSE 0.000000"), "{}", text(&o));
    let o = brdf_sls(
        &["eval", "t.csv", "--kd", "0.15", "--lobe=-1,0.8,0.96,20,45"],
        dir.path(),
    );
    assert!(text(&o).contains("RMSE 0.000000"), "{}", text(&o));

    // Flags: a Phong-like lobe.
    let o = brdf_sls(
        &[
            "gen",
            "--kd",
            "0.1",
            "--lobe=-0.5,-0.5,0.5,5",
            "--samples",
            "50",
            "--out",
            "p.csv",
        ],
        dir.path(),
    );
    assert!(o.status.success(), "{}", text(&o));

    let o = brdf_sls(
        &[
            "fit",
            "t.csv",
            "--algorithm",
            "aed",
            "--set",
            "phi=1.2",
            "--target",
            "0.001",
            "--cpu-seconds",
            "2",
        ],
        dir.path(),
    );
    assert!(o.status.success(), "{}", text(&o));
    let t = text(&o);
    assert!(
        t.contains("lobe1.pan") && t.contains("RMSE") && t.contains("kd"),
        "{t}"
    );

    assert!(t.contains("lobes: lobe1 on ") && !t.contains("dead"), "{t}");
    // An anisotropic lobe has a mirrored form (pan + 90, x and y swapped): fit says so.
    assert!(
        t.contains("same BRDF has other parameter sets") && t.contains("docs/model.md"),
        "{t}"
    );
    // A second lobe held where d < 0 on every sample is dead, and fit says so.
    let dead = [
        "fit",
        "t.csv",
        "--lobes",
        "2",
        "--fix",
        "lobe2.cx=0",
        "--fix",
        "lobe2.cy=0",
        "--fix",
        "lobe2.cz=-1.5",
        "--cpu-seconds",
        "0.3",
        "--target",
        "0.001",
    ];
    let o = brdf_sls(&dead, dir.path());
    assert!(o.status.success(), "{}", text(&o));
    let t = text(&o);
    assert!(
        t.contains("lobe2 dead")
            && t.contains("warning: lobe2 is dead")
            && t.contains("1 working lobe(s) of 2"),
        "{t}"
    );

    let o = brdf_sls(&["info", "missing.csv"], dir.path());
    assert!(!o.status.success());
    assert!(text(&o).contains("missing.csv"));
    let o = brdf_sls(&["fit", "t.csv", "--set", "phy=1"], dir.path());
    assert!(!o.status.success());
    assert!(text(&o).contains("phy"), "{}", text(&o));
    // Issue 45, items 11 and 12: refused up front with status 2, naming what is wrong.
    for (args, says) in [
        (
            &["fit", "t.csv", "--set", "phi=1.4", "--set", "phi=2"][..],
            "`phi` given twice",
        ),
        (
            &["fit", "t.csv", "--cpu-seconds", "1e300"][..],
            "at most 1e7 CPU seconds",
        ),
        (&["fit", "p.csv", "--lobes", "10"][..], "needs at least 52"),
        (
            &[
                "fit",
                "t.csv",
                "--kind",
                "isotropic",
                "--fix",
                "kd=0.1",
                "--fix",
                "lobe1.cxy=-1",
                "--fix",
                "lobe1.cz=1",
                "--fix",
                "lobe1.n=20",
            ][..],
            "every parameter is fixed",
        ),
    ] {
        let o = brdf_sls(args, dir.path());
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", text(&o));
        assert!(text(&o).contains(says), "{args:?}: {}", text(&o));
    }
}

/// The Cornell data shipped with the repository (absolute, so tests can run elsewhere).
fn cornell(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join(format!("../../experiments/data/{name}.brdf"))
        .to_string_lossy()
        .into_owned()
}

/// Width and height from a PNG's IHDR chunk (which always comes first).
fn png_size(bytes: &[u8]) -> (u32, u32) {
    assert!(bytes.len() > 24, "{} bytes", bytes.len());
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
    assert_eq!(&bytes[12..16], b"IHDR");
    let be = |b: &[u8]| u32::from_be_bytes([b[0], b[1], b[2], b[3]]);
    (be(&bytes[16..20]), be(&bytes[20..24]))
}

fn failed_cleanly(o: &Output) -> String {
    assert!(!o.status.success(), "{}", text(o));
    let t = text(o);
    assert!(!t.contains("panicked"), "{t}");
    t
}

#[test]
fn render_writes_a_png_of_the_requested_size() {
    let dir = tempfile::tempdir().unwrap();
    let o = brdf_sls(
        &[
            "render",
            "--params",
            "cross",
            "--width",
            "48",
            "--height",
            "32",
            "--supersampling",
            "1",
            "--light",
            "-0.3,0.2,1.5",
            "--tone-map",
            "reinhard",
            "--tint",
            "1,0.8,0.6",
            "--out",
            "sub/cross.png",
        ],
        dir.path(),
    );
    assert!(o.status.success(), "{}", text(&o));
    assert!(text(&o).contains("48x32"), "{}", text(&o));
    let bytes = std::fs::read(dir.path().join("sub/cross.png")).unwrap();
    assert_eq!(png_size(&bytes), (48, 32));

    // Flags instead of a named set, and the default output name.
    let o = brdf_sls(
        &[
            "render",
            "--kd",
            "0.1",
            "--lobe=-1,1,1,30",
            "--width",
            "20",
            "--height",
            "20",
            "--supersampling",
            "1",
        ],
        dir.path(),
    );
    assert!(o.status.success(), "{}", text(&o));
    let bytes = std::fs::read(dir.path().join("render.png")).unwrap();
    assert_eq!(png_size(&bytes), (20, 20));
}

#[test]
fn render_rejects_bad_options_naming_the_flag() {
    let dir = tempfile::tempdir().unwrap();
    let small = ["--width", "8", "--height", "8", "--params", "tuning"];
    for (extra, flag) in [
        (&["--fov", "200"][..], "--fov"),
        (&["--light", "0,0,-1"][..], "--light"),
        (&["--light", "1,2"][..], "--light"),
        (
            &["--camera", "0,0,1", "--look-at", "0,0,1"][..],
            "--look-at",
        ),
        (&["--exposure", "0"][..], "--exposure"),
        (&["--exposure", "-1"][..], "--exposure"),
        (&["--intensity", "-2"][..], "--intensity"),
        (&["--tint", "1,-1,1"][..], "--tint"),
        (&["--supersampling", "99"][..], "--supersampling"),
        (&["--half-size", "nan"][..], "--half-size"),
        (&["--out", "picture.jpg"][..], "--out"),
    ] {
        let args: Vec<&str> = std::iter::once("render")
            .chain(small)
            .chain(extra.iter().copied())
            .collect();
        let o = brdf_sls(&args, dir.path());
        let t = failed_cleanly(&o);
        assert!(t.contains(flag), "{extra:?}: {t}");
    }
    let o = brdf_sls(
        &["render", "--width", "0", "--params", "tuning"],
        dir.path(),
    );
    assert!(failed_cleanly(&o).contains("--width"));
    let o = brdf_sls(&["render", "--params", "nosuch"], dir.path());
    assert!(failed_cleanly(&o).contains("nosuch"));
    // Nothing was written by the failed runs.
    assert!(!dir.path().join("render.png").exists());
    assert!(!dir.path().join("picture.jpg").exists());
}

#[test]
fn polar_writes_png_and_svg() {
    let dir = tempfile::tempdir().unwrap();
    let data = cornell("krylon_blue");
    let json = r#"{"kd":0.008,"lobes":[{"cx":-1.2,"cy":-1.2,"cz":0.8,"n":10,"pan_deg":0}]}"#;
    std::fs::write(dir.path().join("fit.json"), json).unwrap();
    let o = brdf_sls(
        &[
            "polar",
            &data,
            "--max-value",
            "1",
            "--show-dropped",
            "--incident",
            "10,70",
            "--fit",
            &format!("inline={json}"),
            "--fit",
            "from file=@fit.json",
            "--fit",
            "paper-bluepaint",
            "--radius",
            "measured:1.3",
            "--out",
            "figs/k",
        ],
        dir.path(),
    );
    assert!(o.status.success(), "{}", text(&o));
    let t = text(&o);
    assert!(
        t.contains("inline: RMSE")
            && t.contains("from file: RMSE")
            && t.contains("paper-bluepaint: RMSE"),
        "{t}"
    );
    // The value cap drops the glossy peak at 70 degrees, which --show-dropped reports.
    assert!(
        t.contains("incident 70: 13 measured in-plane samples (3 dropped)"),
        "{t}"
    );
    for ext in ["png", "svg"] {
        let f = dir.path().join(format!("figs/k.{ext}"));
        assert!(std::fs::metadata(&f).unwrap().len() > 1000, "{f:?}");
    }
    let bytes = std::fs::read(dir.path().join("figs/k.png")).unwrap();
    let (w, h) = png_size(&bytes);
    assert!(w >= 2 * 540 && h > 340, "{w}x{h}");
    let svg = std::fs::read_to_string(dir.path().join("figs/k.svg")).unwrap();
    assert!(
        svg.contains("incident 70") && svg.contains("from file"),
        "SVG text"
    );

    // Defaults: angles the data has (10, 40, 70 for Cornell), one format.
    let o = brdf_sls(
        &["polar", &data, "--formats", "png", "--out", "d.svg"],
        dir.path(),
    );
    assert!(o.status.success(), "{}", text(&o));
    let t = text(&o);
    assert!(
        t.contains("incident 10:") && t.contains("incident 40:") && t.contains("incident 70:"),
        "{t}"
    );
    assert!(dir.path().join("d.png").exists() && !dir.path().join("d.svg").exists());
}

#[test]
fn polar_errors_name_the_problem() {
    let dir = tempfile::tempdir().unwrap();
    let data = cornell("krylon_blue");
    // The paper's 35 degrees is not measured in the Cornell files: list what is.
    let o = brdf_sls(
        &["polar", &data, "--incident", "10,35", "--out", "x"],
        dir.path(),
    );
    let t = failed_cleanly(&o);
    assert!(
        t.contains("--incident 35") && t.contains("10, 20, 30, 40, 50, 60, 70, 80"),
        "{t}"
    );
    for (args, needle) in [
        (&["--incident", "95"][..], "--incident 95"),
        (&["--fit", "bad={nope"][..], "--fit"),
        (&["--fit", "x=@missing.json"][..], "missing.json"),
        (&["--radius", "big"][..], "--radius"),
        (&["--plane-tol", "-1"][..], "--plane-tol"),
        (&["--show-dropped"][..], "--max-value"),
        (&["--config", "AED"][..], "--from-results"),
        (
            &["--from-results", "nowhere", "--config", "AED"][..],
            "nowhere",
        ),
    ] {
        let all: Vec<&str> = ["polar", data.as_str(), "--out", "x"]
            .into_iter()
            .chain(args.iter().copied())
            .collect();
        let o = brdf_sls(&all, dir.path());
        let t = failed_cleanly(&o);
        assert!(t.contains(needle), "{args:?}: {t}");
    }
    assert!(!dir.path().join("x.png").exists());
}

#[test]
fn polar_from_results_uses_the_best_trial() {
    let dir = tempfile::tempdir().unwrap();
    let spec = common::TINY
        .replace("trials = 4", "trials = 2")
        .replace("evaluations = 400000", "evaluations = 20000")
        .replace("samples = 400", "samples = 100")
        .replace("[algorithm.sweep]\nphi = [1.2, 1.4]\n", "");
    std::fs::write(dir.path().join("tiny.toml"), spec).unwrap();
    let o = brdf_sls(
        &[
            "run",
            "tiny.toml",
            "--threads",
            "1",
            "--no-plots",
            "--progress",
            "quiet",
        ],
        dir.path(),
    );
    assert!(o.status.success(), "{}", text(&o));
    let data = cornell("krylon_blue");
    let o = brdf_sls(
        &[
            "polar",
            &data,
            "--incident",
            "40",
            "--from-results",
            "runs/tiny",
            "--config",
            "AED",
            "--formats",
            "svg",
            "--out",
            "best",
        ],
        dir.path(),
    );
    assert!(o.status.success(), "{}", text(&o));
    assert!(text(&o).contains("AED best of 2"), "{}", text(&o));
    assert!(dir.path().join("best.svg").exists());
    let o = brdf_sls(
        &[
            "polar",
            &data,
            "--from-results",
            "runs/tiny",
            "--config",
            "ASA",
        ],
        dir.path(),
    );
    let t = failed_cleanly(&o);
    assert!(t.contains("--config `ASA`") && t.contains("AED"), "{t}");
}

#[test]
fn packed_results_are_read_and_resumed_without_unpacking_by_hand() {
    use std::io::Write;
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("tiny.toml"),
        common::TINY.replace("trials = 4", "trials = 1"),
    )
    .unwrap();
    let run = ["run", "tiny.toml", "--no-plots", "--limit", "1"];
    assert!(brdf_sls(&run, dir.path()).status.success());
    // Pack the results as the repository commits them.
    let out = dir.path().join("runs/tiny");
    let plain = out.join("trials.jsonl");
    let mut gz = flate2::write::GzEncoder::new(
        std::fs::File::create(out.join("trials.jsonl.gz")).unwrap(),
        flate2::Compression::best(),
    );
    gz.write_all(&std::fs::read(&plain).unwrap()).unwrap();
    gz.finish().unwrap();
    std::fs::remove_file(&plain).unwrap();

    let o = brdf_sls(&["stats", "runs/tiny", "--print-only"], dir.path());
    assert!(o.status.success(), "{}", text(&o));
    assert!(text(&o).contains("1 of 3 trials"), "{}", text(&o));
    assert!(!plain.exists(), "stats must not unpack");
    let o = brdf_sls(&["run", "tiny.toml", "--no-plots"], dir.path());
    assert!(o.status.success(), "{}", text(&o));
    assert!(text(&o).contains("unpacked"), "{}", text(&o));
    assert!(text(&o).contains("2 new trials"), "{}", text(&o));

    // A corrupt packed file is an error naming it, not a panic.
    let bad = dir.path().join("bad");
    std::fs::create_dir(&bad).unwrap();
    std::fs::write(bad.join("trials.jsonl.gz"), b"not really gzip").unwrap();
    let t = failed_cleanly(&brdf_sls(&["stats", "bad"], dir.path()));
    assert!(t.contains("trials.jsonl.gz"), "{t}");
}

/// Runs `args` with standard output (and, with `close_stderr`, standard error) closed at once
/// by the reader, as `cmd | head -c0` does.
fn with_closed_output(args: &[&str], cwd: &Path, close_stderr: bool) -> std::process::ExitStatus {
    use std::process::Stdio;
    let mut child = Command::new(env!("CARGO_BIN_EXE_brdf-sls"))
        .args(args)
        .current_dir(cwd)
        .env("CI", "true")
        .stdout(Stdio::piped())
        .stderr(if close_stderr {
            Stdio::piped()
        } else {
            Stdio::null()
        })
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    drop(child.stderr.take());
    child.wait().unwrap()
}

#[test]
fn a_closed_output_pipe_ends_quietly_with_status_0() {
    let dir = tempfile::tempdir().unwrap();
    let data = cornell("krylon_blue");
    for args in [
        vec!["info", data.as_str()],
        vec!["eval", data.as_str(), "--params", "tuning"],
        vec!["gen", "--params", "tuning", "--samples", "200000"],
        vec!["check", "--help"],
    ] {
        let status = with_closed_output(&args, dir.path(), false);
        assert_eq!(status.code(), Some(0), "{args:?}");
    }
    // `run` whose output pipes close still writes its statistics, table and plots.
    std::fs::write(dir.path().join("tiny.toml"), common::TINY).unwrap();
    let status = with_closed_output(&["run", "tiny.toml"], dir.path(), true);
    assert_eq!(status.code(), Some(0));
    for f in [
        "table.txt",
        "stats.csv",
        "summary.json",
        "plots/tuning-trace.png",
    ] {
        assert!(dir.path().join("runs/tiny").join(f).exists(), "{f}");
    }
}

#[test]
fn a_full_disk_on_stdout_is_an_error_not_a_panic() {
    let Ok(full) = std::fs::File::create("/dev/full") else {
        return; // not Linux
    };
    let o = Command::new(env!("CARGO_BIN_EXE_brdf-sls"))
        .args(["info", &cornell("krylon_blue")])
        .stdout(full)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(
        err.contains("standard output") && !err.contains("panicked"),
        "{err}"
    );
}

#[test]
fn exit_codes_follow_unix_habits() {
    let dir = tempfile::tempdir().unwrap();
    let code = |args: &[&str]| brdf_sls(args, dir.path()).status.code();
    assert_eq!(code(&["--help"]), Some(0));
    assert_eq!(code(&["no-such-command"]), Some(2));
    assert_eq!(code(&["gen", "--kd", "nan", "--lobe", "1,1,1,2"]), Some(2));
    assert_eq!(code(&["gen", "--kd", "2", "--lobe", "1,1,1,2"]), Some(2));
    assert_eq!(code(&["gen", "--kd", "0.1", "--lobe", "5,1,1,2"]), Some(2));
    assert_eq!(code(&["gen", "--kd", "0.1", "--lobe", "1,1,1,-2"]), Some(2));
    assert_eq!(
        code(&["gen", "--params", "tuning", "--sigma", "1e300"]),
        Some(2)
    );
    assert_eq!(
        code(&["eval", "missing.csv", "--params", "tuning"]),
        Some(2)
    );
    assert_eq!(code(&["run", "missing.toml"]), Some(2));
    std::fs::write(dir.path().join("zero.csv"), vec![0u8; 4096]).unwrap();
    let o = brdf_sls(&["fit", "zero.csv", "--cpu-seconds", "0.1"], dir.path());
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(!text(&o).contains("panicked"));
}

#[test]
fn relative_targets_best_known_and_warnings() {
    let dir = tempfile::tempdir().unwrap();
    let tiny = common::TINY.replace("trials = 4", "trials = 2");
    let with_targets = |t: &str| tiny.replace("targets = [0.105, 0.12]", &format!("targets = {t}"));
    std::fs::write(
        dir.path().join("bad.toml"),
        with_targets("[{ relative = -1 }]"),
    )
    .unwrap();
    let o = brdf_sls(&["check", "bad.toml"], dir.path());
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(text(&o).contains("`targets[0].relative`"), "{}", text(&o));

    // An absolute target below the best-known RMSE is flagged in `check`.
    std::fs::write(dir.path().join("low.toml"), with_targets("[0.01, 0.2]")).unwrap();
    let o = brdf_sls(&["check", "low.toml"], dir.path());
    assert!(o.status.success(), "{}", text(&o));
    assert!(
        text(&o).contains("warning: instance `tuning`: target 0.01 is below the best-known RMSE"),
        "{}",
        text(&o)
    );
    assert!(!text(&o).contains("target 0.2 is"), "{}", text(&o));

    std::fs::write(
        dir.path().join("tiny.toml"),
        with_targets("[{ relative = 0.05 }, 0.2]"),
    )
    .unwrap();
    let o = brdf_sls(&["check", "tiny.toml"], dir.path());
    assert!(o.status.success(), "{}", text(&o));
    assert!(
        text(&o).contains("best-known RMSE") && text(&o).contains("(+5.00%)"),
        "{}",
        text(&o)
    );
    let o = brdf_sls(
        &["run", "tiny.toml", "--no-plots", "--threads", "2"],
        dir.path(),
    );
    assert!(o.status.success(), "{}", text(&o));
    let results = std::fs::read_to_string(dir.path().join("runs/tiny/trials.jsonl")).unwrap();
    let header: serde_json::Value = serde_json::from_str(results.lines().next().unwrap()).unwrap();
    let bk = header["best_known"]["tuning"]["rmse"].as_f64().unwrap();
    assert!((0.08..0.11).contains(&bk), "{bk}");
    // Every trial ran to 5% above the recorded best-known RMSE.
    let trial_target = results
        .lines()
        .filter_map(|l| serde_json::from_str::<serde_json::Value>(l).ok())
        .find(|v| v["type"] == "trial")
        .and_then(|v| v["target"].as_f64())
        .unwrap();
    assert_eq!(trial_target, bk * (1.0 + 0.05));
    let o = brdf_sls(&["stats", "runs/tiny", "--print-only"], dir.path());
    assert!(
        o.status.success() && text(&o).contains("best-known RMSE"),
        "{}",
        text(&o)
    );
}

#[test]
fn ioh_export_matches_the_results() {
    let dir = tempfile::tempdir().unwrap();
    let tiny = common::TINY.replace("trials = 4", "trials = 2");
    std::fs::write(dir.path().join("tiny.toml"), tiny).unwrap();
    let o = brdf_sls(
        &["run", "tiny.toml", "--no-plots", "--threads", "2"],
        dir.path(),
    );
    assert!(o.status.success(), "{}", text(&o));
    let o = brdf_sls(&["export", "--format", "ioh", "nowhere"], dir.path());
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    let o = brdf_sls(
        &["export", "--format", "ioh", "runs/tiny", "--out", "ioh"],
        dir.path(),
    );
    assert!(o.status.success(), "{}", text(&o));
    let meta: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(dir.path().join("ioh/RPLS/IOHprofiler_f1_tuning.json")).unwrap(),
    )
    .unwrap();
    assert_eq!(meta["maximization"], false);
    let scenario = &meta["scenarios"][0];
    assert_eq!(scenario["runs"].as_array().unwrap().len(), 2);
    let dat = std::fs::read_to_string(
        dir.path()
            .join("ioh/RPLS")
            .join(scenario["path"].as_str().unwrap()),
    )
    .unwrap();
    let runs: Vec<&str> = dat.split("evaluations raw_y\n").skip(1).collect();
    assert_eq!(runs.len(), 2, "{dat}");
    for (run, meta_run) in runs.iter().zip(scenario["runs"].as_array().unwrap()) {
        assert!(run.starts_with("1 "), "{run}");
        let last: f64 = run
            .lines()
            .last()
            .unwrap()
            .split(' ')
            .nth(1)
            .unwrap()
            .parse()
            .unwrap();
        assert_eq!(last, meta_run["best"]["y"].as_f64().unwrap());
    }
}

#[test]
fn bench_writes_its_report_shows_progress_and_rejects_bad_flags() {
    let dir = tempfile::tempdir().unwrap();
    let o = brdf_sls(&["bench", "--seeds", "0"], dir.path());
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(text(&o).contains("--seeds 0"), "{}", text(&o));
    let o = brdf_sls(&["bench", "--cutoff", "-1"], dir.path());
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));

    let args = ["bench", "--seeds", "1", "--cutoff", "0.01", "--out", "b"];
    let o = brdf_sls(&[&args[..], &["--progress", "plain"]].concat(), dir.path());
    assert!(o.status.success(), "{}", text(&o));
    // One plain progress line at the end, counting all 12 search rows.
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("12/12 trials") && err.contains("broad log1p RPLS 1/1"),
        "{err}"
    );
    let md = std::fs::read_to_string(dir.path().join("b/bench.md")).unwrap();
    for row in [
        "| tuning | log1p | AED |",
        "| tuning | log1p | RPLS |",
        "| cross | log1p | AERS |",
        "| tuning | raw n | RPLS |",
        "| tuning | raw n | AERS |",
        "| broad | log1p | AED |",
        "| ggx | anisotropic | 6 |",
    ] {
        assert!(md.contains(row), "{row} missing from\n{md}");
    }
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.path().join("b/bench.json")).unwrap()).unwrap();
    assert_eq!(json["searches"].as_array().unwrap().len(), 12);
    // Six goals of issue 38, AED and AERS against RPLS on each of the four search rows, and two
    // per family other than Lafortune.
    let families = json["families"].as_array().unwrap().len();
    assert!(families >= 7, "{families} family rows");
    assert_eq!(
        json["goals"].as_array().unwrap().len(),
        6 + 2 * 4 + 2 * (families - 1)
    );
    assert_eq!(json["seeds"], 1);
    assert!(!json["kernels"].as_array().unwrap().is_empty());
    // The load before and after is recorded (Linux has /proc/loadavg) and reported.
    if std::path::Path::new("/proc/loadavg").exists() {
        for key in ["load_before", "load_after"] {
            assert_eq!(json[key].as_array().map(Vec::len), Some(3), "{key}: {json}");
        }
    }
    assert!(json["cores"].as_u64().unwrap() >= 1);
    assert!(md.contains("Load average (1, 5, 15 minutes)"), "{md}");

    // Quiet shows no progress line.
    let o = brdf_sls(&[&args[..], &["--progress", "quiet"]].concat(), dir.path());
    assert!(o.status.success(), "{}", text(&o));
    assert!(!String::from_utf8_lossy(&o.stderr).contains("trials ("));
}
