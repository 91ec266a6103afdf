//! Scene building on a small hand-built step.

use super::*;
use crate::geometry::{Point, Pose};
use crate::mapping::trace::*;
use crate::mapping::{EndPoint, Map, Segment, SegmentKind, StepTrace};
use crate::run::{FloorPlan, Run, Snapshot, Wall};
use crate::sonar::{SensorLayout, SensorSpec};
use crate::units::Units;

fn ep(x: f64, y: f64) -> EndPoint {
    EndPoint {
        point: Point::new(x, y),
        range_m: 1.0,
    }
}

fn seg(id: u32, a: (f64, f64), b: (f64, f64)) -> Segment {
    Segment {
        id,
        kind: SegmentKind::Fitted,
        a: ep(a.0, a.1),
        b: ep(b.0, b.1),
        face: id,
        object: id,
        created: 0,
        updated: vec![],
        points: vec![].into(),
    }
}

fn reading(
    sensor: usize,
    point: Option<(f64, f64)>,
    discarded: Option<DiscardReason>,
) -> ReadingTrace {
    ReadingTrace {
        sensor,
        range_m: point.map(|(x, y)| (x * x + y * y).sqrt()),
        point: point.map(|(x, y)| Point::new(x, y)),
        ball_radius_m: if point.is_some() { 0.03 } else { 0.0 },
        discarded,
        cluster: None,
    }
}

fn test_pass(pass: bool) -> Test {
    Test {
        value: if pass { 0.0 } else { 1.0 },
        threshold: 0.5,
        pass,
    }
}

fn candidate(existing: u32, orientation: bool, colinear: bool, mpc: bool) -> CandidateTrace {
    CandidateTrace {
        distance_m: 0.1,
        outermost: true,
        evaluation: PairEvaluation {
            existing,
            new_reversed: false,
            new_left: ep(0.0, 0.0),
            new_right: ep(0.0, 0.0),
            orientation: test_pass(orientation),
            colinearity: ColinearityTest {
                test: test_pass(colinear),
                d1_m: 1.0,
                d2_m: 1.0,
                d3_m: 1.0,
                foot_param: 0.5,
            },
            overlap: OverlapTest {
                mid_param: 0.5,
                left_param: 0.0,
                right_param: 1.0,
                existing_on_new_params: [0.0, 1.0],
                mpc,
                containment: false,
                epc: false,
                epc_end: None,
            },
        },
    }
}

fn new_segment(a: (f64, f64), b: (f64, f64)) -> NewSegmentTrace {
    NewSegmentTrace {
        source: SegmentSource::Cluster(0),
        a: ep(a.0, a.1),
        b: ep(b.0, b.1),
        points: vec![],
    }
}

struct Fixture {
    run: Run,
    step: StepTrace,
    previous: StepTrace,
    before: Map,
    after: Map,
}

/// Robot at the origin, four sonars. Sensor 0 and 1 kept, 2 discarded at max range, 3 no
/// echo. New segment 0 matches map segment 0; new segment 1 fails against it and is a new face.
fn fixture() -> Fixture {
    let mut previous = StepTrace {
        snapshot: 0,
        ..Default::default()
    };
    previous.readings = vec![reading(0, Some((1.5, 0.1)), None)];
    let before = Map::from_segments(vec![seg(0, (1.45, -0.3), (1.45, 0.3))]);
    let after = Map::from_segments(vec![
        seg(0, (1.5, -0.4), (1.5, 0.4)),
        seg(1, (0.0, 1.5), (0.5, 1.5)),
    ]);
    Fixture {
        run: fixture_run(),
        step: fixture_step(),
        previous,
        before,
        after,
    }
}

/// The fixture's run: four sonars in a ring, a wall at x = 2, two snapshots.
fn fixture_run() -> Run {
    let layout = SensorLayout::ring(4, std::f64::consts::FRAC_PI_2, 0.0, 0.2);
    Run {
        name: "Test <room> & co".into(),
        units: Units::Metres,
        robot_radius_m: Some(0.2),
        layout,
        sensor: SensorSpec::default(),
        floor_plan: Some(FloorPlan {
            walls: vec![Wall {
                a: Point::new(2.0, -3.0),
                b: Point::new(2.0, 3.0),
                roughness_rad: None,
            }],
            circles: vec![],
        }),
        snapshots: vec![
            Snapshot {
                t: 0.0,
                pose: Pose::new(-0.1, 0.0, 0.0),
                ranges_m: vec![None; 4],
            },
            Snapshot {
                t: 1.0,
                pose: Pose::new(0.0, 0.0, 0.0),
                ranges_m: vec![None; 4],
            },
        ],
    }
}

