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

use crate::geometry::Pose;
use crate::mapping::model::beam::Beam;
use crate::mapping::model::features::PointFeature;
use crate::mapping::model::map::{Face, MemoryPoint, Segment, SupportPoint};
use crate::mapping::model::plane_supports::PlaneSupport;
use crate::mapping::model::support_list::SupportList;
use crate::mapping::MapperState;
use crate::mapping::SegmentId;
use rustc_hash::FxHashSet;
use std::mem::size_of;
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
    /// about [`STEP_COST`] plus that.
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
    /// restore of its state and the catch-up through it, in the units of [`STEP_COST`].
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

/// Consecutive segment ids a run of [`SegmentRuns`] covers. On the `paper` building lap run
/// (100,000 snapshots), the 1,800 to 3,000 segments a late checkpoint interval changes fall
/// in about 350 of 2,500 runs of 64 ids, against 190 of 630 of 256.
const RUN_IDS: usize = 64;

/// A map's segments in runs of [`RUN_IDS`] consecutive ids (run `r` lists those with ids in
/// `r * RUN_IDS..(r + 1) * RUN_IDS`, in order; a run of ids none of which is in the map is
/// empty), each run shared with the
/// checkpoint before while none of its segments changed. A late `paper` checkpoint changes about
/// 1 % of its segments, so its list of 170,000 segment pointers (1.4 MB, a fifth of what each
/// checkpoint kept alive) becomes a few hundred runs (docs/performance.md, stop 32).
#[derive(Clone, Debug, Default)]
pub struct SegmentRuns {
    runs: Vec<Arc<[Arc<Segment>]>>,
    len: usize,
}

impl SegmentRuns {
    /// `segments` (ordered by id) in runs, each sharing the run `previous` holds for the same
    /// ids when that lists the very same segments.
    fn new(segments: &[Arc<Segment>], previous: Option<&SegmentRuns>) -> Self {
        debug_assert!(
            segments.windows(2).all(|w| w[0].id < w[1].id),
            "segments ordered by id"
        );
        let count = segments.last().map_or(0, |s| s.id as usize / RUN_IDS + 1);
        let mut runs = Vec::with_capacity(count);
        let mut rest = segments;
        for r in 0..count {
            let end = rest.partition_point(|s| (s.id as usize) < (r + 1) * RUN_IDS);
            let (run, after) = rest.split_at(end);
            let same = |old: &&Arc<[Arc<Segment>]>| {
                old.len() == run.len() && old.iter().zip(run).all(|(a, b)| Arc::ptr_eq(a, b))
            };
            runs.push(match previous.and_then(|p| p.runs.get(r)).filter(same) {
                Some(old) => Arc::clone(old),
                None => run.into(),
            });
            rest = after;
        }
        Self {
            runs,
            len: segments.len(),
        }
    }

    /// Segments held.
    fn len(&self) -> usize {
        self.len
    }

    /// The segments, ordered by id.
    fn to_vec(&self) -> Vec<Arc<Segment>> {
        let mut list = Vec::with_capacity(self.len);
        for run in &self.runs {
            list.extend(run.iter().cloned());
        }
        list
    }

    /// Each run with the run `previous` holds for the same ids (empty past its end), when the
    /// two are not the very same run.
    fn changed_runs<'a>(
        &'a self,
        previous: Option<&'a SegmentRuns>,
    ) -> impl Iterator<Item = (&'a [Arc<Segment>], &'a [Arc<Segment>])> + 'a {
        let old_run = move |r: usize| previous.and_then(|p| p.runs.get(r));
        self.runs
            .iter()
            .enumerate()
            .filter_map(move |(r, run)| match old_run(r) {
                Some(old) if Arc::ptr_eq(old, run) => None,
                Some(old) => Some((&old[..], &run[..])),
                None => Some((&[][..], &run[..])),
            })
    }
}

/// A checkpoint: a mapper state whose map's segments are kept in [`SegmentRuns`].
#[derive(Clone, Debug)]
struct Kept {
    /// The state, its map's list of segments left empty.
    state: MapperState,
    segments: SegmentRuns,
}

impl Kept {
    /// `state` with `segments` (its map's, ordered by id) in runs, sharing those of `previous`
    /// that did not change.
    fn new(mut state: MapperState, segments: &[Arc<Segment>], previous: Option<&Kept>) -> Self {
        let segments = SegmentRuns::new(segments, previous.map(|p| &p.segments));
        state.map.segments = Vec::new();
        Self { state, segments }
    }

    fn next_snapshot(&self) -> usize {
        self.state.next_snapshot
    }

