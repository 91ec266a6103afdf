//! The layers of what this step decided: the updates of map segments, the matching
//! decisions and the correlations.

use super::{mid, Builder};
use crate::geometry::{lerp, projection_param};
use crate::mapping::model::trace::CorrelationKind;
use crate::mapping::Outcome;
use crate::scene::layer::Layer;
use crate::scene::marker::MarkerShape;
use crate::scene::primitive::{SceneId, Shape};
use crate::scene::style::{decision_marker, Role};

impl Builder<'_, '_> {
    /// The map segments this step updated: after, before, merged duplicates, projections.
    pub(super) fn updates(&mut self) {
        for u in &self.input.step.updates {
            let id = SceneId::Update(u.segment);
            let after = Shape::Segment {
                a: u.after[0].point,
                b: u.after[1].point,
            };
            self.push(Layer::Updates, Role::UpdateAfter, id, after);
            let before = Shape::Segment {
                a: u.before[0].point,
                b: u.before[1].point,
            };
            self.push(Layer::Updates, Role::UpdateBefore, id, before);
            // Duplicates merged into it: their old geometry, ghosted like the segment's own.
            for absorbed in &u.absorbed {
                let shape = Shape::Segment {
                    a: absorbed.ends[0].point,
                    b: absorbed.ends[1].point,
                };
                let id = SceneId::Update(absorbed.into);
                self.push(Layer::Updates, Role::UpdateBefore, id, shape);
            }
            for f in &u.fates {
                if let Some(p) = f.projection {
                    let shape = Shape::Segment {
                        a: f.before.point,
                        b: p,
                    };
                    self.push(Layer::Updates, Role::UpdateProjection, id, shape);
                }
            }
        }
    }

    /// Each decision: a link to every candidate tested, and the outcome on the new segment.
    pub(super) fn decisions(&mut self) {
        let step = self.input.step;
        for d in &step.decisions {
            let Some(n) = step.new_segments.get(d.new_segment) else {
                continue;
            };
            let from = mid(&n.a.point, &n.b.point);
            let decided = outcome_role(d.outcome);
            for c in &d.mpc_stage {
                let existing = c.evaluation.existing;
                let seg = self
                    .input
                    .map_before
                    .segment(existing)
                    .or_else(|| self.input.map_after.segment(existing));
                let Some(seg) = seg else { continue };
                let t = projection_param(&from, &seg.a.point, &seg.b.point).clamp(0.0, 1.0);
                let to = lerp(&seg.a.point, &seg.b.point, t);
                let role = match d.outcome {
                    Outcome::Match | Outcome::Extension | Outcome::Dismissed
                        if d.existing == Some(existing) =>
                    {
                        decided
                    }
                    _ => Role::DecisionFailed,
                };
                let id = SceneId::Decision {
                    new_segment: d.new_segment,
                    existing: Some(existing),
                };
                self.push(
                    Layer::Decisions,
                    role,
                    id,
                    Shape::Segment { a: from, b: to },
                );
                self.push(
                    Layer::Decisions,
                    role,
                    id,
                    Shape::Marker {
                        at: to,
                        shape: decision_marker(role),
                    },
                );
            }
            let id = SceneId::Decision {
                new_segment: d.new_segment,
                existing: None,
            };
            self.push(
                Layer::Decisions,
                decided,
                id,
                Shape::Marker {
                    at: from,
                    shape: decision_marker(decided),
                },
            );
        }
    }

    /// The correlations of this step: corners, shared points, interpolated links.
    pub(super) fn correlations(&mut self) {
        for (i, c) in self.input.step.correlations.iter().enumerate() {
            let id = SceneId::Correlation(i);
            match c.result {
                CorrelationKind::Corner { point } | CorrelationKind::Shared { point } => {
                    let shape = match c.result {
                        CorrelationKind::Shared { .. } => MarkerShape::Diamond,
                        _ => MarkerShape::Square,
                    };
                    self.push(
                        Layer::Correlations,
                        Role::Corner,
                        id,
                        Shape::Marker { at: point, shape },
                    );
                }
                CorrelationKind::Interpolated { link, .. } => {
                    let Some(s) = self.input.map_after.segment(link) else {
                        continue;
                    };
                    let shape = Shape::Segment {
                        a: s.a.point,
                        b: s.b.point,
                    };
                    self.push(Layer::Correlations, Role::MapInterpolated, id, shape);
                }
                CorrelationKind::None => {}
            }
        }
    }
}

/// The decision role of an outcome.
fn outcome_role(outcome: Outcome) -> Role {
    match outcome {
        Outcome::Match => Role::DecisionMatch,
        Outcome::Extension => Role::DecisionExtension,
        Outcome::Dismissed => Role::DecisionDismissed,
        Outcome::NewFace => Role::DecisionNewFace,
    }
}
