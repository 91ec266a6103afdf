//! The map: line segments with their end-point ranges, faces and objects (paper §3.3).
//! A `Map` is a plain value, cheap to clone: its segments and faces are shared until changed
//! (the replay's checkpoints keep them apart: `crate::checkpoints`).

use super::echo_fit::{MAX_ROUND_RADIUS_M, MIN_ROUND_RADIUS_M};
pub use super::features::{FeatureKind, PointFeature};
use super::id_list::IdList;
pub use super::ids::{FaceId, FeatureId, ObjectId, SegmentId};
use super::index::{IndexedSegment, SegmentGrid};
use super::plane_supports::PlaneSupports;
use super::point_features::Beam;
use super::round_reflectors::ROUND_EVIDENCE_KEPT;
pub use super::support::{EndPoint, ReadingRef, SupportPoint};
use super::support_list::SupportList;
use crate::geometry::{distance_to_segment, Point, Pose};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::sync::Arc;

/// Fitted from readings, or a link made by correlation.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum SegmentKind {
    /// Fitted from readings (§3.2).
    Fitted,
    /// A connecting segment made by correlation (§3.3.3).
    Interpolated,
}

/// A line segment of the map.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Segment {
    /// Stable id.
    pub id: SegmentId,
    /// Fitted or interpolated.
    pub kind: SegmentKind,
    /// First end-point.
    pub a: EndPoint,
    /// Second end-point.
    pub b: EndPoint,
    /// The face it belongs to.
    pub face: FaceId,
    /// The object it belongs to.
    pub object: ObjectId,
    /// Snapshot that created it.
    pub created: usize,
    /// Snapshots that updated it, in order (the most recent [`MAX_UPDATES_KEPT`]); 32 bits
    /// each, since every version of a segment (each checkpoint holding one that changed) keeps
    /// its own copy.
    pub updated: Vec<u32>,
    /// Supporting readings (shared between checkpoints until changed).
    pub points: SupportList,
}

/// Update snapshots a segment remembers, for the inspector (a record, not a rule: no decision
/// reads it; docs/algorithm.md §8.4). A wall seen for an hour is updated thousands of times;
/// keeping every index would make each copy of the segment (a checkpoint taking it over) cost
/// more the longer the run.
pub const MAX_UPDATES_KEPT: usize = 64;

impl Segment {
    /// Records an update by `snapshot` (once per snapshot; the oldest record goes past
    /// [`MAX_UPDATES_KEPT`]).
    pub fn note_update(&mut self, snapshot: usize) {
        let snapshot = u32::try_from(snapshot).expect("snapshot indices fit in 32 bits");
        if self.updated.last() == Some(&snapshot) {
            return;
        }
        if self.updated.len() >= MAX_UPDATES_KEPT {
            self.updated.remove(0);
        }
        self.updated.push(snapshot);
    }

    /// What the spatial index keeps of it.
    pub fn indexed(&self) -> IndexedSegment {
        IndexedSegment {
            a: self.a,
            b: self.b,
            face: self.face,
            fitted: self.kind == SegmentKind::Fitted,
        }
    }

    /// Mid-point.
    pub fn mid(&self) -> Point {
        nalgebra::center(&self.a.point, &self.b.point)
    }

    /// Length, metres.
    pub fn length(&self) -> f64 {
        (self.b.point - self.a.point).norm()
    }

    /// Distance from `p` to the segment.
    pub fn distance_to(&self, p: &Point) -> f64 {
        distance_to_segment(p, &self.a.point, &self.b.point)
    }
}

/// A face: its segments in order along the cluster chain.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Face {
    /// Face id.
    pub id: FaceId,
    /// Segment ids in chain order; the first and last hold the face's outermost end-points
    /// (in shared chunks: a change copies one).
    pub segments: IdList,
}

/// A reading kept by point memory (docs/algorithm.md §8).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct MemoryPoint {
    /// The reading, its point and range.
    pub support: SupportPoint,
}

