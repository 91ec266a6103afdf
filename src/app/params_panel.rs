//! The parameters panel: every mapping parameter of docs/algorithm.md §7 and §8, edited in the run's
//! units with the paper's value beside each. A value is applied only when the whole parameter
//! set with it passes [`Params::validate`]; otherwise the field keeps the text and shows why.

use super::command::Command;
use crate::mapping::{FitMode, Params, Preset, SplitMode};
use crate::units::Units;
use egui::{Color32, RichText};
use std::collections::BTreeMap;

/// Colour of a refused value's reason.
const ERROR: Color32 = Color32::from_rgb(0xe0, 0x40, 0x40);

/// What a numeric field holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    /// A plain number (percent, count).
    Plain,
    /// A length, shown in the run's units.
    Length,
    /// An angle, shown in degrees.
    Degrees,
    /// A whole number.
    Count,
}

/// The numeric fields: file name, label, kind.
const FIELDS: [(&str, &str, Kind); 12] = [
    ("accuracy_pct", "ξ accuracy (%)", Kind::Plain),
    ("d_max", "d_max", Kind::Length),
    ("min_range", "min_range", Kind::Length),
    ("t_gap", "t_gap", Kind::Length),
    ("orientation_deg", "θ_o (°)", Kind::Degrees),
    ("split_fixed", "split length", Kind::Length),
    ("max_step", "max_step", Kind::Length),
    ("memory_snapshots", "memory_snapshots", Kind::Count),
    ("memory_gap", "memory_gap", Kind::Length),
    ("memory_min_points", "memory_min_points", Kind::Count),
    ("support_cap", "support_cap", Kind::Count),
    ("min_piece_points", "min_piece_points", Kind::Count),
];

/// The value of field `name` of `p` in the units the panel shows (run units, degrees).
fn value_of(p: &Params, name: &str, units: Units) -> f64 {
    match name {
        "accuracy_pct" => p.accuracy_pct,
        "d_max" => units.from_m(p.d_max_m),
        "min_range" => units.from_m(p.min_range_m),
        "t_gap" => units.from_m(p.t_gap_m),
        "orientation_deg" => p.orientation_rad.to_degrees(),
        "split_fixed" => match p.split {
            SplitMode::Fixed(v) => units.from_m(v),
            SplitMode::Resolution => 0.0,
        },
        "max_step" => units.from_m(p.max_step_m),
        "memory_snapshots" => p.memory_snapshots as f64,
        "memory_gap" => units.from_m(p.memory_gap_m),
        "memory_min_points" => p.memory_min_points as f64,
        "support_cap" => p.support_cap as f64,
        "min_piece_points" => p.min_piece_points as f64,
        _ => f64::NAN,
    }
}

/// `p` with field `name` set to `v` (in the panel's units).
fn with_value(p: &Params, name: &str, v: f64, units: Units) -> Params {
    let mut p = p.clone();
    let count = |v: f64| if v >= 0.0 { v as usize } else { 0 };
    match name {
        "accuracy_pct" => p.accuracy_pct = v,
        "d_max" => p.d_max_m = units.to_m(v),
        "min_range" => p.min_range_m = units.to_m(v),
        "t_gap" => p.t_gap_m = units.to_m(v),
        "orientation_deg" => p.orientation_rad = v.to_radians(),
        "split_fixed" => p.split = SplitMode::Fixed(units.to_m(v)),
        "max_step" => p.max_step_m = units.to_m(v),
        "memory_snapshots" => p.memory_snapshots = count(v),
        "memory_gap" => p.memory_gap_m = units.to_m(v),
        "memory_min_points" => p.memory_min_points = count(v),
        "support_cap" => p.support_cap = count(v),
        "min_piece_points" => p.min_piece_points = count(v),
        _ => {}
    }
    p
}

/// The name of a preset, as the panel and the status bar show it.
pub fn preset_name(preset: Preset) -> &'static str {
    match preset {
        Preset::Paper => "paper",
        Preset::Extended => "extended",
    }
}

