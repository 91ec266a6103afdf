//! Pose correction (docs/algorithm.md §8.17) on generated families given odometry drift: what
//! it may and may not do to a step's pose, and the map's invariants with it on.

use proptest::prelude::*;
use sonarmap::mapping::{Mapper, Params};
use sonarmap::sim::{with_odometry, OdometryError, SceneKind};
use sonarmap::soak::{family_run, map_checked};

fn corrected_params() -> Params {
    Params {
        pose_correction: true,
        ..Params::extended()
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(12))]
    #[test]
    fn correction_keeps_the_prediction_where_nothing_matched_and_stays_within_its_bound(
        kind in 0usize..6,
        seed in 0u64..1000,
        bad in any::<bool>(),
    ) {
        let error = if bad { OdometryError::BAD } else { OdometryError::MILD };
        let run = with_odometry(&family_run(SceneKind::ALL[kind], seed, 150), &error, seed);
        let params = corrected_params();
        let mut mapper = Mapper::new(params.clone(), run.layout.clone(), run.sensor);
        for s in &run.snapshots {
            let trace = mapper.step(s);
            let c = trace.correction.expect("every step records its correction");
            prop_assert_eq!(trace.pose, Some(c.corrected));
            if c.readings.is_empty() || c.refused.is_some() {
                prop_assert_eq!(c.corrected, c.predicted, "step {}", trace.snapshot);
                continue;
            }
            // Within three of the prediction's standard deviations (the bound).
            let shift_m = c.corrected.distance_to(&c.predicted);
            let bound_m = 3.0 * c.prior_sigma[0].hypot(c.prior_sigma[1]);
            prop_assert!(shift_m <= bound_m + 1e-12, "step {}: {} > {}", trace.snapshot, shift_m, bound_m);
            // Taken only when it explains the readings no worse than the prediction.
            prop_assert!(c.rms_after <= c.rms_before + 1e-12, "step {}", trace.snapshot);
        }
        let checked = map_checked(&run, &params, true);
        prop_assert!(checked.failure.is_none(), "{:?}", checked.failure);
    }
}

#[test]
fn without_the_flag_no_step_records_a_correction_and_the_pose_is_the_odometry() {
    let run = with_odometry(
        &family_run(SceneKind::CorridorWithDoors, 4, 120),
        &OdometryError::MILD,
        4,
    );
    let mut mapper = Mapper::new(Params::extended(), run.layout.clone(), run.sensor);
    for s in &run.snapshots {
        let trace = mapper.step(s);
        assert!(trace.correction.is_none());
        assert_eq!(trace.pose, Some(s.pose));
    }
}
