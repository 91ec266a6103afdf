//! The supporting points of an updated segment (docs/algorithm.md §5): the old and the new
//! merged in order along the line, in shared chunks, and the `support_cap` bound.

use crate::geometry::{total_order_key, AlongLine};
use crate::mapping::model::map::{EndPoint, ReadingRef, SupportPoint};
use crate::mapping::model::support_list::SupportList;
use std::borrow::Cow;

/// The supporting points of an updated segment running from `a` to `b`: `old` and `new`
/// together, ordered along it; points at the same place along it are ordered by snapshot, then
/// sensor index (docs/algorithm.md §5).
///
/// `support_cap` (docs/algorithm.md §8, a long-run bound beyond the paper) keeps only that many
/// of the most recent readings; 0 keeps them all, as the paper does.
///
/// ```
/// use sonarmap::geometry::Point;
/// use sonarmap::mapping::model::map::ReadingRef;
/// use sonarmap::mapping::paper::support_points::merge_support_points;
/// use sonarmap::mapping::{EndPoint, SupportPoint};
/// let at = |x: f64, snapshot: usize, sensor: usize| SupportPoint {
///     point: Point::new(x, 0.0),
///     range_m: 1.0,
///     reading: ReadingRef::new(snapshot, sensor),
/// };
/// let (a, b) = (
///     EndPoint { point: Point::new(0.0, 0.0), range_m: 1.0 },
///     EndPoint { point: Point::new(2.0, 0.0), range_m: 1.0 },
/// );
/// // Two readings at x = 1: snapshot 3 before snapshot 5, whichever list holds them.
/// let old = [at(0.0, 5, 0), at(1.0, 5, 1)];
/// let new = [at(1.0, 3, 2), at(2.0, 6, 0)];
/// let merged = merge_support_points(&old, &new, &a, &b, 0);
/// let order: Vec<_> = merged.iter().map(|q| (q.point.x, q.reading.snapshot())).collect();
/// assert_eq!(order, [(0.0, 5), (1.0, 3), (1.0, 5), (2.0, 6)]);
/// // A cap of 3 drops the oldest reading (snapshot 3).
/// assert_eq!(merge_support_points(&old, &new, &a, &b, 3).len(), 3);
/// ```
pub fn merge_support_points(
    old: &[SupportPoint],
    new: &[SupportPoint],
    a: &EndPoint,
    b: &EndPoint,
    support_cap: usize,
) -> Vec<SupportPoint> {
    let oldest_kept = oldest_reading_kept(old, new, support_cap);
    let kept = |q: &&SupportPoint| oldest_kept.is_none_or(|r| q.reading >= r);
    // Position along a→b, computed once a point (dropped points too: they are skipped when
    // the result is written).
    let line = AlongLine::new(&a.point, &b.point);
    // `+ 0.0` makes -0 and 0 one place, as "the same place" means.
    let mut keys: Vec<f64> = old
        .iter()
        .chain(new)
        .map(|q| line.param(&q.point) + 0.0)
        .collect();
    let (old_keys, new_keys) = keys.split_at_mut(old.len());
    let (mut old_run, mut new_run) = (Cow::Borrowed(old), Cow::Borrowed(new));
    if put_in_order(old_keys, &mut old_run) && put_in_order(new_keys, &mut new_run) {
        // The usual case (old points in order along a nearby line, new ones along the chain):
        // each new point goes after every old one that does not come after it (ties: old
        // first, as a stable sort orders them), found by a search (`insertion_indices`).
        // Sized exactly (points that share a reading, as split pieces share their corner, can
        // keep a few over the cap): the list lives on in the map and its checkpoints.
        let kept_count = match oldest_kept {
            None => old.len() + new.len(),
            Some(_) => old.iter().chain(new).filter(kept).count(),
        };
        let mut merged = Vec::with_capacity(kept_count);
        // The runs of old points between new ones, copied whole when every point is kept (the
        // paper's unbounded lists: thousands of points an update).
        let keep_run = |merged: &mut Vec<SupportPoint>, run: &[SupportPoint]| match oldest_kept {
            None => merged.extend_from_slice(run),
            Some(_) => merged.extend(run.iter().filter(kept)),
        };
        let kept_new = new_keys
            .iter()
            .copied()
            .zip(new_run.iter())
            .filter(|(_, r)| kept(r));
        let mut i = 0;
        for ((_, r), at) in kept_new.clone().zip(insertion_indices(
            old_run.len(),
            |k| (old_keys[k], old_run[k].reading),
            kept_new,
        )) {
            keep_run(&mut merged, &old_run[i..at]);
            merged.push(*r);
            i = at;
        }
        keep_run(&mut merged, &old_run[i..]);
        return merged;
    }
    // Otherwise sort the kept points by (place, reading), ties in list order as a stable sort
    // leaves them: small sort keys (the place as an integer in `total_cmp` order, and the
    // point's index) instead of the points themselves.
    let (old_run, new_run) = (&*old_run, &*new_run);
    let mut sorted: Vec<(u64, ReadingRef, usize)> = keys
        .iter()
        .zip(old_run.iter().chain(new_run))
        .enumerate()
        .filter(|(_, (_, q))| kept(q))
        .map(|(i, (&k, q))| (total_order_key(k), q.reading, i))
        .collect();
    sorted.sort_unstable();
    let point = |i: usize| {
        if i < old_run.len() {
            old_run[i]
        } else {
            new_run[i - old_run.len()]
        }
    };
    sorted.iter().map(|&(_, _, i)| point(i)).collect()
}

