//! Fuzz tests that check the contract of issue 18 for every input, not only that nothing
//! panics: each input is refused with the file named (and no control character echoed), or
//! imported as a run whose log the loader takes back and that the mapper maps with finite
//! numbers ([`check_contract`]).
//!
//! The inputs are structure-aware: a valid recording is built from a seed, then mutated where
//! the format is fragile:
//! - Player/Stage logs: field-level mutations (numbers of every magnitude, NaN, infinities,
//!   truncated fields, fields added or removed), lines swapped or dropped, files cut short;
//! - tables: ragged columns, cells of every magnitude, headers, separators, the poses file;
//! - tables of one reading a line: the same, with pose columns, odometry lines or a poses file;
//! - MCAP: valid records with corrupted lengths, opcodes and CRCs, messages in chunks, CDR
//!   messages with corrupted string lengths, sequence counts and floats, files cut short.
//!
//! `IMPORT_FUZZ_CASES=N` sets the cases per test (default 300, CI's short budget); each case
//! runs its importer and `import_any`. Long runs: `IMPORT_FUZZ_CASES=2000000 cargo test
//! --release --test it import_fuzz`.

use super::import_hostile::{
    channel_record, check_contract, header_record, mcap_end, message_record, record, schema_record,
    MAGIC,
};
use super::support::ros2::{Cdr, MOUNTS};
use proptest::prelude::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use sonarmap::geometry::Pose;
use sonarmap::import::{
    builtin_layout, import_any, import_mcap, import_player, import_table, parse_layout, AngleUnit,
    ImportOptions, Layout, NamedBytes, TableForm,
};
use sonarmap::units::Units;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::OnceLock;

/// Per test: cases run and inputs imported (the rest were refused). Printed when a test has
/// run its cases (see with `--nocapture`), so that long runs report how much of what they
/// tried got past the checks into the contract's load-and-map half.
struct Tally {
    name: &'static str,
    cases: AtomicUsize,
    imported: AtomicUsize,
}

impl Tally {
    const fn new(name: &'static str) -> Self {
        Tally {
            name,
            cases: AtomicUsize::new(0),
            imported: AtomicUsize::new(0),
        }
    }

    fn count<T, E>(&self, results: &[&Result<T, E>]) {
        let imported = results.iter().filter(|r| r.is_ok()).count();
        self.imported.fetch_add(imported, Ordering::Relaxed);
        let n = self.cases.fetch_add(1, Ordering::Relaxed) + 1;
        if n == cases() as usize || n.is_multiple_of(1_000_000) {
            eprintln!(
                "import_fuzz {}: {n} cases, {} inputs imported and checked, {} refused",
                self.name,
                self.imported.load(Ordering::Relaxed),
                n * results.len() - self.imported.load(Ordering::Relaxed)
            );
        }
    }
}

static PLAYER: Tally = Tally::new("player");
static TABLE: Tally = Tally::new("table");
static MCAP: Tally = Tally::new("mcap");
static FIRINGS: Tally = Tally::new("firings");
static BYTES: Tally = Tally::new("bytes");

fn cases() -> u32 {
    std::env::var("IMPORT_FUZZ_CASES")
        .ok()
        .and_then(|c| c.parse().ok())
        .unwrap_or(300)
}

/// A number as text, of any magnitude: plausible values most of the time, then NaN,
/// infinities, subnormals, 1e308 and beyond, any bit pattern, long digit strings, and text
/// that only looks like a number.
fn any_number(r: &mut ChaCha8Rng) -> String {
    const SPECIAL: &[&str] = &[
        "nan", "NaN", "-nan", "inf", "-inf", "+inf", "infinity", "1e308", "-1e308", "1e309",
        "4.9e-324", "-0", "0", "1e300", "-1e300", "1e10", "1e5", "1e4", "10001", "-10001", "0x10",
        "1_000", "1.2.3", "", ".", "-", "e5", "1e", "+", "٣", "1,5", "--1",
    ];
    match r.random_range(0..12) {
        0 => SPECIAL[r.random_range(0..SPECIAL.len())].to_string(),
        1 => format!("{:e}", f64::from_bits(r.random())),
        2 => format!("{}", f64::from_bits(r.random())),
        3 => {
            let m: f64 = r.random_range(-10.0..10.0);
            let e: i32 = r.random_range(-330..330);
            format!("{m:.4}e{e}")
        }
        4 => format!("{}", r.random::<i64>()),
        5 => "9".repeat(r.random_range(1..400)),
        6 => format!("-{:.3}", r.random_range(0.0..10.0)),
        _ => format!("{:.4}", r.random_range(-20.0..20.0)),
    }
}

