//! The CPU cutoff holds for large models: trials of 16-lobe anisotropic models (81 parameters)
//! on 2000 samples end soon after a 0.05 s cutoff.

use brdf_model::{Layout, LobeKind, named_params, synthetic};
use sls::{AlgorithmConfig, BrdfObjective, Budget, StopReason, run_trial};
use std::sync::Arc;

/// Bound: `3 x cutoff + 0.05 s`. The context notices the cutoff at the first evaluation or
/// solver iteration after it (it polls the wall clock at every call and reads the CPU clock
/// whenever the budget could be spent, see `context.rs`), so what remains is the work between
/// two calls of the solver plus its wind-down: one step of the bounded LM solver on a
/// 2000 x 81 Jacobian, a few milliseconds optimised (the test profile is optimised; the bound
/// leaves room for a machine ten times slower or heavily shared). The old check (every 4096
/// rows or 64 calls) let a 16-lobe trial run to 61x a 0.05 s cutoff.
///
/// AED is not tested here: its 25-row descents have fewer rows than parameters, where one step
/// of the solver (crates/lm, `compute_step`) can take 0.2 s at 16 lobes and 18 s at 50 lobes
/// between two calls the context sees; no check outside the solver can cut that.
fn check(names: &[&str]) {
    let data = Arc::new(synthetic(&named_params("tuning").unwrap(), 2000, 0.1, 1));
    let layout = Layout::builder(&[LobeKind::Anisotropic; 16])
        .build()
        .unwrap();
    let objective = BrdfObjective::new(data, layout);
    let cutoff = 0.05;
    let bound = 3.0 * cutoff + 0.05;
    let budget = Budget {
        cpu_seconds: Some(cutoff),
        sample_evaluations: None,
    };
    for &name in names {
        let config = AlgorithmConfig::default_for(name).unwrap();
        for seed in 1..=3 {
            let r = run_trial(&objective, &config, seed, budget, 0.0);
            assert_eq!(r.stop, StopReason::CpuBudget, "{name} seed {seed}");
            let t = r.ended_at.cpu_seconds;
            println!("{name} seed {seed}: {t:.4} s ({:.2}x)", t / cutoff);
            assert!(
                (cutoff..=bound).contains(&t),
                "{name} seed {seed}: ended at {t} s, cutoff {cutoff} s, bound {bound} s"
            );
        }
    }
}

/// Algorithms without long solver steps: SA (evaluations only) and DS.
#[test]
fn cpu_cutoff_holds_with_sixteen_lobes() {
    check(&["sa", "ds"]);
}

/// With descents the bound does not hold yet: one step of the bounded LM solver on 16 lobes can
/// take 0.2 to 0.7 s between two calls the context sees (crates/lm `compute_step`; measured with
/// `cargo run --release -p sls --example descent_gaps`), which no check outside the solver can
/// cut. Run with `--ignored` once the solver bounds its per-step work.
#[test]
#[ignore = "needs crates/lm to bound the work of one step (see descent_gaps)"]
fn cpu_cutoff_holds_with_sixteen_lobes_and_descents() {
    check(&["rpls", "aed"]);
}
