//! The rules of docs/algorithm.md made precise where the paper is silent, each on a scene
//! small enough to compute by hand. Sensors in a row facing +y put reading `k` exactly at
//! `(x_k, D_k)`, so every point, range and confidence is chosen.

use super::support::{layout_of, snapshot_at_origin};
use sonarmap::geometry::{Point, Pose};
use sonarmap::mapping::model::map::SegmentKind;
use sonarmap::mapping::model::trace::{Outcome, SegmentSource};
use sonarmap::mapping::{Mapper, Params};
use sonarmap::run::Snapshot;
use sonarmap::sonar::{SensorLayout, SensorSpec};
use std::f64::consts::FRAC_PI_2;

/// Sensors at `(x, 0)` for each `x`, all facing +y.
fn row(xs: &[f64]) -> SensorLayout {
    layout_of(xs.iter().map(|&x| (x, 0.0, FRAC_PI_2)))
}

fn close(p: Point, x: f64, y: f64) -> bool {
    (p - Point::new(x, y)).norm() < 1e-9
}

#[test]
fn a_failed_update_whose_fresh_fit_is_one_piece_takes_that_pieces_end_points() {
    // Snapshot 0: (1, 2) and (2, 2) at D = 2: segment 0.
    // Snapshot 1: (0, 2.08), (1, 2.04), (2, 2.00). Its mid-point (1, 2.04) projects on
    // segment 0's start (t = 0) 0.04 from its line (threshold 0.06 + 0.015·4.08): a MATCH.
    // u_L = e_L (D 2 < 2.08), u_R = e_R (2 = 2, the existing wins), so l_u is y = 2 and n_L
    // projects to (0, 2): the update gives (0, 2)–(2, 2). Its point (0, 2.08) lies 0.08 from
    // l_u, over its tolerance 0.03·2.08 = 0.0624: the post-update test fails. Fitted afresh
    // along l_u, first (0, 2.08) to last (2, 2.00), the farthest point (1, 2) lies
    // 0.04/√1.0016 ≈ 0.03997 off, within 0.06: one piece, which replaces the geometry.
    let mut mapper = Mapper::new(
        Params::paper(),
        row(&[0.0, 1.0, 2.0]),
        SensorSpec::default(),
    );
    mapper.step(&snapshot_at_origin(0.0, &[None, Some(2.0), Some(2.0)]));
    let trace = mapper.step(&snapshot_at_origin(
        1.0,
        &[Some(2.08), Some(2.04), Some(2.0)],
    ));
    assert_eq!(trace.decisions.len(), 1);
    assert_eq!(trace.decisions[0].outcome, Outcome::Match);
    let update = &trace.updates[0];
    assert!(
        close(update.after[0].point, 0.0, 2.0),
        "the update's own geometry"
    );
    let refit = update.refit.as_ref().expect("the post-update test failed");
    assert!(!refit.worst.pass);
    assert!((refit.worst.value - 0.08).abs() < 1e-9);
    assert_eq!(refit.pieces, vec![0], "one piece, keeping the id");
    let s = mapper.map().segment(0).unwrap();
    assert!(close(s.a.point, 0.0, 2.08) && (s.a.range_m - 2.08).abs() < 1e-12);
    assert!(close(s.b.point, 2.0, 2.0) && (s.b.range_m - 2.0).abs() < 1e-12);
    // Supporting points ordered along l_u; the two at x = 1 (and at x = 2) by snapshot.
    let order: Vec<(f64, usize)> = s
        .points
        .iter()
        .map(|q| (q.point.x.round(), q.reading.snapshot()))
        .collect();
    assert_eq!(order, [(0.0, 1), (1.0, 0), (1.0, 1), (2.0, 0), (2.0, 1)]);
}

#[test]
fn new_faces_take_ids_in_decision_order() {
    // Three clusters 2 m apart (t_gap = 42 in = 1.0668 m), each a horizontal pair: three NEW
    // FACE decisions, in cluster order, get ids 0, 1, 2 and faces 0, 1, 2. The next snapshot
    // adds a fourth cluster: id 3.
    let xs = [0.0, 0.5, 2.5, 3.0, 5.0, 5.5, 7.5, 8.0];
    let mut mapper = Mapper::new(Params::paper(), row(&xs), SensorSpec::default());
    let d = Some(2.0);
    let trace = mapper.step(&snapshot_at_origin(0.0, &[d, d, d, d, d, d, None, None]));
    let results: Vec<_> = trace
        .decisions
        .iter()
        .map(|d| (d.outcome, d.result))
        .collect();
    assert_eq!(
        results,
        [
            (Outcome::NewFace, Some(0)),
            (Outcome::NewFace, Some(1)),
            (Outcome::NewFace, Some(2))
        ]
    );
    for id in 0..3 {
        let s = mapper.map().segment(id).unwrap();
        assert!(close(s.a.point, xs[2 * id as usize], 2.0));
        assert_eq!(s.face, id);
    }
    let trace = mapper.step(&snapshot_at_origin(1.0, &[d, d, d, d, d, d, d, d]));
    let new_faces: Vec<_> = trace
        .decisions
        .iter()
        .filter(|d| d.outcome == Outcome::NewFace)
        .map(|d| d.result)
        .collect();
    assert_eq!(new_faces, [Some(3)]);
}

