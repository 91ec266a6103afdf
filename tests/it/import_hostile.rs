//! Hostile recordings (issue 18): every input is refused with its file, place and what was
//! expected, or imported as a run the log loader takes back and the mapper maps with finite
//! numbers. One test (or more) per class: lengths the file cannot hold, memory that must stay
//! a small multiple of the input, files cut short, values no robot produces in every importer
//! and in layouts, control characters echoed from the file, and the messages that misled.

use super::peak::peak_bytes;
use super::support::ros2::{check_err, nomad_options, odom_msg, range_msg, tf_msg, Cdr, MOUNTS};
use sonarmap::import::{
    import_any, import_mcap, import_player, import_table, parse_layout, ImportError, ImportOptions,
    Imported, NamedBytes,
};
use sonarmap::log::{load_run, save_run};
use sonarmap::mapping::{Mapper, Params, Preset};

// ------------------------------------------------------------------ the contract

/// The rule of issue 18 for one import: a refusal names the file and quotes no control
/// character; an import is a run whose log the loader takes back and that the mapper maps
/// with finite numbers only.
pub(super) fn check_contract(result: &Result<Imported, ImportError>, file: &str) {
    match result {
        Err(e) => {
            let m = e.to_string();
            assert!(
                m.contains(file) || matches!(e, ImportError::BadOption { .. }),
                "the error does not name {file}: {m}"
            );
            assert!(
                !m.chars().any(char::is_control),
                "the error echoes a control character: {m:?}"
            );
        }
        Ok(i) => check_run(&i.run),
    }
}

/// An imported run: sane values, a log the loader takes back, a map of finite numbers.
pub(super) fn check_run(run: &sonarmap::run::Run) {
    let sane = |v: f64| v.is_finite() && v.abs() <= 10_000.0;
    for m in &run.layout.mounts {
        assert!(
            sane(m.x_m) && sane(m.y_m) && m.heading_rad.is_finite(),
            "{m:?}"
        );
    }
    for w in run.snapshots.windows(2) {
        assert!(
            w[0].t <= w[1].t,
            "time goes back: {} then {}",
            w[0].t,
            w[1].t
        );
    }
    for s in &run.snapshots {
        assert!(s.t.is_finite() && s.t.abs() <= 1e10, "t {}", s.t);
        assert!(
            s.reading_dt_s.is_empty() || s.reading_dt_s.len() == run.layout.len(),
            "{} offsets for {} sensors",
            s.reading_dt_s.len(),
            run.layout.len()
        );
        assert!(sane(s.pose.x) && sane(s.pose.y) && s.pose.heading_rad.is_finite());
        assert_eq!(s.ranges_m.len(), run.layout.len());
        for r in s.ranges_m.iter().flatten() {
            assert!(r.is_finite() && *r >= 0.0 && *r <= 10_000.0, "range {r}");
        }
    }
    let text = save_run(run);
    let back = load_run(text.as_bytes(), "written").unwrap_or_else(|e| {
        panic!(
            "the log loader refuses what convert wrote: {e}\n{}",
            &text[..text.len().min(2000)]
        )
    });
    assert_eq!(back.snapshots.len(), run.snapshots.len());
    let mut mapper = Mapper::new(
        Params::preset(Preset::Paper),
        back.layout.clone(),
        back.sensor,
    )
    .with_trace(false);
    for s in &back.snapshots {
        mapper.step(s);
    }
    for seg in &mapper.map().segments {
        for e in [&seg.a, &seg.b] {
            assert!(
                e.point.x.is_finite() && e.point.y.is_finite() && e.range_m.is_finite(),
                "segment {:?}",
                seg.id
            );
        }
        for p in seg.points.iter() {
            assert!(p.point.x.is_finite() && p.point.y.is_finite() && p.range_m.is_finite());
        }
    }
}

/// Expects a refusal naming the file and containing every part, and no raw control character.
fn refused(result: Result<Imported, ImportError>, file: &str, parts: &[&str]) -> String {
    check_contract(&result, file);
    let Err(e) = result else {
        panic!("expected a refusal with {parts:?}, got an import")
    };
    let m = e.to_string();
    for p in parts {
        assert!(m.contains(p), "the error lacks {p:?}: {m}");
    }
    m
}

// ------------------------------------------------------------------ MCAP by hand

/// An MCAP record: opcode, little-endian u64 length, body.
pub(super) fn record(opcode: u8, body: &[u8]) -> Vec<u8> {
    let mut r = vec![opcode];
    r.extend_from_slice(&(body.len() as u64).to_le_bytes());
    r.extend_from_slice(body);
    r
}

/// An MCAP string: u32 length, bytes.
pub(super) fn mstr(s: &[u8]) -> Vec<u8> {
    let mut b = (s.len() as u32).to_le_bytes().to_vec();
    b.extend_from_slice(s);
    b
}

pub(super) fn header_record() -> Vec<u8> {
    let mut b = mstr(b"ros2");
    b.extend(mstr(b"sonarmap tests"));
    record(0x01, &b)
}

pub(super) fn schema_record(id: u16, name: &str) -> Vec<u8> {
    let mut b = id.to_le_bytes().to_vec();
    b.extend(mstr(name.as_bytes()));
    b.extend(mstr(b"ros2msg"));
    b.extend(0u32.to_le_bytes());
    record(0x03, &b)
}

pub(super) fn channel_record(id: u16, schema: u16, topic: &[u8]) -> Vec<u8> {
    let mut b = id.to_le_bytes().to_vec();
    b.extend(schema.to_le_bytes());
    b.extend(mstr(topic));
    b.extend(mstr(b"cdr"));
    b.extend(0u32.to_le_bytes());
    record(0x04, &b)
}

pub(super) fn message_record(channel: u16, seq: u32, t: f64, data: &[u8]) -> Vec<u8> {
    let ns = (t * 1e9) as u64;
    let mut b = channel.to_le_bytes().to_vec();
    b.extend(seq.to_le_bytes());
    b.extend(ns.to_le_bytes());
    b.extend(ns.to_le_bytes());
    b.extend_from_slice(data);
    record(0x05, &b)
}

/// An uncompressed chunk of `records` (CRC 0: not checked).
pub(super) fn chunk_record(records: &[u8]) -> Vec<u8> {
    let mut b = 0u64.to_le_bytes().to_vec();
    b.extend(u64::MAX.to_le_bytes());
    b.extend((records.len() as u64).to_le_bytes());
    b.extend(0u32.to_le_bytes());
    b.extend(mstr(b""));
    b.extend((records.len() as u64).to_le_bytes());
    b.extend_from_slice(records);
    record(0x06, &b)
}