/// The map after some snapshots.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct Map {
    /// Segments ordered by id, shared between clones until one changes (cheap checkpoints).
    pub segments: Vec<Arc<Segment>>,
    /// Faces ordered by id (shared between clones until one changes).
    pub faces: Vec<Arc<Face>>,
    /// Readings held by point memory.
    pub memory: Vec<MemoryPoint>,
    /// The poses of the last snapshots, oldest first, as many as point memory spans (the plane
    /// test of a remembered reading needs its sensor's place; docs/algorithm.md §8.7).
    #[serde(default)]
    pub recent_poses: Vec<(usize, Pose)>,
    /// Point features (corners and edges, docs/algorithm.md §8.5, and pillars, §8.14), ordered
    /// by id.
    #[serde(default)]
    pub features: Vec<PointFeature>,
    /// Readings of removed corner diagonals, kept as evidence of round pillars
    /// (docs/algorithm.md §8.14), the most recent last.
    #[serde(default)]
    pub round_evidence: Vec<Beam>,
    /// Next unused feature id.
    #[serde(default)]
    pub next_feature_id: FeatureId,
    /// Whether segments must be confirmed (docs/algorithm.md §8.7); without it every segment
    /// counts as confirmed.
    #[serde(default)]
    pub confirms_segments: bool,
    /// Plane support of the segments that have any (docs/algorithm.md §8.7).
    #[serde(default)]
    pub plane_support: PlaneSupports,
    /// Whether connecting segments are tracked ([`Map::link_ends`]): on when segments can
    /// leave the map (`merge_duplicates` or `free_space`, docs/algorithm.md §8.3).
    #[serde(default)]
    pub tracks_links: bool,
    /// The two fitted segments each connecting segment joins, while tracked: a connecting
    /// segment leaves with either of them ([`Map::drop_dangling_links`]).
    #[serde(default)]
    pub link_ends: BTreeMap<SegmentId, [SegmentId; 2]>,
    /// Whether a segment left the map since the last [`Map::drop_dangling_links`].
    #[serde(skip)]
    removed_since_link_sweep: bool,
    /// Next unused segment id.
    pub next_segment_id: SegmentId,
    /// Next unused face id.
    pub next_face_id: FaceId,
    /// Next unused object id.
    pub next_object_id: ObjectId,
    /// Largest end-point range of any segment so far, metres (bounds the matching thresholds).
    pub max_end_range_m: f64,
    /// Spatial index of the segments (rebuilt by [`Map::rebuild_index`] after deserialising).
    #[serde(skip)]
    index: SegmentGrid,
    /// Spatial index of the point features, each filed as a segment of no length (rebuilt
    /// with the segments' index).
    #[serde(skip)]
    feature_index: SegmentGrid,
    /// Position in `segments` of each id ([`NO_SLOT`] when absent) as of when it was last set,
    /// kept with the index; empty without it (lookups then search `segments`). A removal moves
    /// the later segments one place down without touching their entries, so an entry may be
    /// up to `removals_since_reslot` too high (see [`Map::position`]).
    #[serde(skip)]
    slot_of: Vec<u32>,
    /// Removals since every `slot_of` entry was last exact.
    #[serde(skip)]
    removals_since_reslot: usize,
    /// While a step runs ([`Map::begin_face_journal`]): each face as it stood before the step
    /// first changed it, so a step can still ask what the map was before it.
    #[serde(skip)]
    face_journal: Option<Vec<Arc<Face>>>,
}

/// Maps are equal when their contents are; the index is derived from them.
impl PartialEq for Map {
    fn eq(&self, other: &Self) -> bool {
        self.segments == other.segments
            && self.faces == other.faces
            && self.memory == other.memory
            && self.recent_poses == other.recent_poses
            && self.features == other.features
            && self.round_evidence == other.round_evidence
            && self.next_feature_id == other.next_feature_id
            && self.confirms_segments == other.confirms_segments
            && self.plane_support == other.plane_support
            && self.tracks_links == other.tracks_links
            && self.link_ends == other.link_ends
            && self.next_segment_id == other.next_segment_id
            && self.next_face_id == other.next_face_id
            && self.next_object_id == other.next_object_id
            && self.max_end_range_m == other.max_end_range_m
    }
}

/// A point feature as the grid files it: a segment of no length at its place.
fn feature_filing(f: &PointFeature) -> IndexedSegment {
    let e = EndPoint {
        point: f.at,
        range_m: f.range_m,
    };
    IndexedSegment {
        a: e,
        b: e,
        face: 0,
        fitted: true,
    }
}

/// `Map::slot_of` entry of an id not in the map.
const NO_SLOT: u32 = u32::MAX;

/// Removals after which every `Map::slot_of` entry is set afresh (a lookup then searches at
/// most this many places more).
const MAX_REMOVALS_BEFORE_RESLOT: usize = 16;

