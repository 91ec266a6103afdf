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

/// Which kind of table a table file is (`--table`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TableForm {
    /// Read off the file: a header naming a `sensor` column, or lines whose field counts are
    /// not a ring's, make it a firing table.
    #[default]
    Auto,
    /// A whole ring a line (`t x y heading r_0 …` or `t r_0 …`).
    Ring,
    /// One reading a line (`t sensor range [x y heading]`, odometry lines `t x y heading`).
    Firings,
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
    /// MCAP and firing tables: the longest firing cycle of the ring, seconds (`--window`);
    /// default [`DEFAULT_WINDOW_S`] for MCAP, [`DEFAULT_FIRINGS_WINDOW_S`] for firing tables.
    pub window_s: Option<f64>,
    /// Import with this pose for every snapshot when the file has no odometry
    /// (`--fixed-pose`), metres and radians.
    pub fixed_pose: Option<Pose>,
    /// Tables: the poses file (`--poses`).
    pub poses: Option<NamedBytes>,
    /// Tables: a ring a line or a reading a line (`--table`).
    pub table: TableForm,
}

/// The default MCAP firing-cycle window, seconds.
pub const DEFAULT_WINDOW_S: f64 = 0.1;

/// The default firing-cycle window of a one-reading-a-line table, seconds: sonars fired a
/// few at a time take up to about half a second for a ring (a Pioneer's 8 front sonars,
/// issue 40), and a sensor's repeat ends the cycle first.
pub const DEFAULT_FIRINGS_WINDOW_S: f64 = 1.0;

/// The longest firing-cycle window, seconds: a reading's offset from its snapshot's time is
/// held to this in the run log (docs/formats.md §2).
pub const MAX_WINDOW_S: f64 = 60.0;

impl Default for ImportOptions {
    fn default() -> Self {
        Self {
            layout: None,
            max_range_m: None,
            units: None,
            heading: AngleUnit::Degrees,
            window_s: None,
            fixed_pose: None,
            poses: None,
            table: TableForm::Auto,
        }
    }
}

impl ImportOptions {
    /// Refuses options no importer can use, whatever the format: a `--window` that is not a
    /// duration from 0 to 60 s, a `--max-range` that is
    /// not a length greater than 0 within 10 km, a `--fixed-pose` beyond 10 km or with a
    /// heading no robot turns to.
    pub fn check(&self) -> Result<(), ImportError> {
        let bad = |option: &str, message: String| ImportError::BadOption {
            option: option.into(),
            message,
        };
        if let Some(w) = self.window_s {
            if w.is_nan() || !(0.0..=MAX_WINDOW_S).contains(&w) {
                return Err(bad(
                    "--window",
                    format!(
                        "{}: expected a duration of at least 0 s and at most {MAX_WINDOW_S} s",
                        sane::show(w)
                    ),
                ));
            }
        }
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
