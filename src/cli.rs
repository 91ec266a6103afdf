//! The command line (docs/formats.md §10): every subcommand. Reads and writes files; every
//! write goes to a temporary file in the target's directory and is renamed into place.

use anyhow::{anyhow, bail, Context, Result};
use clap::{Args, Parser, Subcommand, ValueEnum};
use sonarmap::eval::{evaluate, EvalReport};
use sonarmap::log::{parse_json, save_map, save_run};
use sonarmap::mapping::{Map, Mapper, Outcome, Params, ParamsFile, Preset, StepTrace};
use sonarmap::replay::StepView;
use sonarmap::run::Run;
use sonarmap::scene::{Layer, LayerSet};
use sonarmap::sim::{load_plan, simulate, Model};
use std::io::Write;
use std::path::{Path, PathBuf};

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
    Run(RunArgs),
    /// Make a run log from a floor plan with the sonar simulator.
    Simulate(SimulateArgs),
    /// Compare the map of a log with its floor plan; prints one JSON object.
    #[command(long_about = EVAL_HELP)]
    Eval(EvalArgs),
    /// Convert a recording (Player/Stage log, ROS 2 MCAP, table) to a run log.
    Convert(crate::convert::ConvertArgs),
    /// Measure the engine, loading, seeking and drawing; prints one JSON object per log.
    Bench(BenchArgs),
    /// Compare the decisions of two parameter sets (A and B) on one log; prints one JSON object.
    #[command(long_about = DIFF_HELP)]
    Diff(DiffArgs),
    /// Drive long lap runs over generated scenes in every preset and with every single
    /// extension, checking the map's invariants after every step; prints one JSON object.
    Soak(SoakArgs),
}

/// `sonarmap soak`.
#[derive(Debug, Args)]
#[command(
    after_help = "Scenes: rooms, rotated rooms, L-shaped rooms, corridors with doors, \
rooms with pillars, rooms with an acute corner, rooms with desks, each with a random sensor layout \
and noise, simulated with the specular (even seeds) or axis (odd seeds) model, one lap repeated \
to --snapshots. Parameter sets: paper, extended, and the paper with each extension flag alone. \
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
}

const DIFF_HELP: &str = "Compare the decisions of two parameter sets on one log; prints one JSON object.

New segments of A and B are paired by their supporting readings. A decision differs when the outcome differs (kind \"outcome\"), when the same outcome names another existing segment (\"existing_segment\"), or when only one parameter set fitted the segment (\"only_in_a\", \"only_in_b\"). Each difference has a cause: \"direct\" when the new segment and the map within reach of a matching test are the same under A and B (the parameter change itself), \"consequential\" when an earlier difference changed what the decision saw. Output: snapshots (where any decision differs), first_difference, direct and consequential (counts of decisions), direct_snapshots, decisions (each with its cause and both sides: outcome, rule, existing segment), and eval_a / eval_b (the figures of `sonarmap eval`) when the log has a floor plan.";

/// `sonarmap diff`.
#[derive(Debug, Args)]
pub struct DiffArgs {
    /// The run log.
    pub log: PathBuf,
    /// Parameter set A.
    #[command(flatten)]
    pub a: ParamArgs,
    /// A parameters file for B (docs/formats.md §6), applied on top of B's preset.
    #[arg(long = "params-b", value_name = "B.json")]
    pub params_b: Option<PathBuf>,
    /// B's preset.
    #[arg(long = "preset-b", value_enum, default_value = "paper")]
    pub preset_b: PresetArg,
}

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

const EVAL_HELP: &str = "Compare the map of a log with its floor plan; prints one JSON object.

Only fitted segments count. The tolerance of an end-point with range D is the sonar resolution xi*D/100 (xi = the accuracy_pct parameter), at least 1 in.
  segments             fitted segments in the map
  true_segments        segments whose two end-points lie within their tolerance of one wall and whose angle to it is at most theta_o (orientation_deg), or whose end-points lie within tolerance of one pillar
  spurious_fraction    1 - true_segments / segments
  mean_endpoint_error  mean distance of true segments' end-points to their wall or pillar, in the log's units
  mean_angle_error_deg mean angle between true segments and their walls
  coverage             length of the walls covered by true segments (union of their end-points projected on their wall) over the total wall length
  coverage_visible     covered length inside the visible part of the walls over the visible length. A wall is visible around each kept reading (an echo below max_range, within [min_range, d_max]) whose beam-axis point is within its tolerance of the wall: +- the tolerance around the projection, and marks no more than t_gap apart along the wall are joined.
  wall_length, visible_length, covered_length  in the log's units";

/// The parameter preset.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum PresetArg {
    /// The paper alone.
    Paper,
    /// The paper with every extension: point memory, constant-depth groups, long-run bounds.
    Extended,
}

