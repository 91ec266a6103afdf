//! The step itself: the page with nothing selected (the parameters and the step's warnings),
//! the robot and the floor plan.

use super::context::InspectCtx;
use super::widgets::{heading, kv, FAIL};
use crate::app::command::Command;
use egui::RichText;

/// The page with nothing selected.
pub(super) fn nothing_ui(ui: &mut egui::Ui, ctx: &InspectCtx, commands: &mut Vec<Command>) {
    heading(ui, "Inspector");
    ui.label("Click something in the map, or a decision in the list above.");
    let p = ctx.params;
    ui.label(
        RichText::new(format!(
            "ξ = {} %   θ_o = {:.1}°   t_gap = {}   d_max = {}",
            p.accuracy_pct,
            p.orientation_rad.to_degrees(),
            ctx.len(p.t_gap_m),
            ctx.len(p.d_max_m)
        ))
        .weak(),
    );
    warnings_ui(ui, ctx);
    standstill_ui(ui, ctx);
    super::correction::correction_ui(ui, ctx, commands);
    super::extensions::extensions_ui(ui, ctx);
}

/// The floor plan's page.
pub(super) fn floor_plan_ui(ui: &mut egui::Ui) {
    heading(ui, "Floor plan");
    ui.label("Ground truth from the run log (not used by the mapper).");
}

fn warnings_ui(ui: &mut egui::Ui, ctx: &InspectCtx) {
    for w in &ctx.view.trace.warnings {
        let text = match w {
            crate::mapping::model::trace::Warning::MaxStep { step_m, max_step_m } => format!(
                "warning: the robot moved {} since the last snapshot (max_step {})",
                ctx.len(*step_m),
                ctx.len(*max_step_m)
            ),
            crate::mapping::model::trace::Warning::RangeCount { given, expected } => {
                format!("warning: {given} ranges for {expected} sensors")
            }
        };
        ui.label(RichText::new(text).color(FAIL));
    }
}

/// A step that stood still (docs/algorithm.md §8.19): why it mapped nothing.
fn standstill_ui(ui: &mut egui::Ui, ctx: &InspectCtx) {
    if let Some(still) = &ctx.view.trace.stood_still {
        ui.label(RichText::new(format!(
            "stood still since snapshot {} (moved {}, turned {:.2}°): readings set aside, no new view (standstill)",
            still.since_snapshot,
            ctx.len(still.moved_m),
            still.turned_rad.to_degrees()
        )));
    }
}

pub(super) fn robot_ui(ui: &mut egui::Ui, ctx: &InspectCtx, commands: &mut Vec<Command>) {
    heading(ui, "Robot");
    if let Some(pose) = ctx.view.trace.pose {
        egui::Grid::new("robot").num_columns(2).show(ui, |ui| {
            kv(ui, "snapshot", ctx.view.index.to_string());
            kv(ui, "t", format!("{:.2} s", ctx.view.trace.t));
            kv(ui, "position", ctx.point(&pose.position()));
            kv(
                ui,
                "heading",
                format!("{:.1}°", crate::geometry::heading_deg(pose.heading_rad)),
            );
        });
    }
    warnings_ui(ui, ctx);
    standstill_ui(ui, ctx);
    super::correction::correction_ui(ui, ctx, commands);
}

/// The robot's hover text.
pub(super) fn robot_hover(ctx: &InspectCtx) -> Option<String> {
    let p = ctx.view.trace.pose?;
    Some(format!(
        "robot at {} heading {:.1}°",
        ctx.point(&p.position()),
        crate::geometry::heading_deg(p.heading_rad)
    ))
}
