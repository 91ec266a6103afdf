//! Player/Stage text logs (the `writelog` driver of Player 1.x, 2 and 3).
//!
//! # Accepted
//! Lines `time host robot interface index type subtype data...` (Player 2 and 3), `#` starts
//! a comment. Read are:
//! - `sonar` 1:1 (ranges): `range_count r_0 .. r_{n-1}`, metres;
//! - `sonar` 1:2 and 4:1 (geometry): `pose_count` then `x y yaw` per transducer (metres,
//!   radians), or `x y z roll pitch yaw` per transducer (Player 3's 3-D poses);
//! - `position2d` 1:1: `px py pa` (metres, radians), then velocities and stall (ignored).
//!
//! and the Player 1.x lines `time host robot interface index data_time data...`, told apart by
//! the sixth field being a time (it has a decimal point) rather than a message type:
//! - `sonar`: `pose_count` poses (`x y yaw` each) `range_count` ranges;
//! - `position`: `px py pa` then velocities and stall (ignored).
//!
//! Other interfaces (laser, ...), other message types and any sonar or position device after
//! the first one seen are left out (counted in the summary).
//!
//! # Rules
//! - A snapshot is one sonar ranges message at the line's `time` (the first field); its pose
//!   is interpolated from the odometry (see [`super::pose_track`]: the heading on the circle;
//!   within 1 s before the first or after the last odometry the nearest pose is taken, further
//!   away the snapshot is skipped with a reason).
//! - The sensor layout is `--layout` when given, else the file's first geometry message; with
//!   neither the import is refused (the error names `--layout`).
//! - Player drivers report "no echo" as the maximum range: readings at or beyond `--max-range`,
//!   else the layout's `sensor.max_range`, else 5 m (the Pioneer's and Stage's), become no echo.
//! - A sonar or odometry line whose time is earlier than the previous one of the same device is
//!   skipped with a warning (the recording interleaves devices; one stale line should not
//!   lose the run).
//! - No odometry at all: refused unless a fixed pose is given.
//!
//! # Refused (with the file, the line and field, and what was expected)
//! A line with fewer than 7 fields (6 for Player 1.x), text where a number goes, a count that
//! does not match the number of values that follow, a negative range, a range count that
//! differs from the geometry, non-UTF-8 bytes, a last line without a newline (the file was cut
//! short, perhaps in the middle of a number), and values no robot produces (see
//! [`super::sane`]): times beyond ±1e10 s, positions, mounts and ranges beyond 10 km, headings
//! and yaws beyond ±1e5 rad, anything not finite.

use super::assemble::{assemble, sensor_with_max_range, Hardware, Place, RawSnapshot};
use super::error::{at, ImportError};
use super::options::ImportOptions;
use super::pose_track::PoseTrack;
use super::sane;
use super::summary::{Format, ImportSummary, Imported};
use super::text::{checked, count, lines, number, utf8, Line};
use crate::geometry::Pose;
use crate::log::MAX_SENSORS;
use crate::sonar::{SensorLayout, SensorMount};
use crate::units::Units;

/// Player's default maximum sonar range for a Pioneer (and Stage's default ranger), metres.
pub const PLAYER_DEFAULT_MAX_RANGE_M: f64 = 5.0;

/// True when `line` looks like a Player log line (used by content detection).
pub fn looks_like_player_line(fields: &[&str]) -> bool {
    player_line_problem(fields).is_none()
}

/// Why `fields` (a content line) is not a Player log line `time host robot interface index
/// ...`, or `None` when it looks like one.
pub fn player_line_problem(fields: &[&str]) -> Option<String> {
    if fields.len() < 6 {
        return Some(format!("{} fields, fewer than 6", fields.len()));
    }
    let whole = |f: &str| f.parse::<u64>().is_ok();
    let interface = fields[3]
        .chars()
        .next()
        .is_some_and(|c| c.is_ascii_alphabetic())
        && fields[3]
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_');
    let (field, what) = if !fields[0].parse::<f64>().is_ok_and(f64::is_finite) {
        (1, "a time")
    } else if !whole(fields[1]) {
        (2, "a host number")
    } else if !whole(fields[2]) {
        (3, "a robot (port) number")
    } else if !interface {
        (4, "an interface name")
    } else if !whole(fields[4]) {
        (5, "an index")
    } else {
        return None;
    };
    Some(format!(
        "field {field} {:?} is not {what}",
        fields[field - 1]
    ))
}

