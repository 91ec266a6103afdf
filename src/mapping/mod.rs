//! The mapping engine (docs/algorithm.md), in three parts that a newcomer can tell apart:
//! - [`model`]: the map, its ids and support lists, the spatial index, the trace types and the
//!   parameters; plain data that knows no rule;
//! - [`paper`]: the paper's rules, §1 readings to §6 correlation, one rule a file;
//! - [`ext`]: the extensions of docs/algorithm.md §8, each its own flag, listed in [`ext::ALL`].
//!
//! [`Mapper`] (`mapper.rs`) runs one snapshot as a list of stages: the paper's, with the
//! extensions' hooks between them. `model` and `paper` import nothing from `ext` (checked by a
//! test).

pub mod ext;
mod guard;
mod mapper;
pub mod model;
pub mod paper;
mod recorded;
mod step;

pub use guard::{install_quiet_step_hook, note_guarded_panic, StepFailure};
pub use mapper::{Mapper, MapperState};
pub use model::map::{EndPoint, Map, Segment, SegmentId, SegmentKind, SupportPoint};
pub use model::params::EXTENDED_SUPPORT_CAP;
pub use model::params::{FitMode, Params, ParamsError, ParamsFile, Preset, SplitMode};
pub use model::trace::{Outcome, Rule, StepTrace};
pub use paper::candidates::candidate_reach_m;
pub use recorded::RecordedDecision;
