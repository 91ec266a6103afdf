//! Pose correction against the confirmed map (docs/algorithm.md §8.17): the math, apart from
//! the step that uses it (`steps/pose_correction.rs`).
//!
//! The pose is an estimate with a covariance, as in Leonard and Durrant-Whyte's EKF
//! localisation (1991): odometry's increment predicts it and grows its covariance; ranges that
//! a confirmed wall (the plane model: the echo from the foot of the perpendicular, Kleeman and
//! Kuc) or a confirmed point feature explains within the paper's tolerance update it. The
//! update is an iterated EKF (Gauss–Newton on the prior plus the range residuals), the segment
//! map standing in for Crowley's (1989) matched line segments. A direction no range constrains
//! keeps the prediction: a corridor fixes heading and lateral position, not the position along
//! it.

use crate::geometry::{Point, Pose, Vec2};
use crate::mapping::ext::beam_geometry::HalfCone;
use crate::mapping::ext::confirm::axis_meets_wall;
use crate::mapping::ext::odometry_drift::{
    OdometryDrift, CALIBRATED_PRIOR_FACTOR, TURN_ERROR_PRIOR,
};
pub use crate::mapping::ext::range_gate::RangeGate;
use crate::mapping::ext::rectilinear_heading::RectilinearState;
use crate::mapping::model::beam::Beam;
use nalgebra::{Matrix3, SymmetricEigen, Vector3};

/// Odometry's error per metre driven, as a standard deviation of position (3 %: the "bad" end
/// of UMBmark's wheel errors, Borenstein and Feng 1996).
pub const POSITION_NOISE_PER_M: f64 = 0.03;
/// Odometry's heading error per metre driven, radians (5° a 10 m, the same "bad" end).
pub const HEADING_NOISE_RAD_PER_M: f64 = 5.0 * std::f64::consts::PI / 180.0 / 10.0;
/// Odometry's heading error per radian turned (5 %).
pub const HEADING_NOISE_PER_RAD: f64 = 0.05;
/// The noise of an increment however small (1 mm, 0.05°): a standing robot's pose can still be
/// refined.
pub const NOISE_FLOOR: (f64, f64) = (0.001, 0.05 * std::f64::consts::PI / 180.0);
/// The largest standard deviation the estimate keeps (0.5 m, 10°): past it the map says no more
/// than the odometry, and a correction that large is no correction.
pub const MAX_SIGMA: (f64, f64) = (0.5, 10.0 * std::f64::consts::PI / 180.0);
/// Iterations of the update (each re-associates the readings at the new pose).
pub const ITERATIONS: usize = 3;
/// How much a correction must lower the sum of squared normalised residuals (prior included)
/// to be taken: 0, it must not explain the readings worse than the prediction. (6, what
/// fitting three numbers to noise gains twice over, refused nearly every step of the
/// generated families: their specular walls give one reading a wall a step.)
pub const MIN_CHI2_GAIN: f64 = 0.0;
/// Shortest confirmed wall a reading is matched against (0.5 m): a short piece's direction is
/// too uncertain to pull the pose.
pub const MIN_WALL_LENGTH_M: f64 = 0.5;
/// Fewest readings the map must explain for a correction.
pub const MIN_MATCHED_READINGS: usize = 2;
/// The scale of heading in the observability figures: one radian counts as this many metres.
pub const HEADING_SCALE_M: f64 = 1.0;

/// The pose estimate carried from step to step: the transform from the odometry's frame into
/// the map's (`map pose = odometry_to_map ⊕ odometry pose`), the covariance of the map pose
/// (x, y in metres, heading in radians), and the wall windows that observe heading.
#[derive(Clone, Debug, PartialEq)]
pub struct PoseBelief {
    /// The rigid transform from odometry into the map.
    pub odometry_to_map: Pose,
    /// The covariance of the map pose.
    pub covariance: Matrix3<f64>,
    /// The windows of wall readings and the map's axis (`heading_window`).
    pub rectilinear: RectilinearState,
    /// The odometry's drift (`heading_correction` alone, or the calibrated odometry's).
    pub drift: OdometryDrift,
    /// The last step's raw and calibrated odometry (`pose_correction` with a calibration).
    pub calibrated_odometry: Option<(Pose, Pose)>,
}

