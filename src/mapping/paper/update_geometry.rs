//! The geometry of an update (paper §3.3.2, Figures 1 and 2; docs/algorithm.md §5): which
//! end-points a MATCH or an EXTENSION keeps, and which are projected onto the line.
//!
//! End-points are compared by range: the smaller `D` is the higher confidence; on a tie the
//! existing end-point wins. A projected end-point keeps the range of the reading it came from.

use crate::geometry::{fit_line_tls, lerp, projection_param, Point};
use crate::mapping::model::map::EndPoint;
use crate::mapping::model::trace::{EndOrigin, EndPointFate, EndRole, Side};

/// Defining points closer than this (metres) are "nearly coinciding" (§5 fallback).
const COINCIDENT_M: f64 = 1e-6;

/// The result of the update rule, before the post-update split test.
#[derive(Clone, Debug, PartialEq)]
pub struct UpdateGeometry {
    /// New end-points, in the existing segment's direction.
    pub ends: [EndPoint; 2],
    /// The two points that define `l_u`.
    pub line: [Point; 2],
    /// What became of each of the four end-points.
    pub fates: Vec<EndPointFate>,
    /// `l_u` is the total-least-squares line of the four end-points.
    pub fallback_tls: bool,
}

struct Labelled {
    origin: EndOrigin,
    end: EndPoint,
}

/// The higher-confidence of `existing` and `new` (smaller range; a tie keeps the existing).
fn more_confident<'a>(existing: &'a Labelled, new: &'a Labelled) -> (&'a Labelled, &'a Labelled) {
    if new.end.range_m < existing.end.range_m {
        (new, existing)
    } else {
        (existing, new)
    }
}

/// A line through `p` and `q`, or, when they nearly coincide, the total-least-squares line of
/// `all`. Returns two points on it and whether the fallback was used.
fn defining_line(p: Point, q: Point, all: &[Point]) -> ([Point; 2], bool) {
    if (q - p).norm() > COINCIDENT_M {
        return ([p, q], false);
    }
    match fit_line_tls(all) {
        Some((centre, dir)) => ([centre, centre + dir], true),
        // All four coincide: a degenerate segment at that point.
        None => ([p, p + nalgebra::Vector2::new(1.0, 0.0)], true),
    }
}

fn fate(l: &Labelled, role: EndRole, compared_with: EndOrigin) -> EndPointFate {
    EndPointFate {
        origin: l.origin,
        before: l.end,
        role,
        compared_with,
        projection: None,
        is_end_after: false,
    }
}

/// The four end-points of an update with their origins: `e_L`, `e_R`, `n_L`, `n_R`.
fn labelled(e: [EndPoint; 2], n_left: EndPoint, n_right: EndPoint) -> [Labelled; 4] {
    let l = |origin, end| Labelled { origin, end };
    [
        l(EndOrigin::ExistingLeft, e[0]),
        l(EndOrigin::ExistingRight, e[1]),
        l(EndOrigin::NewLeft, n_left),
        l(EndOrigin::NewRight, n_right),
    ]
}

