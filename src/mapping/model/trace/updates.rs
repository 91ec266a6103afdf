//! What a step recorded of §5 and §6 (docs/algorithm.md): the updates with their end-points
//! and refits, the merges, and the correlations.

use super::decisions::*;
use super::fitting::*;
use crate::geometry::Point;
use crate::mapping::model::map::{EndPoint, FaceId, SegmentId};
use serde::{Deserialize, Serialize};

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
    /// catching up spares the pass over every point ([`UpdateRequest::support_in_order`](crate::mapping::paper::update::UpdateRequest::support_in_order)). Not
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
