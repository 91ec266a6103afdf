//! Mapping parameters (docs/algorithm.md §7, §8) and the `--params` file (docs/formats.md §6).
//! Lengths are metres; defaults are the paper's inches converted.

use crate::units::{inches, Units};
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

/// Every parameter of the mapper. Lengths in metres, angles in radians.
/// Persisted sets (the app's settings) written before a parameter existed take the paper's
/// value for it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct Params {
    /// Accuracy `ξ`, percent of range (§2).
    pub accuracy_pct: f64,
    /// Readings beyond this are discarded (§3.1).
    pub d_max_m: f64,
    /// Readings below this are discarded (blind zone).
    pub min_range_m: f64,
    /// Cluster gap threshold (§3.1, §4).
    pub t_gap_m: f64,
    /// Orientation threshold `θ_o` (§3.3.1).
    pub orientation_rad: f64,
    /// Split rule of the recursive fit.
    pub split: SplitMode,
    /// Line placement of the recursive fit.
    pub fit: FitMode,
    /// Largest step between snapshots before a warning (§3.3.1).
    pub max_step_m: f64,
    /// Correlation of new faces (§3.3.3) on or off.
    pub correlate: bool,
    /// Point memory length in snapshots; 0 is off (docs/algorithm.md §8).
    pub memory_snapshots: usize,
    /// Link distance of remembered points.
    pub memory_gap_m: f64,
    /// Fewest points of a memory segment.
    pub memory_min_points: usize,
    /// Constant-depth groups on or off (docs/algorithm.md §8).
    pub constant_depth: bool,
    /// Fuse map segments that match an updated segment into it (a long-run bound beyond the
    /// paper, docs/algorithm.md §8; see `mapping::merge`).
    pub merge_duplicates: bool,
    /// Supporting points a segment keeps, the most recent ones; 0 keeps them all (a long-run
    /// bound beyond the paper, docs/algorithm.md §5 and §8).
    pub support_cap: usize,
    /// Refuse a correlation corner that would collapse a line, joining the two end-points by a
    /// connecting segment instead (beyond the paper, docs/algorithm.md §6 and §8).
    pub corner_guard: bool,
    /// Arc rule: a cluster whose readings, from two or more sensors, pass the ball test
    /// pairwise is one reflector point, filed as a point feature instead of fitted
    /// (docs/algorithm.md §8.5).
    pub arc_features: bool,
    /// Readings a confirmed point feature explains (its range from the sensor, inside the
    /// beam) join no cluster (docs/algorithm.md §8.5).
    pub explain_readings: bool,
    /// A segment whose perpendicular foot lies inside a beam that read farther is removed
    /// (docs/algorithm.md §8.6).
    pub free_space: bool,
    /// Segments are tentative until readings of two snapshots support them as a plane
    /// (docs/algorithm.md §8.7).
    pub confirm_segments: bool,
    /// With `confirm_segments`: a segment made in one step from readings of several snapshots
    /// (a point-memory piece) is confirmed when two of them, of distinct snapshots, support it
    /// as a plane from sensors 8 in or more apart along it (docs/algorithm.md §8.7).
    pub baseline_confirm: bool,
    /// With `confirm_segments`: a confirmed segment that a refit (§5) turned more than `θ_o` or
    /// moved more than `2·tol(D)` off its line is tentative again (docs/algorithm.md §8.7).
    pub refit_unconfirms: bool,
    /// A NEW FACE needs a reading that supports it as a plane (docs/algorithm.md §8.7).
    pub plane_gate: bool,
    /// A fitted piece's readings move to where one plane's echoes came from, when a line fitted
    /// from their ranges explains them all (docs/algorithm.md §8.10).
    pub echo_fit: bool,
    /// A segment lying wholly near the junction of two confirmed walls and turned from both
    /// is a corner's diagonal and leaves the map (docs/algorithm.md §8.11).
    pub corner_diagonals: bool,
    /// The readings of removed diagonals are kept as evidence; a round pillar that explains
    /// enough of them, seen from apart, is filed as a rounded feature and explains its echoes
    /// (docs/algorithm.md §8.14). Acts only with `corner_diagonals`.
    pub round_reflectors: bool,
    /// A reading a confirmed wall explains as a plane echo, well inside its ends, is settled:
    /// kept out of the clusters, point memory and the free-space sweep (docs/algorithm.md
    /// §8.12). Acts only with `confirm_segments`.
    pub settled_walls: bool,
    /// A point-memory piece whose readings are one place read at changing ranges (a stack:
    /// a wall square-on to a sonar the robot drives towards or away from) makes no segment;
    /// its readings leave the memory (docs/algorithm.md §8.15). Acts only with point memory.
    pub memory_stacks: bool,
    /// A point-memory piece that becomes a segment keeps its newest end reading in the memory
    /// as its joint, so that the next piece along the chain shares it and overlaps this one
    /// (docs/algorithm.md §8.16). Acts only with point memory.
    pub memory_joints: bool,
    /// Fewest readings of a fitted piece that becomes a new segment; shorter pieces' readings
    /// go to point memory. 0 is off (the paper fits any piece; docs/algorithm.md §8.8).
    pub min_piece_points: usize,
}

