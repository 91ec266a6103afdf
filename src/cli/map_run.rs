//! Mapping a whole log: the mapper stepped through a run, with the traces of its steps (when
//! kept) and the one-line [`Summary`] that `run` prints.

use super::progress::Progress;
use super::support_growth::SupportGrowth;
use anyhow::{bail, Result};
use sonarmap::mapping::model::trace::DiscardReason;
use sonarmap::mapping::{Mapper, Outcome, Params, StepTrace};
use sonarmap::run::Run;

/// Runs the mapper over snapshots `0..=until` (its progress on stderr) and returns the mapper
/// and the traces.
pub fn map_run(
    run: &Run,
    params: Params,
    until: Option<usize>,
    keep_traces: bool,
) -> Result<(Mapper, Vec<StepTrace>, Summary)> {
    let end = last_snapshot(run, until)? + 1;
    let mut mapping = Mapping::new(run, params, keep_traces);
    mapping.step_to(run, end, &Progress::new(&run.name, end, "snapshots"))?;
    Ok(mapping.finish())
}

/// The last snapshot to map: `until`, checked against the run, or the run's last.
pub fn last_snapshot(run: &Run, until: Option<usize>) -> Result<usize> {
    let last = run.snapshots.len() - 1;
    match until {
        Some(n) if n > last => bail!("--until {n} is beyond the last snapshot, {last}"),
        Some(n) => Ok(n),
        None => Ok(last),
    }
}

/// A mapper going through a run, with the summary and (when kept) the traces of its steps.
pub struct Mapping {
    /// The mapper.
    pub mapper: Mapper,
    traces: Vec<StepTrace>,
    summary: Summary,
    growth: SupportGrowth,
}

impl Mapping {
    /// A mapper at the run's start; `keep_traces` keeps the full trace of every step.
    pub fn new(run: &Run, params: Params, keep_traces: bool) -> Self {
        // The summary needs only readings and decisions, which the slim trace keeps.
        Self {
            growth: SupportGrowth::new(&params),
            mapper: Mapper::new(params, run.layout.clone(), run.sensor).with_trace(keep_traces),
            traces: Vec::new(),
            summary: Summary::default(),
        }
    }

    /// Steps the snapshots from the mapper's next one up to `end` (exclusive), showing the
    /// snapshots done on `progress` and warning there when steps keep getting dearer
    /// ([`SupportGrowth`]); a step that fails ends the mapping with an error naming its
    /// snapshot, and Ctrl-C with [`super::interrupt::Interrupted`].
    pub fn step_to(&mut self, run: &Run, end: usize, progress: &Progress) -> Result<()> {
        let mut report = progress.callback();
        while self.mapper.next_snapshot() < end {
            let trace = self
                .mapper
                .try_step(&run.snapshots[self.mapper.next_snapshot()])?;
            let points = self.mapper.support_points_updated(&trace);
            if let Some(warning) = self.growth.note(points) {
                progress.warn(&warning);
            }
            self.record(trace);
            if !report(self.mapper.next_snapshot()) {
                return Err(super::interrupt::Interrupted.into());
            }
        }
        Ok(())
    }

    /// The mapper, the kept traces and the summary (with the map's size).
    pub fn finish(self) -> (Mapper, Vec<StepTrace>, Summary) {
        let mut summary = self.summary;
        summary.segments = self.mapper.map().segments.len();
        (self.mapper, self.traces, summary)
    }

    /// Counts a step stepped outside [`Mapping::step_to`] (and keeps its trace when kept).
    pub fn record(&mut self, trace: StepTrace) {
        self.summary.add(&trace);
        if self.mapper.records_trace() {
            self.traces.push(trace);
        }
    }
}

/// Counts over a run, for the one-line summary.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Summary {
    /// Snapshots applied.
    pub snapshots: usize,
    /// Readings kept.
    pub kept: usize,
    /// Readings discarded.
    pub discarded: usize,
    /// Echoes: readings with a range below the sensor's maximum.
    pub echoes: usize,
    /// Echoes discarded below `min_range`.
    pub below_min_range: usize,
    /// Segments in the map.
    pub segments: usize,
    /// Decisions by outcome.
    pub matches: usize,
    /// Extensions.
    pub extensions: usize,
    /// Dismissals.
    pub dismissals: usize,
    /// New faces.
    pub new_faces: usize,
    /// The pose each step used (corrected, with pose correction), in order.
    pub poses: Vec<sonarmap::geometry::Pose>,
}

/// The share of echoes below `min_range` past which a run whose sensor reads nearer is warned.
const MIN_RANGE_WARNING_SHARE: f64 = 0.1;

impl Summary {
    fn add(&mut self, trace: &StepTrace) {
        self.snapshots += 1;
        self.poses.extend(trace.pose);
        for r in &trace.readings {
            if r.discarded.is_some() {
                self.discarded += 1;
            } else {
                self.kept += 1;
            }
            match r.discarded {
                Some(reason) if reason.means_no_echo() => {}
                Some(DiscardReason::BelowMinRange) => {
                    self.echoes += 1;
                    self.below_min_range += 1;
                }
                _ => self.echoes += 1,
            }
        }
        for d in &trace.decisions {
            match d.outcome {
                Outcome::Match => self.matches += 1,
                Outcome::Extension => self.extensions += 1,
                Outcome::Dismissed => self.dismissals += 1,
                Outcome::NewFace => self.new_faces += 1,
            }
        }
    }

    /// A warning when `min_range` discarded at least a tenth of the echoes that `run`'s sensor
    /// reads (its own `min_range` is smaller): `min_range` is the Polaroid's blind zone (6 in),
    /// and a small robot's sonars read walls nearer than that. Given once by a command, from the
    /// summary of the pass it reports (a second pass reads the same readings).
    pub fn min_range_warning(&self, run: &Run, params: &Params) -> Option<String> {
        let share = self.below_min_range as f64 / self.echoes.max(1) as f64;
        if share < MIN_RANGE_WARNING_SHARE || run.sensor.min_range_m >= params.min_range_m {
            return None;
        }
        let length = |m: f64| format!("{:.3} {}", run.units.from_m(m), run.units.symbol());
        Some(format!(
            "{}: {} of {} echoes ({:.0} %) lay below min_range {} and were discarded, though this \
             log's sensor reads from {}; set min_range in --params to map them (README, \
             parameters)",
            run.name,
            self.below_min_range,
            self.echoes,
            100.0 * share,
            length(params.min_range_m),
            length(run.sensor.min_range_m),
        ))
    }
}

impl std::fmt::Display for Summary {
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        write!(
            f,
            "snapshots {}, readings kept {} discarded {}, segments {}, matches {}, extensions {}, dismissals {}, new faces {}",
            self.snapshots, self.kept, self.discarded, self.segments, self.matches, self.extensions, self.dismissals, self.new_faces
        )
    }
}