/// What the lines gave so far, read in one pass (nothing per line is kept but the snapshots).
struct Reading {
    /// The first geometry message: its line and mounts.
    geometry: Option<(usize, Vec<SensorMount>)>,
    /// Later geometry messages that differ from the first.
    geometry_changes: usize,
    track: PoseTrack,
    /// Sonar snapshots in file order (ranges not yet checked against the layout's count).
    raw: Vec<RawSnapshot>,
    last_sonar_t: f64,
}

impl Reading {
    fn geometry(&mut self, line: usize, mounts: Vec<SensorMount>) {
        match &self.geometry {
            None => self.geometry = Some((line, mounts)),
            Some((_, first)) if *first != mounts => self.geometry_changes += 1,
            Some(_) => {}
        }
    }

    fn odometry(&mut self, t: f64, line: usize, pose: Pose, summary: &mut ImportSummary) {
        if !self.track.push(t, pose) {
            summary.skip(
                format!("line {line}"),
                format!("odometry time {t} is earlier than the previous odometry's"),
            );
            summary.warn(format!("line {line}: time goes backwards; line skipped"));
        }
    }

    fn ranges(
        &mut self,
        t: f64,
        line: usize,
        ranges_m: Vec<Option<f64>>,
        summary: &mut ImportSummary,
    ) {
        if t < self.last_sonar_t {
            summary.skip(
                format!("line {line}"),
                format!(
                    "sonar time {t} is earlier than the previous sonar message's {}",
                    self.last_sonar_t
                ),
            );
            summary.warn(format!("line {line}: time goes backwards; line skipped"));
            return;
        }
        self.last_sonar_t = t;
        self.raw.push(RawSnapshot {
            t,
            place: Place::Line(line),
            ranges_m,
            reading_dt_s: Vec::new(),
        });
    }
}

/// The first sonar and position devices seen: interface and index (leading zeros dropped).
/// Only their lines are imported.
#[derive(Default)]
struct Devices {
    sonar: Option<(String, String)>,
    position: Option<(String, String)>,
}

impl Devices {
    /// True when `interface:index` is the first device of its kind seen (it becomes it when
    /// none was); a line of another device is skipped.
    fn first(
        &mut self,
        is_sonar: bool,
        interface: &str,
        index: &str,
        line: &Line,
        summary: &mut ImportSummary,
    ) -> bool {
        let slot = if is_sonar {
            &mut self.sonar
        } else {
            &mut self.position
        };
        match slot {
            None => *slot = Some((interface.to_string(), index.to_string())),
            Some((i, k)) if i != interface || k != index => {
                summary.skip(
                    format!("line {}", line.number),
                    format!(
                        "{interface}:{index}: only the first device seen, {i}:{k}, is imported"
                    ),
                );
                return false;
            }
            Some(_) => {}
        }
        true
    }
}

/// Imports a Player/Stage text log. `file` names it in errors. Pure.
pub fn import_player(
    bytes: &[u8],
    file: &str,
    options: &ImportOptions,
) -> Result<Imported, ImportError> {
    options.check()?;
    let text = utf8(bytes, file)?;
    let mut summary = ImportSummary::default();
    let mut reading = Reading {
        geometry: None,
        geometry_changes: 0,
        track: PoseTrack::default(),
        raw: Vec::new(),
        last_sonar_t: f64::NEG_INFINITY,
    };
    let mut devices = Devices::default();
    let mut ignored = 0usize;
    for line in lines(text, false, file) {
        let line = line?;
        let f = &line.fields;
        if !looks_like_player_line(f) {
            return Err(at(
                file,
                format!("line {}", line.number),
                format!(
                    "expected `time host robot interface index type subtype data...` (numbers, an interface name, numbers), found {:?}",
                    super::text::clip(&f.join(" "))
                ),
            ));
        }
        let t = checked(&line, 0, "the time in seconds", file, sane::time)?;
        let v1 = f[5].contains(['.', 'e', 'E']);
        let interface = f[3];
        let index = f[4].trim_start_matches('0');
        let is_sonar = interface == "sonar";
        let is_position = interface == "position2d" || (v1 && interface == "position");
        if !is_sonar && !is_position {
            ignored += 1;
            continue;
        }
        if !devices.first(is_sonar, interface, index, &line, &mut summary) {
            continue;
        }
        let message = Message {
            line: &line,
            t,
            is_sonar,
        };
        if v1 {
            message.read_v1(&mut reading, &mut summary, file)?;
        } else if !message.read(&mut reading, &mut summary, file)? {
            ignored += 1;
        }
    }
    if ignored > 0 {
        summary.warn(format!(
            "{ignored} lines of other interfaces or message types were left out"
        ));
    }
    build(reading, file, options, summary)
}

