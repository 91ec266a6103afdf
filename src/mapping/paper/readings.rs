//! Readings to points (paper §2, §3.1; docs/algorithm.md §1).

use crate::mapping::model::map::{ReadingRef, SupportPoint};
use crate::mapping::model::params::Params;
use crate::mapping::model::trace::{DiscardReason, ReadingTrace};
use crate::mapping::paper::reading_poses::ReadingPlaces;
use crate::sonar::{ball_radius, BeamAxis};

/// Why a reading with range `range_m` is discarded, if it is (docs/algorithm.md §1):
/// no echo, at or beyond the sensor's maximum range, beyond `d_max`, below `min_range`.
pub fn discard_reason(
    range_m: Option<f64>,
    sensor_max_range_m: f64,
    params: &Params,
) -> Option<DiscardReason> {
    match range_m {
        None => Some(DiscardReason::NoEcho),
        Some(d) if !d.is_finite() || d >= sensor_max_range_m => Some(DiscardReason::AtMaxRange),
        Some(d) if d > params.d_max_m => Some(DiscardReason::BeyondDMax),
        Some(d) if d < params.min_range_m => Some(DiscardReason::BelowMinRange),
        Some(_) => None,
    }
}

/// Converts one snapshot's ranges: returns a trace record per sensor and puts the kept points,
/// in sensor order, in `kept` (its previous content is dropped). Each reading is turned into
/// the world with its own pose when `places` has one (§1.1), else with the step's. `beam_axes` are the layout's
/// ([`crate::sonar::SensorLayout::beam_axes`]). Ranges beyond the sensor count are ignored;
/// missing ones count as no echo.
///
/// ```
/// use sonarmap::geometry::Pose;
/// use sonarmap::mapping::paper::reading_poses::ReadingPlaces;
/// use sonarmap::mapping::paper::readings::convert_readings;
/// use sonarmap::mapping::Params;
/// use sonarmap::sonar::SensorLayout;
/// // A 4-sonar ring of radius 0.2 m, the robot at (1, 0) facing +y (90°): sonar 1 faces
/// // 90° + 90° = 180°, so a 1.8 m echo lands at (1, 0) + 0.2·(−1, 0) + 1.8·(−1, 0) = (−1, 0).
/// // Sonar 0's 0.1 m is below min_range (6 in), sonar 2 has no echo, sonar 3's 7 m is beyond
/// // d_max (255 in = 6.477 m).
/// let layout = SensorLayout::ring(4, std::f64::consts::FRAC_PI_2, 0.0, 0.2);
/// let ranges = [Some(0.1), Some(1.8), None, Some(7.0)];
/// let mut kept = Vec::new();
/// let pose = Pose::new(1.0, 0.0, std::f64::consts::FRAC_PI_2);
/// let places = ReadingPlaces::new(&pose, &[]);
/// let traces = convert_readings(3, places, &ranges, &layout.beam_axes(), 10.0, &Params::paper(), &mut kept);
/// assert_eq!(traces.len(), 4);
/// assert_eq!(kept.len(), 1);
/// assert!((kept[0].point.x + 1.0).abs() < 1e-12 && kept[0].point.y.abs() < 1e-12);
/// assert_eq!((kept[0].reading.snapshot(), kept[0].reading.sensor()), (3, 1));
/// assert_eq!(traces.iter().filter(|t| t.discarded.is_some()).count(), 3);
/// ```
pub fn convert_readings(
    snapshot: usize,
    places: ReadingPlaces,
    ranges_m: &[Option<f64>],
    beam_axes: &[BeamAxis],
    sensor_max_range_m: f64,
    params: &Params,
    kept: &mut Vec<SupportPoint>,
) -> Vec<ReadingTrace> {
    let robot = places.frame;
    let mut traces = Vec::with_capacity(beam_axes.len());
    kept.clear();
    for (sensor, axis) in beam_axes.iter().enumerate() {
        let range_m = ranges_m.get(sensor).copied().flatten();
        let discarded = discard_reason(range_m, sensor_max_range_m, params);
        let finite = range_m.filter(|d| d.is_finite());
        let point = finite.map(|d| match places.own_pose(sensor) {
            None => robot.to_world(&axis.point_at(d)),
            Some(own) => own.robot_frame().to_world(&axis.point_at(d)),
        });
        let ball_radius_m = finite.map_or(0.0, |d| ball_radius(params.accuracy_pct, d));
        if let (None, Some(point), Some(range_m)) = (discarded, point, finite) {
            kept.push(SupportPoint {
                point,
                range_m,
                reading: ReadingRef::new(snapshot, sensor),
            });
        }
        traces.push(ReadingTrace {
            sensor,
            range_m,
            point,
            ball_radius_m,
            discarded,
            cluster: None,
            shorter_than_last: None,
        });
    }
    traces
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Point, Pose};
    use crate::sonar::SensorLayout;
    use crate::units::inches;

    #[test]
    fn discard_reasons_follow_algorithm_section_1() {
        let p = Params::paper();
        let max = inches(255.0);
        assert_eq!(discard_reason(None, max, &p), Some(DiscardReason::NoEcho));
        assert_eq!(
            discard_reason(Some(max), max, &p),
            Some(DiscardReason::AtMaxRange)
        );
        let tight = Params {
            d_max_m: inches(100.0),
            ..Params::paper()
        };
        assert_eq!(
            discard_reason(Some(inches(100.5)), max, &tight),
            Some(DiscardReason::BeyondDMax)
        );
        assert_eq!(discard_reason(Some(inches(100.0)), max, &tight), None);
        assert_eq!(
            discard_reason(Some(inches(5.9)), max, &p),
            Some(DiscardReason::BelowMinRange)
        );
        assert_eq!(discard_reason(Some(inches(6.0)), max, &p), None);
    }

    #[test]
    fn kept_points_carry_their_range_and_ball() {
        let layout = SensorLayout::nomad_ring(inches(9.0));
        let pose = Pose::new(0.0, 0.0, 0.0);
        let mut ranges = vec![None; 16];
        ranges[0] = Some(inches(100.0));
        ranges[4] = Some(inches(3.0));
        let mut kept = vec![SupportPoint {
            point: Point::new(1.0, 2.0),
            range_m: 1.0,
            reading: ReadingRef::new(6, 3),
        }];
        let traces = convert_readings(
            7,
            ReadingPlaces::new(&pose, &[]),
            &ranges,
            &layout.beam_axes(),
            inches(255.0),
            &Params::paper(),
            &mut kept,
        );
        assert_eq!(traces.len(), 16);
        assert_eq!(kept.len(), 1);
        assert!((kept[0].point.x - inches(109.0)).abs() < 1e-12);
        assert!((traces[0].ball_radius_m - inches(3.0)).abs() < 1e-12);
        assert_eq!(traces[4].discarded, Some(DiscardReason::BelowMinRange));
        assert_eq!(kept[0].reading, ReadingRef::new(7, 0));
    }

    #[test]
    fn a_reading_fired_at_its_own_moment_is_converted_with_its_own_pose() {
        // Two sonars at the robot centre facing ahead (0°) and left (90°); the step at
        // (1, 0) facing +x. Sonar 1 fired from (0.9, 0) facing +y (10 cm and 90° back on the
        // track): its 2 m echo lands at (0.9, 0) + 2·(−1, 0) = (−1.1, 0), not at (1, 2).
        let layout = SensorLayout::ring(2, std::f64::consts::FRAC_PI_2, 0.0, 0.0);
        let step = Pose::new(1.0, 0.0, 0.0);
        let own = [step, Pose::new(0.9, 0.0, std::f64::consts::FRAC_PI_2)];
        let mut kept = Vec::new();
        let places = ReadingPlaces::new(&step, &own);
        let ranges = [Some(2.0), Some(2.0)];
        let axes = layout.beam_axes();
        convert_readings(0, places, &ranges, &axes, 10.0, &Params::paper(), &mut kept);
        assert!((kept[0].point - Point::new(3.0, 0.0)).norm() < 1e-12);
        assert!((kept[1].point - Point::new(-1.1, 0.0)).norm() < 1e-12);
    }
}
