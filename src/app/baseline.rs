//! The A/B baseline: a pinned parameter set with its own replay, kept beside the current one,
//! and the comparison of the two runs (computed on a thread, [`DiffJob`]).

use super::jobs::{start_diff, DiffJob, JobPoll};
use crate::diff::{diff_step, DecisionDifference, RunDiff};
use crate::mapping::Params;
use crate::replay::{Replay, ReplayCursor, StepView};
use crate::run::Run;
use std::sync::Arc;

/// A pinned parameter set and its results.
pub(super) struct Baseline {
    pub(super) params: Params,
    pub(super) replay: Replay,
    /// Its step at the snapshot shown.
    pub(super) view: Option<StepView>,
    /// Where its last seek left the replay's mapper.
    cursor: ReplayCursor,
    /// Differences from the current parameters, when computed.
    pub(super) diff: Option<RunDiff>,
    pub(super) job: Option<DiffJob>,
}

impl Baseline {
    /// Pins `replay` (the one shown, whose step at the current snapshot is `view`).
    pub(super) fn pin(replay: Replay, view: Option<StepView>) -> Self {
        Baseline {
            params: replay.params().clone(),
            view,
            cursor: ReplayCursor::default(),
            replay,
            diff: None,
            job: None,
        }
    }

    /// Shows snapshot `k` of the baseline's replay.
    pub(super) fn seek(&mut self, k: usize) {
        self.view = self
            .replay
            .view_from(&mut self.cursor, self.view.as_ref(), k);
    }

    /// Stops the comparison being computed, if any.
    pub(super) fn cancel_job(&mut self) {
        if let Some(old) = self.job.take() {
            old.cancel();
        }
    }

    /// Starts comparing with `run` under `current` on a thread (no thread when the parameters
    /// are the same: nothing differs).
    pub(super) fn start_diff(&mut self, run: Arc<Run>, current: Params) {
        self.cancel_job();
        if self.params == current {
            self.diff = Some(RunDiff::default());
            return;
        }
        self.diff = None;
        self.job = Some(start_diff(run, self.params.clone(), current));
    }

    /// Collects the comparison when done; gives the message to show then. Asks for another
    /// frame while it runs.
    pub(super) fn poll(&mut self, ctx: &egui::Context) -> Option<String> {
        let job = self.job.as_ref()?;
        match job.poll() {
            JobPoll::Done(diff) => {
                let message = format!(
                    "{} snapshots differ from the baseline",
                    diff.snapshots.len()
                );
                self.diff = Some(diff);
                self.job = None;
                Some(message)
            }
            JobPoll::Running => {
                ctx.request_repaint();
                None
            }
            JobPoll::Stopped => {
                self.job = None;
                None
            }
        }
    }

    /// The decisions of `view` that differ from the baseline's at the same snapshot (A =
    /// baseline, B = current).
    pub(super) fn differences(&self, view: &StepView) -> Vec<DecisionDifference> {
        match &self.view {
            Some(bv) => diff_step(&bv.trace, &view.trace),
            None => Vec::new(),
        }
    }
}
