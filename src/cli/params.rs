//! The mapping parameters on the command line: a preset and an optional parameters file,
//! shared by `run`, `eval`, `diff` and `bench`.

use super::input::read;
use anyhow::{Context, Result};
use clap::{Args, ValueEnum};
use sonarmap::log::parse_json;
use sonarmap::mapping::{Params, ParamsFile, Preset};
use std::path::PathBuf;

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

/// The parameters from a preset and an optional `--params` file; a parameter on while one it
/// acts only with is off is warned about on stderr.
pub fn read_params(args: &ParamArgs) -> Result<Params> {
    read_params_and_preset(args).map(|(params, _)| params)
}

/// [`read_params`], with the preset the parameters start from: the `--params` file's `preset`
/// when it names one, else `--preset`.
pub fn read_params_and_preset(args: &ParamArgs) -> Result<(Params, Preset)> {
    let preset: Preset = args.preset.into();
    let Some(path) = &args.params else {
        return Ok((Params::preset(preset), preset));
    };
    let name = path.display().to_string();
    let file: ParamsFile = parse_json(&read(path)?, &name)?;
    let params = Params::preset(preset)
        .with_file(&file)
        .with_context(|| format!("{name}: bad parameters"))?;
    for unmet in params.unmet_needs() {
        eprintln!("warning: {name}: {unmet}");
    }
    Ok((params, file.preset.unwrap_or(preset)))
}
