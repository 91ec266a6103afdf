//! Standard-harness benchmarks (divan) of the paths `sonarmap bench` reports: the engine step,
//! candidate search, loading, seeking and scene building. `cargo bench` runs them; inputs are a
//! generated building floor driven back and forth, made once.

use sonarmap::bench::building_run;
use sonarmap::geometry::Point;
use sonarmap::log::{load_run, save_run};
use sonarmap::mapping::{Map, Mapper, Params};
use sonarmap::replay::Replay;
use sonarmap::run::Run;
use sonarmap::scene::{build_scene, SceneInput, ViewOptions};
use std::sync::{Arc, LazyLock};

/// Snapshots of the benchmark run: long enough for the map to be revisited many times.
const SNAPSHOTS: usize = 10_000;

static RUN: LazyLock<Arc<Run>> = LazyLock::new(|| Arc::new(building_run(SNAPSHOTS, 1)));

fn params(merge: bool) -> Params {
    Params {
        merge_duplicates: merge,
        ..Params::paper()
    }
}

/// The mapper after the whole run (for search and single steps on a grown map).
fn mapped(merge: bool) -> Mapper {
    let mut mapper = Mapper::new(params(merge), RUN.layout.clone(), RUN.sensor).with_trace(false);
    for s in &RUN.snapshots {
        mapper.step(s);
    }
    mapper
}

static MAPPED: LazyLock<[Mapper; 2]> = LazyLock::new(|| [mapped(false), mapped(true)]);
static JSON: LazyLock<String> = LazyLock::new(|| save_run(&RUN));
static REPLAY: LazyLock<Replay> = LazyLock::new(|| Replay::new(RUN.clone(), Params::paper()));

fn main() {
    divan::main();
}

/// One snapshot stepped on the map of the whole run (the last snapshots again, in turn), with
/// the trace off or on, with and without `merge_duplicates`.
#[divan::bench(args = [(false, false), (true, false), (false, true), (true, true)])]
fn engine_step(bencher: divan::Bencher, (trace, merge): (bool, bool)) {
    let mut mapper = MAPPED[usize::from(merge)].clone().with_trace(trace);
    let tail = &RUN.snapshots[SNAPSHOTS - 500..];
    let mut k = 0;
    bencher.bench_local(|| {
        k = (k + 1) % tail.len();
        divan::black_box(mapper.step(&tail[k]))
    });
}

/// The whole run, snapshot by snapshot, from an empty map (trace off).
#[divan::bench(sample_count = 5, args = [false, true])]
fn engine_run(merge: bool) -> usize {
    mapped(merge).map().segments.len()
}

/// Index query around points along the robot's path, on the map of the whole run.
#[divan::bench(args = [false, true])]
fn candidate_search(bencher: divan::Bencher, merge: bool) {
    let map: &Map = MAPPED[usize::from(merge)].map();
    let probes: Vec<Point> = RUN
        .snapshots
        .iter()
        .step_by(97)
        .map(|s| Point::new(s.pose.x, s.pose.y))
        .collect();
    let mut out = Vec::new();
    let mut k = 0;
    bencher.bench_local(|| {
        k = (k + 1) % probes.len();
        map.segments_near_into(&probes[k], 1.5, &mut out);
        divan::black_box(out.len())
    });
}

/// Parsing and validating the run's JSON.
#[divan::bench(sample_count = 10)]
fn load(bencher: divan::Bencher) {
    let json = JSON.as_bytes();
    bencher
        .counter(divan::counter::BytesCount::new(json.len()))
        .bench(|| load_run(json, "bench").expect("valid"));
}

/// Making snapshot `k` ready to draw, `k` just before a checkpoint (the longest replay).
#[divan::bench(sample_count = 20)]
fn seek(bencher: divan::Bencher) {
    let replay = &*REPLAY;
    let interval = replay.checkpoint_interval();
    let targets: Vec<usize> = (1..10)
        .map(|i| (i * SNAPSHOTS / 10) / interval * interval + interval - 1)
        .collect();
    let mut k = 0;
    bencher.bench_local(|| {
        k = (k + 1) % targets.len();
        replay.view(targets[k]).expect("in the run")
    });
}

/// The display list of the last snapshot, every layer on, no level-of-detail culling.
#[divan::bench(sample_count = 20)]
fn scene_build(bencher: divan::Bencher) {
    let view = REPLAY.view(SNAPSHOTS - 1).expect("in the run");
    let input = SceneInput::from_view(&RUN, &view);
    bencher.bench(|| build_scene(&input, &ViewOptions::all()));
}
