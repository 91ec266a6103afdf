//! The floor plan of the simulator (`sonarmap-plan` v1, docs/formats.md §3) and path interpolation.

use crate::geometry::Pose;
use crate::log::{
    check_header, floor_plan_from_file, floor_plan_to_file, layout_from_robot, parse_json,
    parse_units, robot_to_file, sensor_from_file, tidy, FloorPlanFile, LogError, RingFile,
    RobotFile, SensorFile, SonarsFile,
};
use crate::run::FloorPlan;
use crate::sonar::{SensorLayout, SensorSpec};
use crate::units::{inches, Units};
use serde::{Deserialize, Serialize};

/// The `format` value of a floor plan.
pub const PLAN_FORMAT: &str = "sonarmap-plan";

/// Default roughness of a wall without its own: the largest incidence angle that still echoes.
pub const DEFAULT_ROUGHNESS_DEG: f64 = 30.0;

/// A whole plan file. Lengths in its units, angles in degrees.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PlanFile {
    /// Always [`PLAN_FORMAT`].
    pub format: String,
    /// Format version; 1.
    pub version: serde_json::Number,
    /// Name given to the simulated run.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// Free text (why the plan is as it is).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub note: Option<String>,
    /// `"in"`, `"mm"`, `"cm"` or `"m"`.
    pub units: String,
    /// Walls `[x1, y1, x2, y2]` or `[x1, y1, x2, y2, roughness_deg]`.
    #[serde(default)]
    pub walls: Vec<Vec<f64>>,
    /// Pillars `[cx, cy, r]`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub circles: Vec<Vec<f64>>,
    /// Poses `[x, y, heading_deg]` (waypoints when `step` or `turn_step_deg` is given).
    pub path: Vec<Vec<f64>>,
    /// Longest distance between snapshots along the path.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub step: Option<f64>,
    /// Largest turn between snapshots along the path, degrees.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub turn_step_deg: Option<f64>,
    /// Largest incidence angle that still echoes, for walls without their own; degrees.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub roughness_deg: Option<f64>,
    /// The robot (default: the Nomad 200's 16-sonar ring of radius 9 in).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub robot: Option<RobotFile>,
    /// The sonar hardware (default: the Polaroid 6500).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sensor: Option<SensorFile>,
    /// Simulator settings.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sim: Option<SimFile>,
}

/// `sim`: simulator settings, all optional.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct SimFile {
    /// Ranges are rounded to multiples of this length (default 0.1 in).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub resolution: Option<f64>,
    /// Probability that a reading is lost (default 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dropout: Option<f64>,
    /// Probability of a multipath ghost: a long spurious range (default 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ghost: Option<f64>,
    /// Angle between the rays that sample the beam, degrees (default 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ray_step_deg: Option<f64>,
    /// A ray hitting this close to a concave corner echoes whatever its angle (default 1 in).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub corner_tolerance: Option<f64>,
    /// Surfaces a ray may be mirrored off before one echoes it (multipath), 0 to
    /// [`MAX_BOUNCES`] (default 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bounces: Option<u32>,
}

/// The most mirror bounces a plan's `sim.bounces` may ask for.
pub const MAX_BOUNCES: u32 = 4;

/// Simulator settings in metres and radians.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct SimSettings {
    /// Range quantum, metres.
    pub resolution_m: f64,
    /// Probability of losing a reading.
    pub dropout: f64,
    /// Probability of a ghost reading.
    pub ghost: f64,
    /// Angle between sampling rays, radians.
    pub ray_step_rad: f64,
    /// Corner reflector distance, metres.
    pub corner_tolerance_m: f64,
    /// Surfaces a ray may be mirrored off before one echoes it (multipath; 0: none).
    pub bounces: u32,
}

impl Default for SimSettings {
    fn default() -> Self {
        Self {
            resolution_m: inches(0.1),
            dropout: 0.0,
            ghost: 0.0,
            ray_step_rad: 1f64.to_radians(),
            corner_tolerance_m: inches(1.0),
            bounces: 0,
        }
    }
}

/// A floor plan ready to simulate: metres and radians.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Plan {
    /// Name of the run it makes.
    pub name: String,
    /// Free text.
    pub note: Option<String>,
    /// The unit of the file (the simulated log uses it).
    pub units: Units,
    /// Walls and pillars.
    pub floor_plan: FloorPlan,
    /// Roughness of walls without their own (and of pillars), radians.
    pub roughness_rad: f64,
    /// Robot body radius, metres.
    pub robot_radius_m: Option<f64>,
    /// Sonar mounts.
    pub layout: SensorLayout,
    /// Sonar hardware.
    pub sensor: SensorSpec,
    /// One pose per snapshot (after interpolation).
    pub poses: Vec<Pose>,
    /// Simulator settings.
    pub sim: SimSettings,
}

