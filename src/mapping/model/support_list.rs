//! A segment's supporting points, kept in shared chunks.
//!
//! The paper keeps every reading that ever supported a segment (docs/algorithm.md §5), so a
//! wall seen for an hour holds thousands of points, and each update inserts a few of them in
//! order along the wall. As one list, every update copied all of them, and every replay
//! checkpoint (which shares what did not change since the one before) kept a copy of each list
//! that changed. In chunks of [`CHUNK_POINTS`] to twice that, an update copies only the chunks
//! it inserts into and the list of chunk pointers; the other chunks stay shared with the
//! previous version of the segment, and with every checkpoint holding it. A refit cuts the
//! list into pieces ([`SupportList::slice`]) that share the chunks lying wholly inside them.

use crate::mapping::model::support::SupportPoint;
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use std::mem::size_of;
use std::sync::Arc;

/// Points a chunk holds at least (unless the whole list is shorter); a chunk grown past twice
/// this by insertions is split. Small, because a robot passing along a wall inserts points all
/// along it: on the `paper` building lap run (100,000 snapshots) the chunks new in a late
/// 1,024-snapshot checkpoint interval held 157,000 points at 64, 96,000 at 32 and 64,000 at
/// 16, while the lists of chunk pointers grew from 0.09 to 0.33 MB.
pub const CHUNK_POINTS: usize = 16;

/// A shared run of points: one allocation (the counts, then the points), its length in the
/// pointer, so that a pass over a list reads each chunk with one fetch from memory (the passes
/// over every point of each long wall a `paper` step updates were a quarter to a third of a
/// late seek's time).
pub type Chunk = Arc<[SupportPoint]>;

/// Supporting points in order, in shared chunks (cheap to clone; see the module docs).
#[derive(Clone, Default)]
pub struct SupportList {
    chunks: Vec<Chunk>,
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
                chunks: vec![Chunk::from(points)],
                len,
            };
        }
        let mut chunks = Vec::with_capacity(len / CHUNK_POINTS);
        // Whole chunks from the front; the remainder joins the last one.
        let whole = len / CHUNK_POINTS;
        let rest = points.split_off((whole - 1) * CHUNK_POINTS);
        for piece in points.chunks(CHUNK_POINTS) {
            chunks.push(Chunk::from(piece));
        }
        chunks.push(Chunk::from(rest));
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
            [only] => Some(&only[..]),
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
        self.chunks.capacity() * size_of::<Chunk>()
    }

    /// Heap bytes of one chunk: its shared allocation (two counts, then its points).
    pub fn chunk_bytes(chunk: &Chunk) -> usize {
        2 * size_of::<usize>() + chunk.len() * size_of::<SupportPoint>()
    }

    /// The chunks, in order.
    pub fn chunks(&self) -> &[Chunk] {
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

    /// The points at indices `range` of this list, in order: the chunks that lie wholly inside
    /// it stay shared, the parts of the (at most two) chunks it cuts are copied. A copied part
    /// shorter than [`CHUNK_POINTS`] joins its neighbouring chunk inside the range (copied too),
    /// so that cutting a list again and again does not leave it in ever smaller chunks; a
    /// range of at most twice [`CHUNK_POINTS`] points is one chunk, as [`Self::from_vec`] makes
    /// it. A refit cuts a segment's points into pieces this way (docs/algorithm.md §5).
    pub fn slice(&self, range: std::ops::Range<usize>) -> Self {
        assert!(
            range.start <= range.end && range.end <= self.len,
            "slice {range:?} of a list of {}",
            self.len
        );
        let len = range.len();
        let parts = self.parts_in(range);
        if len <= 2 * CHUNK_POINTS {
            return Self::from_vec(copy_parts(&parts));
        }
        let is_cut = |i: usize| parts[i].1.len() < parts[i].0.len();
        // The parts copied at the head (`..shared.start`) and the tail (`shared.end..`).
        let mut shared = 0..parts.len();
        if is_cut(0) {
            shared.start = 1;
            if parts[0].1.len() < CHUNK_POINTS && !shared.is_empty() {
                shared.start = 2;
            }
        }
        if !shared.is_empty() && is_cut(shared.end - 1) {
            shared.end -= 1;
            if parts[shared.end].1.len() < CHUNK_POINTS && !shared.is_empty() {
                shared.end -= 1;
            }
        }
        let mut chunks = Vec::with_capacity(parts.len() + 1);
        let head = copy_parts(&parts[..shared.start]);
        if !head.is_empty() {
            push_split(&mut chunks, head);
        }
        chunks.extend(parts[shared.clone()].iter().map(|(c, _)| Arc::clone(c)));
        let tail = copy_parts(&parts[shared.end..]);
        if !tail.is_empty() {
            push_split(&mut chunks, tail);
        }
        Self { chunks, len }
    }

    /// Each chunk meeting the index range `range`, with the part of it inside the range (only
    /// the first and the last can be cut).
    fn parts_in(&self, range: std::ops::Range<usize>) -> Vec<(&Chunk, std::ops::Range<usize>)> {
        let mut parts = Vec::new();
        let mut start = 0;
        for chunk in &self.chunks {
            let end = start + chunk.len();
            let (from, to) = (range.start.max(start), range.end.min(end));
            if from < to {
                parts.push((chunk, from - start..to - start));
            }
            start = end;
        }
        parts
    }
}

/// The points of `parts` (chunks with a range of each), in order, in one list.
fn copy_parts(parts: &[(&Chunk, std::ops::Range<usize>)]) -> Vec<SupportPoint> {
    let mut points = Vec::with_capacity(parts.iter().map(|(_, part)| part.len()).sum());
    for (chunk, part) in parts {
        points.extend_from_slice(&chunk[part.clone()]);
    }
    points
}

