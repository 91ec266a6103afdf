//! Updating a matched map segment (paper §3.3.2, Figures 1 and 2; docs/algorithm.md §5).
//!
//! End-points are compared by range: the smaller `D` is the higher confidence; on a tie the
//! existing end-point wins. A projected end-point keeps the range of the reading it came from.

use super::fit::{piece_end_points, split_recursive, split_tolerance};
use super::map::{EndPoint, Map, ReadingRef, Segment, SegmentId, SegmentKind, SupportPoint};
use super::merge::absorb_duplicates;
use super::params::Params;
use super::support_list::SupportList;
use super::trace::{
    EndOrigin, EndPointFate, EndRole, Outcome, RefitTrace, Side, SplitTrace, Test, UpdateTrace,
};
use crate::geometry::{
    distance_to_line, fit_line_tls, lerp, projection_param, total_order_key, AlongLine, Point,
};
use std::borrow::Cow;

/// Defining points closer than this (metres) are "nearly coinciding" (§5 fallback).
const COINCIDENT_M: f64 = 1e-6;

/// The supporting points of an updated segment running from `a` to `b`: `old` and `new`
/// together, ordered along it; points at the same place along it are ordered by snapshot, then
/// sensor index (docs/algorithm.md §5).
///
/// `support_cap` (docs/algorithm.md §8, a long-run bound beyond the paper) keeps only that many
/// of the most recent readings; 0 keeps them all, as the paper does.
///
/// ```
/// use sonarmap::geometry::Point;
/// use sonarmap::mapping::map::ReadingRef;
/// use sonarmap::mapping::update::merge_support_points;
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
fn partition_point_near(
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

/// The result of the update rule, before the post-update split test.
#[derive(Clone, Debug, PartialEq)]
pub struct UpdateGeometry {
    /// New end-points, in the existing segment's direction.
    pub ends: [EndPoint; 2],
    /// The two points that define `l_u`.
    pub line: [Point; 2],
    /// What became of each of the four end-points.
    pub fates: Vec<EndPointFate>,
    /// `l_u` is the total-least-squares line of the four end-points.
    pub fallback_tls: bool,
}

struct Labelled {
    origin: EndOrigin,
    end: EndPoint,
}

/// The higher-confidence of `existing` and `new` (smaller range; a tie keeps the existing).
fn more_confident<'a>(existing: &'a Labelled, new: &'a Labelled) -> (&'a Labelled, &'a Labelled) {
    if new.end.range_m < existing.end.range_m {
        (new, existing)
    } else {
        (existing, new)
    }
}

/// A line through `p` and `q`, or, when they nearly coincide, the total-least-squares line of
/// `all`. Returns two points on it and whether the fallback was used.
fn defining_line(p: Point, q: Point, all: &[Point]) -> ([Point; 2], bool) {
    if (q - p).norm() > COINCIDENT_M {
        return ([p, q], false);
    }
    match fit_line_tls(all) {
        Some((centre, dir)) => ([centre, centre + dir], true),
        // All four coincide: a degenerate segment at that point.
        None => ([p, p + nalgebra::Vector2::new(1.0, 0.0)], true),
    }
}

fn fate(l: &Labelled, role: EndRole, compared_with: EndOrigin) -> EndPointFate {
    EndPointFate {
        origin: l.origin,
        before: l.end,
        role,
        compared_with,
        projection: None,
        is_end_after: false,
    }
}

/// The four end-points of an update with their origins: `e_L`, `e_R`, `n_L`, `n_R`.
fn labelled(e: [EndPoint; 2], n_left: EndPoint, n_right: EndPoint) -> [Labelled; 4] {
    let l = |origin, end| Labelled { origin, end };
    [
        l(EndOrigin::ExistingLeft, e[0]),
        l(EndOrigin::ExistingRight, e[1]),
        l(EndOrigin::NewLeft, n_left),
        l(EndOrigin::NewRight, n_right),
    ]
}