impl Map {
    /// A map holding `segments` (sorted by id), one face and one object per segment, indexed.
    pub fn from_segments(mut segments: Vec<Segment>) -> Self {
        segments.sort_by_key(|s| s.id);
        let mut map = Map::default();
        for s in segments {
            map.next_segment_id = map.next_segment_id.max(s.id + 1);
            map.next_face_id = map.next_face_id.max(s.face + 1);
            map.next_object_id = map.next_object_id.max(s.object + 1);
            match map.faces.binary_search_by_key(&s.face, |f| f.id) {
                Ok(i) => Arc::make_mut(&mut map.faces[i]).segments.push(s.id),
                Err(i) => map.faces.insert(
                    i,
                    Arc::new(Face {
                        id: s.face,
                        segments: IdList::from_slice(&[s.id]),
                    }),
                ),
            }
            map.push_segment(s);
        }
        map
    }

    /// Position of face `id` in `faces`.
    fn face_position(&self, id: FaceId) -> Option<usize> {
        self.faces.binary_search_by_key(&id, |f| f.id).ok()
    }

    /// Position of segment `id` in `segments`.
    pub fn position(&self, id: SegmentId) -> Option<usize> {
        if self.slot_of.is_empty() {
            return self.segments.binary_search_by_key(&id, |s| s.id).ok();
        }
        let slot = match self.slot_of.get(id as usize) {
            Some(&slot) if slot != NO_SLOT => slot as usize,
            _ => return None,
        };
        // The entry is exact unless removals moved the segment down since it was set.
        if self.segments.get(slot).is_some_and(|s| s.id == id) {
            return Some(slot);
        }
        let low = slot.saturating_sub(self.removals_since_reslot);
        let high = (slot + 1).min(self.segments.len());
        self.segments[low..high]
            .binary_search_by_key(&id, |s| s.id)
            .ok()
            .map(|i| low + i)
    }

    /// The segment with `id`.
    pub fn segment(&self, id: SegmentId) -> Option<&Segment> {
        self.position(id).map(|i| &*self.segments[i])
    }

    /// The segment with `id`, mutable.
    pub fn segment_mut(&mut self, id: SegmentId) -> Option<&mut Segment> {
        self.position(id)
            .map(move |i| Arc::make_mut(&mut self.segments[i]))
    }

    /// The face with `id`.
    pub fn face(&self, id: FaceId) -> Option<&Face> {
        self.face_position(id).map(|i| &*self.faces[i])
    }

    /// The face with `id`, mutable.
    pub fn face_mut(&mut self, id: FaceId) -> Option<&mut Face> {
        let i = self.face_position(id)?;
        self.journal_face(i);
        Some(Arc::make_mut(&mut self.faces[i]))
    }

    /// Starts remembering faces as they stand now, before their first change (see
    /// [`Map::was_outermost`]); any earlier journal is dropped.
    pub(crate) fn begin_face_journal(&mut self) {
        self.face_journal = Some(Vec::new());
    }

    /// Stops remembering faces, and drops the faces the step left empty (kept until now so
    /// that a cluster's later segments can still join the face of its first one).
    pub(crate) fn end_face_journal(&mut self) {
        self.face_journal = None;
        self.faces.retain(|f| !f.segments.is_empty());
    }

    /// Keeps face `faces[i]` as it stands, unless the journal already holds it.
    fn journal_face(&mut self, i: usize) {
        if let Some(journal) = &mut self.face_journal {
            let face = &self.faces[i];
            if !journal.iter().any(|f| f.id == face.id) {
                journal.push(Arc::clone(face));
            }
        }
    }

    /// True when segment `id` of face `face` held an outermost end-point of it when the face
    /// journal began (the map as it stood before the step; [`Map::is_outermost`] without a
    /// journal).
    pub fn was_outermost(&self, id: SegmentId, face: FaceId) -> bool {
        let before = self
            .face_journal
            .iter()
            .flatten()
            .find(|f| f.id == face)
            .map(|f| &**f);
        match before.or_else(|| self.face(face)) {
            Some(f) => f.segments.first() == Some(id) || f.segments.last() == Some(id),
            None => true,
        }
    }

    /// True when segment `id` holds an outermost end-point of its face (first or last in it).
    pub fn is_outermost(&self, id: SegmentId) -> bool {
        self.segment(id)
            .is_some_and(|seg| self.is_outermost_segment(seg))
    }

    /// [`Map::is_outermost`] for a segment at hand.
    pub fn is_outermost_segment(&self, seg: &Segment) -> bool {
        match self.face(seg.face) {
            Some(face) => {
                face.segments.first() == Some(seg.id) || face.segments.last() == Some(seg.id)
            }
            None => true,
        }
    }

    /// Allocates a segment id.
    pub(crate) fn allocate_segment_id(&mut self) -> SegmentId {
        let id = self.next_segment_id;
        self.next_segment_id += 1;
        id
    }

