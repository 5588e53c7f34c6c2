//! Runs the quick stress mode and writes the report to `target/stress-quick/` (or the directory
//! given as the first argument): `cargo run -p brdf-stress --release --example stress_quick`.

fn main() {
    let dir = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "target/stress-quick".into());
    let opts = brdf_stress::StressOptions::default();
    let t = std::time::Instant::now();
    let report = brdf_stress::run(&opts).expect("stress run");
    report
        .write_to(std::path::Path::new(&dir), |p, b| std::fs::write(p, b))
        .expect("write report");
    println!(
        "{} in {:.1} s; {} of {} checks failed; report in {dir}",
        if report.passed() { "PASSED" } else { "FAILED" },
        t.elapsed().as_secs_f64(),
        report.failures().len(),
        report.checks.len()
    );
    for c in report.failures() {
        println!(
            "FAIL {}: {} (tolerance {})",
            c.name, c.measured, c.tolerance
        );
    }
}
