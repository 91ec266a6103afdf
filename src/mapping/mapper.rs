//! The mapper: one snapshot in, the map updated and the step's trace out (paper §3).

use super::cluster::{cluster_points, sensor_ranks, Clusters};
use super::confirm::{
    baseline_pair, note_baseline_support, note_plane_support, refit_moved_off, supports,
    UnconfirmedTrace, CONFIRMING_BASELINE_M, CONFIRMING_BASELINE_TURN_RAD, CONFIRMING_SNAPSHOTS,
};
use super::corner_diagonals::{
    corner_diagonal, corner_diagonals, DiagonalTrace, CORNER_DIAGONAL_RADIUS_M, CORNER_WALL_REACH_M,
};
use super::correlate::correlate_face;
use super::echo_fit::{
    echo_behind_confirmed_wall, fit_echo_line, order_along_line, place_echoes,
    reflector_beating_line, EchoFitTrace, MIN_ECHO_FIT_READINGS,
};
use super::extensions::{memory_step, reduce_constant_depth_in_place, Linkage};
use super::fast_path::decide;
use super::fit::{piece_end_points, split_recursive};
use super::free_space::refuted_segments;
use super::ids::FeatureId;
use super::map::{FaceId, Map, Segment, SegmentId, SegmentKind, SupportPoint};
use super::matching::{evaluate_pair, Candidate, SegmentEnds};
use super::params::Params;
use super::point_features::{
    arc_point, explaining_feature, explaining_feature_among, file_arc, mean_origin, mean_range_m,
    ArcTrace, Beam,
};
use super::readings::convert_readings;
use super::round_reflectors::note_removed_echoes;
use super::settled_walls::{
    any_settling_wall, settling_wall, NearWall, SettleRule, SETTLED_END_MARGIN_GAPS,
};
use super::support::ReadingRef;
use super::trace::{
    CandidateTrace, ClusterTrace, DecisionTrace, ExplainedTrace, NewSegmentTrace, Outcome,
    RefutedTrace, Rule, SegmentSource, SettledTrace, SplitTrace, StepTrace, UpdateTrace, Warning,
};
use super::update::{apply_update, cap_support_points, grew_past, UpdateRequest};
use crate::geometry::{Point, Pose, RobotFrame, Vec2};
use crate::run::Snapshot;
use crate::sonar::{BeamAxis, EchoModel, SensorLayout, SensorSpec};
use std::ops::Range;

/// Most confirmed point features §8.5's explained readings search one by one; more are
/// searched through the map's grid.
const MAX_FEATURES_SEARCHED_DIRECTLY: usize = 64;

/// Runs the paper's algorithm snapshot by snapshot.
#[derive(Clone, Debug)]
pub struct Mapper {
    params: Params,
    layout: SensorLayout,
    sensor: SensorSpec,
    /// Each sensor's place in the layout's bearing order, and whether that order wraps.
    bearing_ranks: (Vec<usize>, bool),
    /// Each sensor's beam axis in the robot frame.
    beam_axes: Vec<BeamAxis>,
    map: Map,
    last_pose: Option<Pose>,
    /// The robot frame of the step's pose: a step's beams are turned into the world with it
    /// (one sine and cosine a step, not one a beam).
    step_frame: Option<(Pose, RobotFrame)>,
    next_snapshot: usize,
    brute_force: bool,
    record_trace: bool,
    /// Buffers each step fills and the next reuses.
    buffers: StepBuffers,
}

/// What one decision of a step was, enough to take it again without testing candidates
/// ([`Mapper::step_as_recorded`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RecordedDecision {
    /// The outcome.
    pub outcome: Outcome,
    /// The rule that decided it.
    pub rule: Rule,
    /// The existing segment it named.
    pub existing: Option<SegmentId>,
    /// For a MATCH or EXTENSION that updated a segment: whether the updated segment's
    /// supporting points failed the post-update test, so that it was fitted afresh
    /// (docs/algorithm.md §5). Taken again, a pass spares the test over every point.
    pub refit: Option<bool>,
    /// For an update: whether the segment's supporting points were in order along the updated
    /// line ([`UpdateTrace::support_in_order`]). Taken again, spares the pass that finds it.
    pub support_in_order: Option<bool>,
}

impl RecordedDecision {
    /// What `decision` was, with the step's `updates`.
    pub fn of(decision: &DecisionTrace, updates: &[UpdateTrace]) -> Self {
        let update = updates
            .iter()
            .find(|u| u.new_segment == decision.new_segment);
        Self {
            outcome: decision.outcome,
            rule: decision.rule,
            existing: decision.existing,
            refit: update.map(|u| u.refit.is_some()),
            support_in_order: update.and_then(|u| u.support_in_order),
        }
    }
}

/// Buffers one step fills and the next reuses, so that an untraced step allocates little. What
/// the trace keeps is copied out of them (or built in its own vectors) only when tracing.
#[derive(Clone, Debug, Default)]
struct StepBuffers {
    /// The kept points.
    kept: Vec<SupportPoint>,
    clusters: Clusters,
    /// The confirmed walls near a reading (§8.12, scratch).
    near_walls: Vec<NearWall>,
    /// Point memory's linkage (§8.1, scratch).
    linkage: Linkage,
    /// The wall that settled each sensor's last settled reading (§8.12), tried first.
    settled_by: Vec<Option<SegmentId>>,
    /// A cluster's points as fitted (untraced).
    fitted: Vec<SupportPoint>,
    /// A cluster's split tests (untraced).
    splits: Vec<SplitTrace>,
    /// A cluster's pieces.
    pieces: Vec<[usize; 2]>,
    /// Every new segment's candidates, one set after another.
    candidates: Vec<Candidate>,
    /// Each new segment's range in `candidates`.
    candidate_sets: Vec<Range<usize>>,
    /// A decision's tested candidates (untraced).
    mpc_stage: Vec<CandidateTrace>,
    /// The readings of earlier snapshots point memory's pieces brought to this step.
    memory_readings: Vec<ReadingRef>,
    /// The confirmed point features, with where they stand and their radius (§8.5, scratch).
    confirmed_features: Vec<(FeatureId, Point, f64)>,
}

/// The mutable state a checkpoint needs to resume a [`Mapper`].
#[derive(Clone, Debug)]
pub struct MapperState {
    /// The map.
    pub map: Map,
    /// Pose of the last snapshot applied.
    pub last_pose: Option<Pose>,
    /// Index of the next snapshot.
    pub next_snapshot: usize,
}

impl Mapper {
    /// A mapper with an empty map. `params` should be valid (see [`Params::validate`]).
    pub fn new(params: Params, layout: SensorLayout, sensor: SensorSpec) -> Self {
        let (order, wraps) = layout.bearing_order();
        let bearing_ranks = (sensor_ranks(&order), wraps);
        let beam_axes = layout.beam_axes();
        let confirms_segments = params.confirm_segments;
        let mut map = Map::confirming(confirms_segments);
        map.tracks_links = params.merge_duplicates || params.free_space;
        Self {
            params,
            layout,
            sensor,
            bearing_ranks,
            beam_axes,
            map,
            last_pose: None,
            step_frame: None,
            next_snapshot: 0,
            brute_force: false,
            record_trace: true,
            buffers: StepBuffers::default(),
        }
    }

