//! Reader tests on the real Cornell files, on a MERL file written here, and on malformed input.

use brdf_io::{Channel, DataError, MerlBrdf, read_cornell, read_csv, read_merl};
use brdf_model::{DataSet, Filters, named_params};
use std::io::Write;
use std::path::PathBuf;

fn data_file(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../experiments/data")
        .join(name)
}

#[test]
fn cornell_files_load_with_1439_samples() {
    for (name, peak_lo, peak_hi) in [
        ("krylon_blue.brdf", 20.0, 60.0),
        ("acryl_blue.brdf", 10.0, 40.0),
    ] {
        let (d, rep) = read_cornell(data_file(name), 550.0, &Filters::none()).unwrap();
        assert_eq!(d.len(), 1439, "{name}");
        assert_eq!(rep.read, 1439);
        let (lo, hi) = d.value_range().unwrap();
        assert!((0.0..0.05).contains(&lo), "{name}: min {lo}");
        assert!(hi > peak_lo && hi < peak_hi, "{name}: max {hi}");
        // Every direction is a unit vector on the upper hemisphere.
        for i in 0..d.len() {
            for w in [d.u(i), d.v(i)] {
                assert!(w[2] >= 0.0);
                assert!(((w[0] * w[0] + w[1] * w[1] + w[2] * w[2]) - 1.0).abs() < 1e-12);
            }
        }
        // The peak sits near the mirror direction: v ~ (-ux, -uy, uz).
        let imax = (0..d.len())
            .max_by(|&a, &b| d.value(a).total_cmp(&d.value(b)))
            .unwrap();
        let (u, v) = (d.u(imax), d.v(imax));
        let cos = -u[0] * v[0] - u[1] * v[1] + u[2] * v[2];
        assert!(cos > 0.99, "{name}: peak at cos {cos}");
        // The paper's filter drops the values above 1 (the specular peak samples).
        let (kept, rep) = read_cornell(data_file(name), 550.0, &Filters::paper()).unwrap();
        assert!(rep.above_max > 0 && rep.above_max < 200, "{rep}");
        assert_eq!(kept.len() + rep.dropped(), 1439);
        assert!(kept.value_range().unwrap().1 <= 1.0);
        // Other wavelengths are selectable; missing ones are typed errors.
        let (d400, _) = read_cornell(data_file(name), 400.0, &Filters::none()).unwrap();
        assert_eq!(d400.len(), 1439);
        assert_ne!(d400.values(), d.values());
        assert!(matches!(
            read_cornell(data_file(name), 555.0, &Filters::none()),
            Err(DataError::NoWavelength { .. })
        ));
    }
}

#[test]
fn missing_and_malformed_files_give_documented_errors() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("nope.brdf");
    let e = read_cornell(&missing, 550.0, &Filters::default()).unwrap_err();
    assert!(matches!(e, DataError::Io { .. }));
    assert!(e.to_string().contains("nope.brdf"));

    let bad = dir.path().join("bad.brdf");
    std::fs::write(&bad, "# header\n2\n500 550\n\n0.1 0 0.2 3.1 0.5 oops\n").unwrap();
    let e = read_cornell(&bad, 550.0, &Filters::default()).unwrap_err();
    let msg = e.to_string();
    assert!(msg.contains("bad.brdf:5: expected a number"), "{msg}");
    assert!(msg.contains("`oops`"), "{msg}");

    let csv = dir.path().join("bad.csv");
    std::fs::write(
        &csv,
        "theta_i,phi_i,theta_o,phi_o,value\n10,0,20,180,0.5\n10,0,20\n",
    )
    .unwrap();
    let e = read_csv(&csv, &Filters::default()).unwrap_err();
    match e {
        DataError::Parse {
            path,
            line,
            expected,
            found,
        } => {
            assert_eq!(path, csv);
            assert_eq!(line, 3);
            assert!(expected.contains("5 comma-separated fields"), "{expected}");
            assert_eq!(found, "3 fields");
        }
        other => panic!("unexpected {other}"),
    }

    let merl = dir.path().join("bad.binary");
    std::fs::write(&merl, [1u8, 0, 0, 0, 1, 0, 0, 0]).unwrap();
    assert!(matches!(
        read_merl(&merl, Channel::Red, &Filters::default()),
        Err(DataError::Binary { .. })
    ));
    let mut bytes = Vec::new();
    for d in [2i32, 2, 4] {
        bytes.extend_from_slice(&d.to_le_bytes());
    }
    bytes.extend_from_slice(&[0u8; 8 * 10]);
    std::fs::write(&merl, &bytes).unwrap();
    let e = read_merl(&merl, Channel::Red, &Filters::default()).unwrap_err();
    assert!(e.to_string().contains("expected 396 bytes"), "{e}");
}

