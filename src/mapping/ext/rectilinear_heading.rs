//! Heading from rectilinear walls (docs/algorithm.md §8.17, "heading from the walls' axes"): the
//! math, apart from the step that uses it (`steps/pose_correction.rs`).
//!
//! A sonar whose readings a confirmed wall explains draws that wall again as the robot drives
//! past it. Laid out in the odometry's frame over the last metres driven, those readings form a
//! line whose direction the odometry's heading error turns. Man-made walls mostly meet at right
//! angles, so the line, carried into the map by the current estimate, should lie along one of the
//! map's two axes; its deviation from the nearer axis, within a gate, observes heading directly
//! (orthogonal SLAM, Nguyen, Harati, Martinelli and Siegwart 2006). Without it, a corridor's
//! walls fix heading only through its correlation with lateral position, and the estimate
//! follows the walls the drifting poses have just drawn.

use crate::geometry::{wrap_pi, Point, Vec2};
use crate::mapping::model::map::SegmentId;
use std::collections::VecDeque;
use std::f64::consts::FRAC_PI_2;

/// Largest deviation from an axis a wall's line may show and still count (5°): larger ones are
/// walls at other angles.
pub const AXIS_GATE_RAD: f64 = 5.0 * std::f64::consts::PI / 180.0;
/// Smallest standard deviation of a line's direction (0.3°): the walls themselves are not
/// straighter than that.
pub const MIN_SIGMA_RAD: f64 = 0.3 * std::f64::consts::PI / 180.0;
/// The largest standard deviation of a line that may set the map's axis (0.5°): a noisier
/// first line would tilt every later heading.
pub const AXIS_MAX_SIGMA_RAD: f64 = 0.5 * std::f64::consts::PI / 180.0;
/// Fewest readings in a window for a line.
pub const MIN_WINDOW_READINGS: usize = 6;
/// The widest the axis gate opens while the heading is uncertain (20°,
/// [`crate::mapping::ext::odometry_drift::OdometryDrift::axis_gate_rad`]): a U-turn at the bad
/// end of UMBmark's wheelbase errors (5 %) turns the heading 9° off, and a wall at 45° to the
/// axes stays more than twice as far.
pub const WIDE_GATE_MAX_RAD: f64 = 20.0 * std::f64::consts::PI / 180.0;
/// Fewest readings of a line that counts beyond [`AXIS_GATE_RAD`] (12, twice
/// [`MIN_WINDOW_READINGS`]): one ghost among six readings can turn a line several degrees.
pub const WIDE_GATE_MIN_READINGS: usize = 2 * MIN_WINDOW_READINGS;
/// The largest RMS distance of a window's readings from their line (3 cm): more is not one
/// straight wall.
pub const MAX_LINE_RMS_M: f64 = 0.03;
/// The RMS distance below which a line's scatter is taken as this (5 mm): a few collinear
/// readings do not fix a direction better than the ranges' own noise.
pub const MIN_LINE_RMS_M: f64 = 0.005;

/// A reading in a window: where the odometry put it, and when, as the odometry counts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WindowReading {
    /// The moment it was read.
    pub read_at: OdometryMoment,
    /// Where, in the odometry's frame.
    pub point: Point,
}

/// A moment as the odometry counts it: the distance driven so far (metres) and the odometry's
/// heading then (radians).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct OdometryMoment {
    /// Distance driven, metres.
    pub travelled_m: f64,
    /// The odometry's heading, radians.
    pub heading_rad: f64,
}

impl WindowReading {
    /// `point` read `travelled_m` driven with the odometry heading `heading_rad`.
    pub fn new(travelled_m: f64, heading_rad: f64, point: Point) -> Self {
        let read_at = OdometryMoment {
            travelled_m,
            heading_rad,
        };
        Self { read_at, point }
    }

    /// The distance driven when it was read, metres.
    pub fn travelled_m(&self) -> f64 {
        self.read_at.travelled_m
    }
}

/// A sensor's recent wall readings in the odometry's frame, oldest first.
pub type WallWindow = VecDeque<WindowReading>;

