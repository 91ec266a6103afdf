//! Generated families of scenes for property tests and the soak: rooms, rotated rooms,
//! L-shaped rooms, corridors with doors, rooms with pillars, rooms with an acute corner and
//! rooms with desks, each with a closed lap inside it, a sensor layout and simulator noise
//! drawn from a seed. A lap ends where it starts, so repeating its snapshots
//! ([`repeat_laps`]) is a robot patrolling the same walls for as long as asked.

use super::plan::{interpolate_path, Plan, SimSettings};
use crate::geometry::{Point, Pose};
use crate::run::{Circle, FloorPlan, Run, Snapshot, Wall};
use crate::sonar::{SensorLayout, SensorSpec};
use crate::units::{inches, Units};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::f64::consts::{PI, TAU};

/// The kinds of scene a family draws from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SceneKind {
    /// A rectangular room (rotated by a random angle, as every kind is).
    Room,
    /// An L-shaped room.
    LRoom,
    /// A corridor with doors into rooms on one side.
    CorridorWithDoors,
    /// A rectangular room with round pillars.
    Pillars,
    /// A room with one acute and one obtuse corner (a trapezoid).
    AcuteCorner,
    /// A rectangular room with rectangular desks.
    Desks,
}

impl SceneKind {
    /// Every kind, in a fixed order.
    pub const ALL: [SceneKind; 6] = [
        SceneKind::Room,
        SceneKind::LRoom,
        SceneKind::CorridorWithDoors,
        SceneKind::Pillars,
        SceneKind::AcuteCorner,
        SceneKind::Desks,
    ];

    /// A short name for reports.
    pub fn name(self) -> &'static str {
        match self {
            SceneKind::Room => "room",
            SceneKind::LRoom => "l-room",
            SceneKind::CorridorWithDoors => "corridor",
            SceneKind::Pillars => "pillars",
            SceneKind::AcuteCorner => "acute",
            SceneKind::Desks => "desks",
        }
    }
}

fn wall(a: (f64, f64), b: (f64, f64)) -> Wall {
    Wall {
        a: Point::new(a.0, a.1),
        b: Point::new(b.0, b.1),
        roughness_rad: None,
    }
}

/// Walls round a closed polygon.
fn polygon(corners: &[(f64, f64)]) -> Vec<Wall> {
    (0..corners.len())
        .map(|i| wall(corners[i], corners[(i + 1) % corners.len()]))
        .collect()
}

/// The walls, pillars and lap (closed loop of points, the robot facing along it) of a scene
/// before it is rotated, metres.
struct Layout {
    walls: Vec<Wall>,
    circles: Vec<Circle>,
    lap: Vec<(f64, f64)>,
}

fn room(rng: &mut ChaCha8Rng) -> Layout {
    let (w, h) = (rng.random_range(3.0..9.0), rng.random_range(2.5..7.0));
    let m = rng.random_range(0.6..1.0f64).min(h / 3.0);
    Layout {
        walls: polygon(&[(0.0, 0.0), (w, 0.0), (w, h), (0.0, h)]),
        circles: Vec::new(),
        lap: vec![(m, m), (w - m, m), (w - m, h - m), (m, h - m)],
    }
}

fn l_room(rng: &mut ChaCha8Rng) -> Layout {
    let (w, h) = (rng.random_range(5.0..10.0), rng.random_range(5.0..9.0));
    let (arm_x, arm_y): (f64, f64) = (
        rng.random_range(2.0..w / 2.0),
        rng.random_range(2.0..h / 2.0),
    );
    let m = arm_x.min(arm_y) / 2.0;
    Layout {
        walls: polygon(&[
            (0.0, 0.0),
            (w, 0.0),
            (w, arm_y),
            (arm_x, arm_y),
            (arm_x, h),
            (0.0, h),
        ]),
        circles: Vec::new(),
        lap: vec![(m, m), (w - m, m), (m, m), (m, h - m)],
    }
}

