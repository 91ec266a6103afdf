//! The desktop inspector (egui). Panels are functions that draw and return [`Command`]s;
//! [`SonarApp::apply`] is the one place where state changes. Panels depend on the command and
//! state types, never on the app itself.
//!
//! Codemap:
//! - the app: `app` (the runtime state, [`SonarApp`], and its queries), `apply` (every
//!   [`Command`] applied), `frame` (one frame: the panels laid out), `loading` (opening runs,
//!   installing replays), `command`;
//! - its state: `settings` (persisted, with [`LeftTab`]), `loaded` (the open run and its
//!   [`Source`]), `jobs` (replays and comparisons on threads), `baseline` (the pinned A/B
//!   baseline), `bookmarks` (bookmarks and their sidecar file); the choices that panels
//!   offer and commands carry, each a leaf that imports no panel: `decision_filter`,
//!   `run_plot`, `layout_choice`;
//! - the panels: `map_view` (the scene in egui_plot, hover, selection, ruler) with
//!   `scene_item` (the scene as one plot item), `timeline`, `inspector/` (the selection's
//!   trace, a file per kind of selection), `decisions` (this snapshot's decisions, marked where
//!   they differ from a pinned baseline), `layers` (layer switches and legend), `params_panel`
//!   (live parameters, presets, A/B pin), `bookmarks_panel`, `menu`;
//! - `headless` (the map view without a window, for `bench`).

#[allow(clippy::module_inception)]
mod app;
mod apply;
mod baseline;
mod bookmarks;
mod bookmarks_panel;
mod command;
mod decision_filter;
mod decisions;
mod file_dialog;
mod frame;
mod headless;
mod in_app_dialog;
mod inspector;
mod jobs;
mod layers;
mod layout_choice;
mod layout_picker;
mod loaded;
mod loading;
mod map_view;
mod marks;
mod menu;
mod params_panel;
mod run_plot;
mod run_plots;
mod scene_cache;
mod scene_item;
mod settings;
mod timeline;
mod truth;

pub use app::SonarApp;
pub use bookmarks::{bookmarks_path, Bookmark};
pub use command::{Command, PanelToggle};
pub use decision_filter::DecisionFilter;
pub use decisions::decision_row_text;
pub use file_dialog::{DialogBackend, FilePurpose};
pub use headless::{FrameStats, HeadlessMapView, HeadlessRunPlots};
pub use inspector::{describe_id, outcome_name, CompareState};
pub use jobs::BACKGROUND_MIN_SNAPSHOTS;
pub use layout_choice::LayoutChoice;
pub use layout_picker::SHIPPED_LAYOUTS;
pub use loaded::{Source, PREVIEW_SNAPSHOTS};
pub use map_view::{MapPlot, MapViewState, ViewRequest};
pub use marks::MarkKind;
pub use params_panel::{format_number, ParamsPanelState};
pub use run_plot::RunPlot;
pub use run_plots::RunCurves;
pub use settings::{InspectorDock, LeftTab, PanelLayout, RightTab, Settings, SETTINGS_KEY};
pub use timeline::snapshot_label;
pub use truth::TruthView;

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
