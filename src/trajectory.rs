//! Trajectories in the TUM format that trajectory tools (evo, the TUM RGB-D benchmark's
//! scripts) read: one line per pose, `timestamp tx ty tz qx qy qz qw`, metres and seconds.

use crate::geometry::Pose;

/// The poses, one per time, as a TUM trajectory: the robot in the plane (`tz` = 0), its heading
/// a rotation about z (`qx` = `qy` = 0, `qz` = sin(θ/2), `qw` = cos(θ/2)).
///
/// ```
/// use sonarmap::geometry::Pose;
/// use sonarmap::trajectory::tum_trajectory;
/// let text = tum_trajectory(&[0.5], &[Pose::new(1.0, 2.0, std::f64::consts::PI)]);
/// assert_eq!(text, "# timestamp tx ty tz qx qy qz qw\n0.5 1 2 0 0 0 1.000000000 0.000000000\n");
/// ```
pub fn tum_trajectory(times_s: &[f64], poses: &[Pose]) -> String {
    let mut out = String::from("# timestamp tx ty tz qx qy qz qw\n");
    for (t, p) in times_s.iter().zip(poses) {
        let (qz, qw) = (p.heading_rad / 2.0).sin_cos();
        out.push_str(&format!("{t} {} {} 0 0 0 {qz:.9} {qw:.9}\n", p.x, p.y));
    }
    out
}
