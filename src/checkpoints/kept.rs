//! A checkpoint as the store keeps it: a mapper state with its segments in runs shared with the
//! checkpoint before, and the bytes it alone keeps alive.

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

/// Consecutive segment ids a run of [`SegmentRuns`] covers. On the `paper` building lap run
/// (100,000 snapshots), the 1,800 to 3,000 segments a late checkpoint interval changes fall
/// in about 350 of 2,500 runs of 64 ids, against 190 of 630 of 256.
const RUN_IDS: usize = 64;

/// A map's segments in runs of `RUN_IDS` consecutive ids (run `r` lists those with ids in
/// `r * RUN_IDS..(r + 1) * RUN_IDS`, in order; a run of ids none of which is in the map is
/// empty), each run shared with the
/// checkpoint before while none of its segments changed. A late `paper` checkpoint changes about
/// 1 % of its segments, so its list of 170,000 segment pointers (1.4 MB, a fifth of what each
/// checkpoint kept alive) becomes a few hundred runs (docs/performance.md, stop 32).
#[derive(Clone, Debug, Default)]
pub struct SegmentRuns {
    pub(super) runs: Vec<Arc<[Arc<Segment>]>>,
    len: usize,
}

impl SegmentRuns {
    /// `segments` (ordered by id) in runs, each sharing the run `previous` holds for the same
    /// ids when that lists the very same segments.
    pub(super) fn new(segments: &[Arc<Segment>], previous: Option<&SegmentRuns>) -> Self {
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
    pub(super) fn len(&self) -> usize {
        self.len
    }

    /// The segments, ordered by id.
    pub(super) fn to_vec(&self) -> Vec<Arc<Segment>> {
        let mut list = Vec::with_capacity(self.len);
        for run in &self.runs {
            list.extend(run.iter().cloned());
        }
        list
    }

    /// Each run with the run `previous` holds for the same ids (empty past its end), when the
    /// two are not the very same run.
    pub(super) fn changed_runs<'a>(
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
pub(super) struct Kept {
    /// The state, its map's list of segments left empty.
    pub(super) state: MapperState,
    pub(super) segments: SegmentRuns,
}

impl Kept {
    /// `state` with `segments` (its map's, ordered by id) in runs, sharing those of `previous`
    /// that did not change.
    pub(super) fn new(
        mut state: MapperState,
        segments: &[Arc<Segment>],
        previous: Option<&Kept>,
    ) -> Self {
        let segments = SegmentRuns::new(segments, previous.map(|p| &p.segments));
        state.map.segments = Vec::new();
        Self { state, segments }
    }

    pub(super) fn next_snapshot(&self) -> usize {
        self.state.next_snapshot
    }

    /// The state with its map made live: its segments listed and filed in its spatial index.
    pub(super) fn live(&self) -> MapperState {
        MapperState {
            map: self.state.map.with_segments_indexed(self.segments.to_vec()),
            last_pose: self.state.last_pose,
            last_t_s: self.state.last_t_s,
            pose_belief: self.state.pose_belief.clone(),
            last_echoes: self.state.last_echoes.clone(),
            next_snapshot: self.state.next_snapshot,
        }
    }
}

/// Bytes that `kept` keeps alive beyond `previous`: its lists of segment runs, faces and
/// remembered points, the runs it does not share with `previous`, and each segment or face
/// (with its heap) not shared with `previous`.
pub(super) fn kept_alive_bytes(previous: Option<&Kept>, kept: &Kept) -> usize {
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
        + map.recent_poses.len() * size_of::<(usize, Pose)>()
        + map
            .recent_reading_poses
            .iter()
            .map(|(_, own)| size_of::<(usize, Vec<Pose>)>() + own.len() * size_of::<Pose>())
            .sum::<usize>();
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
