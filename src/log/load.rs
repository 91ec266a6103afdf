//! Reading a run log: bytes → [`LogFile`] → [`Run`] in metres, with every check of docs/formats.md §2.

use super::duplicates::{check_duplicates, Found};
use super::error::LogError;
use super::file::{
    FloorPlanFile, LogFile, MountFile, RingFile, RobotFile, SensorFile, SnapshotFile, SonarsFile,
    LOG_FORMAT,
};
use crate::geometry::{Point, Pose};
use crate::import::sane;
use crate::run::{Circle, FloorPlan, Run, Snapshot, Wall};
use crate::sonar::{SensorLayout, SensorMount, SensorSpec};
use crate::units::Units;
use serde::de::DeserializeOwned;

/// The most sensors a layout may have; more is taken as a broken file.
pub const MAX_SENSORS: usize = 10_000;

/// The UTF-8 byte-order mark, skipped when a file starts with it.
const BOM: &[u8] = b"\xEF\xBB\xBF";

/// Parses a run log (docs/formats.md §2, `sonarmap-log` v1) into a [`Run`] in metres.
/// `source_name` names the file in error messages. Pure: reads no file.
pub fn load_run(bytes: &[u8], source_name: &str) -> Result<Run, LogError> {
    let file: LogFile = parse_json(bytes, source_name)?;
    run_from_file(file, source_name)
}

/// Parses JSON into `T`: skips a byte-order mark, rejects duplicated keys, and reports the JSON
/// path of any value of the wrong shape. Deserialises from the slice directly (no `Value` tree).
pub fn parse_json<T: DeserializeOwned>(bytes: &[u8], source_name: &str) -> Result<T, LogError> {
    let bytes = bytes.strip_prefix(BOM).unwrap_or(bytes);
    let found = Found::default();
    if let Err(e) = check_duplicates(bytes, &found) {
        if let Some((path, key)) = found.into_inner() {
            return Err(LogError::DuplicateKey {
                file: source_name.to_string(),
                path,
                key,
                line: e.line(),
                column: e.column(),
            });
        }
        return Err(LogError::NotJson {
            file: source_name.to_string(),
            message: strip_location(&e),
            line: e.line(),
            column: e.column(),
        });
    }
    let mut de = serde_json::Deserializer::from_slice(bytes);
    let value: T = serde_path_to_error::deserialize(&mut de).map_err(|e| {
        let path = format!("$.{}", e.path())
            .replace("$.[", "$[")
            .replace("$..", "$.");
        let inner = e.into_inner();
        LogError::Shape {
            file: source_name.to_string(),
            path: if path == "$.." || path == "$." {
                "$".to_string()
            } else {
                path
            },
            message: strip_location(&inner),
            line: inner.line(),
            column: inner.column(),
        }
    })?;
    Ok(value)
}

/// serde_json's message without its " at line L column C" suffix (we print our own).
fn strip_location(e: &serde_json::Error) -> String {
    let text = e.to_string();
    match text.rfind(" at line ") {
        Some(i) => text[..i].to_string(),
        None => text,
    }
}

/// Checks `format` and `version`.
pub(crate) fn check_header(
    format: &str,
    version: &serde_json::Number,
    expected: &'static str,
    file: &str,
) -> Result<(), LogError> {
    if format != expected {
        return Err(LogError::WrongFormat {
            file: file.to_string(),
            found: format.to_string(),
            expected,
        });
    }
    if version.as_u64() != Some(1) {
        return Err(LogError::UnsupportedVersion {
            file: file.to_string(),
            found: version.to_string(),
        });
    }
    Ok(())
}

/// Parses the `units` field.
pub(crate) fn parse_units(units: &str, file: &str) -> Result<Units, LogError> {
    Units::parse(units).ok_or_else(|| LogError::UnknownUnits {
        file: file.to_string(),
        found: units.to_string(),
    })
}

fn bad(
    file: &str,
    path: impl Into<String>,
    value: impl ToString,
    expected: &'static str,
) -> LogError {
    LogError::BadValue {
        file: file.to_string(),
        path: path.into(),
        value: value.to_string(),
        expected,
    }
}

/// Checks a length (in a unit of `metres_per_unit` metres) is finite and within the 10 km of
/// any building (the bound every importer holds lengths to, with [`sane::LOADER_SLACK`]).
fn length(
    v: f64,
    metres_per_unit: f64,
    file: &str,
    path: impl Into<String>,
) -> Result<f64, LogError> {
    sane::within(
        v,
        sane::MAX_LENGTH_M / metres_per_unit * sane::LOADER_SLACK,
        "",
        "",
    )
    .map_err(|_| bad(file, path, sane::show(v), "a finite length within 10 km"))
}

