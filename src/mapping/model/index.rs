//! A uniform grid over map segments for candidate search (docs/algorithm.md §4 allows pruning by a
//! bound that provably fails a test). Segments are filed under every cell their bounding box
//! touches; a query returns the segments filed under the cells the query box touches whose own
//! bounding box meets the query box, so it never misses one.

use crate::geometry::Point;
use crate::mapping::model::cell_table::{Cell, CellTable};
use crate::mapping::model::ids::{FaceId, SegmentId};
use crate::mapping::model::support::EndPoint;

/// Cell edge, metres.
const CELL_M: f64 = 1.0;
/// A segment spanning more cells than this a side is kept in a list every query returns.
const MAX_SPAN_CELLS: i64 = 256;

/// What the grid keeps of a segment: enough for a candidate search to go without reaching for
/// the segment itself (its end-points, face and kind never change without a new filing).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IndexedSegment {
    /// First end-point.
    pub a: EndPoint,
    /// Second end-point.
    pub b: EndPoint,
    /// Its face.
    pub face: FaceId,
    /// Fitted from readings (not a link made by correlation).
    pub fitted: bool,
}

/// Where a segment is filed.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Place {
    /// Under every cell of this cell box `[x0, y0, x1, y1]`.
    Cells([i64; 4]),
    /// In the oversize list.
    Oversize,
}

#[derive(Clone, Copy, Debug, PartialEq)]
struct Filing {
    place: Place,
    /// The segment's bounding box `[min x, min y, max x, max y]`, metres.
    world: [f64; 4],
    segment: IndexedSegment,
}

/// A segment as one cell lists it: enough to pass over it without reading its filing.
#[derive(Clone, Copy, Debug, PartialEq)]
struct CellEntry {
    id: SegmentId,
    /// The cell is in the first column / first row of the segment's cell box.
    first_column: bool,
    first_row: bool,
    /// The segment's bounding box rounded outwards to `f32` (a box that contains the exact
    /// one, so a test against it never rejects a segment the exact test keeps).
    world: [f32; 4],
}

/// `v` as an `f32` no greater than it (no less with `up`).
fn f32_outward(v: f64, up: bool) -> f32 {
    let r = v as f32;
    match (f64::from(r) < v, f64::from(r) > v) {
        (true, _) if up => r.next_up(),
        (_, true) if !up => r.next_down(),
        _ => r,
    }
}

/// Segments filed by grid cell.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SegmentGrid {
    cells: CellTable<CellEntry>,
    /// Filing of each segment, indexed by id (ids are dense and never reused).
    filings: Vec<Option<Filing>>,
    filed: usize,
    oversize: Vec<SegmentId>,
}

fn cell_of(v: f64) -> i64 {
    const LIMIT: f64 = (i64::MAX / 4) as f64;
    let v = v / CELL_M;
    if v.abs() < LIMIT {
        // `floor` without the library call (x86-64's baseline has no rounding instruction):
        // truncation, one less below zero off the integers.
        let t = v as i64;
        t - i64::from((t as f64) > v)
    } else if v.is_finite() {
        v.clamp(-LIMIT, LIMIT) as i64
    } else {
        0
    }
}

fn cell_box(min: &Point, max: &Point) -> Option<[i64; 4]> {
    let b = [
        cell_of(min.x),
        cell_of(min.y),
        cell_of(max.x),
        cell_of(max.y),
    ];
    let finite = [min.x, min.y, max.x, max.y].iter().all(|v| v.is_finite());
    (finite && b[2] - b[0] <= MAX_SPAN_CELLS && b[3] - b[1] <= MAX_SPAN_CELLS).then_some(b)
}

/// Where segment `segment` goes: its filing, and the cell entries it adds (cell and entry),
/// passed to `file` in cell order.
fn file_segment(
    id: SegmentId,
    segment: IndexedSegment,
    mut file: impl FnMut(Cell, CellEntry),
) -> Filing {
    let (a, b) = (segment.a.point, segment.b.point);
    let min = Point::new(a.x.min(b.x), a.y.min(b.y));
    let max = Point::new(a.x.max(b.x), a.y.max(b.y));
    let finite = [a.x, a.y, b.x, b.y].iter().all(|v| v.is_finite());
    let place = match cell_box(&min, &max).filter(|_| finite) {
        Some(bx) => {
            let world = [
                f32_outward(min.x, false),
                f32_outward(min.y, false),
                f32_outward(max.x, true),
                f32_outward(max.y, true),
            ];
            for cx in bx[0]..=bx[2] {
                for cy in bx[1]..=bx[3] {
                    let entry = CellEntry {
                        id,
                        first_column: cx == bx[0],
                        first_row: cy == bx[1],
                        world,
                    };
                    file((cx, cy), entry);
                }
            }
            Place::Cells(bx)
        }
        None => Place::Oversize,
    };
    Filing {
        place,
        world: [min.x, min.y, max.x, max.y],
        segment,
    }
}

