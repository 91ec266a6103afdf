//! Mapping parameters (docs/algorithm.md §7, §8) and the `--params` file (docs/formats.md §6).
//! Lengths are metres; defaults are the paper's inches converted.

mod declare;
mod needs;

pub use declare::{ParamKind, Parameter, Params, ParamsFile, SplitFile, PARAMETERS};
pub use needs::{parameter, UnmetNeed};

use crate::units::Units;
use serde::{Deserialize, Serialize};
use thiserror::Error;

/// How the recursive fit decides to split (docs/algorithm.md §3).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub enum SplitMode {
    /// Split when the farthest point is farther than its own ball radius `ξ·D/100`.
    Resolution,
    /// Split when the farthest point is farther than this length, metres.
    Fixed(f64),
}

/// How a piece's line is placed (docs/algorithm.md §3).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FitMode {
    /// The line through the first and last readings (Crowley's end-point fit).
    EndPoints,
    /// Total least squares through all readings; the end readings projected onto it.
    TotalLeastSquares,
}

/// `support_cap` of the `extended` preset: an update then costs the same after an hour of
/// driving as after a minute.
pub const EXTENDED_SUPPORT_CAP: usize = 64;

/// `memory_snapshots` of the `extended` preset, where `memory_travel` spans the memory: the
/// most snapshots a reading stays while the robot stands still or crawls (2.54 m at 6 mm a
/// cycle).
pub const EXTENDED_MEMORY_SNAPSHOTS: usize = 400;

/// A named parameter set.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Preset {
    /// The paper alone.
    Paper,
    /// The paper with every extension of docs/algorithm.md §8.
    Extended,
}

impl Preset {
    /// Parses `paper` or `extended`.
    pub fn parse(name: &str) -> Option<Preset> {
        match name {
            "paper" => Some(Preset::Paper),
            "extended" => Some(Preset::Extended),
            _ => None,
        }
    }
}

impl Default for Params {
    fn default() -> Self {
        Self::paper()
    }
}

impl Params {
    /// The values of a preset.
    pub fn preset(preset: Preset) -> Self {
        match preset {
            Preset::Paper => Self::paper(),
            Preset::Extended => Self::extended(),
        }
    }

    /// Whether a step's pose is corrected against the map (docs/algorithm.md §8.17): in full
    /// (`pose_correction`) or its heading alone (`heading_correction`).
    pub fn corrects_pose(&self) -> bool {
        self.pose_correction || self.heading_correction
    }

    /// The odometry's drift these parameters are calibrated with (`drift_deg_per_m`,
    /// `drift_per_turn_pct`: degrees per metre, percent of turns), when either is non-zero.
    pub fn drift_calibration(&self) -> Option<(f64, f64)> {
        let (deg_per_m, per_turn_pct) = (self.drift_deg_per_m, self.drift_per_turn_pct);
        (deg_per_m != 0.0 || per_turn_pct != 0.0).then_some((deg_per_m, per_turn_pct))
    }

    /// These parameters calibrated with the drift `(deg_per_m, per_turn_pct)` (see
    /// [`Self::drift_calibration`]; docs/algorithm.md §8.17), without a heading track.
    pub fn calibrated_by(&self, (deg_per_m, per_turn_pct): (f64, f64)) -> Params {
        Params {
            drift_deg_per_m: deg_per_m,
            drift_per_turn_pct: per_turn_pct,
            heading_track: None,
            ..self.clone()
        }
    }

    /// Whether a pass that drove `laps_driven` laps of its map
    /// ([`Map::laps_driven`](crate::mapping::model::map::Map::laps_driven); `None` without a
    /// confirmed wall) came back to its walls: at least `revisit_laps`, never when it is 0
    /// (docs/algorithm.md §8.17, "runs that come back"). Such a run is mapped again with its
    /// pose corrected against the map.
    ///
    /// ```
    /// use sonarmap::mapping::Params;
    /// let p = Params::extended(); // revisit_laps 2
    /// assert!(p.came_back(Some(2.0)) && !p.came_back(Some(1.9)) && !p.came_back(None));
    /// let never = Params { revisit_laps: 0, ..p };
    /// assert!(!never.came_back(Some(100.0)));
    /// ```
    pub fn came_back(&self, laps_driven: Option<f64>) -> bool {
        let laps = self.revisit_laps;
        laps > 0 && laps_driven.is_some_and(|driven| driven >= laps as f64)
    }

    /// Whether the heading alone is corrected: `heading_correction` without `pose_correction`
    /// (docs/algorithm.md §8.17, "the odometry's drift"), or in the first pass of
    /// [`Self::defers_pose_correction`].
    pub fn corrects_heading_alone(&self) -> bool {
        self.heading_correction && (!self.pose_correction || self.defers_pose_correction())
    }

