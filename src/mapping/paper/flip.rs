//! Flip points: the parameter value at which one test's result would change, computed from the
//! test's formula on the numbers the trace holds ("this test alone, the map as it is": a
//! different parameter would also change what came before, which this does not re-run).
//! - Orientation (docs/algorithm.md §4): passes while `θ_o ≥ angle`, so it flips at the angle.
//! - Colinearity (§4): passes while `|d| ≤ ξ/100·(D1 + (D2 + D3)/2)`, so it flips at
//!   `ξ = 100·|d| / (D1 + (D2 + D3)/2)`.
//! - Clustering (§2): neighbours stay together while their distance is `≤ t_gap`, so a gap
//!   flips at its distance: the cluster breaks below its largest inner gap and joins a
//!   neighbour at or above the gap that ended it.

use crate::mapping::model::trace::{ClusterTrace, ColinearityTest, GapTrace, PairEvaluation};

/// The θ_o (radians) at which the orientation test of `e` flips: it passes for θ_o at or above.
pub fn orientation_flip_rad(e: &PairEvaluation) -> f64 {
    e.orientation.value
}

/// The accuracy ξ (percent) at which the colinearity test flips: it passes for ξ at or above.
///
/// ```
/// use sonarmap::mapping::paper::flip::colinearity_flip_pct;
/// use sonarmap::mapping::model::trace::{ColinearityTest, Test};
/// // |d| = 0.05 m, D1 = 2 m, D2 = D3 = 2 m: ξ = 100·0.05 / (2 + 2) = 1.25 %.
/// let c = ColinearityTest {
///     test: Test::at_most(0.05, 0.12),
///     d1_m: 2.0,
///     d2_m: 2.0,
///     d3_m: 2.0,
///     foot_param: 0.5,
/// };
/// assert!((colinearity_flip_pct(&c) - 1.25).abs() < 1e-12);
/// ```
pub fn colinearity_flip_pct(c: &ColinearityTest) -> f64 {
    let ranges = c.d1_m + (c.d2_m + c.d3_m) / 2.0;
    if ranges > 0.0 {
        100.0 * c.test.value.abs() / ranges
    } else {
        f64::INFINITY
    }
}

/// The t_gap flip points of `cluster` among a step's `gaps`: the largest gap inside it (a
/// t_gap below it breaks the cluster; `None` for a single point) and the gaps that ended it on
/// either side (a t_gap at or above one joins the neighbour; `None` where no break bounds it,
/// or where the break is across a right angle, §8.20, which no t_gap joins).
pub fn cluster_gap_flips(
    cluster: &ClusterTrace,
    gaps: &[GapTrace],
) -> (Option<f64>, [Option<f64>; 2]) {
    let inside = |s: usize| cluster.sensors.contains(&s);
    let inner = gaps
        .iter()
        .filter(|g| !g.is_break && inside(g.from_sensor) && inside(g.to_sensor))
        .map(|g| g.distance_m)
        .fold(None, |m: Option<f64>, d| Some(m.map_or(d, |m| m.max(d))));
    let (first, last) = (cluster.sensors.first(), cluster.sensors.last());
    let before = gaps
        .iter()
        .find(|g| g.is_break && Some(&g.to_sensor) == first)
        .filter(|g| !g.across_right_angle)
        .map(|g| g.distance_m);
    let after = gaps
        .iter()
        .find(|g| g.is_break && Some(&g.from_sensor) == last)
        .filter(|g| !g.across_right_angle)
        .map(|g| g.distance_m);
    (inner, [before, after])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn gap(from_sensor: usize, to_sensor: usize, distance_m: f64) -> GapTrace {
        GapTrace {
            from_sensor,
            to_sensor,
            distance_m,
            t_gap_m: 1.0,
            is_break: distance_m > 1.0,
            across_right_angle: false,
        }
    }

    #[test]
    fn the_pair_tests_flip_at_the_computed_theta_and_xi() {
        use crate::geometry::Point;
        use crate::mapping::paper::matching::{evaluate_pair, SegmentEnds};
        use crate::mapping::{EndPoint, Params};
        let end = |x: f64, y: f64, d: f64| EndPoint {
            point: Point::new(x, y),
            range_m: d,
        };
        // l_n tilted by atan(0.1/2) ≈ 2.86° and 0.05 m off l_e at its mid-point.
        let new = SegmentEnds {
            a: end(0.0, 0.0, 2.0),
            b: end(2.0, 0.1, 2.0),
        };
        let existing = SegmentEnds {
            a: end(0.0, 0.0, 2.0),
            b: end(2.0, 0.0, 2.0),
        };
        let e = evaluate_pair(&Params::paper(), &new, 1, &existing);
        let theta = orientation_flip_rad(&e);
        assert!((theta - (0.05f64).atan()).abs() < 1e-12);
        let xi = colinearity_flip_pct(&e.colinearity);
        for (scale, pass) in [(1.0 + 1e-9, true), (1.0 - 1e-9, false)] {
            let p = Params {
                orientation_rad: theta * scale,
                accuracy_pct: xi * scale,
                ..Params::paper()
            };
            let e = evaluate_pair(&p, &new, 1, &existing);
            assert_eq!(e.orientation.pass, pass, "θ_o × {scale}");
            assert_eq!(e.colinearity.test.pass, pass, "ξ × {scale}");
        }
    }

    #[test]
    fn a_cluster_breaks_below_its_largest_inner_gap_and_joins_at_its_bounding_gaps() {
        // Sensors 0..6, t_gap 1 m: gaps 0.5, 1.5 (break), 0.8, 0.9, 2.0 (break), 0.3.
        // The cluster of sensors 2, 3, 4: inner gaps 0.8 and 0.9, ended by 1.5 and 2.0.
        let gaps = [
            gap(0, 1, 0.5),
            gap(1, 2, 1.5),
            gap(2, 3, 0.8),
            gap(3, 4, 0.9),
            gap(4, 5, 2.0),
            gap(5, 6, 0.3),
        ];
        let cluster = ClusterTrace {
            sensors: vec![2, 3, 4],
            constant_depth: vec![],
            fitted: vec![],
            splits: vec![],
            new_segments: vec![],
        };
        assert_eq!(
            cluster_gap_flips(&cluster, &gaps),
            (Some(0.9), [Some(1.5), Some(2.0)])
        );
        let single = ClusterTrace {
            sensors: vec![6],
            ..cluster
        };
        assert_eq!(cluster_gap_flips(&single, &gaps), (None, [None, None]));
    }
}
