//! Confirmation (docs/algorithm.md §8.7) on the Pioneer corridor stand-in.

use super::support::pioneer_corridor_crawl;
use sonarmap::eval::confirmed_map;
use sonarmap::mapping::model::map::SegmentKind;
use sonarmap::mapping::Params;
use sonarmap::suite::map_and_poses_of;

/// The confirmed fitted segments of the stand-in's map (seed `seed`, no drift) turned more
/// than 15° from the corridor's axes (the plan's x and y).
fn confirmed_off_axis(seed: u64, params: &Params) -> Vec<(f64, f64, f64, f64)> {
    let run = pioneer_corridor_crawl(seed);
    let (map, _) = map_and_poses_of(&run, params);
    let confirmed = confirmed_map(&map).unwrap();
    confirmed
        .segments
        .iter()
        .filter(|s| s.kind == SegmentKind::Fitted)
        .filter(|s| {
            let d = s.b.point - s.a.point;
            let deg = d.y.atan2(d.x).to_degrees().rem_euclid(90.0);
            deg.min(90.0 - deg) > 15.0
        })
        .map(|s| (s.a.point.x, s.a.point.y, s.b.point.x, s.b.point.y))
        .collect()
}

/// Approaching the corridor's end, the sonars at 30° and 50° off the robot's axis hear the
/// end wall and the side wall off their cones' edges; laid on their axes, those echoes draw a
/// chord across the corner (seed 9: from (−0.62, 3.16) to (−1.02, 2.34), 26° off the walls,
/// which set the last quarter's rotation 2.6° from the first's). Echoes off a cone's edge
/// confirmed it. With `off_axis_square_on` (in `extended`) a segment turned more than θ_o
/// from the map's axes needs readings that see it square on, and none is confirmed.
#[test]
fn a_corner_chord_drawn_by_cone_edge_echoes_is_not_confirmed_off_the_maps_axes() {
    let without = Params {
        off_axis_square_on: false,
        ..Params::extended()
    };
    let chords = confirmed_off_axis(9, &without);
    assert!(
        chords
            .iter()
            .any(|&(ax, ay, bx, by)| ax.max(bx) < 0.0 && ay.min(by) > 2.0),
        "{chords:?}"
    );
    assert_eq!(confirmed_off_axis(9, &Params::extended()), vec![]);
}

/// The trace says why such a reading did not count: it heard the segment only off its
/// cone's edge, and the segment lies more than θ_o off the map's axes.
#[test]
fn an_edge_echo_refused_off_the_axes_is_traced_with_the_segments_turn() {
    use sonarmap::mapping::Mapper;
    let run = pioneer_corridor_crawl(9);
    let mut mapper = Mapper::new(Params::extended(), run.layout.clone(), run.sensor);
    let refused: Vec<f64> = run
        .snapshots
        .iter()
        .flat_map(|s| mapper.step(s).plane_support)
        .filter_map(|p| p.off_axis_deg)
        .collect();
    assert!(!refused.is_empty());
    assert!(
        refused.iter().all(|&deg| deg > 15.0 && deg <= 45.0),
        "{refused:?}"
    );
}
