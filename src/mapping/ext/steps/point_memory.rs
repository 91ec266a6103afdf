//! The mapper's point-memory stage (docs/algorithm.md §8.1, §8.15, §8.16).

use crate::mapping::ext::memory_linkage::Linkage;
use crate::mapping::ext::point_memory::{memory_step, MemoryClock};
use crate::mapping::model::support::ReadingRef;
use crate::mapping::model::trace::{NewSegmentTrace, SegmentSource, StepTrace};
use crate::mapping::paper::fit::piece_end_points;
use crate::mapping::step::FittedStep;
use crate::mapping::Mapper;

impl Mapper {
    /// §8.1 point memory: this step's one-point clusters join the memory, and the pieces its
    /// groups yield become new segments after the clusters'.
    pub(in crate::mapping) fn fit_remembered_points(
        &mut self,
        fitted: &mut FittedStep,
        trace: &mut StepTrace,
        memory_readings: &mut Vec<ReadingRef>,
        linkage: &mut Linkage,
    ) {
        let (memory_trace, pieces) = memory_step(
            &mut self.map.memory,
            &fitted.singles,
            MemoryClock {
                snapshot: trace.snapshot,
                travelled_m: self.map.travelled_m,
            },
            &self.params,
            self.record_trace,
            linkage,
        );
        for piece in pieces {
            memory_readings.extend(
                piece
                    .points
                    .iter()
                    .map(|q| q.reading)
                    .filter(|r| r.snapshot() != trace.snapshot),
            );
            let last = piece.points.len() - 1;
            let (a, b) = piece_end_points(&piece.points, 0, last, self.params.fit);
            let mut new = NewSegmentTrace {
                source: SegmentSource::Memory(piece.group),
                a,
                b,
                points: piece.points,
            };
            if self.params.echo_fit && !self.place_echoes(&mut new, fitted.segments.len(), trace) {
                continue;
            }
            fitted.segments.push(new);
        }
        if self.record_trace {
            trace.memory = Some(memory_trace);
        }
    }
}