/// How far the odometry drove (metres) and turned (radians) since a line's readings were read,
/// on average ([`LineFit::age`]): the line lies along the heading error of that moment, not
/// of the step that uses it.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LineAge {
    /// Distance driven since, metres.
    pub driven_m: f64,
    /// Turn since, radians.
    pub turned_rad: f64,
}

/// The heading state carried from step to step: each sensor's window and the map's axis.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RectilinearState {
    /// Each sensor's window of the readings a confirmed wall explained.
    pub sensors: SensorWindows,
    /// With `open_windows`: each sensor's window of the readings no confirmed wall settled
    /// (walls not yet confirmed, met for the first time).
    pub open: SensorWindows,
    /// The map's axis (radians in [0, 90°)): the first full window's line, carried into the map.
    pub axis_rad: Option<f64>,
    /// The lines the last step's settled readings gave (`heading_correction` alone with
    /// `settled_walls`): the next step's observation.
    pub pending_lines: HeadingLines,
    /// The windows that gave `pending_lines`.
    pub pending_source: LineSource,
    /// With `wall_windows`: each confirmed wall's window of its settled echoes, in the order
    /// the walls were first read.
    pub wall_windows: Vec<WallEchoWindow>,
}

/// Which windows a step's lines came from (§8.17): the first of these that gave a line.
#[derive(Clone, Debug, Default, PartialEq)]
pub enum LineSource {
    /// The sensors' windows of settled readings.
    #[default]
    Sensors,
    /// The walls' windows (`wall_windows`), these walls in the order of the lines.
    Walls(Vec<SegmentId>),
    /// The sensors' open windows (`open_windows`).
    Open,
}

/// One window per sensor, each one straight pass of the robot, in the odometry's frame.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SensorWindows {
    /// Each sensor's window.
    pub windows: Vec<WallWindow>,
    /// The odometry's heading when each window began, radians: a window is one straight pass,
    /// emptied once the robot has turned more than [`AXIS_GATE_RAD`] from it (a turning
    /// sonar's readings, placed on its axis, would draw an arc).
    pub began_heading_rad: Vec<f64>,
    /// Where the robot stood (odometry) when each window began: a line counts only along the
    /// robot's motion since ([`along_motion`]).
    pub began_at: Vec<Point>,
}

impl SensorWindows {
    /// Adds `readings` (sensor, point in the odometry's frame; the first of each sensor's)
    /// read with the robot at `at` (odometry) at the moment `now`, to the windows of `sensors`
    /// sensors, trims every window to `window_m` driven (emptying those
    /// the robot has turned away from), and fits the windows that took a reading (when
    /// `fit`); a line counts when it runs along the robot's motion since its window began
    /// ([`along_motion`]) and, in `open` windows, whose readings no confirmed wall vouches
    /// for, when its readings follow the robot ([`follows_the_robot`]).
    pub fn extend(
        &mut self,
        sensors: usize,
        (at, now): (Point, OdometryMoment),
        readings: &[(usize, Point)],
        window_m: f64,
        fit: bool,
        open: bool,
    ) -> HeadingLines {
        let heading_rad = now.heading_rad;
        self.windows.resize_with(sensors, Default::default);
        self.began_heading_rad.resize(sensors, heading_rad);
        self.began_at.resize(sensors, at);
        let mut lines = Vec::new();
        for (sensor, window) in self.windows.iter_mut().enumerate() {
            let read = readings.iter().find(|(s, _)| *s == sensor).map(|(_, p)| *p);
            // An empty window that takes nothing stays empty; where it began is set when it
            // next takes a reading (a sparse ring leaves most windows so).
            if window.is_empty() && read.is_none() {
                continue;
            }
            let began_rad = &mut self.began_heading_rad[sensor];
            if window.is_empty() || turned_beyond_gate(heading_rad, *began_rad, AXIS_GATE_RAD) {
                window.clear();
                *began_rad = heading_rad;
                self.began_at[sensor] = at;
            }
            push(window, now, read, window_m);
            if fit && read.is_some() {
                let motion = at - self.began_at[sensor];
                let line = fit_line(window, window_m).filter(|l| {
                    along_motion(l, &motion) && (!open || follows_the_robot(window, l))
                });
                lines.extend(line.map(|line| (sensor, line)));
            }
        }
        lines
    }
}

