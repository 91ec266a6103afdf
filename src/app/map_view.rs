//! The map view: draws a [`Scene`] with egui_plot (equal aspect, pan, zoom, fit), hover
//! tooltips from [`Scene::hit`], click to select, and a ruler (shift-drag, or the Ruler tool).
//!
//! Plot coordinates are the run's units (so the grid reads in inches when the log is in
//! inches); the scene and everything stored here are in metres.

use super::command::Command;
use crate::geometry::Point;
use crate::mapping::Map;
use crate::scene::{
    format_length, MarkerShape, Primitive, Rgba, Scene, SceneId, Shape, Style, TextAlign, ViewRect,
};
use crate::units::Units;
use egui::{Align2, Color32, RichText, Stroke};
use egui_plot::{Line, LineStyle, Plot, PlotBounds, PlotPoint, PlotPoints, Points, Polygon, Text};

/// Colour of the baseline's map drawn ghosted.
pub const GHOST: Color32 = Color32::from_rgba_premultiplied(0x70, 0x70, 0x70, 0xa0);

/// Hover and hit tolerance, screen pixels.
const HIT_TOLERANCE_PX: f64 = 7.0;

/// A change of the view asked for by a command.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ViewRequest {
    /// Fit the view to the scene.
    Fit,
    /// Centre the view on a world point (metres), keeping the zoom.
    Center(Point),
    /// Show this world rectangle (metres; grown to the plot's aspect).
    Frame(ViewRect),
}

/// What the map view remembers between frames.
#[derive(Clone, Debug, Default)]
pub struct MapViewState {
    /// A pending view change.
    pub request: Option<ViewRequest>,
    /// The world rectangle shown in the last frame, metres.
    pub visible_m: Option<ViewRect>,
    /// The plot's size in the last frame, pixels.
    pub size_px: (u32, u32),
    /// The pointer in world metres, when over the plot.
    pub cursor_m: Option<Point>,
    /// The Ruler tool is on (drag measures instead of panning).
    pub ruler_tool: bool,
    /// The last measurement, metres.
    pub ruler_m: Option<(Point, Point)>,
}

impl MapViewState {
    /// World metres per screen pixel in the last frame (0 before the first frame).
    pub fn world_per_px(&self) -> f64 {
        match self.visible_m {
            Some(v) if self.size_px.0 > 0 => v.width_m() / f64::from(self.size_px.0),
            _ => 0.0,
        }
    }

    /// The ruler's measurement as text: length and angle against the x axis.
    pub fn ruler_text(&self, units: Units) -> Option<String> {
        let (a, b) = self.ruler_m?;
        let d = b - a;
        let angle = d.y.atan2(d.x).to_degrees();
        Some(format!("{}  {angle:.1}°", format_length(d.norm(), units)))
    }
}

/// The colour with the style's opacity applied.
pub fn colour(c: Rgba, opacity: f32) -> Color32 {
    let a = (f32::from(c.a) * opacity.clamp(0.0, 1.0)).round() as u8;
    Color32::from_rgba_unmultiplied(c.r, c.g, c.b, a)
}

fn line_style(style: &Style) -> LineStyle {
    match style.dash_px {
        [] | [_] => LineStyle::Solid,
        [on, off, ..] if *on <= 2.0 => LineStyle::Dotted {
            spacing: (on + off).max(3.0),
        },
        [on, ..] => LineStyle::Dashed {
            length: on.max(2.0),
        },
    }
}

fn plot_marker(shape: MarkerShape) -> egui_plot::MarkerShape {
    match shape {
        MarkerShape::Dot | MarkerShape::Ring => egui_plot::MarkerShape::Circle,
        MarkerShape::Cross => egui_plot::MarkerShape::Cross,
        MarkerShape::Plus => egui_plot::MarkerShape::Plus,
        MarkerShape::Square => egui_plot::MarkerShape::Square,
        MarkerShape::Triangle => egui_plot::MarkerShape::Up,
        MarkerShape::Diamond => egui_plot::MarkerShape::Diamond,
    }
}

