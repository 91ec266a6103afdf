//! Links across a right angle (docs/algorithm.md §8.20; beyond the paper).
//!
//! The paper clusters neighbouring readings of a ring (§2) whatever the angle between their
//! sonars: on the Nomad's ring of sixteen, neighbours are 22.5° apart and read one wall side
//! by side. A sonar hears a plane from within its cone (Kleeman and Kuc's plane model: the
//! echo comes from the foot of the perpendicular, inside the beam), and the angles from one
//! plane's normal to two axes add up to at least the angle between the axes. Two sonars a
//! right angle or more apart therefore meet any one plane 45° or more off its normal at one of
//! them, outside every sonar's cone: their two readings are two surfaces, most often the two
//! walls of a corner, and a cluster of the two fits a chord across it. On a ring of sixteen
//! such neighbours are readings four sonars apart with none echoing between; on a robot with
//! four sonars (front, back, left, right) every pair of neighbours is.

use crate::geometry::Vec2;

/// Whether two sonars whose axes point along `a` and `b` (unit vectors, one frame) lie a right
/// angle or more apart: `a · b ≤ 0` (within 1e-9, for axes that should be exactly square).
///
/// ```
/// use sonarmap::geometry::Vec2;
/// use sonarmap::mapping::ext::right_angle_break::across_right_angle;
/// let axis = |deg: f64| Vec2::new(deg.to_radians().cos(), deg.to_radians().sin());
/// // A ring of four: front and left, 90° apart (cos 90° = 6e-17, taken as 0).
/// assert!(across_right_angle(&axis(0.0), &axis(90.0)));
/// // The Pioneer's side and ±50° sonars, 40° apart: a link as the paper has it.
/// assert!(!across_right_angle(&axis(90.0), &axis(50.0)));
/// // Four sonars of a ring of sixteen, 90° apart; three, 67.5°: only the first breaks.
/// assert!(across_right_angle(&axis(0.0), &axis(90.0)));
/// assert!(!across_right_angle(&axis(0.0), &axis(67.5)));
/// ```
pub fn across_right_angle(a: &Vec2, b: &Vec2) -> bool {
    a.dot(b) <= 1e-9
}
