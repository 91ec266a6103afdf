//! Confirmation of segments (docs/algorithm.md §8.7; beyond the paper).
//!
//! A plane returns a sonar's echo from the foot of the perpendicular from the sensor (Kleeman
//! and Kuc's plane model): a reading supports a segment *as a plane* when the perpendicular
//! distance from its sensor to the segment's line is its range within the tolerance
//! (`ξ·D/100`, at least 1 in), the foot lies on the segment (10 % of its length of slack at
//! either end), and the foot lies within half the beam width of the axis. A corner's arc fitted
//! as a slanted line, or a wall seen obliquely and placed short of it, has no such reading from
//! two poses. A segment is **confirmed** once readings of two distinct snapshots support it as
//! a plane; until then it is tentative (drawn dimmed; `eval` reports both sets).

use super::echo_fit::{echo_ray, incidence_cosine, HalfCone};
use super::map::{Map, SegmentId};
use super::point_features::{feature_tolerance_m, Beam};
use crate::geometry::{projection_param, Point, Vec2};
use serde::{Deserialize, Serialize};

/// Snapshots whose readings support a segment as a plane before it is confirmed.
pub const CONFIRMING_SNAPSHOTS: u32 = 2;

/// What the map keeps of a segment's plane support.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct PlaneSupport {
    /// Distinct snapshots whose readings supported it as a plane.
    pub snapshots: u32,
    /// The latest of them.
    pub last_snapshot: usize,
}

impl PlaneSupport {
    /// Confirmed: supported by [`CONFIRMING_SNAPSHOTS`] snapshots.
    pub fn confirmed(&self) -> bool {
        self.snapshots >= CONFIRMING_SNAPSHOTS
    }
}

/// A segment that gained plane support this step, for the trace.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PlaneSupportTrace {
    /// The segment.
    pub segment: SegmentId,
    /// The sensor whose reading supported it.
    pub sensor: usize,
    /// The reading, metres.
    pub range_m: f64,
    /// The perpendicular distance from the sensor to its line, metres.
    pub distance_m: f64,
    /// Snapshots supporting it now.
    pub snapshots: u32,
    /// Whether it is confirmed now.
    pub confirmed: bool,
}

/// Whether `beam` supports the segment `a`–`b` as a plane; returns the perpendicular distance.
///
/// ```
/// use sonarmap::geometry::{Point, Vec2};
/// use sonarmap::mapping::confirm::supports_as_plane;
/// use sonarmap::mapping::point_features::Beam;
/// // A sensor at the origin looking along +y reads 2.03 m; a wall from (-1, 2) to (1, 2):
/// // foot (0, 2) on the axis, |2 − 2.03| = 0.03 ≤ 0.0609 (3 % of 2.03): a plane echo.
/// let beam = Beam { origin: Point::origin(), direction: Vec2::new(0.0, 1.0), range_m: 2.03 };
/// let d = supports_as_plane(&beam, &Point::new(-1.0, 2.0), &Point::new(1.0, 2.0), 3.0, 12.5f64.to_radians());
/// assert!((d.unwrap() - 2.0).abs() < 1e-12);
/// // Read at 2.20 m (a corner 10 % farther): |2 − 2.2| = 0.2 > 0.066, no support.
/// let far = Beam { range_m: 2.2, ..beam };
/// assert!(supports_as_plane(&far, &Point::new(-1.0, 2.0), &Point::new(1.0, 2.0), 3.0, 12.5f64.to_radians()).is_none());
/// // The wall from (0.6, 2) to (2, 2): the foot (0, 2) is 0.6 m before its start (slack 0.14).
/// assert!(supports_as_plane(&beam, &Point::new(0.6, 2.0), &Point::new(2.0, 2.0), 3.0, 12.5f64.to_radians()).is_none());
/// ```
pub fn supports_as_plane(
    beam: &Beam,
    a: &Point,
    b: &Point,
    accuracy_pct: f64,
    half_beam_rad: f64,
) -> Option<f64> {
    let t = projection_param(&beam.origin, a, b);
    if !(-0.1..=1.1).contains(&t) {
        return None;
    }
    let foot = a + (b - a) * t;
    let v = foot - beam.origin;
    let d = v.norm();
    if d <= 0.0 || (d - beam.range_m).abs() > feature_tolerance_m(accuracy_pct, beam.range_m) {
        return None;
    }
    (v.dot(&beam.direction) / d >= half_beam_rad.cos()).then_some(d)
}