/// `plan` as a `sonarmap-plan` v1 file in its units: every pose of its path (already
/// interpolated, so no `step`), its robot, sensor and simulator settings. Loading it gives the
/// plan back to within 1e-9 of a unit (an independent simulator can read the same scene).
pub fn plan_to_file(plan: &Plan) -> PlanFile {
    let u = plan.units;
    let len = |v_m: f64| tidy(u.from_m(v_m));
    let deg = |v_rad: f64| tidy(v_rad.to_degrees());
    let floor = floor_plan_to_file(&plan.floor_plan, u);
    PlanFile {
        format: PLAN_FORMAT.to_string(),
        version: 1.into(),
        name: Some(plan.name.clone()),
        note: plan.note.clone(),
        units: u.symbol().to_string(),
        walls: floor.walls,
        circles: floor.circles,
        path: plan
            .poses
            .iter()
            .map(|p| vec![len(p.x), len(p.y), deg(p.heading_rad)])
            .collect(),
        step: None,
        turn_step_deg: None,
        roughness_deg: Some(deg(plan.roughness_rad)),
        robot: Some(robot_to_file(&plan.layout, plan.robot_radius_m, u)),
        sensor: Some(SensorFile {
            accuracy_pct: Some(tidy(plan.sensor.accuracy_pct)),
            beam_width_deg: Some(deg(plan.sensor.beam_width_rad)),
            max_range: Some(len(plan.sensor.max_range_m)),
            min_range: Some(len(plan.sensor.min_range_m)),
            echo: None,
        }),
        sim: Some(SimFile {
            resolution: Some(len(plan.sim.resolution_m)),
            dropout: Some(plan.sim.dropout),
            ghost: Some(plan.sim.ghost),
            ray_step_deg: Some(deg(plan.sim.ray_step_rad)),
            corner_tolerance: Some(len(plan.sim.corner_tolerance_m)),
            bounces: (plan.sim.bounces > 0).then_some(plan.sim.bounces),
        }),
    }
}

/// Parses a `sonarmap-plan` v1 file. `source_name` names it in errors. Pure.
pub fn load_plan(bytes: &[u8], source_name: &str) -> Result<Plan, LogError> {
    let file: PlanFile = parse_json(bytes, source_name)?;
    plan_from_file(&file, source_name)
}

fn bad(file: &str, path: String, value: impl ToString, expected: &'static str) -> LogError {
    LogError::BadValue {
        file: file.to_string(),
        path,
        value: value.to_string(),
        expected,
    }
}

/// Converts a parsed plan file, checking every value.
pub fn plan_from_file(file: &PlanFile, source_name: &str) -> Result<Plan, LogError> {
    let f = source_name;
    check_header(&file.format, &file.version, PLAN_FORMAT, f)?;
    let units = parse_units(&file.units, f)?;
    let floor_plan = floor_plan_from_file(
        &FloorPlanFile {
            walls: file.walls.clone(),
            circles: file.circles.clone(),
        },
        units,
        f,
        "$.",
    )?;
    let roughness_deg = file.roughness_deg.unwrap_or(DEFAULT_ROUGHNESS_DEG);
    if !(0.0..=90.0).contains(&roughness_deg) {
        return Err(bad(
            f,
            "$.roughness_deg".into(),
            roughness_deg,
            "an angle between 0 and 90 degrees",
        ));
    }
    let nomad = RobotFile {
        radius: Some(units.from_m(inches(9.0))),
        sonars: SonarsFile::Ring(RingFile {
            count: 16.0,
            spacing_deg: 22.5,
            first_deg: None,
        }),
    };
    let (layout, robot_radius_m) =
        layout_from_robot(file.robot.as_ref().unwrap_or(&nomad), units, f, "$.robot")?;
    let sensor = sensor_from_file(file.sensor.as_ref(), units, f, "$.sensor")?;
    let sim = sim_settings(file.sim.unwrap_or_default(), units, f)?;
    let poses = path_poses(file, units, f)?;
    Ok(Plan {
        name: file.name.clone().unwrap_or_else(|| source_name.to_string()),
        note: file.note.clone(),
        units,
        floor_plan,
        roughness_rad: roughness_deg.to_radians(),
        robot_radius_m,
        layout,
        sensor,
        poses,
        sim,
    })
}

