//! The warning of a run whose steps keep getting dearer because support lists have no bound:
//! with `support_cap` 0 (the paper's rule, the `paper` preset) a segment keeps every supporting
//! point, and each update reads its whole list, so a robot that keeps seeing the same walls (a
//! standing robot, a patrol) makes every step cost more than the last. Counted in points, not
//! clocks: the same run always warns at the same step.

use sonarmap::mapping::Params;

/// Steps of one window of the count.
const WINDOW_STEPS: usize = 1_000;

/// How many times the first window's points a step a later window must read to warn.
const GROWTH: f64 = 4.0;

/// The fewest points a step a window must read to warn: about 50 µs of merging a step (at
/// 24.5 ns a point, docs/performance.md), ten times a step's own cost.
const MIN_POINTS_PER_STEP: f64 = 2_000.0;

/// Watches the supporting points a run's steps read, window by window.
pub struct SupportGrowth {
    /// Whether support lists are unbounded (and the run not yet warned about).
    watching: bool,
    /// The first window's points a step.
    first_per_step: Option<f64>,
    window_points: usize,
    window_steps: usize,
}

impl SupportGrowth {
    /// A watch over a run mapped with `params`; it never warns with a `support_cap`.
    pub fn new(params: &Params) -> Self {
        SupportGrowth {
            watching: params.support_cap == 0,
            first_per_step: None,
            window_points: 0,
            window_steps: 0,
        }
    }

    /// Notes a step whose updates read `points` supporting points
    /// ([`sonarmap::mapping::Mapper::support_points_updated`]); the warning, once, at the end
    /// of the first window that reads [`GROWTH`] times the first's and at least
    /// [`MIN_POINTS_PER_STEP`] a step.
    pub fn note(&mut self, points: usize) -> Option<String> {
        if !self.watching {
            return None;
        }
        self.window_points += points;
        self.window_steps += 1;
        if self.window_steps < WINDOW_STEPS {
            return None;
        }
        let per_step = self.window_points as f64 / WINDOW_STEPS as f64;
        (self.window_points, self.window_steps) = (0, 0);
        let first = *self.first_per_step.get_or_insert(per_step);
        if per_step < MIN_POINTS_PER_STEP || per_step < GROWTH * first {
            return None;
        }
        self.watching = false;
        Some(format!(
            "steps keep getting dearer: the last {WINDOW_STEPS} read {per_step:.0} supporting \
             points a step, {:.0} times the first {WINDOW_STEPS}. With `support_cap` 0 (the \
             paper's rule) a segment keeps every supporting point, so a robot that keeps seeing \
             the same walls makes each step cost more than the last; a params file with \
             \"support_cap\": 64 (as in `extended`) bounds the lists (the map is then no longer \
             the paper's)",
            per_step / first.max(1.0)
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The step (from 1) at which `points(step)` warns, if any in `steps`.
    fn warns_at(params: &Params, steps: usize, points: impl Fn(usize) -> usize) -> Option<usize> {
        let mut growth = SupportGrowth::new(params);
        (1..=steps).find(|&k| growth.note(points(k)).is_some())
    }

    #[test]
    fn unbounded_lists_that_keep_growing_warn_once_naming_support_cap() {
        // A standing robot: every step's merge reads one point more per wall than the last.
        let mut growth = SupportGrowth::new(&Params::paper());
        let warnings: Vec<String> = (1..=20_000).filter_map(|k| growth.note(8 * k)).collect();
        assert_eq!(warnings.len(), 1);
        assert!(warnings[0].contains("`support_cap` 0"), "{}", warnings[0]);
        // Window w reads 8,000 w − 3,996 points a step: the third is past 4 × 4,004.
        assert_eq!(warns_at(&Params::paper(), 20_000, |k| 8 * k), Some(3_000));
    }

    #[test]
    fn flat_or_small_costs_and_capped_lists_do_not_warn() {
        assert_eq!(warns_at(&Params::paper(), 50_000, |_| 5_000), None);
        assert_eq!(warns_at(&Params::paper(), 50_000, |k| k / 100), None);
        assert_eq!(warns_at(&Params::extended(), 50_000, |k| 8 * k), None);
    }
}
