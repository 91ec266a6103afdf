//! `sonarmap convert`: a recording of any supported format to a run log.

use super::input::{import_file, read};
use super::output::write_atomic_with;
use super::progress::Progress;
use anyhow::{anyhow, Result};
use clap::{Args, ValueEnum};
use sonarmap::geometry::Pose;
use sonarmap::import::{
    builtin_layout, parse_layout, AngleUnit, ImportOptions, Layout, NamedBytes, TableForm,
};
use sonarmap::log::write_run;
use sonarmap::units::Units;
use std::path::{Path, PathBuf};

/// `sonarmap convert`.
#[derive(Debug, Args)]
pub struct ConvertArgs {
    /// The recording: a Player/Stage text log, a ROS 2 MCAP file, a table (or a run log).
    pub input: PathBuf,
    /// Where to write the run log (`sonarmap-log` v1).
    #[arg(long, value_name = "LOG.json")]
    pub out: PathBuf,
    /// The sensor layout (`sonarmap-layout` file, or `pioneer_8_8` / `nomad_200`).
    #[arg(long, value_name = "LAYOUT.json")]
    pub layout: Option<String>,
    /// Readings at or beyond this range are no echo (in --units).
    #[arg(long, value_name = "R")]
    pub max_range: Option<f64>,
    /// Length unit of tables, --max-range, --fixed-pose and the written log (default m).
    #[arg(long, value_enum)]
    pub units: Option<UnitsArg>,
    /// Heading unit of tables.
    #[arg(long, value_enum, default_value = "deg")]
    pub heading_unit: HeadingArg,
    /// MCAP and firing tables: the longest firing cycle of the ring, seconds (default 0.1 for
    /// MCAP, 1 for firing tables).
    #[arg(long, value_name = "S")]
    pub window: Option<f64>,
    /// Tables: a ring a line, or one reading a line (`t sensor range [x y heading]`); default:
    /// read off the file.
    #[arg(long, value_enum, default_value = "auto")]
    pub table: TableArg,
    /// Tables: the poses file (`t x y heading`).
    #[arg(long, value_name = "FILE")]
    pub poses: Option<PathBuf>,
    /// Without odometry: the robot's pose for every snapshot, `X,Y,HEADING_DEG`.
    #[arg(long, value_name = "X,Y,HEADING_DEG", allow_hyphen_values = true)]
    pub fixed_pose: Option<String>,
}

/// A length unit on the command line.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum UnitsArg {
    /// Inches.
    In,
    /// Millimetres.
    Mm,
    /// Centimetres.
    Cm,
    /// Metres.
    M,
}

/// A table form on the command line.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum TableArg {
    /// Read off the file.
    Auto,
    /// A whole ring a line.
    Ring,
    /// One reading a line.
    Firings,
}

/// A heading unit on the command line.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum HeadingArg {
    /// Degrees.
    Deg,
    /// Radians.
    Rad,
}

/// Reads a `--layout`: a file, or the name of a shipped layout.
fn read_layout(arg: &str) -> Result<Layout> {
    let path = Path::new(arg);
    if !path.exists() {
        if let Some(l) = builtin_layout(arg.trim_end_matches(".layout.json")) {
            return Ok(l);
        }
    }
    Ok(parse_layout(&read(path)?, arg)?)
}

/// Runs `sonarmap convert`.
pub fn convert_command(args: &ConvertArgs) -> Result<()> {
    let units = args.units.map(|u| match u {
        UnitsArg::In => Units::Inches,
        UnitsArg::Mm => Units::Millimetres,
        UnitsArg::Cm => Units::Centimetres,
        UnitsArg::M => Units::Metres,
    });
    let u = units.unwrap_or(Units::Metres);
    let max_range_m = match args.max_range {
        Some(r) if r.is_finite() && r > 0.0 => Some(u.to_m(r)),
        Some(r) => return Err(anyhow!("--max-range {r}: expected a range greater than 0")),
        None => None,
    };
    let fixed_pose = match &args.fixed_pose {
        None => None,
        Some(text) => {
            let v: Vec<f64> = text
                .split(',')
                .map(|p| p.trim().parse::<f64>())
                .collect::<Result<_, _>>()
                .ok()
                .filter(|v: &Vec<f64>| v.len() == 3 && v.iter().all(|x| x.is_finite()))
                .ok_or_else(|| {
                    anyhow!("--fixed-pose {text:?}: expected three numbers X,Y,HEADING_DEG")
                })?;
            Some(Pose::new(u.to_m(v[0]), u.to_m(v[1]), v[2].to_radians()))
        }
    };
    let poses = match &args.poses {
        None => None,
        Some(p) => Some(NamedBytes {
            name: p.display().to_string(),
            bytes: read(p)?,
        }),
    };
    let options = ImportOptions {
        layout: args.layout.as_deref().map(read_layout).transpose()?,
        max_range_m,
        units,
        heading: match args.heading_unit {
            HeadingArg::Deg => AngleUnit::Degrees,
            HeadingArg::Rad => AngleUnit::Radians,
        },
        window_s: args.window,
        fixed_pose,
        poses,
        table: match args.table {
            TableArg::Auto => TableForm::Auto,
            TableArg::Ring => TableForm::Ring,
            TableArg::Firings => TableForm::Firings,
        },
    };
    let imported = import_file(&args.input, &options)?;
    let writing = Progress::spinner(&format!("writing {}", args.out.display()));
    write_atomic_with(&args.out, |f| write_run(&imported.run, f))?;
    drop(writing);
    println!(
        "{} ({}): {}",
        args.input.display(),
        imported.format.name(),
        imported.summary
    );
    Ok(())
}
