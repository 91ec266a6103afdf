//! SVG export of a [`Scene`]: a standalone document with one `<g id="layer-name">` per layer,
//! a title, a legend and a scale bar in the run's units.
//!
//! The writer does the world → screen transform itself (world y up becomes image y down), so
//! stroke widths, dashes, markers and texts are in screen pixels whatever the zoom, and the
//! output needs nothing beyond basic SVG 1.1 (it renders identically in browsers and resvg).

use super::marker::MarkerShape;
use super::primitive::{Primitive, Shape, TextAlign};
use super::query::ViewRect;
use super::style::{Glyph, Rgba, Style};
use super::{format_length, Layer, LayerSet, Scene};
use crate::geometry::{unit, Point};
use crate::units::Units;
use std::fmt::Write;

/// Background of the document (and halo colour behind texts).
pub const BACKGROUND: Rgba = Rgba::rgb(0xff, 0xff, 0xff);
/// Colour of the title, legend texts and scale bar.
pub const INK: Rgba = Rgba::rgb(0x33, 0x33, 0x33);

const TITLE_BAND_PX: f64 = 30.0;
const BOTTOM_BAND_PX: f64 = 30.0;
const MARGIN_PX: f64 = 8.0;
const LEGEND_WIDTH_PX: f64 = 240.0;
const LEGEND_ROW_PX: f64 = 17.0;
const FONT: &str = "DejaVu Sans, Verdana, Arial, sans-serif";

/// The bounds of the scene's content grown by 5 % on every side: a good default view. Beams
/// and discarded readings are left out when anything else is drawn (a reading at maximum
/// range would dwarf the map); a unit square around the origin for an empty scene.
pub fn default_view(scene: &Scene) -> ViewRect {
    let content = LayerSet::all()
        .with(Layer::Beams, false)
        .with(Layer::Discarded, false);
    match scene.bounds_of(content).or_else(|| scene.bounds()) {
        Some(b) => {
            let margin_m = 0.05 * b.width_m().max(b.height_m()).max(1e-3);
            b.expanded(margin_m)
        }
        None => ViewRect::new(Point::new(-0.5, -0.5), Point::new(0.5, 0.5)),
    }
}

/// Where the map goes on the page and how world points map to pixels.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PageTransform {
    /// Pixels per world metre.
    pub scale_px_per_m: f64,
    /// Pixel position of the view's upper-left corner (`view.min.x`, `view.max.y`).
    pub origin_px: (f64, f64),
    /// The world rectangle shown.
    pub view: ViewRect,
}

/// World metres per page pixel of `view` on a `size_px` page, with room kept for a legend:
/// the scale a figure's scene is built at, so its labels are decluttered for the page (the
/// legend's room makes it an upper bound: without a legend the map is drawn larger).
pub fn page_world_per_px(view: ViewRect, size_px: (u32, u32)) -> f64 {
    let (area, _) = map_area(size_px, true);
    1.0 / PageTransform::fit(view, area).scale_px_per_m
}

/// The page's map area `(x, y, width, height)` in pixels and the legend's width: the page
/// less the title band, the scale bar's band, the margins and the legend when there is one
/// (and room for it).
fn map_area(size_px: (u32, u32), has_legend: bool) -> ((f64, f64, f64, f64), f64) {
    let (w, h) = (f64::from(size_px.0.max(1)), f64::from(size_px.1.max(1)));
    let legend_w = if !has_legend || w < 2.5 * LEGEND_WIDTH_PX {
        0.0
    } else {
        LEGEND_WIDTH_PX
    };
    let area = (
        MARGIN_PX,
        TITLE_BAND_PX,
        (w - 2.0 * MARGIN_PX - legend_w).max(1.0),
        (h - TITLE_BAND_PX - BOTTOM_BAND_PX).max(1.0),
    );
    (area, legend_w)
}

/// `title` shortened to fit `width_px` at `size_px` (bold): the middle is cut, so the run's
/// name starts it and the snapshot ends it.
pub fn fit_title(title: &str, width_px: f64, size_px: f64) -> String {
    // DejaVu Sans Bold advances at most about 0.7 em for the characters of titles.
    let fits = ((width_px / (0.7 * size_px)).floor() as usize).max(8);
    let chars: Vec<char> = title.chars().collect();
    if chars.len() <= fits {
        return title.to_owned();
    }
    let tail = (fits - 1) / 2;
    let head = fits - 1 - tail;
    let mut out: String = chars[..head].iter().collect();
    out.push('…');
    out.extend(&chars[chars.len() - tail..]);
    out
}

