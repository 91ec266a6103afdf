//! `sonarmap bench`: the engine, loading, seeking and drawing measured on logs or a generated
//! building floor ([`sonarmap::bench`]).

use super::input::read_run;
use super::interrupt::Interrupted;
use super::output::{emit, emit_each, write_atomic};
use super::params::{read_params, ParamArgs, PresetArg};
use super::progress::Progress;
use anyhow::{bail, Result};
use clap::{Args, ValueEnum};
use sonarmap::bench::BenchReport;
use sonarmap::log::save_run;
use sonarmap::mapping::Params;
use sonarmap::run::Run;
use std::path::PathBuf;

/// `bench` options.
#[derive(Debug, Args)]
#[command(
    after_help = "With no log, a building floor is generated with the simulator and driven \
back and forth (--snapshots). With one log, one JSON object (pretty-printed); with several, one \
JSON object per line (JSON Lines) in the order given, each with a `log` key, measured one after \
another so that no two timings share a core.

The cost of a snapshot depends on the preset: the paper keeps every refit piece, so on a run that \
revisits its walls the map, and each snapshot's cost, keeps growing (see docs/performance.md); \
`--preset extended` (or a params file with \"merge_duplicates\": true) fuses the duplicates."
)]
pub struct BenchArgs {
    /// The run logs to measure (default: a generated building floor, driven back and forth).
    pub logs: Vec<PathBuf>,
    /// Snapshots of the generated run.
    #[arg(long, default_value_t = 100_000)]
    pub snapshots: usize,
    /// Also write the run measured (generated, or the one log with its --laps) to this log
    /// file (to open it in the inspector, or to give it to another tool).
    #[arg(long)]
    pub write_log: Option<PathBuf>,
    /// Runs of each measurement (the median is printed).
    #[arg(long, default_value_t = 3)]
    pub repeats: usize,
    /// The shortest spacing of the replay's checkpoints, snapshots (default: the
    /// inspector's); where steps are cheap they are spaced wider, within the budget.
    #[arg(long, default_value_t = sonarmap::replay::DEFAULT_CHECKPOINT_INTERVAL)]
    pub checkpoint_interval: usize,
    /// Repeat each run's snapshots, lap after lap, to this many snapshots (each lap starts
    /// again at the first pose; `t` counts snapshots): a robot patrolling the same walls.
    #[arg(long, value_name = "N")]
    pub laps: Option<usize>,
    /// Measure the engine alone (no loading, replay, seek, frame or SVG figures).
    #[arg(long)]
    pub engine_only: bool,
    /// A parameters file (docs/formats.md §6), applied on top of each preset.
    #[arg(long, value_name = "P.json")]
    pub params: Option<PathBuf>,
    /// The parameter preset, or `all` for one line per preset.
    #[arg(long, value_enum, default_value = "paper")]
    pub preset: BenchPresetArg,
}

/// `bench --preset`: one preset, or every one.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum BenchPresetArg {
    /// The paper alone.
    Paper,
    /// The paper with every extension.
    Extended,
    /// Every preset, one JSON line each.
    All,
}

impl BenchPresetArg {
    fn presets(self) -> Vec<PresetArg> {
        match self {
            BenchPresetArg::Paper => vec![PresetArg::Paper],
            BenchPresetArg::Extended => vec![PresetArg::Extended],
            BenchPresetArg::All => vec![PresetArg::Paper, PresetArg::Extended],
        }
    }
}

/// One measurement as a JSON line: the log and preset, then the report.
#[derive(serde::Serialize)]
struct Line<'a> {
    log: String,
    preset: String,
    #[serde(flatten)]
    report: &'a BenchReport,
}

/// Runs `sonarmap bench`.
pub fn bench_command(args: &BenchArgs) -> Result<()> {
    let presets: Vec<(PresetArg, Params)> = args
        .preset
        .presets()
        .into_iter()
        .map(|preset| {
            let params = read_params(&ParamArgs {
                params: args.params.clone(),
                preset,
            })?;
            Ok((preset, params))
        })
        .collect::<Result<_>>()?;
    if args.write_log.is_some() && args.logs.len() > 1 {
        bail!("--write-log writes the one run measured: give at most one log with it");
    }
    if args.logs.len() <= 1 {
        return bench_one(args, &presets);
    }
    // One after another: timings must not share a core.
    emit_each(args.logs.iter().map(|path| {
        let lines = read_run(path)
            .and_then(|run| prepare(args, run))
            .and_then(|run| {
                let mut lines = Vec::new();
                for (preset, params) in &presets {
                    lines.push(line(
                        &path.display().to_string(),
                        *preset,
                        &measure(args, &path.display().to_string(), &run, params)?,
                    )?);
                }
                Ok(lines.join("\n"))
            });
        (path.as_path(), lines)
    }))
}

/// The one log given, or the generated run, measured: one pretty-printed object for one
/// preset, one line per preset otherwise.
fn bench_one(args: &BenchArgs, presets: &[(PresetArg, Params)]) -> Result<()> {
    let (name, run) = match args.logs.first() {
        Some(path) => (path.display().to_string(), read_run(path)?),
        None => (
            "generated".to_string(),
            sonarmap::bench::building_run(args.snapshots, 1),
        ),
    };
    let run = prepare(args, run)?;
    if let Some(path) = &args.write_log {
        write_atomic(path, save_run(&run))?;
    }
    if let [(_, params)] = presets {
        return emit(&serde_json::to_string_pretty(&measure(
            args, &name, &run, params,
        )?)?);
    }
    for (preset, params) in presets {
        emit(&line(&name, *preset, &measure(args, &name, &run, params)?)?)?;
    }
    Ok(())
}

/// The run measured: `run` with its `--laps`; a run without snapshots is refused.
fn prepare(args: &BenchArgs, run: Run) -> Result<Run> {
    let run = match args.laps {
        Some(n) => sonarmap::sim::repeat_laps(&run, n),
        None => run,
    };
    if run.snapshots.is_empty() {
        bail!("the run has no snapshot to measure");
    }
    Ok(run)
}

/// `run` (the log `name`) measured with `params` and the options of `args`, its progress
/// shown.
fn measure(args: &BenchArgs, name: &str, run: &Run, params: &Params) -> Result<BenchReport> {
    let steps = sonarmap::bench::bench_steps(run.snapshots.len(), args.repeats, args.engine_only);
    let progress = Progress::new(&format!("bench {name}"), steps, "steps");
    let report = sonarmap::bench::bench(
        run,
        params,
        args.repeats,
        args.checkpoint_interval,
        args.engine_only,
        &mut progress.callback(),
    );
    Ok(report.map_err(|_| Interrupted)?)
}

/// One measurement as a JSON line.
fn line(log: &str, preset: PresetArg, report: &BenchReport) -> serde_json::Result<String> {
    serde_json::to_string(&Line {
        log: log.to_string(),
        preset: format!("{preset:?}").to_lowercase(),
        report,
    })
}
