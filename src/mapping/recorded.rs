//! Decisions as a recording took them (docs/algorithm.md §4): what the replay needs to take a
//! step's decisions again without testing candidates ([`crate::mapping::Mapper::step_as_recorded`]).

use crate::mapping::model::map::SegmentId;
use crate::mapping::model::params::Params;
use crate::mapping::model::trace::{CandidateTrace, DecisionTrace, Outcome, Rule, UpdateTrace};
use crate::mapping::paper::matching::{evaluate_pair, SegmentEnds};

/// What one decision of a step was, enough to take it again without testing candidates
/// ([`Mapper::step_as_recorded`](crate::mapping::Mapper::step_as_recorded)).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RecordedDecision {
    /// The outcome.
    pub outcome: Outcome,
    /// The rule that decided it.
    pub rule: Rule,
    /// The existing segment it named.
    pub existing: Option<SegmentId>,
    /// For a MATCH or EXTENSION that updated a segment: whether the updated segment's
    /// supporting points failed the post-update test, so that it was fitted afresh
    /// (docs/algorithm.md §5). Taken again, a pass spares the test over every point.
    pub refit: Option<bool>,
    /// For an update: whether the segment's supporting points were in order along the updated
    /// line ([`UpdateTrace::support_in_order`]). Taken again, spares the pass that finds it.
    pub support_in_order: Option<bool>,
}

impl RecordedDecision {
    /// What `decision` was, with the step's `updates`.
    pub fn of(decision: &DecisionTrace, updates: &[UpdateTrace]) -> Self {
        let update = updates
            .iter()
            .find(|u| u.new_segment == decision.new_segment);
        Self {
            outcome: decision.outcome,
            rule: decision.rule,
            existing: decision.existing,
            refit: update.map(|u| u.refit.is_some()),
            support_in_order: update.and_then(|u| u.support_in_order),
        }
    }
}

/// The decision `r` recorded for new segment `new_index` (`new`), taken again: the named
/// segment (with `existing_ends`, its ends before the step) evaluated as the decision's one
/// tested candidate when it is a MATCH or an EXTENSION, which is all the update reads.
pub(super) fn recorded_decision(
    params: &Params,
    new_index: usize,
    new: &SegmentEnds,
    r: RecordedDecision,
    existing_ends: Option<SegmentEnds>,
    mut stage: Vec<CandidateTrace>,
) -> DecisionTrace {
    stage.clear();
    if let (Outcome::Match | Outcome::Extension, Some(id), Some(ends)) =
        (r.outcome, r.existing, existing_ends)
    {
        stage.push(CandidateTrace {
            distance_m: 0.0,
            outermost: r.outcome == Outcome::Extension,
            evaluation: evaluate_pair(params, new, id, &ends),
        });
    }
    DecisionTrace {
        new_segment: new_index,
        mpc_stage: stage,
        epc_stage: Vec::new(),
        outcome: r.outcome,
        rule: r.rule,
        existing: r.existing,
        result: None,
    }
}