    /// With `false`, steps return a slim trace: readings, decisions (without their candidate
    /// lists), updates, correlations, free-space removals and warnings; no gaps, clusters, splits, new-segment
    /// geometry or point-memory record. The map is the same either way.
    pub fn with_trace(mut self, on: bool) -> Self {
        self.set_trace(on);
        self
    }

    /// Switches the full trace on or off for the steps to come (see [`Mapper::with_trace`]).
    pub fn set_trace(&mut self, on: bool) {
        self.record_trace = on;
    }

    /// Whether steps return the full trace.
    pub fn records_trace(&self) -> bool {
        self.record_trace
    }

    /// Tests every map segment as a candidate instead of searching the spatial index (the
    /// reference the pruning is checked against; same decisions, longer traces).
    pub fn with_brute_force_search(mut self, on: bool) -> Self {
        self.brute_force = on;
        self
    }

    /// The map segments that could pass a test against `new` (docs/algorithm.md §4 pruning).
    ///
    /// Every passing case needs colinearity (`|d| ≤ thr`, `thr ≤ ξ/100·(D_max + (D2+D3)/2)`
    /// with `D_max` the largest end-point range in the map; `d` from `l_n`'s mid-point `m` to
    /// `l_e`'s line) and an overlap. With `h` half `l_n`'s length and `φ` the angle between
    /// the lines:
    /// - MPC: `m` projects into `l_e`, so `l_e` passes within `thr` of `m`;
    /// - EPC: an end-point `e = m ± h·u_n` projects into `l_e`, so `l_e` passes within
    ///   `|d| + h·sin φ ≤ thr + h` of `e`;
    /// - containment (it only counts with orientation, `φ ≤ θ_o`): an end-point `p` of `l_e`
    ///   projects into `l_n`; writing `p = f + s·u_e` with `f` the foot of `m` on `l_e`'s line,
    ///   `|s| ≤ (h + thr)/cos φ`, so `p` lies within `thr + (h + thr)·tan θ_o` of `l_n`.
    ///
    /// So a segment that can pass, fail only orientation, or match meets the box around `l_n`
    /// widened by `R = max(thr + h, thr + (h + thr)·tan θ_o)`, and lies within `R + h` of `m`;
    /// only those are tested.
    fn candidates_for(&self, new: &SegmentEnds, candidates: &mut Vec<Candidate>) {
        let reach_m = if self.brute_force {
            f64::INFINITY
        } else {
            candidate_reach_m(&self.params, self.map.max_end_range_m, new)
        };
        let radius_m = reach_m + (new.b.point - new.a.point).norm() / 2.0;
        self.map
            .visit_segments_along(&new.a.point, &new.b.point, reach_m, |id, s| {
                if s.fitted {
                    let c = Candidate::new(new, id, SegmentEnds { a: s.a, b: s.b }, s.face);
                    if radius_m.is_infinite() || c.distance_m <= radius_m {
                        candidates.push(c);
                    }
                }
            });
    }

    /// The map as it stands.
    pub fn map(&self) -> &Map {
        &self.map
    }

    /// The parameters.
    pub fn params(&self) -> &Params {
        &self.params
    }

    /// The map segments the last step offered its new segments as candidates, summed over them:
    /// the step's matching work (what grows with a map that piles up copies of its walls).
    pub fn last_step_candidates(&self) -> usize {
        self.buffers.candidates.len()
    }

    /// Index the next step will get.
    pub fn next_snapshot(&self) -> usize {
        self.next_snapshot
    }

    /// A copy of the state (for checkpoints): segments are shared, the index is left out.
    pub fn state(&self) -> MapperState {
        MapperState {
            map: self.map.without_index(),
            last_pose: self.last_pose,
            next_snapshot: self.next_snapshot,
        }
    }

    /// [`Mapper::state`] with its map's list of segments left empty, and that list: a
    /// checkpoint keeps the segments its own way ([`crate::checkpoints::Checkpoints::push_apart`])
    /// and needs no copy of the list.
    pub fn state_apart(&self) -> (MapperState, &[std::sync::Arc<Segment>]) {
        let state = MapperState {
            map: self.map.without_index_or_segments(),
            last_pose: self.last_pose,
            next_snapshot: self.next_snapshot,
        };
        (state, &self.map.segments)
    }

    /// Resumes from `state`, whose map has its spatial index built (a checkpoint made live:
    /// [`crate::checkpoints::Checkpoints::live_before`]).
    pub fn resume(&mut self, state: MapperState) {
        self.buffers.linkage.forget();
        self.map = state.map;
        self.last_pose = state.last_pose;
        self.next_snapshot = state.next_snapshot;
    }

    /// Resumes from a state taken by [`Mapper::state`] (its map shared, not moved: see
    /// [`Map::with_index`]); the replay's checkpoints resume through [`Mapper::resume`].
    pub fn restore(&mut self, state: &MapperState) {
        self.buffers.linkage.forget();
        self.map = state.map.with_index();
        self.last_pose = state.last_pose;
        self.next_snapshot = state.next_snapshot;
    }

    /// An empty vector for what a step traces: a new one (with room for `capacity`) when
    /// tracing, since the trace keeps it; otherwise `buffer`'s, to be put back after use.
    fn fresh_or_reused<T>(&self, buffer: &mut Vec<T>, capacity: usize) -> Vec<T> {
        if self.record_trace {
            Vec::with_capacity(capacity)
        } else {
            let mut reused = std::mem::take(buffer);
            reused.clear();
            reused
        }
    }

    /// [`Mapper::step`] taking the decisions (docs/algorithm.md §4) as `decisions` recorded
    /// them when this step first ran from the same state, instead of testing candidates: the
    /// same map, for a fraction of the cost on a large map (the replay catches up this way
    /// between a checkpoint and the snapshot shown). Everything else (fitting, the updates, the
    /// extensions, correlation) runs as in `step`. With another number of decisions than new
    /// segments, it decides afresh.
    pub fn step_as_recorded(
        &mut self,
        snapshot: &Snapshot,
        decisions: &[RecordedDecision],
    ) -> StepTrace {
        self.step_with(snapshot, Some(decisions))
    }

    /// Applies one snapshot and returns what happened: the paper's §3 as a pipeline.
    pub fn step(&mut self, snapshot: &Snapshot) -> StepTrace {
        self.step_with(snapshot, None)
    }

