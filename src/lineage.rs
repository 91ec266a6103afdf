//! Segment lineage: every event in a map segment's life (made, updated, split, merged,
//! correlated), indexed by segment while the replay runs, so the inspector can lead from a bad
//! segment to the decision that made it without rescanning any trace. Built from the slim
//! trace (decisions, updates, correlations), so it costs the replay little.

use crate::mapping::model::ext_trace::SeenThroughCut;
use crate::mapping::model::trace::{
    CorrelationKind, DecisionTrace, Outcome, StepTrace, UpdateTrace,
};
use crate::mapping::SegmentId;
use serde::{Deserialize, Serialize};

/// One event of a segment's life, at a snapshot.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", tag = "event")]
pub enum LineageEvent {
    /// Made by a NEW FACE decision for new segment `new_segment`.
    Created {
        /// Snapshot.
        snapshot: usize,
        /// The new segment (index in the step's trace).
        new_segment: usize,
    },
    /// Updated by a MATCH or EXTENSION of new segment `new_segment`.
    Updated {
        /// Snapshot.
        snapshot: usize,
        /// The new segment that caused it.
        new_segment: usize,
        /// MATCH or EXTENSION.
        outcome: Outcome,
        /// The post-update test failed and the points were fitted afresh.
        refit: bool,
    },
    /// A refit of this segment left piece `piece` beside it.
    SplitOff {
        /// Snapshot.
        snapshot: usize,
        /// The new piece.
        piece: SegmentId,
    },
    /// Made as a piece of `parent`: of its refit, or beyond a hole a reading saw through it
    /// (docs/algorithm.md §8.18).
    SplitFrom {
        /// Snapshot.
        snapshot: usize,
        /// The segment refitted.
        parent: SegmentId,
    },
    /// Fused `segment` into itself (`merge_duplicates`).
    Absorbed {
        /// Snapshot.
        snapshot: usize,
        /// The duplicate that left the map.
        segment: SegmentId,
    },
    /// Fused into `into` and left the map (`merge_duplicates`).
    AbsorbedInto {
        /// Snapshot.
        snapshot: usize,
        /// The segment it was fused into.
        into: SegmentId,
    },
    /// Tentative again: its refit moved it off the line its confirmation was for
    /// (`refit_unconfirms`, docs/algorithm.md §8.7).
    Unconfirmed {
        /// Snapshot.
        snapshot: usize,
    },
    /// Removed because sensor `sensor`'s reading saw through it (free space,
    /// docs/algorithm.md §8.6).
    Refuted {
        /// Snapshot.
        snapshot: usize,
        /// The sensor.
        sensor: usize,
    },
    /// Sensor `sensor`'s reading saw through part of it, which was cut away (docs/algorithm.md
    /// §8.18): an end moved, a hole left piece `piece` beside it, or nothing was left.
    SeenThrough {
        /// Snapshot.
        snapshot: usize,
        /// The sensor.
        sensor: usize,
        /// What became of it.
        cut: SeenThroughCut,
    },
    /// Removed as the diagonal of the corner of `walls` (docs/algorithm.md §8.11).
    CornerDiagonal {
        /// Snapshot.
        snapshot: usize,
        /// The two walls of the corner.
        walls: [SegmentId; 2],
    },
    /// A connecting segment removed because a segment it joined left the map
    /// (docs/algorithm.md §8.3).
    LinkDropped {
        /// Snapshot.
        snapshot: usize,
    },
    /// Correlated with `other` (§6): a corner, a connecting segment, or a shared end-point.
    Correlated {
        /// Snapshot.
        snapshot: usize,
        /// The segment at the other end of the closest pair.
        other: SegmentId,
        /// Index of the correlation in the step's trace.
        correlation: usize,
        /// The result.
        result: CorrelationResult,
    },
}

/// What a correlation made.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CorrelationResult {
    /// Both end-points moved to the lines' intersection.
    Corner,
    /// A connecting segment joins them.
    Link,
    /// They already coincided.
    Shared,
}

impl LineageEvent {
    /// The snapshot of the event.
    pub fn snapshot(&self) -> usize {
        match *self {
            LineageEvent::Created { snapshot, .. }
            | LineageEvent::Updated { snapshot, .. }
            | LineageEvent::SplitOff { snapshot, .. }
            | LineageEvent::SplitFrom { snapshot, .. }
            | LineageEvent::Absorbed { snapshot, .. }
            | LineageEvent::AbsorbedInto { snapshot, .. }
            | LineageEvent::Unconfirmed { snapshot, .. }
            | LineageEvent::Refuted { snapshot, .. }
            | LineageEvent::SeenThrough { snapshot, .. }
            | LineageEvent::CornerDiagonal { snapshot, .. }
            | LineageEvent::LinkDropped { snapshot }
            | LineageEvent::Correlated { snapshot, .. } => snapshot,
        }
    }
}

/// Every segment's events, in the order they happened, indexed by segment id.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Lineage {
    events: Vec<Vec<LineageEvent>>,
}

