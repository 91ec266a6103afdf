//! The fields of plain tables, shared by the ring tables ([`super::table`]) and the tables of
//! one reading a line ([`super::firings`]): content lines without the header, times that do
//! not decrease, pose columns, ranges, the `--poses` file and the robot of a table.

use super::assemble::{assemble, sensor_with_max_range, Hardware, RawSnapshot};
use super::error::{at, ImportError};
use super::layout::Layout;
use super::options::{AngleUnit, ImportOptions, NamedBytes};
use super::pose_track::PoseTrack;
use super::sane;
use super::summary::{Format, ImportSummary, Imported};
use super::text::{checked, lines, utf8, Line};
use crate::geometry::Pose;
use crate::units::Units;

/// True for a no-echo mark: `-`, `nan`, `null`, `none`, `inf`.
pub(super) fn is_no_echo(field: &str) -> bool {
    matches!(
        field.to_ascii_lowercase().as_str(),
        "-" | "nan" | "null" | "none" | "inf" | "+inf" | "infinity"
    )
}

/// The content lines, one at a time, the header left out.
pub(super) fn table_lines<'a>(
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

/// Refuses `line` unless it has `expected` fields (`form` names them).
pub(super) fn expect_fields(
    line: &Line,
    expected: usize,
    form: &str,
    file: &str,
) -> Result<(), ImportError> {
    if line.fields.len() != expected {
        return Err(at(
            file,
            format!("line {}", line.number),
            format!("{} fields: expected {expected} ({form})", line.fields.len()),
        ));
    }
    Ok(())
}

/// Field 1 of `line`, the time in seconds, not earlier than `previous` (then set to it).
pub(super) fn time(line: &Line, previous: &mut f64, file: &str) -> Result<f64, ImportError> {
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

/// The pose columns `x y heading` of a line from 0-based field `first`, held to the bounds of
/// [`sane`].
pub(super) fn pose(
    line: &Line,
    first: usize,
    units: Units,
    heading: AngleUnit,
    file: &str,
) -> Result<Pose, ImportError> {
    let length =
        |v: f64, what: &str| sane::length(v, units.metres_per_unit(), what, units.symbol());
    let angle = |v: f64, what: &str| match heading {
        AngleUnit::Degrees => sane::heading_deg(v, what),
        AngleUnit::Radians => sane::heading_rad(v, what),
    };
    Ok(Pose::new(
        units.to_m(checked(line, first, "x", file, length)?),
        units.to_m(checked(line, first + 1, "y", file, length)?),
        heading.to_rad(checked(line, first + 2, "the heading", file, angle)?),
    ))
}

/// The layout's sensor count and the units of a table.
#[derive(Clone, Copy)]
pub(super) struct TableSetup {
    /// Sensors of the layout.
    pub n: usize,
    /// Unit of lengths.
    pub units: Units,
    /// Unit of headings.
    pub heading: AngleUnit,
}

impl Hardware {
    /// The robot of a table: `layout` (the `--layout`), with the maximum range of
    /// `--max-range`.
    pub(super) fn of_table(
        file: &str,
        units: Units,
        layout: &Layout,
        options: &ImportOptions,
    ) -> Hardware {
        Hardware {
            name: file.to_string(),
            units,
            layout: layout.layout.clone(),
            robot_radius_m: layout.robot_radius_m,
            sensor: sensor_with_max_range(Some(layout), options.max_range_m, None),
        }
    }
}

/// Reads the `--poses` file (`t x y heading` lines) into `track`.
pub(super) fn read_poses(
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
        track.push(t, pose(&line, 1, units, heading, pf)?);
    }
    Ok(())
}

/// The `n` ranges of `line` from field `first` (in `units`), metres; `-` (or another
/// no-echo mark) is no echo.
pub(super) fn ranges(
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

/// What a table's reader gathered, for [`finish_table`].
pub(super) struct TableRead {
    /// The snapshots, in time order.
    pub raw: Vec<RawSnapshot>,
    /// The odometry: the table's own, or the `--poses` file's.
    pub track: PoseTrack,
    /// True when `track` came from the `--poses` file.
    pub poses_file_read: bool,
    /// What the table lacks when it has no odometry and no `--poses` file.
    pub without_odometry: &'static str,
    /// The warnings so far.
    pub summary: ImportSummary,
    /// Which table it was.
    pub format: Format,
}

/// The run of a table: its snapshots posed by the odometry, with the layout's robot.
pub(super) fn finish_table(
    read: TableRead,
    file: &str,
    layout: &Layout,
    options: &ImportOptions,
    units: Units,
) -> Result<Imported, ImportError> {
    let TableRead {
        raw,
        track,
        poses_file_read,
        without_odometry,
        mut summary,
        format,
    } = read;
    let what_odometry = match &options.poses {
        Some(p) if poses_file_read => format!(
            "the --poses file {} has no pose lines",
            sane::quote(&p.name)
        ),
        _ => without_odometry.to_string(),
    };
    let run = assemble(
        file,
        raw,
        &track,
        options.fixed_pose,
        &what_odometry,
        Hardware::of_table(file, units, layout, options),
        &mut summary,
    )?;
    Ok(Imported {
        run,
        summary,
        format,
    })
}
