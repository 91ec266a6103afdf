//! What a step recorded of §4 (docs/algorithm.md): each new segment's candidates, the tests
//! with their numbers, the outcome and the rule that decided it.

use crate::mapping::model::map::{EndPoint, SegmentId};
use serde::{Deserialize, Serialize};

/// A number compared with a threshold (inclusive: passes when `value ≤ threshold`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Test {
    /// The measured value.
    pub value: f64,
    /// The threshold.
    pub threshold: f64,
    /// `value ≤ threshold`.
    pub pass: bool,
}

impl Test {
    /// Compares `value ≤ threshold`.
    pub fn at_most(value: f64, threshold: f64) -> Self {
        Self {
            value,
            threshold,
            pass: value <= threshold,
        }
    }
}

/// The colinearity test with its terms (docs/algorithm.md §4).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ColinearityTest {
    /// `|d|` against `ξ/100·(D1 + (D2 + D3)/2)`, metres.
    pub test: Test,
    /// Range of `l_e` at the foot of the perpendicular, metres.
    pub d1_m: f64,
    /// Range of `l_n`'s left end-point, metres.
    pub d2_m: f64,
    /// Range of `l_n`'s right end-point, metres.
    pub d3_m: f64,
    /// Parameter of the foot on `l_e`, clamped to [0, 1].
    pub foot_param: f64,
}

/// The overlap test (docs/algorithm.md §4): projection parameters and the checks.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct OverlapTest {
    /// Parameter of `l_n`'s mid-point projected on `l_e`.
    pub mid_param: f64,
    /// Parameter of `l_n`'s left end-point on `l_e`.
    pub left_param: f64,
    /// Parameter of `l_n`'s right end-point on `l_e`.
    pub right_param: f64,
    /// Parameters of `l_e`'s end-points projected on `l_n` (for containment).
    pub existing_on_new_params: [f64; 2],
    /// Mid-point check: `mid_param ∈ [0, 1]`.
    pub mpc: bool,
    /// `l_n` contains `l_e` (counts as MPC).
    pub containment: bool,
    /// End-point check: one end-point of `l_n` projects inside `l_e`.
    pub epc: bool,
    /// Which end of `l_n` projected inside for EPC, when exactly one did.
    pub epc_end: Option<Side>,
}

/// Left or right end of an oriented segment.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Side {
    /// The end with the smaller projection on `l_e`'s direction.
    Left,
    /// The other end.
    Right,
}

/// The three tests for one new/existing pair, with every number (docs/algorithm.md §4).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PairEvaluation {
    /// The existing segment `l_e`.
    pub existing: SegmentId,
    /// True when `l_n` was reversed so that its left end comes first along `l_e`.
    pub new_reversed: bool,
    /// `l_n` oriented: left end-point.
    pub new_left: EndPoint,
    /// `l_n` oriented: right end-point.
    pub new_right: EndPoint,
    /// Angle between the lines modulo 180° against `θ_o`, radians.
    pub orientation: Test,
    /// Colinearity.
    pub colinearity: ColinearityTest,
    /// Overlap.
    pub overlap: OverlapTest,
}

impl PairEvaluation {
    /// Its three test results.
    pub fn tests(&self) -> PairTests<'_> {
        PairTests {
            oriented: self.orientation.pass,
            colinear: self.colinearity.test.pass,
            overlap: &self.overlap,
        }
    }

    /// A MATCH (see [`PairTests::is_match`]).
    pub fn is_match(&self) -> bool {
        self.tests().is_match()
    }

    /// An EXTENSION when the candidate is outermost (see [`PairTests::is_extension`]).
    pub fn is_extension(&self) -> bool {
        self.tests().is_extension()
    }

    /// Fails only the orientation test (see [`PairTests::fails_only_orientation`]).
    pub fn fails_only_orientation(&self) -> bool {
        self.tests().fails_only_orientation()
    }
}

/// A pair's three test results and the §4 rules on them (docs/algorithm.md §4): one definition for
/// a full evaluation and for an untraced decision, which keeps only whether orientation passed.
#[derive(Clone, Copy, Debug)]
pub struct PairTests<'a> {
    /// The orientation test passes.
    pub oriented: bool,
    /// The colinearity test passes.
    pub colinear: bool,
    /// The overlap test.
    pub overlap: &'a OverlapTest,
}

impl PairTests<'_> {
    /// Orientation, colinearity and MPC (or containment) pass: a MATCH.
    pub fn is_match(&self) -> bool {
        self.oriented && self.colinear && (self.overlap.mpc || self.overlap.containment)
    }

    /// Orientation, colinearity and EPC pass: an EXTENSION (when the candidate is outermost).
    pub fn is_extension(&self) -> bool {
        self.oriented && self.colinear && self.overlap.epc
    }

    /// Fails only the orientation test (colinearity passes, and MPC or EPC, not containment).
    pub fn fails_only_orientation(&self) -> bool {
        !self.oriented && self.colinear && (self.overlap.mpc || self.overlap.epc)
    }
}

/// A candidate tested against a new segment.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CandidateTrace {
    /// Distance from `l_n`'s mid-point to the candidate (the ordering key), metres.
    pub distance_m: f64,
    /// Holds an outermost end-point of its face (eligible for EPC).
    pub outermost: bool,
    /// The tests.
    pub evaluation: PairEvaluation,
}

/// What became of a new segment (docs/algorithm.md §4).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Outcome {
    /// All three tests with MPC: fused into the existing segment.
    Match,
    /// All three tests with EPC only: the existing segment was extended.
    Extension,
    /// Failed only the orientation test against some candidate: dropped as erroneous.
    Dismissed,
    /// Kept as a new object face.
    NewFace,
}

/// The rule that decided an outcome.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Rule {
    /// Orientation, colinearity and MPC passed.
    MidPointOverlap,
    /// Orientation, colinearity passed and `l_n` contains `l_e`.
    Containment,
    /// Orientation, colinearity and EPC passed against an outermost segment.
    EndPointOverlap,
    /// Some candidate failed only the orientation test.
    OrientationOnlyFailure,
    /// Candidates were tested and none passed.
    NoCandidatePassed,
    /// No map segment was near enough to be tested (an empty map, or every segment pruned).
    NoCandidates,
}

/// The matching decision for one new segment.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DecisionTrace {
    /// Index into `StepTrace::new_segments`.
    pub new_segment: usize,
    /// Candidates tested in the MPC stage, nearest first.
    pub mpc_stage: Vec<CandidateTrace>,
    /// Indices into `mpc_stage` of the candidates tested in the EPC stage (outermost only).
    pub epc_stage: Vec<usize>,
    /// The outcome.
    pub outcome: Outcome,
    /// The rule that decided it.
    pub rule: Rule,
    /// The existing segment matched, extended or that caused the dismissal.
    pub existing: Option<SegmentId>,
    /// The map segment that holds this new segment's information afterwards
    /// (the matched/extended segment, or the new face's segment).
    pub result: Option<SegmentId>,
}
