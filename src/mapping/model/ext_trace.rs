//! What the extensions (docs/algorithm.md §8) record in a step's trace
//! (docs/formats.md §8): plain values, apart from the rules that make them.

use crate::geometry::{Point, Vec2};
use crate::mapping::model::ids::SegmentId;
use crate::mapping::model::support::{ReadingRef, SupportPoint};
use crate::mapping::model::trace::fitting::SplitTrace;
use serde::{Deserialize, Serialize};

/// Two readings of distinct snapshots that support a segment as a plane, their sensors
/// displaced along it (docs/algorithm.md §8.7, baseline confirmation).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct BaselinePair {
    /// The two readings, the earlier snapshot first.
    pub readings: [ReadingRef; 2],
    /// How far the second sensor stood from the first along the segment, metres.
    pub along_m: f64,
    /// How far across it (along its normal), metres.
    pub across_m: f64,
}

/// A line fitted from the ranges: the points `x` with `normal · x = offset_m`, the sensors on
/// the side `normal · x < offset_m`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct EchoLine {
    /// Unit normal, pointing from the sensors towards the line.
    pub normal: Vec2,
    /// Offset along the normal, metres.
    pub offset_m: f64,
    /// The largest |predicted − read| range over the readings, in units of each reading's
    /// tolerance (`max(ξ·D/100, 1 in)`); at most 1 for an accepted fit.
    pub worst_residual_over_tolerance: f64,
}

/// A segment that gained plane support this step, for the trace.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PlaneSupportTrace {
    /// The segment.
    pub segment: SegmentId,
    /// The sensor whose reading supported it.
    pub sensor: usize,
    /// The reading, metres.
    pub range_m: f64,
    /// The perpendicular distance from the sensor to its line, metres.
    pub distance_m: f64,
    /// Snapshots supporting it now.
    pub snapshots: u32,
    /// Whether it is confirmed now.
    pub confirmed: bool,
    /// When it was confirmed by two poses of one step (docs/algorithm.md §8.7, baseline
    /// confirmation): the two readings and how far apart their sensors stood.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub baseline: Option<BaselinePair>,
    /// When the reading did not count: how far the robot stood from where it stood at the last
    /// view that did, metres, under `confirm_spacing` (the same view, docs/algorithm.md §8.7).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub same_view_moved_m: Option<f64>,
    /// When the reading did not count: it heard the segment only off its cone's edge, and the
    /// segment is turned this far from the map's axes, degrees, more than `θ_o`
    /// (`off_axis_square_on`, docs/algorithm.md §8.7).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub off_axis_deg: Option<f64>,
}

/// A segment that a refit (§5) moved off its line: a confirmed one lost its confirmation
/// (`refit_unconfirms`), a tentative one the support counted for its old line
/// (`refit_recounts`; docs/algorithm.md §8.7).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct UnconfirmedTrace {
    /// The segment (the refit's first piece, which keeps the id).
    pub segment: SegmentId,
    /// Its end-points before the update and after the refit.
    pub before: [Point; 2],
    /// After the refit.
    pub after: [Point; 2],
    /// The angle it turned, radians.
    pub turn_rad: f64,
    /// The distances of its new end-points from the old line, metres.
    pub off_line_m: [f64; 2],
    /// Their limits, `2·tol(D)` with `D` each end-point's range, metres.
    pub limits_m: [f64; 2],
    /// The segment was tentative: the support counted for its old line was dropped
    /// (`refit_recounts`); otherwise it was confirmed and is tentative again.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub tentative: bool,
}

impl PlaneSupportTrace {
    /// The record of `sensor`'s reading `range_m` supporting `segment` at `distance_m`, which
    /// now has `support`'s views; no baseline, and counted unless a field set after says not.
    pub fn new(
        segment: SegmentId,
        sensor: usize,
        range_m: f64,
        distance_m: f64,
        support: &crate::mapping::model::plane_supports::PlaneSupport,
    ) -> Self {
        Self {
            segment,
            sensor,
            range_m,
            distance_m,
            snapshots: support.snapshots,
            confirmed: support.confirmed(),
            baseline: None,
            same_view_moved_m: None,
            off_axis_deg: None,
        }
    }
}

