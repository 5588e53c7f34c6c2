//! The line loop shared by the text formats (Cornell, CSV, ALTA): streaming, bounded, UTF-8,
//! comments and blank lines skipped, line numbers for the errors, and one sample loop that
//! counts rows against [`MAX_SAMPLES`] and applies the filters.

use super::limits::{MAX_INPUT_BYTES, MAX_LINE_BYTES, MAX_SAMPLES, sample_limit};
use super::{DataError, io_err};
use brdf_model::{DataSet, FilterReport, Filters};
use std::io::{BufRead, Read};
use std::path::Path;

/// Streams the content lines of a text input (blank lines and, unless asked for, `#` comments
/// skipped), enforcing [`MAX_INPUT_BYTES`], [`MAX_LINE_BYTES`], no NUL bytes and UTF-8.
pub(super) struct LineSource<'p, R> {
    reader: R,
    path: &'p Path,
    buf: Vec<u8>,
    total: u64,
    line: usize,
    /// The line in `buf` is to be returned again by the next call ([`LineSource::push_back`]).
    replay: bool,
}

impl<'p, R: BufRead> LineSource<'p, R> {
    pub(super) fn new(reader: R, path: &'p Path) -> Self {
        LineSource {
            reader,
            path,
            buf: Vec::new(),
            total: 0,
            line: 0,
            replay: false,
        }
    }

    /// The file named in errors.
    pub(super) fn path(&self) -> &'p Path {
        self.path
    }

    fn limit(&self, message: String) -> DataError {
        DataError::Limit {
            path: self.path.to_path_buf(),
            line: self.line,
            message,
        }
    }

    /// The next non-blank, non-comment line, trimmed, with its number (from 1).
    pub(super) fn next_line(&mut self) -> Result<Option<(usize, &str)>, DataError> {
        self.next_inner(false)
    }

    /// The next non-blank line, trimmed, with its number (from 1); `#` lines included (the
    /// ALTA header is made of them).
    pub(super) fn next_line_with_comments(&mut self) -> Result<Option<(usize, &str)>, DataError> {
        self.next_inner(true)
    }

    /// Makes the next call return the line just returned again (with the same number): a
    /// reader that finds the end of a header on the first data line hands it to the sample
    /// loop this way.
    pub(super) fn push_back(&mut self) {
        self.replay = true;
    }

    fn next_inner(&mut self, keep_comments: bool) -> Result<Option<(usize, &str)>, DataError> {
        loop {
            // A replayed line is still in `buf`, checked by the call that returned it.
            if !std::mem::take(&mut self.replay) && !self.read_checked()? {
                return Ok(None);
            }
            // UTF-8 was checked by `read_checked`.
            let skip = {
                let text = std::str::from_utf8(&self.buf).unwrap_or_default().trim();
                text.is_empty() || (!keep_comments && text.starts_with('#'))
            };
            if !skip {
                // Borrowed only on return, so the loop can keep reading into `buf`.
                let text = std::str::from_utf8(&self.buf).unwrap_or_default().trim();
                return Ok(Some((self.line, text)));
            }
        }
    }

    /// Reads the next line into `buf` (without its line break) and checks the limits, NUL
    /// bytes and UTF-8; false at the end of the input.
    fn read_checked(&mut self) -> Result<bool, DataError> {
        self.buf.clear();
        let left = MAX_INPUT_BYTES + 1 - self.total;
        let cap = left.min(MAX_LINE_BYTES as u64 + 2);
        let n = (&mut self.reader)
            .take(cap)
            .read_until(b'\n', &mut self.buf)
            .map_err(|e| io_err(self.path, e))?;
        if n == 0 {
            return Ok(false);
        }
        self.total += n as u64;
        self.line += 1;
        if self.total > MAX_INPUT_BYTES {
            return Err(self.limit(format!(
                "expected at most {MAX_INPUT_BYTES} bytes of text (MAX_INPUT_BYTES), found more"
            )));
        }
        if self.buf.last() == Some(&b'\n') {
            self.buf.pop();
            if self.buf.last() == Some(&b'\r') {
                self.buf.pop();
            }
        }
        if self.buf.len() > MAX_LINE_BYTES {
            return Err(self.limit(format!(
                "expected lines of at most {MAX_LINE_BYTES} bytes (MAX_LINE_BYTES), found a longer one"
            )));
        }
        if let Some(k) = self.buf.iter().position(|&b| b == 0) {
            return Err(DataError::Parse {
                path: self.path.to_path_buf(),
                line: self.line,
                expected: "text".into(),
                found: format!("a NUL byte at column {} (binary data?)", k + 1),
            });
        }
        if let Err(e) = std::str::from_utf8(&self.buf) {
            return Err(DataError::Parse {
                path: self.path.to_path_buf(),
                line: self.line,
                expected: "UTF-8 text".into(),
                found: format!("an invalid byte at column {}", e.valid_up_to() + 1),
            });
        }
        Ok(true)
    }
}

/// One sample of a text format, before the filters.
pub(super) struct Sample {
    /// Incident direction (unit, away from the surface).
    pub(super) u: [f64; 3],
    /// Exitant direction (unit, away from the surface).
    pub(super) v: [f64; 3],
    /// BRDF value.
    pub(super) value: f64,
    /// The source marks the sample as below the horizon (see `Filters::admit_marked`).
    pub(super) below_mark: bool,
}

impl Sample {
    pub(super) fn new(u: [f64; 3], v: [f64; 3], value: f64) -> Self {
        Sample {
            u,
            v,
            value,
            below_mark: false,
        }
    }
}

/// The sample loop of every text format: each remaining content line is one sample row,
/// turned into a [`Sample`] by `row` (given the line number and the trimmed line); rows are
/// counted against [`MAX_SAMPLES`] before filtering, and `filters` decide what is kept.
pub(super) fn read_samples<R: BufRead>(
    lines: &mut LineSource<'_, R>,
    filters: &Filters,
    mut row: impl FnMut(usize, &str) -> Result<Sample, DataError>,
) -> Result<(DataSet, FilterReport), DataError> {
    let path = lines.path();
    let mut data = DataSet::new();
    let mut rep = FilterReport::default();
    let mut rows = 0usize;
    while let Some((ln, l)) = lines.next_line()? {
        rows += 1;
        if rows > MAX_SAMPLES {
            return Err(sample_limit(path, ln));
        }
        let s = row(ln, l)?;
        if filters.admit_marked(s.u, s.v, s.value, s.below_mark, &mut rep) {
            data.push(s.u, s.v, s.value);
        }
    }
    Ok((data, rep))
}

pub(super) fn short(s: &str) -> String {
    let t: String = s.chars().take(40).collect();
    if t.len() < s.len() {
        format!("`{t}...`")
    } else {
        format!("`{t}`")
    }
}
