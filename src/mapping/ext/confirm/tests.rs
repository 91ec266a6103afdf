//! Plane support's tests (docs/algorithm.md §8.7).

use super::*;
use crate::geometry::Vec2;
use crate::mapping::model::map::{test_wall, EndPoint};

const HALF: f64 = 12.5 * std::f64::consts::PI / 180.0;

/// Sensor `sensor` of snapshot `snapshot` at (`x`, `y`) looking along +y, reading `range_m`.
fn up(snapshot: usize, sensor: usize, x: f64, y: f64, range_m: f64) -> (ReadingRef, Beam) {
    let beam = Beam {
        origin: Point::new(x, y),
        direction: Vec2::new(0.0, 1.0),
        range_m,
    };
    (ReadingRef::new(snapshot, sensor), beam)
}

/// The wall y = 1 from x = −0.2 to 0.8.
fn wall() -> (Point, Point) {
    (Point::new(-0.2, 1.0), Point::new(0.8, 1.0))
}

fn pair_of(beams: &[(ReadingRef, Beam)]) -> Option<BaselinePair> {
    let (a, b) = wall();
    baseline_pair(
        beams,
        &a,
        &b,
        3.0,
        HALF,
        PlaneEchoModel::Foot,
        CONFIRMING_BASELINE_M,
        CONFIRMING_BASELINE_TURN_RAD,
    )
}

#[test]
fn baseline_pair_takes_the_two_snapshots_farthest_apart_along_the_wall() {
    // A side sensor reads 1.00 m from x = 0, 0.25 and 0.5 (snapshots 1, 2, 3): the pair
    // 1–3 is 0.5 m apart along the wall, 0 across.
    let beams = [
        up(1, 4, 0.0, 0.0, 1.0),
        up(2, 4, 0.25, 0.0, 1.0),
        up(3, 4, 0.5, 0.0, 1.0),
    ];
    let pair = pair_of(&beams).unwrap();
    assert_eq!(pair.readings[0].snapshot, 1);
    assert_eq!(pair.readings[1].snapshot, 3);
    assert!((pair.along_m - 0.5).abs() < 1e-12 && pair.across_m.abs() < 1e-12);
    // Given in the other order, the earlier snapshot still comes first.
    let reversed = [beams[2], beams[1], beams[0]];
    assert_eq!(pair_of(&reversed).unwrap().readings, pair.readings);
}

#[test]
fn readings_of_one_snapshot_make_no_baseline() {
    // Two sensors of snapshot 5, 0.3 m apart along the wall, both reading 1 m.
    assert!(pair_of(&[up(5, 3, 0.0, 0.0, 1.0), up(5, 4, 0.3, 0.0, 1.0)]).is_none());
}

#[test]
fn sensors_closer_than_eight_inches_along_the_wall_make_no_baseline() {
    // 0.20 m < 8 in = 0.2032 m; 0.21 m passes.
    assert!(pair_of(&[up(1, 4, 0.0, 0.0, 1.0), up(2, 4, 0.2, 0.0, 1.0)]).is_none());
    let pair = pair_of(&[up(1, 4, 0.0, 0.0, 1.0), up(2, 4, 0.21, 0.0, 1.0)]).unwrap();
    assert!((pair.along_m - 0.21).abs() < 1e-12);
}

#[test]
fn a_sensor_that_moved_towards_the_wall_makes_no_baseline() {
    // 0.3 m along and 0.1 m towards the wall (reading 0.90 m): 0.1 > 0.3 · tan 10° =
    // 0.0529, refused. 0.05 m towards it (reading 0.95 m): 0.05 ≤ 0.0529, a baseline.
    assert!(pair_of(&[up(1, 4, 0.0, 0.0, 1.0), up(2, 4, 0.3, 0.1, 0.9)]).is_none());
    let pair = pair_of(&[up(1, 4, 0.0, 0.0, 1.0), up(2, 4, 0.3, 0.05, 0.95)]).unwrap();
    assert!((pair.along_m - 0.3).abs() < 1e-12 && (pair.across_m - 0.05).abs() < 1e-12);
}

