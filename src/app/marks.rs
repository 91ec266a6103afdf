//! Timeline marks by kind: dismissals, extensions, warnings, correlations, direct differences
//! from the pinned baseline, and spurious creations. Each kind can be switched off (persisted);
//! the timeline draws, and prev/next mark follow, the kinds switched on.

use crate::diff::RunDiff;
use crate::replay::StepSummary;
use serde::{Deserialize, Serialize};

/// A kind of timeline mark.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum MarkKind {
    /// A new segment was dismissed.
    Dismissals,
    /// A new segment extended a map segment.
    Extensions,
    /// A warning (max_step, range count).
    Warnings,
    /// A correlation made a corner, a link or a shared end-point.
    Correlations,
    /// A decision differs directly from the pinned baseline.
    DirectDifferences,
    /// A new face `eval` calls spurious (with a floor plan).
    SpuriousCreations,
}

impl MarkKind {
    /// Every kind, in the order the filter lists them.
    pub const ALL: [MarkKind; 6] = [
        MarkKind::Dismissals,
        MarkKind::Extensions,
        MarkKind::Warnings,
        MarkKind::Correlations,
        MarkKind::DirectDifferences,
        MarkKind::SpuriousCreations,
    ];

    /// The filter's label.
    pub fn label(self) -> &'static str {
        match self {
            MarkKind::Dismissals => "dismissals",
            MarkKind::Extensions => "extensions",
            MarkKind::Warnings => "warnings",
            MarkKind::Correlations => "correlations",
            MarkKind::DirectDifferences => "direct differences",
            MarkKind::SpuriousCreations => "spurious creations",
        }
    }

    /// True when step `s` has a mark of this kind (A/B differences come from the comparison).
    fn marks_step(self, s: &StepSummary) -> bool {
        match self {
            MarkKind::Dismissals => s.dismissals > 0,
            MarkKind::Extensions => s.extensions > 0,
            MarkKind::Warnings => s.warnings > 0,
            MarkKind::Correlations => s.correlations > 0,
            MarkKind::SpuriousCreations => s.spurious_new_faces > 0,
            MarkKind::DirectDifferences => false,
        }
    }
}

/// The snapshots with a mark of each kind, ascending.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct MarksByKind {
    by_kind: Vec<(MarkKind, Vec<usize>)>,
}

impl MarksByKind {
    /// The marks of a replay's steps (`diff`: the comparison with the pinned baseline).
    pub fn of(summaries: &[StepSummary], diff: Option<&RunDiff>) -> Self {
        let by_kind = MarkKind::ALL
            .into_iter()
            .map(|kind| {
                let marks = match (kind, diff) {
                    (MarkKind::DirectDifferences, Some(d)) => d.direct_snapshots.clone(),
                    (MarkKind::DirectDifferences, None) => Vec::new(),
                    _ => summaries
                        .iter()
                        .enumerate()
                        .filter(|(_, s)| kind.marks_step(s))
                        .map(|(k, _)| k)
                        .collect(),
                };
                (kind, marks)
            })
            .collect();
        Self { by_kind }
    }

    /// The marks of `kind`.
    pub fn of_kind(&self, kind: MarkKind) -> &[usize] {
        self.by_kind
            .iter()
            .find(|(k, _)| *k == kind)
            .map_or(&[][..], |(_, m)| m.as_slice())
    }

    /// The snapshots with a mark of a kind not in `hidden`, ascending, each once.
    pub fn shown(&self, hidden: &[MarkKind]) -> Vec<usize> {
        let mut all: Vec<usize> = self
            .by_kind
            .iter()
            .filter(|(k, _)| !hidden.contains(k))
            .flat_map(|(_, m)| m.iter().copied())
            .collect();
        all.sort_unstable();
        all.dedup();
        all
    }
}

/// Marks thinned to a density strip: for each of `columns` columns over `len` snapshots, the
/// number of marks that fall in it.
pub fn density(marks: &[usize], len: usize, columns: usize) -> Vec<u32> {
    let columns = columns.max(1);
    let mut counts = vec![0u32; columns];
    let last = len.saturating_sub(1).max(1);
    for &m in marks {
        let c = (m.min(last) * (columns - 1)) / last;
        counts[c] += 1;
    }
    counts
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn marks_of_the_kinds_shown_merge_once_each() {
        let step = |dismissals, warnings| StepSummary {
            dismissals,
            warnings,
            ..StepSummary::default()
        };
        let summaries = [step(1, 0), step(0, 0), step(1, 1), step(0, 1)];
        let marks = MarksByKind::of(&summaries, None);
        assert_eq!(marks.of_kind(MarkKind::Dismissals), &[0, 2]);
        assert_eq!(marks.of_kind(MarkKind::Warnings), &[2, 3]);
        assert_eq!(marks.shown(&[]), vec![0, 2, 3]);
        assert_eq!(marks.shown(&[MarkKind::Warnings]), vec![0, 2]);
        assert!(marks.of_kind(MarkKind::DirectDifferences).is_empty());
    }

    #[test]
    fn density_counts_the_marks_of_each_column() {
        // 11 snapshots over 3 columns: 0..=4 → column 0, 5..=9 → 1, 10 → 2.
        assert_eq!(density(&[0, 1, 5, 9, 10], 11, 3), vec![2, 2, 1]);
    }
}
