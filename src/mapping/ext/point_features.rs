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

use crate::geometry::{Point, Vec2};
use crate::mapping::ext::beam_geometry::HalfCone;
use crate::mapping::ext::beam_geometry::{
    feature_tolerance_m, mean_origin, mean_range_m, round_residual_m,
};
use crate::mapping::ext::constant_depth::same_depth;
use crate::mapping::model::beam::Beam;
use crate::mapping::model::features::MAX_ROUND_RADIUS_M;
use crate::mapping::model::map::{FeatureKind, Map, PointFeature};

/// The arc rule on one cluster (`beams` in chain order): the reflector point and mean range
/// when it is an arc (two or more distinct sensors, ranges pairwise within the ball test),
/// else `None`.
///
/// ```
/// use sonarmap::geometry::{Point, Vec2};
/// use sonarmap::mapping::ext::point_features::arc_point;
/// use sonarmap::mapping::model::beam::Beam;
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
/// use sonarmap::mapping::ext::point_features::explains;
/// use sonarmap::mapping::model::beam::Beam;
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

/// Whether the confirmed rounded reflector of centre `at` and radius `radius_m` (a pillar,
/// docs/algorithm.md §8.14; 0 for a point, [`explains`]) explains `beam`: the range of its echo
/// ([`round_echo`](super::beam_geometry::round_echo)) is the reading's within the tolerance. When the centre lies inside the beam
/// that is `|at − o| − radius_m`; a point outside it explains nothing.
///
/// ```
/// use sonarmap::geometry::{Point, Vec2};
/// use sonarmap::mapping::ext::point_features::explains_round;
/// use sonarmap::mapping::model::beam::Beam;
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
/// ([`explains_round`]) whose echo's range ([`round_echo`](super::beam_geometry::round_echo)) is nearest the reading's (the lower
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
mod tests;
