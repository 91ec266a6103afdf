//! The open run: where it came from, its replay and the snapshots marked on the timeline.

use super::marks::MarksByKind;
use crate::mapping::Params;
use crate::replay::Replay;
use crate::run::Run;
use std::path::PathBuf;
use std::sync::Arc;

/// Where the open run came from.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Source {
    /// Built into the binary (the Blue Room).
    BuiltIn(String),
    /// A file on disk.
    File(PathBuf),
    /// Bytes without a path (a dropped file).
    Bytes(String),
}

impl Source {
    /// Short name for the status bar and titles.
    pub fn display_name(&self) -> String {
        match self {
            Source::BuiltIn(name) | Source::Bytes(name) => name.clone(),
            Source::File(path) => path.display().to_string(),
        }
    }
}

/// A run and its replay.
pub(super) struct Loaded {
    pub(super) source: Source,
    pub(super) replay: Replay,
    /// The marks of the replay's steps, by kind (A/B differences come from the baseline).
    pub(super) marks: MarksByKind,
}

impl Loaded {
    /// `run` replayed under `params` on the spot.
    pub(super) fn prepare(run: Run, source: Source, params: &Params) -> Loaded {
        Self::new(Replay::new(Arc::new(run), params.clone()), source)
    }

    /// A finished replay, with its steps' marks.
    pub(super) fn new(replay: Replay, source: Source) -> Loaded {
        let marks = MarksByKind::of(replay.summaries(), None);
        Loaded {
            source,
            replay,
            marks,
        }
    }
}