impl SegmentGrid {
    /// A grid filing `segments` (ids distinct), built in one pass: the same grid, with each
    /// cell listing its segments in the same order, as inserting them one by one in that order
    /// gives, for a fraction of the cost (a checkpoint's map is indexed this way on restore).
    /// Room for the filings of ids below `ids_below` is made up front, and an eighth more (a
    /// hint: larger ids still fit; a restored checkpoint's map goes on making segments, and
    /// growing a full list of filings copies all of them).
    pub fn from_segments(
        segments: impl IntoIterator<Item = (SegmentId, IndexedSegment)>,
        ids_below: usize,
    ) -> Self {
        let mut grid = SegmentGrid {
            filings: Vec::with_capacity(ids_below + ids_below / 8),
            ..SegmentGrid::default()
        };
        let segments = segments.into_iter();
        // Most segments take one or two cells.
        let mut entries: Vec<(Cell, CellEntry)> = Vec::with_capacity(2 * segments.size_hint().0);
        for (id, segment) in segments {
            let filing = file_segment(id, segment, |cell, entry| entries.push((cell, entry)));
            if filing.place == Place::Oversize {
                grid.oversize.push(id);
            }
            let slot = id as usize;
            if grid.filings.len() <= slot {
                grid.filings.resize(slot + 1, None);
            }
            debug_assert!(grid.filings[slot].is_none(), "segment {id} filed twice");
            grid.filings[slot] = Some(filing);
            grid.filed += 1;
        }
        grid.cells = CellTable::from_entries(entries);
        grid
    }

    /// Files segment `id` (replacing any earlier filing).
    pub fn insert(&mut self, id: SegmentId, segment: IndexedSegment) {
        self.remove(id);
        let cells = &mut self.cells;
        let filing = file_segment(id, segment, |cell, entry| cells.push(cell, entry));
        if filing.place == Place::Oversize {
            self.oversize.push(id);
        }
        let slot = id as usize;
        if self.filings.len() <= slot {
            self.filings.resize(slot + 1, None);
        }
        self.filings[slot] = Some(filing);
        self.filed += 1;
    }

    /// Removes segment `id`.
    pub fn remove(&mut self, id: SegmentId) {
        let Some(filing) = self.filings.get_mut(id as usize).and_then(Option::take) else {
            return;
        };
        self.filed -= 1;
        match filing.place {
            Place::Cells(bx) => {
                for cx in bx[0]..=bx[2] {
                    for cy in bx[1]..=bx[3] {
                        // A segment is listed once a cell of its box: found, the rest of the
                        // list moves up in one copy (a `paper` map piles thousands of segments
                        // into the cells of a wall it keeps seeing). Sought from the end: a
                        // segment is filed anew at the end of its lists each time it changes,
                        // and the ones that change are the ones that changed lately.
                        self.cells.remove_last((cx, cy), |e| e.id == id);
                    }
                }
            }
            Place::Oversize => self.oversize.retain(|&s| s != id),
        }
    }

    /// Every segment whose bounding box meets the box `[min, max]` (and every oversize one),
    /// sorted by id, no repeats.
    pub fn query(&self, min: &Point, max: &Point) -> Vec<SegmentId> {
        let mut out = Vec::new();
        self.query_into(min, max, &mut out);
        out.sort_unstable();
        out
    }

    /// [`SegmentGrid::query`] into `out` (cleared first, to reuse its allocation), in no
    /// particular order.
    pub fn query_into(&self, min: &Point, max: &Point, out: &mut Vec<SegmentId>) {
        out.clear();
        self.visit_box(min, max, |id, _| out.push(id));
    }

