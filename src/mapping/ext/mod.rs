//! The extensions beyond the paper (docs/algorithm.md §8), each behind its own flag of
//! [`crate::mapping::Params`] and off in the `paper` preset. Each rule is its own module; the
//! mapper calls them through its hooks (`mapper.rs`), and [`ALL`] lists them in run order.

pub mod beam_geometry;
pub mod confirm;
pub mod constant_depth;
pub mod corner_diagonals;
pub mod echo_fit;
pub mod free_space;
pub mod memory_linkage;
pub mod point_features;
pub mod point_memory;
pub mod round_reflectors;
pub mod settled_walls;
mod steps;