fn corridor(rng: &mut ChaCha8Rng) -> Layout {
    let doors = rng.random_range(1..=3usize);
    let (width, room_d) = (rng.random_range(1.4..2.6), rng.random_range(2.0..4.0));
    let room_w = rng.random_range(2.5..4.5);
    let door = rng.random_range(0.8..1.2);
    let length = doors as f64 * room_w + rng.random_range(1.0..3.0);
    let mut walls = vec![
        wall((0.0, 0.0), (length, 0.0)),
        wall((length, 0.0), (length, width)),
        wall((0.0, width), (0.0, 0.0)),
    ];
    // The upper wall, broken by a door into each room.
    let mut x = 0.0;
    for i in 0..doors {
        let (x0, x1) = (0.5 + i as f64 * room_w, 0.5 + (i + 1) as f64 * room_w);
        let door_x = (x0 + x1) / 2.0 - door / 2.0;
        walls.push(wall((x, width), (door_x, width)));
        x = door_x + door;
        walls.push(wall((x0, width), (x0, width + room_d)));
        walls.push(wall((x0, width + room_d), (x1, width + room_d)));
        walls.push(wall((x1, width + room_d), (x1, width)));
    }
    walls.push(wall((x, width), (length, width)));
    let y = width / 2.0;
    Layout {
        walls,
        circles: Vec::new(),
        lap: vec![(0.6, y), (length - 0.6, y)],
    }
}

fn pillars(rng: &mut ChaCha8Rng) -> Layout {
    let mut layout = room(rng);
    let corners = &layout.lap;
    let (w, h) = (corners[1].0 - corners[0].0, corners[2].1 - corners[1].1);
    let (x0, y0) = corners[0];
    for _ in 0..rng.random_range(1..=3) {
        layout.circles.push(Circle {
            centre: Point::new(
                x0 + w * rng.random_range(0.3..0.7),
                y0 + h * rng.random_range(0.3..0.7),
            ),
            radius_m: rng.random_range(0.1..0.3f64).min(w.min(h) / 4.0),
        });
    }
    layout
}

fn acute_corner(rng: &mut ChaCha8Rng) -> Layout {
    // A trapezoid whose left wall leans in: an acute corner at the bottom left.
    let (w, h) = (rng.random_range(5.0..9.0), rng.random_range(3.0..6.0));
    let lean = h / rng
        .random_range(30f64.to_radians()..70f64.to_radians())
        .tan();
    let m = 0.8;
    Layout {
        walls: polygon(&[(0.0, 0.0), (w + lean, 0.0), (w + lean, h), (lean, h)]),
        circles: Vec::new(),
        lap: vec![
            (lean * 0.5 + 2.0 * m, m),
            (w + lean - m, m),
            (w + lean - m, h - m),
            (lean + m, h - m),
        ],
    }
}

fn desks(rng: &mut ChaCha8Rng) -> Layout {
    let (w, h) = (rng.random_range(6.0..10.0), rng.random_range(5.0..8.0));
    let mut walls = polygon(&[(0.0, 0.0), (w, 0.0), (w, h), (0.0, h)]);
    // Desks in the middle band, clear of the lap one metre in from the walls.
    let count = rng.random_range(1..=2usize);
    for i in 0..count {
        let band = (w - 4.0) / count as f64;
        let dx = 2.0 + i as f64 * band + rng.random_range(0.0..band * 0.3);
        let (dw, dh) = (band * 0.5, rng.random_range(0.6..(h - 4.0).max(0.7)));
        let dy = (h - dh) / 2.0;
        walls.extend(polygon(&[
            (dx, dy),
            (dx + dw, dy),
            (dx + dw, dy + dh),
            (dx, dy + dh),
        ]));
    }
    Layout {
        walls,
        circles: Vec::new(),
        lap: vec![
            (1.0, 1.0),
            (w - 1.0, 1.0),
            (w - 1.0, h - 1.0),
            (1.0, h - 1.0),
        ],
    }
}

