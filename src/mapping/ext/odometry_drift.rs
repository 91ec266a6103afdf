//! The odometry's heading error, estimated from the walls' axes with its causes (docs/algorithm.md
//! §8.17, "the odometry's drift"): the math of `heading_correction`, apart from the step that
//! uses it (`steps/heading_alone.rs`).
//!
//! A wheeled robot's heading error is mostly systematic: unequal wheel diameters turn it a
//! little with every metre driven, and a wrong wheelbase scales every turn (Borenstein and
//! Feng's UMBmark, 1996, the paper's reference \[1\]). So the filter estimates those two causes as
//! well as the error itself, the odometry calibrated on line as in Martinelli, Tomatis and
//! Siegwart's "Simultaneous localization and odometry self calibration" (2007) and Roy and
//! Thrun's on-line self-calibration (1999). Its state is
//! - `b`, the odometry's heading minus the map's, radians;
//! - `κ`, its growth per metre driven, radians;
//! - `ε`, its growth per radian turned;
//! - `a`, the offset of the reference axis (the direction of the map's confirmed walls when it
//!   was set, [`crate::mapping::ext::rectilinear_heading::walls_axis`]) from the true axis,
//!   radians.
//!
//! The wall windows' lines, laid out in the odometry's frame, lie along the map's axes turned by
//! `b`: they observe `b − a` (modulo 90°) as it was at their readings' mean moment, `κ` and `ε`
//! times the distance and turn since taken off `b` (docs/algorithm.md §8.17, *Line age*). The
//! reference axis comes from the map's walls, drawn with the heading of their time, so `a`
//! starts as the error that heading had ([`OdometryDrift::set_axis`]); the lines drawn at
//! different distances driven and across turns then separate `b`'s causes. The correction
//! follows the drift the odometry shows instead of each line's noise: on a robot whose odometry
//! does not drift, `κ` and `ε` settle near 0 and the heading stays put.

use crate::mapping::ext::rectilinear_heading::{LineAge, AXIS_GATE_RAD, WIDE_GATE_MAX_RAD};
use nalgebra::{Matrix4, Vector4};

/// The prior standard deviation of the drift per metre driven (0.5°/m: the bad end of UMBmark's
/// wheel errors, 5° a 10 m).
pub const DRIFT_RATE_PRIOR_RAD_PER_M: f64 = 0.5 * std::f64::consts::PI / 180.0;
/// The prior standard deviation of the error per radian turned (5 %).
pub const TURN_ERROR_PRIOR: f64 = 0.05;
/// The largest error per radian turned the estimate may take (10 %, twice its prior): beyond
/// it the filter is explaining something else. Driving straight, the odometry's small turns
/// are its own wheel noise, so a heading that wanders faster than the random growth the
/// filter allows ([`RANDOM_HEADING_RAD_PER_SQRT_M`]) correlates with them and reads as an
/// error per turn: on the Pioneer stand-in given `drift.py`'s wheel noise of 5 mm per √m, the
/// estimate reached 19 % before a U-turn and then turned the map 35° (docs/algorithm.md §8.17,
/// "Bounded causes").
pub const MAX_TURN_ERROR: f64 = 2.0 * TURN_ERROR_PRIOR;
/// The heading error's random growth per metre driven (0.2°/√m, wheel noise and slip), as a
/// standard deviation. Wheel noise of 1 mm per √m on each wheel of a 0.33 m wheelbase (the
/// mild drift of both drift models, `OdometryError::MILD` and `drift.py`) grows the heading by
/// 0.25°/√m; at 0.1°/√m the filter held its error within 0.3–0.45° while the stand-in's was
/// 1–2° (docs/algorithm.md §8.17 has the measurements).
pub const RANDOM_HEADING_RAD_PER_SQRT_M: f64 = 0.2 * std::f64::consts::PI / 180.0;
/// How fast the systematic drift per metre may itself change, per √m driven (0.01°/m per √m): a
/// load or a floor changes it slowly.
pub const DRIFT_RATE_CHANGE_PER_SQRT_M: f64 = 0.01 * std::f64::consts::PI / 180.0;
/// How fast the error per radian turned may change, per √rad turned (0.1 %).
pub const TURN_SCALE_CHANGE_PER_SQRT_RAD: f64 = 0.001;
/// The smallest drift per metre driven the correction acts on (0.05°/m, half of a mild 1° a
/// 10 m): below it the odometry is as good as the walls can tell.
pub const MIN_DRIFT_RAD_PER_M: f64 = 0.05 * std::f64::consts::PI / 180.0;
/// The smallest error per radian turned the correction acts on (0.4 %, under a mild
/// wheelbase error of 0.5 %).
pub const MIN_TURN_ERROR: f64 = 0.004;
/// How many of its standard deviations a cause must be from 0 to count (2; 2.5 and 3 latched
/// later on drifting runs, and none of them on runs without drift).
pub const SIGNIFICANT_SIGMAS: f64 = 2.0;
/// The smallest heading error that latches the correction by itself (1°, with
/// [`ERROR_SIGMAS`]): at 3 m a degree moves a wall 5 cm, past the paper's tolerance.
pub const MIN_ERROR_RAD: f64 = std::f64::consts::PI / 180.0;
/// How many of its standard deviations the heading error must be from 0 to latch (3).
pub const ERROR_SIGMAS: f64 = 3.0;
/// How far an update may pull, in standard deviations of its innovation: a line further off
/// is not the wall the filter expects.
pub const GATE_SIGMAS: f64 = 3.0;

