//! A face's segment ids in order, kept in shared chunks.
//!
//! A face of a long `paper` run gathers thousands of segments (every piece of every refit of
//! its wall), and a step that adds or removes one of them made a new version of the face: as
//! one list, a copy of every id, kept alive by each replay checkpoint holding that version
//! (a fifth of what a late checkpoint kept alive: docs/performance.md, stop 32). In chunks of
//! up to twice [`CHUNK_IDS`], a change copies one chunk and the short list of chunk pointers;
//! the other chunks stay shared with the previous version.

use crate::mapping::model::ids::SegmentId;
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use std::sync::Arc;

/// Ids a chunk holds about, when a list is built whole (a list of at most twice this is one
/// chunk); a chunk grown past twice this is split, and removals leave chunks as they are.
pub const CHUNK_IDS: usize = 64;

/// Segment ids in order, in shared chunks (cheap to clone; see the module docs).
#[derive(Clone, Default)]
pub struct IdList {
    chunks: Vec<Arc<[SegmentId]>>,
    len: usize,
}

impl IdList {
    /// The ids of `ids`, in order.
    pub fn from_slice(ids: &[SegmentId]) -> Self {
        let mut list = Self::default();
        list.splice_chunk_at(0, ids.to_vec());
        list
    }

    /// Number of ids.
    pub fn len(&self) -> usize {
        self.len
    }

    /// True without ids.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The ids in order.
    pub fn iter(&self) -> impl DoubleEndedIterator<Item = SegmentId> + Clone + '_ {
        self.chunks.iter().flat_map(|c| c.iter().copied())
    }

    /// The first id.
    pub fn first(&self) -> Option<SegmentId> {
        self.chunks.first().and_then(|c| c.first().copied())
    }

    /// The last id.
    pub fn last(&self) -> Option<SegmentId> {
        self.chunks.last().and_then(|c| c.last().copied())
    }

    /// Where `id` first appears.
    pub fn position(&self, id: SegmentId) -> Option<usize> {
        self.iter().position(|s| s == id)
    }

    /// The ids copied into one list.
    pub fn to_vec(&self) -> Vec<SegmentId> {
        self.iter().collect()
    }

    /// Bytes of the list's heap not shared with `previous` (another version of it): its list
    /// of chunk pointers, and each chunk `previous` does not hold.
    pub fn bytes_beyond(&self, previous: Option<&IdList>) -> usize {
        let held = |c: &Arc<[SegmentId]>| {
            previous.is_some_and(|p| p.chunks.iter().any(|o| Arc::ptr_eq(o, c)))
        };
        let chunk_bytes = |c: &Arc<[SegmentId]>| 2 * size_of::<usize>() + size_of_val(&**c);
        self.chunks.capacity() * size_of::<Arc<[SegmentId]>>()
            + self
                .chunks
                .iter()
                .filter(|c| !held(c))
                .map(chunk_bytes)
                .sum::<usize>()
    }

    /// Appends `id`.
    pub fn push(&mut self, id: SegmentId) {
        self.insert_at(self.len, &[id]);
    }

    /// Inserts `ids` before the id at index `at` (at the end when `at` is the length).
    pub fn insert_at(&mut self, at: usize, ids: &[SegmentId]) {
        assert!(
            at <= self.len,
            "insertion at {at} in a list of {}",
            self.len
        );
        if ids.is_empty() {
            return;
        }
        // The chunk holding index `at`, or the last one when `at` is the end.
        let Some((c, start)) = self.chunk_at(at.min(self.len.saturating_sub(1))) else {
            self.splice_chunk_at(0, ids.to_vec());
            return;
        };
        let chunk = self.chunks.remove(c);
        let mut merged = Vec::with_capacity(chunk.len() + ids.len());
        merged.extend_from_slice(&chunk[..at - start]);
        merged.extend_from_slice(ids);
        merged.extend_from_slice(&chunk[at - start..]);
        self.len -= chunk.len();
        self.splice_chunk_at(c, merged);
    }

    /// Removes every appearance of `id`.
    pub fn remove_id(&mut self, id: SegmentId) {
        let mut c = 0;
        while c < self.chunks.len() {
            if !self.chunks[c].contains(&id) {
                c += 1;
                continue;
            }
            let chunk = self.chunks.remove(c);
            let kept: Vec<SegmentId> = chunk.iter().copied().filter(|&s| s != id).collect();
            self.len -= chunk.len();
            c += self.splice_chunk_at(c, kept);
        }
    }

    /// The chunk holding index `k` and the index of its first id.
    fn chunk_at(&self, k: usize) -> Option<(usize, usize)> {
        let mut start = 0;
        for (c, chunk) in self.chunks.iter().enumerate() {
            if k < start + chunk.len() {
                return Some((c, start));
            }
            start += chunk.len();
        }
        None
    }

    /// Puts `ids` in at chunk position `c`: as one chunk, or as several of about
    /// [`CHUNK_IDS`] when more than twice that (none when empty). Returns the chunks added.
    fn splice_chunk_at(&mut self, c: usize, ids: Vec<SegmentId>) -> usize {
        self.len += ids.len();
        if ids.is_empty() {
            return 0;
        }
        let pieces = if ids.len() <= 2 * CHUNK_IDS {
            1
        } else {
            ids.len().div_ceil(CHUNK_IDS)
        };
        let size = ids.len().div_ceil(pieces);
        let new = ids.chunks(size).map(Arc::from);
        let added = ids.len().div_ceil(size);
        self.chunks.splice(c..c, new);
        added
    }
}