/// The simulator's settings of a plan's `sim` (in `units`), each checked; defaults where
/// absent.
fn sim_settings(s: SimFile, units: Units, f: &str) -> Result<SimSettings, LogError> {
    let d = SimSettings::default();
    let prob = |v: Option<f64>, name: &str| match v {
        None => Ok(0.0),
        Some(p) if (0.0..=1.0).contains(&p) => Ok(p),
        Some(p) => Err(bad(
            f,
            format!("$.sim.{name}"),
            p,
            "a probability between 0 and 1",
        )),
    };
    let positive = |v: Option<f64>, name: &str, default: f64, to: &dyn Fn(f64) -> f64| match v {
        None => Ok(default),
        Some(x) if x.is_finite() && x > 0.0 => Ok(to(x)),
        Some(x) => Err(bad(
            f,
            format!("$.sim.{name}"),
            x,
            "a finite number greater than 0",
        )),
    };
    Ok(SimSettings {
        resolution_m: positive(s.resolution, "resolution", d.resolution_m, &|x| {
            units.to_m(x)
        })?,
        dropout: prob(s.dropout, "dropout")?,
        ghost: prob(s.ghost, "ghost")?,
        ray_step_rad: positive(s.ray_step_deg, "ray_step_deg", d.ray_step_rad, &|x: f64| {
            x.to_radians()
        })?,
        corner_tolerance_m: positive(
            s.corner_tolerance,
            "corner_tolerance",
            d.corner_tolerance_m,
            &|x| units.to_m(x),
        )?,
        bounces: match s.bounces {
            None => d.bounces,
            Some(n) if n <= MAX_BOUNCES => n,
            Some(n) => {
                return Err(bad(
                    f,
                    "$.sim.bounces".to_owned(),
                    n,
                    "a whole number of bounces from 0 to 4",
                ))
            }
        },
    })
}

/// The poses of a plan's `path` (in `units`): its waypoints, checked, interpolated at its
/// `step` and `turn_step_deg`; at most 10,000,000.
fn path_poses(file: &PlanFile, units: Units, f: &str) -> Result<Vec<Pose>, LogError> {
    if file.path.is_empty() {
        return Err(LogError::Empty {
            file: f.to_string(),
            path: "$.path".into(),
            expected: "at least one pose [x, y, heading_deg]",
        });
    }
    let mut waypoints = Vec::with_capacity(file.path.len());
    for (i, p) in file.path.iter().enumerate() {
        if p.len() != 3 || p.iter().any(|v| !v.is_finite()) {
            return Err(bad(
                f,
                format!("$.path[{i}]"),
                format!("{p:?}"),
                "[x, y, heading_deg] of finite numbers",
            ));
        }
        waypoints.push(Pose::new(
            units.to_m(p[0]),
            units.to_m(p[1]),
            p[2].to_radians(),
        ));
    }
    let step_m = match file.step {
        None => None,
        Some(v) if v.is_finite() && v > 0.0 => Some(units.to_m(v)),
        Some(v) => return Err(bad(f, "$.step".into(), v, "a finite length greater than 0")),
    };
    let turn_step_rad = match file.turn_step_deg {
        None => None,
        Some(v) if v.is_finite() && v > 0.0 => Some(v.to_radians()),
        Some(v) => {
            return Err(bad(
                f,
                "$.turn_step_deg".into(),
                v,
                "a finite angle greater than 0",
            ))
        }
    };
    let poses = interpolate_path(&waypoints, step_m, turn_step_rad);
    if poses.len() > 10_000_000 {
        return Err(bad(
            f,
            "$.step".into(),
            poses.len(),
            "a path of at most 10,000,000 snapshots",
        ));
    }
    Ok(poses)
}

/// Cuts the path between waypoints into poses at most `step_m` apart and `turn_step_rad`
/// apart (each limit only when given). Headings turn the short way round. Every waypoint is
/// one of the poses; without limits the waypoints are returned as they are.
///
/// ```
/// use sonarmap::geometry::Pose;
/// use sonarmap::sim::interpolate_path;
/// let poses = interpolate_path(&[Pose::new(0.0, 0.0, 0.0), Pose::new(1.0, 0.0, 0.0)], Some(0.3), None);
/// assert_eq!(poses.len(), 5); // 0, 0.25, 0.5, 0.75, 1
/// ```
pub fn interpolate_path(
    waypoints: &[Pose],
    step_m: Option<f64>,
    turn_step_rad: Option<f64>,
) -> Vec<Pose> {
    if step_m.is_none() && turn_step_rad.is_none() {
        return waypoints.to_vec();
    }
    let mut poses = Vec::new();
    for pair in waypoints.windows(2) {
        let (a, b) = (pair[0], pair[1]);
        let dist = a.distance_to(&b);
        let turn = (b.heading_rad - a.heading_rad + std::f64::consts::PI)
            .rem_euclid(std::f64::consts::TAU)
            - std::f64::consts::PI;
        let pieces = |amount: f64, limit: Option<f64>| {
            limit.map_or(1.0, |l| (amount / l - 1e-9).ceil().max(1.0))
        };
        let n = pieces(dist, step_m).max(pieces(turn.abs(), turn_step_rad)) as usize;
        for k in 0..n {
            let s = k as f64 / n as f64;
            poses.push(Pose::new(
                a.x + (b.x - a.x) * s,
                a.y + (b.y - a.y) * s,
                a.heading_rad + turn * s,
            ));
        }
    }
    if let Some(last) = waypoints.last() {
        poses.push(*last);
    }
    poses
}