/// Index of the heading error `b` in the state.
pub(crate) const B: usize = 0;
const KAPPA: usize = 1;
const EPSILON: usize = 2;
const A: usize = 3;

/// The filter's state and covariance (order `b`, `κ`, `ε`, `a`), and the reference axis.
#[derive(Clone, Debug, PartialEq)]
pub struct OdometryDrift {
    /// The estimate.
    pub mean: Vector4<f64>,
    /// Its covariance.
    pub covariance: Matrix4<f64>,
    /// The reference axis in the map's frame (radians in [0, 90°)), once the walls set it.
    pub axis_ref_rad: Option<f64>,
    /// Whether a cause of drift has been significant (and beyond the smallest the correction
    /// acts on) at some step: until then the odometry is taken as it is, since correcting a
    /// heading that does not drift only adds the lines' noise to it, and the position would
    /// integrate that noise.
    pub drifting: bool,
}

impl Default for OdometryDrift {
    /// At the start: no heading error, the causes unknown within the bad end of UMBmark's
    /// errors, no axis yet.
    fn default() -> Self {
        Self {
            mean: Vector4::zeros(),
            covariance: Matrix4::from_diagonal(&Vector4::new(
                0.0,
                DRIFT_RATE_PRIOR_RAD_PER_M.powi(2),
                TURN_ERROR_PRIOR.powi(2),
                0.0,
            )),
            axis_ref_rad: None,
            drifting: false,
        }
    }
}

/// What an update did: the innovation (the lines' deviation from where the estimate expects
/// them) before and after, and its standard deviation, radians.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DriftUpdate {
    /// The lines' deviation from the expected axis before the update.
    pub innovation_rad: f64,
    /// The deviation after it.
    pub innovation_after_rad: f64,
    /// The innovation's standard deviation (lines and estimate).
    pub sigma_rad: f64,
    /// False when the innovation was beyond [`GATE_SIGMAS`] and left out.
    pub taken: bool,
}

/// The factor a calibration (`drift_deg_per_m`, `drift_per_turn_pct`) takes the priors of the
/// drift's causes down by: it is known within a tenth of them.
pub const CALIBRATED_PRIOR_FACTOR: f64 = 0.1;

