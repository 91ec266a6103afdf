//! The menu bar, the keyboard shortcuts and their help window.

use super::command::{Command, PanelToggle};
use egui::{Key, KeyboardShortcut, Modifiers};
use std::path::PathBuf;

/// File ▸ Open…
pub const OPEN: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, Key::O);
/// File ▸ Reload.
pub const RELOAD: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, Key::R);
/// File ▸ Export SVG…
pub const EXPORT: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, Key::E);

/// Bookmark the current snapshot.
pub const BOOKMARK: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, Key::B);

/// Every shortcut with what it does, for the help window.
pub const SHORTCUTS: [(&str, &str); 20] = [
    ("Ctrl+O", "open a run log"),
    ("Ctrl+R", "reload the run log"),
    ("Ctrl+E", "export the map view as SVG"),
    ("Ctrl+B", "bookmark the current snapshot"),
    ("Enter", "apply a parameter / go to a snapshot (in a field)"),
    ("Left / Right", "previous / next snapshot"),
    ("Home / End", "first / last snapshot"),
    ("Space", "play / pause"),
    ("[ / ]", "previous / next mark"),
    ("F", "fit the view"),
    ("Z", "zoom to the selected segment"),
    ("Esc", "clear selection and ruler"),
    ("L", "show / hide the left panel"),
    ("I", "show / hide the decisions and inspector"),
    ("M", "map only: hide every side panel"),
    ("S", "A | B: baseline and current side by side (pinned)"),
    ("Shift+drag", "measure (ruler)"),
    ("Scroll / drag", "zoom / pan the map"),
    ("Double-click", "fit the view"),
    ("Drop a file", "open it"),
];

/// Reads the keyboard; navigation keys only when no text field has focus.
pub fn handle_shortcuts(ctx: &egui::Context) -> Vec<Command> {
    let mut commands = Vec::new();
    let typing = ctx.egui_wants_keyboard_input();
    ctx.input_mut(|i| {
        if i.consume_shortcut(&OPEN) {
            commands.push(Command::OpenDialog);
        }
        if i.consume_shortcut(&RELOAD) {
            commands.push(Command::Reload);
        }
        if i.consume_shortcut(&EXPORT) {
            commands.push(Command::ExportDialog);
        }
        if i.consume_shortcut(&BOOKMARK) {
            commands.push(Command::AddBookmark(String::new()));
        }
        if typing {
            return;
        }
        let keys = [
            (Key::ArrowLeft, Command::Step(-1)),
            (Key::ArrowRight, Command::Step(1)),
            (Key::Home, Command::First),
            (Key::End, Command::Last),
            (Key::Space, Command::TogglePlay),
            (Key::OpenBracket, Command::PrevMark),
            (Key::CloseBracket, Command::NextMark),
            (Key::F, Command::FitView),
            (Key::Z, Command::ZoomToSelection),
            (Key::Escape, Command::Select(crate::scene::SceneId::None)),
            (Key::L, Command::TogglePanel(PanelToggle::Left)),
            (Key::I, Command::TogglePanel(PanelToggle::Right)),
            (Key::M, Command::TogglePanel(PanelToggle::MapOnly)),
            (Key::S, Command::TogglePanel(PanelToggle::Split)),
        ];
        for (key, command) in keys {
            if i.consume_key(Modifiers::NONE, key) {
                commands.push(command);
            }
        }
    });
    commands
}

/// Draws the menu bar; `pinned` is true while a baseline is pinned.
pub fn menu_bar_ui(
    ui: &mut egui::Ui,
    recent: &[PathBuf],
    pinned: bool,
    settings: &super::settings::Settings,
) -> Vec<Command> {
    let mut commands = Vec::new();
    egui::MenuBar::new().ui(ui, |ui| {
        ui.menu_button("File", |ui| {
            file_menu_ui(ui, recent, settings, &mut commands)
        });
        ui.menu_button("View", |ui| view_menu_ui(ui, &mut commands));
        ui.menu_button("Parameters", |ui| {
            parameters_menu_ui(ui, pinned, &mut commands)
        });
        ui.menu_button("Help", |ui| {
            if ui.button("Keyboard shortcuts").clicked() {
                commands.push(Command::ToggleShortcuts);
            }
        });
    });
    commands
}

