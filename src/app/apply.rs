//! The one place where the state changes: [`SonarApp::apply`] takes every [`Command`] the
//! panels, the keyboard, dropped files and tests send, and the methods below carry out the
//! larger ones.

use super::app::SonarApp;
use super::baseline::Baseline;
use super::bookmarks::{write_sidecar, Bookmark};
use super::command::{Command, PanelToggle};
use super::file_dialog::{ask_system, probe_system, DialogBackend, FilePurpose, SystemAnswer};
use super::in_app_dialog::InAppDialog;
use super::inspector::{describe_id, CompareState};
use super::jobs::JobKind;
use super::layout_choice::LayoutChoice;
use super::loaded::Source;
use super::map_view::ViewRequest;
use crate::atomic_write::write_atomic;
use crate::export::svg_to_png;
use crate::mapping::paper::matching::evaluate_pair;
use crate::mapping::{Params, ParamsFile};
use crate::scene::figure::{figure_svg, Figure};
use crate::scene::SceneInput;
use crate::scene::{Layer, SceneId, ViewRect};
use std::path::Path;

impl SonarApp {
    /// Applies one command (the only place the state changes).
    pub fn apply(&mut self, command: Command) {
        match command {
            Command::Open(path) => self.open_path(&path, false),
            Command::OpenBytes { name, bytes } => {
                self.open_bytes(&bytes, Source::Bytes(name), false)
            }
            Command::OpenDialog => self.ask_path(FilePurpose::OpenLog),
            Command::Reload => self.reload(),
            Command::Seek(k) => self.seek(k),
            Command::Step(delta) => {
                let k = (self.current() as i64).saturating_add(delta).max(0) as usize;
                self.seek(k);
            }
            Command::First => self.seek(0),
            Command::Last => self.seek(self.len().saturating_sub(1)),
            Command::TogglePlay => self.toggle_play(),
            Command::SetRate(rate) => self.set_rate(rate),
            Command::NextMark => self.next_mark(),
            Command::PrevMark => self.prev_mark(),
            Command::Select(id) => self.select(id),
            Command::CompareWith(id) => {
                self.compare = CompareState::Armed(id);
                self.message = format!("compare #{id} with…: click a segment");
            }
            Command::CancelCompare => self.compare = CompareState::Off,
            Command::ToggleLayer(layer) => self.toggle_layer(layer),
            Command::TogglePlots => self.settings.show_plots = !self.settings.show_plots,
            Command::ToggleMarkKind(kind) => self.toggle_mark_kind(kind),
            Command::FilterDecisions(filter) => self.decision_filter = filter,
            Command::FitView => self.map_view.request = Some(ViewRequest::Fit),
            Command::ZoomToSelection => self.zoom_to_selection(),
            Command::CenterOn(p) => self.map_view.request = Some(ViewRequest::Center(p)),
            Command::ExportDialog => self.ask_path(FilePurpose::ExportFigure),
            Command::ExportSvg(path) => self.export_to(&path),
            Command::DismissError => self.banner = None,
            Command::ToggleShortcuts => self.show_shortcuts = !self.show_shortcuts,
            Command::SetParams(params) => self.set_params(params),
            Command::SetPreset(preset) => {
                self.settings.preset = preset;
                self.set_params(Params::preset(preset));
            }
            Command::LoadParamsDialog => self.ask_path(FilePurpose::LoadParams),
            Command::SaveParamsDialog => self.ask_path(FilePurpose::SaveParams),
            Command::LoadParams(path) => self.load_params(&path),
            Command::SaveParams(path) => self.save_params(&path),
            Command::PinBaseline => self.pin_baseline(),
            Command::Unpin => self.unpin(),
            Command::ShowTab(tab) => self.settings.left_tab = tab,
            Command::ToggleBaselineGhost => {
                self.settings.baseline_ghost = !self.settings.baseline_ghost
            }
            Command::AddBookmark(name) => self.add_bookmark(&name),
            Command::RemoveBookmark(i) => self.remove_bookmark(i),
            Command::SetFileDialog(backend) => self.settings.file_dialog = backend,
            Command::TogglePanel(panel) => self.toggle_panel(panel),
            Command::DockInspector(dock) => self.settings.panels.inspector_dock = dock,
            Command::ShowRightTab(tab) => self.settings.panels.right_tab = tab,
            Command::ToggleFigureStyle => self.settings.figure_style = !self.settings.figure_style,
            Command::SetPngScale(scale) => self.settings.png_scale = scale.clamp(1, 4),
            Command::OpenWithLayout(choice) => self.open_with_layout(choice),
            Command::ChooseLayoutFile => self.ask_path(FilePurpose::LayoutFile),
            Command::ChoosePosesFile => self.ask_path(FilePurpose::PosesFile),
            Command::SetPosesFile(path) => self.set_picker_poses(&path),
            Command::CancelLayoutPicker => {
                if self.layout_picker.take().is_some() {
                    self.message = "not opened: no layout chosen".to_owned();
                }
            }
        }
    }