impl OdometryDrift {
    /// A drift known beforehand: `kappa_rad_per_m` per metre and `epsilon` per radian turned
    /// (held within [`MAX_TURN_ERROR`]), each within [`CALIBRATED_PRIOR_FACTOR`] of its prior,
    /// taken off from the first step.
    ///
    /// ```
    /// use sonarmap::mapping::ext::odometry_drift::OdometryDrift;
    /// // 0.3°/m known: after 2 m straight the correction is 0.6°.
    /// let mut drift = OdometryDrift::calibrated(0.3f64.to_radians(), 0.0);
    /// drift.predict(2.0, 0.0);
    /// assert!((drift.correction_rad().to_degrees() - 0.6).abs() < 1e-12);
    /// ```
    pub fn calibrated(kappa_rad_per_m: f64, epsilon: f64) -> Self {
        let mut drift = Self::default();
        drift.mean[KAPPA] = kappa_rad_per_m;
        drift.mean[EPSILON] = epsilon.clamp(-MAX_TURN_ERROR, MAX_TURN_ERROR);
        let factor2 = CALIBRATED_PRIOR_FACTOR * CALIBRATED_PRIOR_FACTOR;
        drift.covariance[(KAPPA, KAPPA)] *= factor2;
        drift.covariance[(EPSILON, EPSILON)] *= factor2;
        drift.drifting = true;
        drift
    }

    /// The odometry's heading error (its heading minus the map's), radians.
    pub fn heading_error_rad(&self) -> f64 {
        self.mean[B]
    }

    /// The correction to take off the odometry's heading, radians: the estimated error once
    /// the odometry is [`Self::drifting`], else 0.
    pub fn correction_rad(&self) -> f64 {
        if self.drifting {
            self.mean[B]
        } else {
            0.0
        }
    }

    /// Latches [`Self::drifting`] once [`Self::causes_significant`] or
    /// [`Self::error_significant`].
    pub fn note_significance(&mut self) {
        self.drifting |= self.causes_significant() || self.error_significant();
    }

    /// Whether the drift per metre or per radian turned is beyond both its smallest value
    /// ([`MIN_DRIFT_RAD_PER_M`], [`MIN_TURN_ERROR`]) and [`SIGNIFICANT_SIGMAS`] of its standard
    /// deviation.
    pub fn causes_significant(&self) -> bool {
        self.beyond(KAPPA, MIN_DRIFT_RAD_PER_M, SIGNIFICANT_SIGMAS)
            || self.beyond(EPSILON, MIN_TURN_ERROR, SIGNIFICANT_SIGMAS)
    }

    /// Whether state `k` is beyond both `smallest` and `sigmas` of its standard deviation from 0.
    fn beyond(&self, k: usize, smallest: f64, sigmas: f64) -> bool {
        let value = self.mean[k].abs();
        value >= smallest && value >= sigmas * self.covariance[(k, k)].max(0.0).sqrt()
    }

    /// Whether, once the walls have set the axis, the heading error itself is beyond both
    /// [`MIN_ERROR_RAD`] and [`ERROR_SIGMAS`] of its standard deviation: a short run may end
    /// before its lines have told the drift's causes apart, while its heading is already off
    /// by more than the map can bear.
    ///
    /// ```
    /// use nalgebra::{Matrix4, Vector4};
    /// use sonarmap::mapping::ext::odometry_drift::OdometryDrift;
    /// let mut drift = OdometryDrift::default();
    /// drift.axis_ref_rad = Some(0.0);
    /// // 1.2° within 0.3°: four deviations.
    /// drift.mean = Vector4::new(1.2f64.to_radians(), 0.0, 0.0, 0.0);
    /// drift.covariance = Matrix4::from_diagonal(&Vector4::new(0.3f64.to_radians().powi(2), 0.0, 0.0, 0.0));
    /// assert!(drift.error_significant());
    /// // Within 0.5°: under three deviations.
    /// drift.covariance[(0, 0)] = 0.5f64.to_radians().powi(2);
    /// assert!(!drift.error_significant());
    /// // 0.9° within 0.1°: under 1°.
    /// drift.mean[0] = 0.9f64.to_radians();
    /// drift.covariance[(0, 0)] = 0.1f64.to_radians().powi(2);
    /// assert!(!drift.error_significant());
    /// ```
    pub fn error_significant(&self) -> bool {
        self.axis_ref_rad.is_some() && self.beyond(B, MIN_ERROR_RAD, ERROR_SIGMAS)
    }