/// [`merge_support_points`] for a segment's chunked list: when every point is kept (no cap)
/// and both runs are in order along a→b (the usual case), the new points are inserted into the
/// chunks they fall in and the other chunks stay shared; otherwise the lists are merged whole.
/// The points, and their order, are the same either way.
pub fn merge_support_list(
    old: &SupportList,
    new: &[SupportPoint],
    a: &EndPoint,
    b: &EndPoint,
    support_cap: usize,
) -> SupportList {
    merge_support_list_as_recorded(old, new, a, b, support_cap, None).0
}

/// [`merge_support_list`], also returning whether the old list was found in order along a→b
/// (`None` when that was not asked: one chunk, a cap, or new points out of order). With
/// `old_in_order`, the answer a recording of this very merge gave, the pass over every old
/// point that finds it is spared (a replay catching up takes it again).
pub fn merge_support_list_as_recorded(
    old: &SupportList,
    new: &[SupportPoint],
    a: &EndPoint,
    b: &EndPoint,
    support_cap: usize,
    old_in_order: Option<bool>,
) -> (SupportList, Option<bool>) {
    if let Some(slice) = old.as_slice() {
        return (
            merge_support_points(slice, new, a, b, support_cap).into(),
            None,
        );
    }
    let mut asked = None;
    if support_cap == 0 {
        let line = AlongLine::new(&a.point, &b.point);
        let key = |q: &SupportPoint| line.param(&q.point) + 0.0;
        let mut new_keys: Vec<f64> = new.iter().map(key).collect();
        let mut new = Cow::Borrowed(new);
        let in_order = put_in_order(&mut new_keys, &mut new)
            && *asked.insert(old_in_order.unwrap_or_else(|| chunks_in_place_order(old, key)));
        if in_order {
            let starts: Vec<usize> = old
                .chunks()
                .iter()
                .scan(0, |start, c| {
                    let s = *start;
                    *start += c.len();
                    Some(s)
                })
                .collect();
            // Places are computed where the searches look, not for every point.
            let old_place = |k: usize| {
                let c = starts.partition_point(|&s| s <= k) - 1;
                let q = &old.chunks()[c][k - starts[c]];
                (key(q), q.reading)
            };
            let pairs = new_keys.iter().copied().zip(new.iter());
            let at: Vec<usize> = insertion_indices(old.len(), old_place, pairs).collect();
            return (old.with_inserted(&new, &at), asked);
        }
    }
    let merged = merge_support_points(&old.to_vec(), new, a, b, support_cap).into();
    (merged, asked)
}

