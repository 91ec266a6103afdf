//! The replay's checkpoints within a memory budget, placed so that catching up from any of
//! them costs about the same.
//!
//! A checkpoint is a [`MapperState`]: its map shares every segment and face that did not change
//! since the previous checkpoint, so what it alone keeps alive is its lists of segments and
//! faces (a pointer each) and the versions of what changed (of a segment's supporting points,
//! the chunks that changed). That grows with the map: a `paper` map of a long lap run holds
//! hundreds of thousands of segments. So a checkpoint keeps its list of segments in runs of
//! consecutive ids ([`SegmentRuns`]), each shared with the checkpoint before while none of its
//! segments changed. The store counts those bytes as checkpoints are taken.
//!
//! A seek restores the checkpoint before its snapshot and steps on from there, so the slowest
//! seek is the interval whose steps cost most. In a run whose map grows, a late step costs
//! many times an early one (`paper` on a lap run: ten times and more). So checkpoints are taken
//! every `min_interval` snapshots, each interval's cost is estimated as the replay runs it
//! (from what its steps update, by a model measured on seeks), and when the checkpoints pass
//! their budget the one whose removal makes the cheapest merged seek goes, one at a time:
//! early intervals grow long and late ones stay short, each seek costing about the same,
//! within the budget.
//!
//! Files: `kept` (a checkpoint: its segments in shared runs, and what it keeps alive).

mod kept;
#[cfg(test)]
mod tests;

pub use kept::SegmentRuns;

use crate::mapping::model::map::Segment;
use crate::mapping::MapperState;
use kept::{kept_alive_bytes, Kept};
use std::sync::Arc;

/// The checkpoints' memory budget unless told otherwise, bytes.
pub const DEFAULT_CHECKPOINT_BUDGET_BYTES: usize = 512 << 20;

/// The cost of catching up through one step, besides its updates. Costs are in units of the
/// time a catch-up takes for one supporting point of a segment a step updated (its merge
/// reads the segment's whole list). Fitted to 20 seeks on
/// the building asset's lap repeated to 100,000 snapshots in `paper` (docs/performance.md,
/// stop 31): a catch-up took 5.8 µs a step plus 24.5 ns a point (8.5 µs a step early in the
/// run, 79 µs late, where lists hold thousands), and a restore 150–200 ns a segment of the
/// checkpoint's map (25 ms for 161,000: reading them, copying their list, filing them).
const STEP_COST: f64 = 240.0;
/// A restore's cost for each segment of the map restored, in the same units.
const RESTORE_COST_PER_SEGMENT: f64 = 6.0;

/// Mapper states at multiples of `min_interval` snapshots, thinned to stay within a byte
/// budget where seeking costs least, so that seeks cost about the same everywhere.
#[derive(Clone, Debug)]
pub struct Checkpoints {
    min_interval: usize,
    budget_bytes: usize,
    states: Vec<Kept>,
    /// What each state keeps alive beyond the one before it, bytes.
    bytes: Vec<usize>,
    /// The cost of restoring each state.
    restore_costs: Vec<f64>,
    /// The cost of the steps from each state to the next (the last: to the latest step
    /// noted).
    costs: Vec<f64>,
}

impl Checkpoints {
    /// An empty store taking a state at most every `min_interval` snapshots (at least 1)
    /// within `budget_bytes`.
    pub fn new(min_interval: usize, budget_bytes: usize) -> Self {
        Self {
            min_interval: min_interval.max(1),
            budget_bytes,
            states: Vec::new(),
            bytes: Vec::new(),
            restore_costs: Vec::new(),
            costs: Vec::new(),
        }
    }

    /// The shortest spacing: states are taken at multiples of it.
    pub fn min_interval(&self) -> usize {
        self.min_interval
    }

    /// The shortest and the longest spacing between two kept states, snapshots (the snapshots
    /// after the last state, fewer than the shortest spacing, left out); with one state, from
    /// it to `len` (the snapshots run so far); (0, 0) with none.
    pub fn spacing_range(&self, len: usize) -> (usize, usize) {
        let starts: Vec<usize> = self.states.iter().map(Kept::next_snapshot).collect();
        match starts.as_slice() {
            [] => (0, 0),
            [only] => (len - only.min(&len), len - only.min(&len)),
            _ => starts
                .windows(2)
                .map(|w| w[1] - w[0])
                .fold((usize::MAX, 0), |(lo, hi), d| (lo.min(d), hi.max(d))),
        }
    }

    /// The estimated bytes the checkpoints keep alive.
    pub fn bytes(&self) -> usize {
        self.bytes.iter().sum()
    }

    /// The budget, bytes.
    pub fn budget_bytes(&self) -> usize {
        self.budget_bytes
    }

    /// Checkpoints held.
    pub fn len(&self) -> usize {
        self.states.len()
    }

