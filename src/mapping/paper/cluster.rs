//! Clustering kept points into faces (paper §3.1; docs/algorithm.md §2).

use crate::mapping::model::map::SupportPoint;
use crate::mapping::model::trace::GapTrace;

/// The clusters of one snapshot, kept in buffers that the next snapshot reuses.
#[derive(Clone, Debug, Default)]
pub struct Clusters {
    /// Indices into the kept points, cluster after cluster, each in chain order.
    members: Vec<usize>,
    /// Where each cluster ends in `members` (exclusive).
    ends: Vec<usize>,
    /// Every neighbour gap, in chain order from the first sensor in bearing order.
    pub gaps: Vec<GapTrace>,
}

impl Clusters {
    /// Number of clusters.
    pub fn len(&self) -> usize {
        self.ends.len()
    }

    /// True when no point was kept.
    pub fn is_empty(&self) -> bool {
        self.ends.is_empty()
    }

    /// The clusters in order, each as indices into the kept points.
    pub fn iter(&self) -> impl Iterator<Item = &[usize]> {
        let starts = std::iter::once(0).chain(self.ends.iter().copied());
        starts.zip(&self.ends).map(|(a, &b)| &self.members[a..b])
    }
}

/// Splits the kept points into clusters, into `out` (its previous content is dropped).
///
/// `kept` are the kept points of one snapshot; `rank_of_sensor` gives each sensor's place in
/// the layout's bearing order ([`sensor_ranks`]) and `wraps` says whether the last sensor
/// neighbours the first ([`crate::sonar::SensorLayout::bearing_order`]).
/// Neighbours are consecutive kept points in that order; a cluster ends where their distance
/// exceeds `t_gap_m` (strictly). With a wrapping layout the chain is circular: when it has at
/// least one break, clusters start just after a break, so a face across sensor 0 stays whole.
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
/// use sonarmap::mapping::paper::cluster::{cluster_points, sensor_ranks, Clusters};
/// // Sensors 0..4 in bearing order, not wrapping; t_gap = 1 m. Gaps: 0.5, 1.5 (a break), 1.0
/// // (not a break: the test is strict).
/// let kept = [q(0, 0.0, 0.0, 1.0), q(1, 0.5, 0.0, 1.0), q(2, 2.0, 0.0, 1.0), q(3, 3.0, 0.0, 1.0)];
/// let mut clusters = Clusters::default();
/// cluster_points(&kept, &sensor_ranks(&[0, 1, 2, 3]), false, 1.0, &mut clusters);
/// let found: Vec<Vec<usize>> = clusters.iter().map(|c| c.to_vec()).collect();
/// assert_eq!(found, vec![vec![0, 1], vec![2, 3]]);
/// assert_eq!(clusters.gaps.iter().filter(|g| g.is_break).count(), 1);
/// ```
pub fn cluster_points(
    kept: &[SupportPoint],
    rank_of_sensor: &[usize],
    wraps: bool,
    t_gap_m: f64,
    out: &mut Clusters,
) {
    cluster_points_breaking(kept, rank_of_sensor, wraps, t_gap_m, &|_, _| false, out);
}

/// [`cluster_points`] with an extension's breaks: `breaks(a, b)` ends a cluster between
/// neighbouring readings of sensors `a` and `b` whatever their distance (`right_angle_break`,
/// docs/algorithm.md §8.20), and the gap records it.
pub fn cluster_points_breaking(
    kept: &[SupportPoint],
    rank_of_sensor: &[usize],
    wraps: bool,
    t_gap_m: f64,
    breaks: &dyn Fn(usize, usize) -> bool,
    out: &mut Clusters,
) {
    let Clusters {
        members,
        ends,
        gaps,
    } = out;
    members.clear();
    ends.clear();
    gaps.clear();
    let n = kept.len();
    if n == 0 {
        return;
    }
    // The chain in bearing order, built where the members go and rotated into place below.
    members.extend(0..n);
    members.sort_by_key(|&i| {
        (
            rank_of_sensor
                .get(kept[i].reading.sensor())
                .copied()
                .unwrap_or(usize::MAX),
            kept[i].reading.sensor(),
        )
    });
    let chain = &members[..];
    let link_count = if wraps && n > 1 { n } else { n - 1 };
    gaps.extend((0..link_count).map(|i| {
        let (a, b) = (&kept[chain[i]], &kept[chain[(i + 1) % n]]);
        let distance_m = (a.point - b.point).norm();
        let across_right_angle = breaks(a.reading.sensor(), b.reading.sensor());
        GapTrace {
            from_sensor: a.reading.sensor(),
            to_sensor: b.reading.sensor(),
            distance_m,
            t_gap_m,
            is_break: distance_m > t_gap_m || across_right_angle,
            across_right_angle,
        }
    }));
    // Start after a break when the chain is circular, so no cluster spans the seam.
    let start = if link_count == n {
        match gaps.iter().position(|g| g.is_break) {
            Some(i) => (i + 1) % n,
            None => 0,
        }
    } else {
        0
    };
    members.rotate_left(start);
    // Gap `(start + step - 1) % n` links member `step - 1` to member `step`.
    for step in 1..n {
        if gaps[(start + step - 1) % n].is_break {
            ends.push(step);
        }
    }
    ends.push(n);
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
    use crate::mapping::model::map::ReadingRef;

    fn pt(sensor: usize, x: f64, y: f64) -> SupportPoint {
        SupportPoint {
            point: Point::new(x, y),
            range_m: 1.0,
            reading: ReadingRef::new(0, sensor),
        }
    }

    #[test]
    fn a_gap_of_exactly_t_gap_does_not_break() {
        let kept = vec![pt(0, 0.0, 0.0), pt(1, 1.0, 0.0), pt(2, 2.0000001, 0.0)];
        let mut out = Clusters::default();
        cluster_points(&kept, &sensor_ranks(&[0, 1, 2]), false, 1.0, &mut out);
        assert_eq!(out.iter().collect::<Vec<_>>(), [&[0, 1][..], &[2]]);
        assert!(!out.gaps[0].is_break && out.gaps[1].is_break);
        assert!((out.gaps[1].distance_m - 1.0000001).abs() < 1e-12);
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
        let mut out = Clusters::default();
        cluster_points(&kept, &sensor_ranks(&order), true, 1.0, &mut out);
        assert_eq!(out.gaps.len(), 4);
        assert_eq!(out.iter().collect::<Vec<_>>(), [&[2][..], &[3, 0, 1]]);
        // The buffers are reused: a second snapshot leaves nothing of the first.
        cluster_points(&kept[..1], &sensor_ranks(&order), true, 1.0, &mut out);
        assert_eq!(out.iter().collect::<Vec<_>>(), [&[0][..]]);
        assert!(out.gaps.is_empty());
    }
}
