//! The replay's checkpoints within a memory budget.
//!
//! A checkpoint is a [`MapperState`]: its map shares every segment and face that did not change
//! since the previous checkpoint, so what it alone keeps alive is its lists of segments and
//! faces (a pointer each) and the versions of what changed (of a segment's supporting points,
//! the chunks that changed). That grows with the map: a `paper` map of a long lap run holds
//! hundreds of thousands of segments. The store counts those bytes as checkpoints are taken,
//! and when they pass the budget it drops every other checkpoint and doubles the spacing, so
//! the checkpoints of any run stay within the budget (give or take one checkpoint) at the price
//! of longer catch-ups on a seek.

use crate::geometry::Pose;
use crate::mapping::confirm::PlaneSupport;
use crate::mapping::features::PointFeature;
use crate::mapping::map::{Face, MemoryPoint, Segment, SupportPoint};
use crate::mapping::support_list::SupportList;
use crate::mapping::MapperState;
use crate::mapping::SegmentId;
use rustc_hash::FxHashSet;
use std::mem::size_of;
use std::sync::Arc;

/// The checkpoints' memory budget unless told otherwise, bytes.
pub const DEFAULT_CHECKPOINT_BUDGET_BYTES: usize = 512 << 20;

/// Mapper states every `interval` snapshots, within a byte budget.
#[derive(Clone, Debug)]
pub struct Checkpoints {
    interval: usize,
    budget_bytes: usize,
    states: Vec<MapperState>,
    /// What each state keeps alive beyond the one before it, bytes.
    bytes: Vec<usize>,
}

impl Checkpoints {
    /// An empty store taking a state every `interval` snapshots (at least 1) within
    /// `budget_bytes`.
    pub fn new(interval: usize, budget_bytes: usize) -> Self {
        Self {
            interval: interval.max(1),
            budget_bytes,
            states: Vec::new(),
            bytes: Vec::new(),
        }
    }

