//! The whole [`Scene`] as one egui_plot item: its primitives are painted straight into epaint
//! shapes, skipping those outside the visible plot area. One item instead of one per primitive
//! keeps a frame of a map with tens of thousands of segments within budget (`sonarmap bench`,
//! `frame_ms_median`).

use crate::geometry::Point;
use crate::scene::{MarkerShape, Primitive, Rgba, Scene, Shape as SceneShape, Style, TextAlign};
use egui::epaint::{PathShape, PathStroke, TextShape};
use egui::{Align2, Color32, Pos2, Shape, Stroke, Ui};
use egui_plot::{PlotBounds, PlotGeometry, PlotItem, PlotItemBase, PlotPoint, PlotTransform};
use std::ops::RangeInclusive;

/// Halo colour of selected primitives.
const HALO: Color32 = Color32::from_rgba_premultiplied(150, 150, 150, 150);

/// The scene, or the selected part of it drawn as a halo.
pub struct ScenePlotItem<'a> {
    base: PlotItemBase,
    scene: &'a Scene,
    /// Plot units per metre.
    scale: f64,
    /// Only these primitives (by index), drawn as a selection halo; `None`: all, normally.
    halo_of: Option<Vec<usize>>,
}

impl<'a> ScenePlotItem<'a> {
    /// Every primitive of `scene`; `scale` converts metres to plot units.
    pub fn new(scene: &'a Scene, scale: f64) -> Self {
        Self {
            base: PlotItemBase::new("scene".to_owned()),
            scene,
            scale,
            halo_of: None,
        }
    }

    /// The primitives `indices` of `scene` as a white halo under a selection.
    pub fn halo(scene: &'a Scene, scale: f64, indices: Vec<usize>) -> Self {
        let mut item = Self::new(scene, scale);
        item.base = PlotItemBase::new("selection".to_owned());
        item.halo_of = Some(indices);
        item
    }
}

/// The colour with the style's opacity applied.
pub fn colour(c: Rgba, opacity: f32) -> Color32 {
    let a = (f32::from(c.a) * opacity.clamp(0.0, 1.0)).round() as u8;
    Color32::from_rgba_unmultiplied(c.r, c.g, c.b, a)
}

/// A stroked path in the style's dash pattern (pixels).
fn stroke_path(points: Vec<Pos2>, stroke: Stroke, dash_px: &[f32], out: &mut Vec<Shape>) {
    if points.len() < 2 || stroke.width <= 0.0 || stroke.color == Color32::TRANSPARENT {
        return;
    }
    match dash_px {
        [on, off, ..] if *on <= 2.0 => {
            let spacing = (on + off).max(3.0);
            out.extend(Shape::dotted_line(
                &points,
                stroke.color,
                spacing,
                stroke.width.max(1.0) / 1.5,
            ));
        }
        [on, off, ..] => out.extend(Shape::dashed_line(&points, stroke, *on, *off)),
        _ => out.push(Shape::line(points, stroke)),
    }
}

/// World bounding box of a primitive's shape (text and markers: their anchor).
fn world_box(shape: &SceneShape) -> (Point, Point) {
    let mut min = Point::new(f64::INFINITY, f64::INFINITY);
    let mut max = Point::new(f64::NEG_INFINITY, f64::NEG_INFINITY);
    let mut add = |p: &Point, r: f64| {
        min.x = min.x.min(p.x - r);
        min.y = min.y.min(p.y - r);
        max.x = max.x.max(p.x + r);
        max.y = max.y.max(p.y + r);
    };
    match shape {
        SceneShape::Circle { centre, radius_m } => add(centre, *radius_m),
        SceneShape::Segment { a, b } => {
            add(a, 0.0);
            add(b, 0.0);
        }
        SceneShape::Polyline { points, .. } => points.iter().for_each(|p| add(p, 0.0)),
        SceneShape::Wedge { apex, radius_m, .. } => add(apex, *radius_m),
        SceneShape::Text { anchor, .. } => add(anchor, 0.0),
        SceneShape::Marker { at, .. } => add(at, 0.0),
    }
    (min, max)
}

/// How a primitive's lines and fill are drawn: its style's, or the selection's halo.
#[derive(Clone, Copy)]
struct Pen<'s> {
    line: Color32,
    width: f32,
    dash: &'s [f32],
    fill: Color32,
}

impl<'s> Pen<'s> {
    /// The pen of `style`, or of the halo.
    fn of(style: &'s Style, halo: bool) -> Self {
        let (line, width, dash): (Color32, f32, &[f32]) = if halo {
            (HALO, style.stroke_width_px.max(1.0) + 6.0, &[])
        } else {
            (
                style
                    .stroke
                    .map_or(Color32::TRANSPARENT, |c| colour(c, style.opacity)),
                style.stroke_width_px,
                style.dash_px,
            )
        };
        let fill = if halo {
            Color32::TRANSPARENT
        } else {
            style
                .fill
                .map_or(Color32::TRANSPARENT, |c| colour(c, style.opacity))
        };
        Pen {
            line,
            width,
            dash,
            fill,
        }
    }

