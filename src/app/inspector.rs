//! The inspector: everything the trace says about the selection. A new segment shows its
//! cluster, the fitting splits and the table of every candidate with the three tests; a map
//! segment shows its history, its update fates in this step and "compare with…"; a reading
//! shows sensor, pose, range, point and ball. It only reads the trace (docs/architecture.md: the trace is
//! data); "compare with…" calls the engine's own `evaluate_pair`.

use super::command::Command;
use crate::geometry::Point;
use crate::mapping::map::EndPoint;
use crate::mapping::map::ReadingRef;
use crate::mapping::matching::{evaluate_pair, SegmentEnds};
use crate::mapping::trace::{
    CorrelationKind, DecisionTrace, DiscardReason, EndOrigin, EndRole, PairEvaluation,
    SegmentSource, SplitTrace, Test,
};
use crate::mapping::{Outcome, Params, Rule, SegmentId, SegmentKind, StepTrace};
use crate::replay::StepView;
use crate::run::Run;
use crate::scene::{format_length, SceneId};
use crate::units::Units;
use egui::{Color32, RichText};

/// Colour of a passed test.
pub const PASS: Color32 = Color32::from_rgb(0x2e, 0xa0, 0x43);
/// Colour of a failed test.
pub const FAIL: Color32 = Color32::from_rgb(0xd5, 0x5e, 0x00);

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
}

impl InspectCtx<'_> {
    fn units(&self) -> Units {
        self.run.units
    }

    fn len(&self, m: f64) -> String {
        format_length(m, self.units())
    }

    fn point(&self, p: &Point) -> String {
        let u = self.units();
        format!(
            "({:.1}, {:.1}) {}",
            u.from_m(p.x),
            u.from_m(p.y),
            u.symbol()
        )
    }

    fn end(&self, e: &EndPoint) -> String {
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

fn reason_name(r: DiscardReason) -> &'static str {
    match r {
        DiscardReason::NoEcho => "no echo",
        DiscardReason::AtMaxRange => "at the sensor's maximum range (no echo)",
        DiscardReason::BeyondDMax => "beyond d_max",
        DiscardReason::BelowMinRange => "below min_range",
    }
}

fn origin_name(o: EndOrigin) -> &'static str {
    match o {
        EndOrigin::ExistingLeft => "e_L",
        EndOrigin::ExistingRight => "e_R",
        EndOrigin::NewLeft => "n_L",
        EndOrigin::NewRight => "n_R",
    }
}

fn role_name(r: EndRole) -> &'static str {
    match r {
        EndRole::Kept => "kept (smaller range)",
        EndRole::Middle => "kept as middle point M",
        EndRole::Projected => "projected onto l_u (larger range)",
        EndRole::Dropped => "dropped (inner, less confident than M)",
    }
}

/// A pass/fail cell: ✔ or ✘ with text, coloured.
fn verdict(ui: &mut egui::Ui, pass: bool) {
    let (text, colour) = if pass { ("pass", PASS) } else { ("FAIL", FAIL) };
    ui.label(RichText::new(text).color(colour).strong());
}

fn coloured(ui: &mut egui::Ui, text: String, pass: bool) {
    ui.label(RichText::new(text).color(if pass { PASS } else { FAIL }));
}

fn heading(ui: &mut egui::Ui, text: &str) {
    ui.add_space(6.0);
    ui.label(RichText::new(text).strong().size(15.0));
}

fn kv(ui: &mut egui::Ui, key: &str, value: impl Into<egui::WidgetText>) {
    ui.label(RichText::new(key).weak());
    ui.label(value);
    ui.end_row();
}

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
        }
        SceneId::NewSegment(i) | SceneId::Decision { new_segment: i, .. } => {
            new_segment_ui(ui, ctx, i, &mut commands)
        }
        SceneId::MapSegment(id) | SceneId::Update(id) => {
            map_segment_ui(ui, ctx, id, compare, &mut commands)
        }
        SceneId::Reading { snapshot, sensor } => {
            reading_ui(ui, ctx, snapshot, sensor, &mut commands)
        }
        SceneId::Cluster(c) => cluster_ui(ui, ctx, c, &mut commands),
        SceneId::Correlation(c) => correlation_ui(ui, ctx, c),
        SceneId::Robot => robot_ui(ui, ctx),
        SceneId::FloorPlan => {
            heading(ui, "Floor plan");
            ui.label("Ground truth from the run log (not used by the mapper).");
        }
    }
    commands
}

