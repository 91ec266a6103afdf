//! A segment's supporting points, kept in shared chunks.
//!
//! The paper keeps every reading that ever supported a segment (docs/algorithm.md §5), so a
//! wall seen for an hour holds thousands of points, and each update inserts a few of them in
//! order along the wall. As one list, every update copied all of them, and every replay
//! checkpoint (which shares what did not change since the one before) kept a copy of each list
//! that changed. In chunks of [`CHUNK_POINTS`] to twice that, an update copies only the chunks
//! it inserts into and the list of chunk pointers; the other chunks stay shared with the
//! previous version of the segment, and with every checkpoint holding it.

use super::support::SupportPoint;
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use std::mem::size_of;
use std::sync::Arc;

/// Points a chunk holds at least (unless the whole list is shorter); a chunk grown past twice
/// this by insertions is split.
pub const CHUNK_POINTS: usize = 64;

/// Supporting points in order, in shared chunks (cheap to clone; see the module docs).
#[derive(Clone, Default)]
pub struct SupportList {
    chunks: Vec<Arc<Vec<SupportPoint>>>,
    len: usize,
}

impl SupportList {
    /// The points of `points`, in order.
    pub fn from_vec(mut points: Vec<SupportPoint>) -> Self {
        let len = points.len();
        if len == 0 {
            return Self::default();
        }
        if len <= 2 * CHUNK_POINTS {
            return Self {
                chunks: vec![Arc::new(points)],
                len,
            };
        }
        let mut chunks = Vec::with_capacity(len / CHUNK_POINTS);
        // Whole chunks from the front; the remainder joins the last one.
        let whole = len / CHUNK_POINTS;
        let mut rest = points.split_off((whole - 1) * CHUNK_POINTS);
        for piece in points.chunks(CHUNK_POINTS) {
            chunks.push(Arc::new(piece.to_vec()));
        }
        rest.shrink_to_fit();
        chunks.push(Arc::new(rest));
        Self { chunks, len }
    }

    /// Number of points.
    pub fn len(&self) -> usize {
        self.len
    }

    /// True without points.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The points in order.
    pub fn iter(&self) -> impl DoubleEndedIterator<Item = &SupportPoint> + Clone + '_ {
        self.chunks.iter().flat_map(|c| c.iter())
    }

    /// The points as one slice when they are in one chunk (short lists always are).
    pub fn as_slice(&self) -> Option<&[SupportPoint]> {
        match self.chunks.as_slice() {
            [] => Some(&[]),
            [only] => Some(only),
            _ => None,
        }
    }

    /// The points copied into one list.
    pub fn to_vec(&self) -> Vec<SupportPoint> {
        let mut v = Vec::with_capacity(self.len);
        for c in &self.chunks {
            v.extend_from_slice(c);
        }
        v
    }

    /// Heap bytes of the list of chunk pointers (each chunk counted by [`Self::chunk_bytes`]).
    pub fn chunk_list_bytes(&self) -> usize {
        self.chunks.capacity() * size_of::<Arc<Vec<SupportPoint>>>()
    }

    /// Heap bytes of one chunk: its shared allocation (two counts and the vector) and its
    /// points.
    pub fn chunk_bytes(chunk: &Arc<Vec<SupportPoint>>) -> usize {
        2 * size_of::<usize>()
            + size_of::<Vec<SupportPoint>>()
            + chunk.capacity() * size_of::<SupportPoint>()
    }

    /// The chunks, in order.
    pub fn chunks(&self) -> &[Arc<Vec<SupportPoint>>] {
        &self.chunks
    }

    /// The points of this list with `new` inserted: `new[j]` goes before the point at index
    /// `at[j]` of this list (after every point when `at[j] == len`); `at` is non-decreasing and
    /// new points with the same index keep their order. Chunks nothing is inserted into stay
    /// shared; a chunk grown past twice [`CHUNK_POINTS`] is split.
    pub fn with_inserted(&self, new: &[SupportPoint], at: &[usize]) -> Self {
        debug_assert_eq!(new.len(), at.len());
        debug_assert!(at.windows(2).all(|w| w[0] <= w[1]));
        if self.chunks.is_empty() {
            return Self::from_vec(new.to_vec());
        }
        let mut chunks = Vec::with_capacity(self.chunks.len() + 1);
        let last = self.chunks.len() - 1;
        let (mut start, mut j) = (0, 0);
        for (i, chunk) in self.chunks.iter().enumerate() {
            let end = start + chunk.len();
            // Insertions before this chunk's points, or after its last one when it is the
            // list's last chunk.
            let first_j = j;
            while j < at.len() && (at[j] < end || (i == last && at[j] == end)) {
                j += 1;
            }
            if first_j == j {
                chunks.push(Arc::clone(chunk));
            } else {
                let mut merged = Vec::with_capacity(chunk.len() + j - first_j);
                let mut from = 0;
                for (q, &k) in new[first_j..j].iter().zip(&at[first_j..j]) {
                    let k = k - start;
                    merged.extend_from_slice(&chunk[from..k]);
                    merged.push(*q);
                    from = k;
                }
                merged.extend_from_slice(&chunk[from..]);
                push_split(&mut chunks, merged);
            }
            start = end;
        }
        Self {
            chunks,
            len: self.len + new.len(),
        }
    }
}

