//! What the replay keeps of every step: its counts ([`StepSummary`], for the timeline's marks
//! and the run plots) and, now and then, the map's figures against the floor plan
//! ([`TruthSample`]).

use crate::eval::segment_verdict;
use crate::mapping::model::trace::{Outcome, StepTrace};
use crate::mapping::{Map, Params};
use crate::run::FloorPlan;
use serde::{Deserialize, Serialize};

/// Counts of what one step did (the timeline's marks and the command line's summary).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct StepSummary {
    /// Readings kept.
    pub kept: u32,
    /// Readings discarded.
    pub discarded: u32,
    /// New segments that matched.
    pub matches: u32,
    /// New segments that extended a segment.
    pub extensions: u32,
    /// New segments dismissed.
    pub dismissals: u32,
    /// New segments kept as new faces.
    pub new_faces: u32,
    /// Correlations that made a corner or a link.
    pub correlations: u32,
    /// Warnings (max_step and others).
    pub warnings: u32,
    /// Map segments after the step.
    pub segments: u32,
    /// New faces whose segment `eval` calls spurious right after the step (with a floor plan).
    #[serde(default)]
    pub spurious_new_faces: u32,
    /// Map segments offered as candidates to the step's new segments, summed: the step's
    /// matching work.
    #[serde(default)]
    pub candidates: u32,
}

impl StepSummary {
    /// Summarises a step's trace; `segments` is the map's size after it.
    pub fn of(trace: &StepTrace, segments: usize) -> Self {
        let count = |o: Outcome| trace.decisions.iter().filter(|d| d.outcome == o).count() as u32;
        let discarded = trace
            .readings
            .iter()
            .filter(|r| r.discarded.is_some())
            .count() as u32;
        Self {
            kept: trace.readings.len() as u32 - discarded,
            discarded,
            matches: count(Outcome::Match),
            extensions: count(Outcome::Extension),
            dismissals: count(Outcome::Dismissed),
            new_faces: count(Outcome::NewFace),
            correlations: trace
                .correlations
                .iter()
                .filter(|c| {
                    !matches!(
                        c.result,
                        crate::mapping::model::trace::CorrelationKind::None
                    )
                })
                .count() as u32,
            warnings: trace.warnings.len() as u32,
            segments: segments as u32,
            spurious_new_faces: 0,
            candidates: 0,
        }
    }

    /// Counts the step's new faces that lie on no wall of `plan` in `map` (the map after the
    /// step), by `eval`'s verdict.
    pub fn count_spurious_new_faces(
        &mut self,
        trace: &StepTrace,
        map: &Map,
        plan: &FloorPlan,
        params: &Params,
    ) {
        self.spurious_new_faces = trace
            .decisions
            .iter()
            .filter(|d| d.outcome == Outcome::NewFace)
            .filter_map(|d| d.result.and_then(|id| map.segment(id)))
            .filter(|s| !segment_verdict(s, plan, params).is_true())
            .count() as u32;
    }

    /// True when the step deserves a timeline mark: a dismissal, an extension, a warning or a
    /// correlation.
    pub fn is_notable(&self) -> bool {
        self.dismissals > 0 || self.extensions > 0 || self.warnings > 0 || self.correlations > 0
    }
}

/// Most samples of the truth curve in a replay: a `paper` map of a long run holds hundreds of
/// thousands of segments, each tested against every wall.
pub const TRUTH_SAMPLES: usize = 32;

/// The map's figures against the floor plan after one step (`eval`'s spurious fraction and
/// coverage), sampled every shortest checkpoint spacing or less often (see
/// [`Replay::truth_curve`](super::Replay::truth_curve)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TruthSample {
    /// The step.
    pub snapshot: usize,
    /// 1 − true / fitted segments.
    pub spurious_fraction: f64,
    /// Covered wall length over total wall length.
    pub coverage: f64,
}

/// Where a step placed the robot with pose correction on (docs/algorithm.md §8.17), for the
/// corrected path and the correction plot; the replay keeps one per step only then.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepPose {
    /// The pose the step mapped with, metres and radians.
    pub mapped: crate::geometry::Pose,
    /// Distance from the odometry pose, metres: the drift the corrections have taken out.
    pub from_odometry_m: f32,
    /// This step's correction: distance from the predicted pose, metres.
    pub correction_m: f32,
    /// RMS of the used readings' residuals over their sigmas, at the prediction.
    pub rms_before: f32,
    /// The same at the corrected pose.
    pub rms_after: f32,
}

impl StepPose {
    /// The pose of a step whose trace carries a correction record; none without one.
    pub fn of(trace: &StepTrace) -> Option<StepPose> {
        let c = trace.correction.as_ref()?;
        let distance = |a: &crate::geometry::Pose, b: &crate::geometry::Pose| {
            (a.x - b.x).hypot(a.y - b.y) as f32
        };
        Some(StepPose {
            mapped: c.corrected,
            from_odometry_m: distance(&c.corrected, &c.odometry),
            correction_m: distance(&c.corrected, &c.predicted),
            rms_before: c.rms_before as f32,
            rms_after: c.rms_after as f32,
        })
    }
}
