//! Point memory's tests (docs/algorithm.md §8.1, §8.15, §8.16).

use super::*;
use crate::mapping::model::map::ReadingRef;

fn sp(snapshot: usize, sensor: usize, x: f64, y: f64, d: f64) -> SupportPoint {
    SupportPoint {
        point: Point::new(x, y),
        range_m: d,
        reading: ReadingRef::new(snapshot, sensor),
    }
}

/// Steps the memory through `readings`, one a snapshot of a robot standing still (snapshot `k`
/// for the `k`-th); what the last step returned.
fn feed(
    memory: &mut Vec<MemoryPoint>,
    linkage: &mut Linkage,
    readings: &[SupportPoint],
    p: &Params,
) -> Option<(MemoryTrace, Vec<MemoryPiece>)> {
    let mut last = None;
    for (k, q) in readings.iter().enumerate() {
        last = Some(memory_step(
            memory,
            &[*q],
            MemoryClock::standing(k),
            p,
            true,
            linkage,
        ));
    }
    last
}

/// `paper` with `extended`'s point memory: 10 snapshots, a 12 in gap, three readings.
pub(in crate::mapping::ext) fn paper_with_memory() -> Params {
    Params {
        memory_snapshots: 10,
        memory_gap_m: 0.3048,
        memory_min_points: 3,
        ..Params::paper()
    }
}

#[test]
fn a_stack_is_one_place_read_at_ranges_the_ball_test_tells_apart() {
    // ξ = 3. Ranges 2.0 and 2.2 at points 0.10 apart: the places pass the ball test
    // (0.10 ≤ 0.03·4.2 = 0.126) and the ranges fail it (0.2 > 0.126): a stack.
    let near = sp(0, 0, 0.0, 2.0, 2.0);
    assert!(is_stack(&[near, sp(1, 0, 0.10, 2.0, 2.2)], 3.0));
    // 0.13 apart, the places fail too: two places.
    assert!(!is_stack(&[near, sp(1, 0, 0.13, 2.0, 2.2)], 3.0));
    // Ranges 2.0 and 2.1 pass (0.1 ≤ 0.123): one depth, as a sensor standing still or
    // moving along a wall reads it; not a stack.
    assert!(!is_stack(&[near, sp(1, 0, 0.10, 2.0, 2.1)], 3.0));
    // Every two readings must share the place: 0.0, 0.1, 0.2 at 2.0, 2.2, 2.4 pass
    // pairwise neighbour to neighbour (0.1 ≤ 0.126, 0.1 ≤ 0.138) but not end to end
    // (0.2 > 0.03·4.4 = 0.132).
    let spread = [near, sp(1, 0, 0.1, 2.0, 2.2), sp(2, 0, 0.2, 2.0, 2.4)];
    assert!(!is_stack(&spread, 3.0));
}

#[test]
fn a_sonar_driven_square_on_to_a_wall_leaves_a_stack_not_a_segment() {
    // One sonar reads the same foot (0, 5) from 4.0, 3.8 and 3.6 m as the robot drives
    // towards the wall: the third snapshot groups the three (0 apart, within 12 in).
    let stacks_on = Params {
        memory_stacks: true,
        ..paper_with_memory()
    };
    let readings = [
        sp(0, 0, 0.0, 5.0, 4.0),
        sp(1, 0, 0.0, 5.0, 3.8),
        sp(2, 0, 0.0, 5.0, 3.6),
    ];
    let run = |p: &Params| {
        let (mut memory, mut linkage) = (Vec::new(), Linkage::default());
        let last = feed(&mut memory, &mut linkage, &readings, p);
        (last.expect("three steps"), memory.len())
    };
    let ((t, pieces), held) = run(&stacks_on);
    assert!(pieces.is_empty(), "a stack makes no segment");
    assert_eq!(held, 0, "its readings leave the memory");
    assert_eq!(t.stacked.len(), 3);
    assert!(t.used.is_empty());
    assert_eq!(t.groups[0].stacks, vec![0]);
    assert_eq!(t.groups[0].piece_segments, vec![None]);
    // Without the rule, the paper's memory fits the three into a piece (a line through
    // one place, whichever way the noise turns it).
    let stacks_off = Params {
        memory_stacks: false,
        memory_min_span_m: 0.0,
        ..stacks_on
    };
    let ((t, pieces), held) = run(&stacks_off);
    assert_eq!(pieces.len(), 1);
    assert_eq!((held, t.used.len()), (0, 3));
    assert!(t.stacked.is_empty());
    // With a shortest span, the place (0 m long) stays in the memory instead.
    let ((_, pieces), held) = run(&Params {
        memory_min_span_m: 0.3048,
        ..stacks_off
    });
    assert!(pieces.is_empty());
    assert_eq!(held, 3);
}

