//! The map's plane support of its segments (docs/algorithm.md §8.7), by segment id.
//!
//! Looked up for every segment a reading's query meets (is it confirmed?) and listed once a
//! step (the confirmed walls, §8.12), so it is a vector ordered by id: a lookup is a binary
//! search over contiguous entries, a listing one pass. An entry is added when a segment first
//! gains support and removed when it leaves, far less often. It reads and writes as a map from
//! id to support, as the map file always had it.

use super::confirm::PlaneSupport;
use super::map::SegmentId;
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use std::collections::BTreeMap;

/// Plane support by segment id, ordered by id.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct PlaneSupports {
    entries: Vec<(SegmentId, PlaneSupport)>,
}

impl PlaneSupports {
    /// The support of segment `id`.
    pub fn get(&self, id: &SegmentId) -> Option<&PlaneSupport> {
        self.position(*id).ok().map(|i| &self.entries[i].1)
    }

    /// The support of segment `id`, added (empty) if it had none.
    pub fn or_default(&mut self, id: SegmentId) -> &mut PlaneSupport {
        let i = match self.position(id) {
            Ok(i) => i,
            Err(i) => {
                self.entries.insert(i, (id, PlaneSupport::default()));
                i
            }
        };
        &mut self.entries[i].1
    }

    /// Sets the support of segment `id`; returns what it had.
    pub fn insert(&mut self, id: SegmentId, support: PlaneSupport) -> Option<PlaneSupport> {
        match self.position(id) {
            Ok(i) => Some(std::mem::replace(&mut self.entries[i].1, support)),
            Err(i) => {
                self.entries.insert(i, (id, support));
                None
            }
        }
    }

    /// Removes the support of segment `id`; returns what it had.
    pub fn remove(&mut self, id: &SegmentId) -> Option<PlaneSupport> {
        let i = self.position(*id).ok()?;
        Some(self.entries.remove(i).1)
    }

    /// Segments with support.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// True when no segment has support.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// The ids of the segments with support, in order.
    pub fn keys(&self) -> impl Iterator<Item = &SegmentId> {
        self.entries.iter().map(|(id, _)| id)
    }

    /// Each segment's id and support, in id order.
    pub fn iter(&self) -> impl Iterator<Item = (&SegmentId, &PlaneSupport)> {
        self.entries.iter().map(|(id, s)| (id, s))
    }

    fn position(&self, id: SegmentId) -> Result<usize, usize> {
        self.entries.binary_search_by_key(&id, |&(k, _)| k)
    }
}

impl Serialize for PlaneSupports {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.collect_map(self.iter())
    }
}

impl<'de> Deserialize<'de> for PlaneSupports {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let by_id = BTreeMap::<SegmentId, PlaneSupport>::deserialize(deserializer)?;
        Ok(Self {
            entries: by_id.into_iter().collect(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn support(snapshots: u32) -> PlaneSupport {
        PlaneSupport {
            snapshots,
            last_snapshot: 7,
        }
    }

    proptest::proptest! {
        /// Any sequence of additions, updates and removals leaves what a B-tree map would hold,
        /// in order, and reads back the same from JSON.
        #[test]
        fn it_holds_what_a_btree_map_holds(
            ops in proptest::collection::vec((0u8..3, 0u32..40, 0u32..4), 0..120),
        ) {
            let (mut ours, mut theirs) = (PlaneSupports::default(), BTreeMap::new());
            for (op, id, n) in ops {
                match op {
                    0 => proptest::prop_assert_eq!(ours.insert(id, support(n)), theirs.insert(id, support(n))),
                    1 => {
                        ours.or_default(id).snapshots += n;
                        theirs.entry(id).or_insert_with(PlaneSupport::default).snapshots += n;
                    }
                    _ => proptest::prop_assert_eq!(ours.remove(&id), theirs.remove(&id)),
                }
                proptest::prop_assert_eq!(ours.len(), theirs.len());
            }
            let listed: Vec<_> = ours.iter().map(|(k, v)| (*k, *v)).collect();
            let expected: Vec<_> = theirs.iter().map(|(k, v)| (*k, *v)).collect();
            proptest::prop_assert_eq!(&listed, &expected);
            for id in 0..40 {
                proptest::prop_assert_eq!(ours.get(&id), theirs.get(&id));
            }
            let json = serde_json::to_string(&ours).unwrap();
            proptest::prop_assert_eq!(&json, &serde_json::to_string(&theirs).unwrap());
            let back: PlaneSupports = serde_json::from_str(&json).unwrap();
            proptest::prop_assert_eq!(back, ours);
        }
    }
}
