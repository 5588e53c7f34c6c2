//! The line reader shared by the text formats (Cornell, CSV): streaming, bounded, UTF-8.

use super::limits::{MAX_INPUT_BYTES, MAX_LINE_BYTES};
use super::{DataError, io_err};
use std::io::{BufRead, Read};
use std::path::Path;

/// Streams the content lines of a text input (blank lines and `#` comments skipped), enforcing
/// [`MAX_INPUT_BYTES`], [`MAX_LINE_BYTES`], no NUL bytes and UTF-8.
pub(super) struct LineSource<'p, R> {
    reader: R,
    path: &'p Path,
    buf: Vec<u8>,
    total: u64,
    line: usize,
}

impl<'p, R: BufRead> LineSource<'p, R> {
    pub(super) fn new(reader: R, path: &'p Path) -> Self {
        LineSource {
            reader,
            path,
            buf: Vec::new(),
            total: 0,
            line: 0,
        }
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
        loop {
            self.buf.clear();
            let left = MAX_INPUT_BYTES + 1 - self.total;
            let cap = left.min(MAX_LINE_BYTES as u64 + 2);
            let n = (&mut self.reader)
                .take(cap)
                .read_until(b'\n', &mut self.buf)
                .map_err(|e| io_err(self.path, e))?;
            if n == 0 {
                return Ok(None);
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
            let text = match std::str::from_utf8(&self.buf) {
                Ok(t) => t.trim(),
                Err(e) => {
                    return Err(DataError::Parse {
                        path: self.path.to_path_buf(),
                        line: self.line,
                        expected: "UTF-8 text".into(),
                        found: format!("an invalid byte at column {}", e.valid_up_to() + 1),
                    });
                }
            };
            if text.is_empty() || text.starts_with('#') {
                continue;
            }
            let line = self.line;
            // Re-borrow so the returned slice ties to `self.buf` only.
            let text = std::str::from_utf8(&self.buf).unwrap_or_default().trim();
            return Ok(Some((line, text)));
        }
    }
}

pub(super) fn short(s: &str) -> String {
    let t: String = s.chars().take(40).collect();
    if t.len() < s.len() {
        format!("`{t}...`")
    } else {
        format!("`{t}`")
    }
}
