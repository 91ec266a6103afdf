//! Confirmation of segments (docs/algorithm.md §8.7; beyond the paper).
//!
//! A plane returns a sonar's echo from the foot of the perpendicular from the sensor (Kleeman
//! and Kuc's plane model): a reading supports a segment *as a plane* when the perpendicular
//! distance from its sensor to the segment's line is its range within the tolerance
//! (`ξ·D/100`, at least 1 in), the foot lies on the segment (10 % of its length of slack at
//! either end), and the foot lies within half the beam width of the axis. A corner's arc fitted
//! as a slanted line, or a wall seen obliquely and placed short of it, has no such reading from
//! two poses. Where the echo comes from follows the sensor ([`PlaneEchoModel`]): for a sonar
//! that hears its cone, the foot or (§8.10) the cone's nearer edge; for a single ray, where its
//! axis meets the plane. A segment is **confirmed** once readings of two distinct snapshots
//! support it as a plane; until then it is tentative (drawn dimmed; `eval` reports both sets).

use crate::geometry::{
    distance_to_line, line_angle_between, projection_param, ray_meets_segment_line, Point, Vec2,
};
use crate::mapping::ext::beam_geometry::echo_ray;
use crate::mapping::ext::beam_geometry::feature_tolerance_m;
use crate::mapping::ext::beam_geometry::incidence_cosine;
use crate::mapping::ext::beam_geometry::HalfCone;
use crate::mapping::model::beam::Beam;
use crate::mapping::model::ext_trace::BaselinePair;
use crate::mapping::model::ext_trace::PlaneSupportTrace;
use crate::mapping::model::ext_trace::UnconfirmedTrace;
use crate::mapping::model::map::EndPoint;
use crate::mapping::model::map::{Map, SegmentId};
use crate::mapping::model::plane_supports::{PlaneSupport, CONFIRMING_SNAPSHOTS};
use crate::mapping::model::support::ReadingRef;

/// How far apart along a segment the sensors of two readings of one step must have stood for
/// them to confirm it (docs/algorithm.md §8.7, baseline confirmation): 8 in, the baseline
/// that confirms a point feature (§8.5).
pub const CONFIRMING_BASELINE_M: f64 = 8.0 * 0.0254;

/// How far from a segment's direction the displacement between those two sensors may turn
/// (docs/algorithm.md §8.7, baseline confirmation): 10°, across the segment at most
/// `tan 10° = 0.18` of the way along it (measured: 7.5° to 12.5° give the same suite figures).
pub const CONFIRMING_BASELINE_TURN_RAD: f64 = 10.0 * std::f64::consts::PI / 180.0;

/// Whether `beam` supports the segment `a`–`b` as a plane; returns the perpendicular distance.
///
/// ```
/// use sonarmap::geometry::{Point, Vec2};
/// use sonarmap::mapping::ext::confirm::supports_as_plane;
/// use sonarmap::mapping::model::beam::Beam;
/// // A sensor at the origin looking along +y reads 2.03 m; a wall from (-1, 2) to (1, 2):
/// // foot (0, 2) on the axis, |2 − 2.03| = 0.03 ≤ 0.0609 (3 % of 2.03): a plane echo.
/// let beam = Beam { origin: Point::origin(), direction: Vec2::new(0.0, 1.0), range_m: 2.03 };
/// let d = supports_as_plane(&beam, &Point::new(-1.0, 2.0), &Point::new(1.0, 2.0), 3.0, 12.5f64.to_radians());
/// assert!((d.unwrap() - 2.0).abs() < 1e-12);
/// // Read at 2.20 m (a corner 10 % farther): |2 − 2.2| = 0.2 > 0.066, no support.
/// let far = Beam { range_m: 2.2, ..beam };
/// assert!(supports_as_plane(&far, &Point::new(-1.0, 2.0), &Point::new(1.0, 2.0), 3.0, 12.5f64.to_radians()).is_none());
/// // The wall from (0.6, 2) to (2, 2): the foot (0, 2) is 0.6 m before its start (slack 0.14).
/// assert!(supports_as_plane(&beam, &Point::new(0.6, 2.0), &Point::new(2.0, 2.0), 3.0, 12.5f64.to_radians()).is_none());
/// ```
pub fn supports_as_plane(
    beam: &Beam,
    a: &Point,
    b: &Point,
    accuracy_pct: f64,
    half_beam_rad: f64,
) -> Option<f64> {
    foot_echo(beam, a, b, accuracy_pct, HalfCone::new(half_beam_rad)).map(|e| e.range_m)
}

