//! A/B comparison of two parameter sets on one run: which decisions differ, snapshot by snapshot,
//! and which of them the parameter change made itself.
//!
//! New segments of the two runs are paired by their supporting readings (the same readings make
//! "the same" segment even when ids differ); a pair differs when the outcome or the matched
//! segment differs, and a segment fitted under one parameter set only is a difference too.
//! Once two maps differ, every later decision near the difference may differ too. A difference
//! is **direct** when the decision had the same inputs under both: the same new segment (end-points
//! within [`SAME_GEOMETRY_M`]) and the same map around it (the fitted segments within reach of a
//! §4 test under either parameter set, compared by geometry and ranges rounded to
//! [`SAME_GEOMETRY_M`], not by id)
//! — the parameter change itself. Otherwise it is **consequential**: an earlier difference changed
//! what the decision saw.

use crate::mapping::model::map::{ReadingRef, SegmentId};
use crate::mapping::model::trace::{NewSegmentTrace, Outcome, Rule, SegmentSource, StepTrace};
use crate::mapping::paper::matching::SegmentEnds;
use crate::mapping::{candidate_reach_m, EndPoint, Map, Mapper, Params, SegmentKind};
use crate::run::Run;
use serde::{Deserialize, Serialize};

/// One side of a decision.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct DecisionSide {
    /// Index of the new segment in that run's step trace.
    pub new_segment: usize,
    /// The outcome.
    pub outcome: Outcome,
    /// The rule that decided it.
    pub rule: Rule,
    /// The existing segment matched, extended or that caused the dismissal.
    pub existing: Option<SegmentId>,
}

/// How a decision differs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum DifferenceKind {
    /// Both fitted the segment; the outcomes differ.
    Outcome,
    /// Same outcome against another existing segment.
    ExistingSegment,
    /// Only A fitted this segment.
    OnlyInA,
    /// Only B fitted this segment.
    OnlyInB,
}

/// Geometry closer than this (metres) is the same in both runs.
pub const SAME_GEOMETRY_M: f64 = 1e-6;

/// Why a decision differs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Cause {
    /// Same inputs, another result: the parameter change itself.
    #[default]
    Direct,
    /// The inputs differ because earlier decisions differed.
    Consequential,
}

/// A decision that differs between A and B.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct DecisionDifference {
    /// Snapshot index.
    pub snapshot: usize,
    /// How it differs.
    pub kind: DifferenceKind,
    /// Whether the parameter change made it, or an earlier difference.
    #[serde(default)]
    pub cause: Cause,
    /// The readings of the new segment.
    pub readings: Vec<ReadingRef>,
    /// A's decision.
    pub a: Option<DecisionSide>,
    /// B's decision.
    pub b: Option<DecisionSide>,
}

fn sides(trace: &StepTrace) -> Vec<(Vec<ReadingRef>, DecisionSide)> {
    trace
        .decisions
        .iter()
        .map(|d| {
            let mut readings: Vec<ReadingRef> = trace.new_segments[d.new_segment]
                .points
                .iter()
                .map(|p| p.reading)
                .collect();
            readings.sort_unstable();
            readings.dedup();
            let side = DecisionSide {
                new_segment: d.new_segment,
                outcome: d.outcome,
                rule: d.rule,
                existing: d.existing,
            };
            (readings, side)
        })
        .collect()
}

/// The decisions of one snapshot that differ between trace `a` and trace `b`, in A's order
/// then B's segments that A lacks, each marked direct (see `classify` for the cause).
pub fn diff_step(a: &StepTrace, b: &StepTrace) -> Vec<DecisionDifference> {
    let (sa, sb) = (sides(a), sides(b));
    let mut out = Vec::new();
    for (readings, da) in &sa {
        match sb.iter().find(|(r, _)| r == readings) {
            None => out.push(DecisionDifference {
                snapshot: a.snapshot,
                kind: DifferenceKind::OnlyInA,
                cause: Cause::Direct,
                readings: readings.clone(),
                a: Some(*da),
                b: None,
            }),
            Some((_, db)) => {
                let kind = if da.outcome != db.outcome {
                    Some(DifferenceKind::Outcome)
                } else if da.existing != db.existing {
                    Some(DifferenceKind::ExistingSegment)
                } else {
                    None
                };
                if let Some(kind) = kind {
                    out.push(DecisionDifference {
                        snapshot: a.snapshot,
                        kind,
                        cause: Cause::Direct,
                        readings: readings.clone(),
                        a: Some(*da),
                        b: Some(*db),
                    });
                }
            }
        }
    }
    for (readings, db) in &sb {
        if !sa.iter().any(|(r, _)| r == readings) {
            out.push(DecisionDifference {
                snapshot: b.snapshot,
                kind: DifferenceKind::OnlyInB,
                cause: Cause::Direct,
                readings: readings.clone(),
                a: None,
                b: Some(*db),
            });
        }
    }
    out
}

