//! The cells of the segment grid ([`crate::mapping::model::index`]): a dense window over the part of the plane
//! the map fills, where a cell's list is found by arithmetic, and a hash map for the cells
//! outside it (a map spread over more than [`MAX_WINDOW_CELLS`], or a hostile log's far-off
//! coordinates). A query visits a few dozen cells a reading; hashing each was a tenth of a
//! lap run's instructions.

use rustc_hash::FxHashMap;

/// A grid cell: column and row.
pub type Cell = (i64, i64);

/// Most cells the dense window spans: 262,144 (a 512 m square at 1 m cells), 6 MB of empty
/// lists at most.
pub const MAX_WINDOW_CELLS: i64 = 1 << 18;

/// Cells added beyond the one that made the window grow, at least, on each side it grows.
const MIN_GROWTH_CELLS: i64 = 8;

/// Lists of `T` by cell. Empty lists count as absent: two tables are equal when the same cells
/// hold the same lists, however their windows grew.
#[derive(Clone, Debug)]
pub struct CellTable<T> {
    /// First column and row of the window, and its width and height in cells (0 by 0: none).
    x0: i64,
    y0: i64,
    width: i64,
    height: i64,
    /// The window's lists, column after column.
    dense: Vec<Vec<T>>,
    /// Lists of the cells outside the window (never one inside it).
    sparse: FxHashMap<Cell, Vec<T>>,
    /// Cells with a non-empty list.
    occupied: usize,
}

impl<T> Default for CellTable<T> {
    fn default() -> Self {
        CellTable {
            x0: 0,
            y0: 0,
            width: 0,
            height: 0,
            dense: Vec::new(),
            sparse: FxHashMap::default(),
            occupied: 0,
        }
    }
}

impl<T: PartialEq> PartialEq for CellTable<T> {
    fn eq(&self, other: &Self) -> bool {
        self.occupied == other.occupied
            && self
                .iter()
                .all(|(cell, list)| other.get(cell) == list.as_slice())
    }
}

impl<T> CellTable<T> {
    /// The entries grouped by cell, each cell's in the order given (as pushing them one by one
    /// would), in one pass: a window over the entries' cells when it fits in
    /// [`MAX_WINDOW_CELLS`], each list sized by a count first, with an eighth more room (the
    /// first push into a full list of thousands would copy it); otherwise all in the hash map.
    pub fn from_entries(mut entries: Vec<(Cell, T)>) -> Self {
        let mut table = CellTable::default();
        let Some(&((x, y), _)) = entries.first() else {
            return table;
        };
        let (mut x0, mut y0, mut x1, mut y1) = (x, y, x, y);
        for &((x, y), _) in &entries {
            (x0, y0, x1, y1) = (x0.min(x), y0.min(y), x1.max(x), y1.max(y));
        }
        if let Some((width, height)) = window_size(x0, y0, x1, y1) {
            table.set_window(x0, y0, width, height);
            let mut counts = vec![0usize; table.dense.len()];
            for &(cell, _) in &entries {
                counts[table.slot(cell).expect("inside the window")] += 1;
            }
            for (list, n) in table.dense.iter_mut().zip(counts) {
                list.reserve_exact(n + n / 8);
            }
            for (cell, entry) in entries {
                let i = table.slot(cell).expect("inside the window");
                table.dense[i].push(entry);
            }
            table.occupied = table.dense.iter().filter(|l| !l.is_empty()).count();
            return table;
        }
        // A stable sort keeps each cell's entries in the order given.
        entries.sort_by_key(|&(cell, _)| cell);
        let mut entries = entries.into_iter().peekable();
        while let Some((cell, entry)) = entries.next() {
            let mut list = vec![entry];
            while let Some((_, e)) = entries.next_if(|(c, _)| *c == cell) {
                list.push(e);
            }
            table.sparse.insert(cell, list);
        }
        table.occupied = table.sparse.len();
        table
    }

    /// The list of `cell` (empty when it holds none).
    #[inline]
    pub fn get(&self, cell: Cell) -> &[T] {
        if let Some(i) = self.slot(cell) {
            return &self.dense[i];
        }
        if self.sparse.is_empty() {
            return &[];
        }
        self.sparse.get(&cell).map_or(&[], Vec::as_slice)
    }

    /// Appends `entry` to the list of `cell`, growing the window to take it when the window
    /// stays within [`MAX_WINDOW_CELLS`].
    pub fn push(&mut self, cell: Cell, entry: T) {
        if self.slot(cell).is_none() {
            self.grow_to(cell);
        }
        let list = match self.slot(cell) {
            Some(i) => &mut self.dense[i],
            None => self.sparse.entry(cell).or_default(),
        };
        if list.is_empty() {
            self.occupied += 1;
        }
        list.push(entry);
    }