impl Lineage {
    fn push(&mut self, id: SegmentId, event: LineageEvent) {
        let i = id as usize;
        if self.events.len() <= i {
            self.events.resize_with(i + 1, Vec::new);
        }
        self.events[i].push(event);
    }

    /// Records what step `trace` did to the map (the slim trace suffices).
    pub fn record(&mut self, trace: &StepTrace) {
        let snapshot = trace.snapshot;
        let mut updates = trace.updates.iter();
        for d in &trace.decisions {
            match (d.outcome, d.result) {
                (Outcome::NewFace, Some(id)) => self.push(
                    id,
                    LineageEvent::Created {
                        snapshot,
                        new_segment: d.new_segment,
                    },
                ),
                (Outcome::Match | Outcome::Extension, Some(_)) => {
                    // Updates are traced in decision order, one per update made.
                    let Some(u) = updates
                        .as_slice()
                        .first()
                        .filter(|u| u.new_segment == d.new_segment)
                    else {
                        continue;
                    };
                    updates.next();
                    self.record_update(snapshot, d, u);
                }
                _ => {}
            }
        }
        self.record_after_matching(trace);
    }

    /// The events of update `u`, made by decision `d`: the update, the pieces its refit split
    /// off, the duplicates it absorbed.
    fn record_update(&mut self, snapshot: usize, d: &DecisionTrace, u: &UpdateTrace) {
        let pieces = u.refit.as_ref().map_or(&[][..], |r| &r.pieces[..]);
        self.push(
            u.segment,
            LineageEvent::Updated {
                snapshot,
                new_segment: d.new_segment,
                outcome: d.outcome,
                refit: u.refit.is_some(),
            },
        );
        for &piece in pieces.iter().filter(|&&p| p != u.segment) {
            self.push(u.segment, LineageEvent::SplitOff { snapshot, piece });
            self.push(
                piece,
                LineageEvent::SplitFrom {
                    snapshot,
                    parent: u.segment,
                },
            );
        }
        for a in &u.absorbed {
            self.push(
                a.into,
                LineageEvent::Absorbed {
                    snapshot,
                    segment: a.segment,
                },
            );
            self.push(
                a.segment,
                LineageEvent::AbsorbedInto {
                    snapshot,
                    into: a.into,
                },
            );
        }
    }

    /// The events of the step after matching.
    fn record_after_matching(&mut self, trace: &StepTrace) {
        let snapshot = trace.snapshot;
        // In the step's order: refits that lost their confirmation (§8.7), correlation (§6),
        // then free space (§8.6), corner diagonals (§8.11) and the links that left with a
        // segment (§8.3).
        for u in trace.unconfirmed.iter().filter(|u| !u.tentative) {
            self.push(u.segment, LineageEvent::Unconfirmed { snapshot });
        }
        for (correlation, c) in trace.correlations.iter().enumerate() {
            let result = match c.result {
                CorrelationKind::Corner { .. } => CorrelationResult::Corner,
                CorrelationKind::Interpolated { .. } => CorrelationResult::Link,
                CorrelationKind::Shared { .. } => CorrelationResult::Shared,
                CorrelationKind::None => continue,
            };
            if let (Some((n, _)), Some((e, _))) = (c.new_segment, c.existing_segment) {
                for (id, other) in [(n, e), (e, n)] {
                    self.push(
                        id,
                        LineageEvent::Correlated {
                            snapshot,
                            other,
                            correlation,
                            result,
                        },
                    );
                }
            }
        }
        for r in &trace.refuted {
            self.push(
                r.segment,
                LineageEvent::Refuted {
                    snapshot,
                    sensor: r.sensor,
                },
            );
        }
        for c in &trace.seen_through {
            self.push(
                c.segment,
                LineageEvent::SeenThrough {
                    snapshot,
                    sensor: c.sensor,
                    cut: c.cut,
                },
            );
            if let SeenThroughCut::Split { piece } = c.cut {
                self.push(
                    piece,
                    LineageEvent::SplitFrom {
                        snapshot,
                        parent: c.segment,
                    },
                );
            }
        }
        for d in &trace.diagonals {
            self.push(
                d.segment,
                LineageEvent::CornerDiagonal {
                    snapshot,
                    walls: d.walls,
                },
            );
        }
        for &link in &trace.dropped_links {
            self.push(link, LineageEvent::LinkDropped { snapshot });
        }
    }

    /// The events of segment `id` up to and including snapshot `until`, in order.
    pub fn of(&self, id: SegmentId, until: usize) -> &[LineageEvent] {
        let events = self.events.get(id as usize).map_or(&[][..], Vec::as_slice);
        let end = events.partition_point(|e| e.snapshot() <= until);
        &events[..end]
    }

    /// Events recorded in all.
    pub fn len(&self) -> usize {
        self.events.iter().map(Vec::len).sum()
    }

    /// True when nothing was recorded.
    pub fn is_empty(&self) -> bool {
        self.events.iter().all(Vec::is_empty)
    }
}
