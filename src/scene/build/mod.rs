//! `build_scene`: one step of a replay → a display list. Pure and allocation-light: it runs
//! every frame in the app. Each layer is built only when it is switched on, and in drawing
//! order, so the output needs no sorting.
//!
//! The layers are drawn by the [`Builder`]'s methods, a file per family: `map` (floor plan,
//! maps before and after, features, truth), `readings` (beams, balls, clusters, points, new
//! segments), `decisions` (updates, decisions, correlations), `robot`, and `labels`.

mod decisions;
mod labels;
mod map;
mod readings;
mod robot;

use super::declutter::TextBoxes;
use super::layer::{Layer, LayerSet};
use super::primitive::{Primitive, SceneId, Shape};
use super::style::Role;
use super::{Scene, ViewRect};
use crate::eval::Verdict;
use crate::geometry::{Point, Pose};
use crate::mapping::model::trace::ReadingTrace;
use crate::mapping::{Map, SegmentId, SegmentKind, StepTrace};
use crate::run::Run;

/// Everything a scene is built from: borrowed, never copied.
#[derive(Clone, Copy, Debug)]
pub struct SceneInput<'a> {
    /// The run (layout, sensor, floor plan, poses; the path so far is
    /// `run.snapshots[..=snapshot]`).
    pub run: &'a Run,
    /// Index `k` of the snapshot shown.
    pub snapshot: usize,
    /// The trace of step `k`.
    pub step: &'a StepTrace,
    /// The trace of step `k − 1`, for the previous snapshot's points.
    pub previous_step: Option<&'a StepTrace>,
    /// The map before step `k`.
    pub map_before: &'a Map,
    /// The map after step `k`.
    pub map_after: &'a Map,
    /// `eval`'s verdict on the fitted segments of `map_after`, when the run has a floor plan
    /// (the truth layer).
    pub truth: Option<&'a [(SegmentId, Verdict)]>,
    /// A map segment whose supporting readings are drawn, from every snapshot they came from.
    pub support_of: Option<SegmentId>,
    /// Figure style: map segments are labelled only when selected (`support_of`) or met by
    /// this step's decisions.
    pub figure_labels: bool,
    /// Every step's pose with pose correction on (the replay's; empty otherwise): the
    /// corrected path.
    pub corrected_path: &'a [crate::replay::StepPose],
}

impl<'a> SceneInput<'a> {
    /// The input for a replayed snapshot of `run`.
    pub fn from_view(run: &'a Run, view: &'a crate::replay::StepView) -> Self {
        SceneInput {
            run,
            snapshot: view.index,
            step: &view.trace,
            previous_step: view.previous.as_ref(),
            map_before: &view.map_before,
            map_after: &view.map_after,
            truth: None,
            support_of: None,
            figure_labels: false,
            corrected_path: &[],
        }
    }

    /// The input with the corrected path of `poses` (the replay's step poses).
    pub fn with_corrected_path(self, poses: &'a [crate::replay::StepPose]) -> Self {
        SceneInput {
            corrected_path: poses,
            ..self
        }
    }

    /// The input with map labels only for the selection and this step's decisions (figures).
    pub fn with_figure_labels(mut self, on: bool) -> Self {
        self.figure_labels = on;
        self
    }

    /// The input with the supporting readings of map segment `id` drawn.
    pub fn with_support_of(mut self, id: Option<SegmentId>) -> Self {
        self.support_of = id;
        self
    }

    /// The input with `eval`'s verdicts on the map after the step (the truth layer).
    pub fn with_truth(mut self, truth: Option<&'a [(SegmentId, Verdict)]>) -> Self {
        self.truth = truth;
        self
    }
}

/// What to draw and at what level of detail.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ViewOptions {
    /// The layers switched on.
    pub layers: LayerSet,
    /// World metres per screen pixel of the view the scene is for; `0` disables
    /// level-of-detail culling. With it, balls smaller than a pixel, end-point dots of
    /// segments shorter than a few pixels and labels of very short segments are skipped.
    pub world_per_px: f64,
    /// The world rectangle the view shows, `[min x, min y, max x, max y]` in metres: the map's
    /// layers (map before and after, truth, map labels) keep only the segments that meet it,
    /// so a frame zoomed in on a huge map costs what it shows. `None`: everything.
    pub visible_m: Option<[f64; 4]>,
}

impl Default for ViewOptions {
    fn default() -> Self {
        ViewOptions {
            layers: LayerSet::all(),
            world_per_px: 0.0,
            visible_m: None,
        }
    }
}

impl ViewOptions {
    /// Every layer, no culling.
    pub fn all() -> Self {
        Self::default()
    }

    /// The options with `layer` switched `on` or off.
    pub fn with_layer(mut self, layer: Layer, on: bool) -> Self {
        self.layers.set(layer, on);
        self
    }
}

