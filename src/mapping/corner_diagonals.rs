//! Corner diagonals: a segment standing across a corner the map already holds leaves it
//! (docs/algorithm.md §8.11; beyond the paper).
//!
//! A concave corner returns an echo from its vertex to every sonar whose cone contains it, at
//! any incidence (a corner reflector: Kleeman and Kuc). From a narrow baseline those ranges fit a
//! plane standing across the corner as well as they fit the vertex (both models explain them
//! within the sonar's resolution), so the fit draws a short slanted line, a diagonal, near the
//! vertex; once two sensors or two poses heard it it is confirmed like a wall. Once the two
//! walls that make the corner are confirmed, a segment that lies wholly within
//! [`CORNER_DIAGONAL_RADIUS_M`] of their junction and is turned at least `θ_o` from both is
//! such a diagonal, not a third wall: the vertex's echoes, not a plane, explain its readings.

use super::map::{Map, SegmentId, SegmentKind};
use crate::geometry::{distance_to_segment, line_angle_between, line_intersection, Point};
use serde::{Deserialize, Serialize};

/// How near the junction of two confirmed walls both end-points of a diagonal lie, metres
/// (0.8 m, 31.5 in: the length of the chords a corner's arc leaves at the ranges of a room).
pub const CORNER_DIAGONAL_RADIUS_M: f64 = 0.8;

/// Smallest angle between the two walls of a corner, radians (30°; a corner sharper than that
/// is not told from one wall seen twice).
pub const MIN_CORNER_ANGLE_RAD: f64 = 30.0 * std::f64::consts::PI / 180.0;

/// A segment removed as a corner's diagonal, for the trace.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DiagonalTrace {
    /// The segment removed.
    pub segment: SegmentId,
    /// The two confirmed walls of the corner.
    pub walls: [SegmentId; 2],
    /// The junction: where the walls' lines meet.
    pub junction: Point,
    /// Distances of the segment's two end-points from the junction, metres.
    pub end_distances_m: [f64; 2],
    /// The segment's angles to the two walls, radians.
    pub angles_rad: [f64; 2],
    /// The angle between the two walls, radians.
    pub corner_angle_rad: f64,
}

/// Whether the fitted segment `id` of `map` is a diagonal of a corner of two confirmed walls
/// (its end-points both within `radius_m` of their junction, which itself lies within
/// `radius_m` of each wall, the walls at least [`MIN_CORNER_ANGLE_RAD`] apart and the segment
/// at least `min_turn_rad` from each); the first such corner (walls by id) when it is.
pub fn corner_diagonal(
    map: &Map,
    id: SegmentId,
    radius_m: f64,
    min_turn_rad: f64,
) -> Option<DiagonalTrace> {
    let s = map.segment(id)?;
    if s.kind != SegmentKind::Fitted {
        return None;
    }
    let (a, b) = (s.a.point, s.b.point);
    let along = b - a;
    // A wall of the corner comes within `radius_m` of the junction, which is within
    // `radius_m` of both end-points: within `2·radius_m` of the mid-point.
    let walls: Vec<SegmentId> = map
        .segments_near(&s.mid(), 2.0 * radius_m)
        .into_iter()
        .filter(|&w| {
            w != id
                && map.is_confirmed(w)
                && map.segment(w).is_some_and(|ws| {
                    ws.kind == SegmentKind::Fitted
                        && line_angle_between(&along, &(ws.b.point - ws.a.point)) >= min_turn_rad
                })
        })
        .collect();
    for (i, &u) in walls.iter().enumerate() {
        let su = map.segment(u)?;
        let du = su.b.point - su.a.point;
        for &v in &walls[i + 1..] {
            let sv = map.segment(v)?;
            let dv = sv.b.point - sv.a.point;
            let corner_angle_rad = line_angle_between(&du, &dv);
            if corner_angle_rad < MIN_CORNER_ANGLE_RAD {
                continue;
            }
            let Some(j) = line_intersection(&su.a.point, &su.b.point, &sv.a.point, &sv.b.point)
            else {
                continue;
            };
            let ends = [(a - j).norm(), (b - j).norm()];
            if distance_to_segment(&j, &su.a.point, &su.b.point) <= radius_m
                && distance_to_segment(&j, &sv.a.point, &sv.b.point) <= radius_m
                && ends[0] <= radius_m
                && ends[1] <= radius_m
            {
                return Some(DiagonalTrace {
                    segment: id,
                    walls: [u, v],
                    junction: j,
                    end_distances_m: ends,
                    angles_rad: [
                        line_angle_between(&along, &du),
                        line_angle_between(&along, &dv),
                    ],
                    corner_angle_rad,
                });
            }
        }
    }
    None
}

/// The corner diagonals among the segments a step touched (`touched`) and the segments near
/// their end-points (a wall confirmed or moved this step may make a corner of an older
/// diagonal), in id order; each found against the map as it stands, before any leaves.
pub fn corner_diagonals(
    map: &Map,
    touched: &[SegmentId],
    radius_m: f64,
    min_turn_rad: f64,
) -> Vec<DiagonalTrace> {
    let mut candidates: Vec<SegmentId> = Vec::new();
    for &t in touched {
        let Some(s) = map.segment(t) else {
            continue;
        };
        candidates.push(t);
        if map.is_confirmed(t) {
            candidates.extend(map.segments_near(&s.a.point, radius_m));
            candidates.extend(map.segments_near(&s.b.point, radius_m));
        }
    }
    candidates.sort_unstable();
    candidates.dedup();
    candidates
        .into_iter()
        .filter_map(|c| corner_diagonal(map, c, radius_m, min_turn_rad))
        .collect()
}
