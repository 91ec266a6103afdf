//! Segment parts a reading saw through are cut away (docs/algorithm.md §8.18): by hand, and on
//! the Pioneer corridor stand-in's door recesses.

use super::support::{layout_of, pioneer_corridor_crawl, snapshot_at_origin};
use sonarmap::eval::{confirmed_map, evaluate};
use sonarmap::geometry::Point;
use sonarmap::mapping::model::ext_trace::SeenThroughCut;
use sonarmap::mapping::{Map, Mapper, Params};
use sonarmap::sonar::SensorSpec;
use std::f64::consts::FRAC_PI_2;

#[test]
fn a_reading_borne_out_cuts_back_the_end_it_saw_through_and_a_stray_one_cuts_nothing() {
    // `paper` with the rule alone. Sensors at x = 0, 0.5, 1 face +y (beam 25°, ξ = 3 %).
    // Snapshot 0: all three read 2 m: the segment (0, 2)–(1, 2).
    // Snapshot 1: the sensor at x = 1 reads 2.5 m, once: a stray echo, it cuts nothing.
    // Snapshot 2: it reads 2.5 m again (borne out: within 2·tol = 0.15 m). The line y = 2 lies
    // p = 2 m away, its foot on the axis; the cone meets it 2·tan 12.5° = 0.4434 m either
    // side, the disc of radius 2.5 − 0.15 = 2.35 m √(2.35² − 4) = 1.2339 m either side. The
    // free part, x from 0.5566 to 1.4434, holds end b: b moves back to (0.5566, 2), and the
    // reading at x = 1 goes with the part cut.
    let params = Params::paper_with("trim_seen_through").unwrap();
    let layout = layout_of([0.0, 0.5, 1.0].iter().map(|&x| (x, 0.0, FRAC_PI_2)));
    let mut mapper = Mapper::new(params, layout, SensorSpec::default());
    mapper.step(&snapshot_at_origin(0.0, &[Some(2.0), Some(2.0), Some(2.0)]));
    let stray = mapper.step(&snapshot_at_origin(1.0, &[None, None, Some(2.5)]));
    assert!(stray.seen_through.is_empty(), "{:?}", stray.seen_through);
    let borne_out = mapper.step(&snapshot_at_origin(2.0, &[None, None, Some(2.5)]));
    assert_eq!(borne_out.seen_through.len(), 1);
    let cut = &borne_out.seen_through[0];
    assert_eq!(
        (cut.segment, cut.sensor, cut.cut),
        (0, 2, SeenThroughCut::EndB)
    );
    assert_eq!(cut.dropped_points, 1);
    let free = 2.0 * 12.5f64.to_radians().tan();
    assert!((cut.free_part[0][0] - (1.0 - free)).abs() < 1e-9);
    assert!(
        (cut.free_part[1][0] - 1.0).abs() < 1e-9,
        "clipped to the segment"
    );
    let s = mapper.map().segment(0).unwrap();
    assert!((s.a.point - Point::new(0.0, 2.0)).norm() < 1e-9);
    assert!((s.b.point - Point::new(1.0 - free, 2.0)).norm() < 1e-9);
    assert!((s.b.point.x - 0.5566).abs() < 1e-4);
    assert_eq!(s.points.len(), 2);
}

/// How many confirmed segment ends lie in the mouth of a door recess of the stand-in's near
/// wall (on its line `y = 0`, more than 5 cm inside the opening). The robot drives 1.27 m from
/// that wall's sensors, where a 25° cone spans 0.56 m of a 0.9 m mouth: the side sonars see
/// into the recesses. The far wall's recesses, 2.5 m away, are narrower than the cone there and
/// are never seen into.
fn ends_in_mouths(map: &Map) -> usize {
    // (wall line y, the mouth from x0 to x1): assets/pioneer_corridor.plan.json.
    let mouths = [(0.0, 3.0, 3.9), (0.0, 8.0, 8.9)];
    let inside = |p: &Point| {
        mouths
            .iter()
            .any(|&(y, x0, x1)| (p.y - y).abs() < 0.1 && p.x > x0 + 0.05 && p.x < x1 - 0.05)
    };
    map.segments
        .iter()
        .flat_map(|s| [s.a.point, s.b.point])
        .filter(inside)
        .count()
}

#[test]
fn the_corridors_door_recesses_are_neither_bridged_nor_overrun_once_seen_through() {
    // Without drift: every wall end the beam's width carried into a recess, and every line
    // bridging its mouth, is cut back by the readings that looked into the recess.
    let mut without = Params::extended();
    without.trim_seen_through = false;
    let mut ends_before_in_all = 0;
    for seed in 1..=5 {
        let run = pioneer_corridor_crawl(seed);
        let plan = run.floor_plan.clone().unwrap();
        let score = |params: &Params| {
            let (map, _) = sonarmap::suite::map_and_poses_of(&run, params);
            let confirmed = confirmed_map(&map).unwrap();
            let report = evaluate(&confirmed, &run, &plan, params);
            (ends_in_mouths(&confirmed), report.spurious_fraction)
        };
        let (ends_before, spurious_before) = score(&without);
        let (ends_after, spurious_after) = score(&Params::extended());
        // Seeds 1–5: 3, 1, 3, 2, 3 ends before; spurious 0.188, 0.128, 0.222, 0.225, 0.133
        // before and 0.106, 0.083, 0.146, 0.128, 0.095 after.
        ends_before_in_all += ends_before;
        assert_eq!(ends_after, 0, "seed {seed}: ends in mouths after");
        assert!(
            spurious_after < spurious_before - 0.03,
            "seed {seed}: spurious {spurious_before:.3} -> {spurious_after:.3}"
        );
    }
    assert!(
        ends_before_in_all >= 10,
        "{ends_before_in_all} ends in mouths before"
    );
}