impl From<PresetArg> for Preset {
    fn from(p: PresetArg) -> Preset {
        match p {
            PresetArg::Paper => Preset::Paper,
            PresetArg::Extended => Preset::Extended,
        }
    }
}

/// Mapping parameters shared by `run` and `eval`.
#[derive(Debug, Args)]
pub struct ParamArgs {
    /// A parameters file (docs/formats.md §6), applied on top of the preset.
    #[arg(long, value_name = "P.json")]
    pub params: Option<PathBuf>,
    /// The parameter preset.
    #[arg(long, value_enum, default_value = "paper")]
    pub preset: PresetArg,
}

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
    /// Write an SVG of the map here; one log only.
    #[arg(long, value_name = "V.svg")]
    pub svg: Option<PathBuf>,
    /// Write every log's map and SVG (and trace, with --trace) into this directory.
    #[arg(long, value_name = "DIR", conflicts_with_all = ["out_map", "out_trace", "svg"])]
    pub out_dir: Option<PathBuf>,
    /// With --out-dir: also write each log's trace.
    #[arg(long, requires = "out_dir")]
    pub trace: bool,
    /// The figure's region, layers, size, style and PNG.
    #[command(flatten)]
    pub figure: crate::figure_args::FigureArgs,
}

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

/// `sonarmap eval`.
#[derive(Debug, Args)]
pub struct EvalArgs {
    /// The run log (none with --suite).
    #[arg(required_unless_present = "suite", conflicts_with = "suite")]
    pub log: Option<PathBuf>,
    /// Score N generated family scenes instead, each simulated with both sensor models; one
    /// JSON line per scene and model, then a summary line.
    #[arg(long, value_name = "N")]
    pub suite: Option<usize>,
    /// Seed of the suite's first scene.
    #[arg(long, default_value_t = 1, requires = "suite")]
    pub seed: u64,
    /// With --suite: also write each scene's plan (`sonarmap-plan` v1) into DIR as
    /// FAMILY-SEED.plan.json, for another simulator.
    #[arg(long, value_name = "DIR", requires = "suite")]
    pub write_plans: Option<PathBuf>,
    /// With --suite: also score each scene's log simulated elsewhere, DIR/FAMILY-SEED.log.json
    /// when it exists (model "log").
    #[arg(long, value_name = "DIR", requires = "suite")]
    pub logs_from: Option<PathBuf>,
    /// Mapping parameters.
    #[command(flatten)]
    pub params: ParamArgs,
    /// Floor plan to compare with (default: the log's own `floor_plan`).
    #[arg(long, value_name = "PLAN.json")]
    pub plan: Option<PathBuf>,
}

fn read(path: &Path) -> Result<Vec<u8>> {
    std::fs::read(path).with_context(|| format!("cannot read {}", path.display()))
}

/// Reads a run log or any recording the importers read (content decides).
pub fn read_run(path: &Path) -> Result<Run> {
    crate::convert::load_any(path)
}

/// The parameters from a preset and an optional `--params` file; a parameter on while one it
/// acts only with is off is warned about on stderr.
pub fn read_params(args: &ParamArgs) -> Result<Params> {
    let base = Params::preset(args.preset.into());
    let Some(path) = &args.params else {
        return Ok(base);
    };
    let name = path.display().to_string();
    let file: ParamsFile = parse_json(&read(path)?, &name)?;
    let params = base
        .with_file(&file)
        .with_context(|| format!("{name}: bad parameters"))?;
    for unmet in params.unmet_needs() {
        eprintln!("warning: {name}: {unmet}");
    }
    Ok(params)
}

