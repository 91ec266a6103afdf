//! Point features: corners and edges found by the arc rule (docs/algorithm.md §8.5), kept in
//! the map beside its segments (docs/formats.md, the map's `features`).

use crate::geometry::Point;
use crate::mapping::model::ids::FeatureId;
use serde::{Deserialize, Serialize};

/// Smallest radius of a rounded reflector, metres (2 in): below it the ranges are those of a
/// point (a corner or a sharp edge).
pub const MIN_ROUND_RADIUS_M: f64 = 0.0508;

/// Largest radius of a rounded reflector, metres (20 in, a building's column).
pub const MAX_ROUND_RADIUS_M: f64 = 0.508;

/// Readings of removed diagonals kept as evidence (the most recent ones).
pub const ROUND_EVIDENCE_KEPT: usize = 64;

/// What reflects a sonar from one point.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum FeatureKind {
    /// A concave junction of two walls (a corner reflector, seen from inside the angle).
    Corner,
    /// A convex junction or a wall's free end (a door jamb, a desk's corner).
    Edge,
}

/// A point reflector of the map.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PointFeature {
    /// Stable id (never reused in a run).
    pub id: FeatureId,
    /// Corner or edge.
    pub kind: FeatureKind,
    /// Where it is, world frame, metres (a rounded reflector's centre).
    pub at: Point,
    /// A rounded reflector's radius (a pillar, docs/algorithm.md §8.14), metres; 0 for a point
    /// reflector.
    #[serde(default, skip_serializing_if = "is_point")]
    pub radius_m: f64,
    /// The smallest range it was seen from, metres (its confidence, as an end-point's).
    pub range_m: f64,
    /// Arcs that placed it (each a cluster of one snapshot).
    pub observations: usize,
    /// Where the sensors of its first arc stood (their mean), world frame, metres.
    #[serde(default = "origin")]
    pub first_seen_from: Point,
    /// The farthest any later arc's sensors stood from `first_seen_from`, metres.
    #[serde(default)]
    pub baseline_m: f64,
    /// Snapshot that created it.
    pub created: usize,
    /// Snapshots that moved it, in order (the most recent [`crate::mapping::model::map::MAX_UPDATES_KEPT`]).
    pub updated: Vec<usize>,
}

/// How far apart, metres, the sensors of two arcs that placed a point feature must stand to
/// confirm it (8 in, one step of the paper's robot): a wall's nearest point seen at a cone's
/// edge by two sensors reads as an arc too, but it moves along the wall with the robot, while a
/// corner or an edge stays where it is, seen from anywhere. Seeing it again from the same place
/// (a lap driven back) confirms nothing.
pub const CONFIRMING_BASELINE_M: f64 = 0.2032;

fn origin() -> Point {
    Point::origin()
}

fn is_point(radius_m: &f64) -> bool {
    *radius_m == 0.0
}

impl PointFeature {
    /// A point feature of `kind` at `at`, seen once from `seen_from` by `snapshot` at range
    /// `range_m` (its id is given when the map files it).
    pub fn seen_once(
        kind: FeatureKind,
        at: Point,
        range_m: f64,
        seen_from: Point,
        snapshot: usize,
    ) -> Self {
        Self {
            id: 0,
            kind,
            at,
            radius_m: 0.0,
            range_m,
            observations: 1,
            first_seen_from: seen_from,
            baseline_m: 0.0,
            created: snapshot,
            updated: Vec::new(),
        }
    }

    /// Placed by arcs (a pillar: by evidence, §8.14) seen from [`CONFIRMING_BASELINE_M`] apart:
    /// drawn, written, counted and explaining readings. Before, it is the engine's own state.
    pub fn is_confirmed(&self) -> bool {
        self.baseline_m >= CONFIRMING_BASELINE_M
    }
}
