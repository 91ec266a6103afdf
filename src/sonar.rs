//! Sensor layouts and the reading → point conversion (paper §2, §3.1; docs/algorithm.md §1).

use crate::geometry::{normalize_angle_positive, unit, Point, Pose, Vec2};
use serde::{Deserialize, Serialize};

/// One sonar's mount pose in the robot frame.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct SensorMount {
    /// Mount position, robot x, metres.
    pub x_m: f64,
    /// Mount position, robot y, metres.
    pub y_m: f64,
    /// Beam axis against the robot's x axis, radians.
    pub heading_rad: f64,
}

/// The sonars of a robot, sensor `k` at index `k`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SensorLayout {
    /// Mount poses in the robot frame.
    pub mounts: Vec<SensorMount>,
}

impl SensorLayout {
    /// The paper's ring (§3.1): `count` sonars, sonar `k` at `first + k·spacing`, mounted at
    /// `radius_m·(cos α_k, sin α_k)` and facing `α_k`.
    pub fn ring(count: usize, spacing_rad: f64, first_rad: f64, radius_m: f64) -> Self {
        let mounts = (0..count)
            .map(|k| {
                let alpha = first_rad + spacing_rad * k as f64;
                SensorMount {
                    x_m: radius_m * alpha.cos(),
                    y_m: radius_m * alpha.sin(),
                    heading_rad: alpha,
                }
            })
            .collect();
        Self { mounts }
    }

    /// The Nomad 200 ring of the paper: 16 sonars 22.5° apart.
    pub fn nomad_ring(radius_m: f64) -> Self {
        Self::ring(16, 22.5f64.to_radians(), 0.0, radius_m)
    }

    /// Number of sensors.
    pub fn len(&self) -> usize {
        self.mounts.len()
    }

    /// True when the layout has no sensor.
    pub fn is_empty(&self) -> bool {
        self.mounts.is_empty()
    }

    /// Sensor indices in clustering order (docs/algorithm.md §2): by mount bearing in [0°, 360°),
    /// ties by index, starting just after the largest gap unless the layout wraps.
    /// Returns the order and whether the last neighbours the first.
    pub fn bearing_order(&self) -> (Vec<usize>, bool) {
        let n = self.mounts.len();
        let mut order: Vec<usize> = (0..n).collect();
        let bearing = |k: usize| normalize_angle_positive(self.mounts[k].heading_rad);
        order.sort_by(|&a, &b| bearing(a).total_cmp(&bearing(b)).then(a.cmp(&b)));
        if n < 2 {
            return (order, false);
        }
        let mut largest_gap = -1.0;
        let mut start = 0;
        for i in 0..n {
            let here = bearing(order[i]);
            let next = if i + 1 < n {
                bearing(order[i + 1])
            } else {
                bearing(order[0]) + std::f64::consts::TAU
            };
            let gap = next - here;
            if gap > largest_gap {
                largest_gap = gap;
                start = (i + 1) % n;
            }
        }
        let wraps = largest_gap <= std::f64::consts::FRAC_PI_2 + 1e-9;
        if !wraps {
            order.rotate_left(start);
        }
        (order, wraps)
    }

    /// World point of an echo at `range_m` on sensor `k`'s beam axis (β = 0):
    /// `p = R + Rot(γ)·(m_k + D·(cos θ_k, sin θ_k))`.
    pub fn point_in_world(&self, pose: &Pose, k: usize, range_m: f64) -> Point {
        pose.world_from_robot(&self.beam_axis(k).point_at(range_m))
    }

    /// Sensor `k`'s beam axis in the robot frame.
    pub fn beam_axis(&self, k: usize) -> BeamAxis {
        let m = &self.mounts[k];
        BeamAxis {
            origin_in_robot: Point::new(m.x_m, m.y_m),
            direction_in_robot: unit(m.heading_rad),
        }
    }

