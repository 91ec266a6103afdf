//! Matching a new segment against the map (paper §3.3.1; docs/algorithm.md §4).

use crate::geometry::{
    distance_to_line, distance_to_segment, line_angle_at_most, line_angle_between,
    projection_param, AngleLimit, Vec2,
};
use crate::mapping::model::map::{EndPoint, FaceId, SegmentId};
use crate::mapping::model::params::Params;
use crate::mapping::model::trace::{
    CandidateTrace, ColinearityTest, DecisionTrace, Outcome, OverlapTest, PairEvaluation,
    PairTests, Rule, Side, Test,
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
    pub(super) fn precedes(&self, other: &Candidate) -> bool {
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
    place_pair(params, new, existing).with_orientation(params, existing_id, existing)
}

/// A pair's colinearity and overlap tests: everything of [`evaluate_pair`] but the orientation
/// angle (its one `atan2`), which no rule needs when [`Placement::could_pass`] is false.
#[derive(Clone, Copy, Debug)]
pub struct Placement {
    new_reversed: bool,
    left: EndPoint,
    right: EndPoint,
    colinearity: ColinearityTest,
    overlap: OverlapTest,
}

/// `l_n` oriented along `l_e`, with the colinearity and overlap tests of [`evaluate_pair`].
pub fn place_pair(params: &Params, new: &SegmentEnds, existing: &SegmentEnds) -> Placement {
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
    Placement {
        new_reversed,
        left,
        right,
        colinearity,
        overlap,
    }
}

impl Placement {
    /// Its test results, with the orientation test's as given.
    pub(super) fn tests(&self, oriented: bool) -> PairTests<'_> {
        PairTests {
            oriented,
            colinear: self.colinearity.test.pass,
            overlap: &self.overlap,
        }
    }

    /// False when no rule can pass whatever the orientation: a MATCH, an EXTENSION and a
    /// dismissal all need colinearity and an overlap (MPC, EPC or containment).
    pub fn could_pass(&self) -> bool {
        self.could_match()
            || self.tests(true).is_extension()
            || self.tests(false).fails_only_orientation()
    }

    /// True when the pair could be a MATCH (colinearity, and MPC or containment): the
    /// orientation test decides.
    pub fn could_match(&self) -> bool {
        self.tests(true).is_match()
    }

    /// `l_n`'s direction (oriented) and `existing`'s, as the orientation test compares them.
    fn directions(&self, existing: &SegmentEnds) -> (Vec2, Vec2) {
        (
            self.right.point - self.left.point,
            existing.b.point - existing.a.point,
        )
    }

    /// Whether the orientation test passes against `existing` (`limit` is `θ_o`): the same
    /// answer as [`Placement::with_orientation`]'s, mostly without its `atan2`.
    pub fn orientation_passes(&self, existing: &SegmentEnds, limit: AngleLimit) -> bool {
        let (new_dir, existing_dir) = self.directions(existing);
        line_angle_at_most(&new_dir, &existing_dir, limit)
    }

    /// The full evaluation: this placement with the orientation test against `existing`.
    pub fn with_orientation(
        self,
        params: &Params,
        existing_id: SegmentId,
        existing: &SegmentEnds,
    ) -> PairEvaluation {
        let (new_dir, existing_dir) = self.directions(existing);
        let angle = line_angle_between(&new_dir, &existing_dir);
        PairEvaluation {
            existing: existing_id,
            new_reversed: self.new_reversed,
            new_left: self.left,
            new_right: self.right,
            orientation: Test::at_most(angle, params.orientation_rad),
            colinearity: self.colinearity,
            overlap: self.overlap,
        }
    }
}

/// The §4 order of candidates: by distance from `l_n`'s mid-point to the segment, ties by id
/// (a total order: ids are unique).
pub(super) fn in_order(x: &Candidate, y: &Candidate) -> std::cmp::Ordering {
    x.distance_m.total_cmp(&y.distance_m).then(x.id.cmp(&y.id))
}

