//! The paper's mapping algorithm (docs/algorithm.md §1–§8), one rule a file.

mod cell_table;
pub mod cluster;
pub mod confirm;
pub mod corner_diagonals;
pub mod correlate;
pub mod echo_fit;
pub mod extensions;
pub mod fast_path;
pub mod features;
pub mod fit;
pub mod flip;
pub mod free_space;
mod guard;
pub mod id_list;
pub mod ids;
pub mod index;
pub mod map;
mod mapper;
pub mod matching;
pub mod merge;
pub mod params;
pub mod plane_supports;
pub mod point_features;
pub mod readings;
pub mod round_reflectors;
pub mod settled_walls;
pub mod support;
pub mod support_list;
pub mod trace;
pub mod update;

pub use guard::{install_quiet_step_hook, note_guarded_panic, StepFailure};
pub use map::{EndPoint, Map, Segment, SegmentId, SegmentKind, SupportPoint};
pub use mapper::{candidate_reach_m, Mapper, MapperState, RecordedDecision};
pub use params::EXTENDED_SUPPORT_CAP;
pub use params::{FitMode, Params, ParamsError, ParamsFile, Preset, SplitMode};
pub use trace::{Outcome, Rule, StepTrace};
