//! The run-log format: every error path names the file and the place; round trips.

use sonarmap::log::{load_run, save_run, LogError};
use sonarmap::units::Units;

const NAME: &str = "test.log.json";

fn log_with(snapshots: &str) -> String {
    format!(
        r#"{{"format": "sonarmap-log", "version": 1, "units": "in",
  "robot": {{"radius": 9, "sonars": {{"ring": {{"count": 4, "spacing_deg": 90}}}}}},
  "snapshots": [{snapshots}]}}"#
    )
}

const GOOD_SNAPSHOT: &str =
    r#"{"t": 0, "pose": {"x": 1, "y": 2, "heading_deg": 90}, "ranges": [10, null, 255, 20.5]}"#;

/// Loads `text` and expects an error whose message contains every one of `parts`.
fn check_error(text: &str, parts: &[&str]) -> LogError {
    let err = load_run(text.as_bytes(), NAME).expect_err("the log must be rejected");
    let msg = err.to_string();
    assert!(msg.contains(NAME), "message does not name the file: {msg}");
    for p in parts {
        assert!(msg.contains(p), "message lacks {p:?}: {msg}");
    }
    err
}

#[test]
fn a_good_log_is_converted_to_metres() {
    let run = load_run(log_with(GOOD_SNAPSHOT).as_bytes(), NAME).unwrap();
    assert_eq!(run.units, Units::Inches);
    assert_eq!(run.layout.len(), 4);
    let m = &run.layout.mounts[1];
    assert!((m.x_m - 0.0).abs() < 1e-12 && (m.y_m - 9.0 * 0.0254).abs() < 1e-12);
    assert!((m.heading_rad - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
    let s = &run.snapshots[0];
    assert!(
        (s.pose.x - 0.0254).abs() < 1e-12
            && (s.pose.heading_rad - std::f64::consts::FRAC_PI_2).abs() < 1e-12
    );
    assert_eq!(s.ranges_m[1], None);
    // A value at max range is kept (the engine discards it with a reason).
    assert!((s.ranges_m[2].unwrap() - 255.0 * 0.0254).abs() < 1e-12);
    // Sensor defaults: the Polaroid 6500.
    assert!((run.sensor.max_range_m - 255.0 * 0.0254).abs() < 1e-12);
    assert_eq!(run.name, NAME);
}

#[test]
fn bom_unknown_fields_and_missing_t_are_accepted() {
    let text = format!(
        "\u{feff}{}",
        log_with(
            r#"{"pose": {"x": 0, "y": 0, "heading_deg": 0}, "ranges": [1, 2, 3, 4], "extra": {"a": [1]}},
                    {"pose": {"x": 0, "y": 0, "heading_deg": 0}, "ranges": [1, 2, 3, 4]}"#
        )
    );
    let run = load_run(text.as_bytes(), NAME).unwrap();
    assert_eq!(run.snapshots[0].t, 0.0);
    assert_eq!(run.snapshots[1].t, 1.0);
}

#[test]
fn explicit_mounts_and_metric_units() {
    let text = r#"{"format": "sonarmap-log", "version": 1, "units": "cm",
      "robot": {"sonars": [{"x": 10, "y": 0, "heading_deg": 0}, {"x": 0, "y": 10, "heading_deg": 90}]},
      "sensor": {"max_range": 500},
      "floor_plan": {"walls": [[0, 0, 100, 0, 15]], "circles": [[50, 50, 5]]},
      "snapshots": [{"pose": {"x": 100, "y": 0, "heading_deg": 0}, "ranges": [50, null]}]}"#;
    let run = load_run(text.as_bytes(), NAME).unwrap();
    assert_eq!(run.robot_radius_m, None);
    assert!((run.layout.mounts[1].y_m - 0.1).abs() < 1e-12);
    assert!((run.sensor.max_range_m - 5.0).abs() < 1e-12);
    assert!(
        (run.sensor.min_range_m - 6.0 * 0.0254).abs() < 1e-12,
        "default min range converted"
    );
    let plan = run.floor_plan.unwrap();
    assert!((plan.walls[0].roughness_rad.unwrap() - 15f64.to_radians()).abs() < 1e-12);
    assert!((plan.circles[0].radius_m - 0.05).abs() < 1e-12);
}

#[test]
fn not_json_names_line_and_column() {
    let err = check_error("{\n  \"format\": ,\n}", &["not JSON", "line 2"]);
    assert!(matches!(err, LogError::NotJson { line: 2, .. }));
}

#[test]
fn duplicated_keys_are_errors_at_any_depth() {
    check_error(
        &log_with(GOOD_SNAPSHOT)
            .replace("\"units\": \"in\"", "\"units\": \"in\", \"units\": \"m\""),
        &["duplicated key `units`", "$"],
    );
    let snap = r#"{"pose": {"x": 1, "x": 2, "y": 0, "heading_deg": 0}, "ranges": [1, 2, 3, 4]}"#;
    check_error(
        &log_with(&format!("{GOOD_SNAPSHOT}, {snap}")),
        &["duplicated key `x`", "$.snapshots[1].pose"],
    );
    // Unknown keys too.
    let snap =
        r#"{"pose": {"x": 1, "y": 0, "heading_deg": 0}, "ranges": [1, 2, 3, 4], "z": 1, "z": 2}"#;
    check_error(&log_with(snap), &["duplicated key `z`", "$.snapshots[0]"]);
}

#[test]
fn wrong_format_version_and_units() {
    let good = log_with(GOOD_SNAPSHOT);
    check_error(
        &good.replace("sonarmap-log", "other"),
        &["`format`", "other", "sonarmap-log"],
    );
    check_error(
        &good.replace("\"version\": 1", "\"version\": 2"),
        &["`version` 2", "expected 1"],
    );
    check_error(
        &good.replace("\"units\": \"in\"", "\"units\": \"ft\""),
        &["`units`", "ft", "\"mm\""],
    );
}

#[test]
fn ranges_of_the_wrong_length_name_the_snapshot() {
    let snap = r#"{"pose": {"x": 1, "y": 0, "heading_deg": 0}, "ranges": [1, 2, 3]}"#;
    check_error(
        &log_with(&format!("{GOOD_SNAPSHOT}, {snap}")),
        &["snapshot 1", "has 3 ranges", "4"],
    );
}

#[test]
fn negative_and_overflowing_ranges_name_snapshot_and_sensor() {
    let snap = r#"{"pose": {"x": 1, "y": 0, "heading_deg": 0}, "ranges": [1, 2, -3, 4]}"#;
    check_error(
        &log_with(&format!("{GOOD_SNAPSHOT}, {snap}")),
        &["snapshot 1, sensor 2", "-3"],
    );
    // 1e400 does not fit an f64: serde_json refuses it (never an infinity), with line and column.
    let snap = r#"{"pose": {"x": 1, "y": 0, "heading_deg": 0}, "ranges": [1, 1e400, 3, 4]}"#;
    check_error(&log_with(snap), &["number out of range", "line 3 column"]);
}

#[test]
fn missing_pose_fields_and_required_fields() {
    let snap = r#"{"pose": {"x": 1, "heading_deg": 0}, "ranges": [1, 2, 3, 4]}"#;
    check_error(
        &log_with(&format!("{GOOD_SNAPSHOT}, {snap}")),
        &["$.snapshots[1].pose", "missing field `y`"],
    );
    check_error(
        &log_with(GOOD_SNAPSHOT).replace("\"units\": \"in\",", ""),
        &["missing field `units`"],
    );
    check_error(
        &log_with(GOOD_SNAPSHOT).replace("\"ranges\"", "\"rangez\""),
        &["$.snapshots[0]", "missing field `ranges`"],
    );
    check_error(
        &log_with(GOOD_SNAPSHOT).replace("\"x\": 1", "\"x\": \"one\""),
        &["$.snapshots[0].pose.x", "invalid type"],
    );
}

#[test]
fn empty_snapshots_and_decreasing_time() {
    check_error(&log_with(""), &["$.snapshots", "at least one snapshot"]);
    let late = r#"{"t": 5, "pose": {"x": 1, "y": 0, "heading_deg": 0}, "ranges": [1, 2, 3, 4]}"#;
    let early = r#"{"t": 4, "pose": {"x": 1, "y": 0, "heading_deg": 0}, "ranges": [1, 2, 3, 4]}"#;
    check_error(
        &log_with(&format!("{late}, {early}")),
        &["snapshot 1", "must not decrease"],
    );
}

#[test]
fn absurd_layouts_are_rejected() {
    let good = log_with(GOOD_SNAPSHOT);
    check_error(
        &good.replace("\"count\": 4", "\"count\": 0"),
        &["$.robot.sonars.ring.count", "at least one"],
    );
    check_error(
        &good.replace("\"count\": 4", "\"count\": 4.5"),
        &["$.robot.sonars.ring.count", "whole number"],
    );
    check_error(
        &good.replace("\"count\": 4", "\"count\": 20000"),
        &["$.robot.sonars.ring.count", "10000"],
    );
    check_error(
        &good.replace("\"radius\": 9", "\"radius\": -9"),
        &["$.robot.radius", "-9"],
    );
    check_error(
        &good.replace("\"radius\": 9, ", ""),
        &["$.robot.radius", "required with the ring"],
    );
    check_error(
        &good.replace(r#"{"ring": {"count": 4, "spacing_deg": 90}}"#, "[]"),
        &["$.robot.sonars", "at least one sonar"],
    );
    check_error(
        &good.replace(r#""spacing_deg": 90"#, r#""spacing_deg": "x""#),
        &["$.robot.sonars.ring.spacing_deg"],
    );
}

#[test]
fn bad_floor_plans_and_sensors_name_the_place() {
    let good = log_with(GOOD_SNAPSHOT);
    let with_plan = good.replace(
        "\"snapshots\"",
        r#""floor_plan": {"walls": [[0, 0, 1, 1], [0, 0, 1]]}, "snapshots""#,
    );
    check_error(&with_plan, &["$.floor_plan.walls[1]", "[x1, y1, x2, y2]"]);
    let with_sensor = good.replace(
        "\"snapshots\"",
        r#""sensor": {"max_range": 0}, "snapshots""#,
    );
    check_error(&with_sensor, &["$.sensor.max_range", "greater than 0"]);
}

#[test]
fn save_then_load_gives_the_run_back_and_keeps_the_ring() {
    let text = log_with(GOOD_SNAPSHOT).replace(
        "\"snapshots\"",
        r#""floor_plan": {"walls": [[0, 0, 305, 0, 12]], "circles": [[1, 2, 3]]}, "snapshots""#,
    );
    let run = load_run(text.as_bytes(), NAME).unwrap();
    let saved = save_run(&run);
    assert!(saved.contains("\"ring\""), "ring shorthand kept:\n{saved}");
    assert!(
        saved.contains("20.5"),
        "numbers written in inches as given:\n{saved}"
    );
    let again = load_run(saved.as_bytes(), NAME).unwrap();
    assert_eq!(again.layout.len(), run.layout.len());
    for (a, b) in again.layout.mounts.iter().zip(&run.layout.mounts) {
        assert!((a.x_m - b.x_m).abs() < 1e-12 && (a.heading_rad - b.heading_rad).abs() < 1e-12);
    }
    for (a, b) in again.snapshots.iter().zip(&run.snapshots) {
        assert_eq!(a.t, b.t);
        for (ra, rb) in a.ranges_m.iter().zip(&b.ranges_m) {
            assert_eq!(ra.is_some(), rb.is_some());
            if let (Some(x), Some(y)) = (ra, rb) {
                assert!((x - y).abs() < 1e-12);
            }
        }
    }
    assert_eq!(
        again.floor_plan,
        run.floor_plan.map(|mut p| {
            // Walls and circles survive to within the 1e-9 in rounding of the writer.
            for (w, v) in p
                .walls
                .iter_mut()
                .zip(&again.floor_plan.as_ref().unwrap().walls)
            {
                assert!((w.b - v.b).norm() < 1e-12);
                *w = *v;
            }
            for (c, v) in p
                .circles
                .iter_mut()
                .zip(&again.floor_plan.as_ref().unwrap().circles)
            {
                assert!((c.centre - v.centre).norm() < 1e-12);
                *c = *v;
            }
            p
        })
    );
    // Saving is a fixed point after one round.
    assert_eq!(save_run(&again), saved);
}

#[test]
fn explicit_mounts_round_trip_as_a_list() {
    let text = r#"{"format": "sonarmap-log", "version": 1, "units": "mm",
      "robot": {"radius": 200, "sonars": [{"x": 100, "y": 0, "heading_deg": 0}, {"x": 0, "y": 100, "heading_deg": 45}]},
      "snapshots": [{"pose": {"x": 0, "y": 0, "heading_deg": 0}, "ranges": [500, null]}]}"#;
    let run = load_run(text.as_bytes(), NAME).unwrap();
    let saved = save_run(&run);
    assert!(!saved.contains("\"ring\""));
    assert_eq!(load_run(saved.as_bytes(), NAME).unwrap().layout.len(), 2);
}

#[test]
fn the_embedded_default_run_loads() {
    let run = sonarmap::assets::default_run().unwrap();
    assert_eq!(run.snapshots.len(), 2);
    assert_eq!(run.layout.len(), 16);
    assert!(run.floor_plan.is_some());
}

#[test]
fn true_poses_round_trip_and_a_log_without_them_writes_none() {
    let plan_file = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/tight_room.plan.json");
    let plan = sonarmap::sim::load_plan(&std::fs::read(plan_file).unwrap(), "plan").unwrap();
    let run = sonarmap::sim::simulate(&plan, sonarmap::sim::Model::Specular, 4);
    assert!(!save_run(&run).contains("true_pose"));
    let drifted = sonarmap::sim::with_odometry(&run, &sonarmap::sim::OdometryError::BAD, 4);
    let text = save_run(&drifted);
    assert!(text.contains("true_pose"));
    let back = load_run(text.as_bytes(), "drifted").unwrap();
    for (a, b) in drifted.snapshots.iter().zip(&back.snapshots) {
        let (ta, tb) = (a.true_pose.unwrap(), b.true_pose.unwrap());
        assert!(ta.distance_to(&tb) < 1e-9 && (ta.heading_rad - tb.heading_rad).abs() < 1e-9);
        assert!(a.pose.distance_to(&b.pose) < 1e-9);
    }
    // A true pose that is no number is refused with its place.
    let bad = text.replacen(
        "\"true_pose\":{\"x\":",
        "\"true_pose\":{\"x\":\"a\",\"old\":",
        1,
    );
    assert_ne!(bad, text);
    let e = load_run(bad.as_bytes(), "bad.json")
        .unwrap_err()
        .to_string();
    assert!(e.contains("bad.json") && e.contains("true_pose"), "{e}");
}

#[test]
fn reading_times_round_trip_are_checked_and_zero_offsets_map_as_none() {
    use sonarmap::mapping::{Mapper, Params};
    let plan_file = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/tight_room.plan.json");
    let plan = sonarmap::sim::load_plan(&std::fs::read(plan_file).unwrap(), "plan").unwrap();
    let run = sonarmap::sim::simulate(&plan, sonarmap::sim::Model::Specular, 4);
    assert!(!save_run(&run).contains("reading_dt_s"));
    let n = run.layout.len();
    let mut zeroed = run.clone();
    for s in &mut zeroed.snapshots {
        s.reading_dt_s = vec![0.0; n];
    }
    let text = save_run(&zeroed);
    let back = load_run(text.as_bytes(), "zeroed").unwrap();
    assert!(back
        .snapshots
        .iter()
        .all(|s| s.reading_dt_s == vec![0.0; n]));
    // Offsets of zero put every reading at its snapshot's pose: the same map and trace.
    for params in [Params::paper(), Params::extended()] {
        let map_of = |run: &sonarmap::run::Run| {
            let mut m = Mapper::new(params.clone(), run.layout.clone(), run.sensor);
            let traces: Vec<String> = run
                .snapshots
                .iter()
                .map(|s| format!("{:?}", m.step(s)))
                .collect();
            (format!("{:?}", m.map().segments), traces)
        };
        assert!(map_of(&run) == map_of(&zeroed));
        let plain = load_run(save_run(&run).as_bytes(), "plain").unwrap();
        assert!(map_of(&plain) == map_of(&back));
    }
    // One offset too few, and an offset that is no time, are refused with their place.
    let first = format!("\"reading_dt_s\":[{}]", vec!["0.0"; n].join(","));
    assert!(text.contains(&first), "{}", &text[..400]);
    let short = text.replacen(&first, "\"reading_dt_s\":[0.0]", 1);
    let e = load_run(short.as_bytes(), "short.json")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("short.json") && e.contains("snapshots[0].reading_dt_s"),
        "{e}"
    );
    let far = text.replacen(&first, &first.replacen("0.0", "1e9", 1), 1);
    let e = load_run(far.as_bytes(), "far.json")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("far.json") && e.contains("reading_dt_s[0]"),
        "{e}"
    );
}