/// Every differing decision of a run under parameter sets `a` and `b`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct RunDiff {
    /// Snapshots where any decision differs, ascending.
    pub snapshots: Vec<usize>,
    /// The differences, by snapshot.
    pub decisions: Vec<DecisionDifference>,
    /// The first snapshot with a direct difference: where the parameter change first acts.
    #[serde(default)]
    pub first_difference: Option<usize>,
    /// Differences the parameter change made itself.
    #[serde(default)]
    pub direct: usize,
    /// Differences that follow from earlier ones.
    #[serde(default)]
    pub consequential: usize,
    /// Snapshots with a direct difference, ascending.
    #[serde(default)]
    pub direct_snapshots: Vec<usize>,
}

/// What one side's decision saw: the new segment and the map around it.
struct Inputs<'a> {
    trace: &'a StepTrace,
    /// The map before the step (without its index).
    map_before: &'a Map,
    /// The map after the step (with its index).
    map_after: &'a Map,
    /// The segments the step changed.
    touched: Vec<SegmentId>,
    params: &'a Params,
}

/// Rounds a length to [`SAME_GEOMETRY_M`] for the neighbourhood digest.
fn quantised(v: f64) -> i64 {
    (v / SAME_GEOMETRY_M).round() as i64
}

fn same_end(x: &EndPoint, y: &EndPoint) -> bool {
    (x.point - y.point).norm() <= SAME_GEOMETRY_M
        && (x.range_m - y.range_m).abs() <= SAME_GEOMETRY_M
}

fn same_ends(x: &[EndPoint; 2], y: &[EndPoint; 2]) -> bool {
    same_end(&x[0], &y[0]) && same_end(&x[1], &y[1])
}

impl<'a> Inputs<'a> {
    fn of(
        trace: &'a StepTrace,
        map_before: &'a Map,
        map_after: &'a Map,
        params: &'a Params,
    ) -> Self {
        Self {
            trace,
            map_before,
            map_after,
            touched: touched(trace),
            params,
        }
    }
}

/// Ids of the map segments a step changed: updated, split by a refit, absorbed, or moved by a
/// corner.
fn touched(trace: &StepTrace) -> Vec<SegmentId> {
    let mut ids: Vec<SegmentId> = trace
        .updates
        .iter()
        .flat_map(|u| {
            let pieces = u.refit.iter().flat_map(|r| r.pieces.iter().copied());
            std::iter::once(u.segment)
                .chain(pieces)
                .chain(u.absorbed.iter().map(|x| x.segment))
        })
        .chain(
            trace
                .correlations
                .iter()
                .filter_map(|c| c.existing_segment.map(|(id, _)| id)),
        )
        .collect();
    ids.sort_unstable();
    ids.dedup();
    ids
}

