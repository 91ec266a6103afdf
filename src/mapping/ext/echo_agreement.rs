//! Echoes shorter than the sensor's last (docs/algorithm.md §8.21): the rule of
//! `echo_agreement`, apart from the step that applies it (`steps/echo_agreement.rs`).
//!
//! A sonar ring fired a few sensors at a time hears its neighbours' pings (crosstalk), and any
//! sonar hears echoes that arrive early by other paths: such a reading is short, and it does
//! not repeat. Borenstein and Koren's error-eliminating rapid ultrasonic firing (EERUF, IEEE
//! Transactions on Robotics and Automation, 1995) keeps a reading only when the same sensor's
//! next firing agrees with it. A step cannot wait for the next firing, so this rule compares a
//! reading with the sensor's previous one, and refuses only a reading much shorter than it: a
//! wall read again returns about the same range, a surface that ends gives way to a farther
//! one, and what returns a much shorter range out of nowhere is most often no surface. A real
//! surface that comes closer in one cycle (a door frame's edge) loses its first reading only.

use crate::mapping::ext::rectilinear_heading::OdometryMoment;
use crate::sonar::ball_radius;

/// The smallest tolerance between two readings of one place (2 in): twice the 1 in floor of
/// the paper's resolution tolerance.
pub const MIN_AGREEMENT_M: f64 = 0.0508;

/// Each sensor's last echo (its range, metres; `None` without one) and the odometry's moment
/// it was read at.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LastEchoes {
    /// Each sensor's range, metres.
    pub ranges_m: Vec<Option<f64>>,
    /// When they were read.
    pub read_at: Option<OdometryMoment>,
}

/// How much shorter than the sensor's last range `last_m` a range `range_m` may be and still
/// agree with it (metres), the robot having driven `driven_m` and turned `turned_rad` since:
/// both readings' balls (`accuracy_pct`, paper §2) at the longer range, at least
/// [`MIN_AGREEMENT_M`], plus the distance driven and the arc the longer range sweeps through
/// the turn.
///
/// ```
/// use sonarmap::mapping::ext::echo_agreement::shorter_tolerance_m;
/// // 2 m and 1.9 m at 3 %: balls of 6 cm each at 2 m, 12 cm; 1.5 cm driven; a turn of
/// // 0.01 rad sweeps 2 cm at 2 m.
/// let tolerance = shorter_tolerance_m(1.9, 2.0, 3.0, 0.015, 0.01);
/// assert!((tolerance - (0.12 + 0.015 + 0.02)).abs() < 1e-12);
/// // Close ranges keep the 2 in floor.
/// assert!((shorter_tolerance_m(0.3, 0.3, 1.0, 0.0, 0.0) - 0.0508).abs() < 1e-12);
/// ```
pub fn shorter_tolerance_m(
    range_m: f64,
    last_m: f64,
    accuracy_pct: f64,
    driven_m: f64,
    turned_rad: f64,
) -> f64 {
    let longer_m = range_m.max(last_m);
    (2.0 * ball_radius(accuracy_pct, longer_m)).max(MIN_AGREEMENT_M)
        + driven_m.abs()
        + longer_m * turned_rad.abs()
}

/// Whether `range_m` is shorter than the sensor's last range `last_m` by more than `tolerance_m`
/// ([`shorter_tolerance_m`]). (A sensor without a last echo has nothing to compare with: the
/// step refuses none of its readings.)
///
/// ```
/// use sonarmap::mapping::ext::echo_agreement::shorter_than_last;
/// assert!(shorter_than_last(1.0, 2.0, 0.2));
/// assert!(!shorter_than_last(1.85, 2.0, 0.2));
/// // Longer is never refused: a surface that ends gives way to a farther one.
/// assert!(!shorter_than_last(4.0, 2.0, 0.2));
/// ```
pub fn shorter_than_last(range_m: f64, last_m: f64, tolerance_m: f64) -> bool {
    range_m < last_m - tolerance_m
}