/// A line of the first sonar or position device.
struct Message<'l, 'a> {
    line: &'l Line<'a>,
    /// Its time, seconds.
    t: f64,
    /// A sonar's, else a position's.
    is_sonar: bool,
}

impl Message<'_, '_> {
    /// Reads a line of Player 1 (`data time` in field 5): a sonar's geometry and ranges in
    /// one, or a position.
    fn read_v1(
        &self,
        reading: &mut Reading,
        summary: &mut ImportSummary,
        file: &str,
    ) -> Result<(), ImportError> {
        let (line, t) = (self.line, self.t);
        number(line, 5, "the data time in seconds", file)?;
        if self.is_sonar {
            let n = count(line, 6, "the transducer pose count", MAX_SENSORS, file)?;
            let mounts = poses(line, 7, n, 3, file)?;
            let at_ranges = 7 + 3 * n;
            let m = count(line, at_ranges, "the range count", MAX_SENSORS, file)?;
            let ranges = values(line, at_ranges, m, file)?;
            if line.fields.len() != at_ranges + 1 + m {
                return Err(field_count(
                    line,
                    at_ranges + 1 + m,
                    "data time, pose count, poses, range count, ranges",
                    file,
                ));
            }
            reading.geometry(line.number, mounts);
            reading.ranges(t, line.number, ranges, summary);
        } else {
            let p = pose(line, 6, file)?;
            reading.odometry(t, line.number, p, summary);
        }
        Ok(())
    }

    /// Reads a line of Player 2 or later (message type and subtype in fields 5 and 6):
    /// sonar ranges, sonar geometry, or a position. False for a message of another type
    /// (left out).
    fn read(
        &self,
        reading: &mut Reading,
        summary: &mut ImportSummary,
        file: &str,
    ) -> Result<bool, ImportError> {
        let (line, t, f) = (self.line, self.t, &self.line.fields);
        if f.len() < 7 {
            return Err(at(
                file,
                format!("line {}", line.number),
                format!(
                    "{} fields: expected at least 7, `time host robot interface index type subtype`",
                    f.len()
                ),
            ));
        }
        let kind = (
            count(line, 5, "the message type", 255, file)?,
            count(line, 6, "the message subtype", 255, file)?,
        );
        match (self.is_sonar, kind) {
            (true, (1, 1)) => {
                let n = count(line, 7, "the range count", MAX_SENSORS, file)?;
                let ranges = values(line, 7, n, file)?;
                if f.len() != 8 + n {
                    return Err(field_count(
                        line,
                        8 + n,
                        "the range count then the ranges",
                        file,
                    ));
                }
                reading.ranges(t, line.number, ranges, summary);
            }
            (true, (1, 2)) | (true, (4, 1)) => {
                let n = count(line, 7, "the transducer pose count", MAX_SENSORS, file)?;
                let rest = f.len() - 8;
                let per = if rest == 6 * n && n > 0 { 6 } else { 3 };
                let mounts = poses(line, 8, n, per, file)?;
                if 8 + per * n != f.len() {
                    return Err(field_count(
                        line,
                        8 + per * n,
                        "pose count then x y yaw per transducer",
                        file,
                    ));
                }
                reading.geometry(line.number, mounts);
            }
            (false, (1, 1)) => {
                let p = pose(line, 7, file)?;
                reading.odometry(t, line.number, p, summary);
            }
            _ => return Ok(false),
        }
        Ok(true)
    }
}

fn field_count(line: &Line, expected: usize, what: &str, file: &str) -> ImportError {
    at(
        file,
        format!("line {}", line.number),
        format!("{} fields: expected {expected} ({what})", line.fields.len()),
    )
}

