//! Closed intervals of a parameter (a place along a wall, 0 to 1): their union, length and
//! overlap, as `eval` and the near-path spans measure walls.

/// `intervals` as sorted, disjoint closed intervals (overlapping ones joined).
pub fn union(mut intervals: Vec<(f64, f64)>) -> Vec<(f64, f64)> {
    intervals.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut out: Vec<(f64, f64)> = Vec::new();
    for (lo, hi) in intervals {
        match out.last_mut() {
            Some(last) if lo <= last.1 => last.1 = last.1.max(hi),
            _ => out.push((lo, hi)),
        }
    }
    out
}

/// Summed length of disjoint intervals.
pub fn measure(intervals: &[(f64, f64)]) -> f64 {
    intervals.iter().map(|(lo, hi)| hi - lo).sum()
}

/// Length of the intersection of two sorted disjoint interval lists.
pub fn intersection_measure(a: &[(f64, f64)], b: &[(f64, f64)]) -> f64 {
    let (mut i, mut j, mut total) = (0, 0, 0.0);
    while i < a.len() && j < b.len() {
        let lo = a[i].0.max(b[j].0);
        let hi = a[i].1.min(b[j].1);
        if hi > lo {
            total += hi - lo;
        }
        if a[i].1 < b[j].1 {
            i += 1;
        } else {
            j += 1;
        }
    }
    total
}