/// The end of a file: Data End, Footer, magic.
pub(super) fn mcap_end() -> Vec<u8> {
    let mut b = record(0x0F, &0u32.to_le_bytes());
    let mut footer = vec![0u8; 16];
    footer.extend(0u32.to_le_bytes());
    b.extend(record(0x02, &footer));
    b.extend_from_slice(MAGIC);
    b
}

pub(super) const MAGIC: &[u8] = b"\x89MCAP0\r\n";

/// The schemas and channels of a sonar recording: Range on channels 1..=4 (`/sonar_k`),
/// Odometry on 10, /tf_static on 11.
pub(super) fn mcap_start(topic: &[u8]) -> Vec<u8> {
    let mut b = MAGIC.to_vec();
    b.extend(header_record());
    b.extend(schema_record(1, "sensor_msgs/msg/Range"));
    b.extend(schema_record(2, "nav_msgs/msg/Odometry"));
    b.extend(schema_record(3, "tf2_msgs/msg/TFMessage"));
    for k in 0..4u16 {
        let mut t = topic.to_vec();
        t.extend_from_slice(format!("{k}").as_bytes());
        b.extend(channel_record(1 + k, 1, &t));
    }
    b.extend(channel_record(10, 2, b"/odom"));
    b.extend(channel_record(11, 3, b"/tf_static"));
    b
}

/// A whole recording: /tf_static, odometry at 10 Hz, `cycles` firing cycles of 4 sonars.
pub(super) fn mcap_run(cycles: usize) -> Vec<u8> {
    let mut b = mcap_start(b"/sonar_");
    b.extend(message_record(11, 0, 10.0, &tf_msg(&MOUNTS)));
    let end = 10.0 + 0.25 * cycles as f64 + 0.2;
    let mut i = 0;
    while 10.0 + 0.1 * i as f64 <= end {
        let t = 10.0 + 0.1 * i as f64;
        b.extend(message_record(
            10,
            i,
            t,
            &odom_msg(t, 0.1 * i as f64, 0.0, 0.05 * i as f64),
        ));
        i += 1;
    }
    for cycle in 0..cycles {
        for k in 0..4u16 {
            let t = 10.1 + 0.25 * cycle as f64 + 0.02 * k as f64;
            let data = range_msg(true, t, &format!("sonar_{k}"), 1.0 + 0.1 * k as f32);
            b.extend(message_record(1 + k, cycle as u32, t, &data));
        }
    }
    b.extend(mcap_end());
    b
}

#[test]
fn hand_written_mcap_imports() {
    let bytes = mcap_run(3);
    let i = import_mcap(&bytes, "hand.mcap", &ImportOptions::default()).unwrap();
    assert_eq!(i.run.snapshots.len(), 3);
    check_run(&i.run);
}

// ------------------------------------------------------------------ lengths the file cannot hold

#[test]
fn the_17_byte_mcap_with_a_length_near_u64_max_is_refused_with_its_offset() {
    // The magic, one opcode byte, eight 0xFF bytes: the mcap crate 0.26 panics on it.
    for opcode in [0x01u8, 0x02, 0x03, 0x04, 0x05, 0x06, 0x09, 0x0F, 0x42, 0xFF] {
        let mut bytes = MAGIC.to_vec();
        bytes.push(opcode);
        bytes.extend_from_slice(&[0xFF; 8]);
        assert_eq!(bytes.len(), 17);
        let m = refused(
            import_any(&bytes, "tiny.mcap", &ImportOptions::default()),
            "tiny.mcap",
            &["at byte 8", "18446744073709551615 bytes", "expected"],
        );
        assert!(m.starts_with("tiny.mcap: MCAP "), "{m}");
    }
    // Near u64::MAX but not all ones, and one byte too many.
    for len in [u64::MAX - 8, u64::MAX - 9, 1 << 63, 1] {
        let mut bytes = MAGIC.to_vec();
        bytes.push(0x05);
        bytes.extend_from_slice(&len.to_le_bytes());
        refused(
            import_mcap(&bytes, "tiny.mcap", &ImportOptions::default()),
            "tiny.mcap",
            &["at byte 8"],
        );
    }
}

#[test]
fn a_record_inside_an_uncompressed_chunk_with_a_huge_length_is_refused() {
    let mut inner = message_record(1, 0, 10.0, &range_msg(true, 10.0, "sonar_0", 1.0));
    inner[1..9].copy_from_slice(&u64::MAX.to_le_bytes());
    let mut bytes = mcap_start(b"/sonar_");
    let at = bytes.len();
    bytes.extend(chunk_record(&inner));
    bytes.extend(mcap_end());
    refused(
        import_mcap(&bytes, "chunk.mcap", &ImportOptions::default()),
        "chunk.mcap",
        &["Message record", "in a chunk", "18446744073709551615 bytes"],
    );
    // The chunk's own records length beyond the record.
    let mut bytes = mcap_start(b"/sonar_");
    let mut chunk = chunk_record(&message_record(1, 0, 10.0, &[0, 1, 0, 0]));
    let records_len_at = 9 + 8 + 8 + 8 + 4 + 4;
    chunk[records_len_at..records_len_at + 8].copy_from_slice(&(u64::MAX - 3).to_le_bytes());
    bytes.extend(chunk);
    bytes.extend(mcap_end());
    refused(
        import_mcap(&bytes, "chunk.mcap", &ImportOptions::default()),
        "chunk.mcap",
        &[&format!("Chunk record at byte {at}"), "field records"],
    );
}

#[test]
fn an_attachment_that_ends_before_its_crc_is_refused() {
    let mut body = vec![0u8; 16];
    body.extend(mstr(b"notes.txt"));
    body.extend(mstr(b"text/plain"));
    body.extend(5u64.to_le_bytes());
    body.extend_from_slice(b"hello");
    // No CRC.
    let mut bytes = mcap_start(b"/sonar_");
    let at = bytes.len();
    bytes.extend(record(0x09, &body));
    bytes.extend(mcap_end());
    refused(
        import_mcap(&bytes, "attach.mcap", &ImportOptions::default()),
        "attach.mcap",
        &[&format!("Attachment record at byte {at}, field crc")],
    );
}

#[test]
fn strings_in_schema_and_channel_records_longer_than_the_record_are_refused() {
    let mut bytes = MAGIC.to_vec();
    bytes.extend(header_record());
    let mut channel = channel_record(1, 1, b"/sonar_0");
    // The topic's u32 length (after id and schema id).
    channel[13..17].copy_from_slice(&u32::MAX.to_le_bytes());
    bytes.extend(channel);
    bytes.extend(mcap_end());
    refused(
        import_mcap(&bytes, "chan.mcap", &ImportOptions::default()),
        "chan.mcap",
        &["Channel record", "field topic", "4294967295 bytes"],
    );
}

