//! The decisions of the current snapshot: outcome, new segment, existing segment and rule,
//! filterable by outcome. Clicking a row selects the new segment and centres the view on it.

use super::command::Command;
use super::decision_filter::DecisionFilter;
use super::inspector::{centre_of, outcome_name, InspectCtx};
use super::timeline::BASELINE_COLOUR;
use crate::diff::{DecisionDifference, DecisionSide, DifferenceKind};
use crate::mapping::model::trace::DecisionTrace;
use crate::mapping::{Outcome, Rule};
use crate::scene::SceneId;
use egui::RichText;

const FILTERS: [DecisionFilter; 5] = [
    DecisionFilter::All,
    DecisionFilter::Outcome(Outcome::Match),
    DecisionFilter::Outcome(Outcome::Extension),
    DecisionFilter::Outcome(Outcome::Dismissed),
    DecisionFilter::Outcome(Outcome::NewFace),
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

fn side_text(side: &DecisionSide) -> String {
    format!(
        "{}{}",
        outcome_name(side.outcome),
        side.existing.map_or(String::new(), |e| format!(" #{e}"))
    )
}

/// The note beside a decision that differs from the baseline (A = baseline, B = current).
pub fn baseline_note(d: &DecisionDifference) -> String {
    let cause = match d.cause {
        crate::diff::Cause::Direct => "direct",
        crate::diff::Cause::Consequential => "consequential",
    };
    match (d.kind, &d.a) {
        (DifferenceKind::OnlyInB, _) | (_, None) => {
            format!("≠ baseline ({cause}): not fitted under the baseline")
        }
        (_, Some(a)) => format!("≠ baseline ({cause}): was {}", side_text(a)),
    }
}

/// Draws the list. `differences` (when a baseline is pinned) are this snapshot's decisions
/// that differ from it, A = baseline, B = current.
pub fn decisions_ui(
    ui: &mut egui::Ui,
    ctx: &InspectCtx,
    filter: DecisionFilter,
    selection: SceneId,
    differences: Option<&[DecisionDifference]>,
) -> Vec<Command> {
    let mut commands = Vec::new();
    let decisions = &ctx.view.trace.decisions;
    filters_ui(ui, ctx, filter, &mut commands);
    ui.separator();
    egui::ScrollArea::vertical()
        .id_salt("decisions_scroll")
        .show(ui, |ui| {
            if decisions.is_empty() {
                let why = if ctx.view.trace.stood_still.is_some() {
                    "the robot stood still: this snapshot's readings were set aside (standstill, §8.19)"
                } else {
                    "no segment was fitted in this snapshot"
                };
                ui.label(RichText::new(why).weak());
            }
            for d in decisions.iter().filter(|d| filter.keeps(d, ctx.truth)) {
                let selected = matches!(selection, SceneId::NewSegment(i) if i == d.new_segment);
                let differs = differences.and_then(|all| {
                    all.iter()
                        .find(|x| x.b.is_some_and(|b| b.new_segment == d.new_segment))
                });
                let text = match differs {
                    Some(x) => {
                        RichText::new(format!("{}   {}", decision_row_text(d), baseline_note(x)))
                            .color(BASELINE_COLOUR)
                    }
                    None => RichText::new(decision_row_text(d)),
                };
                if ui.selectable_label(selected, text).clicked() {
                    let id = SceneId::NewSegment(d.new_segment);
                    commands.push(Command::Select(id));
                    if let Some(p) = centre_of(ctx.view, id) {
                        commands.push(Command::CenterOn(p));
                    }
                }
            }
            for x in differences
                .unwrap_or_default()
                .iter()
                .filter(|x| x.kind == DifferenceKind::OnlyInA)
            {
                if let Some(a) = &x.a {
                    ui.label(
                        RichText::new(format!(
                            "≠ baseline only: n{} {} (not fitted now)",
                            a.new_segment,
                            side_text(a)
                        ))
                        .color(BASELINE_COLOUR)
                        .italics(),
                    );
                }
            }
            if let Some(all) = differences {
                if all.is_empty() && !decisions.is_empty() {
                    ui.label(RichText::new("= baseline: every decision is the same").weak());
                }
            }
        });
    commands
}

/// The list's title and its filters, each with its count.
fn filters_ui(
    ui: &mut egui::Ui,
    ctx: &InspectCtx,
    filter: DecisionFilter,
    commands: &mut Vec<Command>,
) {
    let decisions = &ctx.view.trace.decisions;
    ui.horizontal_wrapped(|ui| {
        ui.label(RichText::new(format!("Decisions ({})", decisions.len())).strong());
        // "Spurious" only with a floor plan to judge by.
        let spurious = ctx.truth.map(|_| DecisionFilter::Spurious);
        for f in FILTERS.into_iter().chain(spurious) {
            let count = decisions.iter().filter(|d| f.keeps(d, ctx.truth)).count();
            let label = ui.selectable_label(filter == f, format!("{} {count}", f.name()));
            let label = if f == DecisionFilter::Spurious {
                label.on_hover_text(
                    "Decisions that made or updated a segment eval calls spurious (on no wall \
                 of the floor plan)",
                )
            } else {
                label
            };
            if label.clicked() {
                commands.push(Command::FilterDecisions(f));
            }
        }
    });
}
