//! The inspector's state and the one place where commands are applied.

use super::bookmarks::bookmarks_ui;
use super::command::Command;
use super::decisions::decisions_ui;
use super::inspector::{describe_id, hover_text, inspector_ui, CompareState, InspectCtx};
use super::layers::layers_ui;
use super::map_view::{map_view_ui, MapViewState, ViewRequest};
use super::menu::{handle_shortcuts, menu_bar_ui, shortcuts_window_ui};
use super::params_panel::{params_panel_ui, ParamsPanelInfo, ParamsPanelState};
use super::timeline::{timeline_ui, TimelineInfo};
use crate::diff::{diff_run, diff_step, DecisionDifference, RunDiff};
use crate::export::{write_svg_atomically, write_text_atomically};
use crate::import::{import_any, ImportOptions};
use crate::mapping::matching::{evaluate_pair, SegmentEnds};
use crate::mapping::{Outcome, Params, ParamsFile};
use crate::replay::{Replay, StepView, DEFAULT_CHECKPOINT_INTERVAL};
use crate::run::Run;
use crate::scene::svg::{default_view, to_svg};
use crate::scene::ViewRect;
use crate::scene::{
    build_scene, format_length, Layer, LayerSet, Scene, SceneId, SceneInput, ViewOptions,
};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Arc;

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

/// A named snapshot.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Bookmark {
    /// The name given.
    pub name: String,
    /// The snapshot index.
    pub snapshot: usize,
}

/// The sidecar file of bookmarks beside a log: `<log>.bookmarks.json`.
pub fn bookmarks_path(log: &Path) -> PathBuf {
    let mut name = log.file_name().unwrap_or_default().to_os_string();
    name.push(".bookmarks.json");
    log.with_file_name(name)
}

/// The sidecar file's contents.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
struct BookmarksFile {
    format: String,
    version: u32,
    bookmarks: Vec<Bookmark>,
}

const BOOKMARKS_FORMAT: &str = "sonarmap-bookmarks";

impl Default for Settings {
    fn default() -> Self {
        Settings {
            hidden_layers: vec![Layer::Beams.name().to_owned()],
            recent: Vec::new(),
            rate: 4.0,
            window_size: None,
            params: None,
            builtin_bookmarks: Vec::new(),
            baseline_ghost: true,
            left_tab: LeftTab::Parameters,
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
        self
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

    fn set_layer(&mut self, layer: Layer, on: bool) {
        self.hidden_layers.retain(|n| n != layer.name());
        if !on {
            self.hidden_layers.push(layer.name().to_owned());
        }
    }
}

/// Where the open run came from.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Source {
    /// Built into the binary (the Blue Room).
    BuiltIn(String),
    /// A file on disk.
    File(PathBuf),
    /// Bytes without a path (a dropped file).
    Bytes(String),
}

impl Source {
    /// Short name for the status bar and titles.
    pub fn display_name(&self) -> String {
        match self {
            Source::BuiltIn(name) | Source::Bytes(name) => name.clone(),
            Source::File(path) => path.display().to_string(),
        }
    }
}

/// Runs with at least this many snapshots are replayed on a background thread.
pub const BACKGROUND_MIN_SNAPSHOTS: usize = 2000;

/// What a background replay is for.
enum JobKind {
    /// A run being opened.
    Open { source: Source, keep_index: bool },
    /// The open run under new parameters.
    Rerun,
}

/// A replay being built on a thread.
struct Background {
    kind: JobKind,
    label: String,
    started: std::time::Instant,
    total: usize,
    progress: Arc<AtomicUsize>,
    cancel: Arc<AtomicBool>,
    result: std::sync::mpsc::Receiver<Replay>,
}

/// The A/B comparison being computed on a thread.
struct DiffJob {
    total: usize,
    progress: Arc<AtomicUsize>,
    cancel: Arc<AtomicBool>,
    result: std::sync::mpsc::Receiver<RunDiff>,
}

/// A pinned parameter set and its results.
struct Baseline {
    params: Params,
    replay: Replay,
    view: Option<StepView>,
    /// Differences from the current parameters, when computed.
    diff: Option<RunDiff>,
    job: Option<DiffJob>,
}

/// A run and its replay.
struct Loaded {
    source: Source,
    replay: Replay,
    marks: Vec<usize>,
}

/// The inspector. Constructible without eframe, so tests drive it through [`SonarApp::ui`].
pub struct SonarApp {
    settings: Settings,
    params: Params,
    loaded: Loaded,
    background: Option<Background>,
    background_min_snapshots: usize,
    view: Option<StepView>,
    playing: bool,
    play_clock_s: f64,
    selection: SceneId,
    compare: CompareState,
    decision_filter: Option<Outcome>,
    banner: Option<String>,
    message: String,
    map_view: MapViewState,
    pending: Vec<Command>,
    show_shortcuts: bool,
    jump_text: String,
    params_panel: ParamsPanelState,
    baseline: Option<Baseline>,
    bookmarks: Vec<Bookmark>,
    bookmark_text: String,
    last_rerun_s: Option<f64>,
}

impl SonarApp {
    /// The app on `run` (shown as built in), with settings from `storage` when given.
    pub fn new(run: Run, storage: Option<&dyn eframe::Storage>) -> Self {
        let name = run.name.clone();
        Self::with_source(run, Source::BuiltIn(name), storage)
    }

