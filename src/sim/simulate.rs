//! The simulator: a plan's path through the beam model, with the sensor's noise, into a run.

use super::beam::{Model, World};
use super::plan::Plan;
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
    let snapshots = plan
        .poses
        .iter()
        .enumerate()
        .map(|(i, pose)| {
            let ranges_m = (0..plan.layout.len())
                .map(|k| {
                    let u_drop: f64 = rng.random();
                    let u_ghost: f64 = rng.random();
                    let u_noise: f64 = rng.random();
                    let u_far: f64 = rng.random();
                    let sensor_pose = plan.layout.sensor_pose_in_world(pose, k);
                    let truth = world.echo_range(
                        &sensor_pose,
                        sensor.beam_width_rad,
                        sim.ray_step_rad,
                        model,
                    );
                    let range = if u_drop < sim.dropout {
                        None
                    } else if u_ghost < sim.ghost {
                        let from = truth.unwrap_or(sensor.min_range_m).min(sensor.max_range_m);
                        Some(from + u_far * (sensor.max_range_m - from))
                    } else {
                        truth.map(|r| {
                            r * (1.0 + sensor.accuracy_pct / 100.0 * (2.0 * u_noise - 1.0))
                        })
                    };
                    range
                        .map(|r| (r / sim.resolution_m).round() * sim.resolution_m)
                        .filter(|r| *r < sensor.max_range_m)
                })
                .collect();
            Snapshot {
                t: i as f64,
                pose: *pose,
                ranges_m,
                true_pose: None,
                reading_dt_s: Vec::new(),
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