/// Where a plane along `a`–`b` echoes `beam` from: the range it predicts, metres, and the echo
/// point's place along a→b (0 at `a`, 1 at `b`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlaneEcho {
    /// The predicted range, metres.
    pub range_m: f64,
    /// The echo point's place along a→b.
    pub along: f64,
}

/// [`supports_as_plane`], with where the echo comes from (the foot of the perpendicular).
fn foot_echo(
    beam: &Beam,
    a: &Point,
    b: &Point,
    accuracy_pct: f64,
    half: HalfCone,
) -> Option<PlaneEcho> {
    let t = projection_param(&beam.origin, a, b);
    if !(-0.1..=1.1).contains(&t) {
        return None;
    }
    let foot = a + (b - a) * t;
    let v = foot - beam.origin;
    let d = v.norm();
    if d <= 0.0 || (d - beam.range_m).abs() > feature_tolerance_m(accuracy_pct, beam.range_m) {
        return None;
    }
    (v.dot(&beam.direction) / d >= half.cos).then_some(PlaneEcho {
        range_m: d,
        along: t,
    })
}

/// Whether `beam` supports the segment `a`–`b` as a plane, its echo taken from the nearest
/// point of the plane inside the cone (docs/algorithm.md §8.10): the foot of the perpendicular
/// when the normal lies inside the cone ([`supports_as_plane`]), else where the cone's nearer
/// edge meets the line, at most [`MAX_INCIDENCE_RAD`](crate::mapping::ext::beam_geometry::MAX_INCIDENCE_RAD) off the normal. That point must lie on
/// the segment (10 % slack) at the range within the tolerance. Returns the predicted range.
///
/// ```
/// use sonarmap::geometry::{Point, Vec2};
/// use sonarmap::mapping::ext::confirm::supports_as_echo;
/// use sonarmap::mapping::model::beam::Beam;
/// // The wall y = 2 seen 30° off its normal: the cone edge (12.5°) meets it 17.5° off the
/// // normal, at 2 / cos 17.5° = 2.0971 m, at x = 0.6306.
/// let dir = Vec2::new(60f64.to_radians().cos(), 60f64.to_radians().sin());
/// let beam = Beam { origin: Point::origin(), direction: dir, range_m: 2.10 };
/// let (a, b) = (Point::new(0.0, 2.0), Point::new(2.0, 2.0));
/// let d = supports_as_echo(&beam, &a, &b, 3.0, 12.5f64.to_radians()).unwrap();
/// assert!((d - 2.0971).abs() < 1e-4);
/// // The foot model alone refuses it: the foot (0, 2) lies 30° off the axis.
/// assert!(sonarmap::mapping::ext::confirm::supports_as_plane(&beam, &a, &b, 3.0, 12.5f64.to_radians()).is_none());
/// ```
pub fn supports_as_echo(
    beam: &Beam,
    a: &Point,
    b: &Point,
    accuracy_pct: f64,
    half_beam_rad: f64,
) -> Option<f64> {
    cone_echo(beam, a, b, accuracy_pct, HalfCone::new(half_beam_rad)).map(|e| e.range_m)
}

/// Where a plane echoes a reading from, by how the sensor hears (docs/algorithm.md §8.7,
/// §8.10): the plane test every extension takes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PlaneEchoModel {
    /// The foot of the perpendicular, inside the cone (Kleeman and Kuc's plane model:
    /// [`supports_as_plane`]).
    Foot,
    /// The nearest point of the plane inside the cone: the foot, or where the cone's nearer
    /// edge meets the plane (§8.10: [`supports_as_echo`]).
    NearestInCone,
    /// Where the beam's axis meets the plane, at any incidence: a sensor whose echoes come
    /// from its axis alone ([`EchoModel::Axis`](crate::sonar::EchoModel::Axis);
    /// [`supports_along_axis`]).
    Axis,
}

