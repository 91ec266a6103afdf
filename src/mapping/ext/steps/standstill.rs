//! A robot standing still adds no view (docs/algorithm.md §8.19): the step that sets its
//! snapshot aside.

use super::pose_correction::sigmas;
use crate::geometry::Pose;
use crate::mapping::ext::standstill::stood_still;
use crate::mapping::model::ext_trace::{CorrectionRefusal, CorrectionTrace, StandstillTrace};
use crate::mapping::model::trace::StepTrace;
use crate::mapping::Mapper;
use crate::run::Snapshot;

impl Mapper {
    /// Before anything else of a step: with `standstill` on, when the odometry (as the log
    /// gives it) stood still since the last mapped snapshot, the step's trace, and the step
    /// ends there. Such a step changes nothing but the snapshot count and the time the robot
    /// was last seen at its pose (the next step's readings fired in sequence are placed from
    /// it, §1.1): no pose correction or drift update, no readings, no map change. Otherwise
    /// `None`, and this snapshot is the last mapped.
    pub(in crate::mapping) fn hook_stood_still(
        &mut self,
        snapshot: &Snapshot,
    ) -> Option<StepTrace> {
        let tolerance_m = self.params.standstill_m;
        if tolerance_m <= 0.0 {
            return None;
        }
        let index = self.next_snapshot;
        let still = self.map.last_mapped.and_then(|(since_snapshot, last)| {
            stood_still(&last, &snapshot.pose, tolerance_m).map(|(moved_m, turned_rad)| {
                StandstillTrace {
                    since_snapshot,
                    moved_m,
                    turned_rad,
                }
            })
        });
        let Some(still) = still else {
            self.map.last_mapped = Some((index, snapshot.pose));
            return None;
        };
        self.next_snapshot += 1;
        self.last_t_s = Some(snapshot.t);
        // Where the last mapped step put the robot, within the tolerance of where it stands.
        let pose = self.step_frame.map_or(snapshot.pose, |(pose, _)| pose);
        Some(StepTrace {
            snapshot: index,
            t: snapshot.t,
            pose: Some(pose),
            warnings: self.range_count_warning(snapshot).into_iter().collect(),
            stood_still: Some(still),
            correction: self.stood_still_correction(snapshot, index, pose),
            ..Default::default()
        })
    }

    /// With a pose correction on, the record of the step `index` set aside: the pose kept,
    /// refused as [`CorrectionRefusal::StoodStill`], the drift as it stands.
    fn stood_still_correction(
        &self,
        snapshot: &Snapshot,
        index: usize,
        pose: Pose,
    ) -> Option<CorrectionTrace> {
        if !self.params.corrects_pose() {
            return None;
        }
        let mut sigma = sigmas(&self.pose_belief.covariance);
        let tracked_rad = self.params.tracked_heading_error(index);
        // As the steps that map record it: the heading alone's, or the calibrated pass's.
        let drift = (self.params.corrects_heading_alone()
            || self.params.corrects_calibrated_odometry())
        .then(|| self.drift_estimate(tracked_rad));
        if let Some(d) = &drift {
            sigma[2] = d.sigma_deg;
        }
        Some(CorrectionTrace {
            odometry: snapshot.pose,
            predicted: pose,
            corrected: pose,
            readings: Vec::new(),
            rms_before: 0.0,
            rms_after: 0.0,
            prior_sigma: sigma,
            posterior_sigma: sigma,
            directions: Vec::new(),
            refused: Some(CorrectionRefusal::StoodStill),
            heading: None,
            drift,
        })
    }
}
