//! The soak: long lap runs over generated families of scenes ([`crate::sim::SceneKind`]), in
//! every preset and with every single extension flag, checking [`Map::check_invariants`] after
//! every step (as often as a bounded cost allows on a map that grows large) and counting panics.
//! `sonarmap soak` runs it at any size; the property tests run a small budget of it, checking
//! after every step.

use crate::mapping::{Map, Mapper, Params};
use crate::replay::Cancelled;
use crate::run::Run;
use crate::sim::{family_plan, repeat_laps, simulate_paced, Model, SceneKind};
use crate::suite::{drifted, Conditions};

/// The parameter sets a soak drives: both presets, then the paper with each parameter the
/// presets set apart at its `extended` value, with what it acts only with
/// ([`Params::paper_with`]), named `paper+NAME`: every extension of docs/algorithm.md §8 alone.
pub fn soak_variants() -> Vec<(String, Params)> {
    let mut variants = vec![
        ("paper".to_string(), Params::paper()),
        ("extended".to_string(), Params::extended()),
    ];
    variants.extend(Params::extension_parameters().filter_map(|p| {
        Params::paper_with(p.name).map(|params| (format!("paper+{}", p.name), params))
    }));
    variants
}

/// A run that panicked or broke an invariant.
#[derive(Clone, Debug, PartialEq)]
pub struct SoakFailure {
    /// The scene kind.
    pub kind: SceneKind,
    /// Its seed.
    pub seed: u64,
    /// The parameter set's name.
    pub variant: String,
    /// The snapshot whose step failed.
    pub snapshot: usize,
    /// The panic message or the broken invariant.
    pub message: String,
    /// True for a panic, false for a broken invariant.
    pub panicked: bool,
}

/// What a soak did.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SoakReport {
    /// Runs driven (scene × parameter set).
    pub runs: usize,
    /// Steps taken in all.
    pub snapshots: usize,
    /// Invariant checks made (after every step while maps are small, see
    /// [`SEGMENT_CHECKS_PER_STEP`]).
    pub invariant_checks: usize,
    /// Steps that panicked.
    pub panics: usize,
    /// Steps after which an invariant was broken.
    pub broken_invariants: usize,
    /// Segments in the largest final map.
    pub largest_map: usize,
    /// Every failure (a run stops at its first).
    pub failures: Vec<SoakFailure>,
}

/// Segment checks per step the soak spends on invariants, on average: a map of `n` segments is
/// checked every `n / SEGMENT_CHECKS_PER_STEP` steps (every step while it is smaller), so a
/// paper map that grows to tens of thousands of segments does not make the soak quadratic.
pub const SEGMENT_CHECKS_PER_STEP: usize = 2_000;

/// A run mapped with its map checked ([`map_checked`]).
#[derive(Clone, Debug)]
pub struct CheckedRun {
    /// Steps taken (up to and including a failed one).
    pub steps: usize,
    /// Invariant checks made.
    pub checks: usize,
    /// The first failure: snapshot, message, and whether it was a panic.
    pub failure: Option<(usize, String, bool)>,
    /// The map at the end (or at the failure).
    pub map: Map,
}

/// Maps `run` with `params`; every step is guarded ([`Mapper::try_step`]) and the map is
/// checked ([`Map::check_invariants`]) after every step, or, with `every_step` false, as often
/// as [`SEGMENT_CHECKS_PER_STEP`] allows, and after the last.
pub fn map_checked(run: &Run, params: &Params, every_step: bool) -> CheckedRun {
    map_checked_with(run, params, every_step, &mut |_| true).expect("never cancelled")
}

