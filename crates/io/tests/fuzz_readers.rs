//! Property tests ("fuzzing") of everything that turns outside input into model data: the
//! Cornell, CSV and ALTA parsers (ALTA with every format option), the MERL binary parser, parameter JSON (serde of `BrdfParams`)
//! with `BrdfParams::validate`, and `try_synthetic`. Each property asserts no panic and either
//! `Ok` with consistent data or an error whose message names the input and what was
//! expected.
//!
//! `cargo test` runs a few hundred cases per property. `scripts/fuzz-long.sh` runs the same
//! properties with `PROPTEST_CASES` set (one million executions or more in total); each
//! property prints `FUZZ <name>: <n> executions` (visible with `--nocapture`).

use brdf_io::{
    AltaInput, AltaOutput, DataError, Format, MAX_WAVELENGTHS, MerlBrdf, parse_cornell, parse_csv,
};
use brdf_model::params::ParamError;
use brdf_model::{BrdfParams, DataSet, FilterReport, Filters, MAX_SAMPLES, try_synthetic};
use proptest::prelude::*;
use proptest::test_runner::{Config, TestCaseError, TestRunner};
use std::cell::Cell;
use std::path::Path;

/// Cases per property: `PROPTEST_CASES` when set, else 400.
fn config() -> Config {
    let mut c = Config::default();
    if std::env::var_os("PROPTEST_CASES").is_none() {
        c.cases = 400;
    }
    // Keep the shared tree clean; a failure prints the minimal input.
    c.failure_persistence = None;
    c
}

/// Runs `test` on `strategy` and prints the number of executions.
fn run<S: Strategy>(name: &str, strategy: S, test: impl Fn(S::Value) -> Result<(), TestCaseError>)
where
    S::Value: std::fmt::Debug,
{
    let count = Cell::new(0u64);
    let mut runner = TestRunner::new(config());
    let result = runner.run(&strategy, |v| {
        count.set(count.get() + 1);
        test(v)
    });
    println!("FUZZ {name}: {} executions", count.get());
    if let Err(e) = result {
        panic!("{name}: {e}");
    }
}

/// A token for the text formats: numbers of every kind, special values, huge counts,
/// separators, comments and junk.
fn token() -> impl Strategy<Value = String> {
    prop_oneof![
        4 => (-1e3f64..1e3).prop_map(|v| v.to_string()),
        2 => (0u32..5).prop_map(|v| v.to_string()),
        1 => any::<f64>().prop_map(|v| format!("{v:e}")),
        1 => Just("4000000000".to_string()),
        1 => Just("18446744073709551616".to_string()),
        1 => Just(MAX_WAVELENGTHS.to_string()),
        1 => prop::sample::select(vec![
            "nan", "NaN", "-inf", "inf", "infinity", "1e309", "-0", "550", "#", ",", "",
            "0x10", "1_0", "+", "-", ".", "e5", "\u{0}", "\u{feff}", "ux", "value", "theta_i",
        ])
        .prop_map(str::to_string),
        1 => "[a-z0-9_.,# \\-]{0,8}",
    ]
}

/// Tokens joined by spaces, commas, newlines and carriage returns.
fn text_of_tokens() -> impl Strategy<Value = String> {
    prop::collection::vec(
        (
            token(),
            prop::sample::select(vec![" ", " ", ",", "\n", "\n", "\r\n", "\t"]),
        ),
        0..60,
    )
    .prop_map(|v| v.into_iter().map(|(t, s)| t + s).collect())
}

/// Arbitrary (lossy UTF-8) text, including NULs and control characters.
fn raw_text() -> impl Strategy<Value = String> {
    prop::collection::vec(any::<u8>(), 0..300)
        .prop_map(|b| String::from_utf8_lossy(&b).into_owned())
}

/// A plausible Cornell file: a count, wavelengths, rows (some wrong), then mutations.
fn cornell_text() -> impl Strategy<Value = String> {
    (
        prop_oneof![
            3 => (1usize..5).prop_map(|n| n.to_string()),
            1 => token()
        ],
        prop::collection::vec(
            prop_oneof![3 => Just("550".to_string()), 1 => token()],
            0..6,
        ),
        prop::collection::vec(prop::collection::vec(token(), 0..9), 0..8),
    )
        .prop_map(|(count, wls, rows)| {
            let mut s = format!("# fuzz\n{count}\n{}\n", wls.join(" "));
            for r in rows {
                s += &r.join(" ");
                s.push('\n');
            }
            s
        })
}

