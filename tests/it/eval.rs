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
    // Near the path (poses 1 m from the wall, 1.5 m around each): three chords of
    // 2·sqrt(1.5² − 1²) m, two inside the covered span.
    let chord = 2.0 * (1.5f64 * 1.5 - 1.0).sqrt();
    assert!((r.near_path_length - 3.0 * chord).abs() < 1e-9);
    assert!((r.coverage_near_path.unwrap() - 2.0 / 3.0).abs() < 1e-9);
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

/// A room of four walls with a pillar-free stub that breaks its symmetry, metres.
fn room_plan() -> FloorPlan {
    let wall = |a: (f64, f64), b: (f64, f64)| Wall {
        a: Point::new(a.0, a.1),
        b: Point::new(b.0, b.1),
        roughness_rad: None,
    };
    FloorPlan {
        walls: vec![
            wall((0.0, 0.0), (6.0, 0.0)),
            wall((6.0, 0.0), (6.0, 4.0)),
            wall((6.0, 4.0), (0.0, 4.0)),
            wall((0.0, 4.0), (0.0, 0.0)),
            wall((2.0, 0.0), (2.0, 1.5)),
        ],
        circles: vec![],
    }
}

/// The plan's walls drawn as map segments after `p ↦ R(turn_deg)·p + shift`, each made at
/// snapshot `created`.
fn moved_walls(plan: &FloorPlan, turn_deg: f64, shift: (f64, f64), created: usize) -> Vec<Segment> {
    let (s, c) = turn_deg.to_radians().sin_cos();
    let moved = |p: &Point| (c * p.x - s * p.y + shift.0, s * p.x + c * p.y + shift.1);
    plan.walls
        .iter()
        .enumerate()
        .map(|(i, w)| Segment {
            created,
            ..segment(i as u32, SegmentKind::Fitted, moved(&w.a), moved(&w.b), 1.0)
        })
        .collect()
}

/// A run of `n` snapshots standing still with no reading (alignment needs only their count).
fn still_run(n: usize, plan: &FloorPlan) -> Run {
    Run {
        name: "still".into(),
        units: Units::Metres,
        robot_radius_m: None,
        layout: SensorLayout { mounts: vec![] },
        sensor: SensorSpec::default(),
        floor_plan: Some(plan.clone()),
        snapshots: (0..n)
            .map(|i| Snapshot {
                t: i as f64,
                pose: Pose::new(3.0, 2.0, 0.0),
                ranges_m: vec![],
                true_pose: None,
                reading_dt_s: Vec::new(),
            })
            .collect(),
    }
}

#[test]
fn alignment_undoes_a_known_turn_and_shift() {
    use sonarmap::alignment::{align, Search};
    let plan = room_plan();
    // The map is the plan turned by −4° and shifted by (0.3, −0.2) m: aligning turns it back
    // by +4° and lays every end-point on its wall's.
    let segments = moved_walls(&plan, -4.0, (0.3, -0.2), 0);
    let a = align(segments.iter(), &plan, Search::Near(None)).expect("aligned");
    assert!((a.rotation_deg - 4.0).abs() < 1e-6, "{a:?}");
    for (s, w) in segments.iter().zip(&plan.walls) {
        assert!((a.map_to_plan(&s.a.point) - w.a).norm() < 1e-6, "{a:?}");
        assert!((a.map_to_plan(&s.b.point) - w.b).norm() < 1e-6, "{a:?}");
        assert!((a.plan_to_map(&w.a) - s.a.point).norm() < 1e-6);
    }
    assert_eq!(a.inlier_fraction, 1.0);
    assert!(a.inlier_rms_m < 1e-6);
    // 6 + 4 + 6 + 4 + 1.5 m at 5 cm: 120 + 80 + 120 + 80 + 30 pieces, one more point each.
    assert_eq!(a.samples, 435);
}

