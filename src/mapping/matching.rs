//! Matching a new segment against the map (paper §3.3.1; ALGORITHM.md §4).

use super::map::{EndPoint, FaceId, SegmentId};
use super::params::Params;
use super::trace::{
    CandidateTrace, ColinearityTest, DecisionTrace, Outcome, OverlapTest, PairEvaluation, Rule,
    Side, Test,
};
use crate::geometry::{
    distance_to_line, distance_to_segment, line_angle_between, projection_param,
};

/// A segment's end-points as the tests see them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SegmentEnds {
    /// First end-point.
    pub a: EndPoint,
    /// Second end-point.
    pub b: EndPoint,
}

impl SegmentEnds {
    /// Mid-point.
    pub fn mid(&self) -> crate::geometry::Point {
        nalgebra::center(&self.a.point, &self.b.point)
    }
}

/// A map segment offered to the matcher.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Candidate {
    /// Its id.
    pub id: SegmentId,
    /// Its geometry before this snapshot.
    pub ends: SegmentEnds,
    /// Its face.
    pub face: FaceId,
    /// Distance from `l_n`'s mid-point to it, metres (the §4 order).
    pub distance_m: f64,
}

impl Candidate {
    /// Map segment `id` (`ends`, of face `face`) as a candidate for `new`.
    pub fn new(new: &SegmentEnds, id: SegmentId, ends: SegmentEnds, face: FaceId) -> Self {
        Self {
            id,
            ends,
            face,
            distance_m: distance_to_segment(&new.mid(), &ends.a.point, &ends.b.point),
        }
    }

    /// True when `self` comes before `other` in the §4 order (nearer, ties by id).
    fn precedes(&self, other: &Candidate) -> bool {
        in_order(self, other).is_lt()
    }
}

fn inside(t: f64) -> bool {
    (0.0..=1.0).contains(&t)
}

/// The three tests of §3.3.1 for the pair (`new` = `l_n`, `existing` = `l_e`), with every number.
///
/// `l_n` is first oriented like `l_e` (its left end-point has the smaller projection on
/// `l_e`'s direction). Orientation: the angle between the lines modulo 180° ≤ `θ_o`.
/// Colinearity: `|d| ≤ ξ/100·(D1 + (D2 + D3)/2)` (the paper's `0.03·D1 + 0.015·(D2 + D3)` at
/// ξ = 3), `d` from `l_n`'s mid-point to `l_e`'s line, `D1` the range of `l_e` interpolated at
/// the foot (clamped to the segment). Overlap: MPC (mid-point projects into `l_e`, closed
/// interval), EPC (an end-point of `l_n` does), containment (both of `l_e`'s end-points project
/// into `l_n`; counts as MPC).
pub fn evaluate_pair(
    params: &Params,
    new: &SegmentEnds,
    existing_id: SegmentId,
    existing: &SegmentEnds,
) -> PairEvaluation {
    let (ea, eb) = (existing.a.point, existing.b.point);
    let ta = projection_param(&new.a.point, &ea, &eb);
    let tb = projection_param(&new.b.point, &ea, &eb);
    let new_reversed = tb < ta;
    let (left, right) = if new_reversed {
        (new.b, new.a)
    } else {
        (new.a, new.b)
    };
    let (left_param, right_param) = if new_reversed { (tb, ta) } else { (ta, tb) };

    let angle = line_angle_between(&(right.point - left.point), &(eb - ea));
    let orientation = Test::at_most(angle, params.orientation_rad);

    let mid = nalgebra::center(&left.point, &right.point);
    let d = distance_to_line(&mid, &ea, &eb);
    let mid_param = projection_param(&mid, &ea, &eb);
    let foot_param = mid_param.clamp(0.0, 1.0);
    let d1_m = existing.a.range_m + foot_param * (existing.b.range_m - existing.a.range_m);
    let (d2_m, d3_m) = (left.range_m, right.range_m);
    let threshold = params.accuracy_pct / 100.0 * (d1_m + (d2_m + d3_m) / 2.0);
    let colinearity = ColinearityTest {
        test: Test::at_most(d, threshold),
        d1_m,
        d2_m,
        d3_m,
        foot_param,
    };

    let existing_on_new_params = [
        projection_param(&ea, &left.point, &right.point),
        projection_param(&eb, &left.point, &right.point),
    ];
    let (left_in, right_in) = (inside(left_param), inside(right_param));
    let epc_end = match (left_in, right_in) {
        (true, false) => Some(Side::Left),
        (false, true) => Some(Side::Right),
        _ => None,
    };
    let overlap = OverlapTest {
        mid_param,
        left_param,
        right_param,
        existing_on_new_params,
        mpc: inside(mid_param),
        containment: existing_on_new_params.iter().all(|&t| inside(t)),
        epc: left_in || right_in,
        epc_end,
    };
    PairEvaluation {
        existing: existing_id,
        new_reversed,
        new_left: left,
        new_right: right,
        orientation,
        colinearity,
        overlap,
    }
}