    /// [`Mapper::step`], taking the decisions from `recorded` when given.
    fn step_with(
        &mut self,
        snapshot: &Snapshot,
        recorded: Option<&[RecordedDecision]>,
    ) -> StepTrace {
        let mut trace = self.begin_step(snapshot);
        let mut buffers = std::mem::take(&mut self.buffers);
        self.readings_and_clusters(snapshot, &mut trace, &mut buffers);
        let mut fitted = self.fit_clusters(&mut trace, &mut buffers);
        buffers.memory_readings.clear();
        if self.params.memory_snapshots > 0 {
            self.fit_remembered_points(
                &mut fitted,
                &mut trace,
                &mut buffers.memory_readings,
                &mut buffers.linkage,
            );
        }
        let new_faces =
            self.match_and_update(&mut fitted.segments, recorded, &mut trace, &mut buffers);
        if self.params.confirm_segments {
            if self.params.refit_unconfirms {
                self.unconfirm_moved_refits(&mut trace);
            }
            self.note_plane_support(snapshot, &fitted.segments, &mut trace);
            if self.params.baseline_confirm && !buffers.memory_readings.is_empty() {
                self.note_baseline_support(snapshot, &buffers.memory_readings, &mut trace);
            }
        }
        self.buffers = buffers;
        if self.record_trace {
            trace.new_segments = fitted.segments;
        }
        if self.params.correlate {
            self.correlate_new_faces(new_faces, &mut trace);
        }
        if self.params.free_space {
            self.remove_refuted(snapshot, &mut trace);
        }
        if self.params.corner_diagonals {
            self.remove_corner_diagonals(&mut trace);
        }
        // Kept in the slim trace too: the lineage of a link reads its removal there.
        trace.dropped_links = self.map.drop_dangling_links();
        trace
    }

    /// §8.7 confirmation: each segment this step's new segments matched, extended or made
    /// hears of the plane support of their readings.
    fn note_plane_support(
        &mut self,
        snapshot: &Snapshot,
        new_segments: &[NewSegmentTrace],
        trace: &mut StepTrace,
    ) {
        let (xi, half) = self.accuracy_and_half_beam();
        let cone_edges = self.cone_edges();
        let targets: Vec<(usize, SegmentId)> = trace
            .decisions
            .iter()
            .filter_map(|d| d.result.map(|r| (d.new_segment, r)))
            .collect();
        for (ni, target) in targets {
            let now = |q: &&SupportPoint| q.reading.snapshot() == trace.snapshot;
            let beam = |q: &SupportPoint| (q.reading.sensor(), self.beam_of(&snapshot.pose, q));
            let beams: Vec<(usize, Beam)> = match new_segments.get(ni) {
                Some(n) if !n.points.is_empty() => n.points.iter().filter(now).map(beam).collect(),
                // Untraced, a new face's points moved into the map segment.
                _ => match self.map.segment(target) {
                    Some(s) => s.points.iter().filter(now).map(beam).collect(),
                    None => continue,
                },
            };
            if let Some(t) = note_plane_support(
                &mut self.map,
                target,
                &beams,
                trace.snapshot,
                xi,
                half,
                cone_edges,
            ) {
                if self.record_trace {
                    trace.plane_support.push(t);
                }
            }
        }
    }

    /// §8.7 `refit_unconfirms`: a confirmed segment that a refit of this step moved off its
    /// line ([`refit_moved_off`]) is tentative again.
    fn unconfirm_moved_refits(&mut self, trace: &mut StepTrace) {
        for u in &trace.updates {
            if u.refit.is_none() || !self.map.is_confirmed(u.segment) {
                continue;
            }
            let Some(s) = self.map.segment(u.segment) else {
                continue;
            };
            let before = [u.before[0].point, u.before[1].point];
            let moved = refit_moved_off(
                before,
                [s.a, s.b],
                self.params.accuracy_pct,
                self.params.orientation_rad,
            );
            if let Some(moved) = moved {
                self.map.plane_support.remove(&u.segment);
                // Kept in the slim trace too: the lineage of a segment reads it there.
                trace.unconfirmed.push(UnconfirmedTrace {
                    segment: u.segment,
                    ..moved
                });
            }
        }
    }

    /// §8.7 baseline confirmation: each segment this step made (a NEW FACE) is confirmed when
    /// two of its readings of distinct snapshots (this snapshot's, and those of earlier
    /// snapshots that point memory's pieces brought, `memory_readings`), each from its own
    /// snapshot's pose, support it as a plane from sensors at least [`CONFIRMING_BASELINE_M`]
    /// apart along it, within [`CONFIRMING_BASELINE_TURN_RAD`] of its direction.
    fn note_baseline_support(
        &mut self,
        snapshot: &Snapshot,
        memory_readings: &[ReadingRef],
        trace: &mut StepTrace,
    ) {
        let (xi, half) = self.accuracy_and_half_beam();
        let cone_edges = self.cone_edges();
        // Made this step: a MATCH's or an EXTENSION's target holds readings of earlier steps
        // that were tested when they came.
        let mut targets: Vec<SegmentId> = trace
            .decisions
            .iter()
            .filter(|d| d.outcome == Outcome::NewFace)
            .filter_map(|d| d.result)
            .collect();
        targets.sort_unstable();
        targets.dedup();
        for target in targets {
            if !self.map.is_tentative(target) {
                continue;
            }
            let Some(s) = self.map.segment(target) else {
                continue;
            };
            let beams: Vec<(ReadingRef, Beam)> = s
                .points
                .iter()
                .filter_map(|q| {
                    let beam = if q.reading.snapshot() == trace.snapshot {
                        self.beam_of(&snapshot.pose, q)
                    } else if memory_readings.contains(&q.reading) {
                        self.recent_beam_of(q)?
                    } else {
                        return None;
                    };
                    Some((q.reading, beam))
                })
                .collect();
            let (a, b) = (s.a.point, s.b.point);
            let Some(pair) = baseline_pair(
                &beams,
                &a,
                &b,
                xi,
                half,
                cone_edges,
                CONFIRMING_BASELINE_M,
                CONFIRMING_BASELINE_TURN_RAD,
            ) else {
                continue;
            };
            let Some(&(_, later)) = beams.iter().find(|(r, _)| *r == pair.readings[1]) else {
                continue;
            };
            if let Some(t) =
                note_baseline_support(&mut self.map, target, pair, &later, trace.snapshot)
            {
                if self.record_trace {
                    trace.plane_support.push(t);
                }
            }
        }
    }

    /// The sonar's accuracy ξ (%) and the half-width of its beam (radians), which every test of
    /// a reading against a plane or a reflector takes (docs/algorithm.md §8.5–§8.10).
    fn accuracy_and_half_beam(&self) -> (f64, f64) {
        (self.params.accuracy_pct, self.sensor.beam_width_rad / 2.0)
    }

    /// Whether the plane tests of §8.7 take echoes from the cone's edges too (§8.10: echo
    /// placement on, for a sensor whose echoes come from its whole cone).
    fn cone_edges(&self) -> bool {
        self.params.echo_fit && self.sensor.echo == EchoModel::Cone
    }

    /// §8.7 plane gate: whether a reading of `new` supports it as a plane
    /// ([`crate::mapping::confirm::supports_as_plane`]), each from its own snapshot's pose
    /// (point memory's readings are at most `memory_snapshots` old).
    fn plane_gate(&self, new: &NewSegmentTrace) -> bool {
        let (xi, half) = self.accuracy_and_half_beam();
        new.points.iter().any(|q| {
            let Some(beam) = self.recent_beam_of(q) else {
                return false;
            };
            supports(
                &beam,
                &new.a.point,
                &new.b.point,
                xi,
                half,
                self.cone_edges(),
            )
            .is_some()
        })
    }