#[test]
fn a_reading_that_does_not_support_the_plane_makes_no_baseline() {
    // At x = 0.4 the sensor reads 1.10 m: |1 − 1.1| = 0.1 > 0.033 (3 % of 1.1).
    assert!(pair_of(&[up(1, 4, 0.0, 0.0, 1.0), up(2, 4, 0.4, 0.0, 1.1)]).is_none());
}

/// End-points read from `range_m`.
fn ends(a: (f64, f64), b: (f64, f64), range_m: f64) -> [EndPoint; 2] {
    let e = |(x, y): (f64, f64)| EndPoint {
        point: Point::new(x, y),
        range_m,
    };
    [e(a), e(b)]
}

const THETA_O: f64 = 15.0 * std::f64::consts::PI / 180.0;

#[test]
fn a_refit_within_two_tolerances_of_the_old_line_keeps_it() {
    // Old line y = 1 from x = 0 to 2. After: (0, 1)–(1.5, 1.05), read at 1 m: the end is
    // 0.05 m off, under 2 · 0.03 = 0.06; turned atan(0.05 / 1.5) = 1.9° < 15°.
    let before = [Point::new(0.0, 1.0), Point::new(2.0, 1.0)];
    let after = ends((0.0, 1.0), (1.5, 1.05), 1.0);
    assert!(refit_moved_off(before, after, 3.0, THETA_O).is_none());
}

#[test]
fn a_refit_that_moved_an_end_off_the_old_line_unconfirms_it() {
    // 0.07 m off > 0.06 (read at 1 m); read at 3 m the limit is 2 · 0.09 = 0.18: kept.
    let before = [Point::new(0.0, 1.0), Point::new(2.0, 1.0)];
    let t = refit_moved_off(before, ends((0.0, 1.0), (1.5, 1.07), 1.0), 3.0, THETA_O).unwrap();
    assert!(t.off_line_m[0].abs() < 1e-12 && (t.off_line_m[1] - 0.07).abs() < 1e-12);
    assert!((t.limits_m[0] - 0.06).abs() < 1e-12 && (t.limits_m[1] - 0.06).abs() < 1e-12);
    assert!((t.turn_rad - (0.07f64 / 1.5).atan()).abs() < 1e-12);
    assert_eq!(t.after, [Point::new(0.0, 1.0), Point::new(1.5, 1.07)]);
    assert!(refit_moved_off(before, ends((0.0, 1.0), (1.5, 1.07), 3.0), 3.0, THETA_O).is_none());
}

#[test]
fn a_refit_that_turned_past_theta_o_unconfirms_it() {
    // (0, 1)–(0.2, 1.055): the end is 0.055 m off (under 0.06) but the piece turned
    // atan(0.055 / 0.2) = 15.4° > θ_o = 15°.
    let before = [Point::new(0.0, 1.0), Point::new(2.0, 1.0)];
    let t = refit_moved_off(before, ends((0.0, 1.0), (0.2, 1.055), 1.0), 3.0, THETA_O).unwrap();
    assert!((t.turn_rad.to_degrees() - 15.376).abs() < 1e-3);
    assert!(t.off_line_m[1] < t.limits_m[1]);
}

#[test]
fn a_baseline_confirms_a_tentative_segment_once() {
    let mut map = Map::from_segments(vec![test_wall(0, (-0.2, 1.0), (0.8, 1.0), 1.0)]);
    map.confirms_segments = true;
    let beams = [up(1, 4, 0.0, 0.0, 1.0), up(3, 4, 0.5, 0.0, 1.01)];
    let pair = pair_of(&beams).unwrap();
    assert!(map.is_tentative(0));
    let t = note_baseline_support(&mut map, 0, pair, &beams[1].1, 3).unwrap();
    assert!(t.confirmed && t.snapshots == CONFIRMING_SNAPSHOTS);
    assert_eq!((t.sensor, t.range_m), (4, 1.01));
    // The later sensor stands 1 m from the wall's line.
    assert!((t.distance_m - 1.0).abs() < 1e-12);
    assert_eq!(t.baseline, Some(pair));
    assert!(!map.is_tentative(0));
    assert!(map.check_invariants(0).is_ok());
    // Confirmed already: nothing more to note.
    assert!(note_baseline_support(&mut map, 0, pair, &beams[1].1, 4).is_none());
}

