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

use crate::alignment::{align, Alignment, Search};
use crate::geometry::{distance_to_segment, line_angle_between, projection_param, Point};
use crate::intervals::{intersection_measure, measure, union};
use crate::mapping::{Map, Params, Segment, SegmentId, SegmentKind};
use crate::near_path::{near_path_spans, NEAR_PATH_M};
use crate::pose_error::{pose_error, PoseError};
use crate::run::{FloorPlan, Run, Wall};
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
    /// Covered length of the walls within 1.5 m of the robot's path (the snapshots' poses)
    /// over that length (`null` when no wall is that near).
    pub coverage_near_path: Option<f64>,
    /// Length of the walls within 1.5 m of the path.
    pub near_path_length: f64,
    /// How far the poses mapped with lie from the true poses, when the log keeps them
    /// (`true_pose`: a run given odometry error).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pose_error: Option<PoseError>,
    /// The rigid transform the map was scored after (`eval --align`), when it was aligned.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub alignment: Option<AlignmentReport>,
}

/// How a map was laid on its floor plan before scoring ([`crate::alignment`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct AlignmentReport {
    /// The transform of the whole map.
    #[serde(flatten)]
    pub whole: Alignment,
    /// The rotation that aligns the segments made in the run's first quarter of snapshots
    /// alone, degrees (`null` without any): drift shows as a difference from the last's.
    pub first_quarter_rotation_deg: Option<f64>,
    /// The same for the segments made in its last quarter.
    pub last_quarter_rotation_deg: Option<f64>,
}

/// [`evaluate`] after laying `map` on `floor_plan` by the best rigid transform found by
/// `search` ([`crate::alignment::align`]); the plan is moved into the map's frame, so that the
/// readings and the poses keep theirs. The quarters are aligned near the whole's transform.
/// Without fitted segments the map is scored where it is.
pub fn evaluate_aligned(
    map: &Map,
    run: &Run,
    floor_plan: &FloorPlan,
    params: &Params,
    search: Search,
) -> EvalReport {
    let Some(whole) = align(map.segments.iter().map(|s| &**s), floor_plan, search) else {
        return evaluate(map, run, floor_plan, params);
    };
    let snapshots = run.snapshots.len();
    let quarter_rotation = |in_quarter: &dyn Fn(usize) -> bool| {
        align(
            map.segments
                .iter()
                .filter(|s| in_quarter(s.created))
                .map(|s| &**s),
            floor_plan,
            Search::Near(Some(whole)),
        )
        .map(|a| a.rotation_deg)
    };
    let alignment = AlignmentReport {
        whole,
        first_quarter_rotation_deg: quarter_rotation(&|created| created * 4 < snapshots),
        last_quarter_rotation_deg: quarter_rotation(&|created| created * 4 >= snapshots * 3),
    };
    EvalReport {
        alignment: Some(alignment),
        ..evaluate(map, run, &whole.plan_in_map_frame(floor_plan), params)
    }
}

/// What `eval` says of one fitted map segment.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", tag = "verdict")]
pub enum Verdict {
    /// Both end-points within tolerance of wall `wall` (its index in the floor plan) and its
    /// angle to it at most `θ_o`.
    OnWall {
        /// Index of the wall.
        wall: usize,
        /// Mean distance of the two end-points to the wall, metres.
        endpoint_error_m: f64,
        /// Angle to the wall, radians.
        angle_rad: f64,
    },
    /// Both end-points within tolerance of pillar `pillar`'s circle.
    OnPillar {
        /// Index of the pillar.
        pillar: usize,
        /// Mean distance of the two end-points to the circle, metres.
        endpoint_error_m: f64,
    },
    /// On no wall and no pillar.
    Spurious,
}

impl Verdict {
    /// True for a segment on a wall or pillar.
    pub fn is_true(&self) -> bool {
        !matches!(self, Verdict::Spurious)
    }
}

