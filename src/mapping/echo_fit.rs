//! Echo placement: a piece's readings moved to where a plane returned them (docs/algorithm.md
//! §8.10; beyond the paper, whose §2 places every reading on its beam axis).
//!
//! A sonar hears the *nearest* point of a surface inside its beam cone that sends the sound
//! back. For a plane that is the foot of the perpendicular from the sensor when that foot lies
//! inside the cone (Kleeman and Kuc's plane model); for a rough plane seen obliquely it is the
//! point where the cone's edge nearer the normal meets it. Either way the echo comes from a
//! point at the reading's range but *off* the beam axis, so the paper's axis placement puts an
//! oblique wall short of itself: seen 30° off its normal at 2 m, the points lie some 0.2 m
//! inside the room, on a line parallel to the wall that later readings confirm as firmly as the
//! wall itself.
//!
//! Given the readings of one fitted piece, [`fit_echo_line`] finds the line whose predicted
//! ranges (perpendicular distance, or distance along the nearer cone edge) match the readings
//! best, weighting each by its tolerance. When every reading's range is within its tolerance
//! of the prediction, [`place_echoes`] moves each reading to its echo point: on its cone, at its
//! range, towards the line's normal.

use super::point_features::{feature_tolerance_m, Beam};
use super::support::SupportPoint;
use crate::geometry::{fit_line_tls, unit, Point, Vec2};
use serde::{Deserialize, Serialize};

/// Largest angle between an echoing ray and the plane's normal that the fit allows (the
/// roughness of the roughest wall it expects), radians: 40°.
pub const MAX_INCIDENCE_RAD: f64 = 40.0 * std::f64::consts::PI / 180.0;

/// Fewest readings a piece needs before its line is fitted from the ranges.
pub const MIN_ECHO_FIT_READINGS: usize = 3;

/// The half-width of the normal-angle search around the axis points' line, radians (60°).
const SEARCH_HALF_WIDTH_RAD: f64 = 60.0 * std::f64::consts::PI / 180.0;

/// Steps of the coarse search over that range (0.5° apart).
const SEARCH_STEPS: usize = 240;

/// A line fitted from the ranges: the points `x` with `normal · x = offset_m`, the sensors on
/// the side `normal · x < offset_m`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct EchoLine {
    /// Unit normal, pointing from the sensors towards the line.
    pub normal: Vec2,
    /// Offset along the normal, metres.
    pub offset_m: f64,
    /// The largest |predicted − read| range over the readings, in units of each reading's
    /// tolerance (`max(ξ·D/100, 1 in)`); at most 1 for an accepted fit.
    pub worst_residual_over_tolerance: f64,
}

/// What echo placement did to one new segment, for the trace.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct EchoFitTrace {
    /// The new segment (index into the step's new segments).
    pub new_segment: usize,
    /// The fitted line.
    pub line: EchoLine,
    /// Readings whose echo came from inside the cone (the foot of the perpendicular).
    pub at_foot: usize,
    /// Readings whose echo came from the cone's edge (an oblique, rough wall).
    pub at_cone_edge: usize,
    /// The largest distance a reading moved from its beam axis, metres.
    pub moved_max_m: f64,
}

/// Signed angle from `from` to `to`, radians in (−π, π].
fn signed_angle(from: &Vec2, to: &Vec2) -> f64 {
    (from.x * to.y - from.y * to.x).atan2(from.dot(to))
}

/// The angle between `beam`'s echoing ray and the normal `normal` of a plane: zero when the
/// normal lies inside the cone (half-width `half_beam_rad`), else how far outside it lies.
fn incidence_rad(beam: &Beam, normal: &Vec2, half_beam_rad: f64) -> f64 {
    (signed_angle(&beam.direction, normal).abs() - half_beam_rad).max(0.0)
}