/// How far a segment running at `direction_rad` is turned from the map's axes (`axis_rad`,
/// modulo 90°; none before they are set), radians, when more than `max_turn_rad`: such a
/// segment is confirmed only from the foot of the perpendicular, not from the cone's edges
/// (docs/algorithm.md §8.7, `off_axis_square_on`).
///
/// ```
/// use sonarmap::mapping::ext::confirm::off_axis_turn_rad;
/// let turn = 15f64.to_radians();
/// // Axes at 2°: a segment at 32° is 30° off them, one at 94° 2°.
/// let axis = Some(2f64.to_radians());
/// let off = off_axis_turn_rad(32f64.to_radians(), axis, turn).unwrap();
/// assert!((off.to_degrees() - 30.0).abs() < 1e-9);
/// assert_eq!(off_axis_turn_rad(94f64.to_radians(), axis, turn), None);
/// assert_eq!(off_axis_turn_rad(32f64.to_radians(), None, turn), None);
/// ```
pub fn off_axis_turn_rad(
    direction_rad: f64,
    axis_rad: Option<f64>,
    max_turn_rad: f64,
) -> Option<f64> {
    let axis = axis_rad?;
    let turn_rad =
        crate::mapping::ext::rectilinear_heading::deviation_from_axes(direction_rad, axis).abs();
    (turn_rad > max_turn_rad).then_some(turn_rad)
}

/// Whether `beam` of a sensor whose echoes come from its axis alone supports the segment
/// `a`–`b` as a plane: the axis meets the segment (10 % of its length of slack at either end)
/// at the range within the tolerance, at any incidence (a single ray hears whatever it meets
/// first, and never the foot of a perpendicular off its axis). Returns the distance along
/// the axis.
///
/// ```
/// use sonarmap::geometry::{Point, Vec2};
/// use sonarmap::mapping::ext::confirm::{supports_along_axis, supports_as_plane};
/// use sonarmap::mapping::model::beam::Beam;
/// // The wall y = 2 met 20° off its normal: along the axis at 2 / cos 20° = 2.1284 m. Read
/// // at 2.13 m (tol 1 % of it, 0.0254 m, the 1 in floor), the axis model supports it; the
/// // foot model does not (the foot lies 20° off the axis, outside 12.5°).
/// let dir = Vec2::new(20f64.to_radians().sin(), 20f64.to_radians().cos());
/// let beam = Beam { origin: Point::origin(), direction: dir, range_m: 2.13 };
/// let (a, b) = (Point::new(-1.0, 2.0), Point::new(2.0, 2.0));
/// let d = supports_along_axis(&beam, &a, &b, 1.0).unwrap();
/// assert!((d - 2.0 / 20f64.to_radians().cos()).abs() < 1e-12);
/// assert!(supports_as_plane(&beam, &a, &b, 1.0, 12.5f64.to_radians()).is_none());
/// // The same reading of a wall that ends at x = 0.5: the axis meets its line at x = 0.728,
/// // past the 10 % slack (0.65): no support.
/// assert!(supports_along_axis(&beam, &Point::new(-1.0, 2.0), &Point::new(0.5, 2.0), 1.0).is_none());
/// ```
pub fn supports_along_axis(beam: &Beam, a: &Point, b: &Point, accuracy_pct: f64) -> Option<f64> {
    axis_echo(beam, a, b, accuracy_pct).map(|e| e.range_m)
}

/// [`supports_along_axis`], with where the echo comes from.
fn axis_echo(beam: &Beam, a: &Point, b: &Point, accuracy_pct: f64) -> Option<PlaneEcho> {
    axis_meets_wall(beam, a, b).filter(|e| {
        (e.range_m - beam.range_m).abs() <= feature_tolerance_m(accuracy_pct, beam.range_m)
    })
}

/// Where `beam`'s axis meets the wall `a`–`b` ahead of the sensor (10 % slack past its ends),
/// whatever the range read: the echo an axis sensor would hear from it.
pub fn axis_meets_wall(beam: &Beam, a: &Point, b: &Point) -> Option<PlaneEcho> {
    let (d, t) = ray_meets_segment_line(&beam.origin, &beam.direction, a, b)?;
    (d > 0.0 && (-0.1..=1.1).contains(&t)).then_some(PlaneEcho {
        range_m: d,
        along: t,
    })
}

/// [`supports_as_echo`], with where the echo comes from.
fn cone_echo(
    beam: &Beam,
    a: &Point,
    b: &Point,
    accuracy_pct: f64,
    half: HalfCone,
) -> Option<PlaneEcho> {
    let along = b - a;
    let length = along.norm();
    if length <= 0.0 {
        return None;
    }
    let mut normal = Vec2::new(-along.y, along.x) / length;
    let mut perpendicular_m = normal.dot(&(a - beam.origin));
    if perpendicular_m < 0.0 {
        normal = -normal;
        perpendicular_m = -perpendicular_m;
    }
    if perpendicular_m <= 0.0 {
        return None;
    }
    let predicted_m = perpendicular_m / incidence_cosine(beam, &normal, half)?;
    if (predicted_m - beam.range_m).abs() > feature_tolerance_m(accuracy_pct, beam.range_m) {
        return None;
    }
    let (ray, _) = echo_ray(beam, &normal, half);
    let t = projection_param(&(beam.origin + ray * predicted_m), a, b);
    (-0.1..=1.1).contains(&t).then_some(PlaneEcho {
        range_m: predicted_m,
        along: t,
    })
}