/// The verdict of `eval` on segment `s` against `floor_plan` (see the module's definitions):
/// the wall with the smallest summed end-point distance among those it lies on, else the first
/// pillar it lies on, else spurious.
pub fn segment_verdict(s: &Segment, floor_plan: &FloorPlan, params: &Params) -> Verdict {
    let tol = |range_m: f64| (params.accuracy_pct * range_m / 100.0).max(inches(1.0));
    let (ta, tb) = (tol(s.a.range_m), tol(s.b.range_m));
    let dir = s.b.point - s.a.point;
    let mut best: Option<(usize, f64, f64)> = None;
    // Distance from `p` to the wall's bounding box: no more than to the wall itself, and cheap,
    // so most walls are passed over before the exact test.
    let off_box = |p: &crate::geometry::Point, w: &crate::run::Wall| {
        let dx = (w.a.x.min(w.b.x) - p.x)
            .max(p.x - w.a.x.max(w.b.x))
            .max(0.0);
        let dy = (w.a.y.min(w.b.y) - p.y)
            .max(p.y - w.a.y.max(w.b.y))
            .max(0.0);
        dx.hypot(dy)
    };
    for (i, w) in floor_plan.walls.iter().enumerate() {
        if off_box(&s.a.point, w) > ta || off_box(&s.b.point, w) > tb {
            continue;
        }
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
    if let Some((wall, d, angle_rad)) = best {
        return Verdict::OnWall {
            wall,
            endpoint_error_m: d / 2.0,
            angle_rad,
        };
    }
    floor_plan
        .circles
        .iter()
        .enumerate()
        .find_map(|(pillar, c)| {
            let da = ((s.a.point - c.centre).norm() - c.radius_m).abs();
            let db = ((s.b.point - c.centre).norm() - c.radius_m).abs();
            (da <= ta && db <= tb).then_some(Verdict::OnPillar {
                pillar,
                endpoint_error_m: (da + db) / 2.0,
            })
        })
        .unwrap_or(Verdict::Spurious)
}

/// The verdict of every fitted segment of `map`, in map order.
pub fn map_verdicts(
    map: &Map,
    floor_plan: &FloorPlan,
    params: &Params,
) -> Vec<(SegmentId, Verdict)> {
    map.segments
        .iter()
        .filter(|s| s.kind == SegmentKind::Fitted)
        .map(|s| (s.id, segment_verdict(s, floor_plan, params)))
        .collect()
}

/// The figures of the map alone (before visibility): counts, error sums and each wall's
/// covered intervals.
struct MapPart {
    fitted: usize,
    true_count: usize,
    endpoint_sum: f64,
    endpoint_n: usize,
    angle_sum: f64,
    angle_n: usize,
    covered: Vec<Vec<(f64, f64)>>,
}

impl MapPart {
    /// The figures of `map` from `verdicts`, the verdicts on its fitted segments in map order
    /// ([`map_verdicts`]).
    fn of(map: &Map, floor_plan: &FloorPlan, verdicts: &[(SegmentId, Verdict)]) -> Self {
        let walls = &floor_plan.walls;
        let mut part = MapPart {
            fitted: 0,
            true_count: 0,
            endpoint_sum: 0.0,
            endpoint_n: 0,
            angle_sum: 0.0,
            angle_n: 0,
            covered: vec![Vec::new(); walls.len()],
        };
        for (s, verdict) in verdicts
            .iter()
            .filter_map(|(id, v)| map.segment(*id).map(|s| (s, v)))
        {
            part.fitted += 1;
            match *verdict {
                Verdict::OnWall {
                    wall,
                    endpoint_error_m,
                    angle_rad,
                } => {
                    part.true_count += 1;
                    part.endpoint_sum += 2.0 * endpoint_error_m;
                    part.endpoint_n += 2;
                    part.angle_sum += angle_rad;
                    part.angle_n += 1;
                    let w = &walls[wall];
                    let pa = projection_param(&s.a.point, &w.a, &w.b).clamp(0.0, 1.0);
                    let pb = projection_param(&s.b.point, &w.a, &w.b).clamp(0.0, 1.0);
                    part.covered[wall].push((pa.min(pb), pa.max(pb)));
                }
                Verdict::OnPillar {
                    endpoint_error_m, ..
                } => {
                    part.true_count += 1;
                    part.endpoint_sum += 2.0 * endpoint_error_m;
                    part.endpoint_n += 2;
                }
                Verdict::Spurious => {}
            }
        }
        part
    }

    fn spurious_fraction(&self) -> f64 {
        if self.fitted == 0 {
            0.0
        } else {
            1.0 - self.true_count as f64 / self.fitted as f64
        }
    }
}

/// The spurious fraction and the coverage of `eval` for `map` (without the visibility figures,
/// which need the whole run), from `verdicts` ([`map_verdicts`]): the figures the inspector
/// shows for the snapshot on screen.
pub fn truth_figures(
    map: &Map,
    floor_plan: &FloorPlan,
    verdicts: &[(SegmentId, Verdict)],
) -> (f64, f64) {
    let part = MapPart::of(map, floor_plan, verdicts);
    let (mut wall_length, mut covered_length) = (0.0, 0.0);
    for (w, covered) in floor_plan.walls.iter().zip(part.covered.iter()) {
        let len = (w.b - w.a).norm();
        wall_length += len;
        covered_length += measure(&union(covered.clone())) * len;
    }
    let coverage = if wall_length > 0.0 {
        covered_length / wall_length
    } else {
        0.0
    };
    (part.spurious_fraction(), coverage)
}

/// The parameters a map made with `params` is judged with: the same, with the resolution's ξ
/// replaced by `score_accuracy_pct` when one is given (`eval --score-accuracy-pct`), so maps made
/// with different ξ share one tolerance.
pub fn judged_with(params: &Params, score_accuracy_pct: Option<f64>) -> Params {
    Params {
        accuracy_pct: score_accuracy_pct.unwrap_or(params.accuracy_pct),
        ..params.clone()
    }
}

/// Compares `map` with `floor_plan`; `run` gives the readings (for visibility) and the units,
/// `params` the resolution `ξ`, `θ_o`, `t_gap`, `d_max` and `min_range`.
pub fn evaluate(map: &Map, run: &Run, floor_plan: &FloorPlan, params: &Params) -> EvalReport {
    let floor_m = inches(1.0);
    let tol = |range_m: f64| (params.accuracy_pct * range_m / 100.0).max(floor_m);
    let walls = &floor_plan.walls;
    let part = MapPart::of(map, floor_plan, &map_verdicts(map, floor_plan, params));
    let spurious_fraction = part.spurious_fraction();
    let MapPart {
        fitted,
        true_count,
        endpoint_sum,
        endpoint_n,
        angle_sum,
        angle_n,
        mut covered,
    } = part;
    let mut marks = visibility_marks(run, walls, params, &tol);
    let (mut wall_length, mut covered_length, mut visible_length, mut covered_visible) =
        (0.0, 0.0, 0.0, 0.0);
    let (mut near_length, mut covered_near) = (0.0, 0.0);
    let path: Vec<Point> = run
        .snapshots
        .iter()
        .map(|s| Point::new(s.pose.x, s.pose.y))
        .collect();
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
        let visible = visible_spans(m, len, params.t_gap_m);
        visible_length += measure(&visible) * len;
        covered_visible += intersection_measure(&cov, &visible) * len;
        let near = near_path_spans(&w.a, &w.b, &path, NEAR_PATH_M);
        near_length += measure(&near) * len;
        covered_near += intersection_measure(&cov, &near) * len;
    }
    let u = run.units;
    EvalReport {
        units: u.symbol().to_string(),
        segments: fitted,
        true_segments: true_count,
        spurious_fraction,
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
        coverage_near_path: (near_length > 0.0).then(|| covered_near / near_length),
        near_path_length: u.from_m(near_length),
        pose_error: pose_error(run),
        alignment: None,
    }
}

