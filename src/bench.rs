//! `sonarmap bench`: throughput figures of the engine, loading, seeking and scene building,
//! each the median of several runs. Not part of the pure core: it reads the clock.

use crate::alloc_count;
use crate::app::{HeadlessMapView, PREVIEW_SNAPSHOTS};
use crate::log::{load_run, save_run};
use crate::mapping::{Mapper, Params};
use crate::replay::{Cancelled, Replay};
use crate::run::Run;
use crate::scene::svg::{default_view, to_svg};
use crate::scene::{build_scene, SceneInput, ViewOptions};
use crate::sim::{building_plan, simulate, BuildingSpec, Model};
use serde::Serialize;
use std::sync::Arc;
use std::time::Instant;

/// The figures, as `bench` prints them: the engine's always, the inspector's unless
/// `--engine-only`.
#[derive(Clone, Debug, Serialize)]
pub struct BenchReport {
    /// Cores of the machine.
    pub cores: usize,
    /// Snapshots in the benchmarked run.
    pub snapshots: usize,
    /// The parameters measured (a `--params` file's fields, in metres and degrees).
    pub params: crate::mapping::ParamsFile,
    /// The engine alone.
    #[serde(flatten)]
    pub engine: EngineFigures,
    /// The inspector's figures (absent with `--engine-only`).
    #[serde(flatten)]
    pub inspector: Option<InspectorFigures>,
}

/// What the mapper costs, trace off and on.
#[derive(Clone, Debug, Serialize)]
pub struct EngineFigures {
    /// Mapper steps per second with the trace off (median).
    pub engine_snapshots_per_s_trace_off: f64,
    /// Mapper steps per second with the full trace (median).
    pub engine_snapshots_per_s_trace_on: f64,
    /// Time of the last tenth of the run over the first tenth (median, trace off).
    pub engine_last_tenth_over_first_tenth: f64,
    /// Candidates offered to the matching tests in the first tenth of the run, per snapshot.
    pub candidates_per_snapshot_first_tenth: f64,
    /// The same in the last tenth.
    pub candidates_per_snapshot_last_tenth: f64,
    /// Time per offered candidate, last tenth over first tenth (median, trace off): whether
    /// the cost of one test stays flat while the map grows.
    pub cost_per_candidate_last_tenth_over_first_tenth: f64,
    /// Segments in the final map.
    pub final_segments: usize,
}

/// What the inspector costs on the run: loading, replay, seeking, frames, SVG.
#[derive(Clone, Debug, Serialize)]
pub struct InspectorFigures {
    /// Seconds to parse and validate the run's JSON (median).
    pub load_s: f64,
    /// Peak heap during loading over the file size (0 when the counting allocator is absent).
    pub load_peak_memory_over_file_size: f64,
    /// File size of the run's JSON, bytes.
    pub file_bytes: usize,
    /// Median time from the run's bytes to its first snapshot ready to draw in the inspector
    /// (loading, the first snapshots replayed on the spot, the scene), milliseconds.
    pub first_frame_ms: f64,
    /// Largest time to make any snapshot ready to draw, milliseconds.
    pub seek_ms_max: f64,
    /// Median time to make a snapshot ready to draw, milliseconds.
    pub seek_ms_median: f64,
    /// Largest time to show the next snapshot after one is shown (playing, the arrow key):
    /// one traced step from where the last view left the mapper, milliseconds.
    pub step_forward_ms_max: f64,
    /// Checkpoints held at the end of the replay.
    pub checkpoints: usize,
    /// The shortest spacing between checkpoints (late in a run whose steps grow dearer),
    /// snapshots.
    pub checkpoint_spacing_min: usize,
    /// The longest (early in such a run), snapshots.
    pub checkpoint_spacing_max: usize,
    /// Heap the checkpoints alone keep alive: freed when they are dropped and the rest of the
    /// replay kept, bytes (0 without the counting allocator).
    pub checkpoint_bytes: usize,
    /// Heap the whole replay holds once built (checkpoints, the final map, step summaries,
    /// decisions, lineage, truth curve), bytes (0 without the counting allocator).
    pub replay_heap_bytes: usize,
    /// The checkpoints' own estimate of the bytes they keep alive, and their budget.
    pub checkpoint_estimated_bytes: usize,
    /// The budget the spacing was chosen from, bytes.
    pub checkpoint_budget_bytes: usize,
    /// Median time to make the map view's frame of a snapshot with every layer on and the
    /// whole map in a 1600 × 1000 view: scene build (with the view's level of detail), the
    /// inspector's egui_plot drawing, and egui's tessellation into meshes; milliseconds.
    pub frame_ms_median: f64,
    /// The scene-build part of that frame (median), milliseconds.
    pub scene_build_ms_median: f64,
    /// A frame that reuses its scene (nothing shown changed: looking, hovering, a small pan),
    /// median, milliseconds.
    pub frame_reusing_scene_ms_median: f64,
    /// Largest number of mesh vertices those frames tessellated.
    pub frame_vertices_max: usize,
    /// Median time to write the SVG of a snapshot with every layer on (whole content in view), ms.
    pub svg_ms_median: f64,
    /// Largest size of those SVGs, bytes.
    pub svg_bytes_max: usize,
    /// Seconds to build the replay (the whole run with checkpoints, step summaries, lineage
    /// and, with a floor plan, the truth curve), as the inspector does on opening a run.
    pub replay_build_s: f64,
    /// The longest time to list any segment's lineage (every segment ever made), milliseconds.
    pub lineage_ms_max: f64,
    /// A frame of the run plots panel (1400 × 170 points, each plot, tessellated), median, ms.
    pub plots_frame_ms_median: f64,
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    if v.is_empty() {
        0.0
    } else {
        v[v.len() / 2]
    }
}