#[test]
fn walls_all_round_close_the_loop() {
    // Four sensors 90° apart (every bearing gap ≤ 90°: the order wraps) in a diamond of
    // readings at 0.7 m: neighbours 0.99 m apart, under t_gap, so one cluster all round. The
    // fit repeats the first point at the end: (0.7,0) (0,0.7) (−0.7,0) (0,−0.7) (0.7,0) splits
    // at (−0.7, 0), then at (0, ±0.7): four sides, the last closing back to (0.7, 0).
    let layout = SensorLayout::ring(4, FRAC_PI_2, 0.0, 0.0);
    let mut mapper = Mapper::new(Params::paper(), layout, SensorSpec::default());
    let trace = mapper.step(&snapshot_at_origin(0.0, &[Some(0.7); 4]));
    assert_eq!(trace.clusters.len(), 1);
    let sides: Vec<(Point, Point)> = mapper
        .map()
        .segments
        .iter()
        .map(|s| (s.a.point, s.b.point))
        .collect();
    assert_eq!(sides.len(), 4, "three sides without the closing one");
    let corners = [(0.7, 0.0), (0.0, 0.7), (-0.7, 0.0), (0.0, -0.7), (0.7, 0.0)];
    for (k, (a, b)) in sides.iter().enumerate() {
        assert!(
            close(*a, corners[k].0, corners[k].1),
            "side {k} starts at {a}"
        );
        assert!(
            close(*b, corners[k + 1].0, corners[k + 1].1),
            "side {k} ends at {b}"
        );
    }
}

/// A ring of 24 sonars 15° apart on a 0.2 m radius (sensor `k` looks at `15·k` degrees) reads
/// the wall `y = 2` square-on with sensors 5, 6 and 7 (75°, 90°, 105°), the cone (25° wide)
/// reaching the wall's foot for sensor 6 and the cone's edge, 2.5° from the normal, for 5 and 7.
fn ring_facing_a_wall() -> (SensorLayout, Vec<Option<f64>>) {
    let layout = SensorLayout::ring(24, 15f64.to_radians(), 0.0, 0.2);
    let mut ranges = vec![None; 24];
    // Sensor 6 stands at (0, 0.2): 1.8 m from the wall. Sensors 5 and 7 stand at
    // y = 0.2·sin 75° = 0.19319, 1.80681 m from it, their axes 15° off the normal: the cone's
    // edge meets the wall at 2.5° from it, 1.80681 / cos 2.5° = 1.80853 m away.
    ranges[6] = Some(1.8);
    let edge = (2.0 - 0.2 * 75f64.to_radians().sin()) / 2.5f64.to_radians().cos();
    assert!((edge - 1.80853).abs() < 1e-5);
    ranges[5] = Some(edge);
    ranges[7] = Some(edge);
    (layout, ranges)
}

