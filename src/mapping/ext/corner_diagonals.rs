//! Corner diagonals: a segment standing across a corner the map already holds leaves it
//! (docs/algorithm.md §8.11; beyond the paper).
//!
//! A concave corner returns an echo from its vertex to every sonar whose cone contains it, at
//! any incidence (a corner reflector: Kleeman and Kuc). From a narrow baseline those ranges fit a
//! plane standing across the corner as well as they fit the vertex (both models explain them
//! within the sonar's resolution), so the fit draws a short slanted line, a diagonal, near the
//! vertex; once two sensors or two poses heard it it is confirmed like a wall. Once the map
//! holds the two walls that make the corner (one of them confirmed), a segment that lies wholly
//! within [`CORNER_DIAGONAL_RADIUS_M`] of their junction and is turned at least `θ_o` from both
//! is such a diagonal, not a third wall: the vertex's echoes, not a plane, explain its
//! readings. A new face is tested as soon as it is filed ([`corner_diagonal`], "at birth"),
//! before the step correlates or confirms it; the other segments that can make a new corner
//! when the step ends ([`corner_diagonals`]).

use crate::geometry::{
    distance_to_line, distance_to_segment, line_angle_at_most, line_angle_between,
    line_intersection, AngleLimit, Point,
};
use crate::mapping::model::ext_trace::DiagonalTrace;
use crate::mapping::model::index::IndexedSegment;
use crate::mapping::model::map::{Map, SegmentId, SegmentKind};

/// How near the junction of two walls both end-points of a diagonal lie, metres (1 m, 39 in:
/// the chords a corner's arc leaves at the ranges of a room are shorter).
pub const CORNER_DIAGONAL_RADIUS_M: f64 = 1.0;

/// How near the junction each wall of the corner comes, metres (1.6 m, 63 in): the walls are
/// seldom mapped up to the vertex, whose echoes draw the diagonals instead.
pub const CORNER_WALL_REACH_M: f64 = 1.6;

/// Smallest angle between the two walls of a corner, radians (30°; a corner sharper than that
/// is not told from one wall seen twice).
pub const MIN_CORNER_ANGLE_RAD: f64 = 30.0 * std::f64::consts::PI / 180.0;

/// Whether the fitted segment `id` of `map` is a diagonal of a corner of two fitted walls, one
/// of them at least confirmed (both, when `id` itself is confirmed): its end-points both
/// within `radius_m` of the junction of the walls' lines, which itself lies within `reach_m`
/// of each wall, the walls at least [`MIN_CORNER_ANGLE_RAD`] apart and the segment at least
/// `min_turn_rad` from each. The first such corner (walls by id) when it is.
pub fn corner_diagonal(
    map: &Map,
    id: SegmentId,
    radius_m: f64,
    reach_m: f64,
    min_turn_rad: f64,
) -> Option<DiagonalTrace> {
    corner_diagonal_among(map, &Near::Grid(map), id, radius_m, reach_m, min_turn_rad)
}

/// [`corner_diagonal`], the walls found in `near`.
fn corner_diagonal_among(
    map: &Map,
    near: &Near,
    id: SegmentId,
    radius_m: f64,
    reach_m: f64,
    min_turn_rad: f64,
) -> Option<DiagonalTrace> {
    let s = map.segment(id)?;
    let (a, b) = (s.a.point, s.b.point);
    let along = b - a;
    // Both end-points within `radius_m` of one point: no longer than `2·radius_m`.
    if s.kind != SegmentKind::Fitted || along.norm() > 2.0 * radius_m {
        return None;
    }
    struct Wall {
        id: SegmentId,
        a: Point,
        b: Point,
        confirmed: bool,
    }
    let turn = AngleLimit::new(min_turn_rad);
    let sharp = AngleLimit::new(MIN_CORNER_ANGLE_RAD);
    // A wall of the corner comes within `reach_m` of the junction, which is within `radius_m`
    // of both end-points: within `radius_m + reach_m` of each end-point, and of the mid-point.
    let mid = s.mid();
    let mut walls: Vec<Wall> = Vec::new();
    near.visit(&mid, &mid, radius_m + reach_m, |w, ws| {
        if w != id && can_be_wall_of(&a, &b, ws, turn, radius_m, reach_m) {
            walls.push(Wall {
                id: w,
                a: ws.a.point,
                b: ws.b.point,
                confirmed: map.is_confirmed(w),
            });
        }
    });
    walls.sort_unstable_by_key(|w| w.id);
    // A confirmed segment is a diagonal only of a corner of two confirmed walls: readings of
    // two snapshots that support it as a plane outweigh one tentative wall.
    let walls_needed = if map.is_confirmed(id) { 2 } else { 1 };
    for (i, u) in walls.iter().enumerate() {
        let du = u.b - u.a;
        for v in &walls[i + 1..] {
            if usize::from(u.confirmed) + usize::from(v.confirmed) < walls_needed {
                continue;
            }
            let dv = v.b - v.a;
            if line_angle_at_most(&du, &dv, sharp) {
                continue;
            }
            let Some(j) = line_intersection(&u.a, &u.b, &v.a, &v.b) else {
                continue;
            };
            let ends = [(a - j).norm(), (b - j).norm()];
            if ends[0] <= radius_m
                && ends[1] <= radius_m
                && distance_to_segment(&j, &u.a, &u.b) <= reach_m
                && distance_to_segment(&j, &v.a, &v.b) <= reach_m
            {
                return Some(DiagonalTrace {
                    segment: id,
                    ends: [a, b],
                    walls: [u.id, v.id],
                    junction: j,
                    end_distances_m: ends,
                    angles_rad: [
                        line_angle_between(&along, &du),
                        line_angle_between(&along, &dv),
                    ],
                    corner_angle_rad: line_angle_between(&du, &dv),
                });
            }
        }
    }
    None
}

