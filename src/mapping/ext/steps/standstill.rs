//! A robot standing still adds no view (docs/algorithm.md §8.19): the step that sets its
//! readings aside.

use crate::geometry::Pose;
use crate::mapping::ext::standstill::stood_still;
use crate::mapping::model::ext_trace::StandstillTrace;
use crate::mapping::model::trace::StepTrace;
use crate::mapping::Mapper;

impl Mapper {
    /// After the step's pose, before its readings: true when `standstill` is on and the
    /// odometry (`odometry`, as the log gives it) stood still since the last mapped snapshot,
    /// noted in `trace`; the step then maps nothing. Otherwise this snapshot is the last mapped.
    pub(in crate::mapping) fn hook_stood_still(
        &mut self,
        odometry: &Pose,
        trace: &mut StepTrace,
    ) -> bool {
        let tolerance_m = self.params.standstill_m;
        if tolerance_m <= 0.0 {
            return false;
        }
        let still = self.map.last_mapped.and_then(|(since_snapshot, last)| {
            stood_still(&last, odometry, tolerance_m).map(|(moved_m, turned_rad)| StandstillTrace {
                since_snapshot,
                moved_m,
                turned_rad,
            })
        });
        match still {
            Some(still) => trace.stood_still = Some(still),
            None => self.map.last_mapped = Some((trace.snapshot, *odometry)),
        }
        still.is_some()
    }
}
