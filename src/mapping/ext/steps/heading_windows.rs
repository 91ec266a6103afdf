//! Pose correction's heading from rectilinear walls (docs/algorithm.md §8.17): each sensor's
//! window of wall readings in the odometry's frame, its line, and the heading observation the
//! lines give ([`crate::mapping::ext::rectilinear_heading`]).

use super::pose_correction::{inverse, Matched};
use crate::geometry::{wrap_pi, Point, Pose, RobotFrame};
use crate::mapping::ext::pose_correction::RangeObservation;
use crate::mapping::ext::rectilinear_heading::{
    axis_deviation, axis_line, fit_line, push, turned_beyond_gate, HeadingLines, LineAge,
    LineSource, OdometryMoment, WallEchoWindow, WindowReading, AXIS_GATE_RAD,
    WALL_WINDOW_TURN_GATE_RAD,
};
use crate::mapping::model::ext_trace::{CorrectionTarget, HeadingObservation};
use crate::mapping::model::map::SegmentId;
use crate::mapping::Mapper;
use crate::run::Snapshot;
use nalgebra::Vector3;
use std::borrow::Cow;
use std::f64::consts::FRAC_PI_2;

impl Mapper {
    /// Adds this step's wall readings (those `matched` at the prediction) to their sensors'
    /// windows, in the odometry's frame, and fits the windows of those sensors. Empty when
    /// `heading_window` is 0.
    pub(super) fn heading_lines(
        &mut self,
        snapshot: &Snapshot,
        previous: Option<(f64, Pose)>,
        matched: &[Matched],
    ) -> HeadingLines {
        if self.params.heading_window_m <= 0.0 {
            return Vec::new();
        }
        let on_wall = |sensor: usize| {
            matched
                .iter()
                .any(|m| m.sensor == sensor && matches!(m.target, CorrectionTarget::Wall(_)))
        };
        let readings: Vec<(usize, Point)> = self
            .beams_from(snapshot, previous, &snapshot.pose)
            .into_iter()
            .filter(|(sensor, _)| on_wall(*sensor))
            .map(|(sensor, b)| (sensor, b.axis_point()))
            .collect();
        self.extend_windows(&snapshot.pose, &readings, true, false)
    }

    /// With `heading_correction` alone and `settled_walls`, at the step's end: the readings
    /// confirmed walls settled (`settled_points`, in the map's frame) join their windows in
    /// the odometry's frame, and their lines wait for the next step's correction (one step
    /// late, instead of matching every reading to the walls again).
    ///
    /// With `wall_windows`, the walls' windows take `settled_echoes` as well
    /// ([`Self::extend_wall_windows`]), and their lines stand in on a step whose sensors'
    /// windows gave none: a robot that turns as it drives empties those. With
    /// `open_windows`, the readings no wall settled (`open_points`) join the sensors' open
    /// windows, whose lines stand in after those: a robot meeting its walls for the first
    /// time has no confirmed wall to settle its readings.
    pub(super) fn windows_take_settled(
        &mut self,
        settled_points: &[(usize, Point)],
        settled_echoes: &[(SegmentId, usize, Point)],
        open_points: &[(usize, Point)],
    ) {
        let Some(odometry) = self.last_pose else {
            return;
        };
        if self.params.heading_window_m <= 0.0 {
            return;
        }
        // Until the walls set the axis, the drift takes no lines (`update_drift`).
        let fit = self.pose_belief.drift.axis_ref_rad.is_some();
        let to_odometry = (self.pose_belief.odometry_to_map != Pose::default())
            .then(|| inverse(&self.pose_belief.odometry_to_map).robot_frame());
        let in_odometry = |points| in_odometry_frame(points, to_odometry.as_ref());
        let mut lines = self.extend_windows(&odometry, &in_odometry(settled_points), fit, false);
        let mut source = LineSource::Sensors;
        if self.params.wall_windows {
            // Fitted only where they stand in.
            let stand_in = fit && lines.is_empty();
            let (wall_lines, walls) =
                self.extend_wall_windows(&odometry, settled_echoes, to_odometry, stand_in);
            if stand_in && !wall_lines.is_empty() {
                lines = wall_lines;
                source = LineSource::Walls(walls);
            }
        }
        if self.params.open_windows {
            let stand_in = fit && lines.is_empty();
            let open_lines =
                self.extend_windows(&odometry, &in_odometry(open_points), stand_in, true);
            if stand_in && !open_lines.is_empty() {
                lines = open_lines;
                source = LineSource::Open;
            }
        }
        let state = &mut self.pose_belief.rectilinear;
        state.pending_lines = lines;
        state.pending_source = source;
    }

