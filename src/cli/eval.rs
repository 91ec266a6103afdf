//! `sonarmap eval`: the map of a log compared with its floor plan (or, with `--suite`, the
//! generated scenes scored, [`super::suite`]).

use super::input::{read, read_run};
use super::map_run::map_run;
use super::output::emit;
use super::params::{read_params_and_preset, ParamArgs};
use super::suite::{suite_command, SuiteArgs};
use anyhow::{anyhow, Context, Result};
use clap::Args;
use sonarmap::alignment::Search;
use sonarmap::eval::{evaluate, evaluate_aligned, EvalReport};
use sonarmap::mapping::{Params, Preset};
use sonarmap::sim::load_plan;
use std::path::PathBuf;

/// The long help of `sonarmap eval`: what each figure means.
pub const EVAL_HELP: &str = "Compare the map of a log with its floor plan; prints one JSON object.

Only fitted segments count. The tolerance of an end-point with range D is the sonar resolution xi*D/100 (xi = the accuracy_pct parameter), at least 1 in.
  segments             fitted segments in the map
  true_segments        segments whose two end-points lie within their tolerance of one wall and whose angle to it is at most theta_o (orientation_deg), or whose end-points lie within tolerance of one pillar
  spurious_fraction    1 - true_segments / segments
  mean_endpoint_error  mean distance of true segments' end-points to their wall or pillar, in the log's units
  mean_angle_error_deg mean angle between true segments and their walls
  coverage             length of the walls covered by true segments (union of their end-points projected on their wall) over the total wall length
  coverage_visible     covered length inside the visible part of the walls over the visible length. A wall is visible around each kept reading (an echo below max_range, within [min_range, d_max]) whose beam-axis point is within its tolerance of the wall: +- the tolerance around the projection, and marks no more than t_gap apart along the wall are joined.
  coverage_near_path   covered length of the walls within 1.5 m of the robot's path (the snapshots' poses) over that length (near_path_length)
  wall_length, visible_length, covered_length, near_path_length  in the log's units";

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
    /// With --suite: give each scene's run (and each log from --logs-from) the odometry of a
    /// differential-drive robot, as `simulate --drift` does, seeded by the scene's seed; the
    /// maps are scored against the floor plan, in the true frame.
    #[arg(long, value_enum, default_value = "none", requires = "suite")]
    pub drift: super::simulate::DriftArg,
    /// With --suite: the pace and firing order every scene is simulated at, and its echoes'
    /// bounces.
    #[command(flatten)]
    pub pace: super::simulate::PaceArgs,
    /// Mapping parameters.
    #[command(flatten)]
    pub params: ParamArgs,
    /// Floor plan to compare with (default: the log's own `floor_plan`).
    #[arg(long, value_name = "PLAN.json")]
    pub plan: Option<PathBuf>,
    /// Score the map after the rigid transform that best lays it on the floor plan (a real run
    /// whose odometry turned it, or whose plan sits in another frame); the transform and the
    /// rotations that align the run's first and last quarters are printed as `alignment`.
    /// `near` (the default) looks within 15° of the plan's frame, `anywhere` over the whole turn.
    #[arg(long, value_enum, value_name = "SEARCH", num_args = 0..=1, default_missing_value = "near", conflicts_with = "suite")]
    pub align: Option<AlignArg>,
    /// Judge the map's end-points within `max(1 in, P % of their range)` of a wall instead of
    /// the mapping's own ξ (`accuracy_pct`): one yardstick for maps made with different ξ, as a
    /// real run is scored (issue 40 uses 3). With --suite, every scene's maps.
    #[arg(long, value_name = "P", value_parser = positive_pct)]
    pub score_accuracy_pct: Option<f64>,
}

/// A percentage greater than 0 and at most 100.
fn positive_pct(text: &str) -> std::result::Result<f64, String> {
    let value: f64 = text.parse().map_err(|e| format!("{e}"))?;
    if value.is_finite() && value > 0.0 && value <= 100.0 {
        Ok(value)
    } else {
        Err(format!("{value} is not a percentage in (0, 100]"))
    }
}

/// Where `eval --align` looks for the transform.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum AlignArg {
    /// Within 15° of the plan's own frame: a plan drawn in roughly the map's frame.
    Near,
    /// Over the whole turn: a plan in any frame.
    Anywhere,
}

