//! The run-log format `sonarmap-log` v1 (docs/formats.md §2): serde types, loading with every check,
//! saving, and the `sonarmap-map` v1 output. Pure: no file system here (the command line reads
//! the bytes).
//!
//! Loading is two passes over the bytes: the first finds duplicated keys (serde_json would
//! silently keep the last), the second deserialises typed structs straight from the slice and
//! converts them to a [`crate::run::Run`] in metres, moving each snapshot's ranges rather than
//! copying them.

mod duplicates;
mod error;
mod file;
mod load;
mod map_file;
mod save;

pub use error::LogError;
pub use file::{
    FloorPlanFile, LogFile, MountFile, PoseFile, RingFile, RobotFile, SensorFile, SnapshotFile,
    SonarsFile, LOG_FORMAT,
};
pub use load::{load_run, parse_json, run_from_file, MAX_SENSORS};
pub use map_file::{map_to_file, save_map, MapFeatureFile, MapFile, MapSegmentFile, MAP_FORMAT};
pub(crate) use save::{floor_plan_to_file, robot_to_file, tidy};
pub use save::{ring_parameters, run_to_file, save_run, write_run};

pub(crate) use load::{
    check_header, floor_plan_from_file, layout_from_robot, parse_units, sensor_from_file,
};
