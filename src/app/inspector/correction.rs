//! The step's pose correction against the confirmed map (docs/algorithm.md §8.17), with its
//! numbers: odometry, prediction and corrected pose, the residuals before and after, the
//! prior's weight, the observed directions, each reading used, or why it was refused; and the
//! true pose when the run keeps it.

use super::context::InspectCtx;
use super::widgets::{heading, kv, FAIL};
use crate::app::command::Command;
use crate::geometry::Pose;
use crate::mapping::model::ext_trace::{
    CorrectionRefusal, CorrectionTarget, DriftEstimate, HeadingObservation, ObservedDirection,
};
use crate::mapping::Params;
use egui::RichText;

/// `pose` as position and heading (within ±180°: a long run's odometry counts its turns).
fn pose_text(ctx: &InspectCtx, pose: &Pose) -> String {
    format!(
        "{}  {:.2}°",
        ctx.point(&pose.position()),
        crate::geometry::heading_deg(pose.heading_rad)
    )
}

/// How far `b` lies from `a`: distance and turn.
fn offset_text(ctx: &InspectCtx, a: &Pose, b: &Pose) -> String {
    let turn = crate::geometry::wrap_pi(b.heading_rad - a.heading_rad).to_degrees();
    format!("{}  {turn:+.2}°", ctx.len((b.x - a.x).hypot(b.y - a.y)))
}

fn refusal_text(refusal: &CorrectionRefusal) -> String {
    match refusal {
        CorrectionRefusal::FirstStep => "the first step anchors the map".to_string(),
        CorrectionRefusal::TooFewReadings { matched, needed } => format!(
            "the confirmed map explained {matched} readings, {needed} needed: the pose keeps \
             the prediction"
        ),
        CorrectionRefusal::BeyondBound { shift_m, turn_deg } => format!(
            "the correction would move the robot {shift_m:.3} m and turn it {turn_deg:.2}°, \
             beyond three standard deviations of the prediction"
        ),
        CorrectionRefusal::NoBetter => {
            "the corrected pose explained the readings no better than the prediction".to_string()
        }
        CorrectionRefusal::StoodStill => {
            "the robot stood still: the pose stays where the last mapped step put it".to_string()
        }
    }
}

/// The step's correction; nothing when pose correction is off.
pub(super) fn correction_ui(ui: &mut egui::Ui, ctx: &InspectCtx, commands: &mut Vec<Command>) {
    let Some(c) = &ctx.view.trace.correction else {
        return;
    };
    heading(ui, "Pose correction (§8.17)");
    egui::Grid::new("pose_correction")
        .num_columns(2)
        .show(ui, |ui| {
            kv(ui, "odometry", pose_text(ctx, &c.odometry));
            kv(ui, "predicted", pose_text(ctx, &c.predicted));
            kv(ui, "corrected", pose_text(ctx, &c.corrected));
            kv(
                ui,
                "correction",
                offset_text(ctx, &c.predicted, &c.corrected),
            );
            kv(
                ui,
                "from odometry",
                offset_text(ctx, &c.odometry, &c.corrected),
            );
            if let Some(truth) = ctx
                .run
                .snapshots
                .get(ctx.view.index)
                .and_then(|s| s.true_pose)
            {
                kv(ui, "true pose", pose_text(ctx, &truth));
                kv(ui, "error", offset_text(ctx, &truth, &c.corrected));
            }
            kv(
                ui,
                "residual RMS / σ",
                format!("{:.2} before, {:.2} after", c.rms_before, c.rms_after),
            );
            let sigma =
                |[x, y, h]: [f64; 3]| format!("x {}, y {}, {h:.2}°", ctx.len(x), ctx.len(y));
            kv(ui, "prior σ", sigma(c.prior_sigma));
            kv(ui, "posterior σ", sigma(c.posterior_sigma));
            if let Some(h) = &c.heading {
                heading_row(ui, h);
            }
            if let Some(d) = &c.drift {
                drift_rows(ui, d);
            }
        });
    if let Some(refusal) = &c.refused {
        ui.label(RichText::new(format!("refused: {}", refusal_text(refusal))).color(FAIL));
    }
    if let Some(d) = c.drift.as_ref().filter(|d| d.drifting) {
        calibrate_button(ui, ctx, d, commands);
    }
    directions_ui(ui, &c.directions);
    for r in &c.readings {
        let target = match r.target {
            CorrectionTarget::Wall(id) => format!("wall {id}"),
            CorrectionTarget::Feature(id) => format!("feature {id}"),
        };
        ui.label(format!(
            "sensor {} on {target}: residual {} before, {} after (σ {}, gate {})",
            r.sensor,
            ctx.len(r.residual_before_m),
            ctx.len(r.residual_after_m),
            ctx.len(r.sigma_m),
            ctx.len(r.gate_m)
        ));
    }
}