/// Whether `wall` can be one of the two walls of a corner that the segment `a`–`b` is a
/// diagonal of ([`corner_diagonal`]): it is fitted, turned at least `turn` from the segment,
/// and its line passes within `radius_m` of both end-points (the junction lies on it within
/// `radius_m` of both), the wall itself within `radius_m + reach_m` of each.
fn can_be_wall_of(
    a: &Point,
    b: &Point,
    wall: &IndexedSegment,
    turn: AngleLimit,
    radius_m: f64,
    reach_m: f64,
) -> bool {
    let (p, q) = (&wall.a.point, &wall.b.point);
    // The turn first: most segments near a wall's piece run along it. Then the line tests,
    // cheaper than the distances to the wall itself.
    wall.fitted
        && !line_angle_at_most(&(b - a), &(q - p), turn)
        && distance_to_line(a, p, q) <= radius_m
        && distance_to_line(b, p, q) <= radius_m
        && distance_to_segment(a, p, q) <= radius_m + reach_m
        && distance_to_segment(b, p, q) <= radius_m + reach_m
}

/// The corner diagonals ([`corner_diagonal`]) among the segments that can make a corner that
/// was not there before (`new_corners`: made, grown or confirmed this step) and the segments
/// within `radius_m + reach_m` of their end-points whose corner they can be a wall of, in id
/// order; each found against the map as it stands, before any leaves. A segment updated
/// within its old end-points is not tested again: it was tested when it was made or last
/// grew, and the walls around it were tested when they changed.
pub fn corner_diagonals(
    map: &Map,
    new_corners: &[SegmentId],
    radius_m: f64,
    reach_m: f64,
    min_turn_rad: f64,
) -> Vec<DiagonalTrace> {
    corner_diagonals_listing(
        map,
        new_corners,
        radius_m,
        reach_m,
        min_turn_rad,
        MAX_LISTED,
    )
}