/// Appends `points` as one chunk, or as several of about [`CHUNK_POINTS`] when it is longer
/// than twice that.
fn push_split(chunks: &mut Vec<Chunk>, points: Vec<SupportPoint>) {
    if points.len() <= 2 * CHUNK_POINTS {
        chunks.push(Chunk::from(points));
        return;
    }
    let pieces = points.len().div_ceil(CHUNK_POINTS);
    let size = points.len().div_ceil(pieces);
    for piece in points.chunks(size) {
        chunks.push(Chunk::from(piece));
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
        std::slice::Iter<'a, Chunk>,
        std::slice::Iter<'a, SupportPoint>,
        fn(&'a Chunk) -> std::slice::Iter<'a, SupportPoint>,
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
    use crate::mapping::model::support::ReadingRef;
    use proptest::prelude::*;

    fn point(i: usize) -> SupportPoint {
        SupportPoint {
            point: Point::new(i as f64, 0.0),
            range_m: 1.0,
            reading: ReadingRef::new(i, 0),
        }
    }

    fn xs(list: &SupportList) -> Vec<usize> {
        list.iter().map(|q| q.reading.snapshot()).collect()
    }

    #[test]
    fn a_long_list_is_cut_into_chunks_of_at_least_chunk_points() {
        let list = SupportList::from_vec((0..75).map(point).collect());
        let sizes: Vec<usize> = list.chunks().iter().map(|c| c.len()).collect();
        // 75 = 16 * 3 + 27: the remainder joins the last chunk.
        assert_eq!(sizes, [16, 16, 16, 27]);
        assert_eq!(xs(&list), (0..75).collect::<Vec<_>>());
        assert!(list.as_slice().is_none());
        assert_eq!(
            SupportList::from_vec((0..32).map(point).collect())
                .chunks()
                .len(),
            1
        );
    }

    #[test]
    fn inserting_copies_only_the_chunks_it_inserts_into() {
        let list = SupportList::from_vec((0..75).map(|i| point(2 * i)).collect());
        // 2 * 17 + 1 = 35 goes before index 18 (in the second chunk, 16..32), 149 after the
        // end (into the fourth and last).
        let grown = list.with_inserted(&[point(35), point(149)], &[18, 75]);
        assert_eq!(grown.len(), 77);
        let shared: Vec<bool> = list
            .chunks()
            .iter()
            .zip(grown.chunks())
            .map(|(a, b)| Arc::ptr_eq(a, b))
            .collect();
        assert_eq!(shared, [true, false, true, false]);
        let mut expected: Vec<usize> = (0..75).map(|i| 2 * i).collect();
        expected.insert(18, 35);
        expected.push(149);
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

    #[test]
    fn a_slice_shares_the_chunks_inside_it_and_copies_the_cut_ones() {
        let list = SupportList::from_vec((0..100).map(point).collect());
        // Chunks 0..16, 16..32, 32..48, 48..64, 64..80, 80..100.
        let piece = list.slice(25..82);
        assert_eq!(xs(&piece), (25..82).collect::<Vec<_>>());
        let sizes: Vec<usize> = piece.chunks().iter().map(|c| c.len()).collect();
        // 25..32 (7 points, short) joins 32..48 (copied); 48..64 stays shared; 80..82 (2
        // points, short) joins 64..80 (copied).
        assert_eq!(sizes, [23, 16, 18]);
        let is_shared = |c: &Chunk| list.chunks().iter().any(|o| Arc::ptr_eq(o, c));
        let shared: Vec<bool> = piece.chunks().iter().map(is_shared).collect();
        assert_eq!(shared, [false, true, false]);
        // A cut part of at least CHUNK_POINTS (80..97 of the last chunk) is a chunk of its own.
        let piece = list.slice(0..97);
        let sizes: Vec<usize> = piece.chunks().iter().map(|c| c.len()).collect();
        assert_eq!(sizes, [16, 16, 16, 16, 16, 17]);
        let shared: Vec<bool> = piece.chunks().iter().map(is_shared).collect();
        assert_eq!(shared, [true, true, true, true, true, false]);
        // A short range is one chunk.
        assert!(list.slice(10..42).as_slice().is_some());
        assert!(list.slice(7..7).is_empty());
    }

    proptest! {
        #[test]
        fn a_slice_equals_slicing_one_list(
            len in 0usize..900,
            at in prop::collection::vec(0usize..=900, 0..20),
            range in (0usize..=900, 0usize..=900),
        ) {
            // A list grown by insertions (chunks of every size), then cut.
            let mut list = SupportList::from_vec((0..len).map(point).collect());
            let mut at: Vec<usize> = at.iter().map(|&k| k.min(len)).collect();
            at.sort_unstable();
            let new: Vec<SupportPoint> = (0..at.len()).map(|j| point(10_000 + j)).collect();
            list = list.with_inserted(&new, &at);
            let flat = xs(&list);
            let (a, b) = (range.0.min(flat.len()), range.1.min(flat.len()));
            let (a, b) = (a.min(b), a.max(b));
            let piece = list.slice(a..b);
            prop_assert_eq!(xs(&piece), flat[a..b].to_vec());
            prop_assert_eq!(piece.len(), b - a);
            prop_assert!(piece.chunks().iter().all(|c| !c.is_empty() && c.len() <= 2 * CHUNK_POINTS));
            // Every chunk of the list lying inside the range, away from a short cut part at
            // either end, is shared.
            let mut start = 0;
            for c in list.chunks() {
                let end = start + c.len();
                if a + CHUNK_POINTS <= start && end + CHUNK_POINTS <= b {
                    prop_assert!(piece.chunks().iter().any(|p| Arc::ptr_eq(p, c)));
                }
                start = end;
            }
        }

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
