//! What the caller tells an importer: the layout, the no-echo range, units, the fixed pose.

use super::error::ImportError;
use super::layout::Layout;
use super::sane;
use crate::geometry::Pose;
use crate::units::Units;

/// The unit of headings in tables and of `--fixed-pose`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum AngleUnit {
    /// Degrees (the default for tables, as in run logs).
    #[default]
    Degrees,
    /// Radians.
    Radians,
}

impl AngleUnit {
    /// An angle in this unit, in radians.
    pub fn to_rad(self, angle: f64) -> f64 {
        match self {
            AngleUnit::Degrees => angle.to_radians(),
            AngleUnit::Radians => angle,
        }
    }
}

/// A second input file (the poses table) as bytes, with its name for messages.
#[derive(Clone, Debug, PartialEq)]
pub struct NamedBytes {
    /// The file's name, for error messages.
    pub name: String,
    /// Its content.
    pub bytes: Vec<u8>,
}

/// Options of every importer. `Default` is what `run` and `eval` use: nothing given.
#[derive(Clone, Debug, PartialEq)]
pub struct ImportOptions {
    /// Sensor layout (`--layout`); overrides a file's own geometry.
    pub layout: Option<Layout>,
    /// Readings at or beyond this are no echo (`--max-range`), metres. Default: the layout's
    /// `sensor.max_range`, else the importer's (Player: 5 m; MCAP: each message's `max_range`).
    pub max_range_m: Option<f64>,
    /// The length unit of tables and of the written log (`--units`); default metres.
    pub units: Option<Units>,
    /// The heading unit of tables (`--heading-unit`); default degrees.
    pub heading: AngleUnit,
    /// MCAP: the longest firing cycle of the ring, seconds (`--window`, default 0.1).
    pub window_s: f64,
    /// Import with this pose for every snapshot when the file has no odometry
    /// (`--fixed-pose`), metres and radians.
    pub fixed_pose: Option<Pose>,
    /// Tables: the poses file (`--poses`).
    pub poses: Option<NamedBytes>,
}

/// The default MCAP firing-cycle window, seconds.
pub const DEFAULT_WINDOW_S: f64 = 0.1;

impl Default for ImportOptions {
    fn default() -> Self {
        Self {
            layout: None,
            max_range_m: None,
            units: None,
            heading: AngleUnit::Degrees,
            window_s: DEFAULT_WINDOW_S,
            fixed_pose: None,
            poses: None,
        }
    }
}

impl ImportOptions {
    /// Refuses options no importer can use, whatever the format: a `--window` that is not a
    /// duration of at least 0 s (or is longer than any recording), a `--max-range` that is
    /// not a length greater than 0 within 10 km, a `--fixed-pose` beyond 10 km or with a
    /// heading no robot turns to.
    pub fn check(&self) -> Result<(), ImportError> {
        let bad = |option: &str, message: String| ImportError::BadOption {
            option: option.into(),
            message,
        };
        if self.window_s.is_nan() || self.window_s < 0.0 {
            return Err(bad(
                "--window",
                format!("{}: expected a duration of at least 0 s", self.window_s),
            ));
        }
        sane::time(self.window_s, "a duration in seconds").map_err(|m| bad("--window", m))?;
        if let Some(r) = self.max_range_m {
            if r.is_nan() || r < sane::MIN_MAX_RANGE_M {
                return Err(bad(
                    "--max-range",
                    format!(
                        "{} m: expected a range of at least {} m",
                        sane::show(r),
                        sane::MIN_MAX_RANGE_M
                    ),
                ));
            }
            sane::length(r, 1.0, "a range", "m").map_err(|m| bad("--max-range", m))?;
        }
        if let Some(p) = self.fixed_pose {
            for (v, what) in [(p.x, "x"), (p.y, "y")] {
                sane::length(v, 1.0, what, "m").map_err(|m| bad("--fixed-pose", m))?;
            }
            sane::heading_rad(p.heading_rad, "a heading").map_err(|m| bad("--fixed-pose", m))?;
        }
        Ok(())
    }
}
