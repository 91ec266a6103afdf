//! `build_scene`: one step of a replay → a display list. Pure and allocation-light: it runs
//! every frame in the app. Each layer is built only when it is switched on, and in drawing
//! order, so the output needs no sorting.

use super::declutter::{Declutter, TextBoxes};
use super::layer::{Layer, LayerSet};
use super::primitive::{MarkerShape, Primitive, SceneId, Shape, TextAlign};
use super::style::{decision_marker, palette, Role};
use super::{format_length, Scene, ViewRect};
use crate::eval::Verdict;
use crate::geometry::{lerp, projection_param, unit, Point, Pose};
use crate::mapping::model::map::FeatureKind;
use crate::mapping::model::trace::{CorrelationKind, ReadingTrace};
use crate::mapping::{Map, Outcome, SegmentId, SegmentKind, StepTrace};
use crate::run::{Run, Snapshot};
use crate::units::inches;

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

fn mid(a: &Point, b: &Point) -> Point {
    nalgebra::center(a, b)
}

impl Builder<'_, '_> {
    fn push(&mut self, layer: Layer, role: Role, id: SceneId, shape: Shape) {
        self.out.push(Primitive {
            layer,
            role,
            style: role.style(),
            id,
            shape,
        });
    }

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

    fn floor_plan(&mut self) {
        let Some(plan) = &self.input.run.floor_plan else {
            return;
        };
        for w in &plan.walls {
            self.push(
                Layer::FloorPlan,
                Role::FloorPlan,
                SceneId::FloorPlan,
                Shape::Segment { a: w.a, b: w.b },
            );
        }
        for c in &plan.circles {
            let shape = Shape::Circle {
                centre: c.centre,
                radius_m: c.radius_m,
            };
            self.push(Layer::FloorPlan, Role::FloorPlan, SceneId::FloorPlan, shape);
        }
    }

    fn map_before(&mut self) {
        // Under the map after the step, an unchanged segment is hidden by itself: with the map
        // layer on, only what the step moved or removed is drawn. Both maps list their
        // segments by id and share the unchanged ones, so one walk finds what changed.
        let only_changed = self.options.layers.contains(Layer::Map);
        let after = &self.input.map_after.segments;
        let mut j = 0;
        for s in &self.input.map_before.segments {
            // The very segment at the walk's place in the map after is unchanged, known so
            // without fetching either from memory; only a view rectangle needs where it lies
            // (for the culled box).
            if only_changed && after.get(j).is_some_and(|t| std::sync::Arc::ptr_eq(t, s)) {
                j += 1;
                if self.options.visible_m.is_some() {
                    self.shows(Layer::MapBefore, &s.a.point, &s.b.point);
                }
                continue;
            }
            if !self.shows(Layer::MapBefore, &s.a.point, &s.b.point) {
                continue;
            }
            if only_changed {
                while j < after.len() && after[j].id < s.id {
                    j += 1;
                }
                let same = after.get(j).is_some_and(|t| {
                    t.id == s.id
                        && (std::sync::Arc::ptr_eq(t, s)
                            || (t.a.point == s.a.point && t.b.point == s.b.point))
                });
                if same {
                    continue;
                }
            }
            let shape = Shape::Segment {
                a: s.a.point,
                b: s.b.point,
            };
            self.push(
                Layer::MapBefore,
                Role::MapBefore,
                SceneId::MapSegment(s.id),
                shape,
            );
        }
    }

    fn beams(&mut self) {
        let Some(pose) = self.pose else { return };
        let run = self.input.run;
        let half_angle_rad = 0.5 * run.sensor.beam_width_rad;
        let k = self.input.snapshot;
        for r in &self.input.step.readings {
            let (Some(range_m), true) = (r.range_m, r.sensor < run.layout.len()) else {
                continue;
            };
            let sensor = run.layout.sensor_pose_in_world(&pose, r.sensor);
            let apex = sensor.position();
            let id = SceneId::Reading {
                snapshot: k,
                sensor: r.sensor,
            };
            let radius_m = range_m.min(run.sensor.max_range_m);
            // Wedges for kept readings only: a discarded beam at maximum range would dwarf the map.
            if r.discarded.is_none() {
                let heading_rad = sensor.heading_rad;
                let shape = Shape::Wedge {
                    apex,
                    heading_rad,
                    half_angle_rad,
                    radius_m,
                };
                self.push(Layer::Beams, Role::Beam, id, shape);
            }
            let end = apex + unit(sensor.heading_rad) * radius_m;
            self.push(
                Layer::Beams,
                Role::Ray,
                id,
                Shape::Segment {
                    a: apex,
                    b: r.point.unwrap_or(end),
                },
            );
        }
    }

