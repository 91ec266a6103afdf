//! The mapper's confirmation stage (docs/algorithm.md §8.7): plane support, baseline
//! confirmation, refits that unconfirm, and the plane gate on a new face.

use crate::mapping::ext::confirm::{
    baseline_pair, first_plane_support, note_baseline_support, note_plane_support,
    off_axis_turn_rad, refit_moved_off, supports, PlaneEchoModel, View, CONFIRMING_BASELINE_M,
    CONFIRMING_BASELINE_TURN_RAD,
};
use crate::mapping::model::beam::Beam;
use crate::mapping::model::ext_trace::{PlaneSupportTrace, UnconfirmedTrace};
use crate::mapping::model::map::{SegmentId, SupportPoint};
use crate::mapping::model::plane_supports::PlaneSupport;
use crate::mapping::model::support::ReadingRef;
use crate::mapping::model::trace::{NewSegmentTrace, Outcome, StepTrace};
use crate::mapping::Mapper;

impl Mapper {
    /// §8.7 confirmation: each segment this step's new segments matched, extended or made
    /// hears of the plane support of their readings.
    pub(in crate::mapping) fn note_plane_support(
        &mut self,
        new_segments: &[NewSegmentTrace],
        trace: &mut StepTrace,
    ) {
        let (xi, half) = self.accuracy_and_half_beam();
        let echo = self.plane_echo_model();
        let robot = self.reading_places().step.position();
        let targets: Vec<(usize, SegmentId)> = trace
            .decisions
            .iter()
            .filter_map(|d| d.result.map(|r| (d.new_segment, r)))
            .collect();
        for (ni, target) in targets {
            let now = |q: &&SupportPoint| q.reading.snapshot() == trace.snapshot;
            let beam = |q: &SupportPoint| (q.reading.sensor(), self.step_beam_of(q));
            let beams: Vec<(usize, Beam)> = match new_segments.get(ni) {
                Some(n) if !n.points.is_empty() => n.points.iter().filter(now).map(beam).collect(),
                // Untraced, a new face's points moved into the map segment.
                _ => match self.map.segment(target) {
                    Some(s) => s.points.iter().filter(now).map(beam).collect(),
                    None => continue,
                },
            };
            // Off the map's axes, a sensor that hears its cone's edges confirms from the foot
            // alone.
            let off_axis_rad = (echo == PlaneEchoModel::NearestInCone)
                .then(|| self.off_axis_turn(target))
                .flatten();
            let confirming = off_axis_rad.map_or(echo, |_| PlaneEchoModel::Foot);
            let noted = note_plane_support(
                &mut self.map,
                target,
                &beams,
                View {
                    snapshot: trace.snapshot,
                    robot,
                    spacing_m: self.params.confirm_spacing_m,
                },
                xi,
                half,
                confirming,
            );
            let refused = match (&noted, off_axis_rad) {
                (None, Some(turn_rad)) if self.record_trace => {
                    self.edge_echo_refused(target, &beams, echo, turn_rad)
                }
                _ => None,
            };
            if self.record_trace {
                trace.plane_support.extend(noted.or(refused));
            }
        }
    }

    /// §8.7 `refit_unconfirms`: a confirmed segment that a refit of this step moved off its
    /// line ([`refit_moved_off`]) is tentative again; `refit_recounts`: a tentative one
    /// drops the support counted for its old line.
    pub(in crate::mapping) fn unconfirm_moved_refits(&mut self, trace: &mut StepTrace) {
        let p = &self.params;
        let (confirmed_too, tentative_too) = (p.refit_unconfirms, p.refit_recounts);
        for u in &trace.updates {
            if u.refit.is_none() {
                continue;
            }
            let confirmed = self.map.is_confirmed(u.segment);
            let acts = if confirmed {
                confirmed_too
            } else {
                tentative_too
                    && self
                        .map
                        .plane_support
                        .get(&u.segment)
                        .is_some_and(PlaneSupport::counted)
            };
            if !acts {
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
                    tentative: !confirmed,
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
    pub(in crate::mapping) fn note_baseline_support(
        &mut self,
        memory_readings: &[ReadingRef],
        trace: &mut StepTrace,
    ) {
        let (xi, half) = self.accuracy_and_half_beam();
        let echo = self.plane_echo_model();
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
                        self.step_beam_of(q)
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
                echo,
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

    /// §8.7 plane gate: whether a reading of `new` supports it as a plane
    /// ([`crate::mapping::ext::confirm::supports_as_plane`]), each from its own snapshot's pose
    /// (point memory's readings are at most `memory_snapshots` old).
    pub(in crate::mapping) fn plane_gate(&self, new: &NewSegmentTrace) -> bool {
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
                self.plane_echo_model(),
            )
            .is_some()
        })
    }
}

impl Mapper {
    /// With `off_axis_square_on`, how far `target` is turned from the map's axes (those of the
    /// heading correction, or of the pose correction's windows, §8.17), radians, when more
    /// than `θ_o` ([`off_axis_turn_rad`]).
    fn off_axis_turn(&self, target: SegmentId) -> Option<f64> {
        if !self.params.off_axis_square_on {
            return None;
        }
        let belief = &self.pose_belief;
        let axis_rad = belief.drift.axis_ref_rad.or(belief.rectilinear.axis_rad);
        let s = self.map.segment(target)?;
        let along = s.b.point - s.a.point;
        off_axis_turn_rad(
            along.y.atan2(along.x),
            axis_rad,
            self.params.orientation_rad,
        )
    }

    /// The record of a reading that supported `target` only off its cone's edge (`echo`, the
    /// plane test without the rule) and so did not count, `target` being `turn_rad` off the
    /// map's axes (docs/algorithm.md §8.7).
    fn edge_echo_refused(
        &self,
        target: SegmentId,
        beams: &[(usize, Beam)],
        echo: PlaneEchoModel,
        turn_rad: f64,
    ) -> Option<PlaneSupportTrace> {
        let s = self.map.segment(target)?;
        let (a, b) = (s.a.point, s.b.point);
        let (xi, half) = self.accuracy_and_half_beam();
        let (sensor, beam, distance_m) = first_plane_support(beams, &a, &b, xi, half, echo)?;
        let support = self.map.plane_support.get(&target).copied();
        Some(PlaneSupportTrace {
            off_axis_deg: Some(turn_rad.to_degrees()),
            ..PlaneSupportTrace::new(
                target,
                sensor,
                beam.range_m,
                distance_m,
                &support.unwrap_or_default(),
            )
        })
    }
}
