//! Free-space refutation (docs/algorithm.md §8.6; beyond the paper).
//!
//! The paper places each echo on its beam axis (§2). A specular wall seen obliquely echoes
//! from the nearest point of the cone that still reflects, so its readings land inside the
//! room and fit lines parallel to the wall but short of it, and a corner's arc fits slanted
//! lines. Each is refuted by a sonar that looked straight at it: when the foot of the
//! perpendicular from a sensor to a map segment lies inside the segment and inside the beam
//! (within half the beam width of the axis), a real wall there would have echoed from the foot,
//! at the perpendicular distance `p`. A reading `D` with `p + 2·tol(D) < D` (`tol` the
//! resolution `ξ·D/100`, at least 1 in) says nothing is there: the segment leaves the map.
//! Only the segments the grid files in the beam's box are tested, and a confirmed one stays
//! (`Map::is_confirmed`: readings from two snapshots supported it as a plane, §8.7). Refuting confirmed walls too made a lap run churn: a wall refuted by one
//! oblique reading came back as a new face on the next lap, and the map of a small room grew
//! from 273 to 1,176 segments over 20,000 snapshots, each snapshot costing 3× more by the end.

use crate::geometry::{projection_param, Point, Vec2};
use crate::mapping::ext::beam_geometry::feature_tolerance_m;
use crate::mapping::ext::beam_geometry::HalfCone;
use crate::mapping::model::beam::Beam;
use crate::mapping::model::map::{Map, SegmentId};

/// Whether `beam` refutes the segment `a`–`b`: returns the perpendicular distance and its
/// angle off the axis when the foot lies in the segment and the beam and `p + 2·tol(D) < D`.
///
/// ```
/// use sonarmap::geometry::{Point, Vec2};
/// use sonarmap::mapping::ext::free_space::refutes;
/// use sonarmap::mapping::model::beam::Beam;
/// // A sensor at the origin looks along +y and reads 3.00 m (tol 0.09 m). A segment from
/// // (-1, 2) to (1, 2.2): the foot of the perpendicular, at param 1.6/4.04 = 0.396, is
/// // (-0.2079, 2.0792), 5.71° off +y (inside 12.5°); p = 2.0896, p + 0.18 = 2.27 < 3: refuted.
/// let beam = Beam { origin: Point::origin(), direction: Vec2::new(0.0, 1.0), range_m: 3.0 };
/// let half = 12.5f64.to_radians();
/// let (p, off) = refutes(&beam, &Point::new(-1.0, 2.0), &Point::new(1.0, 2.2), 3.0, half).unwrap();
/// assert!((p - 2.0896).abs() < 1e-4 && (off.to_degrees() - 5.71).abs() < 0.01);
/// // The same segment read at 2.20 m: p + 2·0.066 = 2.22 > 2.20, kept.
/// let near = Beam { range_m: 2.2, ..beam };
/// assert!(refutes(&near, &Point::new(-1.0, 2.0), &Point::new(1.0, 2.2), 3.0, half).is_none());
/// // A segment along the axis: the foot (0.1, 0) lies outside it, kept.
/// assert!(refutes(&beam, &Point::new(0.1, 1.0), &Point::new(0.1, 2.0), 3.0, half).is_none());
/// ```
pub fn refutes(
    beam: &Beam,
    a: &Point,
    b: &Point,
    accuracy_pct: f64,
    half_beam_rad: f64,
) -> Option<(f64, f64)> {
    let t = projection_param(&beam.origin, a, b);
    if !(0.0..=1.0).contains(&t) {
        return None;
    }
    let foot = a + (b - a) * t;
    let v = foot - beam.origin;
    let p = v.norm();
    if p <= 0.0 || p + 2.0 * feature_tolerance_m(accuracy_pct, beam.range_m) >= beam.range_m {
        return None;
    }
    let off = (v.dot(&beam.direction) / p).clamp(-1.0, 1.0).acos();
    (off <= half_beam_rad).then_some((p, off))
}

/// The segments of `map` that `beam` refutes (see [`refutes`]), in id order, from the segments
/// the grid files in the box of the beam's cone, less the confirmed ones (`Map::is_confirmed`:
/// a plane supported from two snapshots stays). Reads the index's copy of each segment's
/// end-points (no lookup of the segment itself).
pub fn refuted_segments(
    map: &Map,
    beam: &Beam,
    accuracy_pct: f64,
    half_beam_rad: f64,
    out: &mut Vec<(SegmentId, f64, f64)>,
) {
    out.clear();
    let (low, high, bulge_m) = cone_box(beam, half_beam_rad, 0.0, beam.range_m);
    map.visit_segments_along(&low, &high, bulge_m, |id, s| {
        if map.is_confirmed(id) {
            return;
        }
        if let Some((p, off)) = refutes(beam, &s.a.point, &s.b.point, accuracy_pct, half_beam_rad) {
            out.push((id, p, off));
        }
    });
    out.sort_unstable_by_key(|&(id, _, _)| id);
}