/// A plausible CSV file: a header of known and unknown names, rows of tokens.
fn csv_text() -> impl Strategy<Value = String> {
    let name = prop::sample::select(vec![
        "ux", "uy", "uz", "vx", "vy", "vz", "value", "theta_i", "phi_i", "theta_o", "phi_o",
        "extra", " Value ", "UX", "",
    ]);
    (
        prop_oneof![
            Just(vec!["ux", "uy", "uz", "vx", "vy", "vz", "value"]),
            Just(vec![
                "theta_i", "phi_i", "theta_o", "phi_o", "value", "note"
            ]),
            prop::collection::vec(name, 0..10),
        ],
        prop::collection::vec(prop::collection::vec(token(), 0..9), 0..8),
    )
        .prop_map(|(header, rows)| {
            let mut s = header.join(",");
            s.push('\n');
            for r in rows {
                s += &r.join(",");
                s.push('\n');
            }
            s
        })
}

/// Checks a reader's result: `Ok` data consistent with its report (and, under the default
/// filters, finite and above the horizon), or an error naming the file.
fn check_read(
    r: Result<(DataSet, FilterReport), DataError>,
    name: &str,
    filters: &Filters,
) -> Result<(), TestCaseError> {
    match r {
        Ok((d, rep)) => {
            prop_assert_eq!(d.len(), rep.kept);
            prop_assert_eq!(rep.read, rep.kept + rep.dropped());
            if filters.drop_non_finite {
                for i in 0..d.len() {
                    prop_assert!(d.value(i).is_finite());
                    prop_assert!(d.u(i).iter().chain(d.v(i).iter()).all(|c| c.is_finite()));
                }
            }
            if filters.drop_below_horizon {
                for i in 0..d.len() {
                    prop_assert!(d.u(i)[2] >= 0.0 && d.v(i)[2] >= 0.0);
                }
            }
        }
        Err(e) => {
            let msg = e.to_string();
            prop_assert!(msg.contains(name), "error does not name the file: {}", msg);
            prop_assert!(
                msg.contains("expected") || matches!(e, DataError::NoWavelength { .. }),
                "error does not say what was expected: {}",
                msg
            );
        }
    }
    Ok(())
}

fn filters() -> impl Strategy<Value = Filters> {
    prop_oneof![
        Just(Filters::default()),
        Just(Filters::none()),
        Just(Filters::paper())
    ]
}

#[test]
fn fuzz_parse_cornell() {
    let path = Path::new("fuzz.brdf");
    let text = prop_oneof![3 => cornell_text(), 1 => text_of_tokens(), 1 => raw_text()];
    run(
        "parse_cornell",
        (text, filters(), prop_oneof![Just(550.0), any::<f64>()]),
        |(t, f, wl)| check_read(parse_cornell(&t, path, wl, &f), "fuzz.brdf", &f),
    );
}

#[test]
fn fuzz_parse_csv() {
    let path = Path::new("fuzz.csv");
    let text = prop_oneof![3 => csv_text(), 1 => text_of_tokens(), 1 => raw_text()];
    run("parse_csv", (text, filters()), |(t, f)| {
        check_read(parse_csv(&t, path, &f), "fuzz.csv", &f)
    });
}

/// A plausible ALTA file: header lines (supported, unsupported and junk values, comments,
/// repeats, in any order), then rows of tokens.
fn alta_text() -> impl Strategy<Value = String> {
    let mut ins: Vec<String> = AltaInput::ALL
        .iter()
        .map(|p| p.name().to_string())
        .collect();
    ins.extend(["STARK_2D", "RUSIN_TH_TD", "UNKNOWN_INPUT", ""].map(String::from));
    let mut outs: Vec<String> = AltaOutput::ALL
        .iter()
        .map(|p| p.name().to_string())
        .collect();
    outs.extend(["ENERGY", "XYZ_COLOR", "inv_steradian"].map(String::from));
    let line = prop_oneof![
        3 => (0usize..8, 0usize..5).prop_map(|(n, p)| format!("#DIM {n} {p}")),
        1 => token().prop_map(|t| format!("#DIM {t}")),
        3 => prop::sample::select(ins).prop_map(|p| format!("#PARAM_IN {p}")),
        3 => prop::sample::select(outs).prop_map(|p| format!("#PARAM_OUT {p}")),
        1 => (0usize..4).prop_map(|v| format!("#VS {v}")),
        1 => prop::sample::select(vec![
            "#FORMAT text", "#FORMAT binary", "#ALTA END HEADER", "#ALTA HEADER DATA",
            "# DIM 3 1", "#SAMPLE \"x\"", "#", "#1", "",
        ])
        .prop_map(str::to_string),
    ];
    (
        prop::collection::vec(line, 0..7),
        prop::collection::vec(prop::collection::vec(token(), 0..10), 0..8),
    )
        .prop_map(|(head, rows)| {
            let mut s = head.join("\n");
            s.push('\n');
            for r in rows {
                s += &r.join(" ");
                s.push('\n');
            }
            s
        })
}

