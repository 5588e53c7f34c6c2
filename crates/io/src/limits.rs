//! The size limits on every input and the errors that report exceeding them.

use super::DataError;
#[cfg(doc)]
use brdf_model::DataSet;
use std::path::Path;

/// Largest text input (Cornell, CSV, ALTA) read, in bytes: 1 GiB. A longer input is refused with
/// [`DataError::Limit`] after reading `MAX_INPUT_BYTES + 1` bytes.
pub const MAX_INPUT_BYTES: u64 = 1 << 30;

/// Longest line of a text input, in bytes (without the line break): 1 MiB.
pub const MAX_LINE_BYTES: usize = 1 << 20;

/// Most sample rows a reader accepts (counted before filtering; also the largest synthetic
/// instance, see [`brdf_model::try_synthetic`]): 10,000,000 (about 560 MB as a [`DataSet`]).
/// The full MERL grid has 1,458,000 cells, the paper's instances 10,000 samples.
pub const MAX_SAMPLES: usize = brdf_model::MAX_SAMPLES;

/// Most wavelengths a Cornell file may declare: 10,000 (the real files have 31).
pub const MAX_WAVELENGTHS: usize = 10_000;

/// Largest MERL dimension: 4096 (the real database uses 90, 90, 180).
pub const MAX_MERL_DIM: usize = 4096;

/// Largest MERL file, in bytes: 512 MiB (the real files have 34,992,012 bytes).
pub const MAX_MERL_BYTES: u64 = 512 << 20;

pub(super) fn check_text_len(text: &[u8], path: &Path) -> Result<(), DataError> {
    if text.len() as u64 > MAX_INPUT_BYTES {
        return Err(DataError::Limit {
            path: path.to_path_buf(),
            line: 0,
            message: format!(
                "expected at most {MAX_INPUT_BYTES} bytes of text (MAX_INPUT_BYTES), found {}",
                text.len()
            ),
        });
    }
    Ok(())
}

pub(super) fn sample_limit(path: &Path, line: usize) -> DataError {
    DataError::Limit {
        path: path.to_path_buf(),
        line,
        message: format!("expected at most {MAX_SAMPLES} sample rows (MAX_SAMPLES), found more"),
    }
}
