//! Odometry that drifts: what a differential-drive robot's wheel encoders report of a path
//! (Borenstein and Feng's UMBmark, the paper's reference \[1\]). The path a run was simulated
//! along is the truth; it moves to each snapshot's `true_pose`, and `pose` becomes dead
//! reckoning from the first pose with:
//! - systematic error: unequal wheel diameters (`E_d`, the right wheel's over the left's, their
//!   mean the nominal one: straight runs curve) and a wrong wheelbase (`E_b`, the actual over
//!   the nominal: every turn is over- or under-counted);
//! - random error: a zero-mean Gaussian on each wheel's travel, its deviation proportional to
//!   the square root of the distance, and on each turn, proportional to its angle.
//!
//! Each step's motion is taken from consecutive true poses in the robot frame (forward travel
//! and turn; a sideways part is passed on without error). A step much longer than the run's
//! usual one (a lap run carried back to its start) is passed on without error, keeping the
//! drift so far.

use crate::geometry::{wrap_pi, Pose};
use crate::run::Run;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// The odometry error of a differential-drive robot.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OdometryError {
    /// `E_d`: the right wheel's diameter over the left's (1: equal).
    pub wheel_diameter_ratio: f64,
    /// `E_b`: the actual wheelbase over the nominal one (1: exact).
    pub wheelbase_ratio: f64,
    /// The nominal wheelbase, metres.
    pub wheelbase_m: f64,
    /// Deviation of each wheel's travel per square root of its distance, √m.
    pub noise_per_sqrt_m: f64,
    /// Deviation of each turn per radian turned.
    pub noise_rad_per_rad: f64,
}

impl OdometryError {
    /// No error: the odometry is the truth.
    pub const NONE: OdometryError = OdometryError {
        wheel_diameter_ratio: 1.0,
        wheelbase_ratio: 1.0,
        wheelbase_m: 0.33,
        noise_per_sqrt_m: 0.0,
        noise_rad_per_rad: 0.0,
    };

    /// Mild drift: wheel diameters 0.06 % apart (about 1° of heading per 10 m driven straight
    /// on a 0.33 m wheelbase), the wheelbase 1 % off, and wheel noise.
    pub const MILD: OdometryError = OdometryError {
        wheel_diameter_ratio: 1.0006,
        wheelbase_ratio: 1.01,
        wheelbase_m: 0.33,
        noise_per_sqrt_m: 0.001,
        noise_rad_per_rad: 0.01,
    };

    /// Bad drift: wheel diameters 0.3 % apart (about 5° per 10 m), the wheelbase 3 % off,
    /// and three times the wheel noise.
    pub const BAD: OdometryError = OdometryError {
        wheel_diameter_ratio: 1.003,
        wheelbase_ratio: 1.03,
        wheelbase_m: 0.33,
        noise_per_sqrt_m: 0.003,
        noise_rad_per_rad: 0.03,
    };

    /// `none`, `mild` or `bad`.
    pub fn parse(name: &str) -> Option<OdometryError> {
        match name {
            "none" => Some(Self::NONE),
            "mild" => Some(Self::MILD),
            "bad" => Some(Self::BAD),
            _ => None,
        }
    }

    /// The odometry's motion for a true motion of `forward_m` ahead and `turn_rad`:
    /// `(forward_m, turn_rad)` as the encoders count them, with `noise` the two wheels' and
    /// the turn's standard normal draws.
    pub fn measured(&self, forward_m: f64, turn_rad: f64, noise: [f64; 3]) -> (f64, f64) {
        let actual_base_m = self.wheelbase_m * self.wheelbase_ratio;
        let right_m = forward_m + actual_base_m * turn_rad / 2.0;
        let left_m = forward_m - actual_base_m * turn_rad / 2.0;
        // Measured travel = actual travel × nominal diameter / actual diameter.
        let e = self.wheel_diameter_ratio;
        let (k_right, k_left) = ((e + 1.0) / (2.0 * e), (e + 1.0) / 2.0);
        let wheel_noise = |travel_m: f64, z: f64| self.noise_per_sqrt_m * travel_m.abs().sqrt() * z;
        let right = right_m * k_right + wheel_noise(right_m, noise[0]);
        let left = left_m * k_left + wheel_noise(left_m, noise[1]);
        let turn_noise = self.noise_rad_per_rad * turn_rad.abs() * noise[2];
        (
            (right + left) / 2.0,
            (right - left) / self.wheelbase_m + turn_noise,
        )
    }
}