/// MATCH (MPC) update, Figure 1: `u_L`, `u_R` are the more confident of `{e_L, n_L}` and
/// `{e_R, n_R}`; `l_u` runs through them; the two others are projected on `l_u` and the result
/// is the longest segment on `l_u` covering all four projections.
///
/// ```
/// use sonarmap::geometry::Point;
/// use sonarmap::mapping::paper::update_geometry::update_match;
/// use sonarmap::mapping::EndPoint;
/// let end = |x: f64, y: f64, d: f64| EndPoint { point: Point::new(x, y), range_m: d };
/// // l_e (0,0)–(10,0) read at 60 and 40; l_n (−4,1)–(8,0.2) read at 50 and 45. u_L = n_L
/// // (50 < 60), u_R = e_R (40 < 45): l_u runs from (−4, 1) to (10, 0). e_L and n_R project
/// // inside it, so the result is u_L–u_R, in l_e's direction, each end keeping its range.
/// let g = update_match([end(0.0, 0.0, 60.0), end(10.0, 0.0, 40.0)], end(-4.0, 1.0, 50.0), end(8.0, 0.2, 45.0));
/// assert_eq!(g.ends, [end(-4.0, 1.0, 50.0), end(10.0, 0.0, 40.0)]);
/// assert!(!g.fallback_tls);
/// ```
pub fn update_match(e: [EndPoint; 2], n_left: EndPoint, n_right: EndPoint) -> UpdateGeometry {
    let [el, er, nl, nr] = labelled(e, n_left, n_right);
    let (ul, low_l) = more_confident(&el, &nl);
    let (ur, low_r) = more_confident(&er, &nr);
    let all = [e[0].point, e[1].point, n_left.point, n_right.point];
    let (line, fallback_tls) = defining_line(ul.end.point, ur.end.point, &all);
    let mut fates = vec![
        fate(ul, EndRole::Kept, low_l.origin),
        fate(ur, EndRole::Kept, low_r.origin),
        fate(low_l, EndRole::Projected, ul.origin),
        fate(low_r, EndRole::Projected, ur.origin),
    ];
    // Parameter of each end-point on l_u; kept ones sit on the line unless the fallback is used.
    let params: Vec<f64> = fates
        .iter()
        .map(|f| projection_param(&f.before.point, &line[0], &line[1]))
        .collect();
    for (f, &t) in fates.iter_mut().zip(&params) {
        if f.role == EndRole::Projected || fallback_tls {
            f.projection = Some(lerp(&line[0], &line[1], t));
        }
    }
    // Ends: the kept points unless a projection falls strictly outside them.
    let pick = |want_min: bool| -> usize {
        let mut best = if want_min { 0 } else { 1 };
        for i in 0..4 {
            let better = if want_min {
                params[i] < params[best]
            } else {
                params[i] > params[best]
            };
            if better {
                best = i;
            }
        }
        best
    };
    let (lo, hi) = (pick(true), pick(false));
    // Keep the existing segment's direction: `a` is the end nearer e_L along l_u.
    let e_dir_positive = projection_param(&e[1].point, &line[0], &line[1])
        >= projection_param(&e[0].point, &line[0], &line[1]);
    let (first, second) = if e_dir_positive { (lo, hi) } else { (hi, lo) };
    fates[first].is_end_after = true;
    fates[second].is_end_after = true;
    let end_of = |f: &EndPointFate| EndPoint {
        point: f.projection.unwrap_or(f.before.point),
        range_m: f.before.range_m,
    };
    UpdateGeometry {
        ends: [end_of(&fates[first]), end_of(&fates[second])],
        line,
        fates,
        fallback_tls,
    }
}

/// EXTENSION (EPC) update, Figure 2. With `inside = Left` (`n_L` projects into `l_e`): the
/// middle point `M` is the more confident of `{e_R, n_L}`; of the outer points `e_L` and `n_R`,
/// the more confident stays and `l_u` runs through it and `M`; the other is projected on `l_u`.
/// Symmetric for `inside = Right`. The less confident inner point is dropped.
pub fn update_extension(
    e: [EndPoint; 2],
    n_left: EndPoint,
    n_right: EndPoint,
    inside: Side,
) -> UpdateGeometry {
    let [el, er, nl, nr] = labelled(e, n_left, n_right);
    // (existing inner, new inner, existing outer, new outer)
    let (e_in, n_in, e_out, n_out) = match inside {
        Side::Left => (&er, &nl, &el, &nr),
        Side::Right => (&el, &nr, &er, &nl),
    };
    let (middle, dropped) = more_confident(e_in, n_in);
    let (kept, projected) = more_confident(e_out, n_out);
    let all = [e[0].point, e[1].point, n_left.point, n_right.point];
    let (line, fallback_tls) = defining_line(kept.end.point, middle.end.point, &all);
    let on_line = |p: &Point| lerp(&line[0], &line[1], projection_param(p, &line[0], &line[1]));
    let mut kept_fate = fate(kept, EndRole::Kept, projected.origin);
    let mut projected_fate = fate(projected, EndRole::Projected, kept.origin);
    let mut middle_fate = fate(middle, EndRole::Middle, dropped.origin);
    let dropped_fate = fate(dropped, EndRole::Dropped, middle.origin);
    projected_fate.projection = Some(on_line(&projected.end.point));
    if fallback_tls {
        kept_fate.projection = Some(on_line(&kept.end.point));
        middle_fate.projection = Some(on_line(&middle.end.point));
    }
    kept_fate.is_end_after = true;
    projected_fate.is_end_after = true;
    let end_of = |f: &EndPointFate| EndPoint {
        point: f.projection.unwrap_or(f.before.point),
        range_m: f.before.range_m,
    };
    // The existing outer end stays on its side of the segment.
    let (e_side, n_side) = if kept.origin == e_out.origin {
        (&kept_fate, &projected_fate)
    } else {
        (&projected_fate, &kept_fate)
    };
    let ends = match inside {
        Side::Left => [end_of(e_side), end_of(n_side)],
        Side::Right => [end_of(n_side), end_of(e_side)],
    };
    UpdateGeometry {
        ends,
        line,
        fates: vec![kept_fate, middle_fate, projected_fate, dropped_fate],
        fallback_tls,
    }
}
