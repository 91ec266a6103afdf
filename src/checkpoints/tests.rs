//! The checkpoints' tests: what a checkpoint counts, what it shares, and how the store thins
//! past its budget.

use super::*;
use crate::geometry::Point;
use crate::mapping::model::map::{EndPoint, Face, Map, ReadingRef, SupportPoint};
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
        last_t_s: None,
        pose_belief: Default::default(),
        last_echoes: Default::default(),
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
