//! `heading_correction` alone (docs/algorithm.md §8.17, "the odometry's drift"): the step's
//! heading is the odometry's less the drift the walls' axes show
//! ([`crate::mapping::ext::odometry_drift`]), or, in a second pass, the first pass's smoothed
//! error of the snapshot ([`crate::mapping::ext::drift_smoother`]); the position follows the
//! odometry's increments turned by it. The ranges do not pull.

use super::pose_correction::{odometry_increment, readings_trace, sigmas};
use crate::geometry::Pose;
use crate::mapping::ext::odometry_drift::{DriftUpdate, OdometryDrift};
use crate::mapping::ext::pose_correction::MIN_WALL_LENGTH_M;
use crate::mapping::ext::rectilinear_heading::{
    axis_deviation, walls_axis, HeadingLines, LineAge, LineSource,
};
use crate::mapping::model::ext_trace::{
    CorrectionRefusal, CorrectionTrace, DriftEstimate, HeadingLinesAge, HeadingObservation,
    ObservedDirection,
};
use crate::mapping::Mapper;
use crate::run::Snapshot;
use nalgebra::Matrix3;

/// A step's update of the drift by its wall lines.
#[derive(Clone, Copy, Debug)]
struct LinesUpdate {
    /// What the update did.
    update: DriftUpdate,
    /// The lines' standard deviation, radians.
    sigma_rad: f64,
    /// The gate, radians, when a line beyond
    /// [`crate::mapping::ext::rectilinear_heading::AXIS_GATE_RAD`] counted through it.
    widened_gate_rad: Option<f64>,
    /// The lines' mean age.
    age: LineAge,
}

impl Mapper {
    /// The step's pose with its heading corrected by the odometry's estimated drift (once it
    /// drifts): the drift grows by its causes over the odometry's increment, then the wall
    /// windows' lines update it (with `settled_walls`, the lines of the last step's settled
    /// readings; otherwise of this step's readings matched to the walls, which the trace
    /// lists). `predicted` (the last step's correction carried through the increment) gives
    /// the position, `prior` its covariance.
    pub(super) fn correct_heading_alone(
        &mut self,
        snapshot: &Snapshot,
        previous: Option<(f64, Pose)>,
        predicted: Pose,
        prior: Matrix3<f64>,
    ) -> CorrectionTrace {
        let (at_prediction, lines, source) = if self.heading_windows_from_settled() {
            let state = &mut self.pose_belief.rectilinear;
            let lines = std::mem::take(&mut state.pending_lines);
            let source = std::mem::take(&mut state.pending_source);
            (Vec::new(), lines, source)
        } else {
            let at_prediction =
                self.matched_readings(snapshot, previous, &predicted, &Matrix3::zeros());
            let lines = self.heading_lines(snapshot, previous, &at_prediction);
            (at_prediction, lines, LineSource::Sensors)
        };
        let with_correction = |correction_rad: f64| {
            Pose::new(
                predicted.x,
                predicted.y,
                snapshot.pose.heading_rad - correction_rad,
            )
        };
        if previous.is_none() {
            self.start_drift_from_calibration();
        }
        // The odometry's increment since the last step (none at the first).
        let increment = previous.map(|(_, before)| odometry_increment(&before, &snapshot.pose));
        let drift_before = self.predict_drift(increment);
        let update = self.update_drift(&lines, snapshot);
        self.record_drift_step(increment);
        let drift = &self.pose_belief.drift;
        let predicted = with_correction(drift_before.0);
        let tracked_rad = self.params.tracked_heading_error(self.step_index());
        let corrected = with_correction(tracked_rad.unwrap_or(drift.correction_rad()));
        let estimate = self.drift_estimate(tracked_rad);
        let drift = &self.pose_belief.drift;
        let heading = drift
            .axis_rad()
            .zip(update)
            .map(|(axis_rad, lines_update)| {
                heading_observation(axis_rad, lines_update, &lines, source)
            });
        self.pose_belief.covariance = prior;
        // With no readings matched (the settled windows), there is nothing to re-associate.
        let after = if corrected == predicted || at_prediction.is_empty() {
            at_prediction
                .iter()
                .map(|m| m.observation.residual_m())
                .collect()
        } else {
            self.residuals_at(
                snapshot,
                previous,
                (&corrected, &Matrix3::zeros()),
                &at_prediction,
            )
        };
        let (readings, rms_before, rms_after) = readings_trace(&at_prediction, &after);
        let position_sigma = sigmas(&prior);
        let sigmas_with = |heading_deg: f64| [position_sigma[0], position_sigma[1], heading_deg];
        CorrectionTrace {
            odometry: snapshot.pose,
            predicted,
            corrected,
            readings,
            rms_before,
            rms_after,
            prior_sigma: sigmas_with(drift_before.1.to_degrees()),
            posterior_sigma: sigmas_with(estimate.sigma_deg),
            directions: lines_direction(update).into_iter().collect(),
            refused: refusal(previous.is_none(), update),
            heading,
            drift: Some(estimate),
        }
    }

