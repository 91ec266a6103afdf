//! The `sonarmap-map` v1 output (docs/formats.md §7, `run --out-map`): the map's segments with every
//! length in the log's units.

use super::save::tidy;
use crate::mapping::model::map::FeatureKind;
use crate::mapping::{Map, SegmentKind};
use crate::units::Units;
use serde::{Deserialize, Serialize};

/// The `format` value of a map file.
pub const MAP_FORMAT: &str = "sonarmap-map";

/// A whole map file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MapFile {
    /// Always [`MAP_FORMAT`].
    pub format: String,
    /// Format version; 1.
    pub version: u32,
    /// The unit of every length.
    pub units: String,
    /// Index of the last snapshot applied.
    pub snapshot: usize,
    /// The segments, by id.
    pub segments: Vec<MapSegmentFile>,
    /// Confirmed point features (corners and edges, docs/algorithm.md §8.5), by id; absent
    /// when none.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub features: Vec<MapFeatureFile>,
}

/// One point feature of a map file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MapFeatureFile {
    /// Feature id.
    pub id: u32,
    /// `"corner"` or `"edge"`.
    pub kind: FeatureKind,
    /// Where it is, `[x, y]` (a rounded reflector's centre).
    pub at: [f64; 2],
    /// A rounded reflector's radius (docs/algorithm.md §8.14); absent for a point.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radius: Option<f64>,
    /// The smallest range it was seen from.
    pub range: f64,
    /// Snapshot that created it.
    pub created: usize,
    /// Snapshots that moved it.
    pub updated: Vec<usize>,
}

/// One segment of a map file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MapSegmentFile {
    /// Segment id.
    pub id: u32,
    /// `"fitted"` or `"interpolated"`.
    pub kind: SegmentKind,
    /// First end-point `[x, y]`.
    pub a: [f64; 2],
    /// Second end-point `[x, y]`.
    pub b: [f64; 2],
    /// Range behind `a`.
    pub range_a: f64,
    /// Range behind `b`.
    pub range_b: f64,
    /// Face id.
    pub face: u32,
    /// Object id.
    pub object: u32,
    /// Snapshot that created it.
    pub created: usize,
    /// Snapshots that updated it.
    pub updated: Vec<usize>,
    /// Supporting points `[x, y, D]`.
    pub points: Vec<[f64; 3]>,
    /// `false` for a tentative segment (docs/algorithm.md §8.7); absent means confirmed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub confirmed: Option<bool>,
}

/// The file form of `map` after snapshot `snapshot`, lengths in `units`.
pub fn map_to_file(map: &Map, units: Units, snapshot: usize) -> MapFile {
    let l = |v: f64| tidy(units.from_m(v));
    MapFile {
        format: MAP_FORMAT.to_string(),
        version: 1,
        units: units.symbol().to_string(),
        snapshot,
        segments: map
            .segments
            .iter()
            .map(|s| MapSegmentFile {
                id: s.id,
                kind: s.kind,
                a: [l(s.a.point.x), l(s.a.point.y)],
                b: [l(s.b.point.x), l(s.b.point.y)],
                range_a: l(s.a.range_m),
                range_b: l(s.b.range_m),
                face: s.face,
                object: s.object,
                created: s.created,
                updated: s.updated.iter().map(|&k| k as usize).collect(),
                points: s
                    .points
                    .iter()
                    .map(|p| [l(p.point.x), l(p.point.y), l(p.range_m)])
                    .collect(),
                confirmed: map.is_tentative(s.id).then_some(false),
            })
            .collect(),
        features: map
            .confirmed_features()
            .map(|f| MapFeatureFile {
                id: f.id,
                kind: f.kind,
                at: [l(f.at.x), l(f.at.y)],
                radius: (f.radius_m > 0.0).then(|| l(f.radius_m)),
                range: l(f.range_m),
                created: f.created,
                updated: f.updated.clone(),
            })
            .collect(),
    }
}

/// `map` as `sonarmap-map` v1 JSON text.
pub fn save_map(map: &Map, units: Units, snapshot: usize) -> String {
    let mut text =
        serde_json::to_string_pretty(&map_to_file(map, units, snapshot)).expect("a map serialises");
    text.push('\n');
    text
}
