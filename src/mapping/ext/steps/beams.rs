//! The world beam of a kept reading and the plane test from it: the geometry every extension
//! that tests a reading against a plane or a reflector shares (docs/algorithm.md §8.5–§8.14).

use crate::geometry::{Point, Pose};
use crate::mapping::ext::confirm::{supports, PlaneEchoModel};
use crate::mapping::model::beam::Beam;
use crate::mapping::model::map::SupportPoint;
use crate::mapping::Mapper;
use crate::sonar::EchoModel;

impl Mapper {
    /// The sonar's accuracy ξ (%) and the half-width of its beam (radians), which every test of
    /// a reading against a plane or a reflector takes (docs/algorithm.md §8.5–§8.10).
    pub(in crate::mapping) fn accuracy_and_half_beam(&self) -> (f64, f64) {
        (self.params.accuracy_pct, self.sensor.beam_width_rad / 2.0)
    }

    /// Where the plane tests of §8.7 take a plane's echo from: along the axis for a sensor whose
    /// echoes come from its axis alone; for one that hears its whole cone, from the nearest
    /// point inside it with echo placement on (§8.10), else from the foot of the perpendicular.
    pub(in crate::mapping) fn plane_echo_model(&self) -> PlaneEchoModel {
        match self.sensor.echo {
            EchoModel::Axis => PlaneEchoModel::Axis,
            EchoModel::Cone if self.params.echo_fit => PlaneEchoModel::NearestInCone,
            EchoModel::Cone => PlaneEchoModel::Foot,
        }
    }

    /// Whether segment parts seen through are cut away (§8.18): `trim_seen_through` on, for a
    /// sensor whose echoes come from its whole cone (a single ray sees through nothing but
    /// its axis).
    pub(in crate::mapping) fn trims_seen_through(&self) -> bool {
        self.params.trim_seen_through && self.sensor.echo == EchoModel::Cone
    }

    /// The world beam of reading `q`, from the pose it was taken from when that is among the
    /// recent ones the map keeps (docs/algorithm.md §8.7, §8.10).
    pub(in crate::mapping) fn recent_beam_of(&self, q: &SupportPoint) -> Option<Beam> {
        let pose = self.map.recent_reading_pose(q.reading)?;
        Some(self.beam_of(&pose, q))
    }

    /// The world beam of kept point `q` of this step, from the pose of its own moment when the
    /// sonars fired in sequence (§1.1), else the step's.
    pub(in crate::mapping) fn step_beam_of(&self, q: &SupportPoint) -> Beam {
        let places = self.reading_places();
        let pose = places.own_pose(q.reading.sensor()).unwrap_or(places.step);
        self.beam_of(pose, q)
    }

    /// The world beam of kept point `q` taken from `pose`.
    /// Its direction is the sensor's axis, wherever the point was placed (§8.10 moves points
    /// off their axes).
    pub(in crate::mapping) fn beam_of(&self, pose: &Pose, q: &SupportPoint) -> Beam {
        let frame = match self.step_frame {
            Some((step_pose, frame)) if step_pose == *pose => frame,
            _ => pose.robot_frame(),
        };
        let axis = &self.beam_axes[q.reading.sensor()];
        Beam {
            origin: frame.to_world(&axis.origin_in_robot),
            direction: frame.direction_to_world(&axis.direction_in_robot),
            range_m: q.range_m,
        }
    }

    /// Whether a reading among `points` (of this step) supports the segment `a`–`b` as a plane
    /// (docs/algorithm.md §8.7).
    pub(in crate::mapping) fn supports_as_plane_now(
        &self,
        points: &[SupportPoint],
        a: &Point,
        b: &Point,
    ) -> bool {
        let (xi, half) = self.accuracy_and_half_beam();
        points.iter().any(|q| {
            supports(
                &self.step_beam_of(q),
                a,
                b,
                xi,
                half,
                self.plane_echo_model(),
            )
            .is_some()
        })
    }
}
