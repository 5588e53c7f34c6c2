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
/// systems have it), any sans-serif otherwise; runs of polylines drawn alike merged into one
/// path ([`merge_polylines`]).
pub fn with_font_family(text: String) -> String {
    merge_polylines(&text).replace(
        "font-family=\"sans-serif\"",
        "font-family=\"DejaVu Sans, sans-serif\"",
    )
}

/// plotters draws a dashed line as one `<polyline>` per dash and a grid as one `<line>` per
/// grid line: consecutive such elements with the same attributes (one per line of the text, as
/// plotters writes them) become one `<path>` with a subpath each. The picture is the same; the
/// file is several times smaller.
pub fn merge_polylines(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    // The attributes of the run being merged and its path data.
    let mut run: Option<(&str, String)> = None;
    let flush = |out: &mut String, run: &mut Option<(&str, String)>| {
        if let Some((attrs, d)) = run.take() {
            let fill = if attrs.contains("fill=") {
                ""
            } else {
                "fill=\"none\" "
            };
            out.push_str(&format!("<path {fill}{attrs} d=\"{}\"/>\n", d.trim_end()));
        }
    };
    for line in text.split_inclusive('\n') {
        let Some((attrs, points)) = segment(line.trim_end()) else {
            flush(&mut out, &mut run);
            out.push_str(line);
            continue;
        };
        if run.as_ref().is_some_and(|(a, _)| *a != attrs) {
            flush(&mut out, &mut run);
        }
        let d = &mut run.get_or_insert_with(|| (attrs, String::new())).1;
        for (k, p) in points.iter().enumerate() {
            d.push(if k == 0 { 'M' } else { 'L' });
            d.push_str(p);
            d.push(' ');
        }
    }
    flush(&mut out, &mut run);
    out
}

/// A `<polyline ... points="x,y x,y"/>` or `<line ... x1=".." y1=".." x2=".." y2=".."/>` as
/// (its other attributes, its points as `x,y`).
fn segment(line: &str) -> Option<(&str, Vec<String>)> {
    if let Some(rest) = line.strip_prefix("<polyline ") {
        let (attrs, points) = rest.strip_suffix("\"/>")?.split_once(" points=\"")?;
        return Some((attrs, points.split_whitespace().map(String::from).collect()));
    }
    let rest = line.strip_prefix("<line ")?.strip_suffix("\"/>")?;
    let (attrs, coords) = rest.split_once(" x1=\"")?;
    let (x1, rest) = coords.split_once("\" y1=\"")?;
    let (y1, rest) = rest.split_once("\" x2=\"")?;
    let (x2, y2) = rest.split_once("\" y2=\"")?;
    Some((attrs, vec![format!("{x1},{y1}"), format!("{x2},{y2}")]))
}

/// Writes `bytes` to `path` atomically: a temporary file in the same directory, fsync, then
/// rename. Parent directories of `path` are created.
///
/// A symbolic link is written through: its target gets the new content (atomically, beside the
/// target) and the link stays; a link whose target's folder does not exist is refused, never
/// creating folders where it points. A path that is (or links to) a device, FIFO, socket or
/// directory is refused with [`std::io::ErrorKind::InvalidInput`] and left untouched.
/// Temporaries of the same name left by killed writers are removed first (see
/// [`crate::target::remove_stale_temporaries`]).
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let given = path;
    let path = &crate::target::write_target(path)?;
    let dir = path.parent().filter(|p| !p.as_os_str().is_empty());
    if let Some(d) = dir {
        if path != given && !d.is_dir() {
            // A dangling link: its target's folder is not created (that would make folders
            // wherever the link points).
            return Err(crate::target::refused_link_folder(path));
        }
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
    fn a_dangling_link_creates_no_folders_where_it_points() {
        let dir = tempfile::tempdir().unwrap();
        let link = dir.path().join("link.csv");
        std::os::unix::fs::symlink("far/away/x.csv", &link).unwrap();
        let err = write_atomic(&link, b"new").unwrap_err();
        assert!(crate::target::is_refused_target(&err), "{err}");
        assert!(!dir.path().join("far").exists());
        // With the folder there, the link is written through as any other.
        std::fs::create_dir_all(dir.path().join("far/away")).unwrap();
        write_atomic(&link, b"new").unwrap();
        assert_eq!(
            std::fs::read(dir.path().join("far/away/x.csv")).unwrap(),
            b"new"
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

#[cfg(test)]
mod merge_tests {
    #[test]
    fn runs_of_alike_polylines_become_one_path() {
        let svg = "<svg>\n<polyline fill=\"none\" stroke=\"#000\" points=\"1,2 3,4 \"/>\n\
                   <polyline fill=\"none\" stroke=\"#000\" points=\"5,6 7,8 \"/>\n\
                   <polyline fill=\"none\" stroke=\"#fff\" points=\"0,0 1,1 \"/>\n\
                   <line stroke=\"#eee\" x1=\"1\" y1=\"2\" x2=\"1\" y2=\"9\"/>\n\
                   <line stroke=\"#eee\" x1=\"3\" y1=\"2\" x2=\"3\" y2=\"9\"/>\n</svg>\n";
        assert_eq!(
            super::merge_polylines(svg),
            "<svg>\n<path fill=\"none\" stroke=\"#000\" d=\"M1,2 L3,4 M5,6 L7,8\"/>\n\
             <path fill=\"none\" stroke=\"#fff\" d=\"M0,0 L1,1\"/>\n\
             <path fill=\"none\" stroke=\"#eee\" d=\"M1,2 L1,9 M3,2 L3,9\"/>\n</svg>\n"
        );
    }
}
