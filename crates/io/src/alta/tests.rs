//! Unit tests of the ALTA reader: each parameterisation against directions worked out by hand,
//! the cosine factor, channels, and every header and row error.

use super::*;
use crate::{Format, parse};
use std::path::Path;

const S2: f64 = std::f64::consts::FRAC_1_SQRT_2;

fn alta(channel: Option<Channel>, param_out: Option<AltaOutput>) -> Format {
    Format::Alta { channel, param_out }
}

fn read(text: &str, f: &Format, filters: &Filters) -> Result<(DataSet, FilterReport), DataError> {
    parse(text.as_bytes(), Path::new("t.alta"), f, filters)
}

fn read_ok(text: &str) -> DataSet {
    read(text, &alta(None, None), &Filters::none()).unwrap().0
}

fn err(text: &str, f: &Format) -> String {
    read(text, f, &Filters::default()).unwrap_err().to_string()
}

fn close(a: [f64; 3], b: [f64; 3]) {
    for k in 0..3 {
        assert!((a[k] - b[k]).abs() < 1e-15, "{a:?} != {b:?}");
    }
}

/// The header of a one-channel BRDF file.
fn head(param_in: &str, n: usize) -> String {
    format!("#DIM {n} 1\n#PARAM_IN {param_in}\n#PARAM_OUT INV_STERADIAN\n")
}

#[test]
fn isotropic_tl_tv_proj_dphi_with_the_cosine_factor() {
    // theta_l = pi/3 (cos 1/2); (a, b) = (0.3, 0.4): theta_v = 0.5 along (0.6, 0.8).
    let text = "#SAMPLE \"x\"\n#DIM 3 1\n#VS 0\n#PARAM_IN ISOTROPIC_TL_TV_PROJ_DPHI\n\
                #PARAM_OUT INV_STERADIAN_COSINE_FACTOR\n1.0471975511965976 0.3 0.4 0.25\n\
                0.2 0 0 1\n";
    let d = read_ok(text);
    close(d.u(0), [0.75f64.sqrt(), 0.0, 0.5]);
    let (s, c) = (0.479_425_538_604_203, 0.877_582_561_890_372_8); // sin 0.5, cos 0.5
    close(d.v(0), [0.6 * s, 0.8 * s, c]);
    // 0.25 / cos(pi/3) = 0.5.
    assert!((d.value(0) - 0.5).abs() < 1e-15);
    // theta_v = 0: the normal; the value is divided by cos 0.2.
    assert_eq!(d.v(1), [0.0, 0.0, 1.0]);
    assert!((d.value(1) - 1.0 / 0.2f64.cos()).abs() < 1e-15);
    // The retro direction (a, b) = (theta_l, 0) gives v = u.
    let d = read_ok(&(head("ISOTROPIC_TL_TV_PROJ_DPHI", 3) + "0.5 0.5 0 3\n"));
    close(d.u(0), d.v(0));
    assert_eq!(d.value(0), 3.0);
}

#[test]
fn isotropic_tv_tl_dphi_puts_the_incident_direction_at_phi_0() {
    // ALTA: v = (sin pi/6, 0, cos pi/6), u at azimuth pi/2 and elevation pi/4; turned by
    // -pi/2 about the normal: u = (1/sqrt 2, 0, 1/sqrt 2), v = (0, -1/2, sqrt(3)/2).
    let text = head("ISOTROPIC_TV_TL_DPHI", 3)
        + "0.5235987755982988 0.7853981633974483 1.5707963267948966 2\n";
    let d = read_ok(&text);
    close(d.u(0), [S2, 0.0, S2]);
    close(d.v(0), [0.0, -0.5, 0.75f64.sqrt()]);
    assert_eq!(d.u(0)[1], 0.0);
    assert_eq!(d.value(0), 2.0);
}

