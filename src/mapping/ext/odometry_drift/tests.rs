//! Unit tests of `odometry_drift.rs`.

use super::*;

#[test]
fn the_prediction_is_the_motion_matrix_product_bit_for_bit() {
    // F = I but row b = (1, d, θ, 0); the closed form must give F·x and F·P·Fᵀ + Q exactly.
    let mut drift = OdometryDrift {
        mean: Vector4::new(0.01, 0.002, -0.03, 0.004),
        ..Default::default()
    };
    drift.covariance = Matrix4::from_fn(|i, j| {
        let (i, j) = (i as f64, j as f64);
        1e-4 / (1.0 + i + j) + if i == j { 1e-3 } else { 0.0 }
    });
    let (d, turn) = (0.137, -0.0421);
    let motion = OdometryDrift::motion(d, turn);
    let noise = Matrix4::from_diagonal(&Vector4::new(
        RANDOM_HEADING_RAD_PER_SQRT_M.powi(2) * d,
        DRIFT_RATE_CHANGE_PER_SQRT_M.powi(2) * d,
        TURN_SCALE_CHANGE_PER_SQRT_RAD.powi(2) * turn.abs(),
        0.0,
    ));
    let mean = motion * drift.mean;
    let covariance = motion * drift.covariance * motion.transpose() + noise;
    drift.predict(d, turn);
    assert_eq!(drift.mean, mean);
    assert_eq!(drift.covariance, covariance);
}

#[test]
fn a_steady_drift_is_learnt_and_then_followed_without_lines() {
    // The odometry's heading gains 0.3° a metre. The walls give the axis 0 within 0.1°;
    // lines along it are drawn every metre for 20 m (exact, σ 0.3°); then 10 m without
    // lines: the error keeps growing by the learnt rate.
    let rate = 0.3f64.to_radians();
    let sigma = 0.3f64.to_radians();
    let mut drift = OdometryDrift::default();
    drift.set_axis(0.0, 0.1f64.to_radians());
    for metre in 1..=20 {
        drift.predict(1.0, 0.0);
        // The line in the odometry's frame (the axis 0 turned by the error), turned by the
        // expected rotation.
        let innovation = rate * metre as f64 + drift.expected_rotation_rad(LineAge::default());
        let update = drift.update(innovation, sigma, LineAge::default());
        assert!(update.taken, "metre {metre}: {update:?}");
    }
    let (kappa, _, _) = drift.causes();
    assert!(
        (kappa - rate).abs() < 0.05 * rate,
        "κ {}°/m",
        kappa.to_degrees()
    );
    for _ in 0..10 {
        drift.predict(1.0, 0.0);
    }
    let error_deg = (drift.heading_error_rad() - rate * 30.0).to_degrees();
    assert!(error_deg.abs() < 0.5, "error {error_deg}°");
}

#[test]
fn odometry_that_does_not_drift_is_left_alone() {
    // Noisy lines (±0.3°, alternating) on odometry without error, the axis known within
    // 0.1°: the drift is never significant, so the correction stays 0, and the estimated
    // error stays within half the lines' 0.3° (the heading's random growth lets each line
    // move it by about half its deviation); a U-turn after them does not move it.
    let mut drift = OdometryDrift::default();
    let sigma = 0.3f64.to_radians();
    drift.set_axis(0.0, 0.1f64.to_radians());
    for metre in 1..=50 {
        drift.predict(1.0, 0.0);
        let line = if metre % 2 == 0 { sigma } else { -sigma };
        drift.update(
            line + drift.expected_rotation_rad(LineAge::default()),
            sigma,
            LineAge::default(),
        );
        drift.note_significance();
        assert!(!drift.drifting, "metre {metre}: {:?}", drift.causes());
        assert_eq!(drift.correction_rad(), 0.0);
    }
    let error_deg = drift.heading_error_rad().to_degrees();
    assert!(error_deg.abs() < 0.15, "error {error_deg}°");
    drift.predict(0.0, std::f64::consts::PI);
    assert!((drift.heading_error_rad().to_degrees() - error_deg).abs() < 0.01);
}

