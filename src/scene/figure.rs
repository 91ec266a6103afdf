//! Figures: one step's scene exported for a page, as the screen shows it or in the figure
//! style. The scene is built at the page's scale ([`super::svg::page_world_per_px`]), so its
//! labels are decluttered for the page exactly as the map view declutters them for the screen
//! (the same `super::declutter::TextBoxes`). The app's export and `run --svg` both come here.

use super::build::{build_scene, SceneInput, ViewOptions};
use super::layer::LayerSet;
use super::primitive::{Primitive, SceneId, Shape};
use super::query::ViewRect;
use super::style::{Rgba, Role, Style};
use super::svg::{default_view, page_world_per_px, to_svg};
use crate::units::Units;

/// Colour of the halo under the selection.
const SELECTION_HALO: Rgba = Rgba::rgb(0xff, 0xb0, 0x20);

/// What a figure shows and how.
#[derive(Clone, Debug, PartialEq)]
pub struct Figure {
    /// The world rectangle shown (metres); `None`: the content (see [`default_view`]).
    pub view: Option<ViewRect>,
    /// The layers drawn.
    pub layers: LayerSet,
    /// Page size, pixels.
    pub size_px: (u32, u32),
    /// Highlighted with a halo (and labelled in the figure style).
    pub selection: SceneId,
    /// The figure style: map labels only for the selection and this step's decisions.
    /// Otherwise: labelled as the screen labels (either way, only what is in the view is
    /// written, and the legend lists only that).
    pub figure_style: bool,
    /// The title over the map (shortened to the page).
    pub title: String,
}

/// The figure of `input` as a standalone SVG document, lengths written in `units`.
pub fn figure_svg(input: &SceneInput, figure: &Figure, units: Units) -> String {
    let view = figure.view.unwrap_or_else(|| {
        let all = build_scene(
            input,
            &ViewOptions {
                layers: figure.layers,
                world_per_px: 0.0,
                visible_m: None,
            },
        );
        default_view(&all)
    });
    let support_of = match figure.selection {
        SceneId::MapSegment(id) | SceneId::Update(id) => Some(id),
        _ => input.support_of,
    };
    let input = input
        .with_support_of(support_of)
        .with_figure_labels(figure.figure_style);
    // Built for the view alone (a huge map costs what the page shows), at the page's scale.
    let options = ViewOptions {
        layers: figure.layers,
        world_per_px: page_world_per_px(view, figure.size_px),
        visible_m: Some([view.min.x, view.min.y, view.max.x, view.max.y]),
    };
    // Only what the view shows: the file holds what is seen, the legend lists only that.
    let mut scene = build_scene(&input, &options).within(view);
    highlight(&mut scene.primitives, figure.selection);
    to_svg(&scene, view, figure.size_px, &figure.title, units)
}

/// Puts a halo under every primitive of the selection (in its layer, just before it).
fn highlight(primitives: &mut Vec<Primitive>, selection: SceneId) {
    if selection == SceneId::None {
        return;
    }
    let mut out = Vec::with_capacity(primitives.len() + 8);
    for p in primitives.drain(..) {
        let outline = matches!(
            p.shape,
            Shape::Segment { .. } | Shape::Polyline { .. } | Shape::Circle { .. }
        );
        if outline && selection.selects(p.id) {
            let mut halo = p.clone();
            halo.id = SceneId::None;
            // A role without a legend entry: the halo is not a kind of thing drawn.
            halo.role = Role::Label;
            halo.style = Style {
                fill: None,
                ..Style::line(SELECTION_HALO, p.style.stroke_width_px.max(1.0) + 6.0)
            }
            .faded(0.6);
            out.push(halo);
        }
        out.push(p);
    }
    *primitives = out;
}