/// Builds the display list of step `input.snapshot` (see the module docs).
pub fn build_scene(input: &SceneInput, options: &ViewOptions) -> Scene {
    let mut b = Builder {
        input,
        options,
        out: Vec::with_capacity(estimate(input)),
        culled: Vec::new(),
        map_lines: None,
        texts: TextBoxes::new(options.world_per_px),
        pose: input
            .step
            .pose
            .or_else(|| input.run.snapshots.get(input.snapshot).map(|s| s.pose)),
    };
    for layer in options.layers.iter() {
        match layer {
            Layer::FloorPlan => b.floor_plan(),
            Layer::MapBefore => b.map_before(),
            Layer::Beams => b.beams(),
            Layer::Balls => b.balls(),
            Layer::Clusters => b.clusters(),
            Layer::Updates => b.updates(),
            Layer::Map => {
                b.map_after();
                b.support_points();
            }
            Layer::Features => b.features(),
            Layer::Truth => b.truth(),
            Layer::NewSegments => b.new_segments(),
            Layer::PreviousSnapshot => b.previous_snapshot(),
            Layer::CurrentPoints => b.current_points(),
            Layer::Discarded => b.discarded(),
            Layer::Decisions => b.decisions(),
            Layer::Correlations => b.correlations(),
            Layer::Robot => b.robot(),
            Layer::Labels => b.labels(),
        }
    }
    Scene {
        title: format!("{} — snapshot {}", input.run.name, input.snapshot),
        primitives: b.out,
        culled: b.culled,
    }
}

/// A guess of the primitives a scene holds, to allocate them once.
fn estimate(input: &SceneInput) -> usize {
    let segs = input.map_before.segments.len() + 3 * input.map_after.segments.len();
    let readings = 4 * input.step.readings.len();
    let decisions: usize = input
        .step
        .decisions
        .iter()
        .map(|d| 2 * d.mpc_stage.len() + 1)
        .sum();
    segs + readings + decisions + input.step.new_segments.len() * 2 + 16
}

/// A scene being built: the input, the options and the primitives so far.
struct Builder<'a, 'b> {
    input: &'b SceneInput<'a>,
    options: &'b ViewOptions,
    out: Vec<Primitive>,
    /// The texts placed so far: a label that would cover one is left out.
    texts: TextBoxes,
    pose: Option<Pose>,
    /// The bounding box of what the view rectangle left out, by layer.
    culled: Vec<(Layer, ViewRect)>,
    /// The lines of the map after the step, once a layer needed them.
    map_lines: Option<Vec<MapLine>>,
}

/// What the layers that walk the whole map after the step (map, labels) read of a segment,
/// gathered in one pass: the segments sit behind pointers, all over the heap, and each walk
/// over them fetches every one from memory again (a `paper` map of a long run holds hundreds
/// of thousands).
#[derive(Clone, Copy)]
struct MapLine {
    id: SegmentId,
    kind: SegmentKind,
    a: Point,
    b: Point,
}

impl MapLine {
    /// Length, metres (as [`crate::mapping::model::map::Segment::length`]).
    fn length(&self) -> f64 {
        (self.b - self.a).norm()
    }
}

/// The reading of `sensor` (readings are stored in sensor order; fall back to a search).
fn reading(step: &StepTrace, sensor: usize) -> Option<&ReadingTrace> {
    match step.readings.get(sensor) {
        Some(r) if r.sensor == sensor => Some(r),
        _ => step.readings.iter().find(|r| r.sensor == sensor),
    }
}

/// The middle of `a` and `b`.
fn mid(a: &Point, b: &Point) -> Point {
    nalgebra::center(a, b)
}
impl Builder<'_, '_> {
    /// Adds a primitive of `role`'s style.
    fn push(&mut self, layer: Layer, role: Role, id: SceneId, shape: Shape) {
        self.out.push(Primitive {
            layer,
            role,
            style: role.style(),
            id,
            shape,
        });
    }

    /// `n` screen pixels in world metres (0 without a level of detail).
    fn px(&self, n: f64) -> f64 {
        self.options.world_per_px * n
    }

    /// Whether the segment from `a` to `b` of `layer` meets the visible rectangle (always,
    /// without one); one left out widens the layer's culled box.
    fn shows(&mut self, layer: Layer, a: &Point, b: &Point) -> bool {
        let Some([x0, y0, x1, y1]) = self.options.visible_m else {
            return true;
        };
        if a.x.max(b.x) >= x0 && a.x.min(b.x) <= x1 && a.y.max(b.y) >= y0 && a.y.min(b.y) <= y1 {
            return true;
        }
        match self.culled.iter_mut().find(|(l, _)| *l == layer) {
            Some((_, r)) => {
                r.include(a);
                r.include(b);
            }
            None => {
                let mut r = ViewRect { min: *a, max: *a };
                r.include(b);
                self.culled.push((layer, r));
            }
        }
        false
    }
}
