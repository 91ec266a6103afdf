//! Importers of recorded runs: Player/Stage text logs, ROS 2 MCAP recordings and plain tables
//! become a [`crate::run::Run`] in metres, with an [`ImportSummary`] of what was read, turned
//! into no echo, skipped and why. Pure: bytes in, run out (the command line and the app read
//! the files). [`import_any`] picks the importer from the content.
//!
//! - [`player`]: Player 1.x/2/3 `writelog` lines (`sonar`, `position2d`, `position`).
//! - [`ros2`]: `sensor_msgs/msg/Range`, `nav_msgs/msg/Odometry`, `/tf_static` in MCAP.
//! - [`table`]: `t x y heading r...` or `t r...` plus `t x y heading`; `firings`: one
//!   reading a line, `t sensor range [x y heading]`, cut into firing cycles (`cycles`).
//! - [`layout`]: the `sonarmap-layout` file that `--layout` reads, and the shipped layouts.
//!
//! Every input ends one of two ways (issue 18): it is refused with an [`ImportError`] naming
//! the file, the place (line and field, MCAP record offset or message index and field, JSON
//! path) and what was expected; or it is imported as a run that the log format accepts and
//! that maps without a non-finite number. Values no robot produces are refused ([`sane`]),
//! declared lengths are checked against the bytes present, memory stays a small multiple of
//! the input, and control characters from a file are escaped in every message. The fuzz tests
//! (`tests/it/import_fuzz.rs`) check this contract on mutated recordings.

mod assemble;
pub mod cdr;
mod cycles;
mod detect;
mod error;
mod firings;
pub mod layout;
mod mcap_check;
mod options;
pub mod player;
pub mod pose_track;
pub mod ros2;
pub mod sane;
mod summary;
pub mod table;
mod table_fields;
mod text;

pub use detect::{detect, import_any};
pub use error::ImportError;
pub use layout::{builtin_layout, parse_layout, Layout, LAYOUT_FORMAT};
pub use options::{
    AngleUnit, ImportOptions, NamedBytes, TableForm, DEFAULT_FIRINGS_WINDOW_S, DEFAULT_WINDOW_S,
};
pub use player::import_player;
pub use ros2::import_mcap;
pub use summary::{Format, ImportSummary, Imported, Skipped};
pub use table::import_table;