/// The fixture's step 1: four readings (one discarded at maximum range, one without echo),
/// a cluster and its gap, two new segments, their decisions, an update and a corner.
fn fixture_step() -> StepTrace {
    let mut step = StepTrace {
        snapshot: 1,
        pose: Some(Pose::new(0.0, 0.0, 0.0)),
        ..Default::default()
    };
    step.readings = vec![
        reading(0, Some((1.5, 0.0)), None),
        reading(1, Some((0.0, 1.5)), None),
        reading(2, Some((-6.5, 0.0)), Some(DiscardReason::AtMaxRange)),
        reading(3, None, Some(DiscardReason::NoEcho)),
    ];
    step.clusters = vec![ClusterTrace {
        sensors: vec![0, 1],
        constant_depth: vec![],
        fitted: vec![],
        splits: vec![],
        new_segments: vec![0],
    }];
    step.gaps = vec![GapTrace {
        from_sensor: 1,
        to_sensor: 0,
        distance_m: 2.1,
        t_gap_m: 1.0,
        is_break: true,
    }];
    step.new_segments = vec![
        new_segment((1.5, -0.4), (1.5, 0.4)),
        new_segment((0.0, 1.5), (0.5, 1.5)),
    ];
    step.decisions = fixture_decisions();
    step.updates = vec![UpdateTrace {
        segment: 0,
        new_segment: 0,
        outcome: Outcome::Match,
        before: [ep(1.45, -0.3), ep(1.45, 0.3)],
        after: [ep(1.5, -0.4), ep(1.5, 0.4)],
        line: [Point::new(1.5, -0.4), Point::new(1.5, 0.4)],
        fates: vec![],
        fallback_tls: false,
        refit: None,
        absorbed: Vec::new(),
        support_in_order: None,
    }];
    step.correlations = vec![CorrelationTrace {
        face: 1,
        new_segment: Some((1, 0)),
        existing_segment: Some((0, 1)),
        d_min: Some(Test::at_most(0.2, 1.0)),
        angle_rad: Some(1.5),
        result: CorrelationKind::Corner {
            point: Point::new(1.5, 1.5),
        },
    }];
    step
}

/// The fixture's decisions: new segment 0 matches map segment 0, new segment 1 is a new face.
fn fixture_decisions() -> Vec<DecisionTrace> {
    vec![
        DecisionTrace {
            new_segment: 0,
            mpc_stage: vec![candidate(0, true, true, true)],
            epc_stage: vec![],
            outcome: Outcome::Match,
            rule: Rule::MidPointOverlap,
            existing: Some(0),
            result: Some(0),
        },
        DecisionTrace {
            new_segment: 1,
            mpc_stage: vec![candidate(0, false, false, false)],
            epc_stage: vec![],
            outcome: Outcome::NewFace,
            rule: Rule::NoCandidatePassed,
            existing: None,
            result: Some(1),
        },
    ]
}

fn build(f: &Fixture, options: &ViewOptions, with_previous: bool) -> Scene {
    let input = SceneInput {
        run: &f.run,
        snapshot: 1,
        step: &f.step,
        previous_step: with_previous.then_some(&f.previous),
        map_before: &f.before,
        map_after: &f.after,
        truth: None,
        support_of: None,
        figure_labels: false,
    };
    build_scene(&input, options)
}

#[test]
fn discarded_reading_is_only_in_the_discarded_layer() {
    let f = fixture();
    let scene = build(&f, &ViewOptions::all(), true);
    let id = SceneId::Reading {
        snapshot: 1,
        sensor: 2,
    };
    let layers: Vec<Layer> = scene
        .primitives
        .iter()
        .filter(|p| p.id == id)
        .map(|p| p.layer)
        .collect();
    assert!(layers.contains(&Layer::Discarded));
    for l in &layers {
        assert!(
            matches!(l, Layer::Discarded | Layer::Beams),
            "discarded reading drawn in {l:?}"
        );
    }
    // The no-echo reading has no point: nothing but nothing.
    assert!(!scene.primitives.iter().any(|p| p.id
        == SceneId::Reading {
            snapshot: 1,
            sensor: 3
        }));
}

