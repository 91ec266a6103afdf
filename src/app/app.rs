//! The inspector's runtime state, [`SonarApp`]: the open run, the step shown, the selection,
//! the background work and the panels' state, beside the persisted [`Settings`], and what can
//! be asked of it. Its methods are spread by concern, each file depending only on those before
//! it: `loading.rs` (the constructors, opening runs, installing what background jobs built),
//! `apply.rs` (the one place where [`Command`]s change the state) and `frame.rs` (one frame).

use super::baseline::Baseline;
use super::bookmarks::Bookmark;
use super::command::Command;
use super::inspector::CompareState;
use super::jobs::ReplayJob;
use super::loaded::{Loaded, Source};
use super::map_view::MapViewState;
use super::marks::MarkKind;
use super::params_panel::ParamsPanelState;
use super::scene_cache::{SceneCache, SceneSubject};
use super::settings::Settings;
use super::truth::TruthView;
use crate::diff::{DecisionDifference, RunDiff};
use crate::mapping::paper::matching::SegmentEnds;
use crate::mapping::Params;
use crate::replay::{ReplayCursor, StepView};
use crate::run::Run;
use crate::scene::{build_scene, LayerSet, Scene, SceneId, SceneInput, ViewOptions};
use std::sync::Arc;

/// The inspector. Constructible without eframe, so tests drive it through [`SonarApp::ui`].
pub struct SonarApp {
    pub(super) settings: Settings,
    pub(super) params: Params,
    pub(super) loaded: Loaded,
    pub(super) background: Option<ReplayJob>,
    pub(super) background_min_snapshots: usize,
    pub(super) view: Option<StepView>,
    /// Where the last seek left the replay's mapper (stepping forward costs one step).
    pub(super) cursor: ReplayCursor,
    /// The map view's scene between frames.
    pub(super) scene_cache: SceneCache,
    /// The baseline's (A of the split view).
    pub(super) baseline_scene_cache: SceneCache,
    /// `eval`'s verdicts on the map shown, when the run has a floor plan.
    pub(super) truth: Option<TruthView>,
    pub(super) playing: bool,
    pub(super) play_clock_s: f64,
    pub(super) selection: SceneId,
    pub(super) compare: CompareState,
    pub(super) decision_filter: super::decision_filter::DecisionFilter,
    pub(super) banner: Option<String>,
    pub(super) message: String,
    pub(super) map_view: MapViewState,
    /// The baseline's map view (A) of the split view; its pan and zoom follow `map_view`'s.
    pub(super) split_view: MapViewState,
    /// The in-app file dialog, while open.
    pub(super) file_dialog: Option<super::in_app_dialog::InAppDialog>,
    /// A log that needs a sensor layout, waiting for the layout picker.
    pub(super) layout_picker: Option<super::layout_picker::LayoutPicker>,
    pub(super) pending: Vec<Command>,
    pub(super) show_shortcuts: bool,
    pub(super) jump_text: String,
    pub(super) params_panel: ParamsPanelState,
    pub(super) baseline: Option<Baseline>,
    pub(super) bookmarks: Vec<Bookmark>,
    pub(super) bookmark_text: String,
    pub(super) last_rerun_s: Option<f64>,
    /// The drift (°/m, % of turns) a replay found, while the run is mapped again from it
    /// (`calibrate_first`).
    pub(super) calibrating_from: Option<(f64, f64)>,
    /// The parameters before and after `calibrate_first` mapped the open run again: a
    /// calibration belongs to the run it was found on, so a run opened next, and the saved
    /// settings, take the parameters before it (unless they were changed since).
    pub(super) auto_calibration: Option<(Params, Params)>,
    /// The window title last sent to the window.
    pub(super) shown_title: String,
}

