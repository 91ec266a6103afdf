//! The mapper's free-space stage (docs/algorithm.md §8.6).

use crate::mapping::ext::free_space::refuted_segments;
use crate::mapping::model::trace::{RefutedTrace, StepTrace};
use crate::mapping::Mapper;

impl Mapper {
    /// §8.6 free space: the segments a kept reading of this snapshot saw past leave the map.
    pub(in crate::mapping) fn remove_refuted(&mut self, trace: &mut StepTrace) {
        let (xi, half) = self.accuracy_and_half_beam();
        let mut found = Vec::new();
        // §8.12: a settled reading has left `kept`; the space in front of its wall was swept.
        let buffers = self.buffers.take().unwrap_or_default();
        for q in &buffers.kept {
            let beam = self.step_beam_of(q);
            refuted_segments(&self.map, &beam, xi, half, &mut found);
            // Kept in the slim trace too: the lineage of a segment reads its removal there.
            for &(segment, distance_m, off_axis_rad) in &found {
                self.map.remove_segment(segment);
                trace.refuted.push(RefutedTrace {
                    segment,
                    sensor: q.reading.sensor(),
                    range_m: q.range_m,
                    distance_m,
                    off_axis_rad,
                });
            }
        }
        self.buffers = Some(buffers);
    }
}
