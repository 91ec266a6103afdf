//! The paper's mapping algorithm (ALGORITHM.md §1–§8), one rule a file.

pub mod map;
mod mapper;
pub mod params;
pub mod trace;

pub use map::{EndPoint, Map, Segment, SegmentId, SegmentKind, SupportPoint};
pub use mapper::Mapper;
pub use params::{FitMode, Params, ParamsError, ParamsFile, Preset, SplitMode};
pub use trace::{Outcome, Rule, StepTrace};
