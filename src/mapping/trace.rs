//! The trace of one mapper step: every decision as data, with its numbers.
//! Field names are stable (they are written to `--out-trace` files); vectors are in the order
//! the engine made the decisions, so the same input always gives the same trace.

use super::map::{EndPoint, FaceId, ReadingRef, SegmentId, SupportPoint};
use crate::geometry::{Point, Pose};
use serde::{Deserialize, Serialize};

/// Why a reading was not turned into a point (docs/algorithm.md §1).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum DiscardReason {
    /// The sensor reported no echo (`null`).
    NoEcho,
    /// The range is at or beyond the sensor's maximum range, which drivers use for no echo.
    AtMaxRange,
    /// `D > d_max`.
    BeyondDMax,
    /// `D < min_range`.
    BelowMinRange,
}

/// One sensor's reading in this snapshot.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ReadingTrace {
    /// Sensor index.
    pub sensor: usize,
    /// The range read, metres (`None`: no echo).
    pub range_m: Option<f64>,
    /// The point on the beam axis at that range (also for discarded ranges, for drawing).
    pub point: Option<Point>,
    /// Uncertainty ball radius `ξ·D/100`, metres (0 without a range).
    pub ball_radius_m: f64,
    /// Why it was discarded; `None` when kept.
    pub discarded: Option<DiscardReason>,
    /// Index of the cluster it joined (kept readings only).
    pub cluster: Option<usize>,
}

/// The distance between two neighbouring kept points (docs/algorithm.md §2).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GapTrace {
    /// Sensor of the first point.
    pub from_sensor: usize,
    /// Sensor of the second point.
    pub to_sensor: usize,
    /// Distance between the points, metres.
    pub distance_m: f64,
    /// The threshold `t_gap`, metres.
    pub t_gap_m: f64,
    /// True when `distance > t_gap`: a cluster ends here.
    pub is_break: bool,
}

/// One test of the recursive fit (docs/algorithm.md §3): the farthest point of a piece.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SplitTrace {
    /// Index (in the fitted point list) of the piece's first point.
    pub first: usize,
    /// Index of the piece's last point.
    pub last: usize,
    /// Index of the farthest point from the chord (`None` for a two-point piece).
    pub farthest: Option<usize>,
    /// The farthest point itself.
    pub point: Option<Point>,
    /// Its distance to the piece's line, metres.
    pub deviation_m: f64,
    /// The split tolerance, metres.
    pub tolerance_m: f64,
    /// True when `deviation > tolerance`: the piece was split at `farthest`.
    pub split: bool,
}

/// A constant-depth group replaced by its middle reading (docs/algorithm.md §8).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ConstantDepthTrace {
    /// Sensors of the group, in cluster order.
    pub sensors: Vec<usize>,
    /// The sensor whose reading was kept.
    pub kept_sensor: usize,
}

/// A cluster of neighbouring kept points (docs/algorithm.md §2) and its fit.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ClusterTrace {
    /// Member sensors in chain order.
    pub sensors: Vec<usize>,
    /// Constant-depth groups replaced before fitting.
    pub constant_depth: Vec<ConstantDepthTrace>,
    /// The points that were fitted (after constant-depth replacement), in order.
    pub fitted: Vec<SupportPoint>,
    /// Every test of the recursive fit.
    pub splits: Vec<SplitTrace>,
    /// Indices into `StepTrace::new_segments` of the pieces.
    pub new_segments: Vec<usize>,
}

/// A group of remembered readings (docs/algorithm.md §8, point memory).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MemoryGroupTrace {
    /// The group's readings ordered along its principal axis.
    pub points: Vec<SupportPoint>,
    /// Every test of the recursive fit.
    pub splits: Vec<SplitTrace>,
    /// Pieces as `[first, last]` indices into `points`.
    pub pieces: Vec<[usize; 2]>,
    /// For each piece, the new segment it became (pieces with too few points stay in memory;
    /// stacks leave it without a segment).
    pub piece_segments: Vec<Option<usize>>,
    /// The pieces (indices into `pieces`) that were stacks: one place read at changing ranges,
    /// no line (docs/algorithm.md §8.15).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub stacks: Vec<usize>,
}

/// What point memory did in this step.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct MemoryTrace {
    /// Readings added (one-point clusters of this snapshot).
    pub added: Vec<ReadingRef>,
    /// Readings dropped because they were older than `memory_snapshots`.
    pub expired: Vec<ReadingRef>,
    /// Groups that were fitted.
    pub groups: Vec<MemoryGroupTrace>,
    /// Readings that left memory because they became part of a segment.
    pub used: Vec<ReadingRef>,
    /// Readings that left memory in a stack (docs/algorithm.md §8.15), making no segment.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub stacked: Vec<ReadingRef>,
    /// Readings kept in memory as the joints of this step's pieces (docs/algorithm.md §8.16).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub joints: Vec<ReadingRef>,
    /// Readings held after this step.
    pub held_after: usize,
}

