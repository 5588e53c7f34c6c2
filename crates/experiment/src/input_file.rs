//! Reading a spec or results file only when it is a regular file of bounded size, so that a
//! device (`/dev/zero`), a FIFO or a link to one gets a clear error instead of a read that never
//! ends or exhausts memory; and checking that an output folder is a folder.
//!
//! Errors are [`std::io::Error`]s wrapping a [`Refused`], so every caller's existing
//! "`{path}: {source}`" error names the file; [`is_refused`] lets the binary tell such bad input
//! (exit status 2) from a failing disk (1).

use std::io::{Error, ErrorKind, Read};
use std::path::Path;

/// Largest spec file read (a spec is a few kilobytes; generous against huge sweeps as lists).
pub const MAX_SPEC_BYTES: u64 = 16 << 20;

/// Why an input file was not read.
#[derive(Debug, thiserror::Error)]
pub enum Refused {
    /// The path is a device, FIFO, socket or directory (through links, if any).
    #[error("is {kind}, not a regular file; expected {expected}")]
    NotRegular {
        /// What it is ("a character device", ...).
        kind: &'static str,
        /// What was expected there.
        expected: &'static str,
    },
    /// The file is larger than the limit for its kind.
    #[error("is larger than {limit} bytes, the limit for {expected}; refusing to read it")]
    TooLarge {
        /// The limit in bytes.
        limit: u64,
        /// What was expected there.
        expected: &'static str,
    },
    /// An output folder that exists and is not a folder.
    #[error("is {kind}, not a directory; expected an output folder")]
    NotDirectory {
        /// What it is.
        kind: &'static str,
    },
}

/// True when `e` is (or wraps) an I/O error carrying a [`Refused`]: bad input, not a failure.
/// An output path that [`brdf_graphics::files::write_atomic`] refused (a device, FIFO, socket
/// or directory) counts too.
pub fn is_refused(e: &(dyn std::error::Error + 'static)) -> bool {
    e.downcast_ref::<Error>().is_some_and(|io| {
        brdf_graphics::target::is_refused_target(io)
            || io.get_ref().is_some_and(|inner| inner.is::<Refused>())
    })
}

fn refused(r: Refused) -> Error {
    Error::new(ErrorKind::InvalidInput, r)
}

/// What a file that is not a regular file is, for messages.
pub fn kind_of(meta: &std::fs::Metadata) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        let t = meta.file_type();
        for (is, name) in [
            (t.is_fifo(), "a FIFO"),
            (t.is_char_device(), "a character device"),
            (t.is_block_device(), "a block device"),
            (t.is_socket(), "a socket"),
        ] {
            if is {
                return name;
            }
        }
    }
    if meta.is_dir() {
        "a directory"
    } else if meta.is_file() {
        "a regular file"
    } else {
        "a special file"
    }
}

/// Opens `path` (following links) when it is a regular file of at most `limit` bytes.
pub fn open_regular(
    path: &Path,
    limit: u64,
    expected: &'static str,
) -> std::io::Result<std::fs::File> {
    let meta = std::fs::metadata(path)?;
    if !meta.is_file() {
        let kind = kind_of(&meta);
        return Err(refused(Refused::NotRegular { kind, expected }));
    }
    if meta.len() > limit {
        return Err(refused(Refused::TooLarge { limit, expected }));
    }
    std::fs::File::open(path)
}

/// Reads a regular file of at most `limit` bytes (checked before and while reading, in case it
/// grows).
pub fn read_regular(path: &Path, limit: u64, expected: &'static str) -> std::io::Result<Vec<u8>> {
    let file = open_regular(path, limit, expected)?;
    let mut bytes = Vec::new();
    std::io::BufReader::new(file)
        .take(limit + 1)
        .read_to_end(&mut bytes)?;
    if bytes.len() as u64 > limit {
        return Err(refused(Refused::TooLarge { limit, expected }));
    }
    Ok(bytes)
}

/// Refuses an output folder that exists and is not a directory (a file, a device such as
/// `/dev/full`, a link to one); a missing folder is fine (it is created).
pub fn check_out_dir(dir: &Path) -> std::io::Result<()> {
    match std::fs::metadata(dir) {
        Ok(meta) if !meta.is_dir() => Err(refused(Refused::NotDirectory {
            kind: kind_of(&meta),
        })),
        _ => Ok(()),
    }
}

/// Refuses `path` when it exists (through links) and is not a regular file; a missing file is
/// fine. For files about to be opened for appending or resuming.
pub fn check_regular_if_present(path: &Path, expected: &'static str) -> std::io::Result<()> {
    match std::fs::metadata(path) {
        Ok(meta) if !meta.is_file() => Err(refused(Refused::NotRegular {
            kind: kind_of(&meta),
            expected,
        })),
        _ => Ok(()),
    }
}

/// Reads a spec file as UTF-8 text: a regular file of at most [`MAX_SPEC_BYTES`].
pub fn read_spec_text(path: &Path) -> std::io::Result<String> {
    let bytes = read_regular(path, MAX_SPEC_BYTES, "a spec (a TOML file)")?;
    String::from_utf8(bytes).map_err(|e| Error::new(ErrorKind::InvalidData, e))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[cfg(unix)]
    #[test]
    fn a_link_to_a_device_is_refused_without_reading() {
        let dir = tempfile::tempdir().unwrap();
        let link = dir.path().join("trials.jsonl");
        std::os::unix::fs::symlink("/dev/zero", &link).unwrap();
        let err = read_regular(&link, 10, "a results file").unwrap_err();
        assert!(is_refused(&err));
        assert_eq!(
            err.to_string(),
            "is a character device, not a regular file; expected a results file"
        );
    }

    #[test]
    fn a_file_over_the_limit_is_refused_and_one_at_it_is_read() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("x.toml");
        std::fs::write(&p, "12345").unwrap();
        assert_eq!(read_regular(&p, 5, "a spec").unwrap(), b"12345");
        let err = read_regular(&p, 4, "a spec").unwrap_err();
        assert!(is_refused(&err));
        assert!(err.to_string().contains("larger than 4 bytes"), "{err}");
    }

    #[test]
    fn an_out_folder_must_be_a_folder_or_missing() {
        let dir = tempfile::tempdir().unwrap();
        assert!(check_out_dir(dir.path()).is_ok());
        assert!(check_out_dir(&dir.path().join("new")).is_ok());
        let file = dir.path().join("file");
        std::fs::write(&file, "").unwrap();
        let err = check_out_dir(&file).unwrap_err();
        assert!(
            err.to_string()
                .starts_with("is a regular file, not a directory")
        );
        let other = std::io::Error::other("disk");
        assert!(!is_refused(&other));
    }
}