/// One confirmed wall's recent echoes in the odometry's frame (`wall_windows`, §8.17).
#[derive(Clone, Debug, PartialEq)]
pub struct WallEchoWindow {
    /// The wall that settled the readings.
    pub wall: SegmentId,
    /// Its echoes, oldest first, each with the odometry's moment when it was read.
    pub echoes: WallWindow,
    /// The odometry's heading (radians, unwrapped) when the window began.
    pub began_heading_rad: f64,
}

/// The most a wall's window lets the odometry turn (90°): the wheelbase's error turns every
/// later echo by its share of the turn, 5° after a U-turn at 3 %.
pub const WALL_WINDOW_TURN_GATE_RAD: f64 = std::f64::consts::FRAC_PI_2;

/// The lines of the sensors whose reading a confirmed wall explained this step: (sensor, line
/// in the odometry's frame).
pub type HeadingLines = Vec<(usize, LineFit)>;

/// A line fitted to a window (total least squares).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LineFit {
    /// The line's direction, radians (modulo 180°).
    pub direction_rad: f64,
    /// The direction's standard deviation, radians.
    pub sigma_rad: f64,
    /// RMS distance of the readings from the line, metres.
    pub rms_m: f64,
    /// Distance driven from the oldest reading to the newest, metres.
    pub span_m: f64,
    /// The readings fitted.
    pub readings: usize,
    /// The mean moment its readings were read: a line drawn by a drifting odometry lies along
    /// the heading error of that moment.
    pub read_at: OdometryMoment,
}

impl LineFit {
    /// How far the odometry has driven and turned from the line's mean moment to `now`.
    pub fn age(&self, now: OdometryMoment) -> LineAge {
        LineAge {
            driven_m: now.travelled_m - self.read_at.travelled_m,
            turned_rad: wrap_pi(now.heading_rad - self.read_at.heading_rad),
        }
    }
}

/// Whether a robot now heading `heading_rad` has turned more than `gate_rad` from
/// `began_rad` (a sensor's window: [`AXIS_GATE_RAD`]; a wall's:
/// [`WALL_WINDOW_TURN_GATE_RAD`]). A difference within the gate is taken as it is, without
/// wrapping it, and a log's headings that wrap at ±180° count as the turn they are.
///
/// ```
/// use sonarmap::mapping::ext::rectilinear_heading::{turned_beyond_gate, AXIS_GATE_RAD};
/// use std::f64::consts::{PI, TAU};
/// assert!(!turned_beyond_gate(4f64.to_radians(), 0.0, AXIS_GATE_RAD));
/// assert!(turned_beyond_gate(6f64.to_radians(), 0.0, AXIS_GATE_RAD));
/// // A whole turn later, or across ±180°, is within the gate.
/// assert!(!turned_beyond_gate(TAU + 0.01, 0.0, AXIS_GATE_RAD));
/// assert!(!turned_beyond_gate(-PI + 0.01, PI - 0.01, AXIS_GATE_RAD));
/// ```
pub fn turned_beyond_gate(heading_rad: f64, began_rad: f64, gate_rad: f64) -> bool {
    let turned_rad = heading_rad - began_rad;
    turned_rad.abs() > gate_rad && wrap_pi(turned_rad).abs() > gate_rad
}

/// Adds `point` (read at the moment `now`) to `window` and drops readings older than
/// `window_m` driven.
pub fn push(window: &mut WallWindow, now: OdometryMoment, point: Option<Point>, window_m: f64) {
    while window
        .front()
        .is_some_and(|r| now.travelled_m - r.travelled_m() > window_m)
    {
        window.pop_front();
    }
    if let Some(point) = point {
        window.push_back(WindowReading {
            read_at: now,
            point,
        });
    }
}