/// MATCH (MPC) update, Figure 1: `u_L`, `u_R` are the more confident of `{e_L, n_L}` and
/// `{e_R, n_R}`; `l_u` runs through them; the two others are projected on `l_u` and the result
/// is the longest segment on `l_u` covering all four projections.
///
/// ```
/// use sonarmap::geometry::Point;
/// use sonarmap::mapping::update::update_match;
/// use sonarmap::mapping::EndPoint;
/// let end = |x: f64, y: f64, d: f64| EndPoint { point: Point::new(x, y), range_m: d };
/// // l_e (0,0)–(10,0) read at 60 and 40; l_n (−4,1)–(8,0.2) read at 50 and 45. u_L = n_L
/// // (50 < 60), u_R = e_R (40 < 45): l_u runs from (−4, 1) to (10, 0). e_L and n_R project
/// // inside it, so the result is u_L–u_R, in l_e's direction, each end keeping its range.
/// let g = update_match([end(0.0, 0.0, 60.0), end(10.0, 0.0, 40.0)], end(-4.0, 1.0, 50.0), end(8.0, 0.2, 45.0));
/// assert_eq!(g.ends, [end(-4.0, 1.0, 50.0), end(10.0, 0.0, 40.0)]);
/// assert!(!g.fallback_tls);
/// ```
pub fn update_match(e: [EndPoint; 2], n_left: EndPoint, n_right: EndPoint) -> UpdateGeometry {
    let [el, er, nl, nr] = labelled(e, n_left, n_right);
    let (ul, low_l) = more_confident(&el, &nl);
    let (ur, low_r) = more_confident(&er, &nr);
    let all = [e[0].point, e[1].point, n_left.point, n_right.point];
    let (line, fallback_tls) = defining_line(ul.end.point, ur.end.point, &all);
    let mut fates = vec![
        fate(ul, EndRole::Kept, low_l.origin),
        fate(ur, EndRole::Kept, low_r.origin),
        fate(low_l, EndRole::Projected, ul.origin),
        fate(low_r, EndRole::Projected, ur.origin),
    ];
    // Parameter of each end-point on l_u; kept ones sit on the line unless the fallback is used.
    let params: Vec<f64> = fates
        .iter()
        .map(|f| projection_param(&f.before.point, &line[0], &line[1]))
        .collect();
    for (f, &t) in fates.iter_mut().zip(&params) {
        if f.role == EndRole::Projected || fallback_tls {
            f.projection = Some(lerp(&line[0], &line[1], t));
        }
    }
    // Ends: the kept points unless a projection falls strictly outside them.
    let pick = |want_min: bool| -> usize {
        let mut best = if want_min { 0 } else { 1 };
        for i in 0..4 {
            let better = if want_min {
                params[i] < params[best]
            } else {
                params[i] > params[best]
            };
            if better {
                best = i;
            }
        }
        best
    };
    let (lo, hi) = (pick(true), pick(false));
    // Keep the existing segment's direction: `a` is the end nearer e_L along l_u.
    let e_dir_positive = projection_param(&e[1].point, &line[0], &line[1])
        >= projection_param(&e[0].point, &line[0], &line[1]);
    let (first, second) = if e_dir_positive { (lo, hi) } else { (hi, lo) };
    fates[first].is_end_after = true;
    fates[second].is_end_after = true;
    let end_of = |f: &EndPointFate| EndPoint {
        point: f.projection.unwrap_or(f.before.point),
        range_m: f.before.range_m,
    };
    UpdateGeometry {
        ends: [end_of(&fates[first]), end_of(&fates[second])],
        line,
        fates,
        fallback_tls,
    }
}