fn circle_points(centre: &Point, radius: f64, s: f64) -> Vec<[f64; 2]> {
    const N: usize = 40;
    (0..N)
        .map(|i| {
            let a = std::f64::consts::TAU * i as f64 / N as f64;
            [
                (centre.x + radius * a.cos()) * s,
                (centre.y + radius * a.sin()) * s,
            ]
        })
        .collect()
}

/// Adds one primitive to the plot; `s` converts metres to plot units, `wpp` is metres per
/// pixel, `emphasis` draws it as a selection highlight instead.
fn draw_primitive(
    plot_ui: &mut egui_plot::PlotUi,
    prim: &Primitive,
    n: usize,
    s: f64,
    wpp: f64,
    emphasis: bool,
) {
    let style = &prim.style;
    let (stroke_colour, width, line) = if emphasis {
        (
            Color32::from_rgba_unmultiplied(255, 255, 255, 150),
            style.stroke_width_px.max(1.0) + 6.0,
            LineStyle::Solid,
        )
    } else {
        (
            style
                .stroke
                .map_or(Color32::TRANSPARENT, |c| colour(c, style.opacity)),
            style.stroke_width_px,
            line_style(style),
        )
    };
    let fill = style.fill.map(|c| colour(c, style.opacity));
    let pt = |p: &Point| [p.x * s, p.y * s];
    let id = ("prim", n, emphasis);
    match &prim.shape {
        Shape::Circle { centre, radius_m } => {
            let poly = Polygon::new("", PlotPoints::new(circle_points(centre, *radius_m, s)))
                .stroke(Stroke::new(width, stroke_colour))
                .fill_color(if emphasis {
                    Color32::TRANSPARENT
                } else {
                    fill.unwrap_or(Color32::TRANSPARENT)
                })
                .style(line)
                .allow_hover(false)
                .id(id);
            plot_ui.polygon(poly);
        }
        Shape::Wedge {
            apex,
            heading_rad,
            half_angle_rad,
            radius_m,
        } => {
            let mut pts = vec![pt(apex)];
            const N: usize = 16;
            for i in 0..=N {
                let a = heading_rad - half_angle_rad + 2.0 * half_angle_rad * i as f64 / N as f64;
                pts.push([
                    (apex.x + radius_m * a.cos()) * s,
                    (apex.y + radius_m * a.sin()) * s,
                ]);
            }
            let poly = Polygon::new("", PlotPoints::new(pts))
                .stroke(Stroke::new(width, stroke_colour))
                .fill_color(if emphasis {
                    Color32::TRANSPARENT
                } else {
                    fill.unwrap_or(Color32::TRANSPARENT)
                })
                .allow_hover(false)
                .id(id);
            plot_ui.polygon(poly);
        }
        Shape::Segment { a, b } => {
            let l = Line::new("", PlotPoints::new(vec![pt(a), pt(b)]))
                .color(stroke_colour)
                .width(width)
                .style(line)
                .allow_hover(false)
                .id(id);
            plot_ui.line(l);
        }
        Shape::Polyline { points, closed } => {
            let mut pts: Vec<[f64; 2]> = points.iter().map(pt).collect();
            if *closed && points.len() > 2 {
                pts.push(pt(&points[0]));
            }
            let l = Line::new("", PlotPoints::new(pts))
                .color(stroke_colour)
                .width(width)
                .style(line)
                .allow_hover(false)
                .id(id);
            plot_ui.line(l);
        }
        Shape::Marker { at, shape } => {
            let c = if emphasis {
                stroke_colour
            } else if shape.is_open() {
                style
                    .stroke
                    .or(style.fill)
                    .map_or(Color32::GRAY, |c| colour(c, style.opacity))
            } else {
                fill.or(style.stroke.map(|c| colour(c, style.opacity)))
                    .unwrap_or(Color32::GRAY)
            };
            let size = style.marker_size_px.max(3.0) + if emphasis { 6.0 } else { 0.0 };
            let p = Points::new("", vec![pt(at)])
                .shape(plot_marker(*shape))
                .radius(size / 2.0)
                .filled(!shape.is_open())
                .color(c)
                .allow_hover(false)
                .id(id);
            plot_ui.add(p);
        }
        Shape::Text {
            anchor,
            text,
            offset_px,
            align,
        } => {
            if emphasis {
                return;
            }
            let at = PlotPoint::new(
                (anchor.x + f64::from(offset_px[0]) * wpp) * s,
                (anchor.y + f64::from(offset_px[1]) * wpp) * s,
            );
            let c = style
                .fill
                .or(style.stroke)
                .map_or(Color32::GRAY, |c| colour(c, style.opacity));
            let anchor = match align {
                TextAlign::Start => Align2::LEFT_BOTTOM,
                TextAlign::Middle => Align2::CENTER_BOTTOM,
                TextAlign::End => Align2::RIGHT_BOTTOM,
            };
            let t = Text::new(
                "",
                at,
                RichText::new(text)
                    .size(style.marker_size_px.max(8.0))
                    .color(c),
            )
            .anchor(anchor)
            .allow_hover(false)
            .id(id);
            plot_ui.text(t);
        }
    }
}