/// Writes `text` to a temporary file next to `path` and renames it into place.
pub fn write_atomic(path: &Path, text: &str) -> Result<()> {
    write_atomic_with(path, |f| f.write_all(text.as_bytes()))
}

/// [`write_atomic`] with the content written by `write` (through a buffer), for output too
/// large to hold as one string first.
pub fn write_atomic_with(
    path: &Path,
    write: impl FnOnce(&mut std::io::BufWriter<std::fs::File>) -> std::io::Result<()>,
) -> Result<()> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let name = path
        .file_name()
        .ok_or_else(|| anyhow!("{} is not a file name", path.display()))?;
    let tmp = dir.join(format!(
        ".{}.tmp-{}",
        name.to_string_lossy(),
        std::process::id()
    ));
    let result = (|| {
        let mut f = std::io::BufWriter::new(std::fs::File::create(&tmp)?);
        write(&mut f)?;
        let f = f.into_inner().map_err(|e| e.into_error())?;
        f.sync_all()?;
        std::fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result.with_context(|| format!("cannot write {}", path.display()))
}

/// Runs the mapper over snapshots `0..=until` and returns the mapper and the traces.
pub fn map_run(
    run: &Run,
    params: Params,
    until: Option<usize>,
    keep_traces: bool,
) -> Result<(Mapper, Vec<StepTrace>, Summary)> {
    let mut mapping = Mapping::new(run, params, keep_traces);
    mapping.step_to(run, last_snapshot(run, until)? + 1)?;
    Ok(mapping.finish())
}

/// The last snapshot to map: `until`, checked against the run, or the run's last.
fn last_snapshot(run: &Run, until: Option<usize>) -> Result<usize> {
    let last = run.snapshots.len() - 1;
    match until {
        Some(n) if n > last => bail!("--until {n} is beyond the last snapshot, {last}"),
        Some(n) => Ok(n),
        None => Ok(last),
    }
}

/// A mapper going through a run, with the summary and (when kept) the traces of its steps.
struct Mapping {
    mapper: Mapper,
    traces: Vec<StepTrace>,
    summary: Summary,
}

impl Mapping {
    fn new(run: &Run, params: Params, keep_traces: bool) -> Self {
        // The summary needs only readings and decisions, which the slim trace keeps.
        Self {
            mapper: Mapper::new(params, run.layout.clone(), run.sensor).with_trace(keep_traces),
            traces: Vec::new(),
            summary: Summary::default(),
        }
    }

    /// Steps the snapshots from the mapper's next one up to `end` (exclusive); a step that
    /// fails ends the mapping with an error naming its snapshot.
    fn step_to(&mut self, run: &Run, end: usize) -> Result<()> {
        while self.mapper.next_snapshot() < end {
            let trace = self
                .mapper
                .try_step(&run.snapshots[self.mapper.next_snapshot()])?;
            self.record(trace);
        }
        Ok(())
    }

    /// The mapper, the kept traces and the summary (with the map's size).
    fn finish(self) -> (Mapper, Vec<StepTrace>, Summary) {
        let mut summary = self.summary;
        summary.segments = self.mapper.map().segments.len();
        (self.mapper, self.traces, summary)
    }

    fn record(&mut self, trace: StepTrace) {
        self.summary.add(&trace);
        if self.mapper.records_trace() {
            self.traces.push(trace);
        }
    }
}

/// Counts over a run, for the one-line summary.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Summary {
    /// Snapshots applied.
    pub snapshots: usize,
    /// Readings kept.
    pub kept: usize,
    /// Readings discarded.
    pub discarded: usize,
    /// Segments in the map.
    pub segments: usize,
    /// Decisions by outcome.
    pub matches: usize,
    /// Extensions.
    pub extensions: usize,
    /// Dismissals.
    pub dismissals: usize,
    /// New faces.
    pub new_faces: usize,
}

impl Summary {
    fn add(&mut self, trace: &StepTrace) {
        self.snapshots += 1;
        for r in &trace.readings {
            if r.discarded.is_some() {
                self.discarded += 1;
            } else {
                self.kept += 1;
            }
        }
        for d in &trace.decisions {
            match d.outcome {
                Outcome::Match => self.matches += 1,
                Outcome::Extension => self.extensions += 1,
                Outcome::Dismissed => self.dismissals += 1,
                Outcome::NewFace => self.new_faces += 1,
            }
        }
    }
}

