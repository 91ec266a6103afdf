//! The timeline: a slider over the snapshots, step and play buttons, the playback rate, a
//! "go to" field and marks where notable things happened.

use super::command::Command;
use super::marks::{density, MarkKind};
use egui::{Color32, RichText, Sense, Stroke, Vec2};

/// Colour of spurious creations (the truth layer's vermillion).
const SPURIOUS_COLOUR: Color32 = Color32::from_rgb(0xD5, 0x5E, 0x00);

/// Colour of what differs from the pinned baseline (timeline marks, decision notes).
pub const BASELINE_COLOUR: Color32 = Color32::from_rgb(0xcc, 0x44, 0xdd);

/// Playback rates offered, snapshots per second.
pub const RATES: [f32; 6] = [1.0, 2.0, 4.0, 8.0, 15.0, 30.0];

/// What the timeline shows.
#[derive(Clone, Copy, Debug)]
pub struct TimelineInfo<'a> {
    /// Number of snapshots.
    pub len: usize,
    /// The snapshot shown.
    pub current: usize,
    /// Its time, seconds.
    pub t_s: f64,
    /// Snapshots with a mark of a kind shown, ascending.
    pub marks: &'a [usize],
    /// Each kind of mark: its count and whether it is shown.
    pub mark_counts: &'a [(MarkKind, usize, bool)],
    /// Snapshots where a decision differs directly from the pinned baseline (the parameter
    /// change itself, not its consequences), when known.
    pub baseline_marks: Option<&'a [usize]>,
    /// Snapshots that made a segment `eval` calls spurious (with a floor plan).
    pub spurious_marks: &'a [usize],
    /// True while the run plots are shown.
    pub show_plots: bool,
    /// True while playing.
    pub playing: bool,
    /// Playback rate, snapshots per second.
    pub rate: f32,
}

/// The label that shows the snapshot index (tests look for it).
pub fn snapshot_label(current: usize, len: usize) -> String {
    format!("Snapshot {current} / {}", len.saturating_sub(1))
}

/// Draws the timeline.
pub fn timeline_ui(ui: &mut egui::Ui, info: &TimelineInfo, jump_text: &mut String) -> Vec<Command> {
    let mut commands = Vec::new();
    ui.add_space(2.0);
    ui.horizontal(|ui| {
        transport_ui(ui, info, &mut commands);
        ui.separator();
        marks_ui(ui, info, &mut commands);
        ui.separator();
        rate_and_jump_ui(ui, info, jump_text, &mut commands);
    });
    // The slider, full width, with the marks painted under it.
    let width = ui.available_width().max(100.0);
    let mut k = info.current;
    let slider_width = width - 16.0;
    ui.spacing_mut().slider_width = slider_width;
    let last = info.len.saturating_sub(1);
    let slider = ui.add_enabled(
        info.len > 1,
        egui::Slider::new(&mut k, 0..=last.max(1)).show_value(false),
    );
    if slider.changed() && k != info.current {
        commands.push(Command::Seek(k));
    }
    marks_strip_ui(ui, info, slider.rect, slider_width, &mut commands);
    commands
}

/// The step and play buttons, the snapshot shown and its time.
fn transport_ui(ui: &mut egui::Ui, info: &TimelineInfo, commands: &mut Vec<Command>) {
    if ui
        .button("|<")
        .on_hover_text("First snapshot (Home)")
        .clicked()
    {
        commands.push(Command::First);
    }
    if ui
        .button("<")
        .on_hover_text("Previous snapshot (Left)")
        .clicked()
    {
        commands.push(Command::Step(-1));
    }
    let play = if info.playing { "Pause" } else { "Play" };
    if ui
        .button(play)
        .on_hover_text("Play or pause (Space)")
        .clicked()
    {
        commands.push(Command::TogglePlay);
    }
    if ui
        .button(">")
        .on_hover_text("Next snapshot (Right)")
        .clicked()
    {
        commands.push(Command::Step(1));
    }
    if ui
        .button(">|")
        .on_hover_text("Last snapshot (End)")
        .clicked()
    {
        commands.push(Command::Last);
    }
    ui.separator();
    ui.label(RichText::new(snapshot_label(info.current, info.len)).strong());
    ui.label(format!("t = {:.2} s", info.t_s));
}