/// The fields (as the panel names them) where `params` differs from `preset`'s values.
pub fn changed_fields(params: &Params, preset: Preset) -> Vec<&'static str> {
    let base = Params::preset(preset);
    let mut changed: Vec<&'static str> = FIELDS
        .iter()
        .filter(|(name, _, _)| *name != "split_fixed")
        .filter(|(name, _, _)| {
            let (a, b) = (
                value_of(params, name, Units::Metres),
                value_of(&base, name, Units::Metres),
            );
            (a - b).abs() > 1e-12 * a.abs().max(b.abs()).max(1.0)
        })
        .map(|(name, _, _)| *name)
        .collect();
    let flags = [
        ("split", params.split != base.split),
        ("fit", params.fit != base.fit),
    ];
    changed.extend(flags.into_iter().filter(|(_, c)| *c).map(|(n, _)| n));
    changed.extend(
        SWITCHES
            .iter()
            .filter(|(_, get, _)| get(params) != get(&base))
            .map(|(name, _, _)| *name),
    );
    changed
}

/// A parameter switched on or off: its name in the panel, its getter and its setter.
type Switch = (&'static str, fn(&Params) -> bool, fn(&mut Params, bool));

/// A [`Switch`] for the `Params` field `$field`, named `$name` in the panel (the field's name
/// unless given).
macro_rules! switch {
    ($field:ident) => {
        switch!(stringify!($field), $field)
    };
    ($name:expr, $field:ident) => {
        (
            $name,
            |p: &Params| p.$field,
            |p: &mut Params, v: bool| p.$field = v,
        )
    };
}

/// The parameters switched on or off, in the panel's order.
const SWITCHES: &[Switch] = &[
    switch!("correlation", correlate),
    switch!(constant_depth),
    switch!(merge_duplicates),
    switch!(corner_guard),
    switch!(arc_features),
    switch!(explain_readings),
    switch!(free_space),
    switch!(confirm_segments),
    switch!(baseline_confirm),
    switch!(refit_unconfirms),
    switch!(plane_gate),
    switch!(echo_fit),
    switch!(corner_diagonals),
    switch!(round_reflectors),
    switch!(settled_walls),
    switch!(memory_stacks),
    switch!(memory_joints),
];

/// Colour of a field's name when its value differs from the preset's.
const CHANGED: Color32 = Color32::from_rgb(0xe0, 0x90, 0x30);

/// A field's name, in [`CHANGED`] when its value differs from the preset's.
fn field_label(ui: &mut egui::Ui, label: &str, changed: bool) -> egui::Response {
    if changed {
        ui.label(RichText::new(label).color(CHANGED))
            .on_hover_text("differs from the preset")
    } else {
        ui.label(label)
    }
}

/// The preset's value of a field, shown "≠ value" in [`CHANGED`] only when the field differs
/// from it (the column stays narrow, so the panel does too).
fn preset_value_label(ui: &mut egui::Ui, text: &str, changed: bool) {
    if changed {
        ui.label(RichText::new(format!("≠ {text}")).color(CHANGED))
            .on_hover_text("the preset's value");
    } else {
        ui.label("");
    }
}

/// A number without trailing zeros (at most 4 decimals).
pub fn format_number(v: f64) -> String {
    let s = format!("{v:.4}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".to_owned()
    } else {
        s.to_owned()
    }
}

/// Parses a field's text; the reason when it cannot be used.
fn parse(text: &str, kind: Kind) -> Result<f64, String> {
    let v: f64 = text
        .trim()
        .parse()
        .map_err(|_| format!("`{}` is not a number", text.trim()))?;
    if !v.is_finite() {
        return Err("must be a finite number".to_owned());
    }
    if kind == Kind::Count && (v < 0.0 || v.fract() != 0.0) {
        return Err("must be a whole number of at least 0".to_owned());
    }
    Ok(v)
}

/// The panel's editing state (not persisted): the text of every field and the reason a value
/// was refused.
#[derive(Clone, Debug, Default)]
pub struct ParamsPanelState {
    texts: BTreeMap<&'static str, String>,
    errors: BTreeMap<&'static str, String>,
    shown_for: Option<(Params, Units)>,
}

impl ParamsPanelState {
    /// The reason the value of field `name` was refused, if it was.
    pub fn error(&self, name: &str) -> Option<&str> {
        self.errors.get(name).map(String::as_str)
    }

    fn sync(&mut self, params: &Params, units: Units) {
        if self
            .shown_for
            .as_ref()
            .is_some_and(|(p, u)| p == params && *u == units)
        {
            return;
        }
        self.errors.clear();
        for (name, _, _) in FIELDS {
            let v = value_of(params, name, units);
            self.texts.insert(name, format_number(v));
        }
        self.shown_for = Some((params.clone(), units));
    }
}

/// The comparison with the pinned baseline, in figures.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BaselineSummary {
    /// Snapshots where any decision differs.
    pub snapshots: usize,
    /// Differences the parameter change made itself.
    pub direct: usize,
    /// Differences that follow from earlier ones.
    pub consequential: usize,
    /// The first snapshot with a direct difference.
    pub first: Option<usize>,
}

