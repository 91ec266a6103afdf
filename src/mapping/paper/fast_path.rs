//! The fast paths of matching (docs/algorithm.md §4): the same decisions as the rule in
//! [`crate::mapping::paper::matching`], reached with less work. Each is tied to the plain rule by a property test
//! below.
//! - The nearest candidate is tried first: most new segments match it, and then no other
//!   candidate needs ordering.
//! - A long candidate list is ordered lazily (a binary heap of bit-packed keys), so a list tested
//!   only as far as its first few is never sorted.
//! - Untraced, one pass stops at the first MATCH and otherwise remembers the first outermost
//!   EXTENSION and the first orientation-only failure; a candidate that cannot pass any rule
//!   gets no orientation test.

use crate::geometry::{total_order_key, AngleLimit};
use crate::mapping::model::map::{FaceId, SegmentId};
use crate::mapping::model::params::Params;
use crate::mapping::model::trace::{CandidateTrace, DecisionTrace, Outcome, Rule};
use crate::mapping::paper::matching::{
    decide_after_the_mpc_stage, decide_dismissed, evaluate_pair, in_order, place_pair,
    test_candidate, undecided, Candidate, Placement, SegmentEnds,
};
use std::cmp::Reverse;
use std::collections::BinaryHeap;

/// Below this many candidates, sorting them in place costs less than a heap.
const SORTED_IN_PLACE_BELOW: usize = 32;

/// The candidates in §4 order. A long list is ordered lazily: a binary heap costs O(n) to
/// build and O(log n) a candidate taken, so a list tested only as far as its first few is never
/// sorted; a short one is sorted in place.
fn in_order_lazily(candidates: &mut [Candidate]) -> Box<dyn Iterator<Item = &Candidate> + '_> {
    if candidates.len() < SORTED_IN_PLACE_BELOW || candidates.len() > u32::MAX as usize {
        candidates.sort_unstable_by(in_order);
        return Box::new(candidates.iter());
    }
    // One integer a candidate, ordered as `in_order` orders them: distance, then id, then the
    // place in the list (which makes every key distinct and finds the candidate again).
    let mut heap: BinaryHeap<Reverse<u128>> = candidates
        .iter()
        .enumerate()
        .map(|(i, c)| {
            let key = u128::from(total_order_key(c.distance_m)) << 64
                | u128::from(c.id) << 32
                | i as u128;
            Reverse(key)
        })
        .collect();
    let candidates = &*candidates;
    Box::new(std::iter::from_fn(move || {
        heap.pop()
            .map(|Reverse(key)| &candidates[(key & u128::from(u32::MAX)) as usize])
    }))
}

/// The candidate that comes first in the §4 order (nearest to `l_n`'s mid-point, ties by id).
fn nearest_candidate(candidates: &[Candidate]) -> Option<&Candidate> {
    candidates
        .iter()
        .reduce(|best, c| if c.precedes(best) { c } else { best })
}

/// Decides what becomes of new segment `new_index` (docs/algorithm.md §4): the decision of
/// [`decide_by_the_rule`](super::matching::decide_by_the_rule), reached faster.
///
/// First every candidate, nearest first, with all three tests and MPC (or containment): the
/// first pass is a MATCH. Then EPC against the outermost segments of their faces, in the same
/// order: the first pass is an EXTENSION. Otherwise, when some candidate fails only the
/// orientation test (colinearity and MPC or EPC pass; containment does not count), the new
/// segment is DISMISSED. Otherwise it is a NEW FACE.
///
/// `was_outermost(id, face)` says whether a candidate held an outermost end-point of its face
/// as the map stood before this snapshot; it is asked only for the candidates actually tested.
/// The tested candidates go into `stage` (emptied first): the decision's `mpc_stage`, a buffer
/// the caller may take back. With `every_tested` false (an untraced step) the stage holds only
/// the candidate the decision names, when it is a MATCH or an EXTENSION: the outcome, rule and
/// segment named are the same either way.
pub fn decide(
    params: &Params,
    new_index: usize,
    new: &SegmentEnds,
    candidates: &mut [Candidate],
    was_outermost: &dyn Fn(SegmentId, FaceId) -> bool,
    stage: Vec<CandidateTrace>,
    every_tested: bool,
) -> DecisionTrace {
    let outermost = |c: &Candidate| was_outermost(c.id, c.face);
    let mut decision = undecided(new_index, candidates, stage);
    let limit = AngleLimit::new(params.orientation_rad);
    // Most new segments match the nearest candidate: try it before ordering the rest (the
    // outcome and the trace are the same as with the full order).
    if let Some(c) = nearest_candidate(candidates).copied() {
        let placement = place_pair(params, new, &c.ends);
        if placement.could_match() && placement.orientation_passes(&c.ends, limit) {
            let evaluation = placement.with_orientation(params, c.id, &c.ends);
            test_candidate(&mut decision, &c, outermost(&c), evaluation);
            return decision;
        }
    }
    if !every_tested {
        decide_untraced(params, new, candidates, &outermost, limit, &mut decision);
        return decision;
    }
    for c in in_order_lazily(candidates) {
        let evaluation = evaluate_pair(params, new, c.id, &c.ends);
        if test_candidate(&mut decision, c, outermost(c), evaluation) {
            return decision;
        }
    }
    decide_after_the_mpc_stage(&mut decision);
    decision
}