    /// Whether a reading among `points` (of the snapshot at `pose`) supports the segment
    /// `a`–`b` as a plane (docs/algorithm.md §8.7).
    fn supports_as_plane_now(
        &self,
        pose: &Pose,
        points: &[SupportPoint],
        a: &Point,
        b: &Point,
    ) -> bool {
        let (xi, half) = self.accuracy_and_half_beam();
        points
            .iter()
            .any(|q| supports(&self.beam_of(pose, q), a, b, xi, half, self.cone_edges()).is_some())
    }

    /// §8.6 free space: the segments a kept reading of this snapshot saw past leave the map.
    fn remove_refuted(&mut self, snapshot: &Snapshot, trace: &mut StepTrace) {
        let (xi, half) = self.accuracy_and_half_beam();
        let mut found = Vec::new();
        // §8.12: a settled reading has left `kept`; the space in front of its wall was swept.
        let kept = std::mem::take(&mut self.buffers.kept);
        for q in &kept {
            let beam = self.beam_of(&snapshot.pose, q);
            refuted_segments(&self.map, &beam, xi, half, &mut found);
            // Kept in the slim trace too: the lineage of a segment reads its removal there.
            for &(segment, distance_m, off_axis_rad) in &found {
                self.map.remove_segment(segment);
                trace.refuted.push(RefutedTrace {
                    segment,
                    sensor: q.reading.sensor(),
                    range_m: q.range_m,
                    distance_m,
                    off_axis_rad,
                });
            }
        }
        self.buffers.kept = kept;
    }

    /// §8.11: the segments that can make a corner that was not there before (made, grown or
    /// confirmed this step), and the segments near their end-points, that stand across a
    /// corner of two walls of the map (one confirmed) leave the map.
    fn remove_corner_diagonals(&mut self, trace: &mut StepTrace) {
        // Made this step (a new face, or a refit's piece), grown past their old end-points (or
        // by a duplicate they absorbed), or confirmed this step.
        let made = trace
            .decisions
            .iter()
            .filter(|d| d.outcome == Outcome::NewFace)
            .filter_map(|d| d.result);
        let changed = trace.updates.iter().flat_map(|u| {
            let grew = grew_past(&u.before, &u.after) || !u.absorbed.is_empty();
            let pieces = u.refit.iter().flat_map(|r| r.pieces.iter().copied());
            grew.then_some(u.segment).into_iter().chain(pieces)
        });
        let snapshot = trace.snapshot;
        let matched = trace.decisions.iter().filter_map(|d| d.result);
        let confirmed_now = matched.filter(|id| {
            self.map
                .plane_support
                .get(id)
                .is_some_and(|p| p.snapshots == CONFIRMING_SNAPSHOTS && p.last_snapshot == snapshot)
        });
        let new_corners: Vec<SegmentId> = made.chain(changed).chain(confirmed_now).collect();
        let found = corner_diagonals(
            &self.map,
            &new_corners,
            CORNER_DIAGONAL_RADIUS_M,
            CORNER_WALL_REACH_M,
            self.params.orientation_rad,
        );
        for d in found {
            self.remove_diagonal(d, trace);
        }
    }

    /// §8.11 at birth: new face `id`, just filed, leaves the map at once when it stands across
    /// a corner of the map as it is; what the step does next (correlation, plane support, free
    /// space) would be undone when the step's end found it (docs/algorithm.md §8.11).
    fn remove_if_diagonal_at_birth(&mut self, id: SegmentId, trace: &mut StepTrace) {
        let found = corner_diagonal(
            &self.map,
            id,
            CORNER_DIAGONAL_RADIUS_M,
            CORNER_WALL_REACH_M,
            self.params.orientation_rad,
        );
        if let Some(d) = found {
            self.remove_diagonal(d, trace);
        }
    }

    /// Removes the corner diagonal `d` from the map and records it; its readings, with their
    /// sensors' poses, are evidence of a pillar (§8.14; a specular sonar's: the axis model
    /// places echoes on the axes).
    fn remove_diagonal(&mut self, d: DiagonalTrace, trace: &mut StepTrace) {
        let pillars = self.params.round_reflectors && self.sensor.echo != EchoModel::Axis;
        let echoes: Vec<Beam> = match self.map.segment(d.segment) {
            Some(s) if pillars => s
                .points
                .iter()
                .filter_map(|q| self.recent_beam_of(q))
                .collect(),
            _ => Vec::new(),
        };
        self.map.remove_segment(d.segment);
        // Kept in the slim trace too: the lineage of a segment reads its removal there.
        trace.diagonals.push(d);
        let (xi, half) = self.accuracy_and_half_beam();
        if let Some(t) = note_removed_echoes(&mut self.map, &echoes, trace.snapshot, xi, half) {
            trace.round_reflectors.push(t);
        }
    }

    /// A step's trace with its snapshot, and the warnings of §4: the robot moved more than
    /// `max_step` (the paper's matching is valid only below it), or the snapshot has another
    /// number of ranges than the layout has sensors.
    fn begin_step(&mut self, snapshot: &Snapshot) -> StepTrace {
        let index = self.next_snapshot;
        self.next_snapshot += 1;
        let mut trace = StepTrace {
            snapshot: index,
            t: snapshot.t,
            pose: Some(snapshot.pose),
            ..Default::default()
        };
        if let Some(last) = self.last_pose {
            let step_m = last.distance_to(&snapshot.pose);
            if step_m > self.params.max_step_m {
                trace.warnings.push(Warning::MaxStep {
                    step_m,
                    max_step_m: self.params.max_step_m,
                });
            }
        }
        self.last_pose = Some(snapshot.pose);
        self.step_frame = Some((snapshot.pose, snapshot.pose.robot_frame()));
        if self.params.plane_gate || self.params.echo_fit || self.params.baseline_confirm {
            let keep = self.params.memory_snapshots + 1;
            self.map.note_pose(index, snapshot.pose, keep);
        }
        if snapshot.ranges_m.len() != self.layout.len() {
            trace.warnings.push(Warning::RangeCount {
                given: snapshot.ranges_m.len(),
                expected: self.layout.len(),
            });
        }
        trace
    }

    /// §1: readings to points (kept into `buffers.kept`); §2: the kept points clustered (into
    /// `buffers.clusters`).
    fn readings_and_clusters(
        &self,
        snapshot: &Snapshot,
        trace: &mut StepTrace,
        buffers: &mut StepBuffers,
    ) {
        trace.readings = convert_readings(
            trace.snapshot,
            &snapshot.pose,
            &snapshot.ranges_m,
            &self.beam_axes,
            self.sensor.max_range_m,
            &self.params,
            &mut buffers.kept,
        );
        let (ranks, wraps) = (&self.bearing_ranks.0, self.bearing_ranks.1);
        if self.params.explain_readings {
            self.drop_explained_readings(
                snapshot,
                trace,
                &mut buffers.kept,
                &mut buffers.confirmed_features,
            );
        }
        if self.params.settled_walls {
            self.set_aside_settled_readings(snapshot, trace, buffers);
        }
        cluster_points(
            &buffers.kept,
            ranks,
            wraps,
            self.params.t_gap_m,
            &mut buffers.clusters,
        );
        if self.record_trace {
            trace.gaps = buffers.clusters.gaps.clone();
        }
    }

