//! Importers of recorded runs (issue 7): hand-written Player/Stage and table fixtures, MCAP
//! files written here with the `mcap` crate, round trips through the run log, Stage-style
//! Pioneer and Nomad-style runs mapped, every refusal naming its place (the fuzz tests are in
//! `import_fuzz.rs`, hostile inputs in `import_hostile.rs`).
//! Set `SONARMAP_IMPORT_PNG=/tmp/pioneer.png` to keep the rendered Pioneer map for eyes (and
//! its SVG and the Stage-style Player log beside it).

use super::support::fixture_path;
use super::support::ros2::{check_err, nomad_options, write_mcap, MOUNTS};
use sonarmap::geometry::Pose;
use sonarmap::import::{
    builtin_layout, detect, import_any, import_mcap, import_player, import_table, parse_layout,
    Format, ImportOptions, NamedBytes,
};
use sonarmap::log::{load_run, save_run};
use sonarmap::mapping::{Mapper, Params, Preset, StepTrace};
use sonarmap::run::Run;
use sonarmap::sim::{load_plan, simulate, Model};
use sonarmap::units::{inches, Units};
use std::path::PathBuf;

fn fixture(name: &str) -> Vec<u8> {
    let path = fixture_path(name);
    std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol
}

/// `save_run` then `load_run` gives the same readings, poses and layout.
fn check_round_trip(run: &Run) {
    let back = load_run(save_run(run).as_bytes(), "round trip").expect("the log loads");
    assert_eq!(back.snapshots.len(), run.snapshots.len());
    assert_eq!(back.layout.len(), run.layout.len());
    for (a, b) in run.layout.mounts.iter().zip(&back.layout.mounts) {
        assert!(close(a.x_m, b.x_m, 1e-9) && close(a.y_m, b.y_m, 1e-9));
        assert!(close(a.heading_rad, b.heading_rad, 1e-9));
    }
    for (a, b) in run.snapshots.iter().zip(&back.snapshots) {
        assert!(close(a.t, b.t, 1e-12));
        assert!(close(a.pose.x, b.pose.x, 1e-9) && close(a.pose.y, b.pose.y, 1e-9));
        assert!(close(a.pose.heading_rad, b.pose.heading_rad, 1e-9));
        assert_eq!(a.ranges_m.len(), b.ranges_m.len());
        for (ra, rb) in a.ranges_m.iter().zip(&b.ranges_m) {
            match (ra, rb) {
                (Some(x), Some(y)) => assert!(close(*x, *y, 1e-9)),
                (None, None) => {}
                _ => panic!("reading {ra:?} came back as {rb:?}"),
            }
        }
    }
    assert!(close(back.sensor.max_range_m, run.sensor.max_range_m, 1e-9));
}

pub(super) fn map_all(run: &Run) -> (Mapper, Vec<StepTrace>) {
    let mut mapper = Mapper::new(
        Params::preset(Preset::Paper),
        run.layout.clone(),
        run.sensor,
    );
    let traces = run.snapshots.iter().map(|s| mapper.step(s)).collect();
    (mapper, traces)
}

// ------------------------------------------------------------------ Player/Stage

#[test]
fn player2_fixture_imports_with_its_geometry_and_interpolated_poses() {
    let i = import_player(
        &fixture("pioneer_tiny.player2.log"),
        "p2.log",
        &ImportOptions::default(),
    )
    .unwrap();
    assert_eq!(i.format, Format::Player);
    let run = &i.run;
    assert_eq!(run.layout.len(), 4);
    assert!(close(run.layout.mounts[0].y_m, 0.136, 1e-12));
    assert!(close(run.layout.mounts[3].heading_rad, -1.571, 1e-12));
    assert_eq!(run.snapshots.len(), 2);
    // t = 1000.1 is half way between the odometry at 1000.0 and 1000.2.
    let s = &run.snapshots[0];
    assert!(close(s.t, 1000.1, 1e-9));
    assert!(close(s.pose.x, 0.1, 1e-9) && close(s.pose.heading_rad, 0.05, 1e-9));
    // 5.000 is the Pioneer's "no echo".
    assert_eq!(s.ranges_m, vec![Some(1.25), Some(2.0), None, Some(0.8)]);
    assert_eq!(run.snapshots[1].ranges_m[2], Some(4.5));
    assert_eq!(i.summary.turned_no_echo, 1);
    assert_eq!(i.summary.readings, 8);
    assert!(
        i.summary
            .warnings
            .iter()
            .any(|w| w.contains("1 lines of other")),
        "{:?}",
        i.summary
    );
    check_round_trip(run);
}

