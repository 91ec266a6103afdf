//! The mapper: one snapshot in, the map updated and the step's trace out (paper §3).

use crate::geometry::{Pose, RobotFrame};
use crate::mapping::ext::drift_smoother::DriftHistory;
use crate::mapping::ext::echo_agreement::LastEchoes;
use crate::mapping::ext::pose_correction::PoseBelief;
use crate::mapping::model::heading_track::HeadingTrack;
use crate::mapping::model::map::{Map, Segment};
use crate::mapping::model::params::Params;
use crate::mapping::model::trace::{StepTrace, Warning};
use crate::mapping::paper::cluster::sensor_ranks;
use crate::mapping::paper::reading_poses::{reading_poses, ReadingPlaces};
use crate::mapping::recorded::RecordedDecision;
use crate::mapping::step::StepBuffers;
use crate::run::Snapshot;
use crate::sonar::{BeamAxis, SensorLayout, SensorSpec};
use std::sync::Arc;

mod fit_stage;
mod match_stage;

/// The pose of a step not begun.
const ZERO_POSE: Pose = Pose {
    x: 0.0,
    y: 0.0,
    heading_rad: 0.0,
};

/// Runs the paper's algorithm snapshot by snapshot.
#[derive(Clone, Debug)]
pub struct Mapper {
    pub(super) params: Params,
    pub(super) layout: SensorLayout,
    pub(super) sensor: SensorSpec,
    /// Each sensor's place in the layout's bearing order, and whether that order wraps.
    pub(super) bearing_ranks: (Vec<usize>, bool),
    /// Each sensor's beam axis in the robot frame.
    pub(super) beam_axes: Vec<BeamAxis>,
    pub(super) map: Map,
    pub(super) last_pose: Option<Pose>,
    /// Time of the last snapshot applied, seconds.
    pub(super) last_t_s: Option<f64>,
    /// The pose estimate pose correction carries (docs/algorithm.md §8.17).
    pub(super) pose_belief: PoseBelief,
    /// Each sensor's last echo (`echo_agreement`, docs/algorithm.md §8.21).
    pub(super) last_echoes: LastEchoes,
    /// The drift filter's steps from the first snapshot, for the second pass's heading track
    /// (`calibrate_first` on a pass not yet calibrated; `None` otherwise, and once resumed
    /// from a state).
    pub(super) drift_history: Option<DriftHistory>,
    /// Each sensor's pose in the step, when its readings have their own times (§1.1); empty
    /// otherwise.
    pub(super) step_reading_poses: Vec<Pose>,
    /// The robot frame of the step's pose: a step's beams are turned into the world with it
    /// (one sine and cosine a step, not one a beam).
    pub(super) step_frame: Option<(Pose, RobotFrame)>,
    pub(super) next_snapshot: usize,
    pub(super) brute_force: bool,
    pub(super) record_trace: bool,
    /// Buffers each step fills and the next reuses (boxed: a step takes them out and puts them
    /// back, which moves a pointer, not the buffers). `None` before the first step.
    pub(super) buffers: Option<Box<StepBuffers>>,
}

/// The mutable state a checkpoint needs to resume a [`Mapper`].
#[derive(Clone, Debug)]
pub struct MapperState {
    /// The map.
    pub map: Map,
    /// Pose of the last snapshot applied.
    pub last_pose: Option<Pose>,
    /// Time of the last snapshot applied, seconds.
    pub last_t_s: Option<f64>,
    /// The pose estimate pose correction carries (docs/algorithm.md §8.17).
    pub pose_belief: PoseBelief,
    /// Each sensor's last echo (`echo_agreement`, docs/algorithm.md §8.21).
    pub last_echoes: LastEchoes,
    /// Index of the next snapshot.
    pub next_snapshot: usize,
}