impl Default for Params {
    fn default() -> Self {
        Self::paper()
    }
}

impl Params {
    /// The paper's values (docs/algorithm.md §7).
    pub fn paper() -> Self {
        Self {
            accuracy_pct: 3.0,
            d_max_m: inches(255.0),
            min_range_m: inches(6.0),
            t_gap_m: inches(42.0),
            orientation_rad: 15f64.to_radians(),
            split: SplitMode::Resolution,
            fit: FitMode::EndPoints,
            max_step_m: inches(10.0),
            correlate: true,
            memory_snapshots: 0,
            memory_gap_m: inches(12.0),
            memory_min_points: 3,
            constant_depth: false,
            merge_duplicates: false,
            support_cap: 0,
            corner_guard: false,
            arc_features: false,
            explain_readings: false,
            free_space: false,
            confirm_segments: false,
            baseline_confirm: false,
            refit_unconfirms: false,
            plane_gate: false,
            echo_fit: false,
            corner_diagonals: false,
            round_reflectors: false,
            settled_walls: false,
            memory_stacks: false,
            memory_joints: false,
            min_piece_points: 0,
        }
    }

    /// The paper plus every extension of docs/algorithm.md §8: point memory, constant-depth
    /// groups and the long-run bounds (merging duplicates, the support cap, the corner guard).
    pub fn extended() -> Self {
        Self {
            // Total least squares: a piece's end-points on the line through all its readings,
            // not on one noisy reading each (docs/algorithm.md §8.13).
            fit: FitMode::TotalLeastSquares,
            memory_snapshots: 10,
            constant_depth: true,
            merge_duplicates: true,
            support_cap: EXTENDED_SUPPORT_CAP,
            corner_guard: true,
            arc_features: true,
            explain_readings: true,
            free_space: true,
            confirm_segments: true,
            baseline_confirm: true,
            refit_unconfirms: true,
            plane_gate: true,
            echo_fit: true,
            corner_diagonals: true,
            round_reflectors: true,
            settled_walls: true,
            memory_stacks: true,
            memory_joints: true,
            min_piece_points: 3,
            ..Self::paper()
        }
    }

    /// The values of a preset.
    pub fn preset(preset: Preset) -> Self {
        match preset {
            Preset::Paper => Self::paper(),
            Preset::Extended => Self::extended(),
        }
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
        let len = |v: f64| units.to_m(v);
        if let Some(v) = file.accuracy_pct {
            p.accuracy_pct = v;
        }
        if let Some(v) = file.d_max {
            p.d_max_m = len(v);
        }
        if let Some(v) = file.min_range {
            p.min_range_m = len(v);
        }
        if let Some(v) = file.t_gap {
            p.t_gap_m = len(v);
        }
        if let Some(v) = file.orientation_deg {
            p.orientation_rad = v.to_radians();
        }
        if let Some(split) = &file.split {
            p.split = match split {
                SplitFile::Resolution {} => SplitMode::Resolution,
                SplitFile::Fixed(v) => SplitMode::Fixed(len(*v)),
            };
        }
        if let Some(fit) = file.fit {
            p.fit = fit;
        }
        if let Some(v) = file.max_step {
            p.max_step_m = len(v);
        }
        if let Some(v) = file.correlate {
            p.correlate = v;
        }
        if let Some(v) = file.memory_snapshots {
            p.memory_snapshots = v;
        }
        if let Some(v) = file.memory_gap {
            p.memory_gap_m = len(v);
        }
        if let Some(v) = file.memory_min_points {
            p.memory_min_points = v;
        }
        if let Some(v) = file.constant_depth {
            p.constant_depth = v;
        }
        if let Some(v) = file.merge_duplicates {
            p.merge_duplicates = v;
        }
        if let Some(v) = file.support_cap {
            p.support_cap = v;
        }
        if let Some(v) = file.corner_guard {
            p.corner_guard = v;
        }
        if let Some(v) = file.arc_features {
            p.arc_features = v;
        }
        if let Some(v) = file.explain_readings {
            p.explain_readings = v;
        }
        if let Some(v) = file.free_space {
            p.free_space = v;
        }
        if let Some(v) = file.confirm_segments {
            p.confirm_segments = v;
        }
        if let Some(v) = file.baseline_confirm {
            p.baseline_confirm = v;
        }
        if let Some(v) = file.refit_unconfirms {
            p.refit_unconfirms = v;
        }
        if let Some(v) = file.plane_gate {
            p.plane_gate = v;
        }
        if let Some(v) = file.echo_fit {
            p.echo_fit = v;
        }
        if let Some(v) = file.corner_diagonals {
            p.corner_diagonals = v;
        }
        if let Some(v) = file.round_reflectors {
            p.round_reflectors = v;
        }
        if let Some(v) = file.settled_walls {
            p.settled_walls = v;
        }
        if let Some(v) = file.memory_stacks {
            p.memory_stacks = v;
        }
        if let Some(v) = file.memory_joints {
            p.memory_joints = v;
        }
        if let Some(v) = file.min_piece_points {
            p.min_piece_points = v;
        }
        p.validate()?;
        Ok(p)
    }