// ------------------------------------------------------------------ memory

#[test]
fn a_megabyte_topic_name_on_2500_messages_takes_memory_in_proportion_to_the_file() {
    // Issue 18: 1.17 MB with a 1,000,000-byte topic and 2,500 Range messages took 5.2 GiB.
    let topic = vec![b'a'; 1_000_000];
    let mut bytes = MAGIC.to_vec();
    bytes.extend(header_record());
    bytes.extend(schema_record(1, "sensor_msgs/msg/Range"));
    bytes.extend(channel_record(1, 1, &topic));
    for i in 0..2500u32 {
        let t = 10.0 + 0.01 * i as f64;
        bytes.extend(message_record(1, i, t, &range_msg(true, t, "", 1.0)));
    }
    bytes.extend(mcap_end());
    assert!(bytes.len() > 1_100_000 && bytes.len() < 1_300_000);
    let (result, peak) =
        peak_bytes(|| import_mcap(&bytes, "topic.mcap", &ImportOptions::default()));
    // No /tf_static and no layout: refused, naming --layout; the topic is quoted short.
    let m = refused(result, "topic.mcap", &["--layout"]);
    assert!(m.len() < 2000, "{} bytes of message", m.len());
    assert!(
        peak <= 3 * bytes.len(),
        "peak {peak} bytes for a {} byte file",
        bytes.len()
    );
    // With a layout that takes the one topic as its one sensor, and a fixed pose: imported.
    let layout = parse_layout(
        br#"{"format": "sonarmap-layout", "version": 1, "units": "m",
             "robot": {"sonars": [{"x": 0.1, "y": 0, "heading_deg": 0}]},
             "sensor": {"max_range": 5}}"#,
        "one.layout.json",
    )
    .unwrap();
    let options = ImportOptions {
        layout: Some(layout),
        fixed_pose: Some(sonarmap::geometry::Pose::new(1.0, 2.0, 0.0)),
        ..ImportOptions::default()
    };
    let (result, peak) = peak_bytes(|| import_mcap(&bytes, "topic.mcap", &options));
    let i = result.unwrap();
    assert_eq!(i.run.snapshots.len(), 2500);
    check_run(&i.run);
    assert!(peak <= 3 * bytes.len(), "peak {peak} bytes");
}

/// A Player 2 log of `n` sonar lines (16 ranges) with odometry between them.
fn player_log(n: usize) -> String {
    let mut s = String::from("0.000 16777343 6665 sonar 00 4 1 16");
    for k in 0..16 {
        let a = k as f64 * std::f64::consts::TAU / 16.0;
        s += &format!(" {:.3} {:.3} {a:.4}", 0.2 * a.cos(), 0.2 * a.sin());
    }
    s.push('\n');
    for i in 0..n {
        let t = 0.1 * i as f64;
        s += &format!(
            "{t:.3} 16777343 6665 position2d 00 1 1 {:.3} 0.000 0.000 0.1 0 0 0\n",
            0.01 * i as f64
        );
        s += &format!("{t:.3} 16777343 6665 sonar 00 1 1 16");
        for k in 0..16 {
            s += &format!(" {:.4}", 1.0 + 0.01 * ((i + k) % 50) as f64);
        }
        s.push('\n');
    }
    s
}

#[test]
fn a_player_log_imports_in_memory_in_proportion_to_the_file() {
    let log = player_log(20_000);
    let (result, peak) =
        peak_bytes(|| import_player(log.as_bytes(), "big.log", &ImportOptions::default()));
    let i = result.unwrap();
    assert_eq!(i.run.snapshots.len(), 20_000);
    // The run itself holds 16 bytes per reading for about 7 bytes of text: under 3x.
    assert!(
        peak <= 3 * log.len(),
        "peak {peak} bytes for {} bytes",
        log.len()
    );
}

#[test]
fn one_character_fields_are_refused_at_line_2_without_reading_the_rest() {
    // Issue 18: 150 MB of one-character fields reached 1.3 GiB before the line-2 error.
    // Detection looks at the first 64 KiB only; the importer reads one line at a time.
    let mut text = String::from("0.0 1 6665 sonar 00 1 1 1 2.0\n");
    let filler = "x ".repeat(1000) + "\n";
    while text.len() < 8_000_000 {
        text += &filler;
    }
    let (result, peak) =
        peak_bytes(|| import_any(text.as_bytes(), "fields.log", &ImportOptions::default()));
    refused(result, "fields.log", &["line 2"]);
    assert!(
        peak < 1_000_000,
        "peak {peak} bytes before the line-2 error"
    );
}

// ------------------------------------------------------------------ files cut short

#[test]
fn a_player_log_cut_in_its_last_number_is_refused() {
    let whole = "0.0 1 6665 sonar 00 4 1 2 0.1 0 0 -0.1 0 3.14\n\
                 0.0 1 6665 position2d 00 1 1 0 0 0 0 0 0 0\n\
                 0.1 1 6665 sonar 00 1 1 2 1.25 6.4770\n";
    let ok = import_player(whole.as_bytes(), "cut.log", &ImportOptions::default()).unwrap();
    assert_eq!(ok.run.snapshots[0].ranges_m, vec![Some(1.25), None]);
    let cut = &whole[..whole.len() - 4]; // "... 1.25 6.4"
    assert!(cut.ends_with("6.4"));
    refused(
        import_player(cut.as_bytes(), "cut.log", &ImportOptions::default()),
        "cut.log",
        &["line 3", "without a newline", "\"6.4\"", "cut short"],
    );
    // The same through content detection.
    refused(
        import_any(cut.as_bytes(), "cut.log", &ImportOptions::default()),
        "cut.log",
        &["line 3", "without a newline"],
    );
    // A comment or blank text after the last newline is not a cut line.
    let trailing = format!("{whole}# end");
    assert!(import_player(trailing.as_bytes(), "c.log", &ImportOptions::default()).is_ok());
}

#[test]
fn a_table_cut_in_its_last_number_is_refused() {
    let mut table = String::from("t x y heading");
    for k in 0..16 {
        table += &format!(" r{k}");
    }
    table.push('\n');
    for i in 0..3 {
        table += &format!("{i} 10 20 0");
        for _ in 0..16 {
            table += " 50.25";
        }
        table.push('\n');
    }
    assert!(import_table(table.as_bytes(), "t.csv", &nomad_options()).is_ok());
    let cut = &table[..table.len() - 3];
    refused(
        import_table(cut.as_bytes(), "t.csv", &nomad_options()),
        "t.csv",
        &["line 4", "without a newline"],
    );
}

