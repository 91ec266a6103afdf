//! The map's spatial queries through its grid index, and the index left out of a checkpoint and
//! rebuilt.

use super::*;

impl Map {
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
            travelled_m: self.travelled_m,
            driven_box: self.driven_box,
            last_mapped: self.last_mapped,
            recent_poses: self.recent_poses.clone(),
            recent_reading_poses: self.recent_reading_poses.clone(),
            features: self.features.clone(),
            round_evidence: self.round_evidence.clone(),
            sensor_looks: self.sensor_looks.clone(),
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
}