#[test]
fn player1_lines_give_the_same_run() {
    let a = import_player(
        &fixture("pioneer_tiny.player2.log"),
        "p2",
        &ImportOptions::default(),
    )
    .unwrap()
    .run;
    let b = import_player(
        &fixture("pioneer_tiny.player1.log"),
        "p1",
        &ImportOptions::default(),
    )
    .unwrap()
    .run;
    assert_eq!(a.layout, b.layout);
    assert_eq!(a.snapshots, b.snapshots);
}

#[test]
fn player3_geometry_with_3d_poses() {
    let text =
        "0.0 1 6665 sonar 00 001 002 0002 0.1 0.2 0.3 0.0 0.0 1.5 -0.1 -0.2 0.3 0.0 0.0 -1.5\n\
                0.0 1 6665 position2d 00 001 001 1 2 0.5 0 0 0 0\n\
                0.1 1 6665 sonar 00 001 001 0002 1.0 6.0\n";
    let i = import_player(text.as_bytes(), "p3", &ImportOptions::default()).unwrap();
    let m = &i.run.layout.mounts;
    assert_eq!((m[0].x_m, m[0].y_m, m[0].heading_rad), (0.1, 0.2, 1.5));
    assert_eq!((m[1].x_m, m[1].y_m, m[1].heading_rad), (-0.1, -0.2, -1.5));
    assert_eq!(i.run.snapshots[0].ranges_m, vec![Some(1.0), None]);
    assert_eq!(
        i.run.snapshots[0].pose,
        Pose::new(1.0, 2.0, 0.5),
        "clamped to the last odometry"
    );
    assert!(i
        .summary
        .warnings
        .iter()
        .any(|w| w.contains("took its pose")));
}

#[test]
fn player_max_range_option_and_layout_override() {
    let options = ImportOptions {
        max_range_m: Some(1.95),
        ..ImportOptions::default()
    };
    let i = import_player(&fixture("pioneer_tiny.player2.log"), "p2", &options).unwrap();
    assert_eq!(
        i.summary.turned_no_echo, 3,
        "2.0, 5.0 and 4.5: {:?}",
        i.run.snapshots
    );
    // A 16-sonar layout does not fit 4 ranges: the error names the line and the layout.
    let options = ImportOptions {
        layout: builtin_layout("pioneer_8_8"),
        ..ImportOptions::default()
    };
    check_err(
        import_player(&fixture("pioneer_tiny.player2.log"), "p2.log", &options),
        &[
            "p2.log",
            "line 12",
            "4 ranges",
            "expected one per sensor, 16",
            "--layout",
        ],
    );
}

const HEAD: &str = "1.0 1 6665 position2d 00 001 001 0 0 0 0 0 0 0\n";
const GEOM: &str = "1.0 1 6665 sonar 00 004 001 2 0 0 0 0 0 3.14159\n";