/// A digest of the fitted segments of the map before a step whose boxes meet the box of `new`
/// widened by `reach_m`: their count and an order-free sum of hashes of their end-points and
/// ranges, rounded to [`SAME_GEOMETRY_M`] (end-points in either direction are one segment).
/// They are found through the index of the map after the step (`after`) plus the segments the
/// step changed (`touched`, whose geometry is taken from `before`): a segment the step left
/// alone lies where it lay.
fn neighbourhood(
    before: &Map,
    after: &Map,
    touched: &[SegmentId],
    new: &SegmentEnds,
    reach_m: f64,
) -> (usize, u64) {
    use std::hash::{Hash, Hasher};
    let mut ids = Vec::new();
    after.segments_along_into(&new.a.point, &new.b.point, reach_m, &mut ids);
    let (p, q) = (new.a.point, new.b.point);
    let (min, max) = (
        [p.x.min(q.x) - reach_m, p.y.min(q.y) - reach_m],
        [p.x.max(q.x) + reach_m, p.y.max(q.y) + reach_m],
    );
    // Segments made by the step have ids from the map's next free one on.
    let untouched = ids
        .iter()
        .filter(|&&id| id < before.next_segment_id && touched.binary_search(&id).is_err())
        .filter_map(|&id| after.segment(id));
    let changed = touched.iter().filter_map(|&id| before.segment(id));
    let (mut count, mut sum) = (0usize, 0u64);
    for s in untouched.chain(changed) {
        let (a, b) = (s.a.point, s.b.point);
        let meets = a.x.min(b.x) <= max[0]
            && a.x.max(b.x) >= min[0]
            && a.y.min(b.y) <= max[1]
            && a.y.max(b.y) >= min[1];
        if s.kind != SegmentKind::Fitted || !meets {
            continue;
        }
        let key = |e: &EndPoint| {
            [
                quantised(e.point.x),
                quantised(e.point.y),
                quantised(e.range_m),
            ]
        };
        let (ka, kb) = (key(&s.a), key(&s.b));
        let mut hasher = std::collections::hash_map::DefaultHasher::new();
        ka.min(kb).hash(&mut hasher);
        ka.max(kb).hash(&mut hasher);
        count += 1;
        sum = sum.wrapping_add(hasher.finish());
    }
    (count, sum)
}

/// The new segment of side `s` that `side` names.
fn new_segment<'a>(s: &Inputs<'a>, side: &DecisionSide) -> &'a NewSegmentTrace {
    &s.trace.new_segments[side.new_segment]
}

/// Direct when both decisions saw the same inputs; see the module's doc.
fn classify(d: &DecisionDifference, a: &Inputs<'_>, b: &Inputs<'_>) -> Cause {
    match (&d.a, &d.b) {
        (Some(da), Some(db)) => {
            let (na, nb) = (new_segment(a, da), new_segment(b, db));
            let ends_a = SegmentEnds { a: na.a, b: na.b };
            if !same_ends(&[na.a, na.b], &[nb.a, nb.b]) {
                return Cause::Consequential;
            }
            let reach_m = candidate_reach_m(a.params, a.map_before.max_end_range_m, &ends_a).max(
                candidate_reach_m(b.params, b.map_before.max_end_range_m, &ends_a),
            );
            let around = |s: &Inputs<'_>| {
                neighbourhood(s.map_before, s.map_after, &s.touched, &ends_a, reach_m)
            };
            if around(a) == around(b) {
                Cause::Direct
            } else {
                Cause::Consequential
            }
        }
        // Fitted under one parameter set only: a cluster's fit depends on the snapshot's
        // readings and the parameters alone; a memory group's on the memory too.
        (Some(side), None) | (None, Some(side)) => {
            let s = if d.a.is_some() { a } else { b };
            match new_segment(s, side).source {
                SegmentSource::Cluster(_) => Cause::Direct,
                SegmentSource::Memory(_) if a.map_before.memory == b.map_before.memory => {
                    Cause::Direct
                }
                SegmentSource::Memory(_) => Cause::Consequential,
            }
        }
        (None, None) => Cause::Direct,
    }
}

/// Runs both parameter sets over `run` in lockstep and collects the differences.
/// `progress(done)` is called after every snapshot; returning `false` stops early.
pub fn diff_run(
    run: &Run,
    a: &Params,
    b: &Params,
    progress: &mut dyn FnMut(usize) -> bool,
) -> RunDiff {
    diff_run_keeping_maps(run, a, b, progress).0
}

