//! The simulator: beam model behaviour, plan paths, determinism.

use sonarmap::geometry::{Point, Pose};
use sonarmap::log::save_run;
use sonarmap::run::{Circle, FloorPlan, Wall};
use sonarmap::sim::{interpolate_path, load_plan, simulate, Model, World};

const BEAM: f64 = 25.0;

fn wall(ax: f64, ay: f64, bx: f64, by: f64, roughness_deg: Option<f64>) -> Wall {
    Wall {
        a: Point::new(ax, ay),
        b: Point::new(bx, by),
        roughness_rad: roughness_deg.map(f64::to_radians),
    }
}

/// A world of `walls` alone: no roughness unless a wall has its own, ranges to 1 in.
fn world_of(walls: Vec<Wall>) -> World {
    let plan = FloorPlan {
        walls,
        circles: vec![],
    };
    World::new(&plan, 0.0, 0.0254)
}

fn echo(world: &World, x: f64, y: f64, heading_deg: f64, model: Model) -> Option<f64> {
    echo_bounced(world, x, y, heading_deg, model, 0)
}

fn echo_bounced(
    world: &World,
    x: f64,
    y: f64,
    heading_deg: f64,
    model: Model,
    bounces: u32,
) -> Option<f64> {
    world.echo_range(
        &Pose::new(x, y, heading_deg.to_radians()),
        BEAM.to_radians(),
        1f64.to_radians(),
        model,
        bounces,
    )
}

/// A mirror (roughness 1°) across the line x − y = 2, from (1.5, −0.5) to (2.5, 0.5), and a
/// rough wall (10°) along y = 3 from (1, 3) to (3, 3).
fn mirror_and_wall() -> World {
    world_of(vec![
        wall(1.5, -0.5, 2.5, 0.5, Some(1.0)),
        wall(1.0, 3.0, 3.0, 3.0, Some(10.0)),
    ])
}

#[test]
fn a_mirrored_ray_echoes_from_the_wall_it_is_sent_to_over_the_whole_path() {
    let world = mirror_and_wall();
    // A sonar at the origin looking along +x meets the mirror 45° off its normal at (2, 0): no
    // echo, and nothing else in the cone echoes (the rough wall's normal is 90° off the axis).
    assert_eq!(echo(&world, 0.0, 0.0, 0.0, Model::Specular), None);
    // One bounce: a ray α off the axis is mirrored to 90° − α and meets the rough wall α off
    // its normal, echoing for |α| ≤ 10°; its path runs from the origin's mirror image (2, −2),
    // 5 / cos α long. The rays sampled nearest the axis are 0.5° off it (26 rays 1° apart from
    // −12.5° to 12.5°): 5 / cos 0.5° = 5.00019 m.
    let r = echo_bounced(&world, 0.0, 0.0, 0.0, Model::Specular, 1).unwrap();
    let nearest = 5.0 / 0.5f64.to_radians().cos();
    assert!((r - nearest).abs() < 1e-9, "{r}");
    // The axis model has no bounces: it reads the mirror where its axis meets it.
    let r = echo_bounced(&world, 0.0, 0.0, 0.0, Model::Axis, 1).unwrap();
    assert!((r - 2.0).abs() < 1e-9, "{r}");
}

#[test]
fn a_ray_mirrored_into_open_space_or_past_its_bounces_is_no_echo() {
    // The same mirror alone: the mirrored ray leaves through +y and meets nothing.
    let world = world_of(vec![wall(1.5, -0.5, 2.5, 0.5, Some(1.0))]);
    assert_eq!(
        echo_bounced(&world, 0.0, 0.0, 0.0, Model::Specular, 3),
        None
    );
    // A second mirror across its path, tilted 45° (x + y = 5 from (1.5, 3.5) to (2.5, 2.5)),
    // and a rough wall (10°) along x = 0 from (0, 2) to (0, 4): the ray is mirrored again, to
    // −x at (2, 3), and meets that wall square-on. One bounce is not enough: none. Two: the
    // path runs from the origin's image in both mirrors, (7, 3), 7 / cos α long for a ray α
    // off the axis; the sampled rays nearest it, 0.5° off, give 7.00027 m.
    let world = world_of(vec![
        wall(1.5, -0.5, 2.5, 0.5, Some(1.0)),
        wall(1.5, 3.5, 2.5, 2.5, Some(1.0)),
        wall(0.0, 2.0, 0.0, 4.0, Some(10.0)),
    ]);
    assert_eq!(
        echo_bounced(&world, 0.0, 0.0, 0.0, Model::Specular, 1),
        None
    );
    let r = echo_bounced(&world, 0.0, 0.0, 0.0, Model::Specular, 2).unwrap();
    let nearest = 7.0 / 0.5f64.to_radians().cos();
    assert!((r - nearest).abs() < 1e-9, "{r}");
}

