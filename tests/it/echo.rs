//! Echo placement (docs/algorithm.md §8.10), the sensor's echo model in logs, and connecting
//! segments leaving with what they joined (§8.3).

use sonarmap::geometry::Pose;
use sonarmap::mapping::{Mapper, Params, SegmentKind};
use sonarmap::run::Snapshot;
use sonarmap::sim::{repeat_laps, simulate, Model};
use sonarmap::sonar::{EchoModel, SensorLayout, SensorSpec};
use sonarmap::suite::suite_plans;
use sonarmap::units::inches;

/// The wall y = 2 m heard by a cone sonar with 35° of roughness: the foot of the perpendicular
/// when the normal lies inside the 12.5° half cone, else the cone's nearer edge (range
/// `p / cos(|β| − 12.5°)`), else nothing.
fn oblique_wall_snapshot(layout: &SensorLayout, pose: Pose, t: f64) -> Snapshot {
    let half = 12.5f64.to_radians();
    let ranges_m = (0..layout.len())
        .map(|k| {
            let s = layout.sensor_pose_in_world(&pose, k);
            let perpendicular = 2.0 - s.y;
            let beta = (s.heading_rad - std::f64::consts::FRAC_PI_2 + std::f64::consts::PI)
                .rem_euclid(std::f64::consts::TAU)
                - std::f64::consts::PI;
            let incidence = (beta.abs() - half).max(0.0);
            (incidence <= 35f64.to_radians()).then(|| perpendicular / incidence.cos())
        })
        .collect();
    Snapshot {
        t,
        pose,
        ranges_m,
        true_pose: None,
        reading_dt_s: Vec::new(),
    }
}

fn map_oblique_wall(params: Params) -> Mapper {
    let layout = SensorLayout::nomad_ring(inches(9.0));
    let mut mapper = Mapper::new(params, layout.clone(), SensorSpec::default());
    for i in 0..40 {
        let pose = Pose::new(0.1 * i as f64, 0.0, 0.3);
        mapper.step(&oblique_wall_snapshot(&layout, pose, i as f64));
    }
    mapper
}

/// The largest distance of a fitted segment's end-point from the wall y = 2, over its
/// tolerance `max(3 % of its range, 1 in)`.
fn worst_end_off_the_wall(mapper: &Mapper, confirmed_only: bool) -> (usize, f64) {
    let map = mapper.map();
    let segments: Vec<_> = map
        .segments
        .iter()
        .filter(|s| s.kind == SegmentKind::Fitted && (!confirmed_only || !map.is_tentative(s.id)))
        .collect();
    let worst = segments
        .iter()
        .flat_map(|s| [s.a, s.b])
        .map(|e| (e.point.y - 2.0).abs() / (0.03 * e.range_m).max(inches(1.0)))
        .fold(0.0, f64::max);
    (segments.len(), worst)
}

#[test]
fn an_oblique_wall_heard_from_cone_edges_is_mapped_on_its_line_not_short_of_it() {
    // Heading 0.3 rad: sensor 4 looks 107.2°, 17.2° off the wall's normal, and hears the wall
    // from its cone's edge at p / cos 4.7°; on its axis that reading lies at
    // p · cos 17.2° / cos 4.7° = 0.959 p, 4 % short of the wall (more than the 3 % tolerance).
    let paper = map_oblique_wall(Params::paper());
    let (count, worst) = worst_end_off_the_wall(&paper, false);
    assert!(
        count > 0 && worst > 1.0,
        "paper: {count} segments, worst {worst}"
    );
    let extended = map_oblique_wall(Params::extended());
    let (count, worst) = worst_end_off_the_wall(&extended, true);
    assert!(
        count > 0 && worst <= 1.0,
        "extended: {count} confirmed, worst {worst}"
    );
}

#[test]
fn a_single_ray_sensor_keeps_the_papers_placement() {
    // The same readings from a sensor that declares its echoes come from its axis: no echo
    // is moved, so extended maps what the axis placement gives.
    let layout = SensorLayout::nomad_ring(inches(9.0));
    let sensor = SensorSpec {
        echo: EchoModel::Axis,
        ..SensorSpec::default()
    };
    let mut mapper = Mapper::new(Params::extended(), layout.clone(), sensor);
    let mut moved = 0;
    for i in 0..40 {
        let pose = Pose::new(0.1 * i as f64, 0.0, 0.3);
        let trace = mapper.step(&oblique_wall_snapshot(&layout, pose, i as f64));
        moved += trace.echo_fits.len();
    }
    assert_eq!(moved, 0);
    let cone = {
        let mut mapper = Mapper::new(Params::extended(), layout.clone(), SensorSpec::default());
        (0..40)
            .map(|i| {
                let pose = Pose::new(0.1 * i as f64, 0.0, 0.3);
                mapper
                    .step(&oblique_wall_snapshot(&layout, pose, i as f64))
                    .echo_fits
                    .len()
            })
            .sum::<usize>()
    };
    assert!(cone > 0, "the cone sensor's pieces are fitted");
}