#[test]
fn two_snapshots_of_plane_support_confirm_a_segment_once_each() {
    let mut map = Map::from_segments(vec![test_wall(0, (-1.0, 2.0), (1.0, 2.0), 2.0)]);
    map.confirms_segments = true;
    let half = 12.5f64.to_radians();
    // Straight at the wall, 2.02 m: |2 − 2.02| = 0.02 ≤ 0.0606.
    let straight = Beam {
        origin: Point::origin(),
        direction: Vec2::new(0.0, 1.0),
        range_m: 2.02,
    };
    // 20° off the perpendicular: outside the 12.5° half beam, no support.
    let (s, c) = (20f64.to_radians().sin(), 20f64.to_radians().cos());
    let oblique = Beam {
        direction: Vec2::new(s, c),
        ..straight
    };
    assert!(map.is_tentative(0));
    assert!(note_plane_support(
        &mut map,
        0,
        &[(3, oblique)],
        View::of(0),
        3.0,
        half,
        PlaneEchoModel::Foot
    )
    .is_none());
    let first = note_plane_support(
        &mut map,
        0,
        &[(1, straight)],
        View::of(0),
        3.0,
        half,
        PlaneEchoModel::Foot,
    )
    .unwrap();
    assert_eq!((first.snapshots, first.confirmed), (1, false));
    assert!((first.distance_m - 2.0).abs() < 1e-12);
    // The same snapshot again counts once.
    assert!(note_plane_support(
        &mut map,
        0,
        &[(2, straight)],
        View::of(0),
        3.0,
        half,
        PlaneEchoModel::Foot
    )
    .is_none());
    let second = note_plane_support(
        &mut map,
        0,
        &[(1, straight)],
        View::of(1),
        3.0,
        half,
        PlaneEchoModel::Foot,
    )
    .unwrap();
    assert_eq!((second.snapshots, second.confirmed), (2, true));
    assert!(!map.is_tentative(0));
    assert!(map.check_invariants(0).is_ok());
    // A map that does not confirm calls nothing tentative.
    assert!(!Map::default().is_tentative(7));
}

#[test]
fn a_second_view_counts_only_from_a_robot_that_moved_the_spacing() {
    // The wall y = 2 read straight on at 2.02 m by a robot at x = 0 (snapshot 0), then at
    // x = 0.1 m (snapshot 1: 0.1 m < 6 in = 0.1524 m, the same view) and at x = 0.25 m
    // (snapshot 2: 0.25 m from the first view's place, another view: confirmed).
    let mut map = Map::from_segments(vec![test_wall(0, (-1.0, 2.0), (1.0, 2.0), 2.0)]);
    map.confirms_segments = true;
    let half = 12.5f64.to_radians();
    let at = |x: f64| Beam {
        origin: Point::new(x, 0.0),
        direction: Vec2::new(0.0, 1.0),
        range_m: 2.02,
    };
    let view = |snapshot, x: f64| View {
        snapshot,
        robot: Point::new(x, 0.0),
        spacing_m: 0.1524,
    };
    let note = |map: &mut Map, x: f64, snapshot: usize| {
        note_plane_support(
            map,
            0,
            &[(1, at(x))],
            view(snapshot, x),
            3.0,
            half,
            PlaneEchoModel::Foot,
        )
    };
    assert_eq!(note(&mut map, 0.0, 0).map(|t| t.snapshots), Some(1));
    // Recorded, not counted: the robot stood 0.1 m from the first view's place.
    let same = note(&mut map, 0.1, 1).unwrap();
    assert_eq!((same.snapshots, same.confirmed), (1, false));
    assert!(same
        .same_view_moved_m
        .is_some_and(|m| (m - 0.1).abs() < 1e-9));
    assert!(map.is_tentative(0));
    let second = note(&mut map, 0.25, 2).unwrap();
    assert_eq!((second.snapshots, second.confirmed), (2, true));
    assert_eq!(second.same_view_moved_m, None);
    assert_eq!(map.plane_support.get(&0).unwrap().last_view_mm, [250, 0]);
}

