//! # sonarmap
//!
//! An inspector for "Sonar Resolution-Based Environment Mapping" (Cahut, Valavanis, Deliç).
//! The core (everything but `app`) is pure: no window, no file system; it is used by the
//! command line and the desktop app alike.
//!
//! Bird's-eye view: run log → [`replay`] → [`mapping::Mapper`] (the paper) → map + step trace →
//! scene → map view or SVG.
#![warn(missing_docs)]

pub mod alignment;
pub mod alloc_count;
pub mod app;
pub mod assets;
pub mod atomic_write;
pub mod bench;
pub mod checkpoints;
pub mod diff;
pub mod eval;
pub mod export;
pub mod geometry;
pub mod import;
pub mod intervals;
pub mod lineage;
pub mod log;
pub mod mapping;
pub mod near_path;
pub mod pose_error;
pub mod replay;
pub mod run;
pub mod scene;
pub mod sim;
pub mod soak;
pub mod sonar;
pub mod suite;
pub mod trajectory;
pub mod units;
