//! A beam model of the Polaroid 6500 (paper §2): which surfaces echo and at what range.
//!
//! `Specular`: the cone of `beam_width` is sampled by rays `ray_step` apart (both edges
//! included), plus the exact directions, when inside the cone, of each wall's normal, each
//! pillar's centre and each corner. A ray stops at the first surface it meets; it echoes when the
//! angle of incidence (between the ray and the surface normal) is at most the surface's
//! roughness, or when it hits within `corner_tolerance` of a concave corner (a corner reflector
//! returns sound whatever the angle). The range is the nearest echoing distance in the cone, so a
//! mirror-like wall echoes only when its normal lies within the cone, at the normal distance.
//! With bounces (`sim.bounces`), a ray a surface does not echo is mirrored on instead of
//! stopping, and the range is the whole path to the surface that echoes it (multipath); the
//! special directions are not taken again through a mirror, so a surface seen through one is
//! read by the sampling rays alone.
//! `Axis`: one ray on the beam axis, the first hit whatever the angle.

use crate::geometry::{ray_meets_segment_line, unit, Point, Pose, Vec2};
use crate::run::FloorPlan;
use serde::{Deserialize, Serialize};

/// Which echo model the simulator uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum Model {
    /// Beam cone, incidence limit, corner reflectors (the default).
    #[default]
    Specular,
    /// One ray on the axis, no incidence limit (a run simulated with it declares the sensor's
    /// echo model [`crate::sonar::EchoModel::Axis`]).
    Axis,
}

impl Model {
    /// Parses `specular` or `axis`.
    pub fn parse(name: &str) -> Option<Model> {
        match name {
            "specular" => Some(Model::Specular),
            "axis" => Some(Model::Axis),
            _ => None,
        }
    }
}

/// A corner where two walls meet: its point and the directions of the two walls leaving it.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Corner {
    point: Point,
    u1: Vec2,
    u2: Vec2,
}

impl Corner {
    /// True when `from` lies inside the corner's angle (< 180°): seen from there it is concave.
    fn is_concave_from(&self, from: &Point) -> bool {
        let cross = |a: &Vec2, b: &Vec2| a.x * b.y - a.y * b.x;
        let c12 = cross(&self.u1, &self.u2);
        if c12.abs() < 1e-9 {
            return false;
        }
        let v = from - self.point;
        cross(&self.u1, &v) * c12.signum() > 0.0 && cross(&v, &self.u2) * c12.signum() > 0.0
    }
}

/// The first surface a ray meets.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Distance from the ray's origin, metres.
    pub distance_m: f64,
    /// Where it hit.
    pub point: Point,
    /// Angle between the ray and the surface normal, radians in [0, π/2].
    pub incidence_rad: f64,
    /// The roughness of the surface hit, radians.
    pub roughness_rad: f64,
    /// The surface's unit normal there (either side).
    pub normal: Vec2,
}

/// The geometry the simulator casts rays against.
#[derive(Clone, Debug)]
pub struct World {
    plan: FloorPlan,
    default_roughness_rad: f64,
    corners: Vec<Corner>,
    corner_tolerance_m: f64,
}

/// Points closer than this are the same corner, metres.
const SAME_POINT_M: f64 = 1e-6;

impl World {
    /// A world of `plan`'s walls and pillars; walls without their own roughness (and pillars) use
    /// `default_roughness_rad`.
    pub fn new(plan: &FloorPlan, default_roughness_rad: f64, corner_tolerance_m: f64) -> Self {
        let mut corners = Vec::new();
        let walls = &plan.walls;
        for (i, wi) in walls.iter().enumerate() {
            for (p, q) in [(wi.a, wi.b), (wi.b, wi.a)] {
                let u1 = (q - p).try_normalize(0.0);
                let Some(u1) = u1 else { continue };
                for (j, wj) in walls.iter().enumerate() {
                    if i == j {
                        continue;
                    }
                    let e = wj.b - wj.a;
                    if (wj.a - p).norm() < SAME_POINT_M {
                        if i < j {
                            if let Some(u2) = e.try_normalize(0.0) {
                                corners.push(Corner { point: p, u1, u2 });
                            }
                        }
                    } else if (wj.b - p).norm() < SAME_POINT_M {
                        if i < j {
                            if let Some(u2) = (-e).try_normalize(0.0) {
                                corners.push(Corner { point: p, u1, u2 });
                            }
                        }
                    } else if let Some(u2) = e.try_normalize(0.0) {
                        // A T-junction: wall i ends on the inside of wall j: two corners.
                        let t = (p - wj.a).dot(&e) / e.norm_squared();
                        let off = (wj.a + e * t - p).norm();
                        if off < SAME_POINT_M && t > 0.0 && t < 1.0 {
                            corners.push(Corner { point: p, u1, u2 });
                            corners.push(Corner {
                                point: p,
                                u1,
                                u2: -u2,
                            });
                        }
                    }
                }
            }
        }
        Self {
            plan: plan.clone(),
            default_roughness_rad,
            corners,
            corner_tolerance_m,
        }
    }