    /// Sets the playback rate (a rate that is not a positive number is ignored).
    fn set_rate(&mut self, rate: f32) {
        if rate.is_finite() && rate > 0.0 {
            self.settings.rate = rate.clamp(0.25, 60.0);
        }
    }

    /// Shows the marks of `kind` when hidden, hides them when shown.
    fn toggle_mark_kind(&mut self, kind: super::marks::MarkKind) {
        let hidden = &mut self.settings.hidden_marks;
        if hidden.contains(&kind) {
            hidden.retain(|k| *k != kind);
        } else {
            hidden.push(kind);
        }
    }

    // Opening and reloading.

    /// Asks for a path for `purpose`: the system dialog when it can work, else (or when it
    /// fails) the in-app dialog, which `dialogs_ui` follows frame by frame.
    fn ask_path(&mut self, purpose: FilePurpose) {
        let folder = self.settings.recent_folders().into_iter().next();
        let file_name = match purpose {
            FilePurpose::ExportFigure => format!("snapshot-{}.svg", self.current()),
            FilePurpose::SaveParams => "params.json".to_owned(),
            _ => String::new(),
        };
        let backend = DialogBackend::from_env().unwrap_or(self.settings.file_dialog);
        let use_system = match backend {
            DialogBackend::InApp => false,
            DialogBackend::System => true,
            DialogBackend::Auto => match probe_system() {
                Ok(()) => true,
                Err(why) => {
                    self.message = format!("in-app file dialog: {why}");
                    false
                }
            },
        };
        if use_system {
            match ask_system(purpose, folder.as_deref(), &file_name) {
                SystemAnswer::Chosen(path) => return self.path_chosen(purpose, path),
                SystemAnswer::Cancelled => return,
                SystemAnswer::Failed => {
                    self.banner = Some(
                        "The system file dialog did not open (no XDG desktop portal or zenity \
                         answered); using the in-app dialog."
                            .to_owned(),
                    );
                }
            }
        }
        self.file_dialog = Some(InAppDialog::open(
            purpose,
            folder.as_deref(),
            &file_name,
            self.settings.recent_folders(),
        ));
    }

    /// Carries out what a chosen path was asked for.
    pub(super) fn path_chosen(&mut self, purpose: FilePurpose, path: std::path::PathBuf) {
        self.settings.remember_folder(&path);
        match purpose {
            FilePurpose::OpenLog => self.open_path(&path, false),
            FilePurpose::ExportFigure => self.export_to(&path),
            FilePurpose::LoadParams => self.load_params(&path),
            FilePurpose::SaveParams => self.save_params(&path),
            FilePurpose::LayoutFile => self.open_with_layout(LayoutChoice::File(path)),
            FilePurpose::PosesFile => self.set_picker_poses(&path),
        }
    }

    fn reload(&mut self) {
        match self.loaded.source.clone() {
            Source::File(path) => self.open_path(&path, true),
            _ => self.message = "the built-in run has no file to reload".to_owned(),
        }
    }

    // Playback and the timeline.

    fn toggle_play(&mut self) {
        self.playing = !self.playing;
        self.play_clock_s = 0.0;
        if self.playing && self.current() + 1 >= self.len() {
            self.seek(0);
        }
    }

    fn next_mark(&mut self) {
        let k = self.current();
        match self.marks().into_iter().find(|&m| m > k) {
            Some(m) => self.seek(m),
            None => self.message = "no mark after this snapshot".to_owned(),
        }
    }