/// A long run through a generated building: one lap simulated, then driven back and forth.
pub fn building_run(snapshots: usize, seed: u64) -> Run {
    let plan = building_plan(&BuildingSpec::default(), seed);
    let lap = simulate(&plan, Model::Specular, seed);
    back_and_forth(&lap, snapshots)
}

/// `lap` driven forwards, backwards, forwards… until the run has `snapshots` snapshots, one
/// every 0.2 s (an empty lap gives an empty run).
pub fn back_and_forth(lap: &Run, snapshots: usize) -> Run {
    let mut run = lap.clone();
    run.name = format!("{} — {snapshots} snapshots", lap.name);
    run.snapshots.clear();
    let mut forward = true;
    while run.snapshots.len() < snapshots && !lap.snapshots.is_empty() {
        let lap_iter: Box<dyn Iterator<Item = &crate::run::Snapshot>> = if forward {
            Box::new(lap.snapshots.iter())
        } else {
            Box::new(lap.snapshots.iter().rev())
        };
        for s in lap_iter.take(snapshots - run.snapshots.len()) {
            let mut s = s.clone();
            s.t = run.snapshots.len() as f64 * 0.2;
            run.snapshots.push(s);
        }
        forward = !forward;
    }
    run
}

/// One pass of the mapper over a run: total seconds, and the seconds and offered candidates
/// of its first and last tenth.
struct EnginePass {
    total_s: f64,
    first_s: f64,
    last_s: f64,
    first_candidates: usize,
    last_candidates: usize,
    final_segments: usize,
}

/// Steps a mapper over `run` with the trace on or off, calling `progress(steps)` after every
/// step; returning `false` cancels.
fn time_engine(
    run: &Run,
    params: &Params,
    trace: bool,
    progress: &mut dyn FnMut(usize) -> bool,
) -> Result<EnginePass, Cancelled> {
    let mut mapper = Mapper::new(params.clone(), run.layout.clone(), run.sensor).with_trace(trace);
    let n = run.snapshots.len();
    let tenth = (n / 10).max(1);
    let mut pass = EnginePass {
        total_s: 0.0,
        first_s: 0.0,
        last_s: 0.0,
        first_candidates: 0,
        last_candidates: 0,
        final_segments: 0,
    };
    let start = Instant::now();
    let mut mark = start;
    for (k, s) in run.snapshots.iter().enumerate() {
        std::hint::black_box(mapper.step(s));
        if k < tenth {
            pass.first_candidates += mapper.last_step_candidates();
        } else if k >= n - tenth {
            pass.last_candidates += mapper.last_step_candidates();
        }
        if k + 1 == tenth {
            pass.first_s = mark.elapsed().as_secs_f64();
        }
        if k + 1 == n - tenth {
            mark = Instant::now();
        }
        if !progress(k + 1) {
            return Err(Cancelled);
        }
    }
    if n >= 2 * tenth {
        pass.last_s = mark.elapsed().as_secs_f64();
    }
    pass.total_s = start.elapsed().as_secs_f64();
    pass.final_segments = mapper.map().segments.len();
    Ok(pass)
}