    /// Allocates a face id (and registers the empty face).
    pub(crate) fn new_face(&mut self) -> FaceId {
        let id = self.next_face_id;
        self.next_face_id += 1;
        self.faces.push(Arc::new(Face {
            id,
            segments: IdList::default(),
        }));
        id
    }

    /// Allocates an object id.
    pub(crate) fn allocate_object_id(&mut self) -> ObjectId {
        let id = self.next_object_id;
        self.next_object_id += 1;
        id
    }

    /// Inserts a segment (its id must be the newest).
    pub fn push_segment(&mut self, segment: Segment) {
        debug_assert!(self.segments.last().is_none_or(|s| s.id < segment.id));
        self.note_ends(&segment.a, &segment.b);
        self.index.insert(segment.id, segment.indexed());
        self.set_slot(segment.id, self.segments.len());
        self.segments.push(Arc::new(segment));
    }

    fn set_slot(&mut self, id: SegmentId, slot: usize) {
        let i = id as usize;
        if self.slot_of.len() <= i {
            self.slot_of.resize(i + 1, NO_SLOT);
        }
        self.slot_of[i] = slot as u32;
    }

    /// Removes segment `id` from the map, its face and the index. A face left empty goes too,
    /// at once, or at the end of the step while a step runs ([`Map::end_face_journal`]).
    pub(crate) fn remove_segment(&mut self, id: SegmentId) {
        let Some(i) = self.position(id) else {
            return;
        };
        let face = self.segments.remove(i).face;
        self.index.remove(id);
        self.plane_support.remove(&id);
        if self.tracks_links {
            self.link_ends.remove(&id);
            self.removed_since_link_sweep = true;
        }
        if !self.slot_of.is_empty() {
            self.slot_of[id as usize] = NO_SLOT;
            // Re-slot the later segments only now and then: a lookup searches the few places
            // an entry can have slipped by, and a re-slot reads every later segment.
            self.removals_since_reslot += 1;
            if self.removals_since_reslot > MAX_REMOVALS_BEFORE_RESLOT {
                for (slot, s) in self.segments.iter().enumerate() {
                    self.slot_of[s.id as usize] = slot as u32;
                }
                self.removals_since_reslot = 0;
            }
        }
        if let Some(f) = self.face_position(face) {
            self.journal_face(f);
            Arc::make_mut(&mut self.faces[f]).segments.remove_id(id);
            if self.faces[f].segments.is_empty() && self.face_journal.is_none() {
                self.faces.remove(f);
            }
        }
    }

    /// Moves the end-points of segment `id` (keeping the index current).
    pub(crate) fn set_ends(&mut self, id: SegmentId, a: EndPoint, b: EndPoint) {
        self.note_ends(&a, &b);
        if let Some(s) = self.segment_mut(id) {
            s.a = a;
            s.b = b;
            let indexed = s.indexed();
            self.index.insert(id, indexed);
        }
    }

    fn note_ends(&mut self, a: &EndPoint, b: &EndPoint) {
        for r in [a.range_m, b.range_m] {
            if r.is_finite() && r > self.max_end_range_m {
                self.max_end_range_m = r;
            }
        }
    }

    /// Ids of the segments that may lie within `radius_m` of `p` (a superset), sorted.
    /// A non-finite radius returns every segment.
    pub fn segments_near(&self, p: &Point, radius_m: f64) -> Vec<SegmentId> {
        let mut out = Vec::new();
        self.segments_near_into(p, radius_m, &mut out);
        out.sort_unstable();
        out
    }

    /// [`Map::segments_near`] into `out` (cleared first, to reuse its allocation), in no
    /// particular order.
    pub fn segments_near_into(&self, p: &Point, radius_m: f64, out: &mut Vec<SegmentId>) {
        if !radius_m.is_finite() {
            out.clear();
            out.extend(self.segments.iter().map(|s| s.id));
            return;
        }
        let r = nalgebra::Vector2::new(radius_m, radius_m);
        self.index.query_into(&(p - r), &(p + r), out);
    }

    /// Ids of the segments that may come within `reach_m` of the segment `a`–`b` (their boxes
    /// meet its box widened by `reach_m`; a superset), in no particular order, into `out`.
    pub fn segments_along_into(
        &self,
        a: &Point,
        b: &Point,
        reach_m: f64,
        out: &mut Vec<SegmentId>,
    ) {
        out.clear();
        self.visit_segments_along(a, b, reach_m, |id, _| out.push(id));
    }