/// The plane test a segment's readings take, by `echo`: [`supports_as_plane`],
/// [`supports_as_echo`] or [`supports_along_axis`]. Returns the predicted range.
pub fn supports(
    beam: &Beam,
    a: &Point,
    b: &Point,
    accuracy_pct: f64,
    half_beam_rad: f64,
    echo: PlaneEchoModel,
) -> Option<f64> {
    plane_echo(beam, a, b, accuracy_pct, half_beam_rad, echo).map(|e| e.range_m)
}

/// [`supports`], with where the echo comes from along the segment.
pub fn plane_echo(
    beam: &Beam,
    a: &Point,
    b: &Point,
    accuracy_pct: f64,
    half_beam_rad: f64,
    echo: PlaneEchoModel,
) -> Option<PlaneEcho> {
    plane_echo_in(beam, a, b, accuracy_pct, HalfCone::new(half_beam_rad), echo)
}

/// [`plane_echo`], the beam's half-width given as its [`HalfCone`].
pub fn plane_echo_in(
    beam: &Beam,
    a: &Point,
    b: &Point,
    accuracy_pct: f64,
    half: HalfCone,
    echo: PlaneEchoModel,
) -> Option<PlaneEcho> {
    match echo {
        PlaneEchoModel::Foot => foot_echo(beam, a, b, accuracy_pct, half),
        PlaneEchoModel::NearestInCone => cone_echo(beam, a, b, accuracy_pct, half),
        PlaneEchoModel::Axis => axis_echo(beam, a, b, accuracy_pct),
    }
}

/// A view of the map's segments: a snapshot's readings, where the robot stood, and how far it
/// must have moved since the last view a segment counted for this one to count too.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct View {
    /// The snapshot.
    pub snapshot: usize,
    /// Where the robot stood (its centre, the step's pose).
    pub robot: Point,
    /// `confirm_spacing`, metres (0: every distinct snapshot counts).
    pub spacing_m: f64,
}

impl View {
    /// Snapshot `snapshot`, every distinct snapshot a view.
    pub fn of(snapshot: usize) -> Self {
        View {
            snapshot,
            robot: Point::origin(),
            spacing_m: 0.0,
        }
    }
}

/// `point` in whole millimetres.
fn millimetres(point: &Point) -> [i32; 2] {
    [
        (point.x * 1000.0).round() as i32,
        (point.y * 1000.0).round() as i32,
    ]
}

/// Notes the plane support `beams` (readings of `view`'s snapshot that went into segment `id`)
/// give it: at most once a snapshot, and, after its first, only when the robot stood
/// `view.spacing_m` or more from where it stood at the last counted view (two views of a plane
/// from one place are one view, Kleeman and Kuc; a crawling robot's consecutive snapshots are).
/// The robot's place, not its sensors': turning in place swings a ring's sensors 0.2–0.3 m
/// while every echo keeps its range, the same from a wall's foot as from a corner, a region of
/// constant depth (Leonard and Durrant-Whyte), so a turn confirms nothing.
/// Returns the trace record of the first supporting reading, if any.
pub fn note_plane_support(
    map: &mut Map,
    id: SegmentId,
    beams: &[(usize, Beam)],
    view: View,
    accuracy_pct: f64,
    half_beam_rad: f64,
    echo: PlaneEchoModel,
) -> Option<PlaneSupportTrace> {
    let s = map.segment(id)?;
    let (a, b) = (s.a.point, s.b.point);
    let before = map.plane_support.get(&id).copied();
    // How far the robot stood from the last counted view's place, when there is one.
    let moved_m = before.filter(PlaneSupport::counted).map(|p| {
        let [x, y] = p.last_view_mm;
        (view.robot.x - f64::from(x) / 1000.0).hypot(view.robot.y - f64::from(y) / 1000.0)
    });
    let (sensor, beam, distance_m) =
        first_plane_support(beams, &a, &b, accuracy_pct, half_beam_rad, echo)?;
    if moved_m.is_some_and(|m| m < view.spacing_m) {
        // Supported, but from the last view's place: recorded, not counted.
        let p = before.filter(|p| p.last_snapshot != view.snapshot)?;
        return Some(PlaneSupportTrace {
            same_view_moved_m: moved_m,
            ..PlaneSupportTrace::new(id, sensor, beam.range_m, distance_m, &p)
        });
    }
    let support = map.plane_support.update(id, |support| {
        if support.counted() && support.last_snapshot == view.snapshot {
            return None;
        }
        support.snapshots += 1;
        support.last_snapshot = view.snapshot;
        support.last_view_mm = millimetres(&view.robot);
        Some(*support)
    })?;
    Some(PlaneSupportTrace::new(
        id,
        sensor,
        beam.range_m,
        distance_m,
        &support,
    ))
}

