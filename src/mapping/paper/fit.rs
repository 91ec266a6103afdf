//! Recursive line fitting (paper §3.2 after Crowley 1985; docs/algorithm.md §3).
//!
//! Iterative end-point fit on an ordered point list `q_1..q_n`: the chord `q_1 q_n`; the point
//! `q_j` farthest from it (ties: the first); when its distance is strictly greater than the split
//! tolerance, the list splits into `q_1..q_j` and `q_j..q_n` (the corner point is shared) and
//! each half is fitted the same way.

use crate::geometry::{distance_to_line, fit_line_tls, lerp, projection_param, Point};
use crate::mapping::model::map::{EndPoint, SupportPoint};
use crate::mapping::model::params::{FitMode, Params, SplitMode};
use crate::mapping::model::trace::SplitTrace;
use crate::sonar::ball_radius;

/// The split tolerance for a point read at `range_m` (docs/algorithm.md §3): its ball radius
/// `ξ·D/100` in "resolution" mode, or the fixed length.
pub fn split_tolerance(params: &Params, range_m: f64) -> f64 {
    match params.split {
        SplitMode::Resolution => ball_radius(params.accuracy_pct, range_m),
        SplitMode::Fixed(t) => t,
    }
}

/// Splits `points` recursively; appends the pieces to `pieces` as `[first, last]` index pairs
/// in order and every test to `splits`.
///
/// ```
/// use sonarmap::geometry::Point;
/// use sonarmap::mapping::model::map::ReadingRef;
/// use sonarmap::mapping::SupportPoint;
/// let q = |sensor: usize, x: f64, y: f64, range_m: f64| SupportPoint {
///     point: Point::new(x, y),
///     range_m,
///     reading: ReadingRef::new(0, sensor),
/// };
/// use sonarmap::mapping::paper::fit::split_recursive;
/// use sonarmap::mapping::Params;
/// // A corner: (0, 2) (1, 2) (2, 2) (2, 1), read at 2 m (tolerance 0.03·2 = 0.06 m). The line
/// // (0, 2)–(2, 1) leaves (2, 2) 2/√5 ≈ 0.894 m away (the farthest): split there. Then
/// // (0, 2)–(2, 2) holds (1, 2) exactly, and (2, 2)–(2, 1) is two points: two pieces.
/// let points = [q(0, 0.0, 2.0, 2.0), q(1, 1.0, 2.0, 2.0), q(2, 2.0, 2.0, 2.0), q(3, 2.0, 1.0, 2.0)];
/// let (mut splits, mut pieces) = (Vec::new(), Vec::new());
/// split_recursive(&points, &Params::paper(), &mut splits, &mut pieces);
/// assert_eq!(pieces, vec![[0, 2], [2, 3]]);
/// assert_eq!(splits[0].farthest, Some(2));
/// assert!((splits[0].deviation_m - 2.0 / 5f64.sqrt()).abs() < 1e-12);
/// assert!((splits[0].tolerance_m - 0.06).abs() < 1e-12);
/// ```
pub fn split_recursive(
    points: &[SupportPoint],
    params: &Params,
    splits: &mut Vec<SplitTrace>,
    pieces: &mut Vec<[usize; 2]>,
) {
    if points.len() >= 2 {
        split_range(points, 0, points.len() - 1, params, splits, pieces);
    }
}

/// [`split_recursive`] of `points[first..=last]` (`first < last`), its splits and pieces
/// indexed in `points`.
pub fn split_range(
    points: &[SupportPoint],
    first: usize,
    last: usize,
    params: &Params,
    splits: &mut Vec<SplitTrace>,
    pieces: &mut Vec<[usize; 2]>,
) {
    let (a, b) = (points[first].point, points[last].point);
    let mut farthest: Option<(usize, f64)> = None;
    for (j, q) in points.iter().enumerate().take(last).skip(first + 1) {
        let d = distance_to_line(&q.point, &a, &b);
        if farthest.is_none_or(|(_, best)| d > best) {
            farthest = Some((j, d));
        }
    }
    let Some((j, deviation_m)) = farthest else {
        splits.push(SplitTrace {
            first,
            last,
            farthest: None,
            point: None,
            deviation_m: 0.0,
            tolerance_m: 0.0,
            split: false,
        });
        pieces.push([first, last]);
        return;
    };
    let tolerance_m = split_tolerance(params, points[j].range_m);
    let split = deviation_m > tolerance_m;
    splits.push(SplitTrace {
        first,
        last,
        farthest: Some(j),
        point: Some(points[j].point),
        deviation_m,
        tolerance_m,
        split,
    });
    if split {
        split_range(points, first, j, params, splits, pieces);
        split_range(points, j, last, params, splits, pieces);
    } else {
        pieces.push([first, last]);
    }
}