/// Whether `beam` supports the segment `a`–`b` as a plane, its echo taken from the nearest
/// point of the plane inside the cone (docs/algorithm.md §8.10): the foot of the perpendicular
/// when the normal lies inside the cone ([`supports_as_plane`]), else where the cone's nearer
/// edge meets the line, at most [`MAX_INCIDENCE_RAD`](super::echo_fit::MAX_INCIDENCE_RAD) off the normal. That point must lie on
/// the segment (10 % slack) at the range within the tolerance. Returns the predicted range.
///
/// ```
/// use sonarmap::geometry::{Point, Vec2};
/// use sonarmap::mapping::confirm::supports_as_echo;
/// use sonarmap::mapping::point_features::Beam;
/// // The wall y = 2 seen 30° off its normal: the cone edge (12.5°) meets it 17.5° off the
/// // normal, at 2 / cos 17.5° = 2.0971 m, at x = 0.6306.
/// let dir = Vec2::new(60f64.to_radians().cos(), 60f64.to_radians().sin());
/// let beam = Beam { origin: Point::origin(), direction: dir, range_m: 2.10 };
/// let (a, b) = (Point::new(0.0, 2.0), Point::new(2.0, 2.0));
/// let d = supports_as_echo(&beam, &a, &b, 3.0, 12.5f64.to_radians()).unwrap();
/// assert!((d - 2.0971).abs() < 1e-4);
/// // The foot model alone refuses it: the foot (0, 2) lies 30° off the axis.
/// assert!(sonarmap::mapping::confirm::supports_as_plane(&beam, &a, &b, 3.0, 12.5f64.to_radians()).is_none());
/// ```
pub fn supports_as_echo(
    beam: &Beam,
    a: &Point,
    b: &Point,
    accuracy_pct: f64,
    half_beam_rad: f64,
) -> Option<f64> {
    let along = b - a;
    let length = along.norm();
    if length <= 0.0 {
        return None;
    }
    let mut normal = Vec2::new(-along.y, along.x) / length;
    let mut perpendicular_m = normal.dot(&(a - beam.origin));
    if perpendicular_m < 0.0 {
        normal = -normal;
        perpendicular_m = -perpendicular_m;
    }
    let half = HalfCone::new(half_beam_rad);
    if perpendicular_m <= 0.0 {
        return None;
    }
    let predicted_m = perpendicular_m / incidence_cosine(beam, &normal, half)?;
    if (predicted_m - beam.range_m).abs() > feature_tolerance_m(accuracy_pct, beam.range_m) {
        return None;
    }
    let (ray, _) = echo_ray(beam, &normal, half);
    let echo = beam.origin + ray * predicted_m;
    (-0.1..=1.1)
        .contains(&projection_param(&echo, a, b))
        .then_some(predicted_m)
}

/// The plane test a segment's readings take: [`supports_as_echo`] with `cone_edges`, else
/// [`supports_as_plane`].
pub fn supports(
    beam: &Beam,
    a: &Point,
    b: &Point,
    accuracy_pct: f64,
    half_beam_rad: f64,
    cone_edges: bool,
) -> Option<f64> {
    if cone_edges {
        supports_as_echo(beam, a, b, accuracy_pct, half_beam_rad)
    } else {
        supports_as_plane(beam, a, b, accuracy_pct, half_beam_rad)
    }
}

/// Notes the plane support `beams` (readings of `snapshot` that went into segment `id`) give
/// it: at most once a snapshot. Returns the trace record of the first supporting reading,
/// if any.
pub fn note_plane_support(
    map: &mut Map,
    id: SegmentId,
    beams: &[(usize, Beam)],
    snapshot: usize,
    accuracy_pct: f64,
    half_beam_rad: f64,
    cone_edges: bool,
) -> Option<PlaneSupportTrace> {
    let s = map.segment(id)?;
    let (a, b) = (s.a.point, s.b.point);
    let (sensor, beam, distance_m) = beams.iter().find_map(|(sensor, beam)| {
        supports(beam, &a, &b, accuracy_pct, half_beam_rad, cone_edges).map(|d| (*sensor, *beam, d))
    })?;
    let support = map.plane_support.entry(id).or_default();
    if support.snapshots > 0 && support.last_snapshot == snapshot {
        return None;
    }
    support.snapshots += 1;
    support.last_snapshot = snapshot;
    Some(PlaneSupportTrace {
        segment: id,
        sensor,
        range_m: beam.range_m,
        distance_m,
        snapshots: support.snapshots,
        confirmed: support.confirmed(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Vec2;
    use crate::mapping::map::{EndPoint, Segment, SegmentKind};

    #[test]
    fn two_snapshots_of_plane_support_confirm_a_segment_once_each() {
        let e = |x: f64| EndPoint {
            point: Point::new(x, 2.0),
            range_m: 2.0,
        };
        let mut map = Map::from_segments(vec![Segment {
            id: 0,
            kind: SegmentKind::Fitted,
            a: e(-1.0),
            b: e(1.0),
            face: 0,
            object: 0,
            created: 0,
            updated: Vec::new(),
            points: Vec::new().into(),
        }]);
        map.confirms_segments = true;
        let half = 12.5f64.to_radians();
        // Straight at the wall, 2.02 m: |2 − 2.02| = 0.02 ≤ 0.0606.
        let straight = Beam {
            origin: Point::origin(),
            direction: Vec2::new(0.0, 1.0),
            range_m: 2.02,
        };
        // 20° off the perpendicular: outside the 12.5° half beam, no support.
        let (s, c) = (20f64.to_radians().sin(), 20f64.to_radians().cos());
        let oblique = Beam {
            direction: Vec2::new(s, c),
            ..straight
        };
        assert!(map.is_tentative(0));
        assert!(note_plane_support(&mut map, 0, &[(3, oblique)], 0, 3.0, half, false).is_none());
        let first = note_plane_support(&mut map, 0, &[(1, straight)], 0, 3.0, half, false).unwrap();
        assert_eq!((first.snapshots, first.confirmed), (1, false));
        assert!((first.distance_m - 2.0).abs() < 1e-12);
        // The same snapshot again counts once.
        assert!(note_plane_support(&mut map, 0, &[(2, straight)], 0, 3.0, half, false).is_none());
        let second =
            note_plane_support(&mut map, 0, &[(1, straight)], 1, 3.0, half, false).unwrap();
        assert_eq!((second.snapshots, second.confirmed), (2, true));
        assert!(!map.is_tentative(0));
        assert!(map.check_invariants(0).is_ok());
        // A map that does not confirm calls nothing tentative.
        assert!(!Map::default().is_tentative(7));
    }
}
