//! §8.21 in a step: readings much shorter than their sensor's last are set aside before they
//! are clustered (`echo_agreement`), and each step's ranges are kept for the next.

use crate::geometry::wrap_pi;
use crate::mapping::ext::echo_agreement::{shorter_than_last, shorter_tolerance_m, LastEchoes};
use crate::mapping::model::trace::{DiscardReason, ShorterThanLastTrace, StepTrace};
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
            let last_m = last.ranges_m.get(sensor).copied().flatten();
            let tolerance_m = last_m.map_or(0.0, |last_m| {
                shorter_tolerance_m(q.range_m, last_m, accuracy_pct, driven_m, turned_rad)
            });
            let refused = shorter_than_last(q.range_m, last_m, tolerance_m);
            if let (true, Some(last_m)) = (refused, last_m) {
                let reading = &mut trace.readings[sensor];
                reading.discarded = Some(DiscardReason::ShorterThanLast);
                reading.shorter_than_last = Some(ShorterThanLastTrace {
                    last_m,
                    tolerance_m,
                });
            }
            !refused
        });
    }

    /// §8.21: keeps `snapshot`'s echoes (finite, under the sensor's maximum range) and the
    /// odometry's moment, for the next step.
    pub(super) fn remember_echoes(&mut self, snapshot: &Snapshot) {
        let max_range_m = self.sensor.max_range_m;
        let echo = |r: &Option<f64>| r.filter(|d| d.is_finite() && *d < max_range_m);
        self.last_echoes = LastEchoes {
            ranges_m: snapshot.ranges_m.iter().map(echo).collect(),
            read_at: Some(self.odometry_moment(&snapshot.pose)),
        };
    }
}
