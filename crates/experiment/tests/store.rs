//! Tests of the results store: round trips, resume, torn lines, locks, packed files.

use std::collections::BTreeMap;
use std::fs::{File, OpenOptions};
use std::io::Write;

use brdf_experiment::machine::MachineInfo;
use brdf_experiment::store::*;
use sls::{Budget, EvalCounts, Stamp, StopReason, TracePoint, TrialResult};

fn header(fp: &str) -> Header {
    Header {
        format: FORMAT_VERSION,
        experiment: "t".into(),
        fingerprint: fp.into(),
        created_unix: 0,
        machine: MachineInfo::current(1),
        spec: serde_json::json!({"a": 1}),
        spec_text: String::new(),
        program_version: String::new(),
        kernel: String::new(),
        solver_kernel: String::new(),
        data_hashes: BTreeMap::new(),
        shard: None,
        best_known: BTreeMap::new(),
        program: String::new(),
        schemas: BTreeMap::new(),
    }
}

/// The line of a trial as the store writes it.
fn trial_line(r: &TrialRecord) -> String {
    let mut v = serde_json::to_value(r).unwrap();
    v["type"] = "trial".into();
    format!("{v}\n")
}

fn record(i: u32, best: f64) -> TrialRecord {
    let at = Stamp {
        cpu_seconds: 0.5 + f64::from(i),
        wall_seconds: 0.6,
        evaluations: EvalCounts {
            residual_rows: 10,
            jacobian_rows: 20,
            rmse_rows: 30,
            ..EvalCounts::default()
        },
    };
    TrialRecord {
        key: TrialRecord::make_key("inst", "A", i),
        instance: "inst".into(),
        config: "A".into(),
        trial: i,
        seed: 42 + u64::from(i),
        target: 0.1,
        budget: Budget {
            cpu_seconds: Some(2.0),
            sample_evaluations: None,
        },
        result: TrialResult {
            stop: StopReason::Target,
            reached_at: Some(at),
            ended_at: at,
            best_rmse: best,
            best_x: vec![1.0, 2.0],
            trace: vec![TracePoint { at, rmse: 0.09 }],
            counters: vec![("restarts".into(), 3)],
            failure: None,
        },
    }
}

#[test]
fn round_trip_resume_torn_and_mismatch() {
    let dir = tempfile::tempdir().unwrap();
    let o = ResultStore::open(dir.path(), header("f1"), false).unwrap();
    assert!(o.records.is_empty());
    o.store.append(&record(0, 0.09)).unwrap();
    o.store.append(&record(1, f64::INFINITY)).unwrap();
    drop(o);
    // Simulate a kill in the middle of a third line.
    let path = dir.path().join(TRIALS_FILE);
    let full = trial_line(&record(2, 0.09));
    let mut f = OpenOptions::new().append(true).open(&path).unwrap();
    f.write_all(&full.as_bytes()[..full.len() / 2]).unwrap();
    drop(f);
    let c = read_results(dir.path()).unwrap();
    assert_eq!(c.records.len(), 2);
    assert!(c.torn.is_some());
    assert_eq!(c.records[0], record(0, 0.09));
    assert!(c.records[1].result.best_rmse.is_infinite());

    let o = ResultStore::open(dir.path(), header("f1"), false).unwrap();
    assert_eq!(o.records.len(), 2);
    assert!(o.notes.iter().any(|n| n.contains("torn")), "{:?}", o.notes);
    o.store.append(&record(2, 0.09)).unwrap();
    drop(o);
    let c = read_results(dir.path()).unwrap();
    assert_eq!(c.records.len(), 3);
    assert!(c.torn.is_none());
    assert_eq!(c.sessions.len(), 2);

    let err = ResultStore::open(dir.path(), header("f2"), false).unwrap_err();
    let msg = err.to_string();
    assert!(msg.contains("--fresh") && msg.contains("--out"), "{msg}");
    let o = ResultStore::open(dir.path(), header("f2"), true).unwrap();
    assert!(o.records.is_empty());
    let moved: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name().to_string_lossy().contains(".old-"))
        .collect();
    assert_eq!(moved.len(), 1);
}

#[test]
fn corrupt_middle_line_is_an_error() {
    let dir = tempfile::tempdir().unwrap();
    let o = ResultStore::open(dir.path(), header("f1"), false).unwrap();
    o.store.append(&record(0, 0.09)).unwrap();
    drop(o);
    let path = dir.path().join(TRIALS_FILE);
    let mut text = std::fs::read_to_string(&path).unwrap();
    text.push_str("{garbage\n");
    text.push_str(&trial_line(&record(1, 0.09)));
    std::fs::write(&path, text).unwrap();
    let err = read_results(&path).unwrap_err();
    assert!(matches!(err, StoreError::Corrupt { line: 4, .. }), "{err}");
}

