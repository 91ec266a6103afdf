//! Point memory (docs/algorithm.md §8.1; beyond the paper): the readings of one-point clusters
//! kept for some snapshots, grouped and fitted as §3 fits a cluster; with its stacks (§8.15)
//! and joints (§8.16).

use crate::geometry::{fit_line_tls, AlongLine, Point};
use crate::mapping::ext::constant_depth::same_depth;
use crate::mapping::ext::memory_linkage::{Linkage, Seeds};
use crate::mapping::model::map::{MemoryPoint, ReadingRef, SupportPoint};
use crate::mapping::model::params::Params;
use crate::mapping::model::trace::{MemoryGroupTrace, MemoryTrace};
use crate::mapping::paper::fit::split_range;
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
/// the memory but, with `memory_joints`, a piece's joint, `joint_end`, §8.16); with
/// `memory_stacks`, a piece that is a stack (`is_stack`, §8.15) leaves the memory too but is
/// not returned. With `record` false (an untraced step) the trace only says how many readings
/// are held; the memory and the pieces are the same either way. After a first step, only the
/// groups around the readings just added and those fitted last step are looked for
/// (`Linkage::group_from_seeds`): the others are too small to fit; with neither, none is.
pub fn memory_step(
    memory: &mut Vec<MemoryPoint>,
    singles: &[SupportPoint],
    now: MemoryClock,
    params: &Params,
    record: bool,
    linkage: &mut Linkage,
) -> (MemoryTrace, Vec<MemoryPiece>) {
    let mut trace = MemoryTrace::default();
    // Last step's seeds, while they still describe this memory; they leave with their readings.
    let stale = |s: &Seeds| s.flags.len() != memory.len() || s.ends != memory_ends(memory);
    if linkage.seeds.as_ref().is_some_and(stale) {
        linkage.seeds = None;
    }
    let kept = expire_and_add(
        memory,
        singles,
        now,
        params,
        linkage.seeds.as_mut(),
        &mut trace,
        record,
    );
    let unseeded = |s: &&mut Seeds| singles.is_empty() && !s.flags.contains(&true);
    if let Some(s) = linkage.seeds.as_mut().filter(unseeded) {
        // No seed: no group can have changed, so none is fitted and the memory stays.
        s.ends = memory_ends(memory);
        trace.held_after = memory.len();
        return (trace, Vec::new());
    }
    let (mut flags, dormant) = match linkage.seeds.take() {
        Some(s) => (Some(s.flags), s.dormant),
        None => (None, Vec::new()),
    };
    group_memory(memory, flags.as_mut(), kept, params, linkage);
    let n = memory.len();
    // Next step's seeds: the readings of the groups fitted now that stay and lost a reading;
    // those of a group fitted whole for nothing are dormant.
    let mut next = Seeds {
        flags: flags.unwrap_or_default(),
        dormant,
        ends: None,
    };
    next.flags.clear();
    next.flags.resize(n, false);
    next.dormant.resize(n, None);
    let mut taken = Taken {
        used: std::mem::take(&mut linkage.used),
        in_segment: if record { vec![false; n] } else { Vec::new() },
        joints: Vec::new(),
        pieces: Vec::new(),
    };
    taken.used.clear();
    taken.used.resize(n, false);
    fit_groups(
        memory, params, record, linkage, &mut next, &mut taken, &mut trace,
    );
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
    release_taken(memory, &taken, &mut next, &mut trace, record);
    linkage.used = taken.used;
    next.ends = memory_ends(memory);
    linkage.seeds = Some(next);
    trace.held_after = memory.len();
    (trace, taken.pieces)
}

/// Fits each group the linkage found with at least `memory_min_points` readings
/// ([`fit_group`]); in `next`, the readings of a group that lost some are seeds and those of a
/// group fitted whole for nothing dormant, named by its first reading.
fn fit_groups(
    memory: &[MemoryPoint],
    params: &Params,
    record: bool,
    linkage: &Linkage,
    next: &mut Seeds,
    taken: &mut Taken,
    trace: &mut MemoryTrace,
) {
    let (members, group_ends) = (&linkage.members, &linkage.group_ends);
    let groups = group_ends.iter().scan(0, |start, &end| {
        Some(&members[std::mem::replace(start, end)..end])
    });
    let fitted = groups.filter(|m| m.len() >= params.memory_min_points);
    for (group_index, group) in fitted.enumerate() {
        let group_trace = fit_group(memory, group, group_index, params, record, taken);
        let lost_any = group.iter().any(|&i| taken.used[i]);
        let name = memory[group[0]].support.reading;
        for &i in group {
            next.flags[i] = lost_any;
            next.dormant[i] = (!lost_any).then_some(name);
        }
        if let Some(g) = group_trace {
            trace.groups.push(g);
        }
    }
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

/// Where a step stands on point memory's clock: its snapshot, and how far the robot had driven
/// by then ([`crate::mapping::Map::travelled_m`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MemoryClock {
    /// The step's snapshot.
    pub snapshot: usize,
    /// The distance driven since the first snapshot, metres.
    pub travelled_m: f64,
}