/// [`diff_run`], also returning the two maps as the run left them (for evaluating both without
/// mapping the run again).
pub fn diff_run_keeping_maps(
    run: &Run,
    a: &Params,
    b: &Params,
    progress: &mut dyn FnMut(usize) -> bool,
) -> (RunDiff, Map, Map) {
    let mut ma = Mapper::new(a.clone(), run.layout.clone(), run.sensor);
    let mut mb = Mapper::new(b.clone(), run.layout.clone(), run.sensor);
    let mut diff = RunDiff::default();
    for (k, snapshot) in run.snapshots.iter().enumerate() {
        // The maps before the step share their segments with the mappers (cheap copies).
        let (before_a, before_b) = (ma.map().without_index(), mb.map().without_index());
        let (ta, tb) = (ma.step(snapshot), mb.step(snapshot));
        let mut step = diff_step(&ta, &tb);
        if !step.is_empty() {
            let (side_a, side_b) = (
                Inputs::of(&ta, &before_a, ma.map(), a),
                Inputs::of(&tb, &before_b, mb.map(), b),
            );
            for d in &mut step {
                d.cause = classify(d, &side_a, &side_b);
            }
            diff.add_step(k, step);
        }
        if !progress(k + 1) {
            break;
        }
    }
    (diff, ma.map().without_index(), mb.map().without_index())
}