    /// The app on `run`, which came from `source`.
    pub fn with_source(run: Run, source: Source, storage: Option<&dyn eframe::Storage>) -> Self {
        let (settings, notice) = Settings::load_with_notice(storage);
        let params = settings.params.clone().unwrap_or_else(Params::paper);
        let loaded = Self::prepare(run, source, &params);
        let mut app = SonarApp {
            settings,
            params,
            loaded,
            background: None,
            background_min_snapshots: BACKGROUND_MIN_SNAPSHOTS,
            view: None,
            playing: false,
            play_clock_s: 0.0,
            selection: SceneId::None,
            compare: CompareState::Off,
            decision_filter: None,
            banner: None,
            message: String::new(),
            map_view: MapViewState::default(),
            pending: Vec::new(),
            show_shortcuts: false,
            jump_text: String::new(),
            params_panel: ParamsPanelState::default(),
            baseline: None,
            bookmarks: Vec::new(),
            bookmark_text: String::new(),
            last_rerun_s: None,
        };
        app.seek(0);
        app.load_bookmarks();
        app.message = match notice {
            Some(n) => n,
            None => format!("opened {}", app.loaded.source.display_name()),
        };
        app
    }

    fn prepare(run: Run, source: Source, params: &Params) -> Loaded {
        Self::loaded_from(Replay::new(Arc::new(run), params.clone()), source)
    }

    fn loaded_from(replay: Replay, source: Source) -> Loaded {
        let marks = replay
            .summaries()
            .iter()
            .enumerate()
            .filter(|(_, s)| s.is_notable())
            .map(|(k, _)| k)
            .collect();
        Loaded {
            source,
            replay,
            marks,
        }
    }

    /// Replays runs of at least `snapshots` snapshots in the background (default
    /// [`BACKGROUND_MIN_SNAPSHOTS`]).
    pub fn set_background_threshold(&mut self, snapshots: usize) {
        self.background_min_snapshots = snapshots.max(1);
    }

    /// True while a run is being replayed in the background (a large run opened, or a
    /// re-run under new parameters), or while the baseline comparison is being computed.
    pub fn is_loading(&self) -> bool {
        self.background.is_some() || self.baseline.as_ref().is_some_and(|b| b.job.is_some())
    }

    /// The parameters asked for (the replay shown catches up when a re-run finishes).
    pub fn params(&self) -> &Params {
        &self.params
    }

    /// The parameters of the replay shown.
    pub fn shown_params(&self) -> &Params {
        self.loaded.replay.params()
    }

    /// Seconds the last re-run under new parameters took.
    pub fn last_rerun_s(&self) -> Option<f64> {
        self.last_rerun_s
    }

    /// The reason the parameters panel refused the value of field `name`, if it did.
    pub fn params_error(&self, name: &str) -> Option<&str> {
        self.params_panel.error(name)
    }

    /// True while a baseline is pinned.
    pub fn is_pinned(&self) -> bool {
        self.baseline.is_some()
    }

    /// The comparison with the baseline, when pinned and computed.
    pub fn baseline_diff(&self) -> Option<&RunDiff> {
        self.baseline.as_ref().and_then(|b| b.diff.as_ref())
    }

    /// The decisions of the current snapshot that differ from the baseline (A = baseline,
    /// B = current); empty when no baseline is pinned.
    pub fn differences_here(&self) -> Vec<DecisionDifference> {
        match (&self.baseline, &self.view) {
            (Some(Baseline { view: Some(bv), .. }), Some(v)) => diff_step(&bv.trace, &v.trace),
            _ => Vec::new(),
        }
    }

    /// The bookmarks of the open run.
    pub fn bookmarks(&self) -> &[Bookmark] {
        &self.bookmarks
    }

    /// Waits (sleeping) until no background work is left, at most `timeout`; for tests and
    /// measurements. Returns false on timeout.
    pub fn wait_idle(&mut self, timeout: std::time::Duration) -> bool {
        let ctx = egui::Context::default();
        let deadline = std::time::Instant::now() + timeout;
        while self.is_loading() {
            if std::time::Instant::now() > deadline {
                return false;
            }
            std::thread::sleep(std::time::Duration::from_millis(5));
            self.poll_background(&ctx);
        }
        true
    }

