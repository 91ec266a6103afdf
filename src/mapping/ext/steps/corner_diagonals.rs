//! The mapper's corner-diagonal stage (docs/algorithm.md §8.11), and the pillar evidence its
//! removals leave (§8.14).

use crate::mapping::ext::corner_diagonals::{
    corner_diagonal, corner_diagonals, CORNER_DIAGONAL_RADIUS_M, CORNER_WALL_REACH_M,
};
use crate::mapping::ext::round_reflectors::note_removed_echoes;
use crate::mapping::model::beam::Beam;
use crate::mapping::model::ext_trace::DiagonalTrace;
use crate::mapping::model::map::SegmentId;
use crate::mapping::model::plane_supports::CONFIRMING_SNAPSHOTS;
use crate::mapping::model::trace::{Outcome, StepTrace};
use crate::mapping::paper::update::grew_past;
use crate::mapping::Mapper;
use crate::sonar::EchoModel;

impl Mapper {
    /// §8.11: the segments that can make a corner that was not there before (made, grown or
    /// confirmed this step), and the segments near their end-points, that stand across a
    /// corner of two walls of the map (one confirmed) leave the map.
    pub(in crate::mapping) fn remove_corner_diagonals(&mut self, trace: &mut StepTrace) {
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
    pub(in crate::mapping) fn remove_if_diagonal_at_birth(
        &mut self,
        id: SegmentId,
        trace: &mut StepTrace,
    ) {
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
    pub(in crate::mapping) fn remove_diagonal(&mut self, d: DiagonalTrace, trace: &mut StepTrace) {
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
}