/// [`decide`] past the nearest candidate without the trace: one pass in §4 order that stops at
/// the first MATCH and otherwise remembers the first outermost EXTENSION and the first
/// orientation-only failure, the candidates the later rules would name. A candidate that
/// cannot pass any rule gets no orientation test; only the named candidate is evaluated in full.
fn decide_untraced(
    params: &Params,
    new: &SegmentEnds,
    candidates: &mut [Candidate],
    outermost: &dyn Fn(&Candidate) -> bool,
    limit: AngleLimit,
    decision: &mut DecisionTrace,
) {
    let mut extension: Option<(Candidate, Placement)> = None;
    let mut orientation_only: Option<SegmentId> = None;
    for c in in_order_lazily(candidates) {
        let placement = place_pair(params, new, &c.ends);
        if !placement.could_pass() {
            continue;
        }
        let tests = placement.tests(placement.orientation_passes(&c.ends, limit));
        if tests.is_match() {
            let evaluation = placement.with_orientation(params, c.id, &c.ends);
            test_candidate(decision, c, outermost(c), evaluation);
            return;
        }
        if extension.is_none() && tests.is_extension() && outermost(c) {
            extension = Some((*c, placement));
        }
        if orientation_only.is_none() && tests.fails_only_orientation() {
            orientation_only = Some(c.id);
        }
    }
    if let Some((c, placement)) = extension {
        let evaluation = placement.with_orientation(params, c.id, &c.ends);
        decision.mpc_stage.push(CandidateTrace {
            distance_m: c.distance_m,
            outermost: true,
            evaluation,
        });
        decision.outcome = Outcome::Extension;
        decision.rule = Rule::EndPointOverlap;
        decision.existing = Some(c.id);
    } else if let Some(id) = orientation_only {
        decide_dismissed(decision, id);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mapping::paper::matching::decide_by_the_rule;
    use crate::mapping::paper::matching::test_support::*;
    use proptest::strategy::Strategy;

    proptest::proptest! {
        #[test]
        fn traced_decisions_equal_the_rule_and_untraced_ones_name_the_same_outcome(
            n in any_ends(),
            moves in proptest::collection::vec(
                (-1.2f64..1.2, -0.05f64..0.05, -0.6f64..0.6, 0.1f64..2.0, proptest::bool::ANY),
                0..60,
            ),
            theta_deg in 1.0f64..40.0,
        ) {
            let p = Params { orientation_rad: theta_deg.to_radians(), ..Params::paper() };
            let candidates: Vec<Candidate> = moves
                .iter()
                .enumerate()
                .map(|(i, &(along, off, turn, scale, outer))| {
                    // Slid along l_n by `along` of its length and off it by `off` metres.
                    let (u, v) = (n.b.point - n.a.point, (n.b.point - n.a.point).normalize());
                    let d = u * along + nalgebra::Vector2::new(-v.y, v.x) * off;
                    cand(&n, i as SegmentId, near(&n, d.x, d.y, turn, scale), outer)
                })
                .collect();
            let rule = decide_by_the_rule(&p, 0, &n, &mut candidates.clone(), &outermost_in_face_1);
            let traced = decide(&p, 0, &n, &mut candidates.clone(), &outermost_in_face_1, Vec::new(), true);
            let untraced = decide(&p, 0, &n, &mut candidates.clone(), &outermost_in_face_1, Vec::new(), false);
            proptest::prop_assert_eq!(&traced, &rule);
            proptest::prop_assert_eq!(
                (rule.outcome, rule.rule, rule.existing),
                (untraced.outcome, untraced.rule, untraced.existing)
            );
            proptest::prop_assert!(untraced.mpc_stage.len() <= 1);
        }
    }

    proptest::proptest! {
        #[test]
        fn candidates_come_lazily_in_the_full_order(
            distances in proptest::collection::vec(
                proptest::prop_oneof![
                    (0u8..6).prop_map(|d| f64::from(d) / 2.0),
                    proptest::num::f64::ANY,
                ],
                0..80,
            ),
        ) {
            // Few distinct distances, so ties by id are common; any f64 for the key's order.
            let n = ends(0.0, 0.0, 1.0, 1.0, 0.0, 1.0);
            let candidates: Vec<Candidate> = distances
                .iter()
                .enumerate()
                .map(|(i, &d)| Candidate {
                    id: (distances.len() - i) as SegmentId,
                    ends: n,
                    face: 0,
                    distance_m: d,
                })
                .collect();
            let mut full = candidates.clone();
            full.sort_by(in_order);
            let lazily: Vec<Candidate> = in_order_lazily(&mut candidates.clone()).copied().collect();
            proptest::prop_assert_eq!(
                lazily.iter().map(|c| (c.distance_m.to_bits(), c.id)).collect::<Vec<_>>(),
                full.iter().map(|c| (c.distance_m.to_bits(), c.id)).collect::<Vec<_>>()
            );
        }
    }
}