    /// Calls `visit` once for every segment [`SegmentGrid::query`] returns, in no particular
    /// order. A segment filed under several cells of the query is visited by the cell where its
    /// box and the query's first meet (its lowest x, then y), so no sort or dedup is needed.
    pub fn visit_box(
        &self,
        min: &Point,
        max: &Point,
        mut visit: impl FnMut(SegmentId, &IndexedSegment),
    ) {
        for &id in &self.oversize {
            if let Some(Some(f)) = self.filings.get(id as usize) {
                visit(id, &f.segment);
            }
        }
        let meets = |w: &[f64; 4]| w[0] <= max.x && w[2] >= min.x && w[1] <= max.y && w[3] >= min.y;
        match cell_box(min, max) {
            Some(q)
                if ((q[2] - q[0] + 1) * (q[3] - q[1] + 1)) as usize <= self.cells.occupied() =>
            {
                for cx in q[0]..=q[2] {
                    for cy in q[1]..=q[3] {
                        let list = self.cells.get((cx, cy));
                        let (query_column, query_row) = (cx == q[0], cy == q[1]);
                        for e in list {
                            // Visited from the first cell where the boxes meet: the segment's
                            // own first column (row) or the query's, whichever is later.
                            let first_meet =
                                (query_column || e.first_column) && (query_row || e.first_row);
                            let w = e.world.map(f64::from);
                            if !first_meet || !meets(&w) {
                                continue;
                            }
                            if let Some(Some(f)) = self.filings.get(e.id as usize) {
                                if meets(&f.world) {
                                    visit(e.id, &f.segment);
                                }
                            }
                        }
                    }
                }
            }
            // A query box larger than the filled grid: every filed segment, each from the one
            // entry in its first cell (the filings by id also hold every id removed since,
            // which a long run piles up).
            _ => {
                for e in self.cells.iter().flat_map(|(_, list)| list) {
                    if !(e.first_column && e.first_row && meets(&e.world.map(f64::from))) {
                        continue;
                    }
                    if let Some(Some(f)) = self.filings.get(e.id as usize) {
                        if meets(&f.world) {
                            visit(e.id, &f.segment);
                        }
                    }
                }
            }
        }
    }

    /// Checks that the grid files exactly `expected` (id and what it keeps of each, in any
    /// order), each with its exact bounding box, under exactly the cells of its box (or in the
    /// oversize list); the first difference found is returned.
    pub fn check_files_exactly(
        &self,
        expected: impl IntoIterator<Item = (SegmentId, IndexedSegment)>,
    ) -> Result<(), String> {
        let mut count = 0;
        for (id, segment) in expected {
            count += 1;
            let Some(Some(filing)) = self.filings.get(id as usize) else {
                return Err(format!("segment {id} is not in the index"));
            };
            if filing.segment != segment {
                return Err(format!(
                    "segment {id} is filed with stale end-points or face"
                ));
            }
            let (a, b) = (segment.a.point, segment.b.point);
            let world = [a.x.min(b.x), a.y.min(b.y), a.x.max(b.x), a.y.max(b.y)];
            if filing.world != world {
                return Err(format!("segment {id} is filed with a stale box"));
            }
            match filing.place {
                Place::Cells(bx) => {
                    for cx in bx[0]..=bx[2] {
                        for cy in bx[1]..=bx[3] {
                            let listed = self
                                .cells
                                .get((cx, cy))
                                .iter()
                                .filter(|e| e.id == id)
                                .count();
                            if listed != 1 {
                                return Err(format!(
                                    "segment {id} is listed {listed} times in cell ({cx}, {cy})"
                                ));
                            }
                        }
                    }
                }
                Place::Oversize => {
                    if self.oversize.iter().filter(|&&s| s == id).count() != 1 {
                        return Err(format!("oversize segment {id} is not listed once"));
                    }
                }
            }
        }
        if count != self.filed {
            return Err(format!(
                "the index files {} segments, the map has {count}",
                self.filed
            ));
        }
        let entries: usize = self.cells.iter().map(|(_, list)| list.len()).sum();
        let expected_entries: usize = self
            .filings
            .iter()
            .flatten()
            .map(|f| match f.place {
                Place::Cells(bx) => ((bx[2] - bx[0] + 1) * (bx[3] - bx[1] + 1)) as usize,
                Place::Oversize => 0,
            })
            .sum();
        if entries != expected_entries {
            return Err(format!(
                "the cells hold {entries} entries, the filings ask for {expected_entries}"
            ));
        }
        Ok(())
    }

    /// Number of segments filed.
    pub fn len(&self) -> usize {
        self.filed
    }