/// EXTENSION (EPC) update, Figure 2. With `inside = Left` (`n_L` projects into `l_e`): the
/// middle point `M` is the more confident of `{e_R, n_L}`; of the outer points `e_L` and `n_R`,
/// the more confident stays and `l_u` runs through it and `M`; the other is projected on `l_u`.
/// Symmetric for `inside = Right`. The less confident inner point is dropped.
pub fn update_extension(
    e: [EndPoint; 2],
    n_left: EndPoint,
    n_right: EndPoint,
    inside: Side,
) -> UpdateGeometry {
    let [el, er, nl, nr] = labelled(e, n_left, n_right);
    // (existing inner, new inner, existing outer, new outer)
    let (e_in, n_in, e_out, n_out) = match inside {
        Side::Left => (&er, &nl, &el, &nr),
        Side::Right => (&el, &nr, &er, &nl),
    };
    let (middle, dropped) = more_confident(e_in, n_in);
    let (kept, projected) = more_confident(e_out, n_out);
    let all = [e[0].point, e[1].point, n_left.point, n_right.point];
    let (line, fallback_tls) = defining_line(kept.end.point, middle.end.point, &all);
    let on_line = |p: &Point| lerp(&line[0], &line[1], projection_param(p, &line[0], &line[1]));
    let mut kept_fate = fate(kept, EndRole::Kept, projected.origin);
    let mut projected_fate = fate(projected, EndRole::Projected, kept.origin);
    let mut middle_fate = fate(middle, EndRole::Middle, dropped.origin);
    let dropped_fate = fate(dropped, EndRole::Dropped, middle.origin);
    projected_fate.projection = Some(on_line(&projected.end.point));
    if fallback_tls {
        kept_fate.projection = Some(on_line(&kept.end.point));
        middle_fate.projection = Some(on_line(&middle.end.point));
    }
    kept_fate.is_end_after = true;
    projected_fate.is_end_after = true;
    let end_of = |f: &EndPointFate| EndPoint {
        point: f.projection.unwrap_or(f.before.point),
        range_m: f.before.range_m,
    };
    // The existing outer end stays on its side of the segment.
    let (e_side, n_side) = if kept.origin == e_out.origin {
        (&kept_fate, &projected_fate)
    } else {
        (&projected_fate, &kept_fate)
    };
    let ends = match inside {
        Side::Left => [end_of(e_side), end_of(n_side)],
        Side::Right => [end_of(n_side), end_of(e_side)],
    };
    UpdateGeometry {
        ends,
        line,
        fates: vec![kept_fate, middle_fate, projected_fate, dropped_fate],
        fallback_tls,
    }
}

/// A MATCH or EXTENSION decided for a new segment, to apply to a map segment.
#[derive(Clone, Copy, Debug)]
pub struct UpdateRequest<'a> {
    /// The segment to update: the one that now carries the chosen candidate's id (or the one
    /// it was merged into earlier in the snapshot; docs/algorithm.md §4).
    pub target: SegmentId,
    /// Index of the new segment in the step.
    pub new_index: usize,
    /// The new segment's supporting points.
    pub new_points: &'a [SupportPoint],
    /// The new segment's end-points, oriented like the candidate as it was tested.
    pub new_left: EndPoint,
    /// See `new_left`.
    pub new_right: EndPoint,
    /// MATCH or EXTENSION.
    pub outcome: Outcome,
    /// For an EXTENSION: which end of the new segment projected inside the candidate.
    pub inside: Option<Side>,
    /// The snapshot.
    pub snapshot: usize,
    /// Whether the post-update test fails (the segment is fitted afresh), when a recording of
    /// this very update says so: `Some(false)` spares the test over every supporting point
    /// (thousands, in `paper`). `None`: tested.
    pub refit: Option<bool>,
    /// Whether the segment's supporting points were in order along the updated line, when a
    /// recording of this very update says so ([`UpdateTrace::support_in_order`]): spares the
    /// pass over every point that finds it. `None`: found.
    pub support_in_order: Option<bool>,
}