#[test]
fn a_second_writer_is_refused_with_the_holders_pid() {
    let dir = tempfile::tempdir().unwrap();
    let first = ResultStore::open(dir.path(), header("f1"), false).unwrap();
    let err = ResultStore::open(dir.path(), header("f1"), false).unwrap_err();
    match &err {
        StoreError::Locked { pid, .. } => assert_eq!(*pid, Some(std::process::id())),
        other => panic!("expected Locked, got {other}"),
    }
    assert!(err.to_string().contains("in use"), "{err}");
    drop(first);
    ResultStore::open(dir.path(), header("f1"), false).unwrap();
}

#[test]
fn packed_results_are_read_and_resumed_transparently() {
    let dir = tempfile::tempdir().unwrap();
    let o = ResultStore::open(dir.path(), header("f1"), false).unwrap();
    o.store.append(&record(0, 0.09)).unwrap();
    drop(o);
    let plain = dir.path().join(TRIALS_FILE);
    let packed = dir.path().join(PACKED_TRIALS_FILE);
    let mut gz = flate2::write::GzEncoder::new(
        File::create(&packed).unwrap(),
        flate2::Compression::default(),
    );
    gz.write_all(&std::fs::read(&plain).unwrap()).unwrap();
    gz.finish().unwrap();
    std::fs::remove_file(&plain).unwrap();

    let c = read_results(dir.path()).unwrap();
    assert_eq!(c.records, vec![record(0, 0.09)]);
    assert!(!plain.exists(), "reading must not unpack");

    let o = ResultStore::open(dir.path(), header("f1"), false).unwrap();
    assert_eq!(o.records, vec![record(0, 0.09)]);
    assert!(
        o.notes.iter().any(|n| n.contains("unpacked")),
        "{:?}",
        o.notes
    );
    o.store.append(&record(1, 0.09)).unwrap();
    drop(o);
    assert_eq!(read_results(dir.path()).unwrap().records.len(), 2);
    assert!(packed.exists(), "the packed copy is kept");
}

/// Issue 45, item 4: a packed file whose last line is torn wedged the folder: the first run
/// unpacked it and cut the torn line, after which the plain file no longer started with the
/// packed bytes, and every later `run`, `stats` and `export` refused the folder as holding two
/// different results files. The rule now is the same everywhere: the plain file is the
/// results when it starts with the packed file's complete lines (a torn tail is not results).
#[test]
fn a_packed_file_with_a_torn_last_line_resumes_and_stays_readable() {
    let dir = tempfile::tempdir().unwrap();
    let o = ResultStore::open(dir.path(), header("f1"), false).unwrap();
    o.store.append(&record(0, 0.09)).unwrap();
    drop(o);
    let plain = dir.path().join(TRIALS_FILE);
    let packed = dir.path().join(PACKED_TRIALS_FILE);
    let mut bytes = std::fs::read(&plain).unwrap();
    let torn = trial_line(&record(1, 0.09));
    bytes.extend_from_slice(&torn.as_bytes()[..torn.len() / 2]);
    let mut gz = flate2::write::GzEncoder::new(
        File::create(&packed).unwrap(),
        flate2::Compression::default(),
    );
    gz.write_all(&bytes).unwrap();
    gz.finish().unwrap();
    std::fs::remove_file(&plain).unwrap();

    let c = read_results(dir.path()).unwrap();
    assert_eq!(c.records.len(), 1);
    assert!(c.torn.is_some());

    let o = ResultStore::open(dir.path(), header("f1"), false).unwrap();
    assert_eq!(o.records.len(), 1);
    o.store.append(&record(1, 0.09)).unwrap();
    drop(o);
    // Reading, and resuming again, both use the plain file now.
    let c = read_results(dir.path()).unwrap();
    assert_eq!(c.records.len(), 2, "the plain file is the results");
    let o = ResultStore::open(dir.path(), header("f1"), false).unwrap();
    assert_eq!(o.records.len(), 2);
    drop(o);

    // A plain file that does not start with the packed file's complete lines is still refused.
    std::fs::write(&plain, b"{\"type\":\"other\"}\n").unwrap();
    let err = read_results(dir.path()).unwrap_err();
    assert!(matches!(err, StoreError::BothPresent { .. }), "{err}");
}
