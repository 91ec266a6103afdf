//! Every parameter declared once (docs/algorithm.md §7, §8): its field, its name and unit in a
//! `--params` file, its value in each preset, and the parameters it acts only with. The
//! [`Params`] struct, the [`ParamsFile`], their conversions, the list [`PARAMETERS`] (that the
//! parameters panel, the soak and the prerequisite check read) and the accessors by name are
//! all generated from the one table at the end of this file.

use super::{FitMode, SplitMode, EXTENDED_MEMORY_SNAPSHOTS, EXTENDED_SUPPORT_CAP};
use crate::units::{inches, Units};
use serde::{Deserialize, Serialize};

/// What a parameter holds, as a file and the panel give it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ParamKind {
    /// On or off.
    Flag,
    /// A whole number (readings, snapshots, points); 0 is off where the help says so.
    Count,
    /// A plain number (a percentage).
    Number,
    /// A length: metres in [`Params`], the file's units in a file.
    Length,
    /// An angle: radians in [`Params`], degrees in a file.
    Degrees,
    /// One of named choices (the split rule, the fit).
    Choice,
}

/// One parameter as declared.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Parameter {
    /// Its name in a `--params` file (and the panel, the trace, the docs).
    pub name: &'static str,
    /// What it holds.
    pub kind: ParamKind,
    /// The parameters it acts only with (each "on": a set flag, a count above 0).
    pub needs: &'static [&'static str],
    /// Its doc comment.
    pub help: &'static str,
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

/// A field's value as a file holds it (`$conv` names the conversion).
macro_rules! to_file_value {
    (flag, $v:expr, $u:expr) => {
        $v
    };
    (count, $v:expr, $u:expr) => {
        $v
    };
    (number, $v:expr, $u:expr) => {
        $v
    };
    (choice, $v:expr, $u:expr) => {
        $v
    };
    (length, $v:expr, $u:expr) => {
        $u.from_m($v)
    };
    (degrees, $v:expr, $u:expr) => {
        $v.to_degrees()
    };
    (split, $v:expr, $u:expr) => {
        match $v {
            SplitMode::Resolution => SplitFile::Resolution {},
            SplitMode::Fixed(v) => SplitFile::Fixed($u.from_m(v)),
        }
    };
}

/// A field's value from a file's (`$conv` names the conversion).
macro_rules! from_file_value {
    (flag, $v:expr, $u:expr) => {
        *$v
    };
    (count, $v:expr, $u:expr) => {
        *$v
    };
    (number, $v:expr, $u:expr) => {
        *$v
    };
    (choice, $v:expr, $u:expr) => {
        *$v
    };
    (length, $v:expr, $u:expr) => {
        $u.to_m(*$v)
    };
    (degrees, $v:expr, $u:expr) => {
        $v.to_radians()
    };
    (split, $v:expr, $u:expr) => {
        match $v {
            SplitFile::Resolution {} => SplitMode::Resolution,
            SplitFile::Fixed(v) => SplitMode::Fixed($u.to_m(*v)),
        }
    };
}

/// The [`ParamKind`] of a conversion.
macro_rules! kind_of {
    (flag) => {
        ParamKind::Flag
    };
    (count) => {
        ParamKind::Count
    };
    (number) => {
        ParamKind::Number
    };
    (length) => {
        ParamKind::Length
    };
    (degrees) => {
        ParamKind::Degrees
    };
    (choice) => {
        ParamKind::Choice
    };
    (split) => {
        ParamKind::Choice
    };
}

/// The value of a field as a number in the file's units (flags and choices have none).
macro_rules! number_of {
    (count, $v:expr, $u:expr) => {
        Some($v as f64)
    };
    (number, $v:expr, $u:expr) => {
        Some($v)
    };
    (length, $v:expr, $u:expr) => {
        Some($u.from_m($v))
    };
    (degrees, $v:expr, $u:expr) => {
        Some($v.to_degrees())
    };
    ($other:ident, $v:expr, $u:expr) => {
        None
    };
}

