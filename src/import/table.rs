//! Plain tables of numbers from lab rigs.
//!
//! # Accepted
//! Fields separated by whitespace and/or commas, `#` comments, blank lines; a first line that
//! does not start with a number is a header and is left out. Either
//! - one file with both, `t x y heading r_0 .. r_{n-1}` per line, or
//! - a ranges file `t r_0 .. r_{n-1}` and a poses file `t x y heading` (`--poses`): each
//!   snapshot's pose is interpolated in the poses (see [`super::pose_track`]).
//!
//! The form is read off the first line's field count (`4 + n` or `1 + n`).
//!
//! `n` is the number of sensors of the layout (`--layout`, required). Lengths are in `--units`
//! (default metres), headings in `--heading-unit` (default degrees). A range written `-`,
//! `nan`, `null`, `none` or `inf` is no echo; readings at or beyond the maximum range
//! (`--max-range`, else the layout's) become no echo. Without a poses table, `--fixed-pose`
//! gives every snapshot the same pose.
//!
//! # Refused (with the file, the line and what was expected)
//! A line whose field count is not `1 + n`, `4 + n` or `4` as the form requires, text where a
//! number goes, a negative range, time going backwards (a table is written by one program in
//! order: a decreasing time is an error, not a warning), no layout, a last line without a
//! newline (the file was cut short), and values no robot produces (see [`super::sane`]):
//! times beyond ±1e10 s, positions and ranges beyond 10 km, headings beyond ±1e5 rad.

use super::assemble::{assemble, sensor_with_max_range, Hardware, Place, RawSnapshot};
use super::error::{at, ImportError};
use super::options::{AngleUnit, ImportOptions, NamedBytes};
use super::pose_track::PoseTrack;
use super::sane;
use super::summary::{Format, ImportSummary, Imported};
use super::text::{checked, lines, utf8, Line};
use crate::geometry::Pose;
use crate::units::Units;

/// True when the first content line (after an optional header) is all numbers: detection.
pub fn looks_like_table(fields: &[&str]) -> bool {
    !fields.is_empty() && table_line_problem(fields).is_none()
}

/// Why `fields` (a content line) is not a line of a table, or `None` when every field is a
/// number or a no-echo mark.
pub fn table_line_problem(fields: &[&str]) -> Option<String> {
    let (i, field) = fields
        .iter()
        .enumerate()
        .find(|(_, f)| f.parse::<f64>().is_err() && !is_no_echo(f))?;
    Some(format!("field {} {field:?} is not a number", i + 1))
}

fn is_no_echo(field: &str) -> bool {
    matches!(
        field.to_ascii_lowercase().as_str(),
        "-" | "nan" | "null" | "none" | "inf" | "+inf" | "infinity"
    )
}

/// The content lines, one at a time, the header left out.
fn table_lines<'a>(
    text: &'a str,
    file: &'a str,
) -> impl Iterator<Item = Result<Line<'a>, ImportError>> + 'a {
    lines(text, true, file)
        .enumerate()
        .filter(|(i, l)| {
            !(*i == 0
                && l.as_ref()
                    .is_ok_and(|l| l.fields[0].parse::<f64>().is_err()))
        })
        .map(|(_, l)| l)
}

fn expect_fields(line: &Line, expected: usize, form: &str, file: &str) -> Result<(), ImportError> {
    if line.fields.len() != expected {
        return Err(at(
            file,
            format!("line {}", line.number),
            format!("{} fields: expected {expected} ({form})", line.fields.len()),
        ));
    }
    Ok(())
}

fn time(line: &Line, previous: &mut f64, file: &str) -> Result<f64, ImportError> {
    let t = checked(line, 0, "the time in seconds", file, sane::time)?;
    if t < *previous {
        return Err(at(
            file,
            format!("line {}, field 1", line.number),
            format!("time {t} is earlier than the previous line's {previous}: expected times that do not decrease"),
        ));
    }
    *previous = t;
    Ok(t)
}

/// The pose columns `x y heading` (fields 2 to 4) of a line, held to the bounds of [`sane`].
fn pose(line: &Line, units: Units, heading: AngleUnit, file: &str) -> Result<Pose, ImportError> {
    let length =
        |v: f64, what: &str| sane::length(v, units.metres_per_unit(), what, units.symbol());
    let angle = |v: f64, what: &str| match heading {
        AngleUnit::Degrees => sane::heading_deg(v, what),
        AngleUnit::Radians => sane::heading_rad(v, what),
    };
    Ok(Pose::new(
        units.to_m(checked(line, 1, "x", file, length)?),
        units.to_m(checked(line, 2, "y", file, length)?),
        heading.to_rad(checked(line, 3, "the heading", file, angle)?),
    ))
}

