//! The mapper's pose-correction stage (docs/algorithm.md §8.17): before a step's readings are
//! converted, its pose is predicted from the last estimate and the odometry's increment, then
//! corrected against the confirmed walls and point features.

use crate::geometry::{wrap_pi, Pose};
use crate::mapping::ext::beam_geometry::HalfCone;
use crate::mapping::ext::free_space::cone_box_in;
use crate::mapping::ext::pose_correction::{
    calibrated_heading_share, capped, difference, feature_observation, gauss_newton_step,
    motion_noise, moved, observed_directions, wall_observation, RangeGate, RangeObservation,
    ITERATIONS, MIN_CHI2_GAIN, MIN_MATCHED_READINGS, MIN_WALL_LENGTH_M,
};
use crate::mapping::ext::rectilinear_heading::HeadingLines;
use crate::mapping::model::beam::Beam;
use crate::mapping::model::ext_trace::{
    CorrectionReading, CorrectionRefusal, CorrectionTarget, CorrectionTrace, ObservedDirection,
};
use crate::mapping::model::trace::StepTrace;
use crate::mapping::paper::reading_poses::reading_poses;
use crate::mapping::paper::readings::discard_reason;
use crate::mapping::Mapper;
use crate::run::Snapshot;
use crate::sonar::EchoModel;
use nalgebra::{Matrix3, Vector3};

/// A reading explained by a confirmed target, linearised.
#[derive(Clone, Copy, Debug)]
pub(super) struct Matched {
    /// The sensor that read it.
    pub sensor: usize,
    /// The target that explains it.
    pub target: CorrectionTarget,
    /// Its range against the target's prediction.
    pub observation: RangeObservation,
    /// The validation gate it was kept within, metres.
    pub gate_m: f64,
}

impl Mapper {
    /// The step's pose: the snapshot's odometry, or with `pose_correction` or
    /// `heading_correction` the corrected pose (recorded in `trace.correction`). `previous` is
    /// the last snapshot's time and odometry.
    pub(in crate::mapping) fn hook_step_pose(
        &mut self,
        snapshot: &Snapshot,
        previous: Option<(f64, Pose)>,
        trace: &mut StepTrace,
    ) -> Pose {
        if !self.params.corrects_pose() {
            return snapshot.pose;
        }
        let (predicted, prior) = self.predict(snapshot, previous);
        let correction = if self.params.corrects_heading_alone() {
            self.correct_heading_alone(snapshot, previous, predicted, prior)
        } else {
            self.correct(snapshot, previous, predicted, prior)
        };
        let corrected = correction.corrected;
        // Exactly the identity while the pose is the odometry's, so that a correction that
        // never moved leaves the map bit for bit as without it.
        self.pose_belief.odometry_to_map = if corrected == snapshot.pose {
            Pose::default()
        } else {
            // Its heading within a turn: the odometry's heading counts every turn driven, and
            // the transform would gain a turn each step past ±180° (bit for bit the same within
            // it).
            let transform = corrected.compose(&inverse(&snapshot.pose));
            Pose {
                heading_rad: wrap_pi(transform.heading_rad),
                ..transform
            }
        };
        trace.correction = Some(correction);
        corrected
    }

    /// The pose the last estimate and the odometry's increment predict, and its covariance
    /// (the last one carried through the motion, plus the increment's noise).
    pub(super) fn predict(
        &self,
        snapshot: &Snapshot,
        previous: Option<(f64, Pose)>,
    ) -> (Pose, Matrix3<f64>) {
        let belief = &self.pose_belief;
        let predicted = belief.odometry_to_map.compose(&snapshot.pose);
        let Some((_, odometry_before)) = previous else {
            return (predicted, Matrix3::zeros());
        };
        let (distance_m, turn_rad) = odometry_increment(&odometry_before, &snapshot.pose);
        let before = belief.odometry_to_map.compose(&odometry_before);
        let (dx, dy) = (predicted.x - before.x, predicted.y - before.y);
        let motion = Matrix3::new(1.0, 0.0, -dy, 0.0, 1.0, dx, 0.0, 0.0, 1.0);
        let heading_share = match self.params.drift_calibration() {
            Some((_, per_turn_pct)) => calibrated_heading_share(per_turn_pct / 100.0),
            None => 1.0,
        };
        let covariance = motion * belief.covariance * motion.transpose()
            + motion_noise(distance_m, turn_rad, heading_share);
        (predicted, capped(covariance))
    }