    /// Removes from the list of `cell` the last entry that `is_it` picks, if any (the rest of
    /// the list keeps its order).
    pub fn remove_last(&mut self, cell: Cell, is_it: impl Fn(&T) -> bool) {
        let emptied = match self.slot(cell) {
            Some(i) => remove_last_in(&mut self.dense[i], is_it),
            None => {
                let Some(list) = self.sparse.get_mut(&cell) else {
                    return;
                };
                let emptied = remove_last_in(list, is_it);
                if emptied {
                    self.sparse.remove(&cell);
                }
                emptied
            }
        };
        if emptied {
            self.occupied -= 1;
        }
    }

    /// Number of cells with a non-empty list.
    pub fn occupied(&self) -> usize {
        self.occupied
    }

    /// Every cell with a non-empty list, with its list, in no particular order.
    pub fn iter(&self) -> impl Iterator<Item = (Cell, &Vec<T>)> {
        let (x0, y0, height) = (self.x0, self.y0, self.height);
        let dense = (self.dense.iter().enumerate())
            .map(move |(i, list)| (slot_cell(x0, y0, height, i), list));
        dense
            .chain(self.sparse.iter().map(|(&cell, list)| (cell, list)))
            .filter(|(_, list)| !list.is_empty())
    }

    /// Index in `dense` of `cell`, when the window holds it.
    #[inline]
    fn slot(&self, (x, y): Cell) -> Option<usize> {
        let (dx, dy) = (x.wrapping_sub(self.x0), y.wrapping_sub(self.y0));
        ((dx as u64) < self.width as u64 && (dy as u64) < self.height as u64)
            .then(|| (dx * self.height + dy) as usize)
    }

    /// A window of empty lists (the old one's lists are dropped).
    fn set_window(&mut self, x0: i64, y0: i64, width: i64, height: i64) {
        (self.x0, self.y0, self.width, self.height) = (x0, y0, width, height);
        self.dense = std::iter::repeat_with(Vec::new)
            .take((width * height) as usize)
            .collect();
    }

    /// Grows the window to hold `cell` with room to spare on the side it grew (half the
    /// window's extent there, at least [`MIN_GROWTH_CELLS`]), moving every list it now covers
    /// into it; leaves it as it is when the grown window would pass [`MAX_WINDOW_CELLS`].
    fn grow_to(&mut self, (x, y): Cell) {
        let (x0, y0, x1, y1) = if self.width == 0 {
            (
                x.saturating_sub(MIN_GROWTH_CELLS),
                y.saturating_sub(MIN_GROWTH_CELLS),
                x.saturating_add(MIN_GROWTH_CELLS),
                y.saturating_add(MIN_GROWTH_CELLS),
            )
        } else {
            let (old_x1, old_y1) = (self.x0 + self.width - 1, self.y0 + self.height - 1);
            let pad_x = (self.width / 2).max(MIN_GROWTH_CELLS);
            let pad_y = (self.height / 2).max(MIN_GROWTH_CELLS);
            (
                if x < self.x0 {
                    x.saturating_sub(pad_x)
                } else {
                    self.x0
                },
                if y < self.y0 {
                    y.saturating_sub(pad_y)
                } else {
                    self.y0
                },
                if x > old_x1 {
                    x.saturating_add(pad_x)
                } else {
                    old_x1
                },
                if y > old_y1 {
                    y.saturating_add(pad_y)
                } else {
                    old_y1
                },
            )
        };
        let Some((width, height)) = window_size(x0, y0, x1, y1) else {
            return;
        };
        let old = std::mem::take(self);
        self.set_window(x0, y0, width, height);
        self.occupied = old.occupied;
        for (cell, list) in old.into_lists() {
            match self.slot(cell) {
                Some(i) => self.dense[i] = list,
                None => {
                    self.sparse.insert(cell, list);
                }
            }
        }
    }

    /// Every non-empty list with its cell, moved out.
    fn into_lists(self) -> impl Iterator<Item = (Cell, Vec<T>)> {
        let (x0, y0, height) = (self.x0, self.y0, self.height);
        let dense = (self.dense.into_iter().enumerate())
            .map(move |(i, list)| (slot_cell(x0, y0, height, i), list));
        dense
            .chain(self.sparse)
            .filter(|(_, list)| !list.is_empty())
    }
}

/// The cell at index `i` of a window from column `x0`, row `y0`, `height` rows high (the
/// inverse of [`CellTable::slot`]).
fn slot_cell(x0: i64, y0: i64, height: i64, i: usize) -> Cell {
    let (i, height) = (i as i64, height.max(1));
    (x0 + i / height, y0 + i % height)
}

/// Width and height of the window over cells `x0..=x1`, `y0..=y1`, when it spans at most
/// [`MAX_WINDOW_CELLS`].
fn window_size(x0: i64, y0: i64, x1: i64, y1: i64) -> Option<(i64, i64)> {
    let width = x1.checked_sub(x0)?.checked_add(1)?;
    let height = y1.checked_sub(y0)?.checked_add(1)?;
    (width <= MAX_WINDOW_CELLS && height <= MAX_WINDOW_CELLS && width * height <= MAX_WINDOW_CELLS)
        .then_some((width, height))
}

