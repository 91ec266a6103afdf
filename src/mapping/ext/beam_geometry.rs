//! The beam geometry the extensions share (docs/algorithm.md §8.5–§8.14): a beam's half-cone,
//! the ray a plane's echo comes along and its incidence (§8.10), a pillar's echo (§8.14), and
//! the tolerance of a range in feature tests.

use crate::geometry::{Point, Vec2};
use crate::mapping::model::beam::Beam;
use crate::units::inches;

/// Largest angle between an echoing ray and the plane's normal that the fit allows (the
/// roughness of the roughest wall it expects), radians: 60° (docs/algorithm.md §8.10: at 40°
/// the walls MRPT's simulator echoes from beyond it, since it has no incidence limit, were
/// left on the beam axes, short of themselves).
pub const MAX_INCIDENCE_RAD: f64 = 60.0 * std::f64::consts::PI / 180.0;

/// Half a beam's width as its cosine and sine (and the cosine of half of it), computed once
/// for many readings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HalfCone {
    /// Cosine of the half-width.
    pub cos: f64,
    /// Sine of the half-width.
    pub sin: f64,
    /// Cosine of half the half-width (how far a cone's far arc bulges past its chord).
    pub cos_half: f64,
}

impl HalfCone {
    /// The half-width `half_beam_rad`, radians. The last one asked for is remembered (one per
    /// thread): a step asks for its sensor's half-width thousands of times, and a sine and
    /// cosine each time were a tenth of a lap run's instructions. Never inlined: inlined, the
    /// compiler computed the sine and cosine ahead of the check, in every caller's loop.
    #[inline(never)]
    pub fn new(half_beam_rad: f64) -> Self {
        thread_local! {
            static LAST: std::cell::Cell<Option<(u64, HalfCone)>> = const { std::cell::Cell::new(None) };
        }
        let key = half_beam_rad.to_bits();
        if let Some((k, cone)) = LAST.get() {
            if k == key {
                return cone;
            }
        }
        let (sin, cos) = half_beam_rad.sin_cos();
        let cone = Self {
            cos,
            sin,
            cos_half: (half_beam_rad / 2.0).cos(),
        };
        LAST.set(Some((key, cone)));
        cone
    }
}

/// The direction `beam`'s echo from a plane with normal `normal` comes along: the normal when
/// it lies inside the cone, else the cone's edge nearer to it; and whether it lies inside.
pub fn echo_ray(beam: &Beam, normal: &Vec2, half: HalfCone) -> (Vec2, bool) {
    let d = beam.direction;
    if d.dot(normal) >= half.cos {
        return (*normal, true);
    }
    let s = half.sin.copysign(d.x * normal.y - d.y * normal.x);
    (
        Vec2::new(half.cos * d.x - s * d.y, s * d.x + half.cos * d.y),
        false,
    )
}

/// `cos γ`, where γ is the angle between `beam`'s echoing ray and the normal `normal` of a
/// plane: zero when the normal lies inside the cone, else how far outside it lies; `None`
/// beyond [`MAX_INCIDENCE_RAD`]. A plane at perpendicular distance `p` echoes at `p / cos γ`.
pub fn incidence_cosine(beam: &Beam, normal: &Vec2, half: HalfCone) -> Option<f64> {
    let cos_off = beam.direction.dot(normal);
    if cos_off >= half.cos {
        return Some(1.0);
    }
    // cos(|off| − half) without a trigonometric call.
    let sin_off = (beam.direction.x * normal.y - beam.direction.y * normal.x).abs();
    let cos_incidence = cos_off * half.cos + sin_off * half.sin;
    (cos_incidence >= MAX_INCIDENCE_RAD.cos()).then_some(cos_incidence)
}

/// Tolerance of a range `range_m` in feature tests: the sonar resolution `ξ·D/100`, at least
/// 1 in (as `eval` judges end-points).
pub fn feature_tolerance_m(accuracy_pct: f64, range_m: f64) -> f64 {
    (accuracy_pct * range_m / 100.0).max(inches(1.0))
}

