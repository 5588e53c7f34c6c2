//! The CSV reader (vector or angle columns; format in the crate docs).

use super::lines::{LineSource, Sample, read_samples, short};
use super::{DataError, dir_from_angles, normalise};
use brdf_model::{DataSet, FilterReport, Filters};
use std::io::BufRead;

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
