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

use crate::geometry::{fit_line_tls, segments_cross, unit, Point, Vec2};
use crate::mapping::ext::beam_geometry::{
    echo_ray, feature_tolerance_m, incidence_cosine, mean_origin, round_echo, round_residual_m,
    HalfCone, RoundEcho,
};
use crate::mapping::model::beam::Beam;
use crate::mapping::model::ext_trace::EchoLine;
use crate::mapping::model::features::MAX_ROUND_RADIUS_M;
use crate::mapping::model::features::MIN_ROUND_RADIUS_M;
use crate::mapping::model::map::Map;
use crate::mapping::model::support::SupportPoint;

/// Fewest readings of a piece before a reflector point is tried against its line (two
/// readings fit both exactly).
pub const MIN_REFLECTOR_READINGS: usize = 3;

/// Fewest readings a piece needs before its line is fitted from the ranges.
pub const MIN_ECHO_FIT_READINGS: usize = 2;

/// Steps of the coarse search over the normal angles (within `θ_o` of the paper's line: 3° apart
/// at 15°).
const SEARCH_STEPS: usize = 10;

/// Golden-section steps that refine the best coarse angle (to about 0.007° at `θ_o` = 15°).
const GOLDEN_ITERATIONS: usize = 14;

/// Whether the echo point `echo` of `beam` lies behind a confirmed map segment: the ray from
/// the sensor to it crosses one more than twice the tolerance before the reading's range. A
/// concave corner echoes from its vertex at any incidence, and a plane fitted to a corner's
/// ranges from a narrow baseline stands across the corner with its echo points outside the
/// room, beyond the walls the map already holds.
pub fn echo_behind_confirmed_wall(map: &Map, beam: &Beam, echo: &Point, accuracy_pct: f64) -> bool {
    let reach_m = beam.range_m - 2.0 * feature_tolerance_m(accuracy_pct, beam.range_m);
    let v = echo - beam.origin;
    let length = v.norm();
    if reach_m <= 0.0 || length <= 0.0 {
        return false;
    }
    let end = beam.origin + v * (reach_m / length);
    let mut behind = false;
    map.visit_segments_along(&beam.origin, &end, 0.0, |id, s| {
        behind = behind
            || (s.fitted
                && segments_cross(&beam.origin, &end, &s.a.point, &s.b.point)
                && map.is_confirmed(id));
    });
    behind
}

/// `1 / cos γ` ([`incidence_cosine`]): the predicted range over the perpendicular distance.
fn edge_factor(beam: &Beam, normal: &Vec2, half: HalfCone) -> Option<f64> {
    incidence_cosine(beam, normal, half).map(|c| 1.0 / c)
}

/// The range `beam` reads from the plane `normal · x = offset_m` (see [`incidence_cosine`]); `None`
/// beyond [`MAX_INCIDENCE_RAD`](super::beam_geometry::MAX_INCIDENCE_RAD).
fn predicted_range(beam: &Beam, normal: &Vec2, offset_m: f64, half: HalfCone) -> Option<f64> {
    edge_factor(beam, normal, half).map(|k| k * (offset_m - normal.dot(&beam.origin.coords)))
}

/// `|predicted − read| / tol` of `beam` for the plane `normal · x = offset_m`; infinite beyond
/// [`MAX_INCIDENCE_RAD`](super::beam_geometry::MAX_INCIDENCE_RAD).
fn residual_over_tolerance(
    beam: &Beam,
    normal: &Vec2,
    offset_m: f64,
    accuracy_pct: f64,
    half: HalfCone,
) -> f64 {
    predicted_range(beam, normal, offset_m, half).map_or(f64::INFINITY, |p| {
        (p - beam.range_m).abs() / feature_tolerance_m(accuracy_pct, beam.range_m)
    })
}

