//! The reach of the candidate search (docs/algorithm.md §4, pruning): how far from a new segment
//! a map segment can lie and still pass a test, so that only those nearer are tested.

use crate::mapping::model::params::Params;
use crate::mapping::paper::matching::SegmentEnds;

/// How far from new segment `new` a map segment can lie and still pass a §4 test, or fail
/// only its orientation, under `params` with `max_end_range_m` the largest end-point range in
/// the map (the bound of [`Mapper`](crate::mapping::Mapper)'s candidate search; docs/algorithm.md §4).
pub fn candidate_reach_m(params: &Params, max_end_range_m: f64, new: &SegmentEnds) -> f64 {
    let h = (new.b.point - new.a.point).norm() / 2.0;
    let thr =
        params.accuracy_pct / 100.0 * (max_end_range_m + (new.a.range_m + new.b.range_m) / 2.0);
    let theta = params.orientation_rad;
    let containment = if theta < 89f64.to_radians() {
        thr + (h + thr) * theta.tan()
    } else {
        f64::INFINITY
    };
    // A little slack for rounding: pruning must never drop a candidate that passes.
    (thr + h).max(containment) * (1.0 + 1e-9) + 1e-9
}
