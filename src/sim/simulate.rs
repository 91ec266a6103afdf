//! The simulator: a plan's path through the beam model, with the sensor's noise, into a run.

use super::beam::{Model, World};
use super::pace::{pose_at, Pace};
use super::plan::{Plan, SimSettings};
use crate::run::{Run, Snapshot};
use crate::sonar::{EchoModel, SensorSpec};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Simulates one snapshot per pose of `plan`. Each reading draws four numbers from a
/// `ChaCha8Rng` seeded with `seed`, in snapshot then sensor order, so the same plan, model and
/// seed always give the same run:
/// - with probability `sim.dropout` the reading is lost (`None`);
/// - else with probability `sim.ghost` it is a multipath ghost, a range drawn uniformly between
///   the true range (or the minimum range when nothing echoes) and the maximum range;
/// - else the true range is scaled by `1 + a·u/100` (`a` the sensor's accuracy, `u` uniform in
///   [-1, 1]).
///
/// Then the range is rounded to a multiple of `sim.resolution_m`; a range at or beyond the
/// sensor's maximum is no echo (`None`). The run carries the plan's floor plan as ground truth.
pub fn simulate(plan: &Plan, model: Model, seed: u64) -> Run {
    simulate_paced(plan, model, seed, &Pace::PLAN)
}

/// [`simulate`] at `pace`: the snapshots at [`Pace::cycle_poses`], `pace.cycle_s` apart, each
/// reading taken from the robot's true pose at its own moment ([`Pace::reading_dt_s`]) and
/// logged with that offset (`reading_dt_s`) when the sensors fire in groups. The same draws in
/// the same order as [`simulate`], which is this at [`Pace::PLAN`].
pub fn simulate_paced(plan: &Plan, model: Model, seed: u64, pace: &Pace) -> Run {
    let world = World::new(
        &plan.floor_plan,
        plan.roughness_rad,
        plan.sim.corner_tolerance_m,
    );
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    // The run says where its echoes came from: the axis model's single ray reads along the axis.
    let sensor = SensorSpec {
        echo: match model {
            Model::Specular => EchoModel::Cone,
            Model::Axis => EchoModel::Axis,
        },
        ..plan.sensor
    };
    let sim = plan.sim;
    let poses = pace.cycle_poses(&plan.poses);
    let fired_in_groups = pace.firing_groups > 1;
    let reading_dt_s: Vec<f64> = if fired_in_groups {
        (0..plan.layout.len())
            .map(|k| pace.reading_dt_s(k))
            .collect()
    } else {
        Vec::new()
    };
    let snapshots = poses
        .iter()
        .enumerate()
        .map(|(i, pose)| {
            let ranges_m = (0..plan.layout.len())
                .map(|k| {
                    let u_drop: f64 = rng.random();
                    let u_ghost: f64 = rng.random();
                    let u_noise: f64 = rng.random();
                    let u_far: f64 = rng.random();
                    let robot_pose = if fired_in_groups {
                        pose_at(&poses, i, reading_dt_s[k], pace.cycle_s)
                    } else {
                        *pose
                    };
                    let sensor_pose = plan.layout.sensor_pose_in_world(&robot_pose, k);
                    let truth = world.echo_range(
                        &sensor_pose,
                        sensor.beam_width_rad,
                        sim.ray_step_rad,
                        model,
                        sim.bounces,
                    );
                    noisy_range(truth, [u_drop, u_ghost, u_noise, u_far], &sensor, &sim)
                })
                .collect();
            Snapshot {
                t: i as f64 * pace.cycle_s,
                pose: *pose,
                ranges_m,
                true_pose: None,
                reading_dt_s: reading_dt_s.clone(),
            }
        })
        .collect();
    Run {
        name: plan.name.clone(),
        units: plan.units,
        robot_radius_m: plan.robot_radius_m,
        layout: plan.layout.clone(),
        sensor,
        floor_plan: Some(plan.floor_plan.clone()),
        snapshots,
    }
}

/// What the sensor logs of the `truth` (the beam model's range, or none) given the reading's
/// four uniform draws `[drop, ghost, noise, far]`: lost, a ghost, or the truth with its noise;
/// rounded to the simulator's resolution, no echo at the maximum range.
fn noisy_range(
    truth: Option<f64>,
    [u_drop, u_ghost, u_noise, u_far]: [f64; 4],
    sensor: &SensorSpec,
    sim: &SimSettings,
) -> Option<f64> {
    let range = if u_drop < sim.dropout {
        None
    } else if u_ghost < sim.ghost {
        let from = truth.unwrap_or(sensor.min_range_m).min(sensor.max_range_m);
        Some(from + u_far * (sensor.max_range_m - from))
    } else {
        truth.map(|r| r * (1.0 + sensor.accuracy_pct / 100.0 * (2.0 * u_noise - 1.0)))
    };
    range
        .map(|r| (r / sim.resolution_m).round() * sim.resolution_m)
        .filter(|r| *r < sensor.max_range_m)
}