/// `n` values after the count at `count_at`; for Player 2/3 ranges the line must end there.
fn values(
    line: &Line,
    count_at: usize,
    n: usize,
    file: &str,
) -> Result<Vec<Option<f64>>, ImportError> {
    let end = count_at + 1 + n;
    if line.fields.len() < end {
        return Err(field_count(
            line,
            end,
            &format!("the count {n} then {n} ranges"),
            file,
        ));
    }
    let mut out = Vec::with_capacity(n);
    for i in count_at + 1..end {
        let v = checked(line, i, "a range in metres", file, |v, what| {
            sane::length(v, 1.0, what, "m")
        })?;
        if v < 0.0 {
            return Err(at(
                file,
                format!("line {}, field {}", line.number, i + 1),
                format!("range {v} is negative: expected a range of at least 0 m"),
            ));
        }
        out.push(Some(v));
    }
    Ok(out)
}

fn poses(
    line: &Line,
    from: usize,
    n: usize,
    per: usize,
    file: &str,
) -> Result<Vec<SensorMount>, ImportError> {
    if line.fields.len() < from + per * n {
        return Err(field_count(
            line,
            from + per * n,
            &format!("the pose count {n} then x y yaw per transducer"),
            file,
        ));
    }
    (0..n)
        .map(|k| {
            let i = from + per * k;
            Ok(SensorMount {
                x_m: checked(line, i, "a transducer x in metres", file, metres)?,
                y_m: checked(line, i + 1, "a transducer y in metres", file, metres)?,
                heading_rad: checked(
                    line,
                    i + per - 1,
                    "a transducer yaw in radians",
                    file,
                    sane::heading_rad,
                )?,
            })
        })
        .collect()
}

fn pose(line: &Line, from: usize, file: &str) -> Result<Pose, ImportError> {
    Ok(Pose::new(
        checked(line, from, "px in metres", file, metres)?,
        checked(line, from + 1, "py in metres", file, metres)?,
        checked(line, from + 2, "pa in radians", file, sane::heading_rad)?,
    ))
}

/// A length in metres within the bounds of [`sane`].
fn metres(v: f64, what: &str) -> Result<f64, String> {
    sane::length(v, 1.0, what, "m")
}

fn build(
    reading: Reading,
    file: &str,
    options: &ImportOptions,
    mut summary: ImportSummary,
) -> Result<Imported, ImportError> {
    let Reading {
        geometry,
        geometry_changes,
        track,
        raw,
        ..
    } = reading;
    let (layout, layout_from) = match (&options.layout, geometry) {
        (Some(l), _) => (l.layout.clone(), "the --layout file".to_string()),
        (None, Some((line, mounts))) => {
            if mounts.is_empty() {
                return Err(at(
                    file,
                    format!("line {line}"),
                    "the sonar geometry has no transducer: expected at least one",
                ));
            }
            (
                SensorLayout { mounts },
                format!("the geometry on line {line}"),
            )
        }
        (None, None) => {
            return Err(ImportError::NeedsLayout {
                file: file.to_string(),
                what: "the log has no sonar geometry (sonar 1:2 or 4:1 lines)".to_string(),
            })
        }
    };
    if let Some(s) = raw.iter().find(|s| s.ranges_m.len() != layout.len()) {
        return Err(at(
            file,
            s.place.to_string(),
            format!(
                "{} ranges: expected one per sensor, {} ({layout_from})",
                s.ranges_m.len(),
                layout.len()
            ),
        ));
    }
    if options.layout.is_none() && geometry_changes > 0 {
        summary.warn(format!(
            "{geometry_changes} later geometry messages differ from the first; the first is used"
        ));
    }
    let sensor = sensor_with_max_range(
        options.layout.as_ref(),
        options.max_range_m,
        Some(PLAYER_DEFAULT_MAX_RANGE_M),
    );
    let hw = Hardware {
        name: file.to_string(),
        units: options.units.unwrap_or(Units::Metres),
        robot_radius_m: options.layout.as_ref().and_then(|l| l.robot_radius_m),
        layout,
        sensor,
    };
    let run = assemble(
        file,
        raw,
        &track,
        options.fixed_pose,
        "no position2d 1:1 or Player 1.x position lines",
        hw,
        &mut summary,
    )?;
    Ok(Imported {
        run,
        summary,
        format: Format::Player,
    })
}
