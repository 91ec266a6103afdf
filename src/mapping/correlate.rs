//! Correlation of new faces with the map (paper §3.3.3, Figure 3; ALGORITHM.md §6).

use super::map::{FaceId, Map, Segment, SegmentKind};
use super::params::Params;
use super::trace::{CorrelationKind, CorrelationTrace, InterpolationReason, Test};
use crate::geometry::{line_angle_between, line_intersection, projection_param, Point};
use std::sync::Arc;

/// Correlates new face `face` with the rest of the map.
///
/// Only end-points within `t_gap` are searched (through the spatial index), so when none is,
/// the trace has no `d_min` (and a `d_min` it has always passes). `d_min` is the smallest
/// distance from an end-point of the face's segments to an end-point of a fitted segment of
/// another face (ties: first new segment, then its end `a` before `b`, then the existing
/// segment's id and end). When `d_min ≤ t_gap`: if the two lines are not parallel
/// (angle `> θ_o`) and their intersection lies within `t_gap` of both closest end-points, both
/// end-points move to the intersection (a corner); otherwise a connecting "interpolated"
/// segment joins them. Either way the face joins the existing segment's object. Moved
/// end-points keep their ranges.
pub fn correlate_face(
    map: &mut Map,
    face: FaceId,
    params: &Params,
    snapshot: usize,
) -> CorrelationTrace {
    let mut trace = CorrelationTrace {
        face,
        new_segment: None,
        existing_segment: None,
        d_min: None,
        angle_rad: None,
        result: CorrelationKind::None,
    };
    let new_ids: Vec<_> = map
        .face(face)
        .map(|f| f.segments.clone())
        .unwrap_or_default();
    let mut best: Option<(f64, usize, usize, usize, usize)> = None; // (d, new idx, new end, existing idx, existing end)
    for &nid in &new_ids {
        let Some(ni) = map.position(nid) else {
            continue;
        };
        let n = &map.segments[ni];
        // Only end-points within t_gap can correlate: look there (the index is a superset).
        let near: Vec<usize> = [n.a.point, n.b.point]
            .iter()
            .flat_map(|p| map.segments_near(p, params.t_gap_m))
            .filter_map(|id| map.position(id))
            .collect::<std::collections::BTreeSet<_>>()
            .into_iter()
            .collect();
        for (ei, e) in near.into_iter().map(|i| (i, &map.segments[i])) {
            if e.face == face || e.kind != SegmentKind::Fitted {
                continue;
            }
            for (nend, np) in [n.a.point, n.b.point].iter().enumerate() {
                for (eend, ep) in [e.a.point, e.b.point].iter().enumerate() {
                    let d = (np - ep).norm();
                    // Beyond t_gap is out of the search, whatever the index returned.
                    if d <= params.t_gap_m && best.is_none_or(|b| d < b.0) {
                        best = Some((d, ni, nend, ei, eend));
                    }
                }
            }
        }
    }
    let Some((d_min, ni, nend, ei, eend)) = best else {
        return trace;
    };
    let test = Test::at_most(d_min, params.t_gap_m);
    trace.d_min = Some(test);
    trace.new_segment = Some((map.segments[ni].id, nend));
    trace.existing_segment = Some((map.segments[ei].id, eend));
    let (n, e) = (&map.segments[ni], &map.segments[ei]);
    let end_point = |s: &Segment, end: usize| if end == 0 { s.a } else { s.b };
    let (np, ep) = (end_point(n, nend), end_point(e, eend));
    let angle = line_angle_between(&(n.b.point - n.a.point), &(e.b.point - e.a.point));
    trace.angle_rad = Some(angle);
    if !test.pass {
        return trace;
    }
    let fixed_end = |s: &Segment, end: usize| if end == 0 { s.b.point } else { s.a.point };
    // Beyond ALGORITHM.md §6: a corner must keep each segment pointing the same way and at
    // least half as long; otherwise the literal rule can collapse a segment onto its other end.
    let keeps_shape = |x: &Point, s: &Segment, end: usize| {
        let fixed = fixed_end(s, end);
        projection_param(x, &fixed, &end_point(s, end).point) >= 0.5
    };
    let intersection = if angle > params.orientation_rad {
        line_intersection(&n.a.point, &n.b.point, &e.a.point, &e.b.point).filter(|x| {
            (x - np.point).norm() <= params.t_gap_m && (x - ep.point).norm() <= params.t_gap_m
        })
    } else {
        None
    };
    let corner = intersection.filter(|x| keeps_shape(x, n, nend) && keeps_shape(x, e, eend));
    let object = e.object;
    let new_object = n.object;
    match corner {
        Some(x) => {
            for (idx, end) in [(ni, nend), (ei, eend)] {
                let s = &map.segments[idx];
                let (mut a, mut b) = (s.a, s.b);
                if end == 0 {
                    a.point = x;
                } else {
                    b.point = x;
                }
                map.set_ends(s.id, a, b);
            }
            trace.result = CorrelationKind::Corner { point: x };
        }
        None => {
            let reason = if angle <= params.orientation_rad {
                InterpolationReason::NearlyParallel
            } else if intersection.is_some() {
                InterpolationReason::CornerWouldCollapse
            } else {
                InterpolationReason::IntersectionTooFar
            };
            let id = map.allocate_segment_id();
            let link_face = map.new_face();
            if let Some(f) = map.face_mut(link_face) {
                f.segments.push(id);
            }
            map.push_segment(Segment {
                id,
                kind: SegmentKind::Interpolated,
                a: ep,
                b: np,
                face: link_face,
                object,
                created: snapshot,
                updated: Vec::new(),
                points: Arc::new(Vec::new()),
            });
            trace.result = CorrelationKind::Interpolated { link: id, reason };
        }
    }
    // The new face's object is fresh: only the face's own segments hold it.
    for id in new_ids {
        if let Some(s) = map.segment_mut(id).filter(|s| s.object == new_object) {
            s.object = object;
        }
    }
    trace
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Point;
    use crate::mapping::map::EndPoint;

    fn add(map: &mut Map, a: (f64, f64), b: (f64, f64)) -> FaceId {
        let face = map.new_face();
        let object = map.allocate_object_id();
        let id = map.allocate_segment_id();
        map.face_mut(face).unwrap().segments.push(id);
        map.push_segment(Segment {
            id,
            kind: SegmentKind::Fitted,
            a: EndPoint {
                point: Point::new(a.0, a.1),
                range_m: 50.0,
            },
            b: EndPoint {
                point: Point::new(b.0, b.1),
                range_m: 60.0,
            },
            face,
            object,
            created: 0,
            updated: vec![],
            points: Arc::new(vec![]),
        });
        face
    }

    #[test]
    fn perpendicular_faces_meet_in_a_corner() {
        let p = Params {
            t_gap_m: 5.0,
            ..Params::paper()
        };
        let mut map = Map::default();
        add(&mut map, (0.0, 0.0), (10.0, 0.0));
        let f = add(&mut map, (12.0, 1.0), (12.0, 10.0));
        let t = correlate_face(&mut map, f, &p, 1);
        assert!((t.d_min.unwrap().value - 5f64.sqrt()).abs() < 1e-12);
        assert_eq!(
            t.result,
            CorrelationKind::Corner {
                point: Point::new(12.0, 0.0)
            }
        );
        assert_eq!(map.segments[0].b.point, Point::new(12.0, 0.0));
        assert_eq!(map.segments[1].a.point, Point::new(12.0, 0.0));
        assert_eq!(
            map.segments[1].a.range_m, 50.0,
            "moved end-points keep their ranges"
        );
        assert_eq!(map.segments[0].object, map.segments[1].object);
    }

    #[test]
    fn a_corner_that_would_collapse_a_segment_becomes_a_link() {
        // The new face starts on the existing wall; its far end is the closest end-point.
        let p = Params {
            t_gap_m: 50.0,
            ..Params::paper()
        };
        let mut map = Map::default();
        add(&mut map, (0.0, 60.0), (0.0, 0.0));
        let f = add(&mut map, (0.0, 15.0), (5.0, 0.0));
        let t = correlate_face(&mut map, f, &p, 1);
        assert_eq!(
            t.result,
            CorrelationKind::Interpolated {
                link: 2,
                reason: InterpolationReason::CornerWouldCollapse
            }
        );
        assert_eq!(map.segments[1].length(), 250f64.sqrt());
    }

    #[test]
    fn parallel_faces_are_joined_by_an_interpolated_link() {
        let p = Params {
            t_gap_m: 5.0,
            ..Params::paper()
        };
        let mut map = Map::default();
        add(&mut map, (0.0, 0.0), (10.0, 0.0));
        let f = add(&mut map, (13.0, 0.5), (20.0, 0.5));
        let t = correlate_face(&mut map, f, &p, 1);
        assert_eq!(
            t.result,
            CorrelationKind::Interpolated {
                link: 2,
                reason: InterpolationReason::NearlyParallel
            }
        );
        let link = map.segment(2).unwrap();
        assert_eq!(link.kind, SegmentKind::Interpolated);
        assert_eq!(
            (link.a.point, link.b.point),
            (Point::new(10.0, 0.0), Point::new(13.0, 0.5))
        );
        // Too far: nothing.
        let far = add(&mut map, (40.0, 0.0), (50.0, 0.0));
        let t = correlate_face(&mut map, far, &p, 1);
        assert_eq!(t.result, CorrelationKind::None);
        assert!(t.d_min.is_none_or(|d| !d.pass));
    }
}
