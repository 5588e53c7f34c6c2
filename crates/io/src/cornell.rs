//! The Cornell text reader (`*.brdf`; format in the crate docs).

use super::limits::MAX_WAVELENGTHS;
use super::lines::{LineSource, Sample, read_samples, short};
use super::{DataError, dir_from_angles};
use brdf_model::{DataSet, FilterReport, Filters};
use std::io::BufRead;

pub(super) fn cornell_from<R: BufRead>(
    mut lines: LineSource<'_, R>,
    wavelength_nm: f64,
    filters: &Filters,
) -> Result<(DataSet, FilterReport), DataError> {
    let path = lines.path();
    let perr = |line: usize, expected: String, found: String| DataError::Parse {
        path: path.to_path_buf(),
        line,
        expected,
        found,
    };
    let (ln, first) = lines
        .next_line()?
        .ok_or_else(|| perr(0, "the number of wavelengths".into(), "end of file".into()))?;
    let mut toks = first.split_whitespace();
    let nwl: usize = match (toks.next(), toks.next()) {
        (Some(tok), None) => tok.parse().ok().filter(|&n: &usize| n > 0),
        _ => None,
    }
    .ok_or_else(|| {
        perr(
            ln,
            "the number of wavelengths (a positive integer alone on its line)".into(),
            short(first),
        )
    })?;
    if nwl > MAX_WAVELENGTHS {
        return Err(DataError::Limit {
            path: path.to_path_buf(),
            line: ln,
            message: format!(
                "expected at most {MAX_WAVELENGTHS} wavelengths (MAX_WAVELENGTHS), the file declares {nwl}"
            ),
        });
    }
    let mut wls: Vec<f64> = Vec::with_capacity(nwl);
    while wls.len() < nwl {
        let (ln, l) = lines.next_line()?.ok_or_else(|| {
            perr(
                0,
                format!("{nwl} wavelengths"),
                format!("end of file after {}", wls.len()),
            )
        })?;
        for tok in l.split_whitespace() {
            if wls.len() == nwl {
                return Err(perr(
                    ln,
                    format!("{nwl} wavelengths"),
                    format!("more numbers (`{}` is extra)", short(tok)),
                ));
            }
            let w: f64 = tok
                .parse()
                .ok()
                .filter(|w: &f64| w.is_finite())
                .ok_or_else(|| perr(ln, "a finite wavelength in nm".into(), short(tok)))?;
            wls.push(w);
        }
    }
    let col = wls
        .iter()
        .position(|w| (w - wavelength_nm).abs() < 1e-6)
        .ok_or_else(|| DataError::NoWavelength {
            path: path.to_path_buf(),
            wavelength_nm,
            available: wls.clone(),
        })?;
    let width = 4 + nwl;
    let mut row = [0.0f64; 5];
    read_samples(&mut lines, filters, |ln, l| {
        let mut count = 0usize;
        for tok in l.split_whitespace() {
            let v: f64 = tok.parse().map_err(|_| {
                perr(
                    ln,
                    format!("a number (sample row: 4 angles in radians and {nwl} values)"),
                    short(tok),
                )
            })?;
            if count < 4 {
                row[count] = v;
            } else if count == 4 + col {
                row[4] = v;
            }
            count += 1;
        }
        if count != width {
            return Err(perr(
                ln,
                format!("{width} numbers (4 angles in radians and {nwl} values)"),
                format!("{count} numbers"),
            ));
        }
        let u = dir_from_angles(row[0], row[1]);
        let v = dir_from_angles(row[2], row[3]);
        Ok(Sample::new(u, v, row[4]))
    })
}