fn warnings_ui(ui: &mut egui::Ui, ctx: &InspectCtx) {
    for w in &ctx.view.trace.warnings {
        let text = match w {
            crate::mapping::trace::Warning::MaxStep { step_m, max_step_m } => format!(
                "warning: the robot moved {} since the last snapshot (max_step {})",
                ctx.len(*step_m),
                ctx.len(*max_step_m)
            ),
            crate::mapping::trace::Warning::RangeCount { given, expected } => {
                format!("warning: {given} ranges for {expected} sensors")
            }
        };
        ui.label(RichText::new(text).color(FAIL));
    }
}

fn robot_ui(ui: &mut egui::Ui, ctx: &InspectCtx) {
    heading(ui, "Robot");
    if let Some(pose) = ctx.view.trace.pose {
        egui::Grid::new("robot").num_columns(2).show(ui, |ui| {
            kv(ui, "snapshot", ctx.view.index.to_string());
            kv(ui, "t", format!("{:.2} s", ctx.view.trace.t));
            kv(ui, "position", ctx.point(&pose.position()));
            kv(
                ui,
                "heading",
                format!("{:.1}°", pose.heading_rad.to_degrees()),
            );
        });
    }
    warnings_ui(ui, ctx);
}

fn splits_ui(ui: &mut egui::Ui, ctx: &InspectCtx, id: &str, splits: &[SplitTrace]) {
    if splits.is_empty() {
        ui.label("no split test (two points)");
        return;
    }
    egui::Grid::new(id)
        .striped(true)
        .num_columns(5)
        .show(ui, |ui| {
            for h in ["piece", "farthest", "deviation", "tolerance", "split?"] {
                ui.label(RichText::new(h).strong());
            }
            ui.end_row();
            for s in splits {
                ui.label(format!("{}..{}", s.first, s.last));
                ui.label(s.farthest.map_or("-".to_owned(), |f| f.to_string()));
                ui.label(ctx.len(s.deviation_m));
                ui.label(ctx.len(s.tolerance_m));
                // A split is the test failing: deviation > tolerance.
                coloured(
                    ui,
                    if s.split {
                        "split".to_owned()
                    } else {
                        "kept".to_owned()
                    },
                    !s.split,
                );
                ui.end_row();
            }
        });
}

fn new_segment_ui(ui: &mut egui::Ui, ctx: &InspectCtx, i: usize, commands: &mut Vec<Command>) {
    let trace = &ctx.view.trace;
    let Some(seg) = trace.new_segments.get(i) else {
        ui.label(format!("new segment n{i} is not in this step"));
        return;
    };
    heading(
        ui,
        &format!("New segment n{i} (snapshot {})", ctx.view.index),
    );
    egui::Grid::new("new_segment")
        .num_columns(2)
        .show(ui, |ui| {
            kv(ui, "end a", ctx.end(&seg.a));
            kv(ui, "end b", ctx.end(&seg.b));
            kv(ui, "length", ctx.len((seg.b.point - seg.a.point).norm()));
            kv(ui, "points", seg.points.len().to_string());
            let source = match seg.source {
                SegmentSource::Cluster(c) => format!("cluster {c}"),
                SegmentSource::Memory(g) => format!("point-memory group {g}"),
            };
            kv(ui, "from", source);
        });
    if let SegmentSource::Cluster(c) = seg.source {
        if let Some(cluster) = trace.clusters.get(c) {
            ui.horizontal_wrapped(|ui| {
                ui.label(RichText::new("readings (sensor: D)").weak());
                for p in &seg.points {
                    let text = format!("s{}: {}", p.reading.sensor, ctx.len(p.range_m));
                    if ui.small_button(text).clicked() {
                        commands.push(Command::Select(SceneId::Reading {
                            snapshot: p.reading.snapshot,
                            sensor: p.reading.sensor,
                        }));
                    }
                }
            });
            if ui
                .link(format!("cluster {c}: sensors {:?}", cluster.sensors))
                .clicked()
            {
                commands.push(Command::Select(SceneId::Cluster(c)));
            }
            egui::CollapsingHeader::new(format!(
                "Fitting splits of cluster {c}: deviation vs tolerance ({} tests)",
                cluster.splits.len()
            ))
            .default_open(cluster.splits.len() <= 4)
            .show(ui, |ui| splits_ui(ui, ctx, "splits", &cluster.splits));
        }
    }
    match trace.decisions.iter().find(|d| d.new_segment == i) {
        Some(d) => decision_ui(ui, ctx, d, commands),
        None => {
            ui.label("no decision recorded for this segment");
        }
    }
}

