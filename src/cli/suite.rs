//! `sonarmap eval --suite N`: generated family scenes scored ([`sonarmap::suite`]).

use super::input::read_run;
use super::interrupt::Interrupted;
use super::output::{emit, write_atomic};
use super::progress::Progress;
use anyhow::{anyhow, Context, Result};
use sonarmap::mapping::Params;
use sonarmap::suite::SuiteLine;
use std::path::{Path, PathBuf};

/// What `eval --suite N` scores and writes.
pub struct SuiteArgs<'a> {
    /// Scenes of each family.
    pub scenes: usize,
    /// Seed of the first scene.
    pub seed: u64,
    /// `--write-plans DIR`.
    pub write_plans: Option<&'a Path>,
    /// `--logs-from DIR`.
    pub logs_from: Option<&'a Path>,
    /// `--drift`, the pace and the bounces: how every run is driven and echoes.
    pub conditions: sonarmap::suite::Conditions,
    /// `--score-accuracy-pct`: the ξ the maps are judged with, instead of the mapping's own.
    pub score_accuracy_pct: Option<f64>,
}

/// `eval --suite N`: one JSON line per scene and sensor model, then the summary
/// ([`sonarmap::suite`]); with `--write-plans DIR`, the scenes' plans too.
pub fn suite_command(args: &SuiteArgs, params: &Params) -> Result<()> {
    if let Some(dir) = args.write_plans {
        write_plans(dir, args.scenes, args.seed, &args.conditions)?;
    }
    let elsewhere = match args.logs_from {
        Some(dir) => logs_in(dir, args.scenes, args.seed),
        None => Vec::new(),
    };
    let generated = 2 * args.scenes;
    let progress = Progress::new("suite", generated + elsewhere.len(), "runs");
    let mut lines = sonarmap::suite::run_suite_with(
        args.scenes,
        args.seed,
        params,
        &args.conditions,
        args.score_accuracy_pct,
        &mut |runs| progress.set(runs).is_ok(),
    )
    .map_err(|_| Interrupted)?;
    for (i, (family, seed, path)) in elsewhere.into_iter().enumerate() {
        lines.push(log_line(family, seed, &path, params, args)?);
        progress.set(generated + i + 1)?;
    }
    drop(progress);
    for line in &lines {
        emit(&serde_json::to_string(line)?)?;
    }
    let summary = sonarmap::suite::SuiteSummary {
        score_accuracy_pct: args.score_accuracy_pct,
        ..sonarmap::suite::summarise(&lines)
    };
    emit(&serde_json::to_string(&summary)?)?;
    Ok(())
}

/// Writes each scene's plan, as `conditions` simulate it (their bounces), into `dir` as
/// FAMILY-SEED.plan.json.
fn write_plans(
    dir: &Path,
    scenes: usize,
    seed: u64,
    conditions: &sonarmap::suite::Conditions,
) -> Result<()> {
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    for (kind, seed, plan) in sonarmap::suite::suite_plans(scenes, seed) {
        let path = dir.join(format!("{}-{seed}.plan.json", kind.name()));
        let plan = conditions.simulated(plan);
        let text = serde_json::to_string(&sonarmap::sim::plan_to_file(&plan))?;
        write_atomic(&path, text)?;
    }
    Ok(())
}

/// The scenes' logs simulated elsewhere: family, seed and DIR/FAMILY-SEED.log.json of each
/// scene whose log exists.
fn logs_in(dir: &Path, scenes: usize, seed: u64) -> Vec<(&'static str, u64, PathBuf)> {
    sonarmap::suite::suite_plans(scenes, seed)
        .into_iter()
        .map(|(kind, seed, _)| {
            let path = dir.join(format!("{}-{seed}.log.json", kind.name()));
            (kind.name(), seed, path)
        })
        .filter(|(_, _, path)| path.exists())
        .collect()
}

/// The line of a scene's log simulated elsewhere (model "log").
fn log_line(
    family: &'static str,
    seed: u64,
    path: &Path,
    params: &Params,
    args: &SuiteArgs,
) -> Result<SuiteLine> {
    let run = sonarmap::suite::drifted(read_run(path)?, args.conditions.drift.as_ref(), seed);
    let (map, poses) = sonarmap::suite::map_and_poses_of(&run, params);
    let judged = sonarmap::eval::judged_with(params, args.score_accuracy_pct);
    let figures = sonarmap::suite::scene_figures(&map, &run, &judged)
        .ok_or_else(|| anyhow!("{}: the log has no floor_plan", path.display()))?;
    Ok(SuiteLine {
        family,
        seed,
        model: "log".to_string(),
        snapshots: run.snapshots.len(),
        figures,
        pose: sonarmap::suite::PoseFigures::of(&run, &poses),
    })
}
