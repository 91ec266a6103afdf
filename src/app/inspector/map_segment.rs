//! A map segment (selected in the map or as an update): its ends, history and faces, how the
//! updates of this step moved each end, the decisions against it, and "compare with…", which
//! runs the engine's own three tests against the next segment clicked.

use super::context::{CompareState, InspectCtx};
use super::names::{describe_id, outcome_name};
use super::widgets::{coloured, header_row, heading, kv, test_cells, verdict, FAIL};
use crate::app::command::Command;
use crate::mapping::model::ext_trace::SeenThroughCut;
use crate::mapping::model::map::Segment;
use crate::mapping::model::trace::{EndOrigin, EndRole, PairEvaluation, UpdateTrace};
use crate::mapping::{SegmentId, SegmentKind};
use crate::scene::SceneId;
use egui::RichText;

pub(super) fn map_segment_ui(
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
        lineage_ui(ui, ctx, id, commands);
        return;
    };
    heading(ui, &format!("Map segment #{id}"));
    if after.is_none() {
        ui.label(RichText::new("removed in this step (shown as it stood before)").color(FAIL));
    }
    details_ui(ui, ctx, seg);
    lineage_ui(ui, ctx, id, commands);
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
        update_ui(ui, ctx, u);
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
    compare_ui(ui, ctx, id, compare, commands);
}

/// The segment's ends, faces and history.
fn details_ui(ui: &mut egui::Ui, ctx: &InspectCtx, seg: &Segment) {
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
            let snapshots = seg.points.iter().map(|q| q.reading.snapshot());
            let span = match (snapshots.clone().min(), snapshots.max()) {
                (Some(a), Some(b)) if a != b => format!(" from snapshots {a}–{b}"),
                (Some(a), _) => format!(" from snapshot {a}"),
                _ => String::new(),
            };
            kv(
                ui,
                "points",
                format!("{}{span} (yellow rings in the map)", seg.points.len()),
            );
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
            if let Some(verdict) = ctx.truth.and_then(|t| t.verdict(seg.id)) {
                kv(ui, "truth (eval)", truth_text(ctx, verdict));
            }
        });
}

/// The segment's life up to the snapshot shown, one button an event: it goes to the snapshot
/// and selects what the event names.
fn lineage_ui(ui: &mut egui::Ui, ctx: &InspectCtx, id: SegmentId, commands: &mut Vec<Command>) {
    let events = ctx.lineage.of(id, ctx.view.index);
    egui::CollapsingHeader::new(format!("Lineage ({} events)", events.len()))
        .id_salt(("lineage", id))
        .default_open(true)
        .show(ui, |ui| {
            egui::ScrollArea::vertical()
                .id_salt(("lineage_scroll", id))
                .max_height(220.0)
                .show(ui, |ui| {
                    for event in events {
                        let (text, target) = lineage_row(event, id);
                        let label = format!("snapshot {}: {text}", event.snapshot());
                        if ui.button(label).clicked() {
                            commands.push(Command::Seek(event.snapshot()));
                            commands.push(Command::Select(target));
                        }
                    }
                });
        });
}

/// A lineage row's text and link for a cut of §8.18.
fn seen_through_row(sensor: usize, cut: SeenThroughCut) -> (String, SceneId) {
    match cut {
        SeenThroughCut::EndA | SeenThroughCut::EndB => (
            format!("sensor {sensor} saw through its end: cut back (seen through)"),
            SceneId::None,
        ),
        SeenThroughCut::Split { piece } => (
            format!("sensor {sensor} saw through it: a hole, piece #{piece} beyond"),
            SceneId::MapSegment(piece),
        ),
        SeenThroughCut::Removed => (
            format!("removed: sensor {sensor} saw through it (seen through)"),
            SceneId::None,
        ),
    }
}

