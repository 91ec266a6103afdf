//! The parameters panel: every mapping parameter of docs/algorithm.md §7 and §8, edited in the run's
//! units with the paper's value beside each. A value is applied only when the whole parameter
//! set with it passes [`Params::validate`]; otherwise the field keeps the text and shows why.

use super::command::Command;
use crate::mapping::model::params::{parameter, ParamKind, Parameter, PARAMETERS};
use crate::mapping::{FitMode, Params, Preset, SplitMode};
use crate::units::Units;
use egui::{Color32, RichText};
use std::collections::BTreeMap;

/// Colour of a refused value's reason.
const ERROR: Color32 = Color32::from_rgb(0xe0, 0x40, 0x40);

/// The numeric fields, in declaration order ([`PARAMETERS`]): every parameter but the flags
/// and the choices, with `split_fixed` (the fixed split's length) after `t_gap`'s neighbours,
/// where the split rule is shown.
fn numeric_fields() -> impl Iterator<Item = &'static Parameter> {
    PARAMETERS
        .iter()
        .filter(|p| !matches!(p.kind, ParamKind::Flag | ParamKind::Choice) || p.name == "split")
}

/// The panel's label of field `name`: its name, with the paper's symbol where it has one.
fn label_of(name: &str) -> &str {
    match name {
        "accuracy_pct" => "ξ accuracy (%)",
        "orientation_deg" => "θ_o (°)",
        "split" => "split length",
        other => other,
    }
}

/// The value of field `name` of `p` in the units the panel shows (run units, degrees); the
/// fixed split's length for `split`.
fn value_of(p: &Params, name: &str, units: Units) -> f64 {
    match (name, p.split) {
        ("split", SplitMode::Fixed(v)) => units.from_m(v),
        ("split", SplitMode::Resolution) => 0.0,
        _ => p.number(name, units).unwrap_or(f64::NAN),
    }
}

/// `p` with field `name` set to `v` (in the panel's units).
fn with_value(p: &Params, name: &str, v: f64, units: Units) -> Params {
    let mut p = p.clone();
    if name == "split" {
        p.split = SplitMode::Fixed(units.to_m(v));
    } else {
        p.set_number(name, v, units);
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
    let differs = |name: &str| {
        let (mut a, mut b) = (Params::paper(), Params::paper());
        a.take_from(name, params);
        b.take_from(name, &base);
        a != b
    };
    PARAMETERS
        .iter()
        .map(|p| p.name)
        .filter(|name| differs(name))
        .collect()
}

/// The flags, in declaration order: the paper's correlation, then the extensions.
fn switches() -> impl Iterator<Item = &'static str> {
    PARAMETERS
        .iter()
        .filter(|p| p.kind == ParamKind::Flag)
        .map(|p| p.name)
}

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
fn parse(text: &str, kind: ParamKind) -> Result<f64, String> {
    let v: f64 = text
        .trim()
        .parse()
        .map_err(|_| format!("`{}` is not a number", text.trim()))?;
    if !v.is_finite() {
        return Err("must be a finite number".to_owned());
    }
    if kind == ParamKind::Count && (v < 0.0 || v.fract() != 0.0) {
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
        for name in numeric_fields().map(|p| p.name) {
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
    state.sync(info.params, info.units);
    let rows = Rows {
        params: info.params,
        preset: Params::preset(info.preset),
        units: info.units,
        changed: changed_fields(info.params, info.preset),
    };
    if let Some(f) = info.rerun_progress {
        ui.add(
            egui::ProgressBar::new(f)
                .show_percentage()
                .text(format!("re-running… {:.0}%", f * 100.0)),
        );
    }
    preset_buttons_ui(ui, info, &rows.preset, &mut commands);
    baseline_ui(ui, info, &mut commands);
    ui.separator();
    if !rows.changed.is_empty() {
        ui.label(
            RichText::new(format!(
                "{} ≠ {}: the marked fields",
                rows.changed.len(),
                preset_name(info.preset)
            ))
            .color(CHANGED),
        );
    }
    for unmet in info.params.unmet_needs() {
        ui.add(egui::Label::new(RichText::new(format!("warning: {unmet}")).color(CHANGED)).wrap());
    }
    egui::Grid::new("params_grid")
        .num_columns(3)
        .striped(true)
        .show(ui, |ui| {
            ui.label(RichText::new("parameter").weak());
            ui.label(RichText::new(format!("value ({})", info.units.symbol())).weak());
            ui.label(RichText::new(format!("≠ {}", preset_name(info.preset))).weak())
                .on_hover_text("the preset's value, where a field differs from it");
            ui.end_row();
            for field in numeric_fields() {
                if field.name == "split" {
                    rows.split_ui(ui, &mut commands);
                    if !matches!(rows.params.split, SplitMode::Fixed(_)) {
                        continue;
                    }
                }
                rows.number_ui(ui, state, field, &mut commands);
            }
            rows.fit_ui(ui, &mut commands);
            for name in switches() {
                rows.switch_ui(ui, name, &mut commands);
            }
        });
    commands
}

/// The preset buttons, loading and saving, and the reset to the preset.
fn preset_buttons_ui(
    ui: &mut egui::Ui,
    info: &ParamsPanelInfo,
    preset: &Params,
    commands: &mut Vec<Command>,
) {
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
            info.params != preset,
            egui::Button::new(match info.preset {
                Preset::Paper => "Reset to the paper's defaults".to_owned(),
                other => format!("Reset to the {} values", preset_name(other)),
            }),
        )
        .clicked()
    {
        commands.push(Command::SetPreset(info.preset));
    }
}

/// What the grid's rows share: the parameters, the preset's, the units, the changed fields.
struct Rows<'a> {
    params: &'a Params,
    preset: Params,
    units: Units,
    changed: Vec<&'static str>,
}