#[test]
fn player_refusals_name_the_line_and_what_was_expected() {
    let o = ImportOptions::default();
    let p = |s: &str| import_player(s.as_bytes(), "bad.log", &o);
    check_err(
        p(&format!("{GEOM}{HEAD}1.1 1 6665 sonar 00 001 001 2 1.0\n")),
        &["bad.log: line 3", "expected 10"],
    );
    check_err(
        p(&format!(
            "{GEOM}{HEAD}1.1 1 6665 sonar 00 001 001 2 1.0 abc\n"
        )),
        &[
            "line 3, field 10",
            "\"abc\" is not a finite number",
            "a range in metres",
        ],
    );
    check_err(
        p(&format!(
            "{GEOM}{HEAD}1.1 1 6665 sonar 00 001 001 3 1.0 2.0 3.0\n"
        )),
        &[
            "line 3",
            "3 ranges",
            "expected one per sensor, 2 (the geometry on line 1)",
        ],
    );
    check_err(
        p(&format!(
            "{GEOM}{HEAD}1.1 1 6665 sonar 00 001 001 2 1.0 -2.0\n"
        )),
        &["line 3, field 10", "negative"],
    );
    check_err(
        p("hello world\n"),
        &["bad.log: line 1", "expected `time host robot"],
    );
    check_err(
        p(&format!("{HEAD}1.1 1 6665 sonar 00 001 001 2 1.0 2.0\n")),
        &["no sonar geometry", "--layout"],
    );
    check_err(
        p(&format!("{GEOM}1.1 1 6665 sonar 00 001 001 2 1.0 2.0\n")),
        &["no odometry", "--fixed-pose"],
    );
    check_err(p("# only a comment\n"), &["no sonar geometry"]);
    // Time going backwards: the line is skipped with a warning.
    let i = p(&format!(
        "{GEOM}{HEAD}1.5 1 6665 sonar 00 001 001 2 1.0 2.0\n1.2 1 6665 sonar 00 001 001 2 1.0 2.0\n1.6 1 6665 sonar 00 001 001 2 1.0 2.0\n"
    ))
    .unwrap();
    assert_eq!(i.run.snapshots.len(), 2);
    assert_eq!(i.summary.skipped.len(), 1);
    assert_eq!(i.summary.skipped[0].place, "line 4");
    assert!(i
        .summary
        .warnings
        .iter()
        .any(|w| w.contains("time goes backwards")));
    // Far from any odometry: skipped with a reason; within 1 s: the nearest pose.
    let i = p(&format!(
        "{GEOM}{HEAD}1.5 1 6665 sonar 00 001 001 2 1.0 2.0\n9.0 1 6665 sonar 00 001 001 2 1.0 2.0\n"
    ))
    .unwrap();
    assert_eq!(i.run.snapshots.len(), 1);
    assert!(i.summary.skipped[0].reason.contains("odometry"));
    // No odometry with a fixed pose asked for.
    let o = ImportOptions {
        fixed_pose: Some(Pose::new(1.0, 2.0, 0.5)),
        ..ImportOptions::default()
    };
    let i = import_player(
        format!("{GEOM}1.1 1 6665 sonar 00 001 001 2 1.0 2.0\n").as_bytes(),
        "f",
        &o,
    )
    .unwrap();
    assert_eq!(i.run.snapshots[0].pose, Pose::new(1.0, 2.0, 0.5));
}

// ------------------------------------------------------------------ tables

#[test]
fn table_fixture_imports_in_inches_with_no_echo_marks() {
    let i = import_table(&fixture("nomad_tiny.table.csv"), "t.csv", &nomad_options()).unwrap();
    let run = &i.run;
    assert_eq!(run.units, Units::Inches);
    assert_eq!(run.snapshots.len(), 2);
    assert!(close(run.snapshots[0].pose.x, inches(120.0), 1e-12));
    assert!(close(
        run.snapshots[0].ranges_m[0].unwrap(),
        inches(48.2),
        1e-12
    ));
    assert_eq!(run.snapshots[0].ranges_m[2], None);
    assert_eq!(
        run.snapshots[1].ranges_m[2], None,
        "255 in is the Nomad's no echo"
    );
    assert_eq!(i.summary.turned_no_echo, 1);
    check_round_trip(run);
    // The same as a ranges table and a poses table.
    let ranges = "0.0 48.2 51 - 110.4 230 97.3 77 75.1 74.9 76 80.2 99 - 60 52.3 49.9\n";
    let poses = "# t x y heading\n-1 120 77 0\n1 130 77 90\n";
    let o = ImportOptions {
        poses: Some(NamedBytes {
            name: "poses.txt".into(),
            bytes: poses.as_bytes().to_vec(),
        }),
        ..nomad_options()
    };
    let i = import_table(ranges.as_bytes(), "r.txt", &o).unwrap();
    let p = i.run.snapshots[0].pose;
    assert!(close(p.x, inches(125.0), 1e-12) && close(p.heading_rad, 45f64.to_radians(), 1e-12));
}