#[test]
fn csv_file_round_trip_through_disk() {
    let d = brdf_model::synthetic(&named_params("tuning").unwrap(), 100, 0.1, 3);
    let mut f = tempfile::NamedTempFile::new().unwrap();
    d.write_csv(&mut f).unwrap();
    f.flush().unwrap();
    let (back, rep) = read_csv(f.path(), &Filters::none()).unwrap();
    assert_eq!(rep.kept, 100);
    assert_eq!(back.values(), d.values());
}

/// Writes a small MERL-format file whose entries encode their own cell index, then checks
/// lookups land in the expected cells and grid sampling round-trips.
#[test]
fn merl_small_file_lookup_and_grid() {
    let dims = (6usize, 5usize, 8usize);
    let n = dims.0 * dims.1 * dims.2;
    // Entry = cell index + 1 in every channel (scaled back by the channel scales on lookup);
    // mark one cell negative to exercise the below-horizon filter.
    let mut table: Vec<f64> = (0..3 * n).map(|k| (k % n) as f64 + 1.0).collect();
    for c in 0..3 {
        table[c * n + 7] = -1.0;
    }
    let brdf = MerlBrdf { dims, table };
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("small.binary");
    std::fs::write(&path, brdf.to_bytes()).unwrap();
    let back = MerlBrdf::read(&path).unwrap();
    assert_eq!(back, brdf);

    // Normal incidence and exitance: theta_h = 0, theta_d = 0 -> cell 0 (+ phi_d bin).
    let up = [0.0, 0.0, 1.0];
    let idx = back.index(up, up);
    assert!(idx < dims.2, "{idx}");
    assert_eq!(
        back.lookup(Channel::Red, up, up),
        (idx as f64 + 1.0) / 1500.0
    );
    assert_eq!(
        back.lookup(Channel::Green, up, up),
        (idx as f64 + 1.0) * 1.15 / 1500.0
    );

    // Grid sampling: every cell yields one sample whose lookup maps back to the same cell.
    let (grid, rep) = back.sample_grid(Channel::Blue, &Filters::none());
    assert_eq!(grid.len(), n);
    assert_eq!(rep.read, n);
    for i in 0..grid.len() {
        let (u, v) = (grid.u(i), grid.v(i));
        assert_eq!(back.index(u, v), i, "cell {i}");
        let raw = if i == 7 { -1.0 } else { i as f64 + 1.0 };
        let expect = raw * 1.66 / 1500.0;
        assert!((grid.value(i) - expect).abs() < 1e-12 * expect.abs());
    }
    // Default filters drop the negative entry and directions below the horizon.
    let (kept, rep) = read_merl(&path, Channel::Blue, &Filters::default()).unwrap();
    assert_eq!(rep.read, n);
    assert!(rep.negative + rep.below_horizon >= 1);
    assert_eq!(kept.len(), rep.kept);

    // Sampling at chosen directions.
    let dirs = [(up, up), ([0.6, 0.0, 0.8], [-0.6, 0.0, 0.8])];
    let (at, _) = back.sample_at(Channel::Red, &dirs, &Filters::none());
    assert_eq!(at.len(), 2);
    let mut expect = DataSet::new();
    for (u, v) in dirs {
        expect.push(u, v, back.lookup(Channel::Red, u, v));
    }
    assert_eq!(at, expect);
}