/// The box of the part of `beam`'s cone between `near_m` and `far_m` from its sensor (the
/// ends of its two edges at both distances, and of its axis at `far_m`), and how far the far
/// arc can bulge past it (`far·(1 − cos(half/2))`), metres: every point of the cone between
/// those distances lies within that distance of the box. With `near_m` 0 it is the whole
/// sector up to `far_m`.
pub fn cone_box(beam: &Beam, half_beam_rad: f64, near_m: f64, far_m: f64) -> (Point, Point, f64) {
    cone_box_in(beam, HalfCone::new(half_beam_rad), near_m, far_m)
}

/// [`cone_box`], the beam's half-width given as its [`HalfCone`].
pub fn cone_box_in(beam: &Beam, half: HalfCone, near_m: f64, far_m: f64) -> (Point, Point, f64) {
    let HalfCone {
        cos: cos_half,
        sin: sin_half,
        cos_half: cos_quarter,
    } = half;
    let d = beam.direction;
    let edges = [
        Vec2::new(
            cos_half * d.x - sin_half * d.y,
            sin_half * d.x + cos_half * d.y,
        ),
        Vec2::new(
            cos_half * d.x + sin_half * d.y,
            -sin_half * d.x + cos_half * d.y,
        ),
    ];
    let corners = [
        beam.origin + d * far_m,
        beam.origin + edges[0] * near_m,
        beam.origin + edges[0] * far_m,
        beam.origin + edges[1] * near_m,
        beam.origin + edges[1] * far_m,
    ];
    let low = corners
        .iter()
        .fold(Point::new(f64::INFINITY, f64::INFINITY), |m, c| {
            Point::new(m.x.min(c.x), m.y.min(c.y))
        });
    let high = corners
        .iter()
        .fold(Point::new(f64::NEG_INFINITY, f64::NEG_INFINITY), |m, c| {
            Point::new(m.x.max(c.x), m.y.max(c.y))
        });
    (low, high, far_m * (1.0 - cos_quarter) + 1e-9)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Vec2;
    use crate::mapping::model::map::{test_wall, Segment};

    fn segment(id: u32, a: (f64, f64), b: (f64, f64)) -> Segment {
        test_wall(id, a, b, 1.0)
    }

    #[test]
    fn a_beam_reading_past_a_segment_refutes_it_and_only_it() {
        // The sensor at the origin looks along +x and reads 3 m (tolerance 0.09 m):
        // s0 across the beam at 2 m is seen through (2 + 0.18 < 3); s1 at 2.9 m is within
        // 2·tol of the range (2.9 + 0.18 > 3); s2 at 2 m lies 1 m to the side, its foot
        // (2, 0) lies outside it.
        let map = Map::from_segments(vec![
            segment(0, (2.0, -0.5), (2.0, 0.5)),
            segment(1, (2.9, -0.5), (2.9, 0.5)),
            segment(2, (2.0, 1.0), (2.0, 2.0)),
        ]);
        let beam = Beam {
            origin: Point::origin(),
            direction: Vec2::new(1.0, 0.0),
            range_m: 3.0,
        };
        let mut out = Vec::new();
        refuted_segments(&map, &beam, 3.0, 12.5f64.to_radians(), &mut out);
        assert_eq!(out.len(), 1);
        assert_eq!(out[0].0, 0);
        assert!((out[0].1 - 2.0).abs() < 1e-12 && out[0].2.abs() < 1e-12);
        // Once readings from two snapshots supported s0 as a plane, the reading leaves it.
        let mut confirmed = map;
        confirmed.plane_support.insert(
            0,
            crate::mapping::model::plane_supports::PlaneSupport {
                snapshots: crate::mapping::model::plane_supports::CONFIRMING_SNAPSHOTS,
                last_snapshot: 0,
                ..Default::default()
            },
        );
        refuted_segments(&confirmed, &beam, 3.0, 12.5f64.to_radians(), &mut out);
        assert!(out.is_empty(), "a confirmed segment stays: {out:?}");
    }
}