/// Cuts, drops and duplicates fields and lines; `number` makes a replacement field.
fn mutate_fields(r: &mut ChaCha8Rng, lines: &mut Vec<Vec<String>>, mutations: usize) {
    for _ in 0..mutations {
        if lines.is_empty() {
            return;
        }
        let li = r.random_range(0..lines.len());
        let line = &mut lines[li];
        let fi = r.random_range(0..line.len().max(1));
        match r.random_range(0..10) {
            0..=3 => {
                if fi < line.len() {
                    line[fi] = any_number(r);
                }
            }
            4 => {
                if let Some(f) = line.get_mut(fi) {
                    let keep = r.random_range(0..=f.len());
                    let cut: String = f.chars().take(keep).collect();
                    *f = cut;
                }
            }
            5 => {
                if fi < line.len() {
                    line.remove(fi);
                }
            }
            6 => line.insert(fi.min(line.len()), any_number(r)),
            7 => {
                let other = r.random_range(0..lines.len());
                lines.swap(li, other);
            }
            8 => {
                lines.remove(li);
            }
            _ => {
                let copy = lines[li].clone();
                lines.insert(li, copy);
            }
        }
    }
}

/// Joins lines, then sometimes damages the file as a whole: no final newline, cut at a byte,
/// CRLF endings, a byte that is not UTF-8, control characters, a comment.
fn to_text(r: &mut ChaCha8Rng, lines: &[Vec<String>], sep: &str) -> Vec<u8> {
    let eol = if r.random_bool(0.05) { "\r\n" } else { "\n" };
    let mut text = String::new();
    for l in lines {
        text += &l.join(sep);
        text += eol;
    }
    let mut bytes = text.into_bytes();
    match r.random_range(0..20) {
        0 => {
            bytes.pop();
        }
        1 if !bytes.is_empty() => {
            let at = r.random_range(0..bytes.len());
            bytes.truncate(at);
        }
        2 if !bytes.is_empty() => {
            let at = r.random_range(0..bytes.len());
            bytes.insert(at, [0xFF, 0xC3, 0x80][r.random_range(0..3)]);
        }
        3 if !bytes.is_empty() => {
            let at = r.random_range(0..bytes.len());
            bytes.splice(at..at, b"\x1b[2J\x07".iter().copied());
        }
        4 if !bytes.is_empty() => {
            let at = r.random_range(0..bytes.len());
            bytes.splice(at..at, b" # comment ".iter().copied());
        }
        _ => {}
    }
    bytes
}

fn f(v: f64) -> String {
    format!("{v:.4}")
}

// ------------------------------------------------------------------ Player/Stage

/// A valid Player log (2/3 or 1.x) of `n` sonars, odometry and other devices.
fn player_lines(r: &mut ChaCha8Rng) -> (Vec<Vec<String>>, usize) {
    let n = [1, 2, 4, 8, 16][r.random_range(0..5)];
    let v1 = r.random_bool(0.2);
    let head = |t: f64, interface: &str| -> Vec<String> {
        vec![
            format!("{t:.3}"),
            "16777343".into(),
            "6665".into(),
            interface.into(),
            "00".into(),
        ]
    };
    let mounts: Vec<(f64, f64, f64)> = (0..n)
        .map(|k| {
            let a = k as f64 * std::f64::consts::TAU / n as f64;
            (0.2 * a.cos(), 0.2 * a.sin(), a)
        })
        .collect();
    let mut t = r.random_range(0.0..2e9);
    let mut lines = Vec::new();
    let (mut x, mut y, mut h) = (
        r.random_range(-50.0..50.0),
        r.random_range(-50.0..50.0),
        0.0,
    );
    if !v1 {
        let mut g = head(t, "sonar");
        g.extend(["4".into(), "1".into(), n.to_string()]);
        let six = r.random_bool(0.2);
        for &(mx, my, a) in &mounts {
            g.extend([f(mx), f(my)]);
            if six {
                g.extend(["0".into(), "0".into(), "0".into()]);
            }
            g.push(f(a));
        }
        lines.push(g);
    }
    for _ in 0..r.random_range(1..30) {
        t += r.random_range(0.0..0.3);
        x += r.random_range(-0.1..0.1);
        y += r.random_range(-0.1..0.1);
        h += r.random_range(-0.2..0.2);
        let ranges: Vec<String> = (0..n).map(|_| f(r.random_range(0.0..6.0))).collect();
        match (v1, r.random_range(0..5)) {
            (false, 0 | 1) => {
                let mut l = head(t, "position2d");
                l.extend(["1".into(), "1".into(), f(x), f(y), f(h)]);
                l.extend(["0".into(), "0".into(), "0".into(), "0".into()]);
                lines.push(l);
            }
            (false, 2) => {
                let mut l = head(t, "laser");
                l.extend(["1".into(), "1".into(), "0.5".into()]);
                lines.push(l);
            }
            (false, _) => {
                let mut l = head(t, "sonar");
                l.extend(["1".into(), "1".into(), n.to_string()]);
                l.extend(ranges);
                lines.push(l);
            }
            (true, 0 | 1) => {
                let mut l = head(t, "position");
                l.push(format!("{t:.3}"));
                l.extend([
                    f(x),
                    f(y),
                    f(h),
                    "0".into(),
                    "0".into(),
                    "0".into(),
                    "0".into(),
                ]);
                lines.push(l);
            }
            (true, _) => {
                let mut l = head(t, "sonar");
                l.push(format!("{t:.3}"));
                l.push(n.to_string());
                for &(mx, my, a) in &mounts {
                    l.extend([f(mx), f(my), f(a)]);
                }
                l.push(n.to_string());
                l.extend(ranges);
                lines.push(l);
            }
        }
    }
    (lines, n)
}