fn ratio(num: f64, den: f64) -> f64 {
    if den > 0.0 {
        num / den
    } else {
        0.0
    }
}

/// The steps [`bench()`] reports to its progress callback on a run of `snapshots`: every
/// engine pass (trace off and on, `repeats` each) and, unless `engine_only`, the replay.
pub fn bench_steps(snapshots: usize, repeats: usize, engine_only: bool) -> usize {
    let engine = 2 * repeats.max(1) * snapshots;
    if engine_only {
        engine
    } else {
        engine + snapshots
    }
}

/// The engine's figures on `run` (`repeats` runs each, medians), calling `progress(steps)`
/// after every step of every pass; returning `false` cancels.
pub fn bench_engine(
    run: &Run,
    params: &Params,
    repeats: usize,
    progress: &mut dyn FnMut(usize) -> bool,
) -> Result<EngineFigures, Cancelled> {
    let n = run.snapshots.len();
    let tenth = (n / 10).max(1) as f64;
    let (mut off, mut on, mut tenths, mut per_candidate) = (vec![], vec![], vec![], vec![]);
    let mut last_pass = None;
    for repeat in 0..repeats.max(1) {
        let done = 2 * repeat * n;
        let pass = time_engine(run, params, false, &mut |k| progress(done + k))?;
        off.push(n as f64 / pass.total_s);
        tenths.push(ratio(pass.last_s, pass.first_s));
        per_candidate.push(ratio(
            pass.last_s / pass.last_candidates.max(1) as f64,
            pass.first_s / pass.first_candidates.max(1) as f64,
        ));
        let traced = time_engine(run, params, true, &mut |k| progress(done + n + k))?;
        on.push(n as f64 / traced.total_s);
        last_pass = Some(pass);
    }
    let pass = last_pass.expect("at least one repeat");
    Ok(EngineFigures {
        engine_snapshots_per_s_trace_off: median(off),
        engine_snapshots_per_s_trace_on: median(on),
        engine_last_tenth_over_first_tenth: median(tenths),
        candidates_per_snapshot_first_tenth: pass.first_candidates as f64 / tenth,
        candidates_per_snapshot_last_tenth: pass.last_candidates as f64 / tenth,
        cost_per_candidate_last_tenth_over_first_tenth: median(per_candidate),
        final_segments: pass.final_segments,
    })
}

/// Measures everything on `run` (`repeats` runs each; the median is reported), the replay's
/// checkpoints at least `checkpoint_interval` snapshots apart; with `engine_only`, the engine
/// alone. `progress(steps)` hears of the steps done ([`bench_steps`] in all); returning
/// `false` cancels.
pub fn bench(
    run: &Run,
    params: &Params,
    repeats: usize,
    checkpoint_interval: usize,
    engine_only: bool,
    progress: &mut dyn FnMut(usize) -> bool,
) -> Result<BenchReport, Cancelled> {
    let engine = bench_engine(run, params, repeats, progress)?;
    let done = bench_steps(run.snapshots.len(), repeats, true);
    let inspector = match engine_only {
        true => None,
        false => Some(bench_inspector(
            run,
            params,
            repeats,
            checkpoint_interval,
            &mut |k| progress(done + k),
        )?),
    };
    Ok(BenchReport {
        params: params.to_file(crate::units::Units::Metres),
        cores: std::thread::available_parallelism().map_or(1, |c| c.get()),
        snapshots: run.snapshots.len(),
        engine,
        inspector,
    })
}