impl MemoryClock {
    /// Snapshot `snapshot` of a robot that has not moved.
    pub fn standing(snapshot: usize) -> Self {
        MemoryClock {
            snapshot,
            travelled_m: 0.0,
        }
    }

    /// Whether a reading remembered at `m` is still within the memory's span: taken less than
    /// `memory_snapshots` snapshots ago and, with `memory_travel` on, less than that distance
    /// driven ago (docs/algorithm.md §8.1).
    ///
    /// ```
    /// use sonarmap::mapping::ext::point_memory::MemoryClock;
    /// use sonarmap::mapping::Params;
    /// let p = Params { memory_snapshots: 400, memory_travel_m: 2.54, ..Params::extended() };
    /// let taken = MemoryClock { snapshot: 10, travelled_m: 1.0 };
    /// // 2.5 m and 150 snapshots later: kept; 2.6 m later: driven past the span.
    /// assert!(MemoryClock { snapshot: 160, travelled_m: 3.5 }.keeps(&taken, &p));
    /// assert!(!MemoryClock { snapshot: 160, travelled_m: 3.6 }.keeps(&taken, &p));
    /// // Standing still, 400 snapshots later: too old.
    /// assert!(!MemoryClock { snapshot: 410, travelled_m: 1.0 }.keeps(&taken, &p));
    /// ```
    pub fn keeps(&self, taken: &MemoryClock, params: &Params) -> bool {
        let age = self.snapshot - taken.snapshot.min(self.snapshot);
        let driven_m = self.travelled_m - taken.travelled_m;
        age < params.memory_snapshots
            && (params.memory_travel_m <= 0.0 || driven_m < params.memory_travel_m)
    }
}

/// Readings older than the memory's span leave it (and their seed flags and dormant groups
/// with them), then the step's `singles` join it. A dormant group that lost a reading wakes:
/// its readings are seeds again, as are every dormant group's on a traced step. Returns how
/// many old readings stayed.
fn expire_and_add(
    memory: &mut Vec<MemoryPoint>,
    singles: &[SupportPoint],
    now: MemoryClock,
    params: &Params,
    mut seeds: Option<&mut Seeds>,
    trace: &mut MemoryTrace,
    record: bool,
) -> usize {
    let mut woken = Vec::new();
    let kept = expire(
        memory,
        now,
        params,
        seeds.as_deref_mut(),
        &mut woken,
        trace,
        record,
    );
    if let Some(seeds) = seeds.filter(|_| record || !woken.is_empty()) {
        for (flag, group) in seeds.flags.iter_mut().zip(&mut seeds.dormant) {
            if group.is_some_and(|g| record || woken.contains(&g)) {
                (*flag, *group) = (true, None);
            }
        }
    }
    memory.extend(singles.iter().map(|s| MemoryPoint {
        support: *s,
        travelled_m: now.travelled_m,
    }));
    if record {
        trace.added.extend(singles.iter().map(|s| s.reading));
    }
    kept
}