#[test]
fn a_heading_error_beyond_a_degree_latches_before_its_causes_are_told_apart() {
    // Every step drives 1 m and turns 0.5 rad, and the lines (σ 0.2°) see the error grow
    // 0.3° a step: per metre or per radian turned, the lines cannot tell which. The
    // causes stay insignificant, but once the error is beyond 1° and three of its
    // deviations, the correction latches on the error itself.
    let mut drift = OdometryDrift::default();
    drift.set_axis(0.0, 0.1f64.to_radians());
    let mut latched_at = None;
    for step in 1..=12 {
        drift.predict(1.0, 0.5);
        let innovation =
            0.3f64.to_radians() * step as f64 + drift.expected_rotation_rad(LineAge::default());
        drift.update(innovation, 0.2f64.to_radians(), LineAge::default());
        drift.note_significance();
        if drift.drifting && latched_at.is_none() {
            latched_at = Some(step);
            assert!(
                !drift.causes_significant(),
                "step {step}: {:?}",
                drift.causes()
            );
            assert!(drift.heading_error_rad().to_degrees() >= 1.0);
        }
    }
    let step = latched_at.expect("latched on the error");
    assert!((4..=8).contains(&step), "latched at step {step}");
}

#[test]
fn the_correction_waits_until_the_drift_is_significant() {
    // Lines 0.2° a metre apart from the axis 0 (known within 0.1°), σ 0.3°: until the rate
    // is beyond twice its deviation (and 0.05°/m) the correction is 0; from then on, the
    // whole estimated error.
    let mut drift = OdometryDrift::default();
    drift.set_axis(0.0, 0.1f64.to_radians());
    let rate = 0.2f64.to_radians();
    let mut latched_at = None;
    for metre in 1..=30 {
        drift.predict(1.0, 0.0);
        let innovation = rate * metre as f64 + drift.expected_rotation_rad(LineAge::default());
        drift.update(innovation, 0.3f64.to_radians(), LineAge::default());
        drift.note_significance();
        let (kappa, _, _) = drift.causes();
        let kappa_sigma = drift.covariance[(KAPPA, KAPPA)].sqrt();
        if drift.drifting {
            latched_at.get_or_insert(metre);
            assert_eq!(drift.correction_rad(), drift.heading_error_rad());
        } else {
            assert_eq!(drift.correction_rad(), 0.0);
            assert!(kappa.abs() < MIN_DRIFT_RAD_PER_M || kappa.abs() < 2.0 * kappa_sigma);
        }
    }
    let latched_at = latched_at.expect("a 0.2°/m drift is found within 30 m");
    assert!(latched_at > 1, "latched at once");
}

#[test]
fn after_a_u_turn_the_lines_of_the_next_pass_bring_the_heading_back() {
    use crate::mapping::ext::rectilinear_heading::{axis_deviation, LineFit};
    // The axis is known (0) and the heading right when the robot turns on the spot by
    // 180°; its wheelbase is 5 % off, so its odometry comes out of the turn 9° off. The
    // next pass's wall lines lie 9° from the axis in the odometry's frame. The estimate's
    // σ is 9° (the error per radian turned unknown within 5 %), so the gate opens to 20°:
    // lines of 40 readings count and bring the error back within 0.5°. At the 5° gate, or
    // with six readings, they would count for nothing.
    let mut drift = OdometryDrift::default();
    drift.set_axis(0.0, 0.1f64.to_radians());
    drift.predict(0.0, std::f64::consts::PI);
    let error_rad = 0.05 * std::f64::consts::PI;
    let line = |readings| LineFit {
        direction_rad: error_rad,
        sigma_rad: 0.3f64.to_radians(),
        rms_m: 0.01,
        span_m: 2.0,
        readings,
        read_at: Default::default(),
    };
    let deviation = |drift: &OdometryDrift, readings, gate_rad| {
        axis_deviation(
            [(line(readings), LineAge::default())].into_iter(),
            |age| drift.expected_rotation_rad(age),
            0.0,
            gate_rad,
        )
        .map(|seen| (seen.deviation_rad, seen.sigma_rad, seen.beyond_axis_gate))
    };
    assert_eq!(deviation(&drift, 40, AXIS_GATE_RAD), None);
    assert_eq!(deviation(&drift, 6, drift.axis_gate_rad()), None);
    assert_eq!(drift.axis_gate_rad(), WIDE_GATE_MAX_RAD);
    let (innovation, sigma, beyond) = deviation(&drift, 40, drift.axis_gate_rad()).unwrap();
    assert!(beyond, "the widened gate took the line");
    assert!(drift.update(innovation, sigma, LineAge::default()).taken);
    for _ in 0..10 {
        drift.predict(0.015, 0.0);
        let (innovation, sigma, _) = deviation(&drift, 40, drift.axis_gate_rad()).unwrap();
        assert!(drift.update(innovation, sigma, LineAge::default()).taken);
    }
    let off_deg = (drift.heading_error_rad() - error_rad).to_degrees();
    assert!(off_deg.abs() < 0.5, "{off_deg}°");
    // Known again, the gate is back to 5°.
    assert_eq!(drift.axis_gate_rad(), AXIS_GATE_RAD);
}