impl BaselineSummary {
    /// The figures of a comparison.
    pub fn of(diff: &crate::diff::RunDiff) -> Self {
        Self {
            snapshots: diff.snapshots.len(),
            direct: diff.direct,
            consequential: diff.consequential,
            first: diff.first_difference,
        }
    }
}

/// What the panel shows besides the parameters.
#[derive(Clone, Copy, Debug)]
pub struct ParamsPanelInfo<'a> {
    /// The parameters asked for (possibly still being replayed).
    pub params: &'a Params,
    /// The run's units.
    pub units: Units,
    /// Fraction done while re-running.
    pub rerun_progress: Option<f32>,
    /// True while a baseline is pinned.
    pub pinned: bool,
    /// Fraction done of the baseline comparison, while it runs.
    pub diff_progress: Option<f32>,
    /// How the current parameters' decisions differ from the baseline's (when known).
    pub differing: Option<BaselineSummary>,
    /// The preset the values are compared with.
    pub preset: Preset,
}

/// The baseline's buttons and, while one is pinned, how the current parameters' decisions differ
/// from its: at the top of the panel, above the fields, so that they stay in view.
fn baseline_ui(ui: &mut egui::Ui, info: &ParamsPanelInfo, commands: &mut Vec<Command>) {
    ui.horizontal_wrapped(|ui| {
        if info.pinned {
            if ui
                .button("Unpin baseline")
                .on_hover_text("Stop comparing with the baseline")
                .clicked()
            {
                commands.push(Command::Unpin);
            }
            if let Some(f) = info.diff_progress {
                ui.add(
                    egui::ProgressBar::new(f)
                        .desired_width(100.0)
                        .text("comparing…"),
                );
            } else if let Some(d) = info.differing {
                ui.label(
                    RichText::new(format!(
                        "{} snapshots differ from the baseline: {} direct, {} consequential \
                         decisions",
                        d.snapshots, d.direct, d.consequential
                    ))
                    .color(super::timeline::BASELINE_COLOUR),
                )
                .on_hover_text(
                    "Direct: the same new segment met the same map and was decided otherwise \
                     (the parameter change itself). Consequential: what it met differs because \
                     an earlier decision differed. The timeline marks the direct ones.",
                );
                if let Some(k) = d.first {
                    if ui
                        .button("First difference")
                        .on_hover_text(
                            "Go to the first snapshot where the parameter change itself makes a \
                             decision differ (a direct difference)",
                        )
                        .clicked()
                    {
                        commands.push(Command::Seek(k));
                    }
                }
            }
        } else if ui
            .button("Pin as baseline")
            .on_hover_text("Keep these parameters and their results to compare later changes with")
            .clicked()
        {
            commands.push(Command::PinBaseline);
        }
    });
}