    /// True before the first checkpoint.
    pub fn is_empty(&self) -> bool {
        self.states.is_empty()
    }

    /// Whether the state before snapshot `k` is to be kept: `k` is a multiple of the shortest
    /// spacing past the last state kept (the first at 0).
    pub fn due(&self, k: usize) -> bool {
        k.is_multiple_of(self.min_interval) && (self.states.is_empty() || k > self.last_start())
    }

    /// Notes the step after the latest state (or the last step noted): its segments updated
    /// held `points_updated` supporting points once it ran. A catch-up through it will take
    /// about `STEP_COST` plus that.
    pub fn note_step(&mut self, points_updated: usize) {
        if let Some(last) = self.costs.last_mut() {
            *last += STEP_COST + points_updated as f64;
        }
    }

    /// Keeps `state` (the state before a snapshot [`Checkpoints::due`] named), then, while the
    /// store is over budget and holds more than two states, drops the state whose interval
    /// joined to the one before makes the cheapest seek (the restore of that one's state and
    /// the catch-up through both intervals), never the first. `state` itself, whose interval
    /// has no steps yet, goes at once while the last interval costs less than any two joined:
    /// the last interval then grows until it costs as much as they do (on the 100,000-snapshot
    /// lap run, worst seek 76–82 ms in five runs of six, 107 ms in the other; never dropping
    /// the newest state, 95 ms in one run). Two states stay whatever the budget.
    pub fn push(&mut self, mut state: MapperState) {
        let segments = std::mem::take(&mut state.map.segments);
        self.push_apart(state, &segments);
    }

    /// [`Checkpoints::push`] for a state whose map's segments are given apart (`segments`,
    /// ordered by id; its own list is ignored): a live mapper's, without copying its list of
    /// segments first ([`crate::mapping::Mapper::state_apart`]).
    pub fn push_apart(&mut self, state: MapperState, segments: &[Arc<Segment>]) {
        let kept = Kept::new(state, segments, self.states.last());
        self.bytes.push(kept_alive_bytes(self.states.last(), &kept));
        self.restore_costs
            .push(RESTORE_COST_PER_SEGMENT * kept.segments.len() as f64);
        self.states.push(kept);
        self.costs.push(0.0);
        while self.bytes() > self.budget_bytes && self.states.len() > 2 {
            let merged = |i: usize| self.restore_costs[i - 1] + self.costs[i - 1] + self.costs[i];
            let cheapest = (1..self.states.len())
                .min_by(|&i, &j| merged(i).total_cmp(&merged(j)).then(i.cmp(&j)))
                .expect("more than two states");
            self.drop_state(cheapest);
        }
    }

    /// The estimated cost of the slowest seek (of the last snapshot of an interval): the
    /// restore of its state and the catch-up through it, in the units of `STEP_COST`.
    pub fn slowest_seek_cost(&self) -> f64 {
        let seeks = self.restore_costs.iter().zip(&self.costs);
        seeks.map(|(r, c)| r + c).fold(0.0, f64::max)
    }

    /// The catch-up cost of each interval, in order (the last: up to the latest step noted).
    pub fn interval_costs(&self) -> &[f64] {
        &self.costs
    }

    /// The latest state at or before snapshot `k`, its map made live (its segments listed and
    /// filed in its spatial index), ready for [`crate::mapping::Mapper::resume`].
    pub fn live_before(&self, k: usize) -> Option<MapperState> {
        self.states.get(self.index_before(k)).map(Kept::live)
    }

    /// Snapshot of the latest state at or before snapshot `k` (0 while there is none).
    pub fn snapshot_before(&self, k: usize) -> usize {
        self.states
            .get(self.index_before(k))
            .map_or(0, Kept::next_snapshot)
    }

    /// Snapshot of the first state after snapshot `k`, when there is one.
    pub fn snapshot_after(&self, k: usize) -> Option<usize> {
        self.states
            .get(self.index_before(k) + 1)
            .map(Kept::next_snapshot)
    }

    fn last_start(&self) -> usize {
        self.states.last().map_or(0, Kept::next_snapshot)
    }

    /// Index of the latest state at or before snapshot `k` (0 while there is none).
    fn index_before(&self, k: usize) -> usize {
        self.states
            .partition_point(|s| s.next_snapshot() <= k)
            .saturating_sub(1)
    }

    /// Drops state `i` (not the first): its interval joins the one before, and the state after
    /// it now keeps alive what it shared with it alone.
    fn drop_state(&mut self, i: usize) {
        self.states.remove(i);
        self.bytes.remove(i);
        self.restore_costs.remove(i);
        let cost = self.costs.remove(i);
        self.costs[i - 1] += cost;
        if i < self.states.len() {
            self.bytes[i] = kept_alive_bytes(Some(&self.states[i - 1]), &self.states[i]);
        }
    }
}
