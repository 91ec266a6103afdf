//! What a snapshot is drawn from: its step's trace (and the previous one's) and the maps before
//! and after it, made by stepping a mapper.

use crate::mapping::model::trace::StepTrace;
use crate::mapping::{Map, Mapper};
use crate::run::Snapshot;

/// Everything needed to draw snapshot `k`.
#[derive(Clone, Debug)]
pub struct StepView {
    /// The snapshot index.
    pub index: usize,
    /// The trace of step `k`.
    pub trace: StepTrace,
    /// The trace of step `k - 1` (its points are drawn as the previous snapshot's).
    pub previous: Option<StepTrace>,
    /// The map before step `k` (without its spatial index: [`Map::rebuild_index`] restores it).
    pub map_before: Map,
    /// The map after step `k` (without its spatial index).
    pub map_after: Map,
}

impl StepView {
    /// The view of snapshot `k`, stepping `mapper` (positioned just before snapshot `k - 1`, or
    /// before snapshot 0 when `k` is 0) through its last one or two snapshots with the full
    /// trace. The mapper is left after snapshot `k`, tracing as it was before.
    pub fn by_stepping(mapper: &mut Mapper, snapshots: &[Snapshot], k: usize) -> Self {
        assert_eq!(
            mapper.next_snapshot(),
            k.saturating_sub(1),
            "the mapper stands before snapshot k - 1"
        );
        let was_tracing = mapper.records_trace();
        mapper.set_trace(true);
        let previous = (k > 0).then(|| mapper.step(&snapshots[k - 1]));
        // Copies share the segments; the index is left out (drawing does not search).
        let map_before = mapper.map().without_index();
        let trace = mapper.step(&snapshots[k]);
        mapper.set_trace(was_tracing);
        Self {
            index: k,
            trace,
            previous,
            map_before,
            map_after: mapper.map().without_index(),
        }
    }
}

impl StepView {
    /// The view of the snapshot after `shown`'s, stepping `mapper` (standing just after
    /// `shown`'s snapshot) once with the full trace: `shown` already holds the previous step's
    /// trace and the map before. The mapper is left after the new snapshot.
    pub(super) fn after(mapper: &mut Mapper, shown: &StepView, snapshots: &[Snapshot]) -> Self {
        let k = shown.index + 1;
        assert_eq!(
            mapper.next_snapshot(),
            k,
            "the mapper stands after the shown snapshot"
        );
        let was_tracing = mapper.records_trace();
        mapper.set_trace(true);
        let trace = mapper.step(&snapshots[k]);
        mapper.set_trace(was_tracing);
        Self {
            index: k,
            trace,
            previous: Some(shown.trace.clone()),
            map_before: shown.map_after.clone(),
            map_after: mapper.map().without_index(),
        }
    }
}
