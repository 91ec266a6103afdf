//! A decision: the table of every candidate with the three tests (orientation, colinearity,
//! overlap), the same candidates under a pinned baseline, and the outcome with its rule.

use super::context::InspectCtx;
use super::names::{outcome_name, rule_name};
use super::widgets::{coloured, header_row, heading, kv, test_cells, FAIL, PASS};
use crate::app::command::Command;
use crate::app::timeline::BASELINE_COLOUR;
use crate::mapping::model::map::ReadingRef;
use crate::mapping::model::trace::{CandidateTrace, DecisionTrace, PairEvaluation};
use crate::mapping::paper::matching::{evaluate_pair, SegmentEnds};
use crate::mapping::{Params, SegmentId, StepTrace};
use crate::replay::StepView;
use crate::scene::SceneId;
use egui::RichText;

pub(super) fn decision_ui(
    ui: &mut egui::Ui,
    ctx: &InspectCtx,
    d: &DecisionTrace,
    commands: &mut Vec<Command>,
) {
    heading(ui, &format!("Candidates ({} tested)", d.mpc_stage.len()));
    if d.mpc_stage.is_empty() {
        ui.label("The map had no candidate segment.");
    } else {
        egui::ScrollArea::horizontal()
            .id_salt("candidates_scroll")
            .show(ui, |ui| candidates_table_ui(ui, ctx, d, commands));
    }
    if let Some((params, view)) = ctx.baseline {
        baseline_tests_ui(ui, ctx, d, params, view);
    }
    heading(ui, "Outcome");
    egui::Grid::new("outcome").num_columns(2).show(ui, |ui| {
        kv(
            ui,
            "outcome",
            RichText::new(outcome_name(d.outcome)).strong(),
        );
        kv(ui, "deciding rule", rule_name(d.rule));
        kv(
            ui,
            "existing",
            d.existing.map_or("-".to_owned(), |e| format!("#{e}")),
        );
        kv(
            ui,
            "result",
            d.result.map_or("-".to_owned(), |e| format!("#{e}")),
        );
    });
    if let Some(e) = d.existing {
        if ui.button(format!("Select #{e}")).clicked() {
            commands.push(Command::Select(SceneId::MapSegment(e)));
        }
    }
    flip_points_ui(ui, ctx, d);
}

/// Where each test's result would flip, for the deciding candidate and the nearest one that
/// failed, and the t_gap that would break or join the new segment's cluster
/// (`mapping::flip`): this test alone, the map as it is.
fn flip_points_ui(ui: &mut egui::Ui, ctx: &InspectCtx, d: &DecisionTrace) {
    use crate::mapping::paper::flip::{
        cluster_gap_flips, colinearity_flip_pct, orientation_flip_rad,
    };
    heading(ui, "Flip points (this test alone, the map as it is)");
    let deciding = d
        .mpc_stage
        .iter()
        .find(|c| Some(c.evaluation.existing) == d.existing);
    let failed = d
        .mpc_stage
        .iter()
        .filter(|c| Some(c.evaluation.existing) != d.existing)
        .find(|c| !c.evaluation.is_match());
    egui::Grid::new("flip_points")
        .striped(true)
        .num_columns(3)
        .show(ui, |ui| {
            header_row(ui, &["Candidate", "θ_o flips at", "ξ flips at"]);
            for (role, c) in [("deciding", deciding), ("nearest failed", failed)] {
                let Some(c) = c else { continue };
                let e = &c.evaluation;
                ui.label(format!("#{} ({role})", e.existing));
                ui.label(format!("{:.2}°", orientation_flip_rad(e).to_degrees()));
                ui.label(format!("{:.3} %", colinearity_flip_pct(&e.colinearity)));
                ui.end_row();
            }
        });
    let trace = &ctx.view.trace;
    let cluster = trace
        .clusters
        .iter()
        .find(|c| c.new_segments.contains(&d.new_segment));
    if let Some(cluster) = cluster {
        let (inner, ends) = cluster_gap_flips(cluster, &trace.gaps);
        let mut parts = Vec::new();
        if let Some(g) = inner {
            parts.push(format!("breaks below t_gap = {}", ctx.len(g)));
        }
        for g in ends.iter().flatten() {
            parts.push(format!("joins a neighbour at t_gap = {}", ctx.len(*g)));
        }
        if !parts.is_empty() {
            ui.label(format!("Its cluster {}.", parts.join("; ")));
        }
    }
}

