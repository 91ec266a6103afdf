//! Questions asked of a built scene: its bounds, its legend, what is under the cursor.

use super::layer::{Layer, LayerSet};
use super::primitive::{Primitive, SceneId, Shape};
use super::style::{Glyph, Role, Style};
use super::Scene;
use crate::geometry::{distance_to_segment, unit, Point};

/// An axis-aligned rectangle in world coordinates (metres).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ViewRect {
    /// Lower-left corner (smallest x and y).
    pub min: Point,
    /// Upper-right corner (largest x and y).
    pub max: Point,
}

impl ViewRect {
    /// The rectangle spanned by two corners in any order.
    pub fn new(a: Point, b: Point) -> Self {
        ViewRect {
            min: Point::new(a.x.min(b.x), a.y.min(b.y)),
            max: Point::new(a.x.max(b.x), a.y.max(b.y)),
        }
    }

    /// Width, metres.
    pub fn width_m(&self) -> f64 {
        self.max.x - self.min.x
    }

    /// Height, metres.
    pub fn height_m(&self) -> f64 {
        self.max.y - self.min.y
    }

    /// The rectangle grown by `margin_m` on every side.
    pub fn expanded(&self, margin_m: f64) -> Self {
        let d = crate::geometry::Vec2::new(margin_m, margin_m);
        ViewRect {
            min: self.min - d,
            max: self.max + d,
        }
    }

    /// True when `p` lies inside (boundary included).
    pub fn contains(&self, p: &Point) -> bool {
        p.x >= self.min.x && p.x <= self.max.x && p.y >= self.min.y && p.y <= self.max.y
    }

    /// `rect` widened to take in `p` (the box of `p` alone when there is none yet).
    pub(super) fn grow(rect: &mut Option<ViewRect>, p: &Point) {
        match rect {
            Some(r) => r.include(p),
            None => *rect = Some(ViewRect { min: *p, max: *p }),
        }
    }

    pub(super) fn include(&mut self, p: &Point) {
        self.min = Point::new(self.min.x.min(p.x), self.min.y.min(p.y));
        self.max = Point::new(self.max.x.max(p.x), self.max.y.max(p.y));
    }
}

/// One line of a legend: what a style means.
#[derive(Clone, Debug, PartialEq)]
pub struct LegendEntry {
    /// The layer the entry belongs to.
    pub layer: Layer,
    /// The role it explains.
    pub role: Role,
    /// Its text.
    pub label: &'static str,
    /// The style of the first primitive of this role in the scene.
    pub style: Style,
    /// How to draw the sample.
    pub glyph: Glyph,
}

impl Scene {
    /// Bounding box of every primitive (texts and markers count by their anchor);
    /// `None` for an empty scene.
    pub fn bounds(&self) -> Option<ViewRect> {
        self.bounds_of(LayerSet::all())
    }

    /// Bounding box of the primitives of `layers` only (e.g. without beams and discarded
    /// readings, which may reach far beyond the map); `None` when they hold nothing.
    pub fn bounds_of(&self, layers: LayerSet) -> Option<ViewRect> {
        let mut rect: Option<ViewRect> = None;
        let drawn = (self.primitives.iter())
            .filter(|p| layers.contains(p.layer))
            .map(primitive_bounds);
        let culled = (self.culled.iter())
            .filter(|(l, _)| layers.contains(*l))
            .map(|(_, r)| *r);
        for b in drawn.chain(culled) {
            ViewRect::grow(&mut rect, &b.min);
            ViewRect::grow(&mut rect, &b.max);
        }
        rect
    }

    /// The scene less the primitives entirely outside `view`: what a figure of `view` draws
    /// (so its legend lists only that).
    pub fn within(&self, view: ViewRect) -> Scene {
        let meets = |b: ViewRect| {
            b.min.x <= view.max.x
                && view.min.x <= b.max.x
                && b.min.y <= view.max.y
                && view.min.y <= b.max.y
        };
        Scene {
            title: self.title.clone(),
            primitives: (self.primitives.iter())
                .filter(|p| meets(primitive_bounds(p)))
                .cloned()
                .collect(),
            culled: Vec::new(),
        }
    }

