//! The inspector: everything the trace says about the selection, one file per kind of
//! selection. A new segment shows its cluster, the fitting splits and the table of every
//! candidate with the three tests; a map segment shows its history, its update fates in this
//! step and "compare with…"; a reading shows sensor, pose, range, point and ball. It only reads
//! the trace (docs/architecture.md: the trace is data); "compare with…" calls the engine's own
//! `evaluate_pair`.
//!
//! Files: `overview` (nothing selected, the robot, the floor plan), `reading`, `segment` (a
//! cluster and its new segments), `decision` (candidates, baseline, outcome), `map_segment`
//! (a map segment or update, "compare with…"), `correlation`, `correction` (the step's pose
//! correction); `context` (what the pages
//! read), `widgets` and `names` are shared.

mod context;
mod correction;
mod correlation;
mod decision;
mod extensions;
mod map_segment;
mod names;
mod overview;
mod reading;
mod segment;
mod widgets;

pub use context::{CompareState, InspectCtx};
pub use names::{describe_id, outcome_name};

use super::command::Command;
use crate::geometry::Point;
use crate::replay::StepView;
use crate::scene::SceneId;

/// Draws the inspector for `selection`.
pub fn inspector_ui(
    ui: &mut egui::Ui,
    ctx: &InspectCtx,
    selection: SceneId,
    compare: &CompareState,
) -> Vec<Command> {
    let mut commands = Vec::new();
    match selection {
        SceneId::None => {
            overview::nothing_ui(ui, ctx, &mut commands);
        }
        SceneId::NewSegment(i) | SceneId::Decision { new_segment: i, .. } => {
            segment::new_segment_ui(ui, ctx, i, &mut commands)
        }
        SceneId::MapSegment(id) | SceneId::Update(id) => {
            map_segment::map_segment_ui(ui, ctx, id, compare, &mut commands)
        }
        SceneId::Reading { snapshot, sensor } => {
            reading::reading_ui(ui, ctx, snapshot, sensor, &mut commands)
        }
        SceneId::Cluster(c) => segment::cluster_ui(ui, ctx, c, &mut commands),
        SceneId::Correlation(c) => correlation::correlation_ui(ui, ctx, c),
        SceneId::Robot => overview::robot_ui(ui, ctx, &mut commands),
        SceneId::FloorPlan => overview::floor_plan_ui(ui),
    }
    commands
}

/// The hover text of a scene id (the map view's tooltip).
pub fn hover_text(ctx: &InspectCtx, id: SceneId) -> Option<String> {
    match id {
        SceneId::Reading { snapshot, sensor } => reading::reading_hover(ctx, snapshot, sensor),
        SceneId::MapSegment(sid) | SceneId::Update(sid) => map_segment::map_segment_hover(ctx, sid),
        SceneId::NewSegment(i) | SceneId::Decision { new_segment: i, .. } => {
            segment::new_segment_hover(ctx, id, i)
        }
        SceneId::Cluster(c) => segment::cluster_hover(ctx, c),
        SceneId::Correlation(c) => correlation::correlation_hover(ctx, c),
        SceneId::Robot => overview::robot_hover(ctx),
        SceneId::FloorPlan => Some("floor plan (ground truth)".to_owned()),
        SceneId::None => None,
    }
}

/// The mid-point of what `id` shows, for centring the view (metres).
pub fn centre_of(view: &StepView, id: SceneId) -> Option<Point> {
    match id {
        SceneId::NewSegment(i) | SceneId::Decision { new_segment: i, .. } => {
            let s = view.trace.new_segments.get(i)?;
            Some(nalgebra::center(&s.a.point, &s.b.point))
        }
        SceneId::MapSegment(s) | SceneId::Update(s) => view
            .map_after
            .segment(s)
            .or_else(|| view.map_before.segment(s))
            .map(|s| s.mid()),
        _ => None,
    }
}
