//! Constant-depth groups (docs/algorithm.md §8.2; beyond the paper): Leonard and
//! Durrant-Whyte's regions of constant depth, a run of readings of one range that a wall seen
//! square-on by neighbouring sonars returns, reduced to its middle reading.

use crate::mapping::model::map::SupportPoint;
use crate::mapping::model::trace::ConstantDepthTrace;

/// True when two ranges pass the ball test of §1 as ranges: `|D1 − D2| ≤ ξ·(D1 + D2)/100`.
pub(crate) fn same_depth(accuracy_pct: f64, d1: f64, d2: f64) -> bool {
    (d1 - d2).abs() <= accuracy_pct * (d1 + d2) / 100.0
}

/// Constant-depth groups (Leonard and Durrant-Whyte's "regions of constant depth"): within a
/// cluster, each maximal run (scanning in chain order) of three or more consecutive readings
/// whose ranges pass the ball test pairwise is replaced by its middle reading (the lower
/// middle for an even run). Returns the reduced points and what was replaced.
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
/// use sonarmap::mapping::ext::constant_depth::reduce_constant_depth;
/// // Ranges 2.00, 2.05, 2.10, 3.00 at ξ = 3: |2.00 − 2.10| = 0.10 ≤ 0.03·4.10 = 0.123, so the
/// // first three pass pairwise and become their middle reading (sensor 1); 3.00 fails with all.
/// let chain = [q(0, 0.0, 2.0, 2.0), q(1, 1.0, 2.05, 2.05), q(2, 2.0, 2.1, 2.1), q(3, 3.0, 3.0, 3.0)];
/// let (reduced, groups) = reduce_constant_depth(&chain, 3.0);
/// let sensors: Vec<usize> = reduced.iter().map(|p| p.reading.sensor()).collect();
/// assert_eq!(sensors, vec![1, 3]);
/// assert_eq!(groups[0].sensors, vec![0, 1, 2]);
/// assert_eq!(groups[0].kept_sensor, 1);
/// ```
pub fn reduce_constant_depth(
    points: &[SupportPoint],
    accuracy_pct: f64,
) -> (Vec<SupportPoint>, Vec<ConstantDepthTrace>) {
    let mut out = points.to_vec();
    let traces = reduce_constant_depth_in_place(&mut out, accuracy_pct);
    (out, traces)
}

/// [`reduce_constant_depth`] on `points` itself: each run becomes its middle reading where the
/// run began (a cluster with no run of three keeps its points, and nothing is allocated).
/// Returns what was replaced.
pub fn reduce_constant_depth_in_place(
    points: &mut Vec<SupportPoint>,
    accuracy_pct: f64,
) -> Vec<ConstantDepthTrace> {
    let mut traces = Vec::new();
    // Points are written at `kept`, never past the reading at `i`: every later read is ahead.
    let mut kept = 0;
    let mut i = 0;
    while i < points.len() {
        let mut j = i + 1;
        while j < points.len()
            && points[i..j]
                .iter()
                .all(|q| same_depth(accuracy_pct, q.range_m, points[j].range_m))
        {
            j += 1;
        }
        if j - i >= 3 {
            let middle = points[i + (j - i - 1) / 2];
            traces.push(ConstantDepthTrace {
                sensors: points[i..j].iter().map(|q| q.reading.sensor()).collect(),
                kept_sensor: middle.reading.sensor(),
            });
            points[kept] = middle;
            i = j;
        } else {
            points[kept] = points[i];
            i += 1;
        }
        kept += 1;
    }
    points.truncate(kept);
    traces
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Point;
    use crate::mapping::model::map::ReadingRef;

    fn sp(snapshot: usize, sensor: usize, x: f64, y: f64, d: f64) -> SupportPoint {
        SupportPoint {
            point: Point::new(x, y),
            range_m: d,
            reading: ReadingRef::new(snapshot, sensor),
        }
    }

    #[test]
    fn a_run_of_equal_depths_becomes_its_middle_reading() {
        // Ranges 100, 101, 99, 100 pass pairwise at ξ = 3; then 150 does not.
        let pts = vec![
            sp(0, 0, 0.0, 0.0, 100.0),
            sp(0, 1, 1.0, 0.0, 101.0),
            sp(0, 2, 2.0, 0.0, 99.0),
            sp(0, 3, 3.0, 0.0, 100.0),
            sp(0, 4, 4.0, 0.0, 150.0),
        ];
        let (out, traces) = reduce_constant_depth(&pts, 3.0);
        assert_eq!(
            out.iter().map(|q| q.reading.sensor()).collect::<Vec<_>>(),
            vec![1, 4]
        );
        assert_eq!(
            traces,
            vec![ConstantDepthTrace {
                sensors: vec![0, 1, 2, 3],
                kept_sensor: 1
            }]
        );
        // Two equal readings are not a group.
        let (out, traces) = reduce_constant_depth(&pts[3..], 3.0);
        assert_eq!(out.len(), 2);
        assert!(traces.is_empty());
    }
}