/// Imports a table (and the poses table of `options.poses`). `file` names it in errors. Pure.
pub fn import_table(
    bytes: &[u8],
    file: &str,
    options: &ImportOptions,
) -> Result<Imported, ImportError> {
    options.check()?;
    let Some(layout) = &options.layout else {
        return Err(ImportError::NeedsLayout {
            file: file.to_string(),
            what: "a table has no sensor geometry".to_string(),
        });
    };
    let n = layout.layout.len();
    let units = options.units.unwrap_or(Units::Metres);
    let heading = options.heading;
    let text = utf8(bytes, file)?;
    let mut summary = ImportSummary::default();
    let mut track = PoseTrack::default();
    let mut body = table_lines(text, file).peekable();
    // The form is read off the first line: `1 + n` fields is ranges only, `4 + n` has poses.
    let separate = matches!(body.peek(), Some(Ok(l)) if l.fields.len() == 1 + n);
    if !separate && options.poses.is_some() {
        summary.warn("--poses is ignored: the table has its own pose columns");
    }
    if let Some(poses) = options.poses.as_ref().filter(|_| separate) {
        read_poses(poses, units, heading, &mut track)?;
    }
    let first_range = if separate { 1 } else { 4 };
    let form = if separate {
        format!("t then {n} ranges, one per sensor of the layout, as on the first line")
    } else {
        format!("t x y heading then {n} ranges, one per sensor of the layout (or t then {n} ranges, with the poses in --poses)")
    };
    let mut raw = Vec::new();
    let mut previous = f64::NEG_INFINITY;
    for line in body {
        let line = line?;
        expect_fields(&line, first_range + n, &form, file)?;
        let t = time(&line, &mut previous, file)?;
        if !separate {
            track.push(t, pose(&line, units, heading, file)?);
        }
        let ranges_m = ranges(&line, first_range, n, units, file)?;
        raw.push(RawSnapshot {
            t,
            place: Place::Line(line.number),
            ranges_m,
        });
    }
    let hw = Hardware {
        name: file.to_string(),
        units,
        layout: layout.layout.clone(),
        robot_radius_m: layout.robot_radius_m,
        sensor: sensor_with_max_range(Some(layout), options.max_range_m, None),
    };
    let what_odometry = match &options.poses {
        Some(p) if separate => format!(
            "the --poses file {} has no pose lines",
            sane::quote(&p.name)
        ),
        _ => "the table has no pose columns and no --poses file".to_string(),
    };
    let run = assemble(
        file,
        raw,
        &track,
        options.fixed_pose,
        &what_odometry,
        hw,
        &mut summary,
    )?;
    Ok(Imported {
        run,
        summary,
        format: Format::Table,
    })
}

/// Reads the `--poses` file (`t x y heading` lines) into `track`.
fn read_poses(
    poses: &NamedBytes,
    units: Units,
    heading: AngleUnit,
    track: &mut PoseTrack,
) -> Result<(), ImportError> {
    let pf = poses.name.as_str();
    let mut previous = f64::NEG_INFINITY;
    for line in table_lines(utf8(&poses.bytes, pf)?, pf) {
        let line = line?;
        expect_fields(&line, 4, "t x y heading", pf)?;
        let t = time(&line, &mut previous, pf)?;
        track.push(t, pose(&line, units, heading, pf)?);
    }
    Ok(())
}

/// The `n` ranges of `line` from field `first` (in `units`), metres; `-` (or another
/// no-echo mark) is no echo.
fn ranges(
    line: &Line,
    first: usize,
    n: usize,
    units: Units,
    file: &str,
) -> Result<Vec<Option<f64>>, ImportError> {
    let mut ranges_m = Vec::with_capacity(n);
    for i in first..first + n {
        if is_no_echo(line.fields[i]) {
            ranges_m.push(None);
            continue;
        }
        let v = checked(line, i, "a range, or - for no echo", file, |v, what| {
            sane::length(v, units.metres_per_unit(), what, units.symbol())
        })?;
        if v < 0.0 {
            return Err(at(
                file,
                format!("line {}, field {}", line.number, i + 1),
                format!("range {v} is negative: expected a range of at least 0"),
            ));
        }
        ranges_m.push(Some(units.to_m(v)));
    }
    Ok(ranges_m)
}