/// The inspector's figures on `run`, the replay's steps told to `progress`.
fn bench_inspector(
    run: &Run,
    params: &Params,
    repeats: usize,
    checkpoint_interval: usize,
    progress: &mut dyn FnMut(usize) -> bool,
) -> Result<InspectorFigures, Cancelled> {
    let n = run.snapshots.len();
    let json = save_run(run);
    let (loads, peak) = time_loads(&json, repeats);
    let first_frames = time_first_frames(&json, params, repeats);
    alloc_count::start_counting();
    let start = Instant::now();
    let replay = Replay::build(
        Arc::new(run.clone()),
        params.clone(),
        checkpoint_interval,
        progress,
    );
    let replay_build_s = start.elapsed().as_secs_f64();
    alloc_count::stop_counting();
    let replay_heap_bytes = alloc_count::counted_bytes().max(0) as usize;
    let mut replay = replay?;
    let lineage_ms_max = time_lineages(&replay, n);
    let (checkpoints, spacing_min, spacing_max) = replay.checkpoint_spacing();
    let seeks = time_seeks(run, &replay);
    let plot_frames = time_plots(&replay, n);
    let (checkpoint_estimated_bytes, checkpoint_budget_bytes) = replay.checkpoint_bytes();
    let checkpoint_bytes = checkpoints_alone_bytes(&mut replay);
    Ok(InspectorFigures {
        load_s: median(loads),
        load_peak_memory_over_file_size: peak as f64 / json.len() as f64,
        file_bytes: json.len(),
        first_frame_ms: median(first_frames),
        seek_ms_max: seeks.seeks.iter().cloned().fold(0.0, f64::max),
        seek_ms_median: median(seeks.seeks),
        step_forward_ms_max: seeks.forward_ms_max,
        checkpoints,
        checkpoint_spacing_min: spacing_min,
        checkpoint_spacing_max: spacing_max,
        checkpoint_bytes,
        replay_heap_bytes,
        checkpoint_estimated_bytes,
        checkpoint_budget_bytes,
        frame_ms_median: median(seeks.frames),
        scene_build_ms_median: median(seeks.builds),
        frame_reusing_scene_ms_median: median(seeks.reused_frames),
        frame_vertices_max: seeks.vertices_max,
        svg_ms_median: median(seeks.svgs),
        svg_bytes_max: seeks.svg_bytes_max,
        replay_build_s,
        lineage_ms_max,
        plots_frame_ms_median: median(plot_frames),
    })
}

/// The heap `replay`'s checkpoints alone keep alive: what dropping them frees, the rest of
/// the replay (its final map sharing their segments) kept. Leaves `replay` without them.
fn checkpoints_alone_bytes(replay: &mut Replay) -> usize {
    let checkpoints = replay.take_checkpoints();
    alloc_count::start_counting();
    drop(checkpoints);
    alloc_count::stop_counting();
    (-alloc_count::counted_bytes()).max(0) as usize
}

/// Loading the saved run `json`, `repeats` times: the seconds of each, and the peak memory
/// counted while loading, bytes.
fn time_loads(json: &str, repeats: usize) -> (Vec<f64>, usize) {
    let mut loads = Vec::new();
    let mut peak = 0usize;
    for _ in 0..repeats.max(1) {
        alloc_count::start_counting();
        let start = Instant::now();
        let loaded = load_run(json.as_bytes(), "bench");
        loads.push(start.elapsed().as_secs_f64());
        alloc_count::stop_counting();
        peak = peak.max(alloc_count::peak_counted_bytes().max(0) as usize);
        drop(loaded);
    }
    (loads, peak)
}

/// Opening the run in the inspector, `repeats` times, milliseconds each: loaded, its first
/// snapshots replayed on the spot, and the first of them made ready to draw (the whole
/// replay then runs on a thread).
fn time_first_frames(json: &str, params: &Params, repeats: usize) -> Vec<f64> {
    let mut first_frames = Vec::new();
    for _ in 0..repeats.max(1) {
        let start = Instant::now();
        let loaded = load_run(json.as_bytes(), "bench").expect("a saved run loads");
        let preview = Replay::new(
            Arc::new(loaded.first_snapshots(PREVIEW_SNAPSHOTS)),
            params.clone(),
        );
        if let Some(view) = preview.view(0) {
            let input = SceneInput::from_view(&loaded, &view);
            std::hint::black_box(build_scene(&input, &ViewOptions::all()));
        }
        first_frames.push(start.elapsed().as_secs_f64() * 1e3);
    }
    first_frames
}