/// Applies an update to the map (paper §3.3.2; docs/algorithm.md §5): the geometry of Figure 1
/// (MATCH) or Figure 2 (EXTENSION), then the post-update test of the segment's supporting
/// points against `l_u`; when one lies beyond its split tolerance the points are fitted afresh
/// (§3) and the pieces replace the segment, the first keeping its id (a single piece replaces
/// the update's geometry). With `merge_duplicates` (§8.3) the segments the result now matches
/// are fused into it. `None` when the target is not in the map.
pub fn apply_update(
    map: &mut Map,
    params: &Params,
    request: &UpdateRequest<'_>,
) -> Option<UpdateTrace> {
    let target = request.target;
    let seg = map.segment(target)?;
    let before = [seg.a, seg.b];
    // Orient the new segment along the live geometry (it may have moved this snapshot).
    let (nl, nr) = if projection_param(&request.new_left.point, &seg.a.point, &seg.b.point)
        <= projection_param(&request.new_right.point, &seg.a.point, &seg.b.point)
    {
        (request.new_left, request.new_right)
    } else {
        (request.new_right, request.new_left)
    };
    let geometry: UpdateGeometry = match request.inside {
        Some(side) => update_extension(before, nl, nr, side),
        None => update_match(before, nl, nr),
    };
    let [a, b] = geometry.ends;
    let (points, support_in_order) = merge_support_list_as_recorded(
        &seg.points,
        request.new_points,
        &a,
        &b,
        params.support_cap,
        request.support_in_order,
    );
    let worst = match request.refit {
        // Recorded as passing: the test would find nothing to refit.
        Some(false) => None,
        _ => worst_support_test(&points, &geometry.line, params),
    };
    let mut update = UpdateTrace {
        segment: target,
        new_segment: request.new_index,
        outcome: request.outcome,
        before,
        after: geometry.ends,
        line: geometry.line,
        fates: geometry.fates,
        fallback_tls: geometry.fallback_tls,
        refit: None,
        absorbed: Vec::new(),
        support_in_order,
    };
    map.segment_mut(target)?.note_update(request.snapshot);
    match worst {
        Some(w) if !w.pass => {
            let (splits, pieces) = refit_segment(map, params, target, &points);
            if params.merge_duplicates {
                for &piece in &pieces {
                    let absorbed = absorb_duplicates(map, params, piece, &pieces);
                    update.absorbed.extend(absorbed);
                }
            }
            update.refit = Some(RefitTrace {
                worst: w,
                splits,
                pieces,
            });
        }
        _ => {
            map.segment_mut(target)?.points = points;
            map.set_ends(target, a, b);
            // Only a segment that grew past its old end-points can have come to overlap
            // another one.
            if params.merge_duplicates && grew_past(&before, &[a, b]) {
                update.absorbed = absorb_duplicates(map, params, target, &[]);
            }
        }
    }
    Some(update)
}

/// Whether a segment that ran between `before` now reaches past either of them (an end-point
/// of `after` projects outside `before`).
pub fn grew_past(before: &[EndPoint; 2], after: &[EndPoint; 2]) -> bool {
    after.iter().any(|e| {
        let t = projection_param(&e.point, &before[0].point, &before[1].point);
        !(-1e-9..=1.0 + 1e-9).contains(&t)
    })
}

/// The post-update test: each supporting point's distance to `l_u` against its split
/// tolerance. Returns the worst: a failing one when any fails (the farthest beyond its
/// tolerance), else the passing one nearest its tolerance; `None` without points.
fn worst_support_test(points: &SupportList, line: &[Point; 2], params: &Params) -> Option<Test> {
    let mut tests = points.iter().map(|q| {
        let d = distance_to_line(&q.point, &line[0], &line[1]);
        Test::at_most(d, split_tolerance(params, q.range_m))
    });
    // The worst so far as a plain value, not an `Option` folded through: the loop runs over
    // every supporting point of every update (thousands, in `paper`), and the folded option
    // went through memory each time.
    let mut worst = tests.next()?;
    for t in tests {
        // A failing test is worse than a passing one; between two alike, the one further
        // beyond (or nearer) its threshold, the earlier on a tie.
        let keeps = if worst.pass == t.pass {
            worst.value - worst.threshold >= t.value - t.threshold
        } else {
            !worst.pass
        };
        if !keeps {
            worst = t;
        }
    }
    Some(worst)
}

