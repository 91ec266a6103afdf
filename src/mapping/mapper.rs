//! The mapper: one snapshot in, the map updated and the step's trace out (paper §3).

use super::cluster::{cluster_points, sensor_ranks, Clusters};
use super::correlate::correlate_face;
use super::extensions::{memory_step, reduce_constant_depth};
use super::fit::{piece_end_points, split_recursive, split_tolerance};
use super::map::{EndPoint, FaceId, Map, Segment, SegmentId, SegmentKind, SupportPoint};
use super::matching::{decide, Candidate, SegmentEnds};
use super::merge::absorb_duplicates;
use super::params::Params;
use super::readings::convert_readings;
use super::trace::{
    CandidateTrace, ClusterTrace, NewSegmentTrace, Outcome, RefitTrace, SegmentSource, Side,
    SplitTrace, StepTrace, Test, UpdateTrace, Warning,
};
use super::update::{
    cap_support_points, merge_support_points, update_extension, update_match, UpdateGeometry,
};
use crate::geometry::{distance_to_line, projection_param, Pose};
use crate::run::Snapshot;
use crate::sonar::{BeamAxis, SensorLayout, SensorSpec};
use std::ops::Range;
use std::sync::Arc;

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
    next_snapshot: usize,
    brute_force: bool,
    record_trace: bool,
    /// Buffers each step fills and the next reuses.
    buffers: StepBuffers,
}

