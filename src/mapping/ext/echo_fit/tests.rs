//! Unit tests of `echo_fit.rs`.

use super::*;
use crate::mapping::ext::confirm::PlaneEchoModel;
use crate::mapping::ext::point_features::beams_at_reflector;
use crate::mapping::model::support::ReadingRef;

const HALF: f64 = 12.5 * std::f64::consts::PI / 180.0;
const TURN: f64 = 15.0 * std::f64::consts::PI / 180.0;

fn beam(x: f64, y: f64, heading_deg: f64, range_m: f64) -> Beam {
    Beam {
        origin: Point::new(x, y),
        direction: unit(heading_deg.to_radians()),
        range_m,
    }
}

fn axis_points(beams: &[Beam]) -> Vec<Point> {
    beams.iter().map(Beam::axis_point).collect()
}

fn support(beams: &[Beam]) -> Vec<SupportPoint> {
    axis_points(beams)
        .into_iter()
        .enumerate()
        .map(|(i, point)| SupportPoint {
            point,
            range_m: beams[i].range_m,
            reading: ReadingRef::new(i, 0),
        })
        .collect()
}

#[test]
fn a_wall_seen_square_on_keeps_its_line_and_points_move_to_the_feet() {
    // Sensors at x = 0, 1, 2 looking 10° off the wall's normal (+y); the wall y = 1.5 is read
    // at 1.5 m (the foot, 10° off the axis, lies inside the 12.5° half cone).
    let beams: Vec<Beam> = (0..3).map(|i| beam(i as f64, 0.0, 80.0, 1.5)).collect();
    let axis = axis_points(&beams);
    // On the axis: y = 1.5 · sin 80° = 1.4772, 2.3 cm short.
    assert!((axis[0].y - 1.4772).abs() < 1e-4);
    let line = fit_echo_line(&beams, &axis, 3.0, HALF, TURN).unwrap();
    assert!((line.normal.y - 1.0).abs() < 1e-6 && (line.offset_m - 1.5).abs() < 1e-6);
    let placed = place_echoes(&support(&beams), &beams, &line, HALF);
    assert_eq!((placed.at_foot, placed.at_cone_edge), (3, 0));
    for (q, x) in placed.points.iter().zip([0.0, 1.0, 2.0]) {
        assert!((q.point - Point::new(x, 1.5)).norm() < 1e-6, "{q:?}");
    }
    // Moved by the chord of 10° at 1.5 m: 2 · 1.5 · sin 5° = 0.2615 m.
    assert!((placed.moved_max_m - 0.2615).abs() < 1e-3);
}

#[test]
fn placed_points_are_ordered_along_the_line_the_way_the_piece_ran() {
    // The wall y = 1.5 read from x = 2, 0, 1 by a piece that ran from x = 2 towards x = 0
    // (its first reading at x = 2, its last at x = 1): ordered 2, 1, 0.
    let beams: Vec<Beam> = [2.0, 0.0, 1.0]
        .iter()
        .map(|&x| beam(x, 0.0, 90.0, 1.5))
        .collect();
    let points = support(&beams);
    let line = fit_echo_line(&beams, &axis_points(&beams), 3.0, HALF, TURN).unwrap();
    let mut placed = place_echoes(&points, &beams, &line, HALF).points;
    order_along_line(&mut placed, &line, &points[0], &points[2]);
    let xs: Vec<f64> = placed.iter().map(|q| q.point.x).collect();
    assert!(
        xs.windows(2).all(|w| w[0] > w[1]) && (xs[0] - 2.0).abs() < 1e-9,
        "{xs:?}"
    );
}

#[test]
fn an_oblique_wall_is_found_from_its_cone_edge_echoes() {
    // The wall y = 2 seen 30° off its normal: ranges 2 / cos 17.5° = 2.0971 m.
    let d = 2.0 / 17.5f64.to_radians().cos();
    let beams: Vec<Beam> = [0.0, 0.4, 0.8, 1.2]
        .iter()
        .map(|&x| beam(x, 0.0, 60.0, d))
        .collect();
    let line = fit_echo_line(&beams, &axis_points(&beams), 3.0, HALF, TURN).unwrap();
    assert!((line.offset_m - 2.0).abs() < 1e-3, "{line:?}");
    let placed = place_echoes(&support(&beams), &beams, &line, HALF);
    assert_eq!((placed.at_foot, placed.at_cone_edge), (0, 4));
    // Each echo point lies on the cone edge at 72.5°: (x + 2 tan 17.5°, 2) = (x + 0.6306, 2).
    for (q, x) in placed.points.iter().zip([0.0, 0.4, 0.8, 1.2]) {
        assert!(
            (q.point - Point::new(x + 0.6306, 2.0)).norm() < 2e-3,
            "{q:?}"
        );
    }
}