/// The end-points of the piece `points[first..=last]` (docs/algorithm.md §3): its first and last
/// readings, or with total least squares those readings projected on the fitted line. Each
/// end-point keeps the range of the reading that produced it.
pub fn piece_end_points(
    points: &[SupportPoint],
    first: usize,
    last: usize,
    fit: FitMode,
) -> (EndPoint, EndPoint) {
    let (qa, qb) = (&points[first], &points[last]);
    let mut a = EndPoint {
        point: qa.point,
        range_m: qa.range_m,
    };
    let mut b = EndPoint {
        point: qb.point,
        range_m: qb.range_m,
    };
    if fit == FitMode::TotalLeastSquares && last > first + 1 {
        let coords: Vec<Point> = points[first..=last].iter().map(|q| q.point).collect();
        if let Some((centre, dir)) = fit_line_tls(&coords) {
            let far = centre + dir;
            a.point = lerp(&centre, &far, projection_param(&qa.point, &centre, &far));
            b.point = lerp(&centre, &far, projection_param(&qb.point, &centre, &far));
        }
    }
    (a, b)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mapping::model::map::ReadingRef;

    fn pts(coords: &[(f64, f64, f64)]) -> Vec<SupportPoint> {
        coords
            .iter()
            .enumerate()
            .map(|(i, &(x, y, d))| SupportPoint {
                point: Point::new(x, y),
                range_m: d,
                reading: ReadingRef::new(0, i),
            })
            .collect()
    }

    fn split(points: &[SupportPoint], p: &Params, splits: &mut Vec<SplitTrace>) -> Vec<[usize; 2]> {
        let mut pieces = Vec::new();
        split_recursive(points, p, splits, &mut pieces);
        pieces
    }

    #[test]
    fn split_happens_just_above_the_resolution_tolerance() {
        // Middle point read at D = 100 → tolerance 3 (ξ = 3). Deviation 3 ± ε.
        let p = Params::paper();
        let eps = 1e-9;
        let mut splits = Vec::new();
        let below = pts(&[(0.0, 0.0, 50.0), (5.0, 3.0 - eps, 100.0), (10.0, 0.0, 50.0)]);
        assert_eq!(split(&below, &p, &mut splits), vec![[0, 2]]);
        assert!(!splits[0].split && (splits[0].tolerance_m - 3.0).abs() < 1e-12);
        let at = pts(&[(0.0, 0.0, 50.0), (5.0, 3.0, 100.0), (10.0, 0.0, 50.0)]);
        assert_eq!(split(&at, &p, &mut Vec::new()), vec![[0, 2]]);
        let above = pts(&[(0.0, 0.0, 50.0), (5.0, 3.0 + eps, 100.0), (10.0, 0.0, 50.0)]);
        let mut splits = Vec::new();
        assert_eq!(split(&above, &p, &mut splits), vec![[0, 1], [1, 2]]);
        assert!(splits[0].split && splits[0].farthest == Some(1));
        assert_eq!(splits.len(), 3);
    }

    #[test]
    fn fixed_tolerance_and_first_of_equal_deviations() {
        let p = Params {
            split: SplitMode::Fixed(0.4),
            ..Params::paper()
        };
        let corner = pts(&[
            (0.0, 0.0, 1.0),
            (1.0, 1.0, 1.0),
            (2.0, 1.0, 1.0),
            (3.0, 0.0, 1.0),
        ]);
        let mut splits = Vec::new();
        let pieces = split(&corner, &p, &mut splits);
        assert_eq!(splits[0].farthest, Some(1), "ties go to the first");
        assert_eq!(pieces, vec![[0, 1], [1, 2], [2, 3]]);
    }

    #[test]
    fn total_least_squares_projects_the_end_readings() {
        // Symmetric about y = 0: the fitted line is the x axis.
        let q = pts(&[
            (0.0, 1.0, 10.0),
            (1.0, -1.0, 11.0),
            (2.0, -1.0, 12.0),
            (3.0, 1.0, 13.0),
        ]);
        let (a, b) = piece_end_points(&q, 0, 3, FitMode::TotalLeastSquares);
        assert!((a.point - Point::new(0.0, 0.0)).norm() < 1e-12);
        assert!((b.point - Point::new(3.0, 0.0)).norm() < 1e-12);
        assert_eq!((a.range_m, b.range_m), (10.0, 13.0));
        let (a, _) = piece_end_points(&q, 0, 3, FitMode::EndPoints);
        assert_eq!(a.point, Point::new(0.0, 1.0));
    }
}
