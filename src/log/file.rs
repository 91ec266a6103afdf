//! The serde shape of a `sonarmap-log` v1 file (docs/formats.md §2). Lengths are in the file's units,
//! angles in degrees. Unknown fields are ignored; required fields have no default.

use serde::de::{self, MapAccess, SeqAccess, Visitor};
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use std::fmt;

/// The `format` value of a run log.
pub const LOG_FORMAT: &str = "sonarmap-log";

/// A whole run-log file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LogFile {
    /// Always [`LOG_FORMAT`].
    pub format: String,
    /// Format version; 1.
    pub version: serde_json::Number,
    /// Human-readable name.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// `"in"`, `"mm"`, `"cm"` or `"m"`.
    pub units: String,
    /// The robot and its sonars.
    pub robot: RobotFile,
    /// Sonar hardware; defaults to the Polaroid 6500.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sensor: Option<SensorFile>,
    /// Ground truth.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub floor_plan: Option<FloorPlanFile>,
    /// The snapshots in time order.
    pub snapshots: Vec<SnapshotFile>,
}

/// `robot`: body radius and sonar mounts.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RobotFile {
    /// Body radius; required with the ring (it is the mount radius).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radius: Option<f64>,
    /// The sonars.
    pub sonars: SonarsFile,
}

/// `robot.sonars`: the ring shorthand or an explicit list of mounts.
#[derive(Clone, Debug, PartialEq)]
pub enum SonarsFile {
    /// `{"ring": {...}}`.
    Ring(RingFile),
    /// `[{"x", "y", "heading_deg"}, ...]`.
    Mounts(Vec<MountFile>),
}

/// The ring shorthand.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RingFile {
    /// Number of sonars (an integer; read as a number so that 16.5 gets a clear error).
    #[serde(serialize_with = "serialize_count")]
    pub count: f64,
    /// Angle between neighbouring sonars, degrees.
    pub spacing_deg: f64,
    /// Heading of sonar 0 against the robot's x axis, degrees (default 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub first_deg: Option<f64>,
}

fn serialize_count<S: Serializer>(count: &f64, s: S) -> Result<S::Ok, S::Error> {
    if count.fract() == 0.0 && *count >= 0.0 && *count < 9.0e15 {
        s.serialize_u64(*count as u64)
    } else {
        s.serialize_f64(*count)
    }
}

/// One explicit mount pose in the robot frame.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct MountFile {
    /// Robot-frame x.
    pub x: f64,
    /// Robot-frame y.
    pub y: f64,
    /// Beam axis against the robot's x axis, degrees.
    pub heading_deg: f64,
}

/// `sensor`: every field optional (Polaroid 6500 defaults in the file's units).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct SensorFile {
    /// Accuracy, percent of range.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub accuracy_pct: Option<f64>,
    /// Full beam width, degrees.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub beam_width_deg: Option<f64>,
    /// Largest range reported.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_range: Option<f64>,
    /// Blind zone.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub min_range: Option<f64>,
    /// Where an echo comes from: "cone" (the default) or "axis".
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub echo: Option<crate::sonar::EchoModel>,
}

/// `floor_plan`: walls `[x1, y1, x2, y2]` (optionally a fifth number, roughness in degrees)
/// and circles `[cx, cy, r]`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct FloorPlanFile {
    /// Walls.
    #[serde(default)]
    pub walls: Vec<Vec<f64>>,
    /// Pillars.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub circles: Vec<Vec<f64>>,
}

/// One snapshot.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SnapshotFile {
    /// Seconds; defaults to the snapshot's index.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub t: Option<f64>,
    /// Robot pose in the world.
    pub pose: PoseFile,
    /// One range per sensor; `null` is no echo.
    pub ranges: Vec<Option<f64>>,
    /// Where the robot truly stood, when `pose` is odometry that drifted from it (simulated
    /// runs given odometry error).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub true_pose: Option<PoseFile>,
    /// Each reading's own time minus `t`, seconds, one per sensor (sonars fired in sequence);
    /// absent when every reading was taken at `t`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub reading_dt_s: Vec<f64>,
}

/// A robot pose in the world.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct PoseFile {
    /// World x.
    pub x: f64,
    /// World y.
    pub y: f64,
    /// Heading of the robot's x axis, degrees.
    pub heading_deg: f64,
}

impl Serialize for SonarsFile {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        match self {
            SonarsFile::Ring(ring) => {
                let mut m = s.serialize_map(Some(1))?;
                m.serialize_entry("ring", ring)?;
                m.end()
            }
            SonarsFile::Mounts(mounts) => mounts.serialize(s),
        }
    }
}

impl<'de> Deserialize<'de> for SonarsFile {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct SonarsVisitor;
        impl<'de> Visitor<'de> for SonarsVisitor {
            type Value = SonarsFile;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str(r#"{"ring": {"count", "spacing_deg", "first_deg"}} or a list of {"x", "y", "heading_deg"}"#)
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<SonarsFile, A::Error> {
                let mut mounts = Vec::new();
                while let Some(m) = seq.next_element::<MountFile>()? {
                    mounts.push(m);
                }
                Ok(SonarsFile::Mounts(mounts))
            }
            fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<SonarsFile, A::Error> {
                let mut ring = None;
                while let Some(key) = map.next_key::<String>()? {
                    if key == "ring" {
                        if ring.is_some() {
                            return Err(de::Error::duplicate_field("ring"));
                        }
                        ring = Some(map.next_value::<RingFile>()?);
                    } else {
                        map.next_value::<de::IgnoredAny>()?;
                    }
                }
                ring.map(SonarsFile::Ring)
                    .ok_or_else(|| de::Error::missing_field("ring"))
            }
        }
        d.deserialize_any(SonarsVisitor)
    }
}
