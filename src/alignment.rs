//! The rigid transform that best lays a map on its floor plan, for scoring real runs whose plan
//! sits in another frame (`eval --align`), as trajectory evaluation aligns a trajectory before
//! measuring it (Umeyama 1991; the `evo` tool's `--align`).
//!
//! The fitted segments are sampled every [`SAMPLE_SPACING_M`]; each sample is paired with the
//! nearest point of a wall and the transform minimises the summed squared distances along the
//! wall normals (point-to-line ICP, Censi 2008's PLICP without its correspondence search), by
//! Gauss–Newton on (rotation about the samples' centroid, translation). Pairs farther apart than
//! a gate are left out; the gate shrinks from [`START_GATE_M`] to [`FINAL_GATE_M`]. Several
//! starts (rotations over the whole turn, the translation that lays centroids together or none)
//! keep a plan in any frame within reach; the result with the lowest robust cost wins, the
//! smallest rotation among those within [`TIE_FRACTION`] of it.

use crate::geometry::{projection_param, Point};
use crate::mapping::{Segment, SegmentKind};
use crate::run::{Circle, FloorPlan, Wall};
use nalgebra::{Matrix3, Rotation2, Vector2, Vector3};
use serde::{Deserialize, Serialize};

/// Distance between samples along a segment, metres.
pub const SAMPLE_SPACING_M: f64 = 0.05;
/// The first gate on a sample's distance to its wall, metres.
pub const START_GATE_M: f64 = 1.0;
/// The last gate, metres: the robust cost counts a sample at most this far.
pub const FINAL_GATE_M: f64 = 0.25;
/// Starts whose cost is within this fraction of the best count as ties.
pub const TIE_FRACTION: f64 = 0.02;
const ITERATIONS: usize = 40;

/// The transform `p ↦ R(rotation)·(p − pivot) + pivot + translation` from the map's frame
/// to the floor plan's.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Alignment {
    /// Rotation, degrees (counter-clockwise).
    pub rotation_deg: f64,
    /// Translation, metres, in the plan's frame.
    pub translation_m: [f64; 2],
    /// The point the rotation turns about (the samples' centroid), metres, map frame.
    pub pivot_m: [f64; 2],
    /// Samples of the segments used.
    pub samples: usize,
    /// Share of the samples within [`FINAL_GATE_M`] of a wall after alignment.
    pub inlier_fraction: f64,
    /// RMS distance of those inliers to their walls, metres.
    pub inlier_rms_m: f64,
}

impl Alignment {
    fn rotation(&self) -> Rotation2<f64> {
        Rotation2::new(self.rotation_deg.to_radians())
    }

    fn pivot(&self) -> Vector2<f64> {
        Vector2::from(self.pivot_m)
    }

    /// `p` (map frame) in the plan's frame.
    pub fn map_to_plan(&self, p: &Point) -> Point {
        let c = self.pivot();
        Point::from(self.rotation() * (p.coords - c) + c + Vector2::from(self.translation_m))
    }

    /// `p` (plan frame) in the map's frame.
    pub fn plan_to_map(&self, p: &Point) -> Point {
        let c = self.pivot();
        Point::from(
            self.rotation().inverse() * (p.coords - c - Vector2::from(self.translation_m)) + c,
        )
    }

    /// `plan` moved into the map's frame: scoring the map against it scores the aligned map.
    pub fn plan_in_map_frame(&self, plan: &FloorPlan) -> FloorPlan {
        FloorPlan {
            walls: plan
                .walls
                .iter()
                .map(|w| Wall {
                    a: self.plan_to_map(&w.a),
                    b: self.plan_to_map(&w.b),
                    ..*w
                })
                .collect(),
            circles: plan
                .circles
                .iter()
                .map(|c| Circle {
                    centre: self.plan_to_map(&c.centre),
                    ..*c
                })
                .collect(),
        }
    }
}

/// Points every [`SAMPLE_SPACING_M`] along the fitted segments (both ends included).
pub fn segment_samples<'a>(segments: impl IntoIterator<Item = &'a Segment>) -> Vec<Point> {
    let mut out = Vec::new();
    for s in segments {
        if s.kind != SegmentKind::Fitted {
            continue;
        }
        let (a, b) = (s.a.point, s.b.point);
        // A length that is a whole number of spacings up to rounding gets that number.
        let spacings = (b - a).norm() / SAMPLE_SPACING_M;
        let pieces = (spacings - 1e-9).ceil().clamp(1.0, 10_000.0) as usize;
        out.extend((0..=pieces).map(|i| a + (b - a) * (i as f64 / pieces as f64)));
    }
    out
}

