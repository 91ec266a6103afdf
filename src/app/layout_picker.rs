//! The layout picker: a log that cannot be read without a sensor layout (a table, an MCAP
//! without `/tf_static`) waits here while the user picks a shipped layout or a layout file
//! (and, for a table, its length unit); then it is imported as `sonarmap convert --layout`
//! would. Cancelling keeps the run that was open.

use super::command::Command;
use super::layout_choice::LayoutChoice;
use super::loaded::Source;
use crate::import::NamedBytes;
use crate::units::Units;

/// The shipped layouts offered, by [`crate::import::builtin_layout`] name.
pub const SHIPPED_LAYOUTS: [(&str, &str); 2] = [
    ("pioneer_8_8", "Pioneer, 8 front + 8 rear sonars"),
    ("nomad_200", "Nomad 200, 16 sonars in a ring"),
];

/// The length units a table may be written in.
const TABLE_UNITS: [Units; 4] = [
    Units::Metres,
    Units::Centimetres,
    Units::Millimetres,
    Units::Inches,
];

/// A log waiting for its layout.
pub struct LayoutPicker {
    pub(super) source: Source,
    pub(super) bytes: Vec<u8>,
    /// Why the importer asked for a layout.
    pub(super) reason: String,
    /// The table's length unit.
    pub(super) units: Units,
    /// The poses table, for a table of ranges only.
    pub(super) poses: Option<NamedBytes>,
}

impl LayoutPicker {
    /// The log's name.
    pub fn file_name(&self) -> &str {
        match &self.source {
            Source::File(p) => p.to_str().unwrap_or("the log"),
            Source::BuiltIn(n) | Source::Bytes(n) => n,
        }
    }
}

/// Draws the picker; gives the command chosen (a layout, a layout file to ask for, cancel).
pub fn layout_picker_ui(ctx: &egui::Context, picker: &mut LayoutPicker) -> Vec<Command> {
    let mut commands = Vec::new();
    egui::Window::new("This log needs a sensor layout")
        .id(egui::Id::unique("layout_picker"))
        .anchor(egui::Align2::CENTER_CENTER, egui::Vec2::ZERO)
        .collapsible(false)
        .resizable(false)
        .show(ctx, |ui| {
            ui.set_max_width(520.0);
            ui.label(egui::RichText::new(picker.file_name()).strong());
            ui.add(egui::Label::new(egui::RichText::new(&picker.reason).weak()).wrap());
            ui.separator();
            ui.horizontal(|ui| {
                ui.label("Lengths in the table:");
                for u in TABLE_UNITS {
                    ui.selectable_value(&mut picker.units, u, u.symbol());
                }
            });
            ui.horizontal(|ui| {
                let poses = picker.poses.as_ref().map_or("none", |p| p.name.as_str());
                ui.label(format!("Poses table: {poses}"));
                if ui
                    .small_button("Poses file…")
                    .on_hover_text("For a table of ranges only: its poses, t x y heading")
                    .clicked()
                {
                    commands.push(Command::ChoosePosesFile);
                }
            });
            ui.label("Shipped layouts:");
            for (name, what) in SHIPPED_LAYOUTS {
                if ui.button(name).on_hover_text(what).clicked() {
                    commands.push(Command::OpenWithLayout(LayoutChoice::Shipped(
                        name.to_owned(),
                    )));
                }
            }
            ui.horizontal(|ui| {
                if ui
                    .button("Layout file…")
                    .on_hover_text("A sonarmap-layout JSON file (docs/formats.md)")
                    .clicked()
                {
                    commands.push(Command::ChooseLayoutFile);
                }
                if ui.button("Cancel").clicked() {
                    commands.push(Command::CancelLayoutPicker);
                }
            });
        });
    commands
}
