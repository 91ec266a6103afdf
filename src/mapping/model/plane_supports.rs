//! The map's plane support of its segments (docs/algorithm.md §8.7), by segment id.
//!
//! Looked up for every segment a reading's query meets (is it confirmed?) and listed once a
//! step (the confirmed walls, §8.12), so it is a vector ordered by id: a lookup is a binary
//! search over contiguous entries, a listing one pass. An entry is added when a segment first
//! gains support and removed when it leaves, far less often. Whether a segment is confirmed is
//! asked far more often still (every segment a query meets, §8.6 and §8.12), so a bit set by id
//! answers it without a search. It reads and writes as a map from id to support, as the map
//! file always had it.

use crate::mapping::model::ids::SegmentId;
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use std::collections::BTreeMap;

/// Snapshots whose readings support a segment as a plane before it is confirmed.
pub const CONFIRMING_SNAPSHOTS: u32 = 2;

/// What the map keeps of a segment's plane support.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct PlaneSupport {
    /// Distinct snapshots whose readings supported it as a plane.
    pub snapshots: u32,
    /// The latest of them.
    pub last_snapshot: usize,
    /// Where the robot stood at the latest of them, millimetres (x, y): a view counts when the
    /// robot stood `confirm_spacing` from there (docs/algorithm.md §8.7). Not written to map
    /// files.
    #[serde(skip)]
    pub last_view_mm: [i32; 2],
}

impl PlaneSupport {
    /// Confirmed: supported by [`CONFIRMING_SNAPSHOTS`] snapshots.
    pub fn confirmed(&self) -> bool {
        self.snapshots >= CONFIRMING_SNAPSHOTS
    }

    /// At least one view counted: the supporting views a segment holds toward its
    /// confirmation (a support recorded from the last view's place counts none).
    pub fn counted(&self) -> bool {
        self.snapshots > 0
    }
}

/// Plane support by segment id, ordered by id.
#[derive(Clone, Debug, Default)]
pub struct PlaneSupports {
    entries: Vec<(SegmentId, PlaneSupport)>,
    /// Bit `id` set when segment `id` is confirmed ([`PlaneSupport::confirmed`]).
    confirmed_bits: Vec<u64>,
}

impl PartialEq for PlaneSupports {
    /// The same supports (the bit set follows from them).
    fn eq(&self, other: &Self) -> bool {
        self.entries == other.entries
    }
}

impl Eq for PlaneSupports {}

impl PlaneSupports {
    /// The support of segment `id`.
    pub fn get(&self, id: &SegmentId) -> Option<&PlaneSupport> {
        self.position(*id).ok().map(|i| &self.entries[i].1)
    }

    /// Whether segment `id` is confirmed ([`PlaneSupport::confirmed`]): one bit read.
    pub fn is_confirmed(&self, id: SegmentId) -> bool {
        let (word, bit) = bit_of(id);
        self.confirmed_bits
            .get(word)
            .is_some_and(|w| w & (1 << bit) != 0)
    }

    /// Changes the support of segment `id` (added empty if it had none) with `change`, and
    /// returns what `change` returns.
    pub fn update<R>(&mut self, id: SegmentId, change: impl FnOnce(&mut PlaneSupport) -> R) -> R {
        let i = match self.position(id) {
            Ok(i) => i,
            Err(i) => {
                self.entries.insert(i, (id, PlaneSupport::default()));
                i
            }
        };
        let result = change(&mut self.entries[i].1);
        let confirmed = self.entries[i].1.confirmed();
        self.set_confirmed(id, confirmed);
        result
    }

    /// Sets the support of segment `id`; returns what it had.
    pub fn insert(&mut self, id: SegmentId, support: PlaneSupport) -> Option<PlaneSupport> {
        self.set_confirmed(id, support.confirmed());
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
        self.set_confirmed(*id, false);
        Some(self.entries.remove(i).1)
    }

    fn set_confirmed(&mut self, id: SegmentId, confirmed: bool) {
        let (word, bit) = bit_of(id);
        if confirmed {
            if self.confirmed_bits.len() <= word {
                self.confirmed_bits.resize(word + 1, 0);
            }
            self.confirmed_bits[word] |= 1 << bit;
        } else if let Some(w) = self.confirmed_bits.get_mut(word) {
            *w &= !(1 << bit);
        }
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

/// The word and the bit of segment `id` in the confirmed bit set.
fn bit_of(id: SegmentId) -> (usize, u32) {
    ((id / 64) as usize, id % 64)
}

impl Serialize for PlaneSupports {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.collect_map(self.iter())
    }
}

impl<'de> Deserialize<'de> for PlaneSupports {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let by_id = BTreeMap::<SegmentId, PlaneSupport>::deserialize(deserializer)?;
        let mut supports = Self::default();
        for (id, support) in by_id {
            supports.insert(id, support);
        }
        Ok(supports)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn support(snapshots: u32) -> PlaneSupport {
        PlaneSupport {
            snapshots,
            last_snapshot: 7,
            ..Default::default()
        }
    }

    proptest::proptest! {
        /// Any sequence of additions, updates and removals leaves what a B-tree map would hold,
        /// in order, and reads back the same from JSON.
        #[test]
        fn it_holds_what_a_btree_map_holds(
            ops in proptest::collection::vec((0u8..3, 0u32..150, 0u32..4), 0..200),
        ) {
            let (mut ours, mut theirs) = (PlaneSupports::default(), BTreeMap::new());
            for (op, id, n) in ops {
                match op {
                    0 => proptest::prop_assert_eq!(ours.insert(id, support(n)), theirs.insert(id, support(n))),
                    1 => {
                        ours.update(id, |s| s.snapshots += n);
                        theirs.entry(id).or_insert_with(PlaneSupport::default).snapshots += n;
                    }
                    _ => proptest::prop_assert_eq!(ours.remove(&id), theirs.remove(&id)),
                }
                proptest::prop_assert_eq!(ours.len(), theirs.len());
            }
            let listed: Vec<_> = ours.iter().map(|(k, v)| (*k, *v)).collect();
            let expected: Vec<_> = theirs.iter().map(|(k, v)| (*k, *v)).collect();
            proptest::prop_assert_eq!(&listed, &expected);
            for id in 0..150 {
                proptest::prop_assert_eq!(ours.get(&id), theirs.get(&id));
                let confirmed = theirs.get(&id).is_some_and(PlaneSupport::confirmed);
                proptest::prop_assert_eq!(ours.is_confirmed(id), confirmed);
            }
            let json = serde_json::to_string(&ours).unwrap();
            proptest::prop_assert_eq!(&json, &serde_json::to_string(&theirs).unwrap());
            let back: PlaneSupports = serde_json::from_str(&json).unwrap();
            for id in 0..150 {
                proptest::prop_assert_eq!(back.is_confirmed(id), ours.is_confirmed(id));
            }
            proptest::prop_assert_eq!(back, ours);
        }
    }
}
