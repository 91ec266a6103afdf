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
//! - A reading outside `[min_range, max_range]` of its message, or ±inf or NaN, is no echo
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
//! # Refused (with the file, the message index, topic and field or byte offset, and what was expected)
//! - Bytes that are not MCAP; a record whose declared length (or that of a string, map or
//!   byte array inside it) runs past the bytes present, at the top level or in a chunk (the
//!   error gives the record's byte offset; checked before the `mcap` crate sees the file, and
//!   a panic inside the crate is contained as an error); a compressed chunk (this build reads
//!   uncompressed recordings); a record the `mcap` crate cannot read (the error says after
//!   which message).
//! - A Range/Odometry/TFMessage that is not CDR of its type (too short, a string running past
//!   the end, an unknown encapsulation).
//! - Values no robot produces: a Range's field of view outside 0..π, a negative or non-finite
//!   `min_range` or `max_range`, `min_range ≥ max_range`, a negative finite `range`; an
//!   odometry or /tf_static position that is not finite or beyond 10 km, a quaternion that is
//!   not a finite rotation; a time beyond ±1e10 s; firing cycles with many more slots than
//!   readings (a `--window` far too short for the ring).

use super::assemble::{assemble, sensor_with_max_range, Hardware, Place, RawSnapshot};
use super::cdr::{header, header_bytes, yaw_of, CdrError, CdrReader};
use super::error::{at, ImportError};
use super::mcap_check;
use super::options::ImportOptions;
use super::pose_track;
use super::pose_track::PoseTrack;
use super::sane;
use super::summary::{Format, ImportSummary, Imported};
use crate::geometry::Pose;
use crate::log::MAX_SENSORS;
use crate::sonar::{SensorLayout, SensorMount};
use crate::units::Units;
use std::collections::{BTreeMap, HashMap};
use std::f64::consts::PI;
use std::rc::Rc;
use std::sync::Arc;

/// The first bytes of every MCAP file.
pub const MCAP_MAGIC: &[u8] = b"\x89MCAP0\r\n";

struct RangeMsg {
    /// The message's index in the file.
    index: usize,
    /// Interned topic ([`Collected::topics`]).
    topic: u32,
    /// Interned frame id ([`Collected::frames`]).
    frame: u32,
    t: f64,
    // As in the message (float32).
    fov: f32,
    min: f32,
    max: f32,
    range: f32,
}

/// Distinct strings, each kept once (a topic or frame id may be long and repeated in every
/// message: keeping one copy per message let a 1 MB topic name take gigabytes).
/// Bytes that are not UTF-8 are replaced (U+FFFD), as for every name read from a message.
#[derive(Default)]
struct Names {
    index: HashMap<Rc<str>, u32>,
    names: Vec<Rc<str>>,
}

impl Names {
    fn intern(&mut self, bytes: &[u8]) -> u32 {
        let text = String::from_utf8_lossy(bytes);
        if let Some(&i) = self.index.get(text.as_ref()) {
            return i;
        }
        let i = self.names.len() as u32;
        let name: Rc<str> = Rc::from(text.as_ref());
        self.names.push(name.clone());
        self.index.insert(name, i);
        i
    }
}

/// What a channel's messages are.
#[derive(Clone, Copy)]
enum Kind {
    Range(u32),
    Odometry,
    StaticTf,
    LeftOut,
}

/// The sensor of a reading, looked up once per frame id and topic rather than per reading.
struct SensorOf {
    by_frame: Vec<Option<usize>>,
    by_topic: Vec<Option<usize>>,
    frame_empty: Vec<bool>,
    /// The layout's `frames` decide: the frame id, else the topic. Otherwise the sensors are
    /// the frame ids, or the topics for readings without one.
    layout_frames: bool,
}

impl SensorOf {
    fn get(&self, m: &RangeMsg) -> Option<usize> {
        let (f, t) = (m.frame as usize, m.topic as usize);
        if self.layout_frames {
            self.by_frame[f].or(self.by_topic[t])
        } else if self.frame_empty[f] {
            self.by_topic[t]
        } else {
            self.by_frame[f]
        }
    }
}

/// What the messages gave.
struct Collected {
    ranges: Vec<RangeMsg>,
    /// The Range channels' topics (the channel itself, shared with the MCAP reader: a topic
    /// is not copied).
    topics: Vec<Arc<mcap::Channel<'static>>>,
    frames: Names,
    track: PoseTrack,
    odometry_frame: Option<String>,
    static_tf: BTreeMap<String, (String, Tf)>,
}

