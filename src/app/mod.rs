//! The desktop inspector (egui). Panels are functions that draw and return
//! [`Command`]s; [`SonarApp::apply`] is the one place where state changes.
//!
//! Codemap: `app` (state, commands applied, persistence), `command`, `map_view` (the scene in
//! egui_plot, hover, selection, ruler), `timeline`, `inspector` (the selection's trace),
//! `decisions` (this snapshot's decisions, marked where they differ from a pinned baseline),
//! `layers` (layer switches and legend), `params_panel` (live parameters, presets, A/B pin),
//! `bookmarks`, `menu`, `headless` (the map view without a window, for `bench`), `scene_item` (the scene as one plot
//! item).

#[allow(clippy::module_inception)]
mod app;
mod bookmarks;
mod command;
mod decisions;
mod headless;
mod inspector;
mod layers;
mod map_view;
mod menu;
mod params_panel;
mod scene_item;
mod timeline;

pub use app::{
    bookmarks_path, Bookmark, LeftTab, Settings, SonarApp, Source, BACKGROUND_MIN_SNAPSHOTS,
    SETTINGS_KEY,
};
pub use command::Command;
pub use decisions::decision_row_text;
pub use headless::{FrameStats, HeadlessMapView};
pub use inspector::{describe_id, outcome_name, CompareState};
pub use map_view::{MapViewState, ViewRequest};
pub use params_panel::{format_number, ParamsPanelState};
pub use timeline::snapshot_label;

/// Opens the inspector window on `app` (blocks until the window closes).
pub fn run_native(
    make: impl FnOnce(Option<&dyn eframe::Storage>) -> SonarApp + 'static,
) -> eframe::Result {
    let options = eframe::NativeOptions {
        viewport: egui::ViewportBuilder::default()
            .with_title("sonarmap")
            .with_inner_size([1400.0, 900.0])
            .with_drag_and_drop(true),
        ..Default::default()
    };
    eframe::run_native(
        "sonarmap",
        options,
        Box::new(|cc| Ok(Box::new(make(cc.storage)))),
    )
}
