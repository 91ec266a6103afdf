//! Tables of one reading a line, from robots whose sonars fire in sequence (a Pioneer's sonars
//! a few at a time, one ultrasonic sensor on a servo, a time-of-flight array).
//!
//! # Accepted
//! The table conventions of [`super::table`] (separators, comments, a header line, units,
//! no-echo marks, `--max-range`, `--fixed-pose`), with lines of three kinds told apart by
//! their field count:
//! - `t sensor range`: a firing; its pose comes from the odometry (the odometry lines, else
//!   the `--poses` file `t x y heading`);
//! - `t sensor range x y heading`: a firing with the odometry pose of its moment (which
//!   joins the odometry);
//! - `t x y heading`: an odometry update.
//!
//! `sensor` is the 0-based index of the sensor in the layout (`--layout`, required). The
//! firings are cut into firing cycles as MCAP readings are ([`super::cycles`]): a cycle ends
//! when a sensor repeats or a reading comes more than `--window` (default
//! [`super::options::DEFAULT_FIRINGS_WINDOW_S`]) after the cycle's first. Each snapshot's pose
//! is the odometry's at the mean of its readings' times, and each reading keeps its own
//! moment (`reading_dt_s`), so the engine converts it with its own pose (paper §3.1).
//!
//! # Refused (with the file, the line and field, and what was expected)
//! Another field count, a sensor index that is not a whole number below the layout's sensor
//! count, firings (or odometry lines) whose time decreases, and everything a ring table
//! refuses ([`super::table`]).

use super::assemble::Place;
use super::cycles::{cut_into_cycles, Reading};
use super::error::{at, ImportError};
use super::layout::Layout;
use super::options::{ImportOptions, DEFAULT_FIRINGS_WINDOW_S};
use super::pose_track::PoseTrack;
use super::summary::{Format, ImportSummary, Imported};
use super::table_fields::{
    finish_table, pose, ranges, read_poses, table_lines, time, TableRead, TableSetup,
};
use super::text::count;

/// What each field count of a firing table means, for errors.
const FORMS: &str = "t sensor range, t sensor range x y heading, or an odometry line t x y heading";

/// Imports a table of one reading a line (see the module documentation). Pure.
pub(crate) fn import_firings(
    text: &str,
    file: &str,
    layout: &Layout,
    options: &ImportOptions,
    setup: TableSetup,
) -> Result<Imported, ImportError> {
    let TableSetup { n, units, heading } = setup;
    let mut summary = ImportSummary::default();
    let mut track = PoseTrack::default();
    let readings = read_lines(text, file, setup, &mut track)?;
    let own_odometry = !track.is_empty();
    match &options.poses {
        Some(_) if own_odometry => {
            summary.warn("--poses is ignored: the table has its own poses");
        }
        Some(poses) => read_poses(poses, units, heading, &mut track)?,
        None => {}
    }
    let window_s = options.window_s.unwrap_or(DEFAULT_FIRINGS_WINDOW_S);
    let raw = cut_into_cycles(&readings, n, window_s, file, &mut summary)?;
    drop(readings);
    let read = TableRead {
        raw,
        track,
        poses_file_read: options.poses.is_some() && !own_odometry,
        without_odometry: "the table has no pose columns, no odometry lines and no --poses file",
        summary,
        format: Format::FiringTable,
    };
    finish_table(read, file, layout, options, units)
}

/// The firings of `text` in file order; odometry (its lines and the firings' pose columns)
/// goes to `track`.
fn read_lines(
    text: &str,
    file: &str,
    setup: TableSetup,
    track: &mut PoseTrack,
) -> Result<Vec<Reading>, ImportError> {
    let TableSetup { n, units, heading } = setup;
    let mut readings = Vec::new();
    let (mut previous_firing, mut previous_odometry) = (f64::NEG_INFINITY, f64::NEG_INFINITY);
    for line in table_lines(text, file) {
        let line = line?;
        match line.fields.len() {
            4 => {
                let t = time(&line, &mut previous_odometry, file)?;
                track.push(t, pose(&line, 1, units, heading, file)?);
            }
            3 | 6 => {
                let t = time(&line, &mut previous_firing, file)?;
                let sensor = count(&line, 1, "a sensor index", n.saturating_sub(1), file)?;
                let range_m = ranges(&line, 2, 1, units, file)?[0];
                if line.fields.len() == 6 {
                    let p = pose(&line, 3, units, heading, file)?;
                    if !track.push(t, p) {
                        return Err(at(
                            file,
                            format!("line {}, field 1", line.number),
                            format!("time {t} is earlier than the last odometry line's: expected a firing's pose to come in time order with the odometry"),
                        ));
                    }
                    previous_odometry = t;
                }
                readings.push(Reading {
                    t,
                    sensor,
                    range_m,
                    place: Place::Line(line.number),
                });
            }
            k => {
                return Err(at(
                    file,
                    format!("line {}", line.number),
                    format!("{k} fields: expected {FORMS}"),
                ))
            }
        }
    }
    Ok(readings)
}