/// Where a new segment came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SegmentSource {
    /// A piece of cluster `i` of this snapshot.
    Cluster(usize),
    /// A piece of memory group `i` of this snapshot.
    Memory(usize),
}

/// A segment fitted in this snapshot, before matching.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct NewSegmentTrace {
    /// Where it came from.
    pub source: SegmentSource,
    /// First end-point (chain order).
    pub a: EndPoint,
    /// Second end-point.
    pub b: EndPoint,
    /// Its supporting readings.
    pub points: Vec<SupportPoint>,
}

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

/// Which of the four end-points of an update (docs/algorithm.md §5).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum EndOrigin {
    /// `e_L`.
    ExistingLeft,
    /// `e_R`.
    ExistingRight,
    /// `n_L`.
    NewLeft,
    /// `n_R`.
    NewRight,
}

/// What an update did with one of the four end-points.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum EndRole {
    /// Kept as it is: it defines `l_u` (smaller range than the one it was compared with).
    Kept,
    /// Kept as the middle point `M` of an extension (defines `l_u`, not an end).
    Middle,
    /// Projected onto `l_u` (lower confidence).
    Projected,
    /// An inner end-point of an extension with less confidence than `M`: not used.
    Dropped,
}

/// The fate of one end-point in an update.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct EndPointFate {
    /// Which end-point.
    pub origin: EndOrigin,
    /// Its position and range before the update.
    pub before: EndPoint,
    /// Kept, middle or projected.
    pub role: EndRole,
    /// The end-point it was compared with (by range).
    pub compared_with: EndOrigin,
    /// Where its projection on `l_u` fell (for projected ones).
    pub projection: Option<Point>,
    /// True when it is an end of the updated segment.
    pub is_end_after: bool,
}

/// A post-update split test that failed (docs/algorithm.md §5): the points were fitted afresh.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RefitTrace {
    /// Largest distance of a supporting point to `l_u`, metres, and its tolerance.
    pub worst: Test,
    /// Every test of the fresh fit.
    pub splits: Vec<SplitTrace>,
    /// The pieces that replaced the segment (the first keeps its id).
    pub pieces: Vec<SegmentId>,
}

/// One update of a map segment (docs/algorithm.md §5).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct UpdateTrace {
    /// The updated segment.
    pub segment: SegmentId,
    /// Index into `StepTrace::new_segments`.
    pub new_segment: usize,
    /// Match (MPC) or extension (EPC).
    pub outcome: Outcome,
    /// Geometry before.
    pub before: [EndPoint; 2],
    /// Geometry after the update rule (before any refit).
    pub after: [EndPoint; 2],
    /// The two points that define `l_u`.
    pub line: [Point; 2],
    /// The four end-points and what became of each.
    pub fates: Vec<EndPointFate>,
    /// The defining points nearly coincided: `l_u` is the total-least-squares line of the four.
    pub fallback_tls: bool,
    /// The post-update split test failed and the points were refitted.
    pub refit: Option<RefitTrace>,
    /// Map segments fused into the updated one afterwards (`merge_duplicates`), in order.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub absorbed: Vec<AbsorbTrace>,
    /// Whether the segment's supporting points were found in order along the updated line
    /// before the new ones went in (`None` when that was not asked); recorded so that a replay
    /// catching up spares the pass over every point ([`UpdateRequest::support_in_order`]). Not
    /// written to trace files.
    #[serde(skip)]
    pub support_in_order: Option<bool>,
}

/// A map segment fused into an updated segment because it matched it (`merge_duplicates`,
/// an extension beyond the paper: see `mapping::merge`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct AbsorbTrace {
    /// The segment that left the map.
    pub segment: SegmentId,
    /// The segment it was fused into (the updated one, or a piece of its refit).
    pub into: SegmentId,
    /// Its end-points.
    pub ends: [EndPoint; 2],
    /// It as `l_n` against the updated segment as `l_e`: a MATCH.
    pub evaluation: PairEvaluation,
    /// The updated segment before the fusion.
    pub before: [EndPoint; 2],
    /// The updated segment after the fusion (the §5 MATCH rule).
    pub after: [EndPoint; 2],
}

/// Why correlation did not make a corner.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum InterpolationReason {
    /// The lines are within `θ_o` of parallel.
    NearlyParallel,
    /// The intersection is farther than `t_gap` from a closest end-point.
    IntersectionTooFar,
    /// Moving an end-point to the intersection would reverse a segment or shrink it to less
    /// than half its length (`corner_guard`, docs/algorithm.md §8.3).
    CornerWouldCollapse,
}

/// What correlation made of one new face.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", tag = "kind")]
pub enum CorrelationKind {
    /// Both closest end-points moved to the lines' intersection.
    Corner {
        /// The intersection.
        point: Point,
    },
    /// A connecting segment joins the closest end-points.
    Interpolated {
        /// The connecting segment's id.
        link: SegmentId,
        /// Why no corner.
        reason: InterpolationReason,
    },
    /// `d_min = 0`: the closest end-points already coincide; nothing moves, no segment is
    /// made, and the faces become one object.
    Shared {
        /// The shared end-point.
        point: Point,
    },
    /// `d_min > t_gap`: the face stays a distinct object.
    None,
}

