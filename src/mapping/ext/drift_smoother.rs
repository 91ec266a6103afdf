//! The first pass's heading errors, smoothed over the whole run (docs/algorithm.md §8.17,
//! "calibrate, then map"): the drift filter ([`crate::mapping::ext::odometry_drift`]) runs
//! forwards, so the heading error of a step is estimated from the lines seen up to it. The
//! Rauch–Tung–Striebel smoother (Rauch, Tung and Striebel 1965) runs back over its steps and
//! gives each step the estimate from every line of the run: before the walls set the axis, and
//! over a window's lag, the lines seen later tell what the error was. The second pass takes
//! the heading from it ([`crate::mapping::model::heading_track::HeadingTrack`]).

use crate::mapping::ext::odometry_drift::{OdometryDrift, B};
use nalgebra::{Matrix4, Vector4};

/// The most filter steps a first pass keeps for the smoother (each about 180 bytes): past it
/// the second pass has the calibration alone.
pub const MAX_SMOOTHED_STEPS: usize = 1 << 18;

/// A step of the drift filter as it ran: the odometry's increment, then the estimate.
#[derive(Clone, Debug, PartialEq)]
struct FilterStep {
    snapshot: usize,
    distance_m: f64,
    turn_rad: f64,
    mean: Vector4<f64>,
    covariance: Matrix4<f64>,
}

/// Steps kept in one allocation: the history grows by whole chunks, never copying what it
/// holds (a growing vector's copies cost more than the steps' own recording).
const CHUNK_STEPS: usize = 4096;

/// The drift filter's steps over a first pass, for [`DriftHistory::smoothed`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct DriftHistory {
    /// The steps in order, in chunks of [`CHUNK_STEPS`].
    chunks: Vec<Vec<FilterStep>>,
    /// How many steps the chunks hold.
    len: usize,
    /// The snapshots noted, kept or left out: one past the last.
    noted: usize,
    /// More than [`MAX_SMOOTHED_STEPS`] steps came: none are smoothed.
    overflowed: bool,
}

impl DriftHistory {
    /// Notes snapshot `snapshot`'s step: the odometry drove `distance_m` and turned
    /// `turn_rad`, and the filter ended at `drift`. A step that neither moved nor changed the
    /// estimate is left out: its smoothed error is the one of the step before.
    pub fn record(
        &mut self,
        snapshot: usize,
        distance_m: f64,
        turn_rad: f64,
        drift: &OdometryDrift,
    ) {
        if self.overflowed {
            return;
        }
        self.noted = self.noted.max(snapshot + 1);
        let unchanged = |last: &FilterStep| {
            distance_m == 0.0
                && turn_rad == 0.0
                && last.mean == drift.mean
                && last.covariance == drift.covariance
        };
        if self.last().is_some_and(unchanged) {
            return;
        }
        if self.len == MAX_SMOOTHED_STEPS {
            self.overflowed = true;
            self.chunks = Vec::new();
            return;
        }
        if self.len.is_multiple_of(CHUNK_STEPS) {
            self.chunks.push(Vec::with_capacity(CHUNK_STEPS));
        }
        self.len += 1;
        self.chunks
            .last_mut()
            .expect("pushed above")
            .push(FilterStep {
                snapshot,
                distance_m,
                turn_rad,
                mean: drift.mean,
                covariance: drift.covariance,
            });
    }

    /// Step `i` of those kept.
    fn step(&self, i: usize) -> &FilterStep {
        &self.chunks[i / CHUNK_STEPS][i % CHUNK_STEPS]
    }

    /// The last step kept.
    fn last(&self) -> Option<&FilterStep> {
        self.chunks.last().and_then(|c| c.last())
    }