/// The figures `eval` prints, with what produced them.
#[derive(Debug, serde::Serialize)]
struct EvalOutput {
    log: String,
    preset: &'static str,
    snapshots: usize,
    #[serde(flatten)]
    report: EvalReport,
    /// The pose error of the poses the engine used (corrected by §8.17), when the log has the
    /// truth and the poses were corrected.
    #[serde(skip_serializing_if = "Option::is_none")]
    corrected_pose_error: Option<sonarmap::pose_error::PoseError>,
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
    /// With `calibrate_first`, the drift the first pass found (`null` when none).
    #[serde(skip_serializing_if = "Option::is_none")]
    calibration: Option<Option<Calibration>>,
    /// The tolerance the end-points were judged with, when `--score-accuracy-pct` set it.
    #[serde(skip_serializing_if = "Option::is_none")]
    score_accuracy_pct: Option<f64>,
}

/// The odometry's drift a first pass found (`calibrate_first`).
#[derive(Debug, serde::Serialize)]
struct Calibration {
    drift_deg_per_m: f64,
    drift_per_turn_pct: f64,
    /// The snapshots the first pass's smoothed heading errors cover (0: the drift alone).
    heading_track_snapshots: usize,
    /// Whether the second pass corrects the pose against the map (`pose_correction`, set or
    /// switched on by `revisit_laps`).
    pose_correction: bool,
}

impl Calibration {
    /// The calibration `params` carry, if any.
    fn of(params: &Params) -> Option<Self> {
        params
            .drift_calibration()
            .map(|(drift_deg_per_m, drift_per_turn_pct)| Calibration {
                drift_deg_per_m,
                drift_per_turn_pct,
                heading_track_snapshots: params.heading_track.as_ref().map_or(0, |t| t.len()),
                pose_correction: params.pose_correction,
            })
    }
}

/// Runs `sonarmap eval`.
pub fn eval_command(args: &EvalArgs) -> Result<()> {
    let (params, preset) = read_params_and_preset(&args.params)?;
    let Some(log) = &args.log else {
        let suite = SuiteArgs {
            scenes: args.suite.unwrap_or(0),
            seed: args.seed,
            write_plans: args.write_plans.as_deref(),
            logs_from: args.logs_from.as_deref(),
            conditions: sonarmap::suite::Conditions {
                drift: args.drift.error(),
                pace: args.pace.pace()?,
                bounces: args.pace.bounces,
            },
            score_accuracy_pct: args.score_accuracy_pct,
        };
        return suite_command(&suite, &params);
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
    let (mut mapper, _, mut summary) =
        map_run(&run, params.clone(), None, false).with_context(|| log.display().to_string())?;
    if let Some(calibrated) = mapper.second_pass_params() {
        (mapper, _, summary) =
            map_run(&run, calibrated, None, false).with_context(|| log.display().to_string())?;
    }
    let params = mapper.params().clone();
    if let Some(warning) = summary.min_range_warning(&run, &params) {
        eprintln!("warning: {warning}");
    }
    let map = mapper.map();
    let judged = sonarmap::eval::judged_with(&params, args.score_accuracy_pct);
    let score = |m: &sonarmap::mapping::Map| match args.align {
        Some(AlignArg::Near) => evaluate_aligned(m, &run, &floor_plan, &judged, Search::Near(None)),
        Some(AlignArg::Anywhere) => {
            evaluate_aligned(m, &run, &floor_plan, &judged, Search::Anywhere)
        }
        None => evaluate(m, &run, &floor_plan, &judged),
    };
    let report = score(map);
    // Point features are judged against the plan the whole map was scored on.
    let scored_plan = match &report.alignment {
        Some(a) => a.whole.plan_in_map_frame(&floor_plan),
        None => floor_plan.clone(),
    };
    let features = map.confirmed_features().count();
    let has_features = features > 0;
    let out = EvalOutput {
        log: log.display().to_string(),
        preset: match preset {
            Preset::Paper => "paper",
            Preset::Extended => "extended",
        },
        snapshots: summary.snapshots,
        report,
        corrected_pose_error: params
            .corrects_pose()
            .then(|| sonarmap::pose_error::pose_error_of(&run, summary.poses.iter().copied()))
            .flatten(),
        point_features: has_features.then_some(features),
        true_point_features: has_features
            .then(|| sonarmap::eval::true_point_features(map, &scored_plan, &judged)),
        confirmed: sonarmap::eval::confirmed_map(map).map(|m| score(&m)),
        calibration: params.calibrate_first.then(|| Calibration::of(&params)),
        score_accuracy_pct: args.score_accuracy_pct,
    };
    emit(&serde_json::to_string_pretty(&out)?)?;
    Ok(())
}