    /// The legend: one entry per role present (roles without a legend text left out), in
    /// role order. Only what the scene actually draws is listed.
    pub fn legend(&self) -> Vec<LegendEntry> {
        let mut first: Vec<Option<&Primitive>> = vec![None; Role::Label as usize + 1];
        for p in &self.primitives {
            let slot = &mut first[p.role as usize];
            if slot.is_none() {
                *slot = Some(p);
            }
        }
        first
            .into_iter()
            .flatten()
            .filter_map(|p| {
                Some(LegendEntry {
                    layer: p.layer,
                    role: p.role,
                    label: p.role.legend_label()?,
                    style: p.style,
                    glyph: p.role.glyph(),
                })
            })
            .collect()
    }

    /// The id of the primitive nearest to `point_in_world`, within `tolerance_m`; primitives
    /// without an id are skipped. Lines, outlines and markers win over the insides of filled
    /// areas (a ball or beam counts as `0.9·tolerance` away when the point is inside it); on
    /// equal distance the primitive drawn last (on top) wins.
    pub fn hit(&self, point_in_world: Point, tolerance_m: f64) -> Option<SceneId> {
        let mut best: Option<(f64, SceneId)> = None;
        for prim in &self.primitives {
            if prim.id == SceneId::None {
                continue;
            }
            let d = distance(prim, &point_in_world, tolerance_m);
            if d <= tolerance_m && best.is_none_or(|(bd, _)| d <= bd) {
                best = Some((d, prim.id));
            }
        }
        best.map(|(_, id)| id)
    }
}

fn distance(prim: &Primitive, p: &Point, tolerance_m: f64) -> f64 {
    let inside = 0.9 * tolerance_m;
    let filled = prim.style.fill.is_some();
    match &prim.shape {
        Shape::Circle { centre, radius_m } => {
            let d = (p - centre).norm();
            let to_outline = (d - radius_m).abs();
            if d < *radius_m && filled {
                to_outline.min(inside)
            } else {
                to_outline
            }
        }
        Shape::Segment { a, b } => distance_to_segment(p, a, b),
        Shape::Polyline { points, closed } => {
            let mut d = f64::INFINITY;
            for w in points.windows(2) {
                d = d.min(distance_to_segment(p, &w[0], &w[1]));
            }
            if *closed && points.len() > 2 {
                d = d.min(distance_to_segment(
                    p,
                    &points[points.len() - 1],
                    &points[0],
                ));
            }
            if points.len() == 1 {
                d = (p - points[0]).norm();
            }
            d
        }
        Shape::Wedge {
            apex,
            heading_rad,
            half_angle_rad,
            radius_m,
        } => {
            let v = p - apex;
            let r = v.norm();
            let angle = (v.y.atan2(v.x) - heading_rad + std::f64::consts::PI)
                .rem_euclid(std::f64::consts::TAU)
                - std::f64::consts::PI;
            if r <= *radius_m && angle.abs() <= *half_angle_rad {
                inside
            } else {
                f64::INFINITY
            }
        }
        Shape::Text { anchor, .. } => (p - anchor).norm(),
        Shape::Marker { at, .. } => (p - at).norm(),
    }
}

/// The world rectangle a primitive covers (a text or marker: its anchor).
fn primitive_bounds(prim: &Primitive) -> ViewRect {
    let mut r: Option<ViewRect> = None;
    let mut add = |p: Point| ViewRect::grow(&mut r, &p);
    match &prim.shape {
        Shape::Circle { centre, radius_m } => {
            add(Point::new(centre.x - radius_m, centre.y - radius_m));
            add(Point::new(centre.x + radius_m, centre.y + radius_m));
        }
        Shape::Segment { a, b } => {
            add(*a);
            add(*b);
        }
        Shape::Polyline { points, .. } => points.iter().for_each(|p| add(*p)),
        Shape::Wedge {
            apex,
            heading_rad,
            half_angle_rad,
            radius_m,
        } => {
            add(*apex);
            for i in 0..=4 {
                let angle = heading_rad - half_angle_rad + half_angle_rad * 0.5 * i as f64;
                add(apex + unit(angle) * *radius_m);
            }
        }
        Shape::Text { anchor, .. } => add(*anchor),
        Shape::Marker { at, .. } => add(*at),
    }
    r.unwrap_or(ViewRect {
        min: Point::origin(),
        max: Point::origin(),
    })
}
