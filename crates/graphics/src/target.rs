//! Where an atomic write may land: through symbolic links to the file they name, never over a
//! device, FIFO, socket or directory; and the cleanup of temporaries that killed writers left.

use std::io::{Error, ErrorKind};
use std::path::{Path, PathBuf};

/// Symbolic links followed before giving up (the kernel's own limit, `MAXSYMLINKS`, is 40).
const MAX_LINK_HOPS: usize = 40;

/// Why a write target was refused (carried inside the [`std::io::Error`] that
/// [`write_target`] returns, so callers can tell bad output paths from failing disks).
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct RefusedTarget(String);

/// True when `e` is an I/O error carrying a [`RefusedTarget`].
pub fn is_refused_target(e: &Error) -> bool {
    e.get_ref().is_some_and(|inner| inner.is::<RefusedTarget>())
}

/// What a non-regular file is, for error messages.
fn kind_of(meta: &std::fs::Metadata) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        let t = meta.file_type();
        if t.is_fifo() {
            return "a FIFO";
        }
        if t.is_char_device() {
            return "a character device";
        }
        if t.is_block_device() {
            return "a block device";
        }
        if t.is_socket() {
            return "a socket";
        }
    }
    if meta.is_dir() {
        "a directory"
    } else {
        "not a regular file"
    }
}

/// The file an atomic write of `path` must replace: `path` itself, or, when it is a symbolic
/// link (a chain of them), the file the link names, so the link survives and its target gets
/// the new content. A target that exists and is not a regular file is refused: renaming over
/// a device node, FIFO or socket would destroy it, and writing into one is not a file write.
pub fn write_target(path: &Path) -> std::io::Result<PathBuf> {
    let mut current = path.to_path_buf();
    for _ in 0..MAX_LINK_HOPS {
        let meta = match std::fs::symlink_metadata(&current) {
            Ok(m) => m,
            Err(e) if e.kind() == ErrorKind::NotFound => return Ok(current),
            Err(e) => return Err(e),
        };
        if meta.file_type().is_symlink() {
            let link = std::fs::read_link(&current)?;
            current = match current.parent() {
                Some(dir) if link.is_relative() => dir.join(link),
                _ => link,
            };
            continue;
        }
        if meta.is_file() {
            return Ok(current);
        }
        let via = if current == path {
            String::new()
        } else {
            format!(" (the link's target {})", current.display())
        };
        return Err(refused(format!(
            "is {}{via}, not a regular file; refusing to replace it (write to a file)",
            kind_of(&meta)
        )));
    }
    Err(refused(format!(
        "more than {MAX_LINK_HOPS} symbolic links to follow"
    )))
}

/// The error of a write through a dangling link to `target`, whose folder does not
/// exist (it is not created: that would make folders wherever the link points).
pub fn refused_link_folder(target: &Path) -> Error {
    refused(format!(
        "is a symbolic link to {}, whose folder does not exist; refusing to create folders \
         where a link points (create the folder, or write to another path)",
        target.display()
    ))
}

/// Refuses symbolic links among the derived files `names` of the results folder `dir`, and
/// inside its `plots/` folder when that is among `names`: a results folder may come from
/// anyone, and a link there (`stats.json` to a file in the home folder, `plots/` to another
/// folder) would make `stats`, `plot`, `report` or `run` write outside it. The user did not
/// name those paths, so they are not written through (unlike an `--out` file).
pub fn refuse_links_in(dir: &Path, names: &[&str]) -> std::io::Result<()> {
    let link = |path: &Path| -> std::io::Result<()> {
        match std::fs::symlink_metadata(path) {
            Ok(m) if m.file_type().is_symlink() => {
                let to = std::fs::read_link(path).unwrap_or_default();
                Err(Error::new(
                    ErrorKind::InvalidInput,
                    RefusedTarget(format!(
                        "{}: is a symbolic link (to {}); the files derived in a results folder \
                         are never written through links, which could point outside it: \
                         remove the link",
                        path.display(),
                        to.display()
                    )),
                ))
            }
            _ => Ok(()),
        }
    };
    for name in names {
        let path = dir.join(name);
        link(&path)?;
        if path.is_dir()
            && let Ok(entries) = std::fs::read_dir(&path)
        {
            for entry in entries.flatten() {
                link(&entry.path())?;
            }
        }
    }
    Ok(())
}

fn refused(message: String) -> Error {
    Error::new(ErrorKind::InvalidInput, RefusedTarget(message))
}

/// True when process `pid` is alive on a system with `/proc`; without `/proc` every process
/// counts as alive, so nothing is removed on a guess.
fn process_alive(pid: u32) -> bool {
    let proc = Path::new("/proc");
    !proc.join("self").exists() || proc.join(pid.to_string()).exists()
}

/// Removes `.NAME.tmp-PID` files beside `path` whose writer `PID` is no longer running (a
/// writer killed between creating its temporary and renaming it). Failures are ignored: the
/// cleanup is a courtesy, the write itself does not depend on it.
pub fn remove_stale_temporaries(path: &Path) {
    let Some(name) = path.file_name().map(|n| n.to_string_lossy().into_owned()) else {
        return;
    };
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let prefix = format!(".{name}.tmp-");
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let file_name = entry.file_name();
        let Some(pid) = file_name
            .to_str()
            .and_then(|n| n.strip_prefix(&prefix))
            .and_then(|p| p.parse::<u32>().ok())
        else {
            continue;
        };
        let regular = entry.file_type().is_ok_and(|t| t.is_file());
        if regular && pid != std::process::id() && !process_alive(pid) {
            let _ = std::fs::remove_file(entry.path());
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_missing_file_and_a_regular_file_are_their_own_target() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("x.csv");
        assert_eq!(write_target(&p).unwrap(), p);
        std::fs::write(&p, "a").unwrap();
        assert_eq!(write_target(&p).unwrap(), p);
    }

    #[cfg(unix)]
    #[test]
    fn a_chain_of_relative_links_resolves_to_the_file_it_names() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::create_dir(dir.path().join("sub")).unwrap();
        std::os::unix::fs::symlink("sub/real.csv", dir.path().join("a")).unwrap();
        std::os::unix::fs::symlink("a", dir.path().join("b")).unwrap();
        let got = write_target(&dir.path().join("b")).unwrap();
        assert_eq!(got, dir.path().join("sub/real.csv"));
    }

    #[test]
    fn a_directory_is_refused_by_kind() {
        let dir = tempfile::tempdir().unwrap();
        let err = write_target(dir.path()).unwrap_err();
        assert!(is_refused_target(&err));
        assert!(err.to_string().starts_with("is a directory"), "{err}");
    }

    #[test]
    fn only_temporaries_of_dead_writers_are_removed() {
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("stats.csv");
        // PID 0 never names a user process; our own PID is alive.
        let dead = dir.path().join(".stats.csv.tmp-0");
        let mine = dir
            .path()
            .join(format!(".stats.csv.tmp-{}", std::process::id()));
        let other = dir.path().join(".other.csv.tmp-0");
        for p in [&dead, &mine, &other] {
            std::fs::write(p, "x").unwrap();
        }
        remove_stale_temporaries(&target);
        assert_eq!(dead.exists(), !Path::new("/proc/self").exists());
        assert!(mine.exists());
        assert!(other.exists());
    }
}
