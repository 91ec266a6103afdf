//! The parts of a floor plan's walls near the robot's path: what a run could have mapped, as a
//! real run is scored against a plan that shows far more than the robot passed (issue 40's
//! "coverage near the path", wall length within [`NEAR_PATH_M`] of the path).

use crate::geometry::Point;
use crate::intervals::union;

/// How near the path a wall's point must lie to count, metres.
pub const NEAR_PATH_M: f64 = 1.5;

/// The sorted, disjoint parameter intervals (0 to 1 along `a`→`b`) of the wall's points within
/// `radius_m` of one of `path`'s points.
pub fn near_path_spans(a: &Point, b: &Point, path: &[Point], radius_m: f64) -> Vec<(f64, f64)> {
    let ab = b - a;
    let len2 = ab.norm_squared();
    let mut spans: Vec<(f64, f64)> = Vec::new();
    for p in path {
        let ap = p - a;
        if len2 <= 0.0 {
            if ap.norm() <= radius_m {
                spans.push((0.0, 1.0));
            }
            continue;
        }
        // |ap − t·ab|² ≤ r²: t² len2 − 2t (ap·ab) + |ap|² − r² ≤ 0.
        let centre = ap.dot(&ab) / len2;
        let half2 = centre * centre - (ap.norm_squared() - radius_m * radius_m) / len2;
        if half2 < 0.0 {
            continue;
        }
        let half = half2.sqrt();
        let (lo, hi) = ((centre - half).max(0.0), (centre + half).min(1.0));
        if lo <= hi {
            spans.push((lo, hi));
        }
    }
    union(spans)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_point_2_m_above_the_middle_of_a_10_m_wall_sees_what_its_circle_cuts() {
        // Radius 2.5 m, height 2 m: half-chord sqrt(2.5² − 2²) = 1.5 m, so x 3.5..6.5 of 0..10.
        let (a, b) = (Point::new(0.0, 0.0), Point::new(10.0, 0.0));
        let spans = near_path_spans(&a, &b, &[Point::new(5.0, 2.0)], 2.5);
        assert_eq!(spans.len(), 1);
        assert!((spans[0].0 - 0.35).abs() < 1e-12 && (spans[0].1 - 0.65).abs() < 1e-12);
        // Two points 2 m apart along it join; one too far away adds nothing.
        let path = [
            Point::new(5.0, 2.0),
            Point::new(7.0, 2.0),
            Point::new(5.0, 9.0),
        ];
        let spans = near_path_spans(&a, &b, &path, 2.5);
        assert_eq!(spans.len(), 1);
        assert!((spans[0].0 - 0.35).abs() < 1e-12 && (spans[0].1 - 0.85).abs() < 1e-12);
        // Near an end the interval is clamped to the wall.
        let spans = near_path_spans(&a, &b, &[Point::new(-1.0, 0.0)], 1.5);
        assert_eq!(spans.len(), 1);
        assert!(
            spans[0].0 == 0.0 && (spans[0].1 - 0.05).abs() < 1e-12,
            "{spans:?}"
        );
    }
}
