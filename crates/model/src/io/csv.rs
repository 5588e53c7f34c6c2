//! The CSV reader (vector or angle columns; format in the [`io`](crate::io) module docs).

use super::format::Format;
use super::lines::{LineSource, Sample, read_samples, short};
use super::{DataError, dir_from_angles};
use crate::data::{DataSet, FilterReport, Filters};
use std::io::BufRead;
use std::path::Path;

/// Reads a CSV file (format in the module docs), applying `filters`: [`super::read`] with
/// [`Format::Csv`]. The file is streamed (see the module docs for the limits).
pub fn read_csv(
    path: impl AsRef<Path>,
    filters: &Filters,
) -> Result<(DataSet, FilterReport), DataError> {
    super::read(path.as_ref(), &Format::Csv, filters)
}

/// Parses CSV already in memory; `path` is only used in errors: [`super::parse`] with
/// [`Format::Csv`].
pub fn parse_csv(
    text: &str,
    path: &Path,
    filters: &Filters,
) -> Result<(DataSet, FilterReport), DataError> {
    super::parse(text.as_bytes(), path, &Format::Csv, filters)
}

/// Normalises a direction given by finite or non-finite components: `Ok(None)` for a zero
/// vector, non-finite components are passed through (the filters count them).
pub(super) fn normalise(a: [f64; 3]) -> Option<[f64; 3]> {
    if a.iter().any(|c| !c.is_finite()) {
        return Some(a);
    }
    // Scale first so that huge or tiny components neither overflow nor underflow.
    let m = a.iter().fold(0.0f64, |m, c| m.max(c.abs()));
    if m == 0.0 {
        return None;
    }
    let b = [a[0] / m, a[1] / m, a[2] / m];
    let len = (b[0] * b[0] + b[1] * b[1] + b[2] * b[2]).sqrt();
    Some([b[0] / len, b[1] / len, b[2] / len])
}

