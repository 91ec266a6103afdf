//! The golden corpus: the maps and traces of a fixed set of runs, under both presets and the
//! paper with each extension alone, hashed and compared with
//! `tests/golden/digests.txt`. A restructuring of the engine keeps every digest; a change of
//! behaviour changes some, and re-blessing them (`SONARMAP_BLESS_GOLDEN=1 cargo test golden`)
//! is then a decision the commit states.
//!
//! Each run is stepped twice: traced (every step's full trace and the final map are hashed) and
//! slim (the slim traces and the map). Then the replay's catch-up path
//! ([`Replay::view`], which takes recorded decisions from a checkpoint) is hashed at the run's
//! middle snapshot for the presets.

use super::support::first_pass;
use sonarmap::import::{builtin_layout, import_any, ImportOptions};
use sonarmap::log::{load_run, save_map};
use sonarmap::mapping::{Mapper, Params};
use sonarmap::replay::Replay;
use sonarmap::run::Run;
use sonarmap::sim::{
    family_plan, load_plan, repeat_laps, simulate, Model, OdometryError, Pace, SceneKind,
};
use sonarmap::soak::family_run_under;
use sonarmap::suite::Conditions;
use sonarmap::units::Units;
use std::collections::BTreeMap;
use std::io::Write;
use std::path::PathBuf;
use std::sync::Arc;

/// FNV-1a, 64 bits: a stable hash of the bytes written (the standard library's hasher may
/// change between releases).
struct Fnv(u64);

impl Fnv {
    fn new() -> Self {
        Fnv(0xcbf2_9ce4_8422_2325)
    }
}

