//! ROS 2 recordings in MCAP files (read with the `mcap` crate; CDR decoded by hand, see
//! [`super::cdr`]).
//!
//! # Accepted
//! Messages with CDR encoding whose schema is
//! - `sensor_msgs/msg/Range`: one sonar reading (one topic or one `frame_id` per sonar);
//! - `nav_msgs/msg/Odometry`: the robot pose (x, y and the yaw of the quaternion);
//! - `tf2_msgs/msg/TFMessage` on `/tf_static`: the sonar mounts (chains of static transforms
//!   from the robot's frame, the odometry's `child_frame_id`, else `base_link`, to each
//!   sonar's `frame_id`; x, y and yaw are kept).
//!
//! Everything else is left out (counted in the summary). Times are the header stamps (the log
//! time when a stamp is zero).
//!
//! # Rules
//! - Sensors: with `--layout`, its `frames` map (frame id, else topic → index) decides; a layout
//!   without `frames` takes the distinct frame ids (or topics, for empty frame ids) in natural
//!   order (`sonar_2` before `sonar_10`) as sensors 0, 1, ...; without `--layout` the sonars
//!   are those frame ids in natural order and their mounts come from `/tf_static`. With
//!   neither, the import is refused and the error names `--layout`.
//! - A reading outside `[min_range, max_range]` of its message, or not finite, is no echo
//!   (REP 117), as is one at or beyond `--max-range` (default: the layout's, else the largest
//!   `max_range` of the messages).
//! - Snapshots: the readings, sorted by time, are cut into firing cycles of the ring. A cycle
//!   starts at a reading and takes the following ones until a sensor repeats or a reading comes
//!   more than the window (`--window`, default 0.1 s) after the cycle's first; then the next
//!   cycle starts. The snapshot's time is the mean of its readings' times, its pose interpolated
//!   there; a sensor silent in a cycle is no echo (counted in a warning).
//! - A reading or odometry message earlier than the previous one of the same sensor or odometry
//!   topic is skipped with a warning. No odometry: refused unless a fixed pose is given.
//!
//! # Refused (with the file, the message index, topic and byte offset, and what was expected)
//! Bytes that are not MCAP or a record the `mcap` crate cannot read (the error says after
//! which message), a Range/Odometry/TFMessage that is not CDR of its type (too short, a string
//! running past the end, an unknown encapsulation).

use super::assemble::{assemble, sensor_with_max_range, Hardware, RawSnapshot};
use super::cdr::{header, yaw_of, CdrError, CdrReader};
use super::error::{at, ImportError};
use super::options::ImportOptions;
use super::pose_track::PoseTrack;
use super::summary::{Format, ImportSummary, Imported};
use crate::geometry::Pose;
use crate::log::MAX_SENSORS;
use crate::sonar::{SensorLayout, SensorMount};
use crate::units::Units;
use std::collections::BTreeMap;

/// The first bytes of every MCAP file.
pub const MCAP_MAGIC: &[u8] = b"\x89MCAP0\r\n";

struct RangeMsg {
    index: usize,
    topic: String,
    t: f64,
    frame: String,
    fov: f64,
    min: f64,
    max: f64,
    range: f64,
}

/// A 2-D rigid transform (x, y, yaw).
#[derive(Clone, Copy)]
struct Tf(f64, f64, f64);

fn compose(a: Tf, b: Tf) -> Tf {
    let (s, c) = a.2.sin_cos();
    Tf(a.0 + c * b.0 - s * b.1, a.1 + s * b.0 + c * b.1, a.2 + b.2)
}

fn place(index: usize, topic: &str) -> String {
    format!("MCAP message {index} (topic {topic})")
}

fn cdr_error(file: &str, index: usize, topic: &str, e: CdrError) -> ImportError {
    at(
        file,
        format!("{}, byte {}", place(index, topic), e.offset),
        e.message,
    )
}