/// The first of `beams` (each with its sensor) that supports the segment `a`–`b` as a plane
/// under `echo` ([`supports`]): its sensor, beam and the distance the plane predicts.
pub fn first_plane_support(
    beams: &[(usize, Beam)],
    a: &Point,
    b: &Point,
    accuracy_pct: f64,
    half_beam_rad: f64,
    echo: PlaneEchoModel,
) -> Option<(usize, Beam, f64)> {
    beams.iter().find_map(|(sensor, beam)| {
        supports(beam, a, b, accuracy_pct, half_beam_rad, echo).map(|d| (*sensor, *beam, d))
    })
}

/// Whether a refit moved a segment off its line (docs/algorithm.md §8.7, `refit_unconfirms`):
/// from `before` (its end-points before the update) to `after` (the refit's first piece, its
/// end-points with their ranges), it turned more than `max_turn_rad` (`θ_o`), or an end-point
/// of `after` lies farther than `2·tol(D)` from the old line (`tol(D) = max(ξ·D/100, 1 in)`,
/// `D` that end-point's range). The plane support that confirmed it was support for the old
/// line. Returns the numbers when it did.
///
/// ```
/// use sonarmap::geometry::Point;
/// use sonarmap::mapping::ext::confirm::refit_moved_off;
/// use sonarmap::mapping::model::map::EndPoint;
/// let end = |x: f64, y: f64| EndPoint { point: Point::new(x, y), range_m: 1.0 };
/// let before = [Point::new(0.0, 1.0), Point::new(2.0, 1.0)];
/// // An end 0.05 m off the old line: under 2 · 0.03 = 0.06 (3 % of 1 m): the same line.
/// assert!(refit_moved_off(before, [end(0.0, 1.0), end(1.5, 1.05)], 3.0, 15f64.to_radians()).is_none());
/// // 0.07 m off: moved.
/// let t = refit_moved_off(before, [end(0.0, 1.0), end(1.5, 1.07)], 3.0, 15f64.to_radians()).unwrap();
/// assert!((t.off_line_m[1] - 0.07).abs() < 1e-12 && (t.limits_m[1] - 0.06).abs() < 1e-12);
/// ```
pub fn refit_moved_off(
    before: [Point; 2],
    after: [EndPoint; 2],
    accuracy_pct: f64,
    max_turn_rad: f64,
) -> Option<UnconfirmedTrace> {
    let turn_rad = line_angle_between(&(before[1] - before[0]), &(after[1].point - after[0].point));
    let off = |e: &EndPoint| distance_to_line(&e.point, &before[0], &before[1]);
    let limit = |e: &EndPoint| 2.0 * feature_tolerance_m(accuracy_pct, e.range_m);
    let off_line_m = [off(&after[0]), off(&after[1])];
    let limits_m = [limit(&after[0]), limit(&after[1])];
    let moved =
        turn_rad > max_turn_rad || off_line_m[0] > limits_m[0] || off_line_m[1] > limits_m[1];
    moved.then(|| UnconfirmedTrace {
        segment: 0,
        tentative: false,
        before,
        after: [after[0].point, after[1].point],
        turn_rad,
        off_line_m,
        limits_m,
    })
}