/// [`corner_diagonals`], searching a gathered list of at most `max_listed` segments.
fn corner_diagonals_listing(
    map: &Map,
    new_corners: &[SegmentId],
    radius_m: f64,
    reach_m: f64,
    min_turn_rad: f64,
    max_listed: usize,
) -> Vec<DiagonalTrace> {
    // Most steps of a long run make no new corner: nothing to gather, no limit to set up.
    if new_corners.is_empty() {
        return Vec::new();
    }
    // Only fitted segments no longer than `2·radius_m` can be diagonals ([`corner_diagonal`]).
    let short =
        |ws: &IndexedSegment| ws.fitted && (ws.b.point - ws.a.point).norm() <= 2.0 * radius_m;
    let mut new_corners = new_corners.to_vec();
    new_corners.sort_unstable();
    new_corners.dedup();
    let corners: Vec<(SegmentId, IndexedSegment)> = new_corners
        .iter()
        .filter_map(|&t| map.segment(t).map(|s| (t, s.indexed())))
        .collect();
    // Every segment the tests below look at, gathered from the grid in one pass: a candidate
    // meets the box of an end-point widened by `radius_m + reach_m` and is no longer than
    // `2·radius_m`, so the box its own test looks in (around its mid-point) lies within
    // `2·(radius_m + reach_m) + radius_m` of that end-point.
    let ends = corners.iter().flat_map(|(_, s)| [s.a.point, s.b.point]);
    let low = ends
        .clone()
        .fold(Point::new(f64::INFINITY, f64::INFINITY), |m, p| {
            Point::new(m.x.min(p.x), m.y.min(p.y))
        });
    let high = ends.fold(Point::new(f64::NEG_INFINITY, f64::NEG_INFINITY), |m, p| {
        Point::new(m.x.max(p.x), m.y.max(p.y))
    });
    let mut listed = Vec::new();
    if low.x <= high.x && low.y <= high.y {
        let gather_m = 2.0 * (radius_m + reach_m) + radius_m;
        map.visit_segments_along(&low, &high, gather_m, |id, s| listed.push((id, *s)));
    }
    // A map that crowds the box (a `paper` map with the rule on) is searched through the grid
    // for each test instead.
    let near = if listed.len() <= max_listed {
        Near::Listed(&listed)
    } else {
        Near::Grid(map)
    };
    let turn = AngleLimit::new(min_turn_rad);
    let mut candidates: Vec<SegmentId> = Vec::new();
    for (t, s) in &corners {
        if short(s) {
            candidates.push(*t);
        }
        // A segment whose corner this one can be a wall of: the only corners that can be new
        // around it (its other walls did not change, and it was tested when they did). A
        // confirmed segment is a diagonal only of two confirmed walls.
        let confirmed = map.is_confirmed(*t);
        for p in [&s.a.point, &s.b.point] {
            near.visit(p, p, radius_m + reach_m, |c, cs| {
                if c != *t
                    && short(cs)
                    && can_be_wall_of(&cs.a.point, &cs.b.point, s, turn, radius_m, reach_m)
                    && (confirmed || !map.is_confirmed(c))
                {
                    candidates.push(c);
                }
            });
        }
    }
    candidates.sort_unstable();
    candidates.dedup();
    candidates
        .into_iter()
        .filter_map(|c| corner_diagonal_among(map, &near, c, radius_m, reach_m, min_turn_rad))
        .collect()
}

/// Most segments [`corner_diagonals`] gathers to search through itself.
const MAX_LISTED: usize = 1024;

