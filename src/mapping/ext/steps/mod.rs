//! The extensions' hooks into [`Mapper`]'s step: one method for each place in the paper's
//! stages where an extension acts, each doing nothing unless its flag is on. The stages call
//! them in the order listed here; each hook runs its extensions in run order.

mod beams;
mod calibrated_odometry;
mod confirmation;
mod corner_diagonals;
mod echo_agreement;
mod echo_placement;
mod free_space;
mod heading_alone;
mod heading_windows;
mod point_features;
mod point_memory;
mod pose_correction;
mod right_angle_break;
mod settled_walls;
mod standstill;

use crate::mapping::model::map::{EndPoint, SegmentId, SupportPoint};
use crate::mapping::model::trace::{NewSegmentTrace, StepTrace};
use crate::mapping::step::{FittedStep, StepBuffers};
use crate::mapping::Mapper;
use crate::run::Snapshot;

impl Mapper {
    /// At the step's start: the pose is kept while a remembered reading may need it (§8.7 plane
    /// gate, §8.10 echo placement, §8.7 baseline confirmation): the last `memory_snapshots + 1`
    /// poses or, when the memory spans a distance (§8.1), those back to its oldest reading.
    pub(in crate::mapping) fn hook_step_started(&mut self, index: usize) {
        let p = &self.params;
        if p.plane_gate || p.echo_fit || p.baseline_confirm {
            let mut keep = p.memory_snapshots + 1;
            if p.memory_travel_m > 0.0 {
                let oldest = self
                    .map
                    .memory
                    .first()
                    .map(|m| m.support.reading.snapshot());
                keep = keep.min(index.saturating_sub(oldest.unwrap_or(index)) + 1);
            }
            let places = self.reading_places();
            let (pose, own) = (*places.step, places.own.to_vec());
            self.map.note_pose(index, pose, &own, keep);
        }
    }

    /// After §1, before §2: readings much shorter than their sensor's last (§8.21), readings a
    /// confirmed feature explains (§8.5) and readings a confirmed wall settles (§8.12) leave
    /// `buffers.kept`.
    pub(in crate::mapping) fn hook_readings_kept(
        &self,
        snapshot: &Snapshot,
        trace: &mut StepTrace,
        buffers: &mut StepBuffers,
    ) {
        if self.params.echo_agreement {
            self.drop_shorter_than_last(snapshot, trace, buffers);
        }
        if self.params.explain_readings {
            self.drop_explained_readings(trace, &mut buffers.kept, &mut buffers.confirmed_features);
        }
        if self.params.settled_walls {
            self.set_aside_settled_readings(trace, buffers);
        }
    }

    /// After §1–§2: with `echo_agreement`, the step's echoes are kept for the next (§8.21).
    pub(in crate::mapping) fn hook_echoes_read(&mut self, snapshot: &Snapshot, trace: &StepTrace) {
        if self.params.echo_agreement {
            self.remember_echoes(snapshot, trace);
        }
    }

    /// After §1–§2: with `heading_correction` alone, the readings confirmed walls settled
    /// (§8.12) join the heading windows (§8.17), and with `open_windows` the kept readings no
    /// wall settled join the open windows.
    pub(in crate::mapping) fn hook_readings_settled(&mut self, buffers: &mut StepBuffers) {
        if self.heading_windows_from_settled() {
            buffers.open_points.clear();
            if self.params.open_windows {
                let kept = buffers.kept.iter();
                buffers
                    .open_points
                    .extend(kept.map(|q| (q.reading.sensor(), q.point)));
            }
            self.windows_take_settled(
                &buffers.settled_points,
                &buffers.settled_echoes,
                &buffers.open_points,
            );
        }
    }

    /// In §3, before cluster `ci` (`chain`) is fitted: true when the arc rule (§8.5) filed it
    /// as a point feature instead.
    pub(in crate::mapping) fn hook_cluster_is_feature(
        &mut self,
        ci: usize,
        chain: &[SupportPoint],
        trace: &mut StepTrace,
    ) -> bool {
        self.params.arc_features && self.file_if_arc(ci, chain, trace)
    }

