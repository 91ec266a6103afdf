//! Runs built into the binary.

use crate::log::{load_run, LogError};
use crate::run::Run;

/// The default run: the simulated Blue Room (`assets/blue_room.log.json`, made by
/// `sonarmap simulate assets/blue_room.plan.json --seed 1`).
pub const DEFAULT_RUN_JSON: &str = include_str!("../assets/blue_room.log.json");

/// The name the default run's errors carry.
pub const DEFAULT_RUN_NAME: &str = "blue_room.log.json (built in)";

/// Loads the default run.
pub fn default_run() -> Result<Run, LogError> {
    load_run(DEFAULT_RUN_JSON.as_bytes(), DEFAULT_RUN_NAME)
}
