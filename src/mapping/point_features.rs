//! Point features from sonar arcs (docs/algorithm.md §8.5; beyond the paper, whose §3.2 fits
//! every cluster with lines).
//!
//! A corner or an edge returns an echo to every sonar whose beam contains it, at the same range
//! from each: placed on the beam axes (paper §2), the readings draw an arc, and the recursive
//! fit turns it into short slanted segments. Two rules, both flagged:
//! - **arc rule** (`arc_features`): a cluster of two or more readings from distinct sensors
//!   whose ranges pass the ball test pairwise (Leonard and Durrant-Whyte's region of constant
//!   depth, seen by several sensors at once) is one reflector point, not a line. It becomes an
//!   observation of a point feature at range `r̄` (the mean range) along the mean beam axis,
//!   from the mean sensor position, and yields no segment.
//! - **explained readings** (`explain_readings`): a reading whose range, from its sensor, is
//!   that of a confirmed feature (seen by two snapshots at least) within the ball radius, and
//!   whose beam contains the feature, is its echo: it joins no cluster.
//!
//! Both look only at the cluster's readings and at the features the grid index files near them.

use super::echo_fit::{echo_ray, HalfCone, MAX_INCIDENCE_RAD, MAX_ROUND_RADIUS_M};
use super::map::{FeatureKind, Map, PointFeature};
use crate::geometry::{Point, Vec2};
use crate::units::inches;
use serde::{Deserialize, Serialize};

/// A kept reading with its sensor in the world frame.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Beam {
    /// The sensor's position, world frame.
    pub origin: Point,
    /// Unit vector along the beam axis, world frame.
    pub direction: Vec2,
    /// The range, metres.
    pub range_m: f64,
}

impl Beam {
    /// The point the reading puts on its beam axis (paper §2).
    pub fn axis_point(&self) -> Point {
        self.origin + self.direction * self.range_m
    }
}

/// The mean position of the sensors of `beams` (not empty).
pub fn mean_origin(beams: &[Beam]) -> Point {
    Point::from(beams.iter().map(|b| b.origin.coords).sum::<Vec2>() / beams.len() as f64)
}

/// The mean range of `beams` (not empty), metres.
pub fn mean_range_m(beams: &[Beam]) -> f64 {
    beams.iter().map(|b| b.range_m).sum::<f64>() / beams.len() as f64
}

/// The ball test of §1 on two ranges: `|d1 − d2| ≤ ξ·(d1 + d2)/100`.
fn same_depth(accuracy_pct: f64, d1: f64, d2: f64) -> bool {
    (d1 - d2).abs() <= accuracy_pct * (d1 + d2) / 100.0
}

/// Tolerance of a range `range_m` in feature tests: the sonar resolution `ξ·D/100`, at least
/// 1 in (as `eval` judges end-points).
pub fn feature_tolerance_m(accuracy_pct: f64, range_m: f64) -> f64 {
    (accuracy_pct * range_m / 100.0).max(inches(1.0))
}

/// What the arc rule found in one cluster, for the trace.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ArcTrace {
    /// The cluster (index into the step's clusters).
    pub cluster: usize,
    /// The sensors of the cluster's readings, in chain order.
    pub sensors: Vec<usize>,
    /// Smallest and largest range, metres.
    pub range_min_m: f64,
    /// Largest range, metres.
    pub range_max_m: f64,
    /// The reflector point placed, world frame.
    pub at: Point,
    /// The feature it was filed under (made or moved).
    pub feature: u32,
    /// True when the feature is new.
    pub new_feature: bool,
    /// One plane explains the ranges at least as well as the reflector point (a wall seen
    /// square-on reads so too): the cluster is fitted as well (docs/algorithm.md §8.5).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub also_fitted: bool,
}

