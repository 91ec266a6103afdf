//! Merging duplicates (`merge_duplicates`, a long-run bound beyond the paper, docs/algorithm.md
//! §8.3: off in `paper`, on in `extended`, traced when it acts).
//!
//! The paper fuses a *new* segment with the map (§3.3.2) but never map segments with each
//! other: it ran two snapshots. Over a long run an update extends a segment over its
//! neighbours (the MATCH result covers all four projections) and the post-update refit leaves
//! pieces behind, so a wall seen a thousand times collects overlapping copies, which cost every
//! later snapshot more candidates. With this extension, after every update the map segments that
//! the paper's own test calls the same face as the updated segment are fused into it (after an
//! update that moved an end-point outwards, and after a refit): a fitted
//! segment `T` whose §4 evaluation as `l_n` against the updated segment as `l_e` is a MATCH
//! (orientation, colinearity, mid-point overlap or containment) is applied to it by the §5
//! MATCH rule (Figure 1) and leaves the map; its supporting readings join the updated segment's.

use crate::geometry::{distance_to_segment, line_angle_at_most, AngleLimit};
use crate::mapping::model::map::{EndPoint, Map, SegmentId};
use crate::mapping::model::params::Params;
use crate::mapping::model::trace::AbsorbTrace;
use crate::mapping::paper::matching::{place_pair, Placement, SegmentEnds};
use crate::mapping::paper::support_points::merge_support_list;
use crate::mapping::paper::update_geometry::update_match;

/// Fuses into segment `into` every fitted segment (other than `into` and `exclude`) that
/// matches it, one at a time until none does; returns what was absorbed, in order.
///
/// Searched: the segments whose mid-point lies within the largest colinearity threshold of
/// `into` (every MPC match does: its mid-point projects inside `into` within the threshold;
/// such a segment meets `into`'s bounding box widened by that threshold),
/// nearest first, ties by id. A longer segment that contains `into` is found when it is itself
/// updated.
pub fn absorb_duplicates(
    map: &mut Map,
    params: &Params,
    into: SegmentId,
    exclude: &[SegmentId],
) -> Vec<AbsorbTrace> {
    let mut absorbed = Vec::new();
    while let Some(trace) = absorb_one(map, params, into, exclude) {
        absorbed.push(trace);
    }
    absorbed
}

