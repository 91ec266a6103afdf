//! Property tests: random layouts, poses and ranges never panic, never produce non-finite
//! geometry, and the trace accounts for every reading and every new segment exactly once.

use proptest::prelude::*;
use sonarmap::geometry::Pose;
use sonarmap::mapping::{Mapper, Params, StepTrace};
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

fn wall_snapshots() -> impl Strategy<Value = Vec<(f64, f64, f64, Vec<Option<f64>>)>> {
    prop::collection::vec(
        (
            -0.1f64..0.25,
            -0.1f64..0.1,
            -0.2f64..0.2,
            prop::collection::vec(prop_oneof![Just(None), (0.3f64..4.0).prop_map(Some)], 16),
        ),
        2..30,
    )
}

/// A mapper of the chosen preset with orientation threshold `theta_deg` on a Nomad ring.
fn wall_mapper(extended: bool, theta_deg: f64) -> Mapper {
    let preset = if extended {
        Params::extended()
    } else {
        Params::paper()
    };
    let params = Params {
        orientation_rad: theta_deg.to_radians(),
        ..preset
    };
    Mapper::new(
        params,
        SensorLayout::nomad_ring(0.23),
        SensorSpec::default(),
    )
}

/// Steps `a` and `b` over the same snapshots (each pose relative to the last) and checks them
/// after every step with `check(trace_a, trace_b, a, b)`.
fn step_both(
    steps: Vec<(f64, f64, f64, Vec<Option<f64>>)>,
    a: &mut Mapper,
    b: &mut Mapper,
    check: impl Fn(&StepTrace, &StepTrace, &Mapper, &Mapper) -> Result<(), TestCaseError>,
) -> Result<(), TestCaseError> {
    let (mut x, mut y, mut h) = (0.0, 0.0, 0.0);
    for (i, (dx, dy, dh, ranges)) in steps.into_iter().enumerate() {
        x += dx;
        y += dy;
        h += dh;
        let snapshot = Snapshot {
            t: i as f64,
            pose: Pose::new(x, y, h),
            ranges_m: ranges,
        };
        let (ta, tb) = (a.step(&snapshot), b.step(&snapshot));
        check(&ta, &tb, a, b)?;
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(150))]
    /// The spatial index prunes only candidates that cannot pass: the decisions are the same as
    /// with every segment tested.
    #[test]
    fn indexed_search_and_brute_force_give_identical_decisions(
        steps in wall_snapshots(),
        extended in any::<bool>(),
        theta_deg in 1.0f64..60.0,
    ) {
        let mut indexed = wall_mapper(extended, theta_deg);
        let mut brute = wall_mapper(extended, theta_deg).with_brute_force_search(true);
        step_both(steps, &mut indexed, &mut brute, |a, b, indexed, brute| {
            // The rule may read "no candidates" where the brute force tested far segments in vain.
            let key = |t: &StepTrace| t.decisions.iter().map(|d| (d.outcome, d.existing, d.result)).collect::<Vec<_>>();
            prop_assert_eq!(key(a), key(b));
            prop_assert_eq!(&a.updates, &b.updates);
            prop_assert_eq!(&a.correlations, &b.correlations);
            prop_assert_eq!(&indexed.map().segments, &brute.map().segments);
            Ok(())
        })?;
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(100))]
    /// An untraced step (it skips the orientation test of candidates that cannot pass a rule and
    /// keeps no point-memory record) decides, updates and maps exactly as a traced one.
    #[test]
    fn untraced_steps_decide_and_map_as_traced_ones(
        steps in wall_snapshots(),
        extended in any::<bool>(),
        theta_deg in 1.0f64..60.0,
    ) {
        let mut traced = wall_mapper(extended, theta_deg);
        let mut untraced = wall_mapper(extended, theta_deg).with_trace(false);
        step_both(steps, &mut traced, &mut untraced, |a, b, traced, untraced| {
            let key = |t: &StepTrace| t.decisions.iter().map(|d| (d.outcome, d.rule, d.existing, d.result)).collect::<Vec<_>>();
            prop_assert_eq!(key(a), key(b));
            prop_assert_eq!(&a.updates, &b.updates);
            prop_assert_eq!(&a.correlations, &b.correlations);
            prop_assert_eq!(traced.map(), untraced.map());
            Ok(())
        })?;
    }
}