/// A standard normal draw (Box-Muller).
fn standard_normal(rng: &mut ChaCha8Rng) -> f64 {
    let u1: f64 = rng.random::<f64>().max(f64::MIN_POSITIVE);
    let u2: f64 = rng.random();
    (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
}

/// `run` with the odometry `error` gives its path, drawn from `seed`: each snapshot's pose
/// moves to `true_pose` (a pose already there stays the truth), and `pose` becomes the dead
/// reckoning. The same run, error and seed give the same run.
pub fn with_odometry(run: &Run, error: &OdometryError, seed: u64) -> Run {
    let mut out = run.clone();
    let truth: Vec<Pose> = run
        .snapshots
        .iter()
        .map(|s| s.true_pose.unwrap_or(s.pose))
        .collect();
    let mut steps_m: Vec<f64> = truth.windows(2).map(|w| w[0].distance_to(&w[1])).collect();
    steps_m.sort_by(f64::total_cmp);
    let median_m = steps_m.get(steps_m.len() / 2).copied().unwrap_or(0.0);
    let jump_m = 5.0 * median_m + 1e-9;
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut odometry = truth.first().copied();
    for (i, s) in out.snapshots.iter_mut().enumerate() {
        let Some(mut pose) = odometry else { break };
        if i > 0 {
            let (from, to) = (truth[i - 1], truth[i]);
            let (c, sn) = (from.heading_rad.cos(), from.heading_rad.sin());
            let (dx, dy) = (to.x - from.x, to.y - from.y);
            // The true motion in the robot frame at `from`.
            let (ahead_m, aside_m) = (c * dx + sn * dy, -sn * dx + c * dy);
            let turn_rad = wrap_pi(to.heading_rad - from.heading_rad);
            let (forward_m, measured_turn) = if from.distance_to(&to) > jump_m {
                (ahead_m, turn_rad)
            } else {
                let noise = [
                    standard_normal(&mut rng),
                    standard_normal(&mut rng),
                    standard_normal(&mut rng),
                ];
                error.measured(ahead_m, turn_rad, noise)
            };
            // Integrated along the arc's mean heading; the sideways part as it was.
            let mid = pose.heading_rad + measured_turn / 2.0;
            let (cm, sm) = (mid.cos(), mid.sin());
            let (ch, sh) = (pose.heading_rad.cos(), pose.heading_rad.sin());
            pose = Pose::new(
                pose.x + forward_m * cm - aside_m * sh,
                pose.y + forward_m * sm + aside_m * ch,
                wrap_pi(pose.heading_rad + measured_turn),
            );
        }
        s.true_pose = Some(truth[i]);
        s.pose = pose;
        odometry = Some(pose);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::run::Snapshot;

    fn straight_run(n: usize, step_m: f64) -> Run {
        let mut run = crate::sim::simulate(
            &crate::sim::family_plan(crate::sim::SceneKind::Room, 1),
            crate::sim::Model::Axis,
            1,
        );
        run.snapshots = (0..n)
            .map(|i| Snapshot {
                t: i as f64,
                pose: Pose::new(i as f64 * step_m, 0.0, 0.0),
                ranges_m: vec![None; run.layout.len()],
                true_pose: None,
                reading_dt_s: Vec::new(),
            })
            .collect();
        run
    }

    #[test]
    fn unequal_wheels_turn_a_straight_run_by_the_hand_computed_angle() {
        // E_d = 1.0006 on a 0.33 m wheelbase, 1 m straight: right wheel counts
        // 1·(2.0006/2.0012) = 0.99970018, left 1·1.0003; turn (r − l)/b = −0.00059982/0.33 =
        // −1.81764e-3 rad a metre. Ten metres: −0.0181764 rad (−1.04°).
        let error = OdometryError {
            noise_per_sqrt_m: 0.0,
            noise_rad_per_rad: 0.0,
            ..OdometryError::MILD
        };
        let (forward_m, turn_rad) = error.measured(1.0, 0.0, [0.0; 3]);
        assert!((forward_m - 1.00000009).abs() < 1e-8, "{forward_m}");
        assert!((turn_rad + 0.00059982 / 0.33).abs() < 1e-9, "{turn_rad}");
        let run = with_odometry(&straight_run(11, 1.0), &error, 1);
        let last = run.snapshots.last().unwrap();
        assert!((last.pose.heading_rad + 10.0 * 0.00059982 / 0.33).abs() < 1e-7);
        assert_eq!(last.true_pose, Some(Pose::new(10.0, 0.0, 0.0)));
        assert!(
            last.pose.y < -0.05,
            "a straight run curves: {}",
            last.pose.y
        );
    }

    #[test]
    fn a_wrong_wheelbase_over_counts_a_turn_by_its_ratio() {
        // Turning on the spot by 1 rad, the wheels travel ±b_act/2 = ±0.33·1.01/2; counted
        // over the nominal 0.33 m that is 1.01 rad.
        let error = OdometryError {
            wheel_diameter_ratio: 1.0,
            noise_per_sqrt_m: 0.0,
            noise_rad_per_rad: 0.0,
            ..OdometryError::MILD
        };
        let (forward_m, turn_rad) = error.measured(0.0, 1.0, [0.0; 3]);
        assert!(forward_m.abs() < 1e-12);
        assert!((turn_rad - 1.01).abs() < 1e-12);
    }

    #[test]
    fn no_error_keeps_the_poses_and_the_same_seed_gives_the_same_run() {
        let run = straight_run(20, 0.2);
        let kept = with_odometry(&run, &OdometryError::NONE, 3);
        for (a, b) in run.snapshots.iter().zip(&kept.snapshots) {
            assert!(a.pose.distance_to(&b.pose) < 1e-9);
            assert_eq!(b.true_pose, Some(a.pose));
        }
        let one = with_odometry(&run, &OdometryError::BAD, 5);
        assert_eq!(one, with_odometry(&run, &OdometryError::BAD, 5));
        assert_ne!(one, with_odometry(&run, &OdometryError::BAD, 6));
        // Given drift twice, the truth stays the first run's path.
        let twice = with_odometry(&one, &OdometryError::BAD, 5);
        assert_eq!(twice.snapshots[7].true_pose, Some(run.snapshots[7].pose));
    }

    #[test]
    fn a_jump_back_to_the_start_carries_the_drift_without_adding_to_it() {
        let mut run = straight_run(16, 0.2);
        // Snapshot 8 starts the lap again at x = 0: a step of 1.4 m, over 5 × 0.2.
        for (i, s) in run.snapshots.iter_mut().enumerate() {
            s.pose = Pose::new((i % 8) as f64 * 0.2, 0.0, 0.0);
        }
        let error = OdometryError {
            noise_per_sqrt_m: 0.0,
            noise_rad_per_rad: 0.0,
            ..OdometryError::BAD
        };
        let drifted = with_odometry(&run, &error, 1);
        let heading = |k: usize| drifted.snapshots[k].pose.heading_rad;
        assert!(
            (heading(8) - heading(7)).abs() < 1e-12,
            "the jump adds no turn"
        );
        assert!((heading(15) - heading(8) - (heading(7) - heading(0))).abs() < 1e-9);
    }
}