/// The line through `window`'s readings, when there are enough of them, read over at least
/// half of `window_m` driven and lying along at least half of it, and straight within
/// [`MAX_LINE_RMS_M`].
///
/// ```
/// use sonarmap::geometry::Point;
/// use sonarmap::mapping::ext::rectilinear_heading::{fit_line, WallWindow, WindowReading};
/// // Six readings 0.2 m apart along a wall at 45°, exactly on it.
/// let w: WallWindow = (0..6).map(|k| WindowReading::new(0.2 * k as f64, 0.0, Point::new(0.2 * k as f64, 0.2 * k as f64))).collect();
/// let fit = fit_line(&w, 1.0).unwrap();
/// assert!((fit.direction_rad.to_degrees() - 45.0).abs() < 1e-9);
/// assert!(fit.rms_m < 1e-12 && (fit.span_m - 1.0).abs() < 1e-12);
/// // Read on average 0.5 m driven.
/// assert!((fit.read_at.travelled_m - 0.5).abs() < 1e-12);
/// ```
pub fn fit_line(window: &WallWindow, window_m: f64) -> Option<LineFit> {
    let (first, last) = (window.front()?, window.back()?);
    let span_m = last.travelled_m() - first.travelled_m();
    if window.len() < MIN_WINDOW_READINGS || span_m < 0.5 * window_m {
        return None;
    }
    let n = window.len() as f64;
    let (mx, my) = window.iter().fold((0.0, 0.0), |(x, y), r| {
        (x + r.point.x / n, y + r.point.y / n)
    });
    let (mut sxx, mut syy, mut sxy) = (0.0, 0.0, 0.0);
    for r in window {
        let (dx, dy) = (r.point.x - mx, r.point.y - my);
        sxx += dx * dx;
        syy += dy * dy;
        sxy += dx * dy;
    }
    let direction_rad = 0.5 * (2.0 * sxy).atan2(sxx - syy);
    let (c, s) = (direction_rad.cos(), direction_rad.sin());
    // Spread along the line and squared distances from it: the eigenvalues of the scatter.
    let along2 = c * c * sxx + 2.0 * c * s * sxy + s * s * syy;
    let across2 = (s * s * sxx - 2.0 * c * s * sxy + c * c * syy).max(0.0);
    let rms_m = (across2 / n).sqrt();
    if rms_m > MAX_LINE_RMS_M || along2 <= 0.0 {
        return None;
    }
    // The readings must lie along half the window, not only have been read over it: a robot
    // going to and fro reads the same few places again.
    let (low, high) = window.iter().fold((f64::MAX, f64::MIN), |(low, high), r| {
        let along = c * (r.point.x - mx) + s * (r.point.y - my);
        (low.min(along), high.max(along))
    });
    if high - low < 0.5 * window_m {
        return None;
    }
    Some(LineFit {
        direction_rad,
        sigma_rad: (rms_m.max(MIN_LINE_RMS_M) / along2.sqrt()).max(MIN_SIGMA_RAD),
        rms_m,
        span_m,
        readings: window.len(),
        read_at: mean_moment(window),
    })
}

/// The mean moment `window`'s readings were read (headings averaged about the first's).
fn mean_moment(window: &WallWindow) -> OdometryMoment {
    let n = window.len() as f64;
    let first_rad = window.front().map_or(0.0, |r| r.read_at.heading_rad);
    let (travelled_m, turned_rad) = window.iter().fold((0.0, 0.0), |(t, h), r| {
        let turned_rad = wrap_pi(r.read_at.heading_rad - first_rad);
        (t + r.travelled_m() / n, h + turned_rad / n)
    });
    OdometryMoment {
        travelled_m,
        heading_rad: first_rad + turned_rad,
    }
}

/// Fewest metres along the line a window's readings spread for each metre driven, in each half
/// of the window ([`follows_the_robot`]).
pub const MIN_FOLLOW_M_PER_M: f64 = 0.5;