    /// The correction of a step predicted at `predicted` with covariance `prior`
    /// (`pose_correction`); updates the belief's covariance (and, with `heading_window`, the
    /// wall windows).
    fn correct(
        &mut self,
        snapshot: &Snapshot,
        previous: Option<(f64, Pose)>,
        predicted: Pose,
        prior: Matrix3<f64>,
    ) -> CorrectionTrace {
        let at_prediction = self.matched_readings(snapshot, previous, &predicted, &prior);
        let lines = self.heading_lines(snapshot, previous, &at_prediction);
        self.set_axis_if_none(snapshot, &predicted, &lines);
        let (estimate, posterior) = self.solve(
            snapshot,
            previous,
            (predicted, prior),
            &at_prediction,
            &lines,
        );
        let after = self.residuals_at(snapshot, previous, (&estimate, &prior), &at_prediction);
        let (readings, rms_before, rms_after) = readings_trace(&at_prediction, &after);
        let heading = self.heading_trace(snapshot, &lines, &predicted, &estimate);
        let heading_gain = heading.as_ref().map_or(0.0, |h| {
            (h.deviation_deg.powi(2) - h.deviation_after_deg.powi(2)) / h.sigma_deg.powi(2)
        });
        let rms_pair = (rms_before, rms_after);
        let gain =
            chi2_gain(at_prediction.len(), rms_pair, &prior, &predicted, &estimate) + heading_gain;
        let refused = refusal(
            previous.is_none(),
            &at_prediction,
            &predicted,
            &estimate,
            &prior,
        )
        .or((gain < MIN_CHI2_GAIN).then_some(CorrectionRefusal::NoBetter));
        let corrected = if refused.is_some() {
            predicted
        } else {
            estimate
        };
        self.pose_belief.covariance = if refused.is_some() { prior } else { posterior };
        let observations: Vec<RangeObservation> =
            at_prediction.iter().map(|m| m.observation).collect();
        CorrectionTrace {
            odometry: snapshot.pose,
            predicted,
            corrected,
            readings,
            rms_before,
            rms_after,
            prior_sigma: sigmas(&prior),
            posterior_sigma: sigmas(&self.pose_belief.covariance),
            directions: observed_directions(&observations, &prior)
                .into_iter()
                .map(|(direction, information, observed)| ObservedDirection {
                    direction,
                    information,
                    observed,
                })
                .collect(),
            refused,
            heading,
            drift: None,
        }
    }

    /// The iterated update from the prediction (pose and covariance): each iteration
    /// re-associates the readings at the new estimate; the wall windows' heading observation
    /// joins the ranges. Returns the estimate and its covariance.
    fn solve(
        &self,
        snapshot: &Snapshot,
        previous: Option<(f64, Pose)>,
        (predicted, prior): (Pose, Matrix3<f64>),
        at_prediction: &[Matched],
        lines: &HeadingLines,
    ) -> (Pose, Matrix3<f64>) {
        let mut estimate = predicted;
        let mut posterior = prior;
        let mut matched = at_prediction.to_vec();
        for _ in 0..ITERATIONS {
            if matched.len() < MIN_MATCHED_READINGS {
                break;
            }
            let mut observations: Vec<RangeObservation> =
                matched.iter().map(|m| m.observation).collect();
            observations.extend(self.heading_observation(snapshot, lines, &estimate));
            let from_prior = difference(&predicted, &estimate);
            let Some((step, covariance)) = gauss_newton_step(&prior, &from_prior, &observations)
            else {
                break;
            };
            estimate = moved(&estimate, &step);
            posterior = covariance;
            matched = self.matched_readings(snapshot, previous, &estimate, &prior);
        }
        (estimate, posterior)
    }

    /// Each kept reading of `snapshot` taken from `pose` that a confirmed wall or point feature
    /// explains, with the target whose prediction is nearest the range. The gate widens with
    /// the pose's covariance `covariance` ([`RangeGate::for_pose`]; zeros: the paper's
    /// tolerance).
    pub(super) fn matched_readings(
        &self,
        snapshot: &Snapshot,
        previous: Option<(f64, Pose)>,
        pose: &Pose,
        covariance: &Matrix3<f64>,
    ) -> Vec<Matched> {
        self.beams_from(snapshot, previous, pose)
            .into_iter()
            .filter_map(|(sensor, beam)| {
                let gate = self.gate(&beam, pose, covariance);
                self.best_target(&beam, pose, gate)
                    .map(|(target, observation)| Matched {
                        sensor,
                        target,
                        observation,
                        gate_m: gate.width_m(beam.range_m),
                    })
            })
            .collect()
    }