#[test]
fn kept_readings_are_blue_points_with_balls_and_previous_ones_red() {
    let f = fixture();
    let scene = build(&f, &ViewOptions::all(), true);
    let kept = SceneId::Reading {
        snapshot: 1,
        sensor: 0,
    };
    let roles: Vec<Role> = scene
        .primitives
        .iter()
        .filter(|p| p.id == kept)
        .map(|p| p.role)
        .collect();
    assert!(roles.contains(&Role::CurrentPoint) && roles.contains(&Role::Ball));
    let prev = scene
        .primitives
        .iter()
        .find(|p| {
            p.id == SceneId::Reading {
                snapshot: 0,
                sensor: 0,
            }
        })
        .unwrap();
    assert_eq!(prev.layer, Layer::PreviousSnapshot);
    assert_eq!(prev.style.fill, Some(palette::VERMILLION));
    let cur = scene
        .primitives
        .iter()
        .find(|p| p.role == Role::CurrentPoint)
        .unwrap();
    assert_eq!(cur.style.fill, Some(palette::BLUE));
}

#[test]
fn decision_links_carry_their_outcome_style() {
    let f = fixture();
    let scene = build(&f, &ViewOptions::all(), true);
    let link = |n: usize| {
        scene
            .primitives
            .iter()
            .find(|p| {
                p.id == SceneId::Decision {
                    new_segment: n,
                    existing: Some(0),
                } && matches!(p.shape, Shape::Segment { .. })
            })
            .unwrap()
    };
    assert_eq!(link(0).role, Role::DecisionMatch);
    assert_eq!(link(0).style, Role::DecisionMatch.style());
    assert_eq!(link(1).role, Role::DecisionFailed);
    assert_ne!(link(0).style.dash_px, link(1).style.dash_px);
    // The new face's own marker: a square in the new-face style at its mid-point.
    let own = scene
        .primitives
        .iter()
        .find(|p| {
            p.id == SceneId::Decision {
                new_segment: 1,
                existing: None,
            }
        })
        .unwrap();
    assert_eq!(own.role, Role::DecisionNewFace);
    assert_eq!(
        own.shape,
        Shape::Marker {
            at: Point::new(0.25, 1.5),
            shape: MarkerShape::Square
        }
    );
    // The link ends on the candidate (map before), at the foot of the perpendicular.
    assert_eq!(
        link(0).shape,
        Shape::Segment {
            a: Point::new(1.5, 0.0),
            b: Point::new(1.45, 0.0)
        }
    );
}

#[test]
fn legend_lists_only_what_is_drawn() {
    let f = fixture();
    let options = ViewOptions::all().with_layer(Layer::Balls, false);
    let scene = build(&f, &options, false);
    let legend = scene.legend();
    let roles: Vec<Role> = legend.iter().map(|e| e.role).collect();
    assert!(!roles.contains(&Role::Ball));
    assert!(
        !roles.contains(&Role::PreviousPoint),
        "no previous step given"
    );
    assert!(!roles.contains(&Role::DecisionExtension) && !roles.contains(&Role::DecisionDismissed));
    assert!(roles.contains(&Role::DecisionMatch) && roles.contains(&Role::DecisionNewFace));
    assert!(roles.contains(&Role::FloorPlan) && roles.contains(&Role::Corner));
    assert!(
        roles.windows(2).all(|w| w[0] < w[1]),
        "legend in role order, no duplicates"
    );
    assert!(!scene.layers_present().contains(Layer::Balls));
}

#[test]
fn layers_come_in_drawing_order_and_switch_off() {
    let f = fixture();
    let scene = build(&f, &ViewOptions::all(), true);
    assert!(scene
        .primitives
        .windows(2)
        .all(|w| w[0].layer <= w[1].layer));
    for layer in Layer::ALL {
        let off = build(&f, &ViewOptions::all().with_layer(layer, false), true);
        assert_eq!(off.layer(layer).count(), 0, "{layer:?}");
    }
    assert_eq!(build(&f, &ViewOptions::all(), true), scene, "deterministic");
    assert_eq!(scene.title, "Test <room> & co — snapshot 1");
}