#[test]
fn a_plans_bounces_survive_writing_it_back() {
    let text = PLAN.replace("\"ghost\": 0.05", "\"ghost\": 0.05, \"bounces\": 4");
    let plan = load_plan(text.as_bytes(), "p.json").unwrap();
    assert_eq!(plan.sim.bounces, sonarmap::sim::MAX_BOUNCES);
    let written = serde_json::to_string(&sonarmap::sim::plan_to_file(&plan)).unwrap();
    assert_eq!(
        load_plan(written.as_bytes(), "w.json").unwrap().sim.bounces,
        4
    );
}

#[test]
fn a_mirror_wall_perpendicular_to_the_beam_echoes_at_the_normal_distance() {
    let world = world_of(vec![wall(2.0, -5.0, 2.0, 5.0, Some(1.0))]);
    // Axis 10° off the normal: the normal is inside the 25° cone → normal distance 2.
    let r = echo(&world, 0.0, 0.0, 10.0, Model::Specular).unwrap();
    assert!((r - 2.0).abs() < 1e-9, "{r}");
}

#[test]
fn a_mirror_wall_at_grazing_angle_gives_no_echo() {
    let world = world_of(vec![wall(2.0, -5.0, 2.0, 5.0, Some(5.0))]);
    // Axis 60° off the normal: rays 47.5°..72.5° off, all beyond 5° roughness.
    assert_eq!(echo(&world, 0.0, 0.0, 60.0, Model::Specular), None);
    // The axis model sees it anyway: 2 / cos 60° = 4.
    let r = echo(&world, 0.0, 0.0, 60.0, Model::Axis).unwrap();
    assert!((r - 4.0).abs() < 1e-9, "{r}");
}

#[test]
fn a_rough_wall_echoes_at_the_nearest_ray_within_its_roughness() {
    // Axis 22.5° off the normal, beam edge 10° off: roughness 12° → the edge ray echoes at 2/cos 10°.
    let world = world_of(vec![wall(2.0, -5.0, 2.0, 5.0, Some(12.0))]);
    let r = echo(&world, 0.0, 0.0, 22.5, Model::Specular).unwrap();
    assert!((r - 2.0 / 10f64.to_radians().cos()).abs() < 1e-9, "{r}");
}

#[test]
fn a_concave_corner_returns_whatever_the_angle() {
    // Corner at (2, 2) of two mirror walls; the sonar looks straight at it (45° to both walls).
    let world = world_of(vec![
        wall(2.0, -3.0, 2.0, 2.0, Some(0.0)),
        wall(2.0, 2.0, -3.0, 2.0, Some(0.0)),
    ]);
    let r = echo(&world, 0.0, 0.0, 45.0, Model::Specular).unwrap();
    assert!((r - 8f64.sqrt()).abs() < 1e-6, "{r}");
    // Seen from outside (convex), the same corner gives nothing.
    assert_eq!(echo(&world, 4.0, 4.0, -135.0, Model::Specular), None);
}

#[test]
fn a_pillar_echoes_toward_its_centre_and_occludes_the_wall_behind() {
    let plan = FloorPlan {
        walls: vec![wall(3.0, -5.0, 3.0, 5.0, Some(0.0))],
        circles: vec![Circle {
            centre: Point::new(1.5, 0.3),
            radius_m: 0.2,
        }],
    };
    let world = World::new(&plan, 0.0, 0.0254);
    let r = echo(&world, 0.0, 0.0, 0.0, Model::Specular).unwrap();
    let expected = (1.5f64.powi(2) + 0.09).sqrt() - 0.2;
    assert!((r - expected).abs() < 1e-9, "{r} vs {expected}");
}