/// The best offset for the normal `normal` and its cost (sum of squared residuals over
/// squared tolerances), or `None` when some reading could not have come from such a line
/// (its incidence beyond [`MAX_INCIDENCE_RAD`](super::beam_geometry::MAX_INCIDENCE_RAD), or the line behind its sensor).
///
/// `weights` holds each beam's weight, its tolerance to the power −2 ([`range_weights`]):
/// the fit asks for the cost of some thirty normals, and the weights are the same for all.
fn offset_and_cost(
    beams: &[Beam],
    weights: &[f64],
    normal: &Vec2,
    half: HalfCone,
) -> Option<(f64, f64)> {
    // Each predicted range is k·(c − n·o), linear in the offset c: with the weighted sums
    // below, the best c is sum_kt / sum_kk and the cost sum_tt − sum_kt² / sum_kk.
    let (mut sum_kk, mut sum_kt, mut sum_tt) = (0.0, 0.0, 0.0);
    let mut farthest_sensor = f64::NEG_INFINITY;
    for (b, &w) in beams.iter().zip(weights) {
        let k = edge_factor(b, normal, half)?;
        let along_normal = normal.dot(&b.origin.coords);
        farthest_sensor = farthest_sensor.max(along_normal);
        let target = k * along_normal + b.range_m;
        sum_kk += w * k * k;
        sum_kt += w * k * target;
        sum_tt += w * target * target;
    }
    let offset_m = sum_kt / sum_kk;
    (offset_m > farthest_sensor).then(|| (offset_m, (sum_tt - sum_kt * sum_kt / sum_kk).max(0.0)))
}

/// Each beam's weight in [`offset_and_cost`]: its range's tolerance to the power −2.
fn range_weights(beams: &[Beam], accuracy_pct: f64) -> Vec<f64> {
    beams
        .iter()
        .map(|b| feature_tolerance_m(accuracy_pct, b.range_m).powi(-2))
        .collect()
}

/// The line that best explains the ranges of `beams` (at least [`MIN_ECHO_FIT_READINGS`]) as
/// echoes of one plane, its normal within `max_turn_rad` (the orientation threshold `θ_o` of §4)
/// of the normal of `axis_points`' line (the paper's placement); `None` when no such line
/// explains every reading within its tolerance.
///
/// ```
/// use sonarmap::geometry::{Point, Vec2};
/// use sonarmap::mapping::ext::echo_fit::fit_echo_line;
/// use sonarmap::mapping::model::beam::Beam;
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
/// let line = fit_echo_line(&beams, &axis, 3.0, 12.5f64.to_radians(), 15f64.to_radians()).unwrap();
/// assert!(line.normal.y > 0.999 && (line.offset_m - 2.0).abs() < 1e-3);
/// ```
pub fn fit_echo_line(
    beams: &[Beam],
    axis_points: &[Point],
    accuracy_pct: f64,
    half_beam_rad: f64,
    max_turn_rad: f64,
) -> Option<EchoLine> {
    if beams.len() < MIN_ECHO_FIT_READINGS || beams.len() != axis_points.len() {
        return None;
    }
    let (centre, along) = fit_line_tls(axis_points)?;
    let mut normal0 = Vec2::new(-along.y, along.x);
    if normal0.dot(&(centre - mean_origin(beams))) < 0.0 {
        normal0 = -normal0;
    }
    let angle0 = normal0.y.atan2(normal0.x);
    let half = HalfCone::new(half_beam_rad);
    let weights = range_weights(beams, accuracy_pct);
    let cost_of = |normal: &Vec2| {
        offset_and_cost(beams, &weights, normal, half).map_or(f64::INFINITY, |(_, c)| c)
    };
    let cost_or_inf = |angle: f64| cost_of(&unit(angle));
    // Coarse search, nearest to the paper's line first so that equal costs keep it; the
    // normals are turned step by step (no trigonometric call per angle).
    let step = 2.0 * max_turn_rad / SEARCH_STEPS as f64;
    let (step_sin, step_cos) = step.sin_cos();
    let turn = |v: Vec2, sign: f64| {
        Vec2::new(
            step_cos * v.x - sign * step_sin * v.y,
            sign * step_sin * v.x + step_cos * v.y,
        )
    };
    let mut best: Option<(f64, f64)> = None;
    let mut consider = |angle: f64, cost: f64| {
        if cost.is_finite() && best.is_none_or(|(_, c)| cost < c) {
            best = Some((angle, cost));
        }
    };
    consider(angle0, cost_of(&normal0));
    let (mut plus, mut minus) = (normal0, normal0);
    for k in 1..=SEARCH_STEPS / 2 {
        plus = turn(plus, 1.0);
        minus = turn(minus, -1.0);
        consider(angle0 + k as f64 * step, cost_of(&plus));
        consider(angle0 - k as f64 * step, cost_of(&minus));
    }
    let (coarse, coarse_cost) = best?;
    // Golden-section refinement within one step either side; the refined normal's fit is kept
    // when it is the one taken.
    let refined = unit(golden_section_min(
        coarse - step,
        coarse + step,
        cost_or_inf,
    ));
    let refined_fit = offset_and_cost(beams, &weights, &refined, half);
    let (normal, fit) = if refined_fit.map_or(f64::INFINITY, |(_, c)| c) <= coarse_cost {
        (refined, refined_fit)
    } else {
        let normal = unit(coarse);
        (normal, offset_and_cost(beams, &weights, &normal, half))
    };
    let (offset_m, _) = fit?;
    let worst = beams
        .iter()
        .map(|b| residual_over_tolerance(b, &normal, offset_m, accuracy_pct, half))
        .fold(0.0, f64::max);
    (worst <= 1.0).then_some(EchoLine {
        normal,
        offset_m,
        worst_residual_over_tolerance: worst,
    })
}

