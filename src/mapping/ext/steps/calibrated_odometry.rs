//! Calibrate, then correct (docs/algorithm.md §8.17): with `pose_correction` and a drift
//! calibration (a first pass's, `calibrate_first`), the pose is corrected from the odometry
//! the calibration mends, not from the raw odometry. Each snapshot's odometry is turned by
//! the heading error the first pass tracked (or the calibrated drift, past its track), its
//! position following the odometry's increments turned by the last step's error, as the
//! heading correction alone places a step (UMBmark's calibration before localisation,
//! Borenstein and Feng 1996). Everything in the step then reads the mended snapshot.

use super::pose_correction::{inverse, odometry_increment};
use crate::geometry::Pose;
use crate::mapping::model::trace::StepTrace;
use crate::mapping::Mapper;
use crate::run::Snapshot;

impl Mapper {
    /// The snapshot with its odometry mended by the calibration, when the pose is corrected
    /// from calibrated odometry (`Params::corrects_calibrated_odometry`); `None` otherwise.
    /// Called before the step is counted.
    pub(in crate::mapping) fn hook_calibrated_snapshot(
        &mut self,
        snapshot: &Snapshot,
    ) -> Option<Snapshot> {
        if !self.params.corrects_calibrated_odometry() {
            return None;
        }
        let last = self.pose_belief.calibrated_odometry;
        if last.is_none() {
            self.start_drift_from_calibration();
        }
        let increment = last.map(|(raw_before, _)| odometry_increment(&raw_before, &snapshot.pose));
        self.predict_drift(increment);
        let error_rad = self
            .params
            .tracked_heading_error(self.next_snapshot)
            .unwrap_or(self.pose_belief.drift.correction_rad());
        let position = match last {
            // The raw increment carried by the last step's mending.
            Some((raw_before, mended_before)) => mended_before
                .compose(&inverse(&raw_before))
                .compose(&snapshot.pose),
            None => snapshot.pose,
        };
        let mended = Pose::new(
            position.x,
            position.y,
            snapshot.pose.heading_rad - error_rad,
        );
        self.pose_belief.calibrated_odometry = Some((snapshot.pose, mended));
        Some(Snapshot {
            pose: mended,
            ..snapshot.clone()
        })
    }

    /// The step's correction as traced from calibrated odometry: the raw odometry as the
    /// odometry, and the drift with the heading error the first pass tracked.
    pub(in crate::mapping) fn hook_calibrated_trace(
        &self,
        raw_odometry: Pose,
        trace: &mut StepTrace,
    ) {
        let tracked_rad = self.params.tracked_heading_error(trace.snapshot);
        if let Some(correction) = trace.correction.as_mut() {
            correction.odometry = raw_odometry;
            correction.drift = Some(self.drift_estimate(tracked_rad));
        }
    }
}
