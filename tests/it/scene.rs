//! Scene and SVG export, checked by pixels: every export is parsed by usvg and rendered by
//! resvg. A Blue-Room-like step (two snapshots 5 in apart, paper Figures 4–5) is built by hand.
//! Set `SONARMAP_SCENE_PNG=/tmp/scene.png` to keep the rendered Blue Room for eyes.

use resvg::tiny_skia::Pixmap;
use sonarmap::geometry::{distance_to_line, lerp, projection_param, Point, Pose};
use sonarmap::mapping::model::map::ReadingRef;
use sonarmap::mapping::model::trace::*;
use sonarmap::mapping::{EndPoint, Map, Segment, SegmentKind, StepTrace, SupportPoint};
use sonarmap::run::{FloorPlan, Run, Snapshot, Wall};
use sonarmap::scene::svg::{default_view, page_transform, to_svg};
use sonarmap::scene::{
    build_scene, palette, Layer, LayerSet, MarkerShape, Primitive, Role, Scene, SceneId,
    SceneInput, Shape, ViewOptions, ViewRect,
};
use sonarmap::sonar::{SensorLayout, SensorSpec};
use sonarmap::units::{inches, Units};

const XI_PCT: f64 = 3.0;
const T_GAP_IN: f64 = 42.0;

/// Parses and renders an SVG export; panics with the parser's message when it is invalid.
fn render(svg: &str) -> Pixmap {
    let opt = sonarmap::export::svg_options();
    let tree =
        usvg::Tree::from_str(svg, &opt).unwrap_or_else(|e| panic!("invalid SVG: {e}\n{svg}"));
    let size = tree.size().to_int_size();
    let mut pixmap = Pixmap::new(size.width(), size.height()).unwrap();
    resvg::render(
        &tree,
        resvg::tiny_skia::Transform::identity(),
        &mut pixmap.as_mut(),
    );
    pixmap
}

fn rgb(pixmap: &Pixmap, (x, y): (f64, f64)) -> [u8; 3] {
    let c = pixmap
        .pixel(x.round() as u32, y.round() as u32)
        .expect("pixel inside the image")
        .demultiply();
    [c.red(), c.green(), c.blue()]
}

fn is_background(c: [u8; 3]) -> bool {
    c.iter().all(|&v| v >= 250)
}

// ---------------------------------------------------------------- Blue Room fixture

fn ring() -> SensorLayout {
    SensorLayout::nomad_ring(inches(9.0))
}

fn walls() -> Vec<Wall> {
    let c = [(0.0, 0.0), (305.0, 0.0), (305.0, 154.0), (0.0, 154.0)];
    (0..4)
        .map(|i| {
            let (a, b) = (c[i], c[(i + 1) % 4]);
            Wall {
                a: Point::new(inches(a.0), inches(a.1)),
                b: Point::new(inches(b.0), inches(b.1)),
                roughness_rad: None,
            }
        })
        .collect()
}

/// Range on the beam axis of sensor `k` to the nearest wall (an ideal, non-specular sonar).
fn cast(pose: &Pose, k: usize) -> f64 {
    let s = ring().sensor_pose_in_world(pose, k);
    let (o, d) = (s.position(), sonarmap::geometry::unit(s.heading_rad));
    walls()
        .iter()
        .filter_map(|w| {
            let e = w.b - w.a;
            let denom = d.x * e.y - d.y * e.x;
            if denom.abs() < 1e-12 {
                return None;
            }
            let q = w.a - o;
            let t = (q.x * e.y - q.y * e.x) / denom;
            let u = (q.x * d.y - q.y * d.x) / denom;
            (t > 0.0 && (0.0..=1.0).contains(&u)).then_some(t)
        })
        .fold(f64::INFINITY, f64::min)
}

fn pose(k: usize) -> Pose {
    Pose::new(inches(120.0 + 5.0 * k as f64), inches(77.0), 0.0)
}