/// Whether the readings of `window` follow the robot: in each half of the distance it spans,
/// they spread along `line` over at least [`MIN_FOLLOW_M_PER_M`] of the distance driven in
/// that half. A wall passed alongside is read further along as the robot drives; a wall ahead
/// read square-on returns one place however far the robot drives (Kleeman and Kuc), and two
/// such places read in turn lie on a line that is no wall. A doorway in a wall passed
/// alongside leaves a gap, not a standstill.
///
/// ```
/// use sonarmap::geometry::Point;
/// use sonarmap::mapping::ext::rectilinear_heading::{fit_line, follows_the_robot, WallWindow, WindowReading};
/// let read = |k: usize, x: f64| WindowReading::new(0.1 * k as f64, 0.0, Point::new(x, 1.0));
/// // A wall passed alongside: each reading 0.1 m further along, 0.1 m driven apart.
/// let passed: WallWindow = (0..20).map(|k| read(k, 0.1 * k as f64)).collect();
/// assert!(follows_the_robot(&passed, &fit_line(&passed, 2.0).unwrap()));
/// // Two places 1.8 m apart, each read while the robot drove 0.9 m: each half stands still.
/// let two: WallWindow = (0..20).map(|k| read(k, if k < 10 { 0.0 } else { 1.8 })).collect();
/// assert!(!follows_the_robot(&two, &fit_line(&two, 2.0).unwrap()));
/// ```
pub fn follows_the_robot(window: &WallWindow, line: &LineFit) -> bool {
    let (Some(first), Some(last)) = (window.front(), window.back()) else {
        return true;
    };
    let (c, s) = (line.direction_rad.cos(), line.direction_rad.sin());
    let middle_m = 0.5 * (first.travelled_m() + last.travelled_m());
    [false, true].into_iter().all(|late| {
        let (mut driven, mut along) = ((f64::MAX, f64::MIN), (f64::MAX, f64::MIN));
        for r in window
            .iter()
            .filter(|r| (r.travelled_m() > middle_m) == late)
        {
            let (t, p) = (r.travelled_m(), r.point);
            let at = c * p.x + s * p.y;
            driven = (driven.0.min(t), driven.1.max(t));
            along = (along.0.min(at), along.1.max(at));
        }
        driven.1 <= driven.0 || along.1 - along.0 >= MIN_FOLLOW_M_PER_M * (driven.1 - driven.0)
    })
}

/// Whether `line` runs along the robot's `motion` (odometry, metres) within
/// [`AXIS_GATE_RAD`]. A sonar's echo comes from the foot of the perpendicular on the wall but is
/// laid on the beam's axis, so the readings of a robot driving at an angle to a wall draw a
/// line turned from it by (u·n)(1 − e·n) radians (u the motion, n the wall's normal, e the
/// beam's axis): only a wall passed alongside, or read square on, is drawn true. Approaching
/// a wall ahead, a sonar 10° off the robot's axis draws it about 5° off, within the axis gate.
///
/// ```
/// use sonarmap::geometry::Vec2;
/// use sonarmap::mapping::ext::rectilinear_heading::{along_motion, LineFit};
/// let line = |deg: f64| LineFit { direction_rad: deg.to_radians(), sigma_rad: 0.01, rms_m: 0.0, span_m: 2.0, readings: 10, read_at: Default::default() };
/// let forward = Vec2::new(2.0, 0.0);
/// assert!(along_motion(&line(183.0), &forward));
/// assert!(!along_motion(&line(85.0), &forward));
/// ```
pub fn along_motion(line: &LineFit, motion: &Vec2) -> bool {
    let motion_rad = motion.y.atan2(motion.x);
    let off = wrap_pi(line.direction_rad - motion_rad).rem_euclid(std::f64::consts::PI);
    off.min(std::f64::consts::PI - off) <= AXIS_GATE_RAD
}

/// The line that may set the map's axis: the first that spans nine tenths of `window_m`,
/// within [`AXIS_MAX_SIGMA_RAD`] (a noisier first line would tilt every later heading).
pub fn axis_line(lines: &HeadingLines, window_m: f64) -> Option<&LineFit> {
    lines
        .iter()
        .map(|(_, line)| line)
        .find(|line| line.span_m >= 0.9 * window_m && line.sigma_rad <= AXIS_MAX_SIGMA_RAD)
}