    fn balls(&mut self) {
        let min_radius_m = self.px(0.5);
        let k = self.input.snapshot;
        for r in &self.input.step.readings {
            let (None, Some(centre)) = (r.discarded, r.point) else {
                continue;
            };
            if r.ball_radius_m <= 0.0 || r.ball_radius_m < min_radius_m {
                continue;
            }
            let id = SceneId::Reading {
                snapshot: k,
                sensor: r.sensor,
            };
            self.push(
                Layer::Balls,
                Role::Ball,
                id,
                Shape::Circle {
                    centre,
                    radius_m: r.ball_radius_m,
                },
            );
        }
    }

    fn clusters(&mut self) {
        let step = self.input.step;
        for (i, c) in step.clusters.iter().enumerate() {
            let points: Vec<Point> = c
                .sensors
                .iter()
                .filter_map(|&s| reading(step, s).and_then(|r| r.point))
                .collect();
            let colour = palette::CLUSTERS[i % palette::CLUSTERS.len()];
            let mut style = Role::Cluster.style();
            style.stroke = Some(colour);
            let id = SceneId::Cluster(i);
            let shape = match points.len() {
                0 => continue,
                1 => {
                    style.marker_size_px = 14.0;
                    style.stroke_width_px = 3.0;
                    Shape::Marker {
                        at: points[0],
                        shape: MarkerShape::Ring,
                    }
                }
                _ => Shape::Polyline {
                    points,
                    closed: false,
                },
            };
            self.out.push(Primitive {
                layer: Layer::Clusters,
                role: Role::Cluster,
                style,
                id,
                shape,
            });
        }
        let units = self.input.run.units;
        for g in step.gaps.iter().filter(|g| g.is_break) {
            let from = reading(step, g.from_sensor).and_then(|r| r.point);
            let to = reading(step, g.to_sensor).and_then(|r| r.point);
            let (Some(from), Some(to)) = (from, to) else {
                continue;
            };
            let at = mid(&from, &to);
            self.push(
                Layer::Clusters,
                Role::ClusterBreak,
                SceneId::None,
                Shape::Marker {
                    at,
                    shape: MarkerShape::Plus,
                },
            );
            let text = format!("gap {}", format_length(g.distance_m, units));
            self.push_text(
                Layer::Clusters,
                SceneId::None,
                at,
                text.chars().count(),
                || text,
                [0.0, 8.0],
                TextAlign::Middle,
            );
        }
    }

    fn updates(&mut self) {
        for u in &self.input.step.updates {
            let id = SceneId::Update(u.segment);
            let after = Shape::Segment {
                a: u.after[0].point,
                b: u.after[1].point,
            };
            self.push(Layer::Updates, Role::UpdateAfter, id, after);
            let before = Shape::Segment {
                a: u.before[0].point,
                b: u.before[1].point,
            };
            self.push(Layer::Updates, Role::UpdateBefore, id, before);
            // Duplicates merged into it: their old geometry, ghosted like the segment's own.
            for absorbed in &u.absorbed {
                let shape = Shape::Segment {
                    a: absorbed.ends[0].point,
                    b: absorbed.ends[1].point,
                };
                let id = SceneId::Update(absorbed.into);
                self.push(Layer::Updates, Role::UpdateBefore, id, shape);
            }
            for f in &u.fates {
                if let Some(p) = f.projection {
                    let shape = Shape::Segment {
                        a: f.before.point,
                        b: p,
                    };
                    self.push(Layer::Updates, Role::UpdateProjection, id, shape);
                }
            }
        }
    }

    /// The map's point features (docs/algorithm.md §8.5): a triangle a corner, a diamond an
    /// edge, a circle at its radius a pillar (§8.14).
    fn features(&mut self) {
        for f in self.input.map_after.confirmed_features() {
            if f.radius_m > 0.0 {
                self.push(
                    Layer::Features,
                    Role::FeaturePillar,
                    SceneId::None,
                    Shape::Circle {
                        centre: f.at,
                        radius_m: f.radius_m,
                    },
                );
                continue;
            }
            let (role, shape) = match f.kind {
                FeatureKind::Corner => (Role::FeatureCorner, MarkerShape::Triangle),
                FeatureKind::Edge => (Role::FeatureEdge, MarkerShape::Diamond),
            };
            self.push(
                Layer::Features,
                role,
                SceneId::None,
                Shape::Marker { at: f.at, shape },
            );
        }
    }

