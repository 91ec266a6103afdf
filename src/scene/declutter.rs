//! Level of detail for marks that pile up: a screen-space grid where each cell takes one mark,
//! so end-point dots and labels that would land on top of each other at the current zoom are
//! drawn once (as a viewer sees them), and a map of tens of thousands of segments stays cheap
//! to draw when zoomed out.

use super::primitive::TextAlign;
use crate::geometry::Point;
use rustc_hash::{FxHashMap, FxHashSet};

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

    /// The cell of `p` (`None` without a view: no culling).
    pub fn cell(&self, p: &Point) -> Option<(i64, i64)> {
        let (w, h) = self.cell_m?;
        Some((floor_i64(p.x / w), floor_i64(p.y / h)))
    }

    /// True, and the pair of cells taken, when no line between the cells of `a` and `b`
    /// (either way round) is drawn yet: copies of a segment closer than a cell coincide.
    pub fn claim_line(&mut self, a: &Point, b: &Point) -> bool {
        self.claim_cells(self.cell(a), self.cell(b))
    }

    /// [`Declutter::claim_line`] with the cells of the ends found already (by
    /// [`Declutter::cell`]: a polyline's points each end two lines).
    pub fn claim_cells(&mut self, a: Option<(i64, i64)>, b: Option<(i64, i64)>) -> bool {
        let (Some(ca), Some(cb)) = (a, b) else {
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

/// `v.floor() as i64` (saturating; NaN gives 0) without a call into the C library: x86-64's
/// baseline has no rounding instruction, and a scene takes a few cells for each of the
/// hundreds of thousands of segments of a long `paper` run. Truncation, one less when that
/// went up (below zero, something cut off).
fn floor_i64(v: f64) -> i64 {
    let t = v as i64;
    if t as f64 > v {
        t.saturating_sub(1)
    } else {
        t
    }
}

/// Average advance of a label character, in ems: an upper bound for the digits and lower-case
/// letters of labels in DejaVu Sans (the widest of the fonts the SVG names; digits advance
/// 0.636 em) and in egui's font, so a box never understates the text drawn.
const CHAR_ADVANCE_EM: f64 = 0.66;
/// Above and below the baseline, in ems (DejaVu Sans: ascender 0.93, descender 0.24).
const ASCENT_EM: f64 = 0.95;
const DESCENT_EM: f64 = 0.25;
/// The halo drawn around texts (half its 3-pixel stroke), pixels.
const HALO_PX: f64 = 1.5;

/// The box a text of `chars` characters covers on screen, pixels relative to its anchor (x
/// right, y down), as the renderers place it: `offset_px` moves the baseline's reference point
/// right and up, `align` says which end of the text sits there. `[x0, y0, x1, y1]`.
pub fn text_box_px(chars: usize, size_px: f32, offset_px: [f32; 2], align: TextAlign) -> [f64; 4] {
    let size = f64::from(size_px);
    let width = CHAR_ADVANCE_EM * size * chars as f64;
    let x = f64::from(offset_px[0]);
    let baseline = -f64::from(offset_px[1]);
    let x0 = match align {
        TextAlign::Start => x,
        TextAlign::Middle => x - 0.5 * width,
        TextAlign::End => x - width,
    };
    [
        x0 - HALO_PX,
        baseline - ASCENT_EM * size - HALO_PX,
        x0 + width + HALO_PX,
        baseline + DESCENT_EM * size + HALO_PX,
    ]
}

/// The texts placed so far, as world boxes at one zoom: a text is placed only where its box
/// overlaps none of theirs, so labels never pile up (on screen and in an export alike).
pub struct TextBoxes {
    world_per_px: f64,
    /// Side of the buckets the boxes are filed under, metres.
    cell_m: f64,
    boxes: FxHashMap<(i64, i64), Vec<[f64; 4]>>,
}

impl TextBoxes {
    /// Boxes for a view of `world_per_px` metres per pixel (0: off, every text is placed).
    pub fn new(world_per_px: f64) -> Self {
        let on = world_per_px > 0.0 && world_per_px.is_finite();
        TextBoxes {
            world_per_px: if on { world_per_px } else { 0.0 },
            cell_m: world_per_px * 64.0,
            boxes: FxHashMap::default(),
        }
    }

    /// True, and the box of a text of `chars` characters taken, when it overlaps no box placed
    /// before (the text itself need not be made unless it is placed).
    pub fn claim(
        &mut self,
        anchor: &Point,
        chars: usize,
        size_px: f32,
        offset_px: [f32; 2],
        align: TextAlign,
    ) -> bool {
        if self.world_per_px == 0.0 {
            return true;
        }
        let [x0, y0, x1, y1] = text_box_px(chars, size_px, offset_px, align);
        let w = self.world_per_px;
        // Screen y runs down, world y up.
        let b = [
            anchor.x + x0 * w,
            anchor.y - y1 * w,
            anchor.x + x1 * w,
            anchor.y - y0 * w,
        ];
        let cell = |v: f64| floor_i64(v / self.cell_m);
        let (cx0, cy0, cx1, cy1) = (cell(b[0]), cell(b[1]), cell(b[2]), cell(b[3]));
        for cx in cx0..=cx1 {
            for cy in cy0..=cy1 {
                let overlaps = self.boxes.get(&(cx, cy)).is_some_and(|list| {
                    list.iter()
                        .any(|o| b[0] < o[2] && o[0] < b[2] && b[1] < o[3] && o[1] < b[3])
                });
                if overlaps {
                    return false;
                }
            }
        }
        for cx in cx0..=cx1 {
            for cy in cy0..=cy1 {
                self.boxes.entry((cx, cy)).or_default().push(b);
            }
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_text_whose_box_overlaps_a_placed_one_is_refused_and_one_beside_it_is_placed() {
        // 1 cm per pixel; "s12" at 11 px is about 22 px wide and 13 px high.
        let mut t = TextBoxes::new(0.01);
        let a = Point::new(0.0, 0.0);
        assert!(t.claim(&a, 3, 11.0, [4.0, 4.0], TextAlign::Start));
        // 10 px to the right: overlaps.
        assert!(!t.claim(
            &Point::new(0.10, 0.0),
            3,
            11.0,
            [4.0, 4.0],
            TextAlign::Start
        ));
        // 40 px to the right, or 20 px up: clear.
        assert!(t.claim(
            &Point::new(0.40, 0.0),
            3,
            11.0,
            [4.0, 4.0],
            TextAlign::Start
        ));
        assert!(t.claim(
            &Point::new(0.0, 0.20),
            3,
            11.0,
            [4.0, 4.0],
            TextAlign::Start
        ));
        // Without a view every text is placed.
        let mut off = TextBoxes::new(0.0);
        assert!(off.claim(&a, 2, 11.0, [0.0, 0.0], TextAlign::Start));
        assert!(off.claim(&a, 2, 11.0, [0.0, 0.0], TextAlign::Start));
    }

    #[test]
    fn floor_i64_is_floor_then_a_saturating_cast() {
        let edges = [
            0.0,
            -0.0,
            0.5,
            -0.5,
            1.0,
            -1.0,
            -1.5,
            2.0f64.powi(52) + 0.5,
            -(2.0f64.powi(52) + 0.5),
            2.0f64.powi(53) + 2.0,
            -(2.0f64.powi(63)),
            2.0f64.powi(63),
            -(2.0f64.powi(64)),
            1e300,
            -1e300,
            f64::MIN_POSITIVE,
            -f64::MIN_POSITIVE,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
        ];
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let random = (0..10_000).map(|_| {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1);
            f64::from_bits(state)
        });
        for v in edges.into_iter().chain(random) {
            assert_eq!(floor_i64(v), v.floor() as i64, "{v:e}");
        }
    }

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
