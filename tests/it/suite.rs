//! `eval --suite`: the extended preset on generated family scenes, both sensor models, against
//! the bounds measured when its extensions were chosen (docs/algorithm.md §8.5–§8.8), with a
//! margin. Seeded, so the figures are the same on every machine.

use sonarmap::mapping::Params;
use sonarmap::sim::{simulate, Model};
use sonarmap::soak::map_checked;
use sonarmap::suite::{run_suite, suite_plans, summarise, SuiteLine};

fn of_model(lines: &[SuiteLine], model: &str) -> Vec<SuiteLine> {
    lines.iter().filter(|l| l.model == model).cloned().collect()
}

#[test]
fn extended_on_six_family_scenes_stays_within_its_measured_bounds() {
    let extended = run_suite(6, 1, &Params::extended());
    let paper = run_suite(6, 1, &Params::paper());
    // Measured (seed 1, 6 scenes, free space refuting tentative segments only): axis 32.8 %
    // spurious, confirmed 10.5 %, mean coverage 0.67 (confirmed 0.67); specular 79.9 % (paper
    // 88.8 %); median end-point errors 0.25 in (axis) and 0.55 in (specular).
    let axis = summarise(&of_model(&extended, "axis"));
    let confirmed = axis.confirmed.as_ref().expect("extended confirms segments");
    assert!(axis.spurious_fraction <= 0.40, "{axis:?}");
    assert!(confirmed.spurious_fraction <= 0.15, "{confirmed:?}");
    assert!(
        axis.mean_coverage >= 0.50 && confirmed.mean_coverage >= 0.50,
        "{axis:?}"
    );
    let specular = summarise(&of_model(&extended, "specular"));
    let paper_specular = summarise(&of_model(&paper, "specular"));
    assert!(specular.spurious_fraction <= 0.85, "{specular:?}");
    assert!(specular.spurious_fraction < paper_specular.spurious_fraction - 0.05);
    for s in [&axis, &specular] {
        assert!(
            s.median_endpoint_error_in.is_some_and(|e| e <= 2.0),
            "{s:?}"
        );
    }
    assert!(
        summarise(&paper).confirmed.is_none(),
        "the paper confirms nothing"
    );
}

#[test]
fn a_suite_is_the_same_for_the_same_seed() {
    let p = Params::extended();
    assert_eq!(run_suite(2, 9, &p), run_suite(2, 9, &p));
    assert_ne!(run_suite(2, 9, &p), run_suite(2, 10, &p));
}

#[test]
fn extended_maps_of_the_suite_keep_their_invariants() {
    for (kind, seed, plan) in suite_plans(6, 1) {
        for model in [Model::Specular, Model::Axis] {
            let run = simulate(&plan, model, seed);
            let checked = map_checked(&run, &Params::extended(), true);
            assert_eq!(checked.failure, None, "{kind:?} seed {seed} {model:?}");
        }
    }
}

/// Segments of `params`' map of `run` repeated lap after lap to each of `lengths` snapshots.
fn segments_after(run: &sonarmap::run::Run, params: &Params, lengths: &[usize]) -> Vec<usize> {
    let long = sonarmap::sim::repeat_laps(run, *lengths.iter().max().unwrap());
    let mut mapper =
        sonarmap::mapping::Mapper::new(params.clone(), long.layout.clone(), long.sensor);
    let mut counts = Vec::new();
    for (k, s) in long.snapshots.iter().enumerate() {
        mapper.step(s);
        if lengths.contains(&(k + 1)) {
            counts.push(mapper.map().segments.len());
        }
    }
    counts
}

#[test]
fn extended_maps_stop_growing_on_laps_of_the_suite_scenes() {
    // Laps of each scene, 2,000 then 6,000 snapshots. Measured: from 1.0× (corridor) to 1.70×
    // (room, 81 then 138 segments); when free space also refuted confirmed walls, which the
    // next lap made again, the room went from 162 to 388 (2.4×).
    let mut grown = Vec::new();
    for (kind, seed, plan) in suite_plans(6, 1) {
        let run = simulate(&plan, Model::Specular, seed);
        let counts = segments_after(&run, &Params::extended(), &[2000, 6000]);
        if counts[1] as f64 > 1.8 * counts[0] as f64 + 10.0 {
            grown.push((kind, seed, counts));
        }
    }
    assert!(
        grown.is_empty(),
        "segments after 2,000 and 6,000 snapshots: {grown:?}"
    );
}

