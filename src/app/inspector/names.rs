//! Human names of the trace's enums and of scene ids, shared by the inspector's pages, the
//! decision list and the app's messages.

use crate::mapping::model::trace::DiscardReason;
use crate::mapping::{Outcome, Rule};
use crate::scene::SceneId;

/// Human name of an outcome.
pub fn outcome_name(o: Outcome) -> &'static str {
    match o {
        Outcome::Match => "Match",
        Outcome::Extension => "Extension",
        Outcome::Dismissed => "Dismissed",
        Outcome::NewFace => "New face",
    }
}

/// Human name of a rule.
pub fn rule_name(r: Rule) -> &'static str {
    match r {
        Rule::MidPointOverlap => "orientation, colinearity and mid-point check (MPC) passed",
        Rule::Containment => "orientation, colinearity passed and l_n contains l_e",
        Rule::EndPointOverlap => {
            "orientation, colinearity and end-point check (EPC) passed on an outermost segment"
        }
        Rule::OrientationOnlyFailure => "a candidate failed only the orientation test",
        Rule::NoCandidatePassed => "candidates were tested and none passed",
        Rule::NoCandidates => "the map had no candidate",
    }
}

pub(super) fn reason_name(r: DiscardReason) -> &'static str {
    match r {
        DiscardReason::NoEcho => "no echo",
        DiscardReason::AtMaxRange => "at the sensor's maximum range (no echo)",
        DiscardReason::BeyondDMax => "beyond d_max",
        DiscardReason::BelowMinRange => "below min_range",
        DiscardReason::ShorterThanLast => "much shorter than the sensor's last echo (§8.21)",
    }
}

/// A short name of a scene id, for messages.
pub fn describe_id(id: SceneId) -> String {
    match id {
        SceneId::None => "nothing".to_owned(),
        SceneId::Robot => "the robot".to_owned(),
        SceneId::FloorPlan => "the floor plan".to_owned(),
        SceneId::Reading { snapshot, sensor } => format!("reading {snapshot}/{sensor}"),
        SceneId::Cluster(i) => format!("cluster {i}"),
        SceneId::NewSegment(i) | SceneId::Decision { new_segment: i, .. } => {
            format!("new segment n{i}")
        }
        SceneId::MapSegment(id) | SceneId::Update(id) => format!("segment #{id}"),
        SceneId::Correlation(i) => format!("correlation {i}"),
    }
}