/// The best offset for the normal `normal` and its cost (sum of squared residuals over
/// squared tolerances), or `None` when some reading could not have come from such a line
/// (its incidence beyond [`MAX_INCIDENCE_RAD`], or the line behind its sensor).
fn offset_and_cost(
    beams: &[Beam],
    normal: &Vec2,
    accuracy_pct: f64,
    half_beam_rad: f64,
) -> Option<(f64, f64)> {
    // Each predicted range is k·(c − n·o): linear in the offset c, so c has a closed form.
    let (mut num, mut den) = (0.0, 0.0);
    for b in beams {
        let incidence = incidence_rad(b, normal, half_beam_rad);
        if incidence > MAX_INCIDENCE_RAD {
            return None;
        }
        let k = 1.0 / incidence.cos();
        let w = feature_tolerance_m(accuracy_pct, b.range_m).powi(-2);
        num += w * k * (k * normal.dot(&b.origin.coords) + b.range_m);
        den += w * k * k;
    }
    let offset_m = num / den;
    let mut cost = 0.0;
    for b in beams {
        let perpendicular_m = offset_m - normal.dot(&b.origin.coords);
        if perpendicular_m <= 0.0 {
            return None;
        }
        let k = 1.0 / incidence_rad(b, normal, half_beam_rad).cos();
        let tol = feature_tolerance_m(accuracy_pct, b.range_m);
        cost += ((k * perpendicular_m - b.range_m) / tol).powi(2);
    }
    Some((offset_m, cost))
}

/// The line that best explains the ranges of `beams` (at least [`MIN_ECHO_FIT_READINGS`]) as
/// echoes of one plane, searched within 60° of the normal of `axis_points`' line (the paper's
/// placement); `None` when no line explains every reading within its tolerance.
///
/// ```
/// use sonarmap::geometry::{Point, Vec2};
/// use sonarmap::mapping::echo_fit::fit_echo_line;
/// use sonarmap::mapping::point_features::Beam;
/// // A wall along y = 2; one sensor looking 30° off its normal (60° from +x) at x = 0, 0.5, 1:
/// // the cone's nearer edge (12.5° wide) meets the wall 17.5° off the normal, at
/// // 2 / cos 17.5° = 2.0971 m.
/// let beams: Vec<Beam> = [0.0, 0.5, 1.0]
///     .iter()
///     .map(|&x| Beam {
///         origin: Point::new(x, 0.0),
///         direction: Vec2::new(60f64.to_radians().cos(), 60f64.to_radians().sin()),
///         range_m: 2.0 / 17.5f64.to_radians().cos(),
///     })
///     .collect();
/// let axis: Vec<Point> = beams.iter().map(|b| b.origin + b.direction * b.range_m).collect();
/// // On the axes the points lie at y = 2.0971 · sin 60° = 1.816: 0.18 m short of the wall.
/// assert!((axis[0].y - 1.8161).abs() < 1e-3);
/// let line = fit_echo_line(&beams, &axis, 3.0, 12.5f64.to_radians()).unwrap();
/// assert!(line.normal.y > 0.999 && (line.offset_m - 2.0).abs() < 1e-3);
/// ```
pub fn fit_echo_line(
    beams: &[Beam],
    axis_points: &[Point],
    accuracy_pct: f64,
    half_beam_rad: f64,
) -> Option<EchoLine> {
    if beams.len() < MIN_ECHO_FIT_READINGS || beams.len() != axis_points.len() {
        return None;
    }
    let (centre, along) = fit_line_tls(axis_points)?;
    let mut normal0 = Vec2::new(-along.y, along.x);
    let sensors = beams.iter().map(|b| b.origin.coords).sum::<Vec2>() / beams.len() as f64;
    if normal0.dot(&(centre.coords - sensors)) < 0.0 {
        normal0 = -normal0;
    }
    let angle0 = normal0.y.atan2(normal0.x);
    let cost_at = |angle: f64| offset_and_cost(beams, &unit(angle), accuracy_pct, half_beam_rad);
    // Coarse search, nearest to the paper's line first so that equal costs keep it.
    let step = 2.0 * SEARCH_HALF_WIDTH_RAD / SEARCH_STEPS as f64;
    let mut best: Option<(f64, f64)> = None;
    for i in 0..=SEARCH_STEPS {
        let k = i.div_ceil(2) as f64 * if i % 2 == 1 { 1.0 } else { -1.0 };
        let angle = angle0 + k * step;
        if let Some((_, cost)) = cost_at(angle) {
            if best.is_none_or(|(_, c)| cost < c) {
                best = Some((angle, cost));
            }
        }
    }
    let (mut lo, mut hi) = best.map(|(a, _)| (a - step, a + step))?;
    // Golden-section refinement within one step either side.
    let ratio = (5f64.sqrt() - 1.0) / 2.0;
    let cost_or_inf = |a: f64| cost_at(a).map_or(f64::INFINITY, |(_, c)| c);
    for _ in 0..30 {
        let (m1, m2) = (hi - ratio * (hi - lo), lo + ratio * (hi - lo));
        if cost_or_inf(m1) <= cost_or_inf(m2) {
            hi = m2;
        } else {
            lo = m1;
        }
    }
    let refined = (lo + hi) / 2.0;
    let angle = match (cost_at(refined), best) {
        (Some((_, c)), Some((_, b))) if c <= b => refined,
        _ => best?.0,
    };
    let normal = unit(angle);
    let (offset_m, _) = cost_at(angle)?;
    let worst = beams
        .iter()
        .map(|b| {
            let k = 1.0 / incidence_rad(b, &normal, half_beam_rad).cos();
            let predicted = k * (offset_m - normal.dot(&b.origin.coords));
            (predicted - b.range_m).abs() / feature_tolerance_m(accuracy_pct, b.range_m)
        })
        .fold(0.0, f64::max);
    (worst <= 1.0).then_some(EchoLine {
        normal,
        offset_m,
        worst_residual_over_tolerance: worst,
    })
}

