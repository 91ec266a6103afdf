//! Ends seen through (docs/algorithm.md §8.18; beyond the paper).
//!
//! A sonar's beam is a cone, and §1 places each echo on its axis. Where a wall ends at an
//! opening (a door recess, a doorway, a corridor's side branch), the wall's end stays inside
//! the cone after the axis has left the wall: its echo, a little longer than the wall's
//! perpendicular, is placed on the axis beyond the end, and the wall's segment runs on into the
//! opening by up to `p·tan(β/2)` (0.28 m at 1.27 m with a 25° beam). The reading that next
//! looks into the opening hears past the wall's line; the plane model (Kleeman and Kuc) says
//! what it saw there: had the wall's line gone on under the cone, it would have echoed from its
//! perpendicular foot at `p`, or from the nearest of its points inside the cone, at most at the
//! reading's range. So the part of the line inside the cone and nearer than `D − 2·tol(D)` is
//! free space (Moravec and Elfes 1985 count the whole cone short of the range as empty), and
//! that part of a segment is cut away: an end lying in it moves back to its edge, a part in
//! the middle leaves a hole ([`cut_of`]). Unlike §8.6, which removes a tentative segment whose
//! foot it saw, this keeps what was not seen through, confirmed or not.

use crate::geometry::Point;
use crate::mapping::ext::beam_geometry::{feature_tolerance_m, HalfCone};
use crate::mapping::model::beam::Beam;

/// The part of the infinite line through `a` and `b` that `beam` saw as free space, as
/// distances along it from `a` towards `b` (metres): the points inside the cone and nearer
/// to the sensor than `D − 2·tol(D)`. `None` when the line's perpendicular foot lies outside
/// the cone (the line stands too oblique to the beam for its absence to be heard) or the
/// range is not past the foot by `2·tol(D)`.
///
/// ```
/// use sonarmap::geometry::{Point, Vec2};
/// use sonarmap::mapping::ext::beam_geometry::HalfCone;
/// use sonarmap::mapping::ext::seen_through_ends::free_part_of_line;
/// use sonarmap::mapping::model::beam::Beam;
/// // A sensor at (3.3, 1.27) looks straight down (−y) into a door recess and reads 1.52 m
/// // (tol 0.0254 m). The wall's line y = 0 lies 1.27 m away; its foot is on the axis. The cone
/// // (half-width 12.5°) meets the line 1.27·tan 12.5° = 0.2815 m either side of the foot, and
/// // the disc of radius 1.52 − 0.0508 = 1.4692 m meets it √(1.4692² − 1.27²) = 0.7387 m either
/// // side: the cone is the narrower. Measured from a = (2, 0) towards b = (3.4, 0):
/// let beam = Beam { origin: Point::new(3.3, 1.27), direction: Vec2::new(0.0, -1.0), range_m: 1.52 };
/// let half = HalfCone::new(12.5f64.to_radians());
/// let (a, b) = (Point::new(2.0, 0.0), Point::new(3.4, 0.0));
/// let (near, far) = free_part_of_line(&beam, &a, &b, 1.0, half).unwrap();
/// assert!((near - 1.0185).abs() < 1e-4 && (far - 1.5815).abs() < 1e-4);
/// // Turned 10° towards b, the cone meets the line from 2.5° before the normal to 22.5° past
/// // it: 1.3 − 1.27·tan 2.5° = 1.2446 to 1.3 + 1.27·tan 22.5° = 1.8261.
/// let turned = Beam { direction: Vec2::new(10f64.to_radians().sin(), -10f64.to_radians().cos()), ..beam };
/// let (near, far) = free_part_of_line(&turned, &a, &b, 1.0, half).unwrap();
/// assert!((near - 1.2446).abs() < 1e-4 && (far - 1.8261).abs() < 1e-4);
/// // Read at 1.30 m, within 2·tol of the foot's 1.27 m: nothing is free.
/// let near_wall = Beam { range_m: 1.30, ..beam };
/// assert!(free_part_of_line(&near_wall, &a, &b, 1.0, half).is_none());
/// ```
pub fn free_part_of_line(
    beam: &Beam,
    a: &Point,
    b: &Point,
    accuracy_pct: f64,
    half: HalfCone,
) -> Option<(f64, f64)> {
    let length = (b - a).norm();
    if length <= 0.0 {
        return None;
    }
    let along = (b - a) / length;
    let foot_from_a = (beam.origin - a).dot(&along);
    let to_foot = a + along * foot_from_a - beam.origin;
    let p = to_foot.norm();
    let free_range = beam.range_m - 2.0 * feature_tolerance_m(accuracy_pct, beam.range_m);
    if p <= 0.0 || free_range <= p {
        return None;
    }
    // The axis's angle from the normal, positive towards `along`, as its cosine and sine.
    let (cos_axis, sin_axis) = (beam.direction.dot(&to_foot) / p, beam.direction.dot(&along));
    if cos_axis < half.cos {
        return None;
    }
    // tan(axis ∓ half) for the cone's two edges; both within 90° of the normal, since the axis
    // is within the half-width of it and the half-width is under 45°.
    let edge_tan = |sin_edge: f64, cos_edge: f64| {
        if cos_edge > 0.0 {
            sin_edge / cos_edge
        } else {
            sin_edge.signum() * f64::INFINITY
        }
    };
    let near_tan = edge_tan(
        sin_axis * half.cos - cos_axis * half.sin,
        cos_axis * half.cos + sin_axis * half.sin,
    );
    let far_tan = edge_tan(
        sin_axis * half.cos + cos_axis * half.sin,
        cos_axis * half.cos - sin_axis * half.sin,
    );
    let half_chord = (free_range * free_range - p * p).sqrt();
    let near = (p * near_tan).max(-half_chord);
    let far = (p * far_tan).min(half_chord);
    Some((foot_from_a + near, foot_from_a + far))
}