/// Fits the updated segment's points (`support`) afresh (§3): the first piece keeps the id
/// `target`, the others get new ids and follow it in its face. Returns the split tests and the
/// pieces' ids. Each piece's points share the chunks of `support` that lie wholly inside it.
fn refit_segment(
    map: &mut Map,
    params: &Params,
    target: SegmentId,
    support: &SupportList,
) -> (Vec<SplitTrace>, Vec<SegmentId>) {
    let points = &support.to_vec();
    let (mut splits, mut pieces) = (Vec::new(), Vec::new());
    split_recursive(points, params, &mut splits, &mut pieces);
    let Some(seg) = map.segment(target) else {
        return (splits, Vec::new());
    };
    let (face, object, created, updated) = (seg.face, seg.object, seg.created, seg.updated.clone());
    let mut piece_ids = Vec::with_capacity(pieces.len());
    for (k, &[first, last]) in pieces.iter().enumerate() {
        let (pa, pb) = piece_end_points(points, first, last, params.fit);
        let piece_points = support.slice(first..last + 1);
        if k == 0 {
            if let Some(s) = map.segment_mut(target) {
                s.points = piece_points;
            }
            map.set_ends(target, pa, pb);
            piece_ids.push(target);
        } else {
            let id = map.allocate_segment_id();
            map.push_segment(Segment {
                id,
                kind: SegmentKind::Fitted,
                a: pa,
                b: pb,
                face,
                object,
                created,
                updated: updated.clone(),
                points: piece_points,
            });
            piece_ids.push(id);
        }
    }
    if let Some(f) = map.face_mut(face) {
        let at = f
            .segments
            .position(target)
            .map_or(f.segments.len(), |p| p + 1);
        f.segments.insert_at(at, &piece_ids[1..]);
    }
    (splits, piece_ids)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mapping::map::ReadingRef;
    use proptest::prelude::*;

    /// The specification: keep the most recent, then a stable sort by (position, reading).
    fn merged_by_sorting(
        old: &[SupportPoint],
        new: &[SupportPoint],
        a: &EndPoint,
        b: &EndPoint,
        cap: usize,
    ) -> Vec<SupportPoint> {
        let mut all: Vec<SupportPoint> = old.iter().chain(new).copied().collect();
        let mut newest: Vec<ReadingRef> = all.iter().map(|q| q.reading).collect();
        newest.sort_unstable_by(|x, y| y.cmp(x));
        if let Some(&oldest) = cap.checked_sub(1).and_then(|i| newest.get(i)) {
            all.retain(|q| q.reading >= oldest);
        }
        let key = |q: &SupportPoint| projection_param(&q.point, &a.point, &b.point) + 0.0;
        all.sort_by(|x, y| key(x).total_cmp(&key(y)).then(x.reading.cmp(&y.reading)));
        all
    }

    fn support_points(xs: Vec<(i8, u8)>, first_snapshot: usize) -> Vec<SupportPoint> {
        xs.into_iter()
            .enumerate()
            .map(|(i, (x, sensor))| SupportPoint {
                // Few positions and readings, so that ties are common.
                point: Point::new(f64::from(x) / 8.0, 0.01 * f64::from(sensor)),
                range_m: 1.0,
                reading: ReadingRef::new(first_snapshot + i / 8, usize::from(sensor % 3)),
            })
            .collect()
    }

    proptest! {
        #[test]
        fn merging_support_points_or_lists_equals_keeping_the_newest_and_sorting(
            old in proptest::collection::vec((-8i8..8, 0u8..6), 0..400),
            new in proptest::collection::vec((-8i8..8, 0u8..6), 0..70),
            old_order in 0u8..3,
            new_order in 0u8..3,
            interleave in any::<bool>(),
            cap in prop_oneof![Just(0usize), Just(64), 1usize..80],
        ) {
            let (a, b) = (ep(-3.0, 0.0, 1.0), ep(3.0, 0.0, 1.0));
            // 0: as drawn, 1: along a→b, 2: against it.
            let arrange = |points: Vec<SupportPoint>, how: u8| match how {
                0 => points,
                1 => merged_by_sorting(&points, &[], &a, &b, 0),
                _ => merged_by_sorting(&points, &[], &a, &b, 0).into_iter().rev().collect(),
            };
            let old = arrange(support_points(old, 0), old_order);
            let new = arrange(
                support_points(new, if interleave { 3 } else { 100 }),
                new_order,
            );
            let expected = merged_by_sorting(&old, &new, &a, &b, cap);
            prop_assert_eq!(merge_support_points(&old, &new, &a, &b, cap), expected.clone());
            // The same points from the chunked list (several chunks past 128 points).
            let chunked = merge_support_list(&SupportList::from_vec(old), &new, &a, &b, cap);
            prop_assert_eq!(chunked.to_vec(), expected);
        }

        #[test]
        fn a_search_from_a_guess_finds_the_first_index_past_the_turn(
            high in 0usize..300,
            turn in 0usize..300,
            low in 0usize..300,
            guess in 0usize..400,
        ) {
            let (low, turn) = (low.min(high), turn.min(high));
            let found = partition_point_near(low, high, guess, |m| m < turn);
            prop_assert_eq!(found, turn.max(low));
        }
    }

    fn ep(x: f64, y: f64, d: f64) -> EndPoint {
        EndPoint {
            point: Point::new(x, y),
            range_m: d,
        }
    }

    fn role(g: &UpdateGeometry, o: EndOrigin) -> EndRole {
        g.fates.iter().find(|f| f.origin == o).unwrap().role
    }

    #[test]
    fn figure_1_match_keeps_the_closer_ends_and_extends_to_a_projection() {
        // Existing (0,0)-(10,0) read at 60/40; new (-4,1)-(8,0.2) read at 50/45.
        // u_L = n_L? D(n_L)=50 vs D(e_L)=60 → n_L. u_R: D(e_R)=40 vs D(n_R)=45 → e_R.
        let e = [ep(0.0, 0.0, 60.0), ep(10.0, 0.0, 40.0)];
        let g = update_match(e, ep(-4.0, 1.0, 50.0), ep(8.0, 0.2, 45.0));
        assert_eq!(role(&g, EndOrigin::NewLeft), EndRole::Kept);
        assert_eq!(role(&g, EndOrigin::ExistingRight), EndRole::Kept);
        assert_eq!(role(&g, EndOrigin::ExistingLeft), EndRole::Projected);
        assert_eq!(role(&g, EndOrigin::NewRight), EndRole::Projected);
        assert!(!g.fallback_tls);
        // Both projections fall inside [u_L, u_R]: the result is u_L–u_R.
        assert_eq!(g.ends[0], ep(-4.0, 1.0, 50.0));
        assert_eq!(g.ends[1], ep(10.0, 0.0, 40.0));

        // Now e_L is far left but less confident: its projection extends the segment (Figure 1).
        let e = [ep(-10.0, 0.0, 80.0), ep(10.0, 0.0, 40.0)];
        let g = update_match(e, ep(-4.0, 1.0, 50.0), ep(8.0, 0.2, 45.0));
        // l_u: y = 1 - (x + 4)/14. Projection of (-10, 0) onto it.
        let dir = Point::new(10.0, 0.0) - Point::new(-4.0, 1.0);
        let t = (Point::new(-10.0, 0.0) - Point::new(-4.0, 1.0)).dot(&dir) / dir.norm_squared();
        let expect = Point::new(-4.0, 1.0) + dir * t;
        assert!((g.ends[0].point - expect).norm() < 1e-12);
        assert_eq!(
            g.ends[0].range_m, 80.0,
            "a projected end keeps its reading's range"
        );
        let f = g
            .fates
            .iter()
            .find(|f| f.origin == EndOrigin::ExistingLeft)
            .unwrap();
        assert!(f.is_end_after && f.role == EndRole::Projected);
    }

    #[test]
    fn ties_keep_the_existing_end_point() {
        let e = [ep(0.0, 0.0, 50.0), ep(10.0, 0.0, 50.0)];
        let g = update_match(e, ep(1.0, 0.5, 50.0), ep(9.0, 0.5, 50.0));
        assert_eq!(role(&g, EndOrigin::ExistingLeft), EndRole::Kept);
        assert_eq!(role(&g, EndOrigin::ExistingRight), EndRole::Kept);
        assert_eq!(g.ends, e);
    }

    #[test]
    fn figure_2_extension_keeps_the_middle_and_projects_the_weaker_outer_end() {
        // Existing (0,0)-(10,0) at 40/60; new (8,0.3)-(20,1) at 50/70; n_L inside l_e.
        // M = n_L (50 < 60). Outer: e_L 40 vs n_R 70 → e_L kept, n_R projected on e_L–M.
        let e = [ep(0.0, 0.0, 40.0), ep(10.0, 0.0, 60.0)];
        let g = update_extension(e, ep(8.0, 0.3, 50.0), ep(20.0, 1.0, 70.0), Side::Left);
        assert_eq!(role(&g, EndOrigin::NewLeft), EndRole::Middle);
        assert_eq!(role(&g, EndOrigin::ExistingRight), EndRole::Dropped);
        assert_eq!(role(&g, EndOrigin::ExistingLeft), EndRole::Kept);
        assert_eq!(role(&g, EndOrigin::NewRight), EndRole::Projected);
        assert_eq!(g.ends[0], ep(0.0, 0.0, 40.0));
        // Projection of (20, 1) on the line through (0,0) and (8, 0.3).
        let dir = Point::new(8.0, 0.3) - Point::new(0.0, 0.0);
        let t = Point::new(20.0, 1.0).coords.dot(&dir) / dir.norm_squared();
        assert!((g.ends[1].point - Point::from(dir * t)).norm() < 1e-12);
        assert_eq!(g.ends[1].range_m, 70.0);

        // Symmetric: n_R inside, the new outer end more confident than e_R.
        let g = update_extension(e, ep(-12.0, 0.5, 30.0), ep(2.0, 0.1, 45.0), Side::Right);
        // M = e_L (40 < 45); outer n_L (30) beats e_R (60): l_u through n_L and e_L.
        assert_eq!(role(&g, EndOrigin::ExistingLeft), EndRole::Middle);
        assert_eq!(role(&g, EndOrigin::NewLeft), EndRole::Kept);
        assert_eq!(role(&g, EndOrigin::ExistingRight), EndRole::Projected);
        assert_eq!(g.ends[0], ep(-12.0, 0.5, 30.0));
        assert_eq!(g.ends[1].range_m, 60.0);
    }

    #[test]
    fn coinciding_defining_points_fall_back_to_total_least_squares() {
        let e = [ep(0.0, 0.0, 40.0), ep(10.0, 0.0, 40.0)];
        let g = update_extension(e, ep(0.0, 0.0, 30.0), ep(0.0, 0.0, 30.0), Side::Left);
        assert!(g.fallback_tls);
        assert!(g
            .ends
            .iter()
            .all(|e| e.point.x.is_finite() && e.point.y.is_finite()));
    }
}
