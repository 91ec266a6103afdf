//! Errors of the input formats (run logs and floor plans). Every message names the file, the
//! place (JSON path, snapshot index, sensor index) and what was expected.

use thiserror::Error;

/// A run log or floor plan that cannot be used.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum LogError {
    /// The bytes are not JSON.
    #[error("{file}: not JSON: {message} at line {line} column {column}")]
    NotJson {
        /// The file's name.
        file: String,
        /// What the JSON parser expected.
        message: String,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
    },
    /// A key appears twice in one JSON object.
    #[error("{file}: duplicated key `{key}` in {path} (line {line} column {column}): each key may appear once")]
    DuplicateKey {
        /// The file's name.
        file: String,
        /// JSON path of the object.
        path: String,
        /// The repeated key.
        key: String,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
    },
    /// JSON of the wrong shape (a missing field, a string where a number belongs, ...).
    #[error("{file}: at {path}: {message} (line {line} column {column})")]
    Shape {
        /// The file's name.
        file: String,
        /// JSON path of the value.
        path: String,
        /// What was wrong and what was expected.
        message: String,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
    },
    /// `format` is not the expected one.
    #[error("{file}: `format` is {found:?}, expected \"{expected}\"")]
    WrongFormat {
        /// The file's name.
        file: String,
        /// The format found.
        found: String,
        /// The format expected.
        expected: &'static str,
    },
    /// `version` is not supported.
    #[error("{file}: `version` {found} is not supported: expected 1")]
    UnsupportedVersion {
        /// The file's name.
        file: String,
        /// The version found.
        found: String,
    },
    /// `units` is not one of the known units.
    #[error("{file}: `units` is {found:?}, expected \"in\", \"mm\", \"cm\" or \"m\"")]
    UnknownUnits {
        /// The file's name.
        file: String,
        /// The units found.
        found: String,
    },
    /// A value outside what is allowed.
    #[error("{file}: at {path}: got {value}, expected {expected}")]
    BadValue {
        /// The file's name.
        file: String,
        /// JSON path of the value.
        path: String,
        /// The value found, as text.
        value: String,
        /// What is allowed.
        expected: &'static str,
    },
    /// A snapshot's `ranges` has the wrong length.
    #[error("{file}: snapshot {snapshot} (snapshots[{snapshot}].ranges) has {found} ranges, expected one per sensor: {expected}")]
    RangeCount {
        /// The file's name.
        file: String,
        /// Snapshot index.
        snapshot: usize,
        /// Ranges given.
        found: usize,
        /// Sensors in the layout.
        expected: usize,
    },
    /// A range is negative or not finite.
    #[error("{file}: snapshot {snapshot}, sensor {sensor} (snapshots[{snapshot}].ranges[{sensor}]): range {value} is invalid, expected a finite number of at least 0 or null")]
    BadRange {
        /// The file's name.
        file: String,
        /// Snapshot index.
        snapshot: usize,
        /// Sensor index.
        sensor: usize,
        /// The value found.
        value: f64,
    },
    /// Time goes backwards.
    #[error("{file}: snapshot {snapshot} (snapshots[{snapshot}].t): time {t} is earlier than the previous snapshot's {previous}; `t` must not decrease")]
    TimeDecreases {
        /// The file's name.
        file: String,
        /// Snapshot index.
        snapshot: usize,
        /// Its time.
        t: f64,
        /// The previous snapshot's time.
        previous: f64,
    },
    /// A list that must not be empty is empty.
    #[error("{file}: at {path}: the list is empty, expected {expected}")]
    Empty {
        /// The file's name.
        file: String,
        /// JSON path of the list.
        path: String,
        /// What was expected.
        expected: &'static str,
    },
}
