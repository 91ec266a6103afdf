//! Ground truth in the inspector: `eval`'s verdict on every fitted segment of the map shown,
//! and the map's spurious fraction and coverage, when the run has a floor plan. Computed once
//! per snapshot shown, with the definitions of `sonarmap eval` (one implementation:
//! [`crate::eval`]).

use crate::eval::{map_verdicts, truth_figures, Verdict};
use crate::mapping::{Params, SegmentId};
use crate::replay::StepView;
use crate::run::Run;

/// The truth of the snapshot shown.
#[derive(Clone, Debug, PartialEq)]
pub struct TruthView {
    /// The verdict on each fitted segment of the map after the step, in map order.
    pub verdicts: Vec<(SegmentId, Verdict)>,
    /// 1 − true / fitted segments.
    pub spurious_fraction: f64,
    /// Covered wall length over total wall length.
    pub coverage: f64,
}

impl TruthView {
    /// The truth of `view` under `params`; `None` when `run` has no floor plan.
    pub fn of(run: &Run, view: &StepView, params: &Params) -> Option<Self> {
        let plan = run.floor_plan.as_ref()?;
        let verdicts = map_verdicts(&view.map_after, plan, params);
        let (spurious_fraction, coverage) = truth_figures(&view.map_after, plan, &verdicts);
        Some(Self {
            verdicts,
            spurious_fraction,
            coverage,
        })
    }

    /// The status bar's text.
    pub fn summary(&self) -> String {
        format!(
            "spurious {:.0} % · coverage {:.2}",
            self.spurious_fraction * 100.0,
            self.coverage
        )
    }

    /// The verdict on segment `id`, when it is a fitted segment of the map shown.
    pub fn verdict(&self, id: SegmentId) -> Option<&Verdict> {
        self.verdicts.iter().find(|(s, _)| *s == id).map(|(_, v)| v)
    }
}