/// A segment removed as a corner's diagonal, for the trace.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DiagonalTrace {
    /// The segment removed.
    pub segment: SegmentId,
    /// Its end-points when it left.
    pub ends: [Point; 2],
    /// The two walls of the corner (one of them, at least, confirmed).
    pub walls: [SegmentId; 2],
    /// The junction: where the walls' lines meet.
    pub junction: Point,
    /// Distances of the segment's two end-points from the junction, metres.
    pub end_distances_m: [f64; 2],
    /// The segment's angles to the two walls, radians.
    pub angles_rad: [f64; 2],
    /// The angle between the two walls, radians.
    pub corner_angle_rad: f64,
}

/// What echo placement did to one new segment, for the trace.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct EchoFitTrace {
    /// The new segment (index into the step's new segments; for a dropped piece, the index it
    /// would have had).
    pub new_segment: usize,
    /// The piece did not become a segment: its ranges fit one reflector point better than the
    /// line (`reflector`), or most of its echo points lie behind confirmed walls.
    #[serde(default)]
    pub dropped: bool,
    /// The reflector point (a corner or an edge) whose ranges fit better than the line's; it
    /// was filed as a point feature.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reflector: Option<Point>,
    /// The fitted line.
    pub line: EchoLine,
    /// Readings whose echo came from inside the cone (the foot of the perpendicular).
    pub at_foot: usize,
    /// Readings whose echo came from the cone's edge (an oblique, rough wall).
    pub at_cone_edge: usize,
    /// The largest distance a reading moved from its beam axis, metres.
    pub moved_max_m: f64,
    /// Readings whose echo point lies behind a confirmed wall, which their sound would have
    /// met first ([`echo_behind_confirmed_wall`](crate::mapping::ext::echo_fit::echo_behind_confirmed_wall)); more than half, and the piece is dropped.
    #[serde(default)]
    pub behind_confirmed_wall: usize,
}

/// A segment a reading refuted, for the trace.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RefutedTrace {
    /// The segment removed.
    pub segment: SegmentId,
    /// The sensor whose reading refuted it.
    pub sensor: usize,
    /// The reading, metres.
    pub range_m: f64,
    /// The perpendicular distance from the sensor to the segment, metres.
    pub distance_m: f64,
    /// The perpendicular's angle off the beam axis, radians.
    pub off_axis_rad: f64,
}

/// A segment part a reading saw through, cut away (docs/algorithm.md §8.18), for the trace.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SeenThroughTrace {
    /// The segment cut.
    pub segment: SegmentId,
    /// The sensor whose reading saw through it.
    pub sensor: usize,
    /// The reading, metres.
    pub range_m: f64,
    /// Where the part seen through begins and ends on the segment, metres.
    pub free_part: [[f64; 2]; 2],
    /// What became of the segment.
    pub cut: SeenThroughCut,
    /// Supporting readings dropped with the part cut away.
    pub dropped_points: usize,
}

/// What a reading that saw through part of a segment did to it (docs/algorithm.md §8.18).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SeenThroughCut {
    /// End `a` moved to the free part's edge.
    EndA,
    /// End `b` moved to the free part's edge.
    EndB,
    /// The free part left a hole: the part beyond it is now this segment.
    Split {
        /// The new segment: the part from the hole to `b`.
        piece: SegmentId,
    },
    /// Nothing of it was left that is long enough (or held two readings).
    Removed,
}

/// What the arc rule found in one cluster, for the trace.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ArcTrace {
    /// The cluster (index into the step's clusters).
    pub cluster: usize,
    /// The sensors of the cluster's readings, in chain order.
    pub sensors: Vec<usize>,
    /// Smallest and largest range, metres.
    pub range_min_m: f64,
    /// Largest range, metres.
    pub range_max_m: f64,
    /// The reflector point placed, world frame.
    pub at: Point,
    /// The feature it was filed under (made or moved).
    pub feature: u32,
    /// True when the feature is new.
    pub new_feature: bool,
    /// One plane explains the ranges at least as well as the reflector point (a wall seen
    /// square-on reads so too): the cluster is fitted as well (docs/algorithm.md §8.5).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub also_fitted: bool,
}