    /// The world beam of reading `q`, from the pose of its snapshot when that is among the
    /// recent ones the map keeps (docs/algorithm.md §8.7, §8.10).
    fn recent_beam_of(&self, q: &SupportPoint) -> Option<Beam> {
        let pose = self.map.recent_pose(q.reading.snapshot())?;
        Some(self.beam_of(&pose, q))
    }

    /// The world beam of kept point `q` of a snapshot at `pose`.
    /// Its direction is the sensor's axis, wherever the point was placed (§8.10 moves points
    /// off their axes).
    fn beam_of(&self, pose: &Pose, q: &SupportPoint) -> Beam {
        let frame = match self.step_frame {
            Some((step_pose, frame)) if step_pose == *pose => frame,
            _ => pose.robot_frame(),
        };
        let axis = &self.beam_axes[q.reading.sensor()];
        Beam {
            origin: frame.to_world(&axis.origin_in_robot),
            direction: frame.direction_to_world(&axis.direction_in_robot),
            range_m: q.range_m,
        }
    }

    /// §8.5 explained readings: the kept points a confirmed point feature explains leave
    /// `kept` (each looks only at the features filed near its own point).
    fn drop_explained_readings(
        &self,
        snapshot: &Snapshot,
        trace: &mut StepTrace,
        kept: &mut Vec<SupportPoint>,
        confirmed: &mut Vec<(FeatureId, Point, f64)>,
    ) {
        // Only a confirmed feature explains a reading. A few are searched through directly,
        // many through the grid.
        confirmed.clear();
        confirmed.extend(
            self.map
                .confirmed_features()
                .map(|f| (f.id, f.at, f.radius_m)),
        );
        if confirmed.is_empty() {
            return;
        }
        let (xi, half) = self.accuracy_and_half_beam();
        let mut scratch = Vec::new();
        kept.retain(|q| {
            let beam = self.beam_of(&snapshot.pose, q);
            let id = if confirmed.len() <= MAX_FEATURES_SEARCHED_DIRECTLY {
                explaining_feature_among(confirmed, &beam, xi, half)
            } else {
                explaining_feature(&self.map, &beam, xi, half, &mut scratch)
            };
            let Some(id) = id else {
                return true;
            };
            if self.record_trace {
                let at = self.map.feature(id).map_or(beam.origin, |f| f.at);
                let v = at - beam.origin;
                trace.explained.push(ExplainedTrace {
                    sensor: q.reading.sensor(),
                    range_m: q.range_m,
                    feature: id,
                    feature_distance_m: v.norm(),
                    off_axis_rad: (v.dot(&beam.direction) / v.norm().max(1e-12))
                        .clamp(-1.0, 1.0)
                        .acos(),
                });
            }
            false
        });
    }

    /// §8.12 settled walls: the kept points a confirmed wall explains well inside its ends (at
    /// least [`SETTLED_END_MARGIN_GAPS`] memory gaps from either end) leave `buffers.kept`:
    /// they join no cluster, no point memory and no free-space sweep.
    fn set_aside_settled_readings(
        &self,
        snapshot: &Snapshot,
        trace: &mut StepTrace,
        buffers: &mut StepBuffers,
    ) {
        if self.map.plane_support.is_empty() {
            return;
        }
        let (accuracy_pct, half_beam_rad) = self.accuracy_and_half_beam();
        let rule = SettleRule::new(
            accuracy_pct,
            half_beam_rad,
            self.cone_edges(),
            SETTLED_END_MARGIN_GAPS * self.params.memory_gap_m,
        );
        let (near, settled_by) = (&mut buffers.near_walls, &mut buffers.settled_by);
        settled_by.resize(self.layout.len(), None);
        buffers.kept.retain(|q| {
            let beam = self.beam_of(&snapshot.pose, q);
            let hint = settled_by.get(q.reading.sensor()).copied().flatten();
            // Traced, the wall that predicts the range best, for the trace; untraced, any.
            let segment = if self.record_trace {
                let Some((segment, predicted_m, inside_m)) =
                    settling_wall(&self.map, &beam, &rule, near)
                else {
                    return true;
                };
                trace.settled.push(SettledTrace {
                    sensor: q.reading.sensor(),
                    range_m: q.range_m,
                    segment,
                    predicted_m,
                    inside_m,
                });
                segment
            } else {
                let found = any_settling_wall(&self.map, &beam, &rule, hint, near);
                let Some(segment) = found else {
                    return true;
                };
                segment
            };
            if let Some(slot) = settled_by.get_mut(q.reading.sensor()) {
                *slot = Some(segment);
            }
            false
        });
    }

    /// §8.5 arc rule on cluster `ci` (`chain` in order): when it is an arc, its point is filed
    /// as a point feature; true when the cluster is then not fitted (one plane does not explain
    /// its ranges as well).
    fn file_if_arc(&mut self, ci: usize, chain: &[SupportPoint], trace: &mut StepTrace) -> bool {
        let Some(pose) = trace.pose else {
            return false;
        };
        // An arc takes two readings at least (`arc_point`); most clusters are one.
        if chain.len() < 2 {
            return false;
        }
        let beams: Vec<Beam> = chain.iter().map(|q| self.beam_of(&pose, q)).collect();
        let sensors: Vec<usize> = chain.iter().map(|q| q.reading.sensor()).collect();
        let Some((at, range_m)) = arc_point(&beams, &sensors, self.params.accuracy_pct) else {
            return false;
        };
        // A plane facing the sensors' bisector reads the same range to each of them too: an
        // arc whose chord a reading supports as a plane stays a line.
        let (first, last) = (chain[0].point, chain[chain.len() - 1].point);
        if self.supports_as_plane_now(&pose, chain, &first, &last) {
            return false;
        }
        // With echo placement (§8.10) on for a cone sensor: a plane seen square-on by
        // neighbouring sonars reads (nearly) one range to each, at its foot or its cone's edge.
        // When one plane explains every range at least as well as one reflector point, the
        // cluster is both: filed as a reflector observation (its feature is confirmed only if
        // it stays put as the robot moves, as a corner does) and fitted.
        let mut also_fitted = false;
        if self.params.echo_fit && self.sensor.echo == EchoModel::Cone {
            let (xi, half) = self.accuracy_and_half_beam();
            let axis_points: Vec<Point> = chain.iter().map(|q| q.point).collect();
            let turn = self.params.orientation_rad;
            if let Some(line) = fit_echo_line(&beams, &axis_points, xi, half, turn) {
                also_fitted = reflector_beating_line(&beams, &line, at, xi, half).is_none();
            }
        }
        let origin = mean_origin(&beams);
        let (feature, new_feature) = file_arc(
            &mut self.map,
            at,
            range_m,
            &origin,
            trace.snapshot,
            self.params.accuracy_pct,
        );
        if self.record_trace {
            trace.arcs.push(ArcTrace {
                cluster: ci,
                sensors,
                range_min_m: beams
                    .iter()
                    .map(|b| b.range_m)
                    .fold(f64::INFINITY, f64::min),
                range_max_m: beams.iter().map(|b| b.range_m).fold(0.0, f64::max),
                at,
                feature,
                new_feature,
                also_fitted,
            });
        }
        !also_fitted
    }