/// The transform [`to_svg`] uses for `scene` shown in `view` on a `size_px` page
/// (the legend's room depends on the scene, hence the argument).
pub fn page_transform(scene: &Scene, view: ViewRect, size_px: (u32, u32)) -> PageTransform {
    page(scene, view, size_px).0
}

fn page(scene: &Scene, view: ViewRect, size_px: (u32, u32)) -> (PageTransform, f64, (f64, f64)) {
    let has_legend = scene
        .primitives
        .iter()
        .any(|p| p.role.legend_label().is_some());
    let (area, legend_w) = map_area(size_px, has_legend);
    let (w, h) = (f64::from(size_px.0.max(1)), f64::from(size_px.1.max(1)));
    (PageTransform::fit(view, area), legend_w, (w, h))
}

impl PageTransform {
    fn fit(view: ViewRect, area: (f64, f64, f64, f64)) -> Self {
        let (x, y, w, h) = area;
        let vw = view.width_m().max(1e-9);
        let vh = view.height_m().max(1e-9);
        let scale = (w / vw).min(h / vh).max(1e-9);
        let origin_px = (x + 0.5 * (w - vw * scale), y + 0.5 * (h - vh * scale));
        PageTransform {
            scale_px_per_m: scale,
            origin_px,
            view,
        }
    }

    /// World point → pixel (y flipped: larger world y is higher on the page).
    pub fn px(&self, p: &Point) -> (f64, f64) {
        (
            self.origin_px.0 + (p.x - self.view.min.x) * self.scale_px_per_m,
            self.origin_px.1 + (self.view.max.y - p.y) * self.scale_px_per_m,
        )
    }

    fn view_rect_px(&self) -> (f64, f64, f64, f64) {
        let s = self.scale_px_per_m;
        (
            self.origin_px.0,
            self.origin_px.1,
            self.view.width_m() * s,
            self.view.height_m() * s,
        )
    }
}

/// Writes `scene` as a standalone SVG of `size_px` (width, height) pixels showing the world
/// rectangle `view` (aspect ratio kept, centred, clipped to it), with `title` on top, the
/// legend on the right and a scale bar in `units` at the bottom.
pub fn to_svg(
    scene: &Scene,
    view: ViewRect,
    size_px: (u32, u32),
    title: &str,
    units: Units,
) -> String {
    let (tf, legend_w, (w, h)) = page(scene, view, size_px);
    let mut s = String::with_capacity(256 + 160 * scene.primitives.len());
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" version="1.1" width="{w}" height="{h}" viewBox="0 0 {w} {h}" font-family="{FONT}">"#
    );
    let _ = writeln!(s, "<title>{}</title>", escape(title));
    let _ = writeln!(
        s,
        r#"<rect id="background" x="0" y="0" width="{w}" height="{h}" fill="{}"/>"#,
        BACKGROUND.hex()
    );
    let (cx, cy, cw, ch) = tf.view_rect_px();
    let _ = writeln!(
        s,
        r#"<defs><clipPath id="view-clip"><rect x="{cx:.2}" y="{cy:.2}" width="{cw:.2}" height="{ch:.2}"/></clipPath></defs>"#
    );
    s.push_str("<g id=\"scene\" clip-path=\"url(#view-clip)\">\n");
    let mut current: Option<Layer> = None;
    for prim in &scene.primitives {
        if current != Some(prim.layer) {
            if current.is_some() {
                s.push_str("</g>\n");
            }
            let _ = writeln!(s, r#"<g id="{}">"#, prim.layer.name());
            current = Some(prim.layer);
        }
        primitive(&mut s, &tf, prim);
    }
    if current.is_some() {
        s.push_str("</g>\n");
    }
    s.push_str("</g>\n");
    let _ = writeln!(
        s,
        r#"<rect id="frame" x="{cx:.2}" y="{cy:.2}" width="{cw:.2}" height="{ch:.2}" fill="none" stroke="{}" stroke-opacity="0.3" stroke-width="1"/>"#,
        INK.hex()
    );
    let _ = writeln!(
        s,
        r#"<text id="title" x="{MARGIN_PX}" y="20" font-size="14" font-weight="bold" fill="{}">{}</text>"#,
        INK.hex(),
        escape(&fit_title(title, w - 2.0 * MARGIN_PX, 14.0))
    );
    scale_bar(&mut s, &tf, units, (cx, cy + ch));
    if legend_w > 0.0 {
        legend_panel(
            &mut s,
            scene,
            (w - legend_w, TITLE_BAND_PX),
            h - TITLE_BAND_PX - MARGIN_PX,
        );
    }
    s.push_str("</svg>\n");
    s
}