    /// Whether `pose_correction` waits for a calibration: with `calibrate_first` (and
    /// `heading_correction`), a pass not yet calibrated corrects the heading alone, and only a
    /// second pass, calibrated by the drift the first found, corrects the pose
    /// (docs/algorithm.md §8.17, "calibrate, then correct").
    pub fn defers_pose_correction(&self) -> bool {
        self.pose_correction
            && self.calibrate_first
            && self.heading_correction
            && self.drift_calibration().is_none()
    }

    /// Whether the pose is corrected from the odometry the calibration mends: `pose_correction`
    /// and `heading_correction` with a drift calibration (docs/algorithm.md §8.17, "calibrate,
    /// then correct").
    pub fn corrects_calibrated_odometry(&self) -> bool {
        self.pose_correction && self.heading_correction && self.drift_calibration().is_some()
    }

    /// Whether a pass keeps the drift filter's steps for a second pass's heading track:
    /// `calibrate_first` with the heading corrected alone, not yet calibrated.
    pub fn keeps_drift_history(&self) -> bool {
        self.calibrate_first && self.corrects_heading_alone() && self.drift_calibration().is_none()
    }

    /// The first pass's smoothed heading error at snapshot `snapshot`, radians: with a
    /// calibration ([`Self::drift_calibration`]) and a heading track that goes with it and
    /// reaches the snapshot. A calibration changed since (by hand, in the app) leaves the
    /// track out.
    ///
    /// ```
    /// use std::sync::Arc;
    /// use sonarmap::mapping::model::heading_track::HeadingTrack;
    /// use sonarmap::mapping::Params;
    /// let track = HeadingTrack::new(vec![0.01, 0.02], (0.3, 1.0));
    /// let params = Params {
    ///     heading_track: Some(Arc::new(track)),
    ///     ..Params::extended().calibrated_by((0.3, 1.0))
    /// };
    /// assert_eq!(params.tracked_heading_error(1), Some(0.02));
    /// assert_eq!(params.tracked_heading_error(2), None); // past the first pass
    /// let changed = Params { drift_deg_per_m: 0.4, ..params.clone() };
    /// assert_eq!(changed.tracked_heading_error(1), None);
    /// ```
    pub fn tracked_heading_error(&self, snapshot: usize) -> Option<f64> {
        let drift = self.drift_calibration()?;
        let track = self.heading_track.as_ref()?;
        (track.drift() == drift)
            .then(|| track.error_at(snapshot))
            .flatten()
    }

    /// Checks every value; the first problem found is returned.
    pub fn validate(&self) -> Result<(), ParamsError> {
        let positive = |name: &'static str, v: f64| {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(ParamsError::NotPositive { name, value: v })
            }
        };
        let non_negative = |name: &'static str, v: f64| {
            if v.is_finite() && v >= 0.0 {
                Ok(())
            } else {
                Err(ParamsError::Negative { name, value: v })
            }
        };
        positive("accuracy_pct", self.accuracy_pct)?;
        positive("d_max", self.d_max_m)?;
        non_negative("min_range", self.min_range_m)?;
        non_negative("t_gap", self.t_gap_m)?;
        non_negative("max_step", self.max_step_m)?;
        non_negative("memory_gap", self.memory_gap_m)?;
        non_negative("memory_travel", self.memory_travel_m)?;
        non_negative("memory_min_span", self.memory_min_span_m)?;
        non_negative("confirm_spacing", self.confirm_spacing_m)?;
        non_negative("heading_window", self.heading_window_m)?;
        non_negative("standstill", self.standstill_m)?;
        if !(self.orientation_rad.is_finite()
            && (0.0..=std::f64::consts::FRAC_PI_2).contains(&self.orientation_rad))
        {
            return Err(ParamsError::OutOfRange {
                name: "orientation_deg",
                value: self.orientation_rad.to_degrees(),
                expected: "between 0 and 90 degrees",
            });
        }
        if let SplitMode::Fixed(t) = self.split {
            non_negative("split.fixed", t)?;
        }
        if self.memory_min_points < 2 {
            return Err(ParamsError::OutOfRange {
                name: "memory_min_points",
                value: self.memory_min_points as f64,
                expected: "at least 2",
            });
        }
        if self.min_range_m > self.d_max_m {
            return Err(ParamsError::OutOfRange {
                name: "min_range",
                value: self.min_range_m,
                expected: "no larger than d_max",
            });
        }
        Ok(())
    }

    /// Applies a `--params` file on top of `self` (the file's preset first, then its fields),
    /// and validates the result. Nothing changes on error.
    pub fn with_file(&self, file: &ParamsFile) -> Result<Params, ParamsError> {
        let mut p = match file.preset {
            Some(preset) => Params::preset(preset),
            None => self.clone(),
        };
        let units = match &file.units {
            None => Units::Inches,
            Some(name) => {
                Units::parse(name).ok_or_else(|| ParamsError::UnknownUnits(name.clone()))?
            }
        };
        p.apply_file_fields(file, units);
        p.validate()?;
        Ok(p)
    }

    /// The complete parameter set as a `--params` file in `units`.
    pub fn to_file(&self, units: Units) -> ParamsFile {
        let mut file = self.file_fields(units);
        file.units = Some(units.symbol().to_string());
        file
    }
}