    /// The line as an egui stroke.
    fn stroke(self) -> Stroke {
        Stroke::new(self.width, self.line)
    }
}

/// The egui shapes of `prim` (its halo, when `halo`), added to `out`.
fn paint(
    ui: &Ui,
    prim: &Primitive,
    halo: bool,
    to_screen: &dyn Fn(&Point) -> Pos2,
    px_per_m: f32,
    out: &mut Vec<Shape>,
) {
    let style: &Style = &prim.style;
    let pen = Pen::of(style, halo);
    match &prim.shape {
        SceneShape::Circle { centre, radius_m } => {
            let r = (*radius_m as f32 * px_per_m).max(0.5);
            circle(to_screen(centre), r, pen, out);
        }
        SceneShape::Segment { a, b } => {
            stroke_path(
                vec![to_screen(a), to_screen(b)],
                pen.stroke(),
                pen.dash,
                out,
            );
        }
        SceneShape::Polyline { points, closed } => {
            let mut pts: Vec<Pos2> = points.iter().map(to_screen).collect();
            if *closed && pts.len() > 2 {
                pts.push(pts[0]);
            }
            stroke_path(pts, pen.stroke(), pen.dash, out);
        }
        SceneShape::Wedge {
            apex,
            heading_rad,
            half_angle_rad,
            radius_m,
        } => {
            let from = heading_rad - half_angle_rad;
            out.push(wedge(
                apex,
                from,
                2.0 * half_angle_rad,
                *radius_m,
                pen,
                to_screen,
            ));
        }
        SceneShape::Marker { at, shape } => {
            let c = if halo {
                HALO
            } else if shape.is_open() {
                style
                    .stroke
                    .or(style.fill)
                    .map_or(Color32::GRAY, |c| colour(c, style.opacity))
            } else {
                style
                    .fill
                    .or(style.stroke)
                    .map_or(Color32::GRAY, |c| colour(c, style.opacity))
            };
            let r = (style.marker_size_px.max(3.0) + if halo { 6.0 } else { 0.0 }) / 2.0;
            marker(to_screen(at), r, *shape, c, out);
        }
        SceneShape::Text {
            anchor,
            text,
            offset_px,
            align,
        } => {
            if !halo {
                let at = to_screen(anchor) + egui::vec2(offset_px[0], -offset_px[1]);
                out.push(text_shape(ui, style, at, text, *align));
            }
        }
    }
}

/// A sonar beam: the sector from `apex` (world) of `radius_m`, from heading `from_rad` over
/// `width_rad`, filled and outlined.
fn wedge(
    apex: &Point,
    from_rad: f64,
    width_rad: f64,
    radius_m: f64,
    pen: Pen,
    to_screen: &dyn Fn(&Point) -> Pos2,
) -> Shape {
    const N: usize = 16;
    let mut pts = vec![to_screen(apex)];
    for i in 0..=N {
        let a = from_rad + width_rad * i as f64 / N as f64;
        pts.push(to_screen(&Point::new(
            apex.x + radius_m * a.cos(),
            apex.y + radius_m * a.sin(),
        )));
    }
    Shape::Path(PathShape {
        points: pts,
        closed: true,
        fill: pen.fill,
        stroke: PathStroke::new(pen.width, pen.line),
    })
}

/// A circle of radius `r` pixels at `c`: filled, and outlined (dashed when the pen is).
fn circle(c: Pos2, r: f32, pen: Pen, out: &mut Vec<Shape>) {
    if pen.fill != Color32::TRANSPARENT {
        out.push(Shape::circle_filled(c, r, pen.fill));
    }
    if pen.dash.len() >= 2 {
        let n = ((r * 0.5) as usize).clamp(16, 96);
        let mut ring: Vec<Pos2> = (0..=n)
            .map(|i| {
                let a = std::f32::consts::TAU * i as f32 / n as f32;
                c + egui::vec2(r * a.cos(), r * a.sin())
            })
            .collect();
        ring.dedup();
        stroke_path(ring, pen.stroke(), pen.dash, out);
    } else if pen.width > 0.0 && pen.line != Color32::TRANSPARENT {
        out.push(Shape::circle_stroke(c, r, pen.stroke()));
    }
}

