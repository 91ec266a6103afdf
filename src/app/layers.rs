//! One checkbox per scene layer, each with the legend of what it draws.

use super::command::Command;
use super::map_view::colour;
use crate::scene::{Glyph, Layer, LayerSet, LegendEntry};
use egui::{Sense, Stroke, Vec2};

fn swatch(ui: &mut egui::Ui, entry: &LegendEntry) {
    let (rect, _) = ui.allocate_exact_size(Vec2::new(24.0, 12.0), Sense::hover());
    let p = ui.painter_at(rect);
    let st = &entry.style;
    let stroke_c = st.stroke.map(|c| colour(c, st.opacity.max(0.5)));
    let fill_c = st.fill.map(|c| colour(c, st.opacity.max(0.5)));
    let c = rect.center();
    let line = |p: &egui::Painter| {
        if let Some(s) = stroke_c {
            p.line_segment(
                [egui::pos2(rect.left(), c.y), egui::pos2(rect.right(), c.y)],
                Stroke::new(st.stroke_width_px.clamp(1.0, 6.0), s),
            );
        }
    };
    match entry.glyph {
        Glyph::Line => line(&p),
        Glyph::LineWithMarker(_) => {
            line(&p);
            p.circle_filled(c, 3.5, fill_c.or(stroke_c).unwrap_or(egui::Color32::GRAY));
        }
        Glyph::Marker(_) => {
            p.circle_filled(c, 4.0, fill_c.or(stroke_c).unwrap_or(egui::Color32::GRAY));
        }
        Glyph::Area => {
            p.rect_filled(
                rect.shrink(1.0),
                2.0,
                fill_c.or(stroke_c).unwrap_or(egui::Color32::GRAY),
            );
        }
        Glyph::None => {}
    }
}

/// Draws the layer list; `legend` is the current scene's.
pub fn layers_ui(ui: &mut egui::Ui, layers: LayerSet, legend: &[LegendEntry]) -> Vec<Command> {
    let mut commands = Vec::new();
    ui.heading("Layers");
    for layer in Layer::ALL {
        let mut on = layers.contains(layer);
        if ui.checkbox(&mut on, layer.label()).changed() {
            commands.push(Command::ToggleLayer(layer));
        }
        if on {
            for entry in legend.iter().filter(|e| e.layer == layer) {
                ui.horizontal(|ui| {
                    ui.add_space(22.0);
                    swatch(ui, entry);
                    ui.label(egui::RichText::new(entry.label).small());
                });
            }
        }
    }
    commands
}