/// Natural order: digit runs compare as numbers (`sonar_2` < `sonar_10`).
fn natural_key(s: &str) -> Vec<(u8, u128, String)> {
    let mut out = Vec::new();
    let mut rest = s;
    while !rest.is_empty() {
        let digits = rest.len() - rest.trim_start_matches(|c: char| c.is_ascii_digit()).len();
        if digits > 0 {
            let (d, r) = rest.split_at(digits);
            out.push((0, d.parse().unwrap_or(u128::MAX), d.to_string()));
            rest = r;
        } else {
            let other = rest.len() - rest.trim_start_matches(|c: char| !c.is_ascii_digit()).len();
            let (t, r) = rest.split_at(other);
            out.push((1, 0, t.to_string()));
            rest = r;
        }
    }
    out
}

/// Imports a ROS 2 MCAP recording. `file` names it in errors. Pure.
pub fn import_mcap(
    bytes: &[u8],
    file: &str,
    options: &ImportOptions,
) -> Result<Imported, ImportError> {
    if !bytes.starts_with(MCAP_MAGIC) {
        return Err(at(
            file,
            "byte 0",
            "expected the MCAP magic bytes 89 4D 43 41 50 30 0D 0A",
        ));
    }
    if !(options.window_s.is_finite() && options.window_s >= 0.0) {
        return Err(ImportError::BadOption {
            option: "--window".into(),
            message: format!("{}: expected a duration of at least 0 s", options.window_s),
        });
    }
    let mut summary = ImportSummary::default();
    let stream = mcap::MessageStream::new(bytes)
        .map_err(|e| at(file, "MCAP header", format!("{e}: expected an MCAP file")))?;
    let mut ranges = Vec::new();
    let mut track = PoseTrack::default();
    let mut odometry_frame: Option<String> = None;
    let mut static_tf: BTreeMap<String, (String, Tf)> = BTreeMap::new();
    let mut left_out: BTreeMap<String, usize> = BTreeMap::new();
    for (index, message) in stream.enumerate() {
        let message = message.map_err(|e| {
            at(
                file,
                format!("MCAP record after message {}", index.saturating_sub(1)),
                format!("{e}: expected a readable MCAP record"),
            )
        })?;
        let topic = message.channel.topic.as_str();
        let schema = message
            .channel
            .schema
            .as_ref()
            .map(|s| s.name.as_str())
            .unwrap_or("");
        let kind = match schema {
            "sensor_msgs/msg/Range" | "sensor_msgs/Range" => 0,
            "nav_msgs/msg/Odometry" | "nav_msgs/Odometry" => 1,
            "tf2_msgs/msg/TFMessage" | "tf2_msgs/TFMessage" if topic == "/tf_static" => 2,
            _ => {
                *left_out.entry(format!("{topic} ({schema})")).or_default() += 1;
                continue;
            }
        };
        if message.channel.message_encoding != "cdr" {
            *left_out
                .entry(format!(
                    "{topic} (encoding {:?}, expected \"cdr\")",
                    message.channel.message_encoding
                ))
                .or_default() += 1;
            continue;
        }
        let log_t = message.log_time as f64 * 1e-9;
        let err = |e| cdr_error(file, index, topic, e);
        let mut r = CdrReader::new(&message.data).map_err(err)?;
        match kind {
            0 => {
                let (t, frame) = header(&mut r).map_err(err)?;
                r.u8("radiation_type").map_err(err)?;
                let fov = r.f32("field_of_view").map_err(err)? as f64;
                let min = r.f32("min_range").map_err(err)? as f64;
                let max = r.f32("max_range").map_err(err)? as f64;
                let range = r.f32("range").map_err(err)? as f64;
                ranges.push(RangeMsg {
                    index,
                    topic: topic.to_string(),
                    t: if t == 0.0 { log_t } else { t },
                    frame,
                    fov,
                    min,
                    max,
                    range,
                });
            }
            1 => {
                let (t, _) = header(&mut r).map_err(err)?;
                let child = r.string("child_frame_id").map_err(err)?;
                let x = r.f64("pose.pose.position.x").map_err(err)?;
                let y = r.f64("pose.pose.position.y").map_err(err)?;
                r.f64("pose.pose.position.z").map_err(err)?;
                let q = [
                    r.f64("pose.pose.orientation.x").map_err(err)?,
                    r.f64("pose.pose.orientation.y").map_err(err)?,
                    r.f64("pose.pose.orientation.z").map_err(err)?,
                    r.f64("pose.pose.orientation.w").map_err(err)?,
                ];
                r.skip_f64(36, "pose.covariance").map_err(err)?;
                let t = if t == 0.0 { log_t } else { t };
                let yaw = yaw_of(q[0], q[1], q[2], q[3]);
                if ![x, y, yaw].iter().all(|v| v.is_finite()) {
                    summary.skip(place(index, topic), "the pose is not finite");
                    continue;
                }
                odometry_frame.get_or_insert(child);
                if !track.push(t, Pose::new(x, y, yaw)) {
                    summary.skip(
                        place(index, topic),
                        format!("odometry time {t} is earlier than the previous odometry's"),
                    );
                    summary.warn(format!(
                        "{}: time goes backwards; message skipped",
                        place(index, topic)
                    ));
                }
            }
            _ => {
                let n = r.u32("transforms (sequence length)").map_err(err)? as usize;
                if n > message.data.len() {
                    return Err(err(CdrError {
                        offset: 4,
                        message: format!(
                            "{n} transforms cannot fit in {} bytes: expected a TFMessage",
                            message.data.len()
                        ),
                    }));
                }
                for _ in 0..n {
                    let (_, parent) = header(&mut r).map_err(err)?;
                    let child = r.string("child_frame_id").map_err(err)?;
                    let x = r.f64("transform.translation.x").map_err(err)?;
                    let y = r.f64("transform.translation.y").map_err(err)?;
                    r.f64("transform.translation.z").map_err(err)?;
                    let q = [
                        r.f64("transform.rotation.x").map_err(err)?,
                        r.f64("transform.rotation.y").map_err(err)?,
                        r.f64("transform.rotation.z").map_err(err)?,
                        r.f64("transform.rotation.w").map_err(err)?,
                    ];
                    static_tf.insert(child, (parent, Tf(x, y, yaw_of(q[0], q[1], q[2], q[3]))));
                }
            }
        }
    }
    for (what, n) in &left_out {
        summary.warn(format!("{n} messages on {what} were left out"));
    }
    if ranges.is_empty() {
        return Err(ImportError::NoSnapshots {
            file: file.to_string(),
            why: "no sensor_msgs/msg/Range message in CDR".to_string(),
        });
    }
    // The sensors.
    let key = |m: &RangeMsg| {
        if m.frame.is_empty() {
            m.topic.clone()
        } else {
            m.frame.clone()
        }
    };
    let mut distinct: Vec<String> = ranges.iter().map(key).collect();
    distinct.sort_by_key(|a| natural_key(a));
    distinct.dedup();
    if distinct.len() > MAX_SENSORS {
        return Err(ImportError::NoSnapshots {
            file: file.to_string(),
            why: format!(
                "{} distinct sonar frames: expected at most {MAX_SENSORS}",
                distinct.len()
            ),
        });
    }
    let (layout, index_of): (SensorLayout, BTreeMap<String, usize>) = match &options.layout {
        Some(l) if !l.frames.is_empty() => (l.layout.clone(), BTreeMap::new()),
        Some(l) => {
            if distinct.len() != l.layout.len() {
                return Err(ImportError::NeedsLayout {
                    file: file.to_string(),
                    what: format!(
                        "the recording has {} sonar frames ({}) but the layout has {} sensors and no `frames` map to say which is which",
                        distinct.len(),
                        distinct.join(", "),
                        l.layout.len()
                    ),
                });
            }
            let map = distinct.iter().cloned().zip(0..).collect();
            (l.layout.clone(), map)
        }
        None => {
            if static_tf.is_empty() {
                return Err(ImportError::NeedsLayout {
                    file: file.to_string(),
                    what: "the recording has no /tf_static transforms for the sonar frames".into(),
                });
            }
            let base = odometry_frame
                .clone()
                .unwrap_or_else(|| "base_link".to_string());
            let mut mounts = Vec::new();
            for frame in &distinct {
                let mut acc: Option<Tf> = None;
                let mut current = frame.clone();
                for _ in 0..64 {
                    if current == base {
                        break;
                    }
                    let Some((parent, tf)) = static_tf.get(&current) else {
                        acc = None;
                        break;
                    };
                    acc = Some(match acc {
                        Some(a) => compose(*tf, a),
                        None => *tf,
                    });
                    current = parent.clone();
                }
                match acc {
                    Some(Tf(x, y, yaw)) if current == base => mounts.push(SensorMount {
                        x_m: x,
                        y_m: y,
                        heading_rad: yaw,
                    }),
                    _ => {
                        return Err(ImportError::NeedsLayout {
                            file: file.to_string(),
                            what: format!("/tf_static has no chain of transforms from {base} to the sonar frame {frame}"),
                        })
                    }
                }
            }
            let map = distinct.iter().cloned().zip(0..).collect();
            (SensorLayout { mounts }, map)
        }
    };
    let n = layout.len();
    // Readings: sensor index, time, value.
    let mut readings: Vec<(f64, usize, Option<f64>, usize)> = Vec::with_capacity(ranges.len());
    let mut last_t = vec![f64::NEG_INFINITY; n];
    let mut largest_max = 0.0f64;
    let mut smallest_min = f64::INFINITY;
    let mut fov = None;
    for m in &ranges {
        let k = match &options.layout {
            Some(l) if !l.frames.is_empty() => {
                match l.frames.get(&m.frame).or_else(|| l.frames.get(&m.topic)) {
                    Some(&k) => k,
                    None => {
                        summary.skip(
                            place(m.index, &m.topic),
                            format!(
                                "neither frame {:?} nor the topic is in the layout's frames",
                                m.frame
                            ),
                        );
                        continue;
                    }
                }
            }
            _ => index_of.get(&key(m)).copied().unwrap_or(usize::MAX),
        };
        if k >= n {
            summary.skip(
                place(m.index, &m.topic),
                format!("sensor index {k} is not in the layout"),
            );
            continue;
        }
        if !m.t.is_finite() || m.t < last_t[k] {
            summary.skip(
                place(m.index, &m.topic),
                format!(
                    "time {} is earlier than the previous reading of sensor {k}",
                    m.t
                ),
            );
            summary.warn(format!(
                "{}: time goes backwards; message skipped",
                place(m.index, &m.topic)
            ));
            continue;
        }
        last_t[k] = m.t;
        if m.max.is_finite() {
            largest_max = largest_max.max(m.max);
        }
        if m.min.is_finite() && m.min >= 0.0 {
            smallest_min = smallest_min.min(m.min);
        }
        if m.fov.is_finite() && m.fov > 0.0 {
            fov.get_or_insert(m.fov);
        }
        let echo = m.range.is_finite() && m.range >= m.min && m.range <= m.max;
        if !echo {
            summary.turned_no_echo += 1;
        }
        readings.push((m.t, k, echo.then_some(m.range), m.index));
    }
    readings.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.3.cmp(&b.3)));
    // Firing cycles.
    let mut raw = Vec::new();
    let mut missing = 0;
    let mut i = 0;
    while i < readings.len() {
        let t0 = readings[i].0;
        let mut seen = vec![false; n];
        let mut ranges_m = vec![None; n];
        let mut sum_t = 0.0;
        let mut j = i;
        while j < readings.len() {
            let (t, k, v, _) = readings[j];
            if seen[k] || t - t0 > options.window_s {
                break;
            }
            seen[k] = true;
            ranges_m[k] = v;
            sum_t += t;
            j += 1;
        }
        missing += seen.iter().filter(|s| !**s).count();
        raw.push(RawSnapshot {
            t: sum_t / (j - i) as f64,
            place: format!("the cycle starting at MCAP message {}", readings[i].3),
            ranges_m,
        });
        i = j;
    }
    if missing > 0 {
        summary.warn(format!(
            "{missing} readings were missing from their firing cycle and are no echo"
        ));
    }
    let default_max = (largest_max > 0.0).then_some(largest_max);
    let mut sensor =
        sensor_with_max_range(options.layout.as_ref(), options.max_range_m, default_max);
    if options.layout.is_none() {
        if smallest_min.is_finite() {
            sensor.min_range_m = smallest_min;
        }
        if let Some(f) = fov {
            sensor.beam_width_rad = f;
        }
    }
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
        "no nav_msgs/msg/Odometry messages",
        hw,
        &mut summary,
    )?;
    Ok(Imported {
        run,
        summary,
        format: Format::Mcap,
    })
}
