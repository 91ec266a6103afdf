//! The inspector's small shared widgets: pass/fail colours and cells, headings, key-value rows.

use crate::mapping::model::trace::Test;
use egui::{Color32, RichText};

/// Colour of a passed test.
pub const PASS: Color32 = Color32::from_rgb(0x2e, 0xa0, 0x43);
/// Colour of a failed test.
pub const FAIL: Color32 = Color32::from_rgb(0xd5, 0x5e, 0x00);

/// A pass/fail cell: ✔ or ✘ with text, coloured.
pub(super) fn verdict(ui: &mut egui::Ui, pass: bool) {
    let (text, colour) = if pass { ("pass", PASS) } else { ("FAIL", FAIL) };
    ui.label(RichText::new(text).color(colour).strong());
}

pub(super) fn coloured(ui: &mut egui::Ui, text: String, pass: bool) {
    ui.label(RichText::new(text).color(if pass { PASS } else { FAIL }));
}

pub(super) fn heading(ui: &mut egui::Ui, text: &str) {
    ui.add_space(6.0);
    ui.label(RichText::new(text).strong().size(15.0));
}

pub(super) fn kv(ui: &mut egui::Ui, key: &str, value: impl Into<egui::WidgetText>) {
    ui.label(RichText::new(key).weak());
    ui.label(value);
    ui.end_row();
}

/// A grid's header row: the column names, strong.
pub(super) fn header_row(ui: &mut egui::Ui, headers: &[&str]) {
    for h in headers {
        ui.label(RichText::new(*h).strong());
    }
    ui.end_row();
}

/// A test's cells: its value, its threshold, and the verdict with the margin (threshold -
/// value: how far inside or outside it the test fell), each length or angle written by `fmt`.
pub(super) fn test_cells(ui: &mut egui::Ui, t: &Test, fmt: &dyn Fn(f64) -> String) {
    coloured(ui, fmt(t.value), t.pass);
    ui.label(fmt(t.threshold));
    let (text, colour) = if t.pass {
        ("pass", PASS)
    } else {
        ("FAIL", FAIL)
    };
    ui.label(RichText::new(format!("{text}, margin {}", fmt(t.threshold - t.value))).color(colour))
        .on_hover_text("margin = threshold - value: positive inside the test, negative outside");
}
