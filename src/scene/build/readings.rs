//! The layers of this step's readings: beams, balls, clusters, points (kept, discarded and
//! the previous step's) and the segments fitted to them.

use super::{mid, reading, Builder};
use crate::geometry::{unit, Point};
use crate::scene::format_length;
use crate::scene::layer::Layer;
use crate::scene::marker::MarkerShape;
use crate::scene::primitive::{Primitive, SceneId, Shape, TextAlign};
use crate::scene::style::{palette, Role};

impl Builder<'_, '_> {
    /// Each reading's beam (kept readings) and ray.
    pub(super) fn beams(&mut self) {
        let Some(pose) = self.pose else { return };
        let run = self.input.run;
        let half_angle_rad = 0.5 * run.sensor.beam_width_rad;
        let k = self.input.snapshot;
        for r in &self.input.step.readings {
            let (Some(range_m), true) = (r.range_m, r.sensor < run.layout.len()) else {
                continue;
            };
            let sensor = run.layout.sensor_pose_in_world(&pose, r.sensor);
            let apex = sensor.position();
            let id = SceneId::Reading {
                snapshot: k,
                sensor: r.sensor,
            };
            let radius_m = range_m.min(run.sensor.max_range_m);
            // Wedges for kept readings only: a discarded beam at maximum range would dwarf the map.
            if r.discarded.is_none() {
                let heading_rad = sensor.heading_rad;
                let shape = Shape::Wedge {
                    apex,
                    heading_rad,
                    half_angle_rad,
                    radius_m,
                };
                self.push(Layer::Beams, Role::Beam, id, shape);
            }
            let end = apex + unit(sensor.heading_rad) * radius_m;
            self.push(
                Layer::Beams,
                Role::Ray,
                id,
                Shape::Segment {
                    a: apex,
                    b: r.point.unwrap_or(end),
                },
            );
        }
    }

    /// The uncertainty ball of each kept reading (none smaller than half a pixel).
    pub(super) fn balls(&mut self) {
        let min_radius_m = self.px(0.5);
        let k = self.input.snapshot;
        for r in &self.input.step.readings {
            let (None, Some(centre)) = (r.discarded, r.point) else {
                continue;
            };
            if r.ball_radius_m <= 0.0 || r.ball_radius_m < min_radius_m {
                continue;
            }
            let id = SceneId::Reading {
                snapshot: k,
                sensor: r.sensor,
            };
            self.push(
                Layer::Balls,
                Role::Ball,
                id,
                Shape::Circle {
                    centre,
                    radius_m: r.ball_radius_m,
                },
            );
        }
    }

    /// The clusters of this step's points, and the gaps that broke them.
    pub(super) fn clusters(&mut self) {
        let step = self.input.step;
        for (i, c) in step.clusters.iter().enumerate() {
            let points: Vec<Point> = c
                .sensors
                .iter()
                .filter_map(|&s| reading(step, s).and_then(|r| r.point))
                .collect();
            let colour = palette::CLUSTERS[i % palette::CLUSTERS.len()];
            let mut style = Role::Cluster.style();
            style.stroke = Some(colour);
            let id = SceneId::Cluster(i);
            let shape = match points.len() {
                0 => continue,
                1 => {
                    style.marker_size_px = 14.0;
                    style.stroke_width_px = 3.0;
                    Shape::Marker {
                        at: points[0],
                        shape: MarkerShape::Ring,
                    }
                }
                _ => Shape::Polyline {
                    points,
                    closed: false,
                },
            };
            self.out.push(Primitive {
                layer: Layer::Clusters,
                role: Role::Cluster,
                style,
                id,
                shape,
            });
        }
        let units = self.input.run.units;
        for g in step.gaps.iter().filter(|g| g.is_break) {
            let from = reading(step, g.from_sensor).and_then(|r| r.point);
            let to = reading(step, g.to_sensor).and_then(|r| r.point);
            let (Some(from), Some(to)) = (from, to) else {
                continue;
            };
            let at = mid(&from, &to);
            self.push(
                Layer::Clusters,
                Role::ClusterBreak,
                SceneId::None,
                Shape::Marker {
                    at,
                    shape: MarkerShape::Plus,
                },
            );
            let text = format!("gap {}", format_length(g.distance_m, units));
            self.push_text(
                Layer::Clusters,
                SceneId::None,
                at,
                text.chars().count(),
                || text,
                [0.0, 8.0],
                TextAlign::Middle,
            );
        }
    }

    /// The segments fitted in this step.
    pub(super) fn new_segments(&mut self) {
        for (i, n) in self.input.step.new_segments.iter().enumerate() {
            let shape = Shape::Segment {
                a: n.a.point,
                b: n.b.point,
            };
            self.push(
                Layer::NewSegments,
                Role::NewSegment,
                SceneId::NewSegment(i),
                shape,
            );
        }
    }

    /// The previous step's fitted segments and points.
    pub(super) fn previous_snapshot(&mut self) {
        let Some(prev) = self.input.previous_step else {
            return;
        };
        for n in &prev.new_segments {
            let shape = Shape::Segment {
                a: n.a.point,
                b: n.b.point,
            };
            self.push(
                Layer::PreviousSnapshot,
                Role::PreviousSegment,
                SceneId::None,
                shape,
            );
        }
        for r in &prev.readings {
            let (None, Some(at)) = (r.discarded, r.point) else {
                continue;
            };
            let id = SceneId::Reading {
                snapshot: prev.snapshot,
                sensor: r.sensor,
            };
            let shape = Shape::Marker {
                at,
                shape: MarkerShape::Dot,
            };
            self.push(Layer::PreviousSnapshot, Role::PreviousPoint, id, shape);
        }
    }

    /// This step's kept points.
    pub(super) fn current_points(&mut self) {
        let k = self.input.snapshot;
        for r in &self.input.step.readings {
            let (None, Some(at)) = (r.discarded, r.point) else {
                continue;
            };
            let id = SceneId::Reading {
                snapshot: k,
                sensor: r.sensor,
            };
            self.push(
                Layer::CurrentPoints,
                Role::CurrentPoint,
                id,
                Shape::Marker {
                    at,
                    shape: MarkerShape::Dot,
                },
            );
        }
    }

    /// This step's discarded readings.
    pub(super) fn discarded(&mut self) {
        let k = self.input.snapshot;
        for r in &self.input.step.readings {
            let (Some(_), Some(at)) = (r.discarded, r.point) else {
                continue;
            };
            let id = SceneId::Reading {
                snapshot: k,
                sensor: r.sensor,
            };
            self.push(
                Layer::Discarded,
                Role::Discarded,
                id,
                Shape::Marker {
                    at,
                    shape: MarkerShape::Cross,
                },
            );
        }
    }
}