impl SonarApp {
    /// Replays runs of at least `snapshots` snapshots in the background (default
    /// [`super::BACKGROUND_MIN_SNAPSHOTS`]).
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
            (Some(b), Some(v)) => b.differences(v),
            _ => Vec::new(),
        }
    }

    /// The parameters (asked for) that differ from the active preset's, as the panel names
    /// them; empty when they are the preset's.
    pub fn changed_params(&self) -> Vec<&'static str> {
        super::params_panel::changed_fields(&self.params, self.settings.preset)
    }

    /// The window's title: the run, and a warning when the parameters are not the preset's.
    pub fn window_title(&self) -> String {
        let mut title = format!("sonarmap · {}", self.loaded.source.display_name());
        let changed = self.changed_params();
        if !changed.is_empty() {
            title.push_str(&format!(
                " · parameters ≠ {} ({})",
                super::params_panel::preset_name(self.settings.preset),
                changed.join(", ")
            ));
        }
        title
    }

    /// The bookmarks of the open run.
    pub fn bookmarks(&self) -> &[Bookmark] {
        &self.bookmarks
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

    /// Snapshots with a timeline mark of a kind switched on, ascending (prev/next mark follow
    /// them).
    pub fn marks(&self) -> Vec<usize> {
        let hidden = &self.settings.hidden_marks;
        let mut marks = self.loaded.marks.shown(hidden);
        if !hidden.contains(&MarkKind::DirectDifferences) {
            marks.extend(self.direct_difference_marks().iter().copied());
            marks.sort_unstable();
            marks.dedup();
        }
        marks
    }

    /// Snapshots where a decision differs directly from the pinned baseline (when compared).
    pub(super) fn direct_difference_marks(&self) -> &[usize] {
        self.baseline
            .as_ref()
            .and_then(|b| b.diff.as_ref())
            .map_or(&[][..], |d| d.direct_snapshots.as_slice())
    }

    /// The number of marks of each kind, and whether the kind is shown.
    pub fn mark_counts(&self) -> Vec<(MarkKind, usize, bool)> {
        MarkKind::ALL
            .into_iter()
            .map(|kind| {
                let count = match kind {
                    MarkKind::DirectDifferences => self.direct_difference_marks().len(),
                    _ => self.loaded.marks.of_kind(kind).len(),
                };
                (kind, count, !self.settings.hidden_marks.contains(&kind))
            })
            .collect()
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

    /// The baseline's map view (A) while the split view shows it.
    pub fn split_view(&self) -> Option<&MapViewState> {
        self.is_split().then_some(&self.split_view)
    }

    /// True while the baseline and the current map are shown side by side.
    pub fn is_split(&self) -> bool {
        self.settings.panels.split && self.baseline.is_some()
    }

    /// What the in-app file dialog is open for, and the folder it shows.
    pub fn file_dialog(&self) -> Option<(super::file_dialog::FilePurpose, &std::path::Path)> {
        self.file_dialog
            .as_ref()
            .map(|d| (d.purpose, d.directory()))
    }

    /// The file waiting for a layout in the layout picker, when open.
    pub fn layout_picker(&self) -> Option<&str> {
        self.layout_picker.as_ref().map(|p| p.file_name())
    }

    /// The state of "compare with…".
    pub fn compare(&self) -> &CompareState {
        &self.compare
    }

    /// What each step of the open run did, in counts.
    pub fn step_summaries(&self) -> &[crate::replay::StepSummary] {
        self.loaded.replay.summaries()
    }

    /// `eval`'s verdicts and figures for the snapshot shown (with a floor plan).
    pub fn truth(&self) -> Option<&TruthView> {
        self.truth.as_ref()
    }

    /// The last status message.
    pub fn message(&self) -> &str {
        &self.message
    }

    /// The scene of the current step, as the map view draws it.
    pub fn scene(&self) -> Option<Scene> {
        self.scene_with(self.map_view.world_per_px())
    }

    pub(super) fn scene_with(&self, world_per_px: f64) -> Option<Scene> {
        self.current_scene_for(&self.options_at(world_per_px))
    }

    /// The view options of the layers on at `world_per_px` (no view rectangle).
    fn options_at(&self, world_per_px: f64) -> ViewOptions {
        ViewOptions {
            layers: self.settings.layers(),
            world_per_px,
            visible_m: None,
        }
    }

    /// The scene of the current step under `options`.
    fn current_scene_for(&self, options: &ViewOptions) -> Option<Scene> {
        let truth = self.truth.as_ref().map(|t| t.verdicts.as_slice());
        Some(self.scene_of(
            self.loaded.replay.run(),
            self.view.as_ref()?,
            truth,
            options,
        ))
    }

    /// The baseline's scene at the snapshot shown (A of the split view), drawn as the current
    /// one is: same layers, same selection where it exists; kept between frames as the
    /// current one is ([`SonarApp::frame_scene`]).
    pub(super) fn frame_baseline_scene(&mut self) -> Option<Arc<Scene>> {
        let b = self.baseline.as_ref()?;
        let view = b.view.as_ref()?;
        let subject = SceneSubject {
            source: (b.replay.id(), view.index),
            selection: self.selection,
            layers: self.settings.layers(),
            truth: false,
        };
        let (visible_m, world_per_px) = (self.split_view.visible_m, self.split_view.world_per_px());
        let mut cache = std::mem::take(&mut self.baseline_scene_cache);
        let scene = cache.scene(subject, visible_m, world_per_px, |options| {
            self.scene_of(b.replay.run(), view, None, options)
        });
        self.baseline_scene_cache = cache;
        Some(scene)
    }

    /// The scene of `view` of `run` under `options`, with the selection's supporting readings.
    fn scene_of(
        &self,
        run: &Run,
        view: &StepView,
        truth: Option<&[(crate::mapping::SegmentId, crate::eval::Verdict)]>,
        options: &ViewOptions,
    ) -> Scene {
        // A selected map segment shows where its supporting readings were read.
        let support_of = match self.selection {
            SceneId::MapSegment(id) | SceneId::Update(id) => Some(id),
            _ => None,
        };
        let input = SceneInput::from_view(run, view)
            .with_truth(truth)
            .with_support_of(support_of)
            .with_corrected_path(self.loaded.replay.step_poses());
        build_scene(&input, options)
    }

    /// Scenes the map view has built so far (a frame that reused its scene built none).
    pub fn scene_builds(&self) -> usize {
        self.scene_cache.builds()
    }

    /// The scene the map view draws this frame: the last one while it still serves (same
    /// step, selection, layers, level of detail, and the view inside the region it was built
    /// for), else built for the view, culled to a region around it.
    pub(super) fn frame_scene(&mut self) -> Arc<Scene> {
        let Some(view) = self.view.as_ref() else {
            return Arc::default();
        };
        let subject = SceneSubject {
            source: (self.loaded.replay.id(), view.index),
            selection: self.selection,
            layers: self.settings.layers(),
            truth: self.truth.is_some(),
        };
        let (visible_m, world_per_px) = (self.map_view.visible_m, self.map_view.world_per_px());
        let mut cache = std::mem::take(&mut self.scene_cache);
        let scene = cache.scene(subject, visible_m, world_per_px, |options| {
            self.current_scene_for(options).unwrap_or_default()
        });
        self.scene_cache = cache;
        scene
    }

    pub(super) fn seek(&mut self, k: usize) {
        let k = k.min(self.len().saturating_sub(1));
        if self.view.as_ref().is_some_and(|v| v.index == k) {
            return;
        }
        self.view = self
            .loaded
            .replay
            .view_from(&mut self.cursor, self.view.as_ref(), k);
        self.truth = self
            .view
            .as_ref()
            .and_then(|v| TruthView::of(self.loaded.replay.run(), v, self.loaded.replay.params()));
        if let Some(b) = &mut self.baseline {
            b.seek(k);
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

    /// True when `id` names something of the step shown.
    pub(super) fn exists(&self, id: SceneId) -> bool {
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

    /// End-points of a new segment or a map segment of the current step.
    pub(super) fn ends_of(&self, id: SceneId) -> Option<SegmentEnds> {
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
}
