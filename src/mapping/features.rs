//! Point features: corners and edges found by the arc rule (docs/algorithm.md §8.5), kept in
//! the map beside its segments (docs/formats.md, the map's `features`).

use super::ids::FeatureId;
use crate::geometry::Point;
use serde::{Deserialize, Serialize};

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
    /// Where it is, world frame, metres.
    pub at: Point,
    /// The smallest range it was seen from, metres (its confidence, as an end-point's).
    pub range_m: f64,
    /// Arcs that placed it (each a cluster of one snapshot).
    pub observations: usize,
    /// Snapshot that created it.
    pub created: usize,
    /// Snapshots that moved it, in order (the most recent [`super::map::MAX_UPDATES_KEPT`]).
    pub updated: Vec<usize>,
}