#[test]
fn a_wall_heard_from_the_cone_edge_at_up_to_sixty_degrees_is_found() {
    // The wall y = 2 seen 60° off its normal (the sonars look 30° from +x): the cone's
    // nearer edge meets it at 60° − 12.5° = 47.5° (beyond the old 40° limit, within 60°),
    // read at 2 / cos 47.5° = 2.9604 m. On the axes the points lie at
    // y = 2.9604 · sin 30° = 1.4802, 0.52 m short of the wall.
    let d = 2.0 / 47.5f64.to_radians().cos();
    assert!((d - 2.9604).abs() < 1e-4);
    let beams: Vec<Beam> = [0.0, 0.4, 0.8]
        .iter()
        .map(|&x| beam(x, 0.0, 30.0, d))
        .collect();
    assert!((axis_points(&beams)[0].y - 1.4802).abs() < 1e-4);
    let cos = incidence_cosine(&beams[0], &Vec2::new(0.0, 1.0), HalfCone::new(HALF));
    assert!((cos.unwrap() - 47.5f64.to_radians().cos()).abs() < 1e-12);
    let line = fit_echo_line(&beams, &axis_points(&beams), 3.0, HALF, TURN).unwrap();
    assert!((line.offset_m - 2.0).abs() < 1e-3, "{line:?}");
    // Looking 15° from +x (75° off the normal) the edge meets the wall at 62.5°: beyond the
    // limit, no line.
    let steep = beam(0.0, 0.0, 15.0, 2.0 / 62.5f64.to_radians().cos());
    assert!(incidence_cosine(&steep, &Vec2::new(0.0, 1.0), HalfCone::new(HALF)).is_none());
}

#[test]
fn ranges_no_plane_explains_are_left_on_their_axes() {
    // A corner at (1, 2) read from three places along y = 0 with a sensor looking at it:
    // ranges √5, 2, √5 are too far apart for one plane within 3 %.
    let beams = beams_at_reflector(Point::new(1.0, 2.0), 0.0, &[0.0, 1.0, 2.0]);
    assert!(fit_echo_line(&beams, &axis_points(&beams), 3.0, HALF, TURN).is_none());
}

#[test]
fn an_echo_point_beyond_a_confirmed_wall_is_behind_it_and_one_before_it_is_not() {
    use crate::mapping::ext::confirm::{note_plane_support, View};
    use crate::mapping::model::map::test_wall;
    // A wall y = 1 from x = -1 to 1; a sensor at the origin reads 2 m (tolerance 0.06 m).
    let mut map = Map::from_segments(vec![test_wall(0, (-1.0, 1.0), (1.0, 1.0), 1.0)]);
    map.confirms_segments = true;
    let far = beam(0.0, 0.0, 90.0, 2.0);
    let echo = Point::new(0.3, 1.977);
    // Tentative walls do not hide anything.
    assert!(!echo_behind_confirmed_wall(&map, &far, &echo, 3.0));
    for snapshot in 0..2 {
        let straight = beam(0.0, 0.0, 90.0, 1.0);
        note_plane_support(
            &mut map,
            0,
            &[(0, straight)],
            View::of(snapshot),
            3.0,
            HALF,
            PlaneEchoModel::Foot,
        );
    }
    assert!(map.is_confirmed(0));
    // The ray to (0.3, 1.977) crosses the wall at y = 1, 1.1 m before the range: behind.
    assert!(echo_behind_confirmed_wall(&map, &far, &echo, 3.0));
    // Read at 1.05 m the echo lies within twice the tolerance (0.063 m) of the wall: not
    // behind it, that is the wall.
    let near = beam(0.0, 0.0, 90.0, 1.05);
    assert!(!echo_behind_confirmed_wall(
        &map,
        &near,
        &Point::new(0.0, 1.05),
        3.0
    ));
    // A ray that passes beside the wall's end is not blocked.
    assert!(!echo_behind_confirmed_wall(
        &map,
        &far,
        &Point::new(1.5, 1.3),
        3.0
    ));
}

#[test]
fn a_single_reading_is_not_fitted() {
    let beams: Vec<Beam> = (0..1).map(|i| beam(i as f64, 0.0, 90.0, 1.5)).collect();
    assert!(fit_echo_line(&beams, &axis_points(&beams), 3.0, HALF, TURN).is_none());
}
