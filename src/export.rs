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

/// usvg's options for the exported SVGs: the system's fonts, and egui's own font (Ubuntu
/// Light, built into the program) as the sans-serif that the SVG's font list ends with, so
/// texts are laid out and drawn even on a machine without any font installed.
pub fn svg_options() -> usvg::Options<'static> {
    let mut options = usvg::Options::default();
    options.fontdb_mut().load_system_fonts();
    add_built_in_fonts(&mut options);
    options
}

/// egui's fonts into `options`, Ubuntu Light as the sans-serif.
fn add_built_in_fonts(options: &mut usvg::Options<'static>) {
    let fonts = options.fontdb_mut();
    for data in egui::FontDefinitions::default().font_data.values() {
        fonts.load_font_data((*data.font).as_ref().to_vec());
    }
    fonts.set_sans_serif_family("Ubuntu");
}

/// Renders an SVG document as a PNG image `width_px` wide (the height keeps the document's
/// aspect), with [`svg_options`]' fonts for its texts.
pub fn svg_to_png(svg: &str, width_px: u32) -> Result<Vec<u8>, String> {
    let options = svg_options();
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
    fn without_system_fonts_texts_are_laid_out_in_the_built_in_font() {
        let mut options = usvg::Options::default();
        add_built_in_fonts(&mut options);
        let svg = r#"<svg xmlns="http://www.w3.org/2000/svg" width="200" height="50" font-family="DejaVu Sans, Verdana, Arial, sans-serif"><text id="t" x="10" y="30" font-size="12">s123</text></svg>"#;
        let tree = usvg::Tree::from_str(svg, &options).unwrap();
        let Some(usvg::Node::Text(t)) = tree.node_by_id("t") else {
            panic!("the text was dropped");
        };
        let b = t.abs_bounding_box();
        assert!(b.width() > 10.0 && b.width() < 60.0, "{b:?}");
    }

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
