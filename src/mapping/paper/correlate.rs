//! Correlation of new faces with the map (paper §3.3.3, Figure 3; docs/algorithm.md §6).

use crate::geometry::{line_angle_between, line_intersection, projection_param, Point};
use crate::mapping::model::map::{
    EndPoint, FaceId, Map, ObjectId, Segment, SegmentId, SegmentKind,
};
use crate::mapping::model::params::Params;
use crate::mapping::model::support_list::SupportList;
use crate::mapping::model::trace::{CorrelationKind, CorrelationTrace, InterpolationReason, Test};

/// Correlates new face `face` with the rest of the map (paper §3.3.3, Figure 3;
/// docs/algorithm.md §6).
///
/// `d_min` is the smallest distance from an end-point of one of the face's segments to an
/// end-point of a fitted segment of another face. Only end-points within `t_gap` are searched
/// (through the spatial index), so when none is, the trace has no `d_min` (and a `d_min` it
/// has always passes). Ties go to the earlier new segment in the face, then its end `a` before
/// `b`, then the existing segment with the smaller id, then its end `a` before `b`.
/// - `d_min = 0` (the lines already share an end-point): nothing moves and no segment is made.
/// - Otherwise, if the two lines are not parallel (angle `> θ_o`) and their intersection lies
///   within `t_gap` of both closest end-points, both end-points move to the intersection (a
///   corner; moved end-points keep their ranges). With `corner_guard` (an extension, §8) a
///   corner that would turn a line round or shorten it below half its length is refused.
/// - Otherwise a connecting "interpolated" segment joins the two end-points.
///
/// In every case the face joins the existing segment's object.
///
/// ```
/// use sonarmap::geometry::Point;
/// use sonarmap::mapping::paper::correlate::correlate_face;
/// use sonarmap::mapping::model::trace::CorrelationKind;
/// use sonarmap::mapping::{EndPoint, Map, Params, Segment, SegmentKind};
/// use std::sync::Arc;
/// let end = |x: f64, y: f64| EndPoint { point: Point::new(x, y), range_m: 1.0 };
/// let segment = |id: u32, a: EndPoint, b: EndPoint| Segment {
///     id, kind: SegmentKind::Fitted, a, b, face: id, object: id, created: 0,
///     updated: vec![], points: vec![].into(),
/// };
/// // A wall along y = 0 to x = 10, a new face from (12, 1) up to (12, 10): d_min = √5 ≤ t_gap,
/// // the lines cross at 90° > θ_o, and (12, 0) is within t_gap of both ends: a corner there.
/// let mut map = Map::from_segments(vec![
///     segment(0, end(0.0, 0.0), end(10.0, 0.0)),
///     segment(1, end(12.0, 1.0), end(12.0, 10.0)),
/// ]);
/// let params = Params { t_gap_m: 5.0, ..Params::paper() };
/// let trace = correlate_face(&mut map, 1, &params, 1);
/// assert!((trace.d_min.unwrap().value - 5f64.sqrt()).abs() < 1e-12);
/// assert_eq!(trace.result, CorrelationKind::Corner { point: Point::new(12.0, 0.0) });
/// assert_eq!(map.segments[0].b.point, Point::new(12.0, 0.0));
/// ```
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
        .map(|f| f.segments.to_vec())
        .unwrap_or_default();
    let Some(closest) = closest_pair(map, face, &new_ids, params.t_gap_m) else {
        return trace;
    };
    let ClosestPair {
        distance_m: d_min,
        new_position: ni,
        new_end: nend,
        existing_position: ei,
        existing_end: eend,
        ..
    } = closest;
    let test = Test::at_most(d_min, params.t_gap_m);
    trace.d_min = Some(test);
    trace.new_segment = Some((map.segments[ni].id, nend));
    trace.existing_segment = Some((map.segments[ei].id, eend));
    let (n, e) = (&map.segments[ni], &map.segments[ei]);
    let (np, ep) = (end_point(n, nend), end_point(e, eend));
    let angle = line_angle_between(&(n.b.point - n.a.point), &(e.b.point - e.a.point));
    trace.angle_rad = Some(angle);
    if !test.pass {
        return trace;
    }
    let object = e.object;
    let new_object = n.object;
    if d_min == 0.0 {
        trace.result = CorrelationKind::Shared { point: np.point };
        join_objects(map, &new_ids, new_object, object);
        return trace;
    }
    let intersection = (angle > params.orientation_rad)
        .then(|| line_intersection(&n.a.point, &n.b.point, &e.a.point, &e.b.point))
        .flatten()
        .filter(|x| {
            (x - np.point).norm() <= params.t_gap_m && (x - ep.point).norm() <= params.t_gap_m
        });
    let corner =
        intersection.filter(|x| keeps_shape(params, x, n, nend) && keeps_shape(params, x, e, eend));
    trace.result = match corner {
        Some(x) => {
            meet_at_corner(map, [(ni, nend), (ei, eend)], x);
            CorrelationKind::Corner { point: x }
        }
        None => {
            let reason = if angle <= params.orientation_rad {
                InterpolationReason::NearlyParallel
            } else if intersection.is_some() {
                InterpolationReason::CornerWouldCollapse
            } else {
                InterpolationReason::IntersectionTooFar
            };
            let link = add_link(map, [ep, np], [e.id, n.id], object, snapshot);
            CorrelationKind::Interpolated { link, reason }
        }
    };
    join_objects(map, &new_ids, new_object, object);
    trace
}