    /// Adds `readings` (sensor, point in the odometry's frame) read with the robot at
    /// `odometry` to the sensors' windows of settled readings (`open`: the open windows) and
    /// fits those that took a reading (when `fit`) ([`SensorWindows::extend`]).
    fn extend_windows(
        &mut self,
        odometry: &Pose,
        readings: &[(usize, Point)],
        fit: bool,
        open: bool,
    ) -> HeadingLines {
        let robot = (odometry.position(), self.odometry_moment(odometry));
        let (sensors, window_m) = (self.layout.len(), self.params.heading_window_m);
        let state = &mut self.pose_belief.rectilinear;
        let windows = if open {
            &mut state.open
        } else {
            &mut state.sensors
        };
        windows.extend(sensors, robot, readings, window_m, fit, open)
    }

    /// Adds `echoes` (wall, sensor, echo point in the map's frame), carried into the
    /// odometry's frame by `to_odometry` (none: the frames are one), to their walls' windows,
    /// trims every window to `heading_window` driven (dropping the empty ones, and emptying
    /// those the odometry has turned more than [`WALL_WINDOW_TURN_GATE_RAD`] from), and fits
    /// the windows that took an echo (when `fit`). Unlike a sensor's window, a wall's window
    /// survives the robot's smaller turns: its echoes lie on the wall's line from any sensor,
    /// and a turn of the odometry moves them only through the positions it integrates. Its echoes are one wall's, so a line needs no check against
    /// the robot's motion; [`fit_line`] still wants them spread along half the window. A line
    /// is listed under the sensor of its newest echo; the walls of the lines come second.
    fn extend_wall_windows(
        &mut self,
        odometry: &Pose,
        echoes: &[(SegmentId, usize, Point)],
        to_odometry: Option<RobotFrame>,
        fit: bool,
    ) -> (HeadingLines, Vec<SegmentId>) {
        let window_m = self.params.heading_window_m;
        let now = self.odometry_moment(odometry);
        let heading_rad = now.heading_rad;
        let windows = &mut self.pose_belief.rectilinear.wall_windows;
        for window in windows.iter_mut() {
            let began_rad = window.began_heading_rad;
            if turned_beyond_gate(heading_rad, began_rad, WALL_WINDOW_TURN_GATE_RAD) {
                window.echoes.clear();
            }
            push(&mut window.echoes, now, None, window_m);
        }
        windows.retain(|w| !w.echoes.is_empty());
        for &(wall, _, point) in echoes {
            let index = match windows.iter().position(|w| w.wall == wall) {
                Some(index) => index,
                None => {
                    windows.push(WallEchoWindow {
                        wall,
                        echoes: Default::default(),
                        began_heading_rad: heading_rad,
                    });
                    windows.len() - 1
                }
            };
            let point = to_odometry.map_or(point, |f| f.to_world(&point));
            windows[index].echoes.push_back(WindowReading {
                read_at: now,
                point,
            });
        }
        let (mut lines, mut walls) = (Vec::new(), Vec::new());
        if !fit {
            return (lines, walls);
        }
        for window in windows.iter() {
            // The newest echo of this wall this step, if any.
            let Some(&(_, sensor, _)) = echoes.iter().rev().find(|e| e.0 == window.wall) else {
                continue;
            };
            if let Some(line) = fit_line(&window.echoes, window_m) {
                lines.push((sensor, line));
                walls.push(window.wall);
            }
        }
        (lines, walls)
    }