fn pioneer() -> &'static Layout {
    static L: OnceLock<Layout> = OnceLock::new();
    L.get_or_init(|| builtin_layout("pioneer_8_8").unwrap())
}

fn player_options(r: &mut ChaCha8Rng) -> ImportOptions {
    let mut o = ImportOptions::default();
    if r.random_bool(0.2) {
        o.layout = Some(pioneer().clone());
    }
    if r.random_bool(0.2) {
        o.max_range_m = Some(r.random_range(0.5..8.0));
    }
    if r.random_bool(0.2) {
        o.fixed_pose = Some(Pose::new(1.0, -2.0, 0.3));
    }
    if r.random_bool(0.1) {
        o.units = Some(Units::Inches);
    }
    o
}

fn player_case(seed: u64) {
    let mut r = ChaCha8Rng::seed_from_u64(seed);
    let (mut lines, _) = player_lines(&mut r);
    let mutations = if r.random_bool(0.1) {
        0
    } else {
        r.random_range(1..5)
    };
    mutate_fields(&mut r, &mut lines, mutations);
    let bytes = if mutations == 0 {
        let mut t = lines
            .iter()
            .map(|l| l.join(" "))
            .collect::<Vec<_>>()
            .join("\n");
        t.push('\n');
        t.into_bytes()
    } else {
        to_text(&mut r, &lines, " ")
    };
    let o = player_options(&mut r);
    let result = import_player(&bytes, "fuzz.log", &o);
    check_contract(&result, "fuzz.log");
    if mutations == 0 && o.layout.is_none() && o.fixed_pose.is_none() {
        // A log no one has touched is taken (unless no sonar line lies near odometry).
        if let Err(e) = &result {
            let m = e.to_string();
            assert!(
                m.contains("no odometry") || m.contains("no snapshot") || m.contains("--layout"),
                "a valid log was refused: {m}\n{}",
                String::from_utf8_lossy(&bytes)
            );
        }
    }
    let any = import_any(&bytes, "fuzz.log", &o);
    check_contract(&any, "fuzz.log");
    PLAYER.count(&[&result, &any]);
}

// ------------------------------------------------------------------ tables

fn ring_layout(n: usize) -> &'static Layout {
    static L: OnceLock<Vec<Layout>> = OnceLock::new();
    let all = L.get_or_init(|| {
        [1usize, 3, 16]
            .iter()
            .map(|&n| {
                let json = format!(
                    r#"{{"format": "sonarmap-layout", "version": 1, "units": "m",
                        "robot": {{"radius": 0.2, "sonars": {{"ring": {{"count": {n}, "spacing_deg": {}}}}}}},
                        "sensor": {{"max_range": 5}}}}"#,
                    360.0 / n as f64
                );
                parse_layout(json.as_bytes(), "ring").unwrap()
            })
            .collect()
    });
    all.iter().find(|l| l.layout.len() == n).unwrap()
}

