//! The binary: subcommands on the assets and on broken files.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn assets(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("assets")
        .join(name)
}

fn sonarmap(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_sonarmap"))
        .args(args)
        .output()
        .expect("the binary runs")
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// Expects exit code 2, nothing on stdout, no panic, and a message containing every part.
fn check_fails(args: &[&str], parts: &[&str]) {
    let out = sonarmap(args);
    let err = text(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "args {args:?}, stderr {err}");
    assert!(
        !err.contains("panicked") && !err.contains("backtrace"),
        "{err}"
    );
    for p in parts {
        assert!(err.contains(p), "stderr lacks {p:?}: {err}");
    }
}

#[test]
fn run_writes_the_poses_it_mapped_with_as_a_tum_trajectory() {
    let dir = tempfile::tempdir().unwrap();
    let poses = dir.path().join("poses.tum");
    let log = assets("tight_room.log.json");
    let out = sonarmap(&[
        "run",
        log.to_str().unwrap(),
        "--out-poses",
        poses.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let run = sonarmap::log::load_run(&std::fs::read(&log).unwrap(), "log").unwrap();
    let text = std::fs::read_to_string(&poses).unwrap();
    let lines: Vec<&str> = text.lines().filter(|l| !l.starts_with('#')).collect();
    assert_eq!(lines.len(), run.snapshots.len());
    // Without pose correction, the poses are the log's, in metres, heading as a z rotation.
    for (line, s) in lines.iter().zip(&run.snapshots) {
        let v: Vec<f64> = line.split(' ').map(|f| f.parse().unwrap()).collect();
        assert_eq!(v.len(), 8);
        assert!((v[0] - s.t).abs() < 1e-9 && (v[1] - s.pose.x).abs() < 1e-9);
        assert!((v[2] - s.pose.y).abs() < 1e-9 && v[3] == 0.0);
        let heading = 2.0 * v[6].atan2(v[7]);
        let off = sonarmap::geometry::wrap_pi(heading - s.pose.heading_rad);
        assert!(off.abs() < 1e-6, "{line}");
    }
}

/// `calibrate_first` (on in `extended`) on a log without drift: the mapping finds none, so
/// `run` writes the map it writes with the flag off, and `eval` reports `"calibration": null`.
#[test]
fn calibrating_a_log_without_drift_maps_it_as_without() {
    let dir = tempfile::tempdir().unwrap();
    let log = assets("building.log.json");
    let off = dir.path().join("off.json");
    std::fs::write(&off, r#"{"preset": "extended", "calibrate_first": false}"#).unwrap();
    let map_with = |params: &[&str], name: &str| {
        let map = dir.path().join(name);
        let mut args = vec!["run", log.to_str().unwrap()];
        args.extend(params);
        args.extend(["--out-map", map.to_str().unwrap()]);
        let out = sonarmap(&args);
        assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
        std::fs::read(map).unwrap()
    };
    assert_eq!(
        map_with(&["--preset", "extended"], "calibrated.json"),
        map_with(&["--params", off.to_str().unwrap()], "once.json")
    );
    let out = sonarmap(&["eval", log.to_str().unwrap(), "--preset", "extended"]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(report["calibration"], serde_json::Value::Null);
    assert!(report.as_object().unwrap().contains_key("calibration"));
}

#[test]
fn run_writes_map_and_trace_and_prints_a_summary() {
    let dir = tempfile::tempdir().unwrap();
    let map = dir.path().join("map.json");
    let trace = dir.path().join("trace.json");
    let log = assets("blue_room.log.json");
    let out = sonarmap(&[
        "run",
        log.to_str().unwrap(),
        "--out-map",
        map.to_str().unwrap(),
        "--out-trace",
        trace.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let summary = text(&out.stdout);
    assert!(
        summary.starts_with("snapshots 2, readings kept"),
        "{summary}"
    );
    let map: serde_json::Value = serde_json::from_slice(&std::fs::read(&map).unwrap()).unwrap();
    assert_eq!(map["format"], "sonarmap-map");
    assert_eq!(map["units"], "in");
    assert_eq!(map["snapshot"], 1);
    let trace: serde_json::Value = serde_json::from_slice(&std::fs::read(&trace).unwrap()).unwrap();
    assert_eq!(trace["steps"].as_array().unwrap().len(), 2);
    // No temporary file is left behind.
    let names: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names.len(), 2, "{names:?}");
}

#[test]
fn run_until_stops_early_and_rejects_a_snapshot_past_the_end() {
    let log = assets("building.log.json");
    let out = sonarmap(&[
        "run",
        log.to_str().unwrap(),
        "--until",
        "9",
        "--preset",
        "extended",
    ]);
    assert_eq!(out.status.code(), Some(0));
    assert!(text(&out.stdout).starts_with("snapshots 10,"));
    check_fails(
        &["run", log.to_str().unwrap(), "--until", "100000"],
        &["--until 100000", "last snapshot"],
    );
}

#[test]
fn run_svg_writes_the_snapshot_as_a_paper_figure() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("blue.svg");
    let log = assets("blue_room.log.json");
    let o = sonarmap(&[
        "run",
        log.to_str().unwrap(),
        "--until",
        "1",
        "--svg",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    let svg = std::fs::read_to_string(&out).unwrap();
    let tree = usvg::Tree::from_str(&svg, &usvg::Options::default()).expect("valid SVG");
    assert!(tree.size().width() > 100.0);
    for id in [
        "floor-plan",
        "map",
        "current-points",
        "previous-snapshot",
        "balls",
    ] {
        assert!(
            svg.contains(&format!("<g id=\"{id}\"")),
            "layer {id} missing"
        );
    }
    assert!(
        !svg.contains("<g id=\"beams\""),
        "beams are not part of a paper figure"
    );
    assert!(svg.contains("snapshot 1"));
    // Nothing is left behind but the file itself.
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
}

/// The figure's two snapshots are stepped last, traced in full, in the same pass that writes the
/// map and the trace: every output must equal the one written alone.
#[test]
fn run_svg_in_the_same_pass_leaves_map_trace_and_summary_unchanged() {
    let dir = tempfile::tempdir().unwrap();
    let log = assets("building.log.json");
    let file = |name: &str| dir.path().join(name).to_str().unwrap().to_string();
    for until in ["0", "1", "7"] {
        let run = |outputs: &[&str]| {
            let mut args = vec!["run", log.to_str().unwrap(), "--until", until];
            args.extend_from_slice(outputs);
            let out = sonarmap(&args);
            assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
            text(&out.stdout)
        };
        let (map_a, trace_a, svg_a) = (file("a.map"), file("a.trace"), file("a.svg"));
        let (map_b, trace_b) = (file("b.map"), file("b.trace"));
        let together = run(&[
            "--out-map",
            &map_a,
            "--out-trace",
            &trace_a,
            "--svg",
            &svg_a,
        ]);
        let alone = run(&["--out-map", &map_b, "--out-trace", &trace_b]);
        assert_eq!(together, alone, "summary, --until {until}");
        let read = |p: &str| std::fs::read(p).unwrap();
        assert_eq!(read(&map_a), read(&map_b), "map, --until {until}");
        assert_eq!(read(&trace_a), read(&trace_b), "trace, --until {until}");
        let svg = String::from_utf8(read(&svg_a)).unwrap();
        assert!(
            svg.contains(&format!("snapshot {until}")),
            "--until {until}"
        );
        if until != "0" {
            assert!(
                svg.contains("<g id=\"previous-snapshot\""),
                "--until {until}"
            );
        }
    }
}

#[test]
fn simulate_reproduces_the_assets() {
    let dir = tempfile::tempdir().unwrap();
    for name in ["blue_room", "tight_room", "building"] {
        let out_log = dir.path().join(format!("{name}.log.json"));
        let plan = assets(&format!("{name}.plan.json"));
        let out = sonarmap(&[
            "simulate",
            plan.to_str().unwrap(),
            "--out",
            out_log.to_str().unwrap(),
            "--seed",
            "1",
        ]);
        assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
        let made = std::fs::read_to_string(&out_log).unwrap();
        let shipped = std::fs::read_to_string(assets(&format!("{name}.log.json"))).unwrap();
        assert!(
            made == shipped,
            "assets/{name}.log.json is not what `simulate --seed 1` makes"
        );
    }
}

#[test]
fn simulate_axis_model_and_another_seed() {
    let dir = tempfile::tempdir().unwrap();
    let out_log = dir.path().join("axis.json");
    let plan = assets("tight_room.plan.json");
    let out = sonarmap(&[
        "simulate",
        plan.to_str().unwrap(),
        "--out",
        out_log.to_str().unwrap(),
        "--model",
        "axis",
        "--seed",
        "5",
    ]);
    assert_eq!(out.status.code(), Some(0));
    let run = sonarmap::log::load_run(&std::fs::read(&out_log).unwrap(), "axis.json").unwrap();
    assert_eq!(run.snapshots.len(), 2);
    // The axis model has no incidence limit: only the sonar looking out of the opening misses.
    let hits = run.snapshots[0]
        .ranges_m
        .iter()
        .filter(|r| r.is_some())
        .count();
    assert!(hits >= 15, "{hits} of 16");
}

#[test]
fn eval_prints_one_json_object_with_the_figures() {
    for preset in ["paper", "extended"] {
        let log = assets("tight_room.log.json");
        let out = sonarmap(&["eval", log.to_str().unwrap(), "--preset", preset]);
        assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
        let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        for key in [
            "segments",
            "true_segments",
            "spurious_fraction",
            "mean_endpoint_error",
            "mean_angle_error_deg",
            "coverage",
            "coverage_visible",
        ] {
            assert!(v.get(key).is_some(), "missing {key}: {v}");
        }
        assert_eq!(v["preset"], preset);
    }
}

#[test]
fn eval_names_the_preset_a_params_file_starts_from() {
    let dir = tempfile::tempdir().unwrap();
    let params = dir.path().join("extended.json");
    std::fs::write(&params, r#"{"preset": "extended"}"#).unwrap();
    let log = assets("tight_room.log.json");
    let args = [
        "eval",
        log.to_str().unwrap(),
        "--params",
        params.to_str().unwrap(),
    ];
    let out = sonarmap(&args);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["preset"], "extended");
}

#[test]
fn eval_align_on_a_simulated_run_finds_almost_no_turn_and_scores_no_worse() {
    // A simulated run without drift is drawn in its plan's frame: the alignment is a small
    // correction, and scoring after it keeps at least the true segments' share.
    let log = assets("building.log.json");
    let score = |extra: &[&str]| {
        let mut args = vec!["eval", log.to_str().unwrap(), "--preset", "extended"];
        args.extend_from_slice(extra);
        let out = sonarmap(&args);
        assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
        serde_json::from_slice::<serde_json::Value>(&out.stdout).unwrap()
    };
    let plain = score(&[]);
    let aligned = score(&["--align"]);
    assert!(plain.get("alignment").is_none());
    let a = &aligned["alignment"];
    assert!(a["rotation_deg"].as_f64().unwrap().abs() < 0.5, "{a}");
    assert!(a["inlier_fraction"].as_f64().unwrap() > 0.5, "{a}");
    for quarter in ["first_quarter_rotation_deg", "last_quarter_rotation_deg"] {
        assert!(a.get(quarter).is_some(), "{a}");
    }
    let spurious = |v: &serde_json::Value| v["spurious_fraction"].as_f64().unwrap();
    assert!(
        spurious(&aligned) <= spurious(&plain) + 0.1,
        "{plain} {aligned}"
    );
    check_fails(
        &["eval", log.to_str().unwrap(), "--align", "sideways"],
        &["sideways"],
    );
}

#[test]
fn eval_scores_with_a_given_tolerance_and_maps_as_without_it() {
    // Mapped with ξ = 12 %: by default its end-points are judged within 12 % of their range,
    // with --score-accuracy-pct 3 within 3 %, which fewer of them meet; the map is the same.
    let dir = tempfile::tempdir().unwrap();
    let params = dir.path().join("wide.json");
    std::fs::write(&params, r#"{"preset": "extended", "accuracy_pct": 12}"#).unwrap();
    let log = assets("building.log.json");
    let score = |extra: &[&str]| {
        let mut args = vec![
            "eval",
            log.to_str().unwrap(),
            "--params",
            params.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        let out = sonarmap(&args);
        assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
        serde_json::from_slice::<serde_json::Value>(&out.stdout).unwrap()
    };
    let own = score(&[]);
    let same = score(&["--score-accuracy-pct", "12"]);
    let strict = score(&["--score-accuracy-pct", "3"]);
    assert!(own.get("score_accuracy_pct").is_none());
    assert_eq!(strict["score_accuracy_pct"], 3.0);
    let count = |v: &serde_json::Value, key: &str| v[key].as_u64().unwrap();
    for key in ["segments", "true_segments"] {
        assert_eq!(count(&own, key), count(&same, key), "{key}");
    }
    assert_eq!(count(&own, "segments"), count(&strict, "segments"));
    assert!(
        count(&strict, "true_segments") < count(&own, "true_segments"),
        "{own} {strict}"
    );
    check_fails(
        &["eval", log.to_str().unwrap(), "--score-accuracy-pct", "0"],
        &["--score-accuracy-pct", "percentage"],
    );
}

#[test]
fn eval_suite_scores_with_a_given_tolerance_and_maps_as_without_it() {
    // The suite's scenes mapped with ξ = 12 %: every scene's map is the same whatever the
    // tolerance it is judged with; held to 3 % fewer segments are true, and the summary says
    // which tolerance judged them.
    let dir = tempfile::tempdir().unwrap();
    let params = dir.path().join("wide.json");
    std::fs::write(&params, r#"{"preset": "extended", "accuracy_pct": 12}"#).unwrap();
    let suite = |extra: &[&str]| {
        let mut args = vec!["eval", "--suite", "2", "--params", params.to_str().unwrap()];
        args.extend_from_slice(extra);
        let out = sonarmap(&args);
        assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
        text(&out.stdout)
            .lines()
            .map(|line| serde_json::from_str::<serde_json::Value>(line).unwrap())
            .collect::<Vec<_>>()
    };
    let own = suite(&[]);
    let same = suite(&["--score-accuracy-pct", "12"]);
    let strict = suite(&["--score-accuracy-pct", "3"]);
    assert_eq!(own.len(), 5, "four runs and the summary");
    let count = |v: &serde_json::Value, key: &str| v[key].as_u64().unwrap();
    for ((a, b), c) in own.iter().zip(&same).zip(&strict) {
        for key in ["segments", "true_segments"] {
            assert_eq!(count(a, key), count(b, key), "{key}: {a} {b}");
        }
        assert_eq!(count(a, "segments"), count(c, "segments"), "{a} {c}");
        assert!(
            count(c, "true_segments") <= count(a, "true_segments"),
            "{a} {c}"
        );
    }
    let (own_summary, strict_summary) = (own.last().unwrap(), strict.last().unwrap());
    assert!(own_summary.get("score_accuracy_pct").is_none());
    assert_eq!(strict_summary["score_accuracy_pct"], 3.0);
    assert!(
        count(strict_summary, "true_segments") < count(own_summary, "true_segments"),
        "{own_summary} {strict_summary}"
    );
}

#[test]
fn eval_with_a_plan_and_params_file() {
    let dir = tempfile::tempdir().unwrap();
    let params = dir.path().join("p.json");
    std::fs::write(&params, r#"{"t_gap": 30, "orientation_deg": 10}"#).unwrap();
    let log = assets("blue_room.log.json");
    let plan = assets("blue_room.plan.json");
    let out = sonarmap(&[
        "eval",
        log.to_str().unwrap(),
        "--plan",
        plan.to_str().unwrap(),
        "--params",
        params.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    std::fs::write(&params, r#"{"t_gap": -1}"#).unwrap();
    check_fails(
        &[
            "eval",
            log.to_str().unwrap(),
            "--params",
            params.to_str().unwrap(),
        ],
        &["p.json", "t_gap"],
    );
    std::fs::write(&params, r#"{"tgap": 3}"#).unwrap();
    check_fails(
        &[
            "run",
            log.to_str().unwrap(),
            "--params",
            params.to_str().unwrap(),
        ],
        &["p.json", "tgap"],
    );
}

#[test]
fn broken_inputs_exit_with_code_2_and_a_message() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.json");
    std::fs::write(&bad, "{ not json").unwrap();
    check_fails(
        &["run", bad.to_str().unwrap()],
        &["bad.json", "not JSON", "line 1"],
    );
    std::fs::write(
        &bad,
        std::fs::read_to_string(assets("blue_room.log.json"))
            .unwrap()
            .replace("\"version\": 1", "\"version\": 7"),
    )
    .unwrap();
    check_fails(&["eval", bad.to_str().unwrap()], &["bad.json", "version"]);
    check_fails(
        &["run", dir.path().join("missing.json").to_str().unwrap()],
        &["cannot read", "missing.json"],
    );
    check_fails(
        &[
            "simulate",
            bad.to_str().unwrap(),
            "--out",
            dir.path().join("o.json").to_str().unwrap(),
        ],
        &["bad.json", "missing field `path`"],
    );
    check_fails(&["run"], &["LOG"]);
    check_fails(&["run", "x.json", "--preset", "fancy"], &["fancy"]);
    check_fails(
        &["simulate", "p.json", "--out", "o.json", "--model", "ray"],
        &["ray"],
    );
    // A log without a floor plan cannot be evaluated without --plan.
    let no_plan = dir.path().join("noplan.json");
    std::fs::write(&no_plan, r#"{"format": "sonarmap-log", "version": 1, "units": "in", "robot": {"radius": 9, "sonars": {"ring": {"count": 1, "spacing_deg": 0}}}, "snapshots": [{"pose": {"x": 0, "y": 0, "heading_deg": 0}, "ranges": [10]}]}"#).unwrap();
    check_fails(
        &["eval", no_plan.to_str().unwrap()],
        &["no floor_plan", "--plan"],
    );
}

#[test]
fn no_subcommand_opens_the_inspector_or_says_why_not() {
    // Without a display the window cannot open: a clear error and exit code 2, no panic.
    let out = Command::new(env!("CARGO_BIN_EXE_sonarmap"))
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .env_remove("WAYLAND_SOCKET")
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = text(&out.stderr);
    assert!(
        err.contains("cannot open the window") && !err.contains("panicked"),
        "{err}"
    );
    let help = sonarmap(&["eval", "--help"]);
    assert_eq!(help.status.code(), Some(0));
    assert!(text(&help.stdout).contains("coverage_visible"));
}

#[test]
fn diff_reports_a_match_that_becomes_a_new_face() {
    // docs/algorithm.md §4: colinearity passes when |d| ≤ ξ/100·(D1 + (D2+D3)/2). The Blue Room's
    // upper wall moves by a few tenths of an inch between the snapshots, so shrinking ξ to
    // 0.05 % turns its match into a new face.
    let dir = tempfile::tempdir().unwrap();
    let b = dir.path().join("b.json");
    std::fs::write(&b, r#"{"accuracy_pct": 0.05}"#).unwrap();
    let log = assets("blue_room.log.json");
    let o = sonarmap(&[
        "diff",
        log.to_str().unwrap(),
        "--params-b",
        b.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["snapshots"], serde_json::json!([1]));
    let decisions = v["decisions"].as_array().unwrap();
    assert!(!decisions.is_empty());
    for d in decisions {
        assert_eq!(d["kind"], "outcome");
        assert_eq!(d["a"]["outcome"], "match");
        assert_eq!(d["b"]["outcome"], "new_face");
        assert_eq!(d["b"]["rule"], "no_candidate_passed");
    }
    assert!(v["eval_a"]["segments"].is_number() && v["eval_b"]["segments"].is_number());
    // The same parameters on both sides differ nowhere.
    let o = sonarmap(&["diff", log.to_str().unwrap()]);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["decisions"], serde_json::json!([]));
}

#[test]
fn run_sweeps_several_logs_into_out_dir_and_reports_a_bad_one() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let bad = dir.path().join("broken.json");
    std::fs::write(&bad, "{\"format\": \"sonarmap-log\", \"version\": 1").unwrap();
    let blue = assets("blue_room.log.json");
    let tight = assets("tight_room.log.json");
    let args = [
        blue.to_str().unwrap(),
        bad.to_str().unwrap(),
        tight.to_str().unwrap(),
        "--out-dir",
        out.to_str().unwrap(),
        "--trace",
    ];
    let result = sonarmap(&[&["run"], &args[..]].concat());
    assert_eq!(result.status.code(), Some(2));
    let err = text(&result.stderr);
    assert!(
        err.contains("broken.json") && err.contains("1 of 3 logs failed"),
        "{err}"
    );
    // The good logs' summaries, in the order given, each named by its log.
    let lines: Vec<String> = text(&result.stdout).lines().map(str::to_owned).collect();
    assert_eq!(lines.len(), 2, "{lines:?}");
    assert!(lines[0].starts_with(blue.to_str().unwrap()) && lines[0].contains("segments 2"));
    assert!(lines[1].starts_with(tight.to_str().unwrap()));
    for name in ["blue_room", "tight_room"] {
        for ext in ["map.json", "trace.json", "svg"] {
            let path = out.join(format!("{name}.{ext}"));
            assert!(path.is_file(), "{} missing", path.display());
        }
    }
    let names: Vec<_> = std::fs::read_dir(&out).unwrap().collect();
    assert_eq!(names.len(), 6, "no broken.* and no temporary file");
}

#[test]
fn run_refuses_two_logs_with_one_stem_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    let other = dir.path().join("blue_room.json");
    std::fs::copy(assets("blue_room.log.json"), &other).unwrap();
    let out = dir.path().join("out");
    check_fails(
        &[
            "run",
            assets("blue_room.log.json").to_str().unwrap(),
            other.to_str().unwrap(),
            "--out-dir",
            out.to_str().unwrap(),
        ],
        &["blue_room.json", "blue_room.*"],
    );
    assert!(!out.exists(), "nothing was written");
    // Single-file outputs need one log.
    check_fails(
        &[
            "run",
            assets("blue_room.log.json").to_str().unwrap(),
            assets("tight_room.log.json").to_str().unwrap(),
            "--out-map",
            dir.path().join("m.json").to_str().unwrap(),
        ],
        &["--out-dir"],
    );
}

#[test]
fn bench_over_several_logs_prints_one_json_line_each() {
    let blue = assets("blue_room.log.json");
    let tight = assets("tight_room.log.json");
    let out = sonarmap(&[
        "bench",
        blue.to_str().unwrap(),
        tight.to_str().unwrap(),
        "--repeats",
        "1",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let lines: Vec<serde_json::Value> = text(&out.stdout)
        .lines()
        .map(|l| serde_json::from_str(l).expect("one JSON object a line"))
        .collect();
    assert_eq!(lines.len(), 2);
    assert_eq!(lines[0]["log"], blue.to_str().unwrap());
    assert_eq!(lines[1]["log"], tight.to_str().unwrap());
    for l in &lines {
        assert_eq!(l["snapshots"], 2);
        assert_eq!(l["params"]["merge_duplicates"], false, "the paper preset");
        assert!(l["frame_ms_median"].as_f64().unwrap() > 0.0);
        assert!(l["frame_vertices_max"].as_u64().unwrap() > 0);
        assert!(l["first_frame_ms"].as_f64().unwrap() > 0.0);
        // Two snapshots: one checkpoint, its spacing the run.
        assert_eq!(l["checkpoints"], 1);
        assert_eq!(l["checkpoint_spacing_max"], 2);
    }
}

#[test]
fn bench_counts_the_checkpoints_apart_from_the_replays_whole_heap() {
    let tight = assets("tight_room.log.json");
    let out = sonarmap(&[
        "bench",
        tight.to_str().unwrap(),
        "--laps",
        "600",
        "--repeats",
        "1",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let l: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let bytes = |key: &str| l[key].as_u64().unwrap_or_else(|| panic!("{key}: {l}"));
    assert!(bytes("checkpoints") > 2, "{l}");
    // The checkpoints share their segments with the final map: what they alone keep alive is
    // a part of the replay's heap, and within their budget.
    assert!(bytes("checkpoint_bytes") > 0, "{l}");
    assert!(
        bytes("checkpoint_bytes") < bytes("replay_heap_bytes"),
        "{l}"
    );
    assert!(
        bytes("checkpoint_bytes") <= bytes("checkpoint_budget_bytes"),
        "{l}"
    );
    assert!(bytes("checkpoint_estimated_bytes") > 0, "{l}");
}

#[test]
fn bench_with_laps_and_every_preset_prints_one_engine_line_per_preset() {
    let blue = assets("blue_room.log.json");
    let out = sonarmap(&[
        "bench",
        blue.to_str().unwrap(),
        "--laps",
        "40",
        "--preset",
        "all",
        "--engine-only",
        "--repeats",
        "1",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let lines: Vec<serde_json::Value> = text(&out.stdout)
        .lines()
        .map(|l| serde_json::from_str(l).expect("one JSON object a line"))
        .collect();
    let presets: Vec<&str> = lines
        .iter()
        .map(|l| l["preset"].as_str().unwrap())
        .collect();
    assert_eq!(presets, ["paper", "extended"]);
    for l in &lines {
        assert_eq!(l["log"], blue.to_str().unwrap());
        assert_eq!(l["snapshots"], 40, "two snapshots repeated to 40");
        assert!(l["engine_snapshots_per_s_trace_off"].as_f64().unwrap() > 0.0);
        assert!(l["candidates_per_snapshot_last_tenth"].as_f64().unwrap() > 0.0);
        assert!(l.get("frame_ms_median").is_none(), "engine figures only");
    }
    assert_eq!(lines[0]["params"]["merge_duplicates"], false);
    assert_eq!(lines[1]["params"]["merge_duplicates"], true);
}

#[test]
fn run_svg_takes_the_view_layers_size_and_writes_a_png_beside_it() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("building.svg");
    let log = assets("building.log.json");
    let o = sonarmap(&[
        "run",
        log.to_str().unwrap(),
        "--until",
        "150",
        "--svg",
        out.to_str().unwrap(),
        "--view",
        "0,0,250,200",
        "--layers",
        "floor-plan,map,labels",
        "--size",
        "800x600",
        "--png",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    let svg = std::fs::read_to_string(&out).unwrap();
    assert!(svg.contains(r#"width="800" height="600""#));
    assert!(svg.contains("<g id=\"map\"") && svg.contains("<g id=\"labels\""));
    assert!(
        !svg.contains("<g id=\"balls\""),
        "only the layers asked for"
    );
    let png = std::fs::read(dir.path().join("building.png")).expect("the PNG is written");
    assert_eq!(&png[1..4], b"PNG");
    let width = u32::from_be_bytes([png[16], png[17], png[18], png[19]]);
    assert_eq!(width, 800);
    // A bad option names itself, and nothing is written.
    let o = sonarmap(&[
        "run",
        log.to_str().unwrap(),
        "--svg",
        dir.path().join("x.svg").to_str().unwrap(),
        "--layers",
        "map,walls",
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(text(&o.stderr).contains("walls"), "{}", text(&o.stderr));
    assert!(!dir.path().join("x.svg").exists());
}

#[test]
fn run_warns_when_min_range_discards_echoes_its_sensor_reads() {
    // A robot with four sonars whose sensor reads from 2 cm, 10 cm from every wall of a narrow
    // passage: with the Polaroid's 6 in `min_range` every echo is discarded, and `run` says
    // so, naming the parameter; with `min_range` at 2 cm it maps them and says nothing.
    use sonarmap::geometry::Pose;
    use sonarmap::run::{Run, Snapshot};
    use sonarmap::sonar::SensorSpec;
    use std::f64::consts::FRAC_PI_2;
    let dir = tempfile::tempdir().unwrap();
    let run = Run {
        name: "passage".to_string(),
        units: sonarmap::units::Units::Metres,
        robot_radius_m: Some(0.05),
        layout: super::support::layout_of([(0.0, 0.0, FRAC_PI_2), (0.0, 0.0, -FRAC_PI_2)]),
        sensor: SensorSpec {
            min_range_m: 0.02,
            ..SensorSpec::default()
        },
        floor_plan: None,
        snapshots: (0..20)
            .map(|k| Snapshot {
                t: k as f64,
                pose: Pose::new(0.02 * k as f64, 0.0, 0.0),
                ranges_m: vec![Some(0.1), Some(0.1)],
                true_pose: None,
                reading_dt_s: Vec::new(),
            })
            .collect(),
    };
    let log = dir.path().join("passage.json");
    std::fs::write(&log, sonarmap::log::save_run(&run)).unwrap();
    let near = dir.path().join("near.json");
    std::fs::write(
        &near,
        r#"{"preset": "extended", "units": "m", "min_range": 0.02}"#,
    )
    .unwrap();
    let out = sonarmap(&["run", log.to_str().unwrap(), "--preset", "extended"]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let err = text(&out.stderr);
    assert!(
        err.contains("warning: passage: 40 of 40 echoes (100 %) lay below min_range 0.152 m")
            && err.contains("reads from 0.020 m; set min_range in --params"),
        "{err}"
    );
    let out = sonarmap(&[
        "run",
        log.to_str().unwrap(),
        "--params",
        near.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    assert!(
        !text(&out.stderr).contains("min_range"),
        "{}",
        text(&out.stderr)
    );
    assert!(
        text(&out.stdout).contains("readings kept 40"),
        "{}",
        text(&out.stdout)
    );
}

#[test]
fn a_calibrated_second_pass_warns_of_min_range_once() {
    // The Pioneer crawl given the bad drift: `calibrate_first` finds it and maps the run again.
    // With `min_range` at 1.5 m most echoes are discarded (the sensor reads from 0.15 m); both
    // passes read the same readings, and `run` and `eval` say so once, not once a pass.
    use sonarmap::sim::{with_odometry, OdometryError};
    let dir = tempfile::tempdir().unwrap();
    let run = with_odometry(
        &super::support::pioneer_corridor_crawl(1),
        &OdometryError::BAD,
        1,
    );
    let log = dir.path().join("crawl.json");
    std::fs::write(&log, sonarmap::log::save_run(&run)).unwrap();
    let far = dir.path().join("far.json");
    std::fs::write(
        &far,
        r#"{"preset": "extended", "units": "m", "min_range": 1.5}"#,
    )
    .unwrap();
    let out = sonarmap(&[
        "eval",
        log.to_str().unwrap(),
        "--params",
        far.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert!(report["calibration"].is_object(), "two passes: {report}");
    let err = text(&out.stderr);
    assert_eq!(
        err.matches("lay below min_range 1.500 m").count(),
        1,
        "{err}"
    );
    let out = sonarmap(&[
        "run",
        log.to_str().unwrap(),
        "--params",
        far.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let err = text(&out.stderr);
    assert_eq!(
        err.matches("lay below min_range 1.500 m").count(),
        1,
        "{err}"
    );
}