impl std::fmt::Display for Summary {
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        write!(
            f,
            "snapshots {}, readings kept {} discarded {}, segments {}, matches {}, extensions {}, dismissals {}, new faces {}",
            self.snapshots, self.kept, self.discarded, self.segments, self.matches, self.extensions, self.dismissals, self.new_faces
        )
    }
}

/// Where one log's outputs go.
#[derive(Clone, Debug, Default)]
struct RunOutputs {
    map: Option<PathBuf>,
    trace: Option<PathBuf>,
    svg: Option<PathBuf>,
    figure: Option<crate::figure_args::FigureSpec>,
}

fn run_command(args: &RunArgs) -> Result<()> {
    let params = read_params(&args.params)?;
    if args.figure.any() && args.svg.is_none() && args.out_dir.is_none() {
        bail!("--view, --layers, --size, --png and --figure shape the figure: give --svg V.svg (or --out-dir)");
    }
    let figure = Some(args.figure.spec(paper_figure_layers())?);
    let mut outputs: Vec<RunOutputs> = match &args.out_dir {
        None if args.logs.len() > 1
            && (args.out_map.is_some() || args.out_trace.is_some() || args.svg.is_some()) =>
        {
            bail!("with several logs, write the outputs with --out-dir DIR")
        }
        None => vec![
            RunOutputs {
                map: args.out_map.clone(),
                trace: args.out_trace.clone(),
                svg: args.svg.clone(),
                figure: None,
            };
            args.logs.len()
        ],
        Some(dir) => {
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
            std::fs::create_dir_all(dir)
                .with_context(|| format!("cannot create {}", dir.display()))?;
            stems
                .iter()
                .map(|stem| RunOutputs {
                    map: Some(dir.join(format!("{stem}.map.json"))),
                    trace: args.trace.then(|| dir.join(format!("{stem}.trace.json"))),
                    svg: Some(dir.join(format!("{stem}.svg"))),
                    figure: None,
                })
                .collect()
        }
    };
    for out in &mut outputs {
        out.figure.clone_from(&figure);
    }
    // A bug that panics on one log must not take the process (or a sweep's other results)
    // with it; the steps themselves are guarded and name their snapshot.
    let guarded = |i: usize| {
        let one = || run_one(&args.logs[i], &params, args.until, &outputs[i]);
        std::panic::catch_unwind(std::panic::AssertUnwindSafe(one)).unwrap_or_else(|_| {
            Err(anyhow!(
                "{}: the mapper panicked on this log",
                args.logs[i].display()
            ))
        })
    };
    if args.logs.len() == 1 {
        return emit(&guarded(0)?);
    }
    let results = parallel_map(args.logs.len(), |i| {
        guarded(i).map(|summary| format!("{}: {summary}", args.logs[i].display()))
    });
    emit_each(args.logs.iter().map(PathBuf::as_path).zip(results))
}

/// Prints each log's line on stdout, or its error on stderr, in order; fails (exit 2) when
/// any log failed, after all were reported.
fn emit_each<'a>(results: impl Iterator<Item = (&'a Path, Result<String>)>) -> Result<()> {
    let (mut total, mut failed) = (0, 0);
    for (path, result) in results {
        total += 1;
        match result {
            Ok(line) => emit(&line)?,
            Err(e) => {
                failed += 1;
                report_failure(path, &e);
            }
        }
    }
    if failed > 0 {
        bail!("{failed} of {total} logs failed");
    }
    Ok(())
}

