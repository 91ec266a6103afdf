//! The map view: draws a [`Scene`] with egui_plot (equal aspect, pan, zoom, fit), hover
//! tooltips from [`Scene::hit`], click to select, and a ruler (shift-drag, or the Ruler tool).
//!
//! Plot coordinates are the run's units (so the grid reads in inches when the log is in
//! inches); the scene and everything stored here are in metres.

use super::command::Command;
use super::scene_item::ScenePlotItem;
use super::settings::PanelLayout;
use crate::geometry::Point;
use crate::mapping::Map;
use crate::scene::{format_length, Scene, SceneId, ViewRect};
use crate::units::Units;
use egui::{Color32, RichText};
use egui_plot::{Line, LineStyle, Plot, PlotBounds, PlotPoints, PlotTransform, Points};

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
    /// The plot's world-to-screen transform in the last frame (run units to points).
    pub transform: Option<PlotTransform>,
    /// The part of the plot visible on screen in the last frame (the plot's frame clipped to
    /// its panel), points.
    pub visible_px: Option<egui::Rect>,
    /// Metres per plot unit in the last frame (the run's length unit).
    pub m_per_unit: f64,
}

impl MapViewState {
    /// World metres per screen pixel in the last frame (0 before the first frame).
    pub fn world_per_px(&self) -> f64 {
        match self.visible_m {
            Some(v) if self.size_px.0 > 0 => v.width_m() / f64::from(self.size_px.0),
            _ => 0.0,
        }
    }

    /// Where world point `p` (metres) was drawn on screen in the last frame, points.
    pub fn screen_of(&self, p: Point) -> Option<egui::Pos2> {
        let t = self.transform?;
        let s = 1.0 / self.m_per_unit;
        Some(t.position_from_point(&egui_plot::PlotPoint::new(p.x * s, p.y * s)))
    }

    /// The ruler's measurement as text: length and angle against the x axis.
    pub fn ruler_text(&self, units: Units) -> Option<String> {
        let (a, b) = self.ruler_m?;
        let d = b - a;
        let angle = d.y.atan2(d.x).to_degrees();
        Some(format!("{}  {angle:.1}°", format_length(d.norm(), units)))
    }
}

pub use super::scene_item::colour;

/// True when a primitive with id `id` belongs to the selection `selected`.
pub fn is_selected(id: SceneId, selected: SceneId) -> bool {
    selected.selects(id)
}

/// The map view's tool bar: fit, zoom, ruler, and the panel switches. It wraps rather than
/// grows, so the plot below is laid out in the width the panel really has.
pub fn map_toolbar_ui(
    ui: &mut egui::Ui,
    state: &mut MapViewState,
    units: Units,
    panels: &PanelLayout,
    pinned: bool,
) -> Vec<Command> {
    use super::command::PanelToggle;
    let mut commands = Vec::new();
    ui.horizontal_wrapped(|ui| {
        if ui
            .button("Fit")
            .on_hover_text("Fit the view to the scene (F; double-click also)")
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
        ui.separator();
        let switches = [
            (
                panels.shows_left(),
                "Left",
                "Show or hide the left panel (L)",
                PanelToggle::Left,
            ),
            (
                panels.shows_right(),
                "Right",
                "Show or hide the decisions and inspector (I)",
                PanelToggle::Right,
            ),
            (
                panels.map_only,
                "Map only",
                "Hide every side panel (M)",
                PanelToggle::MapOnly,
            ),
        ];
        for (on, text, hover, toggle) in switches {
            if ui.selectable_label(on, text).on_hover_text(hover).clicked() {
                commands.push(Command::TogglePanel(toggle));
            }
        }
        if pinned
            && ui
                .selectable_label(panels.split, "A | B")
                .on_hover_text("The baseline (A) and the current map (B) side by side, linked (S)")
                .clicked()
        {
            commands.push(Command::TogglePanel(PanelToggle::Split));
        }
        ui.add(
            egui::Label::new(RichText::new("scroll: zoom · drag: pan · click: select").weak())
                .truncate(),
        );
    });
    commands
}

/// Which plot `map_view_ui` draws: its id, and the group whose pan and zoom it shares.
#[derive(Clone, Copy, Debug)]
pub struct MapPlot {
    /// The plot's id (one per plot on screen).
    pub id: &'static str,
    /// Plots of the same group pan and zoom together.
    pub link_group: Option<&'static str>,
    /// A caption drawn over the plot's upper-left corner ("A: baseline").
    pub caption: Option<&'static str>,
}

impl MapPlot {
    /// The single map view.
    pub const MAIN: MapPlot = MapPlot {
        id: "map_view",
        link_group: None,
        caption: None,
    };

    /// The A | B split's left view: the pinned baseline.
    pub const SPLIT_A: MapPlot = MapPlot {
        id: "map_view_a",
        link_group: Some("map_views"),
        caption: Some("A: baseline"),
    };

    /// The A | B split's right view: the current parameters (the main view's plot).
    pub const SPLIT_B: MapPlot = MapPlot {
        id: "map_view",
        link_group: Some("map_views"),
        caption: Some("B: current"),
    };
}

