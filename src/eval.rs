//! A map against its floor plan: how many fitted segments lie on a wall, how well, and how much
//! of the walls they cover.
//!
//! Definitions (only `fitted` segments count; interpolated links are ignored):
//! - **tolerance** of an end-point with range `D`: the sonar resolution `ξ·D/100` (the mapping
//!   parameter `ξ`), at least 1 in.
//! - **true segment**: both end-points within their tolerance of one wall (distance to the wall
//!   as a closed segment) and the angle between segment and wall at most `θ_o`; or both
//!   end-points within tolerance of one pillar's circle. The wall with the smallest summed
//!   end-point distance is its wall.
//! - `spurious_fraction`: 1 − true/fitted (0 without segments).
//! - `mean_endpoint_error`: mean distance of true segments' end-points to their wall or pillar,
//!   in the log's units; `mean_angle_error_deg`: mean angle between true segments and their walls.
//! - `coverage`: the union, per wall, of the true segments' end-points projected on their wall
//!   (clamped to it), summed over walls, over the total wall length.
//! - **visible** part of a wall: each kept reading (an echo below the sensor's maximum range,
//!   within `[min_range, d_max]`) whose beam-axis point lies within its tolerance of the wall
//!   marks the interval of ± its tolerance around its projection; consecutive marks along the wall
//!   no more than `t_gap` apart are joined (the clustering gap of docs/algorithm.md §2).
//!   `coverage_visible` is the covered length inside the visible part over the visible length
//!   (`null` when no wall is visible).

use crate::geometry::{distance_to_segment, line_angle_between, projection_param};
use crate::mapping::{Map, Params, SegmentKind};
use crate::run::{FloorPlan, Run};
use crate::units::inches;
use serde::{Deserialize, Serialize};

/// The figures of one evaluation. Lengths in the log's units.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct EvalReport {
    /// The unit of the lengths.
    pub units: String,
    /// Fitted segments in the map.
    pub segments: usize,
    /// Fitted segments that lie on a wall or pillar.
    pub true_segments: usize,
    /// 1 − true/fitted.
    pub spurious_fraction: f64,
    /// Mean end-point distance of true segments to their wall or pillar (`null` without any).
    pub mean_endpoint_error: Option<f64>,
    /// Mean angle of true segments to their wall, degrees (`null` without any on a wall).
    pub mean_angle_error_deg: Option<f64>,
    /// Covered wall length over total wall length.
    pub coverage: f64,
    /// Covered visible wall length over visible wall length.
    pub coverage_visible: Option<f64>,
    /// Total wall length.
    pub wall_length: f64,
    /// Visible wall length.
    pub visible_length: f64,
    /// Covered wall length.
    pub covered_length: f64,
}

/// Sorted, disjoint closed intervals of a wall's parameter in [0, 1].
fn union(mut intervals: Vec<(f64, f64)>) -> Vec<(f64, f64)> {
    intervals.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut out: Vec<(f64, f64)> = Vec::new();
    for (lo, hi) in intervals {
        match out.last_mut() {
            Some(last) if lo <= last.1 => last.1 = last.1.max(hi),
            _ => out.push((lo, hi)),
        }
    }
    out
}

fn measure(intervals: &[(f64, f64)]) -> f64 {
    intervals.iter().map(|(lo, hi)| hi - lo).sum()
}

/// Length of the intersection of two sorted disjoint interval lists.
fn intersection_measure(a: &[(f64, f64)], b: &[(f64, f64)]) -> f64 {
    let (mut i, mut j, mut total) = (0, 0, 0.0);
    while i < a.len() && j < b.len() {
        let lo = a[i].0.max(b[j].0);
        let hi = a[i].1.min(b[j].1);
        if hi > lo {
            total += hi - lo;
        }
        if a[i].1 < b[j].1 {
            i += 1;
        } else {
            j += 1;
        }
    }
    total
}