/// The middle of the bracket that [`GOLDEN_ITERATIONS`] golden-section steps leave of
/// `lo..hi` around the least `cost`.
fn golden_section_min(mut lo: f64, mut hi: f64, cost: impl Fn(f64) -> f64) -> f64 {
    let ratio = (5f64.sqrt() - 1.0) / 2.0;
    let (mut m1, mut m2) = (hi - ratio * (hi - lo), lo + ratio * (hi - lo));
    let (mut c1, mut c2) = (cost(m1), cost(m2));
    for _ in 0..GOLDEN_ITERATIONS {
        if c1 <= c2 {
            (hi, m2, c2) = (m2, m1, c1);
            m1 = hi - ratio * (hi - lo);
            c1 = cost(m1);
        } else {
            (lo, m1, c1) = (m1, m2, c2);
            m2 = lo + ratio * (hi - lo);
            c2 = cost(m2);
        }
    }
    (lo + hi) / 2.0
}

/// The single reflector point (a corner or an edge) that best explains the ranges of `beams`,
/// found by Gauss-Newton from `start`, with its cost (the sum of squared range residuals over
/// squared tolerances, as [`line_cost`]); `None` unless it lies inside every beam's cone and
/// explains every range within its tolerance.
///
/// ```
/// use sonarmap::geometry::{Point, Vec2};
/// use sonarmap::mapping::ext::echo_fit::fit_reflector_point;
/// use sonarmap::mapping::model::beam::Beam;
/// // A corner at (1, 2) heard from x = 0.6, 1.0, 1.4 on y = 0, each sensor looking at it.
/// let corner = Point::new(1.0, 2.0);
/// let beams: Vec<Beam> = [0.6, 1.0, 1.4]
///     .iter()
///     .map(|&x| {
///         let v: Vec2 = corner - Point::new(x, 0.0);
///         Beam { origin: Point::new(x, 0.0), direction: v / v.norm(), range_m: v.norm() }
///     })
///     .collect();
/// let (at, cost) = fit_reflector_point(&beams, Point::new(1.1, 1.9), 3.0, 12.5f64.to_radians()).unwrap();
/// assert!((at - corner).norm() < 1e-6 && cost < 1e-9);
/// ```
pub fn fit_reflector_point(
    beams: &[Beam],
    start: Point,
    accuracy_pct: f64,
    half_beam_rad: f64,
) -> Option<(Point, f64)> {
    let mut p = start;
    for _ in 0..8 {
        // Normal equations of the linearised residuals r_i = |p − o_i| − D_i.
        let (mut a11, mut a12, mut a22, mut b1, mut b2) = (0.0, 0.0, 0.0, 0.0, 0.0);
        for b in beams {
            let v = p - b.origin;
            let d = v.norm().max(1e-9);
            let g = v / d;
            let w = feature_tolerance_m(accuracy_pct, b.range_m).powi(-2);
            let r = d - b.range_m;
            a11 += w * g.x * g.x;
            a12 += w * g.x * g.y;
            a22 += w * g.y * g.y;
            b1 += w * g.x * r;
            b2 += w * g.y * r;
        }
        let det = a11 * a22 - a12 * a12;
        if det.abs() < 1e-12 {
            return None;
        }
        let dx = (a22 * b1 - a12 * b2) / det;
        let dy = (a11 * b2 - a12 * b1) / det;
        p -= Vec2::new(dx, dy);
    }
    let mut cost = 0.0;
    for b in beams {
        let v = p - b.origin;
        let d = v.norm();
        let tol = feature_tolerance_m(accuracy_pct, b.range_m);
        if d <= 0.0
            || (d - b.range_m).abs() > tol
            || v.dot(&b.direction) / d < HalfCone::new(half_beam_rad).cos
        {
            return None;
        }
        cost += ((d - b.range_m) / tol).powi(2);
    }
    Some((p, cost))
}

