//! Tables of one reading a line (`src/import/firings.rs`): cut into firing cycles, each
//! reading kept at its own moment, hand-computed.

use super::support::ros2::check_err;
use sonarmap::import::{
    import_any, import_table, parse_layout, Format, ImportOptions, NamedBytes, TableForm,
};

fn ring(n: usize) -> ImportOptions {
    let json = format!(
        r#"{{"format": "sonarmap-layout", "version": 1, "units": "m",
            "robot": {{"radius": 0.2, "sonars": {{"ring": {{"count": {n}, "spacing_deg": {}}}}}}},
            "sensor": {{"max_range": 5}}}}"#,
        360.0 / n as f64
    );
    ImportOptions {
        layout: Some(parse_layout(json.as_bytes(), "ring.json").unwrap()),
        ..ImportOptions::default()
    }
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() < 1e-9
}

#[test]
fn a_firing_table_is_cut_where_a_sensor_repeats_and_each_reading_keeps_its_moment() {
    let text = "t sensor range x y heading\n\
                0.00 0 1.00 0.00 0 0\n\
                0.10 1 2.00 0.01 0 0\n\
                0.20 2 -    0.02 0 0\n\
                0.30 0 1.50 0.03 0 0\n\
                0.40 2 2.50 0.04 0 0\n";
    let i = import_any(text.as_bytes(), "f.txt", &ring(3)).unwrap();
    assert_eq!(i.format, Format::FiringTable);
    let s = &i.run.snapshots;
    assert_eq!(s.len(), 2, "sensor 0 repeats at 0.3 s");
    // Cycle 1: 0.0, 0.1, 0.2 s; its time is their mean, 0.1 s, and its pose the odometry's
    // there (x = 0.01 m); offsets -0.1, 0, +0.1 s.
    assert!(close(s[0].t, 0.1) && close(s[0].pose.x, 0.01));
    assert_eq!(s[0].ranges_m, vec![Some(1.0), Some(2.0), None]);
    for (dt, e) in s[0].reading_dt_s.iter().zip([-0.1, 0.0, 0.1]) {
        assert!(close(*dt, e), "{:?}", s[0].reading_dt_s);
    }
    // Cycle 2: 0.3 and 0.4 s, mean 0.35 s (x = 0.035 m); sensor 1 silent: no echo, offset 0.
    assert!(close(s[1].t, 0.35) && close(s[1].pose.x, 0.035));
    assert_eq!(s[1].ranges_m, vec![Some(1.5), None, Some(2.5)]);
    for (dt, e) in s[1].reading_dt_s.iter().zip([-0.05, 0.0, 0.05]) {
        assert!(close(*dt, e), "{:?}", s[1].reading_dt_s);
    }
    assert!(
        i.summary
            .warnings
            .iter()
            .any(|w| w.contains("1 readings were missing")),
        "{:?}",
        i.summary.warnings
    );
}

#[test]
fn odometry_lines_or_a_poses_file_give_the_firings_their_pose() {
    // Odometry from (0, 0, 0°) at 0 s to (1, 0, 90°) at 1 s; one cycle at 0.0 and 0.2 s.
    let firings = "0.0 0 1.0\n0.2 1 1.0\n";
    let odometry = "0.0 0.0 0.0 0\n1.0 1.0 0.0 90\n";
    let mixed = format!("0.0 0.0 0.0 0\n{firings}1.0 1.0 0.0 90\n");
    let with_poses = ImportOptions {
        poses: Some(NamedBytes {
            name: "poses.txt".into(),
            bytes: odometry.as_bytes().to_vec(),
        }),
        table: TableForm::Firings,
        ..ring(3)
    };
    for (text, options) in [(mixed.as_str(), ring(3)), (firings, with_poses)] {
        let i = import_table(text.as_bytes(), "f.txt", &options).unwrap();
        let s = &i.run.snapshots;
        assert_eq!(s.len(), 1);
        // At 0.1 s: a tenth of the way, x = 0.1 m, heading 9°.
        assert!(close(s[0].t, 0.1) && close(s[0].pose.x, 0.1), "{:?}", s[0]);
        assert!(close(s[0].pose.heading_rad.to_degrees(), 9.0));
        assert!(close(s[0].reading_dt_s[0], -0.1) && close(s[0].reading_dt_s[1], 0.1));
    }
}

#[test]
fn a_firing_table_is_refused_with_its_line_and_field() {
    let o = || ImportOptions {
        table: TableForm::Firings,
        ..ring(3)
    };
    let bad = |text: &str, expected: &[&str]| {
        check_err(import_table(text.as_bytes(), "f.txt", &o()), expected);
    };
    bad(
        "0.0 0 1.0 0 0 0\n0.1 3 1.0 0 0 0\n",
        &["f.txt", "line 2, field 2", "a whole number from 0 to 2"],
    );
    bad(
        "0.0 0 1.0 0 0 0\n0.1 1.5 1.0 0 0 0\n",
        &["line 2, field 2", "sensor index"],
    );
    bad(
        "0.0 0 1.0 0 0 0\n0.1 1 1.0 0 0\n",
        &["line 2", "5 fields", "t sensor range"],
    );
    bad(
        "0.5 0 1.0 0 0 0\n0.1 1 1.0 0 0 0\n",
        &["line 2, field 1", "earlier"],
    );
    bad("0.0 0 -1.0 0 0 0\n", &["line 1, field 3", "negative"]);
    bad(
        "0.0 0 1.0\n",
        &["f.txt", "no pose columns, no odometry lines"],
    );
    // A window beyond what a reading's offset may be.
    let o = ImportOptions {
        window_s: Some(61.0),
        ..o()
    };
    check_err(
        import_table(b"0.0 0 1.0 0 0 0\n", "f.txt", &o),
        &["--window", "at most 60 s"],
    );
}

#[test]
fn a_table_is_read_as_firings_when_its_header_or_field_counts_say_so() {
    // Two sensors: a ring line `t r0 r1` has three fields, as a firing does; the header
    // names the sensor column.
    let ring_text = "0.0 1.0 2.0\n0.1 1.0 2.0\n";
    let fixed = |o: ImportOptions| ImportOptions {
        fixed_pose: Some(sonarmap::geometry::Pose::new(0.0, 0.0, 0.0)),
        ..o
    };
    let i = import_table(ring_text.as_bytes(), "r.txt", &fixed(ring(2))).unwrap();
    assert_eq!((i.format, i.run.snapshots.len()), (Format::Table, 2));
    let with_header = format!("t sensor range\n{ring_text}");
    let i = import_table(with_header.as_bytes(), "r.txt", &fixed(ring(2))).unwrap();
    assert_eq!(i.format, Format::FiringTable);
    // Read as firings of sensor 1 (1.0 m) at 0.0 and 0.1 s: the sensor repeats, two cycles.
    assert_eq!(i.run.snapshots.len(), 2);
    assert_eq!(i.run.snapshots[0].ranges_m, vec![None, Some(2.0)]);
    // `--table ring` overrides the header.
    let o = ImportOptions {
        table: TableForm::Ring,
        ..fixed(ring(2))
    };
    let i = import_table(with_header.as_bytes(), "r.txt", &o).unwrap();
    assert_eq!(i.format, Format::Table);
    // Sixteen sensors: three-field lines are no ring form.
    let i = import_table(b"0.0 4 1.0\n0.1 5 1.0\n", "r.txt", &fixed(ring(16))).unwrap();
    assert_eq!(i.format, Format::FiringTable);
}