/// Two single-ray sensors of a robot driving along +x below the wall y = 2 m, their axes 70°
/// and 50° from the robot's, so 20° and 40° off the wall's normal: each reads the distance
/// along its axis, `p / cos β`. A 1 % sonar; mapped in `extended` with ξ = 1 %.
fn map_wall_met_off_its_normal(echo: EchoModel) -> Mapper {
    use sonarmap::sonar::SensorMount;
    let layout = SensorLayout {
        mounts: [70f64, 50.0]
            .iter()
            .map(|deg| SensorMount {
                x_m: 0.0,
                y_m: 0.0,
                heading_rad: deg.to_radians(),
            })
            .collect(),
    };
    let sensor = SensorSpec {
        echo,
        accuracy_pct: 1.0,
        ..SensorSpec::default()
    };
    let params = Params {
        accuracy_pct: 1.0,
        ..Params::extended()
    };
    let mut mapper = Mapper::new(params, layout.clone(), sensor);
    for i in 0..60 {
        let pose = Pose::new(0.05 * i as f64, 0.0, 0.0);
        let ranges_m = (0..layout.len())
            .map(|k| {
                let s = layout.sensor_pose_in_world(&pose, k);
                let beta = s.heading_rad - std::f64::consts::FRAC_PI_2;
                Some((2.0 - s.y) / beta.cos())
            })
            .collect();
        mapper.step(&Snapshot {
            t: i as f64,
            pose,
            ranges_m,
            true_pose: None,
            reading_dt_s: Vec::new(),
        });
    }
    mapper
}

#[test]
fn a_single_ray_sensor_confirms_a_wall_it_meets_off_its_normal() {
    // The sensor 20° off the normal reads 2 / cos 20° = 2.128 m where the foot model predicts
    // 2 m (6 % off, past the 1 % tolerance, and the foot lies 20° off the axis, outside the
    // 12.5° half cone): a plane test at the foot never confirms the wall. Along the axis the
    // wall predicts the reading exactly (docs/algorithm.md §8.7).
    // Confirmed fitted segments, and those of them with both ends within 1 in of the wall.
    let on_the_wall = |mapper: &Mapper| {
        let map = mapper.map();
        let confirmed: Vec<_> = map
            .segments
            .iter()
            .filter(|s| s.kind == SegmentKind::Fitted && !map.is_tentative(s.id))
            .collect();
        let on = confirmed
            .iter()
            .filter(|s| {
                [s.a, s.b]
                    .iter()
                    .all(|e| (e.point.y - 2.0).abs() <= inches(1.0))
            })
            .count();
        (confirmed.len(), on)
    };
    let (count, on) = on_the_wall(&map_wall_met_off_its_normal(EchoModel::Axis));
    assert!(
        count > 0 && on == count,
        "{count} confirmed, {on} on the wall"
    );
    // Declared as hearing its whole cone, the same readings are taken for echoes of the cone's
    // nearer edge (7.5° and 27.5° off the normal) and placed there (§8.10), behind the wall:
    // what they confirm is not on it.
    let (_, on) = on_the_wall(&map_wall_met_off_its_normal(EchoModel::Cone));
    assert_eq!(on, 0);
}

#[test]
fn a_logs_echo_model_round_trips_and_an_unknown_one_is_refused_with_its_place() {
    let plan = &suite_plans(1, 1)[0].2;
    let run = simulate(plan, Model::Axis, 1);
    assert_eq!(run.sensor.echo, EchoModel::Axis);
    let text = sonarmap::log::save_run(&run);
    assert!(text.contains("\"echo\": \"axis\"") || text.contains("\"echo\":\"axis\""));
    let back = sonarmap::log::load_run(text.as_bytes(), "axis.log.json").unwrap();
    assert_eq!(back.sensor.echo, EchoModel::Axis);
    // A cone sensor (the default) writes nothing, so older readers see the same file.
    let cone = simulate(plan, Model::Specular, 1);
    assert!(!sonarmap::log::save_run(&cone).contains("\"echo\""));
    let bad = text
        .replacen("\"echo\": \"axis\"", "\"echo\": \"laser\"", 1)
        .replacen("\"echo\":\"axis\"", "\"echo\":\"laser\"", 1);
    let err = sonarmap::log::load_run(bad.as_bytes(), "bad.log.json")
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("bad.log.json") && err.contains("echo"),
        "error names the file and the field: {err}"
    );
}

/// The suite's scene of family `kind` (seed 1), simulated with the specular model, its lap
/// repeated to `snapshots`.
fn suite_lap_run(kind: &str, snapshots: usize) -> sonarmap::run::Run {
    let (_, seed, plan) = suite_plans(6, 1)
        .into_iter()
        .find(|(k, _, _)| k.name() == kind)
        .expect("a scene of the family");
    repeat_laps(&simulate(&plan, Model::Specular, seed), snapshots)
}