#[test]
fn a_pillar_just_outside_a_beam_echoes_from_its_edge_and_the_fit_hears_it_there() {
    // A pillar of radius 0.25 m at (2, 3) with 35° of surface roughness, heard by sensors on
    // y = 0 whose beams hold its centre inside (0–5° off the axis) or just past the cone's edge
    // (13.5–14.5°, the edge 1–2° short of it: it passes 5–11 cm from the centre and meets the
    // surface at 12–25° of incidence, within the 35°). The simulator's specular echo is the one
    // the engine predicts (docs/algorithm.md §8.14): along the edge when the centre is outside.
    use sonarmap::geometry::{unit, Vec2};
    use sonarmap::mapping::ext::beam_geometry::round_echo;
    use sonarmap::mapping::ext::beam_geometry::HalfCone;
    use sonarmap::mapping::ext::echo_fit::fit_round_reflector;
    use sonarmap::mapping::ext::point_features::explains_round;
    use sonarmap::mapping::model::beam::Beam;
    let centre = Point::new(2.0, 3.0);
    let plan = FloorPlan {
        walls: vec![],
        circles: vec![Circle {
            centre,
            radius_m: 0.25,
        }],
    };
    let world = World::new(&plan, 35f64.to_radians(), 0.0254);
    let half = (BEAM / 2.0).to_radians();
    let mut beams = Vec::new();
    let mut at_edge = 0;
    for (x, off_deg) in [
        (1.0, 0.0),
        (1.4, 14.5),
        (1.8, -5.0),
        (2.2, 13.5),
        (2.6, -14.0),
        (3.0, 3.0),
    ] {
        let to_centre: Vec2 = centre - Point::new(x, 0.0);
        let heading_deg = to_centre.y.atan2(to_centre.x).to_degrees() + off_deg;
        let range_m = echo(&world, x, 0.0, heading_deg, Model::Specular).unwrap();
        let beam = Beam {
            origin: Point::new(x, 0.0),
            direction: unit(heading_deg.to_radians()),
            range_m,
        };
        // The engine's echo is the simulator's: through the centre for the first kind, along
        // the edge for the second, which reads beyond |c − o| − r.
        let predicted = round_echo(&centre, 0.25, &beam, HalfCone::new(half)).unwrap();
        assert!((predicted.range_m - range_m).abs() < 1e-9, "{beam:?}");
        assert!(explains_round(&centre, 0.25, &beam, 1.0, half), "{beam:?}");
        if f64::abs(off_deg) > BEAM / 2.0 {
            at_edge += 1;
            assert!(range_m > to_centre.norm() - 0.25 + 1e-4, "{beam:?}");
        }
        beams.push(beam);
    }
    assert_eq!(at_edge, 3);
    let (c, r, _) = fit_round_reflector(&beams, Point::new(2.0, 2.7), 1.0, half).unwrap();
    assert!((c - centre).norm() < 0.01, "{c:?}");
    assert!((r - 0.25).abs() < 0.01, "{r}");
}

#[test]
fn paths_are_cut_by_step_and_turn() {
    let w = [
        Pose::new(0.0, 0.0, 0.0),
        Pose::new(1.0, 0.0, 0.0),
        Pose::new(1.0, 0.0, 90f64.to_radians()),
    ];
    assert_eq!(interpolate_path(&w, None, None), w.to_vec());
    let p = interpolate_path(&w, Some(0.25), Some(30f64.to_radians()));
    // 4 steps of 0.25, 3 turns of 30°, plus the last waypoint.
    assert_eq!(p.len(), 8);
    assert!((p[1].x - 0.25).abs() < 1e-12);
    assert!((p[5].heading_rad - 30f64.to_radians()).abs() < 1e-12);
    assert_eq!(p[7], w[2]);
    // Headings turn the short way: 350° → 10° is +20°.
    let q = interpolate_path(
        &[
            Pose::new(0.0, 0.0, 350f64.to_radians()),
            Pose::new(0.0, 0.0, 10f64.to_radians()),
        ],
        None,
        Some(10f64.to_radians()),
    );
    assert_eq!(q.len(), 3);
    assert!((q[1].heading_rad - 360f64.to_radians()).abs() < 1e-12);
}

const PLAN: &str = r#"{"format": "sonarmap-plan", "version": 1, "units": "in",
  "walls": [[0, 0, 100, 0], [100, 0, 100, 60], [100, 60, 0, 60], [0, 60, 0, 0, 5]],
  "circles": [[70, 30, 4]], "roughness_deg": 20, "sim": {"dropout": 0.1, "ghost": 0.05},
  "step": 3, "path": [[20, 30, 0], [40, 30, 0]]}"#;

#[test]
fn a_plan_loads_with_defaults_and_its_path_is_interpolated() {
    let plan = load_plan(PLAN.as_bytes(), "p.json").unwrap();
    assert_eq!(plan.layout.len(), 16, "default robot: the Nomad ring");
    assert!((plan.robot_radius_m.unwrap() - 9.0 * 0.0254).abs() < 1e-12);
    assert_eq!(
        plan.poses.len(),
        8,
        "20 in cut into 7 steps of at most 3 in, plus the end"
    );
    assert!((plan.floor_plan.walls[3].roughness_rad.unwrap() - 5f64.to_radians()).abs() < 1e-12);
    assert_eq!(plan.floor_plan.walls[0].roughness_rad, None);
}