/// Removes the last entry of `list` that `is_it` picks; true when that left it empty.
fn remove_last_in<T>(list: &mut Vec<T>, is_it: impl Fn(&T) -> bool) -> bool {
    match list.iter().rposition(is_it) {
        Some(at) => {
            list.remove(at);
            list.is_empty()
        }
        None => false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lists_survive_the_window_growing_in_every_direction_and_far_cells_go_to_the_hash_map() {
        let mut t: CellTable<u32> = CellTable::default();
        let cells: Vec<Cell> = vec![
            (0, 0),
            (3, -2),
            (-40, 7),
            (100, 100),
            (-5, -300),
            (1 << 40, 0),
        ];
        for (i, &c) in cells.iter().enumerate() {
            t.push(c, i as u32);
            t.push(c, 100 + i as u32);
        }
        for (i, &c) in cells.iter().enumerate() {
            assert_eq!(t.get(c), &[i as u32, 100 + i as u32], "cell {c:?}");
        }
        assert_eq!(t.occupied(), cells.len());
        assert!(t.sparse.contains_key(&(1 << 40, 0)), "outside any window");
        assert!(t.sparse.keys().all(|&c| t.slot(c).is_none()));
        assert_eq!(t.get((1, 1)), &[] as &[u32]);
        // Built in one pass from the same entries in the same order: equal.
        let entries: Vec<(Cell, u32)> = cells
            .iter()
            .enumerate()
            .flat_map(|(i, &c)| [(c, i as u32), (c, 100 + i as u32)])
            .collect();
        assert_eq!(CellTable::from_entries(entries), t);
        // Removing empties cells, which then count as absent.
        t.remove_last((3, -2), |&e| e == 101);
        t.remove_last((3, -2), |&e| e == 1);
        t.remove_last((1 << 40, 0), |&e| e == 5);
        t.remove_last((1 << 40, 0), |&e| e == 105);
        assert_eq!(t.occupied(), cells.len() - 2);
        assert_eq!(t.get((3, -2)), &[] as &[u32]);
        assert_eq!(t.iter().count(), cells.len() - 2);
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(128))]
        /// Pushes and removals over cells near and far (the window grows, far cells hash)
        /// leave the same lists as a plain map from cell to list, and building the table
        /// from the surviving entries in one pass gives an equal table.
        #[test]
        fn the_table_keeps_what_a_map_of_lists_keeps(
            ops in proptest::collection::vec(
                (proptest::bool::ANY, -40i64..40, -40i64..40, 0u8..4, 0u32..6),
                1..300,
            ),
        ) {
            // Cells a few apart, or scaled far off (outside any window), or at the clamp.
            let place = |x: i64, y: i64, scale: u8| match scale {
                0 | 1 => (x, y),
                2 => (x * 100_000, y * 7),
                _ => (x.signum() * (i64::MAX / 4), y),
            };
            let mut table: CellTable<u32> = CellTable::default();
            let mut model: std::collections::BTreeMap<Cell, Vec<u32>> = Default::default();
            for &(push, x, y, scale, value) in &ops {
                let cell = place(x, y, scale);
                if push {
                    table.push(cell, value);
                    model.entry(cell).or_default().push(value);
                } else {
                    table.remove_last(cell, |&v| v == value);
                    if let Some(list) = model.get_mut(&cell) {
                        if let Some(at) = list.iter().rposition(|&v| v == value) {
                            list.remove(at);
                        }
                    }
                }
            }
            model.retain(|_, list| !list.is_empty());
            proptest::prop_assert_eq!(table.occupied(), model.len());
            for &(_, x, y, scale, _) in &ops {
                let cell = place(x, y, scale);
                proptest::prop_assert_eq!(table.get(cell), model.get(&cell).map_or(&[][..], |l| &l[..]));
            }
            let mut listed: Vec<(Cell, Vec<u32>)> = table.iter().map(|(c, l)| (c, l.clone())).collect();
            listed.sort();
            let expected: Vec<(Cell, Vec<u32>)> = model.clone().into_iter().collect();
            proptest::prop_assert_eq!(&listed, &expected);
            let entries: Vec<(Cell, u32)> =
                expected.iter().flat_map(|(c, l)| l.iter().map(move |&v| (*c, v))).collect();
            proptest::prop_assert!(CellTable::from_entries(entries) == table);
        }
    }

    #[test]
    fn from_entries_keeps_each_cells_order_dense_or_hashed() {
        for spread in [5i64, 1 << 30] {
            let entries: Vec<(Cell, u32)> = (0..200u32)
                .map(|i| {
                    let c = i64::from(i % 7);
                    ((c * spread, -c * spread), i)
                })
                .collect();
            let mut pushed = CellTable::default();
            for &(c, e) in &entries {
                pushed.push(c, e);
            }
            let built = CellTable::from_entries(entries);
            assert_eq!(built, pushed, "spread {spread}");
            assert_eq!(built.get((spread, -spread)).len(), 29);
            assert!(built.get((spread, -spread)).windows(2).all(|w| w[0] < w[1]));
        }
    }
}