    /// Every sensor's beam axis, in sensor order (to convert many readings without a sine
    /// and cosine each).
    pub fn beam_axes(&self) -> Vec<BeamAxis> {
        (0..self.len()).map(|k| self.beam_axis(k)).collect()
    }

    /// World pose of sensor `k` (its position and beam heading).
    pub fn sensor_pose_in_world(&self, pose: &Pose, k: usize) -> Pose {
        let m = &self.mounts[k];
        let p = pose.world_from_robot(&Point::new(m.x_m, m.y_m));
        Pose::new(p.x, p.y, pose.heading_rad + m.heading_rad)
    }
}

/// A sensor's beam axis (β = 0) in the robot frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BeamAxis {
    /// The mount position.
    pub origin_in_robot: Point,
    /// Unit vector along the beam.
    pub direction_in_robot: Vec2,
}

impl BeamAxis {
    /// The point at `range_m` along the axis, in the robot frame.
    pub fn point_at(&self, range_m: f64) -> Point {
        self.origin_in_robot + self.direction_in_robot * range_m
    }
}

/// The sonar hardware (docs/formats.md §2 `sensor`; defaults: the Polaroid 6500).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct SensorSpec {
    /// Stated accuracy, percent of range.
    pub accuracy_pct: f64,
    /// Full beam width, radians.
    pub beam_width_rad: f64,
    /// Largest range reported; a value at or beyond it means no echo. Metres.
    pub max_range_m: f64,
    /// Blind zone. Metres.
    pub min_range_m: f64,
    /// Where an echo comes from (docs/formats.md §2 `sensor.echo`).
    pub echo: EchoModel,
}

/// Where a ranger's echo comes from.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum EchoModel {
    /// Anywhere in the beam cone: the nearest surface point that sends the sound back (an
    /// ultrasonic sonar; the default).
    #[default]
    Cone,
    /// On the beam axis only (a single-ray ranger such as an infrared or laser range finder,
    /// or a simulator's ideal ray).
    Axis,
}

impl EchoModel {
    /// Its name in a log file.
    pub fn name(self) -> &'static str {
        match self {
            EchoModel::Cone => "cone",
            EchoModel::Axis => "axis",
        }
    }

    /// The model a log file names, if any.
    pub fn parse(name: &str) -> Option<EchoModel> {
        match name {
            "cone" => Some(EchoModel::Cone),
            "axis" => Some(EchoModel::Axis),
            _ => None,
        }
    }
}

impl Default for SensorSpec {
    fn default() -> Self {
        Self {
            accuracy_pct: 1.0,
            beam_width_rad: 25f64.to_radians(),
            max_range_m: crate::units::inches(255.0),
            min_range_m: crate::units::inches(6.0),
            echo: EchoModel::Cone,
        }
    }
}

/// Radius of a reading's uncertainty ball, `ρ = ξ·D/100` (paper §2).
pub fn ball_radius(accuracy_pct: f64, range_m: f64) -> f64 {
    accuracy_pct * range_m / 100.0
}

