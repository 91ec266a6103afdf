//! The map: line segments with their end-point ranges, faces and objects (paper §3.3).
//! A `Map` is a plain value, cheap to clone: its segments and faces are shared until changed
//! (the replay's checkpoints keep them apart: `crate::checkpoints`).

use crate::geometry::{distance_to_segment, Point, Pose};
use crate::mapping::model::beam::Beam;
use crate::mapping::model::features::MAX_ROUND_RADIUS_M;
use crate::mapping::model::features::MIN_ROUND_RADIUS_M;
use crate::mapping::model::features::ROUND_EVIDENCE_KEPT;
pub use crate::mapping::model::features::{FeatureKind, PointFeature};
use crate::mapping::model::id_list::IdList;
pub use crate::mapping::model::ids::{FaceId, FeatureId, ObjectId, SegmentId};
use crate::mapping::model::index::{IndexedSegment, SegmentGrid};
use crate::mapping::model::plane_supports::PlaneSupports;
pub use crate::mapping::model::support::{EndPoint, ReadingRef, SupportPoint};
use crate::mapping::model::support_list::SupportList;
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
    /// How far the robot had driven when the reading was taken ([`Map::travelled_m`]).
    #[serde(default)]
    pub travelled_m: f64,
}

/// A sensor's recent looks, for cutting away what it saw through (docs/algorithm.md §8.18).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct SensorLooks {
    /// Its last reading.
    pub last: Option<Beam>,
    /// Its last reading that the one before it bore out, with how far the robot had driven
    /// then ([`Map::travelled_m`]): the free space it saw cuts segment parts made after it
    /// while the robot is still within its footprint.
    pub long: Option<(Beam, f64)>,
    /// Until how far driven ([`Map::travelled_m`]) its looks are tested: its range jumped at
    /// an edge within a footprint's width before.
    pub edge_until_m: f64,
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
    /// The distance the robot has driven since the first snapshot, metres: the odometry's
    /// steps summed (point memory's span, docs/algorithm.md §8.1).
    #[serde(default)]
    pub travelled_m: f64,
    /// The bounding box of the poses driven so far, lowest and highest corner (the laps of
    /// [`Map::laps_driven`]); `None` before the first snapshot.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub driven_box: Option<(Point, Point)>,
    /// The last mapped snapshot and its odometry pose, while standstill is on (a snapshot
    /// that stood still since is set aside, docs/algorithm.md §8.19).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub last_mapped: Option<(usize, Pose)>,
    /// The poses of the last snapshots, oldest first, as many as point memory spans (the plane
    /// test of a remembered reading needs its sensor's place; docs/algorithm.md §8.7).
    #[serde(default)]
    pub recent_poses: Vec<(usize, Pose)>,
    /// Each sensor's own pose in those of the recent snapshots whose sonars fired in sequence
    /// (docs/algorithm.md §1.1), oldest first.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub recent_reading_poses: Vec<(usize, Vec<Pose>)>,
    /// Point features (corners and edges, docs/algorithm.md §8.5, and pillars, §8.14), ordered
    /// by id.
    #[serde(default)]
    pub features: Vec<PointFeature>,
    /// Readings of removed corner diagonals, kept as evidence of round pillars
    /// (docs/algorithm.md §8.14), the most recent last.
    #[serde(default)]
    pub round_evidence: Vec<Beam>,
    /// Each sensor's recent looks (docs/algorithm.md §8.18), indexed by sensor.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub sensor_looks: Vec<SensorLooks>,
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
    /// segment leaves with either of them (`Map::drop_dangling_links`).
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
            && self.travelled_m == other.travelled_m
            && self.driven_box == other.driven_box
            && self.last_mapped == other.last_mapped
            && self.recent_poses == other.recent_poses
            && self.recent_reading_poses == other.recent_reading_poses
            && self.features == other.features
            && self.round_evidence == other.round_evidence
            && self.sensor_looks == other.sensor_looks
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

    /// Inserts a new fitted segment `a`–`b` supported by `points` as a piece of segment
    /// `parent`: of its face and object, with its creation snapshot and update history. It is
    /// not yet in the face's order ([`Map::place_after_in_face`]). Its id, or `None` without
    /// `parent`.
    pub(crate) fn push_piece_of(
        &mut self,
        parent: SegmentId,
        a: EndPoint,
        b: EndPoint,
        points: SupportList,
    ) -> Option<SegmentId> {
        let s = self.segment(parent)?;
        let (face, object, created, updated) = (s.face, s.object, s.created, s.updated.clone());
        let id = self.allocate_segment_id();
        self.push_segment(Segment {
            id,
            kind: SegmentKind::Fitted,
            a,
            b,
            face,
            object,
            created,
            updated,
            points,
        });
        Some(id)
    }

    /// Puts `pieces` (of [`Map::push_piece_of`]) into the face of segment `parent`, in order,
    /// right after it (at the face's end when `parent` is not in it).
    pub(crate) fn place_after_in_face(&mut self, parent: SegmentId, pieces: &[SegmentId]) {
        let Some(face) = self.segment(parent).map(|s| s.face) else {
            return;
        };
        if let Some(f) = self.face_mut(face) {
            let at = f
                .segments
                .position(parent)
                .map_or(f.segments.len(), |p| p + 1);
            f.segments.insert_at(at, pieces);
        }
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

mod extension_state;
mod invariants;
mod queries;

#[cfg(test)]
mod tests;
