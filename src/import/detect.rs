//! Picking the importer from the content (not the file name): MCAP magic bytes, a JSON object
//! (a `sonarmap-log`), Player/Stage lines, or a table of numbers.

use super::error::ImportError;
use super::options::ImportOptions;
use super::player::{import_player, looks_like_player_line, player_line_problem};
use super::ros2::{import_mcap, MCAP_MAGIC};
use super::summary::{Format, ImportSummary, Imported};
use super::table::{import_table, looks_like_table, table_line_problem};
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
    let bytes = without_bom(bytes);
    let start = bytes.iter().position(|b| !b.is_ascii_whitespace())?;
    if bytes[start] == b'{' {
        return Some(Format::SonarmapLog);
    }
    let content = content_lines(head_text(bytes));
    let (_, first) = content.first()?;
    if looks_like_player_line(first) {
        return Some(Format::Player);
    }
    let (_, data) = table_data_line(&content)?;
    looks_like_table(data).then_some(Format::Table)
}

/// `bytes` without a UTF-8 byte-order mark.
fn without_bom(bytes: &[u8]) -> &[u8] {
    bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes)
}

/// The text detection reads: the first 64 KiB, up to the first byte that is not UTF-8 (the
/// importer then refuses that byte with its line).
fn head_text(bytes: &[u8]) -> &str {
    let head = &bytes[..bytes.len().min(64 * 1024)];
    match std::str::from_utf8(head) {
        Ok(t) => t,
        Err(e) => std::str::from_utf8(&head[..e.valid_up_to()]).unwrap_or(""),
    }
}

/// The first [`LINES_LOOKED_AT`] content lines of `text` (`#` comments and blank lines left
/// out): each line's number, from 1, and its fields (split at whitespace and commas).
fn content_lines(text: &str) -> Vec<(usize, Vec<&str>)> {
    text.lines()
        .enumerate()
        .map(|(i, l)| {
            let fields = l
                .split('#')
                .next()
                .unwrap_or("")
                .split(|c: char| c == ',' || c.is_ascii_whitespace())
                .filter(|f| !f.is_empty())
                .collect::<Vec<_>>();
            (i + 1, fields)
        })
        .filter(|(_, f)| !f.is_empty())
        .take(LINES_LOOKED_AT)
        .collect()
}

/// The line a table's detection reads: the first content line, or the second when the first
/// does not start with a number (a header).
fn table_data_line<'a, 'b>(
    content: &'b [(usize, Vec<&'a str>)],
) -> Option<&'b (usize, Vec<&'a str>)> {
    let first = content.first()?;
    if first.1[0].parse::<f64>().is_err() {
        content.get(1)
    } else {
        Some(first)
    }
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

/// What every importer accepts, for a file that shows none of it.
const EXPECTED: &str = "expected an MCAP file, a `sonarmap-log` JSON object, a Player/Stage \
text log (`time host robot interface index ...` lines) or a table of numbers";

/// Why no importer reads `bytes`, for the error message: the first line that no importer could
/// read, and what each importer expected there (or where the text stops being UTF-8, if it does
/// in the first 64 KiB).
fn describe_start(bytes: &[u8]) -> String {
    if bytes.iter().all(|b| b.is_ascii_whitespace()) {
        return format!("the file is empty; {EXPECTED}");
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
                "line {line}, byte {at} (column {}) is 0x{:02X}, not UTF-8 text; {EXPECTED}",
                column + 1,
                head[at]
            );
        }
    }
    let text = head_text(without_bom(bytes));
    let content = content_lines(text);
    let Some((first_line, first)) = content.first() else {
        return format!("the file holds only comments; {EXPECTED}");
    };
    let player = player_line_problem(first).unwrap_or_default();
    let (table_line, table) = match table_data_line(&content) {
        Some((line, fields)) => (*line, table_line_problem(fields).unwrap_or_default()),
        None => (
            *first_line,
            "a header, and no line of numbers after it".to_string(),
        ),
    };
    // The table importer reads a header line that the Player importer refuses.
    let unread = table_line.max(*first_line);
    let shown: String = text
        .lines()
        .nth(unread - 1)
        .unwrap_or("")
        .chars()
        .take(60)
        .map(|c| if c.is_control() { ' ' } else { c })
        .collect();
    let start: String = text.trim_start().chars().take(1).collect();
    format!(
        "no importer reads line {unread} ({shown:?}): an MCAP file starts with the bytes \
         89 4D 43 41 50 30 0D 0A and a `sonarmap-log` with `{{`, this one with {start:?}; a \
         Player/Stage log has lines `time host robot interface index ...`, and at line \
         {first_line}: {player}; a table has lines of numbers after an optional header line, \
         and at line {table_line}: {table}"
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn message(text: &str) -> String {
        let options = ImportOptions::default();
        match import_any(text.as_bytes(), "notes.txt", &options) {
            Err(e) => e.to_string(),
            Ok(_) => panic!("{text:?} was imported"),
        }
    }

    #[test]
    fn a_text_no_importer_reads_names_its_line_and_each_importers_expectation() {
        let m = message("# field notes\n\nrobot 1 went 3 m\n");
        assert!(m.starts_with("notes.txt: not a recognised run: "), "{m}");
        assert!(
            m.contains("no importer reads line 3 (\"robot 1 went 3 m\")"),
            "{m}"
        );
        assert!(m.contains("this one with \"#\""), "{m}");
        assert!(m.contains("at line 3: 5 fields, fewer than 6"), "{m}");
        // "robot ..." does not start with a number: the table reads it as its header.
        assert!(
            m.contains("at line 3: a header, and no line of numbers after it"),
            "{m}"
        );
    }

    #[test]
    fn after_a_header_the_table_importers_line_is_the_next() {
        let m = message("t x y heading r0 r1\n0.0 1.5 2.0 oops 4 5\n");
        assert!(
            m.contains("no importer reads line 2 (\"0.0 1.5 2.0 oops 4 5\")"),
            "{m}"
        );
        assert!(m.contains("at line 1: field 1 \"t\" is not a time"), "{m}");
        assert!(
            m.contains("at line 2: field 4 \"oops\" is not a number"),
            "{m}"
        );
    }

    #[test]
    fn a_player_line_is_told_which_field_is_wrong() {
        let m = message("1000.0 16777343 robot position 00 1000.0 0 0 0\n");
        assert!(
            m.contains("at line 1: field 3 \"robot\" is not a robot (port) number"),
            "{m}"
        );
        assert!(
            m.contains("at line 1: field 3 \"robot\" is not a number"),
            "{m}"
        );
    }

    #[test]
    fn empty_and_comment_only_files_say_so() {
        assert!(message(" \n").contains("the file is empty; expected an MCAP file"));
        assert!(message("# only\n").contains("only comments; expected an MCAP file"));
    }
}