    /// Calls `visit` for every segment [`Map::segments_along_into`] returns, with what the index
    /// keeps of it (no lookup of the segment itself). A non-finite reach visits every segment.
    pub fn visit_segments_along(
        &self,
        a: &Point,
        b: &Point,
        reach_m: f64,
        mut visit: impl FnMut(SegmentId, &IndexedSegment),
    ) {
        let widen = nalgebra::Vector2::new(reach_m, reach_m);
        let min = Point::new(a.x.min(b.x), a.y.min(b.y)) - widen;
        let max = Point::new(a.x.max(b.x), a.y.max(b.y)) + widen;
        if [min.x, min.y, max.x, max.y].iter().any(|v| !v.is_finite()) {
            for s in &self.segments {
                visit(s.id, &s.indexed());
            }
            return;
        }
        self.index.visit_box(&min, &max, visit);
    }

    /// Ids of the segments whose bounding box may meet the box `[min, max]` (a superset), in no
    /// particular order, into `out` (cleared first). A non-finite box returns every segment.
    pub fn segments_in_box_into(&self, min: &Point, max: &Point, out: &mut Vec<SegmentId>) {
        if [min.x, min.y, max.x, max.y].iter().any(|v| !v.is_finite()) {
            out.clear();
            out.extend(self.segments.iter().map(|s| s.id));
            return;
        }
        self.index.query_into(min, max, out);
    }