#[test]
fn rusinkiewicz_half_and_difference_angles() {
    let s3 = 3f64.sqrt();
    let s7 = 7f64.sqrt();
    // theta_h = 0, theta_d = pi/3: the mirror pair, turned so that u.x > 0.
    // theta_h = theta_d = pi/6, phi_d = pi/2: v = (sqrt3/4, 1/2, 3/4), u = (sqrt3/4, -1/2, 3/4)
    // before the turn; after it u = (sqrt7/4, 0, 3/4), v = (-1/(4 sqrt7), sqrt3/sqrt7, 3/4).
    let text = head("RUSIN_TH_TD_PD", 3)
        + "0 1.0471975511965976 0 1\n\
           0.5235987755982988 0.5235987755982988 1.5707963267948966 1\n";
    let d = read_ok(&text);
    close(d.u(0), [s3 / 2.0, 0.0, 0.5]);
    close(d.v(0), [-s3 / 2.0, 0.0, 0.5]);
    close(d.u(1), [s7 / 4.0, 0.0, 0.75]);
    close(d.v(1), [-1.0 / (4.0 * s7), s3 / s7, 0.75]);
    // With phi_h = pi/2 (anisotropic, no turn): the pair above turned by pi/2 about z.
    let text = head("RUSIN_TH_PH_TD_PD", 4)
        + "0.5235987755982988 1.5707963267948966 0.5235987755982988 1.5707963267948966 1\n";
    let d = read_ok(&text);
    close(d.u(0), [0.5, s3 / 4.0, 0.75]);
    close(d.v(0), [-0.5, s3 / 4.0, 0.75]);
}

#[test]
fn spherical_and_cartesian_pairs() {
    // [theta_l, phi_l, theta_v, phi_v] = [pi/3, pi/2, pi/4, pi].
    let text = head("SPHERICAL_TL_PL_TV_PV", 4)
        + "1.0471975511965976 1.5707963267948966 0.7853981633974483 3.141592653589793 1\n";
    let d = read_ok(&text);
    close(d.u(0), [0.0, 0.75f64.sqrt(), 0.5]);
    close(d.v(0), [-S2, 0.0, S2]);
    // CARTESIAN packs V first; vectors are normalised.
    let d = read_ok(&(head("CARTESIAN", 6) + "0 0 2 3 0 4 0.5\n"));
    assert_eq!(d.v(0), [0.0, 0.0, 1.0]);
    close(d.u(0), [0.6, 0.0, 0.8]);
    let e = err(
        &(head("CARTESIAN", 6) + "0 0 0 3 0 4 0.5\n"),
        &alta(None, None),
    );
    assert!(
        e.contains("t.alta:4: expected non-zero CARTESIAN vectors"),
        "{e}"
    );
}

#[test]
fn rgb_files_take_a_channel_green_by_default() {
    let text = "#DIM 3 3\n#PARAM_IN ISOTROPIC_TV_TL_DPHI\n#PARAM_OUT RGB_COLOR\n\
                0.1 0.2 0.3 1 2 3\n";
    let value = |c| {
        read(text, &alta(c, None), &Filters::none())
            .unwrap()
            .0
            .value(0)
    };
    assert_eq!(value(None), 2.0);
    assert_eq!(value(Some(Channel::Red)), 1.0);
    assert_eq!(value(Some(Channel::Blue)), 3.0);
    // A channel for a one-channel file is refused.
    let e = err(
        &(head("RUSIN_TH_TD_PD", 3) + "0 0 0 1\n"),
        &alta(Some(Channel::Red), None),
    );
    assert!(
        e.contains("t.alta:3:") && e.contains("`#PARAM_OUT RGB_COLOR` for the format option"),
        "{e}"
    );
}

#[test]
fn grazing_incidence_with_the_cosine_factor_has_no_value() {
    let text = "#DIM 3 1\n#PARAM_IN ISOTROPIC_TL_TV_PROJ_DPHI\n\
                #PARAM_OUT INV_STERADIAN_COSINE_FACTOR\n\
                1.5707963267948966 0 0 1\n2 0 0 1\n0 0 0 1\n";
    let f = alta(None, None);
    // Default filters: both dropped as below the horizon (cos(pi/2) rounds to 6e-17).
    let (d, rep) = read(text, &f, &Filters::default()).unwrap();
    assert_eq!((d.len(), rep.below_horizon, rep.non_finite), (1, 2, 0));
    assert_eq!(d.value(0), 1.0);
    // Keeping below-horizon samples leaves a NaN value, which the non-finite filter drops.
    let keep = Filters {
        drop_below_horizon: false,
        ..Filters::default()
    };
    let (d, rep) = read(text, &f, &keep).unwrap();
    assert_eq!((d.len(), rep.below_horizon, rep.non_finite), (1, 0, 2));
    let (d, _) = read(text, &f, &Filters::none()).unwrap();
    assert!(d.value(0).is_nan() && d.value(1).is_nan() && d.value(2) == 1.0);
    // Without the cosine factor the same rows are plain samples.
    let plain = text.replace("INV_STERADIAN_COSINE_FACTOR", "INV_STERADIAN");
    let (d, rep) = read(&plain, &f, &Filters::default()).unwrap();
    assert_eq!((d.len(), rep.below_horizon), (2, 1));
}