/// A 2-D rigid transform (x, y, yaw).
#[derive(Clone, Copy)]
struct Tf(f64, f64, f64);

fn compose(a: Tf, b: Tf) -> Tf {
    let (s, c) = a.2.sin_cos();
    Tf(a.0 + c * b.0 - s * b.1, a.1 + s * b.0 + c * b.1, a.2 + b.2)
}

fn place(index: usize, topic: &str) -> String {
    format!("MCAP message {index} (topic {})", sane::quote(topic))
}

/// A value of a message that no robot produces, refused with its place and field.
fn bad_value(file: &str, index: usize, topic: &str, field: &str, message: String) -> ImportError {
    at(
        file,
        format!("{}, field {field}", place(index, topic)),
        message,
    )
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

fn cdr_error(file: &str, index: usize, topic: &str, e: CdrError) -> ImportError {
    at(
        file,
        format!("{}, byte {}", place(index, topic), e.offset),
        e.message,
    )
}

/// Natural order: digit runs compare as numbers (`sonar_2` < `sonar_10`; between equal
/// numbers, as text: `02` before `2`), other runs as text. Allocates nothing.
fn natural_cmp(a: &str, b: &str) -> std::cmp::Ordering {
    use std::cmp::Ordering;
    fn run(s: &str, digits: bool) -> (&str, &str) {
        let n = s.len()
            - s.trim_start_matches(|c: char| c.is_ascii_digit() == digits)
                .len();
        s.split_at(n)
    }
    let (mut a, mut b) = (a, b);
    loop {
        match (a.is_empty(), b.is_empty()) {
            (true, true) => return Ordering::Equal,
            (true, false) => return Ordering::Less,
            (false, true) => return Ordering::Greater,
            _ => {}
        }
        let da = a.starts_with(|c: char| c.is_ascii_digit());
        let db = b.starts_with(|c: char| c.is_ascii_digit());
        if da != db {
            // A number before text.
            return if da {
                Ordering::Less
            } else {
                Ordering::Greater
            };
        }
        let (ra, rest_a) = run(a, da);
        let (rb, rest_b) = run(b, db);
        let order = if da {
            let ta = ra.trim_start_matches('0');
            let tb = rb.trim_start_matches('0');
            ta.len()
                .cmp(&tb.len())
                .then_with(|| ta.cmp(tb))
                .then_with(|| ra.cmp(rb))
        } else {
            ra.cmp(rb)
        };
        if order != Ordering::Equal {
            return order;
        }
        a = rest_a;
        b = rest_b;
    }
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
    options.check()?;
    mcap_check::check(bytes, file)?;
    let mut summary = ImportSummary::default();
    let collected = contain_panic(file, || collect(bytes, file, &mut summary))?;
    assemble_mcap(collected, file, options, summary)
}

/// Runs `f`, which calls into the `mcap` crate, turning a panic there into an error naming
/// the file (the last line of defence: [`mcap_check`] checks the lengths first). The panic's
/// own message is not printed.
fn contain_panic<T>(
    file: &str,
    f: impl FnOnce() -> Result<T, ImportError>,
) -> Result<T, ImportError> {
    use std::cell::Cell;
    use std::panic::{catch_unwind, AssertUnwindSafe};
    use std::sync::Once;
    thread_local! {
        static QUIET: Cell<bool> = const { Cell::new(false) };
    }
    static HOOK: Once = Once::new();
    HOOK.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if !QUIET.with(Cell::get) {
                previous(info);
            }
        }));
    });
    let was = QUIET.with(|q| q.replace(true));
    let result = catch_unwind(AssertUnwindSafe(f));
    QUIET.with(|q| q.set(was));
    result.unwrap_or_else(|panic| {
        let what = panic
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| panic.downcast_ref::<String>().cloned())
            .unwrap_or_default();
        Err(at(
            file,
            "MCAP file",
            format!(
                "the MCAP reader failed ({}): expected a well-formed MCAP file",
                sane::quote(&what)
            ),
        ))
    })
}

