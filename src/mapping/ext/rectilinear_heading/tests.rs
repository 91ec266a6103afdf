//! Unit tests of `rectilinear_heading.rs`.

use super::*;

fn window(points: &[(f64, f64)], step_m: f64) -> WallWindow {
    points
        .iter()
        .enumerate()
        .map(|(k, &(x, y))| WindowReading::new(k as f64 * step_m, 0.0, Point::new(x, y)))
        .collect()
}

#[test]
fn a_wall_drawn_by_a_robot_turned_2_degrees_deviates_2_degrees() {
    // A wall along x = 0..1 m read every 0.1 m, drawn by odometry whose heading is 2° off:
    // the line turns by 2°; carried into the map with no correction it deviates 2° from
    // the axis 0, and a correction of −2° brings it to 0.
    let turn = 2f64.to_radians();
    let points: Vec<(f64, f64)> = (0..11)
        .map(|k| {
            let x = 0.1 * k as f64;
            (x * turn.cos(), 1.5 + x * turn.sin())
        })
        .collect();
    let fit = fit_line(&window(&points, 0.1), 1.0).unwrap();
    assert!((fit.direction_rad - turn).abs() < 1e-9, "{fit:?}");
    // Perfectly straight: the scatter floor of 5 mm over a spread of sqrt(1.1) m is 0.27°,
    // under the 0.3° floor.
    assert!(0.005 / 1.1f64.sqrt() < MIN_SIGMA_RAD);
    assert!((fit.sigma_rad - MIN_SIGMA_RAD).abs() < 1e-12, "{fit:?}");
    let now = [(fit, LineAge::default())];
    let seen = axis_deviation(now.into_iter(), |_| 0.0, 0.0, AXIS_GATE_RAD).unwrap();
    assert!((seen.deviation_rad - turn).abs() < 1e-9 && !seen.beyond_axis_gate);
    let seen = axis_deviation(now.into_iter(), |_| -turn, 0.0, AXIS_GATE_RAD).unwrap();
    assert!(seen.deviation_rad.abs() < 1e-9);
}

#[test]
fn lines_beyond_the_gate_and_scattered_windows_say_nothing() {
    let diagonal: Vec<(f64, f64)> = (0..8).map(|k| (0.1 * k as f64, 0.1 * k as f64)).collect();
    let fit = fit_line(&window(&diagonal, 0.1), 1.0).unwrap();
    assert_eq!(
        axis_deviation(
            [(fit, LineAge::default())].into_iter(),
            |_| 0.0,
            0.0,
            AXIS_GATE_RAD
        ),
        None
    );
    // A zig-zag 5 cm either side: not one wall.
    let zigzag: Vec<(f64, f64)> = (0..8)
        .map(|k| (0.1 * k as f64, if k % 2 == 0 { 0.05 } else { -0.05 }))
        .collect();
    assert_eq!(fit_line(&window(&zigzag, 0.1), 1.0), None);
    // Too short a span for a 2 m window.
    assert_eq!(fit_line(&window(&diagonal, 0.1), 2.0), None);
}

#[test]
fn the_window_keeps_what_was_read_within_its_length() {
    let mut w = WallWindow::new();
    for k in 0..30 {
        let t = 0.1 * k as f64;
        let now = OdometryMoment {
            travelled_m: t,
            heading_rad: 0.0,
        };
        push(&mut w, now, (k % 3 != 0).then(|| Point::new(t, 0.0)), 1.0);
    }
    assert!(w.iter().all(|r| 2.9 - r.travelled_m() <= 1.0 + 1e-12));
    assert_eq!(w.front().map(|r| r.travelled_m() > 1.85), Some(true));
}
