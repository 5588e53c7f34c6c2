mod common;
use rayon::prelude::*;

#[test]
fn probe() {
    let dir = tempfile::tempdir().unwrap();
    let s = common::spec(common::TINY, dir.path());
    let (exec, _) = harness::run::SlsExecutor::new(&s).unwrap();
    use harness::run::Executor;
    let plan = s.trials_plan();
    let fwd: Vec<_> = plan.iter().map(|t| exec.run(t, 0.105, s.budget)).collect();
    let pool = rayon::ThreadPoolBuilder::new().num_threads(2).build().unwrap();
    for round in 0..3 {
        let par: Vec<_> = pool.install(|| plan.par_iter().with_max_len(1).map(|t| exec.run(t, 0.105, s.budget)).collect());
        for (i, t) in plan.iter().enumerate() {
            if fwd[i].best_x != par[i].best_x { eprintln!("round {round}: {} differs (parallel)", t.key); }
        }
    }
    let pool1 = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    let one: Vec<_> = pool1.install(|| plan.par_iter().with_max_len(1).map(|t| exec.run(t, 0.105, s.budget)).collect());
    for (i, t) in plan.iter().enumerate() {
        if fwd[i].best_x != one[i].best_x { eprintln!("{} differs (pool of 1)", t.key); }
    }
}