impl std::fmt::Debug for IdList {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_list().entries(self.iter()).finish()
    }
}

impl PartialEq for IdList {
    fn eq(&self, other: &Self) -> bool {
        self.len == other.len && self.iter().eq(other.iter())
    }
}

impl From<Vec<SegmentId>> for IdList {
    fn from(ids: Vec<SegmentId>) -> Self {
        Self::from_slice(&ids)
    }
}

impl Serialize for IdList {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.collect_seq(self.iter())
    }
}

impl<'de> Deserialize<'de> for IdList {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        Vec::<SegmentId>::deserialize(deserializer).map(Self::from)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn a_change_copies_one_chunk_and_shares_the_others() {
        let ids: Vec<SegmentId> = (0..1000).collect();
        let list = IdList::from_slice(&ids);
        // 1,000 ids: 16 chunks of 63 (1000 / 64 rounded up, evened out), the last of 55.
        assert_eq!(list.chunks.len(), 16);
        let mut changed = list.clone();
        changed.insert_at(500, &[5000, 5001]);
        changed.remove_id(10);
        let shared = changed
            .chunks
            .iter()
            .filter(|c| list.chunks.iter().any(|o| Arc::ptr_eq(o, c)))
            .count();
        assert_eq!(shared, 14);
        let mut expected = ids.clone();
        expected.splice(500..500, [5000, 5001]);
        expected.retain(|&s| s != 10);
        assert_eq!(changed.to_vec(), expected);
        // Its own bytes: the list of 16 chunk pointers and the two new chunks.
        assert_eq!(
            changed.bytes_beyond(Some(&list)),
            changed.chunks.capacity() * 16 + (16 + 62 * 4) + (16 + 65 * 4)
        );
    }

    proptest! {
        #[test]
        fn changes_equal_changing_one_vec(
            len in 0usize..600,
            ops in prop::collection::vec((0u8..3, 0usize..700, 1usize..200), 0..40),
        ) {
            let mut flat: Vec<SegmentId> = (0..len as u32).collect();
            let mut list = IdList::from_slice(&flat);
            let mut next = 10_000;
            for (kind, at, n) in ops {
                match kind {
                    0 => {
                        list.push(next);
                        flat.push(next);
                        next += 1;
                    }
                    1 => {
                        let at = at.min(flat.len());
                        let new: Vec<SegmentId> = (next..next + n as u32).collect();
                        next += n as u32;
                        list.insert_at(at, &new);
                        flat.splice(at..at, new);
                    }
                    _ => {
                        let id = flat.get(at).copied().unwrap_or(at as u32);
                        list.remove_id(id);
                        flat.retain(|&s| s != id);
                    }
                }
                prop_assert_eq!(list.to_vec(), flat.clone());
                prop_assert_eq!(list.len(), flat.len());
                prop_assert_eq!(list.first(), flat.first().copied());
                prop_assert_eq!(list.last(), flat.last().copied());
                prop_assert!(list.chunks.iter().all(|c| !c.is_empty() && c.len() <= 2 * CHUNK_IDS));
            }
        }
    }
}
