//! Text input shared by the Player and table importers: lines without comments, fields, and
//! numbers that report their line and field when they are not numbers.

use super::error::{at, ImportError};

/// The longest line looked at, in bytes; a longer one is refused (a binary file read as text).
pub const MAX_LINE_BYTES: usize = 1 << 20;

/// One line with content: its 1-based number and its fields.
pub(crate) struct Line<'a> {
    /// 1-based line number.
    pub number: usize,
    /// The fields, split on whitespace (and on commas when `commas`).
    pub fields: Vec<&'a str>,
}

/// Decodes the bytes as UTF-8 (a byte-order mark is skipped), or says where they are not.
pub(crate) fn utf8<'a>(bytes: &'a [u8], file: &str) -> Result<&'a str, ImportError> {
    let bytes = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    std::str::from_utf8(bytes).map_err(|e| {
        let line = 1 + bytes[..e.valid_up_to()]
            .iter()
            .filter(|&&b| b == b'\n')
            .count();
        at(
            file,
            format!("line {line}"),
            format!(
                "byte {} is not UTF-8 text: expected a text file",
                e.valid_up_to()
            ),
        )
    })
}

/// The lines with content, one at a time (nothing is kept: memory does not grow with the file):
/// `#` starts a comment (to the end of the line), blank lines are left out. Fields are split on
/// ASCII whitespace, and on commas too when `commas` is true. A line longer than
/// [`MAX_LINE_BYTES`] is refused, and so is a last line with content but no newline: the file
/// was cut short, perhaps in the middle of a number (`6.4770` cut to `6.4`).
pub(crate) fn lines<'a>(
    text: &'a str,
    commas: bool,
    file: &'a str,
) -> impl Iterator<Item = Result<Line<'a>, ImportError>> + 'a {
    text.split_inclusive('\n')
        .enumerate()
        .filter_map(move |(i, raw)| {
            let number = i + 1;
            if raw.len() > MAX_LINE_BYTES {
                return Some(Err(at(
                    file,
                    format!("line {number}"),
                    format!(
                        "the line is {} bytes long: expected at most {MAX_LINE_BYTES}",
                        raw.len()
                    ),
                )));
            }
            let complete = raw.ends_with('\n');
            let content = match raw.find('#') {
                Some(c) => &raw[..c],
                None => raw,
            };
            // ASCII whitespace only (fast; a text log's other characters are field content,
            // refused where a number goes).
            let fields: Vec<&str> = if commas {
                content
                    .split(|c: char| c == ',' || c.is_ascii_whitespace())
                    .filter(|f| !f.is_empty())
                    .collect()
            } else {
                content.split_ascii_whitespace().collect()
            };
            if fields.is_empty() {
                return None;
            }
            if !complete {
                return Some(Err(at(
                    file,
                    format!("line {number}"),
                    format!(
                        "the file ends in this line, without a newline, after {:?}: expected complete lines (the file may have been cut short; if it is whole, end it with a newline)",
                        clip(fields.last().copied().unwrap_or(""))
                    ),
                )));
            }
            Some(Ok(Line { number, fields }))
        })
}

/// Parses field `index` (0-based) of `line` as a finite number; `what` names it in the error.
pub(crate) fn number(
    line: &Line,
    index: usize,
    what: &str,
    file: &str,
) -> Result<f64, ImportError> {
    let Some(text) = line.fields.get(index) else {
        return Err(at(
            file,
            format!("line {}", line.number),
            format!(
                "the line ends after {} fields: expected {what} in field {}",
                line.fields.len(),
                index + 1
            ),
        ));
    };
    match text.parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        _ => Err(at(
            file,
            format!("line {}, field {}", line.number, index + 1),
            format!("{:?} is not a finite number: expected {what}", clip(text)),
        )),
    }
}

/// Parses field `index` as a number that `check` (one of [`super::sane`]'s bounds) accepts;
/// `what` names it in the error, with the line and field.
pub(crate) fn checked(
    line: &Line,
    index: usize,
    what: &str,
    file: &str,
    check: impl Fn(f64, &str) -> Result<f64, String>,
) -> Result<f64, ImportError> {
    let v = number(line, index, what, file)?;
    check(v, what).map_err(|m| {
        at(
            file,
            format!("line {}, field {}", line.number, index + 1),
            m,
        )
    })
}

/// Parses field `index` as a count (a whole number, at most `max`).
pub(crate) fn count(
    line: &Line,
    index: usize,
    what: &str,
    max: usize,
    file: &str,
) -> Result<usize, ImportError> {
    let v = number(line, index, what, file)?;
    if v.fract() != 0.0 || v < 0.0 || v > max as f64 {
        return Err(at(
            file,
            format!("line {}, field {}", line.number, index + 1),
            format!(
                "{} is not a count: expected {what}, a whole number from 0 to {max}",
                super::sane::show(v)
            ),
        ));
    }
    Ok(v as usize)
}

/// At most 40 characters of a field, for messages.
pub(crate) fn clip(text: &str) -> String {
    if text.chars().count() > 40 {
        let head: String = text.chars().take(40).collect();
        format!("{head}...")
    } else {
        text.to_string()
    }
}