    fn map_after(&mut self) {
        let min_len_m = self.px(6.0);
        // End-point dots in a 3 px cell that already has one add nothing at this zoom.
        let mut dots = Declutter::new(self.options.world_per_px, 3.0, 3.0);
        // A segment whose ends fall within 2 px of one already drawn looks the same.
        let mut lines = Declutter::new(self.options.world_per_px, 2.0, 2.0);
        let map_lines = self.take_map_lines();
        for s in &map_lines {
            if !self.shows(Layer::Map, &s.a, &s.b) || !lines.claim_line(&s.a, &s.b) {
                continue;
            }
            let id = SceneId::MapSegment(s.id);
            let role = match s.kind {
                SegmentKind::Fitted if self.input.map_after.is_tentative(s.id) => {
                    Role::MapTentative
                }
                SegmentKind::Fitted => Role::MapFitted,
                SegmentKind::Interpolated => Role::MapInterpolated,
            };
            self.push(Layer::Map, role, id, Shape::Segment { a: s.a, b: s.b });
            if s.kind == SegmentKind::Fitted && s.length() >= min_len_m {
                for at in [s.a, s.b] {
                    if !dots.claim(&at) {
                        continue;
                    }
                    self.push(
                        Layer::Map,
                        Role::MapEndPoint,
                        id,
                        Shape::Marker {
                            at,
                            shape: MarkerShape::Dot,
                        },
                    );
                }
            }
        }
        self.map_lines = Some(map_lines);
    }

    /// The lines of the map after the step (gathered by the first layer to ask; a layer puts
    /// them back in `map_lines` when it is done with them).
    fn take_map_lines(&mut self) -> Vec<MapLine> {
        self.map_lines.take().unwrap_or_else(|| {
            let segments = &self.input.map_after.segments;
            segments
                .iter()
                .map(|s| MapLine {
                    id: s.id,
                    kind: s.kind,
                    a: s.a.point,
                    b: s.b.point,
                })
                .collect()
        })
    }

    /// The supporting readings of the segment asked for, each marked where it was read.
    fn support_points(&mut self) {
        let Some(id) = self.input.support_of else {
            return;
        };
        let seg = self
            .input
            .map_after
            .segment(id)
            .or_else(|| self.input.map_before.segment(id));
        let Some(seg) = seg else {
            return;
        };
        for q in seg.points.iter() {
            let reading = SceneId::Reading {
                snapshot: q.reading.snapshot(),
                sensor: q.reading.sensor(),
            };
            let shape = Shape::Marker {
                at: q.point,
                shape: MarkerShape::Ring,
            };
            self.push(Layer::Map, Role::SupportPoint, reading, shape);
        }
    }

    fn truth(&mut self) {
        let Some(truth) = self.input.truth else {
            return;
        };
        for (id, verdict) in truth {
            let Some(s) = self.input.map_after.segment(*id) else {
                continue;
            };
            if !self.shows(Layer::Truth, &s.a.point, &s.b.point) {
                continue;
            }
            let role = if verdict.is_true() {
                Role::TruthTrue
            } else {
                Role::TruthSpurious
            };
            let shape = Shape::Segment {
                a: s.a.point,
                b: s.b.point,
            };
            self.push(Layer::Truth, role, SceneId::MapSegment(*id), shape);
        }
    }

    fn new_segments(&mut self) {
        for (i, n) in self.input.step.new_segments.iter().enumerate() {
            let shape = Shape::Segment {
                a: n.a.point,
                b: n.b.point,
            };
            self.push(
                Layer::NewSegments,
                Role::NewSegment,
                SceneId::NewSegment(i),
                shape,
            );
        }
    }

    fn previous_snapshot(&mut self) {
        let Some(prev) = self.input.previous_step else {
            return;
        };
        for n in &prev.new_segments {
            let shape = Shape::Segment {
                a: n.a.point,
                b: n.b.point,
            };
            self.push(
                Layer::PreviousSnapshot,
                Role::PreviousSegment,
                SceneId::None,
                shape,
            );
        }
        for r in &prev.readings {
            let (None, Some(at)) = (r.discarded, r.point) else {
                continue;
            };
            let id = SceneId::Reading {
                snapshot: prev.snapshot,
                sensor: r.sensor,
            };
            let shape = Shape::Marker {
                at,
                shape: MarkerShape::Dot,
            };
            self.push(Layer::PreviousSnapshot, Role::PreviousPoint, id, shape);
        }
    }