#[test]
fn table_refusals_name_the_line_and_what_was_expected() {
    let o = nomad_options();
    let t = |s: &str| import_table(s.as_bytes(), "bad.csv", &o);
    check_err(
        import_table(b"0 1 2 3", "x.csv", &ImportOptions::default()),
        &["x.csv", "a table has no sensor geometry", "--layout"],
    );
    check_err(
        t("0 1 2 3 4\n"),
        &[
            "bad.csv: line 1",
            "5 fields: expected 20",
            "t x y heading then 16 ranges",
        ],
    );
    let row = |t: &str| format!("{t} 0 0 0 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16\n");
    check_err(
        t(&format!("{}{}", row("1"), row("0.5"))),
        &["line 2, field 1", "earlier"],
    );
    check_err(
        t(&row("1").replace(" 7 ", " seven ")),
        &["line 1, field 11", "\"seven\"", "a range"],
    );
    check_err(
        t(&row("1").replace(" 7 ", " -7 ")),
        &["line 1, field 11", "negative"],
    );
    check_err(
        t("0 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16\n"),
        &["no odometry", "--fixed-pose"],
    );
    check_err(t("# nothing\n"), &["no sonar readings"]);
}

// ------------------------------------------------------------------ MCAP

#[test]
fn mcap_with_tf_static_imports_cycles_with_rep117_no_echo() {
    let bytes = write_mcap(true, false);
    assert_eq!(detect(&bytes), Some(Format::Mcap));
    let i = import_mcap(&bytes, "run.mcap", &ImportOptions::default()).unwrap();
    let run = &i.run;
    assert_eq!(run.layout.len(), 4);
    for (m, e) in run.layout.mounts.iter().zip(MOUNTS) {
        assert!(close(m.x_m, e.0, 1e-12) && close(m.y_m, e.1, 1e-12));
        assert!(
            close(m.heading_rad, e.2, 1e-9),
            "{} vs {}",
            m.heading_rad,
            e.2
        );
    }
    assert_eq!(run.snapshots.len(), 3, "{:?}", i.summary);
    let s0 = &run.snapshots[0];
    assert!(
        close(s0.t, 10.13, 1e-6),
        "mean of the cycle's times: {}",
        s0.t
    );
    assert!(close(s0.pose.x, 0.13, 1e-6) && close(s0.pose.heading_rad, 0.065, 1e-6));
    for k in 0..4 {
        assert!(
            close(s0.ranges_m[k].unwrap(), 1.0 + 0.1 * k as f64, 1e-6),
            "{k}"
        );
    }
    assert_eq!(run.snapshots[1].ranges_m[1], None, "infinity is no echo");
    assert_eq!(
        run.snapshots[2].ranges_m[2], None,
        "beyond max_range is no echo"
    );
    assert_eq!(i.summary.turned_no_echo, 2);
    assert!(close(run.sensor.max_range_m, 5.0, 1e-6));
    assert!(close(run.sensor.min_range_m, 0.15, 1e-6));
    assert!(
        i.summary.warnings.iter().any(|w| w.contains("/chatter")),
        "{:?}",
        i.summary
    );
    check_round_trip(run);
}