    fn poll_diff(&mut self, ctx: &egui::Context) {
        let Some(baseline) = &mut self.baseline else {
            return;
        };
        let Some(job) = &baseline.job else {
            return;
        };
        match job.result.try_recv() {
            Ok(diff) => {
                self.message = format!(
                    "{} snapshots differ from the baseline",
                    diff.snapshots.len()
                );
                baseline.diff = Some(diff);
                baseline.job = None;
            }
            Err(std::sync::mpsc::TryRecvError::Empty) => ctx.request_repaint(),
            Err(std::sync::mpsc::TryRecvError::Disconnected) => baseline.job = None,
        }
    }

    /// Starts comparing the baseline with the replay shown, on a thread.
    fn start_diff(&mut self) {
        let current = self.loaded.replay.params().clone();
        let run = self.loaded.replay.run().clone();
        let Some(baseline) = &mut self.baseline else {
            return;
        };
        if let Some(old) = baseline.job.take() {
            old.cancel.store(true, Ordering::Relaxed);
        }
        if baseline.params == current {
            baseline.diff = Some(RunDiff::default());
            return;
        }
        baseline.diff = None;
        let total = run.snapshots.len();
        let progress = Arc::new(AtomicUsize::new(0));
        let cancel = Arc::new(AtomicBool::new(false));
        let (tx, rx) = std::sync::mpsc::channel();
        let (p, c, a) = (progress.clone(), cancel.clone(), baseline.params.clone());
        std::thread::spawn(move || {
            let diff = diff_run(&run, &a, &current, &mut |done| {
                p.store(done, Ordering::Relaxed);
                !c.load(Ordering::Relaxed)
            });
            if !c.load(Ordering::Relaxed) {
                let _ = tx.send(diff);
            }
        });
        baseline.job = Some(DiffJob {
            total,
            progress,
            cancel,
            result: rx,
        });
    }

    /// Installs a re-run of the open run: same snapshot, the selection when it still exists.
    fn install_rerun(&mut self, replay: Replay) {
        let k = self.current();
        let selection = self.selection;
        self.loaded = Self::loaded_from(replay, self.loaded.source.clone());
        self.view = None;
        self.seek(k);
        self.selection = if self.exists(selection) {
            selection
        } else {
            SceneId::None
        };
        if matches!(self.compare, CompareState::Done { .. }) {
            self.compare = CompareState::Off;
        }
        self.report_step_failure();
        self.start_diff();
    }

    /// True when `id` names something of the step shown.
    fn exists(&self, id: SceneId) -> bool {
        let Some(view) = &self.view else {
            return false;
        };
        match id {
            SceneId::None | SceneId::Robot | SceneId::FloorPlan | SceneId::Reading { .. } => true,
            SceneId::NewSegment(i) => i < view.trace.new_segments.len(),
            SceneId::Decision { new_segment, .. } => view
                .trace
                .decisions
                .iter()
                .any(|d| d.new_segment == new_segment),
            SceneId::MapSegment(id) | SceneId::Update(id) => {
                view.map_after.segment(id).is_some() || view.map_before.segment(id).is_some()
            }
            SceneId::Cluster(_) | SceneId::Correlation(_) => false,
        }
    }

    /// Applies new parameters: validated, remembered, and the run replayed in the background.
    fn set_params(&mut self, params: Params) {
        if let Err(e) = params.validate() {
            self.message = format!("parameters refused: {e}");
            return;
        }
        self.params = params.clone();
        self.settings.params = (params != Params::paper()).then_some(params);
        let run = self.loaded.replay.run().clone();
        if let Some(b) = &mut self.baseline {
            if let Some(old) = b.job.take() {
                old.cancel.store(true, Ordering::Relaxed);
            }
            b.diff = None;
        }
        self.start_background(run, JobKind::Rerun);
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
                write_text_atomically(path, &(text + "\n")).map_err(|e| e.to_string())
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
        let replay = self.loaded.replay.clone();
        self.baseline = Some(Baseline {
            params: replay.params().clone(),
            view: self.view.clone(),
            replay,
            diff: None,
            job: None,
        });
        self.start_diff();
        self.message = "pinned the current parameters as the baseline".to_owned();
    }

    fn load_bookmarks(&mut self) {
        self.bookmarks = match &self.loaded.source {
            Source::BuiltIn(_) => self.settings.builtin_bookmarks.clone(),
            Source::Bytes(_) => Vec::new(),
            Source::File(path) => {
                let side = bookmarks_path(path);
                match std::fs::read_to_string(&side) {
                    Err(_) => Vec::new(),
                    Ok(text) => match serde_json::from_str::<BookmarksFile>(&text) {
                        Ok(f) if f.format == BOOKMARKS_FORMAT => f.bookmarks,
                        _ => {
                            self.message =
                                format!("ignored unreadable bookmarks file {}", side.display());
                            Vec::new()
                        }
                    },
                }
            }
        };
    }