/// The readings of new segment `i` of `trace`, sorted (how A/B pairs segments).
fn readings_of(trace: &StepTrace, i: usize) -> Vec<ReadingRef> {
    let mut r: Vec<ReadingRef> = trace
        .new_segments
        .get(i)
        .map(|s| s.points.iter().map(|p| p.reading).collect())
        .unwrap_or_default();
    r.sort_unstable();
    r.dedup();
    r
}

fn short_eval(e: &PairEvaluation) -> (String, bool) {
    let overlap = e.overlap.mpc || e.overlap.containment || e.overlap.epc;
    let mark = |p: bool| if p { "pass" } else { "FAIL" };
    let all = e.orientation.pass && e.colinearity.test.pass && overlap;
    (
        format!(
            "θ {} {:.1}°  col {}  ovl {}",
            mark(e.orientation.pass),
            e.orientation.value.to_degrees(),
            mark(e.colinearity.test.pass),
            mark(overlap)
        ),
        all,
    )
}

/// The same candidates' tests under the pinned baseline, beside the current ones. The new
/// segment is paired with the baseline's by its readings; each candidate is evaluated under
/// the baseline's parameters against the baseline map's segment with the same id.
fn baseline_tests_ui(
    ui: &mut egui::Ui,
    ctx: &InspectCtx,
    d: &DecisionTrace,
    bparams: &Params,
    bview: &StepView,
) {
    heading(ui, "Against the baseline");
    let readings = readings_of(&ctx.view.trace, d.new_segment);
    let paired =
        (0..bview.trace.new_segments.len()).find(|&j| readings_of(&bview.trace, j) == readings);
    let bdecision = paired.and_then(|j| bview.trace.decisions.iter().find(|b| b.new_segment == j));
    ui.label(match bdecision {
        Some(b) => RichText::new(format!(
            "baseline: n{} {} {} ({})  —  now: {} {}",
            b.new_segment,
            outcome_name(b.outcome),
            b.existing.map_or("-".to_owned(), |e| format!("#{e}")),
            rule_name(b.rule),
            outcome_name(d.outcome),
            d.existing.map_or("-".to_owned(), |e| format!("#{e}")),
        ))
        .color(if b.outcome == d.outcome && b.existing == d.existing {
            ui.visuals().text_color()
        } else {
            BASELINE_COLOUR
        }),
        None => RichText::new("the baseline did not fit this segment (same readings)")
            .color(BASELINE_COLOUR),
    });
    let new_ends = match paired.and_then(|j| bview.trace.new_segments.get(j)) {
        Some(s) => SegmentEnds { a: s.a, b: s.b },
        None => {
            let s = &ctx.view.trace.new_segments[d.new_segment];
            SegmentEnds { a: s.a, b: s.b }
        }
    };
    let mut ids: Vec<SegmentId> = d.mpc_stage.iter().map(|c| c.evaluation.existing).collect();
    if let Some(b) = bdecision {
        for c in &b.mpc_stage {
            if !ids.contains(&c.evaluation.existing) {
                ids.push(c.evaluation.existing);
            }
        }
    }
    egui::ScrollArea::horizontal()
        .id_salt("baseline_scroll")
        .show(ui, |ui| {
            egui::Grid::new("baseline_tests")
                .striped(true)
                .num_columns(3)
                .show(ui, |ui| {
                    header_row(ui, &["Candidate", "now", "baseline"]);
                    for id in ids {
                        baseline_row_ui(ui, d, id, bparams, bview, &new_ends);
                    }
                });
        });
    ui.label(
        RichText::new(format!(
            "baseline: ξ = {} %  θ_o = {:.1}°  t_gap = {}",
            bparams.accuracy_pct,
            bparams.orientation_rad.to_degrees(),
            ctx.len(bparams.t_gap_m)
        ))
        .weak()
        .small(),
    );
}