#[test]
fn a_crawl_along_a_wall_waits_for_a_foot_of_wall_before_a_segment() {
    // A side sonar reads the wall y = 2 every 5 cm of driving: with 12 in as the shortest
    // span, the readings at x = 0 .. 0.25 (0.25 m) stay in the memory, and the one at
    // 0.30 m (0.30 < 0.3048) too; at 0.35 m the eight readings become one piece.
    let p = Params {
        memory_min_span_m: 0.3048,
        ..paper_with_memory()
    };
    let (mut memory, mut linkage) = (Vec::new(), Linkage::default());
    for k in 0..8 {
        let x = 0.05 * k as f64;
        let now = MemoryClock {
            snapshot: k,
            travelled_m: x,
        };
        let (_, pieces) = memory_step(
            &mut memory,
            &[sp(k, 0, x, 2.0, 2.0)],
            now,
            &p,
            true,
            &mut linkage,
        );
        if k < 7 {
            assert!(pieces.is_empty(), "{k}");
        } else {
            assert_eq!(pieces.len(), 1);
            assert_eq!(pieces[0].points.len(), 8);
        }
    }
}

#[test]
fn a_joint_is_the_newest_end_reading_of_a_growing_piece() {
    let piece = |snapshots: [usize; 3]| {
        [
            sp(snapshots[0], 0, 0.0, 5.0, 2.0),
            sp(snapshots[1], 0, 0.2, 5.0, 2.0),
            sp(snapshots[2], 0, 0.4, 5.0, 2.0),
        ]
    };
    assert_eq!(joint_end(&piece([3, 4, 5])), Some(2));
    assert_eq!(joint_end(&piece([5, 4, 3])), Some(0));
    // The newest reading inside the piece, or both ends of one snapshot: no joint.
    assert_eq!(joint_end(&piece([3, 5, 4])), None);
    assert_eq!(joint_end(&piece([5, 4, 5])), None);
    // A reading inside of the same snapshot as the newer end: that end is the joint.
    assert_eq!(joint_end(&piece([3, 5, 5])), Some(2));
    assert_eq!(joint_end(&[]), None);
}