    fn save_bookmarks(&mut self) {
        match self.loaded.source.clone() {
            Source::BuiltIn(_) => self.settings.builtin_bookmarks = self.bookmarks.clone(),
            Source::Bytes(_) => {
                self.message = "bookmarks of a dropped file are kept until it closes".to_owned()
            }
            Source::File(path) => {
                let side = bookmarks_path(&path);
                let file = BookmarksFile {
                    format: BOOKMARKS_FORMAT.to_owned(),
                    version: 1,
                    bookmarks: self.bookmarks.clone(),
                };
                let result = serde_json::to_string_pretty(&file)
                    .map_err(|e| e.to_string())
                    .and_then(|t| {
                        write_text_atomically(&side, &(t + "\n")).map_err(|e| e.to_string())
                    });
                if let Err(e) = result {
                    self.banner = Some(format!("Could not write {}: {e}", side.display()));
                }
            }
        }
    }

    /// Installs a finished background replay or comparison.
    fn poll_background(&mut self, ctx: &egui::Context) {
        self.poll_diff(ctx);
        let Some(job) = &self.background else {
            return;
        };
        match job.result.try_recv() {
            Ok(replay) => {
                let job = self.background.take().expect("checked above");
                match job.kind {
                    JobKind::Open { source, keep_index } => {
                        self.install(Self::loaded_from(replay, source), keep_index)
                    }
                    JobKind::Rerun => {
                        let s = job.started.elapsed().as_secs_f64();
                        self.last_rerun_s = Some(s);
                        self.install_rerun(replay);
                        self.message = format!(
                            "re-ran {} snapshots with the new parameters in {s:.2} s",
                            self.len()
                        );
                    }
                }
            }
            Err(std::sync::mpsc::TryRecvError::Empty) => ctx.request_repaint(),
            Err(std::sync::mpsc::TryRecvError::Disconnected) => {
                self.background = None;
                self.banner =
                    Some("the replay stopped unexpectedly; the previous run stays open".to_owned());
            }
        }
    }

    /// Queues a command; it is applied at the start of the next frame.
    pub fn push(&mut self, command: Command) {
        self.pending.push(command);
    }

    /// The snapshot shown.
    pub fn current(&self) -> usize {
        self.view.as_ref().map_or(0, |v| v.index)
    }

    /// Number of snapshots of the open run.
    pub fn len(&self) -> usize {
        self.loaded.replay.len()
    }

    /// True when the run has no snapshot.
    pub fn is_empty(&self) -> bool {
        self.loaded.replay.is_empty()
    }

    /// True while playing.
    pub fn is_playing(&self) -> bool {
        self.playing
    }

    /// The current selection.
    pub fn selection(&self) -> SceneId {
        self.selection
    }

    /// The error banner's text, when shown.
    pub fn banner(&self) -> Option<&str> {
        self.banner.as_deref()
    }

    /// The open run.
    pub fn run(&self) -> &Arc<Run> {
        self.loaded.replay.run()
    }

    /// Where the open run came from.
    pub fn source(&self) -> &Source {
        &self.loaded.source
    }

    /// Snapshots with a timeline mark.
    pub fn marks(&self) -> &[usize] {
        &self.loaded.marks
    }

    /// The step shown.
    pub fn step_view(&self) -> Option<&StepView> {
        self.view.as_ref()
    }

    /// The layers switched on.
    pub fn layers(&self) -> LayerSet {
        self.settings.layers()
    }

    /// The persisted settings.
    pub fn settings(&self) -> &Settings {
        &self.settings
    }

    /// The map view's state (visible rectangle, cursor, ruler).
    pub fn map_view(&self) -> &MapViewState {
        &self.map_view
    }

    /// The state of "compare with…".
    pub fn compare(&self) -> &CompareState {
        &self.compare
    }

    /// The last status message.
    pub fn message(&self) -> &str {
        &self.message
    }

    /// The scene of the current step, as the map view draws it.
    pub fn scene(&self) -> Option<Scene> {
        self.scene_with(self.map_view.world_per_px())
    }

    fn scene_with(&self, world_per_px: f64) -> Option<Scene> {
        let view = self.view.as_ref()?;
        let input = SceneInput::from_view(self.loaded.replay.run(), view);
        let options = ViewOptions {
            layers: self.settings.layers(),
            world_per_px,
        };
        Some(build_scene(&input, &options))
    }

    fn seek(&mut self, k: usize) {
        let k = k.min(self.len().saturating_sub(1));
        if self.view.as_ref().is_some_and(|v| v.index == k) {
            return;
        }
        self.view = self.loaded.replay.view(k);
        if let Some(b) = &mut self.baseline {
            b.view = b.replay.view(k);
        }
        // Ids of this step's clusters and new segments mean nothing in another step.
        if matches!(
            self.selection,
            SceneId::Cluster(_)
                | SceneId::NewSegment(_)
                | SceneId::Decision { .. }
                | SceneId::Correlation(_)
                | SceneId::Reading { .. }
        ) {
            self.selection = SceneId::None;
        }
    }