/// True when a primitive with id `id` belongs to the selection `selected`.
pub fn is_selected(id: SceneId, selected: SceneId) -> bool {
    if selected == SceneId::None || id == SceneId::None {
        return false;
    }
    match (selected, id) {
        (
            SceneId::NewSegment(i),
            SceneId::Decision {
                new_segment,
                existing: None,
            },
        ) => i == new_segment,
        (SceneId::MapSegment(a), SceneId::Update(b)) => a == b,
        _ => id == selected,
    }
}

/// Draws the map view and reports what the user asked for. `describe` gives a hover text for
/// a scene id.
pub fn map_view_ui(
    ui: &mut egui::Ui,
    scene: &Scene,
    units: Units,
    state: &mut MapViewState,
    selected: SceneId,
    describe: &dyn Fn(SceneId) -> Option<String>,
    ghost: Option<&Map>,
) -> Vec<Command> {
    let mut commands = Vec::new();
    let m_per_unit = units.metres_per_unit();
    let s = 1.0 / m_per_unit;
    ui.horizontal(|ui| {
        if ui
            .button("Fit")
            .on_hover_text("Fit the view to the scene (double-click also)")
            .clicked()
        {
            commands.push(Command::FitView);
        }
        if ui
            .button("Zoom to selection")
            .on_hover_text("Frame the selected segment (Z)")
            .clicked()
        {
            commands.push(Command::ZoomToSelection);
        }
        ui.toggle_value(&mut state.ruler_tool, "Ruler")
            .on_hover_text("Drag to measure distance and angle (or hold Shift and drag)");
        if state.ruler_m.is_some() && ui.button("Clear ruler").clicked() {
            state.ruler_m = None;
        }
        if let Some(text) = state.ruler_text(units) {
            ui.label(format!("ruler: {text}"));
        }
        ui.label(RichText::new("scroll: zoom · drag: pan · click: select").weak());
    });
    let shift = ui.input(|i| i.modifiers.shift);
    let measuring = state.ruler_tool || shift;
    let wpp = state.world_per_px();
    let request = state.request.take();
    let ruler = state.ruler_m;
    let x_units = units;
    let plot = Plot::new("map_view")
        .data_aspect(1.0)
        .allow_drag(!measuring)
        .allow_boxed_zoom(false)
        .allow_double_click_reset(true)
        .show_crosshair(false)
        .label_formatter(|_| None)
        .x_axis_formatter(move |m, _| {
            format!(
                "{} {}",
                egui_plot::format_number(m.value, 4),
                x_units.symbol()
            )
        })
        .y_axis_formatter(move |m, _| {
            format!(
                "{} {}",
                egui_plot::format_number(m.value, 4),
                x_units.symbol()
            )
        });
    let response = plot.show(ui, |plot_ui| {
        match request {
            Some(ViewRequest::Fit) => plot_ui.set_auto_bounds(true),
            Some(ViewRequest::Center(p)) => {
                let b = plot_ui.plot_bounds();
                let (w, h) = (b.width() / 2.0, b.height() / 2.0);
                let (cx, cy) = (p.x * s, p.y * s);
                plot_ui
                    .set_plot_bounds(PlotBounds::from_min_max([cx - w, cy - h], [cx + w, cy + h]));
            }
            Some(ViewRequest::Frame(r)) => {
                plot_ui.set_plot_bounds(PlotBounds::from_min_max(
                    [r.min.x * s, r.min.y * s],
                    [r.max.x * s, r.max.y * s],
                ));
            }
            None => {}
        }
        if let Some(map) = ghost {
            // The baseline's map under everything else: dashed grey.
            for seg in &map.segments {
                plot_ui.line(
                    Line::new(
                        "",
                        PlotPoints::new(vec![
                            [seg.a.point.x * s, seg.a.point.y * s],
                            [seg.b.point.x * s, seg.b.point.y * s],
                        ]),
                    )
                    .color(GHOST)
                    .width(2.5)
                    .style(LineStyle::Dashed { length: 8.0 })
                    .allow_hover(false)
                    .id(("baseline_ghost", seg.id)),
                );
            }
        }
        for (n, prim) in scene.primitives.iter().enumerate() {
            draw_primitive(plot_ui, prim, n, s, wpp, false);
        }
        for (n, prim) in scene.primitives.iter().enumerate() {
            if is_selected(prim.id, selected) {
                draw_primitive(plot_ui, prim, n, s, wpp, true);
            }
        }
        if let Some((a, b)) = ruler {
            let c = Color32::from_rgb(0xd0, 0x20, 0x80);
            plot_ui.line(
                Line::new(
                    "",
                    PlotPoints::new(vec![[a.x * s, a.y * s], [b.x * s, b.y * s]]),
                )
                .color(c)
                .width(2.0)
                .allow_hover(false)
                .id("ruler"),
            );
            plot_ui.add(
                Points::new("", vec![[a.x * s, a.y * s], [b.x * s, b.y * s]])
                    .radius(3.0)
                    .color(c)
                    .allow_hover(false)
                    .id("ruler_ends"),
            );
        }
    });
    let transform = response.transform;
    let bounds = transform.bounds();
    state.visible_m = Some(ViewRect::new(
        Point::new(bounds.min()[0] * m_per_unit, bounds.min()[1] * m_per_unit),
        Point::new(bounds.max()[0] * m_per_unit, bounds.max()[1] * m_per_unit),
    ));
    let rect = response.response.rect;
    state.size_px = (rect.width().max(1.0) as u32, rect.height().max(1.0) as u32);
    let to_world = |pos: egui::Pos2| {
        let v = transform.value_from_position(pos);
        Point::new(v.x * m_per_unit, v.y * m_per_unit)
    };
    let resp = &response.response;
    state.cursor_m = resp.hover_pos().map(to_world);
    let m_per_px = transform.dvalue_dpos()[0].abs() * m_per_unit;

    if measuring {
        if resp.drag_started() {
            if let Some(p) = resp.interact_pointer_pos() {
                let w = to_world(p);
                state.ruler_m = Some((w, w));
            }
        } else if resp.dragged() {
            if let (Some(p), Some((a, _))) = (resp.interact_pointer_pos(), state.ruler_m) {
                state.ruler_m = Some((a, to_world(p)));
            }
        }
    }
    let hit = state
        .cursor_m
        .and_then(|p| scene.hit(p, HIT_TOLERANCE_PX * m_per_px));
    if resp.clicked() {
        commands.push(Command::Select(hit.unwrap_or(SceneId::None)));
    }
    if let Some(id) = hit {
        if !resp.dragged() {
            if let Some(text) = describe(id) {
                resp.clone().on_hover_ui_at_pointer(|ui| {
                    ui.label(RichText::new(text).monospace());
                });
            }
        }
    }
    commands
}
