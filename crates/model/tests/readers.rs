//! Reader tests on the real Cornell files, on a MERL file written here, and on malformed input.

use brdf_model::{
    Channel, DataError, DataSet, Filters, MerlBrdf, named_params, read_cornell, read_csv, read_merl,
};
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
