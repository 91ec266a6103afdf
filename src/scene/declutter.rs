//! Level of detail for marks that pile up: a screen-space grid where each cell takes one mark,
//! so end-point dots and labels that would land on top of each other at the current zoom are
//! drawn once (as a viewer sees them), and a map of tens of thousands of segments stays cheap
//! to draw when zoomed out.

use crate::geometry::Point;
use rustc_hash::FxHashSet;

/// Cells of `width_px × height_px` screen pixels over the world.
pub struct Declutter {
    /// World size of a cell, metres; `None`: no culling (every claim succeeds).
    cell_m: Option<(f64, f64)>,
    taken: FxHashSet<(i64, i64)>,
    taken_pairs: FxHashSet<[(i64, i64); 2]>,
}

impl Declutter {
    /// A grid for a view of `world_per_px` metres per pixel (0: off).
    pub fn new(world_per_px: f64, width_px: f64, height_px: f64) -> Self {
        let on = world_per_px > 0.0 && world_per_px.is_finite();
        Self {
            cell_m: on.then_some((world_per_px * width_px, world_per_px * height_px)),
            taken: FxHashSet::default(),
            taken_pairs: FxHashSet::default(),
        }
    }

    fn cell(&self, p: &Point) -> Option<(i64, i64)> {
        let (w, h) = self.cell_m?;
        Some(((p.x / w).floor() as i64, (p.y / h).floor() as i64))
    }

    /// True, and the pair of cells taken, when no line between the cells of `a` and `b`
    /// (either way round) is drawn yet: copies of a segment closer than a cell coincide.
    pub fn claim_line(&mut self, a: &Point, b: &Point) -> bool {
        let (Some(ca), Some(cb)) = (self.cell(a), self.cell(b)) else {
            return true;
        };
        self.taken_pairs
            .insert(if ca <= cb { [ca, cb] } else { [cb, ca] })
    }

    /// True, and the cell of `p` taken, when no mark holds it yet.
    pub fn claim(&mut self, p: &Point) -> bool {
        match self.cell(p) {
            Some(cell) => self.taken.insert(cell),
            None => true,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_mark_per_cell_when_zoomed_out_and_every_mark_without_a_view() {
        // 1 cm per pixel, 4-pixel cells: marks 1 cm apart share a cell, 5 cm apart do not.
        let mut d = Declutter::new(0.01, 4.0, 4.0);
        assert!(d.claim(&Point::new(0.001, 0.001)));
        assert!(!d.claim(&Point::new(0.011, 0.001)));
        assert!(d.claim(&Point::new(0.051, 0.001)));
        let mut all = Declutter::new(0.0, 4.0, 4.0);
        assert!(all.claim(&Point::new(0.0, 0.0)) && all.claim(&Point::new(0.0, 0.0)));
        // Lines: a copy 1 cm off (either direction) is the same line; one 1 m long is not.
        let (a, b) = (Point::new(0.0, 0.0), Point::new(0.5, 0.0));
        assert!(d.claim_line(&a, &b));
        assert!(!d.claim_line(&Point::new(0.51, 0.01), &Point::new(0.01, 0.01)));
        assert!(d.claim_line(&a, &Point::new(1.0, 0.0)));
        assert!(all.claim_line(&a, &b) && all.claim_line(&a, &b));
    }
}