/// [`map_checked`], calling `progress(steps)` after every step; returning `false` cancels.
pub fn map_checked_with(
    run: &Run,
    params: &Params,
    every_step: bool,
    progress: &mut dyn FnMut(usize) -> bool,
) -> Result<CheckedRun, Cancelled> {
    let mut mapper = Mapper::new(params.clone(), run.layout.clone(), run.sensor).with_trace(false);
    let mut out = CheckedRun {
        steps: 0,
        checks: 0,
        failure: None,
        map: Map::default(),
    };
    let mut since_check = 0;
    for (i, snapshot) in run.snapshots.iter().enumerate() {
        out.steps = i + 1;
        if let Err(failure) = mapper.try_step(snapshot) {
            out.failure = Some((i, failure.message, true));
            break;
        }
        since_check += 1;
        let last = i + 1 == run.snapshots.len();
        let due = mapper.map().segments.len() / SEGMENT_CHECKS_PER_STEP;
        if every_step || last || since_check > due {
            since_check = 0;
            out.checks += 1;
            if let Err(broken) = mapper.map().check_invariants(params.support_cap) {
                out.failure = Some((i, broken, false));
                break;
            }
        }
        if !progress(out.steps) {
            return Err(Cancelled);
        }
    }
    out.map = mapper.map().clone();
    Ok(out)
}

/// The lap run of scene `kind` drawn from `seed`, repeated to `snapshots`; every other seed
/// uses the simulator's axis model instead of the specular one.
pub fn family_run(kind: SceneKind, seed: u64, snapshots: usize) -> Run {
    family_run_under(kind, seed, snapshots, &Conditions::PLAIN)
}

/// [`family_run`] simulated at `conditions.pace` with `conditions.bounces` and, repeated, given
/// `conditions.drift` (seeded with `seed`): the odometry drifts on over the laps.
pub fn family_run_under(
    kind: SceneKind,
    seed: u64,
    snapshots: usize,
    conditions: &Conditions,
) -> Run {
    let plan = conditions.simulated(family_plan(kind, seed));
    let model = if seed.is_multiple_of(2) {
        Model::Specular
    } else {
        Model::Axis
    };
    let lap = simulate_paced(&plan, model, seed, &conditions.pace);
    drifted(
        repeat_laps(&lap, snapshots),
        conditions.drift.as_ref(),
        seed,
    )
}

/// Drives `runs_per_kind` scenes of every kind (seeds from `first_seed` on), each
/// `snapshots` long, through every [`soak_variants`] parameter set. `progress(done)` hears
/// of the snapshots done after every step (a run that fails counts as done, all its
/// snapshots); returning `false` cancels.
pub fn soak(
    runs_per_kind: usize,
    snapshots: usize,
    first_seed: u64,
    progress: &mut dyn FnMut(usize) -> bool,
) -> Result<SoakReport, Cancelled> {
    let plain = &Conditions::PLAIN;
    soak_variants_named(runs_per_kind, snapshots, first_seed, &[], plain, progress)
}

/// The parameter sets named in `only` (all when it is empty), in [`soak_variants`] order.
pub fn soak_variants_only(only: &[String]) -> Vec<(String, Params)> {
    let mut variants = soak_variants();
    if !only.is_empty() {
        variants.retain(|(name, _)| only.iter().any(|o| o == name));
    }
    variants
}

/// [`soak`] with only the parameter sets named in `only` ([`soak_variants_only`]), every run
/// driven under `conditions` ([`family_run_under`]).
pub fn soak_variants_named(
    runs_per_kind: usize,
    snapshots: usize,
    first_seed: u64,
    only: &[String],
    conditions: &Conditions,
    progress: &mut dyn FnMut(usize) -> bool,
) -> Result<SoakReport, Cancelled> {
    let mut report = SoakReport::default();
    let variants = soak_variants_only(only);
    let mut runs_done = 0;
    for seed in first_seed..first_seed + runs_per_kind as u64 {
        for kind in SceneKind::ALL {
            let run = family_run_under(kind, seed, snapshots, conditions);
            for (variant, params) in &variants {
                let before = runs_done * snapshots;
                let checked =
                    map_checked_with(&run, params, false, &mut |steps| progress(before + steps))?;
                runs_done += 1;
                report.runs += 1;
                report.snapshots += checked.steps;
                report.invariant_checks += checked.checks;
                report.largest_map = report.largest_map.max(checked.map.segments.len());
                if let Some((snapshot, message, panicked)) = checked.failure {
                    if panicked {
                        report.panics += 1;
                    } else {
                        report.broken_invariants += 1;
                    }
                    report.failures.push(SoakFailure {
                        kind,
                        seed,
                        variant: variant.clone(),
                        snapshot,
                        message,
                        panicked,
                    });
                }
            }
        }
    }
    Ok(report)
}