/// For each wall, the marks of the kept readings whose beam-axis point lies within its
/// tolerance (`tol` of the range) of it: the point's place along the wall (0 to 1) and the
/// tolerance, metres.
fn visibility_marks(
    run: &Run,
    walls: &[Wall],
    params: &Params,
    tol: &dyn Fn(f64) -> f64,
) -> Vec<Vec<(f64, f64)>> {
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
    marks
}

/// The visible spans of a wall `len` metres long from its marks sorted along it: ± each
/// mark's tolerance, marks no more than `t_gap_m` apart joined (a union of spans, 0 to 1).
fn visible_spans(marks: Vec<(f64, f64)>, len: f64, t_gap_m: f64) -> Vec<(f64, f64)> {
    let mut visible = Vec::new();
    let mut current: Option<(f64, f64, f64)> = None; // (lo, hi, last mark)
    for (t, r) in marks {
        let (lo, hi) = ((t - r / len).max(0.0), (t + r / len).min(1.0));
        current = match current {
            Some((clo, chi, last)) if (t - last) * len <= t_gap_m => Some((clo, chi.max(hi), t)),
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
    union(visible)
}

/// The confirmed part of `map` (its tentative segments left out, docs/algorithm.md §8.7), when
/// its segments must be confirmed; `None` otherwise (every segment then counts as confirmed).
pub fn confirmed_map(map: &Map) -> Option<Map> {
    map.confirms_segments.then(|| {
        Map::from_segments(
            map.segments
                .iter()
                .filter(|s| !map.is_tentative(s.id))
                .map(|s| (**s).clone())
                .collect(),
        )
    })
}

/// Confirmed point features of `map` that lie on a wall junction or end: within the tolerance
/// of their range (`ξ·D/100`, at least 1 in), doubled, of a wall's end-point; and rounded ones
/// (docs/algorithm.md §8.14) that are a pillar: centre and radius each within that tolerance
/// of the pillar's.
pub fn true_point_features(map: &Map, floor_plan: &FloorPlan, params: &Params) -> usize {
    map.confirmed_features()
        .filter(|f| {
            let tol = 2.0 * (params.accuracy_pct * f.range_m / 100.0).max(inches(1.0));
            if f.radius_m > 0.0 {
                return floor_plan.circles.iter().any(|c| {
                    (c.centre - f.at).norm() <= tol && (c.radius_m - f.radius_m).abs() <= tol
                });
            }
            floor_plan
                .walls
                .iter()
                .any(|w| (w.a - f.at).norm() <= tol || (w.b - f.at).norm() <= tol)
        })
        .count()
}
