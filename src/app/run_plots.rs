//! The run plots: per-snapshot curves of the whole run under the timeline (egui_plot), linked
//! to it: a line marks the snapshot shown and a click seeks. Read from the replay's step
//! summaries (computed once per replay, off the UI thread), thinned to at most a point per
//! column of pixels; with a baseline pinned, its curves are drawn dashed beside the current ones.

use super::command::Command;
use super::run_plot::RunPlot;
use crate::replay::{StepPose, StepSummary, TruthSample};
use egui_plot::{Legend, Line, LineStyle, Plot, PlotPoints, VLine};

/// At most `columns` points of `value` over `steps`: each the largest value of its bucket of
/// snapshots (so a spike is never thinned away), at the bucket's first snapshot.
pub fn thinned<T>(steps: &[T], value: impl Fn(&T) -> f64, columns: usize) -> Vec<[f64; 2]> {
    let bucket = steps.len().div_ceil(columns.max(1)).max(1);
    steps
        .chunks(bucket)
        .enumerate()
        .map(|(i, chunk)| {
            let top = chunk.iter().map(&value).fold(0.0, f64::max);
            [(i * bucket) as f64, top]
        })
        .collect()
}

/// What the run plots draw: the replay's per-step figures.
#[derive(Clone, Copy)]
pub struct RunCurves<'a> {
    /// One summary a step.
    pub summaries: &'a [StepSummary],
    /// The map against its floor plan, every checkpoint interval.
    pub truth: &'a [TruthSample],
    /// One pose a step when the run was mapped with pose correction, else none.
    pub poses: &'a [StepPose],
}

/// Draws the plots of `summaries` (and of the baseline's, dashed); `current` is the snapshot
/// shown. Returns the seek a click asks for, and the plot chosen.
pub fn run_plots_ui(
    ui: &mut egui::Ui,
    shown: &mut RunPlot,
    curves: RunCurves,
    baseline: Option<&[StepSummary]>,
    current: usize,
) -> Vec<Command> {
    let RunCurves {
        summaries,
        truth,
        poses,
    } = curves;
    let mut commands = Vec::new();
    ui.horizontal(|ui| {
        ui.label("Plot");
        for p in RunPlot::ALL {
            ui.selectable_value(shown, p, p.label());
        }
        ui.label(egui::RichText::new("click: go to the snapshot").weak());
        if shown.needs_correction() && poses.is_empty() {
            ui.label(
                egui::RichText::new("this run was mapped without pose correction (§8.17)")
                    .color(ui.visuals().warn_fg_color),
            );
        }
    });
    let columns = ui.available_width().max(100.0) as usize;
    let plot = Plot::new("run_plots")
        .height(ui.available_height().max(100.0))
        .legend(Legend::default())
        .allow_drag(false)
        .allow_scroll(false)
        .allow_zoom(false)
        .allow_boxed_zoom(false)
        .include_y(0.0);
    let response = plot.show(ui, |plot_ui| {
        for (name, value) in shown.series() {
            let points = PlotPoints::from(thinned(summaries, |s| f64::from(value(s)), columns));
            plot_ui.line(Line::new(name, points));
            if let Some(b) = baseline {
                let points = PlotPoints::from(thinned(b, |s| f64::from(value(s)), columns));
                plot_ui.line(
                    Line::new(format!("{name} (baseline)"), points)
                        .style(LineStyle::dashed_loose()),
                );
            }
        }
        for (name, value) in shown.pose_series() {
            let points = thinned(poses, |p| f64::from(value(p)), columns);
            plot_ui.line(Line::new(name, PlotPoints::from(points)));
        }
        if *shown == RunPlot::Truth {
            let curve = |f: fn(&TruthSample) -> f64| {
                PlotPoints::from(
                    truth
                        .iter()
                        .map(|t| [t.snapshot as f64, f(t)])
                        .collect::<Vec<_>>(),
                )
            };
            plot_ui.line(Line::new(
                "spurious fraction",
                curve(|t| t.spurious_fraction),
            ));
            plot_ui.line(Line::new("coverage", curve(|t| t.coverage)));
        }
        plot_ui.vline(VLine::new("snapshot shown", current as f64));
        plot_ui.pointer_coordinate()
    });
    if response.response.clicked() {
        if let Some(p) = response.inner {
            let last = summaries.len().saturating_sub(1);
            commands.push(Command::Seek((p.x.round().max(0.0) as usize).min(last)));
        }
    }
    commands
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thinning_keeps_each_buckets_peak() {
        let summaries: Vec<StepSummary> = (0..10u32)
            .map(|k| StepSummary {
                segments: if k == 7 { 100 } else { k },
                ..StepSummary::default()
            })
            .collect();
        // Buckets of 4: [0..4) peak 3, [4..8) peak 100 (the spike at 7), [8..10) peak 9.
        assert_eq!(
            thinned(&summaries, |s| f64::from(s.segments), 3),
            vec![[0.0, 3.0], [4.0, 100.0], [8.0, 9.0]]
        );
        assert_eq!(
            thinned(&summaries, |s| f64::from(s.segments), 100).len(),
            10
        );
    }
}
