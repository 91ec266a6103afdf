//! What the inspector's pages read ([`InspectCtx`], with the units' formatting), and the state
//! of "compare with…" ([`CompareState`]).

use crate::geometry::Point;
use crate::mapping::model::map::EndPoint;
use crate::mapping::model::trace::PairEvaluation;
use crate::mapping::{Params, SegmentId};
use crate::replay::StepView;
use crate::run::Run;
use crate::scene::{format_length, SceneId};
use crate::units::Units;

/// What the inspector reads.
#[derive(Clone, Copy)]
pub struct InspectCtx<'a> {
    /// The run.
    pub run: &'a Run,
    /// The step shown.
    pub view: &'a StepView,
    /// The mapping parameters.
    pub params: &'a Params,
    /// The pinned baseline's parameters and its step at the same snapshot.
    pub baseline: Option<(&'a Params, &'a StepView)>,
    /// `eval`'s verdicts on the map shown, when the run has a floor plan.
    pub truth: Option<&'a crate::app::TruthView>,
    /// Every segment's life, indexed by the replay.
    pub lineage: &'a crate::lineage::Lineage,
}

impl InspectCtx<'_> {
    pub(super) fn units(&self) -> Units {
        self.run.units
    }

    /// A length in the run's units, to about a millimetre (whole values without decimals).
    pub(super) fn len(&self, m: f64) -> String {
        let u = self.units();
        let v = u.from_m(m);
        if (v - v.round()).abs() < 1e-9 {
            return format_length(m, u);
        }
        format!("{:.*} {}", u.fine_decimals(), v, u.symbol())
    }

    pub(super) fn point(&self, p: &Point) -> String {
        let u = self.units();
        format!(
            "({:.1}, {:.1}) {}",
            u.from_m(p.x),
            u.from_m(p.y),
            u.symbol()
        )
    }

    pub(super) fn end(&self, e: &EndPoint) -> String {
        format!("{}  D = {}", self.point(&e.point), self.len(e.range_m))
    }
}

/// The state of "compare with…".
#[derive(Clone, Debug, Default, PartialEq)]
pub enum CompareState {
    /// Not comparing.
    #[default]
    Off,
    /// Waiting for the user to click the segment to compare map segment `.0` with.
    Armed(SegmentId),
    /// The three tests of `other` (as `l_n`) against `existing` (as `l_e`).
    Done {
        /// The map segment (`l_e`).
        existing: SegmentId,
        /// What it was compared with (`l_n`).
        other: SceneId,
        /// The engine's evaluation.
        eval: Box<PairEvaluation>,
    },
}