impl Mapper {
    /// A mapper with an empty map. `params` should be valid (see [`Params::validate`]).
    pub fn new(params: Params, layout: SensorLayout, sensor: SensorSpec) -> Self {
        let (order, wraps) = layout.bearing_order();
        let bearing_ranks = (sensor_ranks(&order), wraps);
        let beam_axes = layout.beam_axes();
        let confirms_segments = params.confirm_segments;
        let mut map = Map::confirming(confirms_segments);
        map.tracks_links = params.merge_duplicates || params.free_space || params.trim_seen_through;
        let drift_history = params.keeps_drift_history().then(DriftHistory::default);
        Self {
            params,
            layout,
            sensor,
            bearing_ranks,
            beam_axes,
            map,
            last_pose: None,
            last_t_s: None,
            pose_belief: PoseBelief::default(),
            last_echoes: LastEchoes::default(),
            drift_history,
            step_reading_poses: Vec::new(),
            step_frame: None,
            next_snapshot: 0,
            brute_force: false,
            record_trace: true,
            buffers: None,
        }
    }

    /// With `false`, steps return a slim trace: readings, decisions (without their candidate
    /// lists), updates, correlations, free-space removals and warnings; no gaps, clusters, splits, new-segment
    /// geometry or point-memory record. The map is the same either way.
    pub fn with_trace(mut self, on: bool) -> Self {
        self.set_trace(on);
        self
    }

    /// Switches the full trace on or off for the steps to come (see [`Mapper::with_trace`]).
    pub fn set_trace(&mut self, on: bool) {
        self.record_trace = on;
    }

    /// Whether steps return the full trace.
    pub fn records_trace(&self) -> bool {
        self.record_trace
    }

    /// Tests every map segment as a candidate instead of searching the spatial index (the
    /// reference the pruning is checked against; same decisions, longer traces).
    pub fn with_brute_force_search(mut self, on: bool) -> Self {
        self.brute_force = on;
        self
    }

    /// The map as it stands.
    pub fn map(&self) -> &Map {
        &self.map
    }

    /// The parameters.
    pub fn params(&self) -> &Params {
        &self.params
    }

    /// The map segments the last step offered its new segments as candidates, summed over them:
    /// the step's matching work (what grows with a map that piles up copies of its walls).
    pub fn last_step_candidates(&self) -> usize {
        self.buffers.as_ref().map_or(0, |b| b.candidates.len())
    }

    /// The supporting points of the map segments that `trace` (this mapper's last step)
    /// updated, summed: what the step's merges read, the part of its cost that grows while
    /// support lists grow (docs/performance.md, replay checkpoints).
    pub fn support_points_updated(&self, trace: &StepTrace) -> usize {
        trace
            .updates
            .iter()
            .filter_map(|u| self.map.segment(u.segment))
            .map(|s| s.points.len())
            .sum()
    }

    /// The odometry's drift as the heading correction found it, once it has latched (its
    /// causes were significant at some step): degrees per metre and percent of the angle
    /// turned now, the calibration a second pass may start from (`drift_deg_per_m`,
    /// `drift_per_turn_pct`; docs/algorithm.md §8.17). `None` otherwise, and without the
    /// heading correction alone.
    pub fn found_drift(&self) -> Option<(f64, f64)> {
        let drift = &self.pose_belief.drift;
        let (kappa_rad, epsilon, _) = drift.causes();
        (self.params.corrects_heading_alone() && drift.drifting)
            .then(|| (kappa_rad.to_degrees(), 100.0 * epsilon))
    }

    /// The parameters of a second pass (`calibrate_first`): these with the drift this mapper
    /// found as their calibration ([`Self::found_drift`]), when they had none and it
    /// found one, and the heading errors of its steps smoothed over the whole pass (when it
    /// ran every step from the first), with `pose_correction` on when this pass came back to
    /// its walls (`revisit_laps`); else `None`, the one pass standing.
    pub fn second_pass_params(&self) -> Option<Params> {
        let p = &self.params;
        if !p.calibrate_first || p.drift_calibration().is_some() {
            return None;
        }
        // Smoothed only when a second pass will take it.
        self.found_drift().map(|drift| Params {
            heading_track: self
                .drift_history
                .as_ref()
                .and_then(DriftHistory::smoothed)
                .map(|errors_rad| Arc::new(HeadingTrack::new(errors_rad, drift))),
            pose_correction: p.pose_correction || self.came_back(),
            ..p.calibrated_by(drift)
        })
    }

