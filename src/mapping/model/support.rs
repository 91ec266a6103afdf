//! What a segment is made of: the readings that support it and its end-points, each with the
//! range that gives its confidence (docs/algorithm.md §1, §3, §5).

use crate::geometry::Point;
use serde::{Deserialize, Serialize};

/// A reading of a run: snapshot index and sensor index, 32 bits each (every supporting point
/// holds one, and a `paper` map of a long run holds millions of points: docs/performance.md,
/// stop 32); [`ReadingRef::new`] and [`ReadingRef::snapshot`] convert.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub struct ReadingRef {
    /// Snapshot index.
    pub snapshot: u32,
    /// Sensor index.
    pub sensor: u32,
}

impl ReadingRef {
    /// The reading of sensor `sensor` in snapshot `snapshot`.
    pub fn new(snapshot: usize, sensor: usize) -> Self {
        let fit = |i: usize| u32::try_from(i).expect("snapshot and sensor indices fit in 32 bits");
        Self {
            snapshot: fit(snapshot),
            sensor: fit(sensor),
        }
    }

    /// Snapshot index.
    pub fn snapshot(&self) -> usize {
        self.snapshot as usize
    }

    /// Sensor index.
    pub fn sensor(&self) -> usize {
        self.sensor as usize
    }
}

/// A point that supports a segment, with the range that produced it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct SupportPoint {
    /// World point, metres.
    pub point: Point,
    /// Range of the reading, metres (confidence is 1/range).
    pub range_m: f64,
    /// The reading it came from.
    pub reading: ReadingRef,
}

/// A segment end-point and the range that gives its confidence.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct EndPoint {
    /// World point, metres.
    pub point: Point,
    /// Range of the reading that produced it (kept through projections), metres.
    pub range_m: f64,
}
