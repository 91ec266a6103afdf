//! Opening a run and installing replays: the app's constructors (the first run), then a file
//! or dropped bytes imported, replayed on the spot when small or on a thread ([`super::jobs`])
//! when large or re-run under new parameters, and installed when done with its bookmarks. The
//! baseline's comparison is started and collected here too.

use super::app::SonarApp;
use super::bookmarks::read_sidecar;
use super::inspector::CompareState;
use super::jobs::{JobKind, JobPoll, ReplayJob, BACKGROUND_MIN_SNAPSHOTS};
use super::layout_choice::LayoutChoice;
use super::layout_picker::LayoutPicker;
use super::loaded::{Loaded, Source};
use super::map_view::{MapViewState, ViewRequest};
use super::params_panel::ParamsPanelState;
use super::settings::Settings;
use crate::import::{
    builtin_layout, import_any, parse_layout, ImportError, ImportOptions, NamedBytes,
};
use crate::mapping::Params;
use crate::replay::{Replay, ReplayCursor};
use crate::run::Run;
use crate::scene::SceneId;
use crate::units::Units;
use std::path::Path;
use std::sync::Arc;

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
        let loaded = Loaded::prepare(run, source, &params);
        let mut app = SonarApp {
            settings,
            params,
            loaded,
            background: None,
            background_min_snapshots: BACKGROUND_MIN_SNAPSHOTS,
            view: None,
            cursor: ReplayCursor::default(),
            scene_cache: Default::default(),
            baseline_scene_cache: Default::default(),
            truth: None,
            playing: false,
            play_clock_s: 0.0,
            selection: SceneId::None,
            compare: CompareState::Off,
            decision_filter: Default::default(),
            banner: None,
            message: String::new(),
            map_view: MapViewState::default(),
            split_view: MapViewState::default(),
            file_dialog: None,
            layout_picker: None,
            pending: Vec::new(),
            show_shortcuts: false,
            jump_text: String::new(),
            params_panel: ParamsPanelState::default(),
            baseline: None,
            bookmarks: Vec::new(),
            bookmark_text: String::new(),
            last_rerun_s: None,
            calibrating_from: None,
            auto_calibration: None,
            shown_title: String::new(),
        };
        app.seek(0);
        app.calibrate_if_drifting();
        app.load_bookmarks();
        app.message = match notice {
            Some(n) => n,
            None => format!("opened {}", app.loaded.source.display_name()),
        };
        app
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

    pub(super) fn open_path(&mut self, path: &Path, keep_index: bool) {
        match std::fs::read(path) {
            Ok(bytes) => self.open_bytes(&bytes, Source::File(path.to_path_buf()), keep_index),
            Err(e) => {
                self.banner = Some(format!("Could not read {}: {e}", path.display()));
                self.message = "open failed; the previous run stays open".to_owned();
            }
        }
    }

    pub(super) fn open_bytes(&mut self, bytes: &[u8], source: Source, keep_index: bool) {
        self.open_bytes_with(bytes, source, keep_index, &ImportOptions::default());
    }

    /// Imports `bytes` with `options`; a log that needs a layout (and was given none) opens
    /// the layout picker instead of failing.
    pub(super) fn open_bytes_with(
        &mut self,
        bytes: &[u8],
        source: Source,
        keep_index: bool,
        options: &ImportOptions,
    ) {
        let name = source.display_name();
        // The importer is picked from the content: sonarmap-log, Player/Stage, MCAP or a table
        // (Player logs with geometry and MCAP with /tf_static need no layout).
        let imported = import_any(bytes, &name, options).map(|i| i.run);
        if imported.is_ok() && !keep_index {
            self.forget_auto_calibration();
        }
        match imported {
            Ok(run) if run.snapshots.len() >= self.background_min_snapshots => {
                // Its first snapshots at once, the whole run replayed on a thread.
                let run = Arc::new(run);
                // A reload during a reload's preview goes back to the first one's snapshot.
                let pending = self.background.as_ref().and_then(|j| j.kind.resume_at());
                let resume_at = keep_index.then(|| pending.unwrap_or(self.current()));
                let kind = JobKind::Complete {
                    source: source.clone(),
                    resume_at,
                };
                self.start_background(run.clone(), kind);
                self.install(Loaded::preview(run, source, &self.params), keep_index);
                let verb = if keep_index { "reloaded" } else { "opened" };
                self.message = if self.loaded.is_preview() {
                    format!(
                        "{verb} {name}: the first {} of {} snapshots while the rest replays",
                        self.len(),
                        self.loaded.run.snapshots.len()
                    )
                } else {
                    // A step failed within the preview (the whole replay would stop there
                    // too), or the preview is the whole run: nothing is left to replay.
                    self.cancel_background();
                    format!("{verb} {name}: {} snapshots", self.len())
                };
            }
            Ok(run) => {
                // A replay still running (of the run open before, under new parameters) must not
                // land on top of this one.
                self.cancel_background();
                self.install(Loaded::prepare(run, source, &self.params), keep_index)
            }
            Err(ImportError::NeedsLayout { what, .. }) if options.layout.is_none() => {
                self.message = format!("{name} needs a sensor layout: pick one");
                self.layout_picker = Some(LayoutPicker {
                    source,
                    bytes: bytes.to_vec(),
                    reason: format!("{what}: pick the robot's sensor layout to read it."),
                    units: Units::Metres,
                    poses: options.poses.clone(),
                });
            }
            Err(e) => {
                // The importer's error already names the file and the place.
                self.banner = Some(format!("Could not open the log: {e}"));
                self.message = "open failed; the previous run stays open".to_owned();
            }
        }
    }

    /// Opens the log waiting in the layout picker with the layout chosen; a layout that cannot
    /// be read, or a log that still does not import, goes to the banner.
    pub(super) fn open_with_layout(&mut self, choice: LayoutChoice) {
        let Some(picker) = self.layout_picker.take() else {
            return;
        };
        let layout = match &choice {
            LayoutChoice::Shipped(name) => {
                builtin_layout(name).ok_or_else(|| format!("no shipped layout named {name:?}"))
            }
            LayoutChoice::File(path) => std::fs::read(path)
                .map_err(|e| format!("Could not read {}: {e}", path.display()))
                .and_then(|bytes| {
                    parse_layout(&bytes, &path.display().to_string()).map_err(|e| e.to_string())
                }),
        };
        match layout {
            Ok(layout) => {
                let options = ImportOptions {
                    layout: Some(layout),
                    units: Some(picker.units),
                    poses: picker.poses.clone(),
                    ..ImportOptions::default()
                };
                self.open_bytes_with(&picker.bytes, picker.source, false, &options);
            }
            Err(e) => {
                self.banner = Some(e);
                self.layout_picker = Some(picker);
            }
        }
    }

    /// Reads the poses table for the log waiting in the layout picker.
    pub(super) fn set_picker_poses(&mut self, path: &Path) {
        let Some(picker) = &mut self.layout_picker else {
            return;
        };
        match std::fs::read(path) {
            Ok(bytes) => {
                picker.poses = Some(NamedBytes {
                    name: path.display().to_string(),
                    bytes,
                });
                self.message = format!("poses from {}", path.display());
            }
            Err(e) => self.banner = Some(format!("Could not read {}: {e}", path.display())),
        }
    }

    /// Replays a large run on a thread; what is shown stays usable meanwhile.
    pub(super) fn start_background(&mut self, run: Arc<Run>, kind: JobKind) {
        self.cancel_background();
        let job = ReplayJob::start(run, self.params.clone(), kind);
        self.message = format!("{}…", job.label);
        self.background = Some(job);
    }

    /// Stops the background replay, if any: its result will never be installed.
    fn cancel_background(&mut self) {
        if let Some(old) = self.background.take() {
            old.task.cancel();
        }
    }

    /// Installs a finished background replay or comparison.
    pub(super) fn poll_background(&mut self, ctx: &egui::Context) {
        self.poll_diff(ctx);
        let Some(job) = &self.background else {
            return;
        };
        match job.task.poll() {
            JobPoll::Done(replay) => {
                let job = self.background.take().expect("checked above");
                match job.kind {
                    JobKind::Complete { source, resume_at } => {
                        // Still the run opened (another open cancels the job).
                        self.install_resuming(replay, resume_at);
                        self.message = format!(
                            "{} {}: {} snapshots, replayed in {:.1} s",
                            if resume_at.is_some() {
                                "reloaded"
                            } else {
                                "opened"
                            },
                            source.display_name(),
                            self.len(),
                            job.started.elapsed().as_secs_f64()
                        );
                    }
                    JobKind::Rerun { resume_at } => {
                        let s = job.started.elapsed().as_secs_f64();
                        self.last_rerun_s = Some(s);
                        self.install_resuming(replay, resume_at);
                        let params = self.loaded.replay.params();
                        let tracked = params.heading_track.is_some();
                        let corrects_pose = params.pose_correction;
                        self.message = match self.calibrating_from.take() {
                            Some((deg_per_m, per_turn_pct)) => format!(
                                "mapped again from the drift the first pass found \
                                 ({deg_per_m:+.3}°/m, {per_turn_pct:+.2} % of turns){}{} \
                                 (calibrate_first) in {s:.2} s",
                                if tracked {
                                    " and its heading errors, smoothed"
                                } else {
                                    ""
                                },
                                if corrects_pose {
                                    ", the pose corrected against the map"
                                } else {
                                    ""
                                }
                            ),
                            None => format!(
                                "re-ran {} snapshots with the new parameters in {s:.2} s",
                                self.len()
                            ),
                        };
                    }
                }
                self.calibrate_if_drifting();
            }
            JobPoll::Running => ctx.request_repaint(),
            JobPoll::Stopped => {
                let job = self.background.take().expect("checked above");
                self.banner = Some(match job.kind {
                    JobKind::Complete { .. } => {
                        // The preview is all there is: the run shown is its first snapshots.
                        self.loaded.run = self.loaded.replay.run().clone();
                        format!(
                            "replaying the whole run stopped unexpectedly; only its first {} \
                             snapshots are open",
                            self.len()
                        )
                    }
                    JobKind::Rerun { .. } => {
                        "the replay stopped unexpectedly; the previous run stays open".to_owned()
                    }
                });
            }
        }
    }

    /// Another run is opening: the parameters `calibrate_first` set for the run open before
    /// go back to what they were ([`without_run_calibration`]); the user's other changes stay.
    fn forget_auto_calibration(&mut self) {
        if let Some(calibration) = self.auto_calibration.take() {
            self.params = without_run_calibration(&self.params, &calibration);
        }
    }

    /// With `calibrate_first`, a replay that found the odometry drifting is followed by a
    /// second one from that drift (docs/algorithm.md §8.17, "calibrate, then map").
    fn calibrate_if_drifting(&mut self) {
        if let Some(calibrated) = self.loaded.replay.second_pass().cloned() {
            let drift = (calibrated.drift_deg_per_m, calibrated.drift_per_turn_pct);
            self.message = format!(
                "the odometry drifts ({:+.3}°/m, {:+.2} % of turns): mapping again from that \
                 drift (calibrate_first)",
                drift.0, drift.1
            );
            self.calibrating_from = Some(drift);
            self.auto_calibration = Some((self.params.clone(), calibrated.clone()));
            self.push(crate::app::Command::SetParams(calibrated));
        }
    }

    fn poll_diff(&mut self, ctx: &egui::Context) {
        if let Some(message) = self.baseline.as_mut().and_then(|b| b.poll(ctx)) {
            self.message = message;
        }
    }

    /// Starts comparing the baseline with the replay shown, on a thread.
    pub(super) fn start_diff(&mut self) {
        let current = self.loaded.replay.params().clone();
        let run = self.loaded.replay.run().clone();
        if let Some(baseline) = &mut self.baseline {
            baseline.start_diff(run, current);
        }
    }

    fn install(&mut self, loaded: Loaded, keep_index: bool) {
        let k = self.current();
        let name = loaded.source.display_name();
        if let Source::File(path) = &loaded.source {
            let path = path.clone();
            self.settings.remember(&path);
        }
        self.loaded = loaded;
        self.view = None;
        if let Some(mut b) = self.baseline.take() {
            b.cancel_job();
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
        // A run replayed whole at once (no background job to finish) is calibrated here.
        if !self.loaded.is_preview() {
            self.calibrate_if_drifting();
        }
    }

    /// [`Self::install_rerun`], then snapshot `resume_at` (a reload's, set while its preview
    /// was shown) unless the user moved from where the preview put them.
    fn install_resuming(&mut self, replay: Replay, resume_at: Option<usize>) {
        let unmoved = resume_at.filter(|&k| self.current() == k.min(self.len().saturating_sub(1)));
        self.install_rerun(replay);
        if let Some(k) = unmoved {
            self.seek(k);
        }
    }

    /// Installs a re-run of the open run: same snapshot, the selection when it still exists.
    fn install_rerun(&mut self, replay: Replay) {
        let k = self.current();
        let selection = self.selection;
        self.loaded = Loaded::new(replay, self.loaded.source.clone());
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

    /// Reads the open run's bookmarks: the settings' for the built-in run, the sidecar file's
    /// for a log file, none for a dropped file.
    pub(super) fn load_bookmarks(&mut self) {
        self.bookmarks = match &self.loaded.source {
            Source::BuiltIn(_) => self.settings.builtin_bookmarks.clone(),
            Source::Bytes(_) => Vec::new(),
            Source::File(path) => match read_sidecar(path) {
                Ok(bookmarks) => bookmarks,
                Err(message) => {
                    self.message = message;
                    Vec::new()
                }
            },
        };
    }
}

/// `params` without the calibration `calibrate_first` put on the open run (the parameters
/// `before` and `after` it): each parameter the calibration sets (the drift, the heading track,
/// pose correction) goes back to its value before, unless the user has changed it since. A
/// calibration belongs to its run, not to the settings or the next run.
pub(super) fn without_run_calibration(
    params: &Params,
    (before, after): &(Params, Params),
) -> Params {
    fn back<T: PartialEq + Clone>(now: &T, before: &T, after: &T) -> T {
        if now == after { before } else { now }.clone()
    }
    Params {
        drift_deg_per_m: back(
            &params.drift_deg_per_m,
            &before.drift_deg_per_m,
            &after.drift_deg_per_m,
        ),
        drift_per_turn_pct: back(
            &params.drift_per_turn_pct,
            &before.drift_per_turn_pct,
            &after.drift_per_turn_pct,
        ),
        heading_track: back(
            &params.heading_track,
            &before.heading_track,
            &after.heading_track,
        ),
        pose_correction: back(
            &params.pose_correction,
            &before.pose_correction,
            &after.pose_correction,
        ),
        ..params.clone()
    }
}