/// A sample's nearest point on the plan's walls or pillars.
struct Nearest {
    distance_m: f64,
    point: Point,
    /// Unit normal there: the wall's, or from the point to the sample past a wall's end.
    normal: Vector2<f64>,
}

/// The nearest point of the plan's walls or pillars to `p`; `None` for an empty plan.
fn nearest_on_plan(p: &Point, plan: &FloorPlan) -> Option<Nearest> {
    let mut best: Option<Nearest> = None;
    let mut keep = |point: Point, normal: Vector2<f64>| {
        let distance_m = (p - point).norm();
        if best.as_ref().is_none_or(|b| distance_m < b.distance_m) {
            best = Some(Nearest {
                distance_m,
                point,
                normal,
            });
        }
    };
    for w in &plan.walls {
        let along = w.b - w.a;
        let t = projection_param(p, &w.a, &w.b);
        let q = w.a + along * t.clamp(0.0, 1.0);
        let offset = p - q;
        if offset.norm() > 0.0 && !(t > 0.0 && t < 1.0) {
            keep(q, offset.normalize());
        } else if along.norm() > 0.0 {
            keep(q, Vector2::new(-along.y, along.x).normalize());
        }
    }
    for c in &plan.circles {
        let offset = p - c.centre;
        let r = offset.norm();
        if r > 0.0 {
            keep(c.centre + offset * (c.radius_m / r), offset / r);
        }
    }
    best
}

/// Robust cost of `samples` under `alignment`: squared distances capped at the final gate.
fn cost(samples: &[Point], plan: &FloorPlan, alignment: &Alignment) -> f64 {
    samples
        .iter()
        .filter_map(|p| nearest_on_plan(&alignment.map_to_plan(p), plan))
        .map(|n| n.distance_m.min(FINAL_GATE_M).powi(2))
        .sum()
}

/// Gauss–Newton from `start`, the gate shrinking each iteration.
fn refine(samples: &[Point], plan: &FloorPlan, start: Alignment) -> Alignment {
    let mut a = start;
    let mut gate = START_GATE_M;
    for _ in 0..ITERATIONS {
        let (c, rotation) = (a.pivot(), a.rotation());
        let (mut h, mut g) = (Matrix3::<f64>::zeros(), Vector3::<f64>::zeros());
        for p in samples {
            let moved = a.map_to_plan(p);
            let Some(nearest) = nearest_on_plan(&moved, plan) else {
                continue;
            };
            if nearest.distance_m > gate {
                continue;
            }
            let normal = nearest.normal;
            // Signed distance along the normal; its derivative by (θ, tx, ty).
            let arm = rotation * (p.coords - c);
            let turn = Vector2::new(-arm.y, arm.x);
            let jacobian = Vector3::new(normal.dot(&turn), normal.x, normal.y);
            let signed = normal.dot(&(moved - nearest.point));
            h += jacobian * jacobian.transpose();
            g += jacobian * signed;
        }
        let damped = h + Matrix3::identity() * 1e-9 * (1.0 + h.trace());
        let Some(step) = damped.try_inverse().map(|inv| -(inv * g)) else {
            break;
        };
        a.rotation_deg += step.x.to_degrees();
        a.translation_m[0] += step.y;
        a.translation_m[1] += step.z;
        gate = (gate * 0.8).max(FINAL_GATE_M);
        if step.x.abs() < 1e-7 && step.y.hypot(step.z) < 1e-6 && gate == FINAL_GATE_M {
            break;
        }
    }
    a.rotation_deg = (a.rotation_deg + 180.0).rem_euclid(360.0) - 180.0;
    a
}

/// Length-weighted centroid of the plan's walls (pillars by their centres), metres.
fn plan_centroid(plan: &FloorPlan) -> Option<Vector2<f64>> {
    let (mut sum, mut weight) = (Vector2::zeros(), 0.0);
    for w in &plan.walls {
        let l = (w.b - w.a).norm();
        sum += (w.a.coords + w.b.coords) * 0.5 * l;
        weight += l;
    }
    for c in &plan.circles {
        sum += c.centre.coords * c.radius_m;
        weight += c.radius_m;
    }
    (weight > 0.0).then(|| sum / weight)
}

/// Samples used by the starts' coarse search; the best starts are then refined on all.
const COARSE_SAMPLES: usize = 400;
/// Samples of the final refinement at most (every k-th of a larger map's).
pub const MAX_SAMPLES: usize = 20_000;
/// Starts refined on all the samples.
const FINALISTS: usize = 4;

