//! `sonarmap simulate`: a run log from a floor plan, with the sonar simulator.

use super::input::read;
use super::output::write_atomic;
use anyhow::Result;
use clap::{Args, ValueEnum};
use sonarmap::log::save_run;
use sonarmap::sim::{load_plan, simulate_paced, Model, OdometryError, Pace, MAX_BOUNCES};
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
    /// The robot's pace and firing order, and the echoes' bounces.
    #[command(flatten)]
    pub pace: PaceArgs,
}

/// The robot's pace and its sonars' firing order, and how often their echoes bounce
/// (`simulate`, `eval --suite`, `soak`).
#[derive(Debug, Args)]
pub struct PaceArgs {
    /// Re-cut the plan's path into firing cycles this many metres apart (a crawl: 0.015; the
    /// paper's pace: 0.254); default: the plan's own poses.
    #[arg(long, value_name = "M")]
    pub cycle_step_m: Option<f64>,
    /// With --cycle-step-m, the largest turn in one cycle, degrees.
    #[arg(long, value_name = "DEG", default_value_t = 5.0)]
    pub cycle_turn_deg: f64,
    /// One firing cycle's duration, seconds.
    #[arg(long, value_name = "S", default_value_t = 1.0)]
    pub cycle_s: f64,
    /// Fire the sensors in this many groups across a cycle (sensor k in group k mod G), each
    /// reading from the pose of its own moment and logged with its offset (`reading_dt_s`);
    /// 1: the whole ring at once.
    #[arg(long, value_name = "G", default_value_t = 1)]
    pub firing_groups: usize,
    /// Surfaces a specular ray may be mirrored off before one echoes it (multipath: the range
    /// read is the whole path); overrides the plans' `sim.bounces` (default 0).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(0..=i64::from(MAX_BOUNCES)))]
    pub bounces: Option<u32>,
}

impl PaceArgs {
    /// The pace, checked.
    pub fn pace(&self) -> Result<Pace> {
        let positive = |v: f64| v.is_finite() && v > 0.0;
        if !self.cycle_step_m.is_none_or(positive) {
            anyhow::bail!("--cycle-step-m must be a length greater than 0");
        }
        if !positive(self.cycle_turn_deg) || !positive(self.cycle_s) || self.firing_groups == 0 {
            anyhow::bail!("--cycle-turn-deg, --cycle-s and --firing-groups must be greater than 0");
        }
        Ok(Pace {
            cycle_step_m: self.cycle_step_m,
            cycle_turn_rad: self.cycle_turn_deg.to_radians(),
            cycle_s: self.cycle_s,
            firing_groups: self.firing_groups,
        })
    }
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
    let mut plan = load_plan(&read(&args.plan)?, &args.plan.display().to_string())?;
    if let Some(bounces) = args.pace.bounces {
        plan.sim.bounces = bounces;
    }
    let model = match args.model {
        ModelArg::Specular => Model::Specular,
        ModelArg::Axis => Model::Axis,
    };
    let run = simulate_paced(&plan, model, args.seed, &args.pace.pace()?);
    let run = sonarmap::suite::drifted(run, args.drift.error().as_ref(), args.seed);
    write_atomic(&args.out, save_run(&run))
}
