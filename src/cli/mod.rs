//! The command line (docs/formats.md §10): every subcommand, a module each. Reads and writes
//! files; every write goes to a temporary file in the target's directory and is renamed into
//! place ([`sonarmap::atomic_write`]).

mod bench;
mod convert;
mod diff;
mod eval;
mod figure_args;
mod input;
pub mod interrupt;
mod map_run;
mod output;
mod parallel;
mod params;
mod progress;
mod run;
mod simulate;
mod soak;
mod suite;
mod support_growth;

use anyhow::Result;
use clap::{Parser, Subcommand};
use std::path::PathBuf;

/// Sonar resolution-based environment mapping (Cahut, Valavanis, Deliç): an inspector and
/// headless tools. With no subcommand, opens the inspector on LOG (default: the built-in
/// Blue Room).
#[derive(Debug, Parser)]
#[command(name = "sonarmap", version, args_conflicts_with_subcommands = true)]
pub struct Cli {
    /// A run log to open in the inspector.
    pub log: Option<PathBuf>,
    /// What to do headlessly.
    #[command(subcommand)]
    pub command: Option<Command>,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Run the mapper over one log or several (in parallel) and write the maps and traces.
    Run(run::RunArgs),
    /// Make a run log from a floor plan with the sonar simulator.
    Simulate(simulate::SimulateArgs),
    /// Compare the map of a log with its floor plan; prints one JSON object.
    #[command(long_about = eval::EVAL_HELP)]
    Eval(eval::EvalArgs),
    /// Convert a recording (Player/Stage log, ROS 2 MCAP, table) to a run log.
    Convert(convert::ConvertArgs),
    /// Measure the engine, loading, seeking and drawing; prints one JSON object per log.
    Bench(bench::BenchArgs),
    /// Compare the decisions of two parameter sets (A and B) on one log; prints one JSON object.
    #[command(long_about = diff::DIFF_HELP)]
    Diff(diff::DiffArgs),
    /// Drive long lap runs over generated scenes in every preset and with every single
    /// extension, checking the map's invariants after every step; prints one JSON object.
    Soak(soak::SoakArgs),
}

/// Runs a subcommand; Ctrl-C stops it with [`interrupt::Interrupted`].
pub fn execute(command: &Command) -> Result<()> {
    interrupt::install();
    match command {
        Command::Run(a) => run::run_command(a),
        Command::Simulate(a) => simulate::simulate_command(a),
        Command::Eval(a) => eval::eval_command(a),
        Command::Convert(a) => convert::convert_command(a),
        Command::Bench(a) => bench::bench_command(a),
        Command::Diff(a) => diff::diff_command(a),
        Command::Soak(a) => soak::soak_command(a),
    }
}