impl Default for PoseBelief {
    fn default() -> Self {
        Self {
            odometry_to_map: Pose::default(),
            covariance: Matrix3::zeros(),
            rectilinear: RectilinearState::default(),
            drift: OdometryDrift::default(),
            calibrated_odometry: None,
        }
    }
}

/// The covariance an odometry increment of `distance_m` and `turn_rad` adds, its heading's
/// standard deviation scaled by `heading_share`: 1, or [`calibrated_heading_share`] once the
/// odometry is calibrated.
pub fn motion_noise(distance_m: f64, turn_rad: f64, heading_share: f64) -> Matrix3<f64> {
    let sigma_xy = NOISE_FLOOR.0 + POSITION_NOISE_PER_M * distance_m;
    let sigma_heading = heading_share
        * (NOISE_FLOOR.1
            + HEADING_NOISE_RAD_PER_M * distance_m
            + HEADING_NOISE_PER_RAD * turn_rad.abs());
    Matrix3::from_diagonal(&Vector3::new(
        sigma_xy * sigma_xy,
        sigma_xy * sigma_xy,
        sigma_heading * sigma_heading,
    ))
}

/// The share of the heading noise of [`motion_noise`] that odometry calibrated with an error
/// of `turn_error` per radian turned keeps (docs/algorithm.md §8.17, "Runs that come back"):
/// that error over the prior's 5 % ([`TURN_ERROR_PRIOR`]), within [`CALIBRATED_PRIOR_FACTOR`]
/// and 1. The calibration has taken out the drift the noise stands for, and it leaves more of
/// it, the larger the error per turn it mends.
pub fn calibrated_heading_share(turn_error: f64) -> f64 {
    (turn_error.abs() / TURN_ERROR_PRIOR).clamp(CALIBRATED_PRIOR_FACTOR, 1.0)
}

/// `covariance` with its standard deviations held within [`MAX_SIGMA`].
pub fn capped(covariance: Matrix3<f64>) -> Matrix3<f64> {
    let mut c = covariance;
    let limits = [MAX_SIGMA.0, MAX_SIGMA.0, MAX_SIGMA.1];
    for (k, limit) in limits.iter().enumerate() {
        let sigma = c[(k, k)].max(0.0).sqrt();
        if sigma > *limit {
            let scale = limit / sigma;
            for j in 0..3 {
                c[(k, j)] *= scale;
                c[(j, k)] *= scale;
            }
        }
    }
    c
}

/// One range a confirmed target explains, linearised at the pose it was found at.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RangeObservation {
    /// The range read, metres.
    pub range_m: f64,
    /// The range the target predicts, metres.
    pub predicted_m: f64,
    /// The predicted range's derivatives by the robot's x, y (per metre) and heading (per
    /// radian).
    pub jacobian: Vector3<f64>,
    /// The range's standard deviation, metres: the paper's ball radius ξ·D (at least 1 in).
    pub sigma_m: f64,
}

impl RangeObservation {
    /// Read minus predicted, metres.
    pub fn residual_m(&self) -> f64 {
        self.range_m - self.predicted_m
    }
}

/// The derivatives of a range from a sensor at `origin` along the unit vector `away` (from the
/// target to the sensor), for a robot at `robot`: moving the robot moves the sensor with it,
/// turning it swings the sensor about the robot's centre.
fn range_jacobian(origin: &Point, robot: &Point, away: &Vec2) -> Vector3<f64> {
    let lever = origin - robot;
    Vector3::new(away.x, away.y, away.x * -lever.y + away.y * lever.x)
}

