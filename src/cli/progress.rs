//! Progress of the long commands on stderr: a bar with the count done, the rate and the time
//! left (indicatif), drawn only when stderr is a terminal (indicatif hides it otherwise, and
//! when `TERM` is `dumb`), so piped output carries nothing extra. Every update also checks
//! for Ctrl-C ([`super::interrupt`]).

use super::interrupt::{self, Interrupted};
use indicatif::{MultiProgress, ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::time::Duration;

/// Steps between two updates of a bar from [`Progress::callback`]: the engine calls it after
/// every step, and a step can take a couple of microseconds.
const STEPS_PER_UPDATE: usize = 256;

/// A progress bar on stderr, cleared when dropped.
pub struct Progress {
    bar: ProgressBar,
    /// The bars of a sweep's logs go under this one.
    group: Option<MultiProgress>,
}

impl Progress {
    /// A bar for `what` over `total` things counted in `unit` ("snapshots", "runs").
    pub fn new(what: &str, total: usize, unit: &str) -> Self {
        Self::on(ProgressBar::new(total as u64), what, unit, None)
    }

    /// A bar for `what` over `total_bytes`, with the rate in bytes a second.
    pub fn bytes(what: &str, total_bytes: usize) -> Self {
        let bar = ProgressBar::new(total_bytes as u64).with_style(style(
            "{prefix} [{wide_bar}] {binary_bytes}/{binary_total_bytes} · \
             {binary_bytes_per_sec} · {eta} left",
        ));
        Self::on(bar.with_prefix(what.to_owned()), what, "", None).steady()
    }

    /// A spinner for `what`, whose length is not known, with the time spent so far.
    pub fn spinner(what: &str) -> Self {
        let bar = ProgressBar::new_spinner().with_style(style("{spinner} {prefix} {elapsed}"));
        Self::on(bar.with_prefix(what.to_owned()), what, "", None).steady()
    }

    /// A bar over the `logs` of a sweep (logs done), under which each log's own bar
    /// ([`Progress::within`]) shows while it runs.
    pub fn sweep(logs: usize) -> Self {
        let group = MultiProgress::with_draw_target(ProgressDrawTarget::stderr());
        let bar = group.add(ProgressBar::new(logs as u64));
        Self::on(bar, "sweep", "logs", Some(group))
    }

    /// A bar like [`Progress::new`], shown under `sweep`'s when there is one (a log of a
    /// sweep).
    pub fn within(sweep: Option<&Progress>, what: &str, total: usize, unit: &str) -> Self {
        match sweep.and_then(|s| s.group.as_ref()) {
            Some(group) => {
                let bar = group.add(ProgressBar::new(total as u64));
                Self::on(bar, what, unit, None)
            }
            None => Self::new(what, total, unit),
        }
    }

    /// The bar `bar`, styled as a count of `unit` unless already styled.
    fn on(bar: ProgressBar, what: &str, unit: &str, group: Option<MultiProgress>) -> Self {
        if !unit.is_empty() {
            bar.set_style(style(&format!(
                "{{prefix}} [{{wide_bar}}] {{human_pos}}/{{human_len}} {unit} · \
                 {{per_sec:1}} · {{eta}} left"
            )));
            bar.set_prefix(what.to_owned());
        }
        Progress { bar, group }
    }

    /// Redraws on a timer, for work that does not report its progress often.
    fn steady(self) -> Self {
        self.bar.enable_steady_tick(Duration::from_millis(100));
        self
    }

    /// Prints `warning: MESSAGE` on stderr, above the bar.
    pub fn warn(&self, message: &str) {
        self.bar.suspend(|| eprintln!("warning: {message}"));
    }

    /// Sets the count done to `done`; `Err` once Ctrl-C was pressed.
    pub fn set(&self, done: usize) -> Result<(), Interrupted> {
        self.bar.set_position(done as u64);
        interrupt::check()
    }

    /// Adds one to the count done; `Err` once Ctrl-C was pressed.
    pub fn inc(&self) -> Result<(), Interrupted> {
        self.bar.inc(1);
        interrupt::check()
    }

    /// The count done, as the library's progress callbacks take it (`progress(done)`
    /// answers whether to go on): updates every [`STEPS_PER_UPDATE`] steps, and answers
    /// `false` once Ctrl-C was pressed.
    pub fn callback(&self) -> impl FnMut(usize) -> bool + '_ {
        move |done| done % STEPS_PER_UPDATE != 0 || self.set(done).is_ok()
    }
}

impl Drop for Progress {
    fn drop(&mut self) {
        self.bar.finish_and_clear();
    }
}

/// The style of `template` (fixed, so always valid).
fn style(template: &str) -> ProgressStyle {
    ProgressStyle::with_template(template)
        .expect("a valid progress template")
        .progress_chars("=> ")
}