/// Compares `map` with `floor_plan`; `run` gives the readings (for visibility) and the units,
/// `params` the resolution `ξ`, `θ_o`, `t_gap`, `d_max` and `min_range`.
pub fn evaluate(map: &Map, run: &Run, floor_plan: &FloorPlan, params: &Params) -> EvalReport {
    let floor_m = inches(1.0);
    let tol = |range_m: f64| (params.accuracy_pct * range_m / 100.0).max(floor_m);
    let walls = &floor_plan.walls;
    let mut covered: Vec<Vec<(f64, f64)>> = vec![Vec::new(); walls.len()];
    let (mut fitted, mut true_count) = (0usize, 0usize);
    let (mut endpoint_sum, mut endpoint_n) = (0.0, 0usize);
    let (mut angle_sum, mut angle_n) = (0.0, 0usize);
    for s in map
        .segments
        .iter()
        .filter(|s| s.kind == SegmentKind::Fitted)
    {
        fitted += 1;
        let (ta, tb) = (tol(s.a.range_m), tol(s.b.range_m));
        let dir = s.b.point - s.a.point;
        let mut best: Option<(usize, f64, f64)> = None;
        for (i, w) in walls.iter().enumerate() {
            let da = distance_to_segment(&s.a.point, &w.a, &w.b);
            let db = distance_to_segment(&s.b.point, &w.a, &w.b);
            let angle = line_angle_between(&dir, &(w.b - w.a));
            if da <= ta
                && db <= tb
                && angle <= params.orientation_rad + 1e-12
                && best.is_none_or(|b| da + db < b.1)
            {
                best = Some((i, da + db, angle));
            }
        }
        if let Some((i, d, angle)) = best {
            true_count += 1;
            endpoint_sum += d;
            endpoint_n += 2;
            angle_sum += angle;
            angle_n += 1;
            let w = &walls[i];
            let pa = projection_param(&s.a.point, &w.a, &w.b).clamp(0.0, 1.0);
            let pb = projection_param(&s.b.point, &w.a, &w.b).clamp(0.0, 1.0);
            covered[i].push((pa.min(pb), pa.max(pb)));
            continue;
        }
        let on_circle = floor_plan.circles.iter().find_map(|c| {
            let da = ((s.a.point - c.centre).norm() - c.radius_m).abs();
            let db = ((s.b.point - c.centre).norm() - c.radius_m).abs();
            (da <= ta && db <= tb).then_some(da + db)
        });
        if let Some(d) = on_circle {
            true_count += 1;
            endpoint_sum += d;
            endpoint_n += 2;
        }
    }
    // Visibility from the kept readings.
    let mut marks: Vec<Vec<(f64, f64)>> = vec![Vec::new(); walls.len()];
    for snap in &run.snapshots {
        for (k, r) in snap.ranges_m.iter().enumerate() {
            let Some(d) = *r else { continue };
            if k >= run.layout.len()
                || d >= run.sensor.max_range_m
                || d > params.d_max_m
                || d < params.min_range_m
            {
                continue;
            }
            let p = run.layout.point_in_world(&snap.pose, k, d);
            for (i, w) in walls.iter().enumerate() {
                if distance_to_segment(&p, &w.a, &w.b) <= tol(d) {
                    marks[i].push((projection_param(&p, &w.a, &w.b).clamp(0.0, 1.0), tol(d)));
                }
            }
        }
    }
    let (mut wall_length, mut covered_length, mut visible_length, mut covered_visible) =
        (0.0, 0.0, 0.0, 0.0);
    for (i, w) in walls.iter().enumerate() {
        let len = (w.b - w.a).norm();
        if len <= 0.0 {
            continue;
        }
        wall_length += len;
        let cov = union(std::mem::take(&mut covered[i]));
        covered_length += measure(&cov) * len;
        let mut m = std::mem::take(&mut marks[i]);
        m.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut visible = Vec::new();
        let mut current: Option<(f64, f64, f64)> = None; // (lo, hi, last mark)
        for (t, r) in m {
            let (lo, hi) = ((t - r / len).max(0.0), (t + r / len).min(1.0));
            current = match current {
                Some((clo, chi, last)) if (t - last) * len <= params.t_gap_m => {
                    Some((clo, chi.max(hi), t))
                }
                Some(c) => {
                    visible.push((c.0, c.1));
                    Some((lo, hi, t))
                }
                None => Some((lo, hi, t)),
            };
        }
        if let Some(c) = current {
            visible.push((c.0, c.1));
        }
        let visible = union(visible);
        visible_length += measure(&visible) * len;
        covered_visible += intersection_measure(&cov, &visible) * len;
    }
    let u = run.units;
    EvalReport {
        units: u.symbol().to_string(),
        segments: fitted,
        true_segments: true_count,
        spurious_fraction: if fitted == 0 {
            0.0
        } else {
            1.0 - true_count as f64 / fitted as f64
        },
        mean_endpoint_error: (endpoint_n > 0).then(|| u.from_m(endpoint_sum / endpoint_n as f64)),
        mean_angle_error_deg: (angle_n > 0).then(|| (angle_sum / angle_n as f64).to_degrees()),
        coverage: if wall_length > 0.0 {
            covered_length / wall_length
        } else {
            0.0
        },
        coverage_visible: (visible_length > 0.0).then(|| covered_visible / visible_length),
        wall_length: u.from_m(wall_length),
        visible_length: u.from_m(visible_length),
        covered_length: u.from_m(covered_length),
    }
}
