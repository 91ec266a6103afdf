//! What the extensions keep in the map (docs/algorithm.md §8): connecting segments tracked
//! while segments can leave it (§8.3, §8.6), the recent poses (§8.7, §8.10), confirmation (§8.7)
//! and point features (§8.5, §8.14). Plain bookkeeping: the rules that use it are in
//! `mapping::ext`.

use super::*;

impl Map {
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

    /// Notes the pose of `snapshot` and its sensors' own (`reading_poses`, empty when its
    /// readings were taken at its pose), keeping those of the last `keep` snapshots by number:
    /// a snapshot set aside while the robot stood still (docs/algorithm.md §8.19) has no pose
    /// here, and still counts, so that a pause keeps no older pose than the same run without it.
    pub(crate) fn note_pose(
        &mut self,
        snapshot: usize,
        pose: Pose,
        reading_poses: &[Pose],
        keep: usize,
    ) {
        self.recent_poses.push((snapshot, pose));
        let first_kept = (snapshot + 1).saturating_sub(keep);
        let excess = self.recent_poses.partition_point(|&(k, _)| k < first_kept);
        self.recent_poses.drain(..excess);
        if !reading_poses.is_empty() {
            self.recent_reading_poses
                .push((snapshot, reading_poses.to_vec()));
        }
        let oldest = self.recent_poses.first().map_or(snapshot, |&(k, _)| k);
        self.recent_reading_poses.retain(|(k, _)| *k >= oldest);
    }

    /// The pose reading `reading` was taken from, when its snapshot is among the recent ones:
    /// its sensor's own, or its snapshot's.
    pub fn recent_reading_pose(&self, reading: ReadingRef) -> Option<Pose> {
        let snapshot = reading.snapshot();
        let own = self
            .recent_reading_poses
            .binary_search_by_key(&snapshot, |(k, _)| *k)
            .ok()
            .and_then(|i| {
                self.recent_reading_poses[i]
                    .1
                    .get(reading.sensor())
                    .copied()
            });
        own.or_else(|| self.recent_pose(snapshot))
    }

    /// The pose of `snapshot`, when it is among the recent ones.
    pub fn recent_pose(&self, snapshot: usize) -> Option<Pose> {
        // Oldest first, one a snapshot.
        let i = self
            .recent_poses
            .binary_search_by_key(&snapshot, |&(k, _)| k)
            .ok()?;
        Some(self.recent_poses[i].1)
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

    /// The confirmed fitted segments (walls, not connecting segments), in id order.
    pub fn confirmed_fitted(&self) -> impl Iterator<Item = &Segment> {
        self.segments
            .iter()
            .map(|s| s.as_ref())
            .filter(|s| s.kind == SegmentKind::Fitted && self.is_confirmed(s.id))
    }

    /// How many laps of its map the robot drove: the distance driven ([`Map::travelled_m`])
    /// over the larger of two perimeters, the confirmed fitted walls' bounding box's and the
    /// driven poses' ([`Map::driven_box`]), so that walls confirmed along a short stretch of a
    /// long pass do not count laps never driven (docs/algorithm.md §8.17, "runs that come
    /// back"); `None` without a confirmed wall.
    pub fn laps_driven(&self) -> Option<f64> {
        let walls = bounding_box(self.confirmed_fitted().flat_map(|s| [s.a.point, s.b.point]))?;
        let perimeter_m = |(low, high): (Point, Point)| 2.0 * ((high.x - low.x) + (high.y - low.y));
        let perimeter_m = perimeter_m(walls).max(self.driven_box.map_or(0.0, perimeter_m));
        (perimeter_m > 0.0).then(|| self.travelled_m / perimeter_m)
    }

    /// Widens [`Map::driven_box`] to hold `pose`.
    pub(crate) fn note_driven(&mut self, pose: &Pose) {
        self.driven_box = Some(grown_box(self.driven_box, pose.position()));
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

/// The lowest and highest corners of `points`' bounding box; `None` without a point.
fn bounding_box(points: impl Iterator<Item = Point>) -> Option<(Point, Point)> {
    points.fold(None, |bounds, p| Some(grown_box(bounds, p)))
}

/// The box `bounds` (lowest and highest corners; none yet) widened to hold `p`.
fn grown_box(bounds: Option<(Point, Point)>, p: Point) -> (Point, Point) {
    bounds.map_or((p, p), |(low, high)| (low.inf(&p), high.sup(&p)))
}
