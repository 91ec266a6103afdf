//! Work on threads, so the window stays responsive: replaying the whole of a large run being
//! opened (its first snapshots shown meanwhile) or the open run under new parameters
//! ([`ReplayJob`]), and comparing a pinned baseline with the
//! current parameters ([`DiffJob`]). Each job reports progress and can be cancelled; the app
//! polls it once a frame and installs the result.

use super::loaded::Source;
use crate::diff::{diff_run, RunDiff};
use crate::mapping::Params;
use crate::replay::{Replay, DEFAULT_CHECKPOINT_INTERVAL};
use crate::run::Run;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::mpsc::{Receiver, TryRecvError};
use std::sync::Arc;

/// Runs with at least this many snapshots are replayed on a background thread.
pub const BACKGROUND_MIN_SNAPSHOTS: usize = 2000;

/// Where a job stands.
pub(super) enum JobPoll<T> {
    /// Finished with this result.
    Done(T),
    /// Still working.
    Running,
    /// The thread ended without a result.
    Stopped,
}

/// Work on a thread over a number of snapshots: its progress, its cancel flag and its result.
pub(super) struct Task<T> {
    total: usize,
    done: Arc<AtomicUsize>,
    cancel: Arc<AtomicBool>,
    result: Receiver<T>,
}

impl<T: Send + 'static> Task<T> {
    /// Runs `work` on a thread over `total` snapshots. `work` gets the progress callback the
    /// engine calls with the snapshots done (it answers whether to go on) and gives its result,
    /// if any. A cancelled task sends nothing.
    fn spawn(
        total: usize,
        work: impl FnOnce(&mut dyn FnMut(usize) -> bool) -> Option<T> + Send + 'static,
    ) -> Self {
        let done = Arc::new(AtomicUsize::new(0));
        let cancel = Arc::new(AtomicBool::new(false));
        let (tx, rx) = std::sync::mpsc::channel();
        let (p, c) = (done.clone(), cancel.clone());
        std::thread::spawn(move || {
            let result = work(&mut |n| {
                p.store(n, Ordering::Relaxed);
                !c.load(Ordering::Relaxed)
            });
            if let Some(value) = result.filter(|_| !c.load(Ordering::Relaxed)) {
                let _ = tx.send(value);
            }
        });
        Task {
            total,
            done,
            cancel,
            result: rx,
        }
    }
}

impl<T> Task<T> {
    /// Asks the thread to stop; it sends no result then.
    pub(super) fn cancel(&self) {
        self.cancel.store(true, Ordering::Relaxed);
    }

    /// Snapshots done so far.
    pub(super) fn done(&self) -> usize {
        self.done.load(Ordering::Relaxed)
    }

    /// Snapshots to do.
    pub(super) fn total(&self) -> usize {
        self.total
    }

    /// The part done, 0 to 1.
    pub(super) fn fraction(&self) -> f32 {
        self.done() as f32 / self.total.max(1) as f32
    }

    /// The result, once there.
    pub(super) fn poll(&self) -> JobPoll<T> {
        match self.result.try_recv() {
            Ok(value) => JobPoll::Done(value),
            Err(TryRecvError::Empty) => JobPoll::Running,
            Err(TryRecvError::Disconnected) => JobPoll::Stopped,
        }
    }
}

/// What a background replay is for.
pub(super) enum JobKind {
    /// The whole of a run being opened, whose first snapshots are shown meanwhile; it goes to
    /// snapshot `resume_at` when done (a reload), else stays where the preview was left.
    Complete {
        source: Source,
        resume_at: Option<usize>,
    },
    /// The open run under new parameters; it goes to snapshot `resume_at` when done (set
    /// during a reload's preview), else stays where the user is.
    Rerun { resume_at: Option<usize> },
}

impl JobKind {
    /// The snapshot the job goes to when done, unless the user moved meanwhile.
    pub(super) fn resume_at(&self) -> Option<usize> {
        match self {
            JobKind::Complete { resume_at, .. } | JobKind::Rerun { resume_at } => *resume_at,
        }
    }
}

/// What the status bar says of a job `done` of `total` snapshots in, `elapsed_s` seconds after
/// it started: the share, the count, the rate and the time left (as the command line's
/// progress bars do), then `label`.
pub(super) fn progress_text(done: usize, total: usize, elapsed_s: f64, label: &str) -> String {
    let share = 100.0 * done as f64 / total.max(1) as f64;
    let rate = if elapsed_s > 0.0 {
        done as f64 / elapsed_s
    } else {
        0.0
    };
    let left = if rate > 0.0 {
        format!(
            "{} left",
            seconds_text(total.saturating_sub(done) as f64 / rate)
        )
    } else {
        "time left unknown".to_owned()
    };
    format!("{share:.0} % · {done} / {total} · {rate:.0} snapshots/s · {left} · {label}")
}

/// `s` seconds as `42 s` or `3 min 05 s`.
fn seconds_text(s: f64) -> String {
    let s = s.round() as u64;
    if s < 60 {
        format!("{s} s")
    } else {
        format!("{} min {:02} s", s / 60, s % 60)
    }
}

/// A replay being built on a thread.
pub(super) struct ReplayJob {
    pub(super) kind: JobKind,
    /// What the status bar says it does.
    pub(super) label: String,
    pub(super) started: std::time::Instant,
    pub(super) task: Task<Replay>,
}

impl ReplayJob {
    /// Starts replaying `run` under `params` on a thread.
    pub(super) fn start(run: Arc<Run>, params: Params, kind: JobKind) -> Self {
        let task = Task::spawn(run.snapshots.len(), move |report| {
            Replay::build(run, params, DEFAULT_CHECKPOINT_INTERVAL, report).ok()
        });
        let label = match &kind {
            JobKind::Complete { source, .. } => format!("replaying {}", source.display_name()),
            JobKind::Rerun { .. } => "re-running with new parameters".to_owned(),
        };
        ReplayJob {
            kind,
            label,
            started: std::time::Instant::now(),
            task,
        }
    }
}

/// The A/B comparison being computed on a thread.
pub(super) type DiffJob = Task<RunDiff>;

/// Starts comparing `run` under `baseline` (A) and `current` (B) on a thread.
pub(super) fn start_diff(run: Arc<Run>, baseline: Params, current: Params) -> DiffJob {
    Task::spawn(run.snapshots.len(), move |report| {
        Some(diff_run(&run, &baseline, &current, report))
    })
}

#[cfg(test)]
mod tests {
    use super::progress_text;

    #[test]
    fn the_status_bar_gives_the_rate_and_the_time_left() {
        assert_eq!(
            progress_text(25_000, 100_000, 10.0, "replaying big.log"),
            "25 % · 25000 / 100000 · 2500 snapshots/s · 30 s left · replaying big.log"
        );
        assert_eq!(
            progress_text(1_000, 100_000, 2.0, "x"),
            "1 % · 1000 / 100000 · 500 snapshots/s · 3 min 18 s left · x"
        );
        assert_eq!(
            progress_text(0, 10, 0.0, "x"),
            "0 % · 0 / 10 · 0 snapshots/s · time left unknown · x"
        );
    }
}