/// What a free part of its line does to a segment.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Cut {
    /// End `a` moves this far along the segment towards `b`, metres.
    EndA(f64),
    /// End `b` moves to this far from `a`, metres.
    EndB(f64),
    /// The part between these distances from `a` goes: the segment becomes two.
    Hole(f64, f64),
    /// Nothing long enough is left.
    Remove,
}

/// What the free part `(near, far)` (from [`free_part_of_line`], meeting the segment) does to a
/// segment of `length_m` with `readings_before` of its readings short of the free part and
/// `readings_after` past it: the free part comes off, and a piece left beside it shorter than
/// `shortest_left_m`, or with fewer than two readings, goes too.
///
/// ```
/// use sonarmap::mapping::ext::seen_through_ends::{cut_of, Cut};
/// // A segment 1.3 m long; the free part from 1.0185 m to 1.5815 m holds its end b: b moves
/// // back to 1.0185 m (its 9 readings short of it stay, the 3 past 1.0185 m go).
/// assert_eq!(cut_of((1.0185, 1.5815), 1.3, 0.05, 9, 0), Cut::EndB(1.0185));
/// assert_eq!(cut_of((-0.2, 0.4), 1.3, 0.05, 0, 9), Cut::EndA(0.4));
/// // Inside a segment 2 m long it leaves a hole; 0.03 m from its end, it takes the end too,
/// // and one reading is not enough for a piece.
/// assert_eq!(cut_of((1.0185, 1.5815), 2.0, 0.05, 9, 4), Cut::Hole(1.0185, 1.5815));
/// assert_eq!(cut_of((1.0185, 1.5815), 1.61, 0.05, 9, 2), Cut::EndB(1.0185));
/// assert_eq!(cut_of((1.0185, 1.5815), 2.0, 0.05, 9, 1), Cut::EndB(1.0185));
/// // Over all of a segment.
/// assert_eq!(cut_of((-0.1, 1.4), 1.3, 0.05, 0, 0), Cut::Remove);
/// ```
pub fn cut_of(
    (near, far): (f64, f64),
    length_m: f64,
    shortest_left_m: f64,
    readings_before: usize,
    readings_after: usize,
) -> Cut {
    let keeps = |left_m: f64, readings: usize| left_m >= shortest_left_m && readings >= 2;
    match (
        keeps(near, readings_before),
        keeps(length_m - far, readings_after),
    ) {
        (true, true) => Cut::Hole(near, far),
        (true, false) => Cut::EndB(near),
        (false, true) => Cut::EndA(far),
        (false, false) => Cut::Remove,
    }
}