    /// The estimated drift per metre driven (radians) and per radian turned, with the heading
    /// error's standard deviation (radians).
    pub fn causes(&self) -> (f64, f64, f64) {
        (
            self.mean[KAPPA],
            self.mean[EPSILON],
            self.covariance[(B, B)].max(0.0).sqrt(),
        )
    }

    /// The map's axis as estimated (radians in [0, 90°)): the reference axis less its offset.
    pub fn axis_rad(&self) -> Option<f64> {
        self.axis_ref_rad
            .map(|r| (r - self.mean[A]).rem_euclid(std::f64::consts::FRAC_PI_2))
    }

    /// The motion matrix F of a step that drove `distance_m` and turned `turn_rad`: the
    /// identity but for row b, (1, distance, turn, 0).
    pub fn motion(distance_m: f64, turn_rad: f64) -> Matrix4<f64> {
        let mut motion = Matrix4::identity();
        motion[(B, KAPPA)] = distance_m;
        motion[(B, EPSILON)] = turn_rad;
        motion
    }

    /// The odometry drove `distance_m` and turned `turn_rad`: the error grows by its causes,
    /// and the uncertainty by the random part.
    ///
    /// The motion is the identity but for row b, (1, distance, turn, 0): F·x and F·P·Fᵀ
    /// change row b, then column b, only.
    pub fn predict(&mut self, distance_m: f64, turn_rad: f64) {
        let grown = |v: &Vector4<f64>| v[B] + distance_m * v[KAPPA] + turn_rad * v[EPSILON];
        self.mean[B] = grown(&self.mean);
        let p = &mut self.covariance;
        for j in 0..4 {
            p[(B, j)] = grown(&p.column(j).into_owned());
        }
        for i in 0..4 {
            p[(i, B)] = grown(&p.row(i).transpose());
        }
        p[(B, B)] += RANDOM_HEADING_RAD_PER_SQRT_M.powi(2) * distance_m;
        p[(KAPPA, KAPPA)] += DRIFT_RATE_CHANGE_PER_SQRT_M.powi(2) * distance_m;
        p[(EPSILON, EPSILON)] += TURN_SCALE_CHANGE_PER_SQRT_RAD.powi(2) * turn_rad.abs();
    }

    /// Sets the reference axis, in the map's frame, to `axis_rad`, the walls' directions
    /// spread within `sigma_rad` about it.
    ///
    /// The walls were drawn with the heading of their time, so the axis is off by the error
    /// that heading had: the odometry's error less the correction taken. `a` starts as a copy
    /// of `b` less the correction, correlated with `b` and its causes as `b` is, its variance
    /// `b`'s plus the walls' spread: a feature placed from an uncertain pose inherits that
    /// pose's error (Smith, Self and Cheeseman's stochastic map, 1990). The lines, which
    /// observe `b − a`, then leave the error the heading had when the axis was set to the
    /// odometry's model instead of taking it for the true axis.
    ///
    /// ```
    /// use nalgebra::{Matrix4, Vector4};
    /// use sonarmap::mapping::ext::odometry_drift::OdometryDrift;
    /// // b is 0.2 rad within 0.1 (variance 0.01), not yet corrected; the walls spread 0.02.
    /// let mut drift = OdometryDrift::default();
    /// drift.mean = Vector4::new(0.2, 0.0, 0.0, 0.0);
    /// drift.covariance = Matrix4::from_diagonal(&Vector4::new(0.01, 1e-4, 1e-3, 0.0));
    /// drift.set_axis(0.3, 0.02);
    /// assert_eq!(drift.mean[3], 0.2); // b less the correction (none taken yet)
    /// assert!((drift.covariance[(3, 3)] - 0.0104).abs() < 1e-15); // 0.01 + 0.02²
    /// assert_eq!(drift.covariance[(0, 3)], 0.01); // as correlated with b as b is
    /// ```
    pub fn set_axis(&mut self, axis_rad: f64, sigma_rad: f64) {
        self.axis_ref_rad = Some(axis_rad.rem_euclid(std::f64::consts::FRAC_PI_2));
        self.mean[A] = self.mean[B] - self.correction_rad();
        for k in 0..A {
            self.covariance[(A, k)] = self.covariance[(B, k)];
            self.covariance[(k, A)] = self.covariance[(k, B)];
        }
        self.covariance[(A, A)] = self.covariance[(B, B)] + sigma_rad * sigma_rad;
    }

