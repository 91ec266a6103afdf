//! The two extensions beyond the paper (docs/algorithm.md §8), each off in the `paper` preset.

use super::fit::split_recursive;
use super::map::{MemoryPoint, ReadingRef, SupportPoint};
use super::params::Params;
use super::trace::{ConstantDepthTrace, MemoryGroupTrace, MemoryTrace};
use crate::geometry::{fit_line_tls, AlongLine, Point};
use crate::sonar::balls_intersect;

/// True when two ranges pass the ball test of §1 as ranges: `|D1 − D2| ≤ ξ·(D1 + D2)/100`.
fn same_depth(accuracy_pct: f64, d1: f64, d2: f64) -> bool {
    (d1 - d2).abs() <= accuracy_pct * (d1 + d2) / 100.0
}

/// Constant-depth groups (Leonard and Durrant-Whyte's "regions of constant depth"): within a
/// cluster, each maximal run (scanning in chain order) of three or more consecutive readings
/// whose ranges pass the ball test pairwise is replaced by its middle reading (the lower
/// middle for an even run). Returns the reduced points and what was replaced.
///
/// ```
/// use sonarmap::geometry::Point;
/// use sonarmap::mapping::map::ReadingRef;
/// use sonarmap::mapping::SupportPoint;
/// let q = |sensor: usize, x: f64, y: f64, range_m: f64| SupportPoint {
///     point: Point::new(x, y),
///     range_m,
///     reading: ReadingRef::new(0, sensor),
/// };
/// use sonarmap::mapping::extensions::reduce_constant_depth;
/// // Ranges 2.00, 2.05, 2.10, 3.00 at ξ = 3: |2.00 − 2.10| = 0.10 ≤ 0.03·4.10 = 0.123, so the
/// // first three pass pairwise and become their middle reading (sensor 1); 3.00 fails with all.
/// let chain = [q(0, 0.0, 2.0, 2.0), q(1, 1.0, 2.05, 2.05), q(2, 2.0, 2.1, 2.1), q(3, 3.0, 3.0, 3.0)];
/// let (reduced, groups) = reduce_constant_depth(&chain, 3.0);
/// let sensors: Vec<usize> = reduced.iter().map(|p| p.reading.sensor()).collect();
/// assert_eq!(sensors, vec![1, 3]);
/// assert_eq!(groups[0].sensors, vec![0, 1, 2]);
/// assert_eq!(groups[0].kept_sensor, 1);
/// ```
pub fn reduce_constant_depth(
    points: &[SupportPoint],
    accuracy_pct: f64,
) -> (Vec<SupportPoint>, Vec<ConstantDepthTrace>) {
    let mut out = points.to_vec();
    let traces = reduce_constant_depth_in_place(&mut out, accuracy_pct);
    (out, traces)
}

/// [`reduce_constant_depth`] on `points` itself: each run becomes its middle reading where the
/// run began (a cluster with no run of three keeps its points, and nothing is allocated).
/// Returns what was replaced.
pub fn reduce_constant_depth_in_place(
    points: &mut Vec<SupportPoint>,
    accuracy_pct: f64,
) -> Vec<ConstantDepthTrace> {
    let mut traces = Vec::new();
    // Points are written at `kept`, never past the reading at `i`: every later read is ahead.
    let mut kept = 0;
    let mut i = 0;
    while i < points.len() {
        let mut j = i + 1;
        while j < points.len()
            && points[i..j]
                .iter()
                .all(|q| same_depth(accuracy_pct, q.range_m, points[j].range_m))
        {
            j += 1;
        }
        if j - i >= 3 {
            let middle = points[i + (j - i - 1) / 2];
            traces.push(ConstantDepthTrace {
                sensors: points[i..j].iter().map(|q| q.reading.sensor()).collect(),
                kept_sensor: middle.reading.sensor(),
            });
            points[kept] = middle;
            i = j;
        } else {
            points[kept] = points[i];
            i += 1;
        }
        kept += 1;
    }
    points.truncate(kept);
    traces
}

/// One fitted memory piece that became a new segment.
pub struct MemoryPiece {
    /// Index of its group in `MemoryTrace::groups`.
    pub group: usize,
    /// Its points in order.
    pub points: Vec<SupportPoint>,
}

