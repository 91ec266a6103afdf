//! The three message types read, decoded from CDR and checked: `sensor_msgs/msg/Range`,
//! `nav_msgs/msg/Odometry` and `tf2_msgs/msg/TFMessage`. An error names the message (its index
//! and topic) and the field or byte offset.

use super::tf::{StaticTf, Tf};
use crate::geometry::Pose;
use crate::import::cdr::{header, header_bytes, yaw_of, CdrError, CdrReader};
use crate::import::error::{at, ImportError};
use crate::import::sane;
use std::f64::consts::PI;

/// A Range message, as read.
pub(super) struct RangeMsg {
    /// The message's index in the file.
    pub index: usize,
    /// Interned topic ([`super::collect::Collected::topics`]).
    pub topic: u32,
    /// Interned frame id ([`super::collect::Collected::frames`]).
    pub frame: u32,
    pub t: f64,
    // As in the message (float32).
    pub fov: f32,
    pub min: f32,
    pub max: f32,
    pub range: f32,
}

/// A Range message's fields, decoded but not yet placed (its frame id not interned).
pub(super) struct RangeFields<'a> {
    /// The frame id's bytes.
    pub frame: &'a [u8],
    pub t: f64,
    pub fov: f32,
    pub min: f32,
    pub max: f32,
    pub range: f32,
}

/// An Odometry message, as read.
pub(super) struct OdometryMsg<'a> {
    pub t: f64,
    /// The robot's frame id's bytes.
    pub child: &'a [u8],
    pub pose: Pose,
}

/// Where a message is, for its errors: the file, the message's index and topic, and its log
/// time (the time of a message whose stamp is zero).
pub(super) struct MessageAt<'a> {
    pub file: &'a str,
    pub index: usize,
    pub topic: &'a str,
    pub log_t: f64,
}

/// A message's place in an error or skip: its index and topic.
pub(super) fn place(index: usize, topic: &str) -> String {
    format!("MCAP message {index} (topic {})", sane::quote(topic))
}

impl MessageAt<'_> {
    /// [`place`] of this message.
    pub fn place(&self) -> String {
        place(self.index, self.topic)
    }

    /// Bytes that are not CDR of the message's type, refused with their offset.
    fn cdr(&self, e: CdrError) -> ImportError {
        at(
            self.file,
            format!("{}, byte {}", self.place(), e.offset),
            e.message,
        )
    }

    /// A value that no robot produces, refused with its place and field.
    fn bad(&self, (field, message): (String, String)) -> ImportError {
        at(
            self.file,
            format!("{}, field {field}", self.place()),
            message,
        )
    }

    /// The time of a header stamp `t` (the log time when it is zero), checked.
    fn stamp(&self, t: f64) -> Result<f64, ImportError> {
        let t = if t == 0.0 { self.log_t } else { t };
        sane::time(t, "a time in seconds").map_err(|m| {
            self.bad((
                if t == self.log_t {
                    "log_time"
                } else {
                    "header.stamp"
                }
                .to_string(),
                m,
            ))
        })
    }

    /// Decodes and checks a Range message.
    pub fn range<'d>(&self, data: &'d [u8]) -> Result<RangeFields<'d>, ImportError> {
        let err = |e| self.cdr(e);
        let mut r = CdrReader::new(data).map_err(err)?;
        let (t, frame) = header_bytes(&mut r).map_err(err)?;
        r.u8("radiation_type").map_err(err)?;
        let fov = r.f32("field_of_view").map_err(err)?;
        let min = r.f32("min_range").map_err(err)?;
        let max = r.f32("max_range").map_err(err)?;
        let range = r.f32("range").map_err(err)?;
        let t = self.stamp(t)?;
        check_range(fov, min, max, range).map_err(|e| self.bad(e))?;
        Ok(RangeFields {
            frame,
            t,
            fov,
            min,
            max,
            range,
        })
    }

    /// Decodes and checks an Odometry message.
    pub fn odometry<'d>(&self, data: &'d [u8]) -> Result<OdometryMsg<'d>, ImportError> {
        let err = |e| self.cdr(e);
        let bad = |e| self.bad(e);
        let mut r = CdrReader::new(data).map_err(err)?;
        let (t, _) = header_bytes(&mut r).map_err(err)?;
        let child = r.string_bytes("child_frame_id").map_err(err)?;
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
        let t = self.stamp(t)?;
        let x = position(x, "pose.pose.position.x").map_err(bad)?;
        let y = position(y, "pose.pose.position.y").map_err(bad)?;
        let yaw = rotation(q, "pose.pose.orientation").map_err(bad)?;
        Ok(OdometryMsg {
            t,
            child,
            pose: Pose::new(x, y, yaw),
        })
    }

    /// Decodes and checks a TFMessage, adding its transforms to `static_tf`.
    pub fn static_tf(&self, data: &[u8], static_tf: &mut StaticTf) -> Result<(), ImportError> {
        let err = |e| self.cdr(e);
        let bad = |e| self.bad(e);
        let mut r = CdrReader::new(data).map_err(err)?;
        let n = r.u32("transforms (sequence length)").map_err(err)? as usize;
        if n > data.len() {
            return Err(err(CdrError {
                offset: 4,
                message: format!(
                    "{n} transforms cannot fit in {} bytes: expected a TFMessage",
                    data.len()
                ),
            }));
        }
        for j in 0..n {
            let (_, parent) = header(&mut r).map_err(err)?;
            let child = r.string("child_frame_id").map_err(err)?;
            let x = r.f64("transform.translation.x").map_err(err)?;
            let y = r.f64("transform.translation.y").map_err(err)?;
            let z = r.f64("transform.translation.z").map_err(err)?;
            let q = [
                r.f64("transform.rotation.x").map_err(err)?,
                r.f64("transform.rotation.y").map_err(err)?,
                r.f64("transform.rotation.z").map_err(err)?,
                r.f64("transform.rotation.w").map_err(err)?,
            ];
            let at_j = |f: &str| format!("transforms[{j}].transform.{f}");
            let x = position(x, &at_j("translation.x")).map_err(bad)?;
            let y = position(y, &at_j("translation.y")).map_err(bad)?;
            position(z, &at_j("translation.z")).map_err(bad)?;
            let yaw = rotation(q, &at_j("rotation")).map_err(bad)?;
            static_tf.insert(child, (parent, Tf(x, y, yaw)));
        }
        Ok(())
    }
}

