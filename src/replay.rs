//! A run through the mapper, with checkpoints so that any snapshot can be shown directly.
//!
//! The state at snapshot `k` is the mapper's state after steps `0..=k`. Building a replay runs
//! the whole log once, keeping a [`crate::mapping::MapperState`] every `interval` snapshots
//! (thinned where steps are cheap when the checkpoints would pass their memory budget, see
//! [`crate::checkpoints`]) and a small summary of every step (for timeline marks);
//! [`Replay::view`] then replays the steps from the nearest checkpoint, and
//! [`Replay::view_from`] steps on from the last view when that is closer.

use crate::checkpoints::{Checkpoints, DEFAULT_CHECKPOINT_BUDGET_BYTES};
use crate::eval::{map_verdicts, segment_verdict, truth_figures};
use crate::lineage::Lineage;
use crate::mapping::model::trace::{Outcome, StepTrace};
use crate::mapping::{Map, Mapper, Params, RecordedDecision, StepFailure};
use crate::run::{FloorPlan, Run, Snapshot};
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// Snapshots between checkpoints unless told otherwise: the shortest spacing (past the memory
/// budget, checkpoints go where seeking costs least, see [`crate::checkpoints`]). Chosen,
/// before that placement, from `sonarmap bench` on a generated 100,000-snapshot building run
/// (2-core machine): every 64 snapshots the slowest seek took 12 ms (paper) / 6 ms (extended)
/// and the checkpoints 326 / 349 MB; every 256, 21 / 43 ms and 168 / 251 MB; every 128, 24 /
/// 18 ms and 221 / 285 MB. Most of a checkpoint is the supporting points of the segments
/// updated since the previous one (the rest is shared).
pub const DEFAULT_CHECKPOINT_INTERVAL: usize = 128;

/// Counts of what one step did (the timeline's marks and the command line's summary).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct StepSummary {
    /// Readings kept.
    pub kept: u32,
    /// Readings discarded.
    pub discarded: u32,
    /// New segments that matched.
    pub matches: u32,
    /// New segments that extended a segment.
    pub extensions: u32,
    /// New segments dismissed.
    pub dismissals: u32,
    /// New segments kept as new faces.
    pub new_faces: u32,
    /// Correlations that made a corner or a link.
    pub correlations: u32,
    /// Warnings (max_step and others).
    pub warnings: u32,
    /// Map segments after the step.
    pub segments: u32,
    /// New faces whose segment `eval` calls spurious right after the step (with a floor plan).
    #[serde(default)]
    pub spurious_new_faces: u32,
    /// Map segments offered as candidates to the step's new segments, summed: the step's
    /// matching work.
    #[serde(default)]
    pub candidates: u32,
}

impl StepSummary {
    /// Summarises a step's trace; `segments` is the map's size after it.
    pub fn of(trace: &StepTrace, segments: usize) -> Self {
        let count = |o: Outcome| trace.decisions.iter().filter(|d| d.outcome == o).count() as u32;
        let discarded = trace
            .readings
            .iter()
            .filter(|r| r.discarded.is_some())
            .count() as u32;
        Self {
            kept: trace.readings.len() as u32 - discarded,
            discarded,
            matches: count(Outcome::Match),
            extensions: count(Outcome::Extension),
            dismissals: count(Outcome::Dismissed),
            new_faces: count(Outcome::NewFace),
            correlations: trace
                .correlations
                .iter()
                .filter(|c| {
                    !matches!(
                        c.result,
                        crate::mapping::model::trace::CorrelationKind::None
                    )
                })
                .count() as u32,
            warnings: trace.warnings.len() as u32,
            segments: segments as u32,
            spurious_new_faces: 0,
            candidates: 0,
        }
    }

