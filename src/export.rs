//! Rendering exports: the SVG's fonts, and the SVG drawn as a PNG. Kept apart from the pure
//! scene; the files are written by [`crate::atomic_write`].

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
}
