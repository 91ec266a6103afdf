//! Each reading's own pose (paper §3.1; docs/algorithm.md §1.1). The paper turns a reading into
//! a point with the robot's pose R_x, R_y, γ; a sonar fired after its snapshot's moment takes
//! the pose of its own moment, read off the odometry track between the previous snapshot and
//! this one.

use crate::geometry::{Pose, RobotFrame};

/// Where a step's readings were taken from: the step's pose, and each sensor's own when the
/// sonars fired in sequence (`own` is then one pose per sensor; empty otherwise).
#[derive(Clone, Copy, Debug)]
pub struct ReadingPlaces<'a> {
    /// The step's pose.
    pub step: &'a Pose,
    /// The step pose's robot frame (`step.robot_frame()`, which the mapper computes once a step).
    pub frame: RobotFrame,
    /// Each sensor's pose at its own moment, or none.
    pub own: &'a [Pose],
}

impl<'a> ReadingPlaces<'a> {
    /// The places of readings taken from `step`, or each from its `own` pose.
    pub fn new(step: &'a Pose, own: &'a [Pose]) -> Self {
        Self {
            step,
            frame: step.robot_frame(),
            own,
        }
    }

    /// Sensor `sensor`'s own pose, when the readings have theirs.
    pub fn own_pose(&self, sensor: usize) -> Option<&Pose> {
        self.own.get(sensor)
    }
}

/// The odometry pose `dt_s` seconds after a snapshot at `t_s` whose odometry is `pose`, given
/// the previous snapshot's time and odometry: on the straight track between the two (`dt_s`
/// < 0), or beyond it at the same rate (`dt_s` > 0), at most one snapshot's interval either
/// way. The snapshot's own pose without a previous snapshot, or when time did not advance.
///
/// ```
/// use sonarmap::geometry::Pose;
/// use sonarmap::mapping::paper::reading_poses::odometry_at;
/// // From (0, 0, 0°) at 1 s to (0.2, 0, 10°) at 1.5 s: 0.1 s earlier is 4/5 of the way.
/// let (previous, pose) = (Pose::new(0.0, 0.0, 0.0), Pose::new(0.2, 0.0, 10f64.to_radians()));
/// let p = odometry_at(Some((1.0, previous)), 1.5, &pose, -0.1);
/// assert!((p.x - 0.16).abs() < 1e-12 && (p.heading_rad.to_degrees() - 8.0).abs() < 1e-9);
/// ```
pub fn odometry_at(previous: Option<(f64, Pose)>, t_s: f64, pose: &Pose, dt_s: f64) -> Pose {
    let Some((previous_t_s, previous_pose)) = previous else {
        return *pose;
    };
    let interval_s = t_s - previous_t_s;
    if dt_s == 0.0 || interval_s.is_nan() || interval_s <= 0.0 {
        return *pose;
    }
    let fraction = (1.0 + dt_s / interval_s).clamp(0.0, 2.0);
    previous_pose.interpolate(pose, fraction)
}

/// Each sensor's pose for a step placed at `step_pose` whose odometry is `odometry` (the two
/// differ once the pose is corrected): the odometry's motion from the snapshot's moment to the
/// reading's, carried from `step_pose`. Fills `out` with one pose per entry of `reading_dt_s`
/// (empty when it is).
pub fn reading_poses(
    previous: Option<(f64, Pose)>,
    t_s: f64,
    odometry: &Pose,
    step_pose: &Pose,
    reading_dt_s: &[f64],
    out: &mut Vec<Pose>,
) {
    out.clear();
    out.extend(reading_dt_s.iter().map(|&dt_s| {
        if dt_s == 0.0 {
            *step_pose
        } else {
            let moved = odometry.relative_to(&odometry_at(previous, t_s, odometry, dt_s));
            step_pose.compose(&moved)
        }
    }));
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_reading_fired_later_extrapolates_at_most_one_interval() {
        let previous = Some((0.0, Pose::new(0.0, 0.0, 0.0)));
        let pose = Pose::new(0.1, 0.0, 0.0);
        // 0.05 s after a 0.1 s interval at 1 m/s: 5 cm further on.
        let p = odometry_at(previous, 0.1, &pose, 0.05);
        assert!((p.x - 0.15).abs() < 1e-12);
        // 10 s after: held at one interval beyond (0.2 m), not 10 m.
        assert!((odometry_at(previous, 0.1, &pose, 10.0).x - 0.2).abs() < 1e-12);
        // 10 s before: held at the previous pose.
        assert!(odometry_at(previous, 0.1, &pose, -10.0).x.abs() < 1e-12);
    }

    #[test]
    fn without_a_previous_snapshot_or_elapsed_time_a_reading_takes_the_snapshot_pose() {
        let pose = Pose::new(1.0, 2.0, 0.5);
        assert_eq!(odometry_at(None, 3.0, &pose, -0.2), pose);
        assert_eq!(
            odometry_at(Some((3.0, Pose::default())), 3.0, &pose, -0.2),
            pose
        );
    }

    #[test]
    fn a_corrected_step_carries_the_odometry_motion_in_its_own_frame() {
        // Odometry drove 0.1 m along +x in the last 0.1 s; the corrected pose faces +y. A reading
        // 0.05 s before the snapshot was taken 5 cm behind it, along the corrected heading.
        let previous = Some((0.0, Pose::new(0.0, 0.0, 0.0)));
        let odometry = Pose::new(0.1, 0.0, 0.0);
        let corrected = Pose::new(2.0, 3.0, std::f64::consts::FRAC_PI_2);
        let mut out = Vec::new();
        reading_poses(
            previous,
            0.1,
            &odometry,
            &corrected,
            &[0.0, -0.05],
            &mut out,
        );
        assert_eq!(out[0], corrected);
        assert!((out[1].x - 2.0).abs() < 1e-12 && (out[1].y - 2.95).abs() < 1e-12);
        assert!((out[1].heading_rad - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
    }
}
