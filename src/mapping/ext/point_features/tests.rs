//! Unit tests of `point_features.rs`.

use super::*;
use crate::mapping::ext::beam_geometry::{round_echo, RoundEcho};
use crate::mapping::model::map::{test_wall, Segment};

fn wall(id: u32, a: (f64, f64), b: (f64, f64)) -> Segment {
    test_wall(id, a, b, 2.0)
}

/// A sensor at the origin looking along +x (half-beam 12.5°) and a pillar of radius 0.3 m
/// whose centre stands 1.5 m away, `off_deg` from the axis.
fn pillar_echo(off_deg: f64) -> Option<RoundEcho> {
    let beam = Beam {
        origin: Point::origin(),
        direction: Vec2::new(1.0, 0.0),
        range_m: 1.2,
    };
    let at = Point::from(crate::geometry::unit(off_deg.to_radians()) * 1.5);
    round_echo(&at, 0.3, &beam, HalfCone::new(12.5f64.to_radians()))
}

#[test]
fn a_pillar_inside_the_beam_echoes_along_the_ray_through_its_centre() {
    // 10° off the axis, inside the cone: 1.5 − 0.3 = 1.2 m.
    let echo = pillar_echo(10.0).unwrap();
    assert!((echo.range_m - 1.2).abs() < 1e-12);
    assert_eq!(echo.d_range_d_radius, -1.0);
}

#[test]
fn a_pillar_just_outside_the_beam_echoes_along_the_cone_edge() {
    // 15° off the axis: the edge at 12.5° passes 1.5 sin 2.5° = 0.065429 m from the centre,
    // 1.5 cos 2.5° = 1.498572 m along, and meets the surface √(0.09 − 0.065429²) = 0.292778
    // m short of that: 1.205794 m, 5.8 mm beyond the 1.2 m of the ray through the centre.
    // The incidence there is acos(0.292778 / 0.3) = 12.6°.
    let echo = pillar_echo(15.0).unwrap();
    assert!((echo.range_m - 1.205794).abs() < 1e-6, "{echo:?}");
    assert!((echo.d_range_d_radius - -0.3 / 0.292778).abs() < 1e-5);
    // A reading of 1.2058 m is explained; the centre's own ray would have refused it.
    let beam = Beam {
        origin: Point::origin(),
        direction: Vec2::new(1.0, 0.0),
        range_m: 1.2058,
    };
    let at = Point::from(crate::geometry::unit(15f64.to_radians()) * 1.5);
    assert!(explains_round(&at, 0.3, &beam, 1.0, 12.5f64.to_radians()));
    // A point there (radius 0) echoes nothing: the edge cannot meet it.
    let half = HalfCone::new(12.5f64.to_radians());
    assert_eq!(round_echo(&at, 0.0, &beam, half), None);
}

#[test]
fn a_pillar_met_by_the_cone_edge_beyond_the_incidence_limit_echoes_nothing() {
    // The edge meets the surface within 60° of its normal while it passes within
    // 0.3 sin 60° = 0.2598 m of the centre: 1.5 sin(Δ) ≤ 0.2598, Δ ≤ 9.97° past the edge.
    // At 22° (Δ = 9.5°) it echoes; at 23.5° (Δ = 11°, 0.2862 m: it still grazes the
    // surface) it does not; at 35° (Δ = 22.5°, 0.574 m) the edge misses.
    assert!(pillar_echo(22.0).is_some());
    assert_eq!(pillar_echo(23.5), None);
    assert_eq!(pillar_echo(35.0), None);
}

proptest::proptest! {
    /// The gradient [`round_echo`] gives is the range's: finite differences agree with it.
    #[test]
    fn the_echo_gradient_is_the_ranges(
        off_deg in -22.0..22.0f64,
        distance_m in 0.8..4.0f64,
        radius_m in 0.06..0.5f64,
    ) {
        let beam = Beam { origin: Point::origin(), direction: Vec2::new(1.0, 0.0), range_m: 1.0 };
        let half = HalfCone::new(12.5f64.to_radians());
        let at = Point::from(crate::geometry::unit(off_deg.to_radians()) * distance_m);
        let Some(echo) = round_echo(&at, radius_m, &beam, half) else { return Ok(()) };
        let h = 1e-7;
        let moved = |dx: f64, dy: f64, dr: f64| {
            round_echo(&(at + Vec2::new(dx, dy)), radius_m + dr, &beam, half).map(|e| e.range_m)
        };
        // Skip the seams (the cone's edge, the incidence limit), where one side of the
        // difference takes the other branch.
        let (Some(x), Some(y), Some(r)) = (moved(h, 0.0, 0.0), moved(0.0, h, 0.0), moved(0.0, 0.0, h)) else {
            return Ok(());
        };
        if (off_deg.abs() - 12.5).abs() < 1e-3 {
            return Ok(());
        }
        proptest::prop_assert!(((x - echo.range_m) / h - echo.d_range_d_centre.x).abs() < 1e-4);
        proptest::prop_assert!(((y - echo.range_m) / h - echo.d_range_d_centre.y).abs() < 1e-4);
        proptest::prop_assert!(((r - echo.range_m) / h - echo.d_range_d_radius).abs() < 1e-4);
    }
}

