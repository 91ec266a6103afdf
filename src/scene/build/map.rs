//! The map's layers: the floor plan, the map before and after the step, its point features,
//! the truth verdicts and the supporting readings of the selection.

use super::{Builder, MapLine};
use crate::mapping::model::map::FeatureKind;
use crate::mapping::SegmentKind;
use crate::scene::declutter::Declutter;
use crate::scene::layer::Layer;
use crate::scene::marker::MarkerShape;
use crate::scene::primitive::{SceneId, Shape};
use crate::scene::style::Role;

impl Builder<'_, '_> {
    /// The floor plan: its walls and pillars.
    pub(super) fn floor_plan(&mut self) {
        let Some(plan) = &self.input.run.floor_plan else {
            return;
        };
        for w in &plan.walls {
            self.push(
                Layer::FloorPlan,
                Role::FloorPlan,
                SceneId::FloorPlan,
                Shape::Segment { a: w.a, b: w.b },
            );
        }
        for c in &plan.circles {
            let shape = Shape::Circle {
                centre: c.centre,
                radius_m: c.radius_m,
            };
            self.push(Layer::FloorPlan, Role::FloorPlan, SceneId::FloorPlan, shape);
        }
    }

    /// The map before the step (with the map layer on, only what the step changed).
    pub(super) fn map_before(&mut self) {
        // Under the map after the step, an unchanged segment is hidden by itself: with the map
        // layer on, only what the step moved or removed is drawn. Both maps list their
        // segments by id and share the unchanged ones, so one walk finds what changed.
        let only_changed = self.options.layers.contains(Layer::Map);
        let after = &self.input.map_after.segments;
        let mut j = 0;
        for s in &self.input.map_before.segments {
            // The very segment at the walk's place in the map after is unchanged, known so
            // without fetching either from memory; only a view rectangle needs where it lies
            // (for the culled box).
            if only_changed && after.get(j).is_some_and(|t| std::sync::Arc::ptr_eq(t, s)) {
                j += 1;
                if self.options.visible_m.is_some() {
                    self.shows(Layer::MapBefore, &s.a.point, &s.b.point);
                }
                continue;
            }
            if !self.shows(Layer::MapBefore, &s.a.point, &s.b.point) {
                continue;
            }
            if only_changed {
                while j < after.len() && after[j].id < s.id {
                    j += 1;
                }
                let same = after.get(j).is_some_and(|t| {
                    t.id == s.id
                        && (std::sync::Arc::ptr_eq(t, s)
                            || (t.a.point == s.a.point && t.b.point == s.b.point))
                });
                if same {
                    continue;
                }
            }
            let shape = Shape::Segment {
                a: s.a.point,
                b: s.b.point,
            };
            self.push(
                Layer::MapBefore,
                Role::MapBefore,
                SceneId::MapSegment(s.id),
                shape,
            );
        }
    }

    /// The map's point features (docs/algorithm.md §8.5): a triangle a corner, a diamond an
    /// edge, a circle at its radius a pillar (§8.14).
    pub(super) fn features(&mut self) {
        for f in self.input.map_after.confirmed_features() {
            if f.radius_m > 0.0 {
                self.push(
                    Layer::Features,
                    Role::FeaturePillar,
                    SceneId::None,
                    Shape::Circle {
                        centre: f.at,
                        radius_m: f.radius_m,
                    },
                );
                continue;
            }
            let (role, shape) = match f.kind {
                FeatureKind::Corner => (Role::FeatureCorner, MarkerShape::Triangle),
                FeatureKind::Edge => (Role::FeatureEdge, MarkerShape::Diamond),
            };
            self.push(
                Layer::Features,
                role,
                SceneId::None,
                Shape::Marker { at: f.at, shape },
            );
        }
    }

    /// The map after the step, with the end-points of fitted segments.
    pub(super) fn map_after(&mut self) {
        let min_len_m = self.px(6.0);
        // End-point dots in a 3 px cell that already has one add nothing at this zoom.
        let mut dots = Declutter::new(self.options.world_per_px, 3.0, 3.0);
        // A segment whose ends fall within 2 px of one already drawn looks the same.
        let mut lines = Declutter::new(self.options.world_per_px, 2.0, 2.0);
        let map_lines = self.take_map_lines();
        for s in &map_lines {
            if !self.shows(Layer::Map, &s.a, &s.b) || !lines.claim_line(&s.a, &s.b) {
                continue;
            }
            let id = SceneId::MapSegment(s.id);
            let role = match s.kind {
                SegmentKind::Fitted if self.input.map_after.is_tentative(s.id) => {
                    Role::MapTentative
                }
                SegmentKind::Fitted => Role::MapFitted,
                SegmentKind::Interpolated => Role::MapInterpolated,
            };
            self.push(Layer::Map, role, id, Shape::Segment { a: s.a, b: s.b });
            if s.kind == SegmentKind::Fitted && s.length() >= min_len_m {
                for at in [s.a, s.b] {
                    if !dots.claim(&at) {
                        continue;
                    }
                    self.push(
                        Layer::Map,
                        Role::MapEndPoint,
                        id,
                        Shape::Marker {
                            at,
                            shape: MarkerShape::Dot,
                        },
                    );
                }
            }
        }
        self.map_lines = Some(map_lines);
    }

    /// The lines of the map after the step (gathered by the first layer to ask; a layer puts
    /// them back in `map_lines` when it is done with them).
    pub(super) fn take_map_lines(&mut self) -> Vec<MapLine> {
        self.map_lines.take().unwrap_or_else(|| {
            let segments = &self.input.map_after.segments;
            segments
                .iter()
                .map(|s| MapLine {
                    id: s.id,
                    kind: s.kind,
                    a: s.a.point,
                    b: s.b.point,
                })
                .collect()
        })
    }

    /// The supporting readings of the segment asked for, each marked where it was read.
    pub(super) fn support_points(&mut self) {
        let Some(id) = self.input.support_of else {
            return;
        };
        let seg = self
            .input
            .map_after
            .segment(id)
            .or_else(|| self.input.map_before.segment(id));
        let Some(seg) = seg else {
            return;
        };
        for q in seg.points.iter() {
            let reading = SceneId::Reading {
                snapshot: q.reading.snapshot(),
                sensor: q.reading.sensor(),
            };
            let shape = Shape::Marker {
                at: q.point,
                shape: MarkerShape::Ring,
            };
            self.push(Layer::Map, Role::SupportPoint, reading, shape);
        }
    }

    /// `eval`'s verdict on each fitted segment of the map after the step.
    pub(super) fn truth(&mut self) {
        let Some(truth) = self.input.truth else {
            return;
        };
        for (id, verdict) in truth {
            let Some(s) = self.input.map_after.segment(*id) else {
                continue;
            };
            if !self.shows(Layer::Truth, &s.a.point, &s.b.point) {
                continue;
            }
            let role = if verdict.is_true() {
                Role::TruthTrue
            } else {
                Role::TruthSpurious
            };
            let shape = Shape::Segment {
                a: s.a.point,
                b: s.b.point,
            };
            self.push(Layer::Truth, role, SceneId::MapSegment(*id), shape);
        }
    }
}