/// True when `p` and `q` are linked: `|p − q| ≤ gap`. Points apart by more than the gap (with
/// a margin for rounding) along x or y are not, which skips the square root for most pairs and
/// never changes an answer.
fn within_gap(p: &Point, q: &Point, gap_m: f64) -> bool {
    let slack = gap_m * (1.0 + 1e-9);
    if (p.x - q.x).abs() > slack || (p.y - q.y).abs() > slack {
        return false;
    }
    (q - p).norm() <= gap_m
}

/// The single-linkage groups of `points` (two points within `gap_m` of each other are in one
/// group): every group's indices one group after another, each sorted, the groups in the order
/// of their first index; and where each group ends. Pairs are found by a sweep along x, so a
/// memory of `n` readings costs about `n log n`, not `n²`.
#[cfg(test)]
fn single_linkage_groups(points: &[Point], gap_m: f64) -> (Vec<usize>, Vec<usize>) {
    let mut linkage = Linkage::default();
    linkage.group(points, gap_m);
    (linkage.members, linkage.group_ends)
}

/// [`single_linkage_groups`]'s work, its vectors kept from one step to the next (point memory
/// links its readings every step).
#[derive(Clone, Debug, Default)]
pub struct Linkage {
    parent: Vec<usize>,
    by_x: Vec<(f64, usize)>,
    group_of_root: Vec<usize>,
    group_of: Vec<usize>,
    sizes: Vec<usize>,
    next: Vec<usize>,
    /// Every group's indices, one group after another.
    members: Vec<usize>,
    /// Where each group ends in `members`.
    group_ends: Vec<usize>,
    /// The points grouped (point memory's, scratch).
    points: Vec<Point>,
    /// Which of them a piece took (point memory's, scratch).
    used: Vec<bool>,
    /// The seeds the last step left (`None` until a step has run, or after
    /// [`Linkage::forget`]; [`Linkage::group_from_seeds`]).
    seeds: Option<Seeds>,
    /// Breadth-first search's queue and each reading's visit (scratch).
    queue: Vec<usize>,
    visited: Vec<bool>,
    /// Each group found from the seeds: its first reading, and where it lies in `next`
    /// (scratch).
    spans: Vec<(usize, usize, usize)>,
}

/// Which readings of point memory may be in a group big enough to fit, as a step left the
/// memory: those of a group fitted then that stayed.
#[derive(Clone, Debug)]
struct Seeds {
    /// One flag a reading.
    flags: Vec<bool>,
    /// The memory's first and last readings (with the flags' length, a check that it was not
    /// changed elsewhere; [`Linkage::forget`] is the rule).
    ends: Option<(ReadingRef, ReadingRef)>,
}

impl Linkage {
    /// Forgets what the last step left: the memory was changed elsewhere (a map resumed from a
    /// checkpoint), so the next step groups it all afresh.
    pub fn forget(&mut self) {
        self.seeds = None;
    }

    /// The groups of `points` with at least `min_points` readings (the only ones point memory
    /// fits), as [`Linkage::group`] would give them (each sorted, in the order of their first
    /// index), found by breadth-first search from `seeds` alone. Every such group holds a seed
    /// when the seeds are the readings just added and those of last step's fitted groups that
    /// stayed: a group of old readings alone was linked the same way last step, inside a group
    /// at least as big, which was fitted.
    fn group_from_seeds(
        &mut self,
        points: &[Point],
        seeds: &[bool],
        gap_m: f64,
        min_points: usize,
    ) {
        let n = points.len();
        self.visited.clear();
        self.visited.resize(n, false);
        // Each group's readings, one group after another (in `next`, scratch), and where.
        let found = &mut self.next;
        found.clear();
        self.spans.clear();
        for start in (0..n).filter(|&i| seeds[i]) {
            if self.visited[start] {
                continue;
            }
            let from = found.len();
            self.visited[start] = true;
            self.queue.clear();
            self.queue.push(start);
            while let Some(p) = self.queue.pop() {
                found.push(p);
                for q in 0..n {
                    if !self.visited[q] && within_gap(&points[p], &points[q], gap_m) {
                        self.visited[q] = true;
                        self.queue.push(q);
                    }
                }
            }
            if found.len() - from < min_points {
                found.truncate(from);
            } else {
                found[from..].sort_unstable();
                self.spans.push((found[from], from, found.len()));
            }
        }
        // In the order of each group's first index.
        self.spans.sort_unstable();
        self.members.clear();
        self.group_ends.clear();
        for &(_, from, end) in &self.spans {
            self.members.extend_from_slice(&found[from..end]);
            self.group_ends.push(self.members.len());
        }
    }

