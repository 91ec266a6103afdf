//! Picking the importer from the content (not the file name): MCAP magic bytes, a JSON object
//! (a `sonarmap-log`), Player/Stage lines, or a table of numbers.

use super::error::ImportError;
use super::options::ImportOptions;
use super::player::{import_player, looks_like_player_line};
use super::ros2::{import_mcap, MCAP_MAGIC};
use super::summary::{Format, ImportSummary, Imported};
use super::table::{import_table, looks_like_table};
use crate::log::load_run;

/// How many content lines detection looks at.
const LINES_LOOKED_AT: usize = 20;

/// The format of `bytes`, or `None` when it is none of them. Looks at the first bytes only:
/// MCAP magic; `{` after whitespace (and a byte-order mark) is JSON; text whose first content
/// lines (`#` comments left out) are Player lines; text whose first content line (after an
/// optional header line) is all numbers.
pub fn detect(bytes: &[u8]) -> Option<Format> {
    if bytes.starts_with(MCAP_MAGIC) {
        return Some(Format::Mcap);
    }
    let bytes = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    let start = bytes.iter().position(|b| !b.is_ascii_whitespace())?;
    if bytes[start] == b'{' {
        return Some(Format::SonarmapLog);
    }
    let head = &bytes[..bytes.len().min(64 * 1024)];
    // Detection reads the text up to the first byte that is not UTF-8 (the importer then
    // refuses that byte with its line).
    let text = match std::str::from_utf8(head) {
        Ok(t) => t,
        Err(e) => std::str::from_utf8(&head[..e.valid_up_to()]).ok()?,
    };
    let content: Vec<Vec<&str>> = text
        .lines()
        .map(|l| l.split('#').next().unwrap_or(""))
        .map(|l| {
            l.split(|c: char| c == ',' || c.is_ascii_whitespace())
                .filter(|f| !f.is_empty())
                .collect::<Vec<_>>()
        })
        .filter(|f| !f.is_empty())
        .take(LINES_LOOKED_AT)
        .collect();
    let first = content.first()?;
    if looks_like_player_line(first) {
        return Some(Format::Player);
    }
    let data = if first[0].parse::<f64>().is_err() {
        content.get(1)?
    } else {
        first
    };
    looks_like_table(data).then_some(Format::Table)
}

/// Reads a run from any supported format, chosen by [`detect`]. A `sonarmap-log` is loaded as
/// it is (the options do not apply; its summary has the counts only). `file` names it in
/// errors. Pure.
pub fn import_any(
    bytes: &[u8],
    file: &str,
    options: &ImportOptions,
) -> Result<Imported, ImportError> {
    match detect(bytes) {
        Some(Format::Mcap) => import_mcap(bytes, file, options),
        Some(Format::Player) => import_player(bytes, file, options),
        Some(Format::Table | Format::FiringTable) => import_table(bytes, file, options),
        Some(Format::SonarmapLog) => {
            let run = load_run(bytes, file)?;
            let summary = ImportSummary {
                snapshots: run.snapshots.len(),
                readings: run.snapshots.iter().map(|s| s.ranges_m.len()).sum(),
                ..ImportSummary::default()
            };
            Ok(Imported {
                run,
                summary,
                format: Format::SonarmapLog,
            })
        }
        None => Err(ImportError::Unrecognised {
            file: file.to_string(),
            detail: describe_start(bytes),
        }),
    }
}

/// The first bytes, for the error message (and where the text stops being UTF-8, if it does
/// in the first 64 KiB).
fn describe_start(bytes: &[u8]) -> String {
    if bytes.iter().all(|b| b.is_ascii_whitespace()) {
        return "the file is empty".to_string();
    }
    let head = &bytes[..bytes.len().min(64 * 1024)];
    if let Err(e) = std::str::from_utf8(head) {
        if e.error_len().is_some() {
            let at = e.valid_up_to();
            let line = 1 + head[..at].iter().filter(|&&b| b == b'\n').count();
            let column = at
                - head[..at]
                    .iter()
                    .rposition(|&b| b == b'\n')
                    .map_or(0, |p| p + 1);
            return format!(
                "line {line}, byte {at} (column {}) is 0x{:02X}, not UTF-8 text",
                column + 1,
                head[at]
            );
        }
    }
    let head: String = String::from_utf8_lossy(&bytes[..bytes.len().min(40)])
        .chars()
        .map(|c| if c.is_control() { ' ' } else { c })
        .collect();
    format!("it starts with {head:?}")
}