#[test]
fn a_junction_seen_from_inside_its_angle_is_a_corner_from_outside_an_edge() {
    // Walls from (0, 0) to (3, 0) and to (0, 3): the sensor at (1, 1) looks into the 90°
    // angle (45° to each arm: 45 + 45 = 90), the one at (-1, -1) from outside (135 + 135).
    let map = Map::from_segments(vec![
        wall(0, (0.0, 0.0), (3.0, 0.0)),
        wall(1, (0.0, 3.0), (0.0, 0.0)),
    ]);
    let at = Point::new(0.02, 0.02);
    assert_eq!(
        classify(&map, &at, &Point::new(1.0, 1.0), 0.2),
        FeatureKind::Corner
    );
    assert_eq!(
        classify(&map, &at, &Point::new(-1.0, -1.0), 0.2),
        FeatureKind::Edge
    );
    // One wall ending there (a door jamb): an edge from anywhere.
    let jamb = Map::from_segments(vec![wall(0, (0.0, 0.0), (3.0, 0.0))]);
    assert_eq!(
        classify(&jamb, &at, &Point::new(1.0, 1.0), 0.2),
        FeatureKind::Edge
    );
}

#[test]
fn arcs_within_the_merge_radius_move_one_feature_to_their_mean() {
    // At 2 m: tolerance 0.06 m, merge radius 0.06 + 2·tan 5° = 0.235 m.
    assert!((merge_radius_m(3.0, 2.0) - (0.06 + 2.0 * 5f64.to_radians().tan())).abs() < 1e-12);
    let mut map = Map::default();
    let sensor = Point::new(0.0, -2.0);
    let (f0, new0) = file_arc(&mut map, Point::new(0.0, 0.0), 2.0, &sensor, 3, 3.0);
    let (f1, new1) = file_arc(&mut map, Point::new(0.1, 0.0), 1.9, &sensor, 4, 3.0);
    assert!(new0 && !new1 && f0 == f1);
    let f = map.feature(f0).unwrap();
    assert!((f.at.x - 0.05).abs() < 1e-12 && f.at.y.abs() < 1e-12);
    assert_eq!(
        (f.observations, f.created, f.updated.clone()),
        (2, 3, vec![4])
    );
    assert!((f.range_m - 1.9).abs() < 1e-12);
    // 0.3 m away: a second feature.
    let (f2, new2) = file_arc(&mut map, Point::new(0.35, 0.0), 2.0, &sensor, 5, 3.0);
    assert!(new2 && f2 != f0);
    map.rebuild_index();
    assert!(map.check_invariants(0).is_ok());
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(64))]
    /// Searching the confirmed features one by one finds the feature the grid finds, for
    /// beams among crowded features (some confirmed), some at the edges of their reach.
    #[test]
    fn the_direct_search_finds_the_feature_the_grid_finds(
        features in proptest::collection::vec((0.0..4.0f64, 0.0..4.0f64, proptest::bool::ANY), 1..40),
        beams in proptest::collection::vec((0.0..4.0f64, 0.0..4.0f64, 0.0..std::f64::consts::TAU, 0.2..4.0f64), 1..20),
    ) {
        let mut map = Map::default();
        for &(x, y, confirmed) in &features {
            let id = map.push_feature(PointFeature::seen_once(FeatureKind::Corner, Point::new(x, y), 1.0, Point::origin(), 0));
            if confirmed {
                map.features[id as usize].baseline_m = 1.0;
            }
            // Some of them rounded (a pillar's centre behind its surface, §8.14).
            if x > 2.0 {
                map.features[id as usize].radius_m = 0.3;
            }
        }
        let listed: Vec<(u32, Point, f64)> =
            map.confirmed_features().map(|f| (f.id, f.at, f.radius_m)).collect();
        let half = 12.5f64.to_radians();
        let mut scratch = Vec::new();
        for &(x, y, dir, range_m) in &beams {
            let origin = Point::new(x, y);
            let direction = Vec2::new(dir.cos(), dir.sin());
            // Aimed at a feature now and then, so that some beams are explained.
            let beam = Beam { origin, direction, range_m };
            let aimed = features.first().map(|&(fx, fy, _)| {
                let v = Point::new(fx, fy) - origin;
                let surface_m = v.norm() - map.features[0].radius_m;
                Beam { origin, direction: v.normalize(), range_m: surface_m * (1.0 + 0.02 * dir.sin()) }
            });
            for beam in std::iter::once(beam).chain(aimed.filter(|b| b.range_m > 0.05)) {
                proptest::prop_assert_eq!(
                    explaining_feature_among(&listed, &beam, 3.0, half),
                    explaining_feature(&map, &beam, 3.0, half, &mut scratch)
                );
            }
        }
    }
}

#[test]
fn only_a_confirmed_feature_explains_a_reading() {
    let mut map = Map::default();
    let sensor = Point::new(0.0, 0.0);
    let beam = Beam {
        origin: sensor,
        direction: Vec2::new(1.0, 0.0),
        range_m: 2.0,
    };
    let half = 12.5f64.to_radians();
    let mut scratch = Vec::new();
    let explaining =
        |map: &Map, scratch: &mut Vec<u32>| explaining_feature(map, &beam, 3.0, half, scratch);
    let (id, _) = file_arc(&mut map, Point::new(2.0, 0.1), 2.0, &sensor, 0, 3.0);
    assert_eq!(explaining(&map, &mut scratch), None);
    // Seen again from the same place (a lap driven back): still not confirmed.
    file_arc(&mut map, Point::new(2.0, 0.1), 2.0, &sensor, 1, 3.0);
    assert_eq!(explaining(&map, &mut scratch), None);
    // From 0.25 m aside (at least 0.2032 m): confirmed, it explains the reading.
    let aside = Point::new(0.0, 0.25);
    file_arc(&mut map, Point::new(2.0, 0.1), 2.0, &aside, 2, 3.0);
    assert_eq!(explaining(&map, &mut scratch), Some(id));
    assert!((map.feature(id).unwrap().baseline_m - 0.25).abs() < 1e-12);
}
