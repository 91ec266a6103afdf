//! Property tests: random layouts, poses and ranges never panic, never produce non-finite
//! geometry, and the trace accounts for every reading and every new segment exactly once.

use proptest::prelude::*;
use sonarmap::geometry::Pose;
use sonarmap::mapping::{Mapper, Params};
use sonarmap::run::Snapshot;
use sonarmap::sonar::{SensorLayout, SensorMount, SensorSpec};

fn layout() -> impl Strategy<Value = SensorLayout> {
    prop::collection::vec((-0.5f64..0.5, -0.5f64..0.5, -7.0f64..7.0), 1..24).prop_map(|m| {
        SensorLayout {
            mounts: m
                .into_iter()
                .map(|(x_m, y_m, heading_rad)| SensorMount {
                    x_m,
                    y_m,
                    heading_rad,
                })
                .collect(),
        }
    })
}

fn range() -> impl Strategy<Value = Option<f64>> {
    prop_oneof![
        Just(None),
        (0.0f64..8.0).prop_map(Some),
        Just(Some(0.0)),
        Just(Some(1e6))
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]
    #[test]
    fn random_runs_stay_finite_and_fully_traced(
        layout in layout(),
        extended in any::<bool>(),
        steps in prop::collection::vec(((-3.0f64..3.0, -3.0f64..3.0, -7.0f64..7.0), prop::collection::vec(range(), 24)), 1..6),
    ) {
        let params = if extended { Params::extended() } else { Params::paper() };
        let n = layout.len();
        let mut mapper = Mapper::new(params, layout, SensorSpec::default());
        for (i, ((x, y, h), ranges)) in steps.into_iter().enumerate() {
            let snapshot = Snapshot { t: i as f64, pose: Pose::new(x, y, h), ranges_m: ranges[..n].to_vec() };
            let trace = mapper.step(&snapshot);
            prop_assert_eq!(trace.readings.len(), n);
            for (k, r) in trace.readings.iter().enumerate() {
                prop_assert_eq!(r.sensor, k);
                prop_assert_eq!(r.discarded.is_none(), r.cluster.is_some());
            }
            let clustered: usize = trace.clusters.iter().map(|c| c.sensors.len()).sum();
            prop_assert_eq!(clustered, trace.readings.iter().filter(|r| r.discarded.is_none()).count());
            prop_assert_eq!(trace.decisions.len(), trace.new_segments.len());
            for (i, d) in trace.decisions.iter().enumerate() {
                prop_assert_eq!(d.new_segment, i);
            }
            for s in &mapper.map().segments {
                for p in [s.a.point, s.b.point] {
                    prop_assert!(p.x.is_finite() && p.y.is_finite());
                }
                prop_assert!(s.a.range_m.is_finite() && s.b.range_m.is_finite());
            }
        }
    }
}