    /// The residuals at `pose` (gated with its covariance) of the readings `matched` matched,
    /// each against its own target (the residual at the prediction when the target no longer
    /// explains it there).
    pub(super) fn residuals_at(
        &self,
        snapshot: &Snapshot,
        previous: Option<(f64, Pose)>,
        (pose, covariance): (&Pose, &Matrix3<f64>),
        matched: &[Matched],
    ) -> Vec<f64> {
        let beams = self.beams_from(snapshot, previous, pose);
        matched
            .iter()
            .map(|m| {
                beams
                    .iter()
                    .find(|(s, _)| *s == m.sensor)
                    .and_then(|(_, beam)| {
                        let gate = self.gate(beam, pose, covariance);
                        self.observe(beam, pose, gate, m.target)
                    })
                    .map_or(m.observation.residual_m(), |o| o.residual_m())
            })
            .collect()
    }

    /// The kept readings' beams (§1: what the paper keeps) were the robot at `pose`, each from
    /// its own moment (§1.1).
    pub(super) fn beams_from(
        &self,
        snapshot: &Snapshot,
        previous: Option<(f64, Pose)>,
        pose: &Pose,
    ) -> Vec<(usize, Beam)> {
        let mut own = Vec::new();
        if snapshot.reading_dt_s.len() == self.layout.len() {
            reading_poses(
                previous,
                snapshot.t,
                &snapshot.pose,
                pose,
                &snapshot.reading_dt_s,
                &mut own,
            );
        }
        self.beam_axes
            .iter()
            .enumerate()
            .filter_map(|(sensor, axis)| {
                let range_m = snapshot.ranges_m.get(sensor).copied().flatten();
                if discard_reason(range_m, self.sensor.max_range_m, &self.params).is_some() {
                    return None;
                }
                let frame = own.get(sensor).unwrap_or(pose).robot_frame();
                Some((
                    sensor,
                    Beam {
                        origin: frame.to_world(&axis.origin_in_robot),
                        direction: frame.direction_to_world(&axis.direction_in_robot),
                        range_m: range_m?,
                    },
                ))
            })
            .collect()
    }

    /// The confirmed target whose prediction for `beam` is nearest its range, among the fitted
    /// walls the grid files near the cone and the confirmed point features.
    fn best_target(
        &self,
        beam: &Beam,
        pose: &Pose,
        gate: RangeGate,
    ) -> Option<(CorrectionTarget, RangeObservation)> {
        let (_, half_beam_rad) = self.accuracy_and_half_beam();
        let gate_m = gate.width_m(beam.range_m);
        let (low, high, bulge_m) = cone_box_in(
            beam,
            HalfCone::new(half_beam_rad),
            (beam.range_m - gate_m).max(0.0),
            beam.range_m + gate_m,
        );
        let mut best: Option<(CorrectionTarget, RangeObservation)> = None;
        let mut consider = |target: CorrectionTarget, o: Option<RangeObservation>| {
            if let Some(o) = o {
                if best.is_none_or(|(_, b)| o.residual_m().abs() < b.residual_m().abs()) {
                    best = Some((target, o));
                }
            }
        };
        self.map
            .visit_segments_along(&low, &high, bulge_m, |id, s| {
                let long_enough = (s.b.point - s.a.point).norm() >= MIN_WALL_LENGTH_M;
                if s.fitted && long_enough && self.map.is_confirmed(id) {
                    let target = CorrectionTarget::Wall(id);
                    consider(target, self.observe(beam, pose, gate, target));
                }
            });
        for f in self.map.confirmed_features() {
            let target = CorrectionTarget::Feature(f.id);
            consider(target, self.observe(beam, pose, gate, target));
        }
        best
    }

    /// The validation gate of `beam` from a robot at `pose` with covariance `covariance`.
    fn gate(&self, beam: &Beam, pose: &Pose, covariance: &Matrix3<f64>) -> RangeGate {
        let (accuracy_pct, _) = self.accuracy_and_half_beam();
        RangeGate::for_pose(accuracy_pct, beam, &pose.position(), covariance)
    }

