//! Plane geometry in the world frame: points, poses, projections and angles.
//!
//! Angles are stored in radians; degrees appear only at the edges (files, UI).

use nalgebra::{Point2, Rotation2, Vector2};
use serde::{Deserialize, Serialize};

/// A point in the plane (metres unless a name says otherwise).
pub type Point = Point2<f64>;
/// A displacement in the plane.
pub type Vec2 = Vector2<f64>;

/// A robot pose in the world frame: position and the heading of the robot's x axis.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Pose {
    /// World x of the robot centre.
    pub x: f64,
    /// World y of the robot centre.
    pub y: f64,
    /// Heading of the robot's x axis against the world x axis, radians.
    pub heading_rad: f64,
}

impl Pose {
    /// A pose from position and heading in radians.
    pub fn new(x: f64, y: f64, heading_rad: f64) -> Self {
        Self { x, y, heading_rad }
    }

    /// The robot centre as a point.
    pub fn position(&self) -> Point {
        Point::new(self.x, self.y)
    }

    /// Maps a point given in the robot frame into the world frame.
    pub fn world_from_robot(&self, point_in_robot: &Point) -> Point {
        self.robot_frame().to_world(point_in_robot)
    }

    /// The robot frame at this pose, its rotation computed once for many points.
    pub fn robot_frame(&self) -> RobotFrame {
        RobotFrame {
            origin_in_world: self.position(),
            rotation: Rotation2::new(self.heading_rad),
        }
    }

    /// Distance between the positions of two poses.
    pub fn distance_to(&self, other: &Pose) -> f64 {
        (self.position() - other.position()).norm()
    }

    /// The pose `relative` (given in this pose's robot frame) in the world: `self ⊕ relative`.
    pub fn compose(&self, relative: &Pose) -> Pose {
        let at = self.world_from_robot(&relative.position());
        Pose::new(at.x, at.y, self.heading_rad + relative.heading_rad)
    }

    /// `other` in this pose's robot frame: `self⁻¹ ⊕ other`, so that
    /// `self.compose(&self.relative_to(other))` is `other`.
    pub fn relative_to(&self, other: &Pose) -> Pose {
        let (s, c) = self.heading_rad.sin_cos();
        let (dx, dy) = (other.x - self.x, other.y - self.y);
        Pose::new(
            c * dx + s * dy,
            -s * dx + c * dy,
            wrap_pi(other.heading_rad - self.heading_rad),
        )
    }

    /// The pose a fraction `f` of the way from this one to `to` (positions linearly, heading
    /// the short way round); `f` outside 0..1 extrapolates at the same rate.
    pub fn interpolate(&self, to: &Pose, f: f64) -> Pose {
        Pose::new(
            self.x + f * (to.x - self.x),
            self.y + f * (to.y - self.y),
            self.heading_rad + f * wrap_pi(to.heading_rad - self.heading_rad),
        )
    }
}

/// A heading `heading_rad` as degrees in `(-180°, 180°]`, as the inspector shows it (a long
/// run's odometry counts its turns).
///
/// ```
/// use sonarmap::geometry::heading_deg;
/// // Three quarter turns clockwise and 100 turns anticlockwise then 10° more.
/// assert!((heading_deg(-1.5 * std::f64::consts::PI) - 90.0).abs() < 1e-9);
/// assert!((heading_deg((36_000.0f64 + 10.0).to_radians()) - 10.0).abs() < 1e-9);
/// ```
pub fn heading_deg(heading_rad: f64) -> f64 {
    wrap_pi(heading_rad).to_degrees()
}

/// `a` (radians) in `(-π, π]`.
///
/// An angle already within a turn of it skips the remainder: `x % τ` is `x` exactly for
/// `0 ≤ x < τ` (the floating-point remainder is exact), so both ways give the same bits.
pub fn wrap_pi(a: f64) -> f64 {
    use std::f64::consts::{PI, TAU};
    let shifted = a + PI;
    let r = if (0.0..TAU).contains(&shifted) {
        shifted - PI
    } else {
        shifted.rem_euclid(TAU) - PI
    };
    if r <= -PI {
        r + TAU
    } else {
        r
    }
}

/// The robot frame placed in the world (see [`Pose::robot_frame`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RobotFrame {
    origin_in_world: Point,
    rotation: Rotation2<f64>,
}

impl RobotFrame {
    /// Maps a point given in the robot frame into the world frame.
    pub fn to_world(&self, point_in_robot: &Point) -> Point {
        self.origin_in_world + self.rotation * point_in_robot.coords
    }

