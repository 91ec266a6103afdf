//! Which decisions the decisions list shows: a choice the panel offers and a command carries.

use super::inspector::outcome_name;
use super::truth::TruthView;
use crate::mapping::model::trace::DecisionTrace;
use crate::mapping::Outcome;

/// Which decisions the list shows.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum DecisionFilter {
    /// Every decision.
    #[default]
    All,
    /// Decisions with this outcome.
    Outcome(Outcome),
    /// Decisions that made or updated a segment `eval` calls spurious (with a floor plan).
    Spurious,
}

impl DecisionFilter {
    /// True when decision `d` passes; `truth` gives the verdicts on the map shown.
    pub(super) fn keeps(self, d: &DecisionTrace, truth: Option<&TruthView>) -> bool {
        match self {
            DecisionFilter::All => true,
            DecisionFilter::Outcome(o) => d.outcome == o,
            DecisionFilter::Spurious => d
                .result
                .and_then(|id| truth.and_then(|t| t.verdict(id)))
                .is_some_and(|v| !v.is_true()),
        }
    }

    /// The filter's name in the list's menu.
    pub(super) fn name(self) -> &'static str {
        match self {
            DecisionFilter::All => "All",
            DecisionFilter::Outcome(o) => outcome_name(o),
            DecisionFilter::Spurious => "Spurious",
        }
    }
}