    fn prev_mark(&mut self) {
        let k = self.current();
        match self.marks().into_iter().rev().find(|&m| m < k) {
            Some(m) => self.seek(m),
            None => self.message = "no mark before this snapshot".to_owned(),
        }
    }

    // Selection and the map view.

    fn select(&mut self, id: SceneId) {
        if id == SceneId::None {
            self.map_view.ruler_m = None;
            self.compare = CompareState::Off;
        }
        if let CompareState::Armed(existing) = self.compare {
            if let Some(other) = self.ends_of(id) {
                if let Some(existing_ends) = self.ends_of(SceneId::MapSegment(existing)) {
                    if id != SceneId::MapSegment(existing) {
                        let eval = evaluate_pair(
                            self.loaded.replay.params(),
                            &other,
                            existing,
                            &existing_ends,
                        );
                        self.compare = CompareState::Done {
                            existing,
                            other: id,
                            eval: Box::new(eval),
                        };
                        self.selection = SceneId::MapSegment(existing);
                        self.message = format!("compared #{existing} with {}", describe_id(id));
                        return;
                    }
                }
            }
        }
        self.selection = id;
    }

    fn toggle_layer(&mut self, layer: Layer) {
        let on = self.settings.layers().contains(layer);
        self.settings.set_layer(layer, !on);
    }

    fn toggle_panel(&mut self, panel: PanelToggle) {
        if panel == PanelToggle::Split && self.baseline.is_none() {
            self.message = "A | B needs a baseline: Parameters > Pin as baseline".to_owned();
            return;
        }
        let panels = &mut self.settings.panels;
        match panel {
            PanelToggle::Left => {
                panels.left_open = !panels.shows_left();
                panels.map_only = false;
            }
            PanelToggle::Right => {
                panels.right_open = !panels.shows_right();
                panels.map_only = false;
            }
            PanelToggle::MapOnly => panels.map_only = !panels.map_only,
            PanelToggle::Split => panels.split = !panels.split,
        }
        // The map's size changes: frame the content again in what is left.
        self.map_view.request = Some(ViewRequest::Fit);
    }

    fn zoom_to_selection(&mut self) {
        match self.ends_of(self.selection) {
            Some(ends) => {
                let length = (ends.b.point - ends.a.point).norm();
                let rect =
                    ViewRect::new(ends.a.point, ends.b.point).expanded(length.max(0.5) * 0.75);
                self.map_view.request = Some(ViewRequest::Frame(rect));
            }
            None => self.message = "select a segment to zoom to it".to_owned(),
        }
    }

    // Export.

    fn export_to(&mut self, path: &Path) {
        match self.export_svg(path) {
            Ok(()) => self.message = format!("exported {}", path.display()),
            Err(e) => {
                self.banner = Some(e);
                self.message = "export failed".to_owned();
            }
        }
    }