    fn current_points(&mut self) {
        let k = self.input.snapshot;
        for r in &self.input.step.readings {
            let (None, Some(at)) = (r.discarded, r.point) else {
                continue;
            };
            let id = SceneId::Reading {
                snapshot: k,
                sensor: r.sensor,
            };
            self.push(
                Layer::CurrentPoints,
                Role::CurrentPoint,
                id,
                Shape::Marker {
                    at,
                    shape: MarkerShape::Dot,
                },
            );
        }
    }

    fn discarded(&mut self) {
        let k = self.input.snapshot;
        for r in &self.input.step.readings {
            let (Some(_), Some(at)) = (r.discarded, r.point) else {
                continue;
            };
            let id = SceneId::Reading {
                snapshot: k,
                sensor: r.sensor,
            };
            self.push(
                Layer::Discarded,
                Role::Discarded,
                id,
                Shape::Marker {
                    at,
                    shape: MarkerShape::Cross,
                },
            );
        }
    }

    fn decisions(&mut self) {
        let step = self.input.step;
        for d in &step.decisions {
            let Some(n) = step.new_segments.get(d.new_segment) else {
                continue;
            };
            let from = mid(&n.a.point, &n.b.point);
            let decided = outcome_role(d.outcome);
            for c in &d.mpc_stage {
                let existing = c.evaluation.existing;
                let seg = self
                    .input
                    .map_before
                    .segment(existing)
                    .or_else(|| self.input.map_after.segment(existing));
                let Some(seg) = seg else { continue };
                let t = projection_param(&from, &seg.a.point, &seg.b.point).clamp(0.0, 1.0);
                let to = lerp(&seg.a.point, &seg.b.point, t);
                let role = match d.outcome {
                    Outcome::Match | Outcome::Extension | Outcome::Dismissed
                        if d.existing == Some(existing) =>
                    {
                        decided
                    }
                    _ => Role::DecisionFailed,
                };
                let id = SceneId::Decision {
                    new_segment: d.new_segment,
                    existing: Some(existing),
                };
                self.push(
                    Layer::Decisions,
                    role,
                    id,
                    Shape::Segment { a: from, b: to },
                );
                self.push(
                    Layer::Decisions,
                    role,
                    id,
                    Shape::Marker {
                        at: to,
                        shape: decision_marker(role),
                    },
                );
            }
            let id = SceneId::Decision {
                new_segment: d.new_segment,
                existing: None,
            };
            self.push(
                Layer::Decisions,
                decided,
                id,
                Shape::Marker {
                    at: from,
                    shape: decision_marker(decided),
                },
            );
        }
    }

    fn correlations(&mut self) {
        for (i, c) in self.input.step.correlations.iter().enumerate() {
            let id = SceneId::Correlation(i);
            match c.result {
                CorrelationKind::Corner { point } | CorrelationKind::Shared { point } => {
                    let shape = match c.result {
                        CorrelationKind::Shared { .. } => MarkerShape::Diamond,
                        _ => MarkerShape::Square,
                    };
                    self.push(
                        Layer::Correlations,
                        Role::Corner,
                        id,
                        Shape::Marker { at: point, shape },
                    );
                }
                CorrelationKind::Interpolated { link, .. } => {
                    let Some(s) = self.input.map_after.segment(link) else {
                        continue;
                    };
                    let shape = Shape::Segment {
                        a: s.a.point,
                        b: s.b.point,
                    };
                    self.push(Layer::Correlations, Role::MapInterpolated, id, shape);
                }
                CorrelationKind::None => {}
            }
        }
    }

    /// The robot's path through `path` as polylines: one, unless the view has a level of
    /// detail. Then a stretch between two poses whose ends fall in the 2-pixel cells of a
    /// stretch drawn already is left out, and the path broken there: a patrol goes over the
    /// same ground lap after lap, and each lap drawn again would only add vertices.
    fn path_pieces(&self, path: &[Snapshot]) -> Vec<Vec<Point>> {
        let mut drawn = Declutter::new(self.options.world_per_px, 2.0, 2.0);
        let mut pieces: Vec<Vec<Point>> = Vec::new();
        let mut open = false;
        let Some(first) = path.first() else {
            return pieces;
        };
        // Each pose's cell found once (it ends two stretches).
        let at = |drawn: &Declutter, s: &Snapshot| {
            let p = s.pose.position();
            (p, drawn.cell(&p))
        };
        let mut from = at(&drawn, first);
        for s in &path[1..] {
            let ((a, ca), (b, cb)) = (from, at(&drawn, s));
            from = (b, cb);
            if !drawn.claim_cells(ca, cb) {
                open = false;
                continue;
            }
            if !open {
                pieces.push(vec![a]);
                open = true;
            }
            pieces.last_mut().expect("a piece is open").push(b);
        }
        pieces
    }

