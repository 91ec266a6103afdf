//! Ids of the map's segments, faces and objects (docs/algorithm.md §3, §6): dense numbers,
//! allocated in decision order and never reused in a run.

/// Identifies a map segment for the whole run (ids are never reused).
pub type SegmentId = u32;
/// Identifies a face (the segments fitted from one cluster chain).
pub type FaceId = u32;
/// Identifies an object (faces joined by correlation).
pub type ObjectId = u32;
/// Identifies a point feature (a corner or an edge, docs/algorithm.md §8.5).
pub type FeatureId = u32;