    /// Checks the map's consistency, between steps: ids unique and below the next free ones;
    /// every face non-empty, naming existing segments that name it back, every segment in its
    /// face once; the spatial index (when built) filing exactly the segments with their boxes;
    /// every coordinate and range finite; support lists within `support_cap` readings (0:
    /// unbounded); update histories in order and within [`MAX_UPDATES_KEPT`]; a feature's radius
    /// 0 or a pillar's, the pillar evidence within its bound. The first broken invariant is
    /// returned.
    pub fn check_invariants(&self, support_cap: usize) -> Result<(), String> {
        let finite = |p: &Point| p.x.is_finite() && p.y.is_finite();
        for pair in self.segments.windows(2) {
            if pair[0].id >= pair[1].id {
                return Err(format!(
                    "segment ids out of order: {} then {}",
                    pair[0].id, pair[1].id
                ));
            }
        }
        for pair in self.faces.windows(2) {
            if pair[0].id >= pair[1].id {
                return Err(format!(
                    "face ids out of order: {} then {}",
                    pair[0].id, pair[1].id
                ));
            }
        }
        let mut in_faces = 0;
        for f in &self.faces {
            if f.id >= self.next_face_id {
                return Err(format!("face {} is not below the next id", f.id));
            }
            if f.segments.is_empty() {
                return Err(format!("face {} is empty", f.id));
            }
            for id in f.segments.iter() {
                match self.segment(id) {
                    None => return Err(format!("face {} names missing segment {id}", f.id)),
                    Some(s) if s.face != f.id => {
                        return Err(format!(
                            "face {} names segment {id} of face {}",
                            f.id, s.face
                        ))
                    }
                    Some(_) => {}
                }
            }
            in_faces += f.segments.len();
        }
        if in_faces != self.segments.len() {
            return Err(format!(
                "faces name {in_faces} segments, the map has {}",
                self.segments.len()
            ));
        }
        if self.tracks_links {
            // Between steps every connecting segment is tracked and joins two segments there.
            for s in self
                .segments
                .iter()
                .filter(|s| s.kind == SegmentKind::Interpolated)
            {
                let Some(ends) = self.link_ends.get(&s.id) else {
                    return Err(format!("link {} is not tracked", s.id));
                };
                if ends.iter().any(|&e| self.segment(e).is_none()) {
                    return Err(format!("link {} joins {ends:?}, not all in the map", s.id));
                }
            }
            if let Some(&id) = self
                .link_ends
                .keys()
                .find(|&&id| self.segment(id).is_none())
            {
                return Err(format!("link {id} is tracked but not in the map"));
            }
        }
        for (slot, s) in self.segments.iter().enumerate() {
            let id = s.id;
            if id >= self.next_segment_id || s.object >= self.next_object_id {
                return Err(format!(
                    "segment {id} or its object is not below the next id"
                ));
            }
            if self.position(id) != Some(slot) {
                return Err(format!("segment {id} is not found at its place"));
            }
            if self.face(s.face).is_none() {
                return Err(format!("segment {id} names missing face {}", s.face));
            }
            for e in [s.a, s.b] {
                if !finite(&e.point) || !e.range_m.is_finite() || e.range_m < 0.0 {
                    return Err(format!("segment {id} has a non-finite end-point or range"));
                }
                if e.range_m > self.max_end_range_m {
                    return Err(format!("segment {id} has a range above max_end_range_m"));
                }
            }
            if s.points
                .iter()
                .any(|q| !finite(&q.point) || !q.range_m.is_finite())
            {
                return Err(format!("segment {id} has a non-finite supporting point"));
            }
            if support_cap > 0 {
                let mut readings: Vec<ReadingRef> = s.points.iter().map(|q| q.reading).collect();
                readings.sort_unstable();
                readings.dedup();
                if readings.len() > support_cap {
                    return Err(format!(
                        "segment {id} keeps {} readings, over support_cap {support_cap}",
                        readings.len()
                    ));
                }
            }
            if s.updated.len() > MAX_UPDATES_KEPT || s.updated.windows(2).any(|w| w[0] >= w[1]) {
                return Err(format!(
                    "segment {id} has an update history out of bounds or order"
                ));
            }
        }
        if self
            .memory
            .iter()
            .any(|m| !finite(&m.support.point) || !m.support.range_m.is_finite())
        {
            return Err("point memory holds a non-finite point".to_owned());
        }
        if let Some(id) = self
            .plane_support
            .keys()
            .find(|&&id| self.segment(id).is_none())
        {
            return Err(format!("plane support of missing segment {id}"));
        }
        for pair in self.features.windows(2) {
            if pair[0].id >= pair[1].id {
                return Err(format!(
                    "feature ids out of order: {} then {}",
                    pair[0].id, pair[1].id
                ));
            }
        }
        if self.round_evidence.len() > ROUND_EVIDENCE_KEPT
            || self.round_evidence.iter().any(|e| {
                !finite(&e.origin) || !e.range_m.is_finite() || !e.direction.norm().is_finite()
            })
        {
            return Err("pillar evidence over its bound or not finite".to_string());
        }
        for f in &self.features {
            if f.id >= self.next_feature_id {
                return Err(format!("feature {} is not below the next id", f.id));
            }
            if !finite(&f.at)
                || !finite(&f.first_seen_from)
                || !f.range_m.is_finite()
                || f.range_m < 0.0
                || f.baseline_m.is_nan()
                || f.baseline_m < 0.0
            {
                return Err(format!("feature {} has a non-finite place or range", f.id));
            }
            if f.observations == 0 {
                return Err(format!("feature {} has no observation", f.id));
            }
            if !(f.radius_m == 0.0
                || (MIN_ROUND_RADIUS_M..=MAX_ROUND_RADIUS_M).contains(&f.radius_m))
            {
                return Err(format!(
                    "feature {} has a radius {} neither 0 nor a pillar's",
                    f.id, f.radius_m
                ));
            }
            if f.updated.len() > MAX_UPDATES_KEPT
                || f.updated.windows(2).any(|w| w[0] >= w[1])
                || f.updated.first().is_some_and(|&u| u <= f.created)
            {
                return Err(format!(
                    "feature {} has an update history out of bounds or order",
                    f.id
                ));
            }
        }
        // A map without its index (a checkpoint) has no slots either.
        if !self.slot_of.is_empty() {
            self.index
                .check_files_exactly(self.segments.iter().map(|s| (s.id, s.indexed())))
                .map_err(|e| format!("spatial index: {e}"))?;
            if !self.features.is_empty() {
                self.feature_index
                    .check_files_exactly(self.features.iter().map(|f| (f.id, feature_filing(f))))
                    .map_err(|e| format!("feature index: {e}"))?;
            }
        }
        Ok(())
    }

    /// A copy without the spatial index (for checkpoints); [`Map::rebuild_index`] restores it.
    pub fn without_index(&self) -> Map {
        Map {
            segments: self.segments.clone(),
            ..self.without_index_or_segments()
        }
    }

    /// A copy of everything but its segments and its index.
    pub fn without_index_or_segments(&self) -> Map {
        Map {
            segments: Vec::new(),
            faces: self.faces.clone(),
            memory: self.memory.clone(),
            recent_poses: self.recent_poses.clone(),
            features: self.features.clone(),
            round_evidence: self.round_evidence.clone(),
            next_feature_id: self.next_feature_id,
            confirms_segments: self.confirms_segments,
            plane_support: self.plane_support.clone(),
            tracks_links: self.tracks_links,
            link_ends: self.link_ends.clone(),
            removed_since_link_sweep: false,
            next_segment_id: self.next_segment_id,
            next_face_id: self.next_face_id,
            next_object_id: self.next_object_id,
            max_end_range_m: self.max_end_range_m,
            index: SegmentGrid::default(),
            feature_index: SegmentGrid::default(),
            slot_of: Vec::new(),
            removals_since_reslot: 0,
            face_journal: None,
        }
    }

