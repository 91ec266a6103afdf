//! The last line of defence around a step: a panic inside [`Mapper::step`] becomes a
//! [`StepFailure`] naming the snapshot, so that neither the app nor the command line goes down
//! with it. The causes are fixed where they are found; this only keeps a bug we have not found
//! from ending a session.

use crate::mapping::mapper::Mapper;
use crate::mapping::model::trace::StepTrace;
use crate::run::Snapshot;
use std::cell::{Cell, RefCell};
use std::panic::{catch_unwind, AssertUnwindSafe, PanicHookInfo};

thread_local! {
    /// True while this thread runs a guarded step.
    static IN_GUARDED_STEP: Cell<bool> = const { Cell::new(false) };
    /// Where the last guarded step panicked, as the panic hook saw it.
    static PANIC_LOCATION: RefCell<Option<String>> = const { RefCell::new(None) };
}

/// A step that failed: the snapshot and what went wrong.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("the engine failed at snapshot {snapshot}: {message}")]
pub struct StepFailure {
    /// Index of the snapshot whose step failed.
    pub snapshot: usize,
    /// The panic's message, with its place in the source when known.
    pub message: String,
}

/// For a panic hook: true when the panic comes from a guarded step on this thread, which
/// reports it itself. The hook then records where it happened instead of printing a trace.
pub fn note_guarded_panic(info: &PanicHookInfo<'_>) -> bool {
    if !IN_GUARDED_STEP.with(Cell::get) {
        return false;
    }
    let location = info
        .location()
        .map(|l| format!("{}:{}", l.file(), l.line()));
    PANIC_LOCATION.with(|p| *p.borrow_mut() = location);
    true
}

/// Installs a panic hook that stays quiet for guarded steps ([`note_guarded_panic`]) and
/// leaves every other panic to the hook installed before.
pub fn install_quiet_step_hook() {
    let previous = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        if !note_guarded_panic(info) {
            previous(info);
        }
    }));
}

impl Mapper {
    /// [`Mapper::step`], with a panic inside it turned into a [`StepFailure`]. After a failure
    /// the mapper's state is not to be trusted: drop it (keep what came before).
    pub fn try_step(&mut self, snapshot: &Snapshot) -> Result<StepTrace, StepFailure> {
        let index = self.next_snapshot();
        IN_GUARDED_STEP.with(|g| g.set(true));
        let result = catch_unwind(AssertUnwindSafe(|| self.step(snapshot)));
        IN_GUARDED_STEP.with(|g| g.set(false));
        result.map_err(|payload| {
            let text = payload
                .downcast_ref::<&str>()
                .map(|s| (*s).to_owned())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "a panic without a message".to_owned());
            let message = match PANIC_LOCATION.with(|p| p.borrow_mut().take()) {
                Some(at) => format!("{text} (at {at})"),
                None => text,
            };
            StepFailure {
                snapshot: index,
                message,
            }
        })
    }
}