#[test]
fn pieces_of_a_chain_read_one_step_at_a_time_share_their_joints() {
    // One sonar reads the wall y = 5 at x = 0, 0.2, …, one reading a snapshot. The first
    // three make a piece; its newest end (x = 0.4, snapshot 2) stays as its joint, so the
    // next piece is x = 0.4, 0.6, 0.8: the two overlap at the joint. Without joints the next
    // piece starts at x = 0.6, a reading spacing past the first.
    let run = |joints: bool| {
        let p = Params {
            memory_joints: joints,
            ..paper_with_memory()
        };
        let (mut memory, mut linkage) = (Vec::new(), Linkage::default());
        let mut pieces = Vec::new();
        let mut traces = Vec::new();
        for k in 0..5 {
            let q = sp(k, 0, 0.2 * k as f64, 5.0, 2.0);
            let (t, out) = memory_step(
                &mut memory,
                &[q],
                MemoryClock::standing(k),
                &p,
                true,
                &mut linkage,
            );
            pieces.extend(out.into_iter().map(|piece| {
                piece
                    .points
                    .iter()
                    .map(|q| q.reading.snapshot())
                    .collect::<Vec<_>>()
            }));
            traces.push(t);
        }
        (pieces, traces, memory)
    };
    let (pieces, traces, memory) = run(true);
    assert_eq!(pieces, vec![vec![0, 1, 2], vec![2, 3, 4]]);
    assert_eq!(traces[2].joints, vec![ReadingRef::new(2, 0)]);
    assert_eq!(traces[2].used.len(), 2, "the other two readings left");
    // The second piece took the first's joint, which left with it; its own (snapshot 4)
    // is held.
    let snapshots = |rs: &[ReadingRef]| rs.iter().map(|r| r.snapshot()).collect::<Vec<_>>();
    assert_eq!(snapshots(&traces[4].used), vec![2, 3]);
    assert_eq!(traces[4].joints, vec![ReadingRef::new(4, 0)]);
    assert_eq!(memory.len(), 1);
    assert_eq!(memory[0].support.reading, ReadingRef::new(4, 0));
    let (pieces, _, memory) = run(false);
    assert_eq!(pieces, vec![vec![0, 1, 2]]);
    assert_eq!(memory.len(), 2, "snapshots 3 and 4 wait for a third");
}

#[test]
fn a_corner_two_pieces_keep_as_their_joint_is_held_once() {
    // An L: (−0.4, 0) and (−0.2, 0) of snapshots 0 and 1, (0, 0.2) and (0, 0.4) of 2 and
    // 3, linked at 0.2 m (the 0.25 m gap keeps the arms apart, 0.283 m) until the corner
    // (0, 0) of snapshot 4 joins them. The fit splits at the corner into two pieces of
    // three; the corner is the newest end of both, so both keep it as their joint.
    let p = Params {
        memory_gap_m: 0.25,
        memory_joints: true,
        ..paper_with_memory()
    };
    let (mut memory, mut linkage) = (Vec::new(), Linkage::default());
    let readings = [
        sp(0, 0, -0.4, 0.0, 2.0),
        sp(1, 0, -0.2, 0.0, 2.0),
        sp(2, 0, 0.0, 0.2, 2.0),
        sp(3, 0, 0.0, 0.4, 2.0),
        sp(4, 0, 0.0, 0.0, 2.0),
    ];
    let last = feed(&mut memory, &mut linkage, &readings, &p);
    let (t, pieces) = last.expect("five steps");
    assert_eq!(t.groups[0].pieces, vec![[0, 2], [2, 4]]);
    assert_eq!(pieces.len(), 2);
    assert_eq!(t.joints, vec![ReadingRef::new(4, 0)]);
    assert_eq!(t.used.len(), 4);
    assert_eq!(memory.len(), 1);
    assert_eq!(memory[0].support.reading, ReadingRef::new(4, 0));
}

#[test]
fn memory_fits_remembered_singles_and_expires_old_ones() {
    let p = Params {
        memory_snapshots: 3,
        memory_gap_m: 1.5,
        memory_min_points: 3,
        ..Params::paper()
    };
    let mut memory = Vec::new();
    let step = |memory: &mut Vec<MemoryPoint>, points: &[SupportPoint], snapshot| {
        memory_step(
            memory,
            points,
            MemoryClock::standing(snapshot),
            &p,
            true,
            &mut Linkage::default(),
        )
    };
    let (t, pieces) = step(&mut memory, &[sp(0, 2, 0.0, 5.0, 50.0)], 0);
    assert!(pieces.is_empty() && t.held_after == 1);
    let (_, pieces) = step(&mut memory, &[sp(1, 2, 1.0, 5.0, 50.0)], 1);
    assert!(pieces.is_empty());
    let (t, pieces) = step(&mut memory, &[sp(2, 2, 2.0, 5.0, 50.0)], 2);
    assert_eq!(pieces.len(), 1);
    assert_eq!(pieces[0].points.len(), 3);
    assert_eq!(t.used.len(), 3);
    assert_eq!(t.held_after, 0);
    // A lone reading expires after memory_snapshots.
    step(&mut memory, &[sp(3, 0, 50.0, 50.0, 50.0)], 3);
    let (t, _) = step(&mut memory, &[], 6);
    assert_eq!(t.expired, vec![ReadingRef::new(3, 0)]);
}

