//! The in-app file dialog, drawn by egui itself: a path field with Tab completion, the recent
//! folders, the folder's entries (folders first, then the files of the kinds asked for), and
//! Open/Save. Used when the system dialog cannot work ([`super::file_dialog`]). Errors (a
//! folder that cannot be read, a name that is not there) are shown in the dialog; nothing is
//! written here, the caller does that.
//!
//! (egui_file 0.29 fits egui 0.37, but labels its title and entries with emoji that egui's
//! default fonts do not have: they would draw as boxes.)

use super::file_dialog::FilePurpose;
use std::path::{Path, PathBuf};

/// Colour of the dialog's error line.
const ERROR: egui::Color32 = egui::Color32::from_rgb(0xe0, 0x40, 0x40);

/// One entry of the folder shown.
#[derive(Clone, Debug, PartialEq, Eq)]
struct Entry {
    name: String,
    is_dir: bool,
}

/// The in-app dialog while it is open.
pub struct InAppDialog {
    /// What the chosen path is for.
    pub purpose: FilePurpose,
    folder: PathBuf,
    /// The path field: a file name in `folder`, or a path (absolute or relative to `folder`).
    path_text: String,
    entries: Result<Vec<Entry>, String>,
    recent_folders: Vec<PathBuf>,
    /// Show every file, not only the kinds asked for.
    all_files: bool,
    error: Option<String>,
}

/// What the in-app dialog did this frame.
pub enum InAppAnswer {
    /// Still open.
    Open,
    /// A path chosen (the dialog is closed).
    Chosen(PathBuf),
    /// Closed without a path.
    Cancelled,
}

/// The entries of `folder`: folders, then files, each sorted by name; hidden ones left out.
/// `keep` decides which files are listed.
fn read_entries(folder: &Path, keep: &dyn Fn(&str) -> bool) -> Result<Vec<Entry>, String> {
    let read = std::fs::read_dir(folder)
        .map_err(|e| format!("Could not read the folder {}: {e}", folder.display()))?;
    let mut entries: Vec<Entry> = read
        .filter_map(Result::ok)
        .filter_map(|e| {
            let name = e.file_name().to_string_lossy().into_owned();
            let is_dir = e.path().is_dir();
            (!name.starts_with('.') && (is_dir || keep(&name))).then_some(Entry { name, is_dir })
        })
        .collect();
    entries.sort_by(|a, b| b.is_dir.cmp(&a.is_dir).then_with(|| a.name.cmp(&b.name)));
    Ok(entries)
}

/// Completes `text` (a path, absolute or relative to `folder`) as far as the names it could
/// be agree: the longest common prefix of the matching entries, with a `/` after a single
/// folder. `None` when nothing matches or nothing would be added.
pub fn complete_path(folder: &Path, text: &str) -> Option<String> {
    let (dir_text, prefix) = match text.rfind(std::path::MAIN_SEPARATOR) {
        Some(i) => (&text[..=i], &text[i + 1..]),
        None => ("", text),
    };
    let dir = folder.join(dir_text);
    let matches: Vec<(String, bool)> = std::fs::read_dir(&dir)
        .ok()?
        .filter_map(Result::ok)
        .map(|e| {
            (
                e.file_name().to_string_lossy().into_owned(),
                e.path().is_dir(),
            )
        })
        .filter(|(name, _)| {
            name.starts_with(prefix) && (prefix.starts_with('.') || !name.starts_with('.'))
        })
        .collect();
    let first = &matches.first()?.0;
    let common_len = matches.iter().fold(first.len(), |len, (name, _)| {
        first
            .chars()
            .zip(name.chars())
            .take_while(|(a, b)| a == b)
            .map(|(a, _)| a.len_utf8())
            .sum::<usize>()
            .min(len)
    });
    let mut completed = format!("{dir_text}{}", &first[..common_len]);
    if matches.len() == 1 && matches[0].1 {
        completed.push(std::path::MAIN_SEPARATOR);
    }
    (completed != text).then_some(completed)
}

impl InAppDialog {
    /// Opens the dialog in `folder` (else the working directory), with `file_name` proposed
    /// when saving.
    pub fn open(
        purpose: FilePurpose,
        folder: Option<&Path>,
        file_name: &str,
        recent_folders: Vec<PathBuf>,
    ) -> Self {
        let folder = folder
            .filter(|f| f.is_dir())
            .map(Path::to_path_buf)
            .or_else(|| std::env::current_dir().ok())
            .unwrap_or_else(|| PathBuf::from("."));
        let mut dialog = InAppDialog {
            purpose,
            folder: PathBuf::new(),
            path_text: if purpose.is_save() {
                file_name.to_owned()
            } else {
                String::new()
            },
            entries: Ok(Vec::new()),
            recent_folders,
            all_files: false,
            error: None,
        };
        dialog.go_to(folder);
        dialog
    }

