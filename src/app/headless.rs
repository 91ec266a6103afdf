//! The map view drawn without a window: the inspector's own `map_view_ui` in an
//! `egui::Context` fed a fixed screen, its shapes tessellated into meshes as a renderer would
//! get them. `sonarmap bench` times frames with it; tests count what a frame draws.

use super::map_view::{map_view_ui, MapViewState, ViewRequest};
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
        let input = egui::RawInput {
            screen_rect: Some(egui::Rect::from_min_size(
                egui::Pos2::ZERO,
                egui::vec2(self.size_px.0, self.size_px.1),
            )),
            ..Default::default()
        };
        let state = &mut self.state;
        let mut output = self.ctx.run_ui(input, |ui| {
            map_view_ui(ui, scene, units, state, SceneId::None, &|_| None, None);
        });
        let clipped = std::mem::take(&mut output.shapes);
        let pixels_per_point = output.pixels_per_point;
        // No renderer holds textures here: the font atlas updates are dropped.
        output.drop_without_applying_deltas();
        let shapes = clipped.len();
        let meshes = self.ctx.tessellate(clipped, pixels_per_point);
        let vertices = meshes
            .iter()
            .map(|m| match &m.primitive {
                egui::epaint::Primitive::Mesh(mesh) => mesh.vertices.len(),
                egui::epaint::Primitive::Callback(_) => 0,
            })
            .sum();
        FrameStats { shapes, vertices }
    }
}