/// Each reading of `points` (with its beam in `beams`) moved to its echo point on `line`: at
/// its range, along the normal when that lies inside the cone, else along the cone's nearer
/// edge; the points ordered along the line, in the direction the piece ran. Returns the points, how many came from a foot
/// and how many from a cone edge, and the largest move, metres.
pub fn place_echoes(
    points: &[SupportPoint],
    beams: &[Beam],
    line: &EchoLine,
    half_beam_rad: f64,
) -> (Vec<SupportPoint>, usize, usize, f64) {
    let (mut at_foot, mut at_edge, mut moved_max_m) = (0, 0, 0.0f64);
    let mut placed: Vec<SupportPoint> = points
        .iter()
        .zip(beams)
        .map(|(q, b)| {
            let off = signed_angle(&b.direction, &line.normal);
            if off.abs() <= half_beam_rad {
                at_foot += 1;
            } else {
                at_edge += 1;
            }
            let turn = off.clamp(-half_beam_rad, half_beam_rad);
            let (s, c) = turn.sin_cos();
            let d = b.direction;
            let ray = Vec2::new(c * d.x - s * d.y, s * d.x + c * d.y);
            let point = b.origin + ray * b.range_m;
            moved_max_m = moved_max_m.max((point - q.point).norm());
            SupportPoint { point, ..*q }
        })
        .collect();
    // Along the line in the direction the piece ran.
    let mut along = Vec2::new(-line.normal.y, line.normal.x);
    if let (Some(first), Some(last)) = (points.first(), points.last()) {
        if along.dot(&(last.point - first.point)) < 0.0 {
            along = -along;
        }
    }
    placed.sort_by(|p, q| {
        along
            .dot(&p.point.coords)
            .total_cmp(&along.dot(&q.point.coords))
            .then(p.reading.cmp(&q.reading))
    });
    (placed, at_foot, at_edge, moved_max_m)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mapping::support::ReadingRef;

    const HALF: f64 = 12.5 * std::f64::consts::PI / 180.0;

    fn beam(x: f64, y: f64, heading_deg: f64, range_m: f64) -> Beam {
        Beam {
            origin: Point::new(x, y),
            direction: unit(heading_deg.to_radians()),
            range_m,
        }
    }

    fn axis_points(beams: &[Beam]) -> Vec<Point> {
        beams
            .iter()
            .map(|b| b.origin + b.direction * b.range_m)
            .collect()
    }

    fn support(beams: &[Beam]) -> Vec<SupportPoint> {
        axis_points(beams)
            .into_iter()
            .enumerate()
            .map(|(i, point)| SupportPoint {
                point,
                range_m: beams[i].range_m,
                reading: ReadingRef {
                    snapshot: i,
                    sensor: 0,
                },
            })
            .collect()
    }

    #[test]
    fn a_wall_seen_square_on_keeps_its_line_and_points_move_to_the_feet() {
        // Sensors at x = 0, 1, 2 looking 10° off the wall's normal (+y); the wall y = 1.5 is read
        // at 1.5 m (the foot, 10° off the axis, lies inside the 12.5° half cone).
        let beams: Vec<Beam> = (0..3).map(|i| beam(i as f64, 0.0, 80.0, 1.5)).collect();
        let axis = axis_points(&beams);
        // On the axis: y = 1.5 · sin 80° = 1.4772, 2.3 cm short.
        assert!((axis[0].y - 1.4772).abs() < 1e-4);
        let line = fit_echo_line(&beams, &axis, 3.0, HALF).unwrap();
        assert!((line.normal.y - 1.0).abs() < 1e-6 && (line.offset_m - 1.5).abs() < 1e-6);
        let (placed, foot, edge, moved) = place_echoes(&support(&beams), &beams, &line, HALF);
        assert_eq!((foot, edge), (3, 0));
        for (q, x) in placed.iter().zip([0.0, 1.0, 2.0]) {
            assert!((q.point - Point::new(x, 1.5)).norm() < 1e-6, "{q:?}");
        }
        // Moved by the chord of 10° at 1.5 m: 2 · 1.5 · sin 5° = 0.2615 m.
        assert!((moved - 0.2615).abs() < 1e-3);
    }

    #[test]
    fn an_oblique_wall_is_found_from_its_cone_edge_echoes() {
        // The wall y = 2 seen 30° off its normal: ranges 2 / cos 17.5° = 2.0971 m.
        let d = 2.0 / 17.5f64.to_radians().cos();
        let beams: Vec<Beam> = [0.0, 0.4, 0.8, 1.2]
            .iter()
            .map(|&x| beam(x, 0.0, 60.0, d))
            .collect();
        let line = fit_echo_line(&beams, &axis_points(&beams), 3.0, HALF).unwrap();
        assert!((line.offset_m - 2.0).abs() < 1e-3, "{line:?}");
        let (placed, foot, edge, _) = place_echoes(&support(&beams), &beams, &line, HALF);
        assert_eq!((foot, edge), (0, 4));
        // Each echo point lies on the cone edge at 72.5°: (x + 2 tan 17.5°, 2) = (x + 0.6306, 2).
        for (q, x) in placed.iter().zip([0.0, 0.4, 0.8, 1.2]) {
            assert!(
                (q.point - Point::new(x + 0.6306, 2.0)).norm() < 2e-3,
                "{q:?}"
            );
        }
    }

    #[test]
    fn ranges_no_plane_explains_are_left_on_their_axes() {
        // A corner at (1, 2) read from three places along y = 0 with a sensor looking at it:
        // ranges √5, 2, √5 are too far apart for one plane within 3 %.
        let corner = Point::new(1.0, 2.0);
        let beams: Vec<Beam> = [0.0, 1.0, 2.0]
            .iter()
            .map(|&x| {
                let v: Vec2 = corner - Point::new(x, 0.0);
                Beam {
                    origin: Point::new(x, 0.0),
                    direction: v / v.norm(),
                    range_m: v.norm(),
                }
            })
            .collect();
        assert!(fit_echo_line(&beams, &axis_points(&beams), 3.0, HALF).is_none());
    }

    #[test]
    fn fewer_than_three_readings_are_not_fitted() {
        let beams: Vec<Beam> = (0..2).map(|i| beam(i as f64, 0.0, 90.0, 1.5)).collect();
        assert!(fit_echo_line(&beams, &axis_points(&beams), 3.0, HALF).is_none());
    }
}