/// Draws the panel.
pub fn params_panel_ui(
    ui: &mut egui::Ui,
    state: &mut ParamsPanelState,
    info: &ParamsPanelInfo,
) -> Vec<Command> {
    let mut commands = Vec::new();
    let params = info.params;
    let units = info.units;
    state.sync(params, units);
    let paper = Params::preset(info.preset);
    let changed = changed_fields(params, info.preset);
    let is_changed = |name: &str| changed.contains(&name);
    if let Some(f) = info.rerun_progress {
        ui.add(
            egui::ProgressBar::new(f)
                .show_percentage()
                .text(format!("re-running… {:.0}%", f * 100.0)),
        );
    }
    ui.horizontal_wrapped(|ui| {
        if ui
            .button("Paper")
            .on_hover_text("The paper's values (docs/algorithm.md §7)")
            .clicked()
        {
            commands.push(Command::SetPreset(Preset::Paper));
        }
        if ui
            .button("Extended")
            .on_hover_text("The paper plus the extensions of docs/algorithm.md §8")
            .clicked()
        {
            commands.push(Command::SetPreset(Preset::Extended));
        }
        if ui.button("Load…").clicked() {
            commands.push(Command::LoadParamsDialog);
        }
        if ui.button("Save…").clicked() {
            commands.push(Command::SaveParamsDialog);
        }
    });
    if ui
        .add_enabled(
            *params != paper,
            egui::Button::new(match info.preset {
                Preset::Paper => "Reset to the paper's defaults".to_owned(),
                other => format!("Reset to the {} values", preset_name(other)),
            }),
        )
        .clicked()
    {
        commands.push(Command::SetPreset(info.preset));
    }
    baseline_ui(ui, info, &mut commands);
    ui.separator();
    if !changed.is_empty() {
        ui.label(
            RichText::new(format!(
                "{} ≠ {}: the marked fields",
                changed.len(),
                preset_name(info.preset)
            ))
            .color(CHANGED),
        );
    }
    let submit = |candidate: Params, commands: &mut Vec<Command>| -> Result<(), String> {
        candidate.validate().map_err(|e| e.to_string())?;
        if candidate != *params {
            commands.push(Command::SetParams(candidate));
        }
        Ok(())
    };
    egui::Grid::new("params_grid")
        .num_columns(3)
        .striped(true)
        .show(ui, |ui| {
            ui.label(RichText::new("parameter").weak());
            ui.label(RichText::new(format!("value ({})", units.symbol())).weak());
            ui.label(RichText::new(format!("≠ {}", preset_name(info.preset))).weak())
                .on_hover_text("the preset's value, where a field differs from it");
            ui.end_row();
            for (name, label, kind) in FIELDS {
                if name == "split_fixed" {
                    // The split mode, then its length when fixed.
                    field_label(ui, "split", is_changed("split"));
                    let fixed = matches!(params.split, SplitMode::Fixed(_));
                    egui::ComboBox::from_id_salt("split_mode")
                        .width(86.0)
                        .selected_text(if fixed { "fixed" } else { "resolution" })
                        .show_ui(ui, |ui| {
                            if ui.selectable_label(!fixed, "resolution").clicked() && fixed {
                                let mut p = params.clone();
                                p.split = SplitMode::Resolution;
                                let _ = submit(p, &mut commands);
                            }
                            if ui.selectable_label(fixed, "fixed").clicked() && !fixed {
                                let mut p = params.clone();
                                p.split = SplitMode::Fixed(crate::units::inches(2.0));
                                let _ = submit(p, &mut commands);
                            }
                        });
                    preset_value_label(
                        ui,
                        match paper.split {
                            SplitMode::Fixed(_) => "fixed",
                            SplitMode::Resolution => "resolution",
                        },
                        is_changed("split"),
                    );
                    ui.end_row();
                    if !matches!(params.split, SplitMode::Fixed(_)) {
                        continue;
                    }
                }
                let label_response = field_label(ui, label, is_changed(name));
                let text = state.texts.entry(name).or_default();
                let edit = ui.add(
                    egui::TextEdit::singleline(text)
                        .desired_width(60.0)
                        .id_salt(("param", name)),
                );
                let edit = edit.labelled_by(label_response.id);
                let paper_text = match kind {
                    Kind::Length => format!(
                        "{} {}",
                        format_number(value_of(&paper, name, units)),
                        units.symbol()
                    ),
                    _ => format_number(value_of(&paper, name, units)),
                };
                preset_value_label(ui, &paper_text, is_changed(name));
                ui.end_row();
                if edit.lost_focus() {
                    let text = text.clone();
                    let result = parse(&text, kind).and_then(|v| {
                        if (v - value_of(params, name, units)).abs() <= 1e-12 * v.abs().max(1.0) {
                            Ok(())
                        } else {
                            submit(with_value(params, name, v, units), &mut commands)
                        }
                    });
                    match result {
                        Ok(()) => {
                            state.errors.remove(name);
                        }
                        Err(e) => {
                            state.errors.insert(name, e);
                        }
                    }
                }
                if let Some(e) = state.errors.get(name) {
                    ui.label("");
                    ui.add(
                        egui::Label::new(RichText::new(format!("refused: {e}")).color(ERROR))
                            .wrap(),
                    );
                    ui.label("");
                    ui.end_row();
                }
            }
            field_label(ui, "fit", is_changed("fit"));
            let fit_name = |mode: FitMode| match mode {
                FitMode::EndPoints => "end points",
                FitMode::TotalLeastSquares => "least squares",
            };
            egui::ComboBox::from_id_salt("fit_mode")
                .width(86.0)
                .selected_text(fit_name(params.fit))
                .show_ui(ui, |ui| {
                    for mode in [FitMode::EndPoints, FitMode::TotalLeastSquares] {
                        if ui
                            .selectable_label(params.fit == mode, fit_name(mode))
                            .clicked()
                            && params.fit != mode
                        {
                            let mut p = params.clone();
                            p.fit = mode;
                            let _ = submit(p, &mut commands);
                        }
                    }
                });
            preset_value_label(ui, fit_name(paper.fit), is_changed("fit"));
            ui.end_row();
            for &(name, get, set) in SWITCHES {
                field_label(ui, name, is_changed(name));
                let mut on = get(params);
                if ui.checkbox(&mut on, "").changed() {
                    let mut p = params.clone();
                    set(&mut p, on);
                    let _ = submit(p, &mut commands);
                }
                let preset_text = if get(&paper) { "on" } else { "off" };
                preset_value_label(ui, preset_text, is_changed(name));
                ui.end_row();
            }
        });
    commands
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_lose_trailing_zeros() {
        assert_eq!(format_number(42.0000000001), "42");
        assert_eq!(format_number(0.25), "0.25");
        assert_eq!(format_number(-0.0), "0");
    }

    #[test]
    fn every_switch_that_differs_from_the_preset_is_named_as_changed() {
        // Each switch flipped alone on each preset is reported, by its panel name, and nothing
        // else is (before, the switches added after the long-run bounds were never named).
        for preset in [Preset::Paper, Preset::Extended] {
            let base = Params::preset(preset);
            assert!(changed_fields(&base, preset).is_empty());
            for &(name, get, set) in SWITCHES {
                let mut p = base.clone();
                set(&mut p, !get(&base));
                assert_eq!(changed_fields(&p, preset), vec![name], "{name}");
            }
        }
        assert!(SWITCHES.iter().any(|(name, ..)| *name == "memory_stacks"));
        assert!(SWITCHES.iter().any(|(name, ..)| *name == "memory_joints"));
        // The counts too: `min_piece_points` was missing from the panel.
        let p = Params {
            min_piece_points: 5,
            ..Params::extended()
        };
        assert_eq!(
            changed_fields(&p, Preset::Extended),
            vec!["min_piece_points"]
        );
    }

    #[test]
    fn fields_round_trip_through_the_panel_units() {
        let p = Params::paper();
        for (name, _, _) in FIELDS {
            if name == "split_fixed" {
                continue;
            }
            let v = value_of(&p, name, Units::Centimetres);
            let back = with_value(&p, name, v, Units::Centimetres);
            assert!(back.validate().is_ok(), "{name}");
        }
        assert_eq!(
            format_number(value_of(&p, "t_gap", Units::Inches)),
            "42",
            "t_gap in inches"
        );
    }
}