    /// The rotation that carries odometry lines of age `age` to where the estimate expects
    /// them on the reference axis: −(b − a) as it was when their readings were read, the
    /// drift since (κ·driven + ε·turned) taken off `b`.
    ///
    /// ```
    /// use nalgebra::Vector4;
    /// use sonarmap::mapping::ext::odometry_drift::OdometryDrift;
    /// use sonarmap::mapping::ext::rectilinear_heading::LineAge;
    /// // b 2°, a 0.5°, κ 0.5°/m, ε 2 %: a line read 1 m and 10° ago lies along
    /// // b − a − 0.5° − 0.2° = 0.8°.
    /// let mut drift = OdometryDrift::default();
    /// let deg = |d: f64| d.to_radians();
    /// drift.mean = Vector4::new(deg(2.0), deg(0.5), 0.02, deg(0.5));
    /// assert!((drift.expected_rotation_rad(LineAge::default()) + deg(1.5)).abs() < 1e-12);
    /// let age = LineAge { driven_m: 1.0, turned_rad: deg(10.0) };
    /// assert!((drift.expected_rotation_rad(age) + deg(0.8)).abs() < 1e-12);
    /// ```
    pub fn expected_rotation_rad(&self, age: LineAge) -> f64 {
        -(observation(age).transpose() * self.mean)[(0, 0)]
    }

    /// The variance of what lines of age `age` observe, `b − κ·driven − ε·turned − a`
    /// (radians²).
    fn observed_variance(&self, age: LineAge) -> f64 {
        let h = observation(age);
        (h.transpose() * self.covariance * h)[(0, 0)]
    }

    /// How far from the expected axis a line may lie and count (radians): [`AXIS_GATE_RAD`],
    /// widened to [`GATE_SIGMAS`] standard deviations of `b − a` when the estimate is that
    /// uncertain, up to [`WIDE_GATE_MAX_RAD`]. After a U-turn with the error per radian turned
    /// still unknown (5 %), the heading may be 9° off; the lines of the next pass, beyond 5°,
    /// would be refused for good and the error kept.
    ///
    /// ```
    /// use nalgebra::{Matrix4, Vector4};
    /// use sonarmap::mapping::ext::odometry_drift::OdometryDrift;
    /// let mut drift = OdometryDrift::default();
    /// drift.axis_ref_rad = Some(0.0);
    /// // b − a known within 1°: the 5° gate.
    /// drift.covariance = Matrix4::from_diagonal(&Vector4::new(1f64.to_radians().powi(2), 0.0, 0.0, 0.0));
    /// assert!((drift.axis_gate_rad().to_degrees() - 5.0).abs() < 1e-12);
    /// // A U-turn (π) with the error per radian turned 5 % unknown: σ 9°, gate 20° at most.
    /// drift.covariance = Matrix4::from_diagonal(&Vector4::new(0.0, 0.0, 0.05f64.powi(2), 0.0));
    /// drift.predict(0.0, std::f64::consts::PI);
    /// assert!((drift.axis_gate_rad().to_degrees() - 20.0).abs() < 1e-12);
    /// // σ 4°: 12°.
    /// drift.covariance = Matrix4::from_diagonal(&Vector4::new(4f64.to_radians().powi(2), 0.0, 0.0, 0.0));
    /// assert!((drift.axis_gate_rad().to_degrees() - 12.0).abs() < 1e-9);
    /// ```
    pub fn axis_gate_rad(&self) -> f64 {
        (GATE_SIGMAS * self.observed_variance(LineAge::default()).max(0.0).sqrt())
            .clamp(AXIS_GATE_RAD, WIDE_GATE_MAX_RAD)
    }

