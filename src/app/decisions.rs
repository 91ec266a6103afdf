//! The decisions of the current snapshot: outcome, new segment, existing segment and rule,
//! filterable by outcome. Clicking a row selects the new segment and centres the view on it.

use super::command::Command;
use super::inspector::{centre_of, outcome_name, InspectCtx};
use crate::mapping::trace::DecisionTrace;
use crate::mapping::{Outcome, Rule};
use crate::scene::SceneId;
use egui::RichText;

const FILTERS: [Option<Outcome>; 5] = [
    None,
    Some(Outcome::Match),
    Some(Outcome::Extension),
    Some(Outcome::Dismissed),
    Some(Outcome::NewFace),
];

fn short_rule(r: Rule) -> &'static str {
    match r {
        Rule::MidPointOverlap => "MPC",
        Rule::Containment => "containment",
        Rule::EndPointOverlap => "EPC",
        Rule::OrientationOnlyFailure => "orientation only",
        Rule::NoCandidatePassed => "none passed",
        Rule::NoCandidates => "no candidates",
    }
}

/// The text of a decision row.
pub fn decision_row_text(d: &DecisionTrace) -> String {
    format!(
        "n{}  {}  {}  ({})",
        d.new_segment,
        outcome_name(d.outcome),
        d.existing.map_or("—".to_owned(), |e| format!("#{e}")),
        short_rule(d.rule)
    )
}

/// Draws the list.
pub fn decisions_ui(
    ui: &mut egui::Ui,
    ctx: &InspectCtx,
    filter: Option<Outcome>,
    selection: SceneId,
) -> Vec<Command> {
    let mut commands = Vec::new();
    let decisions = &ctx.view.trace.decisions;
    ui.horizontal_wrapped(|ui| {
        ui.label(RichText::new(format!("Decisions ({})", decisions.len())).strong());
        for f in FILTERS {
            let count = decisions
                .iter()
                .filter(|d| f.is_none_or(|o| d.outcome == o))
                .count();
            let name = f.map_or("All", outcome_name);
            if ui
                .selectable_label(filter == f, format!("{name} {count}"))
                .clicked()
            {
                commands.push(Command::FilterDecisions(f));
            }
        }
    });
    ui.separator();
    egui::ScrollArea::vertical()
        .id_salt("decisions_scroll")
        .show(ui, |ui| {
            if decisions.is_empty() {
                ui.label(RichText::new("no segment was fitted in this snapshot").weak());
            }
            for d in decisions
                .iter()
                .filter(|d| filter.is_none_or(|o| d.outcome == o))
            {
                let selected = matches!(selection, SceneId::NewSegment(i) if i == d.new_segment);
                if ui
                    .selectable_label(selected, decision_row_text(d))
                    .clicked()
                {
                    let id = SceneId::NewSegment(d.new_segment);
                    commands.push(Command::Select(id));
                    if let Some(p) = centre_of(ctx.view, id) {
                        commands.push(Command::CenterOn(p));
                    }
                }
            }
        });
    commands
}