impl Rows<'_> {
    fn is_changed(&self, name: &str) -> bool {
        self.changed.contains(&name)
    }

    /// Sends `candidate` when it is valid and new; the reason when it is refused.
    fn submit(&self, candidate: Params, commands: &mut Vec<Command>) -> Result<(), String> {
        candidate.validate().map_err(|e| e.to_string())?;
        if candidate != *self.params {
            commands.push(Command::SetParams(candidate));
        }
        Ok(())
    }

    /// The split rule's row (its length follows as a numeric row when fixed).
    fn split_ui(&self, ui: &mut egui::Ui, commands: &mut Vec<Command>) {
        field_label(ui, "split", self.is_changed("split"));
        let fixed = matches!(self.params.split, SplitMode::Fixed(_));
        egui::ComboBox::from_id_salt("split_mode")
            .width(86.0)
            .selected_text(if fixed { "fixed" } else { "resolution" })
            .show_ui(ui, |ui| {
                if ui.selectable_label(!fixed, "resolution").clicked() && fixed {
                    let mut p = self.params.clone();
                    p.split = SplitMode::Resolution;
                    let _ = self.submit(p, commands);
                }
                if ui.selectable_label(fixed, "fixed").clicked() && !fixed {
                    let mut p = self.params.clone();
                    p.split = SplitMode::Fixed(crate::units::inches(2.0));
                    let _ = self.submit(p, commands);
                }
            });
        let preset_text = match self.preset.split {
            SplitMode::Fixed(_) => "fixed",
            SplitMode::Resolution => "resolution",
        };
        preset_value_label(ui, preset_text, self.is_changed("split"));
        ui.end_row();
    }

    /// A numeric field's row, and the reason below it when its text was refused.
    fn number_ui(
        &self,
        ui: &mut egui::Ui,
        state: &mut ParamsPanelState,
        field: &'static Parameter,
        commands: &mut Vec<Command>,
    ) {
        let (name, units) = (field.name, self.units);
        let label_response =
            field_label(ui, label_of(name), self.is_changed(name)).on_hover_text(field.help.trim());
        let text = state.texts.entry(name).or_default();
        let edit = ui.add(
            egui::TextEdit::singleline(text)
                .desired_width(60.0)
                .id_salt(("param", name)),
        );
        let edit = edit.labelled_by(label_response.id);
        let preset_number = format_number(value_of(&self.preset, name, units));
        let preset_text = match field.kind {
            ParamKind::Length => format!("{preset_number} {}", units.symbol()),
            _ => preset_number,
        };
        preset_value_label(ui, &preset_text, self.is_changed(name));
        ui.end_row();
        if edit.lost_focus() {
            let text = text.clone();
            let result = parse(&text, field.kind).and_then(|v| {
                let now = value_of(self.params, name, units);
                if (v - now).abs() <= 1e-12 * v.abs().max(1.0) {
                    Ok(())
                } else {
                    self.submit(with_value(self.params, name, v, units), commands)
                }
            });
            match result {
                Ok(()) => state.errors.remove(name),
                Err(e) => state.errors.insert(name, e),
            };
        }
        if let Some(e) = state.errors.get(name) {
            ui.label("");
            ui.add(egui::Label::new(RichText::new(format!("refused: {e}")).color(ERROR)).wrap());
            ui.label("");
            ui.end_row();
        }
    }

    /// The fit's row.
    fn fit_ui(&self, ui: &mut egui::Ui, commands: &mut Vec<Command>) {
        field_label(ui, "fit", self.is_changed("fit"));
        let fit_name = |mode: FitMode| match mode {
            FitMode::EndPoints => "end points",
            FitMode::TotalLeastSquares => "least squares",
        };
        egui::ComboBox::from_id_salt("fit_mode")
            .width(86.0)
            .selected_text(fit_name(self.params.fit))
            .show_ui(ui, |ui| {
                for mode in [FitMode::EndPoints, FitMode::TotalLeastSquares] {
                    let selected = self.params.fit == mode;
                    if ui.selectable_label(selected, fit_name(mode)).clicked() && !selected {
                        let mut p = self.params.clone();
                        p.fit = mode;
                        let _ = self.submit(p, commands);
                    }
                }
            });
        preset_value_label(ui, fit_name(self.preset.fit), self.is_changed("fit"));
        ui.end_row();
    }

    /// A flag's row.
    fn switch_ui(&self, ui: &mut egui::Ui, name: &'static str, commands: &mut Vec<Command>) {
        let help = parameter(name).map_or("", |p| p.help.trim());
        field_label(ui, name, self.is_changed(name)).on_hover_text(help);
        let mut on = self.params.flag(name) == Some(true);
        if ui.checkbox(&mut on, "").changed() {
            let mut p = self.params.clone();
            p.set_flag(name, on);
            let _ = self.submit(p, commands);
        }
        let preset_on = self.preset.flag(name) == Some(true);
        preset_value_label(
            ui,
            if preset_on { "on" } else { "off" },
            self.is_changed(name),
        );
        ui.end_row();
    }
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
            for name in switches() {
                let mut p = base.clone();
                p.set_flag(name, base.flag(name) != Some(true));
                assert_eq!(changed_fields(&p, preset), vec![name], "{name}");
            }
        }
        assert!(switches().any(|name| name == "memory_stacks"));
        assert!(switches().any(|name| name == "memory_joints"));
        assert!(switches().any(|name| name == "open_windows"));
        assert_eq!(
            switches().count(),
            27,
            "correlate and the 26 extension flags"
        );
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
        for name in numeric_fields().map(|p| p.name) {
            if name == "split" {
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