#[test]
fn mcap_cycle_window_splits_and_layout_frames_map() {
    let bytes = write_mcap(false, false);
    check_err(
        import_mcap(&bytes, "run.mcap", &ImportOptions::default()),
        &["run.mcap", "/tf_static", "--layout"],
    );
    let layout = parse_layout(
        br#"{"format": "sonarmap-layout", "version": 1, "units": "m",
             "robot": {"radius": 0.2, "sonars": {"ring": {"count": 4, "spacing_deg": 90}}},
             "frames": {"sonar_0": 0, "sonar_1": 1, "/sonar_2": 2}}"#,
        "ring4.json",
    )
    .unwrap();
    let o = ImportOptions {
        layout: Some(layout),
        window_s: Some(0.03),
        ..ImportOptions::default()
    };
    let i = import_mcap(&bytes, "run.mcap", &o).unwrap();
    // sonar_3 is not in the frames map (neither frame nor topic): skipped; the 30 ms window
    // cuts each cycle of sonars 0..2 (0, 20, 40 ms) in two.
    assert_eq!(i.summary.skipped.len(), 3, "{:?}", i.summary);
    assert!(i.summary.skipped[0].reason.contains("frames"));
    assert_eq!(i.run.snapshots.len(), 6);
    assert_eq!(
        i.run.snapshots[1].ranges_m[2].map(|r| (r * 10.0).round()),
        Some(12.0)
    );
    // Each reading keeps its own moment: sonars 0 and 1 at 0 and 20 ms, the cycle at 10 ms;
    // sonar 2 alone in its cycle, at the cycle's moment.
    let dt = &i.run.snapshots[0].reading_dt_s;
    assert!(
        close(dt[0], -0.01, 1e-9) && close(dt[1], 0.01, 1e-9),
        "{dt:?}"
    );
    assert!(i.run.snapshots[1].reading_dt_s.is_empty());
}

#[test]
fn mcap_refusals_name_the_message() {
    check_err(
        import_mcap(
            &write_mcap(true, true),
            "cut.mcap",
            &ImportOptions::default(),
        ),
        &[
            "cut.mcap",
            "MCAP message",
            "(topic /sonar_2)",
            "expected range",
        ],
    );
    let mut bytes = write_mcap(true, false);
    bytes.truncate(bytes.len() / 2);
    let e = import_mcap(&bytes, "half.mcap", &ImportOptions::default());
    check_err(e, &["half.mcap", "MCAP"]);
    check_err(
        import_mcap(b"not mcap", "x.mcap", &ImportOptions::default()),
        &["x.mcap: byte 0", "magic"],
    );
}

// ------------------------------------------------------------------ detection

#[test]
fn content_decides_the_importer() {
    assert_eq!(
        detect(&fixture("pioneer_tiny.player2.log")),
        Some(Format::Player)
    );
    assert_eq!(
        detect(&fixture("pioneer_tiny.player1.log")),
        Some(Format::Player)
    );
    assert_eq!(
        detect(&fixture("nomad_tiny.table.csv")),
        Some(Format::Table)
    );
    assert_eq!(
        detect(b"\xEF\xBB\xBF  {\"format\": 1}"),
        Some(Format::SonarmapLog)
    );
    assert_eq!(detect(b"hello\nworld\n"), None);
    assert_eq!(detect(b""), None);
    let log = save_run(&sonarmap::assets::default_run().unwrap());
    let i = import_any(log.as_bytes(), "blue.json", &ImportOptions::default()).unwrap();
    assert_eq!(i.format, Format::SonarmapLog);
    check_err(
        import_any(b"\x00\x01binary", "b.bin", &ImportOptions::default()),
        &["b.bin: not a recognised run"],
    );
}

// ------------------------------------------------------------------ realistic runs

pub(super) fn pioneer_plan_json() -> String {
    let layout: serde_json::Value =
        serde_json::from_str(include_str!("../../assets/pioneer_8_8.layout.json")).unwrap();
    serde_json::json!({
        "format": "sonarmap-plan", "version": 1, "units": "m",
        "name": "Stage-style Pioneer in a 6 m x 4 m room",
        "walls": [[0, 0, 6, 0], [6, 0, 6, 4], [6, 4, 0, 4], [0, 4, 0, 0], [2.5, 4, 2.5, 2.8]],
        "path": [[1.2, 1.5, 0], [4.5, 1.5, 0], [4.5, 1.5, 90], [4.5, 2.6, 90]],
        "step": 0.1, "turn_step_deg": 15,
        "robot": layout["robot"], "sensor": layout["sensor"]
    })
    .to_string()
}