fn absorb_one(
    map: &mut Map,
    params: &Params,
    into: SegmentId,
    exclude: &[SegmentId],
) -> Option<AbsorbTrace> {
    let target = map.segment(into)?;
    let existing = SegmentEnds {
        a: target.a,
        b: target.b,
    };
    let reach_m = (params.accuracy_pct / 100.0
        * (target.a.range_m.max(target.b.range_m) + map.max_end_range_m))
        * (1.0 + 1e-9)
        + 1e-9;
    let (a, b) = (existing.a.point, existing.b.point);
    // The first match nearest first (ties by id) is the match with the least (distance, id):
    // found in one pass, testing only the segments that would come before the best so far.
    let limit = AngleLimit::new(params.orientation_rad);
    let mut best: Option<(f64, SegmentId, SegmentEnds, Placement)> = None;
    map.visit_segments_along(&a, &b, reach_m, |id, s| {
        if id == into || !s.fitted || exclude.contains(&id) {
            return;
        }
        let d = distance_to_segment(&nalgebra::center(&s.a.point, &s.b.point), &a, &b);
        let earlier = |&(bd, bid, ..): &(f64, SegmentId, SegmentEnds, Placement)| {
            d.total_cmp(&bd).then(id.cmp(&bid)).is_lt()
        };
        let within = d <= reach_m;
        if !within || !best.as_ref().is_none_or(earlier) {
            return;
        }
        // The orientation test compares lines (either direction), so it can go first, and
        // spare the placement of a crossing wall.
        if !line_angle_at_most(&(s.b.point - s.a.point), &(b - a), limit) {
            return;
        }
        let ends = SegmentEnds { a: s.a, b: s.b };
        let placement = place_pair(params, &ends, &existing);
        if placement.could_match() && placement.orientation_passes(&existing, limit) {
            best = Some((d, id, ends, placement));
        }
    });
    let (_, id, ends, placement) = best?;
    let evaluation = placement.with_orientation(params, into, &existing);
    let other_points = map.segment(id)?.points.to_vec();
    let geometry = update_match(
        [existing.a, existing.b],
        evaluation.new_left,
        evaluation.new_right,
    );
    let [a, b]: [EndPoint; 2] = geometry.ends;
    let target = map.segment(into)?;
    let points = merge_support_list(&target.points, &other_points, &a, &b, params.support_cap);
    map.remove_segment(id);
    if let Some(s) = map.segment_mut(into) {
        s.points = points;
    }
    map.set_ends(into, a, b);
    Some(AbsorbTrace {
        segment: id,
        into,
        ends: [ends.a, ends.b],
        evaluation,
        before: [existing.a, existing.b],
        after: [a, b],
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Point;
    use crate::mapping::model::map::{ReadingRef, Segment, SupportPoint};
    use crate::mapping::SegmentKind;

    fn segment(id: SegmentId, face: u32, a: (f64, f64), b: (f64, f64), range_m: f64) -> Segment {
        let end = |(x, y): (f64, f64)| EndPoint {
            point: Point::new(x, y),
            range_m,
        };
        let support = |(x, y): (f64, f64), sensor| SupportPoint {
            point: Point::new(x, y),
            range_m,
            reading: ReadingRef::new(id as usize, sensor),
        };
        Segment {
            id,
            kind: SegmentKind::Fitted,
            a: end(a),
            b: end(b),
            face,
            object: face,
            created: 0,
            updated: Vec::new(),
            points: vec![support(a, 0), support(b, 1)].into(),
        }
    }

    #[test]
    fn an_overlapping_colinear_copy_is_fused_and_a_crossing_wall_is_not() {
        // A wall along y = 0 from x = 0 to 2 m (range 1 m), a copy from 1 to 2.6 m 1 cm off
        // (threshold 0.03·1 + 0.015·(1 + 1) = 6 cm), a perpendicular wall through x = 1.
        let mut map = Map::from_segments(vec![
            segment(0, 0, (0.0, 0.0), (2.0, 0.0), 1.0),
            segment(1, 1, (1.0, 0.01), (2.6, 0.01), 1.0),
            segment(2, 2, (1.0, -1.0), (1.0, 1.0), 1.0),
        ]);
        let absorbed = absorb_duplicates(&mut map, &Params::paper(), 0, &[]);
        assert_eq!(absorbed.len(), 1);
        assert_eq!(absorbed[0].segment, 1);
        assert!(absorbed[0].evaluation.overlap.mpc);
        assert!(map.segment(1).is_none(), "the copy left the map");
        assert!(map.face(1).is_none(), "its emptied face too");
        assert!(
            map.segment(2).is_some(),
            "a crossing wall fails orientation"
        );
        // Figure 1 on equal ranges keeps the existing end-points (ties) and extends the segment
        // to the copy's right end projected on y = 0.
        let s = map.segment(0).unwrap();
        assert_eq!(s.a.point, Point::new(0.0, 0.0));
        assert!((s.b.point - Point::new(2.6, 0.0)).norm() < 1e-12);
        assert_eq!(s.points.len(), 4);
        assert_eq!(map.segments_near(&Point::new(2.5, 0.0), 0.05), vec![0]);
    }

    #[test]
    fn a_parallel_wall_beyond_the_colinearity_threshold_stays() {
        let mut map = Map::from_segments(vec![
            segment(0, 0, (0.0, 0.0), (2.0, 0.0), 1.0),
            segment(1, 1, (0.5, 0.07), (1.5, 0.07), 1.0),
        ]);
        assert!(absorb_duplicates(&mut map, &Params::paper(), 0, &[]).is_empty());
        assert_eq!(map.segments.len(), 2);
        // At 5.9 cm it passes.
        let mut map = Map::from_segments(vec![
            segment(0, 0, (0.0, 0.0), (2.0, 0.0), 1.0),
            segment(1, 1, (0.5, 0.059), (1.5, 0.059), 1.0),
        ]);
        assert_eq!(
            absorb_duplicates(&mut map, &Params::paper(), 0, &[1]).len(),
            0,
            "excluded segments are never absorbed"
        );
        assert_eq!(
            absorb_duplicates(&mut map, &Params::paper(), 0, &[]).len(),
            1
        );
    }
}