/// Where [`align`] looks for the transform.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Search {
    /// Near a known transform (identity when `None`): rotations within ±[`NEAR_DEG`] of it,
    /// for a plan drawn in roughly the map's frame.
    Near(Option<Alignment>),
    /// Over the whole turn, the translation that lays the centroids together or none, for a
    /// plan in any frame (a map much smaller than its plan can then align with the wrong part).
    Anywhere,
}

/// The reach of [`Search::Near`] in rotation, degrees.
pub const NEAR_DEG: f64 = 15.0;

/// The best alignment of `segments` on `plan`; `None` without fitted segments or walls.
pub fn align<'a>(
    segments: impl IntoIterator<Item = &'a Segment>,
    plan: &FloorPlan,
    search: Search,
) -> Option<Alignment> {
    let all = segment_samples(segments);
    // A large map is thinned evenly: the transform has three unknowns.
    let samples: Vec<Point> = all
        .iter()
        .step_by(all.len().div_ceil(MAX_SAMPLES).max(1))
        .copied()
        .collect();
    let plan_centre = plan_centroid(plan)?;
    if samples.is_empty() {
        return None;
    }
    let pivot = samples.iter().map(|p| p.coords).sum::<Vector2<f64>>() / samples.len() as f64;
    let start_at = |rotation_deg: f64, translation: Vector2<f64>| Alignment {
        rotation_deg,
        translation_m: [translation.x, translation.y],
        pivot_m: [pivot.x, pivot.y],
        samples: samples.len(),
        inlier_fraction: 0.0,
        inlier_rms_m: 0.0,
    };
    let near = |base_deg: f64, translation: Vector2<f64>| {
        (-6..=6).map(move |i| (base_deg + i as f64 * NEAR_DEG / 6.0, translation))
    };
    let candidates: Vec<(f64, Vector2<f64>)> = match search {
        Search::Near(None) => near(0.0, Vector2::zeros()).collect(),
        Search::Near(Some(base)) => {
            // The base transform re-expressed about this part's pivot.
            let target = base.map_to_plan(&Point::from(pivot));
            near(base.rotation_deg, target.coords - pivot).collect()
        }
        Search::Anywhere => (-18..18)
            .flat_map(|i| {
                let r = i as f64 * 10.0;
                [(r, Vector2::zeros()), (r, plan_centre - pivot)]
            })
            .chain(near(0.0, Vector2::zeros()))
            .collect(),
    };
    let stride = samples.len().div_ceil(COARSE_SAMPLES);
    let coarse: Vec<Point> = samples.iter().step_by(stride).copied().collect();
    let mut tried: Vec<(f64, Alignment)> = candidates
        .into_iter()
        .map(|(r, t)| refine(&coarse, plan, start_at(r, t)))
        .map(|a| (cost(&coarse, plan, &a), a))
        .collect();
    tried.sort_by(|x, y| x.0.total_cmp(&y.0));
    let finalists = tried
        .into_iter()
        .take(FINALISTS)
        .map(|(_, a)| refine(&samples, plan, a))
        .map(|a| (cost(&samples, plan, &a), a));
    Some(with_inliers(&samples, plan, least_of(finalists)?))
}

/// The least costly of `results`, the smallest transform among ties.
fn least_of(results: impl Iterator<Item = (f64, Alignment)>) -> Option<Alignment> {
    let results: Vec<(f64, Alignment)> = results.collect();
    let best_cost = results.iter().map(|r| r.0).fold(f64::INFINITY, f64::min);
    let size = |a: &Alignment| a.rotation_deg.abs() + a.translation_m[0].hypot(a.translation_m[1]);
    results
        .into_iter()
        .filter(|r| r.0 <= best_cost * (1.0 + TIE_FRACTION) + 1e-12)
        .map(|r| r.1)
        .min_by(|x, y| size(x).total_cmp(&size(y)))
}

/// `alignment` with its inlier share and RMS on `samples`.
fn with_inliers(samples: &[Point], plan: &FloorPlan, mut alignment: Alignment) -> Alignment {
    let inliers: Vec<f64> = samples
        .iter()
        .filter_map(|p| nearest_on_plan(&alignment.map_to_plan(p), plan))
        .map(|n| n.distance_m)
        .filter(|d| *d <= FINAL_GATE_M)
        .collect();
    alignment.inlier_fraction = inliers.len() as f64 / samples.len() as f64;
    alignment.inlier_rms_m = if inliers.is_empty() {
        0.0
    } else {
        (inliers.iter().map(|d| d * d).sum::<f64>() / inliers.len() as f64).sqrt()
    };
    alignment
}