    /// The drift filter's estimate for the trace, with the heading error a second pass took
    /// from the first pass's track (`tracked_rad`).
    pub(super) fn drift_estimate(&self, tracked_rad: Option<f64>) -> DriftEstimate {
        let drift = &self.pose_belief.drift;
        let (kappa_rad, epsilon, sigma_rad) = drift.causes();
        DriftEstimate {
            heading_error_deg: drift.heading_error_rad().to_degrees(),
            sigma_deg: sigma_rad.to_degrees(),
            deg_per_m: kappa_rad.to_degrees(),
            turn_pct: 100.0 * epsilon,
            drifting: drift.drifting,
            tracked_deg: tracked_rad.map(f64::to_degrees),
        }
    }

    /// Notes the drift filter's step, after the odometry's `increment` (distance, turn), for
    /// the second pass's heading track, when this pass keeps one (`calibrate_first`,
    /// [`crate::mapping::ext::drift_smoother`]).
    fn record_drift_step(&mut self, increment: Option<(f64, f64)>) {
        let index = self.step_index();
        if let Some(history) = self.drift_history.as_mut() {
            let (distance_m, turn_rad) = increment.unwrap_or((0.0, 0.0));
            history.record(index, distance_m, turn_rad, &self.pose_belief.drift);
        }
    }

    /// The snapshot index of the step under way (`begin_step` has counted it).
    fn step_index(&self) -> usize {
        self.next_snapshot - 1
    }

    /// At the first step: a calibrated drift (`drift_deg_per_m`, `drift_per_turn_pct`)
    /// replaces the uninformed start.
    pub(super) fn start_drift_from_calibration(&mut self) {
        if let Some((deg_per_m, per_turn_pct)) = self.params.drift_calibration() {
            self.pose_belief.drift =
                OdometryDrift::calibrated(deg_per_m.to_radians(), per_turn_pct / 100.0);
        }
    }

    /// Carries the drift through the odometry's `increment` (distance, turn; none at the
    /// first step); the correction and the heading error's standard deviation (radians) after
    /// it.
    pub(super) fn predict_drift(&mut self, increment: Option<(f64, f64)>) -> (f64, f64) {
        let drift = &mut self.pose_belief.drift;
        if let Some((distance_m, turn_rad)) = increment {
            drift.predict(distance_m, turn_rad);
        }
        (drift.correction_rad(), drift.causes().2)
    }