fn run() -> Run {
    let snapshots = (0..2)
        .map(|k| {
            let p = pose(k);
            let mut ranges_m: Vec<Option<f64>> = (0..16).map(|s| Some(cast(&p, s))).collect();
            ranges_m[6] = None; // no echo (specular)
            ranges_m[10] = Some(inches(255.0)); // the driver's "no echo"
            Snapshot {
                t: k as f64,
                pose: p,
                ranges_m,
                true_pose: None,
                reading_dt_s: Vec::new(),
            }
        })
        .collect();
    Run {
        name: "Blue Room, two snapshots 5 in apart".into(),
        units: Units::Inches,
        robot_radius_m: Some(inches(9.0)),
        layout: ring(),
        sensor: SensorSpec::default(),
        floor_plan: Some(FloorPlan {
            walls: walls(),
            circles: vec![],
        }),
        snapshots,
    }
}

/// Crowley's recursive end-point fit with the resolution tolerance: piece index pairs.
fn split(points: &[SupportPoint], first: usize, last: usize, out: &mut Vec<[usize; 2]>) {
    let (a, b) = (points[first].point, points[last].point);
    let worst = (first + 1..last)
        .map(|j| (j, distance_to_line(&points[j].point, &a, &b)))
        .fold(None, |acc: Option<(usize, f64)>, x| {
            if acc.is_none_or(|(_, d)| x.1 > d) {
                Some(x)
            } else {
                acc
            }
        });
    match worst {
        Some((j, d)) if d > XI_PCT * points[j].range_m / 100.0 => {
            split(points, first, j, out);
            split(points, j, last, out);
        }
        _ => out.push([first, last]),
    }
}

/// The step trace of snapshot `k` as the engine would give it (readings, clusters, fit).
/// Matching is filled in by [`match_step`].
fn perceive(run: &Run, k: usize) -> StepTrace {
    let snap = &run.snapshots[k];
    let max_m = run.sensor.max_range_m;
    let readings: Vec<ReadingTrace> = snap
        .ranges_m
        .iter()
        .enumerate()
        .map(|(sensor, r)| {
            let point = r.map(|d| run.layout.point_in_world(&snap.pose, sensor, d));
            let discarded = match r {
                None => Some(DiscardReason::NoEcho),
                Some(d) if *d >= max_m - 1e-12 => Some(DiscardReason::AtMaxRange),
                _ => None,
            };
            ReadingTrace {
                sensor,
                range_m: *r,
                point,
                ball_radius_m: r.map_or(0.0, |d| XI_PCT * d / 100.0),
                discarded,
                cluster: None,
                shorter_than_last: None,
            }
        })
        .collect();
    let kept: Vec<usize> = readings
        .iter()
        .filter(|r| r.discarded.is_none())
        .map(|r| r.sensor)
        .collect();
    let t_gap_m = inches(T_GAP_IN);
    let gaps: Vec<GapTrace> = (0..kept.len())
        .map(|i| {
            let (from_sensor, to_sensor) = (kept[i], kept[(i + 1) % kept.len()]);
            let distance_m =
                (readings[from_sensor].point.unwrap() - readings[to_sensor].point.unwrap()).norm();
            GapTrace {
                from_sensor,
                to_sensor,
                distance_m,
                t_gap_m,
                is_break: distance_m > t_gap_m,
                across_right_angle: false,
            }
        })
        .collect();
    // Clusters start after a break (the ring wraps).
    let start = gaps.iter().position(|g| g.is_break).map_or(0, |i| i + 1);
    let mut chains: Vec<Vec<usize>> = vec![vec![]];
    for i in 0..kept.len() {
        let j = (start + i) % kept.len();
        chains.last_mut().unwrap().push(kept[j]);
        if gaps[j].is_break {
            chains.push(vec![]);
        }
    }
    chains.retain(|c| !c.is_empty());
    let mut trace = StepTrace {
        snapshot: k,
        t: snap.t,
        pose: Some(snap.pose),
        readings,
        gaps,
        ..Default::default()
    };
    for (ci, sensors) in chains.into_iter().enumerate() {
        let fitted: Vec<SupportPoint> = sensors
            .iter()
            .map(|&s| SupportPoint {
                point: trace.readings[s].point.unwrap(),
                range_m: trace.readings[s].range_m.unwrap(),
                reading: ReadingRef::new(k, s),
            })
            .collect();
        for &s in &sensors {
            trace.readings[s].cluster = Some(ci);
        }
        let mut pieces = vec![];
        if fitted.len() >= 2 {
            split(&fitted, 0, fitted.len() - 1, &mut pieces);
        }
        let mut new_segments = vec![];
        for [a, b] in pieces {
            new_segments.push(trace.new_segments.len());
            let end = |i: usize| EndPoint {
                point: fitted[i].point,
                range_m: fitted[i].range_m,
            };
            trace.new_segments.push(NewSegmentTrace {
                source: SegmentSource::Cluster(ci),
                a: end(a),
                b: end(b),
                points: fitted[a..=b].to_vec(),
            });
        }
        trace.clusters.push(ClusterTrace {
            sensors,
            constant_depth: vec![],
            fitted,
            splits: vec![],
            new_segments,
        });
    }
    trace
}

