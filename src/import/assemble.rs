//! The common last step of every importer: snapshots with times and ranges, plus odometry (or
//! a fixed pose), become a [`Run`]; readings at or beyond the maximum range become no echo.

use super::error::ImportError;
use super::pose_track::{PoseAt, PoseTrack, CLAMP_LIMIT_S};
use super::summary::ImportSummary;
use crate::geometry::Pose;
use crate::run::{Run, Snapshot};
use crate::sonar::{SensorLayout, SensorSpec};
use crate::units::Units;

/// Where a snapshot came from, for skip reasons (formatted only when used).
#[derive(Clone, Copy, Debug)]
pub(crate) enum Place {
    /// A line of a text file.
    Line(usize),
    /// The firing cycle starting at this MCAP message.
    Cycle(usize),
}

impl std::fmt::Display for Place {
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        match self {
            Place::Line(n) => write!(f, "line {n}"),
            Place::Cycle(i) => write!(f, "the cycle starting at MCAP message {i}"),
        }
    }
}

/// A snapshot before its pose is known.
pub(crate) struct RawSnapshot {
    /// Seconds.
    pub t: f64,
    /// Where it came from (`line 12`), for skip reasons.
    pub place: Place,
    /// One per sensor, metres; `None` is no echo.
    pub ranges_m: Vec<Option<f64>>,
    /// Each reading's own time minus `t`, seconds; empty when all were taken at `t`.
    pub reading_dt_s: Vec<f64>,
}

/// The robot and the run's metadata.
pub(crate) struct Hardware {
    pub name: String,
    pub units: Units,
    pub layout: SensorLayout,
    pub robot_radius_m: Option<f64>,
    pub sensor: SensorSpec,
}

/// Builds the run. `what_odometry` names the odometry messages looked for (for the error).
pub(crate) fn assemble(
    file: &str,
    raw: Vec<RawSnapshot>,
    track: &PoseTrack,
    fixed_pose: Option<Pose>,
    what_odometry: &str,
    hw: Hardware,
    summary: &mut ImportSummary,
) -> Result<Run, ImportError> {
    if raw.is_empty() {
        return Err(ImportError::NoSnapshots {
            file: file.to_string(),
            why: "the file has no sonar readings".to_string(),
        });
    }
    let use_fixed = fixed_pose_to_use(file, track, fixed_pose, what_odometry, summary)?;
    let max_range_m = hw.sensor.max_range_m;
    let mut clamped = 0;
    let mut snapshots = Vec::with_capacity(raw.len());
    for s in raw {
        let pose = match use_fixed {
            Some(p) => p,
            None => match track.at(s.t) {
                PoseAt::Inside(p) => p,
                PoseAt::Clamped(p) => {
                    clamped += 1;
                    p
                }
                PoseAt::Unknown => {
                    summary.skip(
                        s.place.to_string(),
                        format!(
                            "time {} is more than {CLAMP_LIMIT_S} s before the first or after the last odometry",
                            s.t
                        ),
                    );
                    continue;
                }
            },
        };
        snapshots.push(snapshot(s, pose, max_range_m, summary));
    }
    if clamped > 0 {
        summary.warn(format!(
            "{clamped} snapshots lie before the first or after the last odometry (within {CLAMP_LIMIT_S} s) and took its pose"
        ));
    }
    if snapshots.is_empty() {
        return Err(ImportError::NoSnapshots {
            file: file.to_string(),
            why: if summary.skipped.is_empty() {
                "the file has no sonar readings".to_string()
            } else {
                format!(
                    "every sonar reading was skipped (first: {}: {})",
                    summary.skipped[0].place, summary.skipped[0].reason
                )
            },
        });
    }
    summary.snapshots = snapshots.len();
    Ok(Run {
        name: hw.name,
        units: hw.units,
        robot_radius_m: hw.robot_radius_m,
        layout: hw.layout,
        sensor: hw.sensor,
        floor_plan: None,
        snapshots,
    })
}

/// The fixed pose to give every snapshot: `fixed_pose` when there is no odometry (without
/// either, the import is refused), none when there is (a fixed pose then is ignored, with a
/// warning).
fn fixed_pose_to_use(
    file: &str,
    track: &PoseTrack,
    fixed_pose: Option<Pose>,
    what_odometry: &str,
    summary: &mut ImportSummary,
) -> Result<Option<Pose>, ImportError> {
    Ok(match (track.is_empty(), fixed_pose) {
        (true, None) => {
            return Err(ImportError::NoOdometry {
                file: file.to_string(),
                what: what_odometry.to_string(),
            })
        }
        (true, Some(p)) => Some(p),
        (false, Some(_)) => {
            summary.warn("--fixed-pose is ignored: the file has odometry");
            None
        }
        (false, None) => None,
    })
}

/// The snapshot of `s` at `pose`: a range at or beyond `max_range_m` is no echo (counted).
fn snapshot(s: RawSnapshot, pose: Pose, max_range_m: f64, summary: &mut ImportSummary) -> Snapshot {
    let mut ranges_m = s.ranges_m;
    for r in ranges_m.iter_mut() {
        if matches!(r, Some(v) if *v >= max_range_m) {
            *r = None;
            summary.turned_no_echo += 1;
        }
    }
    summary.readings += ranges_m.len();
    Snapshot {
        t: s.t,
        pose,
        ranges_m,
        true_pose: None,
        reading_dt_s: s.reading_dt_s,
    }
}

/// The sensor of an import: the layout's (or the default), with the maximum range from
/// `--max-range`, else the layout's when it gives one, else `importer_default_m`.
pub(crate) fn sensor_with_max_range(
    layout: Option<&super::layout::Layout>,
    max_range_m: Option<f64>,
    importer_default_m: Option<f64>,
) -> SensorSpec {
    let mut sensor = layout.map(|l| l.sensor).unwrap_or_default();
    if let Some(m) = max_range_m {
        sensor.max_range_m = m;
    } else if layout.is_some_and(|l| l.max_range_given) {
    } else if let Some(m) = importer_default_m {
        sensor.max_range_m = m;
    }
    sensor
}
