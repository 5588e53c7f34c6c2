//! Writing output files so that a reader never sees half a file: plain bytes, and figures as
//! PNG or SVG, with the font they are drawn in ([`register_fonts`]) and the error of a figure's
//! file ([`PlotError`]).

use std::fs::File;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Once;

use image::codecs::png::PngEncoder;
use image::{ColorType, ImageEncoder};
use plotters::coord::Shift;
use plotters::prelude::*;

/// Plot errors.
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    /// Drawing failed.
    #[error("{path}: drawing failed: {message}")]
    Draw {
        /// Output file.
        path: PathBuf,
        /// plotters' message.
        message: String,
    },
    /// Writing failed.
    #[error("{path}: {source}")]
    Io {
        /// Output file.
        path: PathBuf,
        /// The error.
        source: std::io::Error,
    },
}

/// Registers DejaVu Sans as plotters' "sans-serif" (no system fonts needed). Idempotent.
pub fn register_fonts() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        // The bytes are a valid TTF shipped by the dejavu crate; a failure would leave text
        // undrawable and every plot reports it.
        let _ = plotters::style::register_font(
            "sans-serif",
            FontStyle::Normal,
            dejavu::sans::regular(),
        );
        let _ = plotters::style::register_font("sans-serif", FontStyle::Bold, dejavu::sans::bold());
    });
}

/// Something that draws itself on any plotters backend (a chart, a polar figure).
pub trait Figure {
    /// Draws the whole figure on `root`; the error is plotters' message.
    fn draw_on<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String>;
}

/// Writes `figure` at `size` pixels to the PNG file `path`, atomically.
///
/// The figure is drawn and encoded in memory and written by [`write_atomic`], so a failed write
/// (a full disk) reports the operating system's error and leaves no partial file.
pub fn write_png(figure: &impl Figure, size: (u32, u32), path: &Path) -> Result<(), PlotError> {
    register_fonts();
    let draw_err = |message: String| PlotError::Draw {
        path: path.to_path_buf(),
        message,
    };
    let (width, height) = size;
    let mut rgb = vec![0u8; width as usize * height as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, size).into_drawing_area();
        figure.draw_on(&root).map_err(draw_err)?;
        root.present().map_err(|e| draw_err(e.to_string()))?;
    }
    let png = encode_png(&rgb, width, height).map_err(draw_err)?;
    write_atomic(path, &png).map_err(|source| PlotError::Io {
        path: path.to_path_buf(),
        source,
    })
}

/// The PNG file's bytes of an 8-bit RGB image (`width * height * 3` bytes, row-major).
pub fn encode_png(rgb: &[u8], width: u32, height: u32) -> Result<Vec<u8>, String> {
    let mut png = Vec::new();
    PngEncoder::new(&mut png)
        .write_image(rgb, width, height, ColorType::Rgb8)
        .map_err(|e| format!("PNG encoding: {e}"))?;
    Ok(png)
}

/// Writes `figure` at `size` pixels to the SVG file `path`, atomically.
pub fn write_svg(figure: &impl Figure, size: (u32, u32), path: &Path) -> Result<(), PlotError> {
    let text = svg_text(figure, size).map_err(|message| PlotError::Draw {
        path: path.to_path_buf(),
        message,
    })?;
    write_atomic(path, text.as_bytes()).map_err(|source| PlotError::Io {
        path: path.to_path_buf(),
        source,
    })
}

/// The SVG document of `figure` at `size` pixels (for files, or inlined in an HTML page); the
/// error is plotters' message.
pub fn svg_text(figure: &impl Figure, size: (u32, u32)) -> Result<String, String> {
    register_fonts();
    let mut text = String::new();
    {
        let root = SVGBackend::with_string(&mut text, size).into_drawing_area();
        figure.draw_on(&root)?;
        root.present().map_err(|e| e.to_string())?;
    }
    Ok(with_font_family(text))
}

/// SVG text drawn with DejaVu Sans metrics, asking SVG viewers for that face first (most
/// systems have it), any sans-serif otherwise.
pub fn with_font_family(text: String) -> String {
    text.replace(
        "font-family=\"sans-serif\"",
        "font-family=\"DejaVu Sans, sans-serif\"",
    )
}