/// The smallest standard deviation of the axis the walls give (0.5°). The first confirmed
/// walls, a few metres of sonar pieces, may lie that far off the room's axis (0.8° on the
/// specular `desks-12` scene without drift); held tighter, the lines that disagree with
/// them are taken for a drift.
pub const MIN_WALLS_AXIS_SIGMA_RAD: f64 = 0.5 * std::f64::consts::PI / 180.0;

/// The map's axis as its `walls` (direction in radians, length in metres) show it, radians in
/// [0, 90°), with its standard deviation: the length-weighted mean of the directions modulo
/// 90° (the mean of 4θ), then again over the walls within [`AXIS_GATE_RAD`] of it. The
/// deviation is the walls' weighted spread over the root of their number. `None` until
/// the walls within the gate are `min_length_m` long in all.
///
/// ```
/// use sonarmap::mapping::ext::rectilinear_heading::walls_axis;
/// // Walls at 29° and 121° (1 m each, 1° either side of 30° modulo 90°) and a 0.5 m wall at
/// // 75° that the gate leaves out.
/// let walls = [(29f64.to_radians(), 1.0), (121f64.to_radians(), 1.0), (75f64.to_radians(), 0.5)];
/// let (axis, sigma) = walls_axis(&walls, 2.0).unwrap();
/// assert!((axis.to_degrees() - 30.0).abs() < 1e-9);
/// assert!((sigma.to_degrees() - 1.0 / 2f64.sqrt()).abs() < 1e-9);
/// assert_eq!(walls_axis(&walls[..1], 2.0), None);
/// // 0.2° either side: the spread says 0.14°, the floor 0.5°.
/// let walls = [(29.8f64.to_radians(), 1.0), (120.2f64.to_radians(), 1.0)];
/// assert!((walls_axis(&walls, 2.0).unwrap().1.to_degrees() - 0.5).abs() < 1e-9);
/// ```
pub fn walls_axis(walls: &[(f64, f64)], min_length_m: f64) -> Option<(f64, f64)> {
    let mean = |gate_around: Option<f64>| {
        let (mut x, mut y, mut length, mut count) = (0.0, 0.0, 0.0, 0usize);
        for &(direction, l) in walls {
            if gate_around
                .is_some_and(|axis| deviation_from_axes(direction, axis).abs() > AXIS_GATE_RAD)
            {
                continue;
            }
            x += l * (4.0 * direction).cos();
            y += l * (4.0 * direction).sin();
            length += l;
            count += 1;
        }
        (length > 0.0).then(|| ((y.atan2(x) / 4.0).rem_euclid(FRAC_PI_2), length, count))
    };
    let (rough, _, _) = mean(None)?;
    let (axis, length, count) = mean(Some(rough))?;
    if length < min_length_m {
        return None;
    }
    let spread2 = walls
        .iter()
        .filter(|(d, _)| deviation_from_axes(*d, axis).abs() <= AXIS_GATE_RAD)
        .map(|&(d, l)| l * deviation_from_axes(d, axis).powi(2))
        .sum::<f64>()
        / length;
    Some((
        axis,
        (spread2.sqrt() / (count as f64).sqrt()).max(MIN_WALLS_AXIS_SIGMA_RAD),
    ))
}

/// `direction_rad`'s deviation from the nearer of the axes `axis_rad` and `axis_rad` + 90°,
/// in (−45°, 45°].
///
/// ```
/// use sonarmap::mapping::ext::rectilinear_heading::deviation_from_axes;
/// let d = |a: f64, axis: f64| deviation_from_axes(a.to_radians(), axis.to_radians()).to_degrees();
/// assert!((d(92.0, 0.0) - 2.0).abs() < 1e-9);
/// assert!((d(-178.5, 0.0) - 1.5).abs() < 1e-9);
/// assert!((d(10.0, 88.0) - 12.0).abs() < 1e-9);
/// ```
pub fn deviation_from_axes(direction_rad: f64, axis_rad: f64) -> f64 {
    let d = wrap_pi(direction_rad - axis_rad).rem_euclid(FRAC_PI_2);
    if d > FRAC_PI_2 / 2.0 {
        d - FRAC_PI_2
    } else {
        d
    }
}