/// The range the wall `a`–`b` predicts for `beam`, when it explains the range within `gate`;
/// linearised for a robot at `robot`. The plane model
/// (§8.7) hears the foot of the perpendicular: its normal must lie inside the cone and the foot
/// on the wall (10 % slack). With `along_axis` (a sensor whose echo comes from its axis, as in
/// `confirm::supports_along_axis`) the wall is heard where the axis meets it (10 % slack), at
/// any incidence, and the range is the distance along the axis.
///
/// ```
/// use sonarmap::geometry::{Point, Vec2};
/// use sonarmap::mapping::ext::beam_geometry::HalfCone;
/// use sonarmap::mapping::ext::pose_correction::{wall_observation, RangeGate};
/// use sonarmap::mapping::model::beam::Beam;
/// // A sensor 0.2 m ahead of the robot at the origin reads 1.82 m towards the wall x = 2:
/// // predicted 1.8 m; moving the robot +x shortens the range (∂/∂x = −1).
/// let beam = Beam { origin: Point::new(0.2, 0.0), direction: Vec2::new(1.0, 0.0), range_m: 1.82 };
/// let half = HalfCone::new(12.5f64.to_radians());
/// let gate = RangeGate::tolerance(3.0);
/// let o = wall_observation(&beam, &Point::new(2.0, -1.0), &Point::new(2.0, 1.0), &Point::origin(), gate, half, false).unwrap();
/// assert!((o.predicted_m - 1.8).abs() < 1e-12 && (o.residual_m() - 0.02).abs() < 1e-12);
/// assert!((o.jacobian.x + 1.0).abs() < 1e-12 && o.jacobian.z.abs() < 1e-12);
/// ```
pub fn wall_observation(
    beam: &Beam,
    a: &Point,
    b: &Point,
    robot: &Point,
    gate: RangeGate,
    half: HalfCone,
    along_axis: bool,
) -> Option<RangeObservation> {
    let along = b - a;
    let length2 = along.norm_squared();
    if length2 <= 0.0 {
        return None;
    }
    let foot = a + along * ((beam.origin - a).dot(&along) / length2);
    let away = beam.origin - foot;
    let distance_m = away.norm();
    if distance_m <= 0.0 {
        return None;
    }
    let away = away / distance_m;
    let cos_off_normal = -away.dot(&beam.direction);
    let (predicted_m, jacobian) = if along_axis {
        // Heard where the axis meets the wall, at any incidence: h = d / c, c = −n·u; moving
        // the robot moves d, turning it moves d and turns u.
        let met_m = axis_meets_wall(beam, a, b)?.range_m;
        let lever = beam.origin - robot;
        let turned_u = Vec2::new(-beam.direction.y, beam.direction.x);
        let dd_dtheta = away.x * -lever.y + away.y * lever.x;
        let dc_dtheta = -away.dot(&turned_u);
        let c = cos_off_normal;
        let jacobian = Vector3::new(
            away.x / c,
            away.y / c,
            dd_dtheta / c - distance_m * dc_dtheta / (c * c),
        );
        (met_m, jacobian)
    } else {
        let foot_along = (foot - a).dot(&along) / length2;
        if !(-0.1..=1.1).contains(&foot_along) || cos_off_normal < half.cos {
            return None;
        }
        (distance_m, range_jacobian(&beam.origin, robot, &away))
    };
    gate.keeps(beam.range_m, predicted_m)
        .then_some(RangeObservation {
            range_m: beam.range_m,
            predicted_m,
            jacobian,
            sigma_m: gate.sigma_m(beam.range_m),
        })
}

