//! What a step recorded of §1–§3 (docs/algorithm.md): readings, gaps, clusters, splits and
//! the new segments fitted.

use crate::geometry::Point;
use crate::mapping::model::map::{EndPoint, SupportPoint};
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
    /// Much shorter than the sensor's last echo (`echo_agreement`, docs/algorithm.md §8.21).
    ShorterThanLast,
}

impl DiscardReason {
    /// Whether the sensor heard no echo (`NoEcho`, or a range at the maximum that drivers use
    /// for it); any other reason discards an echo.
    pub fn means_no_echo(self) -> bool {
        matches!(self, Self::NoEcho | Self::AtMaxRange)
    }
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
    /// Why `echo_agreement` set it aside (docs/algorithm.md §8.21): the sensor's last echo and
    /// the tolerance; `None` otherwise.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shorter_than_last: Option<ShorterThanLastTrace>,
}

/// A reading set aside as much shorter than its sensor's last echo (`echo_agreement`,
/// docs/algorithm.md §8.21).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ShorterThanLastTrace {
    /// The sensor's last echo, metres.
    pub last_m: f64,
    /// How much shorter it may be and agree, metres.
    pub tolerance_m: f64,
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
    /// True when a cluster ends here: `distance > t_gap`, or the link is across a right angle.
    pub is_break: bool,
    /// True when `right_angle_break` broke the link: the two sensors' axes lie a right angle or
    /// more apart (docs/algorithm.md §8.20).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub across_right_angle: bool,
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

/// A constant-depth group replaced by its middle reading (docs/algorithm.md §8).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ConstantDepthTrace {
    /// Sensors of the group, in cluster order.
    pub sensors: Vec<usize>,
    /// The sensor whose reading was kept.
    pub kept_sensor: usize,
}
