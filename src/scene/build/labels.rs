//! Texts: every label placed where it covers no other, and the labels layer.

use super::{mid, Builder};
use crate::geometry::Point;
use crate::mapping::SegmentId;
use crate::scene::layer::Layer;
use crate::scene::primitive::{SceneId, Shape, TextAlign};
use crate::scene::style::Role;

impl Builder<'_, '_> {
    /// A text of role [`Role::Label`] of `chars` characters, unless it would cover a text
    /// placed before: `text` makes it only when it is placed.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn push_text(
        &mut self,
        layer: Layer,
        id: SceneId,
        anchor: Point,
        chars: usize,
        text: impl FnOnce() -> String,
        offset_px: [f32; 2],
        align: TextAlign,
    ) {
        let size_px = Role::Label.style().marker_size_px;
        if self.texts.claim(&anchor, chars, size_px, offset_px, align) {
            let shape = Shape::Text {
                anchor,
                text: text(),
                offset_px,
                align,
            };
            self.push(layer, Role::Label, id, shape);
        }
    }

    /// The labels: this step's new segments, then the map's (the selection first).
    pub(super) fn labels(&mut self) {
        // This step's new segments first: they are what the step is about.
        for (i, n) in self.input.step.new_segments.iter().enumerate() {
            let anchor = mid(&n.a.point, &n.b.point);
            let text = format!("n{i}");
            self.push_text(
                Layer::Labels,
                SceneId::NewSegment(i),
                anchor,
                text.chars().count(),
                || text,
                [-4.0, -14.0],
                TextAlign::End,
            );
        }
        let min_len_m = self.px(12.0);
        let input = self.input;
        let met = |id: SegmentId| {
            input.support_of == Some(id)
                || input
                    .step
                    .decisions
                    .iter()
                    .any(|d| d.existing == Some(id) || d.result == Some(id))
        };
        // The selection first, then the map in order; a label that would cover another is
        // left out (overlapping labels cannot be read).
        let map_lines = self.take_map_lines();
        let selected = input
            .support_of
            .and_then(|id| map_lines.binary_search_by_key(&id, |s| s.id).ok());
        let order = selected
            .into_iter()
            .chain((0..map_lines.len()).filter(|&i| Some(map_lines[i].id) != input.support_of));
        for s in order.map(|i| &map_lines[i]) {
            if s.length() < min_len_m
                || (input.figure_labels && !met(s.id))
                || !self.shows(Layer::Labels, &s.a, &s.b)
            {
                continue;
            }
            // "s" and the id's decimal digits.
            let chars = 2 + s.id.checked_ilog10().unwrap_or(0) as usize;
            self.push_text(
                Layer::Labels,
                SceneId::MapSegment(s.id),
                mid(&s.a, &s.b),
                chars,
                || format!("s{}", s.id),
                [4.0, 4.0],
                TextAlign::Start,
            );
        }
        self.map_lines = Some(map_lines);
    }
}