fn table_case(seed: u64) {
    let mut r = ChaCha8Rng::seed_from_u64(seed);
    let n = [1, 3, 16][r.random_range(0..3)];
    let units = [Units::Metres, Units::Inches, Units::Millimetres][r.random_range(0..3)];
    let heading = if r.random_bool(0.5) {
        AngleUnit::Degrees
    } else {
        AngleUnit::Radians
    };
    let scale = 1.0 / units.metres_per_unit();
    let separate = r.random_bool(0.3);
    let mut t = r.random_range(0.0..1e6);
    let mut rows = Vec::new();
    let mut poses = Vec::new();
    if r.random_bool(0.3) {
        let mut h = vec!["t".to_string()];
        if !separate {
            h.extend(["x".into(), "y".into(), "heading".into()]);
        }
        h.extend((0..n).map(|k| format!("r{k}")));
        rows.push(h);
    }
    for _ in 0..r.random_range(1..25) {
        t += r.random_range(0.0..0.5);
        let pose = vec![
            format!("{t:.3}"),
            f(r.random_range(-30.0..30.0) * scale),
            f(r.random_range(-30.0..30.0) * scale),
            f(r.random_range(-3.0..3.0)
                * if heading == AngleUnit::Degrees {
                    57.0
                } else {
                    1.0
                }),
        ];
        let mut row = vec![format!("{t:.3}")];
        if separate {
            poses.push(pose);
        } else {
            row.extend(pose[1..].iter().cloned());
        }
        for _ in 0..n {
            row.push(match r.random_range(0..10) {
                0 => ["-", "nan", "inf", "null", "none"][r.random_range(0..5)].to_string(),
                _ => f(r.random_range(0.0..6.0) * scale),
            });
        }
        rows.push(row);
    }
    let mutations = if r.random_bool(0.1) {
        0
    } else {
        r.random_range(1..5)
    };
    mutate_fields(&mut r, &mut rows, mutations);
    if separate && r.random_bool(0.3) {
        let m = r.random_range(1..3);
        mutate_fields(&mut r, &mut poses, m);
    }
    let sep = [",", ", ", " ", "\t", " , "][r.random_range(0..5)];
    let bytes = to_text(&mut r, &rows, sep);
    let poses_bytes = to_text(&mut r, &poses, sep);
    let o = ImportOptions {
        layout: Some(ring_layout(n).clone()),
        units: Some(units),
        heading,
        poses: separate.then(|| NamedBytes {
            name: "fuzz-poses.csv".into(),
            bytes: poses_bytes,
        }),
        fixed_pose: r.random_bool(0.1).then(|| Pose::new(0.0, 0.0, 0.0)),
        max_range_m: r.random_bool(0.2).then(|| r.random_range(0.5..8.0)),
        ..ImportOptions::default()
    };
    let table = import_table(&bytes, "fuzz.csv", &o);
    check_table_contract(&table);
    let any = import_any(&bytes, "fuzz.csv", &o);
    check_table_contract(&any);
    TABLE.count(&[&table, &any]);
}

/// The importers' contract for a table `fuzz.csv` with its poses in `fuzz-poses.csv`: a
/// refusal may name the poses file instead.
fn check_table_contract(
    result: &Result<sonarmap::import::Imported, sonarmap::import::ImportError>,
) {
    match result {
        Err(e) if e.to_string().starts_with("fuzz-poses.csv") => {
            check_contract(result, "fuzz-poses.csv")
        }
        _ => check_contract(result, "fuzz.csv"),
    }
}

// ------------------------------------------------------------------ tables of firings

/// How a firing table gives its poses.
#[derive(Clone, Copy, PartialEq)]
enum FiringPoses {
    /// `t sensor range x y heading`.
    Columns,
    /// `t sensor range` lines between `t x y heading` odometry lines.
    OdometryLines,
    /// `t sensor range` lines and a `--poses` file.
    PosesFile,
}

/// A valid table of firings: its rows, its poses file's rows, and each firing as it should be
/// imported (time, sensor, range in metres, parsed back from the text).
struct FiringTable {
    rows: Vec<Vec<String>>,
    poses: Vec<Vec<String>>,
    form: FiringPoses,
    firings: Vec<(f64, usize, Option<f64>)>,
    n: usize,
    units: Units,
}

