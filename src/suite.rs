//! `sonarmap eval --suite N --seed S`: `N` generated scenes of the families
//! ([`crate::sim::SceneKind`], one kind after another), each simulated with both of the
//! project's sensor models ([`Model::Specular`], [`Model::Axis`]), mapped and scored by
//! [`crate::eval`]. The same `N`, `S` and parameters always give the same figures.

use crate::eval::{
    confirmed_map, evaluate, judged_with, map_verdicts, true_point_features, Verdict,
};
use crate::geometry::Pose;
use crate::mapping::{Map, Mapper, Params};
use crate::pose_error::{pose_error, pose_error_of};
use crate::replay::Cancelled;
use crate::run::Run;
use crate::sim::{
    family_plan, simulate_paced, with_odometry, Model, OdometryError, Pace, Plan, SceneKind,
};
use crate::units::Units;
use serde::Serialize;

/// Scene `i` of a suite seeded `seed`: the kinds in turn, seed `seed + i`.
pub fn suite_scene(i: usize, seed: u64) -> (SceneKind, u64) {
    (
        SceneKind::ALL[i % SceneKind::ALL.len()],
        seed.wrapping_add(i as u64),
    )
}

/// The plans of a suite, in order (what `--write-plans` writes, for another simulator).
pub fn suite_plans(scenes: usize, seed: u64) -> Vec<(SceneKind, u64, Plan)> {
    (0..scenes)
        .map(|i| {
            let (kind, s) = suite_scene(i, seed);
            (kind, s, family_plan(kind, s))
        })
        .collect()
}

/// The figures of one map against its floor plan, as a suite line prints them. Lengths in
/// inches.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SceneFigures {
    /// Fitted segments.
    pub segments: usize,
    /// Fitted segments on a wall or pillar.
    pub true_segments: usize,
    /// 1 − true/fitted (0 without segments).
    pub spurious_fraction: f64,
    /// Median over the true segments of their end-points' mean distance to their wall or
    /// pillar, inches (`null` without any).
    pub median_endpoint_error_in: Option<f64>,
    /// Covered wall length over total wall length.
    pub coverage: f64,
    /// Confirmed point features (corners and edges) in the map.
    pub point_features: usize,
    /// Point features on a wall junction or end ([`crate::eval::true_point_features`]).
    pub true_point_features: usize,
    /// The same figures for the confirmed segments alone (docs/algorithm.md §8.7), when
    /// segments must be confirmed.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub confirmed: Option<Box<SceneFigures>>,
}

/// One scene of a suite, one sensor model.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SuiteLine {
    /// The family's short name.
    pub family: &'static str,
    /// The scene's seed.
    pub seed: u64,
    /// `"specular"` or `"axis"`, or the name of the log for a log scored alone.
    pub model: String,
    /// Snapshots mapped.
    pub snapshots: usize,
    /// The figures of the map.
    #[serde(flatten)]
    pub figures: SceneFigures,
    /// How far the poses lay from the truth, when the run keeps it (a drifting run).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pose: Option<PoseFigures>,
}

/// The pose error of a run that keeps its truth: the odometry's, and that of the poses the
/// engine mapped with (the same unless pose correction, docs/algorithm.md §8.17, is on).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct PoseFigures {
    /// RMS distance of the odometry pose from the true pose, metres.
    pub odometry_rms_position_m: f64,
    /// RMS heading error of the odometry, degrees.
    pub odometry_rms_heading_deg: f64,
    /// RMS distance of the mapped pose from the true pose, metres.
    pub mapped_rms_position_m: f64,
    /// RMS heading error of the mapped pose, degrees.
    pub mapped_rms_heading_deg: f64,
}

impl PoseFigures {
    /// The figures of `run` mapped with `mapped_poses` (one per snapshot); none without truth.
    pub fn of(run: &Run, mapped_poses: &[Pose]) -> Option<PoseFigures> {
        let odometry = pose_error(run)?;
        let mapped = pose_error_of(run, mapped_poses.iter().copied())?;
        let m = |length: f64| run.units.to_m(length);
        Some(PoseFigures {
            odometry_rms_position_m: m(odometry.rms_position),
            odometry_rms_heading_deg: odometry.rms_heading_deg,
            mapped_rms_position_m: m(mapped.rms_position),
            mapped_rms_heading_deg: mapped.rms_heading_deg,
        })
    }

    /// The mean of `figures`, none when empty.
    fn mean(figures: &[PoseFigures]) -> Option<PoseFigures> {
        let n = figures.len() as f64;
        let mean = |f: fn(&PoseFigures) -> f64| figures.iter().map(f).sum::<f64>() / n;
        (!figures.is_empty()).then(|| PoseFigures {
            odometry_rms_position_m: mean(|f| f.odometry_rms_position_m),
            odometry_rms_heading_deg: mean(|f| f.odometry_rms_heading_deg),
            mapped_rms_position_m: mean(|f| f.mapped_rms_position_m),
            mapped_rms_heading_deg: mean(|f| f.mapped_rms_heading_deg),
        })
    }
}