/// The range a point feature at `at` (a pillar of radius `radius_m`, 0 for a corner or edge)
/// predicts for `beam`, when it lies inside the cone and explains the range within `gate`;
/// linearised for a robot at `robot`.
pub fn feature_observation(
    beam: &Beam,
    at: &Point,
    radius_m: f64,
    robot: &Point,
    gate: RangeGate,
    half: HalfCone,
) -> Option<RangeObservation> {
    let away = beam.origin - at;
    let distance_m = away.norm();
    let predicted_m = distance_m - radius_m;
    if distance_m <= 0.0 || !gate.keeps(beam.range_m, predicted_m) {
        return None;
    }
    let away = away / distance_m;
    (-away.dot(&beam.direction) >= half.cos).then(|| RangeObservation {
        range_m: beam.range_m,
        predicted_m,
        jacobian: range_jacobian(&beam.origin, robot, &away),
        sigma_m: gate.sigma_m(beam.range_m),
    })
}

/// The information the observations give about the pose: `Σ Hᵀ H / σ²`.
pub fn information(observations: &[RangeObservation]) -> Matrix3<f64> {
    observations.iter().fold(Matrix3::zeros(), |sum, o| {
        sum + o.jacobian * o.jacobian.transpose() / (o.sigma_m * o.sigma_m)
    })
}

/// One Gauss–Newton step of the iterated update from `estimate` (offset `from_prior` =
/// estimate − prediction, as x, y, heading): minimises the prior's Mahalanobis distance plus
/// the observations' squared residuals over their variances. Returns the step to add to the
/// estimate, and the posterior covariance; `None` when the prior's covariance cannot be
/// inverted.
pub fn gauss_newton_step(
    prior_covariance: &Matrix3<f64>,
    from_prior: &Vector3<f64>,
    observations: &[RangeObservation],
) -> Option<(Vector3<f64>, Matrix3<f64>)> {
    let prior_information = prior_covariance.try_inverse()?;
    let a = prior_information + information(observations);
    let b = observations
        .iter()
        .fold(-(prior_information * from_prior), |sum, o| {
            sum + o.jacobian * (o.residual_m() / (o.sigma_m * o.sigma_m))
        });
    let posterior = a.try_inverse()?;
    Some((posterior * b, posterior))
}

/// The pose `estimate` moved by `step` (x, y in metres, heading in radians).
pub fn moved(estimate: &Pose, step: &Vector3<f64>) -> Pose {
    Pose::new(
        estimate.x + step.x,
        estimate.y + step.y,
        estimate.heading_rad + step.z,
    )
}

/// `to − from` as x, y and heading (the short way round).
pub fn difference(from: &Pose, to: &Pose) -> Vector3<f64> {
    Vector3::new(
        to.x - from.x,
        to.y - from.y,
        crate::geometry::wrap_pi(to.heading_rad - from.heading_rad),
    )
}

/// The directions of the pose the observations' information constrains more than the prior
/// does: eigenvectors of the information (heading scaled by [`HEADING_SCALE_M`]), each with its
/// information, strongest first.
pub fn observed_directions(
    observations: &[RangeObservation],
    prior_covariance: &Matrix3<f64>,
) -> Vec<([f64; 3], f64, bool)> {
    let scale = Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, 1.0 / HEADING_SCALE_M));
    let info = scale * information(observations) * scale;
    let prior = prior_covariance
        .try_inverse()
        .map(|p| scale * p * scale)
        .unwrap_or_else(Matrix3::zeros);
    let eigen = SymmetricEigen::new(info);
    let mut directions: Vec<([f64; 3], f64, bool)> = (0..3)
        .map(|k| {
            let v: Vector3<f64> = eigen.eigenvectors.column(k).into_owned();
            let v = if v.x + v.y + v.z < 0.0 { -v } else { v };
            let prior_along = (v.transpose() * prior * v)[(0, 0)];
            let value = eigen.eigenvalues[k].max(0.0);
            ([v.x, v.y, v.z], value, value > prior_along)
        })
        .collect();
    directions.sort_by(|p, q| q.1.total_cmp(&p.1));
    directions
}

#[cfg(test)]
mod tests {
    use super::*;

    fn half() -> HalfCone {
        HalfCone::new(12.5f64.to_radians())
    }