/// The §4 order of candidates: by distance from `l_n`'s mid-point to the segment, ties by id
/// (a total order: ids are unique).
fn in_order(x: &Candidate, y: &Candidate) -> std::cmp::Ordering {
    x.distance_m.total_cmp(&y.distance_m).then(x.id.cmp(&y.id))
}

/// How many candidates are put in order before any is tested past the nearest.
const ORDERED_HEAD: usize = 8;

/// Puts the first [`ORDERED_HEAD`] candidates in order (the rest after them, in no particular
/// order); returns how many are ordered. Most new segments that do not match their nearest
/// candidate match one of the next few, so most lists need no full sort.
fn order_head(candidates: &mut [Candidate]) -> usize {
    let head = ORDERED_HEAD.min(candidates.len());
    if head < candidates.len() {
        candidates.select_nth_unstable_by(head - 1, in_order);
    }
    candidates[..head].sort_unstable_by(in_order);
    head
}

/// The candidate that comes first in the §4 order (nearest to `l_n`'s mid-point, ties by id).
fn nearest_candidate(candidates: &[Candidate]) -> Option<&Candidate> {
    candidates
        .iter()
        .reduce(|best, c| if c.precedes(best) { c } else { best })
}

/// Decides what becomes of new segment `new_index` (ALGORITHM.md §4).
///
/// First every candidate, nearest first, with all three tests and MPC (or containment): the
/// first pass is a MATCH. Then EPC against the outermost segments of their faces, in the same
/// order: the first pass is an EXTENSION. Otherwise, when some candidate fails only the
/// orientation test (colinearity and MPC or EPC pass; containment does not count), the new
/// segment is DISMISSED. Otherwise it is a NEW FACE.
///
/// `was_outermost(id, face)` says whether a candidate held an outermost end-point of its face
/// as the map stood before this snapshot; it is asked only for the candidates actually tested.
///
/// With `trace_all` the trace lists every candidate tested, in order; without it the outcome,
/// rule and segment are the same but the lists keep only the candidates that could decide
/// (and the chosen candidate's evaluation), so a long list is not sorted.
pub fn decide(
    params: &Params,
    new_index: usize,
    new: &SegmentEnds,
    candidates: &mut [Candidate],
    was_outermost: &dyn Fn(SegmentId, FaceId) -> bool,
    trace_all: bool,
) -> DecisionTrace {
    let outermost = |c: &Candidate| was_outermost(c.id, c.face);
    let mut decision = DecisionTrace {
        new_segment: new_index,
        mpc_stage: Vec::with_capacity(if trace_all {
            candidates.len()
        } else {
            candidates.len().min(ORDERED_HEAD + 1)
        }),
        epc_stage: Vec::new(),
        outcome: Outcome::NewFace,
        rule: if candidates.is_empty() {
            Rule::NoCandidates
        } else {
            Rule::NoCandidatePassed
        },
        existing: None,
        result: None,
    };
    // Most new segments match the nearest candidate: try it before ordering the rest (the
    // outcome and the trace are the same as with the full order).
    if let Some(c) = nearest_candidate(candidates).copied() {
        let evaluation = evaluate_pair(params, new, c.id, &c.ends);
        if evaluation.is_match() {
            test_candidate(&mut decision, &c, outermost(&c), evaluation);
            return decision;
        }
    }
    let head = order_head(candidates);
    let (head, rest) = candidates.split_at_mut(head);
    for c in head.iter() {
        let evaluation = evaluate_pair(params, new, c.id, &c.ends);
        if test_candidate(&mut decision, c, outermost(c), evaluation) {
            return decision;
        }
    }
    if trace_all {
        rest.sort_unstable_by(in_order);
        for c in rest.iter() {
            let evaluation = evaluate_pair(params, new, c.id, &c.ends);
            if test_candidate(&mut decision, c, outermost(c), evaluation) {
                return decision;
            }
        }
    } else {
        // Untraced, the rest need no order: a candidate that can neither match, extend nor be
        // dismissed on decides nothing, and leaving it out of the order leaves every stage's
        // first passing candidate the same.
        let mut deciding: Vec<(&Candidate, bool, PairEvaluation)> = Vec::new();
        for c in rest.iter() {
            let evaluation = evaluate_pair(params, new, c.id, &c.ends);
            let can_decide = evaluation.is_match()
                || evaluation.fails_only_orientation()
                || evaluation.is_extension();
            if can_decide {
                deciding.push((c, outermost(c), evaluation));
            }
        }
        deciding.sort_unstable_by(|x, y| in_order(x.0, y.0));
        for (c, is_outermost, evaluation) in deciding {
            if test_candidate(&mut decision, c, is_outermost, evaluation) {
                return decision;
            }
        }
    }
    for (i, c) in decision.mpc_stage.iter().enumerate() {
        if !c.outermost {
            continue;
        }
        decision.epc_stage.push(i);
        if c.evaluation.is_extension() {
            decision.outcome = Outcome::Extension;
            decision.rule = Rule::EndPointOverlap;
            decision.existing = Some(c.evaluation.existing);
            return decision;
        }
    }
    if let Some(c) = decision
        .mpc_stage
        .iter()
        .find(|c| c.evaluation.fails_only_orientation())
    {
        decision.outcome = Outcome::Dismissed;
        decision.rule = Rule::OrientationOnlyFailure;
        decision.existing = Some(c.evaluation.existing);
    }
    decision
}

