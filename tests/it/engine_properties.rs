//! Property tests: random layouts, poses and ranges never panic, never produce non-finite
//! geometry, and the trace accounts for every reading and every new segment exactly once.

use super::support::layout_of;
use proptest::prelude::*;
use sonarmap::geometry::Pose;
use sonarmap::mapping::{Mapper, Params, StepTrace};
use sonarmap::run::Snapshot;
use sonarmap::sonar::{SensorLayout, SensorSpec};

fn layout() -> impl Strategy<Value = SensorLayout> {
    prop::collection::vec((-0.5f64..0.5, -0.5f64..0.5, -7.0f64..7.0), 1..24).prop_map(layout_of)
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
            let snapshot = Snapshot { t: i as f64, pose: Pose::new(x, y, h), ranges_m: ranges[..n].to_vec(), true_pose: None, reading_dt_s: Vec::new() };
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
            true_pose: None,
            reading_dt_s: Vec::new(),
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

/// Snapshots of each generated lap run in the test budget (`sonarmap soak` runs millions).
const LAP_RUN_SNAPSHOTS: usize = 400;

#[test]
fn every_scene_kind_in_every_parameter_set_keeps_the_map_consistent_over_laps() {
    // Six kinds × every parameter set (both presets, each extension flag alone), the map
    // checked after every step (these maps stay under SEGMENT_CHECKS_PER_STEP segments); the
    // report counts what failed.
    let report = sonarmap::soak::soak(1, LAP_RUN_SNAPSHOTS, 3, &mut |_| true).unwrap();
    let variants = sonarmap::soak::soak_variants().len();
    assert_eq!(report.runs, 6 * variants);
    assert_eq!(report.snapshots, 6 * variants * LAP_RUN_SNAPSHOTS);
    assert!(report.largest_map < sonarmap::soak::SEGMENT_CHECKS_PER_STEP);
    assert_eq!(report.invariant_checks, report.snapshots);
    assert_eq!(report.failures, vec![], "panics or broken invariants");
}

#[test]
fn drifting_lap_runs_at_a_crawl_with_multipath_keep_the_map_consistent() {
    // Every kind crawling 2 cm a cycle, the sonars fired in four groups, their rays mirrored
    // off up to two surfaces that do not echo them, with the bad drift of a differential-drive
    // robot carried over the laps, in both presets and with pose correction
    // (docs/algorithm.md §8.17).
    let conditions = sonarmap::suite::Conditions {
        drift: Some(sonarmap::sim::OdometryError::BAD),
        pace: sonarmap::sim::Pace {
            cycle_step_m: Some(0.02),
            cycle_s: 0.3,
            firing_groups: 4,
            ..sonarmap::sim::Pace::PLAN
        },
        bounces: Some(2),
    };
    // An even seed: the soak's runs take the specular model, the one whose rays bounce.
    let seed = 8;
    let only = ["paper", "extended"].map(String::from);
    let report = sonarmap::soak::soak_variants_named(
        1,
        LAP_RUN_SNAPSHOTS,
        seed,
        &only,
        &conditions,
        &mut |_| true,
    )
    .unwrap();
    assert_eq!(report.runs, 6 * only.len());
    assert_eq!(report.invariant_checks, report.snapshots);
    assert_eq!(report.failures, vec![], "panics or broken invariants");
    // From the first step, and from the odometry a calibration mends (§8.17).
    let from_first_step = Params {
        pose_correction: true,
        calibrate_first: false,
        ..Params::extended()
    };
    let from_calibrated = Params {
        pose_correction: true,
        ..Params::extended().calibrated_by((0.2, 1.5))
    };
    for kind in sonarmap::sim::SceneKind::ALL {
        let run = sonarmap::soak::family_run_under(kind, seed, LAP_RUN_SNAPSHOTS, &conditions);
        for corrected in [&from_first_step, &from_calibrated] {
            let checked = sonarmap::soak::map_checked(&run, corrected, true);
            assert_eq!(checked.failure, None, "{kind:?} with pose correction");
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(8))]
    #[test]
    fn generated_lap_runs_never_panic_nor_break_an_invariant(
        kind in prop::sample::select(sonarmap::sim::SceneKind::ALL.to_vec()),
        seed in any::<u64>(),
        variant in 0usize..7,
    ) {
        let (name, params) = sonarmap::soak::soak_variants().swap_remove(variant);
        let run = sonarmap::soak::family_run(kind, seed, LAP_RUN_SNAPSHOTS);
        let checked = sonarmap::soak::map_checked(&run, &params, true);
        prop_assert_eq!(checked.failure, None, "{:?} seed {} with {}", kind, seed, name);
        prop_assert_eq!(checked.steps, LAP_RUN_SNAPSHOTS);
        prop_assert_eq!(checked.checks, LAP_RUN_SNAPSHOTS, "checked after every step");
    }
}

/// Regression: with `merge_duplicates` on, a NEW FACE segment made early in a snapshot could be
/// absorbed by a later update of the same snapshot; its emptied face was dropped at once, and
/// the next NEW FACE of the same cluster panicked with "face exists" (snapshot 61 of this
/// corridor with three doors, in `extended` and in `paper` with merging).
#[test]
fn a_new_face_whose_first_segment_was_merged_away_in_the_same_snapshot_keeps_its_face() {
    use sonarmap::mapping::model::trace::{Outcome, SegmentSource};
    let bytes = include_bytes!("../fixtures/corridor_three_doors.plan.json");
    let plan = sonarmap::sim::load_plan(bytes, "corridor_three_doors.plan.json").unwrap();
    let lap = sonarmap::sim::simulate(&plan, sonarmap::sim::Model::Specular, 20);
    let run = sonarmap::sim::repeat_laps(&lap, 2 * lap.snapshots.len());
    let merging = Params {
        merge_duplicates: true,
        ..Params::paper()
    };
    // `extended` with the long-run bounds of §8.3 but without the rules of §8.5–§8.8, which
    // keep most of this corridor's readings out of new faces, and with the paper's fit (§8.13
    // places the pieces elsewhere, and the scene no longer arises).
    let bounds = Params {
        fit: sonarmap::mapping::model::params::FitMode::EndPoints,
        arc_features: false,
        explain_readings: false,
        free_space: false,
        confirm_segments: false,
        plane_gate: false,
        echo_fit: false,
        corner_diagonals: false,
        settled_walls: false,
        baseline_confirm: false,
        refit_unconfirms: false,
        min_piece_points: 0,
        ..Params::extended()
    };
    for params in [bounds, merging] {
        let mut mapper = Mapper::new(params.clone(), run.layout.clone(), run.sensor);
        let mut rejoined = 0;
        for snapshot in &run.snapshots {
            let trace = mapper.try_step(snapshot).expect("no step fails");
            mapper
                .map()
                .check_invariants(params.support_cap)
                .unwrap_or_else(|e| panic!("after snapshot {}: {e}", trace.snapshot));
            // The scene that broke: a segment made by this step's NEW FACE of a cluster is
            // absorbed, and a later NEW FACE of the same cluster joins that face.
            let absorbed: Vec<u32> = trace
                .updates
                .iter()
                .flat_map(|u| u.absorbed.iter().map(|a| a.segment))
                .collect();
            let source_of = |result: Option<u32>| {
                trace
                    .decisions
                    .iter()
                    .find(|d| d.outcome == Outcome::NewFace && d.result == result)
                    .map(|d| trace.new_segments[d.new_segment].source)
            };
            for (i, d) in trace.decisions.iter().enumerate() {
                let Some(gone) = d.result.filter(|id| absorbed.contains(id)) else {
                    continue;
                };
                let Some(SegmentSource::Cluster(c)) = source_of(Some(gone)) else {
                    continue;
                };
                rejoined += trace.decisions[i + 1..]
                    .iter()
                    .filter(|later| {
                        later.outcome == Outcome::NewFace
                            && trace.new_segments[later.new_segment].source
                                == SegmentSource::Cluster(c)
                    })
                    .count();
            }
        }
        assert!(rejoined > 0, "the run still meets the scene that panicked");
    }
}

#[test]
fn a_steps_cost_counts_at_least_every_candidate_its_decisions_tested() {
    use sonarmap::replay::Replay;
    let run = sonarmap::soak::family_run(sonarmap::sim::SceneKind::CorridorWithDoors, 9, 300);
    let replay = Replay::new(std::sync::Arc::new(run), Params::paper());
    let mut offered_any = false;
    for k in (0..replay.len()).step_by(7) {
        let view = replay.view(k).unwrap();
        let tested: usize = view.trace.decisions.iter().map(|d| d.mpc_stage.len()).sum();
        let cost = replay.summaries()[k].candidates as usize;
        assert!(cost >= tested, "step {k}: {cost} offered, {tested} tested");
        offered_any |= cost > 0;
    }
    assert!(offered_any);
}

#[test]
fn untraced_lap_runs_map_as_traced_ones_in_every_scene_kind() {
    // Every extension, on runs long enough to confirm walls, settle readings and fill point
    // memory: an untraced step keeps fewer records, and the maps must not notice.
    for kind in sonarmap::sim::SceneKind::ALL {
        let run = sonarmap::soak::family_run(kind, 3, 600);
        let mut traced = Mapper::new(Params::extended(), run.layout.clone(), run.sensor);
        let mut untraced =
            Mapper::new(Params::extended(), run.layout.clone(), run.sensor).with_trace(false);
        for (k, s) in run.snapshots.iter().enumerate() {
            traced.step(s);
            untraced.step(s);
            assert_eq!(traced.map(), untraced.map(), "{kind:?} after snapshot {k}");
        }
    }
}

#[test]
fn thinned_checkpoints_show_every_snapshot_as_a_replay_from_zero_does_in_every_scene_kind() {
    // Checkpoints every 8 snapshots within a third of the bytes they would keep: the store
    // drops states as each run goes on, and every view must still be the run's own.
    use sonarmap::checkpoints::Checkpoints;
    use sonarmap::replay::Replay;
    use std::sync::Arc;
    for (i, kind) in sonarmap::sim::SceneKind::ALL.into_iter().enumerate() {
        let params = if i % 2 == 0 {
            Params::paper()
        } else {
            Params::extended()
        };
        let run = Arc::new(sonarmap::soak::family_run(kind, 5, 240));
        let full = Replay::build(run.clone(), params.clone(), 8, &mut |_| true).unwrap();
        let budget = full.checkpoint_bytes().0 / 3;
        let thin = Replay::build_within(
            run.clone(),
            params.clone(),
            Checkpoints::new(8, budget),
            &mut |_| true,
        )
        .unwrap();
        let (held, shortest, _) = thin.checkpoint_spacing();
        assert!(
            held < full.checkpoint_spacing().0,
            "{kind:?}: states were dropped"
        );
        // Within the budget, unless down to the two states that always stay.
        assert!(thin.checkpoint_bytes().0 <= budget || held == 2, "{kind:?}");
        assert!(shortest >= 8 && shortest % 8 == 0, "{kind:?}: {shortest}");
        for k in (0..run.snapshots.len()).step_by(11) {
            // The snapshot itself, and the last of its interval (the longest catch-up).
            for k in [k, thin.slowest_view_like(k)] {
                let (a, b) = (full.view(k).unwrap(), thin.view(k).unwrap());
                assert_eq!(a.trace, b.trace, "{kind:?}, trace {k}");
                assert_eq!(a.map_after, b.map_after, "{kind:?}, map {k}");
            }
        }
    }
}