    /// The heading error at every snapshot up to the last one noted, smoothed, radians; `None`
    /// without steps or past [`MAX_SMOOTHED_STEPS`].
    ///
    /// Backwards from the last step, the smoothed state of step i is its filtered state plus
    /// Cᵢ times what smoothing changed of the next step's prediction, Cᵢ = Pᵢ·Fᵀ·(P⁻ᵢ₊₁)⁺ (the
    /// pseudo-inverse, since the axis offset has no variance before the walls set it). The
    /// prediction is the filter's own ([`OdometryDrift::predict`]). The means alone are
    /// smoothed: the second pass needs no covariance.
    ///
    /// ```
    /// use nalgebra::{Matrix4, Vector4};
    /// use sonarmap::mapping::ext::drift_smoother::DriftHistory;
    /// use sonarmap::mapping::ext::odometry_drift::OdometryDrift;
    /// // A heading that wanders at random (no systematic cause known), 0 at the start, the
    /// // axis known: after 4 m unobserved, a line at the fifth metre says 1° exactly. The
    /// // smoothed error grows evenly to it (a random walk pinned at both ends), 0.2° a metre,
    /// // within 0.01° (the drift per metre may wander a little too, 0.01°/m per √m); the
    /// // filter had 0 until the line.
    /// let mut drift = OdometryDrift::default();
    /// drift.covariance = Matrix4::zeros();
    /// drift.set_axis(0.0, 0.0);
    /// let mut history = DriftHistory::default();
    /// history.record(0, 0.0, 0.0, &drift);
    /// for metre in 1..=5 {
    ///     drift.predict(1.0, 0.0);
    ///     if metre == 5 {
    ///         drift.update(1f64.to_radians() + drift.expected_rotation_rad(Default::default()), 1e-9, Default::default());
    ///     }
    ///     assert_eq!(drift.heading_error_rad() == 0.0, metre < 5);
    ///     history.record(metre, 1.0, 0.0, &drift);
    /// }
    /// let errors_rad = history.smoothed().unwrap();
    /// for metre in 0..=5 {
    ///     let deg = errors_rad[metre].to_degrees();
    ///     assert!((deg - 0.2 * metre as f64).abs() < 0.01, "{metre} m: {deg}°");
    /// }
    /// ```
    pub fn smoothed(&self) -> Option<Vec<f64>> {
        let last = self.last()?;
        if self.overflowed {
            return None;
        }
        let mut smoothed_mean = last.mean;
        let mut by_step = vec![0.0; self.len];
        by_step[self.len - 1] = smoothed_mean[B];
        for i in (0..self.len - 1).rev() {
            let (step, next) = (self.step(i), self.step(i + 1));
            let mut predicted = OdometryDrift {
                mean: step.mean,
                covariance: step.covariance,
                ..OdometryDrift::default()
            };
            predicted.predict(next.distance_m, next.turn_rad);
            let motion = OdometryDrift::motion(next.distance_m, next.turn_rad);
            let gain = step.covariance * motion.transpose() * pseudo_inverse(&predicted.covariance);
            smoothed_mean = step.mean + gain * (smoothed_mean - predicted.mean);
            by_step[i] = smoothed_mean[B];
        }
        let mut errors_rad = vec![0.0; self.noted];
        for (i, error_rad) in by_step.into_iter().enumerate() {
            let until = if i + 1 < self.len {
                self.step(i + 1).snapshot
            } else {
                errors_rad.len()
            };
            errors_rad[self.step(i).snapshot..until].fill(error_rad);
        }
        Some(errors_rad)
    }
}

/// The pseudo-inverse of the covariance `p`, its singular values below 10⁻¹² of the largest
/// taken as 0.
fn pseudo_inverse(p: &Matrix4<f64>) -> Matrix4<f64> {
    let svd = p.svd(true, true);
    let largest = svd.singular_values.max();
    if largest <= 0.0 {
        return Matrix4::zeros();
    }
    svd.pseudo_inverse(largest * 1e-12)
        .unwrap_or_else(|_| Matrix4::zeros())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_robot_standing_still_keeps_one_step_and_its_error_at_every_snapshot() {
        let mut drift = OdometryDrift::default();
        drift.predict(1.0, 0.0);
        let mut history = DriftHistory::default();
        for snapshot in 0..1000 {
            history.record(snapshot, 0.0, 0.0, &drift);
        }
        assert_eq!(history.len, 1);
        let errors_rad = history.smoothed().unwrap();
        assert_eq!(errors_rad.len(), 1000);
        assert!(errors_rad.iter().all(|&e| e == drift.heading_error_rad()));
    }

    #[test]
    fn a_history_longer_than_a_chunk_keeps_every_step_in_order() {
        let mut drift = OdometryDrift::default();
        let mut history = DriftHistory::default();
        let n = 2 * CHUNK_STEPS + 5;
        for snapshot in 0..n {
            drift.predict(0.01, 0.0);
            history.record(snapshot, 0.01, 0.0, &drift);
        }
        assert_eq!((history.len, history.chunks.len()), (n, 3));
        assert!((0..n).all(|i| history.step(i).snapshot == i));
        assert_eq!(history.last().unwrap().mean, drift.mean);
        assert_eq!(history.smoothed().unwrap().len(), n);
    }

    #[test]
    fn the_last_step_keeps_the_filters_estimate_and_too_many_steps_give_none() {
        let mut drift = OdometryDrift::default();
        drift.set_axis(0.0, 0.001);
        let mut history = DriftHistory::default();
        for snapshot in 0..10 {
            drift.predict(0.1, 0.0);
            drift.update(
                0.002 + drift.expected_rotation_rad(Default::default()),
                0.01,
                Default::default(),
            );
            history.record(snapshot, 0.1, 0.0, &drift);
        }
        let errors_rad = history.smoothed().unwrap();
        assert_eq!(errors_rad[9], drift.heading_error_rad());
        history.overflowed = true;
        assert!(history.smoothed().is_none());
    }
}