    /// Whether this pass drove at least `revisit_laps` laps of its map
    /// ([`Params::came_back`]).
    fn came_back(&self) -> bool {
        self.params.came_back(self.map.laps_driven())
    }

    /// Index the next step will get.
    pub fn next_snapshot(&self) -> usize {
        self.next_snapshot
    }

    /// A copy of the state (for checkpoints): segments are shared, the index is left out.
    pub fn state(&self) -> MapperState {
        MapperState {
            map: self.map.without_index(),
            last_pose: self.last_pose,
            last_t_s: self.last_t_s,
            pose_belief: self.pose_belief.clone(),
            last_echoes: self.last_echoes.clone(),
            next_snapshot: self.next_snapshot,
        }
    }

    /// [`Mapper::state`] with its map's list of segments left empty, and that list: a
    /// checkpoint keeps the segments its own way ([`crate::checkpoints::Checkpoints::push_apart`])
    /// and needs no copy of the list.
    pub fn state_apart(&self) -> (MapperState, &[std::sync::Arc<Segment>]) {
        let state = MapperState {
            map: self.map.without_index_or_segments(),
            last_pose: self.last_pose,
            last_t_s: self.last_t_s,
            pose_belief: self.pose_belief.clone(),
            last_echoes: self.last_echoes.clone(),
            next_snapshot: self.next_snapshot,
        };
        (state, &self.map.segments)
    }

    /// Resumes from `state`, whose map has its spatial index built (a checkpoint made live:
    /// [`crate::checkpoints::Checkpoints::live_before`]).
    pub fn resume(&mut self, state: MapperState) {
        self.forget_linkage();
        self.map = state.map;
        self.last_pose = state.last_pose;
        self.last_t_s = state.last_t_s;
        self.pose_belief = state.pose_belief;
        self.last_echoes = state.last_echoes;
        self.next_snapshot = state.next_snapshot;
        self.drift_history = None;
    }

    /// Resumes from a state taken by [`Mapper::state`] (its map shared, not moved: see
    /// [`Map::with_index`]); the replay's checkpoints resume through [`Mapper::resume`].
    pub fn restore(&mut self, state: &MapperState) {
        self.forget_linkage();
        self.map = state.map.with_index();
        self.last_pose = state.last_pose;
        self.last_t_s = state.last_t_s;
        self.pose_belief = state.pose_belief.clone();
        self.last_echoes = state.last_echoes.clone();
        self.next_snapshot = state.next_snapshot;
        self.drift_history = None;
    }