#[test]
fn bad_plans_name_the_place() {
    let e = load_plan(
        PLAN.replace("\"step\": 3", "\"step\": -3").as_bytes(),
        "p.json",
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("p.json") && e.contains("$.step"), "{e}");
    let e = load_plan(
        PLAN.replace("\"dropout\": 0.1", "\"dropout\": 2")
            .as_bytes(),
        "p.json",
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("$.sim.dropout"), "{e}");
    let with_bounces = |n: &str| {
        PLAN.replace(
            "\"ghost\": 0.05",
            &format!("\"ghost\": 0.05, \"bounces\": {n}"),
        )
    };
    assert_eq!(
        load_plan(with_bounces("2").as_bytes(), "p.json")
            .unwrap()
            .sim
            .bounces,
        2
    );
    let e = load_plan(with_bounces("5").as_bytes(), "p.json")
        .unwrap_err()
        .to_string();
    assert!(e.contains("p.json") && e.contains("$.sim.bounces"), "{e}");
    let limit = format!("0 to {}", sonarmap::sim::MAX_BOUNCES);
    assert!(e.contains(&limit), "the refusal names the limit: {e}");
    let e = load_plan(PLAN.replace("[20, 30, 0]", "[20, 30]").as_bytes(), "p.json")
        .unwrap_err()
        .to_string();
    assert!(e.contains("$.path[0]"), "{e}");
    let e = load_plan(
        PLAN.replace("sonarmap-plan", "sonarmap-log").as_bytes(),
        "p.json",
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("sonarmap-plan"), "{e}");
}

#[test]
fn the_same_seed_gives_the_same_log_and_another_seed_does_not() {
    let plan = load_plan(PLAN.as_bytes(), "p.json").unwrap();
    let a = save_run(&simulate(&plan, Model::Specular, 7));
    let b = save_run(&simulate(&plan, Model::Specular, 7));
    let c = save_run(&simulate(&plan, Model::Specular, 8));
    assert_eq!(a, b);
    assert_ne!(a, c);
}

#[test]
fn simulated_ranges_are_quantised_within_accuracy_and_below_max_range() {
    let text = PLAN.replace(r#""sim": {"dropout": 0.1, "ghost": 0.05},"#, "");
    let plan = load_plan(text.as_bytes(), "p.json").unwrap();
    let run = simulate(&plan, Model::Axis, 3);
    let world = World::new(
        &plan.floor_plan,
        plan.roughness_rad,
        plan.sim.corner_tolerance_m,
    );
    for s in &run.snapshots {
        for (k, r) in s.ranges_m.iter().enumerate() {
            let truth = world.echo_range(
                &plan.layout.sensor_pose_in_world(&s.pose, k),
                0.4,
                0.02,
                Model::Axis,
                0,
            );
            let (Some(r), Some(t)) = (r, truth) else {
                continue;
            };
            let q = r / plan.sim.resolution_m;
            assert!((q - q.round()).abs() < 1e-6, "quantised");
            assert!(
                (r - t).abs() <= t * 0.01 + plan.sim.resolution_m,
                "within 1 % + a quantum"
            );
            assert!(*r < plan.sensor.max_range_m);
        }
    }
}

mod pillar_echo_properties {
    use super::*;
    use proptest::prelude::*;
    use sonarmap::geometry::{unit, Vec2};
    use sonarmap::mapping::ext::beam_geometry::round_echo;
    use sonarmap::mapping::ext::beam_geometry::HalfCone;
    use sonarmap::mapping::model::beam::Beam;

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(400))]

        /// Wherever a sensor stands and however its beam points at a lone pillar, the engine's
        /// pillar echo (docs/algorithm.md §8.14) is the simulator's: the same range when the
        /// simulator hears one (through the centre, or along the cone's edge within the
        /// surface's roughness, at most §8.10's 60°), and an echo the engine predicts is heard
        /// by a simulator whose roughness allows its incidence.
        #[test]
        fn the_engine_hears_a_pillar_where_the_simulator_does(
            radius_m in 0.05f64..0.5,
            distance_m in 0.8f64..4.0,
            bearing_deg in 0.0f64..360.0,
            off_axis_deg in -25.0f64..25.0,
            roughness_deg in 5.0f64..60.0,
        ) {
            let centre = Point::new(1.0, 2.0);
            let plan = FloorPlan { walls: vec![], circles: vec![Circle { centre, radius_m }] };
            let world = World::new(&plan, roughness_deg.to_radians(), 0.0254);
            let sensor = centre - unit(bearing_deg.to_radians()) * (distance_m + radius_m);
            let heading_deg = bearing_deg + off_axis_deg;
            let heard = echo(&world, sensor.x, sensor.y, heading_deg, Model::Specular);
            let beam = Beam { origin: sensor, direction: unit(heading_deg.to_radians()), range_m: 1.0 };
            let predicted = round_echo(&centre, radius_m, &beam, HalfCone::new((BEAM / 2.0).to_radians()));
            if let Some(heard_m) = heard {
                let predicted = predicted.expect("the engine hears what the simulator does");
                prop_assert!((predicted.range_m - heard_m).abs() < 1e-6, "{predicted:?} vs {heard_m}");
            }
            if let Some(p) = predicted {
                // The incidence where the echo's ray meets the surface.
                let v: Vec2 = centre - sensor;
                let (e, along) = if off_axis_deg.abs() <= BEAM / 2.0 {
                    (v / v.norm(), v.norm())
                } else {
                    let edge = heading_deg - (BEAM / 2.0).copysign(off_axis_deg);
                    let e = unit(edge.to_radians());
                    (e, e.dot(&v))
                };
                let hit = sensor + e * p.range_m;
                let cos_incidence = -e.dot(&((hit - centre) / radius_m));
                prop_assert!(cos_incidence > 0.0 && (p.range_m - (along - radius_m)) > -1e-9);
                if cos_incidence.acos() < roughness_deg.to_radians() - 1e-6 {
                    prop_assert!(heard.is_some_and(|h| (h - p.range_m).abs() < 1e-6), "{p:?} vs {heard:?}");
                }
            }
        }
    }
}