/// Well-formed ALTA headers for each supported pair of parameterisations, then rows of
/// numbers (some of the right length): most cases get past the header.
fn alta_valid_text() -> impl Strategy<Value = String> {
    (
        prop::sample::select(AltaInput::ALL.to_vec()),
        prop::sample::select(AltaOutput::ALL.to_vec()),
        prop::collection::vec(
            prop::collection::vec(
                prop_oneof![4 => (-4.0f64..4.0).prop_map(|v| v.to_string()), 1 => token()],
                0..10,
            ),
            0..8,
        ),
    )
        .prop_map(|(i, o, rows)| {
            let mut s = format!(
                "#DIM {} {}\n#PARAM_IN {}\n#PARAM_OUT {}\n",
                i.dimension(),
                o.dimension(),
                i.name(),
                o.name()
            );
            for r in rows {
                s += &r.join(" ");
                s.push('\n');
            }
            s
        })
}

fn alta_format() -> impl Strategy<Value = Format> {
    let channel = prop_oneof![
        2 => Just(None),
        1 => prop::sample::select(vec![
            brdf_io::Channel::Red,
            brdf_io::Channel::Green,
            brdf_io::Channel::Blue,
        ])
        .prop_map(Some),
    ];
    let out = prop_oneof![
        2 => Just(None),
        1 => prop::sample::select(AltaOutput::ALL.to_vec()).prop_map(Some),
    ];
    (channel, out).prop_map(|(channel, param_out)| Format::Alta { channel, param_out })
}

#[test]
fn fuzz_parse_alta() {
    let path = Path::new("fuzz.alta");
    let text = prop_oneof![
        3 => alta_text(),
        3 => alta_valid_text(),
        1 => text_of_tokens(),
        1 => raw_text()
    ];
    run(
        "parse_alta",
        (text, alta_format(), filters()),
        |(t, format, f)| {
            check_read(
                brdf_io::parse(t.as_bytes(), path, &format, &f),
                "fuzz.alta",
                &f,
            )
        },
    );
}

/// MERL: arbitrary bytes, and headers with chosen dims followed by a payload of the right
/// length, off by some bytes, or absent.
#[test]
fn fuzz_merl_from_bytes() {
    let path = Path::new("fuzz.binary");
    let dim = prop_oneof![
        4 => 1i32..4,
        1 => any::<i32>(),
        1 => Just(4096),
        1 => Just(4097),
        1 => Just(0),
        1 => Just(-1),
    ];
    let structured =
        (dim.clone(), dim.clone(), dim, -9i64..9, any::<u64>()).prop_map(|(a, b, c, off, seed)| {
            let mut bytes = Vec::new();
            for d in [a, b, c] {
                bytes.extend_from_slice(&d.to_le_bytes());
            }
            let cells = if a > 0 && b > 0 && c > 0 && (a as i128) * (b as i128) * (c as i128) < 100
            {
                (a * b * c) as i64
            } else {
                2
            };
            let len = (cells * 24 + off).max(0) as usize;
            // Payload bytes from the seed: some entries negative, NaN or infinite.
            let mut x = seed | 1;
            for _ in 0..len {
                x ^= x << 13;
                x ^= x >> 7;
                x ^= x << 17;
                bytes.push(x as u8);
            }
            bytes
        });
    let bytes = prop_oneof![3 => structured, 1 => prop::collection::vec(any::<u8>(), 0..64)];
    run("merl_from_bytes", (bytes, filters()), |(b, f)| {
        match MerlBrdf::from_bytes(&b, path) {
            Ok(m) => {
                let n = m.dims.0 * m.dims.1 * m.dims.2;
                prop_assert_eq!(m.table.len(), 3 * n);
                prop_assert_eq!(m.to_bytes(), b);
                for ch in [
                    brdf_io::Channel::Red,
                    brdf_io::Channel::Green,
                    brdf_io::Channel::Blue,
                ] {
                    let (d, rep) = m.sample_grid(ch, &f);
                    check_read(Ok((d, rep)), "", &f)?;
                    prop_assert_eq!(rep.read, n);
                }
            }
            Err(e) => {
                let msg = e.to_string();
                prop_assert!(
                    msg.contains("fuzz.binary") && msg.contains("expected"),
                    "{}",
                    msg
                );
            }
        }
        Ok(())
    });
}