    /// Counts the step's new faces that lie on no wall of `plan` in `map` (the map after the
    /// step), by `eval`'s verdict.
    pub fn count_spurious_new_faces(
        &mut self,
        trace: &StepTrace,
        map: &Map,
        plan: &FloorPlan,
        params: &Params,
    ) {
        self.spurious_new_faces = trace
            .decisions
            .iter()
            .filter(|d| d.outcome == Outcome::NewFace)
            .filter_map(|d| d.result.and_then(|id| map.segment(id)))
            .filter(|s| !segment_verdict(s, plan, params).is_true())
            .count() as u32;
    }

    /// True when the step deserves a timeline mark: a dismissal, an extension, a warning or a
    /// correlation.
    pub fn is_notable(&self) -> bool {
        self.dismissals > 0 || self.extensions > 0 || self.warnings > 0 || self.correlations > 0
    }
}

/// Everything needed to draw snapshot `k`.
#[derive(Clone, Debug)]
pub struct StepView {
    /// The snapshot index.
    pub index: usize,
    /// The trace of step `k`.
    pub trace: StepTrace,
    /// The trace of step `k - 1` (its points are drawn as the previous snapshot's).
    pub previous: Option<StepTrace>,
    /// The map before step `k` (without its spatial index: [`Map::rebuild_index`] restores it).
    pub map_before: Map,
    /// The map after step `k` (without its spatial index).
    pub map_after: Map,
}

impl StepView {
    /// The view of snapshot `k`, stepping `mapper` (positioned just before snapshot `k - 1`, or
    /// before snapshot 0 when `k` is 0) through its last one or two snapshots with the full
    /// trace. The mapper is left after snapshot `k`, tracing as it was before.
    pub fn by_stepping(mapper: &mut Mapper, snapshots: &[Snapshot], k: usize) -> Self {
        assert_eq!(
            mapper.next_snapshot(),
            k.saturating_sub(1),
            "the mapper stands before snapshot k - 1"
        );
        let was_tracing = mapper.records_trace();
        mapper.set_trace(true);
        let previous = (k > 0).then(|| mapper.step(&snapshots[k - 1]));
        // Copies share the segments; the index is left out (drawing does not search).
        let map_before = mapper.map().without_index();
        let trace = mapper.step(&snapshots[k]);
        mapper.set_trace(was_tracing);
        Self {
            index: k,
            trace,
            previous,
            map_before,
            map_after: mapper.map().without_index(),
        }
    }
}

impl StepView {
    /// The view of the snapshot after `shown`'s, stepping `mapper` (standing just after
    /// `shown`'s snapshot) once with the full trace: `shown` already holds the previous step's
    /// trace and the map before. The mapper is left after the new snapshot.
    fn after(mapper: &mut Mapper, shown: &StepView, snapshots: &[Snapshot]) -> Self {
        let k = shown.index + 1;
        assert_eq!(
            mapper.next_snapshot(),
            k,
            "the mapper stands after the shown snapshot"
        );
        let was_tracing = mapper.records_trace();
        mapper.set_trace(true);
        let trace = mapper.step(&snapshots[k]);
        mapper.set_trace(was_tracing);
        Self {
            index: k,
            trace,
            previous: Some(shown.trace.clone()),
            map_before: shown.map_after.clone(),
            map_after: mapper.map().without_index(),
        }
    }
}

/// Where the last view of a replay left its mapper, so that a view further on starts from
/// there instead of from a checkpoint: stepping forward (playing, the arrow keys) costs one
/// step, whatever the map's size, instead of a checkpoint's restore and catch-up.
#[derive(Clone, Debug, Default)]
pub struct ReplayCursor {
    /// The replay the mapper belongs to ([`Replay`]'s identity) and the mapper, standing just
    /// after the last snapshot viewed.
    at: Option<(u64, Mapper)>,
}

/// Identities of replays, so that a cursor never serves another replay.
static NEXT_REPLAY_ID: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(1);

