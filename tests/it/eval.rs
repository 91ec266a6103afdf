//! Map-versus-floor-plan figures on a hand-made map (numbers computed by hand).

use sonarmap::eval::evaluate;
use sonarmap::geometry::{Point, Pose};
use sonarmap::mapping::{EndPoint, Map, Params, Segment, SegmentKind};
use sonarmap::run::{FloorPlan, Run, Snapshot, Wall};
use sonarmap::sonar::{SensorLayout, SensorMount, SensorSpec};
use sonarmap::units::Units;

fn segment(id: u32, kind: SegmentKind, a: (f64, f64), b: (f64, f64), range_m: f64) -> Segment {
    Segment {
        id,
        kind,
        a: EndPoint {
            point: Point::new(a.0, a.1),
            range_m,
        },
        b: EndPoint {
            point: Point::new(b.0, b.1),
            range_m,
        },
        face: id,
        object: id,
        created: 0,
        updated: vec![],
        points: vec![].into(),
    }
}

#[test]
fn eval_figures_of_a_hand_made_map() {
    // One 100 m wall along the x axis; units metres, ξ = 3 %: tolerance at D = 1 m is 0.03 m.
    let plan = FloorPlan {
        walls: vec![Wall {
            a: Point::new(0.0, 0.0),
            b: Point::new(100.0, 0.0),
            roughness_rad: None,
        }],
        circles: vec![],
    };
    let mut map = Map::default();
    // On the wall, end-points 0.01 m off: true; covers x 10..50.
    map.push_segment(segment(
        0,
        SegmentKind::Fitted,
        (10.0, 0.01),
        (50.0, -0.01),
        1.0,
    ));
    // Half a metre off: spurious.
    map.push_segment(segment(
        1,
        SegmentKind::Fitted,
        (60.0, 0.5),
        (80.0, 0.5),
        1.0,
    ));
    // Interpolated links do not count.
    map.push_segment(segment(
        2,
        SegmentKind::Interpolated,
        (50.0, 0.0),
        (60.0, 0.5),
        1.0,
    ));
    // One downward sonar; readings of 1 m from y = 1 hit the wall at x = 30, 45 and 90.
    let layout = SensorLayout {
        mounts: vec![SensorMount {
            x_m: 0.0,
            y_m: 0.0,
            heading_rad: -std::f64::consts::FRAC_PI_2,
        }],
    };
    let snapshots = [30.0, 45.0, 90.0]
        .iter()
        .enumerate()
        .map(|(i, x)| Snapshot {
            t: i as f64,
            pose: Pose::new(*x, 1.0, 0.0),
            ranges_m: vec![Some(1.0)],
            true_pose: None,
            reading_dt_s: Vec::new(),
        })
        .collect();
    let run = Run {
        name: "hand".into(),
        units: Units::Metres,
        robot_radius_m: None,
        layout,
        sensor: SensorSpec::default(),
        floor_plan: Some(plan.clone()),
        snapshots,
    };
    let r = evaluate(&map, &run, &plan, &Params::paper());
    assert_eq!(r.segments, 2);
    assert_eq!(r.true_segments, 1);
    assert!((r.spurious_fraction - 0.5).abs() < 1e-12);
    assert!((r.mean_endpoint_error.unwrap() - 0.01).abs() < 1e-9);
    let angle_deg = (0.02f64 / 40.0).atan().to_degrees();
    assert!((r.mean_angle_error_deg.unwrap() - angle_deg).abs() < 1e-9);
    assert!((r.coverage - 0.4).abs() < 1e-9);
    // Visible: three marks of ± 0.03 m (15 m apart > t_gap), two inside the covered span.
    assert!(
        (r.visible_length - 0.18).abs() < 1e-9,
        "{}",
        r.visible_length
    );
    assert!((r.coverage_visible.unwrap() - 2.0 / 3.0).abs() < 1e-9);
    assert_eq!(r.units, "m");
}

#[test]
fn an_empty_map_scores_zero() {
    let plan = FloorPlan {
        walls: vec![Wall {
            a: Point::new(0.0, 0.0),
            b: Point::new(1.0, 0.0),
            roughness_rad: None,
        }],
        circles: vec![],
    };
    let run = sonarmap::assets::default_run().unwrap();
    let r = evaluate(&Map::default(), &run, &plan, &Params::paper());
    assert_eq!(
        (r.segments, r.true_segments, r.coverage, r.spurious_fraction),
        (0, 0, 0.0, 0.0)
    );
    assert_eq!(r.mean_endpoint_error, None);
}

#[test]
fn the_replays_truth_curve_samples_evals_figures_every_checkpoint_interval() {
    use sonarmap::replay::Replay;
    let run = sonarmap::log::load_run(
        include_bytes!("../../assets/building.log.json"),
        "building.log.json",
    )
    .unwrap();
    let plan = run.floor_plan.clone().unwrap();
    let params = sonarmap::mapping::Params::paper();
    let replay =
        Replay::build(std::sync::Arc::new(run), params.clone(), 50, &mut |_| true).unwrap();
    let curve = replay.truth_curve();
    // Steps 49, 99, …, 299 and the last, 304.
    let at: Vec<usize> = curve.iter().map(|t| t.snapshot).collect();
    assert_eq!(at, vec![49, 99, 149, 199, 249, 299, 304]);
    let last = curve.last().unwrap();
    let map = replay.final_map();
    let verdicts = sonarmap::eval::map_verdicts(map, &plan, &params);
    let (spurious, coverage) = sonarmap::eval::truth_figures(map, &plan, &verdicts);
    assert_eq!(
        (last.spurious_fraction, last.coverage),
        (spurious, coverage)
    );
}
