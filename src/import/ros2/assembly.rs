//! The run from what the messages gave: the sensors, the readings kept, the firing cycles
//! and the sensor's ranges and beam.

use super::collect::Collected;
use super::messages::{place, RangeMsg};
use super::sensors::{layout, Keys, SensorOf};
use crate::import::assemble::{assemble, sensor_with_max_range, Hardware, Place};
use crate::import::cycles::{cut_into_cycles, Reading};
use crate::import::error::ImportError;
use crate::import::options::{ImportOptions, DEFAULT_WINDOW_S};
use crate::import::sane;
use crate::import::summary::{Format, ImportSummary, Imported};
use crate::units::Units;

/// What the readings kept say of the sensor: the largest `max_range`, the smallest
/// `min_range` and the first field of view given.
struct RangeLimits {
    largest_max: f64,
    smallest_min: f64,
    fov: Option<f64>,
}

/// The sensors, the firing cycles and the run from what the messages gave.
pub(super) fn assemble_mcap(
    collected: Collected,
    file: &str,
    options: &ImportOptions,
    mut summary: ImportSummary,
) -> Result<Imported, ImportError> {
    let Collected {
        ranges,
        topics,
        frames,
        track,
        odometry_frame,
        static_tf,
    } = collected;
    if ranges.is_empty() {
        return Err(ImportError::NoSnapshots {
            file: file.to_string(),
            why: "no sensor_msgs/msg/Range message in CDR".to_string(),
        });
    }
    let keys = Keys {
        frames: &frames.names,
        topics: &topics,
    };
    let distinct = keys.distinct(&ranges, file)?;
    let (layout, index_of) = layout(
        &distinct,
        options.layout.as_ref(),
        &static_tf,
        odometry_frame.as_deref(),
        file,
    )?;
    let n = layout.len();
    let sensor_of = SensorOf::new(keys, options.layout.as_ref(), &index_of);
    let (mut readings, limits) = readings(&ranges, keys, &sensor_of, n, &mut summary);
    drop(sensor_of);
    drop(ranges);
    // A stable sort: readings at one time keep their message order.
    readings.sort_by(|a, b| a.t.total_cmp(&b.t));
    let raw = cut_into_cycles(
        &readings,
        n,
        options.window_s.unwrap_or(DEFAULT_WINDOW_S),
        file,
        &mut summary,
    )?;
    let hw = Hardware {
        name: file.to_string(),
        units: options.units.unwrap_or(Units::Metres),
        robot_radius_m: options.layout.as_ref().and_then(|l| l.robot_radius_m),
        layout,
        sensor: sensor_of_messages(options, &limits),
    };
    let run = assemble(
        file,
        raw,
        &track,
        options.fixed_pose,
        "no nav_msgs/msg/Odometry messages in CDR",
        hw,
        &mut summary,
    )?;
    Ok(Imported {
        run,
        summary,
        format: Format::Mcap,
    })
}

/// The sensor model: the layout's when one is given, else the messages' own limits (largest
/// max range, smallest min range, field of view), with `--max-range` over both.
fn sensor_of_messages(options: &ImportOptions, limits: &RangeLimits) -> crate::sonar::SensorSpec {
    let default_max = (limits.largest_max > 0.0).then_some(limits.largest_max);
    let mut sensor =
        sensor_with_max_range(options.layout.as_ref(), options.max_range_m, default_max);
    if options.layout.is_none() {
        if limits.smallest_min.is_finite() {
            sensor.min_range_m = limits.smallest_min;
        }
        if let Some(f) = limits.fov {
            sensor.beam_width_rad = f;
        }
    }
    sensor
}

/// The readings of `ranges` (in message order) with a sensor among the `n` of the layout and
/// a time not before that sensor's previous reading; the others are skipped (with a warning
/// for a time going backwards). A range outside its message's limits is no echo.
fn readings(
    ranges: &[RangeMsg],
    keys: Keys,
    sensor_of: &SensorOf,
    n: usize,
    summary: &mut ImportSummary,
) -> (Vec<Reading>, RangeLimits) {
    let mut readings = Vec::with_capacity(ranges.len());
    let mut last_t = vec![f64::NEG_INFINITY; n];
    let mut limits = RangeLimits {
        largest_max: 0.0,
        smallest_min: f64::INFINITY,
        fov: None,
    };
    for m in ranges {
        let topic = keys.topic(m);
        let Some(k) = sensor_of.get(m) else {
            summary.skip(
                place(m.index, topic),
                format!(
                    "neither frame {:?} nor the topic is in the layout's frames",
                    sane::quote(keys.frame(m))
                ),
            );
            continue;
        };
        if k >= n {
            summary.skip(
                place(m.index, topic),
                format!("sensor index {k} is not in the layout"),
            );
            continue;
        }
        if m.t < last_t[k] {
            summary.skip(
                place(m.index, topic),
                format!(
                    "time {} is earlier than the previous reading of sensor {k}",
                    m.t
                ),
            );
            summary.warn(format!(
                "{}: time goes backwards; message skipped",
                place(m.index, topic)
            ));
            continue;
        }
        last_t[k] = m.t;
        limits.largest_max = limits.largest_max.max(m.max as f64);
        limits.smallest_min = limits.smallest_min.min(m.min as f64);
        if m.fov > 0.0 {
            limits.fov.get_or_insert(m.fov as f64);
        }
        let echo = m.range.is_finite() && m.range >= m.min && m.range <= m.max;
        if !echo {
            summary.turned_no_echo += 1;
        }
        readings.push(Reading {
            t: m.t,
            sensor: k,
            range_m: echo.then_some(m.range as f64),
            place: Place::Cycle(m.index),
        });
    }
    (readings, limits)
}
