//! Work on threads, so the window stays responsive: replaying a large run being opened or the
//! open run under new parameters ([`ReplayJob`]), and comparing a pinned baseline with the
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

/// What a background replay is for.
pub(super) enum JobKind {
    /// A run being opened.
    Open { source: Source, keep_index: bool },
    /// The open run under new parameters.
    Rerun,
}

/// Where a job stands.
pub(super) enum JobPoll<T> {
    /// Finished with this result.
    Done(T),
    /// Still working.
    Running,
    /// The thread ended without a result.
    Stopped,
}

/// Progress shared with a job's thread, and its cancel flag.
struct Progress {
    total: usize,
    done: Arc<AtomicUsize>,
    cancel: Arc<AtomicBool>,
}

impl Progress {
    fn new(total: usize) -> Self {
        Progress {
            total,
            done: Arc::new(AtomicUsize::new(0)),
            cancel: Arc::new(AtomicBool::new(false)),
        }
    }

    /// The callback the engine calls with the snapshots done: stores them, and answers
    /// whether to go on.
    fn reporter(&self) -> impl FnMut(usize) -> bool + Send + 'static {
        let (p, c) = (self.done.clone(), self.cancel.clone());
        move |done| {
            p.store(done, Ordering::Relaxed);
            !c.load(Ordering::Relaxed)
        }
    }

    fn done(&self) -> usize {
        self.done.load(Ordering::Relaxed)
    }

    fn fraction(&self) -> f32 {
        self.done() as f32 / self.total.max(1) as f32
    }
}

fn poll<T>(result: &Receiver<T>) -> JobPoll<T> {
    match result.try_recv() {
        Ok(value) => JobPoll::Done(value),
        Err(TryRecvError::Empty) => JobPoll::Running,
        Err(TryRecvError::Disconnected) => JobPoll::Stopped,
    }
}

/// A replay being built on a thread.
pub(super) struct ReplayJob {
    pub(super) kind: JobKind,
    pub(super) label: String,
    pub(super) started: std::time::Instant,
    progress: Progress,
    result: Receiver<Replay>,
}

impl ReplayJob {
    /// Starts replaying `run` under `params` on a thread.
    pub(super) fn start(run: Arc<Run>, params: Params, kind: JobKind) -> Self {
        let progress = Progress::new(run.snapshots.len());
        let (tx, rx) = std::sync::mpsc::channel();
        let mut report = progress.reporter();
        std::thread::spawn(move || {
            let built = Replay::build(run, params, DEFAULT_CHECKPOINT_INTERVAL, &mut report);
            if let Ok(replay) = built {
                let _ = tx.send(replay);
            }
        });
        let label = match &kind {
            JobKind::Open { source, .. } => format!("replaying {}", source.display_name()),
            JobKind::Rerun => "re-running with new parameters".to_owned(),
        };
        ReplayJob {
            kind,
            label,
            started: std::time::Instant::now(),
            progress,
            result: rx,
        }
    }

    /// Asks the thread to stop; its result, if any, is never installed.
    pub(super) fn cancel(&self) {
        self.progress.cancel.store(true, Ordering::Relaxed);
    }

    /// Snapshots replayed so far.
    pub(super) fn done(&self) -> usize {
        self.progress.done()
    }

    /// Snapshots to replay.
    pub(super) fn total(&self) -> usize {
        self.progress.total
    }

    /// The part done, 0 to 1.
    pub(super) fn fraction(&self) -> f32 {
        self.progress.fraction()
    }

    /// The replay, once built.
    pub(super) fn poll(&self) -> JobPoll<Replay> {
        poll(&self.result)
    }
}

/// The A/B comparison being computed on a thread.
pub(super) struct DiffJob {
    progress: Progress,
    result: Receiver<RunDiff>,
}

impl DiffJob {
    /// Starts comparing `run` under `baseline` (A) and `current` (B) on a thread.
    pub(super) fn start(run: Arc<Run>, baseline: Params, current: Params) -> Self {
        let progress = Progress::new(run.snapshots.len());
        let (tx, rx) = std::sync::mpsc::channel();
        let mut report = progress.reporter();
        let cancel = progress.cancel.clone();
        std::thread::spawn(move || {
            let diff = diff_run(&run, &baseline, &current, &mut report);
            if !cancel.load(Ordering::Relaxed) {
                let _ = tx.send(diff);
            }
        });
        DiffJob {
            progress,
            result: rx,
        }
    }

    /// Asks the thread to stop; it sends no result.
    pub(super) fn cancel(&self) {
        self.progress.cancel.store(true, Ordering::Relaxed);
    }

    /// The part done, 0 to 1.
    pub(super) fn fraction(&self) -> f32 {
        self.progress.fraction()
    }

    /// The comparison, once computed.
    pub(super) fn poll(&self) -> JobPoll<RunDiff> {
        poll(&self.result)
    }
}