/// Baseline confirmation (docs/algorithm.md §8.7): among `beams` (readings, each with its own
/// snapshot's beam), two of distinct snapshots that support the segment `a`–`b` as a plane
/// ([`supports`]) and whose sensors stood at least `min_baseline_m` apart along it, the
/// displacement at most `max_turn_rad` from its direction (across it at most
/// `along·tan max_turn`). The pair displaced farthest along it (the first such in order on
/// ties), if any.
///
/// A sensor that moves towards a surface hears the same patch of it, and its range shrinks
/// as it would for a corner or an edge in the beam; moved along a plane it hears another
/// patch at the same perpendicular distance. Readings that went into a segment in one step
/// from two poses so displaced (point memory's pieces hold readings of up to
/// `memory_snapshots` snapshots) are two observations of the plane, as two steps' readings
/// are.
///
/// ```
/// use sonarmap::geometry::{Point, Vec2};
/// use sonarmap::mapping::ext::confirm::{baseline_pair, PlaneEchoModel};
/// use sonarmap::mapping::model::beam::Beam;
/// use sonarmap::mapping::model::support::ReadingRef;
/// // A side sensor looking along +y at the wall y = 1 from x = 0 and x = 0.4 (snapshots 3, 5).
/// let at = |x: f64, snapshot: usize| {
///     let beam = Beam { origin: Point::new(x, 0.0), direction: Vec2::new(0.0, 1.0), range_m: 1.0 };
///     (ReadingRef::new(snapshot, 2), beam)
/// };
/// let (a, b) = (Point::new(0.0, 1.0), Point::new(0.4, 1.0));
/// let half = 12.5f64.to_radians();
/// let pair = baseline_pair(&[at(0.0, 3), at(0.4, 5)], &a, &b, 3.0, half, PlaneEchoModel::Foot, 0.2032, 15f64.to_radians());
/// assert!((pair.unwrap().along_m - 0.4).abs() < 1e-12);
/// // 0.1 m apart: under the 8 in baseline.
/// assert!(baseline_pair(&[at(0.0, 3), at(0.1, 5)], &a, &b, 3.0, half, PlaneEchoModel::Foot, 0.2032, 15f64.to_radians()).is_none());
/// ```
#[allow(clippy::too_many_arguments)]
pub fn baseline_pair(
    beams: &[(ReadingRef, Beam)],
    a: &Point,
    b: &Point,
    accuracy_pct: f64,
    half_beam_rad: f64,
    echo: PlaneEchoModel,
    min_baseline_m: f64,
    max_turn_rad: f64,
) -> Option<BaselinePair> {
    let along = b - a;
    let length = along.norm();
    if length <= 0.0 {
        return None;
    }
    let direction = along / length;
    let supporting: Vec<&(ReadingRef, Beam)> = beams
        .iter()
        .filter(|(_, beam)| supports(beam, a, b, accuracy_pct, half_beam_rad, echo).is_some())
        .collect();
    let tan_turn = max_turn_rad.tan();
    let mut best: Option<BaselinePair> = None;
    for (i, (r1, b1)) in supporting.iter().enumerate() {
        for (r2, b2) in &supporting[i + 1..] {
            if r1.snapshot == r2.snapshot {
                continue;
            }
            let moved = b2.origin - b1.origin;
            let along_m = moved.dot(&direction).abs();
            let across_m = (moved - direction * moved.dot(&direction)).norm();
            if along_m < min_baseline_m
                || across_m > along_m * tan_turn
                || best.is_some_and(|p| along_m <= p.along_m)
            {
                continue;
            }
            let readings = if r1.snapshot < r2.snapshot {
                [*r1, *r2]
            } else {
                [*r2, *r1]
            };
            best = Some(BaselinePair {
                readings,
                along_m,
                across_m,
            });
        }
    }
    best
}

/// Confirms segment `id` by `pair` (its readings went into it in `snapshot`'s step; see
/// [`baseline_pair`]) unless it is confirmed already. Returns the trace record: the later
/// reading of the pair, its range and its distance from the segment's line.
pub fn note_baseline_support(
    map: &mut Map,
    id: SegmentId,
    pair: BaselinePair,
    later: &Beam,
    snapshot: usize,
) -> Option<PlaneSupportTrace> {
    let s = map.segment(id)?;
    let distance_m = distance_to_line(&later.origin, &s.a.point, &s.b.point);
    let newly_confirmed = map.plane_support.update(id, |support| {
        if support.confirmed() {
            return false;
        }
        support.snapshots = CONFIRMING_SNAPSHOTS;
        support.last_snapshot = snapshot;
        true
    });
    if !newly_confirmed {
        return None;
    }
    Some(PlaneSupportTrace {
        segment: id,
        sensor: pair.readings[1].sensor(),
        range_m: later.range_m,
        distance_m,
        snapshots: CONFIRMING_SNAPSHOTS,
        confirmed: true,
        baseline: Some(pair),
        same_view_moved_m: None,
        off_axis_deg: None,
    })
}

#[cfg(test)]
mod tests;