    /// The folder shown.
    pub fn directory(&self) -> &Path {
        &self.folder
    }

    fn go_to(&mut self, folder: PathBuf) {
        // Absolute, so that "Up" and the recent folders work from a relative path too.
        self.folder = std::fs::canonicalize(&folder).unwrap_or(folder);
        self.refresh();
    }

    fn refresh(&mut self) {
        let extensions = self.purpose.extensions();
        let all = self.all_files;
        let keep = |name: &str| {
            all || Path::new(name)
                .extension()
                .and_then(|e| e.to_str())
                .is_some_and(|e| extensions.iter().any(|x| x.eq_ignore_ascii_case(e)))
        };
        self.entries = read_entries(&self.folder, &keep);
        self.error = None;
    }

    /// The path the field names: absolute, or relative to the folder shown.
    fn target(&self) -> PathBuf {
        self.folder.join(self.path_text.trim())
    }

    /// Accepts the field: a folder is entered; a file is chosen (when opening it must exist;
    /// when saving, its folder must).
    fn accept(&mut self) -> Option<PathBuf> {
        if self.path_text.trim().is_empty() {
            self.error = Some("type or pick a file name".to_owned());
            return None;
        }
        let target = self.target();
        if target.is_dir() {
            self.path_text.clear();
            self.go_to(target);
            return None;
        }
        if self.purpose.is_save() {
            match target.parent() {
                Some(dir) if dir.is_dir() => Some(target),
                _ => {
                    self.error = Some(format!("no folder {}", target.display()));
                    None
                }
            }
        } else if target.is_file() {
            Some(target)
        } else {
            self.error = Some(format!("no file {}", target.display()));
            None
        }
    }

    /// Draws the dialog and says what it did.
    pub fn show(&mut self, ctx: &egui::Context) -> InAppAnswer {
        let mut answer = InAppAnswer::Open;
        let mut open = true;
        let mut go_to: Option<PathBuf> = None;
        egui::Window::new(self.purpose.title())
            .id(egui::Id::unique("in_app_file_dialog"))
            .open(&mut open)
            .anchor(egui::Align2::CENTER_CENTER, egui::Vec2::ZERO)
            .default_size(egui::vec2(620.0, 460.0))
            .collapsible(false)
            .show(ctx, |ui| {
                self.folders_ui(ui, &mut go_to);
                ui.separator();
                if let Some(name) = self.entries_ui(ui, &mut go_to) {
                    self.path_text = name;
                    if let Some(path) = self.accept() {
                        answer = InAppAnswer::Chosen(path);
                    }
                }
                ui.separator();
                ui.horizontal(|ui| self.path_field_ui(ui, &mut answer));
                ui.horizontal(|ui| self.options_ui(ui));
            });
        if let Some(folder) = go_to {
            self.go_to(folder);
        }
        if !open || ctx.input(|i| i.key_pressed(egui::Key::Escape)) {
            answer = InAppAnswer::Cancelled;
        }
        answer
    }

    /// The folder shown with its Up button, and the recent folders; a click sets `go_to`.
    fn folders_ui(&self, ui: &mut egui::Ui, go_to: &mut Option<PathBuf>) {
        ui.horizontal(|ui| {
            if ui
                .add_enabled(self.folder.parent().is_some(), egui::Button::new("Up"))
                .on_hover_text("The parent folder")
                .clicked()
            {
                *go_to = self.folder.parent().map(Path::to_path_buf);
            }
            ui.label(egui::RichText::new(self.folder.display().to_string()).strong());
        });
        if !self.recent_folders.is_empty() {
            ui.horizontal_wrapped(|ui| {
                ui.label(egui::RichText::new("Recent folders:").weak());
                for folder in &self.recent_folders {
                    let name = folder.file_name().map_or_else(
                        || folder.display().to_string(),
                        |n| n.to_string_lossy().into_owned(),
                    );
                    if ui
                        .small_button(name)
                        .on_hover_text(folder.display().to_string())
                        .clicked()
                    {
                        *go_to = Some(folder.clone());
                    }
                }
            });
        }
    }