// ------------------------------------------------------------------ values no robot produces

const PLAYER_HEAD: &str = "0.0 1 6665 sonar 00 4 1 2 0.1 0 0 -0.1 0 3.14\n";

fn player_with(line: &str) -> String {
    format!("{PLAYER_HEAD}0.0 1 6665 position2d 00 1 1 0 0 0 0 0 0 0\n{line}\n")
}

#[test]
fn player_absurd_values_are_refused_with_line_and_field() {
    let o = ImportOptions::default();
    let cases: &[(&str, &[&str])] = &[
        // Geometry yaw 1e308 was written as null.
        (
            "0.0 1 6665 sonar 00 4 1 2 0.1 0 1e308 -0.1 0 3.14",
            &["line 3, field 11", "1e308", "transducer yaw"],
        ),
        (
            "0.0 1 6665 sonar 00 4 1 2 1e300 0 0 -0.1 0 3.14",
            &["line 3, field 9", "beyond ±10000 m"],
        ),
        (
            "0.1 1 6665 position2d 00 1 1 1e300 0 0 0 0 0 0",
            &["line 3, field 8", "px"],
        ),
        (
            "0.1 1 6665 position2d 00 1 1 0 -2e4 0 0 0 0 0",
            &["line 3, field 9", "py"],
        ),
        (
            "0.1 1 6665 position2d 00 1 1 0 0 1e308 0 0 0 0",
            &["line 3, field 10", "pa"],
        ),
        (
            "1e300 1 6665 sonar 00 1 1 2 1 1",
            &["line 3, field 1", "the time"],
        ),
        (
            "0.1 1 6665 sonar 00 1 1 2 1 nan",
            &["line 3, field 10", "finite"],
        ),
        (
            "0.1 1 6665 sonar 00 1 1 2 1 inf",
            &["line 3, field 10", "finite"],
        ),
        (
            "0.1 1 6665 sonar 00 1 1 2 1 1e308",
            &["line 3, field 10", "range"],
        ),
        (
            "0.1 1 6665 sonar 00 1 1 2 1 -0.5",
            &["line 3, field 10", "negative"],
        ),
    ];
    for (line, parts) in cases {
        refused(
            import_player(player_with(line).as_bytes(), "p.log", &o),
            "p.log",
            parts,
        );
    }
    // Player 1.x lines too.
    let v1 = "0.0 1 6665 sonar 00 0.0 2 0.1 0 1e308 -0.1 0 3.14 2 1 1\n\
              0.0 1 6665 position 00 0.0 0 0 0 0 0 0 0\n";
    refused(
        import_player(v1.as_bytes(), "p1.log", &o),
        "p1.log",
        &["line 1, field 10"],
    );
}

#[test]
fn negative_window_is_refused_for_player_logs_too() {
    let o = ImportOptions {
        window_s: Some(-1.0),
        ..ImportOptions::default()
    };
    let text = player_with("0.1 1 6665 sonar 00 1 1 2 1 1");
    let e = import_player(text.as_bytes(), "p.log", &o).unwrap_err();
    assert!(e.to_string().contains("--window"), "{e}");
    let e = import_any(text.as_bytes(), "p.log", &o).unwrap_err();
    assert!(e.to_string().contains("--window"), "{e}");
    for bad in [f64::NAN, f64::INFINITY, 1e300, 60.5] {
        let o = ImportOptions {
            window_s: Some(bad),
            ..ImportOptions::default()
        };
        assert!(import_player(text.as_bytes(), "p.log", &o).is_err());
    }
    let o = ImportOptions {
        fixed_pose: Some(sonarmap::geometry::Pose::new(1e300, 0.0, 0.0)),
        ..ImportOptions::default()
    };
    let e = import_player(text.as_bytes(), "p.log", &o).unwrap_err();
    assert!(e.to_string().contains("--fixed-pose"), "{e}");
}

fn nomad_row(t: &str, x: &str, y: &str, h: &str, r: &str) -> String {
    let mut row = format!("{t},{x},{y},{h}");
    for _ in 0..16 {
        row += &format!(",{r}");
    }
    row + "\n"
}

#[test]
fn table_absurd_values_are_refused_with_line_and_field() {
    let o = nomad_options();
    let cases: &[(String, &[&str])] = &[
        (
            nomad_row("1e300", "0", "0", "0", "50"),
            &["line 2, field 1"],
        ),
        (
            nomad_row("1", "1e300", "0", "0", "50"),
            &["line 2, field 2", "in"],
        ),
        (nomad_row("1", "0", "-1e8", "0", "50"), &["line 2, field 3"]),
        (
            nomad_row("1", "0", "0", "1e308", "50"),
            &["line 2, field 4", "heading"],
        ),
        (
            nomad_row("1", "0", "0", "nan", "50"),
            &["line 2, field 4", "finite"],
        ),
        (nomad_row("1", "0", "0", "0", "1e308"), &["line 2, field 5"]),
        (
            nomad_row("1", "0", "0", "0", "-3"),
            &["line 2, field 5", "negative"],
        ),
    ];
    for (row, parts) in cases {
        let text = nomad_row("0", "0", "0", "0", "50") + row;
        refused(import_table(text.as_bytes(), "t.csv", &o), "t.csv", parts);
    }
    // In the poses file.
    let mut ranges = String::new();
    for t in 0..3 {
        ranges += &format!("{t}");
        for _ in 0..16 {
            ranges += " 50";
        }
        ranges.push('\n');
    }
    let o = ImportOptions {
        poses: Some(NamedBytes {
            name: "p.csv".into(),
            bytes: b"0 0 0 0\n1 1e300 0 0\n".to_vec(),
        }),
        ..nomad_options()
    };
    refused(
        import_table(ranges.as_bytes(), "r.csv", &o),
        "p.csv",
        &["p.csv: line 2, field 2"],
    );
}

/// A Range message with every field given.
fn range_fields(t: f64, frame: &str, fov: f32, min: f32, max: f32, range: f32) -> Vec<u8> {
    let mut c = Cdr::new(true);
    c.header(t, frame);
    c.u8(0);
    for v in [fov, min, max, range] {
        c.f32(v);
    }
    c.b
}

