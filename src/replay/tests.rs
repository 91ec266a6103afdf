//! The replay's tests: views from checkpoints, cursors and thinned checkpoints all equal a
//! run from zero.

use super::*;
use crate::geometry::Pose;
use crate::run::Snapshot;
use crate::sonar::{SensorLayout, SensorSpec};
use crate::units::{inches, Units};

fn wall_run(n: usize) -> Run {
    // A wall at y = 40 in seen by the three sonars facing it while the robot drives.
    let layout = SensorLayout::nomad_ring(inches(9.0));
    let snapshots = (0..n)
        .map(|i| {
            let mut ranges_m = vec![None; 16];
            ranges_m[3] = Some(inches(31.0) / 67.5f64.to_radians().sin());
            ranges_m[4] = Some(inches(31.0));
            ranges_m[5] = Some(inches(31.0) / 112.5f64.to_radians().sin());
            Snapshot {
                t: i as f64,
                pose: Pose::new(inches(3.0 * i as f64), 0.0, 0.0),
                ranges_m,
                true_pose: None,
                reading_dt_s: Vec::new(),
            }
        })
        .collect();
    Run {
        name: "wall".into(),
        units: Units::Inches,
        robot_radius_m: Some(inches(9.0)),
        layout,
        sensor: SensorSpec::default(),
        floor_plan: None,
        snapshots,
    }
}

#[test]
fn over_budget_checkpoints_thin_where_seeking_is_cheap_and_every_view_is_the_same() {
    // Half the bytes the states every 3 snapshots keep: the store drops states as the run
    // goes on.
    let run = Arc::new(wall_run(60));
    let full = Replay::build(run.clone(), Params::paper(), 3, &mut |_| true).unwrap();
    let budget = full.checkpoint_bytes().0 / 2;
    let checkpoints = Checkpoints::new(3, budget);
    let thin =
        Replay::build_within(run.clone(), Params::paper(), checkpoints, &mut |_| true).unwrap();
    let (held, shortest, longest) = thin.checkpoint_spacing();
    assert!(held < full.checkpoint_spacing().0, "states were dropped");
    assert!(thin.checkpoint_bytes().0 <= budget);
    assert!(
        held > 2 && shortest >= 3 && longest >= shortest,
        "{shortest}..{longest}"
    );
    for k in 0..run.snapshots.len() {
        let (a, b) = (full.view(k).unwrap(), thin.view(k).unwrap());
        assert_eq!(a.trace, b.trace, "trace {k}");
        assert_eq!(a.map_after, b.map_after, "map {k}");
        // The slowest view from the checkpoint k's view starts from: at or after k, and
        // starting from that very checkpoint (a view of j restores the one before j − 1).
        let slowest = thin.slowest_view_like(k);
        assert!(slowest >= k && slowest < run.snapshots.len());
        let from = |j: usize| thin.checkpoints.snapshot_before(j.saturating_sub(1));
        assert_eq!(from(slowest), from(k), "{k} -> {slowest}");
        if slowest + 1 < run.snapshots.len() {
            assert_ne!(from(slowest + 1), from(k), "{slowest} is the last from it");
        }
    }
}

#[test]
fn view_from_a_checkpoint_equals_a_replay_from_zero() {
    let run = Arc::new(wall_run(40));
    let replay = Replay::build(run.clone(), Params::paper(), 7, &mut |_| true).unwrap();
    let mut mapper = Mapper::new(Params::paper(), run.layout.clone(), run.sensor);
    let mut previous = None;
    for k in 0..run.snapshots.len() {
        let before = mapper.map().clone();
        let trace = mapper.step(&run.snapshots[k]);
        let view = replay.view(k).unwrap();
        assert_eq!(view.trace, trace, "trace {k}");
        assert_eq!(view.map_before, before, "map before {k}");
        assert_eq!(&view.map_after, mapper.map(), "map after {k}");
        assert_eq!(view.previous, previous, "previous {k}");
        // The build steps with the slim trace; its summaries are the full trace's.
        let segments = mapper.map().segments.len();
        let mut summary = StepSummary::of(&trace, segments);
        summary.candidates = mapper.last_step_candidates() as u32;
        assert_eq!(replay.summaries()[k], summary, "summary {k}");
        previous = Some(trace);
    }
    assert_eq!(replay.final_map(), mapper.map());
    assert_eq!(replay.map_at(39), *mapper.map());
}