/// A run replayed under one parameter set.
#[derive(Clone, Debug)]
pub struct Replay {
    /// This replay's identity (for [`ReplayCursor`]).
    id: u64,
    run: Arc<Run>,
    params: Params,
    checkpoints: Checkpoints,
    summaries: Vec<StepSummary>,
    /// Every step's decisions, one step after another (step `k`'s from `decisions_from[k]` up
    /// to the next step's start), so that catching up from a checkpoint takes them again
    /// instead of testing candidates.
    decisions: Vec<RecordedDecision>,
    decisions_from: Vec<u32>,
    final_map: Map,
    failure: Option<StepFailure>,
    lineage: Arc<Lineage>,
    truth_curve: Vec<TruthSample>,
}

/// Most samples of the truth curve in a replay: a `paper` map of a long run holds hundreds of
/// thousands of segments, each tested against every wall.
pub const TRUTH_SAMPLES: usize = 32;

/// The map's figures against the floor plan after one step (`eval`'s spurious fraction and
/// coverage), sampled every shortest checkpoint spacing or less often (see
/// [`Replay::truth_curve`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TruthSample {
    /// The step.
    pub snapshot: usize,
    /// 1 − true / fitted segments.
    pub spurious_fraction: f64,
    /// Covered wall length over total wall length.
    pub coverage: f64,
}

/// The build was cancelled by its progress callback.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Cancelled;

impl Replay {
    /// Replays `run` under `params` with the default checkpoint interval.
    pub fn new(run: Arc<Run>, params: Params) -> Self {
        Self::build(run, params, DEFAULT_CHECKPOINT_INTERVAL, &mut |_| true)
            .expect("never cancelled")
    }

    /// Replays `run`, calling `progress(done)` after every step; returning `false` cancels.
    /// Checkpoints start `interval` snapshots apart and stay within the default budget
    /// ([`DEFAULT_CHECKPOINT_BUDGET_BYTES`]).
    pub fn build(
        run: Arc<Run>,
        params: Params,
        interval: usize,
        progress: &mut dyn FnMut(usize) -> bool,
    ) -> Result<Self, Cancelled> {
        Self::build_within(
            run,
            params,
            Checkpoints::new(interval, DEFAULT_CHECKPOINT_BUDGET_BYTES),
            progress,
        )
    }

    /// [`Replay::build`] keeping its checkpoints in `checkpoints` (empty: its spacing and
    /// budget).
    pub fn build_within(
        run: Arc<Run>,
        params: Params,
        mut checkpoints: Checkpoints,
        progress: &mut dyn FnMut(usize) -> bool,
    ) -> Result<Self, Cancelled> {
        let interval = checkpoints.min_interval();
        // The summaries need only what the slim trace keeps.
        let mut mapper =
            Mapper::new(params.clone(), run.layout.clone(), run.sensor).with_trace(false);
        let mut summaries = Vec::with_capacity(run.snapshots.len());
        let (mut decisions, mut decisions_from) = (Vec::new(), vec![0u32]);
        let mut failure = None;
        let mut lineage = Lineage::default();
        let mut truth_curve = Vec::new();
        let truth_every = interval.max(run.snapshots.len().div_ceil(TRUTH_SAMPLES));
        for (k, snapshot) in run.snapshots.iter().enumerate() {
            if checkpoints.due(k) {
                let (state, segments) = mapper.state_apart();
                checkpoints.push_apart(state, segments);
            }
            match mapper.try_step(snapshot) {
                Ok(trace) => {
                    // What catching up through this step will cost, for the checkpoints.
                    let updated = trace
                        .updates
                        .iter()
                        .filter_map(|u| mapper.map().segment(u.segment));
                    checkpoints.note_step(updated.map(|s| s.points.len()).sum());
                    let mut summary = StepSummary::of(&trace, mapper.map().segments.len());
                    summary.candidates = mapper.last_step_candidates() as u32;
                    if let Some(plan) = &run.floor_plan {
                        summary.count_spurious_new_faces(&trace, mapper.map(), plan, &params);
                        // The whole map against the plan costs a pass over it (times the
                        // walls): once a checkpoint interval, at most TRUTH_SAMPLES times, and
                        // at the last step.
                        if (k + 1) % truth_every == 0 || k + 1 == run.snapshots.len() {
                            let map = mapper.map();
                            let verdicts = map_verdicts(map, plan, &params);
                            let (spurious_fraction, coverage) = truth_figures(map, plan, &verdicts);
                            truth_curve.push(TruthSample {
                                snapshot: k,
                                spurious_fraction,
                                coverage,
                            });
                        }
                    }
                    summaries.push(summary);
                    let recorded = trace.decisions.iter();
                    decisions.extend(recorded.map(|d| RecordedDecision::of(d, &trace.updates)));
                    decisions_from.push(u32::try_from(decisions.len()).unwrap_or(u32::MAX));
                    lineage.record(&trace);
                }
                Err(f) => {
                    failure = Some(f);
                    break;
                }
            }
            if !progress(k + 1) {
                return Err(Cancelled);
            }
        }
        let mut replay = Self {
            id: NEXT_REPLAY_ID.fetch_add(1, std::sync::atomic::Ordering::Relaxed),
            run,
            params,
            checkpoints,
            summaries,
            decisions,
            decisions_from,
            final_map: Map::default(),
            failure,
            lineage: Arc::new(lineage),
            truth_curve,
        };
        replay.final_map = if replay.failure.is_some() {
            // The failed step may have left the mapper half-way: replay up to the last good one.
            match replay.summaries.len() {
                0 => Map::default(),
                good => replay.map_at(good - 1),
            }
        } else {
            mapper.map().clone()
        };
        Ok(replay)
    }

