//! Updating a matched map segment (paper §3.3.2, Figures 1 and 2; docs/algorithm.md §5).
//!
//! End-points are compared by range: the smaller `D` is the higher confidence; on a tie the
//! existing end-point wins. A projected end-point keeps the range of the reading it came from.

use crate::geometry::{distance_to_line, projection_param, Point};
use crate::mapping::model::map::{EndPoint, Map, SegmentId, SupportPoint};
use crate::mapping::model::params::Params;
use crate::mapping::model::support_list::SupportList;
use crate::mapping::model::trace::{Outcome, RefitTrace, Side, SplitTrace, Test, UpdateTrace};
use crate::mapping::paper::fit::{piece_end_points, split_recursive, split_tolerance};
use crate::mapping::paper::merge::absorb_duplicates;
use crate::mapping::paper::support_points::merge_support_list_as_recorded;
use crate::mapping::paper::update_geometry::{update_extension, update_match, UpdateGeometry};

/// A MATCH or EXTENSION decided for a new segment, to apply to a map segment.
#[derive(Clone, Copy, Debug)]
pub struct UpdateRequest<'a> {
    /// The segment to update: the one that now carries the chosen candidate's id (or the one
    /// it was merged into earlier in the snapshot; docs/algorithm.md §4).
    pub target: SegmentId,
    /// Index of the new segment in the step.
    pub new_index: usize,
    /// The new segment's supporting points.
    pub new_points: &'a [SupportPoint],
    /// The new segment's end-points, oriented like the candidate as it was tested.
    pub new_left: EndPoint,
    /// See `new_left`.
    pub new_right: EndPoint,
    /// MATCH or EXTENSION.
    pub outcome: Outcome,
    /// For an EXTENSION: which end of the new segment projected inside the candidate.
    pub inside: Option<Side>,
    /// The snapshot.
    pub snapshot: usize,
    /// Whether the post-update test fails (the segment is fitted afresh), when a recording of
    /// this very update says so: `Some(false)` spares the test over every supporting point
    /// (thousands, in `paper`). `None`: tested.
    pub refit: Option<bool>,
    /// Whether the segment's supporting points were in order along the updated line, when a
    /// recording of this very update says so ([`UpdateTrace::support_in_order`]): spares the
    /// pass over every point that finds it. `None`: found.
    pub support_in_order: Option<bool>,
}

/// Applies an update to the map (paper §3.3.2; docs/algorithm.md §5): the geometry of Figure 1
/// (MATCH) or Figure 2 (EXTENSION), then the post-update test of the segment's supporting
/// points against `l_u`; when one lies beyond its split tolerance the points are fitted afresh
/// (§3) and the pieces replace the segment, the first keeping its id (a single piece replaces
/// the update's geometry). With `merge_duplicates` (§8.3) the segments the result now matches
/// are fused into it. `None` when the target is not in the map.
pub fn apply_update(
    map: &mut Map,
    params: &Params,
    request: &UpdateRequest<'_>,
) -> Option<UpdateTrace> {
    let target = request.target;
    let seg = map.segment(target)?;
    let before = [seg.a, seg.b];
    // Orient the new segment along the live geometry (it may have moved this snapshot).
    let (nl, nr) = if projection_param(&request.new_left.point, &seg.a.point, &seg.b.point)
        <= projection_param(&request.new_right.point, &seg.a.point, &seg.b.point)
    {
        (request.new_left, request.new_right)
    } else {
        (request.new_right, request.new_left)
    };
    let geometry: UpdateGeometry = match request.inside {
        Some(side) => update_extension(before, nl, nr, side),
        None => update_match(before, nl, nr),
    };
    let [a, b] = geometry.ends;
    let (points, support_in_order) = merge_support_list_as_recorded(
        &seg.points,
        request.new_points,
        &a,
        &b,
        params.support_cap,
        request.support_in_order,
    );
    let worst = match request.refit {
        // Recorded as passing: the test would find nothing to refit.
        Some(false) => None,
        _ => worst_support_test(&points, &geometry.line, params),
    };
    let mut update = UpdateTrace {
        segment: target,
        new_segment: request.new_index,
        outcome: request.outcome,
        before,
        after: geometry.ends,
        line: geometry.line,
        fates: geometry.fates,
        fallback_tls: geometry.fallback_tls,
        refit: None,
        absorbed: Vec::new(),
        support_in_order,
    };
    map.segment_mut(target)?.note_update(request.snapshot);
    match worst {
        Some(w) if !w.pass => {
            let (splits, pieces) = refit_segment(map, params, target, &points);
            if params.merge_duplicates {
                for &piece in &pieces {
                    let absorbed = absorb_duplicates(map, params, piece, &pieces);
                    update.absorbed.extend(absorbed);
                }
            }
            update.refit = Some(RefitTrace {
                worst: w,
                splits,
                pieces,
            });
        }
        _ => {
            map.segment_mut(target)?.points = points;
            map.set_ends(target, a, b);
            // Only a segment that grew past its old end-points can have come to overlap
            // another one.
            if params.merge_duplicates && grew_past(&before, &[a, b]) {
                update.absorbed = absorb_duplicates(map, params, target, &[]);
            }
        }
    }
    Some(update)
}

