//! Which curves the run plots show: a persisted setting, chosen in the plots' menu.

use crate::replay::{StepPose, StepSummary};
use serde::{Deserialize, Serialize};

/// A curve: its name and its value at a step.
type Series = (&'static str, fn(&StepSummary) -> u32);

/// A curve of the pose correction: its name and its value at a step.
type PoseSeries = (&'static str, fn(&StepPose) -> f32);

/// What the plots show.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RunPlot {
    /// Segments in the map after each step.
    #[default]
    Segments,
    /// Decisions by outcome.
    Decisions,
    /// Readings kept and discarded.
    Readings,
    /// The step's matching work: candidates offered to its new segments.
    StepCost,
    /// New faces that `eval` calls spurious (with a floor plan).
    Spurious,
    /// The map's spurious fraction and coverage (with a floor plan; sampled every checkpoint
    /// interval).
    Truth,
    /// Pose correction (§8.17): each step's correction and the drift taken out, metres.
    Correction,
    /// Pose correction's residual RMS before and after, in sigmas.
    Residual,
}

impl RunPlot {
    /// Every plot.
    pub const ALL: [RunPlot; 8] = [
        RunPlot::Segments,
        RunPlot::Decisions,
        RunPlot::Readings,
        RunPlot::StepCost,
        RunPlot::Spurious,
        RunPlot::Truth,
        RunPlot::Correction,
        RunPlot::Residual,
    ];

    /// The plot's name in the menu.
    pub(super) fn label(self) -> &'static str {
        match self {
            RunPlot::Segments => "Segments",
            RunPlot::Decisions => "Decisions",
            RunPlot::Readings => "Readings",
            RunPlot::StepCost => "Step cost",
            RunPlot::Spurious => "Spurious new faces",
            RunPlot::Truth => "Spurious fraction, coverage",
            RunPlot::Correction => "Pose correction",
            RunPlot::Residual => "Correction residuals",
        }
    }

    /// The curves: name and value per step.
    pub(super) fn series(self) -> Vec<Series> {
        match self {
            RunPlot::Segments => vec![("segments", |s| s.segments)],
            RunPlot::Decisions => vec![
                ("match", |s| s.matches),
                ("extension", |s| s.extensions),
                ("dismissed", |s| s.dismissals),
                ("new face", |s| s.new_faces),
            ],
            RunPlot::Readings => vec![("kept", |s| s.kept), ("discarded", |s| s.discarded)],
            RunPlot::StepCost => vec![("candidates offered", |s| s.candidates)],
            RunPlot::Spurious => vec![("spurious new faces", |s| s.spurious_new_faces)],
            RunPlot::Truth | RunPlot::Correction | RunPlot::Residual => Vec::new(),
        }
    }

    /// The curves of the pose correction: name and value per step.
    pub(super) fn pose_series(self) -> Vec<PoseSeries> {
        match self {
            RunPlot::Correction => vec![
                ("correction, m", |p| p.correction_m),
                ("corrected from odometry, m", |p| p.from_odometry_m),
            ],
            RunPlot::Residual => vec![
                ("residual RMS before, σ", |p| p.rms_before),
                ("residual RMS after, σ", |p| p.rms_after),
            ],
            _ => Vec::new(),
        }
    }

    /// True for the plots of the pose correction (empty on a run mapped without it).
    pub(super) fn needs_correction(self) -> bool {
        matches!(self, RunPlot::Correction | RunPlot::Residual)
    }
}