/// The arc rule on one cluster (`beams` in chain order): the reflector point and mean range
/// when it is an arc (two or more distinct sensors, ranges pairwise within the ball test),
/// else `None`.
///
/// ```
/// use sonarmap::geometry::{Point, Vec2};
/// use sonarmap::mapping::point_features::{arc_point, Beam};
/// // Two sensors at (±0.1, 0) looking 10° either side of +y, both reading 2.00 and 2.04 m:
/// // |2.00 − 2.04| = 0.04 ≤ 0.03·4.04 = 0.121. The point is 2.02 m from (0, 0) along +y.
/// let b = |x: f64, deg: f64, r: f64| Beam {
///     origin: Point::new(x, 0.0),
///     direction: Vec2::new(deg.to_radians().cos(), deg.to_radians().sin()),
///     range_m: r,
/// };
/// let (at, r) = arc_point(&[b(0.1, 80.0, 2.0), b(-0.1, 100.0, 2.04)], &[0, 1], 3.0).unwrap();
/// assert!((r - 2.02).abs() < 1e-12);
/// assert!(at.x.abs() < 1e-12 && (at.y - 2.02).abs() < 1e-12);
/// // 2.00 and 2.20: 0.20 > 0.03·4.2 = 0.126, no arc.
/// assert!(arc_point(&[b(0.1, 80.0, 2.0), b(-0.1, 100.0, 2.2)], &[0, 1], 3.0).is_none());
/// ```
pub fn arc_point(beams: &[Beam], sensors: &[usize], accuracy_pct: f64) -> Option<(Point, f64)> {
    if beams.len() < 2 {
        return None;
    }
    let mut distinct = sensors.to_vec();
    distinct.sort_unstable();
    distinct.dedup();
    if distinct.len() != sensors.len() {
        return None;
    }
    for (i, a) in beams.iter().enumerate() {
        for b in &beams[i + 1..] {
            if !same_depth(accuracy_pct, a.range_m, b.range_m) {
                return None;
            }
        }
    }
    let dir: Vec2 = beams.iter().map(|b| b.direction).sum();
    let norm = dir.norm();
    if norm < 1e-9 {
        return None;
    }
    let range_m = mean_range_m(beams);
    Some((mean_origin(beams) + dir / norm * range_m, range_m))
}

/// Whether confirmed feature `f` explains `beam`: its distance from the sensor is the range
/// within the tolerance, and it lies within `half_beam_rad` of the axis.
///
/// ```
/// use sonarmap::geometry::{Point, Vec2};
/// use sonarmap::mapping::point_features::{explains, Beam};
/// // A sensor at the origin looking along +x reads 2.00 m. A feature at (1.97, 0.30): distance
/// // 1.9927 (|1.9927 − 2| = 0.0073 ≤ 0.06), 8.66° off the axis (≤ 12.5°): explained.
/// let beam = Beam { origin: Point::origin(), direction: Vec2::new(1.0, 0.0), range_m: 2.0 };
/// let half = 12.5f64.to_radians();
/// assert!(explains(&Point::new(1.97, 0.30), &beam, 3.0, half));
/// // At (1.90, 0.60): 15.8° off the axis.
/// assert!(!explains(&Point::new(1.90, 0.60), &beam, 3.0, half));
/// // At (1.80, 0.0): 0.20 short of the range.
/// assert!(!explains(&Point::new(1.80, 0.0), &beam, 3.0, half));
/// ```
pub fn explains(at: &Point, beam: &Beam, accuracy_pct: f64, half_beam_rad: f64) -> bool {
    explains_round(at, 0.0, beam, accuracy_pct, half_beam_rad)
}

/// The echo a rounded reflector (a pillar, docs/algorithm.md §8.14) returns to a beam: its
/// range and how the range moves with the reflector's centre and radius.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RoundEcho {
    /// The range the beam reads, metres.
    pub range_m: f64,
    /// The range's gradient in the centre, metres per metre.
    pub d_range_d_centre: Vec2,
    /// The range's derivative in the radius.
    pub d_range_d_radius: f64,
}