impl RunDiff {
    /// Adds snapshot `k`'s differences (none empty) and counts them.
    fn add_step(&mut self, k: usize, step: Vec<DecisionDifference>) {
        self.snapshots.push(k);
        let direct = step.iter().filter(|d| d.cause == Cause::Direct).count();
        if direct > 0 {
            self.first_difference.get_or_insert(k);
            self.direct_snapshots.push(k);
        }
        self.direct += direct;
        self.consequential += step.len() - direct;
        self.decisions.extend(step);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Pose;
    use crate::run::Snapshot;
    use crate::sonar::{SensorLayout, SensorSpec};
    use crate::units::{inches, Units};

    fn two_wall_views() -> Run {
        // The same wall segment seen twice, the second time 3 in farther away.
        let layout = SensorLayout::nomad_ring(inches(9.0));
        let snap = |y_in: f64, t: f64| {
            let mut ranges_m = vec![None; 16];
            ranges_m[3] = Some(inches(y_in) / 67.5f64.to_radians().sin());
            ranges_m[4] = Some(inches(y_in));
            ranges_m[5] = Some(inches(y_in) / 112.5f64.to_radians().sin());
            Snapshot {
                t,
                pose: Pose::new(0.0, 0.0, 0.0),
                ranges_m,
                true_pose: None,
                reading_dt_s: Vec::new(),
            }
        };
        Run {
            name: "two views".into(),
            units: Units::Inches,
            robot_radius_m: Some(inches(9.0)),
            layout,
            sensor: SensorSpec::default(),
            floor_plan: None,
            snapshots: vec![snap(40.0, 0.0), snap(43.0, 1.0)],
        }
    }

    #[test]
    fn a_tighter_accuracy_turns_a_match_into_a_new_face() {
        let run = two_wall_views();
        // The wall moved 3 in: d = 3 in against ξ/100·(D1 + (D2+D3)/2) ≈ ξ/100·(40 + 46.5).
        // ξ = 3 gives 2.6 in (fails), ξ = 5 gives 4.3 in (passes).
        let loose = Params {
            accuracy_pct: 5.0,
            ..Params::paper()
        };
        let tight = Params::paper();
        let d = diff_run(&run, &loose, &tight, &mut |_| true);
        assert_eq!(d.snapshots, vec![1]);
        assert_eq!(d.decisions.len(), 1);
        let x = &d.decisions[0];
        assert_eq!(x.kind, DifferenceKind::Outcome);
        assert_eq!(x.a.unwrap().outcome, Outcome::Match);
        assert_eq!(x.b.unwrap().outcome, Outcome::NewFace);
        assert!(diff_run(&run, &tight, &tight, &mut |_| true)
            .decisions
            .is_empty());
    }

    #[test]
    fn the_first_difference_is_direct_and_what_follows_from_it_consequential() {
        // Snapshots at 40, 43 and 43 in. At snapshot 1 the loose ξ matches and the tight one
        // keeps a new face (direct: both saw one segment at 40 in). At snapshot 2 both see
        // the wall at 43 in again, but A's map holds the fused segment and B's two: whatever
        // differs there follows from snapshot 1.
        let mut run = two_wall_views();
        let mut third = run.snapshots[1].clone();
        third.t = 2.0;
        run.snapshots.push(third);
        let loose = Params {
            accuracy_pct: 5.0,
            ..Params::paper()
        };
        let d = diff_run(&run, &loose, &Params::paper(), &mut |_| true);
        assert_eq!(d.first_difference, Some(1));
        assert_eq!(d.direct_snapshots, vec![1]);
        assert_eq!(d.decisions[0].snapshot, 1);
        assert_eq!(d.decisions[0].cause, Cause::Direct);
        let later: Vec<_> = d.decisions.iter().filter(|x| x.snapshot == 2).collect();
        assert!(!later.is_empty(), "snapshot 2 differs too");
        assert!(later.iter().all(|x| x.cause == Cause::Consequential));
        assert_eq!((d.direct, d.consequential), (1, later.len()));
    }

    #[test]
    fn one_theta_change_makes_one_direct_difference_and_many_consequential_ones() {
        use crate::sonar::SensorMount;
        // Three sonars at x = 0, 1, 2 m facing +y: reading k lands at (k, D_k). Snapshot 0
        // sees a wall along y = 2; snapshots 1 to 6 see a line tilted by atan(0.18) = 10.2°,
        // 0.08 m off at its mid-point (colinearity threshold 0.06 + 0.015·4.16 = 0.122 m).
        // θ_o = 15° matches it, θ_o = 5° dismisses it (it fails only the orientation test):
        // a direct difference at snapshot 1. From then on the maps differ (A's wall was
        // updated, B's was not), so every later difference is consequential.
        let layout = SensorLayout {
            mounts: (0..3)
                .map(|k| SensorMount {
                    x_m: f64::from(k),
                    y_m: 0.0,
                    heading_rad: std::f64::consts::FRAC_PI_2,
                })
                .collect(),
        };
        let snap = |t: f64, ranges: [f64; 3]| Snapshot {
            t,
            pose: Pose::new(0.0, 0.0, 0.0),
            ranges_m: ranges.iter().map(|&r| Some(r)).collect(),
            true_pose: None,
            reading_dt_s: Vec::new(),
        };
        let mut snapshots = vec![snap(0.0, [2.0, 2.0, 2.0])];
        snapshots.extend((1..=6).map(|t| snap(f64::from(t), [1.9, 2.08, 2.26])));
        let run = Run {
            name: "tilted".into(),
            units: Units::Metres,
            robot_radius_m: None,
            layout,
            sensor: SensorSpec::default(),
            floor_plan: None,
            snapshots,
        };
        let wide = Params::paper();
        let narrow = Params {
            orientation_rad: 5f64.to_radians(),
            ..Params::paper()
        };
        let d = diff_run(&run, &wide, &narrow, &mut |_| true);
        assert_eq!(d.first_difference, Some(1));
        assert_eq!(d.direct, 1, "{:?}", d.decisions);
        assert_eq!(d.direct_snapshots, vec![1]);
        let first = &d.decisions[0];
        assert_eq!(first.kind, DifferenceKind::Outcome);
        assert_eq!(first.a.unwrap().outcome, Outcome::Match);
        assert_eq!(first.b.unwrap().outcome, Outcome::Dismissed);
        assert!(d.consequential >= 5, "{:?}", d.decisions);
        assert!(d
            .decisions
            .iter()
            .filter(|x| x.snapshot > 1)
            .all(|x| x.cause == Cause::Consequential));
    }

    #[test]
    fn the_maps_kept_are_the_ones_each_parameter_set_makes_alone() {
        let run = two_wall_views();
        let loose = Params {
            accuracy_pct: 5.0,
            ..Params::paper()
        };
        let tight = Params::paper();
        let (_, map_a, map_b) = diff_run_keeping_maps(&run, &loose, &tight, &mut |_| true);
        let alone = |params: &Params| {
            let mut mapper = Mapper::new(params.clone(), run.layout.clone(), run.sensor);
            for snapshot in &run.snapshots {
                mapper.step(snapshot);
            }
            mapper.map().clone()
        };
        // The parameter sets give different maps (a match against a new face), each as alone.
        assert_ne!(map_a.segments.len(), map_b.segments.len());
        assert_eq!(map_a, alone(&loose));
        assert_eq!(map_b, alone(&tight));
    }
}
