//! The mapper's settled-walls stage (docs/algorithm.md §8.12).

use crate::mapping::ext::settled_walls::{
    any_settling_wall, echo_at_range, settling_wall, SettleRule, SETTLED_END_MARGIN_GAPS,
};
use crate::mapping::model::trace::{SettledTrace, StepTrace};
use crate::mapping::step::StepBuffers;
use crate::mapping::Mapper;

impl Mapper {
    /// §8.12 settled walls: the kept points a confirmed wall explains well inside its ends (at
    /// least [`SETTLED_END_MARGIN_GAPS`] memory gaps from either end) leave `buffers.kept`:
    /// they join no cluster, no point memory and no free-space sweep of §8.6. They are noted in
    /// `buffers.settled_points` (the heading windows take them, §8.17).
    pub(in crate::mapping) fn set_aside_settled_readings(
        &self,
        trace: &mut StepTrace,
        buffers: &mut StepBuffers,
    ) {
        buffers.settled_points.clear();
        buffers.settled_echoes.clear();
        buffers.settled_readings.clear();
        if self.map.plane_support.is_empty() {
            return;
        }
        let (accuracy_pct, half_beam_rad) = self.accuracy_and_half_beam();
        let rule = SettleRule::new(
            accuracy_pct,
            half_beam_rad,
            self.plane_echo_model(),
            SETTLED_END_MARGIN_GAPS * self.params.memory_gap_m,
        );
        let (near, settled_by, settled_points, settled_echoes, settled_readings) = (
            &mut buffers.near_walls,
            &mut buffers.settled_by,
            &mut buffers.settled_points,
            &mut buffers.settled_echoes,
            &mut buffers.settled_readings,
        );
        let keep_readings = self.trims_seen_through();
        let keep_echoes = self.heading_windows_by_wall();
        settled_by.resize(self.layout.len(), None);
        buffers.kept.retain(|q| {
            let beam = self.step_beam_of(q);
            let hint = settled_by.get(q.reading.sensor()).copied().flatten();
            // Traced, the wall that predicts the range best, for the trace; with the walls'
            // windows too, whose echoes must join the same wall's window traced or not, and
            // after a checkpoint's restore (which starts the hints afresh); otherwise any.
            let segment = if self.record_trace || keep_echoes {
                let Some((segment, predicted_m, inside_m)) =
                    settling_wall(&self.map, &beam, &rule, near)
                else {
                    return true;
                };
                if self.record_trace {
                    trace.settled.push(SettledTrace {
                        sensor: q.reading.sensor(),
                        range_m: q.range_m,
                        segment,
                        predicted_m,
                        inside_m,
                    });
                }
                segment
            } else {
                let found = any_settling_wall(&self.map, &beam, &rule, hint, near);
                let Some(segment) = found else {
                    return true;
                };
                segment
            };
            if let Some(slot) = settled_by.get_mut(q.reading.sensor()) {
                *slot = Some(segment);
            }
            settled_points.push((q.reading.sensor(), q.point));
            if keep_echoes {
                let wall = self.map.segment(segment);
                let echo = wall.and_then(|w| echo_at_range(&beam, &w.a.point, &w.b.point, &rule));
                settled_echoes.extend(echo.map(|p| (segment, q.reading.sensor(), p)));
            }
            if keep_readings {
                settled_readings.push(*q);
            }
            false
        });
    }
}

#[cfg(test)]
mod tests {
    use crate::geometry::Pose;
    use crate::mapping::model::map::test_wall;
    use crate::mapping::model::map::{Map, SegmentId};
    use crate::mapping::model::plane_supports::PlaneSupport;
    use crate::mapping::model::plane_supports::CONFIRMING_SNAPSHOTS;
    use crate::mapping::{Mapper, MapperState, Params, StepTrace};
    use crate::run::Snapshot;
    use crate::sonar::SensorMount;
    use crate::sonar::{SensorLayout, SensorSpec};

    /// One sensor at the origin facing +y, over a map of the wall s0 along y = 2 (x from -2 to
    /// 2, confirmed when `wall_confirmed`) and the tentative segment s1 across the beam at
    /// y = 1 (x from -0.3 to 0.3); the sensor reads 2.0 m. Returns the step's trace and the map.
    fn read_the_wall(wall_confirmed: bool) -> (StepTrace, Map) {
        let layout = SensorLayout {
            mounts: vec![SensorMount {
                x_m: 0.0,
                y_m: 0.0,
                heading_rad: std::f64::consts::FRAC_PI_2,
            }],
        };
        let mut mapper = Mapper::new(Params::extended(), layout, SensorSpec::default());
        let mut map = Map::from_segments(vec![
            test_wall(0, (-2.0, 2.0), (2.0, 2.0), 2.0),
            test_wall(1, (-0.3, 1.0), (0.3, 1.0), 1.0),
        ]);
        map.confirms_segments = true;
        if wall_confirmed {
            map.plane_support.insert(
                0,
                PlaneSupport {
                    snapshots: CONFIRMING_SNAPSHOTS,
                    last_snapshot: 0,
                    ..Default::default()
                },
            );
        }
        mapper.restore(&MapperState {
            map,
            last_pose: None,
            last_t_s: None,
            pose_belief: Default::default(),
            last_echoes: Default::default(),
            next_snapshot: 1,
        });
        let trace = mapper.step(&Snapshot {
            t: 1.0,
            pose: Pose::new(0.0, 0.0, 0.0),
            ranges_m: vec![Some(2.0)],
            true_pose: None,
            reading_dt_s: Vec::new(),
        });
        (trace, mapper.map().clone())
    }

    #[test]
    fn a_settled_reading_sweeps_no_free_space_and_an_unsettled_one_does() {
        // s0 confirmed predicts 2.0 m (the foot (0, 2) on the axis, 2 m inside both ends): the
        // reading is settled. It would see through s1 (p = 1, 1 + 2·0.06 = 1.12 < 2), but the
        // space in front of a confirmed wall is not swept again: s1 stays.
        let (trace, map) = read_the_wall(true);
        assert_eq!(trace.settled.len(), 1);
        assert_eq!(trace.settled[0].segment, 0);
        assert!(trace.refuted.is_empty(), "{:?}", trace.refuted);
        assert!(map.segment(1).is_some());
        // s0 tentative: nothing settles the reading, which refutes s1 (and not s0: 2 + 0.12 > 2).
        let (trace, map) = read_the_wall(false);
        assert!(trace.settled.is_empty());
        let refuted: Vec<SegmentId> = trace.refuted.iter().map(|r| r.segment).collect();
        assert_eq!(refuted, vec![1]);
        assert!(map.segment(1).is_none() && map.segment(0).is_some());
    }
}