    /// Turns a direction given in the robot frame into the world frame.
    pub fn direction_to_world(&self, direction_in_robot: &Vec2) -> Vec2 {
        self.rotation * direction_in_robot
    }
}

/// Unit vector at `angle_rad` from the x axis.
pub fn unit(angle_rad: f64) -> Vec2 {
    Vec2::new(angle_rad.cos(), angle_rad.sin())
}

/// Parameter `t` of the orthogonal projection of `p` on the line `a + t (b - a)`.
/// `a == b` gives `t = 0`.
pub fn projection_param(p: &Point, a: &Point, b: &Point) -> f64 {
    AlongLine::new(a, b).param(p)
}

/// The line `a + t (b - a)` ready for many [`projection_param`]s (its terms computed once).
#[derive(Clone, Copy, Debug)]
pub struct AlongLine {
    a: Point,
    ab: Vec2,
    len2: f64,
}

impl AlongLine {
    /// The line through `a` and `b`.
    pub fn new(a: &Point, b: &Point) -> Self {
        let ab = b - a;
        Self {
            a: *a,
            ab,
            len2: ab.norm_squared(),
        }
    }

    /// [`projection_param`] of `p` (0 when `a` and `b` coincide).
    pub fn param(&self, p: &Point) -> f64 {
        if self.len2 <= f64::MIN_POSITIVE {
            0.0
        } else {
            (p - self.a).dot(&self.ab) / self.len2
        }
    }
}

/// `x` as an unsigned integer in the order of [`f64::total_cmp`].
pub fn total_order_key(x: f64) -> u64 {
    let bits = x.to_bits();
    if bits >> 63 == 1 {
        !bits
    } else {
        bits | 1 << 63
    }
}

/// Point at parameter `t` on `a + t (b - a)`.
pub fn lerp(a: &Point, b: &Point, t: f64) -> Point {
    a + (b - a) * t
}

/// Distance from `p` to the infinite line through `a` and `b` (to `a` when they coincide).
pub fn distance_to_line(p: &Point, a: &Point, b: &Point) -> f64 {
    let ab = b - a;
    let len = ab.norm();
    if len <= f64::MIN_POSITIVE {
        (p - a).norm()
    } else {
        (ab.x * (p.y - a.y) - ab.y * (p.x - a.x)).abs() / len
    }
}

/// Whether the segments `p1`–`p2` and `q1`–`q2` cross at a point inside both (touching or
/// collinear segments do not count).
pub fn segments_cross(p1: &Point, p2: &Point, q1: &Point, q2: &Point) -> bool {
    let side = |a: &Point, b: &Point, c: &Point| (b - a).perp(&(c - a));
    let (d1, d2) = (side(q1, q2, p1), side(q1, q2, p2));
    let (d3, d4) = (side(p1, p2, q1), side(p1, p2, q2));
    d1 * d2 < 0.0 && d3 * d4 < 0.0
}

/// Where the ray from `origin` along `direction` meets the line of `a`–`b`: its distance along
/// the ray (in units of `direction`'s length; negative behind the origin) and its place on the
/// segment (0 at `a`, 1 at `b`); `None` when they are (nearly) parallel.
///
/// ```
/// use sonarmap::geometry::{ray_meets_segment_line, Point, Vec2};
/// // Looking along +y from the origin at (-1, 2)–(1, 2.2): met at (0, 2.1), half way along.
/// let (t, s) = ray_meets_segment_line(&Point::origin(), &Vec2::new(0.0, 1.0), &Point::new(-1.0, 2.0), &Point::new(1.0, 2.2)).unwrap();
/// assert!((t - 2.1).abs() < 1e-12 && (s - 0.5).abs() < 1e-12);
/// assert!(ray_meets_segment_line(&Point::origin(), &Vec2::new(1.0, 0.0), &Point::new(0.0, 1.0), &Point::new(2.0, 1.0)).is_none());
/// ```
pub fn ray_meets_segment_line(
    origin: &Point,
    direction: &Vec2,
    a: &Point,
    b: &Point,
) -> Option<(f64, f64)> {
    let cross = |u: &Vec2, v: &Vec2| u.x * v.y - u.y * v.x;
    let e = b - a;
    let denom = cross(direction, &e);
    if denom.abs() < 1e-12 * e.norm() {
        return None;
    }
    let ao = a - origin;
    Some((cross(&ao, &e) / denom, cross(&ao, direction) / denom))
}

/// Distance from `p` to the closed segment `[a, b]`.
pub fn distance_to_segment(p: &Point, a: &Point, b: &Point) -> f64 {
    let t = projection_param(p, a, b).clamp(0.0, 1.0);
    (p - lerp(a, b, t)).norm()
}

