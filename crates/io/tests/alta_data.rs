//! ALTA's retro-reflection measurements (CEA-CESTA tapes, ALTA's `documents/data/`), read
//! from outside the repository: ALTA's data are not shipped here (docs/model.md, "ALTA").
//! Set `BRDF_SLS_ALTA_DATA` to the folder `scripts/fetch-alta-data.sh` filled, e.g.
//! `BRDF_SLS_ALTA_DATA=/tmp/alta-data cargo test -p brdf-io --test alta_data`; without it
//! each test prints a note and passes.

use brdf_io::{AltaOutput, DataError, Format, read};
use brdf_model::{DataSet, Filters};
use std::path::PathBuf;

/// The data folder, or `None` (with a note) when `BRDF_SLS_ALTA_DATA` is unset.
fn data_dir(test: &str) -> Option<PathBuf> {
    match std::env::var_os("BRDF_SLS_ALTA_DATA") {
        Some(d) => Some(PathBuf::from(d)),
        None => {
            println!(
                "{test}: skipped, BRDF_SLS_ALTA_DATA is not set (the folder of ALTA's \
                 retro-*.dat files, see scripts/fetch-alta-data.sh)"
            );
            None
        }
    }
}

fn close(a: f64, b: f64) {
    assert!((a - b).abs() <= 1e-15 * b.abs().max(1.0), "{a} != {b}");
}

fn sample(d: &DataSet, i: usize) -> ([f64; 3], [f64; 3], f64) {
    (d.u(i), d.v(i), d.value(i))
}

/// Pins two samples of `retro-3M-jaune.dat`: 1,066,493 bytes, SHA-256
/// 8a40ee3592129dfeb8c5fe0f05b8ec647e52ded4c4fb762c9b821c90ffd9be76 (git blob
/// ddc2f877c826474e11d94020875ed21370f33d71, ALTA commit 63aa68404b490d9fbacb6578080689e1597227c7).
/// Its header: `#DIM 3 1`, `#VS 0`, `#PARAM_IN ISOTROPIC_TL_TV_PROJ_DPHI`,
/// `#PARAM_OUT INV_STERADIAN_COSINE_FACTOR`.
#[test]
fn retro_3m_yellow_pinned_samples() {
    let Some(dir) = data_dir("retro_3m_yellow_pinned_samples") else {
        return;
    };
    let path = dir.join("retro-3M-jaune.dat");
    let f = Format::from_path(&path).unwrap();
    assert_eq!(f.name(), "alta");
    let (d, rep) = read(&path, &f, &Filters::none()).unwrap();
    assert_eq!((rep.read, d.len()), (7397, 7397));
    // Line 8, the first sample: theta_l = pi/12 (15 degrees), (a, b) = (-pi/2, 1.9e-16), value
    // 0.000501744 = BRDF cos(theta_l): v is grazing at phi = pi, the BRDF is
    // 0.000501744 / cos(pi/12) = 5.194436118636768e-4.
    let (u, v, y) = sample(&d, 0);
    close(u[0], (std::f64::consts::PI / 12.0).sin());
    assert_eq!(u[1], 0.0);
    close(u[2], (std::f64::consts::PI / 12.0).cos());
    close(v[0], -1.0);
    assert!(v[1].abs() < 1e-15 && v[2].abs() < 1e-15, "{v:?}");
    close(y, 5.194436118636768e-4);
    // Line 5900, the largest value: theta_l = pi/3, value 19.3009 / cos(pi/3) = 38.6018.
    let imax = (0..d.len())
        .max_by(|&a, &b| d.value(a).total_cmp(&d.value(b)))
        .unwrap();
    assert_eq!(imax, 5900 - 8);
    let (u, v, y) = sample(&d, imax);
    close(u[2], 0.5);
    close(y, 38.60179999999999);
    // (a, b) = (-1.0455527071059576, 0.021011773637614015): v = (a, b) sin(t) / t, cos(t)
    // with t = hypot(a, b).
    for (got, want) in v.iter().zip([
        -0.8651329663590085,
        0.017385998746910467,
        0.5012411371450224,
    ]) {
        close(*got, want);
    }
    // The default filters drop the 5 samples whose view direction is a rounding below the
    // horizon (hypot(a, b) just above pi/2).
    let (kept, rep) = read(&path, &f, &Filters::default()).unwrap();
    assert_eq!((kept.len(), rep.below_horizon), (7392, 5));
}

/// Every shipped file that is present reads (counts pinned); `retro-gray-tape.dat` has no
/// `#PARAM_OUT` and is refused until the format says what its values are.
#[test]
fn every_shipped_file_reads() {
    let Some(dir) = data_dir("every_shipped_file_reads") else {
        return;
    };
    let alta = Format::from_name("alta").unwrap();
    let counts = [
        ("retro-3M-jaune.dat", 7397),
        ("retro-3M-jaune-dense.dat", 68579),
        ("retro-gray-tape-dense.dat", 79707),
        ("retro-orange-tape-dense.dat", 79707),
    ];
    for (name, n) in counts {
        let path = dir.join(name);
        let (d, rep) = read(&path, &alta, &Filters::none()).unwrap();
        assert_eq!((d.len(), rep.read), (n, n), "{name}");
        assert!(
            d.values().iter().all(|y| y.is_finite() && *y >= 0.0),
            "{name}"
        );
    }
    let path = dir.join("retro-gray-tape.dat");
    let e = read(&path, &alta, &Filters::default()).unwrap_err();
    assert!(matches!(e, DataError::Parse { line: 7, .. }), "{e}");
    assert!(
        e.to_string().contains("the format option `param_out`"),
        "{e}"
    );
    let f = Format::Alta {
        channel: None,
        param_out: Some(AltaOutput::InvSteradianCosineFactor),
    };
    let (d, _) = read(&path, &f, &Filters::none()).unwrap();
    assert_eq!(d.len(), 7405);
    // Not in the snapshot this was written from; when present it must read one way or the
    // other.
    let path = dir.join("retro-orange-tape.dat");
    if path.exists() {
        let r = read(&path, &alta, &Filters::none()).or_else(|_| read(&path, &f, &Filters::none()));
        assert!(r.is_ok(), "{r:?}");
    }
}
