//! §8.21 in a step: readings much shorter than their sensor's last are set aside before they
//! are clustered (`echo_agreement`), and each step's ranges are kept for the next.

use crate::geometry::wrap_pi;
use crate::mapping::ext::echo_agreement::{shorter_than_last, shorter_tolerance_m, LastEchoes};
use crate::mapping::model::trace::{DiscardReason, ReadingTrace, ShorterThanLastTrace, StepTrace};
use crate::mapping::step::StepBuffers;
use crate::mapping::Mapper;
use crate::run::Snapshot;

impl Mapper {
    /// §8.21: drops from `buffers.kept` each reading much shorter than its sensor's last echo
    /// ([`shorter_than_last`]), the trace saying so with the last echo and the tolerance.
    pub(super) fn drop_shorter_than_last(
        &self,
        snapshot: &Snapshot,
        trace: &mut StepTrace,
        buffers: &mut StepBuffers,
    ) {
        let last = &self.last_echoes;
        let Some(before) = last.read_at else {
            return;
        };
        let now = self.odometry_moment(&snapshot.pose);
        let driven_m = now.travelled_m - before.travelled_m;
        let turned_rad = wrap_pi(now.heading_rad - before.heading_rad);
        let accuracy_pct = self.params.accuracy_pct;
        buffers.kept.retain(|q| {
            let sensor = q.reading.sensor();
            // Without a last echo nothing is refused.
            let Some(last_m) = last.ranges_m.get(sensor).copied().flatten() else {
                return true;
            };
            let tolerance_m =
                shorter_tolerance_m(q.range_m, last_m, accuracy_pct, driven_m, turned_rad);
            if !shorter_than_last(q.range_m, last_m, tolerance_m) {
                return true;
            }
            let reading = &mut trace.readings[sensor];
            reading.discarded = Some(DiscardReason::ShorterThanLast);
            reading.shorter_than_last = Some(ShorterThanLastTrace {
                last_m,
                tolerance_m,
            });
            false
        });
    }

    /// §8.21: keeps the step's echoes (its readings' ranges but where the sensor heard none,
    /// [`DiscardReason::means_no_echo`]) and the odometry's moment of `snapshot`, for the next
    /// step.
    pub(super) fn remember_echoes(&mut self, snapshot: &Snapshot, trace: &StepTrace) {
        let echo = |r: &ReadingTrace| {
            r.range_m
                .filter(|_| !r.discarded.is_some_and(DiscardReason::means_no_echo))
        };
        self.last_echoes = LastEchoes {
            ranges_m: trace.readings.iter().map(echo).collect(),
            read_at: Some(self.odometry_moment(&snapshot.pose)),
        };
    }
}
