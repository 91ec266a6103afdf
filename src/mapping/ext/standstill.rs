//! A robot standing still adds no view (docs/algorithm.md §8.19, `standstill`): the rule's test,
//! apart from the step that uses it (`steps/standstill.rs`).
//!
//! A sonar read again and again from one place repeats one view: its echoes come from the same
//! patch of wall, and their differences are the sensor's noise, not evidence. The paper takes
//! every snapshot as a new observation, so a robot that waits drags each wall it sees through
//! one MATCH after another, each moving it a little by the noise alone. Laser SLAM systems take
//! a scan only once the robot has moved or turned (GMapping's `linearUpdate` and
//! `angularUpdate`, Grisetti, Stachniss and Burgard 2007); sonar repeats its views even more,
//! its beam being wide (Leonard and Durrant-Whyte 1992 build their regions of constant depth
//! from readings of a moving sensor).

use crate::geometry::{wrap_pi, Pose};

/// The turn since the last mapped snapshot below which the robot still stands (0.1°): an
/// odometry at rest repeats its pose, and a tenth of a degree turns a sonar's axis 5 mm at 3 m.
pub const STANDSTILL_TURN_RAD: f64 = 0.1 * std::f64::consts::PI / 180.0;

/// How far the odometry moved and turned (absolute, radians) from `last_mapped` to `now`, when
/// it stays within `tolerance_m` and [`STANDSTILL_TURN_RAD`]: the robot stood still.
///
/// ```
/// use sonarmap::geometry::Pose;
/// use sonarmap::mapping::ext::standstill::stood_still;
/// let last = Pose::new(1.0, 2.0, 0.5);
/// // 0.6 mm and 0.05°: still.
/// let now = Pose::new(1.0006, 2.0, 0.5 + 0.05f64.to_radians());
/// let (moved_m, turned_rad) = stood_still(&last, &now, 0.001).unwrap();
/// assert!((moved_m - 0.0006).abs() < 1e-12);
/// assert!((turned_rad.to_degrees() - 0.05).abs() < 1e-9);
/// // 1.5 mm, or 0.2° on the spot: moved.
/// assert_eq!(stood_still(&last, &Pose::new(1.0015, 2.0, 0.5), 0.001), None);
/// assert_eq!(stood_still(&last, &Pose::new(1.0, 2.0, 0.5 + 0.2f64.to_radians()), 0.001), None);
/// ```
pub fn stood_still(last_mapped: &Pose, now: &Pose, tolerance_m: f64) -> Option<(f64, f64)> {
    let moved_m = last_mapped.distance_to(now);
    let turned_rad = wrap_pi(now.heading_rad - last_mapped.heading_rad).abs();
    (moved_m <= tolerance_m && turned_rad < STANDSTILL_TURN_RAD).then_some((moved_m, turned_rad))
}