#[test]
fn a_bent_group_is_cut_where_its_axis_order_jumps_past_the_gap() {
    // A wall along y = 0 read at x = 0.6, 0.7, 1.0 and a wall along x = 0.7 read at y = 0.3,
    // 0.5, all at 2 m: one group, (0.7, 0) and (0.7, 0.3) linked at 0.3 ≤ 0.3048. Ordered
    // along the group's axis, (0.7, 0.5), (0.7, 0.3), (0.6, 0), (0.7, 0), (1.0, 0), the second
    // wall's readings end at (0.7, 0.3), 0.316 m from the next (> 0.3048): the order is cut
    // there. Fitted whole, §3 would split it at (0.6, 0) into the first wall's three readings
    // and a chord of three, (0.7, 0.5)–(0.6, 0) (0.51 m, longer than the 0.3048 m a piece
    // needs), across the corner; cut, the second wall's
    // two readings are too few for a piece and stay to grow.
    let p = paper_with_memory();
    let readings = [
        sp(0, 0, 0.6, 0.0, 2.0),
        sp(1, 0, 0.7, 0.0, 2.0),
        sp(2, 0, 1.0, 0.0, 2.0),
        sp(3, 1, 0.7, 0.3, 2.0),
        sp(4, 1, 0.7, 0.5, 2.0),
    ];
    let memory: Vec<MemoryPoint> = readings
        .iter()
        .map(|&support| MemoryPoint {
            support,
            travelled_m: 0.0,
        })
        .collect();
    let mut taken = Taken {
        used: vec![false; memory.len()],
        in_segment: vec![false; memory.len()],
        joints: Vec::new(),
        pieces: Vec::new(),
    };
    let group = fit_group(&memory, &[0, 1, 2, 3, 4], 0, &p, true, &mut taken).expect("traced");
    let order: Vec<(f64, f64)> = group
        .points
        .iter()
        .map(|q| (q.point.x, q.point.y))
        .collect();
    assert_eq!(
        order,
        vec![(0.7, 0.5), (0.7, 0.3), (0.6, 0.0), (0.7, 0.0), (1.0, 0.0)]
    );
    assert_eq!(group.pieces, vec![[0, 1], [2, 4]]);
    assert_eq!(taken.pieces.len(), 1);
    let wall: Vec<ReadingRef> = taken.pieces[0].points.iter().map(|q| q.reading).collect();
    assert_eq!(
        wall,
        vec![
            ReadingRef::new(0, 0),
            ReadingRef::new(1, 0),
            ReadingRef::new(2, 0)
        ]
    );
    assert_eq!(taken.used, vec![true, true, true, false, false]);
    assert_eq!(group.cuts, vec![2]);
    // The runs themselves: cut once, at the 0.316 m jump.
    let runs: Vec<[usize; 2]> = runs_within_gap(&group.points, 0.3048).collect();
    assert_eq!(runs, vec![[0, 1], [2, 4]]);
    // No readings, no runs; one reading, one run of it.
    assert_eq!(runs_within_gap(&[], 0.3048).count(), 0);
    let one: Vec<[usize; 2]> = runs_within_gap(&group.points[..1], 0.3048).collect();
    assert_eq!(one, vec![[0, 0]]);
}