/// Angle between two undirected lines with directions `u` and `v`, in `[0, π/2]`.
/// Directions that differ by 180° are the same line (§3.3.1 orientation test, modulo 180°).
pub fn line_angle_between(u: &Vec2, v: &Vec2) -> f64 {
    // The angle between the directions, in [0, π], from one atan2.
    let m = (u.x * v.y - u.y * v.x).abs().atan2(u.dot(v));
    m.min(std::f64::consts::PI - m)
}

/// An angle limit with its tangent, computed once for many [`line_angle_at_most`] tests.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AngleLimit {
    /// The limit, radians.
    pub rad: f64,
    tan: f64,
}

impl AngleLimit {
    /// The limit `rad`.
    pub fn new(rad: f64) -> Self {
        Self {
            rad,
            tan: rad.tan(),
        }
    }
}

/// `line_angle_between(u, v) <= limit.rad`, the same answer for every input, mostly without
/// the `atan2`: the angle is `atan(|u × v| / |u · v|)`, so comparing `|u × v|` with
/// `tan(limit)·|u · v|` decides, unless the two are within a relative 1e-6 of each other (far
/// wider than the rounding of either way) or the limit lies outside (1e-6, 1.5) rad; then the
/// angle itself is compared.
pub fn line_angle_at_most(u: &Vec2, v: &Vec2, limit: AngleLimit) -> bool {
    const BAND: f64 = 1e-6;
    if limit.rad > 1e-6 && limit.rad < 1.5 {
        let cross = (u.x * v.y - u.y * v.x).abs();
        let bound = limit.tan * u.dot(v).abs();
        if cross < bound * (1.0 - BAND) {
            return true;
        }
        if cross > bound * (1.0 + BAND) {
            return false;
        }
    }
    line_angle_between(u, v) <= limit.rad
}

/// Intersection of the infinite lines `a1 b1` and `a2 b2`; `None` when (nearly) parallel.
pub fn line_intersection(a1: &Point, b1: &Point, a2: &Point, b2: &Point) -> Option<Point> {
    let d1 = b1 - a1;
    let d2 = b2 - a2;
    let denom = d1.x * d2.y - d1.y * d2.x;
    let scale = d1.norm() * d2.norm();
    if scale <= f64::MIN_POSITIVE || denom.abs() <= 1e-12 * scale {
        return None;
    }
    let w = a2 - a1;
    let t = (w.x * d2.y - w.y * d2.x) / denom;
    Some(a1 + d1 * t)
}

/// Normalises an angle to `[0, 2π)`.
pub fn normalize_angle_positive(angle_rad: f64) -> f64 {
    let r = angle_rad.rem_euclid(std::f64::consts::TAU);
    if r >= std::f64::consts::TAU {
        0.0
    } else {
        r
    }
}