fn firing_table(r: &mut ChaCha8Rng) -> FiringTable {
    let n = [1, 3, 16][r.random_range(0..3)];
    let units = [Units::Metres, Units::Inches, Units::Millimetres][r.random_range(0..3)];
    let scale = 1.0 / units.metres_per_unit();
    let form = [
        FiringPoses::Columns,
        FiringPoses::OdometryLines,
        FiringPoses::PosesFile,
    ][r.random_range(0..3)];
    let mut rows = Vec::new();
    let mut poses = Vec::new();
    let mut firings = Vec::new();
    if r.random_bool(0.5) {
        let mut h: Vec<String> = ["t", "sensor", "range"].map(String::from).to_vec();
        if form == FiringPoses::Columns {
            h.extend(["x", "y", "heading"].map(String::from));
        }
        rows.push(h);
    }
    let mut t: f64 = r.random_range(0.0..1e5);
    let pose_at = |r: &mut ChaCha8Rng, t: f64| {
        vec![
            format!("{t:.3}"),
            f(r.random_range(-30.0..30.0) * scale),
            f(r.random_range(-30.0..30.0) * scale),
            f(r.random_range(-170.0..170.0)),
        ]
    };
    if form != FiringPoses::Columns {
        let p = pose_at(r, t);
        if form == FiringPoses::PosesFile {
            poses.push(p);
        } else {
            rows.push(p);
        }
    }
    for _ in 0..r.random_range(1..12) {
        // A cycle: most of the sensors, in a shuffled order, a few at a moment.
        let mut order: Vec<usize> = (0..n).collect();
        for i in (1..n).rev() {
            order.swap(i, r.random_range(0..=i));
        }
        // At least half the ring: an importer refuses cycles that read a quarter of it on
        // average (a hostile file must not make a million near-empty cycles).
        order.truncate(r.random_range(n.div_ceil(2)..=n));
        for k in order {
            if r.random_bool(0.5) {
                t += r.random_range(0.0..0.08);
            }
            let text = match r.random_range(0..10) {
                0 => "-".to_string(),
                _ => f(r.random_range(0.05..6.0) * scale),
            };
            let range_m = text
                .parse::<f64>()
                .ok()
                .map(|v| units.to_m(v))
                .filter(|&m| m < 5.0);
            let t_text = format!("{t:.3}");
            firings.push((t_text.parse().unwrap(), k, range_m));
            let mut row = vec![t_text, k.to_string(), text];
            if form == FiringPoses::Columns {
                row.extend(pose_at(r, t)[1..].iter().cloned());
            }
            rows.push(row);
        }
        t += r.random_range(0.0..0.5);
        if form != FiringPoses::Columns && r.random_bool(0.7) {
            let p = pose_at(r, t);
            if form == FiringPoses::PosesFile {
                poses.push(p);
            } else {
                rows.push(p);
            }
        }
    }
    // Odometry after the last firing (a firing more than a second beyond the odometry is
    // skipped, as it should be).
    if form != FiringPoses::Columns {
        let p = pose_at(r, t);
        if form == FiringPoses::PosesFile {
            poses.push(p);
        } else {
            rows.push(p);
        }
    }
    FiringTable {
        rows,
        poses,
        form,
        firings,
        n,
        units,
    }
}

fn firing_options(r: &mut ChaCha8Rng, table: &FiringTable, poses: Vec<u8>) -> ImportOptions {
    ImportOptions {
        layout: Some(ring_layout(table.n).clone()),
        units: Some(table.units),
        poses: (table.form == FiringPoses::PosesFile).then(|| NamedBytes {
            name: "fuzz-poses.csv".into(),
            bytes: poses,
        }),
        table: if r.random_bool(0.5) || table.n < 4 {
            TableForm::Firings
        } else {
            TableForm::Auto
        },
        ..ImportOptions::default()
    }
}

fn firings_case(seed: u64) {
    let mut r = ChaCha8Rng::seed_from_u64(seed);
    let mut table = firing_table(&mut r);
    let mutations = r.random_range(1..5);
    mutate_fields(&mut r, &mut table.rows, mutations);
    if table.form == FiringPoses::PosesFile && r.random_bool(0.3) {
        let m = r.random_range(1..3);
        mutate_fields(&mut r, &mut table.poses, m);
    }
    let sep = [",", " ", "\t", " , "][r.random_range(0..4)];
    let bytes = to_text(&mut r, &table.rows, sep);
    let poses = to_text(&mut r, &table.poses, sep);
    let mut o = firing_options(&mut r, &table, poses);
    o.window_s = r.random_bool(0.3).then(|| r.random_range(0.0..2.0));
    let imported = import_table(&bytes, "fuzz.csv", &o);
    check_table_contract(&imported);
    let any = import_any(&bytes, "fuzz.csv", &o);
    check_table_contract(&any);
    FIRINGS.count(&[&imported, &any]);
}

/// A valid table of firings imports, and every reading comes out once, with its sensor, its
/// range (or no echo) and its own moment (the snapshot's `t` plus its `reading_dt_s`); no
/// cycle is longer than the window.
fn valid_firings_case(seed: u64) {
    let mut r = ChaCha8Rng::seed_from_u64(seed);
    let table = firing_table(&mut r);
    let text = |rows: &[Vec<String>]| -> Vec<u8> {
        rows.iter()
            .flat_map(|row| format!("{}\n", row.join(" ")).into_bytes())
            .collect()
    };
    let (bytes, poses) = (text(&table.rows), text(&table.poses));
    let o = firing_options(&mut r, &table, poses);
    let imported = import_table(&bytes, "valid.csv", &o)
        .unwrap_or_else(|e| panic!("a valid firing table is refused: {e}"));
    let run = &imported.run;
    let mut out = Vec::new();
    for s in &run.snapshots {
        let read_at = |k: usize| s.t + s.reading_dt_s.get(k).copied().unwrap_or(0.0);
        let times: Vec<f64> = (0..table.n).map(read_at).collect();
        let span = times.iter().cloned().fold(f64::NEG_INFINITY, f64::max)
            - times.iter().cloned().fold(f64::INFINITY, f64::min);
        assert!(
            span <= 1.0 + 1e-9,
            "a cycle spans {span} s, beyond the 1 s window"
        );
        for (k, range) in s.ranges_m.iter().enumerate() {
            out.push((read_at(k), k, *range));
        }
    }
    for (t, k, range) in &table.firings {
        let found = out.iter().position(|(ot, ok, or)| {
            ok == k
                && (ot - t).abs() < 1e-6
                && match (or, range) {
                    (Some(a), Some(b)) => (a - b).abs() < 1e-9,
                    (None, None) => true,
                    _ => false,
                }
        });
        let i = found.unwrap_or_else(|| {
            panic!("firing ({t}, sensor {k}, {range:?}) is not in the run: {out:?}")
        });
        out.swap_remove(i);
    }
    // What is left is the slots of sensors silent in their cycle: no echo.
    assert!(out.iter().all(|(_, _, r)| r.is_none()), "{out:?}");
    assert_eq!(imported.format, sonarmap::import::Format::FiringTable);
}