    /// The first surface met by the ray from `origin` in direction `dir` (unit length).
    pub fn cast(&self, origin: &Point, dir: &Vec2) -> Option<Hit> {
        let mut best: Option<Hit> = None;
        let mut consider = |hit: Hit| {
            if best.is_none_or(|b| hit.distance_m < b.distance_m) {
                best = Some(hit);
            }
        };
        for w in &self.plan.walls {
            let Some((t, s)) = ray_meets_segment_line(origin, dir, &w.a, &w.b) else {
                continue;
            };
            if t > 1e-9 && (0.0..=1.0).contains(&s) {
                let e = w.b - w.a;
                let normal = Vec2::new(-e.y, e.x) / e.norm();
                consider(Hit {
                    distance_m: t,
                    point: origin + dir * t,
                    incidence_rad: dir.dot(&normal).abs().min(1.0).acos(),
                    roughness_rad: w.roughness_rad.unwrap_or(self.default_roughness_rad),
                    normal,
                });
            }
        }
        for c in &self.plan.circles {
            let oc = origin - c.centre;
            let b = oc.dot(dir);
            let disc = b * b - (oc.norm_squared() - c.radius_m * c.radius_m);
            if disc < 0.0 {
                continue;
            }
            let root = disc.sqrt();
            let t = if -b - root > 1e-9 {
                -b - root
            } else {
                -b + root
            };
            if t > 1e-9 {
                let point = origin + dir * t;
                let normal = (point - c.centre) / c.radius_m;
                consider(Hit {
                    distance_m: t,
                    point,
                    incidence_rad: dir.dot(&normal).abs().min(1.0).acos(),
                    roughness_rad: self.default_roughness_rad,
                    normal,
                });
            }
        }
        best
    }

    /// True when `hit`, reached from `origin`, is within the corner tolerance of a corner that is
    /// concave seen from `origin`.
    fn near_concave_corner(&self, origin: &Point, hit: &Hit) -> bool {
        self.corners.iter().any(|c| {
            (hit.point - c.point).norm() <= self.corner_tolerance_m && c.is_concave_from(origin)
        })
    }

    /// How far sound sent from `origin` along `dir` travels before a surface returns it, or
    /// `None`. A surface echoes when the ray meets it within its roughness of the normal, or near
    /// a concave corner; otherwise it mirrors the ray on, at most `bounces` times, and the echo
    /// of the last surface comes back the way the sound went (the multipath of a specular room,
    /// Kuc and Siegel 1987: the range read is the whole path, as if through the mirror).
    fn echo_along(&self, origin: &Point, dir: &Vec2, bounces: u32) -> Option<f64> {
        let (mut from, mut dir, mut travelled_m) = (*origin, *dir, 0.0);
        for left in (0..=bounces).rev() {
            let hit = self.cast(&from, &dir)?;
            travelled_m += hit.distance_m;
            if hit.incidence_rad <= hit.roughness_rad + 1e-9
                || self.near_concave_corner(&from, &hit)
            {
                return Some(travelled_m);
            }
            if left == 0 {
                break;
            }
            dir -= hit.normal * (2.0 * dir.dot(&hit.normal));
            from = hit.point;
        }
        None
    }

    /// The noise-free range a sonar at `sensor` (position and beam heading) reads, or `None`
    /// when nothing echoes (range limits are the caller's). With the specular model, a ray may
    /// be mirrored off `bounces` surfaces that do not echo it ([`World::echo_along`]).
    pub fn echo_range(
        &self,
        sensor: &Pose,
        beam_width_rad: f64,
        ray_step_rad: f64,
        model: Model,
        bounces: u32,
    ) -> Option<f64> {
        let origin = sensor.position();
        match model {
            Model::Axis => self
                .cast(&origin, &unit(sensor.heading_rad))
                .map(|h| h.distance_m),
            Model::Specular => {
                let half = beam_width_rad / 2.0;
                let mut offsets = Vec::new();
                let n = (beam_width_rad / ray_step_rad - 1e-9).ceil().max(1.0) as usize;
                for i in 0..=n {
                    offsets.push(-half + beam_width_rad * i as f64 / n as f64);
                }
                let mut special = |target_dir: Vec2| {
                    let angle = target_dir.y.atan2(target_dir.x) - sensor.heading_rad;
                    let off = (angle + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU)
                        - std::f64::consts::PI;
                    if off.abs() <= half {
                        offsets.push(off);
                    }
                };
                for w in &self.plan.walls {
                    let e = w.b - w.a;
                    let len2 = e.norm_squared();
                    if len2 <= 0.0 {
                        continue;
                    }
                    let t = (origin - w.a).dot(&e) / len2;
                    if (0.0..=1.0).contains(&t) {
                        special(w.a + e * t - origin);
                    }
                }
                for c in &self.plan.circles {
                    special(c.centre - origin);
                }
                for c in &self.corners {
                    special(c.point - origin);
                }
                let mut best: Option<f64> = None;
                for off in offsets {
                    let dir = unit(sensor.heading_rad + off);
                    let echo = self.echo_along(&origin, &dir, bounces);
                    if let Some(distance_m) = echo.filter(|&d| best.is_none_or(|b| d < b)) {
                        best = Some(distance_m);
                    }
                }
                best
            }
        }
    }
}