/// Appends `points` as one chunk, or as several of about [`CHUNK_POINTS`] when it is longer
/// than twice that.
fn push_split(chunks: &mut Vec<Arc<Vec<SupportPoint>>>, points: Vec<SupportPoint>) {
    if points.len() <= 2 * CHUNK_POINTS {
        chunks.push(Arc::new(points));
        return;
    }
    let pieces = points.len().div_ceil(CHUNK_POINTS);
    let size = points.len().div_ceil(pieces);
    for piece in points.chunks(size) {
        chunks.push(Arc::new(piece.to_vec()));
    }
}

impl std::fmt::Debug for SupportList {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_list().entries(self.iter()).finish()
    }
}

impl PartialEq for SupportList {
    fn eq(&self, other: &Self) -> bool {
        self.len == other.len && self.iter().eq(other.iter())
    }
}

impl From<Vec<SupportPoint>> for SupportList {
    fn from(points: Vec<SupportPoint>) -> Self {
        Self::from_vec(points)
    }
}

impl<'a> IntoIterator for &'a SupportList {
    type Item = &'a SupportPoint;
    type IntoIter = std::iter::FlatMap<
        std::slice::Iter<'a, Arc<Vec<SupportPoint>>>,
        std::slice::Iter<'a, SupportPoint>,
        fn(&'a Arc<Vec<SupportPoint>>) -> std::slice::Iter<'a, SupportPoint>,
    >;
    fn into_iter(self) -> Self::IntoIter {
        self.chunks.iter().flat_map(|c| c.iter())
    }
}

impl Serialize for SupportList {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.collect_seq(self.iter())
    }
}

impl<'de> Deserialize<'de> for SupportList {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        Vec::<SupportPoint>::deserialize(deserializer).map(Self::from_vec)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Point;
    use crate::mapping::support::ReadingRef;
    use proptest::prelude::*;

    fn point(i: usize) -> SupportPoint {
        SupportPoint {
            point: Point::new(i as f64, 0.0),
            range_m: 1.0,
            reading: ReadingRef {
                snapshot: i,
                sensor: 0,
            },
        }
    }

    fn xs(list: &SupportList) -> Vec<usize> {
        list.iter().map(|q| q.reading.snapshot).collect()
    }

    #[test]
    fn a_long_list_is_cut_into_chunks_of_at_least_chunk_points() {
        let list = SupportList::from_vec((0..300).map(point).collect());
        let sizes: Vec<usize> = list.chunks().iter().map(|c| c.len()).collect();
        // 300 = 64 * 3 + 108: the remainder joins the last chunk.
        assert_eq!(sizes, [64, 64, 64, 108]);
        assert_eq!(xs(&list), (0..300).collect::<Vec<_>>());
        assert!(list.as_slice().is_none());
        assert_eq!(
            SupportList::from_vec((0..128).map(point).collect())
                .chunks()
                .len(),
            1
        );
    }

    #[test]
    fn inserting_copies_only_the_chunks_it_inserts_into() {
        let list = SupportList::from_vec((0..300).map(|i| point(2 * i)).collect());
        // 2 * 70 + 1 = 141 goes before index 71 (in the second chunk, 64..128), 599 after the
        // end (into the fourth and last).
        let grown = list.with_inserted(&[point(141), point(599)], &[71, 300]);
        assert_eq!(grown.len(), 302);
        let shared: Vec<bool> = list
            .chunks()
            .iter()
            .zip(grown.chunks())
            .map(|(a, b)| Arc::ptr_eq(a, b))
            .collect();
        assert_eq!(shared, [true, false, true, false]);
        let mut expected: Vec<usize> = (0..300).map(|i| 2 * i).collect();
        expected.insert(71, 141);
        expected.push(599);
        assert_eq!(xs(&grown), expected);
    }

    #[test]
    fn a_chunk_grown_past_twice_chunk_points_is_split() {
        let list = SupportList::from_vec((0..200).map(point).collect());
        let new: Vec<SupportPoint> = (1000..1100).map(point).collect();
        let grown = list.with_inserted(&new, &[150; 100]);
        assert!(grown.chunks().iter().all(|c| c.len() <= 2 * CHUNK_POINTS));
        assert!(
            grown.chunks().len() > list.chunks().len(),
            "the grown chunk was split"
        );
        assert_eq!(grown.len(), 300);
        let mut expected: Vec<usize> = (0..200).collect();
        expected.splice(150..150, 1000..1100);
        assert_eq!(xs(&grown), expected);
    }

    proptest! {
        #[test]
        fn inserting_equals_inserting_into_one_list(
            len in 0usize..700,
            at in prop::collection::vec(0usize..=700, 0..40),
            rounds in 1usize..4,
        ) {
            let mut list = SupportList::from_vec((0..len).map(point).collect());
            let mut flat: Vec<usize> = (0..len).collect();
            for round in 0..rounds {
                let n = flat.len();
                let mut at: Vec<usize> = at.iter().map(|&k| k.min(n)).collect();
                at.sort_unstable();
                let new: Vec<SupportPoint> =
                    (0..at.len()).map(|j| point(10_000 * (round + 1) + j)).collect();
                list = list.with_inserted(&new, &at);
                for (j, &k) in at.iter().enumerate().rev() {
                    flat.insert(k, 10_000 * (round + 1) + j);
                }
                prop_assert_eq!(xs(&list), flat.clone());
                prop_assert_eq!(list.len(), flat.len());
                prop_assert!(list.chunks().iter().all(|c| !c.is_empty() && c.len() <= 2 * CHUNK_POINTS));
            }
        }
    }
}
