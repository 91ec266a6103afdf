//! Reading the messages: the part that calls into the `mcap` crate. Each channel is told once
//! what its messages are (by schema and encoding); the messages read are gathered in
//! [`Collected`], those left out counted.

use super::messages::{MessageAt, RangeMsg};
use super::tf::StaticTf;
use crate::import::error::{at, ImportError};
use crate::import::pose_track::PoseTrack;
use crate::import::sane;
use crate::import::summary::ImportSummary;
use std::collections::{BTreeMap, HashMap};
use std::rc::Rc;
use std::sync::Arc;

/// Distinct strings, each kept once (a topic or frame id may be long and repeated in every
/// message: keeping one copy per message let a 1 MB topic name take gigabytes).
/// Bytes that are not UTF-8 are replaced (U+FFFD), as for every name read from a message.
#[derive(Default)]
pub(super) struct Names {
    index: HashMap<Rc<str>, u32>,
    /// The names, by their interned index.
    pub names: Vec<Rc<str>>,
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

/// What the messages gave.
pub(super) struct Collected {
    pub ranges: Vec<RangeMsg>,
    /// The Range channels' topics (the channel itself, shared with the MCAP reader: a topic
    /// is not copied).
    pub topics: Vec<Arc<mcap::Channel<'static>>>,
    pub frames: Names,
    pub track: PoseTrack,
    pub odometry_frame: Option<String>,
    pub static_tf: StaticTf,
}

/// The channels seen: what each one's messages are, and the count of those left out with
/// what they were (topic and schema, or encoding).
#[derive(Default)]
struct Channels {
    kinds: HashMap<u16, Kind>,
    left_out: BTreeMap<u16, (String, usize)>,
}

impl Channels {
    /// What `channel`'s messages are, decided at its first message (a Range channel is
    /// added to `topics`).
    fn kind(
        &mut self,
        channel: &Arc<mcap::Channel<'static>>,
        topics: &mut Vec<Arc<mcap::Channel<'static>>>,
    ) -> Kind {
        let left_out = &mut self.left_out;
        *self.kinds.entry(channel.id).or_insert_with(|| {
            let topic = channel.topic.as_str();
            let schema = channel
                .schema
                .as_ref()
                .map(|s| s.name.as_str())
                .unwrap_or("");
            let kind = match schema {
                "sensor_msgs/msg/Range" | "sensor_msgs/Range" => {
                    topics.push(channel.clone());
                    Kind::Range(topics.len() as u32 - 1)
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
        })
    }
}

/// Reads the messages (the part that calls into the `mcap` crate).
pub(super) fn collect(
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
    let mut channels = Channels::default();
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
        let here = MessageAt {
            file,
            index,
            topic: message.channel.topic.as_str(),
            log_t: message.log_time as f64 * 1e-9,
        };
        match channels.kind(&message.channel, &mut c.topics) {
            Kind::LeftOut => {
                if let Some(e) = channels.left_out.get_mut(&message.channel.id) {
                    e.1 += 1;
                }
            }
            Kind::Range(topic) => {
                let m = here.range(&message.data)?;
                let frame = c.frames.intern(m.frame);
                c.ranges.push(RangeMsg {
                    index,
                    topic,
                    frame,
                    t: m.t,
                    fov: m.fov,
                    min: m.min,
                    max: m.max,
                    range: m.range,
                });
            }
            Kind::Odometry => add_odometry(&mut c, &here, &message.data, summary)?,
            Kind::StaticTf => here.static_tf(&message.data, &mut c.static_tf)?,
        }
    }
    for (what, n) in channels.left_out.values() {
        summary.warn(format!("{n} messages on {what} were left out"));
    }
    Ok(c)
}

/// Adds an Odometry message to the track (the first one's frame id is the robot's); one
/// earlier than the previous is skipped with a warning.
fn add_odometry(
    c: &mut Collected,
    here: &MessageAt,
    data: &[u8],
    summary: &mut ImportSummary,
) -> Result<(), ImportError> {
    let m = here.odometry(data)?;
    c.odometry_frame
        .get_or_insert_with(|| String::from_utf8_lossy(m.child).into_owned());
    if !c.track.push(m.t, m.pose) {
        summary.skip(
            here.place(),
            format!(
                "odometry time {} is earlier than the previous odometry's",
                m.t
            ),
        );
        summary.warn(format!(
            "{}: time goes backwards; message skipped",
            here.place()
        ));
    }
    Ok(())
}