/// Writes `bytes` to `path` atomically: a temporary file in the same directory, fsync, then
/// rename. Parent directories are created.
///
/// A symbolic link is written through: its target gets the new content (atomically, beside the
/// target) and the link stays. A path that is (or links to) a device, FIFO, socket or
/// directory is refused with [`std::io::ErrorKind::InvalidInput`] and left untouched.
/// Temporaries of the same name left by killed writers are removed first (see
/// [`crate::target::remove_stale_temporaries`]).
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let path = &crate::target::write_target(path)?;
    let dir = path.parent().filter(|p| !p.as_os_str().is_empty());
    if let Some(d) = dir {
        std::fs::create_dir_all(d)?;
    }
    crate::target::remove_stale_temporaries(path);
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "out".into());
    let tmp = path.with_file_name(format!(".{name}.tmp-{}", std::process::id()));
    let written = File::create(&tmp).and_then(|mut f| {
        f.write_all(bytes)?;
        f.sync_all()
    });
    // On any failure (a full disk, most likely) the partial temporary goes too.
    written
        .and_then(|()| std::fs::rename(&tmp, path))
        .inspect_err(|_| {
            let _ = std::fs::remove_file(&tmp);
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn atomic_write_replaces_and_leaves_no_temporary() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("sub/x.json");
        write_atomic(&p, b"one").unwrap();
        write_atomic(&p, b"two").unwrap();
        assert_eq!(std::fs::read(&p).unwrap(), b"two");
        assert_eq!(
            std::fs::read_dir(dir.path().join("sub")).unwrap().count(),
            1
        );
    }

    #[cfg(unix)]
    #[test]
    fn a_symlink_is_written_through_and_kept() {
        let dir = tempfile::tempdir().unwrap();
        let real = dir.path().join("real.csv");
        let link = dir.path().join("link.csv");
        std::fs::write(&real, "old").unwrap();
        std::os::unix::fs::symlink("real.csv", &link).unwrap();
        write_atomic(&link, b"new").unwrap();
        assert!(link.symlink_metadata().unwrap().file_type().is_symlink());
        assert_eq!(std::fs::read(&real).unwrap(), b"new");
    }

    #[cfg(unix)]
    #[test]
    fn a_fifo_is_refused_and_left_in_place() {
        use std::os::unix::fs::FileTypeExt;
        let dir = tempfile::tempdir().unwrap();
        let fifo = dir.path().join("pipe.csv");
        let made = std::process::Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .unwrap();
        assert!(made.success());
        let link = dir.path().join("to-pipe.csv");
        std::os::unix::fs::symlink(&fifo, &link).unwrap();
        for p in [&fifo, &link] {
            let err = write_atomic(p, b"x").unwrap_err();
            assert_eq!(err.kind(), std::io::ErrorKind::InvalidInput);
            assert!(err.to_string().contains("a FIFO"), "{err}");
        }
        assert!(fifo.symlink_metadata().unwrap().file_type().is_fifo());
        assert!(link.symlink_metadata().unwrap().file_type().is_symlink());
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 2);
    }

    struct Blank;

    impl Figure for Blank {
        fn draw_on<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
            root.fill(&WHITE).map_err(|e| e.to_string())
        }
    }

    #[test]
    fn a_png_is_written_whole_and_a_failed_write_leaves_nothing() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("blank.png");
        write_png(&Blank, (30, 20), &p).unwrap();
        let bytes = std::fs::read(&p).unwrap();
        assert_eq!(&bytes[1..4], b"PNG");
        // Width and height in the IHDR chunk, big-endian.
        assert_eq!(bytes[16..24], [0, 0, 0, 30, 0, 0, 0, 20]);

        // A non-empty directory where the file should go: the rename fails.
        let taken = dir.path().join("taken.png");
        std::fs::create_dir_all(taken.join("inside")).unwrap();
        let err = write_png(&Blank, (30, 20), &taken).unwrap_err();
        assert!(matches!(err, PlotError::Io { .. }), "{err}");
        assert!(err.to_string().starts_with(&taken.display().to_string()));
        let left: Vec<_> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(left.len(), 2, "{left:?}");
    }
}
