//! Point memory's linkage (docs/algorithm.md §8.1): remembered readings grouped by single
//! linkage within the memory gap, looked for only around the readings that can seed a group.

use crate::geometry::Point;
use crate::mapping::model::support::ReadingRef;

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

/// `single_linkage_groups`'s work, its vectors kept from one step to the next (point memory
/// links its readings every step).
#[derive(Clone, Debug, Default)]
pub struct Linkage {
    pub(super) parent: Vec<usize>,
    pub(super) by_x: Vec<(f64, usize)>,
    pub(super) group_of_root: Vec<usize>,
    pub(super) group_of: Vec<usize>,
    pub(super) sizes: Vec<usize>,
    pub(super) next: Vec<usize>,
    /// Every group's indices, one group after another.
    pub(super) members: Vec<usize>,
    /// Where each group ends in `members`.
    pub(super) group_ends: Vec<usize>,
    /// The points grouped (point memory's, scratch).
    pub(super) points: Vec<Point>,
    /// Which of them a piece took (point memory's, scratch).
    pub(super) used: Vec<bool>,
    /// The seeds the last step left (`None` until a step has run, or after
    /// [`Linkage::forget`]; [`Linkage::group_from_seeds`]).
    pub(super) seeds: Option<Seeds>,
    /// Breadth-first search's queue and each reading's visit (scratch).
    pub(super) queue: Vec<usize>,
    pub(super) visited: Vec<bool>,
    /// Each group found from the seeds: its first reading, and where it lies in `next`
    /// (scratch).
    pub(super) spans: Vec<(usize, usize, usize)>,
}

/// Which readings of point memory may be in a group big enough to fit, as a step left the
/// memory: those of a group fitted then that stayed.
#[derive(Clone, Debug)]
pub(super) struct Seeds {
    /// One flag a reading.
    pub(super) flags: Vec<bool>,
    /// Each reading's dormant group, named by the group's first reading: a group fitted whole
    /// without a piece to show for it (every piece too short, §8.1), which the same readings
    /// would fit the same way again. It is fitted again once it changes: a reading of it leaves
    /// (it wakes as seeds) or a new reading links to it (a seed itself). Traced steps fit it
    /// every step, so that their record lists every group.
    pub(super) dormant: Vec<Option<ReadingRef>>,
    /// The memory's first and last readings (with the flags' length, a check that it was not
    /// changed elsewhere; [`Linkage::forget`] is the rule).
    pub(super) ends: Option<(ReadingRef, ReadingRef)>,
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
    pub(super) fn group_from_seeds(
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

    /// Groups `points` into `members` and `group_ends` (see `single_linkage_groups`).
    pub(super) fn group(&mut self, points: &[Point], gap_m: f64) {
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mapping::ext::point_memory::tests::paper_with_memory;
    use crate::mapping::ext::point_memory::{memory_step, MemoryClock, MemoryPiece};
    use crate::mapping::model::map::MemoryPoint;
    use crate::mapping::model::map::{ReadingRef, SupportPoint};
    use crate::mapping::model::params::Params;

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
        /// memory as grouping it all afresh, traced or not (untraced, dormant groups and steps
        /// without a seed are skipped).
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
            record in proptest::bool::ANY,
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
                let (t1, p1) = memory_step(&mut kept, &singles, MemoryClock::standing(snapshot), &params, record, &mut kept_linkage);
                let (t2, p2) = memory_step(&mut afresh, &singles, MemoryClock::standing(snapshot), &params, record, &mut afresh_linkage);
                proptest::prop_assert_eq!(&t1, &t2);
                // A piece's group is its place among the groups traced: untraced, none are.
                let points = |p: &[MemoryPiece]| p.iter().map(|q| (record.then_some(q.group), q.points.clone())).collect::<Vec<_>>();
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
        let (trace, _) = memory_step(
            &mut lone,
            &far,
            MemoryClock::standing(0),
            &params,
            true,
            &mut linkage,
        );
        assert!(trace.groups.is_empty() && lone.len() == 3);
        let v = [
            sp(0, 0, 0.0, 0.0, 1.0),
            sp(0, 1, 0.2, 0.2, 1.0),
            sp(0, 2, 0.4, 0.0, 1.0),
        ];
        let mut memory: Vec<MemoryPoint> = v
            .iter()
            .map(|&support| MemoryPoint {
                support,
                travelled_m: 0.0,
            })
            .collect();
        linkage.forget();
        let (trace, pieces) = memory_step(
            &mut memory,
            &[],
            MemoryClock::standing(1),
            &params,
            true,
            &mut linkage,
        );
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
}