    /// The map's spurious fraction and coverage every shortest checkpoint spacing, or at most
    /// [`TRUTH_SAMPLES`] times, and at the last step (with a floor plan; empty without).
    pub fn truth_curve(&self) -> &[TruthSample] {
        &self.truth_curve
    }

    /// Every map segment's life, as the replay recorded it.
    pub fn lineage(&self) -> &Lineage {
        &self.lineage
    }

    /// The step that failed, when one did: the replay then ends at the snapshot before it.
    pub fn failure(&self) -> Option<&StepFailure> {
        self.failure.as_ref()
    }

    /// The run.
    pub fn run(&self) -> &Arc<Run> {
        &self.run
    }

    /// The parameters.
    pub fn params(&self) -> &Params {
        &self.params
    }

    /// Number of snapshots.
    pub fn len(&self) -> usize {
        self.summaries.len()
    }

    /// True when the run has no snapshot.
    pub fn is_empty(&self) -> bool {
        self.summaries.is_empty()
    }

    /// Per-step summaries, in order.
    pub fn summaries(&self) -> &[StepSummary] {
        &self.summaries
    }

    /// The map after the last snapshot.
    pub fn final_map(&self) -> &Map {
        &self.final_map
    }

    /// This replay's identity: distinct for every replay built in the process.
    pub fn id(&self) -> u64 {
        self.id
    }

    /// The checkpoints held, and the shortest and longest spacing between them, snapshots.
    pub fn checkpoint_spacing(&self) -> (usize, usize, usize) {
        let (shortest, longest) = self.checkpoints.spacing_range(self.len());
        (self.checkpoints.len(), shortest, longest)
    }

    /// The snapshot whose view catches up longest from the checkpoint the view of `k` starts
    /// from: the next checkpoint's own (the view of a snapshot `j` restores the checkpoint at
    /// or before `j − 1` and steps on to `j`), or the run's last when none follows.
    pub fn slowest_view_like(&self, k: usize) -> usize {
        let last = self.len().saturating_sub(1);
        let next = self.checkpoints.snapshot_after(k.saturating_sub(1));
        next.unwrap_or(last).min(last)
    }

    /// The checkpoints' estimated bytes and their budget.
    pub fn checkpoint_bytes(&self) -> (usize, usize) {
        (self.checkpoints.bytes(), self.checkpoints.budget_bytes())
    }