/// Sets a field from a number in the file's units; false for flags and choices.
macro_rules! set_number {
    (count, $f:expr, $v:expr, $u:expr) => {{
        $f = if $v >= 0.0 { $v as usize } else { 0 };
        true
    }};
    (number, $f:expr, $v:expr, $u:expr) => {{
        $f = $v;
        true
    }};
    (length, $f:expr, $v:expr, $u:expr) => {{
        $f = $u.to_m($v);
        true
    }};
    (degrees, $f:expr, $v:expr, $u:expr) => {{
        $f = $v.to_radians();
        true
    }};
    ($other:ident, $f:expr, $v:expr, $u:expr) => {
        false
    };
}

/// Whether a field is "on" (a set flag, a count or a length above 0); other kinds never are.
macro_rules! is_on {
    (flag, $v:expr) => {
        $v
    };
    (count, $v:expr) => {
        $v > 0
    };
    (length, $v:expr) => {
        $v > 0.0
    };
    ($other:ident, $v:expr) => {
        false
    };
}

/// The flag's value (flags only).
macro_rules! flag_of {
    (flag, $v:expr) => {
        Some($v)
    };
    ($other:ident, $v:expr) => {
        None
    };
}

/// Sets a flag (flags only); false for the other kinds.
macro_rules! set_flag {
    (flag, $f:expr, $v:expr) => {{
        $f = $v;
        true
    }};
    ($other:ident, $f:expr, $v:expr) => {
        false
    };
}