    /// The complete parameter set as a `--params` file in `units`.
    pub fn to_file(&self, units: Units) -> ParamsFile {
        let len = |v: f64| units.from_m(v);
        ParamsFile {
            preset: None,
            units: Some(units.symbol().to_string()),
            accuracy_pct: Some(self.accuracy_pct),
            d_max: Some(len(self.d_max_m)),
            min_range: Some(len(self.min_range_m)),
            t_gap: Some(len(self.t_gap_m)),
            orientation_deg: Some(self.orientation_rad.to_degrees()),
            split: Some(match self.split {
                SplitMode::Resolution => SplitFile::Resolution {},
                SplitMode::Fixed(v) => SplitFile::Fixed(len(v)),
            }),
            fit: Some(self.fit),
            max_step: Some(len(self.max_step_m)),
            correlate: Some(self.correlate),
            memory_snapshots: Some(self.memory_snapshots),
            memory_gap: Some(len(self.memory_gap_m)),
            memory_min_points: Some(self.memory_min_points),
            constant_depth: Some(self.constant_depth),
            merge_duplicates: Some(self.merge_duplicates),
            support_cap: Some(self.support_cap),
            corner_guard: Some(self.corner_guard),
            arc_features: Some(self.arc_features),
            explain_readings: Some(self.explain_readings),
            free_space: Some(self.free_space),
            confirm_segments: Some(self.confirm_segments),
            baseline_confirm: Some(self.baseline_confirm),
            refit_unconfirms: Some(self.refit_unconfirms),
            plane_gate: Some(self.plane_gate),
            echo_fit: Some(self.echo_fit),
            corner_diagonals: Some(self.corner_diagonals),
            round_reflectors: Some(self.round_reflectors),
            settled_walls: Some(self.settled_walls),
            memory_stacks: Some(self.memory_stacks),
            memory_joints: Some(self.memory_joints),
            min_piece_points: Some(self.min_piece_points),
        }
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

/// `split` in a params file: `{"resolution": {}}` or `{"fixed": 2.0}`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum SplitFile {
    /// The ball radius of the farthest point.
    Resolution {},
    /// A fixed length in the file's units.
    Fixed(f64),
}

/// The `--params` file of docs/formats.md §6. Every field is optional.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
#[allow(missing_docs)]
pub struct ParamsFile {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub preset: Option<Preset>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub units: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub accuracy_pct: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub d_max: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub min_range: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub t_gap: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub orientation_deg: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub split: Option<SplitFile>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fit: Option<FitMode>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_step: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub correlate: Option<bool>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub memory_snapshots: Option<usize>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub memory_gap: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub memory_min_points: Option<usize>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub constant_depth: Option<bool>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub merge_duplicates: Option<bool>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub support_cap: Option<usize>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub corner_guard: Option<bool>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub arc_features: Option<bool>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub explain_readings: Option<bool>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub free_space: Option<bool>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub confirm_segments: Option<bool>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub baseline_confirm: Option<bool>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub refit_unconfirms: Option<bool>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub plane_gate: Option<bool>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub echo_fit: Option<bool>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub corner_diagonals: Option<bool>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub round_reflectors: Option<bool>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub settled_walls: Option<bool>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub memory_stacks: Option<bool>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub memory_joints: Option<bool>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub min_piece_points: Option<usize>,
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
        assert_eq!(p.memory_snapshots, 0);
        assert!(!p.constant_depth);
        assert!(!p.merge_duplicates);
        assert_eq!(p.support_cap, 0, "the paper keeps every supporting point");
        assert!(!p.corner_guard);
        assert!(!p.arc_features && !p.explain_readings && !p.free_space && !p.confirm_segments);
        assert!(!p.plane_gate && !p.echo_fit && p.min_piece_points == 0);
        assert!(!p.corner_diagonals && !p.settled_walls && !p.round_reflectors);
        assert!(!p.memory_stacks && !p.memory_joints);
        assert!(!p.baseline_confirm && !p.refit_unconfirms);
        let e = Params::extended();
        assert_eq!(e.support_cap, 64);
        assert_eq!(
            (p.fit, e.fit),
            (FitMode::EndPoints, FitMode::TotalLeastSquares)
        );
        assert!(e.corner_guard);
        assert_eq!(e.memory_snapshots, 10);
        assert!(e.constant_depth);
        assert!(e.merge_duplicates);
        assert!(e.arc_features && e.explain_readings && e.free_space && e.confirm_segments);
        assert!(e.plane_gate && e.echo_fit && e.min_piece_points == 3);
        assert!(e.corner_diagonals && e.settled_walls && e.round_reflectors);
        assert!(e.memory_stacks && e.memory_joints);
        assert!(e.baseline_confirm && e.refit_unconfirms);
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
        assert_eq!(p.memory_snapshots, 10);
        let back = Params::paper()
            .with_file(&p.to_file(Units::Millimetres))
            .unwrap();
        assert!((back.t_gap_m - p.t_gap_m).abs() < 1e-12);
        assert_eq!(back.memory_snapshots, 10);
    }
}