#[test]
fn missing_param_out_needs_the_option_and_must_agree_with_it() {
    let text = "#DIM 3 1\n#PARAM_IN ISOTROPIC_TL_TV_PROJ_DPHI\n\n# comment\n0.5 0 0 2\n";
    let e = err(text, &alta(None, None));
    assert!(
        e.starts_with("t.alta:5: expected a `#PARAM_OUT` header line (INV_STERADIAN, ")
            && e.contains("or the format option `param_out`")
            && e.ends_with("found the first data line"),
        "{e}"
    );
    let f = alta(None, Some(AltaOutput::InvSteradianCosineFactor));
    let (d, _) = read(text, &f, &Filters::none()).unwrap();
    assert!((d.value(0) - 2.0 / 0.5f64.cos()).abs() < 1e-15);
    let with = head("ISOTROPIC_TL_TV_PROJ_DPHI", 3) + "0.5 0 0 2\n";
    let e = err(&with, &f);
    assert!(
        e.contains("t.alta:3: expected `#PARAM_OUT INV_STERADIAN_COSINE_FACTOR` (the format option `param_out`), found `#PARAM_OUT INV_STERADIAN`"),
        "{e}"
    );
    assert!(
        read(
            &with,
            &alta(None, Some(AltaOutput::InvSteradian)),
            &Filters::none()
        )
        .is_ok()
    );
}

#[test]
fn header_errors_name_the_line_and_the_supported_values() {
    let f = alta(None, None);
    let e = err("#DIM 2 1\n#PARAM_IN STARK_2D\n", &f);
    assert!(
        e.starts_with("t.alta:2: expected `#PARAM_IN` naming a supported input parameterisation (ISOTROPIC_TL_TV_PROJ_DPHI, ISOTROPIC_TV_TL_DPHI, RUSIN_TH_TD_PD, RUSIN_TH_PH_TD_PD, SPHERICAL_TL_PL_TV_PV, CARTESIAN), found `#PARAM_IN STARK_2D`"),
        "{e}"
    );
    for out in ["ENERGY", "XYZ_COLOR", "UNKNOWN_OUTPUT", "inv_steradian"] {
        let e = err(&format!("#PARAM_OUT {out}\n"), &f);
        assert!(
            e.starts_with("t.alta:1: expected `#PARAM_OUT` naming a supported output parameterisation (INV_STERADIAN, INV_STERADIAN_COSINE_FACTOR, RGB_COLOR)"),
            "{e}"
        );
    }
    // #DIM must match the parameterisations; reported on the #DIM line.
    let e = err(
        "#PARAM_IN RUSIN_TH_TD_PD\n#DIM 4 1\n#PARAM_OUT INV_STERADIAN\n",
        &f,
    );
    assert_eq!(
        e,
        "t.alta:2: expected `#DIM 3 1` for `#PARAM_IN RUSIN_TH_TD_PD` (line 1) and `#PARAM_OUT INV_STERADIAN`, found `#DIM 4 1`"
    );
    let e = err(
        &head("RUSIN_TH_TD_PD", 3).replace("INV_STERADIAN", "RGB_COLOR"),
        &f,
    );
    assert!(e.contains("t.alta:1: expected `#DIM 3 3`"), "{e}");
    for bad in ["#DIM 3", "#DIM 3 1 1", "#DIM 0 1", "#DIM x 1"] {
        let e = err(&format!("{bad}\n"), &f);
        assert!(
            e.starts_with("t.alta:1: expected `#DIM N P`: two positive integers"),
            "{e}"
        );
    }
    let e = err(
        "#PARAM_IN RUSIN_TH_TD_PD\n#PARAM_OUT INV_STERADIAN\n1 2 3 4\n",
        &f,
    );
    assert_eq!(
        e,
        "t.alta:3: expected a `#DIM N P` header line, found the first data line"
    );
    let e = err("#DIM 3 1\n", &f);
    assert!(
        e.starts_with("t.alta:0: expected a `#PARAM_IN` header line ("),
        "{e}"
    );
    assert!(e.ends_with("found end of file"), "{e}");
    let e = err("", &f);
    assert_eq!(
        e,
        "t.alta:0: expected a `#DIM N P` header line, found end of file"
    );
    // A key twice, #VS out of range, binary files.
    let e = err("#DIM 3 1\n#DIM 3 1\n", &f);
    assert!(
        e.contains("t.alta:2: expected each header key once (`#DIM` is already on line 1)"),
        "{e}"
    );
    let e = err("#VS 3\n", &f);
    assert!(
        e.starts_with("t.alta:1: expected `#VS 0`, `#VS 1` or `#VS 2`"),
        "{e}"
    );
    let e = err("#FORMAT binary\n", &f);
    assert!(e.contains("the binary format is not supported"), "{e}");
    // Confidence intervals of multi-channel files are refused.
    let e = err(
        "#DIM 3 3\n#PARAM_IN RUSIN_TH_TD_PD\n#PARAM_OUT RGB_COLOR\n#VS 1\n",
        &f,
    );
    assert!(
        e.contains("t.alta:4: expected `#VS 0` for a file with 3 outputs"),
        "{e}"
    );
    // Header lines after #ALTA END HEADER are comments: PARAM_OUT is then missing.
    let e = err(
        "#DIM 3 1\n#PARAM_IN RUSIN_TH_TD_PD\n#ALTA END HEADER\n#PARAM_OUT INV_STERADIAN\n0 0 0 1\n",
        &f,
    );
    assert!(
        e.starts_with("t.alta:5: expected a `#PARAM_OUT` header line"),
        "{e}"
    );
}