/// The figures of a whole suite.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SuiteSummary {
    /// Always `"summary"`.
    pub summary: &'static str,
    /// Runs scored (scenes × models).
    pub runs: usize,
    /// Fitted segments in all maps.
    pub segments: usize,
    /// True segments in all maps.
    pub true_segments: usize,
    /// 1 − true/fitted over all maps.
    pub spurious_fraction: f64,
    /// The largest spurious fraction of one run.
    pub worst_spurious_fraction: f64,
    /// Median of the runs' median end-point errors, inches.
    pub median_endpoint_error_in: Option<f64>,
    /// Mean coverage of the runs.
    pub mean_coverage: f64,
    /// The smallest coverage of one run.
    pub worst_coverage: f64,
    /// Point features in all maps.
    pub point_features: usize,
    /// Point features on a wall junction or end.
    pub true_point_features: usize,
    /// The mean pose error of the runs that keep their truth.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pose: Option<PoseFigures>,
    /// The summary of the confirmed segments alone, when segments must be confirmed.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub confirmed: Option<Box<SuiteSummary>>,
    /// The ξ the end-points were judged with, when `eval --score-accuracy-pct` set it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub score_accuracy_pct: Option<f64>,
}

fn median(mut v: Vec<f64>) -> Option<f64> {
    if v.is_empty() {
        return None;
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    Some(if n % 2 == 1 {
        v[n / 2]
    } else {
        (v[n / 2 - 1] + v[n / 2]) / 2.0
    })
}

/// Maps `run` with `params` (trace off) and returns the final map.
pub fn map_of(run: &Run, params: &Params) -> Map {
    map_and_poses_of(run, params).0
}

/// [`map_of`], with the pose each step mapped with (corrected, with pose correction); with
/// `calibrate_first`, a second pass when the first found a drift
/// ([`Mapper::second_pass_params`]).
pub fn map_and_poses_of(run: &Run, params: &Params) -> (Map, Vec<Pose>) {
    let one_pass = |params: &Params| {
        let mut mapper =
            Mapper::new(params.clone(), run.layout.clone(), run.sensor).with_trace(false);
        let poses: Vec<Pose> = run
            .snapshots
            .iter()
            .filter_map(|s| mapper.step(s).pose)
            .collect();
        (mapper, poses)
    };
    let (mapper, poses) = one_pass(params);
    let (mapper, poses) = match mapper.second_pass_params() {
        Some(calibrated) => one_pass(&calibrated),
        None => (mapper, poses),
    };
    (mapper.map().clone(), poses)
}

/// The suite figures of `map` against `run`'s floor plan (none without one).
pub fn scene_figures(map: &Map, run: &Run, params: &Params) -> Option<SceneFigures> {
    let plan = run.floor_plan.as_ref()?;
    let confirmed = confirmed_map(map)
        .and_then(|m| scene_figures(&m, run, params))
        .map(|mut f| {
            // The confirmed map holds the segments alone; the features are the map's.
            f.point_features = map.confirmed_features().count();
            f.true_point_features = true_point_features(map, plan, params);
            Box::new(f)
        });
    let report = evaluate(map, run, plan, params);
    let errors: Vec<f64> = map_verdicts(map, plan, params)
        .into_iter()
        .filter_map(|(_, v)| match v {
            Verdict::OnWall {
                endpoint_error_m, ..
            }
            | Verdict::OnPillar {
                endpoint_error_m, ..
            } => Some(Units::Inches.from_m(endpoint_error_m)),
            Verdict::Spurious => None,
        })
        .collect();
    Some(SceneFigures {
        segments: report.segments,
        true_segments: report.true_segments,
        spurious_fraction: report.spurious_fraction,
        median_endpoint_error_in: median(errors),
        coverage: report.coverage,
        point_features: map.confirmed_features().count(),
        true_point_features: true_point_features(map, plan, params),
        confirmed,
    })
}

/// The lines of a suite: scene by scene, the specular model then the axis model.
pub fn run_suite(scenes: usize, seed: u64, params: &Params) -> Vec<SuiteLine> {
    run_suite_drifting(scenes, seed, params, None)
}

/// `run` given the odometry error `drift` (seeded with `seed`), or as it is without one.
pub fn drifted(run: Run, drift: Option<&OdometryError>, seed: u64) -> Run {
    match drift {
        None => run,
        Some(error) => with_odometry(&run, error, seed),
    }
}

/// [`run_suite`] with every run given the odometry error `drift` (seeded by its scene's seed),
/// scored against the floor plan in the true frame.
pub fn run_suite_drifting(
    scenes: usize,
    seed: u64,
    params: &Params,
    drift: Option<&OdometryError>,
) -> Vec<SuiteLine> {
    let conditions = Conditions {
        drift: drift.copied(),
        ..Conditions::PLAIN
    };
    run_suite_with(scenes, seed, params, &conditions, None, &mut |_| true).expect("never cancelled")
}

/// How a suite's runs are driven: the odometry's error and the robot's pace and firing order.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Conditions {
    /// The odometry error given to every run (seeded by its scene's seed), if any.
    pub drift: Option<OdometryError>,
    /// The pace and firing order every run is simulated at.
    pub pace: Pace,
    /// The mirror bounces of every run's echoes (`sim.bounces`), instead of its plan's.
    pub bounces: Option<u32>,
}

