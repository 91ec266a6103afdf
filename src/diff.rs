//! A/B comparison of two parameter sets on one run: which decisions differ, snapshot by snapshot.
//!
//! New segments of the two runs are paired by their supporting readings (the same readings make
//! "the same" segment even when ids differ); a pair differs when the outcome or the matched
//! segment differs, and a segment fitted under one parameter set only is a difference too.

use crate::mapping::map::{ReadingRef, SegmentId};
use crate::mapping::trace::{Outcome, Rule, StepTrace};
use crate::mapping::{Map, Mapper, Params};
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

/// A decision that differs between A and B.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct DecisionDifference {
    /// Snapshot index.
    pub snapshot: usize,
    /// How it differs.
    pub kind: DifferenceKind,
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
/// then B's segments that A lacks.
pub fn diff_step(a: &StepTrace, b: &StepTrace) -> Vec<DecisionDifference> {
    let (sa, sb) = (sides(a), sides(b));
    let mut out = Vec::new();
    for (readings, da) in &sa {
        match sb.iter().find(|(r, _)| r == readings) {
            None => out.push(DecisionDifference {
                snapshot: a.snapshot,
                kind: DifferenceKind::OnlyInA,
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
        let (ta, tb) = (ma.step(snapshot), mb.step(snapshot));
        let step = diff_step(&ta, &tb);
        if !step.is_empty() {
            diff.snapshots.push(k);
            diff.decisions.extend(step);
        }
        if !progress(k + 1) {
            break;
        }
    }
    (diff, ma.map().without_index(), mb.map().without_index())
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