    /// The moment of the odometry pose `odometry` of this step, as the heading windows count
    /// it: the distance driven so far and its heading.
    pub(super) fn odometry_moment(&self, odometry: &Pose) -> OdometryMoment {
        OdometryMoment {
            travelled_m: self.map.travelled_m,
            heading_rad: odometry.heading_rad,
        }
    }

    /// With `pose_correction`, before the map has an axis: the first line that may set one
    /// ([`axis_line`]), carried into the map by the prediction.
    pub(super) fn set_axis_if_none(
        &mut self,
        snapshot: &Snapshot,
        predicted: &Pose,
        lines: &HeadingLines,
    ) {
        let state = &mut self.pose_belief.rectilinear;
        if state.axis_rad.is_none() {
            let rotation_rad = wrap_pi(predicted.heading_rad - snapshot.pose.heading_rad);
            state.axis_rad = axis_line(lines, self.params.heading_window_m)
                .map(|line| (line.direction_rad + rotation_rad).rem_euclid(FRAC_PI_2));
        }
    }

    /// The lines' deviation from the map's axes with the robot at `estimate`, and its standard
    /// deviation (radians).
    fn heading_deviation(
        &self,
        snapshot: &Snapshot,
        lines: &HeadingLines,
        estimate: &Pose,
    ) -> Option<(f64, f64)> {
        let axis_rad = self.pose_belief.rectilinear.axis_rad?;
        let rotation_rad = wrap_pi(estimate.heading_rad - snapshot.pose.heading_rad);
        // With `pose_correction` the lines are taken as drawn at the step (§8.17, *Line age*
        // is the drift filter's).
        axis_deviation(
            lines.iter().map(|(_, l)| (*l, LineAge::default())),
            |_| rotation_rad,
            axis_rad,
            AXIS_GATE_RAD,
        )
        .map(|seen| (seen.deviation_rad, seen.sigma_rad))
    }

    /// The heading observation at `estimate`: zero deviation expected, the deviation predicted;
    /// turning the robot turns the lines one for one.
    pub(super) fn heading_observation(
        &self,
        snapshot: &Snapshot,
        lines: &HeadingLines,
        estimate: &Pose,
    ) -> Option<RangeObservation> {
        let (deviation_rad, sigma_rad) = self.heading_deviation(snapshot, lines, estimate)?;
        Some(RangeObservation {
            range_m: 0.0,
            predicted_m: deviation_rad,
            jacobian: Vector3::new(0.0, 0.0, 1.0),
            sigma_m: sigma_rad,
        })
    }

    /// The trace of the heading observation: at the prediction and at `estimate`.
    pub(super) fn heading_trace(
        &self,
        snapshot: &Snapshot,
        lines: &HeadingLines,
        predicted: &Pose,
        estimate: &Pose,
    ) -> Option<HeadingObservation> {
        let (before_rad, sigma_rad) = self.heading_deviation(snapshot, lines, predicted)?;
        let (after_rad, _) = self.heading_deviation(snapshot, lines, estimate)?;
        Some(HeadingObservation {
            axis_deg: self.pose_belief.rectilinear.axis_rad?.to_degrees(),
            deviation_deg: before_rad.to_degrees(),
            deviation_after_deg: after_rad.to_degrees(),
            sigma_deg: sigma_rad.to_degrees(),
            sensors: lines.iter().map(|(s, _)| *s).collect(),
            walls: Vec::new(),
            open: false,
            widened_gate_deg: None,
            lines_age: None,
        })
    }
}

/// `points` (sensor, point in the map's frame) carried into the odometry's frame by
/// `to_odometry`; while the odometry needs no correction (none) the frames are one, and they
/// are taken as they are, without a copy.
fn in_odometry_frame<'a>(
    points: &'a [(usize, Point)],
    to_odometry: Option<&RobotFrame>,
) -> Cow<'a, [(usize, Point)]> {
    match to_odometry {
        None => Cow::Borrowed(points),
        Some(map_to_odometry) => points
            .iter()
            .map(|(sensor, p)| (*sensor, map_to_odometry.to_world(p)))
            .collect(),
    }
}