/// Escapes the five XML special characters (and drops characters XML 1.0 forbids).
pub fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            c if (c as u32) < 0x20 && !matches!(c, '\t' | '\n' | '\r') => {}
            c => out.push(c),
        }
    }
    out
}

fn opacity(c: Rgba, style: &Style) -> f32 {
    f32::from(c.a) / 255.0 * style.opacity.clamp(0.0, 1.0)
}

/// Stroke and fill attributes; `area` says whether the shape has an inside to fill.
fn paint(s: &mut String, style: &Style, area: bool) {
    match style.stroke {
        Some(c) if style.stroke_width_px > 0.0 => {
            let _ = write!(
                s,
                r#" stroke="{}" stroke-opacity="{:.3}" stroke-width="{}""#,
                c.hex(),
                opacity(c, style),
                style.stroke_width_px
            );
            if style.dash_px.is_empty() {
                s.push_str(r#" stroke-linecap="round" stroke-linejoin="round""#);
            } else {
                s.push_str(r#" stroke-dasharray=""#);
                for (i, d) in style.dash_px.iter().enumerate() {
                    let _ = write!(s, "{}{}", if i > 0 { "," } else { "" }, d);
                }
                s.push('"');
            }
        }
        _ => s.push_str(r#" stroke="none""#),
    }
    match style.fill {
        Some(c) if area => {
            let _ = write!(
                s,
                r#" fill="{}" fill-opacity="{:.3}""#,
                c.hex(),
                opacity(c, style)
            );
        }
        _ => s.push_str(r#" fill="none""#),
    }
}

fn primitive(s: &mut String, tf: &PageTransform, prim: &Primitive) {
    let style = &prim.style;
    match &prim.shape {
        Shape::Circle { centre, radius_m } => {
            let (x, y) = tf.px(centre);
            let _ = write!(
                s,
                r#"<circle cx="{x:.2}" cy="{y:.2}" r="{:.2}""#,
                radius_m * tf.scale_px_per_m
            );
            paint(s, style, true);
            s.push_str("/>\n");
        }
        Shape::Segment { a, b } => {
            let ((x1, y1), (x2, y2)) = (tf.px(a), tf.px(b));
            let _ = write!(
                s,
                r#"<line x1="{x1:.2}" y1="{y1:.2}" x2="{x2:.2}" y2="{y2:.2}""#
            );
            paint(s, style, false);
            s.push_str("/>\n");
        }
        Shape::Polyline { points, closed } => {
            s.push_str(if *closed {
                "<polygon points=\""
            } else {
                "<polyline points=\""
            });
            for (i, p) in points.iter().enumerate() {
                let (x, y) = tf.px(p);
                let _ = write!(s, "{}{x:.2},{y:.2}", if i > 0 { " " } else { "" });
            }
            s.push('"');
            paint(s, style, *closed);
            s.push_str("/>\n");
        }
        Shape::Wedge {
            apex,
            heading_rad,
            half_angle_rad,
            radius_m,
        } => {
            let (ax, ay) = tf.px(apex);
            let (x1, y1) = tf.px(&(apex + unit(heading_rad - half_angle_rad) * *radius_m));
            let (x2, y2) = tf.px(&(apex + unit(heading_rad + half_angle_rad) * *radius_m));
            let r = radius_m * tf.scale_px_per_m;
            let large = u8::from(2.0 * half_angle_rad > std::f64::consts::PI);
            // Counter-clockwise in the world is counter-clockwise on the page too, which is
            // SVG's negative-angle direction: sweep-flag 0.
            let _ = write!(
                s,
                r#"<path d="M{ax:.2},{ay:.2} L{x1:.2},{y1:.2} A{r:.2},{r:.2} 0 {large} 0 {x2:.2},{y2:.2} Z""#
            );
            paint(s, style, true);
            s.push_str("/>\n");
        }
        Shape::Text {
            anchor,
            text,
            offset_px,
            align,
        } => {
            let (x, y) = tf.px(anchor);
            let fill = style.fill.or(style.stroke).unwrap_or(INK);
            text_element(
                s,
                (x + f64::from(offset_px[0]), y - f64::from(offset_px[1])),
                text,
                style.marker_size_px,
                fill,
                *align,
            );
        }
        Shape::Marker { at, shape } => {
            let (x, y) = tf.px(at);
            marker(s, (x, y), *shape, style);
        }
    }
}

fn text_element(
    s: &mut String,
    (x, y): (f64, f64),
    text: &str,
    size_px: f32,
    fill: Rgba,
    align: TextAlign,
) {
    let anchor = match align {
        TextAlign::Start => "start",
        TextAlign::Middle => "middle",
        TextAlign::End => "end",
    };
    let _ = writeln!(
        s,
        r#"<text x="{x:.2}" y="{y:.2}" font-size="{size_px}" text-anchor="{anchor}" fill="{}" stroke="{}" stroke-width="3" stroke-linejoin="round" paint-order="stroke">{}</text>"#,
        fill.hex(),
        BACKGROUND.hex(),
        escape(text)
    );
}

fn marker(s: &mut String, (x, y): (f64, f64), shape: MarkerShape, style: &Style) {
    let h = 0.5 * f64::from(style.marker_size_px.max(1.0));
    // Glyphs are drawn solid; closed glyphs without a fill colour stay hollow.
    let mut st = *style;
    st.dash_px = &[];
    match shape {
        MarkerShape::Dot | MarkerShape::Ring => {
            let _ = write!(s, r#"<circle cx="{x:.2}" cy="{y:.2}" r="{h:.2}""#);
        }
        MarkerShape::Square => {
            let _ = write!(
                s,
                r#"<rect x="{:.2}" y="{:.2}" width="{:.2}" height="{:.2}""#,
                x - h,
                y - h,
                2.0 * h,
                2.0 * h
            );
        }
        MarkerShape::Cross => {
            let _ = write!(
                s,
                r#"<path d="M{:.2},{:.2} L{:.2},{:.2} M{:.2},{:.2} L{:.2},{:.2}""#,
                x - h,
                y - h,
                x + h,
                y + h,
                x - h,
                y + h,
                x + h,
                y - h
            );
        }
        MarkerShape::Plus => {
            let _ = write!(
                s,
                r#"<path d="M{:.2},{y:.2} L{:.2},{y:.2} M{x:.2},{:.2} L{x:.2},{:.2}""#,
                x - h,
                x + h,
                y - h,
                y + h
            );
        }
        MarkerShape::Triangle => {
            let _ = write!(
                s,
                r#"<path d="M{x:.2},{:.2} L{:.2},{:.2} L{:.2},{:.2} Z""#,
                y - h,
                x + h,
                y + 0.8 * h,
                x - h,
                y + 0.8 * h
            );
        }
        MarkerShape::Diamond => {
            let _ = write!(
                s,
                r#"<path d="M{x:.2},{:.2} L{:.2},{y:.2} L{x:.2},{:.2} L{:.2},{y:.2} Z""#,
                y - h,
                x + h,
                y + h,
                x - h
            );
        }
    }
    paint(s, &st, !shape.is_open());
    s.push_str("/>\n");
}

/// A round length (1, 2 or 5 times a power of ten, in `units`) about `target_m` long, in metres.
pub fn round_length_m(target_m: f64, units: Units) -> f64 {
    let target = units.from_m(target_m.max(1e-12));
    let power = 10f64.powf(target.log10().floor());
    let nice = [5.0, 2.0, 1.0]
        .into_iter()
        .map(|k| k * power)
        .find(|&v| v <= target)
        .unwrap_or(power);
    units.to_m(nice)
}

fn scale_bar(s: &mut String, tf: &PageTransform, units: Units, (left_px, bottom_px): (f64, f64)) {
    let (_, _, cw, _) = tf.view_rect_px();
    let length_m = round_length_m(0.2 * cw / tf.scale_px_per_m, units);
    let len_px = length_m * tf.scale_px_per_m;
    let (x0, y) = (left_px, bottom_px + 16.0);
    let x1 = x0 + len_px;
    let ink = INK.hex();
    let _ = writeln!(
        s,
        r#"<g id="scale-bar"><path d="M{x0:.2},{:.2} L{x0:.2},{y:.2} L{x1:.2},{y:.2} L{x1:.2},{:.2}" fill="none" stroke="{ink}" stroke-width="1.5"/><text x="{:.2}" y="{:.2}" font-size="11" fill="{ink}">{}</text></g>"#,
        y - 5.0,
        y - 5.0,
        x1 + 6.0,
        y + 4.0,
        escape(&format_length(length_m, units))
    );
}

fn legend_panel(s: &mut String, scene: &Scene, (x0, y0): (f64, f64), height_px: f64) {
    let entries = scene.legend();
    let rows_fit = ((height_px - 8.0) / LEGEND_ROW_PX).floor().max(0.0) as usize;
    let shown = entries.len().min(rows_fit);
    let box_h = shown as f64 * LEGEND_ROW_PX + 8.0;
    let _ = writeln!(
        s,
        r#"<g id="legend"><rect x="{:.2}" y="{y0:.2}" width="{:.2}" height="{box_h:.2}" fill="{}" stroke="{}" stroke-opacity="0.3"/>"#,
        x0,
        LEGEND_WIDTH_PX - MARGIN_PX,
        BACKGROUND.hex(),
        INK.hex()
    );
    for (i, e) in entries.iter().take(shown).enumerate() {
        let y = y0 + 4.0 + LEGEND_ROW_PX * (i as f64 + 0.5);
        let (gx0, gx1) = (x0 + 8.0, x0 + 36.0);
        let mut st = e.style;
        st.stroke_width_px = st.stroke_width_px.min(6.0);
        match e.glyph {
            Glyph::Line | Glyph::LineWithMarker(_) => {
                let _ = write!(
                    s,
                    r#"<line x1="{gx0:.2}" y1="{y:.2}" x2="{gx1:.2}" y2="{y:.2}""#
                );
                paint(s, &st, false);
                s.push_str("/>\n");
                if let Glyph::LineWithMarker(m) = e.glyph {
                    marker(s, (0.5 * (gx0 + gx1), y), m, &e.style);
                }
            }
            Glyph::Marker(m) => marker(s, (0.5 * (gx0 + gx1), y), m, &e.style),
            Glyph::Area => {
                if st.fill.is_none() {
                    st.fill = st.stroke;
                    st.stroke = None;
                }
                let _ = write!(
                    s,
                    r#"<rect x="{gx0:.2}" y="{:.2}" width="{:.2}" height="10""#,
                    y - 5.0,
                    gx1 - gx0
                );
                paint(s, &st, true);
                s.push_str("/>\n");
            }
            Glyph::None => {}
        }
        text_element(
            s,
            (gx1 + 8.0, y + 4.0),
            e.label,
            11.0,
            INK,
            TextAlign::Start,
        );
    }
    if shown < entries.len() {
        let y = y0 + box_h + 12.0;
        text_element(
            s,
            (x0 + 8.0, y),
            &format!("… {} more", entries.len() - shown),
            11.0,
            INK,
            TextAlign::Start,
        );
    }
    s.push_str("</g>\n");
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn escapes_markup() {
        assert_eq!(
            escape(r#"a<b & "c" 'd'>"#),
            "a&lt;b &amp; &quot;c&quot; &apos;d&apos;&gt;"
        );
        assert_eq!(escape("x\u{1}y"), "xy");
    }

    #[test]
    fn round_lengths_are_one_two_five() {
        let r = |m: f64| Units::Inches.from_m(round_length_m(Units::Inches.to_m(m), Units::Inches));
        assert!((r(61.0) - 50.0).abs() < 1e-9);
        assert!((r(19.9) - 10.0).abs() < 1e-9);
        assert!((r(20.0) - 20.0).abs() < 1e-9);
        assert!((Units::Metres.from_m(round_length_m(0.3, Units::Metres)) - 0.2).abs() < 1e-12);
    }

    #[test]
    fn y_axis_points_up() {
        let view = ViewRect::new(Point::new(0.0, 0.0), Point::new(10.0, 10.0));
        let tf = PageTransform::fit(view, (0.0, 0.0, 100.0, 100.0));
        assert!(tf.px(&Point::new(0.0, 9.0)).1 < tf.px(&Point::new(0.0, 1.0)).1);
        assert_eq!(tf.px(&Point::new(0.0, 10.0)), (0.0, 0.0));
    }
}
