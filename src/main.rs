//! The `sonarmap` binary: the inspector, or a headless subcommand (docs/formats.md §10).

mod cli;

use clap::Parser;
use sonarmap::app::{Command, SonarApp, Source};
use sonarmap::scene::SceneId;
use std::path::PathBuf;
use std::process::ExitCode;

#[global_allocator]
static ALLOCATOR: sonarmap::alloc_count::CountingAllocator =
    sonarmap::alloc_count::CountingAllocator;

/// Opens the inspector on `log` (the built-in Blue Room when `None`). A log that fails to load
/// opens the Blue Room with the error in the banner.
///
/// For screenshots only: `SONARMAP_SNAPSHOT=k` starts at snapshot `k`, `SONARMAP_SELECT=n3`
/// selects new segment 3 (`s5`: map segment 5), `SONARMAP_BASELINE_THETA=5` pins the
/// parameters the app starts with as the baseline and re-runs with θ_o = 5°,
/// `SONARMAP_PRESET=paper|extended` starts with that preset.
fn open_app(log: Option<PathBuf>) -> anyhow::Result<()> {
    let builtin = sonarmap::assets::default_run()?;
    let mut startup = Vec::new();
    match std::env::var("SONARMAP_PRESET").as_deref() {
        Ok("paper") => startup.push(Command::SetPreset(sonarmap::mapping::Preset::Paper)),
        Ok("extended") => startup.push(Command::SetPreset(sonarmap::mapping::Preset::Extended)),
        _ => {}
    }
    if let Some(path) = log {
        startup.push(Command::Open(path));
    }
    if let Some(k) = std::env::var("SONARMAP_SNAPSHOT")
        .ok()
        .and_then(|v| v.parse().ok())
    {
        startup.push(Command::Seek(k));
    }
    if let Some(theta_deg) = std::env::var("SONARMAP_BASELINE_THETA")
        .ok()
        .and_then(|v| v.parse::<f64>().ok())
    {
        startup.push(Command::PinBaseline);
        let mut params = sonarmap::mapping::Params::paper();
        params.orientation_rad = theta_deg.to_radians();
        startup.push(Command::SetParams(params));
    }
    if let Ok(sel) = std::env::var("SONARMAP_SELECT") {
        let id = match (sel.get(..1), sel.get(1..).and_then(|n| n.parse().ok())) {
            (Some("n"), Some(i)) => Some(SceneId::NewSegment(i as usize)),
            (Some("s"), Some(i)) => Some(SceneId::MapSegment(i)),
            _ => None,
        };
        if let Some(id) = id {
            startup.push(Command::Select(id));
            startup.push(Command::ZoomToSelection);
        }
    }
    sonarmap::app::run_native(move |storage| {
        let mut app = SonarApp::with_source(
            builtin,
            Source::BuiltIn(sonarmap::assets::DEFAULT_RUN_NAME.to_owned()),
            storage,
        );
        for command in startup {
            app.apply(command);
        }
        app
    })
    .map_err(|e| anyhow::anyhow!("cannot open the window: {e}"))
}

fn main() -> ExitCode {
    // A guarded engine step reports its own failure (naming the snapshot): no panic trace.
    sonarmap::mapping::install_quiet_step_hook();
    // Seeks allocate big grids again and again: freed memory stays for them.
    sonarmap::alloc_count::keep_freed_memory();
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
        Err(e) if cli::interrupt::is_interruption(&e) => {
            eprintln!("interrupted");
            ExitCode::from(cli::interrupt::EXIT_STATUS)
        }
        Err(e) => {
            // Control characters from a file's content (a frame id, a JSON string) must not
            // reach the terminal raw.
            eprintln!(
                "error: {}",
                sonarmap::import::sane::escape(&format!("{e:#}"))
            );
            ExitCode::from(2)
        }
    }
}