    /// The paper's tolerance at ξ = 3 %.
    fn gate() -> RangeGate {
        RangeGate::tolerance(3.0)
    }

    /// Beams from a robot at `pose` along its own axes (sensor at the centre) at `headings`
    /// (robot frame), reading the true ranges `true_ranges`.
    fn beams(pose: &Pose, headings_deg: &[f64], true_ranges: &[f64]) -> Vec<Beam> {
        headings_deg
            .iter()
            .zip(true_ranges)
            .map(|(h, r)| {
                let a = pose.heading_rad + h.to_radians();
                Beam {
                    origin: pose.position(),
                    direction: Vec2::new(a.cos(), a.sin()),
                    range_m: *r,
                }
            })
            .collect()
    }

    /// Iterates the update from `prediction` with the walls, as the step does.
    fn solve(
        prediction: Pose,
        prior: Matrix3<f64>,
        walls: &[(Point, Point)],
        beam_of: impl Fn(&Pose) -> Vec<Beam>,
    ) -> Pose {
        let mut estimate = prediction;
        for _ in 0..ITERATIONS {
            let observations: Vec<RangeObservation> = beam_of(&estimate)
                .iter()
                .filter_map(|b| {
                    walls.iter().find_map(|(a, w)| {
                        wall_observation(b, a, w, &estimate.position(), gate(), half(), true)
                    })
                })
                .collect();
            let from_prior = difference(&prediction, &estimate);
            let (step, _) = gauss_newton_step(&prior, &from_prior, &observations).unwrap();
            estimate = moved(&estimate, &step);
        }
        estimate
    }