    /// Updates the drift with the step's wall `lines` once the walls have set the axis (or
    /// sets it from the confirmed walls), then notes whether the odometry drifts. Each line
    /// observes the heading error of its readings' mean moment, its age before `snapshot`'s.
    fn update_drift(&mut self, lines: &HeadingLines, snapshot: &Snapshot) -> Option<LinesUpdate> {
        let now = self.odometry_moment(&snapshot.pose);
        let update = match self.pose_belief.drift.axis_ref_rad {
            None => {
                let walls = self.confirmed_wall_directions();
                if let Some((axis_rad, sigma_rad)) =
                    walls_axis(&walls, self.params.heading_window_m)
                {
                    self.pose_belief.drift.set_axis(axis_rad, sigma_rad);
                }
                None
            }
            Some(axis_ref_rad) => {
                let drift = &mut self.pose_belief.drift;
                let gate_rad = drift.axis_gate_rad();
                let fits = lines.iter().map(|(_, l)| (*l, l.age(now)));
                let rotation_rad = |age| drift.expected_rotation_rad(age);
                let seen = axis_deviation(fits, rotation_rad, axis_ref_rad, gate_rad);
                seen.map(|seen| LinesUpdate {
                    update: drift.update(seen.deviation_rad, seen.sigma_rad, seen.age),
                    sigma_rad: seen.sigma_rad,
                    widened_gate_rad: seen.beyond_axis_gate.then_some(gate_rad),
                    age: seen.age,
                })
            }
        };
        self.pose_belief.drift.note_significance();
        update
    }

    /// Whether the heading windows take the readings settled walls (§8.12) settled, at the
    /// step's end (`heading_correction` alone with `settled_walls`), instead of the readings
    /// matched to the walls at the prediction.
    pub(super) fn heading_windows_from_settled(&self) -> bool {
        self.params.corrects_heading_alone() && self.params.settled_walls
    }

    /// Whether the settled readings' echoes are kept for the walls' windows (`wall_windows`
    /// with [`Self::heading_windows_from_settled`]).
    pub(in crate::mapping) fn heading_windows_by_wall(&self) -> bool {
        self.params.wall_windows && self.heading_windows_from_settled()
    }

    /// The direction (radians) and length (metres) of each confirmed fitted wall the
    /// correction may match ([`MIN_WALL_LENGTH_M`] or longer).
    fn confirmed_wall_directions(&self) -> Vec<(f64, f64)> {
        self.map
            .confirmed_fitted()
            .map(|s| {
                let d = s.b.point - s.a.point;
                (d.y.atan2(d.x), d.norm())
            })
            .filter(|(_, length_m)| *length_m >= MIN_WALL_LENGTH_M)
            .collect()
    }
}

/// The trace of the lines' update (`lines_update`) against the map's axis (`axis_rad`): the
/// lines of `source`'s windows.
fn heading_observation(
    axis_rad: f64,
    lines_update: LinesUpdate,
    lines: &HeadingLines,
    source: LineSource,
) -> HeadingObservation {
    HeadingObservation {
        axis_deg: axis_rad.to_degrees(),
        deviation_deg: lines_update.update.innovation_rad.to_degrees(),
        deviation_after_deg: lines_update.update.innovation_after_rad.to_degrees(),
        sigma_deg: lines_update.sigma_rad.to_degrees(),
        sensors: lines.iter().map(|(s, _)| *s).collect(),
        open: source == LineSource::Open,
        walls: match source {
            LineSource::Walls(walls) => walls,
            _ => Vec::new(),
        },
        widened_gate_deg: lines_update.widened_gate_rad.map(f64::to_degrees),
        lines_age: Some(HeadingLinesAge {
            driven_m: lines_update.age.driven_m,
            turned_deg: lines_update.age.turned_rad.to_degrees(),
        }),
    }
}

/// Why the lines did not correct the step: the first step, or an innovation beyond the gate.
fn refusal(first_step: bool, update: Option<LinesUpdate>) -> Option<CorrectionRefusal> {
    if first_step {
        return Some(CorrectionRefusal::FirstStep);
    }
    update
        .filter(|l| !l.update.taken)
        .map(|l| CorrectionRefusal::BeyondBound {
            shift_m: 0.0,
            turn_deg: l.update.innovation_rad.to_degrees(),
        })
}

/// The direction the lines observed (heading), with their information, when they updated.
fn lines_direction(update: Option<LinesUpdate>) -> Option<ObservedDirection> {
    update
        .filter(|l| l.update.taken)
        .map(|l| ObservedDirection {
            direction: [0.0, 0.0, 1.0],
            information: 1.0 / (l.sigma_rad * l.sigma_rad),
            observed: true,
        })
}