/// Prints a failed log's error on stderr, naming the log unless the error already does.
fn report_failure(path: &Path, e: &anyhow::Error) {
    let message = sonarmap::import::sane::escape(&format!("{e:#}"));
    let name = path.display().to_string();
    if message.contains(&name) {
        eprintln!("{message}");
    } else {
        eprintln!("{name}: {message}");
    }
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

/// `f(0)`, …, `f(n - 1)` on all cores (a shared queue; results in index order).
fn parallel_map<T: Send>(n: usize, f: impl Fn(usize) -> T + Sync) -> Vec<T> {
    let workers = std::thread::available_parallelism()
        .map_or(1, |c| c.get())
        .min(n)
        .max(1);
    let next = std::sync::atomic::AtomicUsize::new(0);
    let slots: Vec<std::sync::Mutex<Option<T>>> =
        (0..n).map(|_| std::sync::Mutex::new(None)).collect();
    std::thread::scope(|scope| {
        for _ in 0..workers {
            scope.spawn(|| loop {
                let i = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                if i >= n {
                    break;
                }
                let value = f(i);
                *slots[i].lock().unwrap_or_else(|e| e.into_inner()) = Some(value);
            });
        }
    });
    slots
        .into_iter()
        .map(|m| {
            m.into_inner()
                .unwrap_or_else(|e| e.into_inner())
                .expect("every index ran")
        })
        .collect()
}

/// Maps one log and writes what `out` asks; returns its summary line. The log is mapped once:
/// the figure's two snapshots are the run's last steps, traced in full.
fn run_one(path: &Path, params: &Params, until: Option<usize>, out: &RunOutputs) -> Result<String> {
    let run = read_run(path)?;
    let until = last_snapshot(&run, until)?;
    let mut mapping = Mapping::new(&run, params.clone(), out.trace.is_some());
    let figure = match &out.svg {
        Some(_) => {
            mapping
                .step_to(&run, until.saturating_sub(1))
                .with_context(|| path.display().to_string())?;
            let view = StepView::by_stepping(&mut mapping.mapper, &run.snapshots, until);
            for trace in view.previous.iter().chain([&view.trace]) {
                mapping.record(trace.clone());
            }
            Some(match &out.figure {
                Some(spec) => spec.svg(&run, &view),
                None => paper_figure_svg(&run, &view),
            })
        }
        None => {
            mapping
                .step_to(&run, until + 1)
                .with_context(|| path.display().to_string())?;
            None
        }
    };
    let (mapper, traces, summary) = mapping.finish();
    if let Some(path) = &out.map {
        write_atomic(path, &save_map(mapper.map(), run.units, until))?;
    }
    if let Some(path) = &out.trace {
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
            steps: &traces,
        };
        write_atomic(path, &serde_json::to_string(&file)?)?;
    }
    if let (Some(path), Some(svg)) = (&out.svg, figure) {
        write_atomic(path, &svg)?;
        if let Some(spec) = &out.figure {
            if let Some(png) = spec.png_path(path) {
                let bytes = sonarmap::export::svg_to_png(&svg, spec.width_px())
                    .map_err(|e| anyhow!("{}: {e}", png.display()))?;
                sonarmap::export::write_bytes_atomically(&png, &bytes)
                    .with_context(|| format!("cannot write {}", png.display()))?;
            }
        }
    }
    Ok(summary.to_string())
}

/// The layers of a paper figure: ground truth, both snapshots' points, balls, fitted and map
/// segments, updates, decisions, correlations, the robot and labels; no beams or discarded
/// readings (they would dwarf the room).
pub fn paper_figure_layers() -> LayerSet {
    LayerSet::all()
        .with(Layer::Beams, false)
        .with(Layer::Discarded, false)
        .with(Layer::MapBefore, false)
        .with(Layer::Clusters, false)
}

/// The SVG of `view` (a snapshot of `run`) as a paper figure (the whole content in view, the
/// paper figure's layers, 1000×700 pixels, labels decluttered for the page).
pub fn paper_figure_svg(run: &Run, view: &StepView) -> String {
    crate::figure_args::FigureArgs::default()
        .spec(paper_figure_layers())
        .expect("the default figure options are valid")
        .svg(run, view)
}

fn simulate_command(args: &SimulateArgs) -> Result<()> {
    let plan = load_plan(&read(&args.plan)?, &args.plan.display().to_string())?;
    let model = match args.model {
        ModelArg::Specular => Model::Specular,
        ModelArg::Axis => Model::Axis,
    };
    let run = simulate(&plan, model, args.seed);
    write_atomic(&args.out, &save_run(&run))
}