/// Draws the map view and reports what the user asked for. `describe` gives a hover text for
/// a scene id.
#[allow(clippy::too_many_arguments)]
pub fn map_view_ui(
    ui: &mut egui::Ui,
    plot_id: MapPlot,
    scene: &Scene,
    units: Units,
    state: &mut MapViewState,
    selected: SceneId,
    describe: &dyn Fn(SceneId) -> Option<String>,
    ghost: Option<&Map>,
) -> Vec<Command> {
    let m_per_unit = units.metres_per_unit();
    let s = 1.0 / m_per_unit;
    let shift = ui.input(|i| i.modifiers.shift);
    let measuring = state.ruler_tool || shift;
    let request = state.request.take();
    let ruler = state.ruler_m;
    let plot = map_plot(ui, plot_id, units, measuring);
    let response = plot.show(ui, |plot_ui| {
        apply_request(plot_ui, request, s);
        if let Some(map) = ghost {
            ghost_lines(plot_ui, map, s);
        }
        plot_ui.add(ScenePlotItem::new(scene, s));
        let halo: Vec<usize> = (scene.primitives.iter().enumerate())
            .filter(|(_, p)| is_selected(p.id, selected))
            .map(|(n, _)| n)
            .collect();
        if !halo.is_empty() {
            plot_ui.add(ScenePlotItem::halo(scene, s, halo));
        }
        if let Some(ruler) = ruler {
            ruler_lines(plot_ui, ruler, s);
        }
    });
    record_view(ui, plot_id, state, &response, m_per_unit);
    interact(scene, state, &response, measuring, describe)
}

/// The plot of the map view: equal axes in the log's units, dragging (unless measuring) and
/// scrolling, linked to the other views of its group.
fn map_plot(ui: &egui::Ui, plot_id: MapPlot, units: Units, measuring: bool) -> Plot<'static> {
    let plot = Plot::new(plot_id.id)
        .width(ui.available_width().max(1.0))
        .height(ui.available_height().max(1.0))
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
                units.symbol()
            )
        })
        .y_axis_formatter(move |m, _| {
            format!(
                "{} {}",
                egui_plot::format_number(m.value, 4),
                units.symbol()
            )
        });
    match plot_id.link_group {
        Some(group) => plot
            .link_axis(egui::Id::unique(group), [true, true])
            .link_cursor(egui::Id::unique(group), [true, true]),
        None => plot,
    }
}

/// Moves the view as `request` asks (`s`: plot units per metre).
fn apply_request(plot_ui: &mut egui_plot::PlotUi, request: Option<ViewRequest>, s: f64) {
    match request {
        Some(ViewRequest::Fit) => plot_ui.set_auto_bounds(true),
        Some(ViewRequest::Center(p)) => {
            let b = plot_ui.plot_bounds();
            let (w, h) = (b.width() / 2.0, b.height() / 2.0);
            let (cx, cy) = (p.x * s, p.y * s);
            plot_ui.set_plot_bounds(PlotBounds::from_min_max([cx - w, cy - h], [cx + w, cy + h]));
        }
        Some(ViewRequest::Frame(r)) => {
            plot_ui.set_plot_bounds(PlotBounds::from_min_max(
                [r.min.x * s, r.min.y * s],
                [r.max.x * s, r.max.y * s],
            ));
        }
        None => {}
    }
}

/// The baseline's map under everything else: dashed grey.
fn ghost_lines(plot_ui: &mut egui_plot::PlotUi, map: &Map, s: f64) {
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

/// The ruler from `a` to `b` (metres), with its ends marked.
fn ruler_lines(plot_ui: &mut egui_plot::PlotUi, (a, b): (Point, Point), s: f64) {
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

/// Keeps what the view showed in `state` (the visible rectangle, the transform, the size)
/// and paints the view's caption.
fn record_view(
    ui: &egui::Ui,
    plot_id: MapPlot,
    state: &mut MapViewState,
    response: &egui_plot::PlotResponse<()>,
    m_per_unit: f64,
) {
    let transform = response.transform;
    let bounds = transform.bounds();
    state.visible_m = Some(ViewRect::new(
        Point::new(bounds.min()[0] * m_per_unit, bounds.min()[1] * m_per_unit),
        Point::new(bounds.max()[0] * m_per_unit, bounds.max()[1] * m_per_unit),
    ));
    let rect = response.response.rect;
    state.transform = Some(transform);
    state.m_per_unit = m_per_unit;
    state.visible_px = Some(transform.frame().intersect(ui.clip_rect()));
    if let Some(caption) = plot_id.caption {
        ui.painter().text(
            transform.frame().left_top() + egui::vec2(8.0, 6.0),
            egui::Align2::LEFT_TOP,
            caption,
            egui::FontId::proportional(14.0),
            ui.visuals().strong_text_color(),
        );
    }
    state.size_px = (rect.width().max(1.0) as u32, rect.height().max(1.0) as u32);
}

/// The pointer over the view: the cursor's position, the ruler dragged while measuring, a
/// click selecting what is under it, and its description as a tooltip.
fn interact(
    scene: &Scene,
    state: &mut MapViewState,
    response: &egui_plot::PlotResponse<()>,
    measuring: bool,
    describe: &dyn Fn(SceneId) -> Option<String>,
) -> Vec<Command> {
    let mut commands = Vec::new();
    let (transform, m_per_unit) = (response.transform, state.m_per_unit);
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
