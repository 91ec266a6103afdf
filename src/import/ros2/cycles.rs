//! Cutting the readings, sorted by time, into firing cycles of the ring: the snapshots.

use crate::import::assemble::{Place, RawSnapshot};
use crate::import::error::ImportError;

/// A reading kept for the snapshots.
#[derive(Clone, Copy)]
pub(super) struct Reading {
    /// Time, seconds.
    pub t: f64,
    /// Sensor index.
    pub sensor: usize,
    /// The range, metres; `None` for no echo.
    pub range_m: Option<f64>,
    /// The message's index in the file.
    pub index: usize,
}

/// The firing cycles of `readings` (sorted by time, then message): a cycle starts at a
/// reading and takes the following ones until a sensor repeats or a reading comes more than
/// `window_s` after the cycle's first. Returns the snapshots and the count of sensors silent
/// in their cycle. The slots (a sensor each per cycle) are bounded by the readings: a hostile
/// file must not make a million cycles of ten thousand sensors.
pub(super) fn firing_cycles(
    readings: &[Reading],
    n: usize,
    window_s: f64,
    file: &str,
) -> Result<(Vec<RawSnapshot>, usize), ImportError> {
    let slot_limit = 4 * readings.len() + n;
    let mut slots = 0usize;
    let mut raw = Vec::new();
    let mut missing = 0;
    let mut seen = vec![false; n];
    let mut i = 0;
    while i < readings.len() {
        slots += n;
        if slots > slot_limit {
            return Err(ImportError::NoSnapshots {
                file: file.to_string(),
                why: format!(
                    "{} readings of {n} sensors make more than {} firing cycles (the first {} end before the cycle starting at MCAP message {}): expected most cycles to read most sensors (is --window {} s too short?)",
                    readings.len(),
                    raw.len(),
                    raw.len(),
                    readings[i].index,
                    window_s
                ),
            });
        }
        seen.iter_mut().for_each(|s| *s = false);
        let (snapshot, j) = cycle(readings, i, n, window_s, &mut seen);
        missing += n - (j - i);
        raw.push(snapshot);
        i = j;
    }
    Ok((raw, missing))
}

/// The cycle starting at reading `i`, and the index of the first reading after it; `seen`
/// (all false) marks the sensors read.
fn cycle(
    readings: &[Reading],
    i: usize,
    n: usize,
    window_s: f64,
    seen: &mut [bool],
) -> (RawSnapshot, usize) {
    let t0 = readings[i].t;
    let mut ranges_m = vec![None; n];
    let mut sum_t = 0.0;
    let mut j = i;
    while j < readings.len() {
        let r = readings[j];
        if seen[r.sensor] || r.t - t0 > window_s {
            break;
        }
        seen[r.sensor] = true;
        ranges_m[r.sensor] = r.range_m;
        sum_t += r.t;
        j += 1;
    }
    let snapshot = RawSnapshot {
        // The mean, kept within the cycle's readings (rounding must not put it after the
        // next cycle's first reading: times may not decrease).
        t: (sum_t / (j - i) as f64).clamp(t0, readings[j - 1].t),
        place: Place::Cycle(readings[i].index),
        ranges_m,
    };
    (snapshot, j)
}
