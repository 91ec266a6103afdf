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

use super::assemble::{Place, RawSnapshot};
use super::error::ImportError;
use super::firings::import_firings;
use super::options::{ImportOptions, TableForm};
use super::pose_track::PoseTrack;
use super::summary::{Format, ImportSummary, Imported};
use super::table_fields::{
    expect_fields, finish_table, is_no_echo, pose, ranges, read_poses, table_lines, time,
    TableRead, TableSetup,
};
use super::text::{lines, utf8};
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

/// Lines looked at to tell a ring table from a firing table.
const LINES_LOOKED_AT: usize = 20;

/// Whether `text` is a table of one reading a line: `--table` says so, or (automatic) a
/// header names a `sensor` column, or the first lines are not all of one ring form (`1 + n`
/// or `4 + n` fields) and all of a firing form (3, 4 or 6 fields, not all odometry lines).
fn is_firing_table(text: &str, n: usize, form: TableForm, file: &str) -> bool {
    match form {
        TableForm::Ring => return false,
        TableForm::Firings => return true,
        TableForm::Auto => {}
    }
    let mut content = lines(text, true, file).map_while(Result::ok);
    let Some(first) = content.next() else {
        return false;
    };
    let header = first.fields[0].parse::<f64>().is_err();
    if header
        && first
            .fields
            .iter()
            .any(|f| f.to_ascii_lowercase().starts_with("sensor"))
    {
        return true;
    }
    let counts: Vec<usize> = std::iter::once(first)
        .filter(|l| l.fields[0].parse::<f64>().is_ok())
        .chain(content)
        .take(LINES_LOOKED_AT)
        .map(|l| l.fields.len())
        .collect();
    let one_ring_form = counts.windows(2).all(|w| w[0] == w[1])
        && matches!(counts.first(), Some(&c) if c == 1 + n || c == 4 + n);
    !one_ring_form
        && counts.iter().all(|c| matches!(c, 3 | 4 | 6))
        && counts.iter().any(|&c| c != 4)
}

/// Imports a table (and the poses table of `options.poses`): a ring a line, or one reading a
/// line (`super::firings`). `file` names it in errors. Pure.
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
    let setup = TableSetup { n, units, heading };
    if is_firing_table(text, n, options.table, file) {
        import_firings(text, file, layout, options, setup)
    } else {
        import_rings(text, file, layout, options, setup)
    }
}

/// A table of one firing cycle a line: `t x y heading` then a range per sensor, or `t` then
/// the ranges with the poses in `--poses`.
fn import_rings(
    text: &str,
    file: &str,
    layout: &super::layout::Layout,
    options: &ImportOptions,
    setup: TableSetup,
) -> Result<Imported, ImportError> {
    let TableSetup { n, units, heading } = setup;
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
        format!("t x y heading then {n} ranges, one per sensor of the layout (or t then {n} ranges, with the poses in --poses; or one reading a line, t sensor range [x y heading], with --table firings)")
    };
    let mut raw = Vec::new();
    let mut previous = f64::NEG_INFINITY;
    for line in body {
        let line = line?;
        expect_fields(&line, first_range + n, &form, file)?;
        let t = time(&line, &mut previous, file)?;
        if !separate {
            track.push(t, pose(&line, 1, units, heading, file)?);
        }
        let ranges_m = ranges(&line, first_range, n, units, file)?;
        raw.push(RawSnapshot {
            t,
            place: Place::Line(line.number),
            ranges_m,
            reading_dt_s: Vec::new(),
        });
    }
    let read = TableRead {
        raw,
        track,
        poses_file_read: separate && options.poses.is_some(),
        without_odometry: "the table has no pose columns and no --poses file",
        summary,
        format: Format::Table,
    };
    finish_table(read, file, layout, options, units)
}
