//! A kept reading with its sensor in the world frame: what every test of a reading against a
//! plane, a corner or a pillar takes (docs/algorithm.md §8.5–§8.14).

use crate::geometry::{Point, Vec2};
use serde::{Deserialize, Serialize};

/// A kept reading with its sensor in the world frame.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Beam {
    /// The sensor's position, world frame.
    pub origin: Point,
    /// Unit vector along the beam axis, world frame.
    pub direction: Vec2,
    /// The range, metres.
    pub range_m: f64,
}

impl Beam {
    /// The point the reading puts on its beam axis (paper §2).
    pub fn axis_point(&self) -> Point {
        self.origin + self.direction * self.range_m
    }
}