    /// Updates with the lines' innovation `innovation_rad` (their deviation from the reference
    /// axis after [`Self::expected_rotation_rad`] at their `age`) of standard deviation
    /// `sigma_rad`; refused beyond [`GATE_SIGMAS`]. The error per radian turned is held
    /// within [`MAX_TURN_ERROR`].
    ///
    /// ```
    /// use nalgebra::{Matrix4, Vector4};
    /// use sonarmap::mapping::ext::odometry_drift::OdometryDrift;
    /// // The error is 0 ± 5° and the axis known exactly; a line says 1° with σ 0.5°: the error
    /// // moves by σ_b² / (σ_b² + σ²) of it.
    /// let mut drift = OdometryDrift::default();
    /// drift.axis_ref_rad = Some(0.0);
    /// drift.covariance = Matrix4::from_diagonal(&Vector4::new(5f64.to_radians().powi(2), 0.0, 0.0, 0.0));
    /// let update = drift.update(1f64.to_radians(), 0.5f64.to_radians(), Default::default());
    /// let expected = 25.0 / 25.25; // σ_b² / (σ_b² + σ²)
    /// assert!((drift.heading_error_rad().to_degrees() - expected).abs() < 1e-9);
    /// assert!(update.taken && (update.innovation_after_rad.to_degrees() - (1.0 - expected)).abs() < 1e-9);
    /// ```
    pub fn update(&mut self, innovation_rad: f64, sigma_rad: f64, age: LineAge) -> DriftUpdate {
        let h = observation(age);
        let variance = self.observed_variance(age) + sigma_rad * sigma_rad;
        let mut update = DriftUpdate {
            innovation_rad,
            innovation_after_rad: innovation_rad,
            sigma_rad: variance.max(0.0).sqrt(),
            taken: false,
        };
        if variance <= 0.0 || innovation_rad.abs() > GATE_SIGMAS * update.sigma_rad {
            return update;
        }
        let gain = self.covariance * h / variance;
        let mean_before = self.mean;
        self.mean += gain * innovation_rad;
        // The estimate projected onto its bound (Simon and Chia 2002, Kalman filtering with
        // state inequality constraints); the covariance is left as the update made it.
        let unbounded = self.mean[EPSILON];
        self.mean[EPSILON] = unbounded.clamp(-MAX_TURN_ERROR, MAX_TURN_ERROR);
        // Joseph's form keeps the covariance symmetric and positive.
        let keep = Matrix4::identity() - gain * h.transpose();
        self.covariance = keep * self.covariance * keep.transpose()
            + gain * gain.transpose() * (sigma_rad * sigma_rad);
        // What the estimate's change leaves, the bound included (unbounded, the gain's own
        // formula, as the traces have always had it bit for bit).
        update.innovation_after_rad = if self.mean[EPSILON] == unbounded {
            innovation_rad - (h.transpose() * gain)[(0, 0)] * innovation_rad
        } else {
            innovation_rad - h.dot(&(self.mean - mean_before))
        };
        update.taken = true;
        update
    }
}

/// The observation row of lines of age `age`: they observe `b − a` as it was when their
/// readings were read, `b − κ·driven − ε·turned − a`. A window's line fitted to readings drawn
/// while the heading error grew lies along the error at their mean moment (a wall passed
/// alongside drawn on an arc: its chord is the arc's tangent at the middle).
fn observation(age: LineAge) -> Vector4<f64> {
    Vector4::new(1.0, -age.driven_m, -age.turned_rad, -1.0)
}

#[cfg(test)]
mod tests;
