//! The persisted settings: UI state that survives restarts, kept by eframe under
//! [`SETTINGS_KEY`]. Every field has a default (`#[serde(default)]`), and a value that does not
//! parse is replaced by its default, never a crash. Runtime state lives in [`super::SonarApp`].

use super::bookmarks::Bookmark;
use crate::mapping::{Params, Preset};
use crate::scene::{Layer, LayerSet};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// Key of the persisted [`Settings`] in eframe's storage.
pub const SETTINGS_KEY: &str = "sonarmap.settings";

/// Most recent files remembered.
const MAX_RECENT: usize = 10;

/// UI state that survives restarts. Every field has a default, and a value that does not parse
/// is ignored (the whole struct falls back to its default), never a crash.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct Settings {
    /// Machine names ([`Layer::name`]) of the layers switched off.
    pub hidden_layers: Vec<String>,
    /// Recently opened files, most recent first.
    pub recent: Vec<PathBuf>,
    /// Folders where files were last chosen in a file dialog (to open, export, load or save),
    /// most recent first.
    pub recent_dirs: Vec<PathBuf>,
    /// Playback rate, snapshots per second.
    pub rate: f32,
    /// Last window size in points (eframe also restores it by itself).
    pub window_size: Option<[f32; 2]>,
    /// The last parameters applied (lengths in metres); `None`: the paper's.
    pub params: Option<Params>,
    /// Bookmarks of the built-in run (a log file keeps its own in a sidecar file).
    pub builtin_bookmarks: Vec<Bookmark>,
    /// Draw the baseline's map ghosted under the current one while a baseline is pinned.
    pub baseline_ghost: bool,
    /// The page shown in the left panel.
    pub left_tab: LeftTab,
    /// Show the run plots under the timeline.
    pub show_plots: bool,
    /// Kinds of timeline mark switched off.
    pub hidden_marks: Vec<super::marks::MarkKind>,
    /// What the run plots show.
    pub run_plot: super::run_plot::RunPlot,
    /// Where the side panels are and how wide (the map takes the rest).
    pub panels: PanelLayout,
    /// Which file dialog to use (the system's through the XDG portal, or the in-app one).
    pub file_dialog: super::file_dialog::DialogBackend,
    /// The preset the parameters are compared with (status bar, title, marked fields).
    pub preset: Preset,
    /// Exports use the figure style (labels only for the selection and the decisions).
    pub figure_style: bool,
    /// PNG exports are this many times the map view's size.
    pub png_scale: u32,
}

/// Default width of the left panel, points: with the right panel's, the map keeps at least
/// 55 % of a 1400-point window.
pub const LEFT_PANEL_PX: f32 = 280.0;
/// Default width of the right panel (decisions and inspector), points.
pub const RIGHT_PANEL_PX: f32 = 260.0;

/// The side panels: shown or collapsed, their widths (points), and where the inspector docks.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct PanelLayout {
    /// The left panel (parameters, layers, bookmarks) is shown (key L).
    pub left_open: bool,
    /// The right panel (decisions and inspector) is shown (key I).
    pub right_open: bool,
    /// Every side panel hidden, whatever the two switches above say (key M).
    pub map_only: bool,
    /// Width of the left panel, points.
    pub left_px: f32,
    /// Width of the right panel, points.
    pub right_px: f32,
    /// Where the inspector goes in the right panel.
    pub inspector_dock: InspectorDock,
    /// The right panel's page when the inspector is docked in a tab.
    pub right_tab: RightTab,
    /// Show the baseline and the current map side by side while a baseline is pinned.
    pub split: bool,
}

impl Default for PanelLayout {
    fn default() -> Self {
        PanelLayout {
            left_open: true,
            right_open: true,
            map_only: false,
            left_px: LEFT_PANEL_PX,
            right_px: RIGHT_PANEL_PX,
            inspector_dock: InspectorDock::Below,
            right_tab: RightTab::Decisions,
            split: false,
        }
    }
}

impl PanelLayout {
    /// True when the left panel is drawn.
    pub fn shows_left(&self) -> bool {
        self.left_open && !self.map_only
    }