/// Checks a Range message's values: a field of view within 0..π (0 for unknown), finite
/// non-negative ranges with `min_range < max_range`, a `range` not negative; the error names
/// the field.
fn check_range(fov: f32, min: f32, max: f32, range: f32) -> Result<(), (String, String)> {
    let narrowest = sane::MIN_BEAM_DEG.to_radians();
    if !(fov == 0.0 || (fov.is_finite() && (narrowest..=PI).contains(&(fov as f64)))) {
        return Err((
            "field_of_view".into(),
            format!(
                "{} rad: expected a beam width from {} rad ({}°) to π rad, or 0 (unknown)",
                sane::show(fov as f64),
                sane::show(narrowest),
                sane::MIN_BEAM_DEG
            ),
        ));
    }
    for (v, field) in [(min, "min_range"), (max, "max_range")] {
        sane::length(v as f64, 1.0, "a range in metres", "m").map_err(|m| (field.into(), m))?;
        if v < 0.0 {
            return Err((
                field.into(),
                format!(
                    "{} m is negative: expected a range of at least 0 m",
                    sane::show(v as f64)
                ),
            ));
        }
    }
    if (max as f64) < sane::MIN_MAX_RANGE_M {
        return Err((
            "max_range".into(),
            format!(
                "{} m: expected a maximum range of at least {} m",
                sane::show(max as f64),
                sane::MIN_MAX_RANGE_M
            ),
        ));
    }
    if min >= max {
        return Err((
            "min_range".into(),
            format!(
                "{} m is not below max_range {} m: expected min_range < max_range",
                sane::show(min as f64),
                sane::show(max as f64)
            ),
        ));
    }
    if range.is_finite() && range < 0.0 {
        return Err((
            "range".into(),
            format!(
                "{} m is negative: expected a range of at least 0 m, or ±inf for no echo (REP 117)",
                sane::show(range as f64)
            ),
        ));
    }
    Ok(())
}

/// Checks a quaternion is finite and near unit length (a rotation); `field` names it.
fn rotation(q: [f64; 4], field: &str) -> Result<f64, (String, String)> {
    let norm = q.iter().map(|v| v * v).sum::<f64>().sqrt();
    if !(q.iter().all(|v| v.is_finite()) && (0.5..=2.0).contains(&norm)) {
        return Err((
            field.to_string(),
            format!(
                "({}, {}, {}, {}) is not a rotation: expected a finite quaternion of length 1",
                sane::show(q[0]),
                sane::show(q[1]),
                sane::show(q[2]),
                sane::show(q[3])
            ),
        ));
    }
    Ok(yaw_of(q[0], q[1], q[2], q[3]))
}

/// Checks a position (metres) is finite and within 10 km; `field` names it.
fn position(v: f64, field: &str) -> Result<f64, (String, String)> {
    sane::length(v, 1.0, "a position in metres", "m").map_err(|m| (field.to_string(), m))
}