/// A pillar filed (or moved) from the evidence, for the trace.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RoundTrace {
    /// The feature.
    pub feature: u32,
    /// The fitted centre, world frame, metres.
    pub centre: Point,
    /// The fitted radius, metres.
    pub radius_m: f64,
    /// Readings of evidence it explained.
    pub readings: usize,
    /// How far apart their sensors stood, metres (at most).
    pub baseline_m: f64,
}

/// A reading a confirmed wall explained, kept out of the clusters, for the trace.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SettledTrace {
    /// The sensor.
    pub sensor: usize,
    /// Its range, metres.
    pub range_m: f64,
    /// The confirmed wall that explains it.
    pub segment: SegmentId,
    /// The range the wall predicts for the beam (its echo point's distance), metres.
    pub predicted_m: f64,
    /// The echo point's distance from the nearer end of the wall, or of the chain of confirmed
    /// pieces that continue it (docs/algorithm.md §8.12), metres.
    pub inside_m: f64,
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
    /// Where the axis order was cut before the fit (indices into `points`): each starts a run
    /// whose first reading lies more than `memory_gap` from the one before (docs/algorithm.md
    /// §8.1).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub cuts: Vec<usize>,
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

/// What a confirmed target explained in a step's pose correction (docs/algorithm.md §8.17).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CorrectionTarget {
    /// A confirmed wall.
    Wall(SegmentId),
    /// A confirmed point feature.
    Feature(crate::mapping::model::ids::FeatureId),
}

/// One reading a pose correction used.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct CorrectionReading {
    /// The sensor.
    pub sensor: usize,
    /// What explained it.
    pub target: CorrectionTarget,
    /// Read minus predicted range at the predicted pose, metres.
    pub residual_before_m: f64,
    /// The same at the corrected pose, metres.
    pub residual_after_m: f64,
    /// The range's standard deviation (its tolerance), metres.
    pub sigma_m: f64,
    /// The validation gate the residual was kept within, metres: the tolerance widened by
    /// the predicted pose's uncertainty (docs/algorithm.md §8.17, *Association*). Traces
    /// written before it read as 0.
    #[serde(default)]
    pub gate_m: f64,
}

/// A direction of the pose (x, y in metres, heading in radians scaled by 1 m) and how much the
/// step's readings say of it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ObservedDirection {
    /// Unit vector in (x, y, heading).
    pub direction: [f64; 3],
    /// The readings' information along it (1/m²).
    pub information: f64,
    /// Whether the readings say more of it than the prior does.
    pub observed: bool,
}

/// Why a step's pose was not corrected (it kept the prediction).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", tag = "reason")]
pub enum CorrectionRefusal {
    /// The first step anchors the map.
    FirstStep,
    /// Fewer readings than needed were explained by the confirmed map.
    TooFewReadings {
        /// Readings explained.
        matched: usize,
        /// Readings needed.
        needed: usize,
    },
    /// The correction went beyond its bound (three standard deviations of the prediction).
    BeyondBound {
        /// How far it would have moved the robot, metres.
        shift_m: f64,
        /// How far it would have turned it, degrees.
        turn_deg: f64,
    },
    /// The corrected pose explained the readings no better than the prediction.
    NoBetter,
    /// The robot stood still since the last mapped snapshot: its pose stays where that step
    /// put it (docs/algorithm.md §8.19).
    StoodStill,
}

/// A step whose robot stood still since the last mapped snapshot: its readings were set aside
/// (docs/algorithm.md §8.19).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct StandstillTrace {
    /// The last snapshot that was mapped.
    pub since_snapshot: usize,
    /// How far the odometry moved since it, metres.
    pub moved_m: f64,
    /// How far it turned since it, radians (absolute).
    pub turned_rad: f64,
}