    fn open_bytes(&mut self, bytes: &[u8], source: Source, keep_index: bool) {
        let name = source.display_name();
        // The importer is picked from the content: sonarmap-log, Player/Stage, MCAP or a table
        // (Player logs with geometry and MCAP with /tf_static need no layout).
        match import_any(bytes, &name, &ImportOptions::default()).map(|i| i.run) {
            Ok(run) if run.snapshots.len() >= self.background_min_snapshots => {
                self.start_background(Arc::new(run), JobKind::Open { source, keep_index });
            }
            Ok(run) => self.install(Self::prepare(run, source, &self.params), keep_index),
            Err(e) => {
                // The importer's error already names the file and the place.
                self.banner = Some(format!("Could not open the log: {e}"));
                self.message = "open failed; the previous run stays open".to_owned();
            }
        }
    }

    /// Replays a large run on a thread; the current run stays usable meanwhile.
    fn start_background(&mut self, run: Arc<Run>, kind: JobKind) {
        if let Some(old) = self.background.take() {
            old.cancel.store(true, Ordering::Relaxed);
        }
        let total = run.snapshots.len();
        let progress = Arc::new(AtomicUsize::new(0));
        let cancel = Arc::new(AtomicBool::new(false));
        let (tx, rx) = std::sync::mpsc::channel();
        let (p, c, params) = (progress.clone(), cancel.clone(), self.params.clone());
        std::thread::spawn(move || {
            let built = Replay::build(run, params, DEFAULT_CHECKPOINT_INTERVAL, &mut |done| {
                p.store(done, Ordering::Relaxed);
                !c.load(Ordering::Relaxed)
            });
            if let Ok(replay) = built {
                let _ = tx.send(replay);
            }
        });
        let label = match &kind {
            JobKind::Open { source, .. } => format!("replaying {}", source.display_name()),
            JobKind::Rerun => "re-running with new parameters".to_owned(),
        };
        self.message = format!("{label}…");
        self.background = Some(Background {
            kind,
            label,
            started: std::time::Instant::now(),
            total,
            progress,
            cancel,
            result: rx,
        });
    }

    fn install(&mut self, loaded: Loaded, keep_index: bool) {
        let k = self.current();
        let name = loaded.source.display_name();
        if let Source::File(path) = &loaded.source {
            let path = path.clone();
            self.remember(&path);
        }
        self.loaded = loaded;
        self.view = None;
        if let Some(b) = self.baseline.take() {
            if let Some(job) = b.job {
                job.cancel.store(true, Ordering::Relaxed);
            }
        }
        self.load_bookmarks();
        self.selection = SceneId::None;
        self.compare = CompareState::Off;
        self.playing = false;
        self.banner = None;
        self.seek(if keep_index { k } else { 0 });
        if !keep_index {
            self.map_view.request = Some(ViewRequest::Fit);
        }
        self.message = format!(
            "{} {name}: {} snapshots",
            if keep_index { "reloaded" } else { "opened" },
            self.len()
        );
        self.report_step_failure();
    }

    /// Shows in the banner a step that failed while replaying: the run stays open up to the
    /// snapshot before it.
    fn report_step_failure(&mut self) {
        if let Some(failure) = self.loaded.replay.failure() {
            self.banner = Some(format!(
                "{}: {failure}. The run is open up to the snapshot before it.",
                self.loaded.source.display_name()
            ));
        }
    }

    fn open_path(&mut self, path: &Path, keep_index: bool) {
        match std::fs::read(path) {
            Ok(bytes) => self.open_bytes(&bytes, Source::File(path.to_path_buf()), keep_index),
            Err(e) => {
                self.banner = Some(format!("Could not read {}: {e}", path.display()));
                self.message = "open failed; the previous run stays open".to_owned();
            }
        }
    }

    fn remember(&mut self, path: &Path) {
        self.settings.recent.retain(|p| p != path);
        self.settings.recent.insert(0, path.to_path_buf());
        self.settings.recent.truncate(MAX_RECENT);
    }

    /// Writes what the map view shows to `path` as SVG (atomically).
    pub fn export_svg(&mut self, path: &Path) -> Result<(), String> {
        let scene = self
            .scene_with(self.map_view.world_per_px())
            .ok_or_else(|| "nothing to export".to_owned())?;
        let view = self
            .map_view
            .visible_m
            .unwrap_or_else(|| default_view(&scene));
        let (w, h) = self.map_view.size_px;
        let size = (w.max(400) + 180, h.max(300) + 60);
        let title = format!("{} — snapshot {}", self.run().name, self.current());
        let svg = to_svg(&scene, view, size, &title, self.run().units);
        write_svg_atomically(path, &svg)
            .map_err(|e| format!("Could not write {}: {e}", path.display()))
    }

