//! A run through the mapper, with checkpoints so that any snapshot can be shown directly.
//!
//! The state at snapshot `k` is the mapper's state after steps `0..=k`. Building a replay runs
//! the whole log once, keeping a [`crate::mapping::MapperState`] every `interval` snapshots
//! (thinned where steps are cheap when the checkpoints would pass their memory budget, see
//! [`crate::checkpoints`]) and a small summary of every step (for timeline marks);
//! [`Replay::view`] then replays the steps from the nearest checkpoint, and
//! [`Replay::view_from`] steps on from the last view when that is closer.
//!
//! Files: `summary` (what is kept of every step), `record` (keeping it while building),
//! `view` (what a snapshot is drawn from).

//! A run through the mapper, with checkpoints so that any snapshot can be shown directly.
//!
//! The state at snapshot `k` is the mapper's state after steps `0..=k`. Building a replay runs
//! the whole log once, keeping a [`crate::mapping::MapperState`] every `interval` snapshots
//! (thinned where steps are cheap when the checkpoints would pass their memory budget, see
//! [`crate::checkpoints`]) and a small summary of every step (for timeline marks);
//! [`Replay::view`] then replays the steps from the nearest checkpoint, and
//! [`Replay::view_from`] steps on from the last view when that is closer.

mod record;
mod summary;
#[cfg(test)]
mod tests;
mod view;

pub use summary::{StepPose, StepSummary, TruthSample, TRUTH_SAMPLES};
pub use view::StepView;

use crate::checkpoints::{Checkpoints, DEFAULT_CHECKPOINT_BUDGET_BYTES};
use crate::lineage::Lineage;
use crate::mapping::{Map, Mapper, Params, RecordedDecision, StepFailure};
use crate::run::Run;
use record::StepRecords;
use std::sync::Arc;

/// Snapshots between checkpoints unless told otherwise: the shortest spacing (past the memory
/// budget, checkpoints go where seeking costs least, see [`crate::checkpoints`]). Chosen,
/// before that placement, from `sonarmap bench` on a generated 100,000-snapshot building run
/// (2-core machine): every 64 snapshots the slowest seek took 12 ms (paper) / 6 ms (extended)
/// and the checkpoints 326 / 349 MB; every 256, 21 / 43 ms and 168 / 251 MB; every 128, 24 /
/// 18 ms and 221 / 285 MB. Most of a checkpoint is the supporting points of the segments
/// updated since the previous one (the rest is shared).
pub const DEFAULT_CHECKPOINT_INTERVAL: usize = 128;

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
    /// Every step's pose with pose correction on (empty otherwise).
    poses: Vec<StepPose>,
    /// With `calibrate_first`, the parameters of the second pass the drift this replay found
    /// calls for ([`Mapper::second_pass_params`]).
    second_pass: Option<Params>,
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
        let mut records = StepRecords::new(&run, interval);
        let mut failure = None;
        for (k, snapshot) in run.snapshots.iter().enumerate() {
            if checkpoints.due(k) {
                let (state, segments) = mapper.state_apart();
                checkpoints.push_apart(state, segments);
            }
            match mapper.try_step(snapshot) {
                Ok(trace) => {
                    // What catching up through this step will cost, for the checkpoints.
                    checkpoints.note_step(mapper.support_points_updated(&trace));
                    records.record(k, &trace, &mapper, &run, &params);
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
            summaries: records.summaries,
            decisions: records.decisions,
            decisions_from: records.decisions_from,
            final_map: Map::default(),
            failure,
            lineage: Arc::new(records.lineage),
            truth_curve: records.truth_curve,
            poses: records.poses,
            second_pass: None,
        };
        replay.final_map = if replay.failure.is_some() {
            // The failed step may have left the mapper half-way: replay up to the last good one.
            match replay.summaries.len() {
                0 => Map::default(),
                good => replay.map_at(good - 1),
            }
        } else {
            replay.second_pass = mapper.second_pass_params();
            mapper.map().clone()
        };
        Ok(replay)
    }

    /// With `calibrate_first`, the parameters of a second pass, when this one found a drift
    /// ([`Mapper::second_pass_params`]): the app replays the run with them.
    pub fn second_pass(&self) -> Option<&Params> {
        self.second_pass.as_ref()
    }

    /// The map's spurious fraction and coverage every shortest checkpoint spacing, or at most
    /// [`TRUTH_SAMPLES`] times, and at the last step (with a floor plan; empty without).
    pub fn truth_curve(&self) -> &[TruthSample] {
        &self.truth_curve
    }

    /// Every step's pose and correction when pose correction is on, one per step; empty
    /// otherwise.
    pub fn step_poses(&self) -> &[StepPose] {
        &self.poses
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

    /// Takes the checkpoints out, leaving none (the replay can then show only what needs no
    /// checkpoint): `bench` drops them to count the heap they alone keep alive.
    pub(crate) fn take_checkpoints(&mut self) -> Checkpoints {
        let empty = Checkpoints::new(
            self.checkpoints.min_interval(),
            self.checkpoints.budget_bytes(),
        );
        std::mem::replace(&mut self.checkpoints, empty)
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
