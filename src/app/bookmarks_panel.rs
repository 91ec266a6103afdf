//! The bookmarks panel: name the current snapshot, list the bookmarks, jump to one. The
//! bookmarks themselves and their sidecar file are in [`super::bookmarks`].

use super::bookmarks::Bookmark;
use super::command::Command;
use egui::RichText;

/// Draws the bookmark list and the "add" row.
pub fn bookmarks_ui(
    ui: &mut egui::Ui,
    bookmarks: &[Bookmark],
    current: usize,
    name_text: &mut String,
) -> Vec<Command> {
    let mut commands = Vec::new();
    ui.horizontal(|ui| {
        let edit = ui.add(
            egui::TextEdit::singleline(name_text)
                .desired_width(130.0)
                .hint_text(format!("snapshot {current}")),
        );
        let enter = edit.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
        if ui
            .button("Add bookmark")
            .on_hover_text("Bookmark the current snapshot (Ctrl+B)")
            .clicked()
            || enter
        {
            commands.push(Command::AddBookmark(std::mem::take(name_text)));
        }
    });
    if bookmarks.is_empty() {
        ui.label(RichText::new("no bookmarks").weak());
    }
    for (i, b) in bookmarks.iter().enumerate() {
        ui.horizontal(|ui| {
            if ui
                .selectable_label(
                    b.snapshot == current,
                    format!("{} ({})", b.name, b.snapshot),
                )
                .on_hover_text("jump to this snapshot")
                .clicked()
            {
                commands.push(Command::Seek(b.snapshot));
            }
            if ui
                .small_button("remove")
                .on_hover_text("remove this bookmark")
                .clicked()
            {
                commands.push(Command::RemoveBookmark(i));
            }
        });
    }
    commands
}