    /// The state with its map made live: its segments listed and filed in its spatial index.
    fn live(&self) -> MapperState {
        MapperState {
            map: self.state.map.with_segments_indexed(self.segments.to_vec()),
            last_pose: self.state.last_pose,
            next_snapshot: self.state.next_snapshot,
        }
    }
}

/// Bytes that `kept` keeps alive beyond `previous`: its lists of segment runs, faces and
/// remembered points, the runs it does not share with `previous`, and each segment or face
/// (with its heap) not shared with `previous`.
fn kept_alive_bytes(previous: Option<&Kept>, kept: &Kept) -> usize {
    let map = &kept.state.map;
    let old_runs = previous.map(|p| &p.segments);
    let changed: Vec<_> = kept.segments.changed_runs(old_runs).collect();
    // The lists, and what the extensions keep whole in every copy (point features, plane
    // support of tentative segments, recent poses; a B-tree entry counted with two words of
    // overhead).
    let lists = kept.segments.runs.capacity() * size_of::<Arc<[Arc<Segment>]>>()
        + changed
            .iter()
            .map(|(_, run)| 2 * size_of::<usize>() + std::mem::size_of_val(*run))
            .sum::<usize>()
        + map.faces.len() * size_of::<Arc<Face>>()
        + map.memory.len() * size_of::<MemoryPoint>()
        + map.features.len() * size_of::<PointFeature>()
        + map.round_evidence.len() * size_of::<Beam>()
        + map.plane_support.len() * (size_of::<(SegmentId, PlaneSupport)>() + 16)
        + map.recent_poses.len() * size_of::<(usize, Pose)>();
    let empty = Vec::new();
    let old_faces = previous.map_or(&empty, |p| &p.state.map.faces);
    // The supporting-point chunks `previous` holds in the segments this state changed or
    // dropped: a new version of a segment, or a piece of its refit, may share them. A chunk is
    // counted once, the first time a segment here holds it.
    let mut known: FxHashSet<*const SupportPoint> = changed
        .iter()
        .flat_map(|(old, new)| replaced(old, new, |s| s.id))
        .flat_map(|s| s.points.chunks().iter().map(|c| c.as_ptr()))
        .collect();
    let mut segment_bytes = |s: &Segment| {
        let new_chunks = s
            .points
            .chunks()
            .iter()
            .filter(|c| known.insert(c.as_ptr()));
        size_of::<Segment>()
            + s.updated.capacity() * size_of::<u32>()
            + s.points.chunk_list_bytes()
            + new_chunks.map(SupportList::chunk_bytes).sum::<usize>()
    };
    let segments: usize = changed
        .iter()
        .map(|(old, new)| unshared(old, new, |s| s.id, &mut segment_bytes))
        .sum();
    let faces = changed_faces(old_faces, &map.faces);
    lists + segments + faces
}

/// The bytes of each face of `new` (both lists ordered by id) that is not the very face `old`
/// holds under its id: the face, and its list of segments beyond what the old version of it
/// shares.
fn changed_faces(old: &[Arc<Face>], new: &[Arc<Face>]) -> usize {
    let mut j = 0;
    let mut total = 0;
    for face in new {
        while j < old.len() && old[j].id < face.id {
            j += 1;
        }
        let previous = old.get(j).filter(|o| o.id == face.id);
        if !previous.is_some_and(|o| Arc::ptr_eq(o, face)) {
            total += size_of::<Face>() + face.segments.bytes_beyond(previous.map(|o| &o.segments));
        }
    }
    total
}

/// The sum of `size` over the items of `new` (both lists ordered by id) that are not the very
/// item `old` holds under their id, in order.
fn unshared<T>(
    old: &[Arc<T>],
    new: &[Arc<T>],
    id: impl Fn(&T) -> u32,
    mut size: impl FnMut(&T) -> usize,
) -> usize {
    let mut j = 0;
    let mut total = 0;
    for item in new {
        let key = id(item);
        while j < old.len() && id(&old[j]) < key {
            j += 1;
        }
        if !old.get(j).is_some_and(|o| Arc::ptr_eq(o, item)) {
            total += size(item);
        }
    }
    total
}

