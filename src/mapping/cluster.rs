//! Clustering kept points into faces (paper §3.1; ALGORITHM.md §2).

use super::map::SupportPoint;
use super::trace::GapTrace;

/// Splits the kept points into clusters.
///
/// `kept` are the kept points of one snapshot; `rank_of_sensor` gives each sensor's place in
/// the layout's bearing order ([`sensor_ranks`]) and `wraps` says whether the last sensor
/// neighbours the first ([`crate::sonar::SensorLayout::bearing_order`]).
/// Neighbours are consecutive kept points in that order; a cluster ends where their distance
/// exceeds `t_gap_m` (strictly). With a wrapping layout the chain is circular: when it has at
/// least one break, clusters start just after a break, so a face across sensor 0 stays whole.
/// Returns the clusters (indices into `kept`, in chain order) and every neighbour gap.
pub fn cluster_points(
    kept: &[SupportPoint],
    rank_of_sensor: &[usize],
    wraps: bool,
    t_gap_m: f64,
) -> (Vec<Vec<usize>>, Vec<GapTrace>) {
    let mut chain: Vec<usize> = (0..kept.len()).collect();
    chain.sort_by_key(|&i| {
        (
            rank_of_sensor
                .get(kept[i].reading.sensor)
                .copied()
                .unwrap_or(usize::MAX),
            kept[i].reading.sensor,
        )
    });
    let n = chain.len();
    if n == 0 {
        return (Vec::new(), Vec::new());
    }
    let link_count = if wraps && n > 1 { n } else { n - 1 };
    let gap = |i: usize| {
        let (a, b) = (&kept[chain[i]], &kept[chain[(i + 1) % n]]);
        let distance_m = (a.point - b.point).norm();
        GapTrace {
            from_sensor: a.reading.sensor,
            to_sensor: b.reading.sensor,
            distance_m,
            t_gap_m,
            is_break: distance_m > t_gap_m,
        }
    };
    let gaps: Vec<GapTrace> = (0..link_count).map(gap).collect();
    // Start after a break when the chain is circular, so no cluster spans the seam.
    let start = if link_count == n {
        match gaps.iter().position(|g| g.is_break) {
            Some(i) => (i + 1) % n,
            None => 0,
        }
    } else {
        0
    };
    // Sized up front: one allocation per cluster, none for growth.
    let breaks = gaps.iter().filter(|g| g.is_break).count();
    let mut clusters = Vec::with_capacity(breaks + 1);
    let mut cluster = Vec::with_capacity(n);
    cluster.push(chain[start]);
    for step in 1..n {
        let pos = (start + step) % n;
        let link = (pos + n - 1) % n;
        if gaps[link].is_break {
            let rest = n - step;
            clusters.push(std::mem::replace(&mut cluster, Vec::with_capacity(rest)));
        }
        cluster.push(chain[pos]);
    }
    clusters.push(cluster);
    (clusters, gaps)
}

/// Each sensor's place in the bearing order `order` (`usize::MAX` for a sensor not in it).
pub fn sensor_ranks(order: &[usize]) -> Vec<usize> {
    let mut rank = vec![usize::MAX; order.iter().copied().max().map_or(0, |m| m + 1)];
    for (pos, &sensor) in order.iter().enumerate() {
        rank[sensor] = pos;
    }
    rank
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Point;
    use crate::mapping::map::ReadingRef;

    fn pt(sensor: usize, x: f64, y: f64) -> SupportPoint {
        SupportPoint {
            point: Point::new(x, y),
            range_m: 1.0,
            reading: ReadingRef {
                snapshot: 0,
                sensor,
            },
        }
    }

    #[test]
    fn a_gap_of_exactly_t_gap_does_not_break() {
        let kept = vec![pt(0, 0.0, 0.0), pt(1, 1.0, 0.0), pt(2, 2.0000001, 0.0)];
        let (clusters, gaps) = cluster_points(&kept, &sensor_ranks(&[0, 1, 2]), false, 1.0);
        assert_eq!(clusters, vec![vec![0, 1], vec![2]]);
        assert!(!gaps[0].is_break && gaps[1].is_break);
        assert!((gaps[1].distance_m - 1.0000001).abs() < 1e-12);
    }

    #[test]
    fn circular_chain_keeps_the_face_across_sensor_zero() {
        // Sensors 0, 1 and 15 see one wall; 7 sees another far away.
        let kept = vec![
            pt(0, 1.0, 0.0),
            pt(1, 1.0, 0.4),
            pt(7, -5.0, 0.0),
            pt(15, 1.0, -0.4),
        ];
        let order: Vec<usize> = (0..16).collect();
        let (clusters, gaps) = cluster_points(&kept, &sensor_ranks(&order), true, 1.0);
        assert_eq!(gaps.len(), 4);
        assert_eq!(clusters, vec![vec![2], vec![3, 0, 1]]);
    }
}