/// The text of a lineage event of segment `id`, and what a click on it selects.
fn lineage_row(event: &crate::lineage::LineageEvent, id: SegmentId) -> (String, SceneId) {
    use crate::lineage::{CorrelationResult, LineageEvent};
    match *event {
        LineageEvent::Created { new_segment, .. } => (
            format!("made by n{new_segment} (new face)"),
            SceneId::Decision {
                new_segment,
                existing: None,
            },
        ),
        LineageEvent::Updated {
            new_segment,
            outcome,
            refit,
            ..
        } => (
            format!(
                "{} by n{new_segment}{}",
                outcome_name(outcome),
                if refit { ", refitted" } else { "" }
            ),
            SceneId::Update(id),
        ),
        LineageEvent::SplitOff { piece, .. } => (
            format!("its refit left piece #{piece}"),
            SceneId::MapSegment(piece),
        ),
        LineageEvent::SplitFrom { parent, .. } => (
            format!("a piece split from #{parent}"),
            SceneId::MapSegment(parent),
        ),
        LineageEvent::Absorbed { segment, .. } => (
            format!("absorbed duplicate #{segment}"),
            SceneId::Update(id),
        ),
        LineageEvent::AbsorbedInto { into, .. } => {
            (format!("merged into #{into}"), SceneId::MapSegment(into))
        }
        LineageEvent::Unconfirmed { .. } => (
            "tentative again: its refit moved it off the line it was \
             confirmed on"
                .to_string(),
            SceneId::None,
        ),
        LineageEvent::Refuted { sensor, .. } => (
            format!("removed: sensor {sensor} saw through it (free space)"),
            SceneId::None,
        ),
        LineageEvent::SeenThrough { sensor, cut, .. } => seen_through_row(sensor, cut),
        LineageEvent::CornerDiagonal { walls, .. } => (
            format!(
                "removed: a diagonal of the corner of #{} and #{}",
                walls[0], walls[1]
            ),
            SceneId::MapSegment(walls[0]),
        ),
        LineageEvent::LinkDropped { .. } => (
            "removed: a segment it joined left the map".to_string(),
            SceneId::None,
        ),
        LineageEvent::Correlated {
            other,
            correlation,
            result,
            ..
        } => (
            format!(
                "{} with #{other}",
                match result {
                    CorrelationResult::Corner => "corner",
                    CorrelationResult::Link => "connecting segment",
                    CorrelationResult::Shared => "shared end-point",
                }
            ),
            SceneId::Correlation(correlation),
        ),
    }
}

/// `eval`'s verdict on a segment, with its numbers.
fn truth_text(ctx: &InspectCtx, verdict: &crate::eval::Verdict) -> String {
    use crate::eval::Verdict;
    match *verdict {
        Verdict::OnWall {
            wall,
            endpoint_error_m,
            angle_rad,
        } => format!(
            "on wall {wall}: end-point error {}, angle {:.1}°",
            ctx.len(endpoint_error_m),
            angle_rad.to_degrees()
        ),
        Verdict::OnPillar {
            pillar,
            endpoint_error_m,
        } => format!(
            "on pillar {pillar}: end-point error {}",
            ctx.len(endpoint_error_m)
        ),
        Verdict::Spurious => "spurious: on no wall or pillar within tolerance".to_owned(),
    }
}

/// How one update of this step moved the segment's ends.
fn update_ui(ui: &mut egui::Ui, ctx: &InspectCtx, u: &UpdateTrace) {
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
            header_row(ui, &["End", "Range", "Compared with", "Fate"]);
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

/// "Compare with…": the button, the armed state, or the three tests once compared.
fn compare_ui(
    ui: &mut egui::Ui,
    ctx: &InspectCtx,
    id: SegmentId,
    compare: &CompareState,
    commands: &mut Vec<Command>,
) {
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
                describe_id(*other)
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

/// The three tests of a pair, as a vertical table (for "compare with…").
fn pair_ui(ui: &mut egui::Ui, ctx: &InspectCtx, e: &PairEvaluation) {
    let deg = |r: f64| format!("{:.2}°", r.to_degrees());
    egui::Grid::new("pair")
        .striped(true)
        .num_columns(4)
        .show(ui, |ui| {
            header_row(ui, &["Test", "Value", "Threshold", "Result"]);
            ui.label("Orientation");
            test_cells(ui, &e.orientation, &deg);
            ui.end_row();
            ui.label("Colinearity d");
            test_cells(ui, &e.colinearity.test, &|m| ctx.len(m));
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

/// A map segment's hover text.
pub(super) fn map_segment_hover(ctx: &InspectCtx, sid: SegmentId) -> Option<String> {
    let view = ctx.view;
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