/// True when a chunked list is in [`place_order`] by `key`: one pass, a chunk at a time (it
/// runs over every supporting point of every update of a long `paper` wall, so each chunk's
/// places are computed together, then compared; readings only where places tie).
fn chunks_in_place_order(list: &SupportList, key: impl Fn(&SupportPoint) -> f64) -> bool {
    const BLOCK: usize = 32;
    let mut keys = [0.0; BLOCK];
    let mut previous: Option<(f64, ReadingRef)> = None;
    for chunk in list.chunks() {
        for block in chunk.chunks(BLOCK) {
            let keys = &mut keys[..block.len()];
            for (k, q) in keys.iter_mut().zip(block) {
                *k = key(q);
            }
            // `k < l` settles most pairs without the full comparison.
            let in_order = |k: f64, r: &ReadingRef, l: f64, s: &ReadingRef| {
                k < l || place_order(k, r, l, s).is_le()
            };
            if let Some((pk, pr)) = previous {
                if !in_order(pk, &pr, keys[0], &block[0].reading) {
                    return false;
                }
            }
            let pairs = keys.windows(2).zip(block.windows(2));
            if !pairs.fold(true, |ok, (k, q)| {
                ok & in_order(k[0], &q[0].reading, k[1], &q[1].reading)
            }) {
                return false;
            }
            previous = Some((keys[block.len() - 1], block[block.len() - 1].reading));
        }
    }
    true
}

/// The order of supporting points along a line: by place (`k` against `l`), then by reading.
fn place_order(k: f64, q: &ReadingRef, l: f64, r: &ReadingRef) -> std::cmp::Ordering {
    k.total_cmp(&l).then_with(|| q.cmp(r))
}

/// True when the run is in [`place_order`]; a run in strictly descending order (points listed
/// against a→b) is turned round first: the same order a sort gives, since no two of its
/// elements tie.
fn put_in_order(keys: &mut [f64], run: &mut Cow<'_, [SupportPoint]>) -> bool {
    if in_place_order(keys.iter().copied().zip(run.iter())) {
        return true;
    }
    let pairs = || keys.windows(2).zip(run.windows(2));
    if pairs().all(|(k, q)| place_order(k[0], &q[0].reading, k[1], &q[1].reading).is_gt()) {
        keys.reverse();
        run.to_mut().reverse();
        return true;
    }
    false
}

/// True when the (place, point) pairs are in [`place_order`].
fn in_place_order<'a>(mut pairs: impl Iterator<Item = (f64, &'a SupportPoint)>) -> bool {
    let Some(mut previous) = pairs.next() else {
        return true;
    };
    pairs.all(|p| {
        let in_order = place_order(previous.0, &previous.1.reading, p.0, &p.1.reading).is_le();
        previous = p;
        in_order
    })
}

/// Where each new point goes among `old_len` old points in order (`old_place` gives one's
/// place and reading): the index of the first old point that comes after it, ties
/// going to the old point (as a stable sort orders them). `new` must be in order too.
///
/// Each search starts where the point's place falls between the first and the last old
/// point's, as if the old points were evenly spread along the line (readings along a wall
/// nearly are), and gallops out from there: on a `paper` wall of thousands of points, a
/// bisection fetched a dozen chunks from memory for each new point (docs/performance.md, stop
/// 32). The result is the bisection's: the first old point that comes after it.
fn insertion_indices<'a>(
    old_len: usize,
    old_place: impl Fn(usize) -> (f64, ReadingRef) + 'a,
    new: impl Iterator<Item = (f64, &'a SupportPoint)> + 'a,
) -> impl Iterator<Item = usize> + 'a {
    let ends = (old_len > 1).then(|| (old_place(0).0, old_place(old_len - 1).0));
    let mut i = 0;
    new.map(move |(l, r)| {
        let comes_before = |m: usize| {
            let (k, reading) = old_place(m);
            place_order(k, &reading, l, &r.reading).is_le()
        };
        let guess = match ends {
            Some((first, last)) if last > first => {
                let share = (l - first) / (last - first);
                // NaN (a place not on the line) goes to the start.
                (share.clamp(0.0, 1.0) * (old_len - 1) as f64) as usize
            }
            _ => i,
        };
        i = partition_point_near(i, old_len, guess, comes_before);
        i
    })
}