/// [`expire_and_add`]'s expiry: the readings out of the span leave `memory`, with their seed
/// flags; the dormant groups that lost one go to `woken`. Returns how many stayed.
fn expire(
    memory: &mut Vec<MemoryPoint>,
    now: MemoryClock,
    params: &Params,
    mut seeds: Option<&mut Seeds>,
    woken: &mut Vec<ReadingRef>,
    trace: &mut MemoryTrace,
    record: bool,
) -> usize {
    let keeps = |m: &MemoryPoint| now.keeps(&remembered_at(m), params);
    // The memory holds its readings in the order they came, so those that leave are, as a
    // rule, its oldest: a run at its start, taken out in one move.
    let gone = memory.iter().take_while(|m| !keeps(m)).count();
    if memory[gone..].iter().all(keeps) {
        if gone > 0 {
            if record {
                let expired = memory[..gone].iter().map(|m| m.support.reading);
                trace.expired.extend(expired);
            }
            if let Some(seeds) = seeds {
                woken.extend(seeds.dormant[..gone].iter().flatten());
                seeds.flags.drain(..gone);
                seeds.dormant.drain(..gone);
            }
            memory.drain(..gone);
        }
        return memory.len();
    }
    let (mut i, mut kept) = (0, 0);
    memory.retain(|m| {
        let keep = keeps(m);
        if !keep && record {
            trace.expired.push(m.support.reading);
        }
        if let Some(seeds) = seeds.as_mut() {
            if keep {
                seeds.flags[kept] = seeds.flags[i];
                seeds.dormant[kept] = seeds.dormant[i];
            } else if let Some(group) = seeds.dormant[i] {
                woken.push(group);
            }
        }
        (i, kept) = (i + 1, kept + usize::from(keep));
        keep
    });
    if let Some(seeds) = seeds {
        seeds.flags.truncate(kept);
        seeds.dormant.truncate(kept);
    }
    kept
}

/// Where point memory's clock stood when `m` was remembered.
fn remembered_at(m: &MemoryPoint) -> MemoryClock {
    MemoryClock {
        snapshot: m.support.reading.snapshot(),
        travelled_m: m.travelled_m,
    }
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
    for [first, last] in runs_within_gap(&points, params.memory_gap_m) {
        if first < last {
            split_range(&points, first, last, params, &mut splits, &mut pieces);
        }
    }
    let mut piece_segments = Vec::with_capacity(pieces.len());
    let mut stacks = Vec::new();
    for (k, &[first, last]) in pieces.iter().enumerate() {
        let piece = &points[first..=last];
        if piece.len() < params.memory_min_points {
            piece_segments.push(None);
            continue;
        }
        let stack = params.memory_stacks && is_stack(piece, params.accuracy_pct);
        if !stack && too_short(piece, params) {
            piece_segments.push(None);
            continue;
        }
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
    record.then(|| {
        let cuts = runs_within_gap(&points, params.memory_gap_m)
            .skip(1)
            .map(|[first, _]| first)
            .collect();
        MemoryGroupTrace {
            points,
            splits,
            pieces,
            piece_segments,
            stacks,
            cuts,
        }
    })
}

/// The runs of `points` (ordered along their group's axis) whose neighbours lie within
/// `gap_m` of each other, as `[first, last]` (§8.1): a group is linked within the gap in the
/// plane, but ordered along one axis the readings of a bent chain (two walls at a corner)
/// interleave, and the two walls' readings may meet in a piece across a gap no reading
/// spans, fitting a chord. Each run is split by §3 on its own, as a ring's clusters are
/// broken at `t_gap` (paper §3.1, docs/algorithm.md §2) before they are fitted.
fn runs_within_gap(points: &[SupportPoint], gap_m: f64) -> impl Iterator<Item = [usize; 2]> + '_ {
    let gap_sq = gap_m * gap_m;
    let breaks = (1..points.len())
        .filter(move |&i| (points[i].point - points[i - 1].point).norm_squared() > gap_sq);
    let starts = std::iter::once(0).chain(breaks.clone());
    let ends = breaks.map(|i| i - 1).chain(points.len().checked_sub(1));
    starts.zip(ends).map(|(first, last)| [first, last])
}

/// Whether a piece's end readings lie closer than `memory_min_span` (§8.1): at a crawl, a few
/// centimetres of wall read by one sonar, too short to fix a direction within `θ_o`.
fn too_short(piece: &[SupportPoint], params: &Params) -> bool {
    match (piece.first(), piece.last()) {
        (Some(a), Some(b)) => (b.point - a.point).norm() < params.memory_min_span_m,
        _ => true,
    }
}

/// The readings the step's pieces took leave the memory (traced as used by a segment or
/// stacked), with their seed flags.
fn release_taken(
    memory: &mut Vec<MemoryPoint>,
    taken: &Taken,
    next: &mut Seeds,
    trace: &mut MemoryTrace,
    record: bool,
) {
    if !taken.used.contains(&true) {
        return;
    }
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
            next.flags[kept] = next.flags[i];
            next.dormant[kept] = next.dormant[i];
        }
        (i, kept) = (i + 1, kept + usize::from(keep));
        keep
    });
    next.flags.truncate(kept);
    next.dormant.truncate(kept);
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
pub(super) mod tests;