/// The cost of `line` for `beams`: the sum of squared range residuals over squared
/// tolerances.
pub fn line_cost(beams: &[Beam], line: &EchoLine, accuracy_pct: f64, half_beam_rad: f64) -> f64 {
    let half = HalfCone::new(half_beam_rad);
    beams
        .iter()
        .map(|b| {
            residual_over_tolerance(b, &line.normal, line.offset_m, accuracy_pct, half).powi(2)
        })
        .sum()
}

/// The reflector point near `start` that explains the ranges of `beams` (at least
/// [`MIN_REFLECTOR_READINGS`]) better than `line` does (a lower [`fit_reflector_point`] cost
/// than [`line_cost`]): a corner or an edge, not a plane (docs/algorithm.md §8.10). `None`
/// when the line does at least as well, or fewer readings cannot tell.
pub fn reflector_beating_line(
    beams: &[Beam],
    line: &EchoLine,
    start: Point,
    accuracy_pct: f64,
    half_beam_rad: f64,
) -> Option<Point> {
    if beams.len() < MIN_REFLECTOR_READINGS {
        return None;
    }
    fit_reflector_point(beams, start, accuracy_pct, half_beam_rad)
        .filter(|&(_, cost)| cost < line_cost(beams, line, accuracy_pct, half_beam_rad))
        .map(|(at, _)| at)
}

/// The rounded reflector (a pillar, a column, a table leg: a cylinder, docs/algorithm.md
/// §8.14) that best explains the ranges of `beams`: its centre `c` and radius `r`, each reading
/// its sensor's distance from the surface along the ray through the centre (the surface's
/// normal), `|c − o| − r`, or along the cone's edge when the centre lies just outside it
/// ([`round_echo`]). Found by Gauss-Newton from a centre one start radius behind `start` (away
/// from the sensors), with its cost (the sum of squared range residuals over squared
/// tolerances). `None` unless, after twelve Gauss-Newton steps (abandoned once the radius
/// passes four times the largest either way), the radius lies within
/// [`MIN_ROUND_RADIUS_M`]..=[`MAX_ROUND_RADIUS_M`], every sensor outside the cylinder, every
/// beam echoed by it, and every range explained within its tolerance. The
/// sensors must stand apart: from one place only the centre's distance less the radius is
/// seen.
///
/// ```
/// use sonarmap::geometry::{Point, Vec2};
/// use sonarmap::mapping::ext::echo_fit::fit_round_reflector;
/// use sonarmap::mapping::model::beam::Beam;
/// // A pillar of radius 0.2 m at (1, 2) heard from x = 0.4, 1.0, 1.6 on y = 0, each sensor
/// // looking at its centre: from (0.4, 0) the centre is √(0.36 + 4) = 2.088 m away, the
/// // surface 1.888 m; from (1, 0) 2 − 0.2 = 1.8 m.
/// let centre = Point::new(1.0, 2.0);
/// let beams: Vec<Beam> = [0.4, 1.0, 1.6]
///     .iter()
///     .map(|&x| {
///         let v: Vec2 = centre - Point::new(x, 0.0);
///         Beam { origin: Point::new(x, 0.0), direction: v / v.norm(), range_m: v.norm() - 0.2 }
///     })
///     .collect();
/// assert!((beams[0].range_m - 1.8881).abs() < 1e-4);
/// let (c, r, cost) =
///     fit_round_reflector(&beams, Point::new(1.0, 1.8), 1.0, 12.5f64.to_radians()).unwrap();
/// assert!((c - centre).norm() < 1e-6 && (r - 0.2).abs() < 1e-6 && cost < 1e-9);
/// ```
pub fn fit_round_reflector(
    beams: &[Beam],
    start: Point,
    accuracy_pct: f64,
    half_beam_rad: f64,
) -> Option<(Point, f64, f64)> {
    if beams.len() < MIN_REFLECTOR_READINGS {
        return None;
    }
    const START_RADIUS_M: f64 = 0.1;
    let away = start - mean_origin(beams);
    let away = away / away.norm().max(1e-9);
    let (mut c, mut r) = (start + away * START_RADIUS_M, START_RADIUS_M);
    let weights = range_weights(beams, accuracy_pct);
    let half = HalfCone::new(half_beam_rad);
    for _ in 0..12 {
        // Normal equations of the linearised residuals (the echo's range less the reading's,
        // through the centre or along the cone's edge) in (c_x, c_y, r).
        let mut a = nalgebra::Matrix3::<f64>::zeros();
        let mut g = nalgebra::Vector3::<f64>::zeros();
        for (b, &w) in beams.iter().zip(&weights) {
            // A beam the current guess does not echo pulls along the ray through the centre.
            let echo = round_echo(&c, r, b, half).unwrap_or_else(|| {
                let v = c - b.origin;
                RoundEcho::through_centre(v, v.norm().max(1e-9), r)
            });
            let j = nalgebra::Vector3::new(
                echo.d_range_d_centre.x,
                echo.d_range_d_centre.y,
                echo.d_range_d_radius,
            );
            a += w * j * j.transpose();
            g += w * j * (echo.range_m - b.range_m);
        }
        // Sensors standing together cannot tell the radius from the distance.
        let step = a.lu().solve(&g)?;
        if !step.iter().all(|x| x.is_finite()) {
            return None;
        }
        c -= Vec2::new(step.x, step.y);
        r -= step.z;
        // A guess this far off does not come back in the steps left (maps byte-identical
        // with and without this on five 20,000-snapshot lap runs); most seeds of evidence that
        // is no pillar's get here within a few steps.
        if r.abs() > 4.0 * MAX_ROUND_RADIUS_M {
            return None;
        }
    }
    if !(MIN_ROUND_RADIUS_M..=MAX_ROUND_RADIUS_M).contains(&r) {
        return None;
    }
    let mut cost = 0.0;
    for b in beams {
        let residual_m = round_residual_m(&c, r, b, accuracy_pct, half)?;
        cost += (residual_m / feature_tolerance_m(accuracy_pct, b.range_m)).powi(2);
    }
    Some((c, r, cost))
}