#[test]
fn turning_in_place_is_one_view_however_far_the_sensors_swing() {
    // A robot at the origin turns in place before the wall y = 2: two of its sonars, 0.17 m
    // from its centre, read the wall square on at two of its headings, from (0, 0.17) and,
    // turned, from (0.17, 0). The sensors stood 0.24 m apart (over 0.1524 m), the robot not
    // at all; a corner would read the same: one view, not confirmed.
    let mut map = Map::from_segments(vec![test_wall(0, (-1.0, 2.0), (1.0, 2.0), 2.0)]);
    map.confirms_segments = true;
    let half = 12.5f64.to_radians();
    let from = |x: f64, y: f64| Beam {
        origin: Point::new(x, y),
        direction: Vec2::new(0.0, 1.0),
        range_m: 2.0 - y,
    };
    let view = |snapshot| View {
        snapshot,
        robot: Point::origin(),
        spacing_m: 0.1524,
    };
    let first = note_plane_support(
        &mut map,
        0,
        &[(0, from(0.0, 0.17))],
        view(0),
        3.0,
        half,
        PlaneEchoModel::Foot,
    );
    assert_eq!(first.map(|t| t.snapshots), Some(1));
    let turned = note_plane_support(
        &mut map,
        0,
        &[(0, from(0.17, 0.0))],
        view(1),
        3.0,
        half,
        PlaneEchoModel::Foot,
    )
    .unwrap();
    assert_eq!((turned.snapshots, turned.confirmed), (1, false));
    assert_eq!(turned.same_view_moved_m, Some(0.0));
    assert!(map.is_tentative(0));
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(300))]

    /// A single ray meeting a wall at any incidence up to 80°, read at the distance along its
    /// axis within the tolerance, supports the wall along the axis and predicts that distance;
    /// read past the tolerance, it does not.
    #[test]
    fn a_ray_supports_the_wall_it_meets_along_its_axis(
        normal_deg in 0.0f64..360.0,
        offset_m in 0.3f64..5.0,
        incidence_deg in -80.0f64..80.0,
        error_of_tolerance in -0.99f64..0.99,
        along_m in -2.0f64..2.0,
    ) {
        let normal = Vec2::new(normal_deg.to_radians().cos(), normal_deg.to_radians().sin());
        let along = Vec2::new(-normal.y, normal.x);
        // The wall n·x = offset, from 3 m before to 3 m past the axis's hit.
        let axis_rad = (normal_deg + incidence_deg).to_radians();
        let direction = Vec2::new(axis_rad.cos(), axis_rad.sin());
        let origin = Point::origin() + along * along_m;
        let distance_m = (offset_m - normal.dot(&origin.coords)) / normal.dot(&direction);
        let hit = origin + direction * distance_m;
        let (a, b) = (hit - along * 3.0, hit + along * 3.0);
        // The tolerance of any reading within 3 % below the distance is at least this.
        let tolerance_m = feature_tolerance_m(3.0, 0.97 * distance_m);
        let read = |range_m: f64| Beam { origin, direction, range_m };
        let within = read(distance_m + error_of_tolerance * tolerance_m);
        let predicted = supports_along_axis(&within, &a, &b, 3.0);
        proptest::prop_assert!(predicted.is_some_and(|d| (d - distance_m).abs() < 1e-9));
        let past = read(distance_m + 3.0 * feature_tolerance_m(3.0, distance_m * 1.5));
        proptest::prop_assert!(supports_along_axis(&past, &a, &b, 3.0).is_none());
        // The plane test dispatches to it.
        proptest::prop_assert_eq!(
            supports(&within, &a, &b, 3.0, HALF, PlaneEchoModel::Axis),
            predicted
        );
    }
}
