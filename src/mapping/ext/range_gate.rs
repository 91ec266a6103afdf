//! Pose correction's validation gate (docs/algorithm.md §8.17, *Association*): how far a range
//! may lie from a confirmed target's prediction and still be explained by it.

use crate::geometry::Point;
use crate::mapping::ext::beam_geometry::feature_tolerance_m;
use crate::mapping::model::beam::Beam;
use nalgebra::Matrix3;

/// The validation gate's width in standard deviations of the range the pose's uncertainty
/// predicts ([`RangeGate`]): 1, the innovation's own deviation (0.5, 1.5, 2 and 3 mapped the
/// drifting laps worse, docs/algorithm.md §8.17).
pub const GATE_SIGMAS: f64 = 1.0;
/// How far a range may lie from a target's prediction and still be explained by it: the paper's
/// tolerance `max(ξ·D/100, 1 in)` (the range's own standard deviation), widened by what the
/// pose's uncertainty makes of the prediction. This is Leonard and Durrant-Whyte's (1991)
/// validation gate: a residual ν is kept when `ν² ≤ σ² + g²·σ_pose²`, σ the tolerance,
/// g [`GATE_SIGMAS`], σ_pose the predicted range's standard deviation from the pose alone. With
/// a certain pose the gate is the paper's tolerance, bit for bit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RangeGate {
    /// ξ, percent of the range.
    pub accuracy_pct: f64,
    /// The standard deviation of the range the pose's uncertainty predicts, metres.
    pub pose_sigma_m: f64,
}

impl RangeGate {
    /// The paper's tolerance alone (a certain pose).
    pub fn tolerance(accuracy_pct: f64) -> Self {
        Self {
            accuracy_pct,
            pose_sigma_m: 0.0,
        }
    }

    /// The gate for `beam`, from a robot at `robot` whose pose has covariance `covariance` (x,
    /// y in metres, heading in radians). The range's derivative by position is a unit vector
    /// and by heading at most the sensor's lever from the robot's centre, so its standard
    /// deviation is at most √λ (λ the position covariance's larger eigenvalue) plus the lever
    /// times the heading's: the bound is taken, the same for every target of the beam.
    pub fn for_pose(
        accuracy_pct: f64,
        beam: &Beam,
        robot: &Point,
        covariance: &Matrix3<f64>,
    ) -> Self {
        let (xx, yy, xy) = (covariance[(0, 0)], covariance[(1, 1)], covariance[(0, 1)]);
        let larger = 0.5 * (xx + yy) + (0.25 * (xx - yy).powi(2) + xy * xy).sqrt();
        let lever_m = (beam.origin - robot).norm();
        Self {
            accuracy_pct,
            pose_sigma_m: larger.max(0.0).sqrt() + lever_m * covariance[(2, 2)].max(0.0).sqrt(),
        }
    }

    /// The range's own standard deviation: the paper's tolerance at `range_m`.
    pub fn sigma_m(&self, range_m: f64) -> f64 {
        feature_tolerance_m(self.accuracy_pct, range_m)
    }

    /// The largest residual kept for a range `range_m`, metres.
    pub fn width_m(&self, range_m: f64) -> f64 {
        let sigma_m = self.sigma_m(range_m);
        if self.pose_sigma_m > 0.0 {
            sigma_m.hypot(GATE_SIGMAS * self.pose_sigma_m)
        } else {
            sigma_m
        }
    }

    /// Whether `predicted_m` explains the range `range_m`.
    pub fn keeps(&self, range_m: f64, predicted_m: f64) -> bool {
        (predicted_m - range_m).abs() <= self.width_m(range_m)
    }
}
