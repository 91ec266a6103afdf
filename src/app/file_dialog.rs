//! File dialogs that never fail silently. The system dialog (rfd: the XDG desktop portal, or
//! zenity) is used when it can work; otherwise, or when it fails, the in-app dialog
//! ([`super::in_app_dialog`], drawn by egui itself) opens instead.
//!
//! How "can work" is decided, on Linux: rfd talks to `org.freedesktop.portal.Desktop` on the
//! D-Bus session bus and falls back to `zenity`; when neither is there it returns "no file"
//! at once, exactly as if the user had cancelled. So before asking rfd, [`probe_system`]
//! checks for a session bus (`DBUS_SESSION_BUS_ADDRESS`) that owns or can activate the portal
//! (asked with `dbus-send`), or for `zenity` on `PATH`. And an rfd answer of "no file" that
//! comes back faster than a person can cancel ([`INSTANT_CANCEL`]) is taken as a failure: the
//! banner says so and the in-app dialog opens. `SONARMAP_FILE_DIALOG=in-app|system|auto` (or
//! the setting [`DialogBackend`]) forces a choice.

use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::sync::OnceLock;
use std::time::{Duration, Instant};

/// A "no file" from the system dialog quicker than this never showed a dialog.
pub const INSTANT_CANCEL: Duration = Duration::from_millis(300);

/// The environment variable that forces a [`DialogBackend`] (`in-app`, `system`, `auto`).
pub const BACKEND_ENV: &str = "SONARMAP_FILE_DIALOG";

/// Which file dialog to use.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum DialogBackend {
    /// The system dialog when `probe_system` finds one, else the in-app dialog.
    #[default]
    Auto,
    /// Always the system dialog (the in-app one still opens when it fails).
    System,
    /// Always the in-app dialog.
    InApp,
}

impl DialogBackend {
    /// The backend named by `BACKEND_ENV`, when set to a known name.
    pub fn from_env() -> Option<Self> {
        match std::env::var(BACKEND_ENV).ok()?.trim() {
            "in-app" | "inapp" | "in_app" => Some(DialogBackend::InApp),
            "system" => Some(DialogBackend::System),
            "auto" => Some(DialogBackend::Auto),
            _ => None,
        }
    }
}

/// What a chosen path is for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FilePurpose {
    /// A run log to open.
    OpenLog,
    /// Where to write the figure (SVG, or PNG by the extension).
    ExportFigure,
    /// A parameter file to load.
    LoadParams,
    /// Where to write the parameters.
    SaveParams,
    /// A layout file for a log that needs one.
    LayoutFile,
    /// The poses table (`t x y heading`) of a table of ranges only.
    PosesFile,
}

impl FilePurpose {
    /// The dialog's title.
    pub fn title(self) -> &'static str {
        match self {
            FilePurpose::OpenLog => "Open a run log",
            FilePurpose::ExportFigure => "Export the figure (SVG or PNG)",
            FilePurpose::LoadParams => "Load parameters",
            FilePurpose::SaveParams => "Save parameters",
            FilePurpose::LayoutFile => "Choose a layout file",
            FilePurpose::PosesFile => "Choose the poses table",
        }
    }

    /// True when the dialog asks where to write.
    pub fn is_save(self) -> bool {
        matches!(self, FilePurpose::ExportFigure | FilePurpose::SaveParams)
    }

    /// The extensions of the files offered.
    pub fn extensions(self) -> &'static [&'static str] {
        self.filter().1
    }

    /// The file kinds offered: a name and extensions.
    fn filter(self) -> (&'static str, &'static [&'static str]) {
        match self {
            FilePurpose::OpenLog => (
                "run log",
                &["json", "log", "mcap", "csv", "tsv", "txt", "dat"],
            ),
            FilePurpose::ExportFigure => ("figure", &["svg", "png"]),
            FilePurpose::LoadParams | FilePurpose::SaveParams => ("parameters", &["json"]),
            FilePurpose::LayoutFile => ("layout", &["json"]),
            FilePurpose::PosesFile => ("poses table", &["txt", "csv", "tsv", "dat"]),
        }
    }
}

/// The outcome of [`probe_system`]: `Err` says why the system dialog cannot work.
pub type Probe = Result<(), String>;

/// Whether the system dialog can work here (computed once; see the module's account).
pub fn probe_system() -> Probe {
    static PROBE: OnceLock<Probe> = OnceLock::new();
    PROBE.get_or_init(probe_uncached).clone()
}

#[cfg(target_os = "linux")]
fn probe_uncached() -> Probe {
    if on_path("zenity") {
        return Ok(());
    }
    if std::env::var_os("DBUS_SESSION_BUS_ADDRESS").is_none_or(|a| a.is_empty()) {
        return Err("no D-Bus session bus, so no XDG desktop portal (and no zenity)".to_owned());
    }
    const PORTAL: &str = "org.freedesktop.portal.Desktop";
    let mut asked = false;
    for method in ["ListNames", "ListActivatableNames"] {
        let out = std::process::Command::new("dbus-send")
            .args([
                "--session",
                "--print-reply",
                "--reply-timeout=500",
                "--dest=org.freedesktop.DBus",
                "/org/freedesktop/DBus",
                &format!("org.freedesktop.DBus.{method}"),
            ])
            .output();
        match out {
            Ok(o) if o.status.success() => {
                asked = true;
                if String::from_utf8_lossy(&o.stdout).contains(PORTAL) {
                    return Ok(());
                }
            }
            _ => {}
        }
    }
    if asked {
        Err(format!("no {PORTAL} on the session bus (and no zenity)"))
    } else {
        // dbus-send missing or refused: rfd will tell, by answering at once.
        Ok(())
    }
}

#[cfg(not(target_os = "linux"))]
fn probe_uncached() -> Probe {
    Ok(())
}

#[cfg(target_os = "linux")]
fn on_path(program: &str) -> bool {
    std::env::var_os("PATH")
        .is_some_and(|paths| std::env::split_paths(&paths).any(|d| d.join(program).is_file()))
}

/// What the system dialog answered.
pub enum SystemAnswer {
    /// A path chosen.
    Chosen(PathBuf),
    /// The user cancelled.
    Cancelled,
    /// No dialog was shown ("no file" at once).
    Failed,
}

/// Asks with the system dialog (blocks until it closes), starting in `folder`.
pub fn ask_system(purpose: FilePurpose, folder: Option<&Path>, file_name: &str) -> SystemAnswer {
    let (name, extensions) = purpose.filter();
    let mut dialog = rfd::FileDialog::new()
        .set_title(purpose.title())
        .add_filter(name, extensions);
    if let Some(folder) = folder {
        dialog = dialog.set_directory(folder);
    }
    let started = Instant::now();
    let answer = if purpose.is_save() {
        dialog.set_file_name(file_name).save_file()
    } else {
        dialog.pick_file()
    };
    match answer {
        Some(path) => SystemAnswer::Chosen(path),
        None if started.elapsed() < INSTANT_CANCEL => SystemAnswer::Failed,
        None => SystemAnswer::Cancelled,
    }
}