#[test]
fn a_wall_seen_square_on_by_three_sonars_is_fitted_too_and_its_middle_reading_goes_to_point_memory()
{
    // The three ranges pass the ball test pairwise (|1.8 − 1.80853| ≤ 0.03·3.6), and no reading
    // supports the chord of the axis points (y = 0.19319 + 1.80853·sin 75° = 1.94010) as a plane
    // (sensor 6 lies 1.74010 from it, 0.060 off its 1.8 against a tolerance of 0.054): the arc
    // rule of §8.5 alone files the cluster as one reflector point and fits nothing. The line
    // y = 2 explains every range (the foot for sensor 6, the cones' edges for 5 and 7), and a
    // point cannot do better: the reflector is filed and the cluster is fitted too; its
    // constant-depth run (§8.2) keeps sensor 6's reading, and that goes to point memory (§8.1).
    let (layout, ranges) = ring_facing_a_wall();
    let mut mapper = Mapper::new(Params::extended(), layout.clone(), SensorSpec::default());
    let trace = mapper.step(&snapshot_at_origin(0.0, &ranges));
    assert_eq!(trace.arcs.len(), 1);
    assert!(trace.arcs[0].also_fitted);
    let cluster = trace
        .clusters
        .iter()
        .find(|c| c.sensors == [5, 6, 7])
        .expect("one cluster of the three");
    assert_eq!(cluster.constant_depth.len(), 1);
    assert_eq!(cluster.constant_depth[0].kept_sensor, 6);
    assert_eq!(cluster.fitted.len(), 1);
    let added: Vec<usize> = trace
        .memory
        .as_ref()
        .expect("point memory is on")
        .added
        .iter()
        .map(|r| r.sensor())
        .collect();
    assert_eq!(added, vec![6]);

    // Without echo placement (§8.10) nothing explains the ranges as a plane: the arc rule files
    // the reflector alone, and nothing goes to memory.
    let params = Params {
        echo_fit: false,
        ..Params::extended()
    };
    let mut mapper = Mapper::new(params, layout, SensorSpec::default());
    let trace = mapper.step(&snapshot_at_origin(0.0, &ranges));
    assert_eq!(trace.arcs.len(), 1);
    assert_eq!(trace.arcs[0].sensors, vec![5, 6, 7]);
    assert!(!trace.arcs[0].also_fitted);
    assert!(trace.clusters.iter().all(|c| c.constant_depth.is_empty()));
    assert!(trace.memory.as_ref().is_none_or(|m| m.added.is_empty()));
}

#[test]
fn a_sonar_driven_square_on_to_a_wall_stacks_its_readings_instead_of_fitting_them() {
    // One sonar facing +y on a robot driving up x = 0 towards the wall y = 5: it reads the same
    // foot (0, 5) from 4.0, 3.8, 3.6, 3.4 and 3.2 m. Point memory (§8.1) groups them; every
    // two pass the ball test as points (0 apart) but 4.0 and 3.6 fail it as ranges
    // (0.4 > 0.03·7.6 = 0.228): a stack (§8.15), which leaves the memory without a segment.
    let run = |params: Params| {
        let mut mapper = Mapper::new(params, row(&[0.0]), SensorSpec::default());
        (0..5)
            .map(|k| {
                let y = 1.0 + 0.2 * k as f64;
                mapper.step(&Snapshot {
                    t: k as f64,
                    pose: Pose::new(0.0, y, 0.0),
                    ranges_m: vec![Some(5.0 - y)],
                    true_pose: None,
                    reading_dt_s: Vec::new(),
                })
            })
            .collect::<Vec<_>>()
    };
    let traces = run(Params::extended());
    let memory = traces[2].memory.as_ref().expect("point memory is on");
    assert_eq!(memory.stacked.len(), 3, "the first three readings stack");
    assert!(traces.iter().all(|t| t.new_segments.is_empty()));
    // Without the rule (nor a shortest span, which holds a place 0 m long in the memory) the
    // memory fits the three readings of one place into a new segment.
    let traces = run(Params {
        memory_stacks: false,
        memory_min_span_m: 0.0,
        ..Params::extended()
    });
    assert!(matches!(
        traces[2].new_segments.first().map(|s| &s.source),
        Some(SegmentSource::Memory(_))
    ));
}

#[test]
fn a_corner_reading_shared_by_two_short_pieces_goes_to_point_memory_once() {
    // Sensors at x = 0, 0.5, 1 read 2.0, 2.5, 2.0: points (0, 2), (0.5, 2.5), (1, 2), one
    // cluster (0.71 m apart, under t_gap = 42 in). The middle point lies 0.5 m off the line
    // through the ends, over its ball radius 0.075: split into (0, 2)–(0.5, 2.5) and
    // (0.5, 2.5)–(1, 2), which share the middle reading. Both are under `min_piece_points`
    // (3, §8.8), so their readings go to point memory: each once.
    let mut mapper = Mapper::new(
        Params::extended(),
        row(&[0.0, 0.5, 1.0]),
        SensorSpec::default(),
    );
    let trace = mapper.step(&snapshot_at_origin(0.0, &[Some(2.0), Some(2.5), Some(2.0)]));
    assert_eq!(trace.clusters.len(), 1);
    let added: Vec<usize> = trace
        .memory
        .expect("point memory is on")
        .added
        .iter()
        .map(|r| r.sensor())
        .collect();
    assert_eq!(added, vec![0, 1, 2]);
}