impl RoundEcho {
    /// The echo along the ray through the centre, `v` from the sensor (`d` its length):
    /// `d − radius_m`, the surface's normal.
    pub fn through_centre(v: Vec2, d: f64, radius_m: f64) -> Self {
        RoundEcho {
            range_m: d - radius_m,
            d_range_d_centre: v / d,
            d_range_d_radius: -1.0,
        }
    }
}

/// The echo `beam`'s sonar hears from a pillar of centre `at` and radius `radius_m` (0 for a
/// point), as for a plane (§8.10): along the ray through the centre, the surface's normal,
/// `|at − o| − radius_m`, when the centre lies inside the cone; else along the cone's edge
/// nearer the centre, where that edge meets the surface within [`MAX_INCIDENCE_RAD`] of its
/// normal (a pillar whose centre lies just outside a wide beam still fills its edge). `None`
/// when the sensor is inside the pillar, or the centre lies outside the cone and the radius is
/// not positive (a point), the edge misses the circle, meets it beyond that incidence, or
/// points away from it.
///
/// The edge ray `e` meets the circle at `t = e·v − s`, where `v = at − o` and
/// `s = √(r² − |v|² + (e·v)²)`; the incidence there is `acos(s / r)`.
pub fn round_echo(at: &Point, radius_m: f64, beam: &Beam, half: HalfCone) -> Option<RoundEcho> {
    let v = at - beam.origin;
    let d = v.norm();
    if d <= radius_m {
        return None;
    }
    if v.dot(&beam.direction) / d >= half.cos {
        return Some(RoundEcho::through_centre(v, d, radius_m));
    }
    // A point (or, in a fit's steps, a negative radius) gives no echo outside the cone.
    if radius_m.is_nan() || radius_m <= 0.0 {
        return None;
    }
    let (ray, _) = echo_ray(beam, &(v / d), half);
    let along = ray.dot(&v);
    let s2 = radius_m * radius_m - (d * d - along * along);
    let s_min = radius_m * MAX_INCIDENCE_RAD.cos();
    if along.is_nan() || s2.is_nan() || along <= 0.0 || s2 < s_min * s_min {
        return None;
    }
    let s = s2.sqrt();
    Some(RoundEcho {
        range_m: along - s,
        d_range_d_centre: ray + (v - ray * along) / s,
        d_range_d_radius: -radius_m / s,
    })
}

/// Whether the confirmed rounded reflector of centre `at` and radius `radius_m` (a pillar,
/// docs/algorithm.md §8.14; 0 for a point, [`explains`]) explains `beam`: the range of its echo
/// ([`round_echo`]) is the reading's within the tolerance. When the centre lies inside the beam
/// that is `|at − o| − radius_m`; a point outside it explains nothing.
///
/// ```
/// use sonarmap::geometry::{Point, Vec2};
/// use sonarmap::mapping::point_features::{explains_round, Beam};
/// // A sensor at the origin looking along +x reads 1.80 m. A pillar of radius 0.2 m centred at
/// // (2, 0): its surface is 2 − 0.2 = 1.8 m away: explained.
/// let beam = Beam { origin: Point::origin(), direction: Vec2::new(1.0, 0.0), range_m: 1.8 };
/// let half = 12.5f64.to_radians();
/// assert!(explains_round(&Point::new(2.0, 0.0), 0.2, &beam, 3.0, half));
/// // A point at its centre, 2 m away: |2 − 1.8| = 0.2 > 0.054 (3 % of 1.8), not explained.
/// assert!(!explains_round(&Point::new(2.0, 0.0), 0.0, &beam, 3.0, half));
/// ```
pub fn explains_round(
    at: &Point,
    radius_m: f64,
    beam: &Beam,
    accuracy_pct: f64,
    half_beam_rad: f64,
) -> bool {
    round_residual_m(
        at,
        radius_m,
        beam,
        accuracy_pct,
        HalfCone::new(half_beam_rad),
    )
    .is_some()
}