/// The items of `old` that `new` (both lists ordered by id) no longer holds: those whose id
/// it lacks or holds another item under.
fn replaced<'a, T>(
    old: &'a [Arc<T>],
    new: &'a [Arc<T>],
    id: impl Fn(&T) -> u32 + 'a,
) -> impl Iterator<Item = &'a T> + 'a {
    let mut j = 0;
    old.iter().filter_map(move |item| {
        let key = id(item);
        while j < new.len() && id(&new[j]) < key {
            j += 1;
        }
        (!new.get(j).is_some_and(|n| Arc::ptr_eq(n, item))).then_some(&**item)
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Point;
    use crate::mapping::model::map::{EndPoint, Map, ReadingRef};
    use crate::mapping::SegmentKind;

    fn segment(id: u32, points: usize) -> Segment {
        let end = EndPoint {
            point: Point::new(f64::from(id), 0.0),
            range_m: 1.0,
        };
        let q = SupportPoint {
            point: end.point,
            range_m: 1.0,
            reading: ReadingRef::new(0, 0),
        };
        Segment {
            id,
            kind: SegmentKind::Fitted,
            a: end,
            b: end,
            face: id,
            object: id,
            created: 0,
            updated: Vec::new(),
            points: vec![q; points].into(),
        }
    }

    fn kept(map: Map, previous: Option<&Kept>) -> Kept {
        let segments = map.segments.clone();
        Kept::new(state(map), &segments, previous)
    }

    fn state(map: Map) -> MapperState {
        MapperState {
            map,
            last_pose: None,
            next_snapshot: 0,
        }
    }

    /// What a run of `n` segment pointers keeps alive: two counts, then the pointers.
    fn run(n: usize) -> usize {
        16 + n * 8
    }

    #[test]
    fn a_checkpoint_counts_its_lists_and_only_what_changed_since_the_previous_one() {
        let first = Map::from_segments((0..4).map(|id| segment(id, 10)).collect());
        let mut second = first.clone();
        // Segment 2 changes (a new version, new points); segment 9 is new; segment 3 moves and
        // keeps its points (its one chunk stays shared).
        second.segments[2] = Arc::new(segment(2, 3));
        second.segments.push(Arc::new(segment(9, 1)));
        let mut moved = (*second.segments[3]).clone();
        moved.a.point.x += 1.0;
        second.segments[3] = Arc::new(moved);
        let a = kept(first, None);
        let b = kept(second, Some(&a));
        let one = size_of::<Segment>();
        // A short list: one chunk pointer (with its length, 16 bytes), and the chunk (two
        // counts, then its points).
        let chunk_list = 16;
        let chunk = |n: usize| 16 + n * size_of::<SupportPoint>();
        // The lists of the first: one run of segments (a pointer with its length, 16 bytes)
        // holding 4 segment pointers, and 4 face pointers.
        let first_lists = 16 + run(4) + 4 * 8;
        assert_eq!(
            kept_alive_bytes(None, &a),
            first_lists + 4 * (one + chunk_list + chunk(10)) + kept_faces(&a.state.map)
        );
        // The lists of the second: its one run changed (5 segments), and 4 face pointers.
        let second_lists = 16 + run(5) + 4 * 8;
        assert_eq!(
            kept_alive_bytes(Some(&a), &b),
            second_lists
                + (one + chunk_list + chunk(3))
                + (one + chunk_list + chunk(1))
                + (one + chunk_list)
        );
    }

    #[test]
    fn a_checkpoint_shares_the_runs_of_segments_that_did_not_change() {
        // Ids 0..200: runs 0..64, 64..128, 128..192 and 192..200.
        let first = Map::from_segments((0..200).map(|id| segment(id, 1)).collect());
        let mut second = first.clone();
        // Segment 70 changes and segment 140 leaves: the second and third runs change.
        second.segments[70] = Arc::new(segment(70, 2));
        second.remove_segment(140);
        let a = kept(first.clone(), None);
        let b = kept(second.clone(), Some(&a));
        let shared: Vec<bool> = (0..4)
            .map(|r| Arc::ptr_eq(&a.segments.runs[r], &b.segments.runs[r]))
            .collect();
        assert_eq!(shared, [true, false, false, true]);
        // Each state made live lists its segments, filed in its index.
        let live = b.live();
        assert_eq!(live.map.segments, second.segments);
        assert_eq!(live.map, second);
        assert_eq!(live.map.check_invariants(0), Ok(()));
        assert_eq!(a.live().map, first);
        // What the second keeps alive: its list of 4 runs, the 2 changed runs, the new version
        // of segment 70 (its one chunk of 2 points), and 199 face pointers (face 140 left).
        let one = size_of::<Segment>();
        assert_eq!(
            kept_alive_bytes(Some(&a), &b),
            4 * 16 + run(64) + run(63) + 199 * 8 + one + 16 + (16 + 2 * size_of::<SupportPoint>())
        );
    }

    #[test]
    fn a_refit_piece_sharing_chunks_of_the_segment_it_came_from_counts_only_its_own() {
        // 128 points: eight chunks of 16.
        let first = Map::from_segments(vec![segment(0, 128)]);
        let mut second = first.clone();
        let whole = second.segments[0].points.clone();
        // A refit keeps points 0..80 under id 0 (the first five chunks, shared) and makes
        // piece 1 of points 88..128: 88..96 (8 points, short) joins the chunk 96..112 in a
        // copy of 24 points, and 112..128 stays shared.
        let mut head = (*second.segments[0]).clone();
        head.points = whole.slice(0..80);
        second.segments[0] = Arc::new(head);
        let mut tail = segment(1, 0);
        tail.points = whole.slice(88..128);
        second.segments.push(Arc::new(tail));
        let a = kept(first, None);
        let b = kept(second, Some(&a));
        let one = size_of::<Segment>();
        let chunk = |n: usize| 16 + n * size_of::<SupportPoint>();
        // Lists: one run of two segment pointers and one face pointer. A slice's list of chunk
        // pointers has room for the chunks the range meets and one more, 16 bytes each: 6 for
        // the head, 4 for the tail.
        assert_eq!(
            kept_alive_bytes(Some(&a), &b),
            (16 + run(2) + 8) + (one + 6 * 16) + (one + 4 * 16 + chunk(24))
        );
    }

    fn kept_faces(map: &Map) -> usize {
        map.faces
            .iter()
            .map(|f| size_of::<Face>() + f.segments.bytes_beyond(None))
            .sum()
    }

    #[test]
    fn over_budget_the_cheapest_intervals_merge_and_the_costly_ones_stay_short() {
        let big = Map::from_segments((0..100).map(|id| segment(id, 50)).collect());
        let one_state = kept_alive_bytes(None, &kept(big.clone(), None));
        // Room for the first state and a few lists, not for 16 states.
        let mut store = Checkpoints::new(4, one_state + 8 * 1000);
        for k in 0..64 {
            if store.due(k) {
                let mut s = state(big.clone());
                s.next_snapshot = k;
                store.push(s);
            }
            // A step updates 100 more points than the one before: late steps cost more.
            store.note_step(100 * k);
        }
        assert!(store.len() < 16, "states were dropped");
        assert!(store.bytes() <= store.budget_bytes());
        // Each kept state sits at a multiple of the shortest spacing, in order, and is the
        // latest at or before any snapshot of its interval.
        let starts: Vec<usize> = store.states.iter().map(Kept::next_snapshot).collect();
        assert_eq!(starts[0], 0);
        assert!(starts.windows(2).all(|w| w[0] < w[1] && w[1] % 4 == 0));
        for k in 0..64 {
            let s = store.live_before(k).unwrap();
            assert_eq!(s.next_snapshot, store.snapshot_before(k));
            assert!(s.next_snapshot <= k);
            assert!(store.snapshot_after(k).is_none_or(|next| k < next));
        }
        // The costs noted are all kept, each in the interval it fell in.
        let step_cost = |k: usize| STEP_COST + (100 * k) as f64;
        let costs = store.interval_costs();
        assert_eq!(
            costs.iter().sum::<f64>(),
            (0..64).map(step_cost).sum::<f64>()
        );
        for (i, &c) in costs.iter().enumerate() {
            let end = starts.get(i + 1).copied().unwrap_or(64);
            assert_eq!(
                c,
                (starts[i]..end).map(step_cost).sum::<f64>(),
                "interval {i}"
            );
        }
        // The early (cheap) intervals are the long ones.
        let (first, last) = (starts[1] - starts[0], 64 - starts[starts.len() - 1]);
        assert!(first > last, "{starts:?}");
        // The slowest seek is the restore of a 100-segment map and the dearest interval.
        let worst = costs.iter().copied().fold(0.0, f64::max);
        assert_eq!(store.slowest_seek_cost(), 600.0 + worst);
    }

    #[test]
    fn two_states_stay_whatever_the_budget() {
        let big = Map::from_segments((0..100).map(|id| segment(id, 50)).collect());
        let mut store = Checkpoints::new(1, 0);
        for k in 0..10 {
            if store.due(k) {
                let mut s = state(big.clone());
                s.next_snapshot = k;
                store.push(s);
            }
            store.note_step(0);
        }
        // The first state and the second: the newest, its interval empty, goes at each push.
        assert_eq!(store.len(), 2);
        assert_eq!(store.snapshot_before(0), 0);
        assert_eq!(store.snapshot_before(9), 1);
        assert_eq!(store.spacing_range(10), (1, 1));
        assert_eq!(store.interval_costs(), &[STEP_COST, 9.0 * STEP_COST]);
    }
}