pub(super) fn csv_from<R: BufRead>(
    mut lines: LineSource<'_, R>,
    filters: &Filters,
) -> Result<(DataSet, FilterReport), DataError> {
    let path = lines.path();
    let perr = |line: usize, expected: String, found: String| DataError::Parse {
        path: path.to_path_buf(),
        line,
        expected,
        found,
    };
    const HEADER: &str = "a header naming ux,uy,uz,vx,vy,vz,value or theta_i,phi_i,theta_o,phi_o,value (extra columns are ignored)";
    let (hl, header) = lines
        .next_line()?
        .ok_or_else(|| perr(0, HEADER.into(), "end of file".into()))?;
    let names: Vec<String> = header
        .split(',')
        .map(|s| s.trim().to_ascii_lowercase())
        .collect();
    let header_short = short(header);
    let find = |n: &str| names.iter().position(|h| h == n);
    const VEC: [&str; 7] = ["ux", "uy", "uz", "vx", "vy", "vz", "value"];
    const ANG: [&str; 5] = ["theta_i", "phi_i", "theta_o", "phi_o", "value"];
    let vec_cols: Option<Vec<usize>> = VEC.iter().map(|n| find(n)).collect();
    let ang_cols: Option<Vec<usize>> = ANG.iter().map(|n| find(n)).collect();
    let (cols, angles) = match (vec_cols, ang_cols) {
        (Some(c), _) => (c, false),
        (None, Some(c)) => (c, true),
        (None, None) => return Err(perr(hl, HEADER.into(), header_short)),
    };
    let wanted: &[&str] = if angles { &ANG } else { &VEC };
    for n in wanted {
        if names.iter().filter(|h| h == n).count() > 1 {
            return Err(perr(
                hl,
                format!("each column name once in the header (`{n}` is repeated)"),
                header_short,
            ));
        }
    }
    let ncols = names.len();
    // slot[k] = Some(j): field k is column j of the wanted list.
    let mut slot: Vec<Option<usize>> = vec![None; ncols];
    for (j, &c) in cols.iter().enumerate() {
        slot[c] = Some(j);
    }
    let mut vals = [0.0f64; 7];
    read_samples(&mut lines, filters, |ln, l| {
        let mut count = 0usize;
        for (k, tok) in l.split(',').enumerate() {
            count += 1;
            let Some(j) = slot.get(k).copied().flatten() else {
                continue;
            };
            let tok = tok.trim();
            vals[j] = tok.parse().map_err(|_| {
                perr(
                    ln,
                    format!("a number in column `{}`", wanted[j]),
                    short(tok),
                )
            })?;
        }
        if count != ncols {
            return Err(perr(
                ln,
                format!("{ncols} comma-separated fields as in the header"),
                format!("{count} fields"),
            ));
        }
        Ok(if angles {
            Sample::new(
                dir_from_angles(vals[0].to_radians(), vals[1].to_radians()),
                dir_from_angles(vals[2].to_radians(), vals[3].to_radians()),
                vals[4],
            )
        } else {
            let norm = |a: [f64; 3], what: &str| {
                normalise(a).ok_or_else(|| {
                    perr(ln, format!("a non-zero direction {what}"), format!("{a:?}"))
                })
            };
            Sample::new(
                norm([vals[0], vals[1], vals[2]], "u")?,
                norm([vals[3], vals[4], vals[5]], "v")?,
                vals[6],
            )
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p() -> &'static Path {
        Path::new("t.csv")
    }

    #[test]
    fn csv_vectors_and_angles() {
        let text = "# comment\nux, uy, uz, vx, vy, vz, value\n0,0,2,0,0,1,0.5\n0,0,1,0,0,-1,0.2\n";
        let (d, rep) = parse_csv(text, p(), &Filters::default()).unwrap();
        assert_eq!(d.len(), 1);
        assert_eq!(d.u(0), [0.0, 0.0, 1.0]);
        assert_eq!(rep.below_horizon, 1);
        let text = "theta_i,phi_i,theta_o,phi_o,value,extra\n90,0,0,0,0.25,1\n";
        let (d, _) = parse_csv(text, p(), &Filters::default()).unwrap();
        assert!((d.u(0)[0] - 1.0).abs() < 1e-15 && d.u(0)[2].abs() < 1e-15);
        assert_eq!(d.value(0), 0.25);
    }

    #[test]
    fn csv_errors_name_line_and_expectation() {
        let e = parse_csv("a,b\n1,2\n", p(), &Filters::default()).unwrap_err();
        assert!(matches!(e, DataError::Parse { line: 1, .. }), "{e}");
        let e = parse_csv(
            "ux,uy,uz,vx,vy,vz,value\n0,0,1,0,0,1,x\n",
            p(),
            &Filters::default(),
        )
        .unwrap_err();
        let msg = e.to_string();
        assert!(
            msg.contains("t.csv:2") && msg.contains("column `value`"),
            "{msg}"
        );
        let e = parse_csv(
            "ux,uy,uz,vx,vy,vz,value\n0,0,1,0,0,1\n",
            p(),
            &Filters::default(),
        )
        .unwrap_err();
        assert!(e.to_string().contains("7 comma-separated fields"), "{e}");
        let e = parse_csv(
            "ux,uy,uz,vx,vy,vz,value\n0,0,0,0,0,1,1\n",
            p(),
            &Filters::default(),
        )
        .unwrap_err();
        assert!(e.to_string().contains("non-zero direction u"), "{e}");
        assert!(matches!(
            parse_csv("", p(), &Filters::default()),
            Err(DataError::Parse { line: 0, .. })
        ));
    }

    #[test]
    fn csv_round_trip() {
        let params = crate::named_params("cross").unwrap();
        let d = crate::synthetic(&params, 50, 0.1, 9);
        let mut buf = Vec::new();
        d.write_csv(&mut buf).unwrap();
        let (back, _) =
            parse_csv(std::str::from_utf8(&buf).unwrap(), p(), &Filters::none()).unwrap();
        assert_eq!(back.len(), 50);
        for i in 0..50 {
            assert_eq!(back.value(i), d.value(i));
            for k in 0..3 {
                assert!((back.u(i)[k] - d.u(i)[k]).abs() < 1e-15);
            }
        }
    }
}