/// Buffers one step fills and the next reuses, so that an untraced step allocates little. What
/// the trace keeps is copied out of them (or built in its own vectors) only when tracing.
#[derive(Clone, Debug, Default)]
struct StepBuffers {
    /// The kept points.
    kept: Vec<SupportPoint>,
    clusters: Clusters,
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
        Self {
            params,
            layout,
            sensor,
            bearing_ranks,
            beam_axes,
            map: Map::default(),
            last_pose: None,
            next_snapshot: 0,
            brute_force: false,
            record_trace: true,
            buffers: StepBuffers::default(),
        }
    }

    /// With `false`, steps return a slim trace: readings, decisions (without their candidate
    /// lists), updates, correlations and warnings; no gaps, clusters, splits, new-segment
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
            let h = (new.b.point - new.a.point).norm() / 2.0;
            let thr = self.params.accuracy_pct / 100.0
                * (self.map.max_end_range_m + (new.a.range_m + new.b.range_m) / 2.0);
            let theta = self.params.orientation_rad;
            let containment = if theta < 89f64.to_radians() {
                thr + (h + thr) * theta.tan()
            } else {
                f64::INFINITY
            };
            // A little slack for rounding: pruning must never drop a candidate that passes.
            (thr + h).max(containment) * (1.0 + 1e-9) + 1e-9
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

    /// Resumes from a checkpoint.
    pub fn restore(&mut self, state: MapperState) {
        self.map = state.map;
        self.map.rebuild_index();
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

    /// Applies one snapshot and returns what happened.
    pub fn step(&mut self, snapshot: &Snapshot) -> StepTrace {
        let index = self.next_snapshot;
        self.next_snapshot += 1;
        let params_owned = self.params.clone();
        let params = &params_owned;
        let mut trace = StepTrace {
            snapshot: index,
            t: snapshot.t,
            pose: Some(snapshot.pose),
            ..Default::default()
        };

        // §3.3.1: matching is valid only below max_step.
        if let Some(last) = self.last_pose {
            let step_m = last.distance_to(&snapshot.pose);
            if step_m > params.max_step_m {
                trace.warnings.push(Warning::MaxStep {
                    step_m,
                    max_step_m: params.max_step_m,
                });
            }
        }
        self.last_pose = Some(snapshot.pose);
        if snapshot.ranges_m.len() != self.layout.len() {
            trace.warnings.push(Warning::RangeCount {
                given: snapshot.ranges_m.len(),
                expected: self.layout.len(),
            });
        }

        // §1 readings → points; §2 clusters.
        let mut buffers = std::mem::take(&mut self.buffers);
        let StepBuffers {
            kept,
            clusters,
            fitted: fitted_buffer,
            splits: splits_buffer,
            pieces,
            candidates,
            candidate_sets,
            mpc_stage,
        } = &mut buffers;
        trace.readings = convert_readings(
            index,
            &snapshot.pose,
            &snapshot.ranges_m,
            &self.beam_axes,
            self.sensor.max_range_m,
            params,
            kept,
        );
        let (ranks, wraps) = (&self.bearing_ranks.0, self.bearing_ranks.1);
        cluster_points(kept, ranks, wraps, params.t_gap_m, clusters);
        let chain_has_break = clusters.gaps.iter().any(|g| g.is_break);
        if self.record_trace {
            trace.gaps = clusters.gaps.clone();
        }

        // §3 fitting of each cluster (with constant-depth groups when on).
        let mut new_segments: Vec<NewSegmentTrace> = Vec::with_capacity(kept.len());
        let mut singles: Vec<SupportPoint> = Vec::new();
        for (ci, members) in clusters.iter().enumerate() {
            let mut chain = self.fresh_or_reused(fitted_buffer, members.len() + 1);
            chain.extend(members.iter().map(|&i| kept[i]));
            for q in &chain {
                trace.readings[q.reading.sensor].cluster = Some(ci);
            }
            let chain_len = chain.len();
            let sensors: Vec<usize> = if self.record_trace {
                chain.iter().map(|q| q.reading.sensor).collect()
            } else {
                Vec::new()
            };
            let (mut fitted, constant_depth) = if params.constant_depth {
                reduce_constant_depth(&chain, params.accuracy_pct)
            } else {
                (chain, Vec::new())
            };
            // docs/algorithm.md §2: a chain that wraps all round without a break is a closed
            // loop (its last point neighbours its first), so the fit closes it by repeating the
            // first point at the end; the reading itself is still traced once. Two points make
            // no polygon: they are fitted as an open chain.
            let closed_loop = wraps && clusters.len() == 1 && !chain_has_break;
            if closed_loop && fitted.len() >= 3 {
                fitted.push(fitted[0]);
            }
            let mut splits = self.fresh_or_reused(splits_buffer, 0);
            pieces.clear();
            split_recursive(&fitted, params, &mut splits, pieces);
            let first_new = new_segments.len();
            for &[first, last] in pieces.iter() {
                let (a, b) = piece_end_points(&fitted, first, last, params.fit);
                new_segments.push(NewSegmentTrace {
                    source: SegmentSource::Cluster(ci),
                    a,
                    b,
                    points: fitted[first..=last].to_vec(),
                });
            }
            if chain_len == 1 {
                singles.push(fitted[0]);
            }
            if self.record_trace {
                trace.clusters.push(ClusterTrace {
                    sensors,
                    constant_depth,
                    fitted,
                    splits,
                    new_segments: (first_new..new_segments.len()).collect(),
                });
            } else {
                *splits_buffer = splits;
                *fitted_buffer = fitted;
            }
        }

        // §8 point memory.
        if params.memory_snapshots > 0 {
            let (memory_trace, pieces) = memory_step(
                &mut self.map.memory,
                &singles,
                index,
                params,
                self.record_trace,
            );
            for piece in pieces {
                let last = piece.points.len() - 1;
                let (a, b) = piece_end_points(&piece.points, 0, last, params.fit);
                new_segments.push(NewSegmentTrace {
                    source: SegmentSource::Memory(piece.group),
                    a,
                    b,
                    points: piece.points,
                });
            }
            if self.record_trace {
                trace.memory = Some(memory_trace);
            }
        }

        // §4 matching against the map as it stood before this snapshot, §5 updates.
        candidates.clear();
        candidate_sets.clear();
        trace.decisions.reserve_exact(new_segments.len());
        trace.updates.reserve_exact(new_segments.len());
        for seg in &new_segments {
            let start = candidates.len();
            self.candidates_for(&SegmentEnds { a: seg.a, b: seg.b }, candidates);
            candidate_sets.push(start..candidates.len());
        }
        // Whether a candidate is outermost is asked as the map stood before this snapshot: the
        // map keeps each face as it was before the step first changes it.
        self.map.begin_face_journal();
        let mut face_of_source: Vec<(SegmentSource, FaceId)> = Vec::new();
        let mut absorbed_into: Vec<(SegmentId, SegmentId)> = Vec::new();
        let mut new_faces: Vec<FaceId> = Vec::new();
        for ni in 0..new_segments.len() {
            let seg = &new_segments[ni];
            let cands = &mut candidates[candidate_sets[ni].clone()];
            let ends = SegmentEnds { a: seg.a, b: seg.b };
            let map = &self.map;
            let was_outermost = |id, face| map.was_outermost(id, face);
            // Room for the usual few tested candidates (a candidate's trace is large to move).
            let stage = self.fresh_or_reused(mpc_stage, cands.len().min(8));
            let mut decision = decide(
                params,
                ni,
                &ends,
                cands,
                &was_outermost,
                stage,
                self.record_trace,
            );
            match decision.outcome {
                Outcome::Match | Outcome::Extension => {
                    let named = decision.existing.expect("a match names its segment");
                    let evaluation = &decision
                        .mpc_stage
                        .iter()
                        .find(|c| c.evaluation.existing == named)
                        .expect("tested")
                        .evaluation;
                    // A segment fused into another earlier in this snapshot: update that one.
                    let mut target = named;
                    while let Some(&(_, into)) = absorbed_into.iter().find(|(s, _)| *s == target) {
                        target = into;
                    }
                    let inside = if decision.outcome == Outcome::Extension {
                        evaluation.overlap.epc_end
                    } else {
                        None
                    };
                    let (nl, nr) = (evaluation.new_left, evaluation.new_right);
                    if let Some(update) =
                        self.apply_update(target, ni, seg, nl, nr, decision.outcome, inside, index)
                    {
                        absorbed_into.extend(update.absorbed.iter().map(|x| (x.segment, x.into)));
                        trace.updates.push(update);
                    }
                    decision.result = Some(target);
                }
                Outcome::Dismissed => {}
                Outcome::NewFace => {
                    let face = match face_of_source.iter().find(|(s, _)| *s == seg.source) {
                        Some(&(_, f)) => f,
                        None => {
                            let f = self.map.new_face();
                            face_of_source.push((seg.source, f));
                            new_faces.push(f);
                            f
                        }
                    };
                    let object = match self
                        .map
                        .face(face)
                        .and_then(|f| f.segments.first())
                        .and_then(|&id| self.map.segment(id))
                    {
                        Some(s) => s.object,
                        None => self.map.allocate_object_id(),
                    };
                    let (a, b) = (seg.a, seg.b);
                    // Untraced, the new segment's points are not kept in the trace.
                    let mut points = if self.record_trace {
                        seg.points.clone()
                    } else {
                        std::mem::take(&mut new_segments[ni].points)
                    };
                    cap_support_points(&mut points, params.support_cap);
                    let id = self.map.allocate_segment_id();
                    // The face was made this step and stays, even emptied by a merge, until
                    // the step ends.
                    if let Some(f) = self.map.face_mut(face) {
                        f.segments.push(id);
                    }
                    self.map.push_segment(Segment {
                        id,
                        kind: SegmentKind::Fitted,
                        a,
                        b,
                        face,
                        object,
                        created: index,
                        updated: Vec::new(),
                        points: Arc::new(points),
                    });
                    decision.result = Some(id);
                }
            }
            if !self.record_trace {
                *mpc_stage = std::mem::take(&mut decision.mpc_stage);
                decision.epc_stage = Vec::new();
            }
            trace.decisions.push(decision);
        }
        self.map.end_face_journal();
        self.buffers = buffers;
        if self.record_trace {
            trace.new_segments = new_segments;
        }

        // §6 correlation of the new faces, in cluster order.
        if params.correlate {
            // A new face whose segments were all merged away this step is gone.
            new_faces.retain(|&f| self.map.face(f).is_some());
            for face in new_faces {
                trace
                    .correlations
                    .push(correlate_face(&mut self.map, face, params, index));
            }
        }
        trace
    }

    /// Applies a MATCH or EXTENSION to segment `target` and runs the post-update split test.
    #[allow(clippy::too_many_arguments)]
    fn apply_update(
        &mut self,
        target: SegmentId,
        new_index: usize,
        new: &NewSegmentTrace,
        new_left: EndPoint,
        new_right: EndPoint,
        outcome: Outcome,
        inside: Option<Side>,
        snapshot: usize,
    ) -> Option<UpdateTrace> {
        let params = self.params.clone();
        let seg = self.map.segment(target)?;
        let before = [seg.a, seg.b];
        // Orient the new segment along the live geometry (it may have moved this snapshot).
        let (nl, nr) = if projection_param(&new_left.point, &seg.a.point, &seg.b.point)
            <= projection_param(&new_right.point, &seg.a.point, &seg.b.point)
        {
            (new_left, new_right)
        } else {
            (new_right, new_left)
        };
        let geometry: UpdateGeometry = match inside {
            Some(side) => update_extension(before, nl, nr, side),
            None => update_match(before, nl, nr),
        };
        let [a, b] = geometry.ends;
        let points = merge_support_points(&seg.points, &new.points, &a, &b, params.support_cap);
        let worst = points
            .iter()
            .map(|q| {
                let d = distance_to_line(&q.point, &geometry.line[0], &geometry.line[1]);
                Test::at_most(d, split_tolerance(&params, q.range_m))
            })
            .fold(None::<Test>, |acc, t| match acc {
                Some(w) if !w.pass && t.pass => Some(w),
                Some(w) if w.pass == t.pass && w.value - w.threshold >= t.value - t.threshold => {
                    Some(w)
                }
                _ => Some(t),
            });
        let mut update = UpdateTrace {
            segment: target,
            new_segment: new_index,
            outcome,
            before,
            after: geometry.ends,
            line: geometry.line,
            fates: geometry.fates,
            fallback_tls: geometry.fallback_tls,
            refit: None,
            absorbed: Vec::new(),
        };
        let seg = self.map.segment_mut(target)?;
        seg.note_update(snapshot);
        let stands = worst.is_none_or(|w| w.pass);
        if stands {
            seg.points = Arc::new(points);
            self.map.set_ends(target, a, b);
            // Only a segment that grew past its old end-points can have come to overlap
            // another one.
            let grew = [a, b].iter().any(|e| {
                let t = projection_param(&e.point, &before[0].point, &before[1].point);
                !(-1e-9..=1.0 + 1e-9).contains(&t)
            });
            if params.merge_duplicates && grew {
                update.absorbed = absorb_duplicates(&mut self.map, &params, target, &[]);
            }
            return Some(update);
        }
        // The update's line does not explain its points: fit them afresh (§3); the first piece
        // keeps the id, the others are inserted after it in the face.
        let (mut splits, mut pieces) = (Vec::new(), Vec::new());
        split_recursive(&points, &params, &mut splits, &mut pieces);
        let (face, object, created, updated) =
            (seg.face, seg.object, seg.created, seg.updated.clone());
        let mut piece_ids = Vec::with_capacity(pieces.len());
        for (k, &[first, last]) in pieces.iter().enumerate() {
            let (pa, pb) = piece_end_points(&points, first, last, params.fit);
            let piece_points = Arc::new(points[first..=last].to_vec());
            if k == 0 {
                self.map.segment_mut(target)?.points = piece_points;
                self.map.set_ends(target, pa, pb);
                piece_ids.push(target);
            } else {
                let id = self.map.allocate_segment_id();
                self.map.push_segment(Segment {
                    id,
                    kind: SegmentKind::Fitted,
                    a: pa,
                    b: pb,
                    face,
                    object,
                    created,
                    updated: updated.clone(),
                    points: piece_points,
                });
                piece_ids.push(id);
            }
        }
        if let Some(f) = self.map.face_mut(face) {
            let at = f
                .segments
                .iter()
                .position(|&s| s == target)
                .map_or(f.segments.len(), |p| p + 1);
            f.segments.splice(at..at, piece_ids[1..].iter().copied());
        }
        if params.merge_duplicates {
            for &piece in &piece_ids {
                let absorbed = absorb_duplicates(&mut self.map, &params, piece, &piece_ids);
                update.absorbed.extend(absorbed);
            }
        }
        update.refit = Some(RefitTrace {
            worst: worst.expect("failed test exists"),
            splits,
            pieces: piece_ids,
        });
        Some(update)
    }
}