/// A recording with one Range message of the given fields among good ones.
fn mcap_with_range(fov: f32, min: f32, max: f32, range: f32) -> Vec<u8> {
    let mut b = mcap_start(b"/sonar_");
    b.extend(message_record(11, 0, 10.0, &tf_msg(&MOUNTS)));
    for i in 0..5 {
        let t = 10.0 + 0.1 * i as f64;
        b.extend(message_record(10, i, t, &odom_msg(t, 0.0, 0.0, 0.0)));
    }
    for k in 0..4u16 {
        let t = 10.1 + 0.02 * k as f64;
        let data = if k == 2 {
            range_fields(t, "sonar_2", fov, min, max, range)
        } else {
            range_msg(true, t, &format!("sonar_{k}"), 1.0)
        };
        b.extend(message_record(1 + k, 0, t, &data));
    }
    b.extend(mcap_end());
    b
}

#[test]
fn mcap_range_fields_no_sonar_produces_are_refused_with_message_and_field() {
    let o = ImportOptions::default();
    // The good message imports.
    let i = import_mcap(&mcap_with_range(0.4, 0.15, 5.0, 1.0), "r.mcap", &o).unwrap();
    check_run(&i.run);
    // REP 117: ±inf and NaN are no echo, a finite reading outside [min, max] too.
    for r in [f32::INFINITY, f32::NEG_INFINITY, f32::NAN, 7.0, 0.1] {
        let i = import_mcap(&mcap_with_range(0.4, 0.15, 5.0, r), "r.mcap", &o).unwrap();
        assert_eq!(i.run.snapshots[0].ranges_m[2], None, "{r}");
        check_run(&i.run);
    }
    type Fields = (f32, f32, f32, f32);
    let cases: &[(Fields, &[&str])] = &[
        ((-0.4, 0.15, 5.0, 1.0), &["field field_of_view"]),
        ((f32::NAN, 0.15, 5.0, 1.0), &["field field_of_view"]),
        ((7.0, 0.15, 5.0, 1.0), &["field field_of_view"]),
        ((0.4, -0.15, 5.0, 1.0), &["field min_range", "negative"]),
        ((0.4, -1.0, -0.5, -0.7), &["field min_range", "negative"]),
        ((0.4, 0.15, -5.0, 1.0), &["field max_range", "negative"]),
        (
            (0.4, 0.15, f32::INFINITY, 1.0),
            &["field max_range", "finite"],
        ),
        ((0.4, 0.15, 1e30, 1.0), &["field max_range", "10000"]),
        (
            (0.4, 5.0, 5.0, 1.0),
            &["field min_range", "min_range < max_range"],
        ),
        ((0.4, 6.0, 5.0, 1.0), &["field min_range"]),
        ((0.4, 0.15, 5.0, -1.0), &["field range", "negative"]),
    ];
    for ((fov, min, max, range), parts) in cases {
        let bytes = mcap_with_range(*fov, *min, *max, *range);
        let m = refused(import_mcap(&bytes, "r.mcap", &o), "r.mcap", parts);
        assert!(m.contains("topic /sonar_2"), "{m}");
    }
}

/// A TFMessage with one transform of the given translation and quaternion.
fn tf_fields(xyz: [f64; 3], q: [f64; 4]) -> Vec<u8> {
    let mut c = Cdr::new(true);
    c.u32(4);
    for (k, &(x, y, yaw)) in MOUNTS.iter().enumerate() {
        c.header(0.0, "base_link");
        c.string(&format!("sonar_{k}"));
        if k == 1 {
            for v in xyz {
                c.f64(v);
            }
            for v in q {
                c.f64(v);
            }
        } else {
            for v in [x, y, 0.1] {
                c.f64(v);
            }
            c.quaternion_yaw(yaw);
        }
    }
    c.b
}

fn mcap_with_tf_and_odom(tf: &[u8], odom: &[(f64, f64, [f64; 4])]) -> Vec<u8> {
    let mut b = mcap_start(b"/sonar_");
    b.extend(message_record(11, 0, 10.0, tf));
    for (i, (x, y, q)) in odom.iter().enumerate() {
        let t = 10.0 + 0.1 * i as f64;
        let mut c = Cdr::new(true);
        c.header(t, "odom");
        c.string("base_link");
        for v in [*x, *y, 0.0] {
            c.f64(v);
        }
        for v in q {
            c.f64(*v);
        }
        for _ in 0..(36 + 6 + 36) {
            c.f64(0.0);
        }
        b.extend(message_record(10, i as u32, t, &c.b));
    }
    for k in 0..4u16 {
        let t = 10.1 + 0.02 * k as f64;
        b.extend(message_record(
            1 + k,
            0,
            t,
            &range_msg(true, t, &format!("sonar_{k}"), 1.0),
        ));
    }
    b.extend(mcap_end());
    b
}

const UNIT_Q: [f64; 4] = [0.0, 0.0, 0.0, 1.0];

#[test]
fn mcap_non_finite_and_absurd_poses_and_mounts_are_refused() {
    let o = ImportOptions::default();
    let good_odom: Vec<(f64, f64, [f64; 4])> = (0..5).map(|_| (0.0, 0.0, UNIT_Q)).collect();
    let good_tf = tf_fields(
        [0.0, 0.2, 0.1],
        [
            0.0,
            0.0,
            std::f64::consts::FRAC_1_SQRT_2,
            std::f64::consts::FRAC_1_SQRT_2,
        ],
    );
    let i = import_mcap(&mcap_with_tf_and_odom(&good_tf, &good_odom), "m.mcap", &o).unwrap();
    check_run(&i.run);
    // /tf_static: NaN or infinite translations and quaternions were written as null.
    for (xyz, q, field) in [
        (
            [f64::NAN, 0.2, 0.1],
            UNIT_Q,
            "transforms[1].transform.translation.x",
        ),
        (
            [0.0, f64::INFINITY, 0.1],
            UNIT_Q,
            "transforms[1].transform.translation.y",
        ),
        (
            [0.0, 0.2, 1e300],
            UNIT_Q,
            "transforms[1].transform.translation.z",
        ),
        (
            [1e300, 0.2, 0.1],
            UNIT_Q,
            "transforms[1].transform.translation.x",
        ),
        (
            [0.0, 0.2, 0.1],
            [0.0, 0.0, f64::NAN, 1.0],
            "transforms[1].transform.rotation",
        ),
        (
            [0.0, 0.2, 0.1],
            [0.0, 0.0, 0.0, 0.0],
            "transforms[1].transform.rotation",
        ),
        (
            [0.0, 0.2, 0.1],
            [0.0, 0.0, 1e300, 1.0],
            "transforms[1].transform.rotation",
        ),
    ] {
        let bytes = mcap_with_tf_and_odom(&tf_fields(xyz, q), &good_odom);
        refused(
            import_mcap(&bytes, "m.mcap", &o),
            "m.mcap",
            &["topic /tf_static", field],
        );
    }
    // Odometry of 1e300, or with NaN quaternions.
    for (x, y, q, field) in [
        (1e300, 0.0, UNIT_Q, "pose.pose.position.x"),
        (0.0, -1e308, UNIT_Q, "pose.pose.position.y"),
        (0.0, f64::NAN, UNIT_Q, "pose.pose.position.y"),
        (0.0, 0.0, [f64::NAN; 4], "pose.pose.orientation"),
    ] {
        let mut odom = good_odom.clone();
        odom[2] = (x, y, q);
        let bytes = mcap_with_tf_and_odom(&good_tf, &odom);
        refused(
            import_mcap(&bytes, "m.mcap", &o),
            "m.mcap",
            &["MCAP message", "topic /odom", field],
        );
    }
}