    /// Files every segment in the spatial index afresh.
    pub fn rebuild_index(&mut self) {
        let kept = self.indexed_segments();
        self.file_all(kept);
    }

    /// A copy with its spatial index built: a saved state's map made live. The same as
    /// cloning and [`Map::rebuild_index`], with fewer waits on memory: the pass that reads
    /// the segments for the index goes first, so the copy's reference counts are found in
    /// the cache.
    pub fn with_index(&self) -> Map {
        let kept = self.indexed_segments();
        let mut map = self.clone();
        map.file_all(kept);
        map
    }

    /// A copy holding `segments` (ordered by id) instead of its own, with its spatial index
    /// built: a checkpoint's map made live, where the checkpoint keeps its segments apart
    /// (see [`crate::checkpoints`]).
    pub fn with_segments_indexed(&self, segments: Vec<Arc<Segment>>) -> Map {
        let mut map = Map {
            segments,
            ..self.without_index_or_segments()
        };
        let kept = map.indexed_segments();
        map.file_all(kept);
        map
    }

    /// What the index keeps of each segment, in order, fetched in a pass of its own: the
    /// segments sit behind pointers all over the heap, and a loop doing nothing else keeps
    /// many of those fetches in flight where the filing's would wait on each in turn.
    fn indexed_segments(&self) -> Vec<(SegmentId, IndexedSegment)> {
        self.segments.iter().map(|s| (s.id, s.indexed())).collect()
    }

    /// Files the segments (`kept`, this map's [`Map::indexed_segments`]) and the point
    /// features afresh, and notes every segment's slot.
    fn file_all(&mut self, kept: Vec<(SegmentId, IndexedSegment)>) {
        self.removals_since_reslot = 0;
        // Segments are listed by id: the last has the largest.
        let ids_below = kept.last().map_or(0, |&(id, _)| id as usize + 1);
        self.slot_of.clear();
        self.slot_of.resize(ids_below, NO_SLOT);
        for (slot, &(id, _)) in kept.iter().enumerate() {
            self.slot_of[id as usize] = slot as u32;
        }
        self.index = SegmentGrid::from_segments(kept, ids_below);
        self.feature_index = SegmentGrid::default();
        for f in &self.features {
            self.feature_index.insert(f.id, feature_filing(f));
        }
    }

    /// An empty map whose segments must be confirmed (docs/algorithm.md §8.7) or not.
    pub fn confirming(confirms_segments: bool) -> Self {
        Map {
            confirms_segments,
            ..Map::default()
        }
    }

    /// Records that connecting segment `link` joins the fitted segments `ends` (when tracked).
    pub(crate) fn note_link(&mut self, link: SegmentId, ends: [SegmentId; 2]) {
        if self.tracks_links {
            self.link_ends.insert(link, ends);
        }
    }

    /// Removes the connecting segments whose fitted segments left the map since the last call
    /// (docs/algorithm.md §8.3), returning their ids in id order: a link to a duplicate that
    /// was fused away, or to a refuted line, joins nothing.
    pub(crate) fn drop_dangling_links(&mut self) -> Vec<SegmentId> {
        if !std::mem::take(&mut self.removed_since_link_sweep) {
            return Vec::new();
        }
        let dangling: Vec<SegmentId> = self
            .link_ends
            .iter()
            .filter(|(_, ends)| ends.iter().any(|&e| self.position(e).is_none()))
            .map(|(&link, _)| link)
            .collect();
        for &link in &dangling {
            self.remove_segment(link);
        }
        self.removed_since_link_sweep = false;
        dangling
    }

    /// Notes the pose of `snapshot`, keeping the last `keep` poses.
    pub(crate) fn note_pose(&mut self, snapshot: usize, pose: Pose, keep: usize) {
        self.recent_poses.push((snapshot, pose));
        let excess = self.recent_poses.len().saturating_sub(keep);
        self.recent_poses.drain(..excess);
    }

    /// The pose of `snapshot`, when it is among the recent ones.
    pub fn recent_pose(&self, snapshot: usize) -> Option<Pose> {
        self.recent_poses
            .iter()
            .rev()
            .find(|(k, _)| *k == snapshot)
            .map(|(_, p)| *p)
    }