/// The File menu: open, recent files, reload, export and the figure's options.
fn file_menu_ui(
    ui: &mut egui::Ui,
    recent: &[PathBuf],
    settings: &super::settings::Settings,
    commands: &mut Vec<Command>,
) {
    let ctx = ui.ctx().clone();
    if ui
        .add(egui::Button::new("Open…").shortcut_text(ctx.format_shortcut(&OPEN)))
        .clicked()
    {
        commands.push(Command::OpenDialog);
    }
    ui.menu_button("Open Recent", |ui| {
        if recent.is_empty() {
            ui.label("no recent files");
        }
        for path in recent {
            if ui.button(path.display().to_string()).clicked() {
                commands.push(Command::Open(path.clone()));
            }
        }
    });
    if ui
        .add(egui::Button::new("Reload").shortcut_text(ctx.format_shortcut(&RELOAD)))
        .clicked()
    {
        commands.push(Command::Reload);
    }
    ui.separator();
    if ui
        .add(
            egui::Button::new("Export figure (SVG/PNG)…")
                .shortcut_text(ctx.format_shortcut(&EXPORT)),
        )
        .clicked()
    {
        commands.push(Command::ExportDialog);
    }
    let mut figure = settings.figure_style;
    if ui
        .checkbox(&mut figure, "Figure style")
        .on_hover_text(
            "Label only the selection and the map segments this snapshot's decisions \
             met",
        )
        .changed()
    {
        commands.push(Command::ToggleFigureStyle);
    }
    ui.horizontal(|ui| {
        ui.label("PNG size:");
        for scale in 1..=3 {
            if ui
                .selectable_label(settings.png_scale == scale, format!("{scale}x"))
                .on_hover_text("times the map view's size")
                .clicked()
            {
                commands.push(Command::SetPngScale(scale));
            }
        }
    });
}

/// The View menu: the view, the snapshots, the panels and bookmarking, with their keys.
fn view_menu_ui(ui: &mut egui::Ui, commands: &mut Vec<Command>) {
    let ctx = ui.ctx().clone();
    let items = [
        ("Fit view", "F", Command::FitView),
        ("Zoom to selection", "Z", Command::ZoomToSelection),
        (
            "Clear selection",
            "Esc",
            Command::Select(crate::scene::SceneId::None),
        ),
        ("Previous snapshot", "Left", Command::Step(-1)),
        ("Next snapshot", "Right", Command::Step(1)),
        ("First snapshot", "Home", Command::First),
        ("Last snapshot", "End", Command::Last),
        ("Play / pause", "Space", Command::TogglePlay),
        ("Previous mark", "[", Command::PrevMark),
        ("Next mark", "]", Command::NextMark),
        ("Left panel", "L", Command::TogglePanel(PanelToggle::Left)),
        (
            "Decisions and inspector",
            "I",
            Command::TogglePanel(PanelToggle::Right),
        ),
        ("Map only", "M", Command::TogglePanel(PanelToggle::MapOnly)),
        (
            "A | B split (pinned)",
            "S",
            Command::TogglePanel(PanelToggle::Split),
        ),
    ];
    for (name, keys, command) in items {
        if ui
            .add(egui::Button::new(name).shortcut_text(keys))
            .clicked()
        {
            commands.push(command);
        }
    }
    ui.separator();
    if ui
        .add(
            egui::Button::new("Bookmark this snapshot")
                .shortcut_text(ctx.format_shortcut(&BOOKMARK)),
        )
        .clicked()
    {
        commands.push(Command::AddBookmark(String::new()));
    }
}

/// The Parameters menu: load, save, reset, and the baseline pin.
fn parameters_menu_ui(ui: &mut egui::Ui, pinned: bool, commands: &mut Vec<Command>) {
    if ui.button("Load parameters…").clicked() {
        commands.push(Command::LoadParamsDialog);
    }
    if ui.button("Save parameters…").clicked() {
        commands.push(Command::SaveParamsDialog);
    }
    if ui.button("Reset to the paper's defaults").clicked() {
        commands.push(Command::SetParams(crate::mapping::Params::paper()));
    }
    ui.separator();
    if pinned {
        if ui.button("Unpin baseline").clicked() {
            commands.push(Command::Unpin);
        }
    } else if ui.button("Pin as baseline").clicked() {
        commands.push(Command::PinBaseline);
    }
}

/// The keyboard shortcut help window.
pub fn shortcuts_window_ui(ctx: &egui::Context, open: &mut bool) {
    egui::Window::new("Keyboard shortcuts")
        .open(open)
        .resizable(false)
        .collapsible(false)
        .show(ctx, |ui| {
            egui::Grid::new("shortcuts")
                .num_columns(2)
                .striped(true)
                .show(ui, |ui| {
                    for (keys, what) in SHORTCUTS {
                        ui.label(egui::RichText::new(keys).monospace().strong());
                        ui.label(what);
                        ui.end_row();
                    }
                });
        });
}