/// The mean position of the sensors of `beams` (not empty).
pub fn mean_origin(beams: &[Beam]) -> Point {
    Point::from(beams.iter().map(|b| b.origin.coords).sum::<Vec2>() / beams.len() as f64)
}

/// The mean range of `beams` (not empty), metres.
pub fn mean_range_m(beams: &[Beam]) -> f64 {
    beams.iter().map(|b| b.range_m).sum::<f64>() / beams.len() as f64
}

/// The echo a rounded reflector (a pillar, docs/algorithm.md §8.14) returns to a beam: its
/// range and how the range moves with the reflector's centre and radius.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RoundEcho {
    /// The range the beam reads, metres.
    pub range_m: f64,
    /// The range's gradient in the centre, metres per metre.
    pub d_range_d_centre: Vec2,
    /// The range's derivative in the radius.
    pub d_range_d_radius: f64,
}

impl RoundEcho {
    /// The echo along the ray through the centre, `v` from the sensor (`d` its length):
    /// `d − radius_m`, the surface's normal.
    pub fn through_centre(v: Vec2, d: f64, radius_m: f64) -> Self {
        RoundEcho {
            range_m: d - radius_m,
            d_range_d_centre: v / d,
            d_range_d_radius: -1.0,
        }
    }
}

/// The echo `beam`'s sonar hears from a pillar of centre `at` and radius `radius_m` (0 for a
/// point), as for a plane (§8.10): along the ray through the centre, the surface's normal,
/// `|at − o| − radius_m`, when the centre lies inside the cone; else along the cone's edge
/// nearer the centre, where that edge meets the surface within [`MAX_INCIDENCE_RAD`] of its
/// normal (a pillar whose centre lies just outside a wide beam still fills its edge). `None`
/// when the sensor is inside the pillar, or the centre lies outside the cone and the radius is
/// not positive (a point), the edge misses the circle, meets it beyond that incidence, or
/// points away from it.
///
/// The edge ray `e` meets the circle at `t = e·v − s`, where `v = at − o` and
/// `s = √(r² − |v|² + (e·v)²)`; the incidence there is `acos(s / r)`.
pub fn round_echo(at: &Point, radius_m: f64, beam: &Beam, half: HalfCone) -> Option<RoundEcho> {
    let v = at - beam.origin;
    let d = v.norm();
    if d <= radius_m {
        return None;
    }
    if v.dot(&beam.direction) / d >= half.cos {
        return Some(RoundEcho::through_centre(v, d, radius_m));
    }
    // A point (or, in a fit's steps, a negative radius) gives no echo outside the cone.
    if radius_m.is_nan() || radius_m <= 0.0 {
        return None;
    }
    let (ray, _) = echo_ray(beam, &(v / d), half);
    let along = ray.dot(&v);
    let s2 = radius_m * radius_m - (d * d - along * along);
    let s_min = radius_m * MAX_INCIDENCE_RAD.cos();
    if along.is_nan() || s2.is_nan() || along <= 0.0 || s2 < s_min * s_min {
        return None;
    }
    let s = s2.sqrt();
    Some(RoundEcho {
        range_m: along - s,
        d_range_d_centre: ray + (v - ray * along) / s,
        d_range_d_radius: -radius_m / s,
    })
}

/// The range of the echo `beam`'s sonar hears from the rounded reflector of centre `at` and
/// radius `radius_m` ([`round_echo`]) less the reading's, metres, when that lies within the
/// reading's tolerance ([`feature_tolerance_m`]): the reflector explains the reading.
pub fn round_residual_m(
    at: &Point,
    radius_m: f64,
    beam: &Beam,
    accuracy_pct: f64,
    half: HalfCone,
) -> Option<f64> {
    let residual_m = round_echo(at, radius_m, beam, half)?.range_m - beam.range_m;
    (residual_m.abs() <= feature_tolerance_m(accuracy_pct, beam.range_m)).then_some(residual_m)
}