/// Whether a segment that ran between `before` now reaches past either of them (an end-point
/// of `after` projects outside `before`).
pub fn grew_past(before: &[EndPoint; 2], after: &[EndPoint; 2]) -> bool {
    after.iter().any(|e| {
        let t = projection_param(&e.point, &before[0].point, &before[1].point);
        !(-1e-9..=1.0 + 1e-9).contains(&t)
    })
}

/// The post-update test: each supporting point's distance to `l_u` against its split
/// tolerance. Returns the worst: a failing one when any fails (the farthest beyond its
/// tolerance), else the passing one nearest its tolerance; `None` without points.
fn worst_support_test(points: &SupportList, line: &[Point; 2], params: &Params) -> Option<Test> {
    let mut tests = points.iter().map(|q| {
        let d = distance_to_line(&q.point, &line[0], &line[1]);
        Test::at_most(d, split_tolerance(params, q.range_m))
    });
    // The worst so far as a plain value, not an `Option` folded through: the loop runs over
    // every supporting point of every update (thousands, in `paper`), and the folded option
    // went through memory each time.
    let mut worst = tests.next()?;
    for t in tests {
        // A failing test is worse than a passing one; between two alike, the one further
        // beyond (or nearer) its threshold, the earlier on a tie.
        let keeps = if worst.pass == t.pass {
            worst.value - worst.threshold >= t.value - t.threshold
        } else {
            !worst.pass
        };
        if !keeps {
            worst = t;
        }
    }
    Some(worst)
}

/// Fits the updated segment's points (`support`) afresh (§3): the first piece keeps the id
/// `target`, the others get new ids and follow it in its face. Returns the split tests and the
/// pieces' ids. Each piece's points share the chunks of `support` that lie wholly inside it.
fn refit_segment(
    map: &mut Map,
    params: &Params,
    target: SegmentId,
    support: &SupportList,
) -> (Vec<SplitTrace>, Vec<SegmentId>) {
    let points = &support.to_vec();
    let (mut splits, mut pieces) = (Vec::new(), Vec::new());
    split_recursive(points, params, &mut splits, &mut pieces);
    if map.segment(target).is_none() {
        return (splits, Vec::new());
    }
    let mut piece_ids = Vec::with_capacity(pieces.len());
    for (k, &[first, last]) in pieces.iter().enumerate() {
        let (pa, pb) = piece_end_points(points, first, last, params.fit);
        let piece_points = support.slice(first..last + 1);
        if k == 0 {
            if let Some(s) = map.segment_mut(target) {
                s.points = piece_points;
            }
            map.set_ends(target, pa, pb);
            piece_ids.push(target);
        } else if let Some(id) = map.push_piece_of(target, pa, pb, piece_points) {
            piece_ids.push(id);
        }
    }
    map.place_after_in_face(target, &piece_ids[1..]);
    (splits, piece_ids)
}

#[cfg(test)]
mod tests;
