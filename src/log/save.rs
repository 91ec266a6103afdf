//! Writing a run back as a `sonarmap-log` v1 file in the run's units.

use super::file::{
    FloorPlanFile, LogFile, MountFile, PoseFile, RingFile, RobotFile, SensorFile, SnapshotFile,
    SonarsFile, LOG_FORMAT,
};
use crate::run::{FloorPlan, Run, Snapshot};
use crate::sonar::{EchoModel, SensorLayout};
use crate::units::Units;
use std::io::Write;

/// Rounds a value converted from metres to 12 significant decimal places below the unit, so
/// that `48.2 in → m → in` is written `48.2` again (the difference is far below any
/// instrument's resolution). Very large values are kept as they are.
pub(crate) fn tidy(v: f64) -> f64 {
    if v.is_finite() && v.abs() < 1.0e6 {
        let r = (v * 1.0e9).round() / 1.0e9;
        if r == 0.0 {
            0.0
        } else {
            r
        }
    } else {
        v
    }
}

/// A length in metres as a tidy number in `units`.
fn len(units: Units, v_m: f64) -> f64 {
    tidy(units.from_m(v_m))
}

/// An angle in radians as tidy degrees.
fn deg(v_rad: f64) -> f64 {
    tidy(v_rad.to_degrees())
}

/// The ring parameters `(count, spacing_rad, first_rad)` when `layout` is exactly
/// `SensorLayout::ring(count, spacing, first, radius_m)`.
pub fn ring_parameters(layout: &SensorLayout, radius_m: f64) -> Option<(usize, f64, f64)> {
    let n = layout.len();
    let first = layout.mounts.first()?.heading_rad;
    let spacing = if n > 1 {
        layout.mounts[1].heading_rad - first
    } else {
        0.0
    };
    let ring = SensorLayout::ring(n, spacing, first, radius_m);
    let scale = radius_m.abs().max(1e-3);
    let same = ring.mounts.iter().zip(&layout.mounts).all(|(a, b)| {
        (a.x_m - b.x_m).abs() <= 1e-9 * scale
            && (a.y_m - b.y_m).abs() <= 1e-9 * scale
            && (a.heading_rad - b.heading_rad).abs() <= 1e-9
    });
    same.then_some((n, spacing, first))
}

/// The robot block of a layout, in `units` (ring shorthand when the layout is a ring of the
/// robot's radius).
pub(crate) fn robot_to_file(
    layout: &SensorLayout,
    radius_m: Option<f64>,
    units: Units,
) -> RobotFile {
    let sonars = match radius_m.and_then(|r| ring_parameters(layout, r)) {
        Some((count, spacing, first)) => SonarsFile::Ring(RingFile {
            count: count as f64,
            spacing_deg: deg(spacing),
            first_deg: Some(deg(first)),
        }),
        None => SonarsFile::Mounts(
            layout
                .mounts
                .iter()
                .map(|m| MountFile {
                    x: len(units, m.x_m),
                    y: len(units, m.y_m),
                    heading_deg: deg(m.heading_rad),
                })
                .collect(),
        ),
    };
    RobotFile {
        radius: radius_m.map(|r| len(units, r)),
        sonars,
    }
}

/// A floor plan as file walls and circles, in `units`.
pub(crate) fn floor_plan_to_file(plan: &FloorPlan, units: Units) -> FloorPlanFile {
    FloorPlanFile {
        walls: plan
            .walls
            .iter()
            .map(|w| {
                let mut v = vec![
                    len(units, w.a.x),
                    len(units, w.a.y),
                    len(units, w.b.x),
                    len(units, w.b.y),
                ];
                if let Some(r) = w.roughness_rad {
                    v.push(deg(r));
                }
                v
            })
            .collect(),
        circles: plan
            .circles
            .iter()
            .map(|c| {
                vec![
                    len(units, c.centre.x),
                    len(units, c.centre.y),
                    len(units, c.radius_m),
                ]
            })
            .collect(),
    }
}

