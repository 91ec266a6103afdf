//! What building a replay records of every step: its summary, its decisions (so that catching
//! up from a checkpoint takes them again), the segments' lineage and, now and then, the map's
//! figures against the floor plan.

use super::summary::{StepPose, StepSummary, TruthSample, TRUTH_SAMPLES};
use crate::eval::{map_verdicts, truth_figures};
use crate::lineage::Lineage;
use crate::mapping::model::trace::StepTrace;
use crate::mapping::{Mapper, Params, RecordedDecision};
use crate::run::Run;

/// The records of the steps so far.
pub(super) struct StepRecords {
    pub summaries: Vec<StepSummary>,
    /// Every step's decisions, one step after another (see [`super::Replay`]).
    pub decisions: Vec<RecordedDecision>,
    pub decisions_from: Vec<u32>,
    pub lineage: Lineage,
    pub truth_curve: Vec<TruthSample>,
    /// Every step's pose, when pose correction is on (empty otherwise).
    pub poses: Vec<StepPose>,
    /// Steps between samples of the truth curve.
    truth_every: usize,
}

impl StepRecords {
    /// Empty records for `run`, its truth curve sampled every `interval` snapshots or less
    /// often (at most [`TRUTH_SAMPLES`] times).
    pub fn new(run: &Run, interval: usize) -> Self {
        StepRecords {
            summaries: Vec::with_capacity(run.snapshots.len()),
            decisions: Vec::new(),
            decisions_from: vec![0u32],
            lineage: Lineage::default(),
            truth_curve: Vec::new(),
            poses: Vec::new(),
            truth_every: interval.max(run.snapshots.len().div_ceil(TRUTH_SAMPLES)),
        }
    }

    /// Records step `k`, whose trace is `trace`; `mapper` stands after it.
    pub fn record(
        &mut self,
        k: usize,
        trace: &StepTrace,
        mapper: &Mapper,
        run: &Run,
        params: &Params,
    ) {
        let mut summary = StepSummary::of(trace, mapper.map().segments.len());
        summary.candidates = mapper.last_step_candidates() as u32;
        if let Some(plan) = &run.floor_plan {
            summary.count_spurious_new_faces(trace, mapper.map(), plan, params);
            // The whole map against the plan costs a pass over it (times the walls): once a
            // checkpoint interval, at most TRUTH_SAMPLES times, and at the last step.
            if (k + 1).is_multiple_of(self.truth_every) || k + 1 == run.snapshots.len() {
                let map = mapper.map();
                let verdicts = map_verdicts(map, plan, params);
                let (spurious_fraction, coverage) = truth_figures(map, plan, &verdicts);
                self.truth_curve.push(TruthSample {
                    snapshot: k,
                    spurious_fraction,
                    coverage,
                });
            }
        }
        self.summaries.push(summary);
        self.poses.extend(StepPose::of(trace));
        let recorded = trace.decisions.iter();
        self.decisions
            .extend(recorded.map(|d| RecordedDecision::of(d, &trace.updates)));
        self.decisions_from
            .push(u32::try_from(self.decisions.len()).unwrap_or(u32::MAX));
        self.lineage.record(trace);
    }
}