    /// What `target` predicts for `beam` from a robot at `pose`, if it explains the reading
    /// within `gate`.
    fn observe(
        &self,
        beam: &Beam,
        pose: &Pose,
        gate: RangeGate,
        target: CorrectionTarget,
    ) -> Option<RangeObservation> {
        let (_, half_beam_rad) = self.accuracy_and_half_beam();
        let half = HalfCone::new(half_beam_rad);
        let robot = pose.position();
        match target {
            CorrectionTarget::Wall(id) => {
                let s = self.map.segment(id)?;
                let along_axis = self.sensor.echo == EchoModel::Axis;
                wall_observation(beam, &s.a.point, &s.b.point, &robot, gate, half, along_axis)
            }
            CorrectionTarget::Feature(id) => {
                let f = self.map.feature(id)?;
                feature_observation(beam, &f.at, f.radius_m, &robot, gate, half)
            }
        }
    }
}

/// Why the correction from `predicted` to `estimate` is refused, before its residuals are
/// compared: the first step, too few readings `matched`, or a move beyond three of the prior's
/// standard deviations.
fn refusal(
    first_step: bool,
    matched: &[Matched],
    predicted: &Pose,
    estimate: &Pose,
    prior: &Matrix3<f64>,
) -> Option<CorrectionRefusal> {
    if first_step {
        return Some(CorrectionRefusal::FirstStep);
    }
    if matched.len() < MIN_MATCHED_READINGS {
        return Some(CorrectionRefusal::TooFewReadings {
            matched: matched.len(),
            needed: MIN_MATCHED_READINGS,
        });
    }
    let d: Vector3<f64> = difference(predicted, estimate);
    let shift_m = d.x.hypot(d.y);
    let bound_m = 3.0 * (prior[(0, 0)] + prior[(1, 1)]).max(0.0).sqrt();
    let bound_rad = 3.0 * prior[(2, 2)].max(0.0).sqrt();
    (shift_m > bound_m || d.z.abs() > bound_rad).then_some(CorrectionRefusal::BeyondBound {
        shift_m,
        turn_deg: d.z.to_degrees(),
    })
}

/// The trace of the readings `matched` at the prediction, with their residuals `after` the
/// correction, and the RMS of their normalised residuals before and after.
pub(super) fn readings_trace(
    matched: &[Matched],
    after: &[f64],
) -> (Vec<CorrectionReading>, f64, f64) {
    let rms_before = rms(matched
        .iter()
        .map(|m| m.observation.residual_m() / m.observation.sigma_m));
    let rms_after = rms(after
        .iter()
        .zip(matched)
        .map(|(r, m)| r / m.observation.sigma_m));
    let readings = matched
        .iter()
        .zip(after)
        .map(|(m, &residual_after_m)| CorrectionReading {
            sensor: m.sensor,
            target: m.target,
            residual_before_m: m.observation.residual_m(),
            residual_after_m,
            sigma_m: m.observation.sigma_m,
            gate_m: m.gate_m,
        })
        .collect();
    (readings, rms_before, rms_after)
}

/// How much moving from `predicted` to `estimate` lowers the sum of squared normalised
/// residuals of `n` readings (RMS before and after), less the prior's Mahalanobis term.
fn chi2_gain(
    n: usize,
    (rms_before, rms_after): (f64, f64),
    prior: &Matrix3<f64>,
    predicted: &Pose,
    estimate: &Pose,
) -> f64 {
    let from_prior = difference(predicted, estimate);
    let prior_term = prior.try_inverse().map_or(0.0, |information| {
        (from_prior.transpose() * information * from_prior)[(0, 0)]
    });
    n as f64 * (rms_before * rms_before - rms_after * rms_after) - prior_term
}

/// The odometry's increment from `before` to `now`: the distance driven (metres) and the turn
/// (radians, the short way round).
pub(super) fn odometry_increment(before: &Pose, now: &Pose) -> (f64, f64) {
    let increment = before.relative_to(now);
    (increment.x.hypot(increment.y), increment.heading_rad)
}

/// `pose⁻¹`: the transform that undoes it.
pub(super) fn inverse(pose: &Pose) -> Pose {
    pose.relative_to(&Pose::default())
}

/// The root mean square of `values` (0 for none).
fn rms(values: impl Iterator<Item = f64>) -> f64 {
    let (sum, n) = values.fold((0.0, 0usize), |(s, n), v| (s + v * v, n + 1));
    if n == 0 {
        0.0
    } else {
        (sum / n as f64).sqrt()
    }
}

/// The standard deviations of `covariance`: x and y in metres, heading in degrees.
pub(super) fn sigmas(covariance: &Matrix3<f64>) -> [f64; 3] {
    let s = |k: usize| covariance[(k, k)].max(0.0).sqrt();
    [s(0), s(1), s(2).to_degrees()]
}
