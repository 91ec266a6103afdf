//! How far a run's poses (the odometry the engine maps with) lie from the truth its snapshots
//! keep (`true_pose`, a simulated run given odometry error): the figures `eval` reports.

use crate::geometry::{wrap_pi, Pose};
use crate::run::Run;
use serde::{Deserialize, Serialize};

/// The pose error over the snapshots that know their true pose. Lengths in the log's units.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PoseError {
    /// Snapshots with a true pose.
    pub snapshots: usize,
    /// Root mean square distance between pose and true pose.
    pub rms_position: f64,
    /// Root mean square of its part across the true heading (the lateral error).
    #[serde(default)]
    pub rms_lateral: f64,
    /// Root mean square of its part along the true heading.
    #[serde(default)]
    pub rms_along: f64,
    /// Largest distance.
    pub max_position: f64,
    /// Distance at the last such snapshot.
    pub final_position: f64,
    /// Root mean square heading difference, degrees.
    pub rms_heading_deg: f64,
    /// Largest heading difference, degrees.
    pub max_heading_deg: f64,
}

/// The pose error of `run`; `None` when no snapshot knows its true pose.
///
/// ```
/// use sonarmap::geometry::Pose;
/// use sonarmap::pose_error::pose_error;
/// let mut run = sonarmap::assets::default_run().unwrap();
/// assert!(pose_error(&run).is_none());
/// // 3 and 4 in off (5 in), then exact; 0.1 rad then 0 of heading.
/// let p0 = run.snapshots[0].pose;
/// run.snapshots[0].true_pose = Some(Pose::new(p0.x + 0.0762, p0.y + 0.1016, p0.heading_rad + 0.1));
/// run.snapshots[1].true_pose = Some(run.snapshots[1].pose);
/// let e = pose_error(&run).unwrap();
/// assert_eq!(e.snapshots, 2);
/// assert!((e.max_position - 5.0).abs() < 1e-9 && e.final_position.abs() < 1e-9);
/// assert!((e.rms_position - (25.0f64 / 2.0).sqrt()).abs() < 1e-9);
/// assert!((e.rms_heading_deg - 0.1f64.to_degrees() / 2f64.sqrt()).abs() < 1e-9);
/// // Facing +y, the truth 3 in behind in x and 4 in behind in y: 4 in along, 3 in across.
/// let facing_y = std::f64::consts::FRAC_PI_2;
/// run.snapshots.truncate(1);
/// run.snapshots[0].pose = Pose::new(0.0762, 0.1016, facing_y);
/// run.snapshots[0].true_pose = Some(Pose::new(0.0, 0.0, facing_y));
/// let e = pose_error(&run).unwrap();
/// assert!((e.rms_along - 4.0).abs() < 1e-9 && (e.rms_lateral - 3.0).abs() < 1e-9);
/// ```
pub fn pose_error(run: &Run) -> Option<PoseError> {
    pose_error_of(run, run.snapshots.iter().map(|s| s.pose))
}

/// [`pose_error`] of `poses` (one per snapshot, in order: the poses the engine used, corrected
/// or not) against the run's truth.
pub fn pose_error_of(run: &Run, poses: impl IntoIterator<Item = Pose>) -> Option<PoseError> {
    let errors: Vec<StepError> = run
        .snapshots
        .iter()
        .zip(poses)
        .filter_map(|(s, pose)| {
            let truth = s.true_pose?;
            let in_truth_frame = truth.relative_to(&pose);
            Some(StepError {
                distance_m: pose.distance_to(&truth),
                along_m: in_truth_frame.x,
                lateral_m: in_truth_frame.y,
                turn_rad: wrap_pi(pose.heading_rad - truth.heading_rad).abs(),
            })
        })
        .collect();
    let n = errors.len();
    if n == 0 {
        return None;
    }
    let rms = |f: &dyn Fn(&StepError) -> f64| {
        (errors.iter().map(|e| f(e).powi(2)).sum::<f64>() / n as f64).sqrt()
    };
    let max = |f: &dyn Fn(&StepError) -> f64| errors.iter().map(f).fold(0.0, f64::max);
    let u = run.units;
    Some(PoseError {
        snapshots: n,
        rms_position: u.from_m(rms(&|e| e.distance_m)),
        rms_lateral: u.from_m(rms(&|e| e.lateral_m)),
        rms_along: u.from_m(rms(&|e| e.along_m)),
        max_position: u.from_m(max(&|e| e.distance_m)),
        final_position: u.from_m(errors[n - 1].distance_m),
        rms_heading_deg: rms(&|e| e.turn_rad).to_degrees(),
        max_heading_deg: max(&|e| e.turn_rad).to_degrees(),
    })
}

/// One snapshot's error: the distance, its parts along and across the true heading, and the
/// turn between the headings.
struct StepError {
    distance_m: f64,
    along_m: f64,
    lateral_m: f64,
    turn_rad: f64,
}
