//! The scene: a world-space display list built from one step of a replay.
//!
//! "One scene, two renderers" (docs/architecture.md): the map view and the SVG export both translate the
//! same [`Scene`], so an export shows what the screen shows, and the scene is tested headlessly.
//! [`build_scene`] is a pure function of the run, the step's trace and the maps before and
//! after the step; every primitive carries its [`Layer`], its [`Style`] (sizes in screen
//! pixels) and the [`SceneId`] of what it shows, for hover and selection.
//!
//! World coordinates are metres with y up; renderers flip y.

mod build;
mod declutter;
pub mod figure;
mod layer;
mod marker;
mod primitive;
mod query;
mod style;
pub mod svg;

pub use build::{build_scene, SceneInput, ViewOptions};
pub use layer::{Layer, LayerSet};
pub use marker::MarkerShape;
pub use primitive::{Primitive, SceneId, Shape, TextAlign};
pub use query::{LegendEntry, ViewRect};
pub use style::{decision_marker, palette, Glyph, Rgba, Role, Style};

/// A display list in world coordinates, in drawing order (layers in [`Layer::ALL`] order).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Scene {
    /// Run name and snapshot, for titles.
    pub title: String,
    /// The primitives, sorted by layer (stable within a layer).
    pub primitives: Vec<Primitive>,
    /// What the view rectangle left out ([`ViewOptions::visible_m`]): the bounding box of the
    /// map segments not drawn, by layer, so that the scene's bounds (and Fit) are those of
    /// the whole content.
    pub culled: Vec<(Layer, ViewRect)>,
}

impl Scene {
    /// The primitives of `layer`, in drawing order.
    pub fn layer(&self, layer: Layer) -> impl Iterator<Item = &Primitive> {
        self.primitives.iter().filter(move |p| p.layer == layer)
    }

    /// The layers that hold at least one primitive, in drawing order.
    pub fn layers_present(&self) -> LayerSet {
        let mut set = LayerSet::empty();
        for p in &self.primitives {
            set.set(p.layer, true);
        }
        set
    }
}

/// A length in metres written in `units` with one decimal (whole numbers without),
/// e.g. `"48.2 in"`.
pub fn format_length(length_m: f64, units: crate::units::Units) -> String {
    let v = units.from_m(length_m);
    if (v - v.round()).abs() < 1e-9 {
        format!("{} {}", v.round(), units.symbol())
    } else {
        format!("{:.1} {}", v, units.symbol())
    }
}

#[cfg(test)]
mod tests;
