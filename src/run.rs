//! A run in memory: the robot, its sonars, optional ground truth and the snapshots.
//! Every length is in metres; `units` remembers the file's unit for output.

use crate::geometry::{Point, Pose};
use crate::sonar::{SensorLayout, SensorSpec};
use crate::units::Units;
use serde::{Deserialize, Serialize};

/// One firing of the ring: when, where, and what each sensor read.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Snapshot {
    /// Time, seconds.
    pub t: f64,
    /// Robot pose in the world.
    pub pose: Pose,
    /// `ranges_m[k]` belongs to sensor `k`; `None` is no echo. Metres.
    pub ranges_m: Vec<Option<f64>>,
    /// Where the robot truly stood, when the run knows it apart from `pose` (a simulated run
    /// given odometry error: `pose` is then the odometry). The engine never reads it; `eval`
    /// measures the pose error with it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub true_pose: Option<Pose>,
    /// Each reading's own time minus `t`, seconds, one per sensor, for a run whose sonars fire
    /// in sequence; empty when every reading was taken at `t`. The engine converts a reading
    /// with the pose of its own moment ([`reading_poses`](crate::mapping::paper::reading_poses::reading_poses)).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub reading_dt_s: Vec<f64>,
}

/// A wall of the ground truth.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Wall {
    /// First end-point, metres.
    pub a: Point,
    /// Second end-point, metres.
    pub b: Point,
    /// Largest incidence angle that still echoes, radians; `None` uses the plan's.
    pub roughness_rad: Option<f64>,
}

/// A round pillar of the ground truth.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Circle {
    /// Centre, metres.
    pub centre: Point,
    /// Radius, metres.
    pub radius_m: f64,
}

/// Ground truth: walls and pillars.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct FloorPlan {
    /// Straight walls.
    pub walls: Vec<Wall>,
    /// Round pillars.
    pub circles: Vec<Circle>,
}

/// A run: everything needed to replay the mapper and draw it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Run {
    /// Human-readable name.
    pub name: String,
    /// The unit of the file the run came from (for output and display).
    pub units: Units,
    /// Robot body radius for drawing, metres.
    pub robot_radius_m: Option<f64>,
    /// Sonar mounts.
    pub layout: SensorLayout,
    /// Sonar hardware.
    pub sensor: SensorSpec,
    /// Ground truth, when known.
    pub floor_plan: Option<FloorPlan>,
    /// The snapshots, in time order.
    pub snapshots: Vec<Snapshot>,
}

impl Run {
    /// The same run cut to its first `n` snapshots (all of them when it has fewer).
    pub fn first_snapshots(&self, n: usize) -> Run {
        Run {
            name: self.name.clone(),
            units: self.units,
            robot_radius_m: self.robot_radius_m,
            layout: self.layout.clone(),
            sensor: self.sensor,
            floor_plan: self.floor_plan.clone(),
            snapshots: self.snapshots.iter().take(n).cloned().collect(),
        }
    }
}