#[test]
fn cluster_breaks_carry_the_gap_in_the_log_units() {
    let f = fixture();
    let scene = build(&f, &ViewOptions::all(), true);
    let texts: Vec<&str> = scene
        .layer(Layer::Clusters)
        .filter_map(|p| match &p.shape {
            Shape::Text { text, .. } => Some(text.as_str()),
            _ => None,
        })
        .collect();
    assert_eq!(texts, ["gap 2.1 m"]);
}

#[test]
fn bounds_and_hit_testing() {
    let f = fixture();
    let scene = build(&f, &ViewOptions::all(), true);
    let b = scene.bounds().unwrap();
    assert!(b.contains(&Point::new(2.0, 3.0)) && b.contains(&Point::new(-6.5, 0.0)));
    // On the new face's segment, away from other lines: the segment (or its label / decision).
    let hit = scene.hit(Point::new(0.4, 1.5), 0.02).unwrap();
    assert!(
        matches!(hit, SceneId::NewSegment(1) | SceneId::MapSegment(1)),
        "{hit:?}"
    );
    // Inside a ball but near nothing else: the reading.
    let only_balls = build(
        &f,
        &ViewOptions {
            layers: LayerSet::empty().with(Layer::Balls, true),
            world_per_px: 0.0,
            visible_m: None,
        },
        true,
    );
    assert_eq!(
        only_balls.hit(Point::new(0.01, 1.5), 0.005),
        Some(SceneId::Reading {
            snapshot: 1,
            sensor: 1
        })
    );
    assert_eq!(scene.hit(Point::new(-5.0, 5.0), 0.01), None);
}

#[test]
fn level_of_detail_drops_sub_pixel_balls() {
    let f = fixture();
    let coarse = ViewOptions {
        world_per_px: 0.1,
        ..ViewOptions::all()
    };
    assert_eq!(build(&f, &coarse, true).layer(Layer::Balls).count(), 0);
    assert_eq!(
        build(&f, &ViewOptions::all(), true)
            .layer(Layer::Balls)
            .count(),
        2
    );
}

#[test]
fn map_before_shows_only_what_the_step_changed_under_the_map() {
    let mut f = fixture();
    // Segment 0 moved this step; segment 7 did not.
    let still = seg(7, (-1.0, -1.0), (-1.0, 1.0));
    f.before = Map::from_segments(vec![seg(0, (1.45, -0.3), (1.45, 0.3)), still.clone()]);
    f.after = Map::from_segments(vec![seg(0, (1.5, -0.4), (1.5, 0.4)), still]);
    let ids = |s: &Scene| -> Vec<SceneId> { s.layer(Layer::MapBefore).map(|p| p.id).collect() };
    let scene = build(&f, &ViewOptions::all(), true);
    assert_eq!(ids(&scene), vec![SceneId::MapSegment(0)]);
    // Without the map on top, the whole map before is drawn.
    let scene = build(&f, &ViewOptions::all().with_layer(Layer::Map, false), true);
    assert_eq!(
        ids(&scene),
        vec![SceneId::MapSegment(0), SceneId::MapSegment(7)]
    );
}

#[test]
fn zoomed_out_copies_of_a_segment_its_dots_and_labels_are_drawn_once() {
    let mut f = fixture();
    // Fifty copies of one wall, 0.2 mm apart.
    f.after = Map::from_segments(
        (0..50)
            .map(|i| seg(i, (1.0 + 0.0002 * f64::from(i), -1.0), (1.0, 1.0)))
            .collect(),
    );
    let zoomed_out = ViewOptions {
        world_per_px: 0.01,
        ..ViewOptions::all()
    };
    let scene = build(&f, &zoomed_out, true);
    let dots = scene
        .layer(Layer::Map)
        .filter(|p| p.role == Role::MapEndPoint)
        .count();
    assert_eq!(dots, 2, "one dot per end at 1 cm per pixel");
    let lines = scene
        .layer(Layer::Map)
        .filter(|p| p.role == Role::MapFitted)
        .count();
    assert_eq!(lines, 1, "the copies coincide on screen");
    let labels = scene
        .layer(Layer::Labels)
        .filter(|p| matches!(p.id, SceneId::MapSegment(_)))
        .count();
    assert_eq!(labels, 1);
    let close_up = build(&f, &ViewOptions::all(), true);
    assert_eq!(
        close_up
            .layer(Layer::Map)
            .filter(|p| p.role == Role::MapEndPoint)
            .count(),
        100
    );
}

