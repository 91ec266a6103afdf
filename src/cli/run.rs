//! `sonarmap run`: the mapper over one log or several (in parallel), writing maps, traces and
//! figures, printing a summary line per log.

use super::figure_args::{paper_figure_layers, paper_figure_svg, FigureArgs, FigureSpec};
use super::input::read_run;
use super::interrupt;
use super::map_run::{last_snapshot, Mapping};
use super::output::{emit, emit_each, write_atomic};
use super::parallel::parallel_map;
use super::params::{read_params, ParamArgs};
use super::progress::Progress;
use anyhow::{anyhow, bail, Context, Result};
use clap::Args;
use sonarmap::log::save_map;
use sonarmap::mapping::{Params, StepTrace};
use sonarmap::replay::StepView;
use sonarmap::run::Run;
use sonarmap::trajectory::tum_trajectory;
use std::path::{Path, PathBuf};

/// `sonarmap run`.
#[derive(Debug, Args)]
#[command(
    after_help = "Several logs run in parallel on all cores; each prints its summary line \
prefixed by its path, in the order given. A log that fails prints its error on stderr and the \
others go on; the exit code is then 2. With several logs the outputs go to --out-dir: for a log \
LOG/stem.json (or any other extension) the map is DIR/stem.map.json, the SVG DIR/stem.svg and, \
with --trace, the trace DIR/stem.trace.json. Two logs with the same stem are refused before any \
work."
)]
pub struct RunArgs {
    /// The run logs.
    #[arg(required = true, num_args = 1..)]
    pub logs: Vec<PathBuf>,
    /// Mapping parameters.
    #[command(flatten)]
    pub params: ParamArgs,
    /// Apply snapshots 0..=N only (default: all).
    #[arg(long, value_name = "N")]
    pub until: Option<usize>,
    /// Write the map here (`sonarmap-map` v1, the log's units); one log only.
    #[arg(long, value_name = "M.json")]
    pub out_map: Option<PathBuf>,
    /// Write the step traces here (JSON, metres); one log only.
    #[arg(long, value_name = "T.json")]
    pub out_trace: Option<PathBuf>,
    /// Write the poses the engine used (corrected, with pose_correction) here, as a TUM
    /// trajectory (`timestamp tx ty tz qx qy qz qw`, metres), for evo; one log only.
    #[arg(long, value_name = "P.tum")]
    pub out_poses: Option<PathBuf>,
    /// Write an SVG of the map here; one log only.
    #[arg(long, value_name = "V.svg")]
    pub svg: Option<PathBuf>,
    /// Write every log's map and SVG (and trace, with --trace) into this directory.
    #[arg(long, value_name = "DIR", conflicts_with_all = ["out_map", "out_trace", "out_poses", "svg"])]
    pub out_dir: Option<PathBuf>,
    /// With --out-dir: also write each log's trace.
    #[arg(long, requires = "out_dir")]
    pub trace: bool,
    /// The figure's region, layers, size, style and PNG.
    #[command(flatten)]
    pub figure: FigureArgs,
}

/// Where one log's outputs go.
#[derive(Clone, Debug, Default)]
struct RunOutputs {
    map: Option<PathBuf>,
    trace: Option<PathBuf>,
    poses: Option<PathBuf>,
    svg: Option<PathBuf>,
    figure: Option<FigureSpec>,
}

/// Runs `sonarmap run`.
pub fn run_command(args: &RunArgs) -> Result<()> {
    let params = read_params(&args.params)?;
    if args.figure.any() && args.svg.is_none() && args.out_dir.is_none() {
        bail!("--view, --layers, --size, --png and --figure shape the figure: give --svg V.svg (or --out-dir)");
    }
    let figure = Some(args.figure.spec(paper_figure_layers())?);
    let mut outputs = outputs(args)?;
    for out in &mut outputs {
        out.figure.clone_from(&figure);
    }
    // A bug that panics on one log must not take the process (or a sweep's other results)
    // with it; the steps themselves are guarded and name their snapshot.
    let guarded = |i: usize, sweep: Option<&Progress>| {
        let one = || run_one(&args.logs[i], &params, args.until, &outputs[i], sweep);
        std::panic::catch_unwind(std::panic::AssertUnwindSafe(one)).unwrap_or_else(|_| {
            Err(anyhow!(
                "{}: the mapper panicked on this log",
                args.logs[i].display()
            ))
        })
    };
    if args.logs.len() == 1 {
        return emit(&guarded(0, None)?);
    }
    let sweep = Progress::sweep(args.logs.len());
    let results = parallel_map(args.logs.len(), |i| {
        let result = guarded(i, Some(&sweep));
        let _ = sweep.inc();
        result.map(|summary| format!("{}: {summary}", args.logs[i].display()))
    });
    drop(sweep);
    // The logs that finished before Ctrl-C keep their outputs; none is printed.
    interrupt::check()?;
    emit_each(args.logs.iter().map(PathBuf::as_path).zip(results))
}

/// Where each log's outputs go (the figure's options not yet set): the paths given, for one
/// log, or files in `--out-dir` named after each log.
fn outputs(args: &RunArgs) -> Result<Vec<RunOutputs>> {
    match &args.out_dir {
        None if args.logs.len() > 1
            && (args.out_map.is_some()
                || args.out_trace.is_some()
                || args.out_poses.is_some()
                || args.svg.is_some()) =>
        {
            bail!("with several logs, write the outputs with --out-dir DIR")
        }
        None => Ok(vec![
            RunOutputs {
                map: args.out_map.clone(),
                trace: args.out_trace.clone(),
                poses: args.out_poses.clone(),
                svg: args.svg.clone(),
                figure: None,
            };
            args.logs.len()
        ]),
        Some(dir) => out_dir_outputs(args, dir),
    }
}