    /// Snapshots between checkpoints (doubled each time the budget was reached).
    pub fn interval(&self) -> usize {
        self.interval
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

    /// Whether the state before snapshot `k` is to be kept.
    pub fn due(&self, k: usize) -> bool {
        k.is_multiple_of(self.interval) && k / self.interval == self.states.len()
    }

    /// Keeps `state` (the state before a snapshot [`Checkpoints::due`] named), then thins the
    /// store while it is over budget and holds more than one state.
    pub fn push(&mut self, state: MapperState) {
        self.bytes
            .push(kept_alive_bytes(self.states.last(), &state));
        self.states.push(state);
        while self.bytes() > self.budget_bytes && self.states.len() > 1 {
            self.thin();
        }
    }

    /// The latest state at or before snapshot `k`.
    pub fn before(&self, k: usize) -> Option<&MapperState> {
        self.states.get(self.index_before(k))
    }

    /// Snapshot of the latest state at or before snapshot `k`.
    pub fn snapshot_before(&self, k: usize) -> usize {
        self.index_before(k) * self.interval
    }

    /// Index of the latest state at or before snapshot `k` (0 while there is none).
    fn index_before(&self, k: usize) -> usize {
        (k / self.interval).min(self.states.len().saturating_sub(1))
    }

    /// Drops every other state (keeping the first) and doubles the spacing.
    fn thin(&mut self) {
        let states = std::mem::take(&mut self.states);
        self.states = states.into_iter().step_by(2).collect();
        self.interval *= 2;
        self.bytes = (0..self.states.len())
            .map(|i| kept_alive_bytes(i.checked_sub(1).map(|p| &self.states[p]), &self.states[i]))
            .collect();
    }
}

/// Bytes that `state` keeps alive beyond `previous`: its lists of segments, faces and
/// remembered points, and each segment or face (with its heap) not shared with `previous`.
fn kept_alive_bytes(previous: Option<&MapperState>, state: &MapperState) -> usize {
    let map = &state.map;
    // The lists, and what the extensions keep whole in every copy (point features, plane
    // support of tentative segments, recent poses; a B-tree entry counted with two words of
    // overhead).
    let lists = map.segments.len() * size_of::<Arc<Segment>>()
        + map.faces.len() * size_of::<Arc<Face>>()
        + map.memory.len() * size_of::<MemoryPoint>()
        + map.features.len() * size_of::<PointFeature>()
        + map.plane_support.len() * (size_of::<(SegmentId, PlaneSupport)>() + 16)
        + map.recent_poses.len() * size_of::<(usize, Pose)>();
    let empty = Vec::new();
    let (old_segments, old_faces) = match previous {
        Some(p) => (&p.map.segments, &p.map.faces),
        None => (&empty, &Vec::new()),
    };
    // The supporting-point chunks `previous` holds in the segments this state changed or
    // dropped: a new version of a segment, or a piece of its refit, may share them. A chunk is
    // counted once, the first time a segment here holds it.
    let mut known: FxHashSet<*const SupportPoint> = replaced(old_segments, &map.segments, |s| s.id)
        .flat_map(|s| s.points.chunks().iter().map(|c| c.as_ptr()))
        .collect();
    let segments = unshared(
        old_segments,
        &map.segments,
        |s| s.id,
        |s| {
            let new_chunks = s
                .points
                .chunks()
                .iter()
                .filter(|c| known.insert(c.as_ptr()));
            size_of::<Segment>()
                + s.updated.capacity() * size_of::<u32>()
                + s.points.chunk_list_bytes()
                + new_chunks.map(SupportList::chunk_bytes).sum::<usize>()
        },
    );
    let faces = unshared(
        old_faces,
        &map.faces,
        |f| f.id,
        |f| size_of::<Face>() + f.segments.capacity() * size_of::<u32>(),
    );
    lists + segments + faces
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
    use crate::mapping::map::{EndPoint, Map, ReadingRef};
    use crate::mapping::SegmentKind;

    fn segment(id: u32, points: usize) -> Segment {
        let end = EndPoint {
            point: Point::new(f64::from(id), 0.0),
            range_m: 1.0,
        };
        let q = SupportPoint {
            point: end.point,
            range_m: 1.0,
            reading: ReadingRef {
                snapshot: 0,
                sensor: 0,
            },
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

    fn state(map: Map) -> MapperState {
        MapperState {
            map,
            last_pose: None,
            next_snapshot: 0,
        }
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
        let (a, b) = (state(first), state(second));
        let one = size_of::<Segment>();
        // A short list: one chunk pointer (with its length, 16 bytes), and the chunk (two
        // counts, then its points).
        let chunk_list = 16;
        let chunk = |n: usize| 16 + n * size_of::<SupportPoint>();
        // The lists of the first: 4 segment and 4 face pointers.
        let first_lists = 4 * 8 + 4 * 8;
        assert_eq!(
            kept_alive_bytes(None, &a),
            first_lists + 4 * (one + chunk_list + chunk(10)) + kept_faces(&a.map)
        );
        // The lists of the second: 5 segment and 4 face pointers.
        let second_lists = 5 * 8 + 4 * 8;
        assert_eq!(
            kept_alive_bytes(Some(&a), &b),
            second_lists
                + (one + chunk_list + chunk(3))
                + (one + chunk_list + chunk(1))
                + (one + chunk_list)
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
        let (a, b) = (state(first), state(second));
        let one = size_of::<Segment>();
        let chunk = |n: usize| 16 + n * size_of::<SupportPoint>();
        // Lists: two segment pointers and one face pointer. A slice's list of chunk pointers
        // has room for the chunks the range meets and one more, 16 bytes each: 6 for the head,
        // 4 for the tail.
        assert_eq!(
            kept_alive_bytes(Some(&a), &b),
            (2 * 8 + 8) + (one + 6 * 16) + (one + 4 * 16 + chunk(24))
        );
    }

    fn kept_faces(map: &Map) -> usize {
        map.faces
            .iter()
            .map(|f| size_of::<Face>() + f.segments.capacity() * 4)
            .sum()
    }

    #[test]
    fn over_budget_every_other_checkpoint_goes_and_the_spacing_doubles() {
        let big = Map::from_segments((0..100).map(|id| segment(id, 50)).collect());
        let one_state = kept_alive_bytes(None, &state(big.clone()));
        // Room for the first state and a few lists, not for 16 states.
        let mut store = Checkpoints::new(4, one_state + 8 * 1000);
        for k in 0..64 {
            if store.due(k) {
                let mut s = state(big.clone());
                s.next_snapshot = k;
                store.push(s);
            }
        }
        assert!(store.interval() > 4, "the spacing grew");
        assert!(store.bytes() <= store.budget_bytes());
        // Each kept state sits at a multiple of the spacing, in order.
        for k in [0, 17, 40, 63] {
            let s = store.before(k).unwrap();
            assert_eq!(s.next_snapshot, store.snapshot_before(k));
            assert!(s.next_snapshot <= k && k - s.next_snapshot < store.interval());
        }
    }
}