#[test]
fn a_view_rectangle_keeps_only_the_map_segments_that_meet_it() {
    let mut f = fixture();
    // A wall inside the view, one crossing its edge, one outside; the step moved the outside one.
    let inside = seg(0, (0.0, 0.0), (1.0, 0.0));
    let crossing = seg(1, (1.5, -1.0), (3.0, -1.0));
    f.before = Map::from_segments(vec![
        inside.clone(),
        crossing.clone(),
        seg(2, (5.0, 5.0), (6.0, 5.0)),
    ]);
    f.after = Map::from_segments(vec![inside, crossing, seg(2, (5.0, 5.1), (6.0, 5.1))]);
    let view = ViewOptions {
        visible_m: Some([-1.0, -2.0, 2.0, 2.0]),
        ..ViewOptions::all()
    };
    let ids = |s: &Scene, layer| -> Vec<SceneId> { s.layer(layer).map(|p| p.id).collect() };
    let culled = build(&f, &view, true);
    let map: Vec<SceneId> = culled
        .layer(Layer::Map)
        .filter(|p| p.role == Role::MapFitted)
        .map(|p| p.id)
        .collect();
    assert_eq!(map, [SceneId::MapSegment(0), SceneId::MapSegment(1)]);
    assert!(
        ids(&culled, Layer::MapBefore).is_empty(),
        "the moved one is out of view"
    );
    assert!(!ids(&culled, Layer::Labels).contains(&SceneId::MapSegment(2)));
    let whole = build(&f, &ViewOptions::all(), true);
    assert_eq!(ids(&whole, Layer::MapBefore), [SceneId::MapSegment(2)]);
    // The bounds (and Fit) still take in what was left out.
    let map_only = LayerSet::empty().with(Layer::Map, true);
    assert_eq!(culled.bounds_of(map_only), whole.bounds_of(map_only));
    assert_eq!(
        culled.bounds_of(map_only).unwrap().max,
        Point::new(6.0, 5.1),
        "segment 2 after the step"
    );
}

#[test]
fn zoomed_out_a_path_over_the_same_ground_is_drawn_once_and_whole_without_a_view() {
    let mut f = fixture();
    // Out to 1 m and back in 10 cm steps, three times.
    let lap: Vec<f64> = (0..=10)
        .chain((1..10).rev())
        .map(|i| 0.1 * f64::from(i))
        .collect();
    f.run.snapshots = (lap.iter().cycle().take(3 * lap.len()).enumerate())
        .map(|(i, &x)| Snapshot {
            t: i as f64,
            pose: Pose::new(x, 0.0, 0.0),
            ranges_m: vec![None; 4],
        })
        .collect();
    let input = SceneInput {
        run: &f.run,
        snapshot: f.run.snapshots.len() - 1,
        step: &f.step,
        previous_step: None,
        map_before: &f.before,
        map_after: &f.after,
        truth: None,
        support_of: None,
        figure_labels: false,
    };
    let path = |options: &ViewOptions| -> Vec<Vec<Point>> {
        (build_scene(&input, options).layer(Layer::Robot))
            .filter(|p| p.role == Role::RobotPath)
            .map(|p| match &p.shape {
                Shape::Polyline { points, .. } => points.clone(),
                other => panic!("the path is a polyline, not {other:?}"),
            })
            .collect()
    };
    let whole = path(&ViewOptions::all());
    let poses: Vec<Point> = f.run.snapshots.iter().map(|s| s.pose.position()).collect();
    assert_eq!(whole, vec![poses]);
    let zoomed_out = path(&ViewOptions {
        world_per_px: 0.01,
        ..ViewOptions::all()
    });
    let out: Vec<Point> = (0..=10)
        .map(|i| Point::new(0.1 * f64::from(i), 0.0))
        .collect();
    assert_eq!(zoomed_out, vec![out], "the first way out only");
}