// ------------------------------------------------------------------ MCAP

fn range_cdr(r: &mut ChaCha8Rng, t: f64, frame: &str) -> Vec<u8> {
    let mut c = Cdr::new(r.random_bool(0.9));
    c.header(t, frame);
    c.u8(0);
    let range = if r.random_bool(0.1) {
        f32::INFINITY
    } else {
        r.random_range(0.0..7.0)
    };
    for v in [0.4363f32, 0.15, 5.0, range] {
        c.f32(v);
    }
    c.b
}

fn odom_cdr(t: f64, x: f64, y: f64, yaw: f64) -> Vec<u8> {
    let mut c = Cdr::new(true);
    c.header(t, "odom");
    c.string("base_link");
    for v in [x, y, 0.0] {
        c.f64(v);
    }
    c.quaternion_yaw(yaw);
    for _ in 0..(36 + 6 + 36) {
        c.f64(0.0);
    }
    c.b
}

fn tf_cdr(n: usize) -> Vec<u8> {
    let mut c = Cdr::new(true);
    c.u32(n as u32);
    for k in 0..n {
        c.header(0.0, "base_link");
        c.string(&format!("sonar_{k}"));
        let (x, y, yaw) = MOUNTS[k % 4];
        for v in [x, y, 0.1] {
            c.f64(v);
        }
        c.quaternion_yaw(yaw + k as f64);
    }
    c.b
}

/// Overwrites the CDR of a message record (body from byte 9 + 22) where it is fragile: the
/// frame id's length, the transforms count, or any aligned field with a special value.
fn corrupt_cdr(r: &mut ChaCha8Rng, rec: &mut [u8]) {
    let cdr = 9 + 22;
    if rec.len() < cdr + 8 {
        return;
    }
    let specials32: [u32; 8] = [
        0,
        1,
        3,
        0x7FFF_FFFF,
        u32::MAX,
        u32::MAX - 3,
        (rec.len() - cdr) as u32,
        (rec.len() - cdr + 1) as u32,
    ];
    let floats: [f64; 10] = [
        f64::NAN,
        f64::INFINITY,
        f64::NEG_INFINITY,
        -1.0,
        1e308,
        -1e300,
        1e30,
        f64::MIN_POSITIVE,
        -0.0,
        2e4,
    ];
    match r.random_range(0..4) {
        // The frame id's length (header.frame_id) or a TFMessage's transforms count.
        0 => {
            let at = cdr + [4, 12][r.random_range(0..2)];
            if at + 4 <= rec.len() {
                let v = specials32[r.random_range(0..specials32.len())];
                rec[at..at + 4].copy_from_slice(&v.to_le_bytes());
            }
        }
        1 => {
            let words = (rec.len() - cdr - 4) / 4;
            let at = cdr + 4 + 4 * r.random_range(0..words);
            let v = floats[r.random_range(0..floats.len())] as f32;
            rec[at..at + 4].copy_from_slice(&v.to_le_bytes());
        }
        2 => {
            let words = (rec.len() - cdr - 4) / 8;
            if words > 0 {
                let at = cdr + 4 + 8 * r.random_range(0..words);
                let v = floats[r.random_range(0..floats.len())];
                rec[at..at + 8].copy_from_slice(&v.to_le_bytes());
            }
        }
        _ => {
            let at = r.random_range(cdr..rec.len());
            rec[at] = r.random();
        }
    }
}