    /// The folder's entries: a click on a folder sets `go_to`, on a file puts its name in the
    /// path field; gives the file double-clicked.
    fn entries_ui(&mut self, ui: &mut egui::Ui, go_to: &mut Option<PathBuf>) -> Option<String> {
        let list_height = (ui.available_height() - 70.0).max(120.0);
        let mut accept_name: Option<String> = None;
        egui::ScrollArea::vertical()
            .max_height(list_height)
            .auto_shrink([false, false])
            .show(ui, |ui| match &self.entries {
                Err(e) => {
                    ui.colored_label(ERROR, e);
                }
                Ok(entries) if entries.is_empty() => {
                    ui.label(egui::RichText::new("(no files of this kind here)").weak());
                }
                Ok(entries) => {
                    for entry in entries {
                        let text = if entry.is_dir {
                            format!("{}/", entry.name)
                        } else {
                            entry.name.clone()
                        };
                        let selected = !entry.is_dir && self.path_text == entry.name;
                        let r = ui.selectable_label(selected, text);
                        if entry.is_dir && (r.clicked() || r.double_clicked()) {
                            *go_to = Some(self.folder.join(&entry.name));
                        } else if r.double_clicked() {
                            accept_name = Some(entry.name.clone());
                        } else if r.clicked() {
                            self.path_text = entry.name.clone();
                            self.error = None;
                        }
                    }
                }
            });
        accept_name
    }

    /// The path field (Tab completes), Open or Save, and Cancel; sets `answer`.
    fn path_field_ui(&mut self, ui: &mut egui::Ui, answer: &mut InAppAnswer) {
        let label = ui.label("File:");
        let edit = ui
            .add(
                egui::TextEdit::singleline(&mut self.path_text)
                    .desired_width(ui.available_width() - 150.0)
                    .hint_text("a name here, or a path (Tab completes)")
                    .lock_focus(true)
                    .id_salt("in_app_file_dialog_path"),
            )
            .labelled_by(label.id);
        if edit.has_focus()
            && ui.input_mut(|i| i.consume_key(egui::Modifiers::NONE, egui::Key::Tab))
        {
            self.complete(ui, edit.id);
        }
        let enter = edit.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
        let verb = if self.purpose.is_save() {
            "Save"
        } else {
            "Open"
        };
        let clicked = ui.button(verb).clicked();
        if enter || clicked {
            if let Some(path) = self.accept() {
                *answer = InAppAnswer::Chosen(path);
            }
        }
        if ui.button("Cancel").clicked() {
            *answer = InAppAnswer::Cancelled;
        }
    }

    /// Completes the path field (the text edit `edit`), the cursor put at its end.
    fn complete(&mut self, ui: &egui::Ui, edit: egui::Id) {
        if let Some(completed) = complete_path(&self.folder, &self.path_text) {
            self.path_text = completed;
            if let Some(mut state) = egui::TextEdit::load_state(ui.ctx(), edit) {
                let end = egui::text::CCursor::new(self.path_text.chars().count());
                state
                    .cursor
                    .set_char_range(Some(egui::text::CCursorRange::one(end)));
                state.store(ui.ctx(), edit);
            }
        }
    }

    /// "Show all files", whether a file to save over exists, and the error.
    fn options_ui(&mut self, ui: &mut egui::Ui) {
        if ui.checkbox(&mut self.all_files, "Show all files").changed() {
            self.refresh();
        }
        if self.purpose.is_save() && self.target().is_file() {
            ui.label(egui::RichText::new("exists: it will be replaced").weak());
        }
        if let Some(e) = &self.error {
            ui.colored_label(ERROR, e);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tab_completes_to_the_common_prefix_and_a_single_folder_gets_a_slash() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::create_dir(dir.path().join("runs")).unwrap();
        std::fs::write(dir.path().join("room_a.log.json"), "").unwrap();
        std::fs::write(dir.path().join("room_b.log.json"), "").unwrap();
        let sep = std::path::MAIN_SEPARATOR;
        assert_eq!(complete_path(dir.path(), "ro").as_deref(), Some("room_"));
        assert_eq!(complete_path(dir.path(), "ru"), Some(format!("runs{sep}")));
        assert_eq!(complete_path(dir.path(), "room_"), None, "nothing to add");
        assert_eq!(complete_path(dir.path(), "x"), None, "nothing matches");
        let abs = format!("{}{sep}room_a", dir.path().display());
        assert_eq!(
            complete_path(Path::new("/"), &abs),
            Some(format!("{abs}.log.json"))
        );
    }
}
