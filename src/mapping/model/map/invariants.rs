//! [`Map::check_invariants`]: what must hold of a map after every step (the soak and the
//! property tests check it).

use super::*;

/// Both coordinates finite.
fn finite(p: &Point) -> bool {
    p.x.is_finite() && p.y.is_finite()
}

impl Map {
    /// Checks the map's consistency, between steps: ids unique and below the next free ones;
    /// every face non-empty, naming existing segments that name it back, every segment in its
    /// face once; the spatial index (when built) filing exactly the segments with their boxes;
    /// every coordinate and range finite; support lists within `support_cap` readings (0:
    /// unbounded); update histories in order and within [`MAX_UPDATES_KEPT`]; a feature's radius
    /// 0 or a pillar's, the pillar evidence within its bound. The first broken invariant is
    /// returned.
    pub fn check_invariants(&self, support_cap: usize) -> Result<(), String> {
        self.check_id_order()?;
        self.check_faces()?;
        self.check_links()?;
        self.check_segments(support_cap)?;
        self.check_extension_state()?;
        self.check_features()?;
        self.check_index()
    }

    /// Segment and face ids ascend.
    fn check_id_order(&self) -> Result<(), String> {
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
        Ok(())
    }

    /// Every face is non-empty, below the next id, and names segments of its own; they are all the segments.
    fn check_faces(&self) -> Result<(), String> {
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
        Ok(())
    }

    /// While tracked, every connecting segment joins two segments of the map, and only those are tracked.
    fn check_links(&self) -> Result<(), String> {
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
        Ok(())
    }

    /// Each segment: ids below the next, found at its place, of a face, finite, within `support_cap`, its history in order.
    fn check_segments(&self, support_cap: usize) -> Result<(), String> {
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
        Ok(())
    }

    /// Point memory finite, plane support of present segments, feature ids ascending, pillar evidence bounded and finite.
    fn check_extension_state(&self) -> Result<(), String> {
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
        Ok(())
    }

    /// Each point feature: below the next id, finite, observed, of a pillar's radius or none, its history in order.
    fn check_features(&self) -> Result<(), String> {
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
        Ok(())
    }

    /// The spatial indexes file exactly the segments and the features (a map without its index has none).
    fn check_index(&self) -> Result<(), String> {
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
}