/// Decides what becomes of new segment `new_index`: the rule of docs/algorithm.md §4 as
/// written, every candidate in order (the reference the mapper's
/// [`fast_path::decide`](crate::mapping::paper::fast_path::decide) is tested against).
///
/// First every candidate, nearest first (ties by id), with all three tests and MPC (or
/// containment): the first pass is a MATCH. Then EPC against the segments that held an
/// outermost end-point of their face before this snapshot (`was_outermost(id, face)`), in the
/// same order: the first pass is an EXTENSION. Otherwise, when some candidate fails only the
/// orientation test (colinearity and MPC or EPC pass; containment does not count), the new
/// segment is DISMISSED. Otherwise it is a NEW FACE. The trace lists every candidate tested.
///
/// ```
/// use sonarmap::geometry::Point;
/// use sonarmap::mapping::paper::matching::{decide_by_the_rule, Candidate, SegmentEnds};
/// use sonarmap::mapping::{EndPoint, Outcome, Params};
/// let end = |x: f64, y: f64, d: f64| EndPoint { point: Point::new(x, y), range_m: d };
/// // l_n from (1, 0.05) to (3, 0.05), read at 2 m; l_e along y = 0 from 0 to 2, read at 2 m.
/// // Colinearity: |d| = 0.05 ≤ 0.03·2 + 0.015·(2 + 2) = 0.12; l_n's mid-point (2, 0.05)
/// // projects at t = 1, inside [0, 1]: MPC, a MATCH.
/// let new = SegmentEnds { a: end(1.0, 0.05, 2.0), b: end(3.0, 0.05, 2.0) };
/// let wall = SegmentEnds { a: end(0.0, 0.0, 2.0), b: end(2.0, 0.0, 2.0) };
/// let mut candidates = vec![Candidate::new(&new, 7, wall, 0)];
/// let decision = decide_by_the_rule(&Params::paper(), 0, &new, &mut candidates, &|_, _| true);
/// assert_eq!(decision.outcome, Outcome::Match);
/// assert_eq!(decision.existing, Some(7));
/// let colinearity = decision.mpc_stage[0].evaluation.colinearity;
/// assert!((colinearity.test.value - 0.05).abs() < 1e-12);
/// assert!((colinearity.test.threshold - 0.12).abs() < 1e-12);
/// ```
pub fn decide_by_the_rule(
    params: &Params,
    new_index: usize,
    new: &SegmentEnds,
    candidates: &mut [Candidate],
    was_outermost: &dyn Fn(SegmentId, FaceId) -> bool,
) -> DecisionTrace {
    candidates.sort_unstable_by(in_order);
    let mut decision = undecided(new_index, candidates, Vec::new());
    for c in candidates.iter() {
        let evaluation = evaluate_pair(params, new, c.id, &c.ends);
        if test_candidate(&mut decision, c, was_outermost(c.id, c.face), evaluation) {
            return decision;
        }
    }
    decide_after_the_mpc_stage(&mut decision);
    decision
}

/// A NEW FACE decision for `new_index` with no candidate tested yet; its rule says whether
/// there was any candidate. `stage` (emptied) becomes the MPC stage.
pub(super) fn undecided(
    new_index: usize,
    candidates: &[Candidate],
    mut stage: Vec<CandidateTrace>,
) -> DecisionTrace {
    stage.clear();
    DecisionTrace {
        new_segment: new_index,
        mpc_stage: stage,
        epc_stage: Vec::new(),
        outcome: Outcome::NewFace,
        rule: if candidates.is_empty() {
            Rule::NoCandidates
        } else {
            Rule::NoCandidatePassed
        },
        existing: None,
        result: None,
    }
}

/// The rules after a MPC stage without a MATCH: the first outermost candidate that passes EPC
/// makes an EXTENSION; otherwise the first that fails only orientation, a dismissal.
pub(super) fn decide_after_the_mpc_stage(decision: &mut DecisionTrace) {
    for (i, c) in decision.mpc_stage.iter().enumerate() {
        if !c.outermost {
            continue;
        }
        decision.epc_stage.push(i);
        if c.evaluation.is_extension() {
            decision.outcome = Outcome::Extension;
            decision.rule = Rule::EndPointOverlap;
            decision.existing = Some(c.evaluation.existing);
            return;
        }
    }
    let orientation_only = decision
        .mpc_stage
        .iter()
        .find(|c| c.evaluation.fails_only_orientation())
        .map(|c| c.evaluation.existing);
    if let Some(id) = orientation_only {
        decide_dismissed(decision, id);
    }
}

/// Makes `decision` a dismissal naming segment `existing`.
pub(super) fn decide_dismissed(decision: &mut DecisionTrace, existing: SegmentId) {
    decision.outcome = Outcome::Dismissed;
    decision.rule = Rule::OrientationOnlyFailure;
    decision.existing = Some(existing);
}

