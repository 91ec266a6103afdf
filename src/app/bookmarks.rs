//! The bookmarks of a run and their sidecar file beside the log, `<log>.bookmarks.json`:
//! `{"format": "sonarmap-bookmarks", "version": 1, "bookmarks": [{"name", "snapshot"}]}`
//! (docs/formats.md §9). The built-in run keeps its bookmarks in the settings instead.

use crate::atomic_write::write_atomic;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// A named snapshot.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Bookmark {
    /// The name given.
    pub name: String,
    /// The snapshot index.
    pub snapshot: usize,
}

/// The sidecar file of bookmarks beside a log: `<log>.bookmarks.json`.
pub fn bookmarks_path(log: &Path) -> PathBuf {
    let mut name = log.file_name().unwrap_or_default().to_os_string();
    name.push(".bookmarks.json");
    log.with_file_name(name)
}

/// The sidecar file's contents.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
struct BookmarksFile {
    format: String,
    version: u32,
    bookmarks: Vec<Bookmark>,
}

const BOOKMARKS_FORMAT: &str = "sonarmap-bookmarks";

/// Reads the bookmarks of the log at `log` from its sidecar file. A missing or unreadable file
/// gives none; a file that is not a bookmarks file gives none and the message to show.
pub fn read_sidecar(log: &Path) -> Result<Vec<Bookmark>, String> {
    let side = bookmarks_path(log);
    match std::fs::read_to_string(&side) {
        Err(_) => Ok(Vec::new()),
        Ok(text) => match serde_json::from_str::<BookmarksFile>(&text) {
            Ok(f) if f.format == BOOKMARKS_FORMAT => Ok(f.bookmarks),
            _ => Err(format!(
                "ignored unreadable bookmarks file {}",
                side.display()
            )),
        },
    }
}

/// Writes `bookmarks` to the sidecar file of the log at `log` (atomically); the error names
/// the file.
pub fn write_sidecar(log: &Path, bookmarks: &[Bookmark]) -> Result<(), String> {
    let side = bookmarks_path(log);
    let file = BookmarksFile {
        format: BOOKMARKS_FORMAT.to_owned(),
        version: 1,
        bookmarks: bookmarks.to_vec(),
    };
    serde_json::to_string_pretty(&file)
        .map_err(|e| e.to_string())
        .and_then(|t| write_atomic(&side, (t + "\n").as_bytes()).map_err(|e| e.to_string()))
        .map_err(|e| format!("Could not write {}: {e}", side.display()))
}
