//! The `sonarmap-layout` v1 file: a robot's sonar mounts for importers whose recordings lack
//! them (`--layout`). It reuses the run log's `robot` and `sensor` blocks (docs/formats.md §2, §4):
//!
//! ```json
//! { "format": "sonarmap-layout", "version": 1, "name": "Pioneer 2/3 DX, 8 front + 8 rear",
//!   "units": "m",
//!   "robot": { "radius": 0.26, "sonars": [ {"x": 0.069, "y": 0.136, "heading_deg": 90}, ... ] },
//!   "sensor": { "max_range": 5.0 },
//!   "frames": { "sonar_0": 0, "/sonar/front_left": 1 } }
//! ```
//! - `format`, `version`, `units` and `robot` are required; `robot.sonars` is the ring shorthand
//!   or the explicit list, exactly as in a run log.
//! - `sensor` is optional (Polaroid 6500 defaults); its `max_range` is the default of
//!   `--max-range`: readings at or beyond it become no echo.
//! - `frames` (optional) maps a ROS `frame_id` or topic to a sensor index, for MCAP files.

use super::error::ImportError;
use super::sane;
use crate::log::{
    check_header, layout_from_robot, parse_json, parse_units, sensor_from_file, RobotFile,
    SensorFile,
};
use crate::sonar::{SensorLayout, SensorSpec};
use crate::units::Units;
use serde::Deserialize;
use std::collections::BTreeMap;

/// The `format` value of a layout file.
pub const LAYOUT_FORMAT: &str = "sonarmap-layout";

/// The Pioneer 2/3 DX 8 front + 8 rear sonars, max range 5 m (`assets/pioneer_8_8.layout.json`).
pub const PIONEER_8_8_LAYOUT_JSON: &str = include_str!("../../assets/pioneer_8_8.layout.json");

/// The Nomad 200 16-ring, radius 9 in, max range 255 in (`assets/nomad_200.layout.json`).
pub const NOMAD_200_LAYOUT_JSON: &str = include_str!("../../assets/nomad_200.layout.json");

#[derive(Deserialize)]
struct LayoutFile {
    format: String,
    version: serde_json::Number,
    #[serde(default)]
    name: Option<String>,
    units: String,
    robot: RobotFile,
    #[serde(default)]
    sensor: Option<SensorFile>,
    #[serde(default)]
    frames: BTreeMap<String, f64>,
}

/// A parsed layout file, in metres and radians.
#[derive(Clone, Debug, PartialEq)]
pub struct Layout {
    /// Human-readable name.
    pub name: Option<String>,
    /// The file's unit.
    pub units: Units,
    /// Sonar mounts.
    pub layout: SensorLayout,
    /// Robot body radius, metres.
    pub robot_radius_m: Option<f64>,
    /// The sensor (defaults where the file has no `sensor`).
    pub sensor: SensorSpec,
    /// True when the file gave `sensor.max_range`.
    pub max_range_given: bool,
    /// ROS frame id or topic → sensor index.
    pub frames: BTreeMap<String, usize>,
}

/// Parses a `sonarmap-layout` v1 file; `source_name` names it in errors.
pub fn parse_layout(bytes: &[u8], source_name: &str) -> Result<Layout, ImportError> {
    let f = source_name;
    let file: LayoutFile = parse_json(bytes, f)?;
    check_header(&file.format, &file.version, LAYOUT_FORMAT, f)?;
    let units = parse_units(&file.units, f)?;
    let (layout, robot_radius_m) = layout_from_robot(&file.robot, units, f, "$.robot")?;
    let sensor = sensor_from_file(file.sensor.as_ref(), units, f, "$.sensor")?;
    check_values(&file, units, robot_radius_m, &sensor, f)?;
    let mut frames = BTreeMap::new();
    let mut frame_of: BTreeMap<usize, &str> = BTreeMap::new();
    for (name, &k) in &file.frames {
        if !(k.fract() == 0.0 && k >= 0.0 && (k as usize) < layout.len()) {
            return Err(super::error::at(
                f,
                format!("$.frames.{name}"),
                format!(
                    "sensor index {} is not a sensor of the layout: expected a whole number from 0 to {}",
                    sane::show(k),
                    layout.len().saturating_sub(1)
                ),
            ));
        }
        if let Some(other) = frame_of.insert(k as usize, name) {
            return Err(super::error::at(
                f,
                format!("$.frames.{}", sane::quote(name)),
                format!(
                    "sensor {k} is already the sensor of frame {}: expected one frame or topic per sensor (two would make two snapshots of one firing)",
                    sane::quote(other)
                ),
            ));
        }
        frames.insert(name.clone(), k as usize);
    }
    Ok(Layout {
        name: file.name,
        units,
        layout,
        robot_radius_m,
        sensor,
        max_range_given: file.sensor.and_then(|s| s.max_range).is_some(),
        frames,
    })
}

