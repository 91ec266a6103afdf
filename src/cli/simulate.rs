//! `sonarmap simulate`: a run log from a floor plan, with the sonar simulator.

use super::input::read;
use super::output::write_atomic;
use anyhow::Result;
use clap::{Args, ValueEnum};
use sonarmap::log::save_run;
use sonarmap::sim::{load_plan, simulate, Model, OdometryError};
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
    /// Odometry error of a differential-drive robot (UMBmark): `pose` becomes the drifting
    /// odometry and the truth is kept as each snapshot's `true_pose`. mild: wheel diameters
    /// 0.06 % apart (about 1 deg per 10 m), wheelbase 1 % off; bad: 0.3 % (5 deg per 10 m), 3 %.
    #[arg(long, value_enum, default_value = "none")]
    pub drift: DriftArg,
}

/// The odometry error of `simulate --drift`.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum DriftArg {
    /// The odometry is the truth.
    None,
    /// `OdometryError::MILD`.
    Mild,
    /// `OdometryError::BAD`.
    Bad,
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

impl DriftArg {
    /// The odometry error, none for [`DriftArg::None`] (the run is left as it is).
    pub fn error(self) -> Option<OdometryError> {
        match self {
            DriftArg::None => None,
            DriftArg::Mild => Some(OdometryError::MILD),
            DriftArg::Bad => Some(OdometryError::BAD),
        }
    }
}

/// Runs `sonarmap simulate`.
pub fn simulate_command(args: &SimulateArgs) -> Result<()> {
    let plan = load_plan(&read(&args.plan)?, &args.plan.display().to_string())?;
    let model = match args.model {
        ModelArg::Specular => Model::Specular,
        ModelArg::Axis => Model::Axis,
    };
    let run = simulate(&plan, model, args.seed);
    let run = sonarmap::suite::drifted(run, args.drift.error().as_ref(), args.seed);
    write_atomic(&args.out, save_run(&run))
}
