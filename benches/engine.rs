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

/// Snapshots stepped per sample of `engine_step`: enough to average over the kinds of snapshot
/// (a single step costs from well under a microsecond to tens of them).
const STEPPED: usize = 200;

/// The run's last [`STEPPED`] snapshots stepped again on a copy of the map of the whole run
/// (each sample starts from the same map), with the trace off or on, with and without
/// `merge_duplicates`; the throughput counts snapshots.
#[divan::bench(args = [(false, false), (true, false), (false, true), (true, true)])]
fn engine_step(bencher: divan::Bencher, (trace, merge): (bool, bool)) {
    let tail = &RUN.snapshots[SNAPSHOTS - STEPPED..];
    bencher
        .counter(divan::counter::ItemsCount::new(tail.len()))
        .with_inputs(|| MAPPED[usize::from(merge)].clone().with_trace(trace))
        .bench_local_values(|mut mapper| {
            for s in tail {
                divan::black_box(mapper.step(s));
            }
            mapper
        });
}

/// The whole run, snapshot by snapshot, from an empty map (trace off).
#[divan::bench(sample_count = 5, args = [false, true])]
fn engine_run(merge: bool) -> usize {
    mapped(merge).map().segments.len()
}

/// Index queries around points along the robot's path (all of them each sample), on the map of
/// the whole run; the throughput counts queries.
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
    bencher
        .counter(divan::counter::ItemsCount::new(probes.len()))
        .bench_local(|| {
            let mut found = 0;
            for p in &probes {
                map.segments_near_into(p, 1.5, &mut out);
                found += out.len();
            }
            divan::black_box(found)
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
    let targets: Vec<usize> = (1..10)
        .map(|i| replay.slowest_view_like(i * SNAPSHOTS / 10))
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