#[test]
fn a_replay_catching_up_with_recorded_decisions_gives_the_maps_of_a_plain_run() {
    // The replay catches up from a checkpoint by taking each step's recorded decisions again
    // instead of testing candidates: the maps must be those of stepping from the start, in
    // both presets, on laps of generated scenes with both sensor models.
    for (kind, seed, plan) in suite_plans(4, 3) {
        for model in [Model::Specular, Model::Axis] {
            let run = std::sync::Arc::new(sonarmap::sim::repeat_laps(
                &simulate(&plan, model, seed),
                400,
            ));
            for params in [Params::paper(), Params::extended()] {
                let replay =
                    sonarmap::replay::Replay::build(run.clone(), params.clone(), 64, &mut |_| true)
                        .unwrap();
                let mut mapper =
                    sonarmap::mapping::Mapper::new(params.clone(), run.layout.clone(), run.sensor);
                for (k, s) in run.snapshots.iter().enumerate() {
                    mapper.step(s);
                    if k % 57 == 56 {
                        assert_eq!(
                            &replay.map_at(k),
                            &mapper.map().without_index(),
                            "{kind:?} seed {seed} {model:?} snapshot {k}"
                        );
                    }
                }
            }
        }
    }
}

#[test]
fn a_drifting_suite_reports_its_pose_error_and_without_drift_is_the_plain_suite() {
    use sonarmap::sim::OdometryError;
    use sonarmap::suite::run_suite_drifting;
    let p = Params::extended();
    let plain = run_suite(2, 4, &p);
    assert_eq!(run_suite_drifting(2, 4, &p, None), plain);
    assert!(plain.iter().all(|l| l.pose.is_none()));
    // With the heading corrected from the walls (as in `extended`), some run maps with other
    // poses than the odometry's.
    let corrected = run_suite_drifting(2, 4, &p, Some(&OdometryError::BAD));
    assert!(corrected.iter().any(|l| l
        .pose
        .is_some_and(|pose| pose.mapped_rms_position_m != pose.odometry_rms_position_m)));
    let uncorrected = Params {
        heading_correction: false,
        ..Params::extended()
    };
    let bad = run_suite_drifting(2, 4, &uncorrected, Some(&OdometryError::BAD));
    for line in &bad {
        let pose = line.pose.expect("a drifting run keeps its truth");
        assert!(pose.odometry_rms_position_m > 0.0, "{line:?}");
        // Without correction the engine maps with the odometry.
        assert_eq!(pose.mapped_rms_position_m, pose.odometry_rms_position_m);
    }
    assert!(summarise(&bad).pose.is_some());
    assert_ne!(bad, plain);
}

#[test]
fn extended_holds_at_a_crawl_what_it_maps_at_the_papers_pace() {
    use sonarmap::suite::{run_suite_with, Conditions};
    // The same four scenes at the plans' pace and crawling 15 mm a cycle, the sonars fired in
    // three groups (docs/algorithm.md §8.1, §8.7: the memory's span and confirmation stated in
    // distances, not snapshots). Measured (seed 13, confirmed, spurious / coverage): the plans'
    // pace 0.118 / 0.624; at the crawl 0.164 / 0.588, where the rules counted in snapshots (point
    // memory of 10 snapshots, any 3 readings a piece, any two snapshots a confirmation) gave
    // 0.270 / 0.379.
    let crawl = Conditions {
        pace: super::support::CRAWL,
        ..Conditions::PLAIN
    };
    let confirmed = |params: &Params, conditions: &Conditions| {
        let lines = run_suite_with(4, 13, params, conditions, None, &mut |_| true).unwrap();
        summarise(&lines)
            .confirmed
            .expect("extended confirms segments")
    };
    let paced = confirmed(&Params::extended(), &Conditions::PLAIN);
    let crawled = confirmed(&Params::extended(), &crawl);
    let counted_in_snapshots = Params {
        memory_snapshots: 10,
        memory_travel_m: 0.0,
        memory_min_span_m: 0.0,
        confirm_spacing_m: 0.0,
        ..Params::extended()
    };
    let crawled_before = confirmed(&counted_in_snapshots, &crawl);
    assert!(
        crawled.mean_coverage >= paced.mean_coverage - 0.15,
        "{crawled:?} {paced:?}"
    );
    assert!(crawled.spurious_fraction <= paced.spurious_fraction + 0.1);
    assert!(crawled.mean_coverage >= crawled_before.mean_coverage + 0.05);
    assert!(crawled.spurious_fraction <= crawled_before.spurious_fraction - 0.05);
}

