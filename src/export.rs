//! Writing exports to disk. Kept apart from the pure scene: this is the only file-system code
//! the export path needs.

use std::io::{self, Write};
use std::path::Path;

/// Writes any text file atomically (a temp file beside it, then a rename): parameter sets,
/// bookmarks. The same as [`write_svg_atomically`], named for what it does.
pub fn write_text_atomically(path: &Path, contents: &str) -> io::Result<()> {
    write_svg_atomically(path, contents)
}

/// Writes `contents` to `path` atomically (see [`write_bytes_atomically`]).
pub fn write_svg_atomically(path: &Path, contents: &str) -> io::Result<()> {
    write_bytes_atomically(path, contents.as_bytes())
}

/// Renders an SVG document as a PNG image `width_px` wide (the height keeps the document's
/// aspect), with the system's fonts for its texts.
pub fn svg_to_png(svg: &str, width_px: u32) -> Result<Vec<u8>, String> {
    let mut options = usvg::Options::default();
    options.fontdb_mut().load_system_fonts();
    let tree = usvg::Tree::from_str(svg, &options).map_err(|e| format!("the SVG: {e}"))?;
    let size = tree.size();
    let scale = f64::from(width_px.clamp(16, 16_384)) / f64::from(size.width().max(1.0));
    let (w, h) = (
        (f64::from(size.width()) * scale).round().max(1.0) as u32,
        (f64::from(size.height()) * scale).round().max(1.0) as u32,
    );
    let mut pixmap = resvg::tiny_skia::Pixmap::new(w, h)
        .ok_or_else(|| format!("cannot make a {w}×{h} image"))?;
    resvg::render(
        &tree,
        resvg::tiny_skia::Transform::from_scale(scale as f32, scale as f32),
        &mut pixmap.as_mut(),
    );
    pixmap
        .encode_png()
        .map_err(|e| format!("PNG encoding: {e}"))
}

/// Writes `contents` to `path` atomically: into a temporary file in the same directory, which
/// is then renamed over `path`. A reader never sees a half-written file; on error the
/// temporary file is removed and `path` is left as it was.
pub fn write_bytes_atomically(path: &Path, contents: &[u8]) -> io::Result<()> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let name = path.file_name().ok_or_else(|| {
        io::Error::new(
            io::ErrorKind::InvalidInput,
            format!("{}: not a file path", path.display()),
        )
    })?;
    let tmp = dir.join(format!(
        ".{}.{}.tmp",
        name.to_string_lossy(),
        std::process::id()
    ));
    let result = (|| {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(contents)?;
        f.sync_all()?;
        std::fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn writes_and_replaces_without_leaving_temporaries() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("out.svg");
        write_svg_atomically(&path, "<svg/>").unwrap();
        write_svg_atomically(&path, "<svg></svg>").unwrap();
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "<svg></svg>");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
    }

    #[test]
    fn missing_directory_is_an_error() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("nope").join("out.svg");
        assert!(write_svg_atomically(&path, "x").is_err());
    }
}
