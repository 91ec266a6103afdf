//! A robot's pace and its sonars' firing order, for the simulator: how far the robot moves in
//! one firing cycle, how long a cycle lasts, and which sensors fire together at which moment
//! (a Pioneer's sonars fire one bank after another, not as one ring; docs/algorithm.md §1.1).

use crate::geometry::Pose;

/// How a simulated robot moves and fires. [`Pace::PLAN`] is the plan's own path with the
/// whole ring fired at each pose's moment, one pose a second.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pace {
    /// The path re-cut into firing cycles this far apart along it, metres (`None`: the plan's
    /// own poses).
    pub cycle_step_m: Option<f64>,
    /// With `cycle_step_m`, the largest turn in one cycle, radians (a turn on the spot).
    pub cycle_turn_rad: f64,
    /// One firing cycle's duration, seconds.
    pub cycle_s: f64,
    /// Sensors fired in this many groups across a cycle: sensor `k` in group `k % groups`,
    /// group `g` at `−(groups − 1 − g)/groups` of a cycle before the snapshot's moment, while
    /// the robot moves. 1: the whole ring at the snapshot's moment.
    pub firing_groups: usize,
}

impl Pace {
    /// The plan's poses, one a second, the ring fired at once.
    pub const PLAN: Pace = Pace {
        cycle_step_m: None,
        cycle_turn_rad: 5.0 * std::f64::consts::PI / 180.0,
        cycle_s: 1.0,
        firing_groups: 1,
    };

    /// The time offset of sensor `sensor`'s reading from its snapshot's moment, seconds (≤ 0).
    ///
    /// ```
    /// use sonarmap::sim::Pace;
    /// let pace = Pace { firing_groups: 3, cycle_s: 0.3, ..Pace::PLAN };
    /// // Sensors 0, 3, 6 fire first (0.2 s before), 2 and 5 last (at the snapshot's moment).
    /// assert!((pace.reading_dt_s(3) + 0.2).abs() < 1e-12);
    /// assert_eq!(pace.reading_dt_s(5), 0.0);
    /// ```
    pub fn reading_dt_s(&self, sensor: usize) -> f64 {
        let groups = self.firing_groups.max(1);
        let waits = groups - 1 - sensor % groups;
        -(waits as f64) * self.cycle_s / groups as f64
    }

    /// The snapshots' poses: `poses` re-cut by [`resample_path`] when `cycle_step_m` is set.
    pub fn cycle_poses(&self, poses: &[Pose]) -> Vec<Pose> {
        match self.cycle_step_m {
            Some(step_m) => resample_path(poses, step_m, self.cycle_turn_rad),
            None => poses.to_vec(),
        }
    }
}

/// The path through `poses` cut into poses whose neighbours are `step_m` apart along it, or
/// `turn_rad` apart in heading where it turns faster than that (on the spot), whichever comes
/// first: each leg between two given poses is costed `max(length/step_m, |turn|/turn_rad)`
/// cycles, and a pose is placed at every whole cycle of the running cost (linearly within its
/// leg, heading the short way round). The first and last given poses are kept.
///
/// ```
/// use sonarmap::geometry::Pose;
/// use sonarmap::sim::resample_path;
/// let path = [Pose::new(0.0, 0.0, 0.0), Pose::new(0.1, 0.0, 0.0), Pose::new(1.0, 0.0, 0.0)];
/// let poses = resample_path(&path, 0.25, 0.1);
/// assert_eq!(poses.len(), 5); // 0, 0.25, 0.5, 0.75, 1
/// assert!((poses[1].x - 0.25).abs() < 1e-12);
/// ```
pub fn resample_path(poses: &[Pose], step_m: f64, turn_rad: f64) -> Vec<Pose> {
    let (Some(first), Some(last)) = (poses.first(), poses.last()) else {
        return Vec::new();
    };
    let mut out = vec![*first];
    let mut cost_before_leg = 0.0;
    let mut next_cycle = 1.0;
    for leg in poses.windows(2) {
        let (a, b) = (leg[0], leg[1]);
        let turn = crate::geometry::wrap_pi(b.heading_rad - a.heading_rad);
        let cost = (a.distance_to(&b) / step_m).max(turn.abs() / turn_rad);
        while cost > 0.0 && next_cycle <= cost_before_leg + cost {
            out.push(a.interpolate(&b, (next_cycle - cost_before_leg) / cost));
            next_cycle += 1.0;
        }
        cost_before_leg += cost;
    }
    let at_end = out
        .last()
        .is_some_and(|p| p.distance_to(last) < 1e-9 * step_m);
    if !at_end {
        out.push(*last);
    }
    out
}

/// The pose at `dt_s` (≤ 0) before snapshot `i` of `poses` taken `cycle_s` apart: on the
/// straight line from the previous pose (the first pose stands still before it).
pub fn pose_at(poses: &[Pose], i: usize, dt_s: f64, cycle_s: f64) -> Pose {
    if i == 0 || dt_s == 0.0 {
        return poses[i];
    }
    let fraction = (1.0 + dt_s / cycle_s).clamp(0.0, 1.0);
    poses[i - 1].interpolate(&poses[i], fraction)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_turn_on_the_spot_is_cut_by_the_turn_limit() {
        // 90° on the spot at 5° a cycle: 18 cycles, 19 poses.
        let path = [
            Pose::new(0.0, 0.0, 0.0),
            Pose::new(0.0, 0.0, std::f64::consts::FRAC_PI_2),
        ];
        let poses = resample_path(&path, 0.01, 5f64.to_radians());
        assert_eq!(poses.len(), 19);
        assert!((poses[1].heading_rad.to_degrees() - 5.0).abs() < 1e-9);
    }

    #[test]
    fn a_crawl_cuts_a_metre_into_fifteen_millimetre_cycles() {
        let path = [Pose::new(0.0, 0.0, 0.0), Pose::new(1.2, 0.0, 0.0)];
        let poses = resample_path(&path, 0.015, 0.1);
        // 1.2 / 0.015 = 80 cycles.
        assert_eq!(poses.len(), 81);
        for pair in poses.windows(2) {
            assert!((pair[0].distance_to(&pair[1]) - 0.015).abs() < 1e-9);
        }
    }

    #[test]
    fn a_reading_fired_earlier_in_the_cycle_takes_the_pose_of_its_moment() {
        // Poses 0.03 m apart, 0.3 s a cycle; 0.1 s before the second: 2/3 of the way.
        let poses = [Pose::new(0.0, 0.0, 0.0), Pose::new(0.03, 0.0, 0.0)];
        let p = pose_at(&poses, 1, -0.1, 0.3);
        assert!((p.x - 0.02).abs() < 1e-12);
        assert_eq!(pose_at(&poses, 0, -0.1, 0.3), poses[0]);
    }
}