/// The range of the echo `beam`'s sonar hears from the rounded reflector of centre `at` and
/// radius `radius_m` ([`round_echo`]) less the reading's, metres, when that lies within the
/// reading's tolerance ([`feature_tolerance_m`]): the reflector explains the reading.
pub fn round_residual_m(
    at: &Point,
    radius_m: f64,
    beam: &Beam,
    accuracy_pct: f64,
    half: HalfCone,
) -> Option<f64> {
    let residual_m = round_echo(at, radius_m, beam, half)?.range_m - beam.range_m;
    (residual_m.abs() <= feature_tolerance_m(accuracy_pct, beam.range_m)).then_some(residual_m)
}

/// Radius within which an arc's point joins an existing feature rather than making a new one:
/// the tolerance plus 5° of arc at range `range_m` (the beams' overlap places the point no
/// better than that across the axis).
pub fn merge_radius_m(accuracy_pct: f64, range_m: f64) -> f64 {
    feature_tolerance_m(accuracy_pct, range_m) + range_m * 5f64.to_radians().tan()
}

/// The kind of a reflector at `at` seen from `sensor`: a corner when two map segments end near
/// it at more than 30° to each other and the sensor looks into the angle they make (concave),
/// an edge otherwise (a convex junction or a free wall end). Only the segments the grid files
/// near `at` are read.
pub fn classify(map: &Map, at: &Point, sensor: &Point, radius_m: f64) -> FeatureKind {
    let mut near = Vec::new();
    map.segments_near_into(at, radius_m, &mut near);
    near.sort_unstable();
    let arms: Vec<Vec2> = near
        .iter()
        .filter_map(|&id| map.segment(id))
        .filter_map(|s| {
            let (da, db) = ((s.a.point - at).norm(), (s.b.point - at).norm());
            let (close, far) = if da <= db {
                (da, s.b.point)
            } else {
                (db, s.a.point)
            };
            let arm = far - at;
            (close <= radius_m && arm.norm() > radius_m).then(|| arm.normalize())
        })
        .collect();
    let view = sensor - at;
    if view.norm() <= 0.0 {
        return FeatureKind::Edge;
    }
    let view = view.normalize();
    for (i, a) in arms.iter().enumerate() {
        for b in &arms[i + 1..] {
            let between = a.dot(b).clamp(-1.0, 1.0).acos();
            if between < 30f64.to_radians() || between > 150f64.to_radians() {
                continue;
            }
            let (va, vb) = (
                a.dot(&view).clamp(-1.0, 1.0).acos(),
                b.dot(&view).clamp(-1.0, 1.0).acos(),
            );
            if (va + vb - between).abs() < 1e-6 {
                return FeatureKind::Corner;
            }
        }
    }
    FeatureKind::Edge
}

/// Files an arc's point `at` (range `range_m`, seen by `snapshot` from `sensor`): it moves the
/// nearest point feature (not a pillar, §8.14) within [`merge_radius_m`] to the observations'
/// mean, or makes a new one. Returns the feature's id and whether it is new.
pub fn file_arc(
    map: &mut Map,
    at: Point,
    range_m: f64,
    sensor: &Point,
    snapshot: usize,
    accuracy_pct: f64,
) -> (u32, bool) {
    let radius = merge_radius_m(accuracy_pct, range_m);
    // A point joins a point: a pillar's place is its centre, its radius behind its echoes.
    let nearest = nearest_feature_within(map, &at, radius, false);
    let kind = classify(map, &at, sensor, radius);
    match nearest {
        Some(id) => {
            let f = map.feature(id).expect("filed features exist").clone();
            let n = f.observations as f64;
            let moved = PointFeature {
                at: Point::from((f.at.coords * n + at.coords) / (n + 1.0)),
                range_m: f.range_m.min(range_m),
                observations: f.observations + 1,
                baseline_m: f.baseline_m.max((sensor - f.first_seen_from).norm()),
                kind: if kind == FeatureKind::Corner {
                    kind
                } else {
                    f.kind
                },
                ..f
            };
            map.replace_feature(moved, snapshot);
            (id, false)
        }
        None => {
            let id = map.push_feature(PointFeature::seen_once(
                kind, at, range_m, *sensor, snapshot,
            ));
            (id, true)
        }
    }
}