/// Adds `c` to the MPC stage; true (with the decision made a MATCH) when it matches.
fn test_candidate(
    decision: &mut DecisionTrace,
    c: &Candidate,
    outermost: bool,
    evaluation: PairEvaluation,
) -> bool {
    let is_match = evaluation.is_match();
    let rule = if evaluation.overlap.mpc {
        Rule::MidPointOverlap
    } else {
        Rule::Containment
    };
    decision.mpc_stage.push(CandidateTrace {
        distance_m: c.distance_m,
        outermost,
        evaluation,
    });
    if is_match {
        decision.outcome = Outcome::Match;
        decision.rule = rule;
        decision.existing = Some(c.id);
    }
    is_match
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Point;

    fn ends(ax: f64, ay: f64, da: f64, bx: f64, by: f64, db: f64) -> SegmentEnds {
        SegmentEnds {
            a: EndPoint {
                point: Point::new(ax, ay),
                range_m: da,
            },
            b: EndPoint {
                point: Point::new(bx, by),
                range_m: db,
            },
        }
    }

    #[test]
    fn colinearity_threshold_is_the_papers_formula_at_xi_3() {
        let p = Params::paper();
        // l_e from (0,0) D=100 to (100,0) D=200; l_n mid at x=25 → D1 = 125.
        let e = ends(0.0, 0.0, 100.0, 100.0, 0.0, 200.0);
        let n = ends(20.0, 2.0, 80.0, 30.0, 2.0, 90.0);
        let ev = evaluate_pair(&p, &n, 1, &e);
        let paper = 0.03 * 125.0 + 0.015 * (80.0 + 90.0);
        assert!((ev.colinearity.test.threshold - paper).abs() < 1e-12);
        assert!((ev.colinearity.d1_m - 125.0).abs() < 1e-12);
        assert!((ev.colinearity.test.value - 2.0).abs() < 1e-12);
        assert!(ev.colinearity.test.pass);
        // d exactly at the threshold passes (inclusive).
        let n_at = ends(20.0, paper, 80.0, 30.0, paper, 90.0);
        assert!(evaluate_pair(&p, &n_at, 1, &e).colinearity.test.pass);
        let n_over = ends(20.0, paper + 1e-9, 80.0, 30.0, paper + 1e-9, 90.0);
        assert!(!evaluate_pair(&p, &n_over, 1, &e).colinearity.test.pass);
    }

    #[test]
    fn orientation_test_wraps_at_180_degrees_and_reverses_the_new_segment() {
        let p = Params::paper();
        let e = ends(0.0, 0.0, 50.0, 100.0, 0.0, 50.0);
        // Drawn right-to-left at 174° (6° off the line): passes, and is reversed.
        let dir = 174f64.to_radians();
        let n = ends(
            60.0,
            0.0,
            50.0,
            60.0 + 20.0 * dir.cos(),
            20.0 * dir.sin(),
            50.0,
        );
        let ev = evaluate_pair(&p, &n, 1, &e);
        assert!(ev.new_reversed);
        assert!((ev.orientation.value.to_degrees() - 6.0).abs() < 1e-9);
        assert!(ev.orientation.pass);
        assert!(ev.new_left.point.x < ev.new_right.point.x);
        let dir = 164f64.to_radians();
        let n = ends(
            60.0,
            0.0,
            50.0,
            60.0 + 20.0 * dir.cos(),
            20.0 * dir.sin(),
            50.0,
        );
        assert!(!evaluate_pair(&p, &n, 1, &e).orientation.pass);
    }

    #[test]
    fn mpc_epc_and_containment() {
        let p = Params::paper();
        let e = ends(0.0, 0.0, 50.0, 10.0, 0.0, 50.0);
        let mpc = evaluate_pair(&p, &ends(5.0, 0.0, 50.0, 14.0, 0.0, 50.0), 1, &e).overlap;
        assert!(mpc.mpc && mpc.epc && !mpc.containment && mpc.epc_end == Some(Side::Left));
        let epc = evaluate_pair(&p, &ends(8.0, 0.0, 50.0, 30.0, 0.0, 50.0), 1, &e).overlap;
        assert!(!epc.mpc && epc.epc && epc.epc_end == Some(Side::Left));
        assert!((epc.mid_param - 1.9).abs() < 1e-12);
        let at_end = evaluate_pair(&p, &ends(10.0, 0.0, 50.0, 30.0, 0.0, 50.0), 1, &e).overlap;
        assert!(at_end.epc, "closed interval: the end-point itself counts");
        // l_n contains l_e but its mid-point is outside it.
        let contains = evaluate_pair(&p, &ends(-2.0, 0.0, 50.0, 40.0, 0.0, 50.0), 1, &e).overlap;
        assert!(!contains.mpc && contains.containment && !contains.epc);
        let none = evaluate_pair(&p, &ends(12.0, 0.0, 50.0, 30.0, 0.0, 50.0), 1, &e).overlap;
        assert!(!none.mpc && !none.epc && !none.containment);
    }

    /// A candidate in face 1 (where every segment is outermost) or face 0 (where none is).
    fn cand(new: &SegmentEnds, id: SegmentId, e: SegmentEnds, outermost: bool) -> Candidate {
        Candidate::new(new, id, e, FaceId::from(outermost))
    }

    fn outermost_in_face_1(_: SegmentId, face: FaceId) -> bool {
        face == 1
    }

    #[test]
    fn match_is_taken_nearest_first_and_extension_needs_an_outermost_segment() {
        let p = Params::paper();
        let n = ends(0.0, 0.0, 50.0, 10.0, 0.0, 50.0);
        let far = cand(&n, 1, ends(-5.0, 1.0, 50.0, 15.0, 1.0, 50.0), true);
        let near = cand(&n, 2, ends(-5.0, 0.1, 50.0, 15.0, 0.1, 50.0), true);
        let d = decide(&p, 0, &n, &mut [far, near], &outermost_in_face_1, true);
        assert_eq!(
            (d.outcome, d.rule, d.existing),
            (Outcome::Match, Rule::MidPointOverlap, Some(2))
        );
        assert_eq!(d.mpc_stage.len(), 1, "the first pass ends the search");

        let partial = ends(8.0, 0.0, 50.0, 30.0, 0.0, 50.0);
        let inner = cand(&n, 3, partial, false);
        let d = decide(&p, 0, &n, &mut [inner], &outermost_in_face_1, true);
        assert_eq!(d.outcome, Outcome::NewFace);
        let outer = cand(&n, 3, partial, true);
        let d = decide(&p, 0, &n, &mut [outer], &outermost_in_face_1, true);
        assert_eq!(
            (d.outcome, d.rule, d.existing),
            (Outcome::Extension, Rule::EndPointOverlap, Some(3))
        );
        assert_eq!(d.epc_stage, vec![0]);
    }

    #[test]
    fn dismissal_needs_a_candidate_failing_only_orientation() {
        let p = Params::paper();
        let e = ends(0.0, 0.0, 50.0, 10.0, 0.0, 50.0);
        // 30° off, crossing l_e's mid-point: colinearity and MPC pass, orientation fails.
        let dir = 30f64.to_radians();
        let n = ends(
            5.0 - 2.0 * dir.cos(),
            -2.0 * dir.sin(),
            50.0,
            5.0 + 2.0 * dir.cos(),
            2.0 * dir.sin(),
            50.0,
        );
        let d = decide(
            &p,
            0,
            &n,
            &mut [cand(&n, 7, e, true)],
            &outermost_in_face_1,
            true,
        );
        assert_eq!(
            (d.outcome, d.rule, d.existing),
            (Outcome::Dismissed, Rule::OrientationOnlyFailure, Some(7))
        );
        // A long crossing segment that contains l_e but has neither MPC nor EPC does not dismiss.
        let n = ends(
            30.0 - 40.0 * dir.cos(),
            -40.0 * dir.sin(),
            50.0,
            30.0 + 40.0 * dir.cos(),
            40.0 * dir.sin(),
            50.0,
        );
        let ev = evaluate_pair(&p, &n, 7, &e);
        assert!(!ev.overlap.mpc && !ev.overlap.epc && ev.overlap.containment);
        assert!(ev.colinearity.test.pass && !ev.orientation.pass);
        let d = decide(
            &p,
            0,
            &n,
            &mut [cand(&n, 7, e, true)],
            &outermost_in_face_1,
            true,
        );
        assert_eq!(
            (d.outcome, d.rule),
            (Outcome::NewFace, Rule::NoCandidatePassed)
        );
        let d = decide(&p, 0, &n, &mut [], &outermost_in_face_1, true);
        assert_eq!(d.rule, Rule::NoCandidates);
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(2000))]
        #[test]
        fn ordering_the_head_then_the_rest_gives_the_full_order(
            distances in proptest::collection::vec(0u8..6, 0..40),
        ) {
            // Few distinct distances, so ties by id are common.
            let n = ends(0.0, 0.0, 1.0, 1.0, 0.0, 1.0);
            let mut candidates: Vec<Candidate> = distances
                .iter()
                .enumerate()
                .map(|(i, &d)| Candidate {
                    id: (distances.len() - i) as SegmentId,
                    ends: n,
                    face: 0,
                    distance_m: f64::from(d) / 2.0,
                })
                .collect();
            let mut full = candidates.clone();
            full.sort_by(in_order);
            let head = order_head(&mut candidates);
            proptest::prop_assert_eq!(head, ORDERED_HEAD.min(full.len()));
            proptest::prop_assert_eq!(&candidates[..head], &full[..head]);
            candidates[head..].sort_unstable_by(in_order);
            proptest::prop_assert_eq!(candidates, full);
        }

        #[test]
        fn untraced_decisions_equal_the_traced_ones(
            segments in proptest::collection::vec(
                (-3.0f64..3.0, -0.6f64..0.6, 0.2f64..3.0, -1.0f64..1.0, 0.5f64..4.0, proptest::bool::ANY),
                0..40,
            ),
            new_half_length_m in 0.2f64..2.0,
        ) {
            // Segments scattered about the new one's line: every outcome occurs.
            let p = Params::paper();
            let n = ends(-new_half_length_m, 0.0, 2.0, new_half_length_m, 0.05, 2.1);
            let outermost: Vec<bool> = segments.iter().map(|s| s.5).collect();
            let candidates: Vec<Candidate> = segments
                .iter()
                .enumerate()
                .map(|(i, &(x, y, half, angle, range_m, _))| {
                    let (dx, dy) = (half * angle.cos(), half * angle.sin());
                    let e = ends(x - dx, y - dy, range_m, x + dx, y + dy, range_m + 0.1);
                    Candidate::new(&n, i as SegmentId, e, 0)
                })
                .collect();
            let was_outermost = |id: SegmentId, _| outermost[id as usize];
            let traced = decide(&p, 0, &n, &mut candidates.clone(), &was_outermost, true);
            let untraced = decide(&p, 0, &n, &mut candidates.clone(), &was_outermost, false);
            proptest::prop_assert_eq!(
                (traced.outcome, traced.rule, traced.existing),
                (untraced.outcome, untraced.rule, untraced.existing)
            );
            let chosen = |d: &DecisionTrace| {
                d.mpc_stage
                    .iter()
                    .find(|c| Some(c.evaluation.existing) == d.existing)
                    .cloned()
            };
            proptest::prop_assert_eq!(chosen(&traced), chosen(&untraced));
        }
    }
}