    /// True when the right panel is drawn.
    pub fn shows_right(&self) -> bool {
        self.right_open && !self.map_only
    }
}

/// Where the inspector is docked in the right panel.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum InspectorDock {
    /// Under the decision list.
    #[default]
    Below,
    /// In a tab of its own beside the decision list.
    Tab,
}

/// The right panel's pages when the inspector is docked in a tab.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RightTab {
    /// This snapshot's decisions.
    #[default]
    Decisions,
    /// The selection's inspector.
    Inspector,
}

/// The pages of the left panel.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum LeftTab {
    /// Live parameters and the A/B baseline.
    #[default]
    Parameters,
    /// Layer switches and legend.
    Layers,
    /// Bookmarks of the run.
    Bookmarks,
}

impl LeftTab {
    /// Every page, in the order shown.
    pub const ALL: [LeftTab; 3] = [LeftTab::Parameters, LeftTab::Layers, LeftTab::Bookmarks];

    /// The tab's label.
    pub fn label(self) -> &'static str {
        match self {
            LeftTab::Parameters => "Parameters",
            LeftTab::Layers => "Layers",
            LeftTab::Bookmarks => "Bookmarks",
        }
    }
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            hidden_layers: vec![
                Layer::Beams.name().to_owned(),
                Layer::Truth.name().to_owned(),
            ],
            recent: Vec::new(),
            recent_dirs: Vec::new(),
            rate: 4.0,
            window_size: None,
            params: None,
            builtin_bookmarks: Vec::new(),
            baseline_ghost: true,
            show_plots: false,
            hidden_marks: Vec::new(),
            run_plot: Default::default(),
            left_tab: LeftTab::Parameters,
            panels: PanelLayout::default(),
            file_dialog: Default::default(),
            preset: Preset::Paper,
            figure_style: false,
            png_scale: 2,
        }
    }
}

impl Settings {
    /// Reads the settings from `storage`; a missing or corrupt value gives the defaults.
    pub fn load(storage: Option<&dyn eframe::Storage>) -> Self {
        Self::load_with_notice(storage).0
    }

    /// Reads the settings from `storage`, value by value: a value that does not parse (or is
    /// out of range) is replaced by its default and named in the notice; text that is not a
    /// JSON object gives the defaults and a notice.
    pub fn load_with_notice(storage: Option<&dyn eframe::Storage>) -> (Self, Option<String>) {
        use serde_json::Value;
        let Some(text) = storage.and_then(|s| s.get_string(SETTINGS_KEY)) else {
            return (Settings::default(), None);
        };
        let stored = match serde_json::from_str::<Value>(&text) {
            Ok(Value::Object(map)) => map,
            Ok(_) => {
                return (
                    Settings::default(),
                    Some("settings ignored: not a JSON object; using the defaults".to_owned()),
                )
            }
            Err(e) => {
                return (
                    Settings::default(),
                    Some(format!(
                        "settings ignored: not JSON ({e}); using the defaults"
                    )),
                )
            }
        };
        let stored = with_missing_params_from_preset(stored);
        let mut merged = match serde_json::to_value(Settings::default()) {
            Ok(Value::Object(map)) => map,
            _ => return (Settings::default(), None),
        };
        let mut bad = Vec::new();
        for (key, value) in stored {
            let mut trial = merged.clone();
            trial.insert(key.clone(), value);
            if serde_json::from_value::<Settings>(Value::Object(trial.clone())).is_ok() {
                merged = trial;
            } else {
                bad.push(key);
            }
        }
        let mut settings: Settings =
            serde_json::from_value(Value::Object(merged)).unwrap_or_default();
        if let Some(e) = settings.params.as_ref().and_then(|p| p.validate().err()) {
            settings.params = None;
            bad.push(format!("params ({e})"));
        }
        let rate = settings.rate;
        let settings = settings.sanitised();
        if settings.rate != rate {
            bad.push("rate".to_owned());
        }
        let notice = (!bad.is_empty()).then(|| {
            format!(
                "ignored corrupt settings: {}; using defaults for them",
                bad.join(", ")
            )
        });
        (settings, notice)
    }