/// Checks a heading in degrees is finite and within ±1e5 rad (some 16,000 turns).
fn heading(v: f64, file: &str, path: impl Into<String>) -> Result<f64, LogError> {
    sane::within(
        v,
        sane::MAX_HEADING_RAD.to_degrees() * sane::LOADER_SLACK,
        "",
        "",
    )
    .map_err(|_| {
        bad(
            file,
            path,
            sane::show(v),
            "a finite heading within ±1e5 rad in degrees",
        )
    })
}

/// Checks a length is finite and at least 0.
fn non_negative(v: f64, file: &str, path: impl Into<String>) -> Result<f64, LogError> {
    if v.is_finite() && v >= 0.0 {
        Ok(v)
    } else {
        Err(bad(file, path, v, "a finite number of at least 0"))
    }
}

/// The layout and body radius (metres) of a `robot` block.
pub(crate) fn layout_from_robot(
    robot: &RobotFile,
    units: Units,
    file: &str,
    at: &str,
) -> Result<(SensorLayout, Option<f64>), LogError> {
    let radius_m = match robot.radius {
        Some(r) => {
            non_negative(r, file, format!("{at}.radius"))?;
            Some(units.to_m(length(
                r,
                units.metres_per_unit(),
                file,
                format!("{at}.radius"),
            )?))
        }
        None => None,
    };
    let layout = match &robot.sonars {
        SonarsFile::Ring(ring) => ring_layout(ring, radius_m, file, at)?,
        SonarsFile::Mounts(mounts) => mounts_layout(mounts, units, file, at)?,
    };
    Ok((layout, radius_m))
}

/// The layout of a `sonars.ring` block: `count` sonars `spacing_deg` apart from
/// `first_deg`, on the robot's rim (`radius_m`, required).
fn ring_layout(
    ring: &RingFile,
    radius_m: Option<f64>,
    file: &str,
    at: &str,
) -> Result<SensorLayout, LogError> {
    let path = format!("{at}.sonars.ring");
    let count = ring.count;
    if !(count.is_finite() && count.fract() == 0.0 && count >= 0.0) {
        return Err(bad(
            file,
            format!("{path}.count"),
            count,
            "a whole number of sonars",
        ));
    }
    if count == 0.0 {
        return Err(bad(
            file,
            format!("{path}.count"),
            count,
            "at least one sonar",
        ));
    }
    if count > MAX_SENSORS as f64 {
        return Err(bad(
            file,
            format!("{path}.count"),
            count,
            "at most 10000 sonars",
        ));
    }
    let spacing = heading(ring.spacing_deg, file, format!("{path}.spacing_deg"))?;
    let first = heading(
        ring.first_deg.unwrap_or(0.0),
        file,
        format!("{path}.first_deg"),
    )?;
    let Some(radius_m) = radius_m else {
        return Err(bad(
            file,
            format!("{at}.radius"),
            "nothing",
            "the robot radius (required with the ring: it is the mount radius)",
        ));
    };
    Ok(SensorLayout::ring(
        count as usize,
        spacing.to_radians(),
        first.to_radians(),
        radius_m,
    ))
}

/// The layout of a `sonars` list of mounts (in `units`), each checked.
fn mounts_layout(
    mounts: &[MountFile],
    units: Units,
    file: &str,
    at: &str,
) -> Result<SensorLayout, LogError> {
    let path = format!("{at}.sonars");
    if mounts.is_empty() {
        return Err(LogError::Empty {
            file: file.to_string(),
            path,
            expected: "at least one sonar",
        });
    }
    if mounts.len() > MAX_SENSORS {
        return Err(bad(file, path, mounts.len(), "at most 10000 sonars"));
    }
    let mounts = mounts
        .iter()
        .enumerate()
        .map(|(k, m)| {
            let u = units.metres_per_unit();
            Ok(SensorMount {
                x_m: units.to_m(length(m.x, u, file, format!("{path}[{k}].x"))?),
                y_m: units.to_m(length(m.y, u, file, format!("{path}[{k}].y"))?),
                heading_rad: heading(m.heading_deg, file, format!("{path}[{k}].heading_deg"))?
                    .to_radians(),
            })
        })
        .collect::<Result<Vec<_>, LogError>>()?;
    Ok(SensorLayout { mounts })
}