#[test]
fn a_single_ray_sensor_maps_at_a_crawl_what_it_maps_at_the_papers_pace() {
    use sonarmap::suite::{run_suite_with, Conditions};
    // The axis model's runs of the four scenes above. A single ray hears a wall wherever its
    // axis meets it, so its plane test is taken along the axis (docs/algorithm.md §8.7).
    // Measured (seed 13, confirmed, spurious / coverage): the plans' pace 0.030 / 0.895, the
    // crawl 0.110 / 0.872; with the foot of the perpendicular as the plane test, which a
    // sensor 13° or more off a wall's normal never passes, 0.136 / 0.680 and 0.000 / 0.514.
    let crawl = Conditions {
        pace: super::support::CRAWL,
        ..Conditions::PLAIN
    };
    let axis_confirmed = |conditions: &Conditions| {
        let lines =
            run_suite_with(4, 13, &Params::extended(), conditions, None, &mut |_| true).unwrap();
        summarise(&of_model(&lines, "axis"))
            .confirmed
            .expect("extended confirms segments")
    };
    let paced = axis_confirmed(&Conditions::PLAIN);
    let crawled = axis_confirmed(&crawl);
    assert!(paced.mean_coverage >= 0.8, "{paced:?}");
    assert!(
        crawled.mean_coverage >= paced.mean_coverage - 0.1,
        "{crawled:?} {paced:?}"
    );
    assert!(crawled.spurious_fraction <= 0.2, "{crawled:?}");
}

/// A suite calibrated (`calibrate_first`, as in `extended`, docs/algorithm.md §8.17) without
/// drift finds no drift to calibrate with, so its maps are those of one pass. A run whose first
/// pass latched on a drift it does not have would be mapped again, and the second pass must map
/// it better. Seed 21's l-room (specular) did so until §8.18 cut its overruns (confirmed 0.600
/// spurious, 0.210 covered; 0.412 and 0.484 after the second pass); now it maps at 0.056 and
/// 0.767 with or without the heading correction, and no run of the seed's twelve scenes
/// latches. Two of them, that l-room and `pillars-24` (specular), latched under a latch on the
/// heading error itself, tried in stop 55 and left out (docs/algorithm.md §8.17).
#[test]
fn a_calibrated_suite_without_drift_is_the_plain_suite_and_a_false_latch_would_be_mended() {
    let run = |calibrate_first: bool| {
        let params = Params {
            calibrate_first,
            ..Params::extended()
        };
        run_suite(12, 21, &params)
    };
    let (calibrated, plain) = (run(true), run(false));
    let mut mended = Vec::new();
    for (c, p) in calibrated.iter().zip(&plain) {
        if c == p {
            continue;
        }
        let (cc, pc) = (
            c.figures.confirmed.as_ref().unwrap(),
            p.figures.confirmed.as_ref().unwrap(),
        );
        assert!(
            cc.spurious_fraction < pc.spurious_fraction && cc.coverage > pc.coverage,
            "{} {}: {cc:?} against {pc:?}",
            c.family,
            c.model
        );
        mended.push((c.family, c.model.as_str()));
    }
    assert_eq!(mended, Vec::<(&str, &str)>::new(), "no run latches");
}