/// Total-least-squares line through `points`: centroid and unit direction.
/// Returns `None` for fewer than two distinct points.
pub fn fit_line_tls(points: &[Point]) -> Option<(Point, Vec2)> {
    if points.len() < 2 {
        return None;
    }
    let n = points.len() as f64;
    let cx = points.iter().map(|p| p.x).sum::<f64>() / n;
    let cy = points.iter().map(|p| p.y).sum::<f64>() / n;
    let (mut sxx, mut sxy, mut syy) = (0.0, 0.0, 0.0);
    for p in points {
        let dx = p.x - cx;
        let dy = p.y - cy;
        sxx += dx * dx;
        sxy += dx * dy;
        syy += dy * dy;
    }
    if sxx + syy <= f64::MIN_POSITIVE {
        return None;
    }
    let angle = 0.5 * (2.0 * sxy).atan2(sxx - syy);
    Some((Point::new(cx, cy), unit(angle)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn wrap_pi_gives_the_remainders_bits_with_or_without_its_shortcut() {
        use std::f64::consts::TAU;
        let by_remainder = |a: f64| {
            let r = (a + PI).rem_euclid(TAU) - PI;
            if r <= -PI {
                r + TAU
            } else {
                r
            }
        };
        let mut angles = vec![
            0.0,
            -0.0,
            PI,
            -PI,
            TAU,
            -TAU,
            1e-300,
            -1e-300,
            3.0 * PI,
            -7.5,
        ];
        angles.extend([PI.next_up(), (-PI).next_down(), (TAU - PI).next_down()]);
        angles.extend((-4000..4000).map(|k| f64::from(k) * 0.00157 + 1e-7 * f64::from(k % 7)));
        for a in angles {
            assert_eq!(wrap_pi(a).to_bits(), by_remainder(a).to_bits(), "{a:e}");
        }
        assert!(wrap_pi(f64::NAN).is_nan());
    }

    #[test]
    fn segments_cross_only_inside_both() {
        let p = |x: f64, y: f64| Point::new(x, y);
        assert!(segments_cross(
            &p(0.0, 0.0),
            &p(2.0, 2.0),
            &p(0.0, 2.0),
            &p(2.0, 0.0)
        ));
        // Touching at an end-point, or parallel, is not crossing.
        assert!(!segments_cross(
            &p(0.0, 0.0),
            &p(1.0, 1.0),
            &p(1.0, 1.0),
            &p(2.0, 0.0)
        ));
        assert!(!segments_cross(
            &p(0.0, 0.0),
            &p(2.0, 0.0),
            &p(0.0, 1.0),
            &p(2.0, 1.0)
        ));
        // The lines cross, the segments do not.
        assert!(!segments_cross(
            &p(0.0, 0.0),
            &p(1.0, 1.0),
            &p(3.0, 0.0),
            &p(2.0, 1.0)
        ));
    }

    #[test]
    fn angle_limit_test_handles_degenerate_directions_like_the_angle() {
        let limit = AngleLimit::new(15f64.to_radians());
        let odd = [
            Vec2::zeros(),
            Vec2::new(f64::NAN, 1.0),
            Vec2::new(f64::INFINITY, 0.0),
            Vec2::new(f64::INFINITY, f64::INFINITY),
            Vec2::new(0.0, -1.0),
            Vec2::new(1.0, 1e-300),
        ];
        for u in odd {
            for v in odd {
                assert_eq!(
                    line_angle_at_most(&u, &v, limit),
                    line_angle_between(&u, &v) <= limit.rad,
                    "{u:?} {v:?}"
                );
            }
        }
    }

    proptest::proptest! {
        #[test]
        fn angle_limit_test_agrees_with_the_angle(
            u_angle in -4.0f64..4.0,
            turn in -4.0f64..4.0,
            (len_u, len_v) in (1e-4f64..1e4, 1e-4f64..1e4),
            limit_rad in 0.0f64..1.6,
            jitter in -1e-12f64..1e-12,
            on_limit in 0u8..3,
        ) {
            // Directions at any angle, or within a hair of the limit (either way round).
            let turn = match on_limit {
                0 => turn,
                1 => limit_rad + jitter,
                _ => PI - limit_rad + jitter,
            };
            let u = unit(u_angle) * len_u;
            let v = unit(u_angle + turn) * len_v;
            let limit = AngleLimit::new(limit_rad);
            proptest::prop_assert_eq!(
                line_angle_at_most(&u, &v, limit),
                line_angle_between(&u, &v) <= limit_rad
            );
        }
    }

    #[test]
    fn line_angle_wraps_at_180_degrees() {
        let a = unit(179f64.to_radians());
        let b = unit(1f64.to_radians());
        assert!((line_angle_between(&a, &b) - 2f64.to_radians()).abs() < 1e-12);
        let c = unit(-PI + 0.1);
        let d = unit(0.05);
        assert!((line_angle_between(&c, &d) - 0.05).abs() < 1e-12);
        assert!((line_angle_between(&unit(0.0), &unit(PI / 2.0)) - PI / 2.0).abs() < 1e-12);
    }

    #[test]
    fn projection_and_distances() {
        let a = Point::new(0.0, 0.0);
        let b = Point::new(10.0, 0.0);
        let p = Point::new(12.0, 3.0);
        assert!((projection_param(&p, &a, &b) - 1.2).abs() < 1e-12);
        assert!((distance_to_line(&p, &a, &b) - 3.0).abs() < 1e-12);
        assert!((distance_to_segment(&p, &a, &b) - 13f64.sqrt()).abs() < 1e-12);
    }

    #[test]
    fn intersection_of_perpendicular_lines() {
        let p = line_intersection(
            &Point::new(0.0, 1.0),
            &Point::new(2.0, 1.0),
            &Point::new(5.0, 0.0),
            &Point::new(5.0, 3.0),
        )
        .unwrap();
        assert!((p - Point::new(5.0, 1.0)).norm() < 1e-12);
        assert!(line_intersection(
            &Point::new(0.0, 0.0),
            &Point::new(1.0, 0.0),
            &Point::new(0.0, 1.0),
            &Point::new(1.0, 1.0)
        )
        .is_none());
    }

    #[test]
    fn pose_maps_robot_frame_to_world() {
        let pose = Pose::new(1.0, 2.0, PI / 2.0);
        let w = pose.world_from_robot(&Point::new(1.0, 0.0));
        assert!((w - Point::new(1.0, 3.0)).norm() < 1e-12);
    }
}