/// What the windows' lines say of the heading ([`axis_deviation`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AxisDeviation {
    /// The lines' mean deviation from the nearer axis, radians.
    pub deviation_rad: f64,
    /// Its standard deviation, radians.
    pub sigma_rad: f64,
    /// Whether a line beyond [`AXIS_GATE_RAD`] counted (a widened gate took it).
    pub beyond_axis_gate: bool,
    /// The lines' age, averaged with the same weights: the mean deviation observes the heading
    /// error of that long ago.
    pub age: LineAge,
}

/// The heading observation the windows' lines give: their deviations from the axes (each line
/// in the odometry's frame, with its age, turned into the map by the rotation its age expects),
/// those that count ([`counts_within`] `gate_rad`), averaged with weights 1/σ²; with their
/// standard deviation and mean age. Each reading stays in its window for as many steps as the
/// window holds readings, so a line's σ is widened by the root of its readings: over the steps
/// that reuse them, they say once what they know. `None` when no line counts.
pub fn axis_deviation(
    lines: impl Iterator<Item = (LineFit, LineAge)>,
    odometry_to_map_rad: impl Fn(LineAge) -> f64,
    axis_rad: f64,
    gate_rad: f64,
) -> Option<AxisDeviation> {
    let (mut sum, mut weight, mut beyond_axis_gate) = (0.0, 0.0, false);
    let (mut driven_m, mut turned_rad) = (0.0, 0.0);
    for (line, age) in lines {
        let d = deviation_from_axes(line.direction_rad + odometry_to_map_rad(age), axis_rad);
        if !counts_within(&line, d, gate_rad) {
            continue;
        }
        let w = 1.0 / (line.sigma_rad * line.sigma_rad * line.readings as f64);
        sum += d * w;
        weight += w;
        driven_m += age.driven_m * w;
        turned_rad += age.turned_rad * w;
        beyond_axis_gate |= d.abs() > AXIS_GATE_RAD;
    }
    (weight > 0.0).then(|| AxisDeviation {
        deviation_rad: sum / weight,
        sigma_rad: (1.0 / weight).sqrt(),
        beyond_axis_gate,
        age: LineAge {
            driven_m: driven_m / weight,
            turned_rad: turned_rad / weight,
        },
    })
}

/// Whether `line`, `deviation_rad` from the nearer axis, counts within `gate_rad`: within
/// [`AXIS_GATE_RAD`] any line does; beyond it, up to `gate_rad` (a gate widened while the
/// heading is uncertain), only a line of [`WIDE_GATE_MIN_READINGS`] or more.
///
/// ```
/// use sonarmap::mapping::ext::rectilinear_heading::{counts_within, LineFit};
/// let line = |readings| LineFit { direction_rad: 0.0, sigma_rad: 0.01, rms_m: 0.0, span_m: 2.0, readings, read_at: Default::default() };
/// let deg = |d: f64| d.to_radians();
/// assert!(counts_within(&line(6), deg(4.0), deg(5.0)));
/// assert!(!counts_within(&line(6), deg(8.0), deg(15.0)));
/// assert!(counts_within(&line(12), deg(-8.0), deg(15.0)));
/// assert!(!counts_within(&line(40), deg(16.0), deg(15.0)));
/// // A wall 25° or 45° off the axes never counts, the gate at its widest (20°).
/// use sonarmap::mapping::ext::rectilinear_heading::WIDE_GATE_MAX_RAD;
/// assert!(!counts_within(&line(40), deg(25.0), WIDE_GATE_MAX_RAD));
/// assert!(!counts_within(&line(40), deg(45.0), WIDE_GATE_MAX_RAD));
/// ```
pub fn counts_within(line: &LineFit, deviation_rad: f64, gate_rad: f64) -> bool {
    let off_rad = deviation_rad.abs();
    off_rad <= AXIS_GATE_RAD || (off_rad <= gate_rad && line.readings >= WIDE_GATE_MIN_READINGS)
}

#[cfg(test)]
mod tests;
