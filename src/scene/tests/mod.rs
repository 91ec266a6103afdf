//! Scene building on a small hand-built step: the fixture here, the tests of what each layer
//! draws in `layers`, of bounds, hits, level of detail and view culling in `view`.

mod layers;
mod view;

use super::*;
use crate::geometry::{Point, Pose};
use crate::mapping::model::trace::*;
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
        shorter_than_last: None,
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
                true_pose: None,
                reading_dt_s: Vec::new(),
            },
            Snapshot {
                t: 1.0,
                pose: Pose::new(0.0, 0.0, 0.0),
                ranges_m: vec![None; 4],
                true_pose: None,
                reading_dt_s: Vec::new(),
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
        across_right_angle: false,
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
        corrected_path: &[],
    };
    build_scene(&input, options)
}