/// A run written as Stage's writelog would: geometry, then odometry and sonar lines.
pub(super) fn to_player2(run: &Run) -> String {
    let mut s = String::from("## Player version 3.0.2\n## File version 0.3.0\n");
    let g: Vec<String> = run
        .layout
        .mounts
        .iter()
        .map(|m| format!("{:+.3} {:+.3} {:+.6}", m.x_m, m.y_m, m.heading_rad))
        .collect();
    s += &format!(
        "0.000 16777343 6665 sonar 00 004 001 {:04} {}\n",
        g.len(),
        g.join(" ")
    );
    for (i, snap) in run.snapshots.iter().enumerate() {
        let t = 100.0 + 0.2 * i as f64;
        let p = snap.pose;
        s += &format!(
            "{t:.3} 16777343 6665 position2d 00 001 001 {:+.6} {:+.6} {:+.6} +0.000 +0.000 +0.000 0\n",
            p.x, p.y, p.heading_rad
        );
        let r: Vec<String> = snap
            .ranges_m
            .iter()
            .map(|r| format!("{:.3}", r.unwrap_or(5.0).min(5.0)))
            .collect();
        s += &format!(
            "{t:.3} 16777343 6665 sonar 00 001 001 {:04} {}\n",
            r.len(),
            r.join(" ")
        );
        s += &format!("{t:.3} 16777343 6665 laser 00 001 001 0000\n");
    }
    s
}

#[test]
fn stage_style_pioneer_run_imports_maps_and_exports_an_svg() {
    let plan = load_plan(pioneer_plan_json().as_bytes(), "pioneer plan").unwrap();
    let truth = simulate(&plan, Model::Specular, 7);
    let text = to_player2(&truth);
    if let Ok(path) = std::env::var("SONARMAP_IMPORT_PNG") {
        std::fs::write(PathBuf::from(path).with_extension("log"), &text).unwrap();
    }
    let i = import_any(text.as_bytes(), "stage.log", &ImportOptions::default()).unwrap();
    assert_eq!(i.format, Format::Player);
    let run = &i.run;
    assert_eq!(run.snapshots.len(), truth.snapshots.len());
    for (a, b) in truth.snapshots.iter().zip(&run.snapshots) {
        assert!(
            close(a.pose.x, b.pose.x, 1e-6) && close(a.pose.heading_rad, b.pose.heading_rad, 1e-6)
        );
        for (ra, rb) in a.ranges_m.iter().zip(&b.ranges_m) {
            match (ra.filter(|v| *v < 4.9995), rb) {
                (Some(x), Some(y)) => assert!(close(x, *y, 5e-4)),
                (None, None) => {}
                other => panic!("{other:?}"),
            }
        }
    }
    check_round_trip(run);
    let (mapper, traces) = map_all(run);
    let segments = mapper.map().segments.len();
    assert!(segments >= 3, "the room gives segments: {segments}");
    write_png(run, &mapper, &traces);
}

/// The last step of an imported run as SVG (scene + SVG writer) and PNG (resvg).
fn write_png(run: &Run, mapper: &Mapper, traces: &[StepTrace]) {
    use sonarmap::scene::svg::{default_view, to_svg};
    use sonarmap::scene::{build_scene, SceneInput, ViewOptions};
    // Map before the last step: replay all but the last snapshot.
    let mut before = Mapper::new(
        Params::preset(Preset::Paper),
        run.layout.clone(),
        run.sensor,
    );
    for s in &run.snapshots[..run.snapshots.len() - 1] {
        before.step(s);
    }
    let k = run.snapshots.len() - 1;
    let input = SceneInput {
        run,
        snapshot: k,
        step: &traces[k],
        previous_step: traces.get(k.wrapping_sub(1)),
        map_before: before.map(),
        map_after: mapper.map(),
        truth: None,
        support_of: None,
        figure_labels: false,
        corrected_path: &[],
    };
    let scene = build_scene(&input, &ViewOptions::default());
    let svg = to_svg(
        &scene,
        default_view(&scene),
        (900, 650),
        "Stage-style Pioneer (imported)",
        run.units,
    );
    let opt = sonarmap::export::svg_options();
    let tree = usvg::Tree::from_str(&svg, &opt).expect("the SVG parses");
    let size = tree.size().to_int_size();
    let mut pixmap = resvg::tiny_skia::Pixmap::new(size.width(), size.height()).unwrap();
    resvg::render(
        &tree,
        resvg::tiny_skia::Transform::identity(),
        &mut pixmap.as_mut(),
    );
    let drawn = pixmap
        .pixels()
        .iter()
        .filter(|p| p.red() < 200 || p.blue() < 200)
        .count();
    assert!(drawn > 1000, "the map draws something: {drawn} pixels");
    if let Ok(path) = std::env::var("SONARMAP_IMPORT_PNG") {
        pixmap.save_png(PathBuf::from(&path)).unwrap();
        std::fs::write(PathBuf::from(path).with_extension("svg"), &svg).unwrap();
    }
}