/// Readings moved to their echo points ([`place_echoes`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Placement {
    /// The moved readings, in the order given.
    pub points: Vec<SupportPoint>,
    /// Readings whose echo came from the foot of the perpendicular.
    pub at_foot: usize,
    /// Readings whose echo came from the cone's edge.
    pub at_cone_edge: usize,
    /// The largest distance a reading moved, metres.
    pub moved_max_m: f64,
}

/// Each reading of `points` (with its beam in `beams`) moved to its echo point on `line`: at
/// its range, along the normal when that lies inside the cone, else along the cone's nearer
/// edge; in the order given ([`order_along_line`] orders them).
pub fn place_echoes(
    points: &[SupportPoint],
    beams: &[Beam],
    line: &EchoLine,
    half_beam_rad: f64,
) -> Placement {
    let half = HalfCone::new(half_beam_rad);
    let mut placement = Placement {
        points: Vec::with_capacity(points.len()),
        at_foot: 0,
        at_cone_edge: 0,
        moved_max_m: 0.0,
    };
    for (q, b) in points.iter().zip(beams) {
        let (ray, inside) = echo_ray(b, &line.normal, half);
        if inside {
            placement.at_foot += 1;
        } else {
            placement.at_cone_edge += 1;
        }
        let point = b.origin + ray * b.range_m;
        placement.moved_max_m = placement.moved_max_m.max((point - q.point).norm());
        placement.points.push(SupportPoint { point, ..*q });
    }
    placement
}

/// Orders `placed` along `line`, in the direction the piece ran from `first` to `last` (its
/// readings as the paper placed them), equal places by reading.
pub fn order_along_line(
    placed: &mut [SupportPoint],
    line: &EchoLine,
    first: &SupportPoint,
    last: &SupportPoint,
) {
    let mut along = Vec2::new(-line.normal.y, line.normal.x);
    if along.dot(&(last.point - first.point)) < 0.0 {
        along = -along;
    }
    placed.sort_by(|p, q| {
        along
            .dot(&p.point.coords)
            .total_cmp(&along.dot(&q.point.coords))
            .then(p.reading.cmp(&q.reading))
    });
}

#[cfg(test)]
mod tests;