    /// Applies one command (the only place the state changes).
    pub fn apply(&mut self, command: Command) {
        match command {
            Command::Open(path) => self.open_path(&path, false),
            Command::OpenBytes { name, bytes } => {
                self.open_bytes(&bytes, Source::Bytes(name), false)
            }
            Command::OpenDialog => {
                if let Some(path) = rfd::FileDialog::new()
                    .add_filter("run log", &["json"])
                    .pick_file()
                {
                    self.open_path(&path, false);
                }
            }
            Command::Reload => match self.loaded.source.clone() {
                Source::File(path) => self.open_path(&path, true),
                _ => self.message = "the built-in run has no file to reload".to_owned(),
            },
            Command::Seek(k) => self.seek(k),
            Command::Step(delta) => {
                let k = (self.current() as i64).saturating_add(delta).max(0) as usize;
                self.seek(k);
            }
            Command::First => self.seek(0),
            Command::Last => self.seek(self.len().saturating_sub(1)),
            Command::TogglePlay => {
                self.playing = !self.playing;
                self.play_clock_s = 0.0;
                if self.playing && self.current() + 1 >= self.len() {
                    self.seek(0);
                }
            }
            Command::SetRate(rate) => {
                if rate.is_finite() && rate > 0.0 {
                    self.settings.rate = rate.clamp(0.25, 60.0);
                }
            }
            Command::NextMark => {
                let k = self.current();
                match self.loaded.marks.iter().find(|&&m| m > k) {
                    Some(&m) => self.seek(m),
                    None => self.message = "no mark after this snapshot".to_owned(),
                }
            }
            Command::PrevMark => {
                let k = self.current();
                match self.loaded.marks.iter().rev().find(|&&m| m < k) {
                    Some(&m) => self.seek(m),
                    None => self.message = "no mark before this snapshot".to_owned(),
                }
            }
            Command::Select(id) => self.select(id),
            Command::CompareWith(id) => {
                self.compare = CompareState::Armed(id);
                self.message = format!("compare #{id} with…: click a segment");
            }
            Command::CancelCompare => self.compare = CompareState::Off,
            Command::ToggleLayer(layer) => {
                let on = self.settings.layers().contains(layer);
                self.settings.set_layer(layer, !on);
            }
            Command::FilterDecisions(filter) => self.decision_filter = filter,
            Command::FitView => self.map_view.request = Some(ViewRequest::Fit),
            Command::ZoomToSelection => match self.ends_of(self.selection) {
                Some(ends) => {
                    let length = (ends.b.point - ends.a.point).norm();
                    let rect =
                        ViewRect::new(ends.a.point, ends.b.point).expanded(length.max(0.5) * 0.75);
                    self.map_view.request = Some(ViewRequest::Frame(rect));
                }
                None => self.message = "select a segment to zoom to it".to_owned(),
            },
            Command::CenterOn(p) => self.map_view.request = Some(ViewRequest::Center(p)),
            Command::ExportDialog => {
                let name = format!("snapshot-{}.svg", self.current());
                if let Some(path) = rfd::FileDialog::new()
                    .add_filter("SVG", &["svg"])
                    .set_file_name(name)
                    .save_file()
                {
                    self.apply(Command::ExportSvg(path));
                }
            }
            Command::ExportSvg(path) => match self.export_svg(&path) {
                Ok(()) => self.message = format!("exported {}", path.display()),
                Err(e) => {
                    self.banner = Some(e);
                    self.message = "export failed".to_owned();
                }
            },
            Command::DismissError => self.banner = None,
            Command::ToggleShortcuts => self.show_shortcuts = !self.show_shortcuts,
            Command::SetParams(params) => self.set_params(params),
            Command::LoadParamsDialog => {
                if let Some(path) = rfd::FileDialog::new()
                    .add_filter("parameters", &["json"])
                    .pick_file()
                {
                    self.load_params(&path);
                }
            }
            Command::SaveParamsDialog => {
                if let Some(path) = rfd::FileDialog::new()
                    .add_filter("parameters", &["json"])
                    .set_file_name("params.json")
                    .save_file()
                {
                    self.save_params(&path);
                }
            }
            Command::LoadParams(path) => self.load_params(&path),
            Command::SaveParams(path) => self.save_params(&path),
            Command::PinBaseline => self.pin_baseline(),
            Command::Unpin => {
                if let Some(b) = self.baseline.take() {
                    if let Some(job) = b.job {
                        job.cancel.store(true, Ordering::Relaxed);
                    }
                    self.message = "baseline unpinned".to_owned();
                }
            }
            Command::ShowTab(tab) => self.settings.left_tab = tab,
            Command::ToggleBaselineGhost => {
                self.settings.baseline_ghost = !self.settings.baseline_ghost
            }
            Command::AddBookmark(name) => {
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
            Command::RemoveBookmark(i) => {
                if i < self.bookmarks.len() {
                    let b = self.bookmarks.remove(i);
                    self.message = format!("removed bookmark {:?}", b.name);
                    self.save_bookmarks();
                }
            }
        }
    }

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

    /// End-points of a new segment or a map segment of the current step.
    fn ends_of(&self, id: SceneId) -> Option<SegmentEnds> {
        let view = self.view.as_ref()?;
        match id {
            SceneId::NewSegment(i) | SceneId::Decision { new_segment: i, .. } => {
                let s = view.trace.new_segments.get(i)?;
                Some(SegmentEnds { a: s.a, b: s.b })
            }
            SceneId::MapSegment(id) | SceneId::Update(id) => {
                let s = view
                    .map_after
                    .segment(id)
                    .or_else(|| view.map_before.segment(id))?;
                Some(SegmentEnds { a: s.a, b: s.b })
            }
            _ => None,
        }
    }

    fn advance_playback(&mut self, ctx: &egui::Context) {
        if !self.playing {
            return;
        }
        let dt = f64::from(ctx.input(|i| i.stable_dt)).clamp(0.0, 0.5);
        self.play_clock_s += dt;
        let period = 1.0 / f64::from(self.settings.rate.max(0.25));
        while self.play_clock_s >= period {
            self.play_clock_s -= period;
            if self.current() + 1 >= self.len() {
                self.playing = false;
                self.message = "reached the last snapshot".to_owned();
                break;
            }
            self.seek(self.current() + 1);
        }
        ctx.request_repaint();
    }

    fn dropped_files(ctx: &egui::Context) -> Vec<Command> {
        ctx.input(|i| {
            i.raw
                .dropped_files
                .iter()
                .take(1)
                .map(|f| {
                    let path = f.path();
                    if path.exists() {
                        Command::Open(path.to_path_buf())
                    } else {
                        let name = path.display().to_string();
                        match f.bytes() {
                            Ok(bytes) => Command::OpenBytes { name, bytes },
                            Err(_) => Command::Open(path.to_path_buf()),
                        }
                    }
                })
                .collect()
        })
    }

    /// One frame of the whole window: applies queued commands, then lays out the panels.
    pub fn ui(&mut self, ui: &mut egui::Ui) {
        let ctx = ui.ctx().clone();
        for command in std::mem::take(&mut self.pending) {
            self.apply(command);
        }
        self.poll_background(&ctx);
        self.advance_playback(&ctx);
        let mut commands = handle_shortcuts(&ctx);
        commands.extend(Self::dropped_files(&ctx));
        if let Some(rect) = ctx.input(|i| i.viewport().inner_rect) {
            self.settings.window_size = Some([rect.width(), rect.height()]);
        }

        egui::Panel::top("menu_bar").show(ui, |ui| {
            commands.extend(menu_bar_ui(
                ui,
                &self.settings.recent,
                self.baseline.is_some(),
            ));
        });
        if let Some(text) = &self.banner {
            let frame = egui::Frame::new()
                .fill(egui::Color32::from_rgb(0x7a, 0x1e, 0x1e))
                .inner_margin(6.0);
            egui::Panel::top("error_banner")
                .frame(frame)
                .show(ui, |ui| {
                    ui.horizontal(|ui| {
                        if ui.button("Dismiss").clicked() {
                            commands.push(Command::DismissError);
                        }
                        ui.add(
                            egui::Label::new(egui::RichText::new(text).color(egui::Color32::WHITE))
                                .wrap(),
                        );
                    });
                });
        }
        egui::Panel::bottom("status_bar").show(ui, |ui| self.status_bar_ui(ui));
        egui::Panel::bottom("timeline").show(ui, |ui| {
            let info = TimelineInfo {
                len: self.len(),
                current: self.current(),
                t_s: self.view.as_ref().map_or(0.0, |v| v.trace.t),
                marks: &self.loaded.marks,
                baseline_marks: self
                    .baseline
                    .as_ref()
                    .and_then(|b| b.diff.as_ref())
                    .map(|d| d.snapshots.as_slice()),
                playing: self.playing,
                rate: self.settings.rate,
            };
            commands.extend(timeline_ui(ui, &info, &mut self.jump_text));
        });

        let scene = self.scene().unwrap_or_default();
        egui::Panel::left("layers")
            .resizable(true)
            .default_size(290.0)
            .show(ui, |ui| {
                ui.horizontal(|ui| {
                    for tab in LeftTab::ALL {
                        if ui
                            .selectable_label(self.settings.left_tab == tab, tab.label())
                            .clicked()
                        {
                            commands.push(Command::ShowTab(tab));
                        }
                    }
                });
                ui.separator();
                egui::ScrollArea::vertical().show(ui, |ui| match self.settings.left_tab {
                    LeftTab::Parameters => {
                        let fraction =
                            |done: usize, total: usize| done as f32 / total.max(1) as f32;
                        let info = ParamsPanelInfo {
                            params: &self.params,
                            units: self.loaded.replay.run().units,
                            rerun_progress: self.background.as_ref().and_then(|j| {
                                matches!(j.kind, JobKind::Rerun)
                                    .then(|| fraction(j.progress.load(Ordering::Relaxed), j.total))
                            }),
                            pinned: self.baseline.is_some(),
                            diff_progress: self.baseline.as_ref().and_then(|b| {
                                b.job
                                    .as_ref()
                                    .map(|j| fraction(j.progress.load(Ordering::Relaxed), j.total))
                            }),
                            differing: self
                                .baseline
                                .as_ref()
                                .and_then(|b| b.diff.as_ref())
                                .map(|d| d.snapshots.len()),
                        };
                        commands.extend(params_panel_ui(ui, &mut self.params_panel, &info));
                        if self.baseline.is_some() {
                            let mut ghost = self.settings.baseline_ghost;
                            if ui.checkbox(&mut ghost, "Baseline map (ghosted)").changed() {
                                commands.push(Command::ToggleBaselineGhost);
                            }
                        }
                    }
                    LeftTab::Bookmarks => {
                        commands.extend(bookmarks_ui(
                            ui,
                            &self.bookmarks,
                            self.current(),
                            &mut self.bookmark_text,
                        ));
                    }
                    LeftTab::Layers => {
                        commands.extend(layers_ui(ui, self.settings.layers(), &scene.legend()));
                    }
                });
            });
        let differences = self.differences_here();
        egui::Panel::right("inspector")
            .resizable(true)
            .default_size(580.0)
            .show(ui, |ui| {
                if let Some(view) = &self.view {
                    let ictx = InspectCtx {
                        run: self.loaded.replay.run(),
                        view,
                        params: self.loaded.replay.params(),
                        baseline: self
                            .baseline
                            .as_ref()
                            .and_then(|b| b.view.as_ref().map(|v| (&b.params, v))),
                    };
                    egui::Panel::top("decisions")
                        .resizable(true)
                        .default_size(190.0)
                        .show(ui, |ui| {
                            commands.extend(decisions_ui(
                                ui,
                                &ictx,
                                self.decision_filter,
                                self.selection,
                                self.baseline.as_ref().map(|_| differences.as_slice()),
                            ));
                        });
                    egui::CentralPanel::default().show(ui, |ui| {
                        egui::ScrollArea::both().show(ui, |ui| {
                            commands.extend(inspector_ui(ui, &ictx, self.selection, &self.compare));
                        });
                    });
                }
            });
        egui::CentralPanel::default().show(ui, |ui| {
            let describe = |id: SceneId| {
                self.view.as_ref().and_then(|view| {
                    hover_text(
                        &InspectCtx {
                            run: self.loaded.replay.run(),
                            view,
                            params: self.loaded.replay.params(),
                            baseline: None,
                        },
                        id,
                    )
                })
            };
            commands.extend(map_view_ui(
                ui,
                &scene,
                self.run().units,
                &mut self.map_view,
                self.selection,
                &describe,
                self.baseline
                    .as_ref()
                    .filter(|_| self.settings.baseline_ghost)
                    .and_then(|b| b.view.as_ref())
                    .map(|v| &v.map_after),
            ));
        });
        if self.show_shortcuts {
            let mut open = true;
            shortcuts_window_ui(&ctx, &mut open);
            if !open {
                commands.push(Command::ToggleShortcuts);
            }
        }
        for command in commands {
            self.apply(command);
        }
    }

    fn status_bar_ui(&self, ui: &mut egui::Ui) {
        ui.horizontal(|ui| {
            ui.label(self.loaded.source.display_name());
            ui.separator();
            if let Some(job) = &self.background {
                ui.spinner();
                let done = job.progress.load(Ordering::Relaxed);
                ui.add(
                    egui::ProgressBar::new(done as f32 / job.total.max(1) as f32)
                        .desired_width(160.0)
                        .text(format!("{}: {done} / {}", job.label, job.total)),
                );
                ui.separator();
            }
            ui.label(format!(
                "snapshot {} / {}",
                self.current(),
                self.len().saturating_sub(1)
            ));
            ui.separator();
            let units = self.run().units;
            match self.map_view.cursor_m {
                Some(p) => ui.label(format!(
                    "x {}  y {}",
                    format_length(p.x, units),
                    format_length(p.y, units)
                )),
                None => ui.label("x -  y -"),
            };
            if let Some(r) = self.map_view.ruler_text(units) {
                ui.separator();
                ui.label(format!("ruler {r}"));
            }
            ui.separator();
            ui.label(&self.message);
        });
    }
}

impl eframe::App for SonarApp {
    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        SonarApp::ui(self, ui);
    }

    fn save(&mut self, storage: &mut dyn eframe::Storage) {
        if let Ok(text) = serde_json::to_string(&self.settings) {
            storage.set_string(SETTINGS_KEY, text);
        }
    }
}