/// The walls' axes observation of a step's correction (docs/algorithm.md §8.17), in short rows
/// (a long one would widen the panel).
fn heading_row(ui: &mut egui::Ui, h: &HeadingObservation) {
    kv(ui, "walls' axis", format!("{:.2}° (mod 90°)", h.axis_deg));
    kv(
        ui,
        "wall lines",
        format!(
            "{:+.2}° before, {:+.2}° after",
            h.deviation_deg, h.deviation_after_deg
        ),
    );
    if h.open {
        kv(
            ui,
            "lines' σ, open windows",
            format!("{:.2}°, sensors {:?}", h.sigma_deg, h.sensors),
        );
    } else if h.walls.is_empty() {
        kv(
            ui,
            "lines' σ, sensors",
            format!("{:.2}°, {:?}", h.sigma_deg, h.sensors),
        );
    } else {
        let walls: Vec<String> = h.walls.iter().map(|w| format!("s{w}")).collect();
        kv(
            ui,
            "lines' σ, walls",
            format!(
                "{:.2}°, {} (sensors {:?})",
                h.sigma_deg,
                walls.join(", "),
                h.sensors
            ),
        );
    }
    if let Some(age) = h.lines_age {
        kv(
            ui,
            "lines read",
            format!(
                "{:.2} m, {:+.1}° ago (their heading error's moment)",
                age.driven_m, age.turned_deg
            ),
        );
    }
    if let Some(gate_deg) = h.widened_gate_deg {
        kv(
            ui,
            "axis gate",
            format!("{gate_deg:.1}°, widened (heading uncertain)"),
        );
    }
}

/// The eigen-directions of the readings' information, each with whether it says more than the
/// prior.
fn directions_ui(ui: &mut egui::Ui, directions: &[ObservedDirection]) {
    for d in directions {
        let [x, y, h] = d.direction;
        ui.label(
            RichText::new(format!(
                "direction (x {x:+.2}, y {y:+.2}, heading {h:+.2}): information {:.0} /m², {}",
                d.information,
                if d.observed {
                    "observed"
                } else {
                    "left to the prior"
                }
            ))
            .weak(),
        );
    }
}

/// "Map again from this drift": the run mapped again with the drift estimated here as the
/// odometry's calibration (`drift_deg_per_m`, `drift_per_turn_pct`), corrected from its first
/// step, as `calibrate_first` does with the last step's; and, as there, with its pose corrected
/// against the map when the robot has driven `revisit_laps` laps of it by this step
/// (docs/algorithm.md §8.17, "runs that come back").
fn calibrate_button(
    ui: &mut egui::Ui,
    ctx: &InspectCtx,
    d: &DriftEstimate,
    commands: &mut Vec<Command>,
) {
    let laps_driven = ctx.view.map_after.laps_driven();
    let came_back = ctx.params.came_back(laps_driven);
    let calibrated = Params {
        pose_correction: ctx.params.pose_correction || came_back,
        ..ctx.params.calibrated_by((d.deg_per_m, d.turn_pct))
    };
    let pose = if came_back {
        format!(
            "; the robot drove {:.1} laps of its map by here (revisit_laps {}), so the pose is \
             corrected against the map too (pose_correction)",
            laps_driven.unwrap_or_default(),
            ctx.params.revisit_laps
        )
    } else {
        String::new()
    };
    let button = ui
        .button("Map again from this drift")
        .on_hover_text(format!(
            "Replays the run with the odometry calibrated as {:+.3}°/m and {:+.2} % of turns, \
         corrected from the first step (drift_deg_per_m, drift_per_turn_pct){pose}",
            d.deg_per_m, d.turn_pct
        ));
    if button.clicked() {
        commands.push(Command::SetParams(calibrated));
    }
}

/// The odometry's drift as the heading alone estimates it (docs/algorithm.md §8.17).
fn drift_rows(ui: &mut egui::Ui, d: &DriftEstimate) {
    kv(
        ui,
        "odometry's heading error",
        format!("{:+.2}° ± {:.2}°", d.heading_error_deg, d.sigma_deg),
    );
    kv(
        ui,
        "drift",
        format!("{:+.3}°/m, {:+.2} % of turns", d.deg_per_m, d.turn_pct),
    );
    match d.tracked_deg {
        Some(tracked_deg) => kv(
            ui,
            "corrected by",
            format!("{tracked_deg:+.2}°: the first pass's error here, smoothed"),
        ),
        None => kv(
            ui,
            "corrected",
            if d.drifting {
                "yes: the drift is significant"
            } else {
                "not yet: no significant drift"
            },
        ),
    }
}