#[test]
fn layouts_with_values_no_robot_has_are_refused_with_the_json_path() {
    let layout = |robot: &str, sensor: &str, frames: &str| {
        format!(
            r#"{{"format": "sonarmap-layout", "version": 1, "units": "m", "robot": {robot},
                "sensor": {sensor}, "frames": {frames}}}"#
        )
    };
    let ring = r#"{"radius": 0.2, "sonars": {"ring": {"count": 4, "spacing_deg": 90}}}"#;
    let good = layout(ring, r#"{"max_range": 5}"#, r#"{"a": 0, "b": 1}"#);
    assert!(parse_layout(good.as_bytes(), "l.json").is_ok());
    let cases: &[(String, &[&str])] = &[
        (
            layout(
                r#"{"radius": 0.2, "sonars": {"ring": {"count": 4, "spacing_deg": 1e308}}}"#,
                "{}",
                "{}",
            ),
            &["$.robot.sonars.ring.spacing_deg", "1e308"],
        ),
        (
            layout(
                r#"{"radius": 0.2, "sonars": {"ring": {"count": 4, "spacing_deg": 90, "first_deg": -1e300}}}"#,
                "{}",
                "{}",
            ),
            &["$.robot.sonars.ring.first_deg"],
        ),
        (
            layout(
                r#"{"radius": 1e300, "sonars": {"ring": {"count": 4, "spacing_deg": 90}}}"#,
                "{}",
                "{}",
            ),
            &["$.robot.radius"],
        ),
        (
            layout(
                r#"{"sonars": [{"x": 1e300, "y": 0, "heading_deg": 0}]}"#,
                "{}",
                "{}",
            ),
            &["$.robot.sonars[0].x"],
        ),
        (
            layout(
                r#"{"sonars": [{"x": 0, "y": 0, "heading_deg": 1e308}]}"#,
                "{}",
                "{}",
            ),
            &["$.robot.sonars[0].heading_deg"],
        ),
        (
            layout(ring, r#"{"beam_width_deg": 1e308}"#, "{}"),
            &["$.sensor.beam_width_deg"],
        ),
        (
            layout(ring, r#"{"max_range": 1e308}"#, "{}"),
            &["$.sensor.max_range"],
        ),
        (
            layout(ring, r#"{"accuracy_pct": 1e5}"#, "{}"),
            &["$.sensor.accuracy_pct"],
        ),
        (
            layout(ring, r#"{"min_range": 6, "max_range": 5}"#, "{}"),
            &["$.sensor.min_range", "min_range < max_range"],
        ),
        (
            layout(ring, r#"{"min_range": 5, "max_range": 5}"#, "{}"),
            &["$.sensor.min_range"],
        ),
        (
            layout(ring, r#"{"min_range": 7}"#, "{}"),
            &["$.sensor.min_range"],
        ),
        (
            layout(ring, "{}", r#"{"sonar_a": 2, "sonar_b": 2}"#),
            &["$.frames.sonar_b", "already the sensor of frame sonar_a"],
        ),
    ];
    for (json, parts) in cases {
        let e = parse_layout(json.as_bytes(), "l.json")
            .unwrap_err()
            .to_string();
        assert!(e.contains("l.json"), "{e}");
        for p in parts.iter() {
            assert!(e.contains(p), "the error lacks {p:?}: {e}");
        }
    }
}

// ------------------------------------------------------------------ what messages say

/// An MCAP of four range messages from frames `sonar_0` … `sonar_3`, each followed by `suffix`.
fn mcap_with_frames_ending_in(suffix: &str) -> Vec<u8> {
    let mut b = mcap_start(b"/sonar_");
    for k in 0..4u16 {
        let t = 10.0 + 0.02 * k as f64;
        let frame = format!("sonar_{k}{suffix}");
        b.extend(message_record(
            1 + k,
            0,
            t,
            &range_msg(true, t, &frame, 1.0),
        ));
    }
    b.extend(mcap_end());
    b
}

#[test]
fn control_characters_from_the_file_are_escaped_in_messages() {
    // A frame id that would clear the screen: the layout has 2 sensors, the recording 4
    // frames, and the error lists them.
    let b = mcap_with_frames_ending_in("\u{1b}[2J\u{7}");
    let two = parse_layout(
        br#"{"format": "sonarmap-layout", "version": 1, "units": "m",
             "robot": {"sonars": [{"x": 0, "y": 0, "heading_deg": 0}, {"x": 0, "y": 0, "heading_deg": 90}]}}"#,
        "two.json",
    )
    .unwrap();
    let o = ImportOptions {
        layout: Some(two),
        ..ImportOptions::default()
    };
    let m = refused(
        import_mcap(&b, "esc.mcap", &o),
        "esc.mcap",
        &["sonar_3\\u{1b}[2J\\u{7}"],
    );
    assert!(!m.contains('\u{1b}'));
    // Player: a field with control characters.
    let text = player_with("0.1 1 6665 sonar 00 1 1 2 1 \u{1b}[2J");
    let m = refused(
        import_player(text.as_bytes(), "esc.log", &ImportOptions::default()),
        "esc.log",
        &["\\u{1b}[2J"],
    );
    assert!(!m.contains('\u{1b}'));
    // A topic in the summary's warnings.
    let mut b = mcap_run(2);
    let end = b.len() - mcap_end().len();
    b.truncate(end);
    b.extend(schema_record(9, "std_msgs/msg/String"));
    b.extend(channel_record(9, 9, b"/chat\x1b]0;owned\x07"));
    b.extend(message_record(9, 0, 10.5, &[0, 1, 0, 0, 1, 0, 0, 0, 0]));
    b.extend(mcap_end());
    let i = import_mcap(&b, "w.mcap", &ImportOptions::default()).unwrap();
    let shown = i.summary.to_string();
    assert!(shown.contains("/chat\\u{1b}]0;owned\\u{7}"), "{shown}");
    assert!(!shown.contains('\u{1b}'));
}

#[test]
fn invalid_utf8_in_the_first_64_kib_gives_line_and_byte() {
    let mut bytes = player_with("0.1 1 6665 sonar 00 1 1 2 1 1").into_bytes();
    bytes.splice(60..60, [0xFF, 0xFE]);
    let m = refused(
        import_any(&bytes, "bad.log", &ImportOptions::default()),
        "bad.log",
        &["line 2", "byte 60", "not UTF-8"],
    );
    assert!(!m.contains("not a recognised run"), "{m}");
    // Binary from the first byte: not recognised, but the place is given.
    let m = refused(
        import_any(
            b"\xFF\xD8\xFF\xE0 JFIF",
            "photo.jpg",
            &ImportOptions::default(),
        ),
        "photo.jpg",
        &["line 1, byte 0", "not UTF-8"],
    );
    assert!(m.contains("not a recognised run"), "{m}");
    // In a table.
    let mut t = nomad_row("0", "0", "0", "0", "50").into_bytes();
    t.extend(nomad_row("1", "0", "0", "0", "50").into_bytes());
    t.splice(t.len() - 3..t.len() - 3, [0xC3]);
    refused(
        import_any(&t, "t.csv", &nomad_options()),
        "t.csv",
        &["line 2", "not UTF-8"],
    );
}

#[test]
fn odometry_with_nan_quaternions_is_refused_at_its_message_not_called_missing() {
    // Issue 18: 60 odometry messages, all with NaN quaternions, gave "no odometry (no
    // nav_msgs/msg/Odometry messages)".
    let odom: Vec<(f64, f64, [f64; 4])> = (0..60).map(|_| (0.0, 0.0, [f64::NAN; 4])).collect();
    let good_tf = tf_fields([0.0, 0.2, 0.1], UNIT_Q);
    let m = refused(
        import_mcap(
            &mcap_with_tf_and_odom(&good_tf, &odom),
            "nan.mcap",
            &ImportOptions::default(),
        ),
        "nan.mcap",
        &["topic /odom", "pose.pose.orientation", "not a rotation"],
    );
    assert!(!m.contains("no odometry"), "{m}");
}

#[test]
fn an_empty_poses_file_is_named_as_empty_not_as_missing() {
    let mut ranges = String::new();
    for t in 0..3 {
        ranges += &format!("{t}");
        for _ in 0..16 {
            ranges += " 50";
        }
        ranges.push('\n');
    }
    for poses in [&b""[..], b"# no poses yet\n", b"t x y heading\n"] {
        let o = ImportOptions {
            poses: Some(NamedBytes {
                name: "poses.csv".into(),
                bytes: poses.to_vec(),
            }),
            ..nomad_options()
        };
        let m = refused(
            import_table(ranges.as_bytes(), "r.csv", &o),
            "r.csv",
            &["the --poses file poses.csv has no pose lines"],
        );
        assert!(!m.contains("no --poses file"), "{m}");
    }
    // No --poses at all keeps its message.
    check_err(
        import_table(ranges.as_bytes(), "r.csv", &nomad_options()),
        &["no --poses file"],
    );
}

#[test]
fn an_mcap_error_before_any_message_says_so() {
    // A Message record on a channel never defined: the crate refuses the first message.
    let mut b = MAGIC.to_vec();
    b.extend(header_record());
    b.extend(message_record(7, 0, 10.0, &[0, 1, 0, 0]));
    b.extend(mcap_end());
    let m = refused(
        import_mcap(&b, "early.mcap", &ImportOptions::default()),
        "early.mcap",
        &["before the first message"],
    );
    assert!(!m.contains("after message 0"), "{m}");
    // After some messages: the last one read is named.
    let mut b = mcap_run(1);
    let end = b.len() - mcap_end().len();
    b.truncate(end);
    b.extend(message_record(7, 0, 10.0, &[0, 1, 0, 0]));
    b.extend(mcap_end());
    refused(
        import_mcap(&b, "late.mcap", &ImportOptions::default()),
        "late.mcap",
        &["after message"],
    );
}

#[test]
fn a_layout_maps_each_sensor_from_one_frame_only() {
    // Two frames to one sensor silently doubled the snapshots; now the layout is refused, and
    // a layout with distinct frames makes one snapshot per cycle.
    let json = r#"{"format": "sonarmap-layout", "version": 1, "units": "m",
        "robot": {"radius": 0.2, "sonars": {"ring": {"count": 4, "spacing_deg": 90}}},
        "frames": {"sonar_0": 0, "sonar_1": 1, "sonar_2": 2, "sonar_3": 3}}"#;
    let l = parse_layout(json.as_bytes(), "f.json").unwrap();
    let o = ImportOptions {
        layout: Some(l),
        ..ImportOptions::default()
    };
    let i = import_mcap(&mcap_run(5), "f.mcap", &o).unwrap();
    assert_eq!(i.run.snapshots.len(), 5);
    assert_eq!(i.run.layout.len(), 4);
}

#[test]
fn firing_cycles_cannot_outgrow_the_readings() {
    // 10,000 frames (sensors) and then 3,000 readings of one sensor: each its own cycle of
    // 10,000 slots would be 30 million slots from a file of a few hundred kilobytes.
    let mut b = MAGIC.to_vec();
    b.extend(header_record());
    b.extend(schema_record(1, "sensor_msgs/msg/Range"));
    b.extend(channel_record(1, 1, b"/s"));
    let mut seq = 0;
    for k in 0..10_000 {
        let t = 10.0 + 1e-6 * k as f64;
        b.extend(message_record(
            1,
            seq,
            t,
            &range_msg(true, t, &format!("f{k}"), 1.0),
        ));
        seq += 1;
    }
    for i in 0..3000 {
        let t = 11.0 + 1.0 * i as f64;
        b.extend(message_record(1, seq, t, &range_msg(true, t, "f0", 1.0)));
        seq += 1;
    }
    b.extend(mcap_end());
    let mut mounts = String::new();
    for k in 0..10_000 {
        mounts += &format!(
            r#"{}{{"x": 0, "y": 0, "heading_deg": {}}}"#,
            if k > 0 { "," } else { "" },
            k % 360
        );
    }
    let l = parse_layout(
        format!(r#"{{"format": "sonarmap-layout", "version": 1, "units": "m", "robot": {{"sonars": [{mounts}]}}}}"#).as_bytes(),
        "big.json",
    )
    .unwrap();
    let o = ImportOptions {
        layout: Some(l),
        fixed_pose: Some(sonarmap::geometry::Pose::new(0.0, 0.0, 0.0)),
        ..ImportOptions::default()
    };
    let (result, peak) = peak_bytes(|| import_mcap(&b, "cycles.mcap", &o));
    refused(result, "cycles.mcap", &["firing cycles", "--window"]);
    // Ten thousand names and a cycle of ten thousand slots cost more per byte than a ring of
    // 16 does; 30 million slots would have been 480 MB.
    assert!(peak <= 6 * b.len(), "peak {peak} for {} bytes", b.len());
}

// ------------------------------------------------------------------ the command line

#[test]
fn the_command_line_exits_2_with_escaped_messages_on_hostile_files() {
    let bin = env!("CARGO_BIN_EXE_sonarmap");
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.json");
    let mut tiny = MAGIC.to_vec();
    tiny.push(0x01);
    tiny.extend_from_slice(&[0xFF; 8]);
    let esc = mcap_with_frames_ending_in("\u{1b}[2J");
    let json = br#"{"format": "sonarmap-log", "version": 1, "units": "\u001b[2J",
        "robot": {"radius": 1, "sonars": {"ring": {"count": 1, "spacing_deg": 0}}},
        "snapshots": [{"pose": {"x": 0, "y": 0, "heading_deg": 0}, "ranges": [1]}]}"#;
    let cut = b"0.0 1 6665 sonar 00 4 1 1 0 0 0\n0.0 1 6665 position2d 00 1 1 0 0 0 0 0 0 0\n0.1 1 6665 sonar 00 1 1 1 6.4";
    for (name, bytes) in [
        ("tiny.mcap", &tiny[..]),
        ("esc.mcap", &esc[..]),
        ("esc.json", &json[..]),
        ("cut.log", &cut[..]),
    ] {
        let input = dir.path().join(name);
        std::fs::write(&input, bytes).unwrap();
        for args in [
            vec![
                "convert",
                input.to_str().unwrap(),
                "--out",
                out.to_str().unwrap(),
            ],
            vec!["run", input.to_str().unwrap()],
        ] {
            let o = std::process::Command::new(bin)
                .args(&args)
                .output()
                .unwrap();
            let stderr = String::from_utf8_lossy(&o.stderr);
            assert_eq!(o.status.code(), Some(2), "{name} {args:?}: {stderr}");
            assert!(stderr.contains(name), "{name}: {stderr}");
            assert!(
                !stderr.chars().any(|c| c.is_control() && c != '\n'),
                "{name}: raw control characters: {stderr:?}"
            );
            assert!(!out.exists());
        }
    }
}

#[test]
fn run_logs_with_values_no_robot_produces_are_refused_with_the_json_path() {
    // What convert writes the loader takes back; what no robot produces it refuses, so that
    // `import_any` on a hostile run log keeps the same contract as the importers.
    let log = |snapshot: &str, robot: &str| {
        format!(
            r#"{{"format": "sonarmap-log", "version": 1, "units": "m", "robot": {robot},
                "snapshots": [{snapshot}]}}"#
        )
    };
    let ring = r#"{"radius": 0.2, "sonars": {"ring": {"count": 2, "spacing_deg": 180}}}"#;
    let good = r#"{"t": 1, "pose": {"x": 1, "y": 2, "heading_deg": 30}, "ranges": [1, null]}"#;
    let i = import_any(
        log(good, ring).as_bytes(),
        "l.json",
        &ImportOptions::default(),
    )
    .unwrap();
    check_run(&i.run);
    for (snapshot, robot, path) in [
        (
            r#"{"t": 1e300, "pose": {"x": 1, "y": 2, "heading_deg": 30}, "ranges": [1, null]}"#,
            ring,
            "$.snapshots[0].t",
        ),
        (
            r#"{"pose": {"x": 1e300, "y": 2, "heading_deg": 30}, "ranges": [1, null]}"#,
            ring,
            "$.snapshots[0].pose.x",
        ),
        (
            r#"{"pose": {"x": 1, "y": 2, "heading_deg": 1e308}, "ranges": [1, null]}"#,
            ring,
            "$.snapshots[0].pose.heading_deg",
        ),
        (
            r#"{"pose": {"x": 1, "y": 2, "heading_deg": 0}, "ranges": [1, 1e308]}"#,
            ring,
            "$.snapshots[0].ranges[1]",
        ),
        (
            good,
            r#"{"radius": 0.2, "sonars": {"ring": {"count": 2, "spacing_deg": 1e308}}}"#,
            "$.robot.sonars.ring.spacing_deg",
        ),
        (
            good,
            r#"{"sonars": [{"x": 1e300, "y": 0, "heading_deg": 0}, {"x": 0, "y": 0, "heading_deg": 0}]}"#,
            "$.robot.sonars[0].x",
        ),
    ] {
        let m = refused(
            import_any(
                log(snapshot, robot).as_bytes(),
                "l.json",
                &ImportOptions::default(),
            ),
            "l.json",
            &[path],
        );
        assert!(m.len() < 300, "{m}");
    }
}

#[test]
fn a_summary_keeps_a_thousand_skipped_places_and_counts_the_rest() {
    // Each stale sonar line is skipped with a place and a warning; a file of them must not
    // grow the summary without bound.
    let mut text = String::from(PLAYER_HEAD);
    text += "0.0 1 6665 position2d 00 1 1 0 0 0 0 0 0 0\n";
    text += "100.0 1 6665 sonar 00 1 1 2 1 1\n";
    for i in 0..2500 {
        text += &format!("{}.0 1 6665 sonar 00 1 1 2 1 1\n", 99 - i % 50);
    }
    text += "100.5 1 6665 position2d 00 1 1 0 0 0 0 0 0 0\n";
    let i = import_player(text.as_bytes(), "stale.log", &ImportOptions::default()).unwrap();
    assert_eq!(i.summary.skipped.len(), 1000);
    assert_eq!(i.summary.skipped_more, 1500);
    assert_eq!(i.summary.warnings.len(), 1000);
    let shown = i.summary.to_string();
    assert!(shown.contains("skipped 2500"), "{}", &shown[..200]);
    assert!(shown.contains("... and 2480 more skipped"));
    assert!(shown.lines().count() < 1100);
}