/// The feature nearest `at` within `radius_m` of it (the lower id on a tie), among the
/// pillars (§8.14) when `rounded`, else among the points: what an observation of either
/// joins.
pub(crate) fn nearest_feature_within(
    map: &Map,
    at: &Point,
    radius_m: f64,
    rounded: bool,
) -> Option<u32> {
    map.features_near(at, radius_m)
        .into_iter()
        .filter_map(|id| map.feature(id))
        .filter(|f| (f.radius_m > 0.0) == rounded)
        .map(|f| (f.id, (f.at - at).norm()))
        .filter(|(_, d)| *d <= radius_m)
        .min_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)))
        .map(|(id, _)| id)
}

/// The confirmed feature (seen by two snapshots or more) that explains `beam`, if any: the
/// nearest to the range among those the grid files within reach of the beam's point (widened
/// by the largest radius a pillar may have, §8.14).
pub fn explaining_feature(
    map: &Map,
    beam: &Beam,
    accuracy_pct: f64,
    half_beam_rad: f64,
    scratch: &mut Vec<u32>,
) -> Option<u32> {
    if map.features.is_empty() {
        return None;
    }
    let (tip, reach) = feature_reach(beam, accuracy_pct, half_beam_rad);
    map.features_near_into(&tip, reach + MAX_ROUND_RADIUS_M, scratch);
    let near = scratch
        .iter()
        .filter_map(|&id| map.feature(id))
        .filter(|f| f.is_confirmed())
        .map(|f| (f.id, f.at, f.radius_m));
    nearest_explaining(near, beam, accuracy_pct, half_beam_rad)
}

/// [`explaining_feature`] among `confirmed`, the map's confirmed features (id, place and
/// radius, in any order), each tested within the box where a feature of its radius can explain
/// the reading: the same feature, without the grid, for a map with few confirmed features.
pub fn explaining_feature_among(
    confirmed: &[(u32, Point, f64)],
    beam: &Beam,
    accuracy_pct: f64,
    half_beam_rad: f64,
) -> Option<u32> {
    let (tip, reach) = feature_reach(beam, accuracy_pct, half_beam_rad);
    // A pillar's centre lies its radius further out than a point would.
    let in_box = |at: &Point, radius_m: f64| {
        let r = reach + radius_m;
        !r.is_finite() || ((at.x - tip.x).abs() <= r && (at.y - tip.y).abs() <= r)
    };
    let near = confirmed
        .iter()
        .filter(|(_, at, r)| in_box(at, *r))
        .copied();
    nearest_explaining(near, beam, accuracy_pct, half_beam_rad)
}

/// The point a beam's reading puts on its axis, and how far from it a point feature that
/// explains the reading can lie (the cone's half-width at the range, and the tolerance), metres;
/// a pillar's centre lies its radius further.
fn feature_reach(beam: &Beam, accuracy_pct: f64, half_beam_rad: f64) -> (Point, f64) {
    let tip = beam.axis_point();
    let reach = beam.range_m * half_beam_rad + feature_tolerance_m(accuracy_pct, beam.range_m);
    (tip, reach)
}

/// Of the features `near` (id, place and radius), the one that explains `beam`
/// ([`explains_round`]) whose echo's range ([`round_echo`]) is nearest the reading's (the lower
/// id on a tie).
fn nearest_explaining(
    near: impl Iterator<Item = (u32, Point, f64)>,
    beam: &Beam,
    accuracy_pct: f64,
    half_beam_rad: f64,
) -> Option<u32> {
    let half = HalfCone::new(half_beam_rad);
    near.filter_map(|(id, at, r)| {
        round_residual_m(&at, r, beam, accuracy_pct, half).map(|residual_m| (id, residual_m.abs()))
    })
    .min_by(|(ia, a), (ib, b)| a.total_cmp(b).then(ia.cmp(ib)))
    .map(|(id, _)| id)
}