    /// Whether segment `id` is tentative: segments must be confirmed and it is not
    /// (docs/algorithm.md §8.7).
    pub fn is_tentative(&self, id: SegmentId) -> bool {
        self.confirms_segments && !self.is_confirmed(id)
    }

    /// Whether readings from two snapshots supported segment `id` as a plane (docs/algorithm.md
    /// §8.7; never while confirmation is off, which records no support).
    pub fn is_confirmed(&self, id: SegmentId) -> bool {
        self.plane_support.is_confirmed(id)
    }

    /// The confirmed point features ([`PointFeature::is_confirmed`]), by id.
    pub fn confirmed_features(&self) -> impl Iterator<Item = &PointFeature> {
        self.features.iter().filter(|f| f.is_confirmed())
    }

    /// Point feature `id`.
    pub fn feature(&self, id: FeatureId) -> Option<&PointFeature> {
        self.features
            .binary_search_by_key(&id, |f| f.id)
            .ok()
            .map(|i| &self.features[i])
    }

    /// Ids of the point features that may lie within `radius_m` of `p` (a superset), sorted.
    pub fn features_near(&self, p: &Point, radius_m: f64) -> Vec<FeatureId> {
        let mut out = Vec::new();
        self.features_near_into(p, radius_m, &mut out);
        out.sort_unstable();
        out
    }

    /// [`Map::features_near`] into `out` (cleared first), in no particular order. Without the
    /// index (a checkpoint), every feature.
    pub fn features_near_into(&self, p: &Point, radius_m: f64, out: &mut Vec<FeatureId>) {
        out.clear();
        if self.feature_index.len() != self.features.len() || !radius_m.is_finite() {
            out.extend(self.features.iter().map(|f| f.id));
            return;
        }
        let r = nalgebra::Vector2::new(radius_m, radius_m);
        self.feature_index.query_into(&(p - r), &(p + r), out);
    }

    /// Adds feature `f` with the next free id (its own is replaced); returns that id.
    pub(crate) fn push_feature(&mut self, mut f: PointFeature) -> FeatureId {
        let id = self.next_feature_id;
        self.next_feature_id += 1;
        f.id = id;
        self.feature_index.insert(id, feature_filing(&f));
        self.features.push(f);
        id
    }

    /// Replaces the feature with `f`'s id by `f`, noting an update by `snapshot`.
    pub(crate) fn replace_feature(&mut self, mut f: PointFeature, snapshot: usize) {
        let Ok(i) = self.features.binary_search_by_key(&f.id, |g| g.id) else {
            return;
        };
        if f.updated.last() != Some(&snapshot) && f.created != snapshot {
            if f.updated.len() >= MAX_UPDATES_KEPT {
                f.updated.remove(0);
            }
            f.updated.push(snapshot);
        }
        self.feature_index.insert(f.id, feature_filing(&f));
        self.features[i] = f;
    }
}

/// A fitted segment from `a` to `b` (metres), both ends at `range_m`, alone in face and
/// object `id`, without supporting readings: the unit tests' wall.
#[cfg(test)]
pub(crate) fn test_wall(id: SegmentId, a: (f64, f64), b: (f64, f64), range_m: f64) -> Segment {
    let end = |(x, y): (f64, f64)| EndPoint {
        point: Point::new(x, y),
        range_m,
    };
    Segment {
        id,
        kind: SegmentKind::Fitted,
        a: end(a),
        b: end(b),
        face: id,
        object: id,
        created: 0,
        updated: Vec::new(),
        points: Vec::new().into(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn segment(id: SegmentId) -> Segment {
        test_wall(id, (0.0, f64::from(id)), (1.0, f64::from(id)), 1.0)
    }

    #[test]
    fn lookups_find_every_segment_through_many_removals_and_pushes() {
        let mut map = Map::from_segments((0..200).map(segment).collect());
        let mut present: Vec<SegmentId> = (0..200).collect();
        let mut next = 200;
        // Remove every third segment from the front half, push a new one now and then, and
        // check every id after each change against a plain search.
        for round in 0..60 {
            let victim = present[(round * 3) % (present.len() / 2)];
            map.remove_segment(victim);
            present.retain(|&id| id != victim);
            if round % 4 == 0 {
                map.next_segment_id = next + 1;
                map.push_segment(segment(next));
                present.push(next);
                next += 1;
            }
            for id in 0..next {
                let expected = present.binary_search(&id).ok();
                assert_eq!(map.position(id), expected, "id {id} after round {round}");
                assert_eq!(map.segment(id).map(|s| s.id), expected.map(|_| id));
            }
        }
        assert_eq!(map.segments.len(), present.len());
    }
}