    /// §3: each cluster fitted by the recursive end-point fit (after constant-depth groups,
    /// §8.2, when on; a closed loop, §2, repeats its first point at the end). Returns the new
    /// segments in cluster order and the points of one-point clusters.
    fn fit_clusters(&mut self, trace: &mut StepTrace, buffers: &mut StepBuffers) -> FittedStep {
        let params = self.params.clone();
        let params = &params;
        let StepBuffers {
            kept,
            clusters,
            fitted: fitted_buffer,
            splits: splits_buffer,
            pieces,
            ..
        } = buffers;
        let wraps = self.bearing_ranks.1;
        let chain_has_break = clusters.gaps.iter().any(|g| g.is_break);
        let mut out = FittedStep {
            segments: Vec::new(),
            singles: Vec::new(),
        };
        for (ci, members) in clusters.iter().enumerate() {
            let mut chain = self.fresh_or_reused(fitted_buffer, members.len() + 1);
            chain.extend(members.iter().map(|&i| kept[i]));
            for q in &chain {
                trace.readings[q.reading.sensor()].cluster = Some(ci);
            }
            if params.arc_features && self.file_if_arc(ci, &chain, trace) {
                if self.record_trace {
                    trace.clusters.push(ClusterTrace {
                        sensors: chain.iter().map(|q| q.reading.sensor()).collect(),
                        constant_depth: Vec::new(),
                        fitted: chain,
                        splits: Vec::new(),
                        new_segments: Vec::new(),
                    });
                } else {
                    *fitted_buffer = chain;
                }
                continue;
            }
            let sensors: Vec<usize> = if self.record_trace {
                chain.iter().map(|q| q.reading.sensor()).collect()
            } else {
                Vec::new()
            };
            let mut fitted = chain;
            let constant_depth = if params.constant_depth {
                reduce_constant_depth_in_place(&mut fitted, params.accuracy_pct)
            } else {
                Vec::new()
            };
            // docs/algorithm.md §2: a chain that wraps all round without a break is a closed
            // loop (its last point neighbours its first), so the fit closes it by repeating the
            // first point at the end; the reading itself is still traced once. Two points make
            // no polygon: they are fitted as an open chain.
            let closed_loop = wraps && clusters.len() == 1 && !chain_has_break;
            let repeats_first = closed_loop && fitted.len() >= 3;
            if repeats_first {
                fitted.push(fitted[0]);
            }
            let mut splits = self.fresh_or_reused(splits_buffer, 0);
            pieces.clear();
            split_recursive(&fitted, params, &mut splits, pieces);
            let first_new = out.segments.len();
            // The last reading sent to point memory: consecutive pieces share their corner
            // reading, which goes there once.
            let mut sent_until: Option<usize> = None;
            for &[first, last] in pieces.iter() {
                // §8.8: a piece too short to be trusted as a line; its readings go to point
                // memory (when on) as one-point clusters do.
                let (a, b) = piece_end_points(&fitted, first, last, params.fit);
                if last + 1 - first < params.min_piece_points
                    && !(pieces.len() == 1
                        && trace.pose.is_some_and(|pose| {
                            self.supports_as_plane_now(
                                &pose,
                                &fitted[first..=last],
                                &a.point,
                                &b.point,
                            )
                        }))
                {
                    // A closed loop's last point repeats its first (after the constant-depth
                    // reduction, which may have shortened the chain).
                    let end = if repeats_first {
                        last.min(fitted.len() - 2)
                    } else {
                        last
                    };
                    let start = sent_until.map_or(first, |sent| first.max(sent + 1));
                    out.singles
                        .extend(fitted.iter().take(end + 1).skip(start).copied());
                    sent_until = Some(end);
                    continue;
                }
                let mut new = NewSegmentTrace {
                    source: SegmentSource::Cluster(ci),
                    a,
                    b,
                    points: fitted[first..=last].to_vec(),
                };
                if params.echo_fit && !self.place_echoes(&mut new, out.segments.len(), trace) {
                    continue;
                }
                out.segments.push(new);
            }
            // A one-point cluster, or one the constant-depth reduction (§8.2) left with one
            // reading (a wall seen square-on by three sonars), goes to point memory (§8.1).
            if fitted.len() == 1 {
                out.singles.push(fitted[0]);
            }
            if self.record_trace {
                trace.clusters.push(ClusterTrace {
                    sensors,
                    constant_depth,
                    fitted,
                    splits,
                    new_segments: (first_new..out.segments.len()).collect(),
                });
            } else {
                *splits_buffer = splits;
                *fitted_buffer = fitted;
            }
        }
        out
    }

    /// §8.10 echo placement: when one plane's echoes explain the readings of `new` (the
    /// `index`-th new segment of the step), they move to where those echoes came from and its
    /// end-points are taken again from them (§3's fit of the moved piece).
    /// A sensor whose echoes come from its axis ([`EchoModel::Axis`]) keeps the paper's
    /// placement.
    /// Returns false when the piece must not become a segment: most of its echo points lie
    /// behind confirmed walls.
    fn place_echoes(
        &mut self,
        new: &mut NewSegmentTrace,
        index: usize,
        trace: &mut StepTrace,
    ) -> bool {
        if new.points.len() < MIN_ECHO_FIT_READINGS || self.sensor.echo == EchoModel::Axis {
            return true;
        }
        let beams: Option<Vec<Beam>> = new.points.iter().map(|q| self.recent_beam_of(q)).collect();
        let Some(beams) = beams else {
            return true;
        };
        let axis_points: Vec<Point> = new.points.iter().map(|q| q.point).collect();
        let (xi, half) = self.accuracy_and_half_beam();
        let turn = self.params.orientation_rad;
        let Some(line) = fit_echo_line(&beams, &axis_points, xi, half, turn) else {
            return true;
        };
        let mut placed = place_echoes(&new.points, &beams, &line, half);
        let behind_confirmed_wall = placed
            .points
            .iter()
            .zip(&beams)
            .filter(|(q, beam)| echo_behind_confirmed_wall(&self.map, beam, &q.point, xi))
            .count();
        let (first, last) = (new.points[0], new.points[new.points.len() - 1]);
        order_along_line(&mut placed.points, &line, &first, &last);
        // A corner or an edge: one reflector point explains the ranges better than the line.
        let centre =
            placed.points.iter().map(|q| q.point.coords).sum::<Vec2>() / placed.points.len() as f64;
        let reflector = reflector_beating_line(&beams, &line, Point::from(centre), xi, half);
        if let Some(at) = reflector {
            let origin = mean_origin(&beams);
            file_arc(
                &mut self.map,
                at,
                mean_range_m(&beams),
                &origin,
                trace.snapshot,
                xi,
            );
        }
        let keep = reflector.is_none() && 2 * behind_confirmed_wall <= new.points.len();
        let (a, b) = piece_end_points(&placed.points, 0, placed.points.len() - 1, self.params.fit);
        new.a = a;
        new.b = b;
        new.points = placed.points;
        if self.record_trace {
            trace.echo_fits.push(EchoFitTrace {
                new_segment: index,
                dropped: !keep,
                reflector,
                line,
                at_foot: placed.at_foot,
                at_cone_edge: placed.at_cone_edge,
                moved_max_m: placed.moved_max_m,
                behind_confirmed_wall,
            });
        }
        keep
    }

