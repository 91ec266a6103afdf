//! A reading: sensor and robot pose, range, point, ball radius, and whether it was kept and in
//! which cluster.

use super::context::InspectCtx;
use super::names::reason_name;
use super::widgets::{heading, kv, FAIL, PASS};
use crate::app::command::Command;
use crate::geometry::Pose;
use crate::scene::SceneId;
use egui::RichText;

pub(super) fn reading_ui(
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
        // A supporting reading of an older snapshot: offer to go there.
        ui.label("read in another snapshot");
        if ui.button(format!("Go to snapshot {snapshot}")).clicked() {
            commands.push(Command::Seek(snapshot));
            commands.push(Command::Select(SceneId::Reading { snapshot, sensor }));
        }
        return;
    };
    let Some(r) = trace.readings.iter().find(|r| r.sensor == sensor) else {
        ui.label("no such sensor");
        return;
    };
    egui::Grid::new("reading").num_columns(2).show(ui, |ui| {
        if let Some(pose) = trace.pose {
            pose_rows(ui, ctx, &pose, sensor);
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
        if let (Some(s), Some(range_m)) = (r.shorter_than_last, r.range_m) {
            kv(
                ui,
                "sensor's last echo",
                format!(
                    "{}: {} shorter, more than the {} it may be",
                    ctx.len(s.last_m),
                    ctx.len(s.last_m - range_m),
                    ctx.len(s.tolerance_m)
                ),
            );
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

/// The grid rows of the robot's pose and of the sensor's, in the world.
fn pose_rows(ui: &mut egui::Ui, ctx: &InspectCtx, pose: &Pose, sensor: usize) {
    kv(
        ui,
        "robot pose",
        format!(
            "{}  {:.1}°",
            ctx.point(&pose.position()),
            crate::geometry::heading_deg(pose.heading_rad)
        ),
    );
    if sensor < ctx.run.layout.len() {
        let sp = ctx.run.layout.sensor_pose_in_world(pose, sensor);
        kv(
            ui,
            "sensor pose",
            format!(
                "{}  {:.1}°",
                ctx.point(&sp.position()),
                crate::geometry::heading_deg(sp.heading_rad)
            ),
        );
    }
}

/// A reading's hover text.
pub(super) fn reading_hover(ctx: &InspectCtx, snapshot: usize, sensor: usize) -> Option<String> {
    let view = ctx.view;
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