/// Corrupts a record's length, opcode or CRC.
fn corrupt_record(r: &mut ChaCha8Rng, rec: &mut [u8]) {
    if rec.len() < 9 {
        return;
    }
    let len = (rec.len() - 9) as u64;
    match r.random_range(0..4) {
        0 | 1 => {
            let v = [
                0,
                1,
                len.wrapping_sub(1),
                len + 1,
                len + 8,
                u64::MAX,
                u64::MAX - 8,
                u64::MAX - 9,
                u32::MAX as u64,
                1 << 63,
                r.random(),
            ][r.random_range(0..11)];
            rec[1..9].copy_from_slice(&v.to_le_bytes());
        }
        2 => rec[0] = r.random(),
        _ => {
            // The CRC of a chunk (after start, end, uncompressed size), a Data End or an
            // attachment's last 4 bytes.
            let at = match rec[0] {
                0x06 if rec.len() >= 9 + 28 => 9 + 24,
                _ => rec.len() - 4,
            };
            let v: u32 = r.random();
            rec[at..at + 4].copy_from_slice(&v.to_le_bytes());
        }
    }
}

fn chunk(records: &[u8], compression: &[u8]) -> Vec<u8> {
    let mut b = 0u64.to_le_bytes().to_vec();
    b.extend(u64::MAX.to_le_bytes());
    b.extend((records.len() as u64).to_le_bytes());
    b.extend(0u32.to_le_bytes());
    b.extend((compression.len() as u32).to_le_bytes());
    b.extend_from_slice(compression);
    b.extend((records.len() as u64).to_le_bytes());
    b.extend_from_slice(records);
    record(0x06, &b)
}

fn mcap_case(seed: u64) {
    let mut r = ChaCha8Rng::seed_from_u64(seed);
    let n = r.random_range(1..6usize);
    let mut defs = vec![header_record()];
    defs.push(schema_record(1, "sensor_msgs/msg/Range"));
    defs.push(schema_record(2, "nav_msgs/msg/Odometry"));
    defs.push(schema_record(3, "tf2_msgs/msg/TFMessage"));
    defs.push(schema_record(4, "std_msgs/msg/String"));
    let one_topic = r.random_bool(0.3);
    for k in 0..n as u16 {
        defs.push(channel_record(1 + k, 1, format!("/sonar_{k}").as_bytes()));
    }
    defs.push(channel_record(10, 2, b"/odom"));
    defs.push(channel_record(11, 3, b"/tf_static"));
    defs.push(channel_record(12, 4, b"/chatter"));
    let mut messages = Vec::new();
    let t0 = r.random_range(1.0..2e9);
    if r.random_bool(0.8) {
        messages.push(message_record(11, 0, t0, &tf_cdr(n)));
    }
    let cycles = r.random_range(1..8);
    let mut seq = 1;
    for i in 0..(cycles * 3 + 3) {
        let t = t0 + 0.1 * i as f64;
        if r.random_bool(0.9) {
            messages.push(message_record(
                10,
                seq,
                t,
                &odom_cdr(t, 0.05 * i as f64, 0.0, 0.03 * i as f64),
            ));
            seq += 1;
        }
    }
    for c in 0..cycles {
        for k in 0..n {
            let t = t0 + 0.1 + 0.25 * c as f64 + 0.02 * k as f64;
            let channel = if one_topic { 1 } else { 1 + k as u16 };
            let data = range_cdr(&mut r, t, &format!("sonar_{k}"));
            messages.push(message_record(channel, seq, t, &data));
            seq += 1;
        }
        if r.random_bool(0.2) {
            messages.push(message_record(12, seq, t0, &[0, 1, 0, 0, 1, 0, 0, 0, 0]));
        }
    }
    // Mutations of records and messages.
    let mutations = if r.random_bool(0.1) {
        0
    } else {
        r.random_range(1..4)
    };
    for _ in 0..mutations {
        match r.random_range(0..6) {
            0 | 1 => {
                let i = r.random_range(0..messages.len());
                corrupt_cdr(&mut r, &mut messages[i]);
            }
            2 => {
                let i = r.random_range(0..messages.len());
                corrupt_record(&mut r, &mut messages[i]);
            }
            3 => {
                let i = r.random_range(0..defs.len());
                corrupt_record(&mut r, &mut defs[i]);
            }
            4 => {
                let i = r.random_range(0..messages.len());
                let j = r.random_range(0..messages.len());
                messages.swap(i, j);
            }
            _ => {
                let i = r.random_range(0..messages.len());
                if r.random_bool(0.5) {
                    messages.remove(i);
                    if messages.is_empty() {
                        messages.push(message_record(12, 0, t0, &[0, 1, 0, 0]));
                    }
                } else {
                    let copy = messages[i].clone();
                    messages.insert(i, copy);
                }
            }
        }
    }
    let mut damaged = mutations > 0;
    let mut bytes = MAGIC.to_vec();
    for d in &defs {
        bytes.extend_from_slice(d);
    }
    let body: Vec<u8> = messages.concat();
    match r.random_range(0..4) {
        0 => {
            let mut c = chunk(&body, b"");
            if r.random_bool(0.3) {
                corrupt_record(&mut r, &mut c);
                damaged = true;
            }
            bytes.extend(c);
        }
        1 => bytes.extend(chunk(
            &body,
            [&b"zstd"[..], b"lz4", b"\x1b[2J"][r.random_range(0..3)],
        )),
        _ => bytes.extend(body),
    }
    bytes.extend(mcap_end());
    match r.random_range(0..10) {
        0 => {
            let at = r.random_range(8..bytes.len());
            bytes.truncate(at);
            damaged = true;
        }
        1 => {
            let at = r.random_range(8..bytes.len());
            bytes[at] = r.random();
            damaged = true;
        }
        _ => {}
    }
    // Options: /tf_static (none), or a layout with or without frames.
    let mut o = ImportOptions::default();
    match r.random_range(0..4) {
        0 => {
            let frames: Vec<String> = (0..n).map(|k| format!("\"sonar_{k}\": {k}")).collect();
            let json = format!(
                r#"{{"format": "sonarmap-layout", "version": 1, "units": "m",
                    "robot": {{"radius": 0.2, "sonars": {{"ring": {{"count": {n}, "spacing_deg": 30}}}}}},
                    "sensor": {{"max_range": 5}}, "frames": {{{}}}}}"#,
                frames.join(", ")
            );
            o.layout = Some(parse_layout(json.as_bytes(), "l").unwrap());
        }
        1 => o.layout = Some(ring_layout([1, 3, 16][r.random_range(0..3)]).clone()),
        _ => {}
    }
    if r.random_bool(0.2) {
        o.window_s = Some([0.0, 0.01, 0.05, 1.0, 10.0][r.random_range(0..5)]);
    }
    if r.random_bool(0.1) {
        o.fixed_pose = Some(Pose::new(0.0, 0.0, 0.0));
    }
    let result = import_mcap(&bytes, "fuzz.mcap", &o);
    check_contract(&result, "fuzz.mcap");
    if !damaged && o.layout.is_none() && !one_topic {
        // Untouched: taken when it has what an import needs.
        if let Err(e) = &result {
            let m = e.to_string();
            assert!(
                m.contains("--layout")
                    || m.contains("odometry")
                    || m.contains("compression")
                    || m.contains("no snapshot"),
                "a valid recording was refused: {m}"
            );
        }
    }
    let any = import_any(&bytes, "fuzz.mcap", &o);
    check_contract(&any, "fuzz.mcap");
    MCAP.count(&[&result, &any]);
}