/// Declared counts beyond the limits, endless or binary input, and huge lines give
/// quick errors naming the file, the line and the limit (no allocation abort, no hang).
#[test]
fn limits_give_quick_clear_errors() {
    use brdf_io::{MAX_LINE_BYTES, MAX_WAVELENGTHS};
    let dir = tempfile::tempdir().unwrap();
    let huge = dir.path().join("huge.brdf");
    std::fs::write(&huge, "# fuzz\n4000000000\n550\n0 0 0 0 1\n").unwrap();
    let e = read_cornell(&huge, 550.0, &Filters::default()).unwrap_err();
    let msg = e.to_string();
    assert!(matches!(e, DataError::Limit { line: 2, .. }), "{msg}");
    assert!(
        msg.contains("huge.brdf:2")
            && msg.contains(&MAX_WAVELENGTHS.to_string())
            && msg.contains("MAX_WAVELENGTHS")
            && msg.contains("4000000000"),
        "{msg}"
    );
    // A count too large even for usize is a parse error on that line.
    std::fs::write(&huge, "99999999999999999999999\n").unwrap();
    let e = read_cornell(&huge, 550.0, &Filters::default()).unwrap_err();
    assert!(matches!(e, DataError::Parse { line: 1, .. }), "{e}");

    // A line longer than MAX_LINE_BYTES.
    let long = dir.path().join("long.csv");
    std::fs::write(&long, vec![b'1'; MAX_LINE_BYTES + 10]).unwrap();
    let e = read_csv(&long, &Filters::default()).unwrap_err();
    assert!(e.to_string().contains("MAX_LINE_BYTES"), "{e}");

    // NUL bytes: an error on line 1 straight away, for a file and for /dev/zero.
    let nul = dir.path().join("nul.csv");
    std::fs::write(&nul, [0u8; 64]).unwrap();
    let e = read_csv(&nul, &Filters::default()).unwrap_err();
    assert!(e.to_string().contains("nul.csv:1: expected text"), "{e}");
    let zero = std::path::Path::new("/dev/zero");
    if zero.exists() {
        let t = std::time::Instant::now();
        assert!(read_csv(zero, &Filters::default()).is_err());
        assert!(read_cornell(zero, 550.0, &Filters::default()).is_err());
        let e = read_merl(zero, Channel::Green, &Filters::default()).unwrap_err();
        assert!(e.to_string().contains("expected three dims"), "{e}");
        assert!(t.elapsed().as_secs() < 5, "{:?}", t.elapsed());
    }

    // MERL dims whose size passes MAX_MERL_BYTES are refused before reading the table.
    let big = dir.path().join("big.binary");
    let mut bytes = Vec::new();
    for d in [4096i32, 4096, 4096] {
        bytes.extend_from_slice(&d.to_le_bytes());
    }
    std::fs::write(&big, &bytes).unwrap();
    let e = read_merl(&big, Channel::Red, &Filters::default()).unwrap_err();
    assert!(e.to_string().contains("MAX_MERL_BYTES"), "{e}");
    // Trailing bytes after the table are an error too.
    let brdf = MerlBrdf {
        dims: (1, 1, 2),
        table: vec![1.0; 6],
    };
    let mut bytes = brdf.to_bytes();
    bytes.push(0);
    std::fs::write(&big, &bytes).unwrap();
    let e = read_merl(&big, Channel::Red, &Filters::default()).unwrap_err();
    assert!(e.to_string().contains("expected 60 bytes"), "{e}");
}

/// The CSV docs say extra columns are ignored: they may hold anything.
#[test]
fn csv_extra_columns_are_ignored_and_repeated_names_refused() {
    let p = std::path::Path::new("x.csv");
    let text = "note, theta_i,phi_i,theta_o,phi_o,value,comment\n\
                krylon,10,0,20,180,0.5,\"hello\"\n\
                ,10,0,20,180,0.25,\n";
    let (d, rep) = brdf_io::parse_csv(text, p, &Filters::default()).unwrap();
    assert_eq!((d.len(), rep.read), (2, 2));
    assert_eq!(d.values(), &[0.5, 0.25]);
    // Rows still need the header's field count.
    let e = brdf_io::parse_csv(
        "ux,uy,uz,vx,vy,vz,value,w\n0,0,1,0,0,1,1\n",
        p,
        &Filters::default(),
    )
    .unwrap_err();
    assert!(
        e.to_string()
            .contains("x.csv:2: expected 8 comma-separated"),
        "{e}"
    );
    let e =
        brdf_io::parse_csv("ux,uy,uz,vx,vy,vz,value,value\n", p, &Filters::default()).unwrap_err();
    assert!(e.to_string().contains("`value` is repeated"), "{e}");
}

