//! A cluster and the new segments fitted from it: end-points, the readings, the fitting splits
//! (deviation against tolerance) and, for a new segment, its decision.

use super::context::InspectCtx;
use super::decision::decision_ui;
use super::names::outcome_name;
use super::widgets::{coloured, header_row, heading, kv};
use crate::app::command::Command;
use crate::mapping::model::trace::{SegmentSource, SplitTrace};
use crate::scene::SceneId;
use egui::RichText;

fn splits_ui(ui: &mut egui::Ui, ctx: &InspectCtx, id: &str, splits: &[SplitTrace]) {
    if splits.is_empty() {
        ui.label("no split test (two points)");
        return;
    }
    egui::Grid::new(id)
        .striped(true)
        .num_columns(5)
        .show(ui, |ui| {
            header_row(
                ui,
                &["piece", "farthest", "deviation", "tolerance", "split?"],
            );
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

pub(super) fn new_segment_ui(
    ui: &mut egui::Ui,
    ctx: &InspectCtx,
    i: usize,
    commands: &mut Vec<Command>,
) {
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
                    let text = format!("s{}: {}", p.reading.sensor(), ctx.len(p.range_m));
                    if ui.small_button(text).clicked() {
                        commands.push(Command::Select(SceneId::Reading {
                            snapshot: p.reading.snapshot(),
                            sensor: p.reading.sensor(),
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

pub(super) fn cluster_ui(
    ui: &mut egui::Ui,
    ctx: &InspectCtx,
    c: usize,
    commands: &mut Vec<Command>,
) {
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

/// A new segment's (or its decision's) hover text.
pub(super) fn new_segment_hover(ctx: &InspectCtx, id: SceneId, i: usize) -> Option<String> {
    let view = ctx.view;
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

/// A cluster's hover text.
pub(super) fn cluster_hover(ctx: &InspectCtx, c: usize) -> Option<String> {
    let cl = ctx.view.trace.clusters.get(c)?;
    Some(format!("cluster {c}: sensors {:?}", cl.sensors))
}