    /// Groups `points` into `members` and `group_ends` (see [`single_linkage_groups`]).
    fn group(&mut self, points: &[Point], gap_m: f64) {
        let n = points.len();
        fn root(parent: &mut [usize], mut i: usize) -> usize {
            while parent[i] != i {
                parent[i] = parent[parent[i]];
                i = parent[i];
            }
            i
        }
        let parent = &mut self.parent;
        parent.clear();
        parent.extend(0..n);
        // Each index with its x, sorted by x (ties in any order: the groups do not depend on
        // the order pairs are linked in).
        let by_x = &mut self.by_x;
        by_x.clear();
        by_x.extend(points.iter().enumerate().map(|(i, p)| (p.x, i)));
        by_x.sort_unstable_by(|a, b| a.0.total_cmp(&b.0));
        // `within_gap` refuses pairs further apart than this along x.
        let slack = gap_m * (1.0 + 1e-9);
        for (k, &(xi, i)) in by_x.iter().enumerate() {
            for &(xj, j) in &by_x[k + 1..] {
                // A NaN ends the sweep too (it links nothing).
                let dx = xj - xi;
                if dx.is_nan() || dx > slack {
                    break;
                }
                if within_gap(&points[i], &points[j], gap_m) {
                    let (ri, rj) = (root(parent, i), root(parent, j));
                    parent[ri.max(rj)] = ri.min(rj);
                }
            }
        }
        // Group ids in the order of each group's first index; then the indices by group.
        self.group_of_root.clear();
        self.group_of_root.resize(n, usize::MAX);
        self.group_of.clear();
        self.group_of.resize(n, 0);
        self.sizes.clear();
        for i in 0..n {
            let r = root(parent, i);
            if self.group_of_root[r] == usize::MAX {
                self.group_of_root[r] = self.sizes.len();
                self.sizes.push(0);
            }
            self.group_of[i] = self.group_of_root[r];
            self.sizes[self.group_of[i]] += 1;
        }
        self.group_ends.clear();
        let mut end = 0;
        for &size in &self.sizes {
            end += size;
            self.group_ends.push(end);
        }
        self.next.clear();
        self.next
            .extend(self.group_ends.iter().zip(&self.sizes).map(|(e, s)| e - s));
        self.members.clear();
        self.members.resize(n, 0);
        for (i, &g) in self.group_of.iter().enumerate() {
            self.members[self.next[g]] = i;
            self.next[g] += 1;
        }
    }
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
    let horizon = params.memory_snapshots;
    // Last step's seeds, while they still describe this memory; they leave with their readings.
    let ends = |memory: &[MemoryPoint]| {
        Some((
            memory.first()?.support.reading,
            memory.last()?.support.reading,
        ))
    };
    let mut seeds = linkage
        .seeds
        .take()
        .filter(|s| s.flags.len() == memory.len() && s.ends == ends(memory))
        .map(|s| s.flags);
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
    let n = memory.len();
    let mut points = std::mem::take(&mut linkage.points);
    points.clear();
    points.extend(memory.iter().map(|m| m.support.point));
    match seeds.as_mut() {
        Some(seeds) => {
            // The readings just added are seeds.
            seeds.truncate(kept);
            seeds.resize(n, true);
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
    // Next step's seeds: the readings of the groups fitted now that stay.
    let mut next_seeds = seeds.unwrap_or_default();
    next_seeds.clear();
    next_seeds.resize(n, false);
    let (members, group_ends) = (&linkage.members, &linkage.group_ends);
    let used = &mut linkage.used;
    used.clear();
    used.resize(n, false);
    let mut pieces_out = Vec::new();
    // Traced: which leaving readings a segment took (the rest left in stacks). Pieces share
    // their corner readings, so this is told apart per reading, not per piece.
    let mut in_segment = if record { vec![false; n] } else { Vec::new() };
    // Traced: the joints kept this step (§8.16).
    let mut joints = Vec::new();
    let groups = group_ends.iter().scan(0, |start, &end| {
        Some(&members[std::mem::replace(start, end)..end])
    });
    let fitted = groups.filter(|m| m.len() >= params.memory_min_points);
    for (group_index, group) in fitted.enumerate() {
        for &i in group {
            next_seeds[i] = true;
        }
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
                // A joint is in this segment too: should another piece take it, it leaves as
                // a segment's reading.
                if record && !stack {
                    in_segment[i] = true;
                }
                if joint != Some(at) {
                    used[i] = true;
                } else if record {
                    joints.push(i);
                }
            }
            if stack {
                piece_segments.push(None);
                stacks.push(k);
            } else {
                piece_segments.push(Some(pieces_out.len()));
                pieces_out.push(MemoryPiece {
                    group: group_index,
                    points: piece.to_vec(),
                });
            }
        }
        if record {
            trace.groups.push(MemoryGroupTrace {
                points,
                splits,
                pieces,
                piece_segments,
                stacks,
            });
        }
    }
    if record {
        // A joint another piece of its group took left with that piece; a corner two pieces
        // both keep as their joint is one reading held.
        joints.sort_unstable();
        joints.dedup();
        let kept = joints.iter().filter(|&&i| !used[i]);
        trace
            .joints
            .extend(kept.map(|&i| memory[i].support.reading));
    }
    let (mut i, mut kept) = (0, 0);
    memory.retain(|m| {
        let keep = !used[i];
        if !keep && record {
            if in_segment[i] {
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
    linkage.seeds = Some(Seeds {
        flags: next_seeds,
        ends: ends(memory),
    });
    trace.held_after = memory.len();
    (trace, pieces_out)
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
mod tests {
    use super::*;
    use crate::mapping::map::ReadingRef;

    /// The groups by flood fill over every pair, as point memory first found them.
    fn flood_fill_groups(points: &[Point], gap_m: f64) -> (Vec<usize>, Vec<usize>) {
        let n = points.len();
        let mut group_of = vec![usize::MAX; n];
        let (mut members, mut ends) = (Vec::new(), Vec::new());
        for seed in 0..n {
            if group_of[seed] != usize::MAX {
                continue;
            }
            let start = members.len();
            group_of[seed] = ends.len();
            members.push(seed);
            let mut k = start;
            while k < members.len() {
                let p = points[members[k]];
                for other in 0..n {
                    if group_of[other] == usize::MAX && within_gap(&p, &points[other], gap_m) {
                        group_of[other] = ends.len();
                        members.push(other);
                    }
                }
                k += 1;
            }
            members[start..].sort_unstable();
            ends.push(members.len());
        }
        (members, ends)
    }

    proptest::proptest! {
        #[test]
        fn the_sweep_finds_the_groups_a_flood_fill_over_every_pair_finds(
            coords in proptest::collection::vec((0u8..40, 0u8..40), 0..80),
            gap_tenths in 1u8..12,
        ) {
            // Points on a 0.1 m lattice, so that many pairs lie exactly at the gap.
            let points: Vec<Point> = coords
                .iter()
                .map(|&(x, y)| Point::new(f64::from(x) * 0.1, f64::from(y) * 0.1))
                .collect();
            let gap_m = f64::from(gap_tenths) * 0.1;
            proptest::prop_assert_eq!(
                single_linkage_groups(&points, gap_m),
                flood_fill_groups(&points, gap_m)
            );
        }
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(128))]
        /// Point memory grouping from last step's seeds (the readings just added and those of
        /// the groups fitted then that stayed) gives every step the same pieces, trace and
        /// memory as grouping it all afresh.
        #[test]
        fn grouping_from_seeds_is_grouping_afresh(
            steps in proptest::collection::vec(
                proptest::collection::vec((0u8..30, 0u8..30, 5u8..40), 0..5),
                1..60,
            ),
            min_points in 2usize..5,
            gap_tenths in 1u8..5,
            horizon in 1usize..12,
            joints in proptest::bool::ANY,
            stacks in proptest::bool::ANY,
        ) {
            let params = Params {
                memory_snapshots: horizon,
                memory_gap_m: f64::from(gap_tenths) * 0.1,
                memory_min_points: min_points,
                memory_joints: joints,
                memory_stacks: stacks,
                ..Params::paper()
            };
            let (mut kept, mut afresh) = (Vec::new(), Vec::new());
            let (mut kept_linkage, mut afresh_linkage) = (Linkage::default(), Linkage::default());
            for (snapshot, singles) in steps.iter().enumerate() {
                let singles: Vec<SupportPoint> = singles
                    .iter()
                    .enumerate()
                    .map(|(k, &(x, y, d))| {
                        let (x, y) = (f64::from(x) * 0.1, f64::from(y) * 0.1);
                        sp(snapshot, k, x, y, f64::from(d) * 0.1)
                    })
                    .collect();
                afresh_linkage.forget();
                let (t1, p1) = memory_step(&mut kept, &singles, snapshot, &params, true, &mut kept_linkage);
                let (t2, p2) = memory_step(&mut afresh, &singles, snapshot, &params, true, &mut afresh_linkage);
                proptest::prop_assert_eq!(&t1, &t2);
                let points = |p: &[MemoryPiece]| p.iter().map(|q| (q.group, q.points.clone())).collect::<Vec<_>>();
                proptest::prop_assert_eq!(points(&p1), points(&p2));
                proptest::prop_assert_eq!(&kept, &afresh);
            }
        }
    }

    #[test]
    fn a_forgetting_linkage_finds_the_groups_of_a_memory_changed_elsewhere() {
        // A V of three readings 0.28 m apart (gap 0.3048): one group, split into two pieces of
        // two, too few to fit, so it stays in the memory and is fitted again every step. A
        // linkage last used on three lone readings (no group: no seeds) is given this memory,
        // as a map resumed from a checkpoint gives it: once told to forget, it finds the V.
        let params = paper_with_memory();
        let mut linkage = Linkage::default();
        let mut lone = vec![];
        let far = [
            sp(0, 0, 0.0, 0.0, 1.0),
            sp(0, 1, 5.0, 0.0, 1.0),
            sp(0, 2, 9.0, 0.0, 1.0),
        ];
        let (trace, _) = memory_step(&mut lone, &far, 0, &params, true, &mut linkage);
        assert!(trace.groups.is_empty() && lone.len() == 3);
        let v = [
            sp(0, 0, 0.0, 0.0, 1.0),
            sp(0, 1, 0.2, 0.2, 1.0),
            sp(0, 2, 0.4, 0.0, 1.0),
        ];
        let mut memory: Vec<MemoryPoint> =
            v.iter().map(|&support| MemoryPoint { support }).collect();
        linkage.forget();
        let (trace, pieces) = memory_step(&mut memory, &[], 1, &params, true, &mut linkage);
        assert_eq!(trace.groups.len(), 1);
        assert_eq!(trace.groups[0].pieces, vec![[0, 1], [1, 2]]);
        assert!(pieces.is_empty() && memory.len() == 3);
    }

    #[test]
    fn a_reading_without_a_place_is_a_group_of_its_own() {
        let points = [
            Point::new(0.0, 0.0),
            Point::new(f64::NAN, 0.0),
            Point::new(0.2, 0.0),
            Point::new(f64::INFINITY, 0.0),
        ];
        assert_eq!(
            single_linkage_groups(&points, 0.3),
            (vec![0, 2, 1, 3], vec![2, 3, 4])
        );
    }

    fn sp(snapshot: usize, sensor: usize, x: f64, y: f64, d: f64) -> SupportPoint {
        SupportPoint {
            point: Point::new(x, y),
            range_m: d,
            reading: ReadingRef::new(snapshot, sensor),
        }
    }

    #[test]
    fn a_run_of_equal_depths_becomes_its_middle_reading() {
        // Ranges 100, 101, 99, 100 pass pairwise at ξ = 3; then 150 does not.
        let pts = vec![
            sp(0, 0, 0.0, 0.0, 100.0),
            sp(0, 1, 1.0, 0.0, 101.0),
            sp(0, 2, 2.0, 0.0, 99.0),
            sp(0, 3, 3.0, 0.0, 100.0),
            sp(0, 4, 4.0, 0.0, 150.0),
        ];
        let (out, traces) = reduce_constant_depth(&pts, 3.0);
        assert_eq!(
            out.iter().map(|q| q.reading.sensor()).collect::<Vec<_>>(),
            vec![1, 4]
        );
        assert_eq!(
            traces,
            vec![ConstantDepthTrace {
                sensors: vec![0, 1, 2, 3],
                kept_sensor: 1
            }]
        );
        // Two equal readings are not a group.
        let (out, traces) = reduce_constant_depth(&pts[3..], 3.0);
        assert_eq!(out.len(), 2);
        assert!(traces.is_empty());
    }

    /// `paper` with `extended`'s point memory: 10 snapshots, a 12 in gap, three readings.
    fn paper_with_memory() -> Params {
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