impl Write for Fnv {
    fn write(&mut self, bytes: &[u8]) -> std::io::Result<usize> {
        for &b in bytes {
            self.0 ^= u64::from(b);
            self.0 = self.0.wrapping_mul(0x0000_0100_0000_01b3);
        }
        Ok(bytes.len())
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

/// The digest of `run` mapped with `params`: every step's trace (full or slim) and the map.
fn mapped_digest(run: &Run, params: &Params, traced: bool) -> u64 {
    let mut mapper = Mapper::new(params.clone(), run.layout.clone(), run.sensor).with_trace(traced);
    let mut h = Fnv::new();
    for snapshot in &run.snapshots {
        let trace = mapper.step(snapshot);
        serde_json::to_writer(&mut h, &trace).unwrap();
    }
    let last = run.snapshots.len().saturating_sub(1);
    h.write_all(save_map(mapper.map(), Units::Metres, last).as_bytes())
        .unwrap();
    h.0
}

/// The digest of the replay's view of the middle snapshot (checkpoints every 16 snapshots, so
/// that the view catches up through recorded decisions).
fn replay_digest(run: &Run, params: &Params) -> u64 {
    let replay = Replay::build(Arc::new(run.clone()), params.clone(), 16, &mut |_| true)
        .expect("not cancelled");
    let mut h = Fnv::new();
    if let Some(view) = replay.view(run.snapshots.len() / 2) {
        serde_json::to_writer(&mut h, &view.trace).unwrap();
        serde_json::to_writer(&mut h, &view.previous).unwrap();
        let k = view.index;
        h.write_all(save_map(&view.map_before, Units::Metres, k).as_bytes())
            .unwrap();
        h.write_all(save_map(&view.map_after, Units::Metres, k).as_bytes())
            .unwrap();
    }
    h.0
}

fn repo_path(relative: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(relative)
}

fn read(relative: &str) -> Vec<u8> {
    std::fs::read(repo_path(relative)).unwrap_or_else(|e| panic!("{relative}: {e}"))
}

/// The shipped logs and the fixtures of other formats and layouts (Player, a Nomad table).
fn recorded_runs() -> Vec<(String, Run)> {
    let mut runs: Vec<(String, Run)> = ["blue_room", "building", "tight_room"]
        .iter()
        .map(|name| {
            let file = format!("assets/{name}.log.json");
            (name.to_string(), load_run(&read(&file), &file).unwrap())
        })
        .collect();
    for fixture in ["pioneer_tiny.player2.log", "nomad_tiny.table.csv"] {
        let file = format!("tests/fixtures/{fixture}");
        let table = fixture.starts_with("nomad");
        let options = ImportOptions {
            layout: table.then(|| builtin_layout("nomad_200").unwrap()),
            units: table.then_some(Units::Inches),
            ..ImportOptions::default()
        };
        let imported = import_any(&read(&file), &file, &options).unwrap();
        runs.push((fixture.to_string(), imported.run));
    }
    runs
}

/// Simulated runs of the shipped plans and the fixture corridor (both sensor models), and the
/// generated families as lap runs that revisit their walls.
fn simulated_runs(lap_snapshots: usize) -> Vec<(String, Run)> {
    let mut runs = Vec::new();
    for plan_file in [
        "assets/blue_room.plan.json",
        "assets/tight_room.plan.json",
        "tests/fixtures/corridor_three_doors.plan.json",
    ] {
        let plan = load_plan(&read(plan_file), plan_file).unwrap();
        for (model, name) in [(Model::Specular, "specular"), (Model::Axis, "axis")] {
            let run = repeat_laps(&simulate(&plan, model, 7), lap_snapshots);
            runs.push((format!("{plan_file}:{name}"), run));
        }
    }
    for kind in SceneKind::ALL {
        for seed in [1u64, 2] {
            let plan = family_plan(kind, seed);
            let model = if seed == 1 {
                Model::Axis
            } else {
                Model::Specular
            };
            let run = repeat_laps(&simulate(&plan, model, seed), lap_snapshots);
            runs.push((format!("{}:{seed}", kind.name()), run));
        }
    }
    runs
}

/// The parameter sets of the corpus: both presets, then the paper with each extension (and what
/// it needs). Frozen here, apart from the soak's list, so that a change to that list cannot
/// change what the digests mean.
fn golden_variants() -> Vec<(&'static str, Params)> {
    let paper = Params::paper();
    let extended = Params::extended();
    vec![
        ("paper", paper.clone()),
        ("extended", extended.clone()),
        (
            "paper+memory",
            Params {
                memory_snapshots: extended.memory_snapshots,
                ..paper.clone()
            },
        ),
        (
            "paper+constant_depth",
            Params {
                constant_depth: true,
                ..paper.clone()
            },
        ),
        (
            "paper+merge_duplicates",
            Params {
                merge_duplicates: true,
                ..paper.clone()
            },
        ),
        (
            "paper+support_cap",
            Params {
                support_cap: extended.support_cap,
                ..paper.clone()
            },
        ),
        (
            "paper+corner_guard",
            Params {
                corner_guard: true,
                ..paper.clone()
            },
        ),
        (
            "paper+arc_features",
            Params {
                arc_features: true,
                ..paper.clone()
            },
        ),
        (
            "paper+explain_readings",
            Params {
                arc_features: true,
                explain_readings: true,
                ..paper.clone()
            },
        ),
        (
            "paper+free_space",
            Params {
                free_space: true,
                ..paper.clone()
            },
        ),
        (
            "paper+confirm_segments",
            Params {
                confirm_segments: true,
                ..paper.clone()
            },
        ),
        (
            // Confirms point memory's pieces: memory and confirmation come along.
            "paper+baseline_confirm",
            Params {
                memory_snapshots: extended.memory_snapshots,
                confirm_segments: true,
                baseline_confirm: true,
                ..paper.clone()
            },
        ),
        (
            // Only confirmed segments lose their confirmation: confirmation comes along.
            "paper+refit_unconfirms",
            Params {
                confirm_segments: true,
                refit_unconfirms: true,
                ..paper.clone()
            },
        ),
        (
            "paper+plane_gate",
            Params {
                plane_gate: true,
                ..paper.clone()
            },
        ),
        (
            "paper+echo_fit",
            Params {
                echo_fit: true,
                ..paper.clone()
            },
        ),
        (
            // Diagonals are found against confirmed walls: confirmation comes along.
            "paper+corner_diagonals",
            Params {
                confirm_segments: true,
                corner_diagonals: true,
                round_reflectors: true,
                ..paper.clone()
            },
        ),
        (
            // Settling needs confirmed walls: confirmation comes along.
            "paper+settled_walls",
            Params {
                confirm_segments: true,
                settled_walls: true,
                ..paper.clone()
            },
        ),
        (
            // Stacks are point memory's pieces: memory comes along.
            "paper+memory_stacks",
            Params {
                memory_snapshots: extended.memory_snapshots,
                memory_stacks: true,
                ..paper.clone()
            },
        ),
        (
            // Joints are point memory's readings: memory comes along.
            "paper+memory_joints",
            Params {
                memory_snapshots: extended.memory_snapshots,
                memory_joints: true,
                ..paper.clone()
            },
        ),
        (
            "paper+min_piece_points",
            Params {
                min_piece_points: extended.min_piece_points,
                ..paper
            },
        ),
    ]
}

/// Every digest of `runs`: `name variant` to `traced slim [replay]`.
fn digests(runs: &[(String, Run)]) -> BTreeMap<String, String> {
    let mut out = BTreeMap::new();
    for (name, run) in runs {
        for (variant, params) in golden_variants() {
            let mut line = format!(
                "{:016x} {:016x}",
                mapped_digest(run, &params, true),
                mapped_digest(run, &params, false)
            );
            if variant == "paper" || variant == "extended" {
                line += &format!(" {:016x}", replay_digest(run, &params));
            }
            out.insert(format!("{name} {variant}"), line);
        }
    }
    out
}

const DIGESTS_FILE: &str = "tests/golden/digests.txt";

/// The committed digests of group `group`.
fn committed(group: &str) -> BTreeMap<String, String> {
    let text = std::fs::read_to_string(repo_path(DIGESTS_FILE)).unwrap_or_default();
    text.lines()
        .filter_map(|l| l.strip_prefix(group)?.strip_prefix(' '))
        .filter_map(|l| {
            let (key, value) = l.split_once(" = ")?;
            Some((key.to_string(), value.to_string()))
        })
        .collect()
}

/// Compares the digests of `group` with the committed ones, or (blessing) writes them.
fn check_group(group: &str, now: BTreeMap<String, String>) {
    if std::env::var_os("SONARMAP_BLESS_GOLDEN").is_some() {
        bless(group, &now);
        return;
    }
    let before = committed(group);
    assert!(
        !before.is_empty(),
        "no digests for {group} in {DIGESTS_FILE}: bless them"
    );
    let changed: Vec<String> = now
        .iter()
        .filter(|(k, v)| before.get(*k) != Some(v))
        .map(|(k, v)| format!("{k}: {} -> {v}", before.get(k).map_or("(none)", |s| s)))
        .chain(
            before
                .keys()
                .filter(|k| !now.contains_key(*k))
                .map(|k| format!("{k}: gone")),
        )
        .collect();
    assert!(
        changed.is_empty(),
        "{} of {} golden digests of {group} changed:\n{}",
        changed.len(),
        now.len(),
        changed.join("\n")
    );
}

/// Rewrites `group`'s lines of the digests file, keeping the other groups'.
fn bless(group: &str, now: &BTreeMap<String, String>) {
    static LOCK: std::sync::Mutex<()> = std::sync::Mutex::new(());
    let _guard = LOCK.lock().unwrap();
    let path = repo_path(DIGESTS_FILE);
    let text = std::fs::read_to_string(&path).unwrap_or_default();
    let prefix = format!("{group} ");
    let mut lines: Vec<String> = text
        .lines()
        .filter(|l| !l.starts_with(&prefix) && !l.is_empty())
        .map(str::to_string)
        .collect();
    lines.extend(now.iter().map(|(k, v)| format!("{group} {k} = {v}")));
    lines.sort();
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    std::fs::write(&path, lines.join("\n") + "\n").unwrap();
}

#[test]
fn golden_recorded_runs_keep_their_maps_and_traces() {
    check_group("recorded", digests(&recorded_runs()));
}

#[test]
fn golden_simulated_plans_keep_their_maps_and_traces() {
    let runs = simulated_runs(120);
    check_group("plans", digests(&runs[..6]));
}

#[test]
fn golden_family_laps_keep_their_maps_and_traces() {
    let runs = simulated_runs(120);
    check_group("families", digests(&runs[6..]));
}

/// Without drift, `extended`'s heading correction should never act (docs/algorithm.md §8.17):
/// every golden run maps with its odometry's poses. (The short `l-room:2` lap, specular,
/// latched falsely until §8.18 cut its overruns: its first confirmed walls gave an axis about
/// 3° off the room's.) Its axis still serves `off_axis_square_on` (§8.7).
#[test]
fn golden_runs_map_with_their_odometry_under_the_heading_correction() {
    let mut runs = recorded_runs();
    runs.extend(simulated_runs(120));
    let changed: Vec<&str> = runs
        .iter()
        .filter(|(_, run)| {
            let (_, poses) = sonarmap::suite::map_and_poses_of(run, &Params::extended());
            let odometry: Vec<_> = run.snapshots.iter().map(|s| s.pose).collect();
            poses != odometry
        })
        .map(|(name, _)| name.as_str())
        .collect();
    assert_eq!(changed, Vec::<&str>::new());
}

/// Drifting runs that come back to their walls: `extended`'s first pass (the heading alone),
/// its second pass (the pose corrected from calibrated odometry, docs/algorithm.md §8.17,
/// "runs that come back"), and `pose_correction` from the first step.
fn drifting_digests() -> BTreeMap<String, String> {
    let mut out = BTreeMap::new();
    for (kind, seed, drift) in [
        (SceneKind::Room, 1, OdometryError::BAD),
        (SceneKind::CorridorWithDoors, 2, OdometryError::MILD),
    ] {
        let conditions = Conditions {
            drift: Some(drift),
            pace: Pace::PLAN,
            bounces: None,
        };
        let run = family_run_under(kind, seed, 1500, &conditions);
        let extended = Params::extended();
        let second = first_pass(&run, extended.clone())
            .second_pass_params()
            .expect("the drift is found and the run comes back");
        assert!(second.pose_correction, "{}: corrected", kind.name());
        let from_first_step = Params {
            pose_correction: true,
            calibrate_first: false,
            ..extended.clone()
        };
        for (variant, params) in [
            ("extended", extended),
            ("extended second pass", second),
            ("extended+pose_correction", from_first_step),
        ] {
            let line = format!(
                "{:016x} {:016x}",
                mapped_digest(&run, &params, true),
                mapped_digest(&run, &params, false)
            );
            out.insert(format!("{}:{seed} {variant}", kind.name()), line);
        }
    }
    out
}

#[test]
fn golden_drifting_runs_that_come_back_keep_their_maps_and_traces() {
    check_group("drifting", drifting_digests());
}