/// Generates [`Params`], [`ParamsFile`], [`PARAMETERS`] and the accessors from the table.
macro_rules! parameters {
    ($(
        $(#[doc = $doc:literal])*
        $field:ident: $ty:ty, file $file:ident: $file_ty:ty, $conv:ident,
            paper $paper:expr, extended $extended:expr, needs [$($need:literal),*];
    )*) => {
        /// Every parameter of the mapper. Lengths in metres, angles in radians.
        /// A set deserialized without a parameter takes the paper's value for it; the app's
        /// persisted set takes the value of the preset it is compared with.
        #[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
        #[serde(default)]
        pub struct Params {
            $( $(#[doc = $doc])* pub $field: $ty, )*
            /// The odometry's heading errors a first pass found, smoothed (`calibrate_first`,
            /// docs/algorithm.md §8.17): with a calibration, each step's heading is the
            /// odometry's less its snapshot's error. Not a file parameter: a first pass over
            /// a log gives it for that log ([`super::Params::calibrated_by`] leaves it out).
            #[serde(skip)]
            pub heading_track: Option<std::sync::Arc<crate::mapping::model::heading_track::HeadingTrack>>,
        }

        /// The `--params` file of docs/formats.md §6. Every field is optional.
        #[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
        #[serde(deny_unknown_fields)]
        #[allow(missing_docs)]
        pub struct ParamsFile {
            #[serde(default, skip_serializing_if = "Option::is_none")]
            pub preset: Option<super::Preset>,
            #[serde(default, skip_serializing_if = "Option::is_none")]
            pub units: Option<String>,
            $(
                #[serde(default, skip_serializing_if = "Option::is_none")]
                pub $file: Option<$file_ty>,
            )*
        }

        /// Every parameter, in the order of [`Params`] and of a params file.
        pub const PARAMETERS: &[Parameter] = &[
            $( Parameter {
                name: stringify!($file),
                kind: kind_of!($conv),
                needs: &[$($need),*],
                help: concat!($($doc),*),
            }, )*
        ];

        impl Params {
            /// The paper's values (docs/algorithm.md §7).
            pub fn paper() -> Self {
                Self { $( $field: $paper, )* heading_track: None }
            }

            /// The paper plus every extension of docs/algorithm.md §8 (each parameter's
            /// `extended` value in the table of `params/declare.rs`).
            pub fn extended() -> Self {
                Self { $( $field: $extended, )* heading_track: None }
            }

            /// Sets the fields `file` gives, its lengths in `units`.
            pub(super) fn apply_file_fields(&mut self, file: &ParamsFile, units: Units) {
                $( if let Some(v) = &file.$file {
                    self.$field = from_file_value!($conv, v, units);
                } )*
            }

            /// Every field as a file gives it, lengths in `units` (no preset, no units).
            pub(super) fn file_fields(&self, units: Units) -> ParamsFile {
                ParamsFile {
                    preset: None,
                    units: None,
                    $( $file: Some(to_file_value!($conv, self.$field, units)), )*
                }
            }

            /// Parameter `name`'s value as a number in a file's units (`units` for
            /// lengths); `None` for flags, choices and unknown names.
            pub fn number(&self, name: &str, units: Units) -> Option<f64> {
                let _ = units;
                match name {
                    $( stringify!($file) => number_of!($conv, self.$field, units), )*
                    _ => None,
                }
            }

            /// Sets parameter `name` from a number in a file's units; false when it takes
            /// none (a flag, a choice, an unknown name).
            pub fn set_number(&mut self, name: &str, v: f64, units: Units) -> bool {
                let _ = (v, units);
                match name {
                    $( stringify!($file) => set_number!($conv, self.$field, v, units), )*
                    _ => false,
                }
            }

            /// Flag `name`'s value; `None` for the other parameters.
            pub fn flag(&self, name: &str) -> Option<bool> {
                match name {
                    $( stringify!($file) => flag_of!($conv, self.$field), )*
                    _ => None,
                }
            }

            /// Sets flag `name`; false when `name` is no flag.
            pub fn set_flag(&mut self, name: &str, on: bool) -> bool {
                let _ = on;
                match name {
                    $( stringify!($file) => set_flag!($conv, self.$field, on), )*
                    _ => false,
                }
            }

            /// Whether parameter `name` is on (a set flag, a count or a length above 0).
            pub fn is_on(&self, name: &str) -> bool {
                match name {
                    $( stringify!($file) => is_on!($conv, self.$field), )*
                    _ => false,
                }
            }

            /// Parameter `name` takes its value in `from`; false for an unknown name.
            pub fn take_from(&mut self, name: &str, from: &Params) -> bool {
                match name {
                    $( stringify!($file) => {
                        self.$field = from.$field.clone();
                        true
                    } )*
                    _ => false,
                }
            }
        }
    };
}

parameters! {
    /// Accuracy `ξ`, percent of range (§2).
    accuracy_pct: f64, file accuracy_pct: f64, number,
        paper 3.0, extended 3.0, needs [];
    /// Readings beyond this are discarded (§3.1).
    d_max_m: f64, file d_max: f64, length,
        paper inches(255.0), extended inches(255.0), needs [];
    /// Readings below this are discarded (blind zone).
    min_range_m: f64, file min_range: f64, length,
        paper inches(6.0), extended inches(6.0), needs [];
    /// Cluster gap threshold (§3.1, §4).
    t_gap_m: f64, file t_gap: f64, length,
        paper inches(42.0), extended inches(42.0), needs [];
    /// Orientation threshold `θ_o` (§3.3.1).
    orientation_rad: f64, file orientation_deg: f64, degrees,
        paper 15f64.to_radians(), extended 15f64.to_radians(), needs [];
    /// Split rule of the recursive fit.
    split: SplitMode, file split: SplitFile, split,
        paper SplitMode::Resolution, extended SplitMode::Resolution, needs [];
    /// Line placement of the recursive fit. `extended`: total least squares, a piece's
    /// end-points on the line through all its readings, not on one noisy reading each
    /// (docs/algorithm.md §8.13).
    fit: FitMode, file fit: FitMode, choice,
        paper FitMode::EndPoints, extended FitMode::TotalLeastSquares, needs [];
    /// Largest step between snapshots before a warning (§3.3.1).
    max_step_m: f64, file max_step: f64, length,
        paper inches(10.0), extended inches(10.0), needs [];
    /// Correlation of new faces (§3.3.3) on or off.
    correlate: bool, file correlate: bool, flag,
        paper true, extended true, needs [];
    /// Point memory on (above 0) and the most snapshots a reading stays in it (docs/algorithm.md
    /// §8.1): its span is the distance driven (`memory_travel`), and this bounds a robot that
    /// stands still.
    memory_snapshots: usize, file memory_snapshots: usize, count,
        paper 0, extended EXTENDED_MEMORY_SNAPSHOTS, needs [];
    /// Point memory's span in distance driven: a remembered reading leaves once the robot has
    /// driven this far since it was taken, whatever its pace; 0 leaves the span to
    /// `memory_snapshots` alone (docs/algorithm.md §8.1).
    memory_travel_m: f64, file memory_travel: f64, length,
        paper inches(100.0), extended inches(100.0), needs [];
    /// A snapshot whose odometry pose lies within this distance of the last mapped snapshot's
    /// (and turned less than 0.1°) adds no view: the robot stood still, and its readings are
    /// set aside, not mapped (docs/algorithm.md §8.19); 0: every snapshot is mapped.
    standstill_m: f64, file standstill: f64, length,
        paper 0.0, extended 0.001, needs [];
    /// Link distance of remembered points (§8.1).
    memory_gap_m: f64, file memory_gap: f64, length,
        paper inches(12.0), extended inches(12.0), needs [];
    /// Fewest points of a memory segment (§8.1).
    memory_min_points: usize, file memory_min_points: usize, count,
        paper 3, extended 3, needs [];
    /// Shortest memory segment: a piece whose end readings lie closer than this stays in the
    /// memory to grow, however many readings it has (a crawling robot's readings of a few
    /// centimetres of wall fix no direction); 0 is off (docs/algorithm.md §8.1).
    memory_min_span_m: f64, file memory_min_span: f64, length,
        paper inches(12.0), extended inches(12.0), needs [];
    /// Constant-depth groups on or off (docs/algorithm.md §8.2).
    constant_depth: bool, file constant_depth: bool, flag,
        paper false, extended true, needs [];
    /// Fuse map segments that match an updated segment into it (a long-run bound beyond the
    /// paper, docs/algorithm.md §8.3; see `mapping::paper::merge`).
    merge_duplicates: bool, file merge_duplicates: bool, flag,
        paper false, extended true, needs [];
    /// Supporting points a segment keeps, the most recent ones; 0 keeps them all (a long-run
    /// bound beyond the paper, docs/algorithm.md §5 and §8).
    support_cap: usize, file support_cap: usize, count,
        paper 0, extended EXTENDED_SUPPORT_CAP, needs [];
    /// Refuse a correlation corner that would collapse a line, joining the two end-points by a
    /// connecting segment instead (beyond the paper, docs/algorithm.md §6 and §8).
    corner_guard: bool, file corner_guard: bool, flag,
        paper false, extended true, needs [];
    /// Arc rule: a cluster whose readings, from two or more sensors, pass the ball test
    /// pairwise is one reflector point, filed as a point feature instead of fitted
    /// (docs/algorithm.md §8.5).
    arc_features: bool, file arc_features: bool, flag,
        paper false, extended true, needs [];
    /// Readings a confirmed point feature explains (its range from the sensor, inside the
    /// beam) join no cluster (docs/algorithm.md §8.5). Acts only with `arc_features`, which
    /// files the features.
    explain_readings: bool, file explain_readings: bool, flag,
        paper false, extended true, needs ["arc_features"];
    /// A segment whose perpendicular foot lies inside a beam that read farther is removed
    /// (docs/algorithm.md §8.6).
    free_space: bool, file free_space: bool, flag,
        paper false, extended true, needs [];
    /// The part of a fitted segment's line a reading saw through (inside the cone, short of
    /// the range) is cut away, confirmed or not: an end moves back to that part's edge, a hole
    /// splits the segment, or too little is left and it goes (docs/algorithm.md §8.18).
    trim_seen_through: bool, file trim_seen_through: bool, flag,
        paper false, extended true, needs [];
    /// Segments are tentative until readings of two views support them as a plane
    /// (docs/algorithm.md §8.7).
    confirm_segments: bool, file confirm_segments: bool, flag,
        paper false, extended true, needs [];
    /// How far the robot must have moved since the last view that supported a segment for its
    /// snapshot to count as another view (docs/algorithm.md §8.7): views, not snapshots,
    /// confirm, whatever the pace; turning in place is no new view. 0: every distinct snapshot
    /// counts.
    confirm_spacing_m: f64, file confirm_spacing: f64, length,
        paper inches(6.0), extended inches(6.0), needs [];
    /// A segment made in one step from readings of several snapshots (a point-memory piece)
    /// is confirmed when two of them, of distinct snapshots, support it as a plane from
    /// sensors 8 in or more apart along it (docs/algorithm.md §8.7). Acts only with
    /// `confirm_segments` and point memory.
    baseline_confirm: bool, file baseline_confirm: bool, flag,
        paper false, extended true, needs ["confirm_segments", "memory_snapshots"];
    /// A confirmed segment that a refit (§5) turned more than `θ_o` or moved more than
    /// `2·tol(D)` off its line is tentative again (docs/algorithm.md §8.7). Acts only with
    /// `confirm_segments`.
    refit_unconfirms: bool, file refit_unconfirms: bool, flag,
        paper false, extended true, needs ["confirm_segments"];
    /// A tentative segment that a refit (§5) moved off its line, as `refit_unconfirms`
    /// tests it, drops the plane support counted for its old line: its next supporting view
    /// counts as its first (docs/algorithm.md §8.7). Acts only with `confirm_segments`.
    refit_recounts: bool, file refit_recounts: bool, flag,
        paper false, extended true, needs ["confirm_segments"];
    /// A segment turned more than `θ_o` from the map's axes (the walls' axis the heading
    /// correction keeps, §8.17) is confirmed only by readings that see it square on (its
    /// normal inside the cone), not by echoes off the cone's edges: a corner's chord drawn by
    /// edge echoes is not confirmed (docs/algorithm.md §8.7). Acts only with
    /// `confirm_segments`, once the axis is set.
    off_axis_square_on: bool, file off_axis_square_on: bool, flag,
        paper false, extended true, needs ["confirm_segments"];
    /// A reading much shorter than its sensor's last echo is set aside as crosstalk or an early
    /// echo by another path (docs/algorithm.md §8.21).
    echo_agreement: bool, file echo_agreement: bool, flag,
        paper false, extended false, needs [];
    /// Neighbouring readings of two cone sonars whose axes lie a right angle or more apart are
    /// never one cluster: no plane echoes to both from within their cones (docs/algorithm.md
    /// §8.20).
    right_angle_break: bool, file right_angle_break: bool, flag,
        paper false, extended true, needs [];
    /// A NEW FACE needs a reading that supports it as a plane (docs/algorithm.md §8.7).
    plane_gate: bool, file plane_gate: bool, flag,
        paper false, extended true, needs [];
    /// A fitted piece's readings move to where one plane's echoes came from, when a line fitted
    /// from their ranges explains them all (docs/algorithm.md §8.10).
    echo_fit: bool, file echo_fit: bool, flag,
        paper false, extended true, needs [];
    /// A segment lying wholly near the junction of two confirmed walls and turned from both
    /// is a corner's diagonal and leaves the map (docs/algorithm.md §8.11). Acts only with
    /// `confirm_segments`.
    corner_diagonals: bool, file corner_diagonals: bool, flag,
        paper false, extended true, needs ["confirm_segments"];
    /// The readings of removed diagonals are kept as evidence; a round pillar that explains
    /// enough of them, seen from apart, is filed as a rounded feature and explains its echoes
    /// (docs/algorithm.md §8.14). Acts only with `corner_diagonals`.
    round_reflectors: bool, file round_reflectors: bool, flag,
        paper false, extended true, needs ["corner_diagonals"];
    /// A reading a confirmed wall explains as a plane echo, well inside its ends, is settled:
    /// kept out of the clusters, point memory and the free-space sweep (docs/algorithm.md
    /// §8.12). Acts only with `confirm_segments`.
    settled_walls: bool, file settled_walls: bool, flag,
        paper false, extended true, needs ["confirm_segments"];
    /// Before a step's readings are matched, its pose is corrected against the confirmed walls
    /// and point features (docs/algorithm.md §8.17). With `calibrate_first` it waits for a
    /// second pass and corrects from the odometry the first pass's drift mends. Off in both
    /// presets: the Pioneer stand-in with drift maps better with the heading alone (§8.17's
    /// figures); `revisit_laps` switches it on for the second pass of a run that comes back to
    /// its walls. Acts only with `confirm_segments`.
    pose_correction: bool, file pose_correction: bool, flag,
        paper false, extended false, needs ["confirm_segments"];
    /// The odometry's heading drift is estimated from the lines of the sensors' wall windows
    /// against the map's axes, and once it is significant it is taken off each step's heading,
    /// without the range readings' pull on position (docs/algorithm.md §8.17); a run without
    /// drift maps as without it. With `pose_correction` the windows join its update instead.
    /// Acts only with `confirm_segments`.
    heading_correction: bool, file heading_correction: bool, flag,
        paper false, extended true, needs ["confirm_segments"];
    /// A run whose mapping found its odometry drifting is mapped again from that drift
    /// (`drift_deg_per_m`, `drift_per_turn_pct`) and from the first pass's heading errors
    /// smoothed over the whole run, corrected from its first step: `run`, `eval` and the app do
    /// so (docs/algorithm.md §8.17, "calibrate, then map"). Acts only with
    /// `heading_correction`.
    calibrate_first: bool, file calibrate_first: bool, flag,
        paper false, extended true, needs ["heading_correction"];
    /// A second pass (`calibrate_first`) also corrects the pose against the confirmed map
    /// (`pose_correction`, from the odometry the first pass mends) when the first pass drove at
    /// least this many laps of its map: the distance driven over the perimeter of the
    /// confirmed walls' bounding box. A robot that comes back to walls it mapped laps before
    /// drifts away from them without bound on its heading alone; on a single pass the pose
    /// correction follows the walls it has just drawn (docs/algorithm.md §8.17, "runs that
    /// come back"). 0: never. Acts only with `calibrate_first`.
    revisit_laps: usize, file revisit_laps: usize, count,
        paper 0, extended 2, needs ["calibrate_first"];
    /// The odometry's known heading drift per metre driven, degrees (a calibration, such as a
    /// first pass's estimate: `calibrate_first`). With it or `drift_per_turn` non-zero, the
    /// heading correction starts from them, taken as known within a tenth of its priors, and
    /// corrects from the first step (docs/algorithm.md §8.17). Acts only with
    /// `heading_correction`.
    drift_deg_per_m: f64, file drift_deg_per_m: f64, number,
        paper 0.0, extended 0.0, needs ["heading_correction"];
    /// The odometry's known heading error per turn, percent of the angle turned (a wheelbase
    /// off by that much; see `drift_deg_per_m`). Acts only with `heading_correction`.
    drift_per_turn_pct: f64, file drift_per_turn_pct: f64, number,
        paper 0.0, extended 0.0, needs ["heading_correction"];
    /// Distance driven over which a sensor's wall readings, laid out by the odometry, form a
    /// line whose deviation from the map's nearer axis (within 5°, or the drift filter's
    /// widened gate) observes heading
    /// (docs/algorithm.md §8.17); 0 is off. Acts only with `pose_correction` or
    /// `heading_correction`.
    heading_window_m: f64, file heading_window: f64, length,
        paper 2.0, extended 2.0, needs [];
    /// The heading windows are kept per confirmed wall instead of per sensor: each settled
    /// reading joins the window of the wall that settled it, placed where that wall's echo
    /// came from at the measured range, and no turn of the robot empties a window
    /// (docs/algorithm.md §8.17). Acts only with `heading_correction` and `settled_walls`.
    wall_windows: bool, file wall_windows: bool, flag,
        paper false, extended true, needs ["heading_correction", "settled_walls"];
    /// Each sensor also keeps a window of the readings no confirmed wall settled, whose
    /// lines stand in on a step where neither the sensors' windows of settled readings nor
    /// the walls' gave one: a robot meeting its walls for the first time (docs/algorithm.md
    /// §8.17). Acts only with `heading_correction` and `settled_walls`.
    open_windows: bool, file open_windows: bool, flag,
        paper false, extended true, needs ["heading_correction", "settled_walls"];
    /// A point-memory piece whose readings are one place read at changing ranges (a stack:
    /// a wall square-on to a sonar the robot drives towards or away from) makes no segment;
    /// its readings leave the memory (docs/algorithm.md §8.15). Acts only with point memory.
    memory_stacks: bool, file memory_stacks: bool, flag,
        paper false, extended true, needs ["memory_snapshots"];
    /// A point-memory piece that becomes a segment keeps its newest end reading in the memory
    /// as its joint, so that the next piece along the chain shares it and overlaps this one
    /// (docs/algorithm.md §8.16). Acts only with point memory.
    memory_joints: bool, file memory_joints: bool, flag,
        paper false, extended true, needs ["memory_snapshots"];
    /// Fewest readings of a fitted piece that becomes a new segment; shorter pieces' readings
    /// go to point memory. 0 is off (the paper fits any piece; docs/algorithm.md §8.8).
    min_piece_points: usize, file min_piece_points: usize, count,
        paper 0, extended 3, needs [];
}