    /// True when nothing is filed.
    pub fn is_empty(&self) -> bool {
        self.filed == 0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn filed(a: Point, b: Point) -> IndexedSegment {
        let end = |point| EndPoint {
            point,
            range_m: 1.0,
        };
        IndexedSegment {
            a: end(a),
            b: end(b),
            face: 0,
            fitted: true,
        }
    }

    #[test]
    fn a_grid_built_in_one_pass_equals_one_filed_segment_by_segment() {
        // Segments in and across cells, long ones, an oversize one, an infinite one (NaN would
        // make the grids unequal to themselves); spread thinly over the grid (its cells
        // grouped by sorting) and crowded (by counting over the cells' box).
        for spread_m in [100.0, 6.0] {
            let mut rng = 0x2545_f491_4f6c_dd1du64;
            let mut next = || {
                rng ^= rng << 13;
                rng ^= rng >> 7;
                rng ^= rng << 17;
                ((rng % 10_000) as f64 / 10_000.0 - 0.5) * spread_m
            };
            let mut segments: Vec<(SegmentId, IndexedSegment)> = (0..500)
                .map(|id| {
                    let a = Point::new(next(), next());
                    let b = a + (Point::new(next(), next()) - a) * 0.05;
                    (id * 2 + 1, filed(a, b))
                })
                .collect();
            segments.push((2000, filed(Point::new(-1e4, 0.0), Point::new(1e4, 0.0))));
            segments.push((
                2001,
                filed(Point::new(f64::INFINITY, 0.0), Point::new(1.0, 1.0)),
            ));
            let mut one_by_one = SegmentGrid::default();
            for &(id, s) in &segments {
                one_by_one.insert(id, s);
            }
            for ids_below in [0, 2002, 5000] {
                let at_once = SegmentGrid::from_segments(segments.iter().copied(), ids_below);
                assert_eq!(at_once, one_by_one, "spread {spread_m} m");
                assert!(at_once
                    .check_files_exactly(segments.iter().copied())
                    .is_ok());
            }
        }
    }

    #[test]
    fn a_query_over_the_whole_grid_visits_the_live_segments_once_whatever_was_removed() {
        // A long run allocates ids and removes most: a box wider than the grid (the whole-grid
        // pass) finds exactly the segments left, each once, however many ids came before.
        let mut g = SegmentGrid::default();
        for id in 0..2000 {
            let x = f64::from(id % 7);
            g.insert(id, filed(Point::new(x, 0.5), Point::new(x + 2.5, 1.5)));
        }
        for id in 0..2000 {
            if id % 100 != 0 {
                g.remove(id);
            }
        }
        let live: Vec<SegmentId> = (0..2000).filter(|id| id % 100 == 0).collect();
        let everything = g.query(&Point::new(-1e3, -1e3), &Point::new(1e3, 1e3));
        assert_eq!(everything, live);
        let mut visits = 0;
        g.visit_box(&Point::new(-1e3, -1e3), &Point::new(1e3, 1e3), |_, _| {
            visits += 1;
        });
        assert_eq!(visits, live.len(), "each once");
    }

    #[test]
    fn query_finds_segments_through_the_box_and_forgets_removed_ones() {
        let mut g = SegmentGrid::default();
        g.insert(1, filed(Point::new(0.5, 0.5), Point::new(3.5, 0.5)));
        g.insert(2, filed(Point::new(10.0, 10.0), Point::new(11.0, 10.0)));
        g.insert(3, filed(Point::new(f64::NAN, 0.0), Point::new(1.0, 1.0)));
        assert_eq!(
            g.query(&Point::new(2.0, 0.0), &Point::new(2.2, 0.6)),
            vec![1, 3]
        );
        // Same cell, but segment 1's box (y = 0.5) stays above the query's.
        assert_eq!(
            g.query(&Point::new(2.0, 0.0), &Point::new(2.2, 0.2)),
            vec![3]
        );
        assert_eq!(
            g.query(&Point::new(-100.0, -100.0), &Point::new(100.0, 100.0)),
            vec![1, 2, 3]
        );
        g.insert(1, filed(Point::new(20.0, 20.0), Point::new(21.0, 20.0)));
        assert_eq!(
            g.query(&Point::new(2.0, 0.0), &Point::new(2.2, 0.2)),
            vec![3]
        );
        g.remove(3);
        g.remove(2);
        assert_eq!(
            g.query(&Point::new(9.0, 9.0), &Point::new(30.0, 30.0)),
            vec![1]
        );
    }
}