/// The figures `eval` prints, with what produced them.
#[derive(Debug, serde::Serialize)]
struct EvalOutput {
    log: String,
    preset: &'static str,
    snapshots: usize,
    #[serde(flatten)]
    report: EvalReport,
    /// Point features (docs/algorithm.md §8.5), when the map has any.
    #[serde(skip_serializing_if = "Option::is_none")]
    point_features: Option<usize>,
    /// Those on a wall junction or end.
    #[serde(skip_serializing_if = "Option::is_none")]
    true_point_features: Option<usize>,
    /// The figures of the confirmed segments alone, when segments must be confirmed
    /// (docs/algorithm.md §8.7).
    #[serde(skip_serializing_if = "Option::is_none")]
    confirmed: Option<EvalReport>,
}

fn eval_command(args: &EvalArgs) -> Result<()> {
    let params = read_params(&args.params)?;
    let Some(log) = &args.log else {
        return suite_command(args, &params);
    };
    let run = read_run(log)?;
    let floor_plan = match &args.plan {
        Some(path) => load_plan(&read(path)?, &path.display().to_string())?.floor_plan,
        None => run.floor_plan.clone().ok_or_else(|| {
            anyhow!(
                "{}: the log has no floor_plan; give one with --plan PLAN.json",
                log.display()
            )
        })?,
    };
    let (mapper, _, summary) =
        map_run(&run, params.clone(), None, false).with_context(|| log.display().to_string())?;
    let map = mapper.map();
    let report = evaluate(map, &run, &floor_plan, &params);
    let features = map.confirmed_features().count();
    let has_features = features > 0;
    let out = EvalOutput {
        log: log.display().to_string(),
        preset: match args.params.preset {
            PresetArg::Paper => "paper",
            PresetArg::Extended => "extended",
        },
        snapshots: summary.snapshots,
        report,
        point_features: has_features.then_some(features),
        true_point_features: has_features
            .then(|| sonarmap::eval::true_point_features(map, &floor_plan, &params)),
        confirmed: sonarmap::eval::confirmed_map(map)
            .map(|m| evaluate(&m, &run, &floor_plan, &params)),
    };
    emit(&serde_json::to_string_pretty(&out)?)?;
    Ok(())
}

/// `eval --suite N`: one JSON line per scene and sensor model, then the summary
/// ([`crate::suite`]); with `--write-plans DIR`, the scenes' plans too.
fn suite_command(args: &EvalArgs, params: &Params) -> Result<()> {
    let scenes = args.suite.unwrap_or(0);
    if let Some(dir) = &args.write_plans {
        std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
        for (kind, seed, plan) in sonarmap::suite::suite_plans(scenes, args.seed) {
            let path = dir.join(format!("{}-{seed}.plan.json", kind.name()));
            let text = serde_json::to_string(&sonarmap::sim::plan_to_file(&plan))?;
            write_atomic(&path, &text)?;
        }
    }
    let mut lines = sonarmap::suite::run_suite(scenes, args.seed, params);
    if let Some(dir) = &args.logs_from {
        for (kind, seed, _) in sonarmap::suite::suite_plans(scenes, args.seed) {
            let path = dir.join(format!("{}-{seed}.log.json", kind.name()));
            if !path.exists() {
                continue;
            }
            let run = read_run(&path)?;
            let map = sonarmap::suite::map_of(&run, params);
            let figures = sonarmap::suite::scene_figures(&map, &run, params)
                .ok_or_else(|| anyhow!("{}: the log has no floor_plan", path.display()))?;
            lines.push(sonarmap::suite::SuiteLine {
                family: kind.name(),
                seed,
                model: "log".to_string(),
                snapshots: run.snapshots.len(),
                figures,
            });
        }
    }
    for line in &lines {
        emit(&serde_json::to_string(line)?)?;
    }
    emit(&serde_json::to_string(&sonarmap::suite::summarise(&lines))?)?;
    Ok(())
}

/// Runs a subcommand.
pub fn execute(command: &Command) -> Result<()> {
    match command {
        Command::Run(a) => run_command(a),
        Command::Simulate(a) => simulate_command(a),
        Command::Eval(a) => eval_command(a),
        Command::Convert(a) => crate::convert::convert_command(a),
        Command::Bench(a) => bench_command(a),
        Command::Diff(a) => diff_command(a),
        Command::Soak(a) => soak_command(a),
    }
}