/// The marks: previous and next, the plots switch, the kinds of mark shown, and the counts
/// of spurious snapshots and of differences from the baseline.
fn marks_ui(ui: &mut egui::Ui, info: &TimelineInfo, commands: &mut Vec<Command>) {
    if ui
        .button("< Prev mark")
        .on_hover_text("Previous notable snapshot ([)")
        .clicked()
    {
        commands.push(Command::PrevMark);
    }
    if ui
        .button("Next mark >")
        .on_hover_text("Next notable snapshot (])")
        .clicked()
    {
        commands.push(Command::NextMark);
    }
    if ui
        .selectable_label(info.show_plots, "Plots")
        .on_hover_text("Per-snapshot plots of the whole run, under the timeline")
        .clicked()
    {
        commands.push(Command::TogglePlots);
    }
    ui.menu_button(format!("{} marks", info.marks.len()), |ui| {
        ui.label("Marks shown (prev/next mark follow them)");
        for &(kind, count, shown) in info.mark_counts {
            let mut on = shown;
            if ui
                .checkbox(&mut on, format!("{} ({count})", kind.label()))
                .changed()
            {
                commands.push(Command::ToggleMarkKind(kind));
            }
        }
    })
    .response
    .on_hover_text("Choose the kinds of mark");
    if !info.spurious_marks.is_empty() {
        ui.label(
            RichText::new(format!(
                "{} with a spurious new segment",
                info.spurious_marks.len()
            ))
            .color(SPURIOUS_COLOUR),
        )
        .on_hover_text(
            "Snapshots whose new faces eval calls spurious (on no wall of the floor \
             plan): the short ticks at the top of the marks strip",
        );
    }
    if let Some(diff) = info.baseline_marks {
        ui.label(
            RichText::new(format!(
                "≠ baseline: {} snapshots with a direct difference",
                diff.len()
            ))
            .color(BASELINE_COLOUR),
        );
    }
}

/// The playback rate and the "go to" field.
fn rate_and_jump_ui(
    ui: &mut egui::Ui,
    info: &TimelineInfo,
    jump_text: &mut String,
    commands: &mut Vec<Command>,
) {
    egui::ComboBox::from_id_salt("rate")
        .selected_text(format!("{} /s", info.rate))
        .show_ui(ui, |ui| {
            for r in RATES {
                if ui
                    .selectable_label(info.rate == r, format!("{r} /s"))
                    .clicked()
                {
                    commands.push(Command::SetRate(r));
                }
            }
        });
    ui.separator();
    ui.label("Go to");
    let edit = ui.add(
        egui::TextEdit::singleline(jump_text)
            .desired_width(56.0)
            .hint_text("k"),
    );
    if edit.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter)) {
        match jump_text.trim().parse::<usize>() {
            Ok(k) => commands.push(Command::Seek(k)),
            Err(_) => jump_text.clear(),
        }
    }
}

/// Where the snapshots lie along the slider: from `left` (the first) to `right` (the last).
#[derive(Clone, Copy)]
struct Track {
    left: f32,
    right: f32,
    last: usize,
}

impl Track {
    /// The x of snapshot `m`.
    fn x_of(self, m: usize) -> f32 {
        if self.last == 0 {
            self.left
        } else {
            self.left + (self.right - self.left) * m as f32 / self.last as f32
        }
    }