/// Adds `c` to the MPC stage; true (with the decision made a MATCH) when it matches.
pub(super) fn test_candidate(
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

/// Segments and candidates for the tests of matching and its fast paths.
#[cfg(test)]
pub(super) mod test_support {
    use super::*;
    use crate::geometry::Point;
    use proptest::strategy::Strategy;

    pub(crate) fn ends(ax: f64, ay: f64, da: f64, bx: f64, by: f64, db: f64) -> SegmentEnds {
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

    /// A candidate in face 1 (where every segment is outermost) or face 0 (where none is).
    pub(crate) fn cand(
        new: &SegmentEnds,
        id: SegmentId,
        e: SegmentEnds,
        outermost: bool,
    ) -> Candidate {
        Candidate::new(new, id, e, FaceId::from(outermost))
    }

    pub(crate) fn outermost_in_face_1(_: SegmentId, face: FaceId) -> bool {
        face == 1
    }

    /// A segment within a few metres of the origin, ranges from 0.3 to 4 m.
    pub(crate) fn any_ends() -> impl Strategy<Value = SegmentEnds> {
        let coord = -3.0f64..3.0;
        let range = 0.3f64..4.0;
        (
            coord.clone(),
            coord.clone(),
            range.clone(),
            coord.clone(),
            coord,
            range,
        )
            .prop_map(|(ax, ay, da, bx, by, db)| ends(ax, ay, da, bx, by, db))
    }

    /// A copy of `e` moved by (`dx`, `dy`), turned by `turn` about its mid-point and scaled by
    /// `scale`: near-duplicates, crossing and parallel segments, so every rule gets exercised.
    pub(crate) fn near(e: &SegmentEnds, dx: f64, dy: f64, turn: f64, scale: f64) -> SegmentEnds {
        let m = e.mid();
        let (s, c) = turn.sin_cos();
        let place = |p: &EndPoint| {
            let v = (p.point - m) * scale;
            EndPoint {
                point: crate::geometry::Point::new(
                    m.x + dx + c * v.x - s * v.y,
                    m.y + dy + s * v.x + c * v.y,
                ),
                range_m: p.range_m,
            }
        };
        SegmentEnds {
            a: place(&e.a),
            b: place(&e.b),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::test_support::*;
    use super::*;

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

    /// `decide` for new segment 0, with candidates in face 1 outermost.
    fn decide_in_face_1(
        p: &Params,
        n: &SegmentEnds,
        candidates: &mut [Candidate],
    ) -> DecisionTrace {
        decide_by_the_rule(p, 0, n, candidates, &outermost_in_face_1)
    }

    #[test]
    fn match_is_taken_nearest_first_and_extension_needs_an_outermost_segment() {
        let p = Params::paper();
        let n = ends(0.0, 0.0, 50.0, 10.0, 0.0, 50.0);
        let far = cand(&n, 1, ends(-5.0, 1.0, 50.0, 15.0, 1.0, 50.0), true);
        let near = cand(&n, 2, ends(-5.0, 0.1, 50.0, 15.0, 0.1, 50.0), true);
        let d = decide_in_face_1(&p, &n, &mut [far, near]);
        assert_eq!(
            (d.outcome, d.rule, d.existing),
            (Outcome::Match, Rule::MidPointOverlap, Some(2))
        );
        assert_eq!(d.mpc_stage.len(), 1, "the first pass ends the search");

        let partial = ends(8.0, 0.0, 50.0, 30.0, 0.0, 50.0);
        let inner = cand(&n, 3, partial, false);
        let d = decide_in_face_1(&p, &n, &mut [inner]);
        assert_eq!(d.outcome, Outcome::NewFace);
        let outer = cand(&n, 3, partial, true);
        let d = decide_in_face_1(&p, &n, &mut [outer]);
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
        let d = decide_in_face_1(&p, &n, &mut [cand(&n, 7, e, true)]);
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
        let d = decide_in_face_1(&p, &n, &mut [cand(&n, 7, e, true)]);
        assert_eq!(
            (d.outcome, d.rule),
            (Outcome::NewFace, Rule::NoCandidatePassed)
        );
        let d = decide_in_face_1(&p, &n, &mut []);
        assert_eq!(d.rule, Rule::NoCandidates);
    }

    proptest::proptest! {
        #[test]
        fn a_pair_that_cannot_pass_fails_every_rule_whatever_its_orientation(
            n in any_ends(),
            e in any_ends(),
            (dx, dy, turn, scale) in (-0.2f64..0.2, -0.2f64..0.2, -0.5f64..0.5, 0.2f64..3.0),
        ) {
            let p = Params::paper();
            for existing in [e, near(&n, dx, dy, turn, scale)] {
                let placement = place_pair(&p, &n, &existing);
                let ev = placement.with_orientation(&p, 1, &existing);
                proptest::prop_assert_eq!(&ev, &evaluate_pair(&p, &n, 1, &existing));
                if !placement.could_pass() {
                    proptest::prop_assert!(
                        !ev.is_match() && !ev.is_extension() && !ev.fails_only_orientation()
                    );
                }
                if !placement.could_match() {
                    proptest::prop_assert!(!ev.is_match());
                }
            }
        }

    }
}