    fn robot(&mut self) {
        let run = self.input.run;
        let k = self.input.snapshot;
        let radius_m = run.robot_radius_m.unwrap_or(inches(9.0));
        let path = &run.snapshots[..(k + 1).min(run.snapshots.len())];
        if path.len() >= 2 {
            for points in self.path_pieces(path) {
                self.push(
                    Layer::Robot,
                    Role::RobotPath,
                    SceneId::Robot,
                    Shape::Polyline {
                        points,
                        closed: false,
                    },
                );
            }
            let prev = path[path.len() - 2].pose.position();
            self.push(
                Layer::Robot,
                Role::RobotPrevious,
                SceneId::Robot,
                Shape::Circle {
                    centre: prev,
                    radius_m,
                },
            );
        }
        let Some(pose) = self.pose else { return };
        let centre = pose.position();
        self.push(
            Layer::Robot,
            Role::Robot,
            SceneId::Robot,
            Shape::Circle { centre, radius_m },
        );
        let nose = centre + unit(pose.heading_rad) * radius_m;
        self.push(
            Layer::Robot,
            Role::Robot,
            SceneId::Robot,
            Shape::Segment { a: centre, b: nose },
        );
    }

    /// A text of role [`Role::Label`] of `chars` characters, unless it would cover a text
    /// placed before: `text` makes it only when it is placed.
    #[allow(clippy::too_many_arguments)]
    fn push_text(
        &mut self,
        layer: Layer,
        id: SceneId,
        anchor: Point,
        chars: usize,
        text: impl FnOnce() -> String,
        offset_px: [f32; 2],
        align: TextAlign,
    ) {
        let size_px = Role::Label.style().marker_size_px;
        if self.texts.claim(&anchor, chars, size_px, offset_px, align) {
            let shape = Shape::Text {
                anchor,
                text: text(),
                offset_px,
                align,
            };
            self.push(layer, Role::Label, id, shape);
        }
    }

    fn labels(&mut self) {
        // This step's new segments first: they are what the step is about.
        for (i, n) in self.input.step.new_segments.iter().enumerate() {
            let anchor = mid(&n.a.point, &n.b.point);
            let text = format!("n{i}");
            self.push_text(
                Layer::Labels,
                SceneId::NewSegment(i),
                anchor,
                text.chars().count(),
                || text,
                [-4.0, -14.0],
                TextAlign::End,
            );
        }
        let min_len_m = self.px(12.0);
        let input = self.input;
        let met = |id: SegmentId| {
            input.support_of == Some(id)
                || input
                    .step
                    .decisions
                    .iter()
                    .any(|d| d.existing == Some(id) || d.result == Some(id))
        };
        // The selection first, then the map in order; a label that would cover another is
        // left out (overlapping labels cannot be read).
        let map_lines = self.take_map_lines();
        let selected = input
            .support_of
            .and_then(|id| map_lines.binary_search_by_key(&id, |s| s.id).ok());
        let order = selected
            .into_iter()
            .chain((0..map_lines.len()).filter(|&i| Some(map_lines[i].id) != input.support_of));
        for s in order.map(|i| &map_lines[i]) {
            if s.length() < min_len_m
                || (input.figure_labels && !met(s.id))
                || !self.shows(Layer::Labels, &s.a, &s.b)
            {
                continue;
            }
            // "s" and the id's decimal digits.
            let chars = 2 + s.id.checked_ilog10().unwrap_or(0) as usize;
            self.push_text(
                Layer::Labels,
                SceneId::MapSegment(s.id),
                mid(&s.a, &s.b),
                chars,
                || format!("s{}", s.id),
                [4.0, 4.0],
                TextAlign::Start,
            );
        }
        self.map_lines = Some(map_lines);
    }
}

/// The decision role of an outcome.
fn outcome_role(outcome: Outcome) -> Role {
    match outcome {
        Outcome::Match => Role::DecisionMatch,
        Outcome::Extension => Role::DecisionExtension,
        Outcome::Dismissed => Role::DecisionDismissed,
        Outcome::NewFace => Role::DecisionNewFace,
    }
}