/// Holds the layout's values to what a robot has (the run-log loader checks only that they
/// are finite): mounts and radius within 10 km, ring spacing and first heading within a
/// turn, mount headings within ±[`sane::MAX_HEADING_RAD`], a beam width up to 180°, accuracy
/// up to 100 %, `max_range` within 10 km and above `min_range`.
fn check_values(
    file: &LayoutFile,
    units: Units,
    radius_m: Option<f64>,
    sensor: &SensorSpec,
    f: &str,
) -> Result<(), ImportError> {
    let u = units.metres_per_unit();
    if let Some(r) = radius_m {
        sane::length(r / u, u, "a robot radius", units.symbol())
            .map_err(|m| super::error::at(f, "$.robot.radius", m))?;
    }
    check_sonars(&file.robot.sonars, units, f)?;
    check_sensor(file, units, sensor, f)
}

/// [`check_values`] of the sonars: ring spacing and first heading within a turn, mounts
/// within 10 km and their headings within two turns.
fn check_sonars(sonars: &crate::log::SonarsFile, units: Units, f: &str) -> Result<(), ImportError> {
    let fail = |path: &str, message: String| super::error::at(f, path, message);
    let u = units.metres_per_unit();
    let sym = units.symbol();
    match sonars {
        crate::log::SonarsFile::Ring(ring) => {
            let turn = |v: f64, path: &str| {
                sane::within(v, 360.0, "an angle within a turn", "°").map_err(|m| fail(path, m))
            };
            turn(ring.spacing_deg, "$.robot.sonars.ring.spacing_deg")?;
            turn(
                ring.first_deg.unwrap_or(0.0),
                "$.robot.sonars.ring.first_deg",
            )?;
        }
        crate::log::SonarsFile::Mounts(mounts) => {
            for (k, m) in mounts.iter().enumerate() {
                for (v, name) in [(m.x, "x"), (m.y, "y")] {
                    sane::length(v, u, "a mount offset", sym)
                        .map_err(|e| fail(&format!("$.robot.sonars[{k}].{name}"), e))?;
                }
                sane::within(
                    m.heading_deg,
                    720.0,
                    "a mount heading within two turns",
                    "°",
                )
                .map_err(|e| fail(&format!("$.robot.sonars[{k}].heading_deg"), e))?;
            }
        }
    }
    Ok(())
}

/// [`check_values`] of the sensor: beam width, accuracy, the ranges, `min_range` below
/// `max_range` (of `sensor`, the sensor as read).
fn check_sensor(
    file: &LayoutFile,
    units: Units,
    sensor: &SensorSpec,
    f: &str,
) -> Result<(), ImportError> {
    let fail = |path: &str, message: String| super::error::at(f, path, message);
    let u = units.metres_per_unit();
    let sym = units.symbol();
    let given = file.sensor.unwrap_or_default();
    if let Some(w) = given.beam_width_deg {
        if !(sane::MIN_BEAM_DEG..=180.0).contains(&w) {
            return Err(fail(
                "$.sensor.beam_width_deg",
                format!(
                    "{}°: expected a beam width from {}° to 180°",
                    sane::show(w),
                    sane::MIN_BEAM_DEG
                ),
            ));
        }
    }
    if let Some(a) = given.accuracy_pct {
        if !(sane::MIN_ACCURACY_PCT..=100.0).contains(&a) {
            return Err(fail(
                "$.sensor.accuracy_pct",
                format!(
                    "{} %: expected an accuracy from {} % to 100 %",
                    sane::show(a),
                    sane::MIN_ACCURACY_PCT
                ),
            ));
        }
    }
    if let Some(r) = given.max_range {
        sane::length(r, u, "a maximum range", sym).map_err(|m| fail("$.sensor.max_range", m))?;
        if r * u < sane::MIN_MAX_RANGE_M {
            return Err(fail(
                "$.sensor.max_range",
                format!(
                    "{} {sym}: expected a maximum range of at least {} m",
                    sane::show(r),
                    sane::MIN_MAX_RANGE_M
                ),
            ));
        }
    }
    if let Some(r) = given.min_range {
        sane::length(r, u, "a minimum range", sym).map_err(|m| fail("$.sensor.min_range", m))?;
    }
    if sensor.min_range_m >= sensor.max_range_m {
        let path = if given.min_range.is_some() {
            "$.sensor.min_range"
        } else {
            "$.sensor.max_range"
        };
        return Err(fail(
            path,
            format!(
                "min_range {} {sym} is not below max_range {} {sym}: expected min_range < max_range",
                sensor.min_range_m / u,
                sensor.max_range_m / u
            ),
        ));
    }
    Ok(())
}

/// A shipped layout by name: `pioneer_8_8` or `nomad_200`.
pub fn builtin_layout(name: &str) -> Option<Layout> {
    let json = match name {
        "pioneer_8_8" => PIONEER_8_8_LAYOUT_JSON,
        "nomad_200" => NOMAD_200_LAYOUT_JSON,
        _ => return None,
    };
    parse_layout(json.as_bytes(), name).ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shipped_layouts_parse() {
        let p = builtin_layout("pioneer_8_8").unwrap();
        assert_eq!(p.layout.len(), 16);
        assert!((p.sensor.max_range_m - 5.0).abs() < 1e-12);
        assert!(p.max_range_given);
        let n = builtin_layout("nomad_200").unwrap();
        assert_eq!(n.layout.len(), 16);
        assert!((n.sensor.max_range_m - 255.0 * 0.0254).abs() < 1e-12);
        assert!((n.robot_radius_m.unwrap() - 0.2286).abs() < 1e-12);
    }
}