/// `text` at `at` (screen), aligned as `align` says, in the style's colour and size.
fn text_shape(ui: &Ui, style: &Style, at: Pos2, text: &str, align: TextAlign) -> Shape {
    let c = style
        .fill
        .or(style.stroke)
        .map_or(Color32::GRAY, |c| colour(c, style.opacity));
    let align = match align {
        TextAlign::Start => Align2::LEFT_BOTTOM,
        TextAlign::Middle => Align2::CENTER_BOTTOM,
        TextAlign::End => Align2::RIGHT_BOTTOM,
    };
    let font = egui::FontId::proportional(style.marker_size_px.max(8.0));
    let galley = ui.painter().layout_no_wrap(text.to_owned(), font, c);
    let rect = align.anchor_size(at, galley.size());
    TextShape::new(rect.min, galley, c).into()
}

/// A marker glyph of radius `r` pixels.
fn marker(p: Pos2, r: f32, shape: MarkerShape, c: Color32, out: &mut Vec<Shape>) {
    let v = |x: f32, y: f32| p + egui::vec2(x * r, y * r);
    let thin = Stroke::new((r / 2.5).max(1.0), c);
    match shape {
        MarkerShape::Dot => out.push(Shape::circle_filled(p, r, c)),
        MarkerShape::Ring => out.push(Shape::circle_stroke(p, r, thin)),
        MarkerShape::Square => out.push(Shape::rect_filled(
            egui::Rect::from_center_size(p, egui::vec2(2.0 * r, 2.0 * r) * 0.85),
            0.0,
            c,
        )),
        MarkerShape::Diamond => out.push(Shape::convex_polygon(
            vec![v(0.0, -1.0), v(1.0, 0.0), v(0.0, 1.0), v(-1.0, 0.0)],
            c,
            Stroke::NONE,
        )),
        MarkerShape::Triangle => out.push(Shape::convex_polygon(
            vec![v(0.0, -1.0), v(0.87, 0.5), v(-0.87, 0.5)],
            c,
            Stroke::NONE,
        )),
        MarkerShape::Cross => {
            out.push(Shape::line_segment([v(-0.7, -0.7), v(0.7, 0.7)], thin));
            out.push(Shape::line_segment([v(-0.7, 0.7), v(0.7, -0.7)], thin));
        }
        MarkerShape::Plus => {
            out.push(Shape::line_segment([v(-1.0, 0.0), v(1.0, 0.0)], thin));
            out.push(Shape::line_segment([v(0.0, -1.0), v(0.0, 1.0)], thin));
        }
    }
}

impl PlotItem for ScenePlotItem<'_> {
    fn shapes(&self, ui: &Ui, transform: &PlotTransform, shapes: &mut Vec<Shape>) {
        let s = self.scale;
        let to_screen =
            |p: &Point| transform.position_from_point(&PlotPoint::new(p.x * s, p.y * s));
        let px_per_m = (transform.dpos_dvalue_x().abs() * s) as f32;
        // The visible world rectangle, widened by a margin for strokes and markers.
        let b = transform.bounds();
        let margin_m = 20.0 / f64::from(px_per_m.max(1e-9));
        let (vmin, vmax) = (
            Point::new(b.min()[0] / s - margin_m, b.min()[1] / s - margin_m),
            Point::new(b.max()[0] / s + margin_m, b.max()[1] / s + margin_m),
        );
        let visible = |prim: &Primitive| {
            let (min, max) = world_box(&prim.shape);
            min.x <= vmax.x && max.x >= vmin.x && min.y <= vmax.y && max.y >= vmin.y
        };
        let mut draw = |prim: &Primitive, halo: bool| {
            if visible(prim) {
                paint(ui, prim, halo, &to_screen, px_per_m, shapes);
            }
        };
        match &self.halo_of {
            None => self.scene.primitives.iter().for_each(|p| draw(p, false)),
            Some(indices) => {
                for &i in indices {
                    if let Some(p) = self.scene.primitives.get(i) {
                        draw(p, true);
                    }
                }
            }
        }
    }

    fn initialize(&mut self, _x_range: RangeInclusive<f64>) {}

    fn color(&self) -> Color32 {
        Color32::TRANSPARENT
    }

    fn allow_hover(&self) -> bool {
        false
    }

    fn geometry(&self) -> PlotGeometry<'_> {
        PlotGeometry::None
    }

    fn bounds(&self) -> PlotBounds {
        let mut bounds = PlotBounds::NOTHING;
        if self.halo_of.is_some() {
            return bounds;
        }
        if let Some(r) = self.scene.bounds() {
            bounds.extend_with(&PlotPoint::new(r.min.x * self.scale, r.min.y * self.scale));
            bounds.extend_with(&PlotPoint::new(r.max.x * self.scale, r.max.y * self.scale));
        }
        bounds
    }

    fn base(&self) -> &PlotItemBase {
        &self.base
    }

    fn base_mut(&mut self) -> &mut PlotItemBase {
        &mut self.base
    }
}