/// Correlation of one new face (docs/algorithm.md §6).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CorrelationTrace {
    /// The new face.
    pub face: FaceId,
    /// The closest new segment and which end (0 = a, 1 = b).
    pub new_segment: Option<(SegmentId, usize)>,
    /// The closest existing segment and which end.
    pub existing_segment: Option<(SegmentId, usize)>,
    /// `d_min` against `t_gap`, metres.
    pub d_min: Option<Test>,
    /// Angle between the two lines, radians.
    pub angle_rad: Option<f64>,
    /// What was done.
    pub result: CorrelationKind,
}

/// Something the engine warns about.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", tag = "kind")]
pub enum Warning {
    /// The robot moved more than `max_step` since the last snapshot (§3.3.1).
    MaxStep {
        /// Distance moved, metres.
        step_m: f64,
        /// The limit, metres.
        max_step_m: f64,
    },
    /// The snapshot had a different number of ranges than the layout has sensors.
    RangeCount {
        /// Ranges given.
        given: usize,
        /// Sensors in the layout.
        expected: usize,
    },
}

/// Everything one step did.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct StepTrace {
    /// Snapshot index.
    pub snapshot: usize,
    /// Snapshot time, seconds.
    pub t: f64,
    /// Robot pose.
    pub pose: Option<Pose>,
    /// One record per sensor, in sensor order.
    pub readings: Vec<ReadingTrace>,
    /// Every neighbour distance in clustering order.
    pub gaps: Vec<GapTrace>,
    /// Clusters in chain order.
    pub clusters: Vec<ClusterTrace>,
    /// Point memory, when on.
    pub memory: Option<MemoryTrace>,
    /// Segments fitted in this snapshot.
    pub new_segments: Vec<NewSegmentTrace>,
    /// One decision per new segment, in order.
    pub decisions: Vec<DecisionTrace>,
    /// Updates of map segments.
    pub updates: Vec<UpdateTrace>,
    /// Correlations of new faces.
    pub correlations: Vec<CorrelationTrace>,
    /// Warnings.
    pub warnings: Vec<Warning>,
    /// Readings a confirmed point feature explained, kept out of the clusters (docs/algorithm.md
    /// §8.5).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub explained: Vec<ExplainedTrace>,
    /// Readings a confirmed wall explained, kept out of the clusters, point memory and the
    /// free-space sweep (docs/algorithm.md §8.12).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub settled: Vec<SettledTrace>,
    /// Clusters the arc rule filed as point features instead of fitting them
    /// (docs/algorithm.md §8.5).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub arcs: Vec<ArcTrace>,
    /// Segments removed because a reading saw past them (docs/algorithm.md §8.6).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub refuted: Vec<RefutedTrace>,
    /// Segments this step's readings supported as a plane (docs/algorithm.md §8.7).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub plane_support: Vec<PlaneSupportTrace>,
    /// New segments (indices into `new_segments`) the plane gate kept out of the map although
    /// their decision was NEW FACE: no reading of theirs supports them as a plane
    /// (docs/algorithm.md §8.7).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub gated: Vec<usize>,
    /// New segments whose readings were moved to where one plane's echoes came from
    /// (docs/algorithm.md §8.10).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub echo_fits: Vec<EchoFitTrace>,
    /// Connecting segments removed because a segment they joined left the map
    /// (docs/algorithm.md §8.3).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub dropped_links: Vec<SegmentId>,
    /// Segments removed as the diagonal of a corner of two confirmed walls
    /// (docs/algorithm.md §8.11).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub diagonals: Vec<DiagonalTrace>,
    /// Round pillars filed or moved from the readings of removed diagonals (docs/algorithm.md
    /// §8.14).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub round_reflectors: Vec<RoundTrace>,
    /// Confirmed segments a refit moved off their line, tentative again (docs/algorithm.md
    /// §8.7, `refit_unconfirms`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub unconfirmed: Vec<UnconfirmedTrace>,
}

pub use super::confirm::{PlaneSupportTrace, UnconfirmedTrace};
pub use super::corner_diagonals::DiagonalTrace;
pub use super::echo_fit::EchoFitTrace;
pub use super::free_space::RefutedTrace;
pub use super::point_features::ArcTrace;
pub use super::round_reflectors::RoundTrace;
pub use super::settled_walls::SettledTrace;

/// A reading explained by a confirmed point feature (docs/algorithm.md §8.5).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ExplainedTrace {
    /// The sensor.
    pub sensor: usize,
    /// Its range, metres.
    pub range_m: f64,
    /// The feature.
    pub feature: u32,
    /// The feature's distance from the sensor, metres.
    pub feature_distance_m: f64,
    /// The feature's angle off the beam axis, radians.
    pub off_axis_rad: f64,
}
