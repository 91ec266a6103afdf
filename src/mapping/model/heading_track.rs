//! The odometry's heading errors a first pass found, smoothed, one a snapshot (docs/algorithm.md
//! §8.17, "calibrate, then map"): what the second pass corrects its heading by.

use std::fmt;

/// The odometry's heading error (its heading minus the map's, radians) at each snapshot of a
/// run, smoothed over a whole first pass
/// ([`crate::mapping::ext::drift_smoother::DriftHistory::smoothed`]).
#[derive(Clone, PartialEq)]
pub struct HeadingTrack {
    errors_rad: Vec<f64>,
    /// The calibration (°/m, % of turns) the first pass found with it: the track goes with
    /// those parameters alone, so that changing them is not overridden by it.
    drift: (f64, f64),
}

impl HeadingTrack {
    /// The track of `errors_rad`, one a snapshot from the first, going with the calibration
    /// `drift` (`drift_deg_per_m`, `drift_per_turn_pct`) the same pass found.
    pub fn new(errors_rad: Vec<f64>, drift: (f64, f64)) -> Self {
        Self { errors_rad, drift }
    }

    /// The calibration it goes with.
    pub fn drift(&self) -> (f64, f64) {
        self.drift
    }

    /// The error at snapshot `snapshot`; `None` past the first pass's last step.
    pub fn error_at(&self, snapshot: usize) -> Option<f64> {
        self.errors_rad.get(snapshot).copied()
    }

    /// The snapshots it covers.
    pub fn len(&self) -> usize {
        self.errors_rad.len()
    }

    /// Whether it covers none.
    pub fn is_empty(&self) -> bool {
        self.errors_rad.is_empty()
    }
}

impl fmt::Debug for HeadingTrack {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "HeadingTrack({} snapshots)", self.errors_rad.len())
    }
}