    /// The snapshot a click at `x` asks for: the nearest of `marks` within a few pixels, else
    /// the snapshot under it.
    fn snapshot_at(self, x: f32, marks: &[usize]) -> usize {
        let near = marks
            .iter()
            .copied()
            .min_by(|a, b| {
                (self.x_of(*a) - x)
                    .abs()
                    .total_cmp(&(self.x_of(*b) - x).abs())
            })
            .filter(|m| (self.x_of(*m) - x).abs() < 5.0);
        near.unwrap_or_else(|| {
            let f = ((x - self.left) / (self.right - self.left).max(1.0)).clamp(0.0, 1.0);
            (f * self.last as f32).round() as usize
        })
    }
}

/// The strip of marks under the slider (at `slider`): spurious creations in its top band,
/// notable steps below them, differences from the baseline, the snapshot shown. A click
/// seeks.
fn marks_strip_ui(
    ui: &mut egui::Ui,
    info: &TimelineInfo,
    slider: egui::Rect,
    width: f32,
    commands: &mut Vec<Command>,
) {
    let (rect, response) = ui.allocate_exact_size(Vec2::new(width, 14.0), Sense::click());
    let band_m = rect.top() + 5.0;
    let track = Track {
        left: slider.left() + 6.0,
        right: slider.right() - 6.0,
        last: info.len.saturating_sub(1),
    };
    let painter = ui.painter_at(rect.expand2(Vec2::new(8.0, 0.0)));
    paint_marks(&painter, info, track, rect, band_m);
    // Spurious creations: short ticks in the top band, in the truth layer's colour.
    for &m in info.spurious_marks {
        let x = track.x_of(m);
        painter.line_segment(
            [egui::pos2(x, rect.top()), egui::pos2(x, band_m)],
            Stroke::new(2.0, SPURIOUS_COLOUR),
        );
    }
    for &m in info.baseline_marks.unwrap_or_default() {
        let x = track.x_of(m);
        painter.line_segment(
            [
                egui::pos2(x, rect.center().y),
                egui::pos2(x, rect.bottom() + 3.0),
            ],
            Stroke::new(2.0, BASELINE_COLOUR),
        );
    }
    let x = track.x_of(info.current);
    painter.line_segment(
        [egui::pos2(x, rect.top()), egui::pos2(x, rect.bottom())],
        Stroke::new(1.0, ui.visuals().strong_text_color()),
    );
    if response.clicked() {
        if let Some(p) = response.interact_pointer_pos() {
            commands.push(Command::Seek(track.snapshot_at(p.x, info.marks)));
        }
    }
}

/// The notable steps, below the strip's top band: a tick each, or a density strip when there
/// are more marks than pixels.
fn paint_marks(
    painter: &egui::Painter,
    info: &TimelineInfo,
    track: Track,
    rect: egui::Rect,
    band_m: f32,
) {
    let (left, right) = (track.left, track.right);
    let mark_colour = Color32::from_rgb(0xE6, 0x9F, 0x00);
    let columns = (right - left).max(1.0) as usize;
    if info.marks.len() > columns {
        // More marks than pixels: a density strip, each column as strong as its share of marks.
        let counts = density(info.marks, info.len, columns);
        let most = counts.iter().copied().max().unwrap_or(1).max(1) as f32;
        for (c, &n) in counts.iter().enumerate().filter(|(_, n)| **n > 0) {
            let x = left + (right - left) * c as f32 / (columns.max(2) - 1) as f32;
            let alpha = (0.25 + 0.75 * n as f32 / most).min(1.0);
            painter.line_segment(
                [egui::pos2(x, band_m + 1.0), egui::pos2(x, rect.bottom())],
                Stroke::new(1.0, mark_colour.gamma_multiply(alpha)),
            );
        }
    } else {
        for &m in info.marks {
            let x = track.x_of(m);
            painter.line_segment(
                [egui::pos2(x, band_m + 1.0), egui::pos2(x, rect.bottom())],
                Stroke::new(2.0, mark_colour),
            );
        }
    }
}