/// End `end` (0 for `a`, 1 for `b`) of `s`.
fn end_point(s: &Segment, end: usize) -> EndPoint {
    if end == 0 {
        s.a
    } else {
        s.b
    }
}

/// `corner_guard` (§8): whether moving end `end` of `s` to `x` keeps the segment pointing the
/// same way and at least half as long; otherwise the literal rule can collapse a segment onto
/// its other end. Always true without the guard.
fn keeps_shape(params: &Params, x: &Point, s: &Segment, end: usize) -> bool {
    let fixed = end_point(s, 1 - end).point;
    !params.corner_guard || projection_param(x, &fixed, &end_point(s, end).point) >= 0.5
}

/// A corner: the given ends (position in `map.segments`, 0 for `a`, 1 for `b`) move to `x`.
fn meet_at_corner(map: &mut Map, ends: [(usize, usize); 2], x: Point) {
    for (idx, end) in ends {
        let s = &map.segments[idx];
        let (mut a, mut b) = (s.a, s.b);
        if end == 0 {
            a.point = x;
        } else {
            b.point = x;
        }
        map.set_ends(s.id, a, b);
    }
}

/// A connecting segment from `ends[0]` to `ends[1]`, of a face of its own and `object`, that
/// joins the segments `joins`. Returns its id.
fn add_link(
    map: &mut Map,
    ends: [EndPoint; 2],
    joins: [SegmentId; 2],
    object: ObjectId,
    snapshot: usize,
) -> SegmentId {
    let id = map.allocate_segment_id();
    let link_face = map.new_face();
    if let Some(f) = map.face_mut(link_face) {
        f.segments.push(id);
    }
    map.push_segment(Segment {
        id,
        kind: SegmentKind::Interpolated,
        a: ends[0],
        b: ends[1],
        face: link_face,
        object,
        created: snapshot,
        updated: Vec::new(),
        points: SupportList::default(),
    });
    map.note_link(id, joins);
    id
}

/// The closest pair of end-points of [`correlate_face`]: positions in `map.segments`, ends
/// 0 (`a`) or 1 (`b`).
#[derive(Clone, Copy, Debug, PartialEq)]
struct ClosestPair {
    distance_m: f64,
    /// Place of the new segment in its face.
    face_order: usize,
    new_position: usize,
    new_end: usize,
    existing_id: SegmentId,
    existing_position: usize,
    existing_end: usize,
}

impl ClosestPair {
    /// True when `self` wins over `other`: nearer, then the tie order of §6.
    fn precedes(&self, other: &ClosestPair) -> bool {
        let ties = |p: &ClosestPair| (p.face_order, p.new_end, p.existing_id, p.existing_end);
        self.distance_m
            .total_cmp(&other.distance_m)
            .then(ties(self).cmp(&ties(other)))
            .is_lt()
    }
}

/// The closest pair within `t_gap_m` between an end-point of the segments `new_ids` (of
/// `face`, in face order) and an end-point of a fitted segment of another face. Ties: the
/// earlier new segment, its end `a` before `b`, the existing segment with the smaller id, its
/// end `a` before `b`.
fn closest_pair(
    map: &Map,
    face: FaceId,
    new_ids: &[SegmentId],
    t_gap_m: f64,
) -> Option<ClosestPair> {
    let mut best: Option<ClosestPair> = None;
    for (face_order, &nid) in new_ids.iter().enumerate() {
        let Some(ni) = map.position(nid) else {
            continue;
        };
        let n = &map.segments[ni];
        for (new_end, np) in [n.a.point, n.b.point].iter().enumerate() {
            // Only end-points within t_gap can correlate: look there (the index is a superset),
            // reading what the index keeps of each segment (a `paper` map piles thousands of
            // segments near a wall's ends; fetching each one was a tenth of a catch-up).
            map.visit_segments_along(np, np, t_gap_m, |existing_id, e| {
                if e.face == face || !e.fitted {
                    return;
                }
                for (existing_end, ep) in [e.a.point, e.b.point].iter().enumerate() {
                    let pair = ClosestPair {
                        distance_m: (np - ep).norm(),
                        face_order,
                        new_position: ni,
                        new_end,
                        existing_id,
                        existing_position: usize::MAX,
                        existing_end,
                    };
                    // Beyond t_gap is out of the search, whatever the index returned.
                    if pair.distance_m <= t_gap_m && best.is_none_or(|b| pair.precedes(&b)) {
                        best = Some(pair);
                    }
                }
            });
        }
    }
    // The pairs are ordered by distance and ids, not by where the index listed them.
    let mut best = best?;
    best.existing_position = map.position(best.existing_id)?;
    Some(best)
}

