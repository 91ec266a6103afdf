//! The paper's §1–§3 in a step: readings to points, clusters, and the recursive fit of each
//! cluster, with the extensions' hooks where they act.

use super::Mapper;
use crate::mapping::model::map::SupportPoint;
use crate::mapping::model::trace::{ClusterTrace, NewSegmentTrace, SegmentSource, StepTrace};
use crate::mapping::paper::cluster::cluster_points_breaking;
use crate::mapping::paper::fit::{piece_end_points, split_recursive};
use crate::mapping::paper::readings::convert_readings;
use crate::mapping::step::{FittedStep, StepBuffers};
use crate::run::Snapshot;

impl Mapper {
    /// §1: readings to points (kept into `buffers.kept`); §2: the kept points clustered (into
    /// `buffers.clusters`).
    pub(super) fn readings_and_clusters(
        &self,
        snapshot: &Snapshot,
        trace: &mut StepTrace,
        buffers: &mut StepBuffers,
    ) {
        trace.readings = convert_readings(
            trace.snapshot,
            self.reading_places(),
            &snapshot.ranges_m,
            &self.beam_axes,
            self.sensor.max_range_m,
            &self.params,
            &mut buffers.kept,
        );
        let (ranks, wraps) = (&self.bearing_ranks.0, self.bearing_ranks.1);
        self.hook_readings_kept(snapshot, trace, buffers);
        cluster_points_breaking(
            &buffers.kept,
            ranks,
            wraps,
            self.params.t_gap_m,
            &|a, b| self.breaks_across_right_angle(a, b),
            &mut buffers.clusters,
        );
        if self.record_trace {
            trace.gaps = buffers.clusters.gaps.clone();
        }
    }

    /// §3: each cluster fitted by the recursive end-point fit (after constant-depth groups,
    /// §8.2, when on; a closed loop, §2, repeats its first point at the end). Returns the new
    /// segments in cluster order and the points of one-point clusters.
    pub(super) fn fit_clusters(
        &mut self,
        trace: &mut StepTrace,
        buffers: &mut StepBuffers,
    ) -> FittedStep {
        let StepBuffers {
            kept,
            clusters,
            fitted: fitted_buffer,
            splits: splits_buffer,
            pieces,
            ..
        } = buffers;
        let wraps = self.bearing_ranks.1;
        let chain_has_break = clusters.gaps.iter().any(|g| g.is_break);
        let mut out = FittedStep {
            segments: Vec::new(),
            singles: Vec::new(),
        };
        for (ci, members) in clusters.iter().enumerate() {
            let mut chain = self.fresh_or_reused(fitted_buffer, members.len() + 1);
            chain.extend(members.iter().map(|&i| kept[i]));
            for q in &chain {
                trace.readings[q.reading.sensor()].cluster = Some(ci);
            }
            if self.hook_cluster_is_feature(ci, &chain, trace) {
                if self.record_trace {
                    trace.clusters.push(ClusterTrace {
                        sensors: chain.iter().map(|q| q.reading.sensor()).collect(),
                        constant_depth: Vec::new(),
                        fitted: chain,
                        splits: Vec::new(),
                        new_segments: Vec::new(),
                    });
                } else {
                    *fitted_buffer = chain;
                }
                continue;
            }
            let sensors: Vec<usize> = if self.record_trace {
                chain.iter().map(|q| q.reading.sensor()).collect()
            } else {
                Vec::new()
            };
            let mut fitted = chain;
            let constant_depth = self.hook_constant_depth(&mut fitted);
            // docs/algorithm.md §2: a chain that wraps all round without a break is a closed
            // loop (its last point neighbours its first), so the fit closes it by repeating the
            // first point at the end; the reading itself is still traced once. Two points make
            // no polygon: they are fitted as an open chain.
            let closed_loop = wraps && clusters.len() == 1 && !chain_has_break;
            let repeats_first = closed_loop && fitted.len() >= 3;
            if repeats_first {
                fitted.push(fitted[0]);
            }
            let mut splits = self.fresh_or_reused(splits_buffer, 0);
            pieces.clear();
            split_recursive(&fitted, &self.params, &mut splits, pieces);
            let first_new = out.segments.len();
            self.fit_pieces(ci, &fitted, pieces, repeats_first, trace, &mut out);
            // A one-point cluster, or one the constant-depth reduction (§8.2) left with one
            // reading (a wall seen square-on by three sonars), goes to point memory (§8.1).
            if fitted.len() == 1 {
                out.singles.push(fitted[0]);
            }
            if self.record_trace {
                trace.clusters.push(ClusterTrace {
                    sensors,
                    constant_depth,
                    fitted,
                    splits,
                    new_segments: (first_new..out.segments.len()).collect(),
                });
            } else {
                *splits_buffer = splits;
                *fitted_buffer = fitted;
            }
        }
        out
    }

    /// §3's `pieces` of cluster `ci` (its points `fitted`; `repeats_first` when it is a closed
    /// loop whose last point repeats its first) become new segments in `out`, unless a hook
    /// keeps one back: a piece too short (§8.8) sends its readings to point memory, once each
    /// (consecutive pieces share their corner reading), and echo placement (§8.10) may drop one.
    fn fit_pieces(
        &mut self,
        ci: usize,
        fitted: &[SupportPoint],
        pieces: &[[usize; 2]],
        repeats_first: bool,
        trace: &mut StepTrace,
        out: &mut FittedStep,
    ) {
        // The last reading sent to point memory.
        let mut sent_until: Option<usize> = None;
        for &[first, last] in pieces {
            let (a, b) = piece_end_points(fitted, first, last, self.params.fit);
            if self.hook_piece_too_short(&fitted[first..=last], (&a, &b), pieces.len(), trace) {
                // A closed loop's last point repeats its first (after the constant-depth
                // reduction, which may have shortened the chain).
                let end = if repeats_first {
                    last.min(fitted.len() - 2)
                } else {
                    last
                };
                let start = sent_until.map_or(first, |sent| first.max(sent + 1));
                out.singles
                    .extend(fitted.iter().take(end + 1).skip(start).copied());
                sent_until = Some(end);
                continue;
            }
            let mut new = NewSegmentTrace {
                source: SegmentSource::Cluster(ci),
                a,
                b,
                points: fitted[first..=last].to_vec(),
            };
            if self.hook_keeps_piece(&mut new, out.segments.len(), trace) {
                out.segments.push(new);
            }
        }
    }
}