    /// §8.1 point memory: this step's one-point clusters join the memory, and the pieces its
    /// groups yield become new segments after the clusters'.
    fn fit_remembered_points(
        &mut self,
        fitted: &mut FittedStep,
        trace: &mut StepTrace,
        memory_readings: &mut Vec<ReadingRef>,
        linkage: &mut Linkage,
    ) {
        let (memory_trace, pieces) = memory_step(
            &mut self.map.memory,
            &fitted.singles,
            trace.snapshot,
            &self.params,
            self.record_trace,
            linkage,
        );
        for piece in pieces {
            memory_readings.extend(
                piece
                    .points
                    .iter()
                    .map(|q| q.reading)
                    .filter(|r| r.snapshot() != trace.snapshot),
            );
            let last = piece.points.len() - 1;
            let (a, b) = piece_end_points(&piece.points, 0, last, self.params.fit);
            let mut new = NewSegmentTrace {
                source: SegmentSource::Memory(piece.group),
                a,
                b,
                points: piece.points,
            };
            if self.params.echo_fit && !self.place_echoes(&mut new, fitted.segments.len(), trace) {
                continue;
            }
            fitted.segments.push(new);
        }
        if self.record_trace {
            trace.memory = Some(memory_trace);
        }
    }

    /// §4 each new segment matched against the map as it stood before this snapshot, in order;
    /// §5 the updates; a NEW FACE added to the map (its id allocated as it is decided). With
    /// `script` (one recorded decision a new segment), the decisions are taken as recorded.
    /// Returns the faces made, in order.
    fn match_and_update(
        &mut self,
        new_segments: &mut [NewSegmentTrace],
        script: Option<&[RecordedDecision]>,
        trace: &mut StepTrace,
        buffers: &mut StepBuffers,
    ) -> Vec<FaceId> {
        let StepBuffers {
            candidates,
            candidate_sets,
            mpc_stage,
            ..
        } = buffers;
        candidates.clear();
        candidate_sets.clear();
        trace.decisions.reserve_exact(new_segments.len());
        trace.updates.reserve_exact(new_segments.len());
        // Recorded decisions name their segments with the ends they had before this step.
        let script = script.filter(|s| s.len() == new_segments.len());
        let recorded: Option<Vec<(RecordedDecision, Option<SegmentEnds>)>> = script.map(|s| {
            s.iter()
                .map(|&r| {
                    let ends = r.existing.and_then(|id| self.map.segment(id));
                    (r, ends.map(|e| SegmentEnds { a: e.a, b: e.b }))
                })
                .collect()
        });
        if recorded.is_none() {
            for seg in new_segments.iter() {
                let start = candidates.len();
                self.candidates_for(&SegmentEnds { a: seg.a, b: seg.b }, candidates);
                candidate_sets.push(start..candidates.len());
            }
        }
        // Whether a candidate is outermost is asked as the map stood before this snapshot: the
        // map keeps each face as it was before the step first changes it.
        self.map.begin_face_journal();
        let mut faces = NewFaces::default();
        let mut absorbed_into: Vec<(SegmentId, SegmentId)> = Vec::new();
        for ni in 0..new_segments.len() {
            let ends = SegmentEnds {
                a: new_segments[ni].a,
                b: new_segments[ni].b,
            };
            let mut decision = match &recorded {
                Some(recorded) => {
                    let (r, existing_ends) = recorded[ni];
                    let stage = self.fresh_or_reused(mpc_stage, 1);
                    recorded_decision(&self.params, ni, &ends, r, existing_ends, stage)
                }
                None => {
                    let cands = &mut candidates[candidate_sets[ni].clone()];
                    let map = &self.map;
                    let was_outermost = |id, face| map.was_outermost(id, face);
                    // Room for the usual few tested candidates (a candidate's trace is large
                    // to move).
                    let stage = self.fresh_or_reused(mpc_stage, cands.len().min(8));
                    decide(
                        &self.params,
                        ni,
                        &ends,
                        cands,
                        &was_outermost,
                        stage,
                        self.record_trace,
                    )
                }
            };
            decision.result = match decision.outcome {
                Outcome::Match | Outcome::Extension => {
                    let taken = recorded.as_ref().map(|r| &r[ni].0);
                    let update =
                        self.update_for(&decision, &new_segments[ni], &absorbed_into, taken);
                    update.map(|(target, update)| {
                        if let Some(update) = update {
                            absorbed_into
                                .extend(update.absorbed.iter().map(|x| (x.segment, x.into)));
                            trace.updates.push(update);
                        }
                        target
                    })
                }
                Outcome::Dismissed => None,
                Outcome::NewFace
                    if self.params.plane_gate && !self.plane_gate(&new_segments[ni]) =>
                {
                    trace.gated.push(ni);
                    None
                }
                Outcome::NewFace => {
                    let id = self.add_new_face_segment(
                        &mut new_segments[ni],
                        &mut faces,
                        trace.snapshot,
                    );
                    if self.params.corner_diagonals {
                        self.remove_if_diagonal_at_birth(id, trace);
                    }
                    Some(id)
                }
            };
            if !self.record_trace {
                *mpc_stage = std::mem::take(&mut decision.mpc_stage);
                decision.epc_stage = Vec::new();
            }
            trace.decisions.push(decision);
        }
        self.map.end_face_journal();
        faces.made
    }

    /// §5 for a MATCH or EXTENSION `decision` of `new`: the update of the segment that now
    /// carries the chosen candidate's id (following the merges of this snapshot, `absorbed_into`);
    /// `recorded`, this decision as a recording took it, says whether it is fitted afresh and
    /// whether its points were in order ([`UpdateRequest::refit`],
    /// [`UpdateRequest::support_in_order`]).
    /// Returns that segment's id and the update's trace (none when it is gone).
    fn update_for(
        &mut self,
        decision: &DecisionTrace,
        new: &NewSegmentTrace,
        absorbed_into: &[(SegmentId, SegmentId)],
        recorded: Option<&RecordedDecision>,
    ) -> Option<(SegmentId, Option<UpdateTrace>)> {
        let named = decision.existing?;
        let evaluation = &decision
            .mpc_stage
            .iter()
            .find(|c| c.evaluation.existing == named)?
            .evaluation;
        let mut target = named;
        while let Some(&(_, into)) = absorbed_into.iter().find(|(s, _)| *s == target) {
            target = into;
        }
        let request = UpdateRequest {
            target,
            new_index: decision.new_segment,
            new_points: &new.points,
            new_left: evaluation.new_left,
            new_right: evaluation.new_right,
            outcome: decision.outcome,
            inside: if decision.outcome == Outcome::Extension {
                evaluation.overlap.epc_end
            } else {
                None
            },
            snapshot: self.next_snapshot - 1,
            refit: recorded.and_then(|r| r.refit),
            support_in_order: recorded.and_then(|r| r.support_in_order),
        };
        Some((target, apply_update(&mut self.map, &self.params, &request)))
    }