/// JSON values shaped like parameters, with wrong types, unknown keys and odd numbers.
fn params_json() -> impl Strategy<Value = String> {
    let num = prop_oneof![
        4 => (-2.0f64..2.0).prop_map(|v| v.to_string()),
        1 => (0.0f64..20000.0).prop_map(|v| v.to_string()),
        1 => any::<f64>().prop_map(|v| format!("{v:e}")),
        1 => prop::sample::select(vec!["1e999", "-1e999", "null", "\"1\"", "true", "[]", "{}", "NaN"])
            .prop_map(str::to_string),
    ];
    let key = prop::sample::select(vec!["cx", "cy", "cz", "n", "pan_deg", "pan", "kd", "lobes"]);
    let lobe = prop::collection::vec((key, num.clone()), 0..7).prop_map(|kv| {
        let fields: Vec<String> = kv.iter().map(|(k, v)| format!("\"{k}\":{v}")).collect();
        format!("{{{}}}", fields.join(","))
    });
    let full = (
        num,
        prop::collection::vec(lobe, 0..4),
        prop::option::of(Just("\"extra\":1")),
    )
        .prop_map(|(kd, lobes, extra)| {
            let mut s = format!("{{\"kd\":{kd},\"lobes\":[{}]", lobes.join(","));
            if let Some(e) = extra {
                s += ",";
                s += e;
            }
            s + "}"
        });
    // Well-formed parameters (all fields present) in and out of the box.
    let good = (
        -0.5f64..1.5,
        prop::collection::vec(
            (
                -2.0f64..2.0,
                -2.0f64..2.0,
                -2.0f64..2.0,
                -10.0f64..12000.0,
                -100.0f64..100.0,
            ),
            0..4,
        ),
    )
        .prop_map(|(kd, lobes)| {
            let lobes: Vec<String> = lobes
                .iter()
                .map(|(cx, cy, cz, n, p)| {
                    format!("{{\"cx\":{cx},\"cy\":{cy},\"cz\":{cz},\"n\":{n},\"pan_deg\":{p}}}")
                })
                .collect();
            format!("{{\"kd\":{kd},\"lobes\":[{}]}}", lobes.join(","))
        });
    prop_oneof![3 => good, 3 => full, 1 => "[ -~]{0,40}"]
}

#[test]
fn fuzz_params_json_validate_and_synthetic() {
    run(
        "params_json",
        (
            params_json(),
            0usize..40,
            prop_oneof![Just(0.1), any::<f64>()],
            any::<u64>(),
        ),
        |(json, count, sigma, seed)| {
            let p: BrdfParams = match serde_json::from_str(&json) {
                Ok(p) => p,
                Err(e) => {
                    prop_assert!(!e.to_string().is_empty());
                    return Ok(());
                }
            };
            let valid = p.validate();
            if let Err(e) = &valid {
                let msg = e.to_string();
                prop_assert!(msg.contains("expected"), "{}", msg);
            }
            match try_synthetic(&p, count, sigma, seed) {
                Ok(d) => {
                    prop_assert!(valid.is_ok());
                    prop_assert_eq!(d.len(), count);
                    prop_assert!(d.values().iter().all(|v| v.is_finite()));
                }
                Err(e) => {
                    let msg = e.to_string();
                    prop_assert!(msg.contains("expected"), "{}", msg);
                    let explained = valid.is_err()
                        || matches!(
                            e,
                            ParamError::SampleCount { .. }
                                | ParamError::Sigma { .. }
                                | ParamError::NonFiniteValue { .. }
                        );
                    prop_assert!(explained, "{}", msg);
                }
            }
            Ok(())
        },
    );
}

/// Huge counts and sigmas are refused before anything is allocated.
#[test]
fn fuzz_synthetic_limits() {
    let p = brdf_model::named_params("tuning").unwrap();
    run(
        "synthetic_limits",
        (MAX_SAMPLES + 1..usize::MAX, any::<f64>()),
        |(count, sigma)| {
            let e = try_synthetic(&p, count, sigma, 1).unwrap_err();
            prop_assert!(matches!(e, ParamError::SampleCount { .. }), "{}", e);
            if sigma.is_finite() && sigma > brdf_model::data::MAX_SIGMA {
                let e = try_synthetic(&p, 10, sigma, 1).unwrap_err();
                prop_assert!(e.to_string().contains("MAX_SIGMA"), "{}", e);
            }
            Ok(())
        },
    );
}
