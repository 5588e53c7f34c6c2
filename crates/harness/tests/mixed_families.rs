//! One spec fitting two model families to one data set (issue 43): it runs, a run stopped
//! part-way resumes to the plan's end, and the statistics and the report name both
//! instances with their own family.

mod support;
use support::{brdf_sls, text};

/// GGX data (one suite material, Cornell-like sampling) fitted by GGX and by Lafortune.
const SPEC: &str = r#"
name = "mixed"
seed = 3
trials = 2

[budget]
evaluations = 20000

[[instance]]
name = "gold-ggx"
targets = [{ relative = 0.05 }]
[instance.suite]
suite = "ngan-ggx"
material = "gold-metallic-paint"
sampling = "cornell"
samples = 300

[[instance]]
name = "gold-lafortune"
targets = [{ relative = 0.05 }]
[instance.suite]
suite = "ngan-ggx"
material = "gold-metallic-paint"
sampling = "cornell"
samples = 300
[instance.model]
family = "lafortune"

[[algorithm]]
kind = "rpls"
"#;

#[test]
fn two_families_on_one_data_set_run_resume_and_report() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("mixed.toml"), SPEC).unwrap();

    let o = brdf_sls(&["check", "mixed.toml"], dir.path());
    assert!(o.status.success(), "{}", text(&o));
    // The plan names each instance's family.
    let plan = text(&o);
    assert!(plan.contains("model ggx [isotropic]"), "{plan}");
    assert!(plan.contains("model lafortune [isotropic]"), "{plan}");

    let o = brdf_sls(&["run", "mixed.toml", "--limit", "1"], dir.path());
    assert!(o.status.success(), "{}", text(&o));
    assert!(text(&o).contains("still to run"), "{}", text(&o));

    let o = brdf_sls(&["run", "mixed.toml"], dir.path());
    assert!(o.status.success(), "{}", text(&o));
    assert!(
        text(&o).contains("3 new trials") && text(&o).contains("(1 resumed)"),
        "{}",
        text(&o)
    );

    let out = dir.path().join("runs/mixed");
    let trials = std::fs::read_to_string(out.join("trials.jsonl")).unwrap();
    assert_eq!(trials.lines().filter(|l| l.contains("\"key\"")).count(), 4);
    let stats = std::fs::read_to_string(out.join("stats.csv")).unwrap();
    assert!(
        stats.contains("gold-ggx") && stats.contains("gold-lafortune"),
        "{stats}"
    );
    let page = std::fs::read_to_string(out.join("report.html")).unwrap();
    assert!(page.contains("gold-ggx") && page.contains("gold-lafortune"));
    // The folder alone reads back with both families (the stored spec names them).
    let o = brdf_sls(&["stats", "runs/mixed", "--print-only"], dir.path());
    assert!(o.status.success(), "{}", text(&o));
    assert!(text(&o).contains("gold-lafortune"), "{}", text(&o));
}