/// One candidate's tests now and under the baseline (a row of the baseline grid).
fn baseline_row_ui(
    ui: &mut egui::Ui,
    d: &DecisionTrace,
    id: SegmentId,
    bparams: &Params,
    bview: &StepView,
    new_ends: &SegmentEnds,
) {
    ui.label(format!("#{id}"));
    match d.mpc_stage.iter().find(|c| c.evaluation.existing == id) {
        Some(c) => {
            let (t, pass) = short_eval(&c.evaluation);
            coloured(ui, t, pass);
        }
        None => {
            ui.label(RichText::new("not a candidate").weak());
        }
    }
    match bview.map_before.segment(id) {
        Some(seg) => {
            let e = evaluate_pair(bparams, new_ends, id, &SegmentEnds { a: seg.a, b: seg.b });
            let (t, pass) = short_eval(&e);
            coloured(ui, t, pass);
        }
        None => {
            ui.label(RichText::new("not in the baseline map").weak());
        }
    }
    ui.end_row();
}

/// The columns of the candidates table.
const CANDIDATE_COLUMNS: [&str; 16] = [
    "Candidate",
    "Distance",
    "Outermost",
    "Orientation",
    "θ_o",
    "",
    "Colinearity d",
    "Threshold",
    "D1",
    "D2",
    "D3",
    "",
    "MPC t_mid",
    "EPC t_L / t_R",
    "Overlap",
    "Stage",
];

fn candidates_table_ui(
    ui: &mut egui::Ui,
    ctx: &InspectCtx,
    d: &DecisionTrace,
    commands: &mut Vec<Command>,
) {
    egui::Grid::new("candidates")
        .striped(true)
        .num_columns(16)
        .show(ui, |ui| {
            header_row(ui, &CANDIDATE_COLUMNS);
            for (n, c) in d.mpc_stage.iter().enumerate() {
                candidate_row_ui(ui, ctx, d, n, c, commands);
            }
        });
    ui.label(
        RichText::new(
            "Orientation: angle between the lines mod 180° <= θ_o. Colinearity: |d| <= ξ/100·(D1 + (D2+D3)/2). \
             MPC: mid-point of l_n projects into l_e (t in [0,1]); EPC: one end-point does.",
        )
        .weak()
        .small(),
    );
}

/// One candidate of the MPC stage: its three tests and the stage it reached.
fn candidate_row_ui(
    ui: &mut egui::Ui,
    ctx: &InspectCtx,
    d: &DecisionTrace,
    n: usize,
    c: &CandidateTrace,
    commands: &mut Vec<Command>,
) {
    let deg = |r: f64| format!("{:.2}°", r.to_degrees());
    let e = &c.evaluation;
    let deciding = d.existing == Some(e.existing);
    let name = format!(
        "#{}{}",
        e.existing,
        if deciding { " (deciding)" } else { "" }
    );
    if ui
        .link(name)
        .on_hover_text("select this map segment")
        .clicked()
    {
        commands.push(Command::Select(SceneId::MapSegment(e.existing)));
    }
    ui.label(ctx.len(c.distance_m));
    ui.label(if c.outermost { "yes" } else { "no" });
    test_cells(ui, &e.orientation, &deg);
    test_cells(ui, &e.colinearity.test, &|m| ctx.len(m));
    ui.label(ctx.len(e.colinearity.d1_m));
    ui.label(ctx.len(e.colinearity.d2_m));
    ui.label(ctx.len(e.colinearity.d3_m));
    ui.label("");
    coloured(ui, format!("{:.3}", e.overlap.mid_param), e.overlap.mpc);
    coloured(
        ui,
        format!("{:.3} / {:.3}", e.overlap.left_param, e.overlap.right_param),
        e.overlap.epc,
    );
    let overlap = if e.overlap.mpc {
        "MPC"
    } else if e.overlap.containment {
        "contains"
    } else if e.overlap.epc {
        "EPC"
    } else {
        "none"
    };
    let pass = e.overlap.mpc || e.overlap.containment || e.overlap.epc;
    ui.label(
        RichText::new(format!("{} {overlap}", if pass { "pass" } else { "FAIL" })).color(if pass {
            PASS
        } else {
            FAIL
        }),
    );
    ui.label(if d.epc_stage.contains(&n) {
        "MPC+EPC"
    } else {
        "MPC"
    });
    ui.end_row();
}