    /// Steps `mapper` untraced until it stands before snapshot `k`, each step taking the
    /// decisions the build recorded for it.
    fn catch_up(&self, mapper: &mut Mapper, k: usize) {
        // Catching up needs no trace: only the steps drawn are traced in full.
        mapper.set_trace(false);
        while mapper.next_snapshot() < k {
            let i = mapper.next_snapshot();
            let recorded = match (self.decisions_from.get(i), self.decisions_from.get(i + 1)) {
                (Some(&a), Some(&b)) => self.decisions.get(a as usize..b as usize),
                _ => None,
            };
            match recorded {
                Some(decisions) => mapper.step_as_recorded(&self.run.snapshots[i], decisions),
                None => mapper.step(&self.run.snapshots[i]),
            };
        }
    }

    /// A mapper positioned just before snapshot `k` (from the nearest checkpoint).
    fn mapper_before(&self, k: usize) -> Mapper {
        let mut mapper = Mapper::new(
            self.params.clone(),
            self.run.layout.clone(),
            self.run.sensor,
        );
        if let Some(state) = self.checkpoints.live_before(k) {
            mapper.resume(state);
        }
        self.catch_up(&mut mapper, k);
        mapper
    }

    /// The state at snapshot `k` (clamped to the run), with the previous step's trace.
    pub fn view(&self, k: usize) -> Option<StepView> {
        if self.is_empty() {
            return None;
        }
        let k = k.min(self.len() - 1);
        let mut mapper = self.mapper_before(k.saturating_sub(1));
        Some(StepView::by_stepping(&mut mapper, &self.run.snapshots, k))
    }

    /// [`Replay::view`], starting from where `cursor` left the mapper when that is closer than
    /// any checkpoint: `shown`, the view on screen, makes the next snapshot one traced step.
    /// The result is the same as [`Replay::view`]'s.
    pub fn view_from(
        &self,
        cursor: &mut ReplayCursor,
        shown: Option<&StepView>,
        k: usize,
    ) -> Option<StepView> {
        if self.is_empty() {
            return None;
        }
        let k = k.min(self.len() - 1);
        let mapper = match cursor.at.take() {
            Some((id, m)) if id == self.id => Some(m),
            _ => None,
        };
        if let (Some(m), Some(v)) = (&mapper, shown) {
            if v.index + 1 == k && m.next_snapshot() == k {
                let mut m = mapper.expect("matched");
                let view = StepView::after(&mut m, v, &self.run.snapshots);
                cursor.at = Some((self.id, m));
                return Some(view);
            }
        }
        let mut m = match mapper {
            Some(mut m) if self.cursor_is_closer(m.next_snapshot(), k) => {
                self.catch_up(&mut m, k.saturating_sub(1));
                m
            }
            other => {
                if let Some(far) = other {
                    drop_in_background(far);
                }
                self.mapper_before(k.saturating_sub(1))
            }
        };
        let view = StepView::by_stepping(&mut m, &self.run.snapshots, k);
        cursor.at = Some((self.id, m));
        Some(view)
    }

    /// Whether a mapper standing before snapshot `next` reaches the place before view `k`'s
    /// steps in fewer steps than the nearest checkpoint does.
    fn cursor_is_closer(&self, next: usize, k: usize) -> bool {
        let target = k.saturating_sub(1);
        let from_checkpoint = target - self.checkpoints.snapshot_before(target).min(target);
        next <= target && target - next <= from_checkpoint
    }

    /// The map after snapshot `k` (without its spatial index).
    pub fn map_at(&self, k: usize) -> Map {
        let mut mapper = self.mapper_before(k.min(self.len()));
        if k < self.len() {
            mapper.step(&self.run.snapshots[k]);
        }
        mapper.map().without_index()
    }
}