    fn sanitised(mut self) -> Self {
        if !self.rate.is_finite() || self.rate <= 0.0 {
            self.rate = Settings::default().rate;
        }
        self.rate = self.rate.clamp(0.25, 60.0);
        self.recent.truncate(MAX_RECENT);
        self.recent_dirs.truncate(MAX_RECENT);
        self.png_scale = self.png_scale.clamp(1, 4);
        let panels = &mut self.panels;
        let default = PanelLayout::default();
        if !panels.left_px.is_finite() || !(120.0..=2000.0).contains(&panels.left_px) {
            panels.left_px = default.left_px;
        }
        if !panels.right_px.is_finite() || !(160.0..=2000.0).contains(&panels.right_px) {
            panels.right_px = default.right_px;
        }
        self
    }

    /// The folders for the file dialog, most recent first, each once: where files were last
    /// chosen in a dialog, then the folders of the recent files.
    pub fn recent_folders(&self) -> Vec<PathBuf> {
        let mut folders: Vec<PathBuf> = Vec::new();
        let recent_files = self.recent.iter().filter_map(|p| p.parent());
        for dir in self
            .recent_dirs
            .iter()
            .map(PathBuf::as_path)
            .chain(recent_files)
        {
            if !dir.as_os_str().is_empty() && !folders.iter().any(|d| d == dir) {
                folders.push(dir.to_path_buf());
            }
        }
        folders
    }

    /// Puts the folder of `path`, a file chosen in a dialog, first among the recent folders.
    pub(super) fn remember_folder(&mut self, path: &Path) {
        let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) else {
            return;
        };
        self.recent_dirs.retain(|d| d != dir);
        self.recent_dirs.insert(0, dir.to_path_buf());
        self.recent_dirs.truncate(MAX_RECENT);
    }

    /// The layers switched on.
    pub fn layers(&self) -> LayerSet {
        let mut set = LayerSet::all();
        for name in &self.hidden_layers {
            if let Some(layer) = Layer::from_name(name) {
                set.set(layer, false);
            }
        }
        set
    }

    pub(super) fn set_layer(&mut self, layer: Layer, on: bool) {
        self.hidden_layers.retain(|n| n != layer.name());
        if !on {
            self.hidden_layers.push(layer.name().to_owned());
        }
    }

    /// Puts `path` first in the recent files (once), keeping at most [`MAX_RECENT`].
    pub(super) fn remember(&mut self, path: &Path) {
        self.recent.retain(|p| p != path);
        self.recent.insert(0, path.to_path_buf());
        self.recent.truncate(MAX_RECENT);
    }
}

/// `stored` with its parameter set (`params`) completed from the preset it is compared with
/// (`preset`, else the default's): a set saved before a parameter existed takes that preset's
/// value for it, so an `extended` set saved by an older version runs with the extensions added
/// since, instead of with them off.
fn with_missing_params_from_preset(
    mut stored: serde_json::Map<String, serde_json::Value>,
) -> serde_json::Map<String, serde_json::Value> {
    use serde_json::Value;
    let Some(Value::Object(params)) = stored.get("params") else {
        return stored;
    };
    let preset = stored
        .get("preset")
        .and_then(|p| serde_json::from_value::<Preset>(p.clone()).ok())
        .unwrap_or(Settings::default().preset);
    let Ok(Value::Object(mut completed)) = serde_json::to_value(Params::preset(preset)) else {
        return stored;
    };
    completed.extend(params.clone());
    stored.insert("params".to_owned(), Value::Object(completed));
    stored
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn folders_chosen_in_a_dialog_come_first_among_the_recent_folders_each_once() {
        let mut s = Settings::default();
        s.remember(Path::new("/runs/a/hall.json"));
        s.remember_folder(Path::new("/figures/fig.svg"));
        s.remember_folder(Path::new("/params/p.json"));
        s.remember_folder(Path::new("/figures/other.png"));
        s.remember_folder(Path::new("bare-name.json"));
        assert_eq!(
            s.recent_folders(),
            ["/figures", "/params", "/runs/a"].map(PathBuf::from)
        );
    }
}
