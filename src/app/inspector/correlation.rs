//! A correlation: the two ends it joined, d_min against t_gap, and what it made (a corner, an
//! interpolated link, a shared end-point or nothing).

use super::context::InspectCtx;
use super::widgets::{heading, kv, FAIL, PASS};
use crate::mapping::model::trace::CorrelationKind;
use egui::RichText;

pub(super) fn correlation_ui(ui: &mut egui::Ui, ctx: &InspectCtx, c: usize) {
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

/// A correlation's hover text.
pub(super) fn correlation_hover(ctx: &InspectCtx, c: usize) -> Option<String> {
    let t = ctx.view.trace.correlations.get(c)?;
    Some(format!("correlation {c} (face {})", t.face))
}