/// A parameter value that cannot be used.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum ParamsError {
    /// Must be greater than zero.
    #[error("parameter `{name}` must be a finite number greater than 0, got {value}")]
    NotPositive {
        /// Parameter name as in files.
        name: &'static str,
        /// The value given.
        value: f64,
    },
    /// Must not be negative.
    #[error("parameter `{name}` must be a finite number of at least 0, got {value}")]
    Negative {
        /// Parameter name as in files.
        name: &'static str,
        /// The value given.
        value: f64,
    },
    /// Outside its range.
    #[error("parameter `{name}` = {value} is out of range: expected {expected}")]
    OutOfRange {
        /// Parameter name as in files.
        name: &'static str,
        /// The value given.
        value: f64,
        /// What is allowed.
        expected: &'static str,
    },
    /// Units not known.
    #[error("unknown units `{0}`: expected \"in\", \"mm\", \"cm\" or \"m\"")]
    UnknownUnits(String),
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paper_defaults_are_the_papers_inches() {
        let p = Params::paper();
        assert!((Units::Inches.from_m(p.t_gap_m) - 42.0).abs() < 1e-9);
        assert!((Units::Inches.from_m(p.d_max_m) - 255.0).abs() < 1e-9);
        assert!((p.orientation_rad.to_degrees() - 15.0).abs() < 1e-9);
        let e = Params::extended();
        assert_eq!(
            (p.support_cap, e.support_cap),
            (0, 64),
            "the paper keeps every point"
        );
        assert_eq!(
            (p.fit, e.fit),
            (FitMode::EndPoints, FitMode::TotalLeastSquares)
        );
        assert_eq!(
            (p.memory_snapshots, e.memory_snapshots),
            (0, EXTENDED_MEMORY_SNAPSHOTS)
        );
        // Every flag and count the presets set apart is off in the paper and on in extended.
        for q in Params::extension_parameters().filter(|q| q.name != "fit") {
            assert!(!p.is_on(q.name) && e.is_on(q.name), "{}", q.name);
        }
        assert!(p.validate().is_ok() && e.validate().is_ok());
    }

    #[test]
    fn negative_t_gap_and_zero_accuracy_are_errors() {
        let p = Params {
            t_gap_m: -1.0,
            ..Params::paper()
        };
        assert!(matches!(
            p.validate(),
            Err(ParamsError::Negative { name: "t_gap", .. })
        ));
        let p = Params {
            accuracy_pct: 0.0,
            ..Params::paper()
        };
        assert!(matches!(
            p.validate(),
            Err(ParamsError::NotPositive {
                name: "accuracy_pct",
                ..
            })
        ));
        let p = Params {
            accuracy_pct: f64::NAN,
            ..Params::paper()
        };
        assert!(p.validate().is_err());
    }

    #[test]
    fn params_file_applies_preset_then_fields_in_its_units() {
        let file: ParamsFile = serde_json::from_str(
            r#"{"preset": "extended", "t_gap": 100, "units": "cm", "split": {"fixed": 2.0}, "fit": "total_least_squares"}"#,
        )
        .unwrap();
        let p = Params::paper().with_file(&file).unwrap();
        assert!((p.t_gap_m - 1.0).abs() < 1e-12);
        assert_eq!(p.split, SplitMode::Fixed(0.02));
        assert_eq!(p.fit, FitMode::TotalLeastSquares);
        assert_eq!(p.memory_snapshots, EXTENDED_MEMORY_SNAPSHOTS);
        let back = Params::paper()
            .with_file(&p.to_file(Units::Millimetres))
            .unwrap();
        assert!((back.t_gap_m - p.t_gap_m).abs() < 1e-12);
        assert_eq!(back.memory_snapshots, EXTENDED_MEMORY_SNAPSHOTS);
    }
}
