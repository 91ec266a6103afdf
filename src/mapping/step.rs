//! What one step of the [`crate::mapping::Mapper`] works with besides the map: the buffers it
//! fills and the next step reuses, what §3 made of the clusters, and the faces made.

use crate::geometry::Point;
use crate::mapping::ext::memory_linkage::Linkage;
use crate::mapping::ext::settled_walls::NearWall;
use crate::mapping::model::ids::{FaceId, FeatureId};
use crate::mapping::model::map::{SegmentId, SupportPoint};
use crate::mapping::model::support::ReadingRef;
use crate::mapping::model::trace::{CandidateTrace, NewSegmentTrace, SegmentSource, SplitTrace};
use crate::mapping::paper::cluster::Clusters;
use crate::mapping::paper::matching::Candidate;
use std::ops::Range;

/// Buffers one step fills and the next reuses, so that an untraced step allocates little. What
/// the trace keeps is copied out of them (or built in its own vectors) only when tracing.
#[derive(Clone, Debug, Default)]
pub(in crate::mapping) struct StepBuffers {
    /// The kept points.
    pub(in crate::mapping) kept: Vec<SupportPoint>,
    pub(in crate::mapping) clusters: Clusters,
    /// The confirmed walls near a reading (§8.12, scratch).
    pub(in crate::mapping) near_walls: Vec<NearWall>,
    /// Point memory's linkage (§8.1, scratch).
    pub(in crate::mapping) linkage: Linkage,
    /// The wall that settled each sensor's last settled reading (§8.12), tried first.
    pub(in crate::mapping) settled_by: Vec<Option<SegmentId>>,
    /// This step's settled readings (§8.12): sensor and point in the map's frame.
    pub(in crate::mapping) settled_points: Vec<(usize, Point)>,
    /// With `open_windows` (§8.17): the step's kept readings no wall settled, sensor and point
    /// in the map's frame.
    pub(in crate::mapping) open_points: Vec<(usize, Point)>,
    /// With `wall_windows` (§8.17): each settled reading's wall, sensor and echo point (where
    /// the wall's echo came from, at the measured range) in the map's frame.
    pub(in crate::mapping) settled_echoes: Vec<(SegmentId, usize, Point)>,
    /// This step's settled readings themselves, with `trim_seen_through` (§8.18: a settled
    /// reading that looked into an opening still sees through the walls' ends beside it).
    pub(in crate::mapping) settled_readings: Vec<SupportPoint>,
    /// A cluster's points as fitted (untraced).
    pub(in crate::mapping) fitted: Vec<SupportPoint>,
    /// A cluster's split tests (untraced).
    pub(in crate::mapping) splits: Vec<SplitTrace>,
    /// A cluster's pieces.
    pub(in crate::mapping) pieces: Vec<[usize; 2]>,
    /// Every new segment's candidates, one set after another.
    pub(in crate::mapping) candidates: Vec<Candidate>,
    /// Each new segment's range in `candidates`.
    pub(in crate::mapping) candidate_sets: Vec<Range<usize>>,
    /// A decision's tested candidates (untraced).
    pub(in crate::mapping) mpc_stage: Vec<CandidateTrace>,
    /// The readings of earlier snapshots point memory's pieces brought to this step.
    pub(in crate::mapping) memory_readings: Vec<ReadingRef>,
    /// The confirmed point features, with where they stand and their radius (§8.5, scratch).
    pub(in crate::mapping) confirmed_features: Vec<(FeatureId, Point, f64)>,
}

/// What §3 made of a step's clusters.
pub(in crate::mapping) struct FittedStep {
    /// The new segments, in cluster order (then memory groups').
    pub(in crate::mapping) segments: Vec<NewSegmentTrace>,
    /// The points of one-point clusters, and of clusters §8.2 reduced to one (for point
    /// memory).
    pub(in crate::mapping) singles: Vec<SupportPoint>,
}

/// The faces a step makes for its NEW FACE segments: one per cluster or memory group.
#[derive(Default)]
pub(in crate::mapping) struct NewFaces {
    pub(in crate::mapping) of_source: Vec<(SegmentSource, FaceId)>,
    pub(in crate::mapping) made: Vec<FaceId>,
}