/// The slowest of every segment's lineage, as the inspector lists it (the events and their
/// snapshots), milliseconds.
fn time_lineages(replay: &Replay, n: usize) -> f64 {
    let mut lineage_ms_max: f64 = 0.0;
    for id in 0..replay.final_map().next_segment_id {
        let start = Instant::now();
        let events = replay.lineage().of(id, n - 1);
        let rows: usize = events.iter().map(|e| format!("{e:?}").len()).sum();
        std::hint::black_box(rows);
        lineage_ms_max = lineage_ms_max.max(start.elapsed().as_secs_f64() * 1e3);
    }
    lineage_ms_max
}

/// The timings of the seeks and of drawing what they show, milliseconds.
#[derive(Default)]
struct SeekTimes {
    seeks: Vec<f64>,
    forward_ms_max: f64,
    frames: Vec<f64>,
    reused_frames: Vec<f64>,
    builds: Vec<f64>,
    vertices_max: usize,
    svgs: Vec<f64>,
    svg_bytes_max: usize,
}

/// Seeks to snapshots spread over the run, each the slowest view from its checkpoint (once
/// each: a long early interval takes several of the 20 places); each then stepped forward,
/// drawn in the map view and exported as SVG.
fn time_seeks(run: &Run, replay: &Replay) -> SeekTimes {
    let n = run.snapshots.len();
    let mut targets: Vec<usize> = (0..20)
        .map(|i| replay.slowest_view_like(i * n / 20))
        .collect();
    targets.dedup();
    let mut times = SeekTimes::default();
    for &k in &targets {
        let mut cursor = crate::replay::ReplayCursor::default();
        let start = Instant::now();
        let view = replay
            .view_from(&mut cursor, None, k)
            .expect("non-empty run");
        times.seeks.push(start.elapsed().as_secs_f64() * 1e3);
        let start = Instant::now();
        std::hint::black_box(replay.view_from(&mut cursor, Some(&view), k + 1));
        times.forward_ms_max = times
            .forward_ms_max
            .max(start.elapsed().as_secs_f64() * 1e3);
        let input = SceneInput::from_view(run, &view);
        time_frames(run, &input, &mut times);
        let scene = build_scene(&input, &ViewOptions::all());
        let start = Instant::now();
        let svg = to_svg(
            &scene,
            default_view(&scene),
            (1600, 1000),
            &run.name,
            run.units,
        );
        times.svgs.push(start.elapsed().as_secs_f64() * 1e3);
        times.svg_bytes_max = times.svg_bytes_max.max(svg.len());
    }
    times
}

/// A frame of `input` in the map view, as the inspector draws it after a jump (the view
/// settled on the whole map first: the plot fits itself over a couple of frames): the scene
/// built, the frame drawn, and the frame drawn again from the same scene.
fn time_frames(run: &Run, input: &SceneInput, times: &mut SeekTimes) {
    let mut map_view = HeadlessMapView::new(1600.0, 1000.0);
    for _ in 0..3 {
        let options = ViewOptions {
            world_per_px: map_view.world_per_px(),
            ..ViewOptions::all()
        };
        map_view.frame(&build_scene(input, &options), run.units);
    }
    let options = ViewOptions {
        world_per_px: map_view.world_per_px(),
        ..ViewOptions::all()
    };
    let start = Instant::now();
    let scene = build_scene(input, &options);
    let built = start.elapsed().as_secs_f64() * 1e3;
    let stats = map_view.frame(&scene, run.units);
    times.frames.push(start.elapsed().as_secs_f64() * 1e3);
    let start = Instant::now();
    map_view.frame(&scene, run.units);
    times
        .reused_frames
        .push(start.elapsed().as_secs_f64() * 1e3);
    times.builds.push(built);
    times.vertices_max = times.vertices_max.max(stats.vertices);
}

/// The run plots panel under the timeline, every plot three times, at the run's last
/// snapshot: milliseconds each.
fn time_plots(replay: &Replay, n: usize) -> Vec<f64> {
    let mut plots = crate::app::HeadlessRunPlots::new(1400.0, 170.0);
    let mut plot_frames = Vec::new();
    for plot in crate::app::RunPlot::ALL {
        for _ in 0..3 {
            let start = Instant::now();
            let curves = crate::app::RunCurves {
                summaries: replay.summaries(),
                truth: replay.truth_curve(),
                poses: replay.step_poses(),
            };
            plots.frame(plot, curves, n - 1);
            plot_frames.push(start.elapsed().as_secs_f64() * 1e3);
        }
    }
    plot_frames
}