/// The paper's ball test (§2): two readings match when their balls intersect,
/// `|p1 − p2| ≤ ξ·(D1 + D2)/100`.
pub fn balls_intersect(accuracy_pct: f64, p1: &Point, d1: f64, p2: &Point, d2: f64) -> bool {
    (p1 - p2).norm() <= accuracy_pct * (d1 + d2) / 100.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ring_point_matches_the_papers_formula() {
        // x_k = D cos(α_k+γ) + r cos(α_k+γ) + R_x (§3.1, β = 0).
        let r = 9.0;
        let layout = SensorLayout::nomad_ring(r);
        let gamma = 30f64.to_radians();
        let pose = Pose::new(120.0, 77.0, gamma);
        for k in 0..16 {
            let d = 50.0 + k as f64;
            let alpha = (22.5 * k as f64).to_radians();
            let x = d * (alpha + gamma).cos() + r * (alpha + gamma).cos() + 120.0;
            let y = d * (alpha + gamma).sin() + r * (alpha + gamma).sin() + 77.0;
            let p = layout.point_in_world(&pose, k, d);
            assert!(
                (p.x - x).abs() < 1e-9 && (p.y - y).abs() < 1e-9,
                "sensor {k}"
            );
        }
    }

    #[test]
    fn ball_test_is_inclusive() {
        // ξ = 3, D1 = 100, D2 = 100: radius sum 6.
        let a = Point::new(0.0, 0.0);
        assert!(balls_intersect(
            3.0,
            &a,
            100.0,
            &Point::new(6.0, 0.0),
            100.0
        ));
        assert!(!balls_intersect(
            3.0,
            &a,
            100.0,
            &Point::new(6.0001, 0.0),
            100.0
        ));
        assert!((ball_radius(3.0, 50.0) - 1.5).abs() < 1e-12);
    }

    /// The Pioneer's 8 front and 8 rear sonars (mounts in metres, headings in degrees).
    fn pioneer_8_8() -> SensorLayout {
        let m = [
            (0.069, 0.136, 90.0),
            (0.114, 0.119, 50.0),
            (0.148, 0.078, 30.0),
            (0.166, 0.027, 10.0),
            (0.166, -0.027, -10.0),
            (0.148, -0.078, -30.0),
            (0.114, -0.119, -50.0),
            (0.069, -0.136, -90.0),
            (-0.157, -0.136, -90.0),
            (-0.203, -0.119, -130.0),
            (-0.237, -0.078, -150.0),
            (-0.255, -0.027, -170.0),
            (-0.255, 0.027, 170.0),
            (-0.237, 0.078, 150.0),
            (-0.203, 0.119, 130.0),
            (-0.157, 0.136, 90.0),
        ];
        SensorLayout {
            mounts: m
                .iter()
                .map(|&(x_m, y_m, h): &(f64, f64, f64)| SensorMount {
                    x_m,
                    y_m,
                    heading_rad: h.to_radians(),
                })
                .collect(),
        }
    }

    #[test]
    fn pioneer_8_8_and_a_24_ring_are_expressible() {
        let pioneer = pioneer_8_8();
        let (order, wraps) = pioneer.bearing_order();
        assert!(
            wraps,
            "front and rear arcs cover the circle (largest gap 40°)"
        );
        assert_eq!(order.len(), 16);
        // Sonar 3 (10°) at 1 m from a robot at the origin facing +x.
        let p = pioneer.point_in_world(&Pose::new(0.0, 0.0, 0.0), 3, 1.0);
        assert!((p.x - (0.166 + 10f64.to_radians().cos())).abs() < 1e-12);
        assert!((p.y - (0.027 + 10f64.to_radians().sin())).abs() < 1e-12);
        let ring24 = SensorLayout::ring(24, 15f64.to_radians(), 7.5f64.to_radians(), 0.25);
        assert_eq!(ring24.len(), 24);
        assert!(ring24.bearing_order().1);
        assert!((ring24.mounts[23].heading_rad.to_degrees() - 352.5).abs() < 1e-9);
    }

    #[test]
    fn full_ring_wraps_and_a_front_arc_starts_after_the_largest_gap() {
        let (order, wraps) = SensorLayout::nomad_ring(0.2).bearing_order();
        assert!(wraps);
        assert_eq!(order, (0..16).collect::<Vec<_>>());
        // Pioneer-like front arc: -90..90 in 8 sensors, sensor 0 at +90.
        let angles = [90.0, 50.0, 30.0, 10.0, -10.0, -30.0, -50.0, -90.0];
        let layout = SensorLayout {
            mounts: angles
                .iter()
                .map(|a: &f64| SensorMount {
                    x_m: 0.0,
                    y_m: 0.0,
                    heading_rad: a.to_radians(),
                })
                .collect(),
        };
        let (order, wraps) = layout.bearing_order();
        assert!(!wraps);
        assert_eq!(order, vec![7, 6, 5, 4, 3, 2, 1, 0]);
    }
}