#[test]
fn nomad_style_table_run_imports_and_maps() {
    let plan = load_plan(
        br#"{"format": "sonarmap-plan", "version": 1, "units": "in",
             "walls": [[0, 0, 305, 0], [305, 0, 305, 154], [305, 154, 0, 154], [0, 154, 0, 0]],
             "path": [[60, 77, 0], [240, 77, 0]], "step": 5}"#,
        "nomad plan",
    )
    .unwrap();
    let truth = simulate(&plan, Model::Specular, 3);
    let mut table = String::from("# t x y heading_deg r0..r15 (in)\n");
    for (i, s) in truth.snapshots.iter().enumerate() {
        let r: Vec<String> = s
            .ranges_m
            .iter()
            .map(|r| r.map_or("-".to_string(), |v| format!("{:.4}", v / 0.0254)))
            .collect();
        table += &format!(
            "{i}, {:.4}, {:.4}, {:.4}, {}\n",
            s.pose.x / 0.0254,
            s.pose.y / 0.0254,
            s.pose.heading_rad.to_degrees(),
            r.join(", ")
        );
    }
    let i = import_any(table.as_bytes(), "nomad.csv", &nomad_options()).unwrap();
    assert_eq!(i.format, Format::Table);
    assert_eq!(i.run.snapshots.len(), truth.snapshots.len());
    check_round_trip(&i.run);
    let (mapper, _) = map_all(&i.run);
    assert!(
        mapper.map().segments.len() >= 2,
        "{}",
        mapper.map().segments.len()
    );
}

// ------------------------------------------------------------------ command line

#[test]
fn convert_writes_a_log_that_run_reads_and_run_reads_a_player_log_directly() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("stage.log");
    let plan = load_plan(pioneer_plan_json().as_bytes(), "plan").unwrap();
    std::fs::write(&input, to_player2(&simulate(&plan, Model::Specular, 7))).unwrap();
    let out = dir.path().join("stage.log.json");
    let bin = env!("CARGO_BIN_EXE_sonarmap");
    let o = std::process::Command::new(bin)
        .args([
            "convert",
            input.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--max-range",
            "4.5",
        ])
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(
        stdout.contains("Player/Stage text log") && stdout.contains("turned into no echo"),
        "{stdout}"
    );
    let run = load_run(&std::fs::read(&out).unwrap(), "out").unwrap();
    assert!(close(run.sensor.max_range_m, 4.5, 1e-9));
    for path in [&out, &input] {
        let o = std::process::Command::new(bin)
            .args(["run", path.to_str().unwrap()])
            .output()
            .unwrap();
        assert_eq!(
            o.status.code(),
            Some(0),
            "{}",
            String::from_utf8_lossy(&o.stderr)
        );
        assert!(String::from_utf8_lossy(&o.stdout).starts_with("snapshots "));
    }
    // A table without --layout: exit 2, the message names --layout.
    let table = dir.path().join("t.csv");
    std::fs::write(&table, "0 1 2 3\n").unwrap();
    let o = std::process::Command::new(bin)
        .args([
            "convert",
            table.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--layout"));
    // A shipped layout by name, and a fixed pose.
    let o = std::process::Command::new(bin)
        .args([
            "convert",
            table.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--layout",
            "nomad_200",
            "--units",
            "in",
            "--fixed-pose",
            "10,20,-90",
        ])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2), "4 fields do not fit a 16-ring");
    assert!(String::from_utf8_lossy(&o.stderr).contains("t.csv: line 1"));
}

// The fuzz tests, which check the contract for what is accepted, are in `import_fuzz.rs`; the
// hostile inputs of issue 18 in `import_hostile.rs`.