impl Conditions {
    /// `plan` with these conditions' bounces, when they set them.
    pub fn simulated(&self, mut plan: Plan) -> Plan {
        if let Some(bounces) = self.bounces {
            plan.sim.bounces = bounces;
        }
        plan
    }

    /// The plans' own paths, the ring fired at once, the odometry the truth.
    pub const PLAIN: Conditions = Conditions {
        drift: None,
        pace: Pace::PLAN,
        bounces: None,
    };
}

/// [`run_suite`] under `conditions`, calling `progress(runs)` after every run (a scene in one
/// model); returning `false` cancels.
pub fn run_suite_with(
    scenes: usize,
    seed: u64,
    params: &Params,
    conditions: &Conditions,
    score_accuracy_pct: Option<f64>,
    progress: &mut dyn FnMut(usize) -> bool,
) -> Result<Vec<SuiteLine>, Cancelled> {
    let judged = judged_with(params, score_accuracy_pct);
    let mut lines = Vec::with_capacity(2 * scenes);
    for (kind, s, plan) in suite_plans(scenes, seed) {
        let plan = conditions.simulated(plan);
        for (model, name) in [(Model::Specular, "specular"), (Model::Axis, "axis")] {
            let run = simulate_paced(&plan, model, s, &conditions.pace);
            let run = drifted(run, conditions.drift.as_ref(), s);
            let (map, poses) = map_and_poses_of(&run, params);
            let figures = scene_figures(&map, &run, &judged).expect("a family plan has walls");
            lines.push(SuiteLine {
                family: kind.name(),
                seed: s,
                model: name.to_string(),
                snapshots: run.snapshots.len(),
                figures,
                pose: PoseFigures::of(&run, &poses),
            });
            if !progress(lines.len()) {
                return Err(Cancelled);
            }
        }
    }
    Ok(lines)
}

/// The summary of `lines`.
pub fn summarise(lines: &[SuiteLine]) -> SuiteSummary {
    let confirmed: Vec<SuiteLine> = lines
        .iter()
        .filter_map(|l| {
            l.figures.confirmed.as_ref().map(|c| SuiteLine {
                figures: (**c).clone(),
                model: l.model.clone(),
                pose: None,
                ..*l
            })
        })
        .collect();
    let segments: usize = lines.iter().map(|l| l.figures.segments).sum();
    let true_segments: usize = lines.iter().map(|l| l.figures.true_segments).sum();
    let n = lines.len().max(1) as f64;
    SuiteSummary {
        summary: "summary",
        runs: lines.len(),
        segments,
        true_segments,
        spurious_fraction: if segments == 0 {
            0.0
        } else {
            1.0 - true_segments as f64 / segments as f64
        },
        worst_spurious_fraction: lines
            .iter()
            .map(|l| l.figures.spurious_fraction)
            .fold(0.0, f64::max),
        median_endpoint_error_in: median(
            lines
                .iter()
                .filter_map(|l| l.figures.median_endpoint_error_in)
                .collect(),
        ),
        mean_coverage: lines.iter().map(|l| l.figures.coverage).sum::<f64>() / n,
        worst_coverage: lines
            .iter()
            .map(|l| l.figures.coverage)
            .fold(f64::INFINITY, f64::min)
            .min(1.0),
        point_features: lines.iter().map(|l| l.figures.point_features).sum(),
        true_point_features: lines.iter().map(|l| l.figures.true_point_features).sum(),
        pose: PoseFigures::mean(&lines.iter().filter_map(|l| l.pose).collect::<Vec<_>>()),
        confirmed: (!confirmed.is_empty()).then(|| Box::new(summarise(&confirmed))),
        score_accuracy_pct: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median_of_odd_and_even_counts() {
        assert_eq!(median(vec![3.0, 1.0, 2.0]), Some(2.0));
        assert_eq!(median(vec![4.0, 1.0, 2.0, 3.0]), Some(2.5));
        assert_eq!(median(Vec::new()), None);
    }

    #[test]
    fn scenes_take_the_kinds_in_turn() {
        assert_eq!(suite_scene(0, 5), (SceneKind::Room, 5));
        assert_eq!(suite_scene(7, 5), (SceneKind::LRoom, 12));
    }
}
