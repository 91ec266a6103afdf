//! The `sonarmap` binary: the inspector, or a headless subcommand (FORMATS.md, command line).

mod cli;
mod convert;

use clap::Parser;
use std::path::PathBuf;
use std::process::ExitCode;

/// Opens the inspector on `log` (the built-in Blue Room when `None`).
fn open_app(log: Option<PathBuf>) -> anyhow::Result<()> {
    let _ = log;
    println!("the inspector is not built yet");
    Ok(())
}

fn main() -> ExitCode {
    let cli = match cli::Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            // Help and version go to stdout with code 0; usage errors to stderr with code 2.
            let _ = e.print();
            return if e.use_stderr() {
                ExitCode::from(2)
            } else {
                ExitCode::SUCCESS
            };
        }
    };
    let result = match &cli.command {
        Some(command) => cli::execute(command),
        None => open_app(cli.log.clone()),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::from(2)
        }
    }
}
