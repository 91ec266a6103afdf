//! Point memory (docs/algorithm.md §8.1; beyond the paper): the readings of one-point clusters
//! kept for some snapshots, grouped and fitted as §3 fits a cluster; with its stacks (§8.15)
//! and joints (§8.16).

use crate::geometry::{fit_line_tls, AlongLine, Point};
use crate::mapping::ext::constant_depth::same_depth;
use crate::mapping::ext::memory_linkage::{Linkage, Seeds};
use crate::mapping::model::map::{MemoryPoint, ReadingRef, SupportPoint};
use crate::mapping::model::params::Params;
use crate::mapping::model::trace::{MemoryGroupTrace, MemoryTrace};
use crate::mapping::paper::fit::split_recursive;
use crate::sonar::balls_intersect;

/// One fitted memory piece that became a new segment.
pub struct MemoryPiece {
    /// Index of its group in `MemoryTrace::groups`.
    pub group: usize,
    /// Its points in order.
    pub points: Vec<SupportPoint>,
}

/// The nearest and the farthest range of `readings`, metres.
pub fn range_span_m(readings: &[SupportPoint]) -> (f64, f64) {
    readings
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(near, far), q| {
            (near.min(q.range_m), far.max(q.range_m))
        })
}

/// Whether `readings` are a stack (docs/algorithm.md §8.15): one place read at changing
/// ranges. Every two pass the ball test of §1 as points, `|p1 − p2| ≤ ξ·(D1 + D2)/100`, but the
/// nearest and farthest ranges do not pass it as ranges (§8.2): the sensor moved towards or
/// away from the place, as a sonar does that the robot drives square-on to a wall. Such a
/// piece's line joins noise: its direction is none the readings resolve.
fn is_stack(readings: &[SupportPoint], accuracy_pct: f64) -> bool {
    let (nearest_m, farthest_m) = range_span_m(readings);
    !same_depth(accuracy_pct, nearest_m, farthest_m)
        && readings.iter().enumerate().all(|(i, p)| {
            readings[i + 1..]
                .iter()
                .all(|q| balls_intersect(accuracy_pct, &p.point, p.range_m, &q.point, q.range_m))
        })
}

/// Point memory for one snapshot (docs/algorithm.md §8): expires readings older than
/// `memory_snapshots`, adds this snapshot's one-point clusters, links readings within
/// `memory_gap` into groups (single linkage), orders each group along its principal axis, fits
/// it by §3, and returns the pieces of at least `memory_min_points` points (their readings leave
/// the memory but, with `memory_joints`, a piece's joint, [`joint_end`], §8.16); with
/// `memory_stacks`, a piece that is a stack ([`is_stack`], §8.15) leaves the memory too but is
/// not returned. With `record` false (an untraced step) the trace only says how many readings
/// are held; the memory and the pieces are the same either way. After a first step, only the
/// groups around the readings just added and those fitted last step are looked for
/// ([`Linkage::group_from_seeds`]): the others are too small to fit.
pub fn memory_step(
    memory: &mut Vec<MemoryPoint>,
    singles: &[SupportPoint],
    snapshot: usize,
    params: &Params,
    record: bool,
    linkage: &mut Linkage,
) -> (MemoryTrace, Vec<MemoryPiece>) {
    let mut trace = MemoryTrace::default();
    // Last step's seeds, while they still describe this memory; they leave with their readings.
    let mut seeds = linkage
        .seeds
        .take()
        .filter(|s| s.flags.len() == memory.len() && s.ends == memory_ends(memory))
        .map(|s| s.flags);
    let kept = expire_and_add(
        memory,
        singles,
        snapshot,
        params,
        seeds.as_mut(),
        &mut trace,
        record,
    );
    group_memory(memory, seeds.as_mut(), kept, params, linkage);
    let n = memory.len();
    // Next step's seeds: the readings of the groups fitted now that stay.
    let mut next_seeds = seeds.unwrap_or_default();
    next_seeds.clear();
    next_seeds.resize(n, false);
    let mut taken = Taken {
        used: std::mem::take(&mut linkage.used),
        in_segment: if record { vec![false; n] } else { Vec::new() },
        joints: Vec::new(),
        pieces: Vec::new(),
    };
    taken.used.clear();
    taken.used.resize(n, false);
    let (members, group_ends) = (&linkage.members, &linkage.group_ends);
    let groups = group_ends.iter().scan(0, |start, &end| {
        Some(&members[std::mem::replace(start, end)..end])
    });
    let fitted = groups.filter(|m| m.len() >= params.memory_min_points);
    for (group_index, group) in fitted.enumerate() {
        for &i in group {
            next_seeds[i] = true;
        }
        let group_trace = fit_group(memory, group, group_index, params, record, &mut taken);
        if let Some(g) = group_trace {
            trace.groups.push(g);
        }
    }
    if record {
        // A joint another piece of its group took left with that piece; a corner two pieces
        // both keep as their joint is one reading held.
        taken.joints.sort_unstable();
        taken.joints.dedup();
        let kept = taken.joints.iter().filter(|&&i| !taken.used[i]);
        trace
            .joints
            .extend(kept.map(|&i| memory[i].support.reading));
    }
    release_taken(memory, &taken, &mut next_seeds, &mut trace, record);
    linkage.used = taken.used;
    linkage.seeds = Some(Seeds {
        flags: next_seeds,
        ends: memory_ends(memory),
    });
    trace.held_after = memory.len();
    (trace, taken.pieces)
}

