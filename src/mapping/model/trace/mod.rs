//! The trace of one mapper step: every decision as data, with its numbers.
//! Field names are stable (they are written to `--out-trace` files); vectors are in the order
//! the engine made the decisions, so the same input always gives the same trace.

use crate::geometry::Pose;
use crate::mapping::model::map::SegmentId;
use serde::{Deserialize, Serialize};

mod decisions;
pub(crate) mod fitting;
mod updates;

pub use decisions::*;
pub use fitting::*;
pub use updates::*;

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
    /// free-space sweep of §8.6 (docs/algorithm.md §8.12).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub settled: Vec<SettledTrace>,
    /// The robot stood still since the last mapped snapshot, and this step's readings were set
    /// aside (docs/algorithm.md §8.19).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stood_still: Option<crate::mapping::model::ext_trace::StandstillTrace>,
    /// The pose correction against the confirmed map (docs/algorithm.md §8.17).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub correction: Option<crate::mapping::model::ext_trace::CorrectionTrace>,
    /// Clusters the arc rule filed as point features instead of fitting them
    /// (docs/algorithm.md §8.5).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub arcs: Vec<ArcTrace>,
    /// Segments removed because a reading saw past them (docs/algorithm.md §8.6).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub refuted: Vec<RefutedTrace>,
    /// Segment parts cut away because a reading saw through them (docs/algorithm.md §8.18).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub seen_through: Vec<crate::mapping::model::ext_trace::SeenThroughTrace>,
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

pub use crate::mapping::model::ext_trace::{
    ArcTrace, BaselinePair, DiagonalTrace, EchoFitTrace, EchoLine, ExplainedTrace,
    MemoryGroupTrace, MemoryTrace, PlaneSupportTrace, RefutedTrace, RoundTrace, SettledTrace,
    UnconfirmedTrace,
};