/// Reads the messages (the part that calls into the `mcap` crate).
fn collect(
    bytes: &[u8],
    file: &str,
    summary: &mut ImportSummary,
) -> Result<Collected, ImportError> {
    let stream = mcap::MessageStream::new(bytes)
        .map_err(|e| at(file, "MCAP header", format!("{e}: expected an MCAP file")))?;
    let mut c = Collected {
        ranges: Vec::new(),
        topics: Vec::new(),
        frames: Names::default(),
        track: PoseTrack::default(),
        odometry_frame: None,
        static_tf: BTreeMap::new(),
    };
    let mut kinds: HashMap<u16, Kind> = HashMap::new();
    let mut left_out: BTreeMap<u16, (String, usize)> = BTreeMap::new();
    for (index, message) in stream.enumerate() {
        let message = message.map_err(|e| {
            at(
                file,
                if index == 0 {
                    "MCAP file, before the first message".to_string()
                } else {
                    format!("MCAP file, after message {}", index - 1)
                },
                format!("{e}: expected a readable MCAP record"),
            )
        })?;
        let channel = &message.channel;
        let topic = channel.topic.as_str();
        let kind = *kinds.entry(channel.id).or_insert_with(|| {
            let schema = channel
                .schema
                .as_ref()
                .map(|s| s.name.as_str())
                .unwrap_or("");
            let kind = match schema {
                "sensor_msgs/msg/Range" | "sensor_msgs/Range" => {
                    c.topics.push(channel.clone());
                    Kind::Range(c.topics.len() as u32 - 1)
                }
                "nav_msgs/msg/Odometry" | "nav_msgs/Odometry" => Kind::Odometry,
                "tf2_msgs/msg/TFMessage" | "tf2_msgs/TFMessage" if topic == "/tf_static" => {
                    Kind::StaticTf
                }
                _ => {
                    left_out.insert(
                        channel.id,
                        (
                            format!("{} ({})", sane::quote(topic), sane::quote(schema)),
                            0,
                        ),
                    );
                    return Kind::LeftOut;
                }
            };
            if channel.message_encoding != "cdr" {
                left_out.insert(
                    channel.id,
                    (
                        format!(
                            "{} (encoding {:?}, expected \"cdr\")",
                            sane::quote(topic),
                            sane::quote(&channel.message_encoding)
                        ),
                        0,
                    ),
                );
                return Kind::LeftOut;
            }
            kind
        });
        let log_t = message.log_time as f64 * 1e-9;
        let err = |e| cdr_error(file, index, topic, e);
        let bad =
            |(field, message): (String, String)| bad_value(file, index, topic, &field, message);
        let stamp = |t: f64| {
            let t = if t == 0.0 { log_t } else { t };
            sane::time(t, "a time in seconds").map_err(|m| {
                bad((
                    if t == log_t {
                        "log_time"
                    } else {
                        "header.stamp"
                    }
                    .to_string(),
                    m,
                ))
            })
        };
        match kind {
            Kind::LeftOut => {
                if let Some(e) = left_out.get_mut(&channel.id) {
                    e.1 += 1;
                }
                continue;
            }
            Kind::Range(topic_id) => {
                let mut r = CdrReader::new(&message.data).map_err(err)?;
                let (t, frame) = header_bytes(&mut r).map_err(err)?;
                r.u8("radiation_type").map_err(err)?;
                let fov = r.f32("field_of_view").map_err(err)?;
                let min = r.f32("min_range").map_err(err)?;
                let max = r.f32("max_range").map_err(err)?;
                let range = r.f32("range").map_err(err)?;
                let t = stamp(t)?;
                let narrowest = sane::MIN_BEAM_DEG.to_radians();
                if !(fov == 0.0 || (fov.is_finite() && (narrowest..=PI).contains(&(fov as f64)))) {
                    return Err(bad((
                        "field_of_view".into(),
                        format!(
                            "{} rad: expected a beam width from {} rad ({}°) to π rad, or 0 (unknown)",
                            sane::show(fov as f64),
                            sane::show(narrowest),
                            sane::MIN_BEAM_DEG
                        ),
                    )));
                }
                for (v, field) in [(min, "min_range"), (max, "max_range")] {
                    sane::length(v as f64, 1.0, "a range in metres", "m")
                        .map_err(|m| bad((field.into(), m)))?;
                    if v < 0.0 {
                        return Err(bad((
                            field.into(),
                            format!(
                                "{} m is negative: expected a range of at least 0 m",
                                sane::show(v as f64)
                            ),
                        )));
                    }
                }
                if (max as f64) < sane::MIN_MAX_RANGE_M {
                    return Err(bad((
                        "max_range".into(),
                        format!(
                            "{} m: expected a maximum range of at least {} m",
                            sane::show(max as f64),
                            sane::MIN_MAX_RANGE_M
                        ),
                    )));
                }
                if min >= max {
                    return Err(bad((
                        "min_range".into(),
                        format!(
                            "{} m is not below max_range {} m: expected min_range < max_range",
                            sane::show(min as f64),
                            sane::show(max as f64)
                        ),
                    )));
                }
                if range.is_finite() && range < 0.0 {
                    return Err(bad((
                        "range".into(),
                        format!(
                            "{} m is negative: expected a range of at least 0 m, or ±inf for no echo (REP 117)",
                            sane::show(range as f64)
                        ),
                    )));
                }
                let frame = c.frames.intern(frame);
                c.ranges.push(RangeMsg {
                    index,
                    topic: topic_id,
                    frame,
                    t,
                    fov,
                    min,
                    max,
                    range,
                });
            }
            Kind::Odometry => {
                let mut r = CdrReader::new(&message.data).map_err(err)?;
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
                let t = stamp(t)?;
                let x = position(x, "pose.pose.position.x").map_err(bad)?;
                let y = position(y, "pose.pose.position.y").map_err(bad)?;
                let yaw = rotation(q, "pose.pose.orientation").map_err(bad)?;
                c.odometry_frame
                    .get_or_insert_with(|| String::from_utf8_lossy(child).into_owned());
                if !c.track.push(t, Pose::new(x, y, yaw)) {
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
            Kind::StaticTf => {
                let mut r = CdrReader::new(&message.data).map_err(err)?;
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
                    c.static_tf.insert(child, (parent, Tf(x, y, yaw)));
                }
            }
        }
    }
    for (what, n) in left_out.values() {
        summary.warn(format!("{n} messages on {what} were left out"));
    }
    Ok(c)
}

/// The sensors, the firing cycles and the run from what the messages gave.
fn assemble_mcap(
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
    // The sensors: a reading's key is its frame id, else its topic.
    let topic_of = |m: &RangeMsg| topics[m.topic as usize].topic.as_str();
    let key = |m: &RangeMsg| -> &str {
        let frame = &frames.names[m.frame as usize];
        if frame.is_empty() {
            topic_of(m)
        } else {
            frame
        }
    };
    let mut distinct: Vec<&str> = Vec::new();
    {
        let mut seen_frames = vec![false; frames.names.len()];
        let mut seen_topics = vec![false; topics.len()];
        for m in &ranges {
            let seen = if frames.names[m.frame as usize].is_empty() {
                &mut seen_topics[m.topic as usize]
            } else {
                &mut seen_frames[m.frame as usize]
            };
            if !*seen {
                *seen = true;
                distinct.push(key(m));
            }
        }
    }
    if distinct.len() > MAX_SENSORS {
        return Err(ImportError::NoSnapshots {
            file: file.to_string(),
            why: format!(
                "{} distinct sonar frames: expected at most {MAX_SENSORS}",
                distinct.len()
            ),
        });
    }
    distinct.sort_by(|a, b| natural_cmp(a, b));
    distinct.dedup();
    let quoted = |names: &[&str]| {
        let mut list: Vec<String> = names.iter().take(20).map(|n| sane::quote(n)).collect();
        if names.len() > 20 {
            list.push(format!("... {} more", names.len() - 20));
        }
        list.join(", ")
    };
    let (layout, index_of): (SensorLayout, BTreeMap<&str, usize>) = match &options.layout {
        Some(l) if !l.frames.is_empty() => (l.layout.clone(), BTreeMap::new()),
        Some(l) => {
            if distinct.len() != l.layout.len() {
                return Err(ImportError::NeedsLayout {
                    file: file.to_string(),
                    what: format!(
                        "the recording has {} sonar frames ({}) but the layout has {} sensors and no `frames` map to say which is which",
                        distinct.len(),
                        quoted(&distinct),
                        l.layout.len()
                    ),
                });
            }
            let map = distinct.iter().copied().zip(0..).collect();
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
            for &frame in &distinct {
                let mut acc: Option<Tf> = None;
                let mut current = frame;
                for _ in 0..64 {
                    if current == base {
                        break;
                    }
                    let Some((parent, tf)) = static_tf.get(current) else {
                        acc = None;
                        break;
                    };
                    acc = Some(match acc {
                        Some(a) => compose(*tf, a),
                        None => *tf,
                    });
                    current = parent;
                }
                match acc {
                    Some(Tf(x, y, yaw)) if current == base => {
                        for v in [x, y] {
                            sane::length(v, 1.0, "a sonar mount within 10 km of the robot", "m")
                                .map_err(|m| {
                                    at(
                                        file,
                                        format!(
                                            "/tf_static, the chain from {} to {}",
                                            sane::quote(&base),
                                            sane::quote(frame)
                                        ),
                                        m,
                                    )
                                })?;
                        }
                        mounts.push(SensorMount {
                            x_m: x,
                            y_m: y,
                            heading_rad: pose_track::wrap_pi(yaw),
                        })
                    }
                    _ => {
                        return Err(ImportError::NeedsLayout {
                            file: file.to_string(),
                            what: format!(
                            "/tf_static has no chain of transforms from {} to the sonar frame {}",
                            sane::quote(&base),
                            sane::quote(frame)
                        ),
                        })
                    }
                }
            }
            let map = distinct.iter().copied().zip(0..).collect();
            (SensorLayout { mounts }, map)
        }
    };
    let n = layout.len();
    // The sensor of each frame and topic, looked up once per name rather than per reading.
    let layout_frames = options.layout.as_ref().filter(|l| !l.frames.is_empty());
    let sensor_of = SensorOf {
        by_frame: frames
            .names
            .iter()
            .map(|f| match layout_frames {
                Some(l) => l.frames.get(f.as_ref()).copied(),
                None => index_of.get(f.as_ref()).copied(),
            })
            .collect(),
        by_topic: topics
            .iter()
            .map(|c| match layout_frames {
                Some(l) => l.frames.get(&c.topic).copied(),
                None => index_of.get(c.topic.as_str()).copied(),
            })
            .collect(),
        frame_empty: frames.names.iter().map(|f| f.is_empty()).collect(),
        layout_frames: layout_frames.is_some(),
    };
    // Readings: time, sensor index, value, message index.
    let mut readings: Vec<(f64, usize, Option<f64>, usize)> = Vec::with_capacity(ranges.len());
    let mut last_t = vec![f64::NEG_INFINITY; n];
    let mut largest_max = 0.0f64;
    let mut smallest_min = f64::INFINITY;
    let mut fov = None;
    for m in &ranges {
        let topic = topic_of(m);
        let Some(k) = sensor_of.get(m) else {
            summary.skip(
                place(m.index, topic),
                format!(
                    "neither frame {:?} nor the topic is in the layout's frames",
                    sane::quote(&frames.names[m.frame as usize])
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
        largest_max = largest_max.max(m.max as f64);
        smallest_min = smallest_min.min(m.min as f64);
        if m.fov > 0.0 {
            fov.get_or_insert(m.fov as f64);
        }
        let echo = m.range.is_finite() && m.range >= m.min && m.range <= m.max;
        if !echo {
            summary.turned_no_echo += 1;
        }
        readings.push((m.t, k, echo.then_some(m.range as f64), m.index));
    }
    drop(sensor_of);
    drop(ranges);
    readings.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.3.cmp(&b.3)));
    // Firing cycles. Each cycle holds a slot per sensor, so the slots are bounded by the
    // readings (a hostile file must not make a million cycles of ten thousand sensors).
    let slot_limit = 4 * readings.len() + n;
    let mut slots = 0usize;
    let mut raw = Vec::new();
    let mut missing = 0;
    let mut seen = vec![false; n];
    let mut i = 0;
    while i < readings.len() {
        let t0 = readings[i].0;
        slots += n;
        if slots > slot_limit {
            return Err(ImportError::NoSnapshots {
                file: file.to_string(),
                why: format!(
                    "{} readings of {n} sensors make more than {} firing cycles (the first {} end before the cycle starting at MCAP message {}): expected most cycles to read most sensors (is --window {} s too short?)",
                    readings.len(),
                    raw.len(),
                    raw.len(),
                    readings[i].3,
                    options.window_s
                ),
            });
        }
        seen.iter_mut().for_each(|s| *s = false);
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
        missing += n - (j - i);
        raw.push(RawSnapshot {
            // The mean, kept within the cycle's readings (rounding must not put it after the
            // next cycle's first reading: times may not decrease).
            t: (sum_t / (j - i) as f64).clamp(t0, readings[j - 1].0),
            place: Place::Cycle(readings[i].3),
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn natural_order() {
        let mut names = vec![
            "sonar_10", "sonar_2", "b", "sonar_02", "a1", "sonar_1x", "10", "9",
        ];
        names.sort_by(|a, b| natural_cmp(a, b));
        assert_eq!(
            names,
            ["9", "10", "a1", "b", "sonar_1x", "sonar_02", "sonar_2", "sonar_10"]
        );
    }

    #[test]
    fn a_panic_in_the_reader_becomes_an_error_naming_the_file() {
        let e = contain_panic::<()>("x.mcap", || panic!("range start index 9 out of range"))
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("x.mcap: MCAP file: the MCAP reader failed"),
            "{e}"
        );
        assert!(e.contains("range start index 9"), "{e}");
        // Later panics elsewhere are reported as usual (the hook is only quiet inside).
        assert_eq!(contain_panic("x", || Ok(3)), Ok(3));
    }
}