/// The first and last readings of `memory`: what last step's seeds were taken against.
fn memory_ends(memory: &[MemoryPoint]) -> Option<(ReadingRef, ReadingRef)> {
    Some((
        memory.first()?.support.reading,
        memory.last()?.support.reading,
    ))
}

/// What one step's pieces took from the memory.
struct Taken {
    /// Per remembered reading: a piece that became a segment (or a stack) took it.
    used: Vec<bool>,
    /// Traced: per reading, whether a segment took it (the rest left in stacks). Pieces share
    /// their corner readings, so this is told apart per reading, not per piece.
    in_segment: Vec<bool>,
    /// Traced: the joints kept this step (§8.16), by place in the memory.
    joints: Vec<usize>,
    /// The pieces that become new segments.
    pieces: Vec<MemoryPiece>,
}

/// Readings older than the memory's span leave it (and their seed flags with them), then the
/// step's `singles` join it. Returns how many old readings stayed.
fn expire_and_add(
    memory: &mut Vec<MemoryPoint>,
    singles: &[SupportPoint],
    snapshot: usize,
    params: &Params,
    mut seeds: Option<&mut Vec<bool>>,
    trace: &mut MemoryTrace,
    record: bool,
) -> usize {
    let horizon = params.memory_snapshots;
    let (mut i, mut kept) = (0, 0);
    memory.retain(|m| {
        let keep = snapshot - m.support.reading.snapshot().min(snapshot) < horizon;
        if !keep && record {
            trace.expired.push(m.support.reading);
        }
        if let (Some(seeds), true) = (seeds.as_mut(), keep) {
            seeds[kept] = seeds[i];
        }
        (i, kept) = (i + 1, kept + usize::from(keep));
        keep
    });
    memory.extend(singles.iter().map(|s| MemoryPoint { support: *s }));
    if record {
        trace.added.extend(singles.iter().map(|s| s.reading));
    }
    kept
}

/// Groups the memory's readings by single linkage: around the seeds (the `kept` old ones
/// flagged, and every reading just added) when last step's seeds still hold, else afresh.
fn group_memory(
    memory: &[MemoryPoint],
    seeds: Option<&mut Vec<bool>>,
    kept: usize,
    params: &Params,
    linkage: &mut Linkage,
) {
    let mut points = std::mem::take(&mut linkage.points);
    points.clear();
    points.extend(memory.iter().map(|m| m.support.point));
    match seeds {
        Some(seeds) => {
            // The readings just added are seeds.
            seeds.truncate(kept);
            seeds.resize(memory.len(), true);
            linkage.group_from_seeds(
                &points,
                seeds,
                params.memory_gap_m,
                params.memory_min_points,
            );
        }
        None => linkage.group(&points, params.memory_gap_m),
    }
    linkage.points = points;
}

/// Fits one group (`group`, places in the memory) as §3 fits a cluster: its pieces of enough
/// readings become segments, unless they are stacks (§8.15); a segment's newest end reading
/// stays as its joint (§8.16). What they take goes to `taken`. Traced, the group's record.
fn fit_group(
    memory: &[MemoryPoint],
    group: &[usize],
    group_index: usize,
    params: &Params,
    record: bool,
    taken: &mut Taken,
) -> Option<MemoryGroupTrace> {
    let mut points: Vec<SupportPoint> = group.iter().map(|&i| memory[i].support).collect();
    order_along_principal_axis(&mut points);
    // Each reading's place in the memory.
    let index_of = |q: &SupportPoint| {
        group
            .iter()
            .copied()
            .find(|&i| memory[i].support.reading == q.reading)
    };
    let mut splits = Vec::new();
    let mut pieces = Vec::new();
    split_recursive(&points, params, &mut splits, &mut pieces);
    let mut piece_segments = Vec::with_capacity(pieces.len());
    let mut stacks = Vec::new();
    for (k, &[first, last]) in pieces.iter().enumerate() {
        let piece = &points[first..=last];
        if piece.len() < params.memory_min_points {
            piece_segments.push(None);
            continue;
        }
        let stack = params.memory_stacks && is_stack(piece, params.accuracy_pct);
        let joint = (params.memory_joints && !stack)
            .then(|| joint_end(piece))
            .flatten();
        for (at, q) in piece.iter().enumerate() {
            let Some(i) = index_of(q) else { continue };
            // A joint is in this segment too: should another piece take it, it leaves as a
            // segment's reading.
            if record && !stack {
                taken.in_segment[i] = true;
            }
            if joint != Some(at) {
                taken.used[i] = true;
            } else if record {
                taken.joints.push(i);
            }
        }
        if stack {
            piece_segments.push(None);
            stacks.push(k);
        } else {
            piece_segments.push(Some(taken.pieces.len()));
            taken.pieces.push(MemoryPiece {
                group: group_index,
                points: piece.to_vec(),
            });
        }
    }
    record.then_some(MemoryGroupTrace {
        points,
        splits,
        pieces,
        piece_segments,
        stacks,
    })
}