#[test]
fn a_line_drawn_while_the_heading_drifts_observes_the_error_of_its_mean_moment() {
    use crate::geometry::Point;
    use crate::mapping::ext::rectilinear_heading::{
        axis_deviation, fit_line, LineFit, OdometryMoment, WallWindow, WindowReading,
    };
    // The robot drives 2 m straight along a wall 1.5 m to its left, read square-on every
    // 0.1 m; its odometry's heading error grows 0.5°/m from 0. The odometry draws the wall
    // on an arc: x = (1 − 1.5 κ) t, y = 1.5 + (1 − 1.5 κ) κ t²/2 (to second order in κ t),
    // whose least-squares chord over t in [0, 2] has slope κ·t̄ = 0.5°, the error at the
    // readings' mean moment (1 m driven), not at the end (1°).
    let kappa = 0.5f64.to_radians();
    let (step_m, range_m) = (0.1, 1.5);
    let (mut x, mut y) = (0.0, 0.0);
    let mut window = WallWindow::new();
    for k in 0..=20 {
        let (t, heading) = (step_m * k as f64, kappa * step_m * k as f64);
        let left = heading + std::f64::consts::FRAC_PI_2;
        let point = Point::new(x + range_m * left.cos(), y + range_m * left.sin());
        window.push_back(WindowReading::new(t, heading, point));
        // The odometry moves on along its own heading (midpoint rule, exact for a steady turn).
        let mid = heading + 0.5 * kappa * step_m;
        (x, y) = (x + step_m * mid.cos(), y + step_m * mid.sin());
    }
    let line = fit_line(&window, 2.0).unwrap();
    assert!(
        (line.direction_rad.to_degrees() - 0.5).abs() < 1e-4,
        "{line:?}"
    );
    assert!((line.read_at.travelled_m - 1.0).abs() < 1e-12);
    let now = OdometryMoment {
        travelled_m: 2.0,
        heading_rad: 2.0 * kappa,
    };
    let age = line.age(now);
    assert!((age.driven_m - 1.0).abs() < 1e-12 && (age.turned_rad - kappa).abs() < 1e-12);
    // The filter knows the drift exactly (b = 1°, κ = 0.5°/m, a = 0): at the line's age the
    // line lies where it expects; taken as drawn now, it would say the heading is 0.5° off.
    let mut drift = OdometryDrift::default();
    drift.set_axis(0.0, 0.0);
    drift.mean = Vector4::new(2.0 * kappa, kappa, 0.0, 0.0);
    let seen = |age_of: &dyn Fn(&LineFit) -> LineAge| {
        let rotation = |age| drift.expected_rotation_rad(age);
        let lines = [(line, age_of(&line))].into_iter();
        axis_deviation(lines, rotation, 0.0, AXIS_GATE_RAD).unwrap()
    };
    let with_age = seen(&|l: &LineFit| l.age(now));
    assert!(
        with_age.deviation_rad.to_degrees().abs() < 1e-4,
        "{with_age:?}"
    );
    assert!((with_age.age.driven_m - age.driven_m).abs() < 1e-12);
    assert!((with_age.age.turned_rad - age.turned_rad).abs() < 1e-12);
    let as_now = seen(&|_: &LineFit| LineAge::default());
    assert!(
        (as_now.deviation_rad.to_degrees() + 0.5).abs() < 1e-4,
        "{as_now:?}"
    );
}

#[test]
fn a_line_far_beyond_the_expected_axis_is_refused() {
    let mut drift = OdometryDrift::default();
    drift.predict(1.0, 0.0);
    drift.set_axis(0.0, 0.001);
    let before = drift.clone();
    let update = drift.update(4f64.to_radians(), 0.001, LineAge::default());
    assert!(!update.taken);
    assert_eq!(drift, before);
}