/// Readings of a reflector of radius `radius_m` (0: a point) centred at `centre`, from
/// sensors on y = 0 at `xs`, each looking at the centre: the tests' echoes of a corner or a
/// pillar.
#[cfg(test)]
pub(crate) fn beams_at_reflector(centre: Point, radius_m: f64, xs: &[f64]) -> Vec<Beam> {
    xs.iter()
        .map(|&x| {
            let v: Vec2 = centre - Point::new(x, 0.0);
            Beam {
                origin: Point::new(x, 0.0),
                direction: v / v.norm(),
                range_m: v.norm() - radius_m,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mapping::map::{test_wall, Segment};

    fn wall(id: u32, a: (f64, f64), b: (f64, f64)) -> Segment {
        test_wall(id, a, b, 2.0)
    }

    /// A sensor at the origin looking along +x (half-beam 12.5°) and a pillar of radius 0.3 m
    /// whose centre stands 1.5 m away, `off_deg` from the axis.
    fn pillar_echo(off_deg: f64) -> Option<RoundEcho> {
        let beam = Beam {
            origin: Point::origin(),
            direction: Vec2::new(1.0, 0.0),
            range_m: 1.2,
        };
        let at = Point::from(crate::geometry::unit(off_deg.to_radians()) * 1.5);
        round_echo(&at, 0.3, &beam, HalfCone::new(12.5f64.to_radians()))
    }

    #[test]
    fn a_pillar_inside_the_beam_echoes_along_the_ray_through_its_centre() {
        // 10° off the axis, inside the cone: 1.5 − 0.3 = 1.2 m.
        let echo = pillar_echo(10.0).unwrap();
        assert!((echo.range_m - 1.2).abs() < 1e-12);
        assert_eq!(echo.d_range_d_radius, -1.0);
    }

    #[test]
    fn a_pillar_just_outside_the_beam_echoes_along_the_cone_edge() {
        // 15° off the axis: the edge at 12.5° passes 1.5 sin 2.5° = 0.065429 m from the centre,
        // 1.5 cos 2.5° = 1.498572 m along, and meets the surface √(0.09 − 0.065429²) = 0.292778
        // m short of that: 1.205794 m, 5.8 mm beyond the 1.2 m of the ray through the centre.
        // The incidence there is acos(0.292778 / 0.3) = 12.6°.
        let echo = pillar_echo(15.0).unwrap();
        assert!((echo.range_m - 1.205794).abs() < 1e-6, "{echo:?}");
        assert!((echo.d_range_d_radius - -0.3 / 0.292778).abs() < 1e-5);
        // A reading of 1.2058 m is explained; the centre's own ray would have refused it.
        let beam = Beam {
            origin: Point::origin(),
            direction: Vec2::new(1.0, 0.0),
            range_m: 1.2058,
        };
        let at = Point::from(crate::geometry::unit(15f64.to_radians()) * 1.5);
        assert!(explains_round(&at, 0.3, &beam, 1.0, 12.5f64.to_radians()));
        // A point there (radius 0) echoes nothing: the edge cannot meet it.
        let half = HalfCone::new(12.5f64.to_radians());
        assert_eq!(round_echo(&at, 0.0, &beam, half), None);
    }

    #[test]
    fn a_pillar_met_by_the_cone_edge_beyond_the_incidence_limit_echoes_nothing() {
        // The edge meets the surface within 60° of its normal while it passes within
        // 0.3 sin 60° = 0.2598 m of the centre: 1.5 sin(Δ) ≤ 0.2598, Δ ≤ 9.97° past the edge.
        // At 22° (Δ = 9.5°) it echoes; at 23.5° (Δ = 11°, 0.2862 m: it still grazes the
        // surface) it does not; at 35° (Δ = 22.5°, 0.574 m) the edge misses.
        assert!(pillar_echo(22.0).is_some());
        assert_eq!(pillar_echo(23.5), None);
        assert_eq!(pillar_echo(35.0), None);
    }

    proptest::proptest! {
        /// The gradient [`round_echo`] gives is the range's: finite differences agree with it.
        #[test]
        fn the_echo_gradient_is_the_ranges(
            off_deg in -22.0..22.0f64,
            distance_m in 0.8..4.0f64,
            radius_m in 0.06..0.5f64,
        ) {
            let beam = Beam { origin: Point::origin(), direction: Vec2::new(1.0, 0.0), range_m: 1.0 };
            let half = HalfCone::new(12.5f64.to_radians());
            let at = Point::from(crate::geometry::unit(off_deg.to_radians()) * distance_m);
            let Some(echo) = round_echo(&at, radius_m, &beam, half) else { return Ok(()) };
            let h = 1e-7;
            let moved = |dx: f64, dy: f64, dr: f64| {
                round_echo(&(at + Vec2::new(dx, dy)), radius_m + dr, &beam, half).map(|e| e.range_m)
            };
            // Skip the seams (the cone's edge, the incidence limit), where one side of the
            // difference takes the other branch.
            let (Some(x), Some(y), Some(r)) = (moved(h, 0.0, 0.0), moved(0.0, h, 0.0), moved(0.0, 0.0, h)) else {
                return Ok(());
            };
            if (off_deg.abs() - 12.5).abs() < 1e-3 {
                return Ok(());
            }
            proptest::prop_assert!(((x - echo.range_m) / h - echo.d_range_d_centre.x).abs() < 1e-4);
            proptest::prop_assert!(((y - echo.range_m) / h - echo.d_range_d_centre.y).abs() < 1e-4);
            proptest::prop_assert!(((r - echo.range_m) / h - echo.d_range_d_radius).abs() < 1e-4);
        }
    }

    #[test]
    fn a_junction_seen_from_inside_its_angle_is_a_corner_from_outside_an_edge() {
        // Walls from (0, 0) to (3, 0) and to (0, 3): the sensor at (1, 1) looks into the 90°
        // angle (45° to each arm: 45 + 45 = 90), the one at (-1, -1) from outside (135 + 135).
        let map = Map::from_segments(vec![
            wall(0, (0.0, 0.0), (3.0, 0.0)),
            wall(1, (0.0, 3.0), (0.0, 0.0)),
        ]);
        let at = Point::new(0.02, 0.02);
        assert_eq!(
            classify(&map, &at, &Point::new(1.0, 1.0), 0.2),
            FeatureKind::Corner
        );
        assert_eq!(
            classify(&map, &at, &Point::new(-1.0, -1.0), 0.2),
            FeatureKind::Edge
        );
        // One wall ending there (a door jamb): an edge from anywhere.
        let jamb = Map::from_segments(vec![wall(0, (0.0, 0.0), (3.0, 0.0))]);
        assert_eq!(
            classify(&jamb, &at, &Point::new(1.0, 1.0), 0.2),
            FeatureKind::Edge
        );
    }

    #[test]
    fn arcs_within_the_merge_radius_move_one_feature_to_their_mean() {
        // At 2 m: tolerance 0.06 m, merge radius 0.06 + 2·tan 5° = 0.235 m.
        assert!((merge_radius_m(3.0, 2.0) - (0.06 + 2.0 * 5f64.to_radians().tan())).abs() < 1e-12);
        let mut map = Map::default();
        let sensor = Point::new(0.0, -2.0);
        let (f0, new0) = file_arc(&mut map, Point::new(0.0, 0.0), 2.0, &sensor, 3, 3.0);
        let (f1, new1) = file_arc(&mut map, Point::new(0.1, 0.0), 1.9, &sensor, 4, 3.0);
        assert!(new0 && !new1 && f0 == f1);
        let f = map.feature(f0).unwrap();
        assert!((f.at.x - 0.05).abs() < 1e-12 && f.at.y.abs() < 1e-12);
        assert_eq!(
            (f.observations, f.created, f.updated.clone()),
            (2, 3, vec![4])
        );
        assert!((f.range_m - 1.9).abs() < 1e-12);
        // 0.3 m away: a second feature.
        let (f2, new2) = file_arc(&mut map, Point::new(0.35, 0.0), 2.0, &sensor, 5, 3.0);
        assert!(new2 && f2 != f0);
        map.rebuild_index();
        assert!(map.check_invariants(0).is_ok());
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(64))]
        /// Searching the confirmed features one by one finds the feature the grid finds, for
        /// beams among crowded features (some confirmed), some at the edges of their reach.
        #[test]
        fn the_direct_search_finds_the_feature_the_grid_finds(
            features in proptest::collection::vec((0.0..4.0f64, 0.0..4.0f64, proptest::bool::ANY), 1..40),
            beams in proptest::collection::vec((0.0..4.0f64, 0.0..4.0f64, 0.0..std::f64::consts::TAU, 0.2..4.0f64), 1..20),
        ) {
            let mut map = Map::default();
            for &(x, y, confirmed) in &features {
                let id = map.push_feature(PointFeature::seen_once(FeatureKind::Corner, Point::new(x, y), 1.0, Point::origin(), 0));
                if confirmed {
                    map.features[id as usize].baseline_m = 1.0;
                }
                // Some of them rounded (a pillar's centre behind its surface, §8.14).
                if x > 2.0 {
                    map.features[id as usize].radius_m = 0.3;
                }
            }
            let listed: Vec<(u32, Point, f64)> =
                map.confirmed_features().map(|f| (f.id, f.at, f.radius_m)).collect();
            let half = 12.5f64.to_radians();
            let mut scratch = Vec::new();
            for &(x, y, dir, range_m) in &beams {
                let origin = Point::new(x, y);
                let direction = Vec2::new(dir.cos(), dir.sin());
                // Aimed at a feature now and then, so that some beams are explained.
                let beam = Beam { origin, direction, range_m };
                let aimed = features.first().map(|&(fx, fy, _)| {
                    let v = Point::new(fx, fy) - origin;
                    let surface_m = v.norm() - map.features[0].radius_m;
                    Beam { origin, direction: v.normalize(), range_m: surface_m * (1.0 + 0.02 * dir.sin()) }
                });
                for beam in std::iter::once(beam).chain(aimed.filter(|b| b.range_m > 0.05)) {
                    proptest::prop_assert_eq!(
                        explaining_feature_among(&listed, &beam, 3.0, half),
                        explaining_feature(&map, &beam, 3.0, half, &mut scratch)
                    );
                }
            }
        }
    }

    #[test]
    fn only_a_confirmed_feature_explains_a_reading() {
        let mut map = Map::default();
        let sensor = Point::new(0.0, 0.0);
        let beam = Beam {
            origin: sensor,
            direction: Vec2::new(1.0, 0.0),
            range_m: 2.0,
        };
        let half = 12.5f64.to_radians();
        let mut scratch = Vec::new();
        let explaining =
            |map: &Map, scratch: &mut Vec<u32>| explaining_feature(map, &beam, 3.0, half, scratch);
        let (id, _) = file_arc(&mut map, Point::new(2.0, 0.1), 2.0, &sensor, 0, 3.0);
        assert_eq!(explaining(&map, &mut scratch), None);
        // Seen again from the same place (a lap driven back): still not confirmed.
        file_arc(&mut map, Point::new(2.0, 0.1), 2.0, &sensor, 1, 3.0);
        assert_eq!(explaining(&map, &mut scratch), None);
        // From 0.25 m aside (at least 0.2032 m): confirmed, it explains the reading.
        let aside = Point::new(0.0, 0.25);
        file_arc(&mut map, Point::new(2.0, 0.1), 2.0, &aside, 2, 3.0);
        assert_eq!(explaining(&map, &mut scratch), Some(id));
        assert!((map.feature(id).unwrap().baseline_m - 0.25).abs() < 1e-12);
    }
}