/// The sensor of a `sensor` block (absent fields: the Polaroid 6500).
pub(crate) fn sensor_from_file(
    sensor: Option<&SensorFile>,
    units: Units,
    file: &str,
    at: &str,
) -> Result<SensorSpec, LogError> {
    let default = SensorSpec::default();
    let Some(s) = sensor else { return Ok(default) };
    let positive = |v: f64, name: &str| {
        if v.is_finite() && v > 0.0 {
            Ok(v)
        } else {
            Err(bad(
                file,
                format!("{at}.{name}"),
                v,
                "a finite number greater than 0",
            ))
        }
    };
    let spec = SensorSpec {
        accuracy_pct: match s.accuracy_pct {
            Some(v) => positive(v, "accuracy_pct")?,
            None => default.accuracy_pct,
        },
        beam_width_rad: match s.beam_width_deg {
            Some(v) => positive(v, "beam_width_deg")?.to_radians(),
            None => default.beam_width_rad,
        },
        max_range_m: match s.max_range {
            Some(v) => {
                positive(v, "max_range")?;
                units.to_m(length(
                    v,
                    units.metres_per_unit(),
                    file,
                    format!("{at}.max_range"),
                )?)
            }
            None => default.max_range_m,
        },
        min_range_m: match s.min_range {
            Some(v) => {
                non_negative(v, file, format!("{at}.min_range"))?;
                units.to_m(length(
                    v,
                    units.metres_per_unit(),
                    file,
                    format!("{at}.min_range"),
                )?)
            }
            None => default.min_range_m,
        },
        echo: s.echo.unwrap_or(default.echo),
    };
    Ok(spec)
}

/// Walls and circles of a `floor_plan` (or a plan file's top level), in metres.
pub(crate) fn floor_plan_from_file(
    plan: &FloorPlanFile,
    units: Units,
    file: &str,
    at: &str,
) -> Result<FloorPlan, LogError> {
    let mut walls = Vec::with_capacity(plan.walls.len());
    for (i, w) in plan.walls.iter().enumerate() {
        let path = format!("{at}walls[{i}]");
        if w.len() != 4 && w.len() != 5 {
            return Err(bad(
                file,
                path,
                format!("{} numbers", w.len()),
                "[x1, y1, x2, y2] or [x1, y1, x2, y2, roughness_deg]",
            ));
        }
        for (j, v) in w.iter().enumerate().take(4) {
            length(*v, units.metres_per_unit(), file, format!("{path}[{j}]"))?;
        }
        let roughness_rad = match w.get(4) {
            Some(&r) if (0.0..=90.0).contains(&r) => Some(r.to_radians()),
            Some(&r) => {
                return Err(bad(
                    file,
                    format!("{path}[4]"),
                    r,
                    "a roughness between 0 and 90 degrees",
                ))
            }
            None => None,
        };
        walls.push(Wall {
            a: Point::new(units.to_m(w[0]), units.to_m(w[1])),
            b: Point::new(units.to_m(w[2]), units.to_m(w[3])),
            roughness_rad,
        });
    }
    let mut circles = Vec::with_capacity(plan.circles.len());
    for (i, c) in plan.circles.iter().enumerate() {
        let path = format!("{at}circles[{i}]");
        if c.len() != 3 {
            return Err(bad(
                file,
                path,
                format!("{} numbers", c.len()),
                "[cx, cy, r]",
            ));
        }
        for (j, v) in c.iter().enumerate() {
            length(*v, units.metres_per_unit(), file, format!("{path}[{j}]"))?;
        }
        let r = c[2];
        if !(r.is_finite() && r > 0.0) {
            return Err(bad(
                file,
                format!("{path}[2]"),
                r,
                "a radius greater than 0",
            ));
        }
        circles.push(Circle {
            centre: Point::new(units.to_m(c[0]), units.to_m(c[1])),
            radius_m: units.to_m(r),
        });
    }
    Ok(FloorPlan { walls, circles })
}

