//! What an import did: counts, skipped input with reasons, warnings.

use super::sane::escape;
use crate::run::Run;
use std::fmt;

/// The kind of input an importer read.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// A `sonarmap-log` JSON run log (loaded, not imported).
    SonarmapLog,
    /// A Player/Stage text log (Player 1.x, 2 or 3).
    Player,
    /// A ROS 2 MCAP recording.
    Mcap,
    /// A plain table of numbers, a ring a line.
    Table,
    /// A plain table of numbers, one reading a line.
    FiringTable,
}

impl Format {
    /// A short name for messages.
    pub fn name(self) -> &'static str {
        match self {
            Format::SonarmapLog => "sonarmap-log JSON",
            Format::Player => "Player/Stage text log",
            Format::Mcap => "ROS 2 MCAP",
            Format::Table => "table",
            Format::FiringTable => "table of firings (one reading a line)",
        }
    }
}

/// Input that was read but not used, and why.
#[derive(Clone, Debug, PartialEq)]
pub struct Skipped {
    /// Where: `line 12`, `MCAP message 40 (topic /sonar_3)`.
    pub place: String,
    /// Why it was left out.
    pub reason: String,
}

/// The counts of an import, printed by `sonarmap convert`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ImportSummary {
    /// Snapshots made.
    pub snapshots: usize,
    /// Readings in them (one per sensor and snapshot, echoes and no echoes).
    pub readings: usize,
    /// Readings at or beyond the maximum range (or outside a ROS message's
    /// `[min_range, max_range]`, or infinite) turned into no echo.
    pub turned_no_echo: usize,
    /// Lines or messages left out, with the reason.
    pub skipped: Vec<Skipped>,
    /// Anything else the user should know.
    pub warnings: Vec<String>,
    /// Skipped places beyond the first `KEPT` (counted, not kept: a hostile file must not
    /// grow the summary without bound).
    pub skipped_more: usize,
    /// Warnings beyond the first `KEPT`.
    pub warnings_more: usize,
}

/// How many skipped places and warnings a summary keeps (the rest are counted).
pub const KEPT: usize = 1000;

impl ImportSummary {
    /// Records input left out.
    pub fn skip(&mut self, place: impl Into<String>, reason: impl Into<String>) {
        if self.skipped.len() >= KEPT {
            self.skipped_more += 1;
            return;
        }
        self.skipped.push(Skipped {
            place: escape(&place.into()),
            reason: escape(&reason.into()),
        });
    }

    /// Records a warning.
    pub fn warn(&mut self, warning: impl Into<String>) {
        if self.warnings.len() >= KEPT {
            self.warnings_more += 1;
            return;
        }
        self.warnings.push(escape(&warning.into()));
    }
}

/// Shows the counts, then up to 20 skipped places and every warning, one a line.
impl fmt::Display for ImportSummary {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        write!(
            f,
            "snapshots {}, readings {}, turned into no echo {}, skipped {}, warnings {}",
            self.snapshots,
            self.readings,
            self.turned_no_echo,
            self.skipped.len() + self.skipped_more,
            self.warnings.len() + self.warnings_more
        )?;
        for s in self.skipped.iter().take(20) {
            write!(f, "\n  skipped {}: {}", s.place, s.reason)?;
        }
        let more = self.skipped.len() + self.skipped_more;
        if more > 20 {
            write!(f, "\n  ... and {} more skipped", more - 20)?;
        }
        for w in &self.warnings {
            write!(f, "\n  warning: {w}")?;
        }
        if self.warnings_more > 0 {
            write!(f, "\n  ... and {} more warnings", self.warnings_more)?;
        }
        Ok(())
    }
}

/// A run read from a recording, with what the import did.
#[derive(Clone, Debug, PartialEq)]
pub struct Imported {
    /// The run, in metres.
    pub run: Run,
    /// What the import did.
    pub summary: ImportSummary,
    /// What was read.
    pub format: Format,
}
