//! The `brdf-sls` binary: every command runs and fails cleanly on bad input.

mod common;

use std::path::Path;
use std::process::{Command, Output};

fn brdf_sls(args: &[&str], cwd: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_brdf-sls"))
        .args(args)
        .current_dir(cwd)
        .env("CI", "true")
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

#[test]
fn help_on_every_command() {
    let dir = tempfile::tempdir().unwrap();
    for cmd in [
        "run", "check", "plot", "stats", "fit", "gen", "eval", "info",
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

    let o = brdf_sls(
        &["run", "tiny.toml", "--threads", "2", "--no-plots"],
        dir.path(),
    );
    assert!(o.status.success(), "{}", text(&o));
    let t = text(&o);
    assert!(t.contains("target RMSE 0.105") && t.contains("RPLS"), "{t}");
    assert!(dir.path().join("results/tiny/trials.jsonl").exists());
    assert!(!dir.path().join("results/tiny/plots").exists());

    // Re-plot from the results directory alone (spec read from the header).
    let o = brdf_sls(&["plot", "results/tiny"], dir.path());
    assert!(o.status.success(), "{}", text(&o));
    assert!(
        dir.path()
            .join("results/tiny/plots/tuning-trace.png")
            .exists()
    );
    let o = brdf_sls(&["stats", "tiny.toml"], dir.path());
    assert!(o.status.success(), "{}", text(&o));

    // A changed spec is refused with advice.
    std::fs::write(&spec, common::TINY.replace("seed = 11", "seed = 99")).unwrap();
    let o = brdf_sls(&["run", "tiny.toml", "--progress", "quiet"], dir.path());
    assert!(!o.status.success());
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

    let o = brdf_sls(&["info", "missing.csv"], dir.path());
    assert!(!o.status.success());
    assert!(text(&o).contains("missing.csv"));
    let o = brdf_sls(&["fit", "t.csv", "--set", "phy=1"], dir.path());
    assert!(!o.status.success());
    assert!(text(&o).contains("phy"), "{}", text(&o));
}