/// The file form of a run, lengths in the run's units.
pub fn run_to_file(run: &Run) -> LogFile {
    let mut file = head_to_file(run);
    file.snapshots = run
        .snapshots
        .iter()
        .map(|s| snapshot_to_file(s, run.units))
        .collect();
    file
}

/// The file form of a run without its snapshots.
fn head_to_file(run: &Run) -> LogFile {
    let u = run.units;
    LogFile {
        format: LOG_FORMAT.to_string(),
        version: 1.into(),
        name: Some(run.name.clone()),
        units: u.symbol().to_string(),
        robot: robot_to_file(&run.layout, run.robot_radius_m, u),
        sensor: Some(SensorFile {
            accuracy_pct: Some(tidy(run.sensor.accuracy_pct)),
            beam_width_deg: Some(deg(run.sensor.beam_width_rad)),
            max_range: Some(len(u, run.sensor.max_range_m)),
            min_range: Some(len(u, run.sensor.min_range_m)),
            echo: (run.sensor.echo != EchoModel::Cone).then_some(run.sensor.echo),
        }),
        floor_plan: run.floor_plan.as_ref().map(|p| floor_plan_to_file(p, u)),
        snapshots: Vec::new(),
    }
}

fn snapshot_to_file(s: &Snapshot, u: Units) -> SnapshotFile {
    SnapshotFile {
        t: Some(s.t),
        pose: PoseFile {
            x: len(u, s.pose.x),
            y: len(u, s.pose.y),
            heading_deg: deg(s.pose.heading_rad),
        },
        ranges: s.ranges_m.iter().map(|r| r.map(|v| len(u, v))).collect(),
        true_pose: s.true_pose.map(|p| PoseFile {
            x: len(u, p.x),
            y: len(u, p.y),
            heading_deg: deg(p.heading_rad),
        }),
        reading_dt_s: s.reading_dt_s.clone(),
    }
}

/// Writes a run as a `sonarmap-log` v1 file in its units: the header, robot and sensor blocks
/// first, then one line per snapshot (diff-friendly). `load_run(save_run(run))` gives the run
/// back to within 1e-9 of a unit.
pub fn save_run(run: &Run) -> String {
    let mut out = Vec::new();
    write_run(run, &mut out).expect("writing to memory does not fail");
    String::from_utf8(out).expect("JSON is UTF-8")
}

/// [`save_run`] to a writer, one snapshot at a time: the file form of the whole run is never
/// held in memory (for a run of millions of readings it was as large as the run itself).
pub fn write_run<W: Write>(run: &Run, w: &mut W) -> std::io::Result<()> {
    let mut head = head_to_file(run);
    let floor_plan = head.floor_plan.take();
    let mut text = serde_json::to_string_pretty(&head).expect("a log file serialises");
    // Replace the empty snapshot list with the floor plan (one wall a line) and one snapshot
    // a line (diff-friendly).
    let empty = "\"snapshots\": []";
    let at = text.rfind(empty).expect("the snapshots key is written");
    text.truncate(at);
    if let Some(plan) = &floor_plan {
        let rows = |rows: &[Vec<f64>]| {
            let lines: Vec<String> = rows
                .iter()
                .map(|r| {
                    format!(
                        "      {}",
                        serde_json::to_string(r).expect("numbers serialise")
                    )
                })
                .collect();
            format!("[\n{}\n    ]", lines.join(",\n"))
        };
        text.push_str("\"floor_plan\": {\n    \"walls\": ");
        text.push_str(&rows(&plan.walls));
        if !plan.circles.is_empty() {
            text.push_str(",\n    \"circles\": ");
            text.push_str(&rows(&plan.circles));
        }
        text.push_str("\n  },\n  ");
    }
    text.push_str("\"snapshots\": [\n");
    w.write_all(text.as_bytes())?;
    let n = run.snapshots.len();
    for (i, s) in run.snapshots.iter().enumerate() {
        w.write_all(b"    ")?;
        serde_json::to_writer(&mut *w, &snapshot_to_file(s, run.units))
            .map_err(std::io::Error::other)?;
        if i + 1 < n {
            w.write_all(b",")?;
        }
        w.write_all(b"\n")?;
    }
    w.write_all(b"  ]\n}\n")
}