    /// Where the step's readings were taken from (§1.1).
    pub(super) fn reading_places(&self) -> ReadingPlaces<'_> {
        match &self.step_frame {
            Some((step, frame)) => ReadingPlaces {
                step,
                frame: *frame,
                own: &self.step_reading_poses,
            },
            None => ReadingPlaces::new(&ZERO_POSE, &self.step_reading_poses),
        }
    }

    /// An empty vector for what a step traces: a new one (with room for `capacity`) when
    /// tracing, since the trace keeps it; otherwise `buffer`'s, to be put back after use.
    pub(super) fn fresh_or_reused<T>(&self, buffer: &mut Vec<T>, capacity: usize) -> Vec<T> {
        if self.record_trace {
            Vec::with_capacity(capacity)
        } else {
            let mut reused = std::mem::take(buffer);
            reused.clear();
            reused
        }
    }

    /// [`Mapper::step`] taking the decisions (docs/algorithm.md §4) as `decisions` recorded
    /// them when this step first ran from the same state, instead of testing candidates: the
    /// same map, for a fraction of the cost on a large map (the replay catches up this way
    /// between a checkpoint and the snapshot shown). Everything else (fitting, the updates, the
    /// extensions, correlation) runs as in `step`. With another number of decisions than new
    /// segments, it decides afresh.
    pub fn step_as_recorded(
        &mut self,
        snapshot: &Snapshot,
        decisions: &[RecordedDecision],
    ) -> StepTrace {
        self.step_with(snapshot, Some(decisions))
    }

    /// Applies one snapshot and returns what happened: the paper's §3 as a pipeline.
    pub fn step(&mut self, snapshot: &Snapshot) -> StepTrace {
        self.step_with(snapshot, None)
    }

    /// [`Mapper::step`], taking the decisions from `recorded` when given.
    fn step_with(
        &mut self,
        snapshot: &Snapshot,
        recorded: Option<&[RecordedDecision]>,
    ) -> StepTrace {
        if let Some(still) = self.hook_stood_still(snapshot) {
            return still;
        }
        let mended = self.hook_calibrated_snapshot(snapshot);
        let raw_odometry = snapshot.pose;
        let snapshot = mended.as_ref().unwrap_or(snapshot);
        // Built here and filled in place: a trace is large, and returned once, not moved through
        // the stages.
        let mut trace = StepTrace {
            snapshot: self.next_snapshot,
            t: snapshot.t,
            pose: Some(snapshot.pose),
            ..Default::default()
        };
        self.begin_step(snapshot, &mut trace);
        if mended.is_some() {
            self.hook_calibrated_trace(raw_odometry, &mut trace);
        }
        let mut buffers = self.buffers.take().unwrap_or_default();
        self.readings_and_clusters(snapshot, &mut trace, &mut buffers);
        self.hook_echoes_read(snapshot, &trace);
        self.hook_readings_settled(&mut buffers);
        let mut fitted = self.fit_clusters(&mut trace, &mut buffers);
        self.hook_fitted(&mut fitted, &mut trace, &mut buffers);
        let new_faces =
            self.match_and_update(&mut fitted.segments, recorded, &mut trace, &mut buffers);
        self.hook_updated(&fitted.segments, &mut trace, &buffers);
        self.buffers = Some(buffers);
        if self.record_trace {
            trace.new_segments = fitted.segments;
        }
        if self.params.correlate {
            self.correlate_new_faces(new_faces, &mut trace);
        }
        self.hook_step_ending(&mut trace);
        // Kept in the slim trace too: the lineage of a link reads its removal there.
        trace.dropped_links = self.map.drop_dangling_links();
        trace
    }

    /// Starts the step whose `trace` holds its snapshot: the warnings of §4 (the robot moved
    /// more than `max_step`, the paper's matching being valid only below it, or the snapshot
    /// has another number of ranges than the layout has sensors) and the step's pose.
    fn begin_step(&mut self, snapshot: &Snapshot, trace: &mut StepTrace) {
        let index = self.next_snapshot;
        self.next_snapshot += 1;
        self.map.note_driven(&snapshot.pose);
        if let Some(last) = self.last_pose {
            let step_m = last.distance_to(&snapshot.pose);
            self.map.travelled_m += step_m;
            if step_m > self.params.max_step_m {
                trace.warnings.push(Warning::MaxStep {
                    step_m,
                    max_step_m: self.params.max_step_m,
                });
            }
        }
        let previous = self.last_t_s.zip(self.last_pose);
        let step_pose = self.hook_step_pose(snapshot, previous, trace);
        trace.pose = Some(step_pose);
        self.last_pose = Some(snapshot.pose);
        self.last_t_s = Some(snapshot.t);
        self.step_frame = Some((step_pose, step_pose.robot_frame()));
        if snapshot.reading_dt_s.len() == self.layout.len() {
            reading_poses(
                previous,
                snapshot.t,
                &snapshot.pose,
                &step_pose,
                &snapshot.reading_dt_s,
                &mut self.step_reading_poses,
            );
        } else {
            self.step_reading_poses.clear();
        }
        self.hook_step_started(index);
        trace.warnings.extend(self.range_count_warning(snapshot));
    }

    /// The warning of §4 for a snapshot with another number of ranges than the layout has
    /// sensors.
    pub(super) fn range_count_warning(&self, snapshot: &Snapshot) -> Option<Warning> {
        (snapshot.ranges_m.len() != self.layout.len()).then(|| Warning::RangeCount {
            given: snapshot.ranges_m.len(),
            expected: self.layout.len(),
        })
    }

    /// Point memory's linkage (§8.1) forgets what it had linked: the map it linked is replaced.
    fn forget_linkage(&mut self) {
        if let Some(buffers) = &mut self.buffers {
            buffers.linkage.forget();
        }
    }
}