/// A scene of `kind` drawn from `seed`: walls rotated by a random angle, a random sensor
/// layout (16-sonar Nomad ring, 8 or 24 in a ring, or 8 facing forwards only), random wall
/// roughness, dropouts and ghost echoes, and one closed lap at most 8 in a step.
pub fn family_plan(kind: SceneKind, seed: u64) -> Plan {
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ (kind as u64) << 56);
    let layout = match kind {
        SceneKind::Room => room(&mut rng),
        SceneKind::LRoom => l_room(&mut rng),
        SceneKind::CorridorWithDoors => corridor(&mut rng),
        SceneKind::Pillars => pillars(&mut rng),
        SceneKind::AcuteCorner => acute_corner(&mut rng),
        SceneKind::Desks => desks(&mut rng),
    };
    let turn = if kind == SceneKind::Room || rng.random_bool(0.5) {
        rng.random_range(0.0..TAU)
    } else {
        0.0
    };
    let offset = (rng.random_range(-20.0..20.0), rng.random_range(-20.0..20.0));
    let (sin, cos) = turn.sin_cos();
    let place =
        |(x, y): (f64, f64)| Point::new(x * cos - y * sin + offset.0, x * sin + y * cos + offset.1);
    let walls = layout
        .walls
        .iter()
        .map(|w| Wall {
            a: place((w.a.x, w.a.y)),
            b: place((w.b.x, w.b.y)),
            roughness_rad: None,
        })
        .collect();
    let circles = layout
        .circles
        .iter()
        .map(|c| Circle {
            centre: place((c.centre.x, c.centre.y)),
            radius_m: c.radius_m,
        })
        .collect();
    // The lap: each leg driven facing along it, turning on the spot at the corners, back to
    // the start.
    let lap: Vec<Point> = layout.lap.iter().map(|&p| place(p)).collect();
    let mut waypoints = Vec::new();
    for i in 0..lap.len() {
        let (a, b) = (lap[i], lap[(i + 1) % lap.len()]);
        let heading = (b.y - a.y).atan2(b.x - a.x);
        waypoints.push(Pose::new(a.x, a.y, heading));
        waypoints.push(Pose::new(b.x, b.y, heading));
    }
    waypoints.push(waypoints[0]);
    let poses = interpolate_path(&waypoints, Some(inches(8.0)), Some(20f64.to_radians()));
    let radius_m = inches(9.0);
    let sensors = match rng.random_range(0..4) {
        0 => SensorLayout::nomad_ring(radius_m),
        1 => SensorLayout::ring(8, PI / 4.0, 0.0, radius_m),
        2 => SensorLayout::ring(24, TAU / 24.0, 0.0, radius_m),
        _ => SensorLayout::ring(8, 20f64.to_radians(), -70f64.to_radians(), radius_m),
    };
    Plan {
        name: format!("{} (generated, seed {seed})", kind.name()),
        note: None,
        units: Units::Metres,
        floor_plan: FloorPlan { walls, circles },
        roughness_rad: rng.random_range(5f64..35.0).to_radians(),
        robot_radius_m: Some(radius_m),
        layout: sensors,
        sensor: SensorSpec::default(),
        poses,
        sim: SimSettings {
            dropout: rng.random_range(0.0..0.1),
            ghost: rng.random_range(0.0..0.05),
            ray_step_rad: 2.5f64.to_radians(),
            ..SimSettings::default()
        },
    }
}

/// `run` with its snapshots repeated, lap after lap, to `snapshots` in all (`t` counts
/// snapshots), as a robot patrolling the same walls would record them.
pub fn repeat_laps(run: &Run, snapshots: usize) -> Run {
    let lap = &run.snapshots;
    let mut long = run.clone();
    long.snapshots = if lap.is_empty() {
        Vec::new()
    } else {
        (0..snapshots)
            .map(|i| Snapshot {
                t: i as f64,
                ..lap[i % lap.len()].clone()
            })
            .collect()
    };
    long
}