#[test]
fn a_plan_in_another_frame_is_found_over_the_whole_turn_not_near_its_own() {
    use sonarmap::alignment::{align, Search};
    let plan = room_plan();
    let segments = moved_walls(&plan, 100.0, (-5.0, 7.0), 0);
    let anywhere = align(segments.iter(), &plan, Search::Anywhere).expect("aligned");
    assert!((anywhere.rotation_deg + 100.0).abs() < 1e-6, "{anywhere:?}");
    for (s, w) in segments.iter().zip(&plan.walls) {
        assert!(
            (anywhere.map_to_plan(&s.a.point) - w.a).norm() < 1e-6,
            "{anywhere:?} {w:?}"
        );
    }
    assert_eq!(anywhere.inlier_fraction, 1.0, "{anywhere:?}");
    let near = align(segments.iter(), &plan, Search::Near(None)).expect("aligned");
    assert!(near.inlier_fraction < 0.5, "{near:?}");
}

#[test]
fn an_aligned_map_scores_as_the_map_drawn_in_the_plans_frame_and_its_quarters_show_the_drift() {
    use sonarmap::alignment::Search;
    use sonarmap::eval::evaluate_aligned;
    let plan = room_plan();
    // The first quarter's walls (made at snapshot 0 of 100) turned by −1°, the last
    // quarter's (made at 90) by −5°: the drift of a heading that wandered 4°.
    let mut map = Map::default();
    for s in moved_walls(&plan, -1.0, (0.0, 0.0), 0)
        .into_iter()
        .chain(moved_walls(&plan, -5.0, (0.0, 0.0), 90))
    {
        map.push_segment(Segment {
            id: s.id + if s.created == 0 { 0 } else { 10 },
            ..s
        });
    }
    let run = still_run(100, &plan);
    let unaligned = evaluate(&map, &run, &plan, &Params::paper());
    let aligned = evaluate_aligned(&map, &run, &plan, &Params::paper(), Search::Near(None));
    let alignment = aligned.alignment.as_ref().expect("aligned");
    assert!((alignment.first_quarter_rotation_deg.unwrap() - 1.0).abs() < 1e-6);
    assert!((alignment.last_quarter_rotation_deg.unwrap() - 5.0).abs() < 1e-6);
    // The whole map's rotation lies between the two.
    let whole = alignment.whole.rotation_deg;
    assert!(whole > 1.0 - 1e-6 && whole < 5.0 + 1e-6, "{whole}");
    assert!(unaligned.alignment.is_none());
    assert_eq!(aligned.segments, 10);
    // A map drawn in the plan's frame needs no alignment and scores every wall true.
    let mut exact = Map::default();
    for s in moved_walls(&plan, 0.0, (0.0, 0.0), 0) {
        exact.push_segment(s);
    }
    let exact_aligned = evaluate_aligned(&exact, &run, &plan, &Params::paper(), Search::Near(None));
    assert!(
        exact_aligned
            .alignment
            .as_ref()
            .unwrap()
            .whole
            .rotation_deg
            .abs()
            < 1e-9
    );
    assert_eq!(exact_aligned.true_segments, 5);
    assert_eq!(exact_aligned.coverage, 1.0);
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(48))]
    /// Any turn within the near search's reach and any shift under half a metre of a map drawn
    /// from the plan is undone, wherever the asymmetric stub stands.
    #[test]
    fn alignment_undoes_any_near_turn_and_shift(
        turn_deg in -12.0f64..12.0,
        dx in -0.5f64..0.5,
        dy in -0.5f64..0.5,
        stub_x in 1.0f64..5.0,
    ) {
        use sonarmap::alignment::{align, Search};
        let mut plan = room_plan();
        plan.walls[4].a.x = stub_x;
        plan.walls[4].b.x = stub_x;
        let segments = moved_walls(&plan, turn_deg, (dx, dy), 0);
        let a = align(segments.iter(), &plan, Search::Near(None)).expect("aligned");
        proptest::prop_assert!((a.rotation_deg + turn_deg).abs() < 1e-5, "{:?}", a);
        for (s, w) in segments.iter().zip(&plan.walls) {
            proptest::prop_assert!((a.map_to_plan(&s.a.point) - w.a).norm() < 1e-5, "{:?}", a);
        }
        proptest::prop_assert_eq!(a.inlier_fraction, 1.0);
    }
}
