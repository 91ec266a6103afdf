//! `sonarmap simulate`: a run log from a floor plan, with the sonar simulator.

use super::input::read;
use super::output::write_atomic;
use anyhow::Result;
use clap::{Args, ValueEnum};
use sonarmap::log::save_run;
use sonarmap::sim::{load_plan, simulate, Model};
use std::path::PathBuf;

/// `sonarmap simulate`.
#[derive(Debug, Args)]
pub struct SimulateArgs {
    /// The floor plan (`sonarmap-plan` v1).
    pub plan: PathBuf,
    /// Where to write the run log.
    #[arg(long, value_name = "LOG.json")]
    pub out: PathBuf,
    /// Seed of the noise.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Echo model.
    #[arg(long, value_enum, default_value = "specular")]
    pub model: ModelArg,
}

/// The echo model.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum ModelArg {
    /// Beam cone, incidence limit (roughness), corner reflectors.
    Specular,
    /// One ray on the axis, first hit whatever the angle; the log's sensor says so
    /// ("echo": "axis").
    Axis,
}

/// Runs `sonarmap simulate`.
pub fn simulate_command(args: &SimulateArgs) -> Result<()> {
    let plan = load_plan(&read(&args.plan)?, &args.plan.display().to_string())?;
    let model = match args.model {
        ModelArg::Specular => Model::Specular,
        ModelArg::Axis => Model::Axis,
    };
    let run = simulate(&plan, model, args.seed);
    write_atomic(&args.out, save_run(&run))
}