fn segment_from(id: u32, n: &NewSegmentTrace, k: usize) -> Segment {
    Segment {
        id,
        kind: SegmentKind::Fitted,
        a: n.a,
        b: n.b,
        face: id,
        object: id,
        created: k,
        updated: vec![],
        points: n.points.clone().into(),
    }
}

/// A simplified §4–§5: each new segment against every map segment, nearest first.
fn match_step(trace: &mut StepTrace, before: &Map, k: usize) -> Map {
    let mut after = before.clone();
    for (i, n) in trace.new_segments.clone().iter().enumerate() {
        let m = nalgebra::center(&n.a.point, &n.b.point);
        let mut candidates: Vec<CandidateTrace> = before
            .segments
            .iter()
            .map(|e| {
                let (ea, eb) = (e.a.point, e.b.point);
                let angle =
                    sonarmap::geometry::line_angle_between(&(eb - ea), &(n.b.point - n.a.point));
                let t = projection_param(&m, &ea, &eb);
                let d1 = lerp(
                    &Point::new(e.a.range_m, 0.0),
                    &Point::new(e.b.range_m, 0.0),
                    t.clamp(0.0, 1.0),
                )
                .x;
                let col = Test::at_most(
                    distance_to_line(&m, &ea, &eb),
                    XI_PCT / 100.0 * (d1 + 0.5 * (n.a.range_m + n.b.range_m)),
                );
                let (pa, pb) = (
                    projection_param(&n.a.point, &ea, &eb),
                    projection_param(&n.b.point, &ea, &eb),
                );
                let inside = |p: f64| (0.0..=1.0).contains(&p);
                CandidateTrace {
                    distance_m: e.distance_to(&m),
                    outermost: true,
                    evaluation: PairEvaluation {
                        existing: e.id,
                        new_reversed: false,
                        new_left: n.a,
                        new_right: n.b,
                        orientation: Test::at_most(angle, 15f64.to_radians()),
                        colinearity: ColinearityTest {
                            test: col,
                            d1_m: d1,
                            d2_m: n.a.range_m,
                            d3_m: n.b.range_m,
                            foot_param: t.clamp(0.0, 1.0),
                        },
                        overlap: OverlapTest {
                            mid_param: t,
                            left_param: pa,
                            right_param: pb,
                            existing_on_new_params: [0.0, 1.0],
                            mpc: inside(t),
                            containment: false,
                            epc: inside(pa) != inside(pb),
                            epc_end: None,
                        },
                    },
                }
            })
            .filter(|c| c.distance_m < inches(60.0))
            .collect();
        candidates.sort_by(|a, b| a.distance_m.total_cmp(&b.distance_m));
        let hit = |f: &dyn Fn(&PairEvaluation) -> bool| {
            candidates
                .iter()
                .find(|c| f(&c.evaluation))
                .map(|c| c.evaluation.existing)
        };
        let (outcome, rule, existing) = if let Some(e) = hit(&|p| p.is_match()) {
            (Outcome::Match, Rule::MidPointOverlap, Some(e))
        } else if let Some(e) = hit(&|p| p.is_extension()) {
            (Outcome::Extension, Rule::EndPointOverlap, Some(e))
        } else if let Some(e) = hit(&|p| p.fails_only_orientation()) {
            (Outcome::Dismissed, Rule::OrientationOnlyFailure, Some(e))
        } else if candidates.is_empty() {
            (Outcome::NewFace, Rule::NoCandidates, None)
        } else {
            (Outcome::NewFace, Rule::NoCandidatePassed, None)
        };
        let result = match (outcome, existing) {
            (Outcome::Match | Outcome::Extension, Some(e)) => {
                let seg = after.segment_mut(e).unwrap();
                let before_ends = [seg.a, seg.b];
                // Keep the nearer (higher-confidence) end on each side, project the other.
                let (ea, eb) = (seg.a.point, seg.b.point);
                let (pa, pb) = (
                    projection_param(&n.a.point, &ea, &eb),
                    projection_param(&n.b.point, &ea, &eb),
                );
                let (lo, hi) = if pa < pb { (n.a, n.b) } else { (n.b, n.a) };
                let pick = |x: EndPoint, y: EndPoint| if y.range_m < x.range_m { y } else { x };
                let (ua, ub) = (pick(seg.a, lo), pick(seg.b, hi));
                let t_lo = projection_param(&lo.point, &ua.point, &ub.point).min(0.0);
                let t_hi = projection_param(&hi.point, &ua.point, &ub.point).max(1.0);
                let a = EndPoint {
                    point: lerp(&ua.point, &ub.point, t_lo),
                    range_m: ua.range_m,
                };
                let b = EndPoint {
                    point: lerp(&ua.point, &ub.point, t_hi),
                    range_m: ub.range_m,
                };
                seg.a = a;
                seg.b = b;
                seg.updated.push(k as u32);
                trace.updates.push(UpdateTrace {
                    segment: e,
                    new_segment: i,
                    outcome,
                    before: before_ends,
                    after: [a, b],
                    line: [ua.point, ub.point],
                    fates: vec![],
                    fallback_tls: false,
                    refit: None,
                    absorbed: Vec::new(),
                    support_in_order: None,
                });
                Some(e)
            }
            (Outcome::NewFace, _) => {
                let id = after.next_segment_id;
                after.next_segment_id += 1;
                after.push_segment(segment_from(id, n, k));
                Some(id)
            }
            _ => None,
        };
        trace.decisions.push(DecisionTrace {
            new_segment: i,
            mpc_stage: candidates,
            epc_stage: vec![],
            outcome,
            rule,
            existing,
            result,
        });
    }
    after
}

