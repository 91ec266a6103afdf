//! The engine's data: the map and what it is made of, the step's trace, the parameters. Plain
//! values and their bookkeeping; no rule of the paper or of an extension lives here, and nothing
//! here imports [`crate::mapping::paper`] or [`crate::mapping::ext`].
//!
//! Extension state that a checkpoint must keep (point memory, point features, pillar evidence,
//! plane support, recent poses) is held by the [`map::Map`], as plain values defined here.

pub mod beam;
mod cell_table;
pub mod ext_trace;
pub mod features;
pub mod heading_track;
pub mod id_list;
pub mod ids;
pub mod index;
pub mod map;
pub mod params;
pub mod plane_supports;
pub mod support;
pub mod support_list;
pub mod trace;
