//! Errors of the importers. Every message names the file, the place (line, field, MCAP message
//! index and topic) and what was expected.

use super::sane::escape;
use crate::log::LogError;
use thiserror::Error;

/// A recorded run (or a layout file) that cannot be imported.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum ImportError {
    /// Something at a known place is not what the format says.
    #[error("{file}: {place}: {message}")]
    At {
        /// The file's name.
        file: String,
        /// Where: `line 12`, `line 12, field 7`, `MCAP message 3 (topic /sonar_0)`.
        place: String,
        /// What was found and what was expected.
        message: String,
    },
    /// The file has no sensor geometry and none was given.
    #[error("{file}: {what}; give the sensor layout with --layout LAYOUT.json (a `sonarmap-layout` file, e.g. assets/pioneer_8_8.layout.json)")]
    NeedsLayout {
        /// The file's name.
        file: String,
        /// What is missing.
        what: String,
    },
    /// The file has no odometry and no fixed pose was asked for.
    #[error("{file}: no odometry ({what}); the robot's pose is unknown. To import anyway with the robot standing still, give --fixed-pose X,Y,HEADING_DEG")]
    NoOdometry {
        /// The file's name.
        file: String,
        /// Which messages were looked for.
        what: String,
    },
    /// Nothing usable in the file.
    #[error("{file}: no snapshot could be made: {why}")]
    NoSnapshots {
        /// The file's name.
        file: String,
        /// Why.
        why: String,
    },
    /// The content matches no known format.
    #[error("{file}: not a recognised run: {detail}")]
    Unrecognised {
        /// The file's name.
        file: String,
        /// Why no importer reads it: the line none could read and what each expected there,
        /// or that the file is empty or not text.
        detail: String,
    },
    /// An option that cannot be used.
    #[error("{option}: {message}")]
    BadOption {
        /// The option, e.g. `--max-range`.
        option: String,
        /// What is wrong.
        message: String,
    },
    /// A `sonarmap-log` or `sonarmap-layout` JSON file that cannot be used.
    #[error(transparent)]
    Json(#[from] LogError),
}

/// `ImportError::At` from its parts; control characters in them are escaped (they may quote
/// the file).
pub(crate) fn at(file: &str, place: impl Into<String>, message: impl Into<String>) -> ImportError {
    ImportError::At {
        file: escape(file),
        place: escape(&place.into()),
        message: escape(&message.into()),
    }
}