struct BlueRoom {
    run: Run,
    steps: Vec<StepTrace>,
    maps: Vec<Map>,
}

fn blue_room() -> BlueRoom {
    let run = run();
    let mut maps = vec![Map::default()];
    let mut steps = vec![];
    for k in 0..2 {
        let mut t = perceive(&run, k);
        let after = match_step(&mut t, &maps[k], k);
        steps.push(t);
        maps.push(after);
    }
    BlueRoom { run, steps, maps }
}

fn blue_room_scene(b: &BlueRoom, options: &ViewOptions) -> Scene {
    let input = SceneInput {
        run: &b.run,
        snapshot: 1,
        step: &b.steps[1],
        previous_step: Some(&b.steps[0]),
        map_before: &b.maps[1],
        map_after: &b.maps[2],
        truth: None,
        support_of: None,
        figure_labels: false,
        corrected_path: &[],
    };
    build_scene(&input, options)
}

// ---------------------------------------------------------------- tests

#[test]
fn blue_room_renders_with_every_layer() {
    let b = blue_room();
    let scene = blue_room_scene(&b, &ViewOptions::all());
    for layer in [
        Layer::FloorPlan,
        Layer::Map,
        Layer::CurrentPoints,
        Layer::PreviousSnapshot,
        Layer::Decisions,
        Layer::Discarded,
    ] {
        assert!(scene.layer(layer).count() > 0, "{layer:?} empty");
    }
    let view = default_view(&scene);
    let size = (1000, 620);
    let svg = to_svg(&scene, view, size, &scene.title, b.run.units);
    for layer in scene.layers_present().iter() {
        assert!(
            svg.contains(&format!(r#"<g id="{}">"#, layer.name())),
            "{layer:?}"
        );
    }
    assert!(svg.contains("Blue Room, two snapshots 5 in apart — snapshot 1"));
    let pixmap = render(&svg);
    if let Some(path) = std::env::var_os("SONARMAP_SCENE_PNG") {
        pixmap.save_png(path).unwrap();
    }
    // The robot's centre is inside its tinted body, a wall's mid-point is drawn.
    let tf = page_transform(&scene, view, size);
    assert!(!is_background(rgb(&pixmap, tf.px(&pose(1).position()))));
    assert!(!is_background(rgb(
        &pixmap,
        tf.px(&Point::new(inches(152.5), 0.0))
    )));
}

#[test]
fn ball_centre_is_coloured_and_disappears_with_its_layer() {
    let b = blue_room();
    let balls_only = ViewOptions {
        layers: LayerSet::empty().with(Layer::Balls, true),
        world_per_px: 0.0,
        visible_m: None,
    };
    let nothing = ViewOptions {
        layers: LayerSet::empty().with(Layer::Robot, true),
        world_per_px: 0.0,
        visible_m: None,
    };
    let with = blue_room_scene(&b, &balls_only);
    let without = blue_room_scene(&b, &nothing);
    // One fixed view so that both pages place the world alike.
    let view = ViewRect::new(
        Point::new(0.0, 0.0),
        Point::new(inches(305.0), inches(154.0)),
    )
    .expanded(inches(10.0));
    let size = (900, 520);
    let ball = with
        .layer(Layer::Balls)
        .find(|p| {
            p.id == SceneId::Reading {
                snapshot: 1,
                sensor: 4,
            }
        })
        .unwrap();
    let Shape::Circle { centre, radius_m } = ball.shape else {
        panic!("a ball is a circle")
    };
    assert!(radius_m > 0.0);
    let p_with = render(&to_svg(&with, view, size, "balls", Units::Inches));
    let p_without = render(&to_svg(&without, view, size, "no balls", Units::Inches));
    let at_with = page_transform(&with, view, size).px(&centre);
    let at_without = page_transform(&without, view, size).px(&centre);
    let c = rgb(&p_with, at_with);
    assert!(!is_background(c), "ball centre {c:?}");
    assert!(c[2] > c[0], "ball is blue-ish: {c:?}");
    assert!(
        is_background(rgb(&p_without, at_without)),
        "disabled layer drawn"
    );
}

/// Centroid of pixels close to `colour`.
fn centroid(pixmap: &Pixmap, colour: [u8; 3]) -> Option<(f64, f64)> {
    let (mut sx, mut sy, mut n) = (0.0, 0.0, 0.0);
    for y in 0..pixmap.height() {
        for x in 0..pixmap.width() {
            let c = rgb(pixmap, (f64::from(x), f64::from(y)));
            if c.iter().zip(colour).all(|(a, b)| a.abs_diff(b) <= 6) {
                sx += f64::from(x);
                sy += f64::from(y);
                n += 1.0;
            }
        }
    }
    (n > 0.0).then(|| (sx / n, sy / n))
}

#[test]
fn larger_world_y_is_higher_in_the_image() {
    let dot = |y: f64, role: Role| Primitive {
        layer: role.layer(),
        role,
        style: role.style().sized(14.0),
        id: SceneId::None,
        shape: Shape::Marker {
            at: Point::new(1.0, y),
            shape: MarkerShape::Dot,
        },
    };
    let scene = Scene {
        title: "y".into(),
        primitives: vec![dot(0.5, Role::PreviousPoint), dot(2.5, Role::CurrentPoint)],
        ..Scene::default()
    };
    let view = ViewRect::new(Point::new(0.0, 0.0), Point::new(2.0, 3.0));
    let pixmap = render(&to_svg(&scene, view, (600, 400), "y up", Units::Metres));
    let rgb_of = |c: sonarmap::scene::Rgba| [c.r, c.g, c.b];
    let low = centroid(&pixmap, rgb_of(palette::VERMILLION)).expect("low dot drawn");
    let high = centroid(&pixmap, rgb_of(palette::BLUE)).expect("high dot drawn");
    assert!(
        high.1 + 50.0 < low.1,
        "world y up must be image y down: high {high:?}, low {low:?}"
    );
}

#[test]
fn text_is_escaped_and_clipped_to_the_view() {
    let text = Primitive {
        layer: Layer::Labels,
        role: Role::Label,
        style: Role::Label.style(),
        id: SceneId::None,
        shape: Shape::Text {
            anchor: Point::new(0.5, 0.5),
            text: "a<b & \"c\"".into(),
            offset_px: [0.0, 0.0],
            align: sonarmap::scene::TextAlign::Start,
        },
    };
    let far = Primitive {
        layer: Layer::Map,
        role: Role::MapFitted,
        style: Role::MapFitted.style(),
        id: SceneId::MapSegment(0),
        shape: Shape::Segment {
            a: Point::new(-10.0, 5.0),
            b: Point::new(10.0, 5.0),
        },
    };
    let scene = Scene {
        title: "<&>".into(),
        primitives: vec![far, text],
        ..Scene::default()
    };
    let view = ViewRect::new(Point::new(0.0, 0.0), Point::new(1.0, 1.0));
    let svg = to_svg(&scene, view, (500, 400), "run <&> \"x\"", Units::Metres);
    assert!(svg.contains("a&lt;b &amp; &quot;c&quot;"));
    let pixmap = render(&svg);
    // The map line at y = 5 m lies above the view: clipped, it must not reach the title band.
    let tf = page_transform(&scene, view, (500, 400));
    let (x, _) = tf.px(&Point::new(0.5, 0.0));
    let y_line = tf.px(&Point::new(0.5, 5.0)).1;
    if y_line >= 0.0 {
        assert!(is_background(rgb(&pixmap, (x, y_line))));
    }
    for y in 0..(tf.origin_px.1 as u32).saturating_sub(1) {
        let c = rgb(&pixmap, (x, f64::from(y)));
        assert!(
            c != [0x00, 0x9e, 0x73],
            "map colour outside the view at y={y}"
        );
    }
}

#[test]
fn scale_bar_is_a_round_length_in_the_log_units() {
    let b = blue_room();
    let scene = blue_room_scene(&b, &ViewOptions::all());
    let svg = to_svg(&scene, default_view(&scene), (800, 500), "t", Units::Inches);
    let bar = &svg[svg.find(r#"<g id="scale-bar">"#).unwrap()..];
    let bar = &bar[..bar.find("</g>").unwrap()];
    assert!(
        ["1 in<", "2 in<", "5 in<", "10 in<", "20 in<", "50 in<", "100 in<", "200 in<"]
            .iter()
            .any(|s| bar.contains(s)),
        "{bar}"
    );
}