    /// A NEW FACE: `new` joins the face made this step for its cluster (or memory group), the
    /// face's object, and the map, with the next free id. Untraced, its points move into the
    /// map instead of being copied.
    fn add_new_face_segment(
        &mut self,
        new: &mut NewSegmentTrace,
        faces: &mut NewFaces,
        snapshot: usize,
    ) -> SegmentId {
        let face = match faces.of_source.iter().find(|(s, _)| *s == new.source) {
            Some(&(_, f)) => f,
            None => {
                let f = self.map.new_face();
                faces.of_source.push((new.source, f));
                faces.made.push(f);
                f
            }
        };
        let object = match self
            .map
            .face(face)
            .and_then(|f| f.segments.first())
            .and_then(|id| self.map.segment(id))
        {
            Some(s) => s.object,
            None => self.map.allocate_object_id(),
        };
        let mut points = if self.record_trace {
            new.points.clone()
        } else {
            std::mem::take(&mut new.points)
        };
        cap_support_points(&mut points, self.params.support_cap);
        let id = self.map.allocate_segment_id();
        // The face was made this step and stays, even emptied by a merge, until the step ends.
        if let Some(f) = self.map.face_mut(face) {
            f.segments.push(id);
        }
        self.map.push_segment(Segment {
            id,
            kind: SegmentKind::Fitted,
            a: new.a,
            b: new.b,
            face,
            object,
            created: snapshot,
            updated: Vec::new(),
            points: points.into(),
        });
        id
    }

    /// §6: each new face correlated with the map, in the order the faces were made. A face
    /// whose segments were all merged away this step is gone and has no correlation.
    fn correlate_new_faces(&mut self, new_faces: Vec<FaceId>, trace: &mut StepTrace) {
        for face in new_faces {
            if self.map.face(face).is_some() {
                let correlation = correlate_face(&mut self.map, face, &self.params, trace.snapshot);
                trace.correlations.push(correlation);
            }
        }
    }
}

/// The decision `r` recorded for new segment `new_index` (`new`), taken again: the named
/// segment (with `existing_ends`, its ends before the step) evaluated as the decision's one
/// tested candidate when it is a MATCH or an EXTENSION, which is all the update reads.
fn recorded_decision(
    params: &Params,
    new_index: usize,
    new: &SegmentEnds,
    r: RecordedDecision,
    existing_ends: Option<SegmentEnds>,
    mut stage: Vec<CandidateTrace>,
) -> DecisionTrace {
    stage.clear();
    if let (Outcome::Match | Outcome::Extension, Some(id), Some(ends)) =
        (r.outcome, r.existing, existing_ends)
    {
        stage.push(CandidateTrace {
            distance_m: 0.0,
            outermost: r.outcome == Outcome::Extension,
            evaluation: evaluate_pair(params, new, id, &ends),
        });
    }
    DecisionTrace {
        new_segment: new_index,
        mpc_stage: stage,
        epc_stage: Vec::new(),
        outcome: r.outcome,
        rule: r.rule,
        existing: r.existing,
        result: None,
    }
}

/// How far from new segment `new` a map segment can lie and still pass a §4 test, or fail
/// only its orientation, under `params` with `max_end_range_m` the largest end-point range in
/// the map (the bound of [`Mapper`]'s candidate search; docs/algorithm.md §4).
pub fn candidate_reach_m(params: &Params, max_end_range_m: f64, new: &SegmentEnds) -> f64 {
    let h = (new.b.point - new.a.point).norm() / 2.0;
    let thr =
        params.accuracy_pct / 100.0 * (max_end_range_m + (new.a.range_m + new.b.range_m) / 2.0);
    let theta = params.orientation_rad;
    let containment = if theta < 89f64.to_radians() {
        thr + (h + thr) * theta.tan()
    } else {
        f64::INFINITY
    };
    // A little slack for rounding: pruning must never drop a candidate that passes.
    (thr + h).max(containment) * (1.0 + 1e-9) + 1e-9
}

/// What §3 made of a step's clusters.
struct FittedStep {
    /// The new segments, in cluster order (then memory groups').
    segments: Vec<NewSegmentTrace>,
    /// The points of one-point clusters, and of clusters §8.2 reduced to one (for point
    /// memory).
    singles: Vec<SupportPoint>,
}

/// The faces a step makes for its NEW FACE segments: one per cluster or memory group.
#[derive(Default)]
struct NewFaces {
    of_source: Vec<(SegmentSource, FaceId)>,
    made: Vec<FaceId>,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mapping::confirm::{PlaneSupport, CONFIRMING_SNAPSHOTS};
    use crate::mapping::map::test_wall;
    use crate::sonar::SensorMount;

    /// One sensor at the origin facing +y, over a map of the wall s0 along y = 2 (x from -2 to
    /// 2, confirmed when `wall_confirmed`) and the tentative segment s1 across the beam at
    /// y = 1 (x from -0.3 to 0.3); the sensor reads 2.0 m. Returns the step's trace and the map.
    fn read_the_wall(wall_confirmed: bool) -> (StepTrace, Map) {
        let layout = SensorLayout {
            mounts: vec![SensorMount {
                x_m: 0.0,
                y_m: 0.0,
                heading_rad: std::f64::consts::FRAC_PI_2,
            }],
        };
        let mut mapper = Mapper::new(Params::extended(), layout, SensorSpec::default());
        let mut map = Map::from_segments(vec![
            test_wall(0, (-2.0, 2.0), (2.0, 2.0), 2.0),
            test_wall(1, (-0.3, 1.0), (0.3, 1.0), 1.0),
        ]);
        map.confirms_segments = true;
        if wall_confirmed {
            map.plane_support.insert(
                0,
                PlaneSupport {
                    snapshots: CONFIRMING_SNAPSHOTS,
                    last_snapshot: 0,
                },
            );
        }
        mapper.restore(&MapperState {
            map,
            last_pose: None,
            next_snapshot: 1,
        });
        let trace = mapper.step(&Snapshot {
            t: 1.0,
            pose: Pose::new(0.0, 0.0, 0.0),
            ranges_m: vec![Some(2.0)],
        });
        (trace, mapper.map().clone())
    }

    #[test]
    fn a_settled_reading_sweeps_no_free_space_and_an_unsettled_one_does() {
        // s0 confirmed predicts 2.0 m (the foot (0, 2) on the axis, 2 m inside both ends): the
        // reading is settled. It would see through s1 (p = 1, 1 + 2·0.06 = 1.12 < 2), but the
        // space in front of a confirmed wall is not swept again: s1 stays.
        let (trace, map) = read_the_wall(true);
        assert_eq!(trace.settled.len(), 1);
        assert_eq!(trace.settled[0].segment, 0);
        assert!(trace.refuted.is_empty(), "{:?}", trace.refuted);
        assert!(map.segment(1).is_some());
        // s0 tentative: nothing settles the reading, which refutes s1 (and not s0: 2 + 0.12 > 2).
        let (trace, map) = read_the_wall(false);
        assert!(trace.settled.is_empty());
        let refuted: Vec<SegmentId> = trace.refuted.iter().map(|r| r.segment).collect();
        assert_eq!(refuted, vec![1]);
        assert!(map.segment(1).is_none() && map.segment(0).is_some());
    }
}
