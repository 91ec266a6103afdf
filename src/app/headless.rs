//! The map view drawn without a window: the inspector's own `map_view_ui` in an
//! `egui::Context` fed a fixed screen, its shapes tessellated into meshes as a renderer would
//! get them. `sonarmap bench` times frames with it; tests count what a frame draws.

use super::map_view::{map_view_ui, MapViewState, ViewRequest};
use super::run_plot::RunPlot;
use super::run_plots::{run_plots_ui, RunCurves};
use crate::scene::{Scene, SceneId};
use crate::units::Units;

/// A map view of a fixed size, frame after frame.
pub struct HeadlessMapView {
    ctx: egui::Context,
    state: MapViewState,
    size_px: (f32, f32),
}

/// What one frame produced.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FrameStats {
    /// Shapes egui was asked to paint.
    pub shapes: usize,
    /// Triangle-mesh vertices after tessellation.
    pub vertices: usize,
}

/// Runs `ui` for one frame on a fixed screen of `size_px` and tessellates what it painted.
fn tessellated_frame(
    ctx: &egui::Context,
    size_px: (f32, f32),
    ui: impl FnMut(&mut egui::Ui),
) -> FrameStats {
    let input = egui::RawInput {
        screen_rect: Some(egui::Rect::from_min_size(
            egui::Pos2::ZERO,
            egui::vec2(size_px.0, size_px.1),
        )),
        ..Default::default()
    };
    let mut output = ctx.run_ui(input, ui);
    let clipped = std::mem::take(&mut output.shapes);
    let pixels_per_point = output.pixels_per_point;
    // No renderer holds textures here: the font atlas updates are dropped.
    output.drop_without_applying_deltas();
    let shapes = clipped.len();
    let meshes = ctx.tessellate(clipped, pixels_per_point);
    let vertices = meshes
        .iter()
        .map(|m| match &m.primitive {
            egui::epaint::Primitive::Mesh(mesh) => mesh.vertices.len(),
            egui::epaint::Primitive::Callback(_) => 0,
        })
        .sum();
    FrameStats { shapes, vertices }
}

/// The run plots panel drawn without a window, for `sonarmap bench`.
pub struct HeadlessRunPlots {
    ctx: egui::Context,
    size_px: (f32, f32),
}

impl HeadlessRunPlots {
    /// A panel of `width × height` points.
    pub fn new(width: f32, height: f32) -> Self {
        Self {
            ctx: egui::Context::default(),
            size_px: (width, height),
        }
    }

    /// One frame of the panel showing `plot` of `curves` at snapshot `current`.
    pub fn frame(&mut self, plot: RunPlot, curves: RunCurves, current: usize) -> FrameStats {
        let mut shown = plot;
        tessellated_frame(&self.ctx, self.size_px, |ui| {
            run_plots_ui(ui, &mut shown, curves, None, current);
        })
    }
}

impl HeadlessMapView {
    /// A view of `width × height` points (one pixel per point) that fits the first scene shown.
    pub fn new(width: f32, height: f32) -> Self {
        let state = MapViewState {
            request: Some(ViewRequest::Fit),
            ..MapViewState::default()
        };
        Self {
            ctx: egui::Context::default(),
            state,
            size_px: (width, height),
        }
    }

    /// World metres per pixel in the last frame (what the scene's level of detail should use).
    pub fn world_per_px(&self) -> f64 {
        self.state.world_per_px()
    }

    /// Runs one frame of the map view showing `scene` and tessellates it.
    pub fn frame(&mut self, scene: &Scene, units: Units) -> FrameStats {
        let state = &mut self.state;
        tessellated_frame(&self.ctx, self.size_px, |ui| {
            map_view_ui(
                ui,
                super::map_view::MapPlot::MAIN,
                scene,
                units,
                state,
                SceneId::None,
                &|_| None,
                None,
            );
        })
    }
}
