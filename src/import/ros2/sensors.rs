//! Which sonar each reading is: the sensors named by frame id (else topic), in natural order,
//! and the layout that places them (`--layout`, or the mounts from `/tf_static`).

use super::messages::RangeMsg;
use super::tf::{chain, StaticTf, Tf};
use crate::import::error::{at, ImportError};
use crate::import::layout::Layout;
use crate::import::pose_track;
use crate::import::sane;
use crate::log::MAX_SENSORS;
use crate::sonar::{SensorLayout, SensorMount};
use std::collections::BTreeMap;
use std::rc::Rc;
use std::sync::Arc;

/// The names a reading refers to by index: the frame ids and the Range channels.
#[derive(Clone, Copy)]
pub(super) struct Keys<'a> {
    /// The interned frame ids.
    pub frames: &'a [Rc<str>],
    /// The Range channels.
    pub topics: &'a [Arc<mcap::Channel<'static>>],
}

impl<'a> Keys<'a> {
    /// The topic of `m`.
    pub fn topic(&self, m: &RangeMsg) -> &'a str {
        self.topics[m.topic as usize].topic.as_str()
    }

    /// The frame id of `m` (maybe empty).
    pub fn frame(&self, m: &RangeMsg) -> &'a str {
        &self.frames[m.frame as usize]
    }

    /// A reading's key: its frame id, else its topic.
    fn key(&self, m: &RangeMsg) -> &'a str {
        let frame = self.frame(m);
        if frame.is_empty() {
            self.topic(m)
        } else {
            frame
        }
    }

    /// The distinct keys of `ranges` in natural order; more than [`MAX_SENSORS`] are refused.
    pub fn distinct(&self, ranges: &[RangeMsg], file: &str) -> Result<Vec<&'a str>, ImportError> {
        let mut distinct: Vec<&str> = Vec::new();
        let mut seen_frames = vec![false; self.frames.len()];
        let mut seen_topics = vec![false; self.topics.len()];
        for m in ranges {
            let seen = if self.frames[m.frame as usize].is_empty() {
                &mut seen_topics[m.topic as usize]
            } else {
                &mut seen_frames[m.frame as usize]
            };
            if !*seen {
                *seen = true;
                distinct.push(self.key(m));
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
        Ok(distinct)
    }
}

/// The layout, and the sensor index of each distinct key (empty when the layout's `frames`
/// decide): `--layout` with `frames`; `--layout` without, its sensors taken by the keys in
/// natural order; else the mounts from `/tf_static`.
pub(super) fn layout<'a>(
    distinct: &[&'a str],
    layout: Option<&Layout>,
    static_tf: &StaticTf,
    odometry_frame: Option<&str>,
    file: &str,
) -> Result<(SensorLayout, BTreeMap<&'a str, usize>), ImportError> {
    let layout = match layout {
        Some(l) if !l.frames.is_empty() => return Ok((l.layout.clone(), BTreeMap::new())),
        Some(l) => {
            if distinct.len() != l.layout.len() {
                return Err(ImportError::NeedsLayout {
                    file: file.to_string(),
                    what: format!(
                        "the recording has {} sonar frames ({}) but the layout has {} sensors and no `frames` map to say which is which",
                        distinct.len(),
                        quoted(distinct),
                        l.layout.len()
                    ),
                });
            }
            l.layout.clone()
        }
        None => layout_from_tf(distinct, static_tf, odometry_frame, file)?,
    };
    Ok((layout, distinct.iter().copied().zip(0..).collect()))
}

/// Up to 20 names, quoted, and how many more.
fn quoted(names: &[&str]) -> String {
    let mut list: Vec<String> = names.iter().take(20).map(|n| sane::quote(n)).collect();
    if names.len() > 20 {
        list.push(format!("... {} more", names.len() - 20));
    }
    list.join(", ")
}

/// The mounts of the sonar frames `distinct`, each from its chain of static transforms up to
/// the robot's frame (the odometry's, else `base_link`).
fn layout_from_tf(
    distinct: &[&str],
    static_tf: &StaticTf,
    odometry_frame: Option<&str>,
    file: &str,
) -> Result<SensorLayout, ImportError> {
    if static_tf.is_empty() {
        return Err(ImportError::NeedsLayout {
            file: file.to_string(),
            what: "the recording has no /tf_static transforms for the sonar frames".into(),
        });
    }
    let base = odometry_frame.unwrap_or("base_link");
    let mut mounts = Vec::new();
    for &frame in distinct {
        let Some(Tf(x, y, yaw)) = chain(static_tf, base, frame) else {
            return Err(ImportError::NeedsLayout {
                file: file.to_string(),
                what: format!(
                    "/tf_static has no chain of transforms from {} to the sonar frame {}",
                    sane::quote(base),
                    sane::quote(frame)
                ),
            });
        };
        for v in [x, y] {
            sane::length(v, 1.0, "a sonar mount within 10 km of the robot", "m").map_err(|m| {
                at(
                    file,
                    format!(
                        "/tf_static, the chain from {} to {}",
                        sane::quote(base),
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
    Ok(SensorLayout { mounts })
}

/// The sensor of a reading, looked up once per frame id and topic rather than per reading.
pub(super) struct SensorOf {
    by_frame: Vec<Option<usize>>,
    by_topic: Vec<Option<usize>>,
    frame_empty: Vec<bool>,
    /// The layout's `frames` decide: the frame id, else the topic. Otherwise the sensors are
    /// the frame ids, or the topics for readings without one.
    layout_frames: bool,
}

impl SensorOf {
    /// The lookup for `keys`: by the layout's `frames` when it has them, else by `index_of`.
    pub fn new(keys: Keys, layout: Option<&Layout>, index_of: &BTreeMap<&str, usize>) -> Self {
        let layout_frames = layout.filter(|l| !l.frames.is_empty());
        SensorOf {
            by_frame: keys
                .frames
                .iter()
                .map(|f| match layout_frames {
                    Some(l) => l.frames.get(f.as_ref()).copied(),
                    None => index_of.get(f.as_ref()).copied(),
                })
                .collect(),
            by_topic: keys
                .topics
                .iter()
                .map(|c| match layout_frames {
                    Some(l) => l.frames.get(&c.topic).copied(),
                    None => index_of.get(c.topic.as_str()).copied(),
                })
                .collect(),
            frame_empty: keys.frames.iter().map(|f| f.is_empty()).collect(),
            layout_frames: layout_frames.is_some(),
        }
    }

    /// The sensor of `m`, when the layout or the keys name one.
    pub fn get(&self, m: &RangeMsg) -> Option<usize> {
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
}