    /// Writes what the map view shows to `path` (atomically): the visible region, the layers
    /// on, the selection highlighted; SVG, or PNG when the name ends in `.png` (the page
    /// scaled by the PNG scale setting). The figure style when it is on.
    pub fn export_svg(&mut self, path: &Path) -> Result<(), String> {
        let view = self
            .view
            .as_ref()
            .ok_or_else(|| "nothing to export".to_owned())?;
        let truth = self.truth.as_ref().map(|t| t.verdicts.as_slice());
        let replay = &self.loaded.replay;
        let input = SceneInput::from_view(replay.run(), view)
            .with_truth(truth)
            .with_corrected_path(replay.step_poses());
        let (w, h) = self.map_view.size_px;
        let figure = Figure {
            view: self.map_view.visible_m,
            layers: self.settings.layers(),
            size_px: (w.max(400) + 180, h.max(300) + 60),
            selection: self.selection,
            figure_style: self.settings.figure_style,
            title: format!("{} — snapshot {}", self.run().name, self.current()),
        };
        let svg = figure_svg(&input, &figure, self.run().units);
        let png = path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("png"));
        let written = if png {
            let width = figure.size_px.0 * self.settings.png_scale.clamp(1, 4);
            svg_to_png(&svg, width)
                .and_then(|bytes| write_atomic(path, &bytes).map_err(|e| e.to_string()))
        } else {
            write_atomic(path, svg.as_bytes()).map_err(|e| e.to_string())
        };
        written.map_err(|e| format!("Could not write {}: {e}", path.display()))
    }

    // Parameters and the A/B baseline.

    /// Applies new parameters: validated, remembered, and the run replayed in the background.
    fn set_params(&mut self, params: Params) {
        if let Err(e) = params.validate() {
            self.message = format!("parameters refused: {e}");
            return;
        }
        self.params = params.clone();
        // A calibration `calibrate_first` found belongs to the open run, not to the settings.
        let saved = match &self.auto_calibration {
            Some(calibration) => super::loading::without_run_calibration(&params, calibration),
            None => params,
        };
        self.settings.params = (saved != Params::paper()).then_some(saved);
        // The whole run, even while only its first snapshots are shown.
        let run = self.loaded.run.clone();
        if let Some(b) = &mut self.baseline {
            b.cancel_job();
            b.diff = None;
        }
        // A reload's snapshot still to go back to goes on with the re-run.
        let resume_at = self.background.as_ref().and_then(|j| j.kind.resume_at());
        self.start_background(run, JobKind::Rerun { resume_at });
    }

    fn load_params(&mut self, path: &Path) {
        let result = std::fs::read_to_string(path)
            .map_err(|e| e.to_string())
            .and_then(|text| serde_json::from_str::<ParamsFile>(&text).map_err(|e| e.to_string()))
            .and_then(|file| Params::paper().with_file(&file).map_err(|e| e.to_string()));
        match result {
            Ok(params) => {
                self.set_params(params);
                self.message = format!("loaded parameters from {}", path.display());
            }
            Err(e) => {
                self.banner = Some(format!(
                    "Could not load parameters from {}: {e}",
                    path.display()
                ));
                self.message = "parameters unchanged".to_owned();
            }
        }
    }

    fn save_params(&mut self, path: &Path) {
        let file = self.params.to_file(self.run().units);
        let result = serde_json::to_string_pretty(&file)
            .map_err(|e| e.to_string())
            .and_then(|text| {
                write_atomic(path, (text + "\n").as_bytes()).map_err(|e| e.to_string())
            });
        match result {
            Ok(()) => self.message = format!("saved parameters to {}", path.display()),
            Err(e) => {
                self.banner = Some(format!("Could not write {}: {e}", path.display()));
                self.message = "saving the parameters failed".to_owned();
            }
        }
    }

    fn pin_baseline(&mut self) {
        // A baseline is a whole run's replay: the preview's would compare its first snapshots
        // only.
        if self.loaded.is_preview() {
            self.message =
                "the whole run is still replaying: pin the baseline once it is in".to_owned();
            return;
        }
        self.baseline = Some(Baseline::pin(self.loaded.replay.clone(), self.view.clone()));
        self.start_diff();
        self.message = "pinned the current parameters as the baseline".to_owned();
    }

    fn unpin(&mut self) {
        if let Some(mut b) = self.baseline.take() {
            b.cancel_job();
            self.message = "baseline unpinned".to_owned();
        }
    }

    // Bookmarks.

    fn add_bookmark(&mut self, name: &str) {
        let k = self.current();
        let name = match name.trim() {
            "" => format!("snapshot {k}"),
            n => n.to_owned(),
        };
        self.message = format!("bookmarked snapshot {k} as {name:?}");
        self.bookmarks.push(Bookmark { name, snapshot: k });
        self.bookmarks.sort_by_key(|b| b.snapshot);
        self.save_bookmarks();
    }

    fn remove_bookmark(&mut self, i: usize) {
        if i < self.bookmarks.len() {
            let b = self.bookmarks.remove(i);
            self.message = format!("removed bookmark {:?}", b.name);
            self.save_bookmarks();
        }
    }

    fn save_bookmarks(&mut self) {
        match self.loaded.source.clone() {
            Source::BuiltIn(_) => self.settings.builtin_bookmarks = self.bookmarks.clone(),
            Source::Bytes(_) => {
                self.message = "bookmarks of a dropped file are kept until it closes".to_owned()
            }
            Source::File(path) => {
                if let Err(e) = write_sidecar(&path, &self.bookmarks) {
                    self.banner = Some(e);
                }
            }
        }
    }
}