#[test]
fn lines_of_two_ages_observe_the_error_at_their_weighted_mean_age() {
    use crate::mapping::ext::rectilinear_heading::{axis_deviation, LineFit, OdometryMoment};
    // The filter: b = 2°, κ = 0.4°/m, ε = 3 %, a = 0.5°. Two lines of equal weight: one read
    // 1 m and 0° ago, one 2 m and 20° ago. Each lies where the filter expects it at its own
    // age (b − κd − εθ − a: 1.1°, then 1.1° − 0.4° − 0.6° = 0.1°), so the deviation is 0; their
    // mean age is 1.5 m and 10°, and the update's row at that age predicts the same.
    let deg = |d: f64| d.to_radians();
    let mut drift = OdometryDrift::default();
    drift.set_axis(0.0, 0.0);
    drift.mean = Vector4::new(deg(2.0), deg(0.4), 0.03, deg(0.5));
    let now = OdometryMoment {
        travelled_m: 5.0,
        heading_rad: deg(30.0),
    };
    let line = |direction_deg: f64, travelled_m: f64, heading_deg: f64| LineFit {
        direction_rad: deg(direction_deg),
        sigma_rad: deg(0.5),
        rms_m: 0.01,
        span_m: 2.0,
        readings: 10,
        read_at: OdometryMoment {
            travelled_m,
            heading_rad: deg(heading_deg),
        },
    };
    let lines = [line(1.1, 4.0, 30.0), line(0.1, 3.0, 10.0)];
    let ages: Vec<LineAge> = lines.iter().map(|l| l.age(now)).collect();
    assert!(
        (ages[1].driven_m - 2.0).abs() < 1e-12 && (ages[1].turned_rad - deg(20.0)).abs() < 1e-12
    );
    let rotation = |age| drift.expected_rotation_rad(age);
    let pairs = lines.iter().copied().zip(ages.iter().copied());
    let seen = axis_deviation(pairs, rotation, 0.0, AXIS_GATE_RAD).unwrap();
    assert!(seen.deviation_rad.to_degrees().abs() < 1e-9, "{seen:?}");
    assert!((seen.age.driven_m - 1.5).abs() < 1e-12);
    assert!((seen.age.turned_rad - deg(10.0)).abs() < 1e-12);
    // The update takes that innovation at the mean age: nothing to correct.
    let before = drift.mean;
    let update = drift.update(seen.deviation_rad, seen.sigma_rad, seen.age);
    assert!(update.taken && (drift.mean - before).norm() < 1e-12);
}

#[test]
fn an_error_per_turn_beyond_twice_its_prior_is_held_at_the_bound() {
    // Only ε is uncertain (5 %); a line read a quarter turn ago (turned −π/2) observes
    // b − ε·(−π/2) − a, so ε's gain is 1 / (π/2) = 0.6366 with an exact line. An innovation
    // of 0.2 rad (within the gate of 3 × 0.0785 rad) would move ε by 0.1273, past the 10 %
    // bound: it stops there.
    let uncertain_turn_error = || OdometryDrift {
        covariance: Matrix4::from_diagonal(&Vector4::new(0.0, 0.0, 0.05f64.powi(2), 0.0)),
        axis_ref_rad: Some(0.0),
        ..Default::default()
    };
    let quarter_turn_ago = LineAge {
        driven_m: 0.0,
        turned_rad: -std::f64::consts::FRAC_PI_2,
    };
    let mut drift = uncertain_turn_error();
    let update = drift.update(0.2, 1e-6, quarter_turn_ago);
    assert!(update.taken);
    assert_eq!(drift.causes().1, MAX_TURN_ERROR);
    // What is left of the innovation is what the bounded estimate leaves: 0.2 − 0.1·π/2.
    let left_rad = 0.2 - 0.1 * std::f64::consts::FRAC_PI_2;
    assert!(
        (update.innovation_after_rad - left_rad).abs() < 1e-9,
        "{update:?}"
    );
    // Negative, it stops at the other bound; a small innovation is taken whole.
    let mut drift = uncertain_turn_error();
    drift.update(-0.2, 1e-6, quarter_turn_ago);
    assert_eq!(drift.causes().1, -MAX_TURN_ERROR);
    let mut drift = uncertain_turn_error();
    drift.update(0.05, 1e-6, quarter_turn_ago);
    assert!((drift.causes().1 - 0.05 / std::f64::consts::FRAC_PI_2).abs() < 1e-6);
}
