//! The mapper's cluster links across a right angle (docs/algorithm.md §8.20).

use crate::mapping::ext::right_angle_break::across_right_angle;
use crate::mapping::Mapper;
use crate::sonar::EchoModel;

impl Mapper {
    /// §8.20: whether `right_angle_break` ends a cluster between neighbouring readings of
    /// sensors `a` and `b`, whatever their distance: their axes lie a right angle or more
    /// apart. A sensor whose echo comes from its axis at any incidence (`"echo": "axis"`) reads
    /// a plane from any angle, so its links stay as the paper has them.
    pub(in crate::mapping) fn breaks_across_right_angle(&self, a: usize, b: usize) -> bool {
        self.params.right_angle_break
            && self.sensor.echo == EchoModel::Cone
            && match (self.beam_axes.get(a), self.beam_axes.get(b)) {
                (Some(a), Some(b)) => {
                    across_right_angle(&a.direction_in_robot, &b.direction_in_robot)
                }
                _ => false,
            }
    }
}

#[cfg(test)]
mod tests {
    use crate::geometry::Pose;
    use crate::mapping::{Mapper, Params};
    use crate::run::Snapshot;
    use crate::sonar::{EchoModel, SensorLayout, SensorMount, SensorSpec};

    /// A robot at the origin facing +x with four sonars at its centre (front, left, back,
    /// right, 90° apart) reads 0.3 m ahead and 0.4 m to the left: the points (0.3, 0) and
    /// (0, 0.4), 0.5 m apart, well within `t_gap` (42 in). The step's clusters, by sensor,
    /// and whether the link between the two was broken across the right angle.
    fn front_and_left(params: Params, echo: EchoModel) -> (Vec<Vec<usize>>, bool) {
        let mount = |deg: f64| SensorMount {
            x_m: 0.0,
            y_m: 0.0,
            heading_rad: deg.to_radians(),
        };
        let layout = SensorLayout {
            mounts: vec![mount(0.0), mount(90.0), mount(180.0), mount(-90.0)],
        };
        let sensor = SensorSpec {
            echo,
            min_range_m: 0.02,
            ..SensorSpec::default()
        };
        let mut mapper = Mapper::new(params, layout, sensor);
        let trace = mapper.step(&Snapshot {
            t: 0.0,
            pose: Pose::new(0.0, 0.0, 0.0),
            ranges_m: vec![Some(0.3), Some(0.4), None, None],
            true_pose: None,
            reading_dt_s: Vec::new(),
        });
        let clusters = trace.clusters.iter().map(|c| c.sensors.clone()).collect();
        let across = trace.gaps.iter().any(|g| g.across_right_angle);
        (clusters, across)
    }

    #[test]
    fn readings_of_sonars_a_right_angle_apart_are_two_clusters() {
        let with = Params {
            min_range_m: 0.02,
            ..Params::extended()
        };
        // Extended: 0.5 m ≤ t_gap, but the axes are 90° apart: two one-reading clusters (the
        // ring's chain starts after its first break), the gaps marked.
        let (clusters, across) = front_and_left(with.clone(), EchoModel::Cone);
        assert_eq!(clusters, vec![vec![1], vec![0]]);
        assert!(across);
        // The paper's rule alone: one cluster of two readings, a chord across the corner.
        let without = Params {
            right_angle_break: false,
            ..with.clone()
        };
        let (clusters, across) = front_and_left(without, EchoModel::Cone);
        assert_eq!(clusters, vec![vec![0, 1]]);
        assert!(!across);
        // Sonars whose echo comes from their axis at any incidence keep the link.
        let (clusters, across) = front_and_left(with, EchoModel::Axis);
        assert_eq!(clusters, vec![vec![0, 1]]);
        assert!(!across);
    }
}
