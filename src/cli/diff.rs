//! `sonarmap diff`: the decisions of two parameter sets on one log compared.

use super::input::read_run;
use super::output::emit;
use super::params::{read_params, ParamArgs, PresetArg};
use anyhow::Result;
use clap::Args;
use sonarmap::eval::{evaluate, EvalReport};
use sonarmap::mapping::{Map, Params};
use std::path::PathBuf;

/// The long help of `sonarmap diff`: how decisions are paired and what the output holds.
pub const DIFF_HELP: &str = "Compare the decisions of two parameter sets on one log; prints one JSON object.

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

/// Runs `sonarmap diff`.
pub fn diff_command(args: &DiffArgs) -> Result<()> {
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