#[test]
fn comments_confidence_intervals_and_row_errors() {
    // `# ` and `#1` lines are comments; unknown keys are ignored; #VS 2 adds two numbers.
    let text = "#ALTA_BEGIN_HEADER\n# DIM 9 9\n#1 not a key\n#CMD anything\n#DIM 3  1\r\n\
                #PARAM_IN RUSIN_TH_TD_PD\n#PARAM_OUT INV_STERADIAN\n#VS 2\n#ALTA END HEADER\n\
                0 0 0 1.5 1.4 1.6\n# body comment\n\n0\t0.1 0 2 1 3\n";
    let (d, rep) = read(text, &alta(None, None), &Filters::none()).unwrap();
    assert_eq!((d.len(), rep.read), (2, 2));
    assert_eq!((d.value(0), d.value(1)), (1.5, 2.0));
    let f = alta(None, None);
    let e = err(&text.replace("0 0 0 1.5 1.4 1.6", "0 0 0 1.5 1.4"), &f);
    assert_eq!(
        e,
        "t.alta:10: expected 6 numbers (3 input numbers of RUSIN_TH_TD_PD, 1 output and 2 interval numbers), found 5 numbers"
    );
    let e = err(&(head("RUSIN_TH_TD_PD", 3) + "0 0 x 1\n"), &f);
    assert_eq!(
        e,
        "t.alta:4: expected a number (sample row: 3 input, 1 output and 0 interval numbers), found `x`"
    );
    // nan and inf are numbers; the default filters drop them as non-finite.
    let (d, rep) = read(
        &(head("RUSIN_TH_TD_PD", 3) + "0 0 0 nan\n0 inf 0 1\n0 0 0 1\n"),
        &f,
        &Filters::default(),
    )
    .unwrap();
    assert_eq!((d.len(), rep.non_finite), (1, 2));
}

#[test]
fn parameterisation_names_and_dimensions() {
    for p in AltaInput::ALL {
        assert_eq!(AltaInput::from_name(p.name()), Some(p));
        assert!(p.directions(&[0.1; 5][..p.dimension() - 1]).is_none());
    }
    for p in AltaOutput::ALL {
        assert_eq!(AltaOutput::from_name(p.name()), Some(p));
    }
    assert_eq!(AltaInput::from_name("RUSIN_TH_TD"), None);
    assert_eq!(
        serde_json::to_string(&AltaOutput::InvSteradianCosineFactor).unwrap(),
        "\"INV_STERADIAN_COSINE_FACTOR\""
    );
    // Every direction is a unit vector; isotropic pairs have u.y = 0 and u.x >= 0.
    for p in AltaInput::ALL {
        let x = [0.4, -0.7, 1.1, 0.3, -2.0, 0.9];
        let (u, v) = p.directions(&x).unwrap();
        for w in [u, v] {
            assert!((w[0] * w[0] + w[1] * w[1] + w[2] * w[2] - 1.0).abs() < 1e-15);
        }
        if p.is_isotropic() {
            assert!(u[1] == 0.0 && u[0] >= 0.0, "{p:?}: {u:?}");
        }
    }
}