    #[test]
    fn two_walls_at_a_right_angle_fix_a_known_offset() {
        // Walls x = 2 and y = 3 meet at a corner. The robot truly stands at (0, 0) facing +x
        // and its sensors (at its centre, echoes along their axes) read each wall on its normal
        // and 5° either side of it: 2 m and 2/cos 5° = 2.00764 m ahead, 3 m and 3/cos 5° =
        // 3.01147 m to its left. Odometry says
        // (0.05, −0.04), 1° off: the solved pose is the truth.
        let walls = [
            (Point::new(2.0, -5.0), Point::new(2.0, 5.0)),
            (Point::new(-5.0, 3.0), Point::new(5.0, 3.0)),
        ];
        let c5 = 5f64.to_radians().cos();
        let headings = [-5.0, 0.0, 5.0, 85.0, 90.0, 95.0];
        let ranges = [2.0 / c5, 2.0, 2.0 / c5, 3.0 / c5, 3.0, 3.0 / c5];
        let prediction = Pose::new(0.05, -0.04, 1f64.to_radians());
        // A loose prior (1 m, 1 rad): the ranges decide. (One snapshot's readings 5° off the
        // normals say little of heading: a 20° prior would keep a fifth of the 1°.)
        let prior = Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, 1.0));
        let solved = solve(prediction, prior, &walls, |p| beams(p, &headings, &ranges));
        assert!(solved.x.abs() < 2e-3 && solved.y.abs() < 2e-3, "{solved:?}");
        assert!(
            solved.heading_rad.abs() < 0.05f64.to_radians(),
            "{solved:?}"
        );
    }

    #[test]
    fn a_corridor_fixes_lateral_position_and_heading_and_leaves_the_along_position_to_the_prior() {
        // Walls y = ±1 along x. Truly at (0, 0), heading 0; readings at ±90° and ±85° (1 m and
        // 1/cos 5°). Odometry says (0.3, 0.02), heading 1° (the ranges it predicts within the
        // 3 % tolerance of those read): the x offset must stay, y and heading must go.
        let walls = [
            (Point::new(-10.0, 1.0), Point::new(10.0, 1.0)),
            (Point::new(-10.0, -1.0), Point::new(10.0, -1.0)),
        ];
        let c5 = 5f64.to_radians().cos();
        let headings = [85.0, 90.0, 95.0, -85.0, -90.0, -95.0];
        let ranges = [1.0 / c5, 1.0, 1.0 / c5, 1.0 / c5, 1.0, 1.0 / c5];
        let prediction = Pose::new(0.3, 0.02, 1f64.to_radians());
        let prior = Matrix3::from_diagonal(&Vector3::new(0.01, 0.01, 1.0));
        let solved = solve(prediction, prior, &walls, |p| beams(p, &headings, &ranges));
        assert!((solved.x - 0.3).abs() < 1e-9, "along kept: {solved:?}");
        assert!(solved.y.abs() < 2e-3, "lateral fixed: {solved:?}");
        assert!(solved.heading_rad.abs() < 0.1f64.to_radians(), "{solved:?}");
        // The information says which: y and heading observed, x not.
        let observations: Vec<RangeObservation> =
            beams(&Pose::new(0.0, 0.0, 0.0), &headings, &ranges)
                .iter()
                .filter_map(|b| {
                    walls.iter().find_map(|(a, w)| {
                        wall_observation(b, a, w, &Point::origin(), gate(), half(), true)
                    })
                })
                .collect();
        let directions = observed_directions(&observations, &prior);
        let unobserved: Vec<_> = directions.iter().filter(|d| !d.2).collect();
        assert_eq!(unobserved.len(), 1);
        assert!(unobserved[0].0[0].abs() > 0.999, "{directions:?}");
    }

    #[test]
    fn an_axis_sensor_observes_a_wall_where_its_axis_meets_it_off_the_normal() {
        // The wall y = 2 from x = 0.5 to 5. A sensor 0.2 m ahead of the robot at the origin
        // looks 40° off the wall's normal, towards +x: its axis meets the wall at x = 0.2 +
        // 2·tan 40° = 1.878, 2/cos 40° = 2.6108 m away, far outside any cone about the normal.
        let (a, w) = (Point::new(0.5, 2.0), Point::new(5.0, 2.0));
        let off = 40f64.to_radians();
        let beam_at = |robot: &Pose| {
            let heading = robot.heading_rad + std::f64::consts::FRAC_PI_2 - off;
            let (s, c) = robot.heading_rad.sin_cos();
            Beam {
                origin: Point::new(robot.x + 0.2 * c, robot.y + 0.2 * s),
                direction: Vec2::new(heading.cos(), heading.sin()),
                range_m: 2.0 / off.cos(),
            }
        };
        // The robot at `robot` reading the wall `a`–`b`, its echo along the axis or at the foot.
        let observe = |robot: &Pose, b: &Point, along_axis: bool| {
            let at = robot.position();
            wall_observation(&beam_at(robot), &a, b, &at, gate(), half(), along_axis)
        };
        let robot = Pose::new(0.0, 0.0, 0.0);
        let o = observe(&robot, &w, true).unwrap();
        assert!((o.predicted_m - 2.0 / off.cos()).abs() < 1e-12, "{o:?}");
        // ∂h/∂y = −1/cos 40° = −1.3054; ∂h/∂x = 0; ∂h/∂θ against a finite difference.
        assert!(o.jacobian.x.abs() < 1e-12 && (o.jacobian.y + 1.0 / off.cos()).abs() < 1e-12);
        let h = observe(&Pose::new(0.0, 0.0, 1e-6), &w, true)
            .unwrap()
            .predicted_m;
        assert!(
            ((h - o.predicted_m) / 1e-6 - o.jacobian.z).abs() < 1e-4,
            "{o:?}"
        );
        // The plane model hears only the foot: 40° off the normal is outside the 12.5° cone.
        assert!(observe(&robot, &w, false).is_none());
        // The axis past the wall's end (10 % slack) observes nothing.
        assert!(observe(&robot, &Point::new(1.2, 2.0), true).is_none());
    }

    #[test]
    fn the_gate_widens_by_the_range_deviation_the_pose_covariance_predicts() {
        // A sensor 0.2 m from the robot's centre reads 1 m (ξ = 3 %: σ = 3 cm). The pose's
        // position deviations are 3 cm and 2 cm, its heading's 1°: the range's deviation from
        // the pose is at most 3 cm + 0.2 m · 1° = 3.349 cm, and the gate √(3² + 3.349²) =
        // 4.496 cm. A wall 4 cm off the range is explained; 5 cm is not; with a certain pose,
        // neither.
        let beam = Beam {
            origin: Point::new(0.2, 0.0),
            direction: Vec2::new(1.0, 0.0),
            range_m: 1.0,
        };
        let covariance =
            Matrix3::from_diagonal(&Vector3::new(0.0009, 0.0004, 1f64.to_radians().powi(2)));
        let gate = RangeGate::for_pose(3.0, &beam, &Point::origin(), &covariance);
        assert!(
            (gate.pose_sigma_m - 0.033490658504).abs() < 1e-12,
            "{gate:?}"
        );
        assert!((gate.width_m(1.0) - 0.044962475544).abs() < 1e-12);
        let wall_at = |x: f64| (Point::new(x, -1.0), Point::new(x, 1.0));
        let robot = Point::origin();
        let observe = |x: f64, gate: RangeGate| {
            let (a, b) = wall_at(x);
            wall_observation(&beam, &a, &b, &robot, gate, half(), false)
        };
        let o = observe(1.16, gate).unwrap();
        assert!((o.residual_m() - 0.04).abs() < 1e-12 && o.sigma_m == 0.03);
        assert!(observe(1.15, gate).is_none());
        assert!(observe(1.16, RangeGate::tolerance(3.0)).is_none());
        assert!(observe(1.175, RangeGate::tolerance(3.0)).is_some());
    }

    #[test]
    fn with_nothing_observed_the_step_is_zero() {
        let prior = Matrix3::identity() * 0.01;
        let (step, posterior) = gauss_newton_step(&prior, &Vector3::zeros(), &[]).unwrap();
        assert_eq!(step, Vector3::zeros());
        assert!((posterior - prior).norm() < 1e-15);
    }

    #[test]
    fn motion_noise_grows_with_distance_and_turn() {
        let still = motion_noise(0.0, 0.0, 1.0);
        assert!((still[(0, 0)].sqrt() - 0.001).abs() < 1e-15);
        // 1 m: 1 mm + 3 cm.
        assert!((motion_noise(1.0, 0.0, 1.0)[(0, 0)].sqrt() - 0.031).abs() < 1e-12);
        assert!(motion_noise(0.0, 1.0, 1.0)[(2, 2)] > still[(2, 2)]);
        // 1 m and a quarter turn: 0.05° + 0.5° + 5 % of 90° = 5.05°; calibrated with 2 % a
        // turn, 2/5 of it, 2.02°; the position's noise is the same.
        let quarter = std::f64::consts::FRAC_PI_2;
        let heading_deg = |share| {
            motion_noise(1.0, quarter, share)[(2, 2)]
                .sqrt()
                .to_degrees()
        };
        assert!((heading_deg(1.0) - 5.05).abs() < 1e-12);
        let share = calibrated_heading_share(-0.02);
        assert!((share - 0.4).abs() < 1e-12);
        assert!((heading_deg(share) - 2.02).abs() < 1e-12);
        let calibrated = motion_noise(1.0, quarter, share);
        assert_eq!(calibrated[(0, 0)], motion_noise(1.0, quarter, 1.0)[(0, 0)]);
        // 0.5 % a turn keeps a tenth (the least), 8 % all of it.
        assert_eq!(calibrated_heading_share(0.005), 0.1);
        assert_eq!(calibrated_heading_share(0.08), 1.0);
        let big = capped(Matrix3::identity() * 4.0);
        assert!((big[(0, 0)].sqrt() - 0.5).abs() < 1e-12);
        assert!((big[(2, 2)].sqrt() - MAX_SIGMA.1).abs() < 1e-12);
    }
}