/// Arbitrary bytes, alone and after the MCAP magic.
fn bytes_case(seed: u64) {
    let mut r = ChaCha8Rng::seed_from_u64(seed);
    let len = r.random_range(0..600);
    let bytes: Vec<u8> = (0..len).map(|_| r.random()).collect();
    let o = if r.random_bool(0.5) {
        ImportOptions::default()
    } else {
        ImportOptions {
            layout: Some(ring_layout(16).clone()),
            ..ImportOptions::default()
        }
    };
    let mut results = Vec::new();
    for b in [bytes.clone(), [MAGIC, &bytes].concat()] {
        results.push(import_any(&b, "fuzz.bin", &o));
        results.push(import_player(&b, "fuzz.bin", &o));
        results.push(import_table(&b, "fuzz.bin", &o));
        results.push(import_mcap(&b, "fuzz.bin", &o));
    }
    for result in &results {
        check_contract(result, "fuzz.bin");
    }
    BYTES.count(&results.iter().collect::<Vec<_>>());
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: cases(),
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    #[test]
    fn player_logs_mutated_field_by_field(seed in any::<u64>()) {
        player_case(seed);
    }

    #[test]
    fn tables_with_ragged_columns_and_numbers_of_every_magnitude(seed in any::<u64>()) {
        table_case(seed);
    }

    #[test]
    fn firing_tables_mutated_field_by_field(seed in any::<u64>()) {
        firings_case(seed);
    }

    #[test]
    fn a_valid_firing_table_keeps_every_reading_at_its_own_moment(seed in any::<u64>()) {
        valid_firings_case(seed);
    }

    #[test]
    fn mcap_records_and_cdr_messages_corrupted(seed in any::<u64>()) {
        mcap_case(seed);
    }

    #[test]
    fn arbitrary_bytes(seed in any::<u64>()) {
        bytes_case(seed);
    }
}

/// Inputs the long runs found (`IMPORT_FUZZ_CASES=5000000 --release`), kept as tests.
#[test]
fn inputs_the_long_runs_found() {
    // A mount at 10 km, written in inches and rounded, was just beyond the loader's bound.
    player_case(6329489640392051133);
    // A Range field of view of a few 1e-39 rad was written as a beam width of 0°.
    mcap_case(2643182937703160269);
}