/// The first index in `low..high` at which `comes_before` turns false (`high` when it never
/// does), for a `comes_before` true up to some index and false after it: probed at `guess`
/// (clamped into the range) first, then at doubling steps away from it until the turn is
/// bracketed, then by bisection inside the bracket.
pub(super) fn partition_point_near(
    low: usize,
    high: usize,
    guess: usize,
    comes_before: impl Fn(usize) -> bool,
) -> usize {
    if low >= high {
        return low;
    }
    let g = guess.clamp(low, high - 1);
    // The turn lies in `lo..=hi`: `comes_before` holds below `lo` and fails from `hi` on.
    let (mut lo, mut hi);
    if comes_before(g) {
        (lo, hi) = (g + 1, high);
        let mut step = 1;
        while lo + step - 1 < high {
            let probe = lo + step - 1;
            if comes_before(probe) {
                lo = probe + 1;
                step *= 2;
            } else {
                hi = probe;
                break;
            }
        }
    } else {
        (lo, hi) = (low, g);
        let mut step = 1;
        while hi >= low + step {
            let probe = hi - step;
            if comes_before(probe) {
                lo = probe + 1;
                break;
            }
            hi = probe;
            step *= 2;
        }
    }
    while lo < hi {
        let mid = lo + (hi - lo) / 2;
        if comes_before(mid) {
            lo = mid + 1;
        } else {
            hi = mid;
        }
    }
    lo
}

/// Keeps the `support_cap` most recent of `points` (all when the cap is 0), in their order:
/// a new segment's points, as an update keeps them (docs/algorithm.md §8).
pub fn cap_support_points(points: &mut Vec<SupportPoint>, support_cap: usize) {
    if let Some(oldest) = oldest_reading_kept(points, &[], support_cap) {
        points.retain(|q| q.reading >= oldest);
    }
}

/// The oldest reading among the `support_cap` most recent of `old` and `new` (`None` when all
/// fit or the cap is 0). An update usually drops only a few: those are found with a small
/// buffer instead of a selection over all of them.
fn oldest_reading_kept(
    old: &[SupportPoint],
    new: &[SupportPoint],
    support_cap: usize,
) -> Option<ReadingRef> {
    const SMALL: usize = 16;
    if support_cap == 0 {
        return None;
    }
    let total = old.len() + new.len();
    let dropped = total.checked_sub(support_cap).filter(|&d| d > 0)?;
    let readings = old.iter().chain(new).map(|q| q.reading);
    // The oldest kept is the one with `dropped` older than it: the (dropped + 1)-th oldest.
    if dropped < SMALL {
        let mut oldest = [ReadingRef::new(0, 0); SMALL];
        let mut len = 0;
        for r in readings {
            if len <= dropped {
                len += 1;
            } else if r >= oldest[dropped] {
                continue;
            }
            // Insert in order into oldest[..len], the last one falling off when full.
            let mut at = len - 1;
            while at > 0 && oldest[at - 1] > r {
                oldest[at] = oldest[at - 1];
                at -= 1;
            }
            oldest[at] = r;
        }
        return Some(oldest[dropped]);
    }
    let mut all: Vec<ReadingRef> = readings.collect();
    let (_, nth, _) = all.select_nth_unstable(dropped);
    Some(*nth)
}