/// Non-finite values parse and are counted and dropped by every filter set but `none()`.
#[test]
fn non_finite_values_are_counted_and_dropped() {
    let p = std::path::Path::new("x.csv");
    let text = "ux,uy,uz,vx,vy,vz,value\n\
                0,0,1,0,0,1,nan\n\
                0,0,1,0,0,1,inf\n\
                0,0,1,inf,0,1,0.5\n\
                1e300,1e300,1e300,0,0,1e-300,-0.01\n";
    let (d, rep) = brdf_io::parse_csv(text, p, &Filters::default()).unwrap();
    assert_eq!((rep.read, rep.non_finite, rep.kept), (4, 3, 1));
    // Huge and tiny components normalise without overflow; the negative value is kept.
    let s = 1.0 / 3f64.sqrt();
    assert!(d.u(0).iter().all(|c| (c - s).abs() < 1e-15), "{:?}", d.u(0));
    assert_eq!(d.v(0), [0.0, 0.0, 1.0]);
    assert_eq!(d.value(0), -0.01);
    let (_, rep) = brdf_io::parse_csv(text, p, &Filters::paper()).unwrap();
    assert_eq!((rep.non_finite, rep.negative, rep.kept), (3, 1, 0));
    let (all, _) = brdf_io::parse_csv(text, p, &Filters::none()).unwrap();
    assert_eq!(all.len(), 4);
    assert!(all.value(0).is_nan());
}

/// One default policy: negative values (noise) are kept, non-finite and below-horizon
/// samples dropped; MERL's negative entries count as below the horizon.
#[test]
fn default_filters_keep_negative_noise() {
    let d = brdf_model::synthetic(&named_params("tuning").unwrap(), 2000, 0.1, 5);
    let (kept, rep) = Filters::default().apply(&d);
    assert!(d.values().iter().any(|&v| v < 0.0));
    assert_eq!(kept, d);
    assert_eq!(rep.dropped(), 0);
    let brdf = MerlBrdf {
        dims: (1, 1, 2),
        table: vec![-1.0, 3.0, -1.0, 3.0, -1.0, 3.0],
    };
    let (grid, rep) = brdf.sample_grid(Channel::Red, &Filters::default());
    assert_eq!((grid.len(), rep.below_horizon, rep.negative), (1, 1, 0));
}

#[test]
fn try_synthetic_checks_its_inputs() {
    use brdf_model::{MAX_SAMPLES, try_synthetic};
    let p = named_params("tuning").unwrap();
    assert_eq!(
        try_synthetic(&p, 100, 0.1, 3).unwrap(),
        brdf_model::synthetic(&p, 100, 0.1, 3)
    );
    let msg = |r: Result<DataSet, brdf_model::params::ParamError>| r.unwrap_err().to_string();
    assert!(msg(try_synthetic(&p, MAX_SAMPLES + 1, 0.1, 3)).contains("MAX_SAMPLES"));
    assert!(msg(try_synthetic(&p, 0, 0.1, 3)).contains("sample count 0"));
    assert!(msg(try_synthetic(&p, 10, 1e300, 3)).starts_with("sigma = 1e300"));
    assert!(msg(try_synthetic(&p, 10, -0.1, 3)).starts_with("sigma = -0.1"));
    assert!(msg(try_synthetic(&p, 10, f64::NAN, 3)).starts_with("sigma = NaN"));
    let mut bad = p.clone();
    bad.lobes[0].cz = 5.0;
    assert_eq!(
        msg(try_synthetic(&bad, 10, 0.1, 3)),
        "lobe1.cz = 5: expected a finite value in [-1.5, 1.5]"
    );
    // In the box but overflowing: (1.5 * cos^2)^10000 is infinite near the normal.
    let over = brdf_model::BrdfParams {
        kd: 0.0,
        lobes: vec![brdf_model::Lobe::isotropic(0.0, 1.5, 10000.0)],
    };
    assert!(msg(try_synthetic(&over, 1000, 0.0, 3)).contains("non-finite"));
    // Parameter JSON refuses unknown keys (a typo would otherwise be silently ignored).
    let e = serde_json::from_str::<brdf_model::BrdfParams>(
        r#"{"kd":0.1,"lobes":[{"cx":-1,"cy":-1,"cz":1,"n":10,"pan":45}]}"#,
    )
    .unwrap_err();
    assert!(e.to_string().contains("unknown field `pan`"), "{e}");
}