    /// In §3, a cluster's constant-depth groups (§8.2) reduced in place; their record.
    pub(in crate::mapping) fn hook_constant_depth(
        &self,
        chain: &mut Vec<SupportPoint>,
    ) -> Vec<crate::mapping::model::trace::ConstantDepthTrace> {
        if self.params.constant_depth {
            crate::mapping::ext::constant_depth::reduce_constant_depth_in_place(
                chain,
                self.params.accuracy_pct,
            )
        } else {
            Vec::new()
        }
    }

    /// In §3, piece `points` (end-points `a`, `b`; one of `pieces` of its cluster): true when
    /// it is too short to be trusted as a line (§8.8, `min_piece_points`), unless it is its
    /// cluster's only piece and one of its readings supports it as a plane.
    pub(in crate::mapping) fn hook_piece_too_short(
        &self,
        points: &[SupportPoint],
        (a, b): (&EndPoint, &EndPoint),
        pieces: usize,
        trace: &StepTrace,
    ) -> bool {
        if points.len() >= self.params.min_piece_points {
            return false;
        }
        !(pieces == 1
            && trace
                .pose
                .is_some_and(|_| self.supports_as_plane_now(points, &a.point, &b.point)))
    }

    /// In §3, a piece about to become new segment `index`: echo placement (§8.10) moves its
    /// readings; false when it must not become a segment.
    pub(in crate::mapping) fn hook_keeps_piece(
        &mut self,
        new: &mut NewSegmentTrace,
        index: usize,
        trace: &mut StepTrace,
    ) -> bool {
        !self.params.echo_fit || self.place_echoes(new, index, trace)
    }

    /// After §3: point memory (§8.1) takes the step's one-point clusters and yields its pieces
    /// as new segments after the clusters'.
    pub(in crate::mapping) fn hook_fitted(
        &mut self,
        fitted: &mut FittedStep,
        trace: &mut StepTrace,
        buffers: &mut StepBuffers,
    ) {
        buffers.memory_readings.clear();
        if self.params.memory_snapshots > 0 {
            self.fit_remembered_points(
                fitted,
                trace,
                &mut buffers.memory_readings,
                &mut buffers.linkage,
            );
        }
    }

    /// In §4, a NEW FACE decided for `new`: false when the plane gate (§8.7) refuses it.
    pub(in crate::mapping) fn hook_admits_new_face(&self, new: &NewSegmentTrace) -> bool {
        !self.params.plane_gate || self.plane_gate(new)
    }

    /// In §4, new face `id` just filed: a corner diagonal at birth leaves the map (§8.11).
    pub(in crate::mapping) fn hook_new_face_filed(&mut self, id: SegmentId, trace: &mut StepTrace) {
        if self.params.corner_diagonals {
            self.remove_if_diagonal_at_birth(id, trace);
        }
    }

    /// After §5: confirmation (§8.7): refits that unconfirm, plane support of the step's
    /// matches, extensions and new faces, and baseline confirmation of point memory's pieces.
    pub(in crate::mapping) fn hook_updated(
        &mut self,
        new_segments: &[NewSegmentTrace],
        trace: &mut StepTrace,
        buffers: &StepBuffers,
    ) {
        if !self.params.confirm_segments {
            return;
        }
        if self.params.refit_unconfirms || self.params.refit_recounts {
            self.unconfirm_moved_refits(trace);
        }
        self.note_plane_support(new_segments, trace);
        if self.params.baseline_confirm && !buffers.memory_readings.is_empty() {
            self.note_baseline_support(&buffers.memory_readings, trace);
        }
    }

    /// After §6: free space (§8.6) removes the segments a kept reading saw past, then corner
    /// diagonals (§8.11) leave the map.
    pub(in crate::mapping) fn hook_step_ending(&mut self, trace: &mut StepTrace) {
        if self.params.free_space || self.trims_seen_through() {
            self.sweep_free_space(trace);
        }
        if self.params.corner_diagonals {
            self.remove_corner_diagonals(trace);
        }
    }
}