/// Moves the face's segments from their fresh object `new_object` to `object` (only the
/// face's own segments hold a new face's object).
fn join_objects(map: &mut Map, new_ids: &[SegmentId], new_object: ObjectId, object: ObjectId) {
    for &id in new_ids {
        if let Some(s) = map.segment_mut(id).filter(|s| s.object == new_object) {
            s.object = object;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Point;
    use crate::mapping::model::map::EndPoint;

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
            points: vec![].into(),
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
    fn with_the_corner_guard_a_corner_that_would_collapse_a_segment_becomes_a_link() {
        // The new face starts on the existing wall; its far end is the closest end-point.
        let p = Params {
            t_gap_m: 50.0,
            corner_guard: true,
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
    fn the_paper_makes_the_corner_even_when_it_collapses_a_segment() {
        // Same scene without the guard: d_min = |(5,0) − (0,0)| = 5 ≤ 50, angle atan(5/15) =
        // 18.4° > 15°, the lines meet at (0, 15), √250 from (5, 0) and 15 from (0, 0): a
        // corner there, which moves the new segment's b onto its a (length 0).
        let p = Params {
            t_gap_m: 50.0,
            ..Params::paper()
        };
        let mut map = Map::default();
        add(&mut map, (0.0, 60.0), (0.0, 0.0));
        let f = add(&mut map, (0.0, 15.0), (5.0, 0.0));
        let t = correlate_face(&mut map, f, &p, 1);
        assert_eq!(t.d_min.unwrap().value, 5.0);
        assert_eq!(t.new_segment, Some((1, 1)));
        assert_eq!(t.existing_segment, Some((0, 1)));
        let CorrelationKind::Corner { point } = t.result else {
            panic!("expected a corner, got {:?}", t.result);
        };
        assert!((point - Point::new(0.0, 15.0)).norm() < 1e-12);
        assert!(
            map.segments[1].length() < 1e-12,
            "the new segment collapsed"
        );
        assert!((map.segments[0].b.point - Point::new(0.0, 15.0)).norm() < 1e-12);
        assert_eq!(map.segments.len(), 2, "no link");
    }

    #[test]
    fn a_shared_end_point_moves_nothing_and_makes_no_link() {
        // d_min = 0, colinear (today's engine made a zero-length "nearly parallel" link) and
        // perpendicular (a corner at the shared point itself).
        for far_end in [(20.0, 0.0), (10.0, 10.0)] {
            let p = Params {
                t_gap_m: 5.0,
                ..Params::paper()
            };
            let mut map = Map::default();
            add(&mut map, (0.0, 0.0), (10.0, 0.0));
            let f = add(&mut map, (10.0, 0.0), far_end);
            let before: Vec<Segment> = map.segments.iter().map(|s| (**s).clone()).collect();
            let t = correlate_face(&mut map, f, &p, 1);
            assert_eq!(t.d_min.unwrap().value, 0.0);
            assert_eq!(
                t.result,
                CorrelationKind::Shared {
                    point: Point::new(10.0, 0.0)
                }
            );
            assert_eq!(map.segments.len(), 2, "no connecting segment");
            for (s, b) in map.segments.iter().zip(&before) {
                assert_eq!((s.a, s.b), (b.a, b.b), "nothing moves");
            }
            assert_eq!(map.segments[0].object, map.segments[1].object, "one object");
        }
    }

    #[test]
    fn ties_for_the_closest_pair_take_the_new_end_a_first_then_the_smaller_id() {
        // New line (0,0)–(10,0). Segment 0 ends 3 from its b, at (10, 3); segment 1 ends 3 from
        // its a, at (0, 3). End a comes first although segment 0 has the smaller id.
        let p = Params {
            t_gap_m: 5.0,
            ..Params::paper()
        };
        let mut map = Map::default();
        add(&mut map, (10.0, 3.0), (10.0, 20.0));
        add(&mut map, (0.0, 3.0), (0.0, 20.0));
        let f = add(&mut map, (0.0, 0.0), (10.0, 0.0));
        let t = correlate_face(&mut map, f, &p, 1);
        assert_eq!(t.new_segment, Some((2, 0)));
        assert_eq!(t.existing_segment, Some((1, 0)));
        // The lines meet at (0, 0), within t_gap of both: a corner, segment 1's a moves there.
        assert_eq!(
            t.result,
            CorrelationKind::Corner {
                point: Point::new(0.0, 0.0)
            }
        );
        assert_eq!(map.segments[1].a.point, Point::new(0.0, 0.0));
        assert_eq!(map.segments[0].a.point, Point::new(10.0, 3.0), "untouched");

        // Same end of the new line at the same distance from two segments: the smaller id.
        let mut map = Map::default();
        add(&mut map, (-3.0, 0.0), (-3.0, -20.0));
        add(&mut map, (0.0, 3.0), (0.0, 20.0));
        // Segment 2 touches the same point as segment 1 from the other side (id order only).
        let f = add(&mut map, (0.0, 0.0), (0.0, -1.0));
        let t = correlate_face(&mut map, f, &p, 1);
        assert_eq!(t.new_segment, Some((2, 0)));
        assert_eq!(t.existing_segment, Some((0, 0)), "3 = 3: the smaller id");
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