#[test]
fn views_through_a_cursor_equal_views_from_checkpoints_in_any_order() {
    let run = Arc::new(wall_run(60));
    let replay = Replay::build(run.clone(), Params::extended(), 16, &mut |_| true).unwrap();
    let other = Replay::build(run, Params::paper(), 16, &mut |_| true).unwrap();
    let mut cursor = ReplayCursor::default();
    let mut shown: Option<StepView> = None;
    // Forward by one (one traced step), forward within and beyond a checkpoint interval,
    // backwards, the same snapshot again, the ends.
    let order = [
        0, 1, 2, 3, 9, 10, 30, 29, 5, 5, 6, 59, 58, 0, 40, 41, 42, 57,
    ];
    for (i, &k) in order.iter().enumerate() {
        if i == 12 {
            // A view of another replay through the same cursor does not leak into this one.
            other.view_from(&mut cursor, None, 20);
        }
        let got = replay.view_from(&mut cursor, shown.as_ref(), k).unwrap();
        let want = replay.view(k).unwrap();
        assert_eq!(got.index, k);
        assert_eq!(got.trace, want.trace, "trace {k}");
        assert_eq!(got.previous, want.previous, "previous {k}");
        assert_eq!(got.map_before, want.map_before, "map before {k}");
        assert_eq!(got.map_after, want.map_after, "map after {k}");
        shown = Some(got);
    }
}

#[test]
fn views_caught_up_with_recorded_refits_equal_a_run_from_zero() {
    // The building asset's lap, driven back and forth: the paper's updates fail their
    // post-update test and refit often, and catching up takes those outcomes as recorded.
    let lap = crate::log::load_run(
        include_str!("../../assets/building.log.json").as_bytes(),
        "building.log.json",
    )
    .unwrap();
    let run = Arc::new(crate::bench::back_and_forth(&lap, 2 * lap.snapshots.len()));
    for params in [Params::paper(), Params::extended()] {
        let replay = Replay::build(run.clone(), params.clone(), 8, &mut |_| true).unwrap();
        let mut mapper = Mapper::new(params, run.layout.clone(), run.sensor);
        let mut refits = 0;
        for (k, s) in run.snapshots.iter().enumerate() {
            let trace = mapper.step(s);
            refits += trace.updates.iter().filter(|u| u.refit.is_some()).count();
            if k % 3 == 2 {
                assert_eq!(replay.view(k).unwrap().map_after, *mapper.map(), "{k}");
            }
        }
        assert!(refits > 0, "the run refits");
    }
}

#[test]
fn a_value_dropped_in_the_background_is_dropped_soon() {
    let held = Arc::new(());
    for _ in 0..3 {
        drop_in_background(Arc::clone(&held));
    }
    let start = std::time::Instant::now();
    while Arc::strong_count(&held) > 1 {
        assert!(start.elapsed().as_secs() < 10, "still held after 10 s");
        std::thread::sleep(std::time::Duration::from_millis(1));
    }
}

#[test]
fn build_can_be_cancelled() {
    let run = Arc::new(wall_run(10));
    let r = Replay::build(run, Params::paper(), 4, &mut |done| done < 5);
    assert_eq!(r.err(), Some(Cancelled));
}

#[test]
fn views_with_echo_agreement_equal_a_replay_from_zero() {
    // Every fifth snapshot, sonar 4 hears a short crosstalk echo that `echo_agreement`
    // (§8.21) sets aside; a mapper restored from the state before any step, and a view from
    // the checkpoints, must compare each reading with the same last echo as the run from zero.
    let mut run = wall_run(40);
    for s in run.snapshots.iter_mut().step_by(5).skip(1) {
        s.ranges_m[4] = Some(inches(12.0));
    }
    let run = Arc::new(run);
    let params = Params {
        echo_agreement: true,
        ..Params::extended()
    };
    let replay = Replay::build(run.clone(), params.clone(), 7, &mut |_| true).unwrap();
    let mut mapper = Mapper::new(params.clone(), run.layout.clone(), run.sensor);
    let mut set_aside = 0;
    for k in 0..run.snapshots.len() {
        // A mapper restored from the state before a crosstalk step refuses it as the run does.
        let mut restored = Mapper::new(params.clone(), run.layout.clone(), run.sensor);
        restored.restore(&mapper.state());
        let trace = mapper.step(&run.snapshots[k]);
        assert_eq!(restored.step(&run.snapshots[k]), trace, "restored {k}");
        set_aside += trace
            .readings
            .iter()
            .filter(|r| {
                r.discarded == Some(crate::mapping::model::trace::DiscardReason::ShorterThanLast)
            })
            .count();
        assert_eq!(replay.view(k).unwrap().trace, trace, "trace {k}");
    }
    assert_eq!(set_aside, 7, "the crosstalk echoes");
}