/// The outputs in `dir`, named after each log's stem; two logs with the same stem are
/// refused before the directory is made.
fn out_dir_outputs(args: &RunArgs, dir: &Path) -> Result<Vec<RunOutputs>> {
    let stems: Vec<String> = args
        .logs
        .iter()
        .map(|p| log_stem(p))
        .collect::<Result<_>>()?;
    for (i, stem) in stems.iter().enumerate() {
        if let Some(j) = stems[..i].iter().position(|s| s == stem) {
            bail!(
                "{} and {} would both write {}/{stem}.*: rename one",
                args.logs[j].display(),
                args.logs[i].display(),
                dir.display()
            );
        }
    }
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    Ok(stems
        .iter()
        .map(|stem| RunOutputs {
            map: Some(dir.join(format!("{stem}.map.json"))),
            trace: args.trace.then(|| dir.join(format!("{stem}.trace.json"))),
            poses: None,
            svg: Some(dir.join(format!("{stem}.svg"))),
            figure: None,
        })
        .collect())
}

/// Maps one log and writes what `out` asks, its progress shown (under `sweep`'s in a sweep);
/// returns its summary line. With `calibrate_first`, a log whose mapping found a drift is mapped
/// again from it ([`sonarmap::mapping::Mapper::second_pass_params`]), and that pass is written.
fn run_one(
    path: &Path,
    params: &Params,
    until: Option<usize>,
    out: &RunOutputs,
    sweep: Option<&Progress>,
) -> Result<String> {
    interrupt::check()?;
    let run = read_run(path)?;
    let until = last_snapshot(&run, until)?;
    let what = path.display().to_string();
    let mut progress = Progress::within(sweep, &what, until + 1, "snapshots");
    let (mut mapping, mut figure) = map_for(&run, params, until, out, &progress).context(what)?;
    if let Some(calibrated) = mapping.mapper.second_pass_params() {
        drop(progress);
        let what = format!("{} (calibrated)", path.display());
        progress = Progress::within(sweep, &what, until + 1, "snapshots");
        (mapping, figure) = map_for(&run, &calibrated, until, out, &progress).context(what)?;
    }
    let (mapper, traces, summary) = mapping.finish();
    if let Some(warning) = summary.min_range_warning(&run, mapper.params()) {
        progress.warn(&warning);
    }
    if let Some(path) = &out.map {
        write_atomic(path, save_map(mapper.map(), run.units, until))?;
    }
    if let Some(path) = &out.trace {
        write_trace(path, &traces)?;
    }
    if let Some(path) = &out.poses {
        let times_s: Vec<f64> = run.snapshots.iter().map(|s| s.t).collect();
        write_atomic(path, tum_trajectory(&times_s, &summary.poses))?;
    }
    if let (Some(path), Some(svg)) = (&out.svg, figure) {
        write_figure(path, &svg, out.figure.as_ref())?;
    }
    Ok(summary.to_string())
}

/// One pass over `run` to snapshot `until` with `params`, traced when `out` asks, and the
/// figure's SVG when it asks one: the figure's two snapshots are the run's last steps, traced
/// in full.
fn map_for(
    run: &Run,
    params: &Params,
    until: usize,
    out: &RunOutputs,
    progress: &Progress,
) -> Result<(Mapping, Option<String>)> {
    let mut mapping = Mapping::new(run, params.clone(), out.trace.is_some());
    if out.svg.is_none() {
        mapping.step_to(run, until + 1, progress)?;
        return Ok((mapping, None));
    }
    mapping.step_to(run, until.saturating_sub(1), progress)?;
    let view = StepView::by_stepping(&mut mapping.mapper, &run.snapshots, until);
    for trace in view.previous.iter().chain([&view.trace]) {
        mapping.record(trace.clone());
    }
    let svg = match &out.figure {
        Some(spec) => spec.svg(run, &view),
        None => paper_figure_svg(run, &view),
    };
    Ok((mapping, Some(svg)))
}

/// Writes the step traces to `path` (`sonarmap-trace` v1, metres).
fn write_trace(path: &Path, traces: &[StepTrace]) -> Result<()> {
    #[derive(serde::Serialize)]
    struct TraceFile<'a> {
        format: &'static str,
        version: u32,
        units: &'static str,
        steps: &'a [StepTrace],
    }
    let file = TraceFile {
        format: "sonarmap-trace",
        version: 1,
        units: "m",
        steps: traces,
    };
    write_atomic(path, serde_json::to_string(&file)?)
}

/// Writes the figure's SVG to `path`, and its PNG beside it when `spec` asks for one.
fn write_figure(path: &Path, svg: &str, spec: Option<&FigureSpec>) -> Result<()> {
    write_atomic(path, svg)?;
    if let Some(spec) = spec {
        if let Some(png) = spec.png_path(path) {
            let bytes = sonarmap::export::svg_to_png(svg, spec.width_px())
                .map_err(|e| anyhow!("{}: {e}", png.display()))?;
            write_atomic(&png, bytes)?;
        }
    }
    Ok(())
}

/// The file name of `path` up to its first dot (`runs/hall.log.json` → `hall`).
fn log_stem(path: &Path) -> Result<String> {
    let name = path
        .file_name()
        .and_then(|n| n.to_str())
        .with_context(|| format!("{} has no usable file name", path.display()))?;
    let stem = name
        .split('.')
        .next()
        .filter(|s| !s.is_empty())
        .unwrap_or(name);
    Ok(stem.to_owned())
}
