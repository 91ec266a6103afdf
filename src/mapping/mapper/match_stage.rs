//! The paper's §4–§6 in a step: each new segment matched against the map (the candidate search
//! and the decision), the updates, the new faces filed, and their correlation.

use super::Mapper;
use crate::mapping::model::map::{FaceId, Segment, SegmentId, SegmentKind};
use crate::mapping::model::trace::{
    DecisionTrace, NewSegmentTrace, Outcome, StepTrace, UpdateTrace,
};
use crate::mapping::paper::candidates::candidate_reach_m;
use crate::mapping::paper::correlate::correlate_face;
use crate::mapping::paper::fast_path::decide;
use crate::mapping::paper::matching::{Candidate, SegmentEnds};
use crate::mapping::paper::support_points::cap_support_points;
use crate::mapping::paper::update::{apply_update, UpdateRequest};
use crate::mapping::recorded::{recorded_decision, RecordedDecision};
use crate::mapping::step::{NewFaces, StepBuffers};
use std::ops::Range;

/// Each decision of a step as recorded, with its named segment's ends before the step.
type Recorded = Vec<(RecordedDecision, Option<SegmentEnds>)>;

impl Mapper {
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
    pub(super) fn candidates_for(&self, new: &SegmentEnds, candidates: &mut Vec<Candidate>) {
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

    /// §4 each new segment matched against the map as it stood before this snapshot, in order;
    /// §5 the updates; a NEW FACE added to the map (its id allocated as it is decided). With
    /// `script` (one recorded decision a new segment), the decisions are taken as recorded.
    /// Returns the faces made, in order.
    pub(super) fn match_and_update(
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
        let recorded =
            self.recorded_or_candidates(new_segments, script, candidates, candidate_sets);
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
            let taken = recorded.as_ref().map(|r| &r[ni].0);
            decision.result = self.act_on(
                &decision,
                &mut new_segments[ni],
                taken,
                &mut absorbed_into,
                &mut faces,
                trace,
            );
            if !self.record_trace {
                *mpc_stage = std::mem::take(&mut decision.mpc_stage);
                decision.epc_stage = Vec::new();
            }
            trace.decisions.push(decision);
        }
        self.map.end_face_journal();
        faces.made
    }

    /// With `script` (one recorded decision a new segment), each decision as recorded with its
    /// named segment's ends before this step (which is how a recording names them); without,
    /// each new segment's candidates gathered into `candidates`, a range of it each.
    fn recorded_or_candidates(
        &self,
        new_segments: &[NewSegmentTrace],
        script: Option<&[RecordedDecision]>,
        candidates: &mut Vec<Candidate>,
        candidate_sets: &mut Vec<Range<usize>>,
    ) -> Option<Recorded> {
        let script = script.filter(|s| s.len() == new_segments.len());
        let recorded: Option<Recorded> = script.map(|s| {
            s.iter()
                .map(|&r| {
                    let ends = r.existing.and_then(|id| self.map.segment(id));
                    (r, ends.map(|e| SegmentEnds { a: e.a, b: e.b }))
                })
                .collect()
        });
        if recorded.is_none() {
            for seg in new_segments {
                let start = candidates.len();
                self.candidates_for(&SegmentEnds { a: seg.a, b: seg.b }, candidates);
                candidate_sets.push(start..candidates.len());
            }
        }
        recorded
    }

    /// What `decision` (of new segment `new`) does to the map: a MATCH or EXTENSION updates
    /// its segment (§5; `taken`, as a recording took it), a NEW FACE is filed unless a hook
    /// refuses it (§8.7 plane gate). Returns the segment it ends up in.
    fn act_on(
        &mut self,
        decision: &DecisionTrace,
        new: &mut NewSegmentTrace,
        taken: Option<&RecordedDecision>,
        absorbed_into: &mut Vec<(SegmentId, SegmentId)>,
        faces: &mut NewFaces,
        trace: &mut StepTrace,
    ) -> Option<SegmentId> {
        match decision.outcome {
            Outcome::Match | Outcome::Extension => {
                let update = self.update_for(decision, new, absorbed_into, taken);
                update.map(|(target, update)| {
                    if let Some(update) = update {
                        absorbed_into.extend(update.absorbed.iter().map(|x| (x.segment, x.into)));
                        trace.updates.push(update);
                    }
                    target
                })
            }
            Outcome::Dismissed => None,
            Outcome::NewFace if !self.hook_admits_new_face(new) => {
                trace.gated.push(decision.new_segment);
                None
            }
            Outcome::NewFace => {
                let id = self.add_new_face_segment(new, faces, trace.snapshot);
                self.hook_new_face_filed(id, trace);
                Some(id)
            }
        }
    }

    /// §5 for a MATCH or EXTENSION `decision` of `new`: the update of the segment that now
    /// carries the chosen candidate's id (following the merges of this snapshot, `absorbed_into`);
    /// `recorded`, this decision as a recording took it, says whether it is fitted afresh and
    /// whether its points were in order ([`UpdateRequest::refit`],
    /// [`UpdateRequest::support_in_order`]).
    /// Returns that segment's id and the update's trace (none when it is gone).
    pub(super) fn update_for(
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
    pub(super) fn add_new_face_segment(
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
    pub(super) fn correlate_new_faces(&mut self, new_faces: Vec<FaceId>, trace: &mut StepTrace) {
        for face in new_faces {
            if self.map.face(face).is_some() {
                let correlation = correlate_face(&mut self.map, face, &self.params, trace.snapshot);
                trace.correlations.push(correlation);
            }
        }
    }
}