/// Converts a parsed log file to a run in metres, checking every value.
pub fn run_from_file(file: LogFile, source_name: &str) -> Result<Run, LogError> {
    let f = source_name;
    check_header(&file.format, &file.version, LOG_FORMAT, f)?;
    let units = parse_units(&file.units, f)?;
    let (layout, robot_radius_m) = layout_from_robot(&file.robot, units, f, "$.robot")?;
    let sensor = sensor_from_file(file.sensor.as_ref(), units, f, "$.sensor")?;
    let floor_plan = match &file.floor_plan {
        Some(p) => Some(floor_plan_from_file(p, units, f, "$.floor_plan.")?),
        None => None,
    };
    if file.snapshots.is_empty() {
        return Err(LogError::Empty {
            file: f.to_string(),
            path: "$.snapshots".into(),
            expected: "at least one snapshot",
        });
    }
    let sensors = layout.len();
    let mut snapshots = Vec::with_capacity(file.snapshots.len());
    let mut previous_t = f64::NEG_INFINITY;
    for (i, s) in file.snapshots.into_iter().enumerate() {
        snapshots.push(snapshot_from_file(
            i,
            s,
            units,
            sensors,
            &mut previous_t,
            f,
        )?);
    }
    Ok(Run {
        name: file.name.unwrap_or_else(|| source_name.to_string()),
        units,
        robot_radius_m,
        layout,
        sensor,
        floor_plan,
        snapshots,
    })
}

/// Snapshot `i` in metres, checked: its time (not before `previous_t`, which becomes it), its
/// pose, and its ranges (one per sensor of the `sensors`).
fn snapshot_from_file(
    i: usize,
    s: SnapshotFile,
    units: Units,
    sensors: usize,
    previous_t: &mut f64,
    f: &str,
) -> Result<Snapshot, LogError> {
    let t = s.t.unwrap_or(i as f64);
    sane::time(t, "").map_err(|_| {
        bad(
            f,
            format!("$.snapshots[{i}].t"),
            sane::show(t),
            "a finite time within ±1e10 s",
        )
    })?;
    if t < *previous_t {
        return Err(LogError::TimeDecreases {
            file: f.to_string(),
            snapshot: i,
            t,
            previous: *previous_t,
        });
    }
    *previous_t = t;
    let u = units.metres_per_unit();
    let x = length(s.pose.x, u, f, format!("$.snapshots[{i}].pose.x"))?;
    let y = length(s.pose.y, u, f, format!("$.snapshots[{i}].pose.y"))?;
    let h = heading(
        s.pose.heading_deg,
        f,
        format!("$.snapshots[{i}].pose.heading_deg"),
    )?;
    let true_pose = match &s.true_pose {
        None => None,
        Some(p) => {
            let at = |field: &str| format!("$.snapshots[{i}].true_pose.{field}");
            let x = length(p.x, u, f, at("x"))?;
            let y = length(p.y, u, f, at("y"))?;
            let h = heading(p.heading_deg, f, at("heading_deg"))?;
            Some(Pose::new(units.to_m(x), units.to_m(y), h.to_radians()))
        }
    };
    if s.ranges.len() != sensors {
        return Err(LogError::RangeCount {
            file: f.to_string(),
            snapshot: i,
            found: s.ranges.len(),
            expected: sensors,
        });
    }
    let reading_dt_s = reading_times(i, s.reading_dt_s, sensors, f)?;
    let mut ranges = s.ranges;
    for (k, r) in ranges.iter_mut().enumerate() {
        if let Some(v) = r {
            if !(v.is_finite() && *v >= 0.0) {
                return Err(LogError::BadRange {
                    file: f.to_string(),
                    snapshot: i,
                    sensor: k,
                    value: *v,
                });
            }
            length(*v, u, f, format!("$.snapshots[{i}].ranges[{k}]"))?;
            *v = units.to_m(*v);
        }
    }
    Ok(Snapshot {
        t,
        pose: Pose::new(units.to_m(x), units.to_m(y), h.to_radians()),
        ranges_m: ranges,
        true_pose,
        reading_dt_s,
    })
}

/// Snapshot `i`'s `reading_dt_s`, checked: none, or one finite offset within a minute per
/// sensor of the `sensors`.
fn reading_times(
    i: usize,
    reading_dt_s: Vec<f64>,
    sensors: usize,
    f: &str,
) -> Result<Vec<f64>, LogError> {
    if !reading_dt_s.is_empty() && reading_dt_s.len() != sensors {
        return Err(bad(
            f,
            format!("$.snapshots[{i}].reading_dt_s"),
            format!("{} offsets", reading_dt_s.len()),
            "none, or one offset per sensor",
        ));
    }
    if let Some((k, dt)) = reading_dt_s
        .iter()
        .enumerate()
        .find(|(_, dt)| !(dt.is_finite() && dt.abs() <= MAX_READING_DT_S))
    {
        return Err(bad(
            f,
            format!("$.snapshots[{i}].reading_dt_s[{k}]"),
            sane::show(*dt),
            "a finite offset within ±60 s of the snapshot's t",
        ));
    }
    Ok(reading_dt_s)
}

/// How far a reading's own time may lie from its snapshot's, seconds.
const MAX_READING_DT_S: f64 = 60.0;