/// Where the tests find the segments near a point: the map's grid, or a list gathered from it
/// that holds every segment the grid would give.
enum Near<'a> {
    Grid(&'a Map),
    Listed(&'a [(SegmentId, IndexedSegment)]),
}

impl Near<'_> {
    /// Calls `visit` for the segments whose bounding box meets the box of `a` and `b` widened
    /// by `reach_m` (through the grid: and those it keeps for every query).
    fn visit(
        &self,
        a: &Point,
        b: &Point,
        reach_m: f64,
        mut visit: impl FnMut(SegmentId, &IndexedSegment),
    ) {
        match self {
            Near::Grid(map) => map.visit_segments_along(a, b, reach_m, visit),
            Near::Listed(list) => {
                let (x0, y0) = (a.x.min(b.x) - reach_m, a.y.min(b.y) - reach_m);
                let (x1, y1) = (a.x.max(b.x) + reach_m, a.y.max(b.y) + reach_m);
                for (id, s) in list.iter() {
                    let (p, q) = (s.a.point, s.b.point);
                    if p.x.min(q.x) <= x1
                        && p.x.max(q.x) >= x0
                        && p.y.min(q.y) <= y1
                        && p.y.max(q.y) >= y0
                    {
                        visit(*id, s);
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mapping::model::map::test_wall;
    use crate::mapping::model::plane_supports::PlaneSupport;
    use crate::mapping::model::plane_supports::CONFIRMING_SNAPSHOTS;

    const TURN: f64 = 15.0 * std::f64::consts::PI / 180.0;

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(64))]
        /// The gathered list finds what the grid finds: random walls and short pieces crowded
        /// into a few metres (each a corner the step made, some confirmed), searched both ways.
        #[test]
        fn the_gathered_list_finds_the_diagonals_the_grid_finds(
            pieces in proptest::collection::vec(
                (0.0..8.0f64, 0.0..8.0f64, 0.0..std::f64::consts::TAU, 0.1..4.0f64, proptest::bool::ANY),
                2..60,
            ),
            corners in proptest::collection::vec(0usize..60, 1..8),
        ) {
            let segments = pieces
                .iter()
                .enumerate()
                .map(|(i, &(x, y, dir, len, _))| {
                    test_wall(i as SegmentId, (x, y), (x + len * dir.cos(), y + len * dir.sin()), 1.0)
                })
                .collect();
            let mut map = Map::from_segments(segments);
            for (i, p) in pieces.iter().enumerate() {
                if p.4 {
                    confirm(&mut map, i as SegmentId);
                }
            }
            let corners: Vec<SegmentId> = corners.iter().map(|&c| (c % pieces.len()) as SegmentId).collect();
            let (r, reach) = (CORNER_DIAGONAL_RADIUS_M, CORNER_WALL_REACH_M);
            let listed = corner_diagonals_listing(&map, &corners, r, reach, TURN, usize::MAX);
            let through_grid = corner_diagonals_listing(&map, &corners, r, reach, TURN, 0);
            proptest::prop_assert_eq!(listed, through_grid);
        }
    }

    fn confirm(map: &mut Map, id: SegmentId) {
        map.plane_support.insert(
            id,
            PlaneSupport {
                snapshots: CONFIRMING_SNAPSHOTS,
                last_snapshot: 0,
                ..Default::default()
            },
        );
    }

    /// A corner at the origin: s0 along +x, s1 along +y, both 3 m long. s2 stands across it
    /// from (0.6, 0.2) to (0.2, 0.6); s3 lies along s0, 5 cm in front of it; s4 stands across
    /// the room 2.5 m from the vertex.
    fn room_corner() -> Map {
        Map::from_segments(vec![
            test_wall(0, (0.0, 0.0), (3.0, 0.0), 1.0),
            test_wall(1, (0.0, 0.0), (0.0, 3.0), 1.0),
            test_wall(2, (0.6, 0.2), (0.2, 0.6), 1.0),
            test_wall(3, (0.2, 0.05), (0.9, 0.05), 1.0),
            test_wall(4, (2.0, 1.5), (1.5, 2.0), 1.0),
        ])
    }

    #[test]
    fn a_chord_across_a_confirmed_corner_is_a_diagonal_and_a_wall_beside_it_is_not() {
        let mut map = room_corner();
        confirm(&mut map, 0);
        confirm(&mut map, 1);
        let r = CORNER_DIAGONAL_RADIUS_M;
        let d = corner_diagonal(&map, 2, r, CORNER_WALL_REACH_M, TURN).expect("a diagonal");
        // Both ends lie sqrt(0.6² + 0.2²) = sqrt(0.4) = 0.6325 m from the vertex (<= 1 m), the
        // chord runs along (-0.4, 0.4): 45° from both walls (>= 15°), which meet at 90°.
        assert_eq!(d.walls, [0, 1]);
        assert!(d.junction.coords.norm() < 1e-12);
        for e in d.end_distances_m {
            assert!((e - 0.4f64.sqrt()).abs() < 1e-12, "{e}");
        }
        for a in d.angles_rad {
            assert!((a.to_degrees() - 45.0).abs() < 1e-9);
        }
        assert!((d.corner_angle_rad.to_degrees() - 90.0).abs() < 1e-9);
        // s3 lies along s0 (0° from it, under 15°); s4's ends lie sqrt(2² + 1.5²) = 2.5 m from
        // the vertex; the walls themselves are no diagonals.
        for id in [0, 1, 3, 4] {
            assert!(
                corner_diagonal(&map, id, r, CORNER_WALL_REACH_M, TURN).is_none(),
                "s{id}"
            );
        }
    }

    #[test]
    fn a_corner_needs_one_confirmed_wall() {
        let r = CORNER_DIAGONAL_RADIUS_M;
        let tentative = room_corner();
        assert!(corner_diagonal(&tentative, 2, r, CORNER_WALL_REACH_M, TURN).is_none());
        let mut one = room_corner();
        confirm(&mut one, 1);
        let d = corner_diagonal(&one, 2, r, CORNER_WALL_REACH_M, TURN).expect("s1 is confirmed");
        assert_eq!(d.walls, [0, 1]);
    }

    #[test]
    fn a_confirmed_chord_needs_two_confirmed_walls() {
        let r = CORNER_DIAGONAL_RADIUS_M;
        // s2 (the chord) confirmed, and only s1 of the walls: s2's two snapshots of plane
        // support outweigh the one confirmed wall, and it stays.
        let mut one = room_corner();
        confirm(&mut one, 1);
        confirm(&mut one, 2);
        assert!(corner_diagonal(&one, 2, r, CORNER_WALL_REACH_M, TURN).is_none());
        // With both walls confirmed it is a diagonal again (45° from each, ends 0.632 m away).
        confirm(&mut one, 0);
        let d = corner_diagonal(&one, 2, r, CORNER_WALL_REACH_M, TURN).expect("two walls");
        assert_eq!(d.walls, [0, 1]);
    }

    #[test]
    fn walls_short_of_the_vertex_make_a_corner_within_their_reach() {
        // The walls stop 1.2 m short of the vertex (within the 1.6 m reach); then 2 m short.
        for (gap, corner) in [(1.2, true), (2.0, false)] {
            let mut map = Map::from_segments(vec![
                test_wall(0, (gap, 0.0), (4.0, 0.0), 1.0),
                test_wall(1, (0.0, gap), (0.0, 4.0), 1.0),
                test_wall(2, (0.6, 0.2), (0.2, 0.6), 1.0),
            ]);
            confirm(&mut map, 0);
            confirm(&mut map, 1);
            let found = corner_diagonal(&map, 2, CORNER_DIAGONAL_RADIUS_M, 1.6, TURN);
            assert_eq!(found.is_some(), corner, "walls {gap} m short");
        }
    }

    #[test]
    fn walls_sharper_than_thirty_degrees_make_no_corner() {
        // s1 turned 20° from s0 (under 30°): the pair is not a corner; at 40° it is. The chord
        // runs at 120° (perpendicular to the 30° line that bisects 0° and 60°, kept at least
        // 15° from both walls in either case).
        for (deg, corner) in [(20.0f64, false), (40.0, true)] {
            let t = deg.to_radians();
            let c = 120f64.to_radians();
            let mid = (0.5, 0.25);
            let mut map = Map::from_segments(vec![
                test_wall(0, (0.0, 0.0), (3.0, 0.0), 1.0),
                test_wall(1, (0.0, 0.0), (3.0 * t.cos(), 3.0 * t.sin()), 1.0),
                test_wall(
                    2,
                    (mid.0 - 0.1 * c.cos(), mid.1 - 0.1 * c.sin()),
                    (mid.0 + 0.1 * c.cos(), mid.1 + 0.1 * c.sin()),
                    1.0,
                ),
            ]);
            confirm(&mut map, 0);
            confirm(&mut map, 1);
            let found = corner_diagonal(&map, 2, 1.0, 1.6, TURN);
            assert_eq!(found.is_some(), corner, "walls {deg}° apart");
        }
    }

    #[test]
    fn a_wall_confirmed_this_step_finds_an_older_diagonal_near_it() {
        let mut map = room_corner();
        confirm(&mut map, 0);
        confirm(&mut map, 1);
        // s0 can make a new corner (confirmed this step): s2 lies near its end-points and is
        // found; s3 and s4 are not diagonals.
        let found = corner_diagonals(&map, &[0], 1.0, 1.6, TURN);
        assert_eq!(found.iter().map(|d| d.segment).collect::<Vec<_>>(), vec![2]);
        // s2 made or grown itself: it is tested, and found.
        let itself = corner_diagonals(&map, &[2], 1.0, 1.6, TURN);
        assert_eq!(
            itself.iter().map(|d| d.segment).collect::<Vec<_>>(),
            vec![2]
        );
        // Both changed: s2 is found once.
        let both = corner_diagonals(&map, &[2, 0, 2], 1.0, 1.6, TURN);
        assert_eq!(both.iter().map(|d| d.segment).collect::<Vec<_>>(), vec![2]);
        // Nothing changed this step: nothing is tested, nothing found.
        assert!(corner_diagonals(&map, &[], 1.0, 1.6, TURN).is_empty());
    }

    #[test]
    fn only_the_corners_a_changed_segment_can_be_a_wall_of_are_tested() {
        // s2 (the chord, confirmed) stands across the corner of s0 and s1, both confirmed.
        let mut map = room_corner();
        for id in [0, 1, 2] {
            confirm(&mut map, id);
        }
        // s3 changed: it runs 45° from s2 and its line passes 0.15 and 0.55 m from s2's ends,
        // so it could be a wall of s2's corner; but it is tentative and s2 confirmed, and a
        // confirmed chord is a diagonal only of two confirmed walls: s2 is not tested.
        assert!(corner_diagonals(&map, &[3], 1.0, 1.6, TURN).is_empty());
        // s4 changed (its line 1.91 m from both of s2's ends): no corner of s2 is new.
        assert!(corner_diagonals(&map, &[4], 1.0, 1.6, TURN).is_empty());
        // s0 changed: s2 is tested and found, with its corner of s0 and s1.
        let found = corner_diagonals(&map, &[0], 1.0, 1.6, TURN);
        assert_eq!(found.len(), 1);
        assert_eq!((found[0].segment, found[0].walls), (2, [0, 1]));
    }
}