/// The readings the step's pieces took leave the memory (traced as used by a segment or
/// stacked), with their seed flags.
fn release_taken(
    memory: &mut Vec<MemoryPoint>,
    taken: &Taken,
    next_seeds: &mut Vec<bool>,
    trace: &mut MemoryTrace,
    record: bool,
) {
    let (mut i, mut kept) = (0, 0);
    memory.retain(|m| {
        let keep = !taken.used[i];
        if !keep && record {
            if taken.in_segment[i] {
                trace.used.push(m.support.reading);
            } else {
                trace.stacked.push(m.support.reading);
            }
        }
        if keep {
            next_seeds[kept] = next_seeds[i];
        }
        (i, kept) = (i + 1, kept + usize::from(keep));
        keep
    });
    next_seeds.truncate(kept);
}

/// Orders `points` along their principal (total-least-squares) axis, equal places by reading
/// (snapshot, then sensor); leaves them as they are when no axis is defined.
fn order_along_principal_axis(points: &mut Vec<SupportPoint>) {
    let coords: Vec<Point> = points.iter().map(|q| q.point).collect();
    if let Some((centre, dir)) = fit_line_tls(&coords) {
        let axis = AlongLine::new(&centre, &(centre + dir));
        // Each point's place along the axis computed once (a sort asks for it many times).
        let mut keyed: Vec<(f64, SupportPoint)> =
            points.iter().map(|q| (axis.param(&q.point), *q)).collect();
        keyed.sort_by(|x, y| {
            x.0.total_cmp(&y.0)
                .then_with(|| x.1.reading.cmp(&y.1.reading))
        });
        points.clear();
        points.extend(keyed.into_iter().map(|(_, q)| q));
    }
}

/// The end of `piece` (0 or its last index) that point memory keeps as the piece's joint
/// (docs/algorithm.md §8.16): the end whose reading is of the piece's latest snapshot, the
/// other end's of an earlier one (readings inside may share the latest snapshot). None when
/// neither end is of the latest snapshot, or both are: the chain is not growing from one end.
fn joint_end(piece: &[SupportPoint]) -> Option<usize> {
    let last = piece.len().checked_sub(1)?;
    let newest = piece.iter().map(|q| q.reading.snapshot()).max()?;
    let (first_s, last_s) = (piece[0].reading.snapshot(), piece[last].reading.snapshot());
    if last_s == newest && first_s < newest {
        Some(last)
    } else if first_s == newest && last_s < newest {
        Some(0)
    } else {
        None
    }
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use crate::mapping::model::map::ReadingRef;

    fn sp(snapshot: usize, sensor: usize, x: f64, y: f64, d: f64) -> SupportPoint {
        SupportPoint {
            point: Point::new(x, y),
            range_m: d,
            reading: ReadingRef::new(snapshot, sensor),
        }
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
            let mut last = None;
            for (k, q) in readings.iter().enumerate() {
                last = Some(memory_step(&mut memory, &[*q], k, p, true, &mut linkage));
            }
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
            ..stacks_on
        };
        let ((t, pieces), held) = run(&stacks_off);
        assert_eq!(pieces.len(), 1);
        assert_eq!((held, t.used.len()), (0, 3));
        assert!(t.stacked.is_empty());
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
                let (t, out) = memory_step(&mut memory, &[q], k, &p, true, &mut linkage);
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
        let mut last = None;
        for (k, q) in readings.iter().enumerate() {
            last = Some(memory_step(&mut memory, &[*q], k, &p, true, &mut linkage));
        }
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
            memory_step(memory, points, snapshot, &p, true, &mut Linkage::default())
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
}