fn decision_ui(
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
            super::timeline::BASELINE_COLOUR
        }),
        None => RichText::new("the baseline did not fit this segment (same readings)")
            .color(super::timeline::BASELINE_COLOUR),
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
                    for h in ["Candidate", "now", "baseline"] {
                        ui.label(RichText::new(h).strong());
                    }
                    ui.end_row();
                    for id in ids {
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
                                let e = evaluate_pair(
                                    bparams,
                                    &new_ends,
                                    id,
                                    &SegmentEnds { a: seg.a, b: seg.b },
                                );
                                let (t, pass) = short_eval(&e);
                                coloured(ui, t, pass);
                            }
                            None => {
                                ui.label(RichText::new("not in the baseline map").weak());
                            }
                        }
                        ui.end_row();
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

fn test_cells(ui: &mut egui::Ui, value: String, threshold: String, t: &Test) {
    coloured(ui, value, t.pass);
    ui.label(threshold);
    verdict(ui, t.pass);
}

fn candidates_table_ui(
    ui: &mut egui::Ui,
    ctx: &InspectCtx,
    d: &DecisionTrace,
    commands: &mut Vec<Command>,
) {
    let deg = |r: f64| format!("{:.2}°", r.to_degrees());
    egui::Grid::new("candidates")
        .striped(true)
        .num_columns(16)
        .show(ui, |ui| {
            for h in [
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
            ] {
                ui.label(RichText::new(h).strong());
            }
            ui.end_row();
            for (n, c) in d.mpc_stage.iter().enumerate() {
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
                test_cells(
                    ui,
                    deg(e.orientation.value),
                    deg(e.orientation.threshold),
                    &e.orientation,
                );
                test_cells(
                    ui,
                    ctx.len(e.colinearity.test.value),
                    ctx.len(e.colinearity.test.threshold),
                    &e.colinearity.test,
                );
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
                    RichText::new(format!("{} {overlap}", if pass { "pass" } else { "FAIL" }))
                        .color(if pass { PASS } else { FAIL }),
                );
                ui.label(if d.epc_stage.contains(&n) {
                    "MPC+EPC"
                } else {
                    "MPC"
                });
                ui.end_row();
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

/// The three tests of a pair, as a vertical table (for "compare with…").
fn pair_ui(ui: &mut egui::Ui, ctx: &InspectCtx, e: &PairEvaluation) {
    let deg = |r: f64| format!("{:.2}°", r.to_degrees());
    egui::Grid::new("pair")
        .striped(true)
        .num_columns(4)
        .show(ui, |ui| {
            for h in ["Test", "Value", "Threshold", "Result"] {
                ui.label(RichText::new(h).strong());
            }
            ui.end_row();
            ui.label("Orientation");
            test_cells(
                ui,
                deg(e.orientation.value),
                deg(e.orientation.threshold),
                &e.orientation,
            );
            ui.end_row();
            ui.label("Colinearity d");
            test_cells(
                ui,
                ctx.len(e.colinearity.test.value),
                ctx.len(e.colinearity.test.threshold),
                &e.colinearity.test,
            );
            ui.end_row();
            ui.label("  D1 / D2 / D3");
            ui.label(format!(
                "{} / {} / {}",
                ctx.len(e.colinearity.d1_m),
                ctx.len(e.colinearity.d2_m),
                ctx.len(e.colinearity.d3_m)
            ));
            ui.end_row();
            ui.label("MPC (t_mid)");
            coloured(ui, format!("{:.3}", e.overlap.mid_param), e.overlap.mpc);
            ui.label("[0, 1]");
            verdict(ui, e.overlap.mpc);
            ui.end_row();
            ui.label("EPC (t_L / t_R)");
            coloured(
                ui,
                format!("{:.3} / {:.3}", e.overlap.left_param, e.overlap.right_param),
                e.overlap.epc,
            );
            ui.label("[0, 1]");
            verdict(ui, e.overlap.epc);
            ui.end_row();
            ui.label("Containment");
            ui.label(format!(
                "{:.3} / {:.3}",
                e.overlap.existing_on_new_params[0], e.overlap.existing_on_new_params[1]
            ));
            ui.label("[0, 1]");
            verdict(ui, e.overlap.containment);
            ui.end_row();
        });
    let verdict_text = if e.is_match() {
        "would MATCH"
    } else if e.is_extension() {
        "would EXTEND (if outermost)"
    } else if e.fails_only_orientation() {
        "fails only orientation: would be DISMISSED"
    } else {
        "no match"
    };
    ui.label(RichText::new(verdict_text).strong());
}

fn map_segment_ui(
    ui: &mut egui::Ui,
    ctx: &InspectCtx,
    id: SegmentId,
    compare: &CompareState,
    commands: &mut Vec<Command>,
) {
    let view = ctx.view;
    let after = view.map_after.segment(id);
    let seg = after.or_else(|| view.map_before.segment(id));
    let Some(seg) = seg else {
        heading(ui, &format!("Segment #{id}"));
        ui.label("not in the map at this snapshot");
        return;
    };
    heading(ui, &format!("Map segment #{id}"));
    if after.is_none() {
        ui.label(RichText::new("removed in this step (shown as it stood before)").color(FAIL));
    }
    egui::Grid::new("map_segment")
        .num_columns(2)
        .show(ui, |ui| {
            kv(
                ui,
                "kind",
                match seg.kind {
                    SegmentKind::Fitted => "fitted",
                    SegmentKind::Interpolated => "interpolated (correlation link)",
                },
            );
            kv(ui, "end a", ctx.end(&seg.a));
            kv(ui, "end b", ctx.end(&seg.b));
            kv(ui, "length", ctx.len(seg.length()));
            kv(
                ui,
                "face / object",
                format!("{} / {}", seg.face, seg.object),
            );
            kv(ui, "points", seg.points.len().to_string());
            kv(ui, "created at", format!("snapshot {}", seg.created));
            let updated = if seg.updated.is_empty() {
                "never".to_owned()
            } else {
                seg.updated
                    .iter()
                    .map(|k| k.to_string())
                    .collect::<Vec<_>>()
                    .join(", ")
            };
            kv(ui, "updated at", updated);
        });
    if seg.created < view.index {
        ui.horizontal(|ui| {
            if ui
                .button(format!("Go to snapshot {} (created)", seg.created))
                .clicked()
            {
                commands.push(Command::Seek(seg.created));
            }
        });
    }
    for u in view.trace.updates.iter().filter(|u| u.segment == id) {
        heading(
            ui,
            &format!(
                "Updated in this step by n{} ({})",
                u.new_segment,
                outcome_name(u.outcome)
            ),
        );
        egui::Grid::new(("fates", u.new_segment))
            .striped(true)
            .num_columns(4)
            .show(ui, |ui| {
                for h in ["End", "Range", "Compared with", "Fate"] {
                    ui.label(RichText::new(h).strong());
                }
                ui.end_row();
                for f in &u.fates {
                    ui.label(origin_name(f.origin));
                    ui.label(ctx.len(f.before.range_m));
                    ui.label(origin_name(f.compared_with));
                    ui.label(format!(
                        "{}{}",
                        role_name(f.role),
                        if f.is_end_after { ", an end after" } else { "" }
                    ));
                    ui.end_row();
                }
            });
        if u.fallback_tls {
            ui.label("the defining points nearly coincided: l_u is the TLS line of the four");
        }
        if let Some(r) = &u.refit {
            ui.label(format!(
                "post-update split test failed (worst {} > {}): refitted into {:?}",
                ctx.len(r.worst.value),
                ctx.len(r.worst.threshold),
                r.pieces
            ));
        }
        for a in &u.absorbed {
            let c = &a.evaluation.colinearity.test;
            ui.label(format!(
                "merged duplicate s{} into s{} (merge_duplicates): it matches (angle {:.1}°, d {} ≤ {})",
                a.segment,
                a.into,
                a.evaluation.orientation.value.to_degrees(),
                ctx.len(c.value),
                ctx.len(c.threshold),
            ));
        }
    }
    let deciding: Vec<_> = view
        .trace
        .decisions
        .iter()
        .filter(|d| d.existing == Some(id))
        .collect();
    if !deciding.is_empty() {
        heading(ui, "Decisions against it in this step");
        for d in deciding {
            if ui
                .link(format!("n{}: {}", d.new_segment, outcome_name(d.outcome)))
                .clicked()
            {
                commands.push(Command::Select(SceneId::NewSegment(d.new_segment)));
            }
        }
    }
    heading(ui, "Compare");
    match compare {
        CompareState::Armed(e) if *e == id => {
            ui.label("Click another segment in the map (or a new segment) to run the three tests.");
            if ui.button("Cancel").clicked() {
                commands.push(Command::CancelCompare);
            }
        }
        CompareState::Done {
            existing,
            other,
            eval,
        } if *existing == id => {
            ui.label(format!(
                "{} as l_n against #{id} as l_e:",
                super::app::describe_id(*other)
            ));
            pair_ui(ui, ctx, eval);
            if ui.button("Compare with another…").clicked() {
                commands.push(Command::CompareWith(id));
            }
        }
        _ => {
            if ui
                .button("Compare with…")
                .on_hover_text("evaluate orientation, colinearity and overlap against the next segment you click")
                .clicked()
            {
                commands.push(Command::CompareWith(id));
            }
        }
    }
}

fn reading_ui(
    ui: &mut egui::Ui,
    ctx: &InspectCtx,
    snapshot: usize,
    sensor: usize,
    commands: &mut Vec<Command>,
) {
    let view = ctx.view;
    let trace = if snapshot == view.index {
        Some(&view.trace)
    } else {
        view.previous.as_ref().filter(|p| p.snapshot == snapshot)
    };
    heading(
        ui,
        &format!("Reading: sensor {sensor}, snapshot {snapshot}"),
    );
    let Some(trace) = trace else {
        ui.label("not in this step");
        return;
    };
    let Some(r) = trace.readings.iter().find(|r| r.sensor == sensor) else {
        ui.label("no such sensor");
        return;
    };
    egui::Grid::new("reading").num_columns(2).show(ui, |ui| {
        if let Some(pose) = trace.pose {
            kv(
                ui,
                "robot pose",
                format!(
                    "{}  {:.1}°",
                    ctx.point(&pose.position()),
                    pose.heading_rad.to_degrees()
                ),
            );
            if sensor < ctx.run.layout.len() {
                let sp = ctx.run.layout.sensor_pose_in_world(&pose, sensor);
                kv(
                    ui,
                    "sensor pose",
                    format!(
                        "{}  {:.1}°",
                        ctx.point(&sp.position()),
                        sp.heading_rad.to_degrees()
                    ),
                );
            }
        }
        kv(
            ui,
            "range D",
            r.range_m.map_or("no echo".to_owned(), |d| ctx.len(d)),
        );
        kv(
            ui,
            "point",
            r.point.map_or("-".to_owned(), |p| ctx.point(&p)),
        );
        kv(ui, "ball radius ξ·D/100", ctx.len(r.ball_radius_m));
        match r.discarded {
            None => kv(ui, "status", RichText::new("kept").color(PASS)),
            Some(reason) => kv(
                ui,
                "status",
                RichText::new(format!("discarded: {}", reason_name(reason))).color(FAIL),
            ),
        }
        kv(
            ui,
            "cluster",
            r.cluster.map_or("-".to_owned(), |c| c.to_string()),
        );
    });
    if let (Some(c), true) = (r.cluster, snapshot == view.index) {
        if ui.button(format!("Select cluster {c}")).clicked() {
            commands.push(Command::Select(SceneId::Cluster(c)));
        }
    }
}

fn cluster_ui(ui: &mut egui::Ui, ctx: &InspectCtx, c: usize, commands: &mut Vec<Command>) {
    let Some(cluster) = ctx.view.trace.clusters.get(c) else {
        ui.label(format!("cluster {c} is not in this step"));
        return;
    };
    heading(ui, &format!("Cluster {c}"));
    ui.label(format!("sensors {:?}", cluster.sensors));
    for g in &cluster.constant_depth {
        ui.label(format!(
            "constant-depth group {:?} -> kept sensor {}",
            g.sensors, g.kept_sensor
        ));
    }
    heading(ui, "Fitting splits (deviation vs tolerance)");
    splits_ui(ui, ctx, "cluster_splits", &cluster.splits);
    heading(ui, "Segments");
    for &n in &cluster.new_segments {
        if ui.link(format!("new segment n{n}")).clicked() {
            commands.push(Command::Select(SceneId::NewSegment(n)));
        }
    }
}

fn correlation_ui(ui: &mut egui::Ui, ctx: &InspectCtx, c: usize) {
    let Some(t) = ctx.view.trace.correlations.get(c) else {
        ui.label(format!("correlation {c} is not in this step"));
        return;
    };
    heading(ui, &format!("Correlation {c} (face {})", t.face));
    egui::Grid::new("correlation")
        .num_columns(2)
        .show(ui, |ui| {
            if let Some((s, end)) = t.new_segment {
                kv(
                    ui,
                    "new segment",
                    format!("#{s} end {}", if end == 0 { "a" } else { "b" }),
                );
            }
            if let Some((s, end)) = t.existing_segment {
                kv(
                    ui,
                    "existing segment",
                    format!("#{s} end {}", if end == 0 { "a" } else { "b" }),
                );
            }
            if let Some(d) = t.d_min {
                kv(
                    ui,
                    "d_min vs t_gap",
                    RichText::new(format!("{} <= {}", ctx.len(d.value), ctx.len(d.threshold)))
                        .color(if d.pass { PASS } else { FAIL }),
                );
            }
            if let Some(a) = t.angle_rad {
                kv(ui, "angle", format!("{:.1}°", a.to_degrees()));
            }
            let result = match &t.result {
                CorrelationKind::Corner { point } => format!("corner at {}", ctx.point(point)),
                CorrelationKind::Interpolated { link, reason } => {
                    format!("interpolated link #{link} ({reason:?})")
                }
                CorrelationKind::Shared { point } => format!(
                    "shared end-point at {} (d_min = 0): nothing moves, one object",
                    ctx.point(point)
                ),
                CorrelationKind::None => "none: the face stays a distinct object".to_owned(),
            };
            kv(ui, "result", result);
        });
}

/// The hover text of a scene id (the map view's tooltip).
pub fn hover_text(ctx: &InspectCtx, id: SceneId) -> Option<String> {
    let view = ctx.view;
    match id {
        SceneId::Reading { snapshot, sensor } => {
            let trace = if snapshot == view.index {
                &view.trace
            } else {
                view.previous.as_ref()?
            };
            let r = trace.readings.iter().find(|r| r.sensor == sensor)?;
            let status = match r.discarded {
                None => format!(
                    "kept, cluster {}",
                    r.cluster.map_or("-".to_owned(), |c| c.to_string())
                ),
                Some(reason) => format!("discarded: {}", reason_name(reason)),
            };
            Some(format!(
                "reading s{sensor} (snapshot {snapshot})\nrange {}\nball radius {}\n{status}",
                r.range_m.map_or("no echo".to_owned(), |d| ctx.len(d)),
                ctx.len(r.ball_radius_m),
            ))
        }
        SceneId::MapSegment(sid) | SceneId::Update(sid) => {
            let s = view
                .map_after
                .segment(sid)
                .or_else(|| view.map_before.segment(sid))?;
            Some(format!(
                "segment #{sid} ({})\na {}\nb {}\nlength {}\nface {}",
                match s.kind {
                    SegmentKind::Fitted => "fitted",
                    SegmentKind::Interpolated => "interpolated",
                },
                ctx.end(&s.a),
                ctx.end(&s.b),
                ctx.len(s.length()),
                s.face
            ))
        }
        SceneId::NewSegment(i) | SceneId::Decision { new_segment: i, .. } => {
            let s = view.trace.new_segments.get(i)?;
            let d = view.trace.decisions.iter().find(|d| d.new_segment == i);
            let mut text = format!(
                "new segment n{i}\na {}\nb {}\nlength {}",
                ctx.end(&s.a),
                ctx.end(&s.b),
                ctx.len((s.b.point - s.a.point).norm())
            );
            if let Some(d) = d {
                text.push_str(&format!(
                    "\n{}{}",
                    outcome_name(d.outcome),
                    d.existing.map_or(String::new(), |e| format!(" with #{e}"))
                ));
            }
            if let SceneId::Decision {
                existing: Some(e), ..
            } = id
            {
                text.push_str(&format!("\ntested against #{e}"));
            }
            Some(text)
        }
        SceneId::Cluster(c) => {
            let cl = view.trace.clusters.get(c)?;
            Some(format!("cluster {c}: sensors {:?}", cl.sensors))
        }
        SceneId::Correlation(c) => {
            let t = view.trace.correlations.get(c)?;
            Some(format!("correlation {c} (face {})", t.face))
        }
        SceneId::Robot => {
            let p = view.trace.pose?;
            Some(format!(
                "robot at {} heading {:.1}°",
                ctx.point(&p.position()),
                p.heading_rad.to_degrees()
            ))
        }
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
