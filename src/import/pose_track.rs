//! Robot poses over time from odometry, and the pose at any time between them.
//!
//! Between two odometry samples the position is interpolated linearly and the heading on the
//! circle (the short way round). Before the first sample and after the last, the nearest
//! sample's pose is used when it is at most [`CLAMP_LIMIT_S`] away; further away the pose is
//! unknown and the importer skips the snapshot, saying so.

use crate::geometry::Pose;

/// How far before the first or after the last odometry sample a snapshot may take that
/// sample's pose, seconds.
pub const CLAMP_LIMIT_S: f64 = 1.0;

/// Odometry samples in time order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PoseTrack {
    samples: Vec<(f64, Pose)>,
}

/// The pose at a time, and how it was found.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PoseAt {
    /// Interpolated between two samples (or at one).
    Inside(Pose),
    /// Taken from the first or last sample, at most [`CLAMP_LIMIT_S`] away.
    Clamped(Pose),
    /// More than [`CLAMP_LIMIT_S`] before the first or after the last sample, or no sample.
    Unknown,
}

pub use crate::geometry::wrap_pi;

impl PoseTrack {
    /// Adds a sample; refuses (returns false) one earlier than the last.
    pub fn push(&mut self, t: f64, pose: Pose) -> bool {
        if let Some(&(last, _)) = self.samples.last() {
            if t < last {
                return false;
            }
        }
        self.samples.push((t, pose));
        true
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.samples.len()
    }

    /// True without samples.
    pub fn is_empty(&self) -> bool {
        self.samples.is_empty()
    }

    /// The pose at `t`.
    pub fn at(&self, t: f64) -> PoseAt {
        let (Some(&(t0, p0)), Some(&(t1, p1))) = (self.samples.first(), self.samples.last()) else {
            return PoseAt::Unknown;
        };
        if t < t0 {
            return if t0 - t <= CLAMP_LIMIT_S {
                PoseAt::Clamped(p0)
            } else {
                PoseAt::Unknown
            };
        }
        if t > t1 {
            return if t - t1 <= CLAMP_LIMIT_S {
                PoseAt::Clamped(p1)
            } else {
                PoseAt::Unknown
            };
        }
        // First sample later than t (t <= t1, so one exists unless t == t1).
        let i = self.samples.partition_point(|&(s, _)| s <= t);
        if i == 0 || i >= self.samples.len() {
            return PoseAt::Inside(self.samples[i.min(self.samples.len() - 1)].1);
        }
        let (ta, a) = self.samples[i - 1];
        let (tb, b) = self.samples[i];
        let f = if tb > ta { (t - ta) / (tb - ta) } else { 0.0 };
        PoseAt::Inside(Pose::new(
            a.x + (b.x - a.x) * f,
            a.y + (b.y - a.y) * f,
            wrap_pi(a.heading_rad + wrap_pi(b.heading_rad - a.heading_rad) * f),
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn heading_is_interpolated_the_short_way_round() {
        let mut track = PoseTrack::default();
        assert!(track.push(0.0, Pose::new(0.0, 0.0, 170f64.to_radians())));
        assert!(track.push(1.0, Pose::new(2.0, 4.0, -170f64.to_radians())));
        assert!(!track.push(0.5, Pose::new(0.0, 0.0, 0.0)));
        let PoseAt::Inside(p) = track.at(0.5) else {
            panic!("inside")
        };
        assert!((p.x - 1.0).abs() < 1e-12 && (p.y - 2.0).abs() < 1e-12);
        assert!((p.heading_rad.abs() - PI).abs() < 1e-9, "{}", p.heading_rad);
        assert!(matches!(track.at(1.0), PoseAt::Inside(_)));
        assert!(matches!(track.at(-0.5), PoseAt::Clamped(_)));
        assert!(matches!(track.at(2.5), PoseAt::Unknown));
    }
}
