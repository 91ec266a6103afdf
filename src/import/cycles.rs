//! Cutting readings fired one at a time, sorted by time, into firing cycles of the ring: the
//! snapshots of the MCAP importer and of one-reading-a-line tables. Each snapshot keeps its
//! readings' own moments as offsets from its time (`reading_dt_s`, docs/formats.md §2), so
//! that each reading is converted with the pose of its own moment (paper §3.1;
//! docs/algorithm.md §1.1).

use super::assemble::{Place, RawSnapshot};
use super::error::ImportError;
use super::summary::ImportSummary;

/// A reading kept for the snapshots.
#[derive(Clone, Copy)]
pub(crate) struct Reading {
    /// Time, seconds.
    pub t: f64,
    /// Sensor index.
    pub sensor: usize,
    /// The range, metres; `None` for no echo.
    pub range_m: Option<f64>,
    /// Where the reading came from; a cycle takes its first reading's place.
    pub place: Place,
}

/// [`firing_cycles`], with a warning in `summary` when sensors were silent in their cycle.
pub(crate) fn cut_into_cycles(
    readings: &[Reading],
    n: usize,
    window_s: f64,
    file: &str,
    summary: &mut ImportSummary,
) -> Result<Vec<RawSnapshot>, ImportError> {
    let (raw, missing) = firing_cycles(readings, n, window_s, file)?;
    if missing > 0 {
        summary.warn(format!(
            "{missing} readings were missing from their firing cycle and are no echo"
        ));
    }
    Ok(raw)
}

/// The firing cycles of `readings` (sorted by time): a cycle starts at a reading and takes the
/// following ones until a sensor repeats or a reading comes more than `window_s` after the
/// cycle's first. Returns the snapshots and the count of sensors silent in their cycle. The
/// slots (a sensor each per cycle) are bounded by the readings: a hostile file must not make a
/// million cycles of ten thousand sensors.
pub(crate) fn firing_cycles(
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
                    "{} readings of {n} sensors make more than {} firing cycles (the first {} end before {}): expected most cycles to read most sensors (is --window {} s too short?)",
                    readings.len(),
                    raw.len(),
                    raw.len(),
                    readings[i].place,
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
    // The mean, kept within the cycle's readings (rounding must not put it after the next
    // cycle's first reading: times may not decrease).
    let t = (sum_t / (j - i) as f64).clamp(t0, readings[j - 1].t);
    let reading_dt_s = if readings[j - 1].t > t0 {
        let mut dt_s = vec![0.0; n];
        for r in &readings[i..j] {
            dt_s[r.sensor] = r.t - t;
        }
        dt_s
    } else {
        Vec::new()
    };
    let snapshot = RawSnapshot {
        t,
        place: readings[i].place,
        ranges_m,
        reading_dt_s,
    };
    (snapshot, j)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn reading(t: f64, sensor: usize, range_m: f64, line: usize) -> Reading {
        Reading {
            t,
            sensor,
            range_m: Some(range_m),
            place: Place::Line(line),
        }
    }

    #[test]
    fn a_cycle_ends_where_a_sensor_repeats_and_keeps_each_readings_offset() {
        // Sensors 0, 1 at 0.0 s; 2 at 0.3 s; 0 again at 0.6 s starts the next cycle.
        let readings = [
            reading(0.0, 0, 1.0, 1),
            reading(0.0, 1, 2.0, 2),
            reading(0.3, 2, 3.0, 3),
            reading(0.6, 0, 4.0, 4),
        ];
        let (raw, missing) = firing_cycles(&readings, 3, 1.0, "f").unwrap();
        assert_eq!(raw.len(), 2);
        // Mean time 0.1 s; offsets -0.1, -0.1, +0.2.
        assert!((raw[0].t - 0.1).abs() < 1e-12);
        let expected = [-0.1, -0.1, 0.2];
        for (dt, e) in raw[0].reading_dt_s.iter().zip(expected) {
            assert!((dt - e).abs() < 1e-12, "{dt} vs {e}");
        }
        assert_eq!(raw[0].ranges_m, vec![Some(1.0), Some(2.0), Some(3.0)]);
        // The second cycle: one reading at one moment, no offsets; two sensors silent.
        assert_eq!(raw[1].t, 0.6);
        assert!(raw[1].reading_dt_s.is_empty());
        assert_eq!(raw[1].ranges_m, vec![Some(4.0), None, None]);
        assert_eq!(missing, 2);
        assert_eq!(raw[1].place.to_string(), "line 4");
    }

    #[test]
    fn a_cycle_ends_after_the_window() {
        let readings = [reading(0.0, 0, 1.0, 1), reading(0.25, 1, 2.0, 2)];
        let (raw, _) = firing_cycles(&readings, 2, 0.2, "f").unwrap();
        assert_eq!(raw.len(), 2);
        let (raw, _) = firing_cycles(&readings, 2, 0.25, "f").unwrap();
        assert_eq!(raw.len(), 1);
    }
}