/// A step's pose correction against the confirmed map (docs/algorithm.md §8.17).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CorrectionTrace {
    /// The snapshot's odometry pose.
    pub odometry: crate::geometry::Pose,
    /// The pose the last correction and the odometry's increment predict.
    pub predicted: crate::geometry::Pose,
    /// The pose the step used: the corrected one, or the prediction when refused.
    pub corrected: crate::geometry::Pose,
    /// The readings used, with what explained them.
    pub readings: Vec<CorrectionReading>,
    /// RMS of the residuals over their sigmas at the prediction and at the corrected pose.
    pub rms_before: f64,
    /// See `rms_before`.
    pub rms_after: f64,
    /// The prediction's standard deviations (x m, y m, heading deg): the prior's weight.
    pub prior_sigma: [f64; 3],
    /// The corrected pose's standard deviations (x m, y m, heading deg).
    pub posterior_sigma: [f64; 3],
    /// The directions the readings observed, strongest first.
    pub directions: Vec<ObservedDirection>,
    /// Why the pose kept the prediction, if it did.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub refused: Option<CorrectionRefusal>,
    /// The heading the wall windows observed (`heading_window`), if any line counted.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub heading: Option<HeadingObservation>,
    /// The odometry's drift as estimated after the step (`heading_correction` alone).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub drift: Option<DriftEstimate>,
}

/// The odometry's heading error and its causes, as `heading_correction` estimates them from the
/// walls' axes (docs/algorithm.md §8.17).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct DriftEstimate {
    /// The odometry's heading minus the map's, degrees (the correction turns the pose by its
    /// negative).
    pub heading_error_deg: f64,
    /// Its standard deviation, degrees.
    pub sigma_deg: f64,
    /// Its systematic growth per metre driven, degrees (unequal wheel diameters).
    pub deg_per_m: f64,
    /// Its systematic growth per turn, percent of the angle turned (a wrong wheelbase).
    pub turn_pct: f64,
    /// Whether the drift has been significant, so that the heading is corrected.
    pub drifting: bool,
    /// In a second pass (`calibrate_first`), the heading error the first pass found at this
    /// snapshot, smoothed over its whole run, degrees: the correction taken instead of
    /// `heading_error_deg`. Absent otherwise.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tracked_deg: Option<f64>,
}

/// The heading the lines of the sensors' wall windows observe (docs/algorithm.md §8.17).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct HeadingObservation {
    /// The map's axis, degrees in [0, 90).
    pub axis_deg: f64,
    /// The lines' deviation from the nearer axis at the prediction, degrees (the correction
    /// would turn the pose by about its negative).
    pub deviation_deg: f64,
    /// The deviation at the corrected pose, degrees.
    pub deviation_after_deg: f64,
    /// The deviation's standard deviation, degrees.
    pub sigma_deg: f64,
    /// The sensors whose windows gave a line this step (a line beyond the gate counts for
    /// nothing); for the walls' windows, the sensor of each line's newest echo.
    pub sensors: Vec<usize>,
    /// With `wall_windows`, when the lines are the walls' windows' (no sensor's window gave
    /// one): those walls, in the order of `sensors`. Absent for the sensors' windows.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub walls: Vec<SegmentId>,
    /// With `open_windows`, true when the lines are the sensors' open windows' (readings no
    /// confirmed wall settled; neither the sensors' windows of settled readings nor the
    /// walls' gave one). Absent when false.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub open: bool,
    /// The gate, degrees, when a line beyond 5° counted through it: the heading's uncertainty
    /// widens it (after a turn, lines of 12 readings or more up to three of its standard
    /// deviations off, at most 20°). Absent when every line that counted was within 5°.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub widened_gate_deg: Option<f64>,
    /// With `heading_correction` alone: how far the odometry drove (metres) and turned
    /// (degrees) since the lines' readings were read, on average; the lines observe the
    /// heading error of that moment (docs/algorithm.md §8.17, *Line age*). Absent otherwise.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lines_age: Option<HeadingLinesAge>,
}

/// How long ago, as the odometry counts, a step's heading lines were read on average (the
/// trace's form of [`crate::mapping::ext::rectilinear_heading::LineAge`], in degrees).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct HeadingLinesAge {
    /// Distance driven since, metres.
    pub driven_m: f64,
    /// Turn since, degrees, counter-clockwise positive.
    pub turned_deg: f64,
}
