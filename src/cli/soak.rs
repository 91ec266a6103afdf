//! `sonarmap soak`: long lap runs over generated scenes in every parameter set, the map's
//! invariants checked after every step ([`sonarmap::soak`]).

use super::interrupt::Interrupted;
use super::output::emit;
use super::progress::Progress;
use anyhow::{bail, Result};
use clap::Args;

/// `sonarmap soak`.
#[derive(Debug, Args)]
#[command(
    after_help = "Scenes: rooms, rotated rooms, L-shaped rooms, corridors with doors, \
rooms with pillars, rooms with an acute corner, rooms with desks, each with a random sensor layout \
and noise, simulated with the specular (even seeds) or axis (odd seeds) model, one lap repeated \
to --snapshots. Parameter sets: paper, extended, and the paper with each extension alone (with the parameters it acts only with). \
Exits 2 when any step panicked or broke an invariant."
)]
pub struct SoakArgs {
    /// Scenes of each kind.
    #[arg(long, default_value_t = 4)]
    pub runs_per_kind: usize,
    /// Snapshots of each run.
    #[arg(long, default_value_t = 20_000)]
    pub snapshots: usize,
    /// Seed of the first scene of each kind.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Only these parameter sets: paper, extended, or the paper with one extension and what it
    /// needs, paper+NAME for each parameter the presets set apart (paper+memory_snapshots,
    /// paper+settled_walls, ...; an unknown name lists them all); default all.
    #[arg(long, value_delimiter = ',')]
    pub only: Vec<String>,
    /// The odometry error of every run (a differential-drive robot's, as `simulate --drift`
    /// gives), drifting on over its laps.
    #[arg(long, value_enum, default_value = "none")]
    pub drift: super::simulate::DriftArg,
    /// The pace and firing order every lap is simulated at, and its echoes' bounces.
    #[command(flatten)]
    pub pace: super::simulate::PaceArgs,
}

/// A failed run, as printed.
#[derive(serde::Serialize)]
struct Failure {
    scene: &'static str,
    seed: u64,
    params: String,
    snapshot: usize,
    panicked: bool,
    message: String,
}

/// What `soak` prints.
#[derive(serde::Serialize)]
struct SoakOutput {
    runs: usize,
    snapshots: usize,
    invariant_checks: usize,
    panics: usize,
    broken_invariants: usize,
    largest_map: usize,
    seconds: f64,
    failures: Vec<Failure>,
}

/// Runs `sonarmap soak`; fails (exit 2) when any run failed.
pub fn soak_command(args: &SoakArgs) -> Result<()> {
    let started = std::time::Instant::now();
    let known: Vec<String> = sonarmap::soak::soak_variants()
        .into_iter()
        .map(|(n, _)| n)
        .collect();
    if let Some(bad) = args.only.iter().find(|o| !known.contains(o)) {
        bail!(
            "--only {bad}: not a parameter set of the soak ({})",
            known.join(", ")
        );
    }
    let runs = args.runs_per_kind
        * sonarmap::sim::SceneKind::ALL.len()
        * sonarmap::soak::soak_variants_only(&args.only).len();
    let progress = Progress::new("soak", runs * args.snapshots, "snapshots");
    let report = sonarmap::soak::soak_variants_named(
        args.runs_per_kind,
        args.snapshots,
        args.seed,
        &args.only,
        &sonarmap::suite::Conditions {
            drift: args.drift.error(),
            pace: args.pace.pace()?,
            bounces: args.pace.bounces,
        },
        &mut progress.callback(),
    )
    .map_err(|_| Interrupted)?;
    drop(progress);
    let failed = !report.failures.is_empty();
    let out = SoakOutput {
        runs: report.runs,
        snapshots: report.snapshots,
        invariant_checks: report.invariant_checks,
        panics: report.panics,
        broken_invariants: report.broken_invariants,
        largest_map: report.largest_map,
        seconds: started.elapsed().as_secs_f64(),
        failures: report
            .failures
            .into_iter()
            .map(|f| Failure {
                scene: f.kind.name(),
                seed: f.seed,
                params: f.variant,
                snapshot: f.snapshot,
                panicked: f.panicked,
                message: f.message,
            })
            .collect(),
    };
    emit(&serde_json::to_string_pretty(&out)?)?;
    if failed {
        bail!("{} of {} runs failed", out.failures.len(), out.runs);
    }
    Ok(())
}