#[test]
fn no_connecting_segment_outlives_a_segment_it_joined_on_a_lap_run() {
    // Desks, one lap repeated to 3,000 snapshots in `extended`: duplicates fused away and
    // refuted lines take their connecting segments with them (before, the links piled up:
    // 137 at 2,000 snapshots, 336 at 6,000, while the fitted segments stayed at 113–116).
    let run = suite_lap_run("desks", 3000);
    let mut mapper =
        Mapper::new(Params::extended(), run.layout.clone(), run.sensor).with_trace(false);
    let mut dropped = 0;
    for snapshot in &run.snapshots {
        dropped += mapper.step(snapshot).dropped_links.len();
        let map = mapper.map();
        for s in map
            .segments
            .iter()
            .filter(|s| s.kind == SegmentKind::Interpolated)
        {
            let ends = map.link_ends.get(&s.id).expect("every link is tracked");
            assert!(
                ends.iter().all(|&e| map.segment(e).is_some()),
                "link {} joins {ends:?}, not all in the map",
                s.id
            );
        }
    }
    assert!(dropped > 0, "the run fuses duplicates that had links");
}

mod fit_properties {
    use proptest::prelude::*;
    use sonarmap::geometry::{Point, Vec2};
    use sonarmap::mapping::ext::echo_fit::{fit_echo_line, place_echoes};
    use sonarmap::mapping::model::beam::Beam;
    use sonarmap::mapping::model::support::{ReadingRef, SupportPoint};

    const HALF: f64 = 12.5 * std::f64::consts::PI / 180.0;

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(300))]

        /// Noise-free echoes of one plane (feet inside the cone, cone edges up to 30° of
        /// incidence outside it) from sensors moving along it: the fit finds the plane, and the
        /// moved points lie on it.
        #[test]
        fn echoes_of_one_plane_are_placed_on_it(
            normal_deg in 0.0f64..360.0,
            offset_m in 0.8f64..4.0,
            off_axis_deg in -40.0f64..40.0,
            spacing_m in 0.05f64..0.25,
            count in 3usize..9,
        ) {
            let normal = Vec2::new(normal_deg.to_radians().cos(), normal_deg.to_radians().sin());
            let along = Vec2::new(-normal.y, normal.x);
            let axis_rad = (normal_deg + off_axis_deg).to_radians();
            let direction = Vec2::new(axis_rad.cos(), axis_rad.sin());
            let incidence = (off_axis_deg.abs().to_radians() - HALF).max(0.0);
            let beams: Vec<Beam> = (0..count)
                .map(|i| {
                    let origin = Point::origin() + along * (spacing_m * i as f64);
                    // The plane n·x = offset: perpendicular distance offset − n·o = offset.
                    Beam { origin, direction, range_m: offset_m / incidence.cos() }
                })
                .collect();
            let points: Vec<SupportPoint> = beams
                .iter()
                .enumerate()
                .map(|(i, b)| SupportPoint {
                    point: b.origin + b.direction * b.range_m,
                    range_m: b.range_m,
                    reading: ReadingRef::new(i, 0),
                })
                .collect();
            let axis: Vec<Point> = points.iter().map(|q| q.point).collect();
            let line = fit_echo_line(&beams, &axis, 3.0, HALF, 15f64.to_radians());
            let line = line.expect("one plane's echoes fit a line");
            prop_assert!(line.normal.dot(&normal) > 1f64.to_radians().cos(), "{line:?}");
            let tol = (0.03 * beams[0].range_m).max(0.0254);
            prop_assert!((line.offset_m - offset_m).abs() <= tol, "{line:?}");
            let placed = place_echoes(&points, &beams, &line, HALF);
            for q in &placed.points {
                prop_assert!((normal.dot(&q.point.coords) - offset_m).abs() <= tol, "{q:?}");
            }
        }
    }
}

#[test]
fn a_new_face_across_a_corner_leaves_before_the_step_correlates_or_confirms_it() {
    // Pillars, one lap repeated to 1,000 snapshots in `extended`: a new face that stands across
    // a corner of the map when it is filed leaves at once (docs/algorithm.md §8.11, at birth):
    // no correlation of its step joins it to anything, and no reading of the step confirms it.
    let run = suite_lap_run("pillars", 1000);
    let mut mapper = Mapper::new(Params::extended(), run.layout.clone(), run.sensor);
    let mut at_birth = 0;
    for snapshot in &run.snapshots {
        let trace = mapper.step(snapshot);
        let made: Vec<_> = trace
            .decisions
            .iter()
            .filter(|d| d.outcome == sonarmap::mapping::model::trace::Outcome::NewFace)
            .filter_map(|d| d.result)
            .collect();
        for d in trace.diagonals.iter().filter(|d| made.contains(&d.segment)) {
            at_birth += 1;
            let named = |s: Option<(u32, usize)>| s.is_some_and(|(id, _)| id == d.segment);
            assert!(
                !trace
                    .correlations
                    .iter()
                    .any(|c| named(c.new_segment) || named(c.existing_segment)),
                "snapshot {}: s{} was correlated before it left",
                trace.snapshot,
                d.segment
            );
            assert!(
                !trace.plane_support.iter().any(|p| p.segment == d.segment),
                "snapshot {}: s{} was supported before it left",
                trace.snapshot,
                d.segment
            );
            assert!(mapper.map().segment(d.segment).is_none());
        }
    }
    assert!(at_birth > 0, "no new face left as a diagonal");
}