fn soak_command(args: &SoakArgs) -> Result<()> {
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
    let report = sonarmap::soak::soak_variants_named(
        args.runs_per_kind,
        args.snapshots,
        args.seed,
        &args.only,
        |r| {
            eprint!(
                "\r{} runs, {} snapshots, {} failures",
                r.runs,
                r.snapshots,
                r.failures.len()
            );
        },
    );
    eprintln!();
    #[derive(serde::Serialize)]
    struct Failure {
        scene: &'static str,
        seed: u64,
        params: String,
        snapshot: usize,
        panicked: bool,
        message: String,
    }
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

fn bench_command(args: &BenchArgs) -> Result<()> {
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
    let prepare = |run: Run| -> Result<Run> {
        let run = match args.laps {
            Some(n) => sonarmap::sim::repeat_laps(&run, n),
            None => run,
        };
        if run.snapshots.is_empty() {
            bail!("the run has no snapshot to measure");
        }
        Ok(run)
    };
    let measure = |run: &Run, params: &Params| {
        sonarmap::bench::bench(
            run,
            params,
            args.repeats,
            args.checkpoint_interval,
            args.engine_only,
        )
    };
    #[derive(serde::Serialize)]
    struct Line<'a> {
        log: String,
        preset: String,
        #[serde(flatten)]
        report: &'a sonarmap::bench::BenchReport,
    }
    let line = |log: &str, preset: PresetArg, report: &sonarmap::bench::BenchReport| {
        serde_json::to_string(&Line {
            log: log.to_string(),
            preset: format!("{preset:?}").to_lowercase(),
            report,
        })
    };
    if args.write_log.is_some() && args.logs.len() > 1 {
        bail!("--write-log writes the one run measured: give at most one log with it");
    }
    if args.logs.len() <= 1 {
        let (name, run) = match args.logs.first() {
            Some(path) => (path.display().to_string(), read_run(path)?),
            None => (
                "generated".to_string(),
                sonarmap::bench::building_run(args.snapshots, 1),
            ),
        };
        let run = prepare(run)?;
        if let Some(path) = &args.write_log {
            write_atomic(path, &save_run(&run))?;
        }
        if let [(_, params)] = presets.as_slice() {
            return emit(&serde_json::to_string_pretty(&measure(&run, params))?);
        }
        for (preset, params) in &presets {
            emit(&line(&name, *preset, &measure(&run, params))?)?;
        }
        return Ok(());
    }
    // One after another: timings must not share a core.
    emit_each(args.logs.iter().map(|path| {
        let lines = read_run(path).and_then(prepare).and_then(|run| {
            let mut lines = Vec::new();
            for (preset, params) in &presets {
                lines.push(line(
                    &path.display().to_string(),
                    *preset,
                    &measure(&run, params),
                )?);
            }
            Ok(lines.join("\n"))
        });
        (path.as_path(), lines)
    }))
}

fn diff_command(args: &DiffArgs) -> Result<()> {
    let run = read_run(&args.log)?;
    let a = read_params(&args.a)?;
    let b = read_params(&ParamArgs {
        params: args.params_b.clone(),
        preset: args.preset_b,
    })?;
    // One pass: the maps the comparison leaves are the ones evaluated.
    let (diff, map_a, map_b) = sonarmap::diff::diff_run_keeping_maps(&run, &a, &b, &mut |_| true);
    let eval = |map: &Map, params: &Params| {
        run.floor_plan
            .as_ref()
            .map(|plan| evaluate(map, &run, plan, params))
    };
    #[derive(serde::Serialize)]
    struct DiffOutput {
        log: String,
        snapshots_compared: usize,
        #[serde(flatten)]
        diff: sonarmap::diff::RunDiff,
        eval_a: Option<EvalReport>,
        eval_b: Option<EvalReport>,
    }
    let out = DiffOutput {
        log: args.log.display().to_string(),
        snapshots_compared: run.snapshots.len(),
        eval_a: eval(&map_a, &a),
        eval_b: eval(&map_b, &b),
        diff,
    };
    emit(&serde_json::to_string_pretty(&out)?)?;
    Ok(())
}

/// Prints a line on stdout; a closed pipe (`| head`) is not an error.
fn emit(text: &str) -> Result<()> {
    let mut out = std::io::stdout().lock();
    match writeln!(out, "{text}").and_then(|()| out.flush()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => Err(e.into()),
        _ => Ok(()),
    }
}