/// Drops `value` on a thread kept for that: a mapper of a long `paper` run holds hundreds of
/// thousands of shared segments, and letting go of each took a few milliseconds of a seek. One
/// thread takes them in turn (a dragged slider seeks far many times a second); without it, the
/// value is dropped here.
fn drop_in_background<T: Send + 'static>(value: T) {
    type Garbage = Box<dyn Send>;
    static DROPPER: std::sync::OnceLock<Option<std::sync::mpsc::Sender<Garbage>>> =
        std::sync::OnceLock::new();
    let dropper = DROPPER.get_or_init(|| {
        let (send, receive) = std::sync::mpsc::channel::<Garbage>();
        let thread = std::thread::Builder::new()
            .name("sonarmap-drop".into())
            .spawn(move || receive.into_iter().for_each(drop));
        thread.ok().map(|_| send)
    });
    let garbage: Garbage = Box::new(value);
    if let Some(Err(failed)) = dropper.as_ref().map(|d| d.send(garbage)) {
        drop(failed.0);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Pose;
    use crate::sonar::{SensorLayout, SensorSpec};
    use crate::units::{inches, Units};

    fn wall_run(n: usize) -> Run {
        // A wall at y = 40 in seen by the three sonars facing it while the robot drives.
        let layout = SensorLayout::nomad_ring(inches(9.0));
        let snapshots = (0..n)
            .map(|i| {
                let mut ranges_m = vec![None; 16];
                ranges_m[3] = Some(inches(31.0) / 67.5f64.to_radians().sin());
                ranges_m[4] = Some(inches(31.0));
                ranges_m[5] = Some(inches(31.0) / 112.5f64.to_radians().sin());
                Snapshot {
                    t: i as f64,
                    pose: Pose::new(inches(3.0 * i as f64), 0.0, 0.0),
                    ranges_m,
                }
            })
            .collect();
        Run {
            name: "wall".into(),
            units: Units::Inches,
            robot_radius_m: Some(inches(9.0)),
            layout,
            sensor: SensorSpec::default(),
            floor_plan: None,
            snapshots,
        }
    }

    #[test]
    fn over_budget_checkpoints_thin_where_seeking_is_cheap_and_every_view_is_the_same() {
        // Half the bytes the states every 3 snapshots keep: the store drops states as the run
        // goes on.
        let run = Arc::new(wall_run(60));
        let full = Replay::build(run.clone(), Params::paper(), 3, &mut |_| true).unwrap();
        let budget = full.checkpoint_bytes().0 / 2;
        let checkpoints = Checkpoints::new(3, budget);
        let thin =
            Replay::build_within(run.clone(), Params::paper(), checkpoints, &mut |_| true).unwrap();
        let (held, shortest, longest) = thin.checkpoint_spacing();
        assert!(held < full.checkpoint_spacing().0, "states were dropped");
        assert!(thin.checkpoint_bytes().0 <= budget);
        assert!(
            held > 2 && shortest >= 3 && longest >= shortest,
            "{shortest}..{longest}"
        );
        for k in 0..run.snapshots.len() {
            let (a, b) = (full.view(k).unwrap(), thin.view(k).unwrap());
            assert_eq!(a.trace, b.trace, "trace {k}");
            assert_eq!(a.map_after, b.map_after, "map {k}");
            // The slowest view from the checkpoint k's view starts from: at or after k, and
            // starting from that very checkpoint (a view of j restores the one before j − 1).
            let slowest = thin.slowest_view_like(k);
            assert!(slowest >= k && slowest < run.snapshots.len());
            let from = |j: usize| thin.checkpoints.snapshot_before(j.saturating_sub(1));
            assert_eq!(from(slowest), from(k), "{k} -> {slowest}");
            if slowest + 1 < run.snapshots.len() {
                assert_ne!(from(slowest + 1), from(k), "{slowest} is the last from it");
            }
        }
    }

    #[test]
    fn view_from_a_checkpoint_equals_a_replay_from_zero() {
        let run = Arc::new(wall_run(40));
        let replay = Replay::build(run.clone(), Params::paper(), 7, &mut |_| true).unwrap();
        let mut mapper = Mapper::new(Params::paper(), run.layout.clone(), run.sensor);
        let mut previous = None;
        for k in 0..run.snapshots.len() {
            let before = mapper.map().clone();
            let trace = mapper.step(&run.snapshots[k]);
            let view = replay.view(k).unwrap();
            assert_eq!(view.trace, trace, "trace {k}");
            assert_eq!(view.map_before, before, "map before {k}");
            assert_eq!(&view.map_after, mapper.map(), "map after {k}");
            assert_eq!(view.previous, previous, "previous {k}");
            // The build steps with the slim trace; its summaries are the full trace's.
            let segments = mapper.map().segments.len();
            let mut summary = StepSummary::of(&trace, segments);
            summary.candidates = mapper.last_step_candidates() as u32;
            assert_eq!(replay.summaries()[k], summary, "summary {k}");
            previous = Some(trace);
        }
        assert_eq!(replay.final_map(), mapper.map());
        assert_eq!(replay.map_at(39), *mapper.map());
    }

    #[test]
    fn views_through_a_cursor_equal_views_from_checkpoints_in_any_order() {
        let run = Arc::new(wall_run(60));
        let replay = Replay::build(run.clone(), Params::extended(), 16, &mut |_| true).unwrap();
        let other = Replay::build(run, Params::paper(), 16, &mut |_| true).unwrap();
        let mut cursor = ReplayCursor::default();
        let mut shown: Option<StepView> = None;
        // Forward by one (one traced step), forward within and beyond a checkpoint interval,
        // backwards, the same snapshot again, the ends.
        let order = [
            0, 1, 2, 3, 9, 10, 30, 29, 5, 5, 6, 59, 58, 0, 40, 41, 42, 57,
        ];
        for (i, &k) in order.iter().enumerate() {
            if i == 12 {
                // A view of another replay through the same cursor does not leak into this one.
                other.view_from(&mut cursor, None, 20);
            }
            let got = replay.view_from(&mut cursor, shown.as_ref(), k).unwrap();
            let want = replay.view(k).unwrap();
            assert_eq!(got.index, k);
            assert_eq!(got.trace, want.trace, "trace {k}");
            assert_eq!(got.previous, want.previous, "previous {k}");
            assert_eq!(got.map_before, want.map_before, "map before {k}");
            assert_eq!(got.map_after, want.map_after, "map after {k}");
            shown = Some(got);
        }
    }

    #[test]
    fn views_caught_up_with_recorded_refits_equal_a_run_from_zero() {
        // The building asset's lap, driven back and forth: the paper's updates fail their
        // post-update test and refit often, and catching up takes those outcomes as recorded.
        let lap = crate::log::load_run(
            include_str!("../assets/building.log.json").as_bytes(),
            "building.log.json",
        )
        .unwrap();
        let run = Arc::new(crate::bench::back_and_forth(&lap, 2 * lap.snapshots.len()));
        for params in [Params::paper(), Params::extended()] {
            let replay = Replay::build(run.clone(), params.clone(), 8, &mut |_| true).unwrap();
            let mut mapper = Mapper::new(params, run.layout.clone(), run.sensor);
            let mut refits = 0;
            for (k, s) in run.snapshots.iter().enumerate() {
                let trace = mapper.step(s);
                refits += trace.updates.iter().filter(|u| u.refit.is_some()).count();
                if k % 3 == 2 {
                    assert_eq!(replay.view(k).unwrap().map_after, *mapper.map(), "{k}");
                }
            }
            assert!(refits > 0, "the run refits");
        }
    }

    #[test]
    fn a_value_dropped_in_the_background_is_dropped_soon() {
        let held = Arc::new(());
        for _ in 0..3 {
            drop_in_background(Arc::clone(&held));
        }
        let start = std::time::Instant::now();
        while Arc::strong_count(&held) > 1 {
            assert!(start.elapsed().as_secs() < 10, "still held after 10 s");
            std::thread::sleep(std::time::Duration::from_millis(1));
        }
    }

    #[test]
    fn build_can_be_cancelled() {
        let run = Arc::new(wall_run(10));
        let r = Replay::build(run, Params::paper(), 4, &mut |done| done < 5);
        assert_eq!(r.err(), Some(Cancelled));
    }
}