#[test]
fn a_wall_read_once_a_step_by_one_sonar_is_one_segment_with_joints_and_pieces_without() {
    // One sonar facing +y on a robot driving along x, 0.19 m a step, reads the wall y = 2 at
    // 2.0 m: one reading a snapshot, each a one-point cluster for point memory (§8.1). With
    // joints (§8.16) each piece shares its newest reading with the next, which overlaps it and
    // extends it: the wall is one segment. Without them the pieces lie a reading's spacing
    // (more than the tolerance) apart: each is a new face, and correlation (§6) links them
    // across the gaps.
    let run = |memory_joints: bool| {
        let params = Params {
            memory_joints,
            ..Params::extended()
        };
        let mut mapper = Mapper::new(params, row(&[0.0]), SensorSpec::default());
        let traces: Vec<_> = (0..13)
            .map(|k| {
                mapper.step(&Snapshot {
                    t: k as f64,
                    pose: Pose::new(0.19 * k as f64, 0.0, 0.0),
                    ranges_m: vec![Some(2.0)],
                    true_pose: None,
                    reading_dt_s: Vec::new(),
                })
            })
            .collect();
        let new_faces = traces
            .iter()
            .flat_map(|t| &t.decisions)
            .filter(|d| d.outcome == Outcome::NewFace)
            .count();
        let spans: Vec<(f64, f64)> = mapper
            .map()
            .segments
            .iter()
            .filter(|s| s.kind == SegmentKind::Fitted)
            .map(|s| (s.a.point.x.min(s.b.point.x), s.a.point.x.max(s.b.point.x)))
            .collect();
        (new_faces, spans)
    };
    let (new_faces, spans) = run(true);
    assert_eq!(new_faces, 1, "{spans:?}");
    assert_eq!(spans.len(), 1);
    let (from, to) = spans[0];
    assert!(
        from.abs() < 1e-9 && (to - 0.19 * 12.0).abs() < 1e-9,
        "{spans:?}"
    );
    let (new_faces, spans) = run(false);
    assert_eq!(new_faces, 4, "{spans:?}");
    // Pieces of three readings, x = 0–0.38, 0.57–0.95, …: 0.19 m between each and the next.
    assert_eq!(spans.len(), 4);
    for (k, &(from, to)) in spans.iter().enumerate() {
        let start = 0.57 * k as f64;
        assert!(
            (from - start).abs() < 1e-9 && (to - start - 0.38).abs() < 1e-9,
            "{spans:?}"
        );
    }
}

/// §8.21 (`echo_agreement`): one sonar facing +y, the robot driving along x 15 mm a step past
/// the wall y = 2 (2.0 m). A crosstalk echo of 0.8 m among the wall's is much shorter than the
/// sensor's last (2.0 m, tolerance 2 × 6 cm at 3 % plus 15 mm driven: 0.135 m) and is set
/// aside; the wall's next reading, longer than it, is kept; 1.9 m (0.1 m shorter) and a
/// doorway's 3.5 m are kept; the wall after the doorway, 1.5 m nearer in one step, loses its
/// first reading (the rule's cost). Without the flag every reading is kept.
#[test]
fn a_reading_much_shorter_than_the_sensors_last_is_set_aside() {
    use sonarmap::mapping::model::trace::DiscardReason;
    let ranges = [2.0, 2.0, 2.0, 0.8, 2.0, 1.9, 3.5, 2.0];
    let readings = |echo_agreement: bool| {
        let params = Params {
            echo_agreement,
            ..Params::extended()
        };
        assert_eq!(params.accuracy_pct, 3.0);
        let mut mapper = Mapper::new(params, row(&[0.0]), SensorSpec::default());
        ranges
            .iter()
            .enumerate()
            .map(|(k, &range_m)| {
                let trace = mapper.step(&Snapshot {
                    t: k as f64,
                    pose: Pose::new(0.015 * k as f64, 0.0, 0.0),
                    ranges_m: vec![Some(range_m)],
                    true_pose: None,
                    reading_dt_s: Vec::new(),
                });
                trace.readings[0].clone()
            })
            .collect::<Vec<_>>()
    };
    let with = readings(true);
    // The crosstalk reading's numbers: its sensor's last echo 2.0 m, tolerance 2 × 0.06 +
    // 0.015 m.
    let refused = with[3].shorter_than_last.expect("the refusal's numbers");
    assert_eq!(refused.last_m, 2.0);
    assert!((refused.tolerance_m - 0.135).abs() < 1e-9, "{refused:?}");
    let discarded = |readings: Vec<sonarmap::mapping::model::trace::ReadingTrace>| {
        readings
            .into_iter()
            .map(|r| r.discarded)
            .collect::<Vec<_>>()
    };
    let mut expected = vec![None; ranges.len()];
    expected[3] = Some(DiscardReason::ShorterThanLast);
    expected[7] = Some(DiscardReason::ShorterThanLast);
    assert_eq!(discarded(with), expected);
    assert_eq!(discarded(readings(false)), vec![None; ranges.len()]);
}