#[test]
fn sonars_fired_in_groups_read_from_the_pose_of_their_own_moment() {
    use sonarmap::sim::{family_plan, pose_at, simulate_paced, Pace, SceneKind};
    // A room at a crawl (2 cm a cycle, 0.3 s), the ring fired in 4 groups: every reading is the
    // echo the axis model gives from the true pose of its own moment, within the sensor's
    // accuracy and the range's rounding; and it is logged with that moment's offset.
    let mut plan = family_plan(SceneKind::Room, 2);
    (plan.sim.dropout, plan.sim.ghost) = (0.0, 0.0);
    let pace = Pace {
        cycle_step_m: Some(0.02),
        cycle_s: 0.3,
        firing_groups: 4,
        ..Pace::PLAN
    };
    let run = simulate_paced(&plan, Model::Axis, 5, &pace);
    let poses = pace.cycle_poses(&plan.poses);
    assert_eq!(run.snapshots.len(), poses.len());
    assert!(
        poses.len() > 5 * plan.poses.len(),
        "a crawl has more cycles"
    );
    let world = World::new(
        &plan.floor_plan,
        plan.roughness_rad,
        plan.sim.corner_tolerance_m,
    );
    let (mut compared, mut moved_apart) = (0, 0);
    for (i, s) in run.snapshots.iter().enumerate() {
        assert!((s.t - 0.3 * i as f64).abs() < 1e-9);
        assert_eq!(s.reading_dt_s.len(), plan.layout.len());
        for (k, range) in s.ranges_m.iter().enumerate() {
            let dt_s = s.reading_dt_s[k];
            assert!((dt_s + 0.3 * (3 - k % 4) as f64 / 4.0).abs() < 1e-12);
            let Some(range) = range else { continue };
            let at = pose_at(&poses, i, dt_s, 0.3);
            let sensor = plan.layout.sensor_pose_in_world(&at, k);
            let truth = world
                .echo_range(
                    &sensor,
                    plan.sensor.beam_width_rad,
                    plan.sim.ray_step_rad,
                    Model::Axis,
                    0,
                )
                .expect("a reading has an echo");
            let tolerance = truth * plan.sensor.accuracy_pct / 100.0 + plan.sim.resolution_m;
            assert!(
                (range - truth).abs() <= tolerance,
                "{i}/{k}: {range} vs {truth}"
            );
            compared += 1;
            moved_apart += usize::from(at.distance_to(&s.pose) > 1e-6);
        }
    }
    assert!(
        compared > 100 && moved_apart > compared / 2,
        "{compared} {moved_apart}"
    );
}

#[test]
fn the_plans_pace_simulates_as_before() {
    use sonarmap::sim::{family_plan, simulate_paced, Pace, SceneKind};
    let plan = family_plan(SceneKind::Desks, 3);
    let plain = simulate(&plan, Model::Specular, 4);
    assert_eq!(
        save_run(&plain),
        save_run(&simulate_paced(&plan, Model::Specular, 4, &Pace::PLAN))
    );
    assert!(plain.snapshots.iter().all(|s| s.reading_dt_s.is_empty()));
}
