//! The scene in a view: bounds and hit testing, level of detail, culling to the view
//! rectangle.

use super::*;

#[test]
fn bounds_and_hit_testing() {
    let f = fixture();
    let scene = build(&f, &ViewOptions::all(), true);
    let b = scene.bounds().unwrap();
    assert!(b.contains(&Point::new(2.0, 3.0)) && b.contains(&Point::new(-6.5, 0.0)));
    // On the new face's segment, away from other lines: the segment (or its label / decision).
    let hit = scene.hit(Point::new(0.4, 1.5), 0.02).unwrap();
    assert!(
        matches!(hit, SceneId::NewSegment(1) | SceneId::MapSegment(1)),
        "{hit:?}"
    );
    // Inside a ball but near nothing else: the reading.
    let only_balls = build(
        &f,
        &ViewOptions {
            layers: LayerSet::empty().with(Layer::Balls, true),
            world_per_px: 0.0,
            visible_m: None,
        },
        true,
    );
    assert_eq!(
        only_balls.hit(Point::new(0.01, 1.5), 0.005),
        Some(SceneId::Reading {
            snapshot: 1,
            sensor: 1
        })
    );
    assert_eq!(scene.hit(Point::new(-5.0, 5.0), 0.01), None);
}

#[test]
fn level_of_detail_drops_sub_pixel_balls() {
    let f = fixture();
    let coarse = ViewOptions {
        world_per_px: 0.1,
        ..ViewOptions::all()
    };
    assert_eq!(build(&f, &coarse, true).layer(Layer::Balls).count(), 0);
    assert_eq!(
        build(&f, &ViewOptions::all(), true)
            .layer(Layer::Balls)
            .count(),
        2
    );
}

#[test]
fn map_before_shows_only_what_the_step_changed_under_the_map() {
    let mut f = fixture();
    // Segment 0 moved this step; segment 7 did not.
    let still = seg(7, (-1.0, -1.0), (-1.0, 1.0));
    f.before = Map::from_segments(vec![seg(0, (1.45, -0.3), (1.45, 0.3)), still.clone()]);
    f.after = Map::from_segments(vec![seg(0, (1.5, -0.4), (1.5, 0.4)), still]);
    let ids = |s: &Scene| -> Vec<SceneId> { s.layer(Layer::MapBefore).map(|p| p.id).collect() };
    let scene = build(&f, &ViewOptions::all(), true);
    assert_eq!(ids(&scene), vec![SceneId::MapSegment(0)]);
    // Without the map on top, the whole map before is drawn.
    let scene = build(&f, &ViewOptions::all().with_layer(Layer::Map, false), true);
    assert_eq!(
        ids(&scene),
        vec![SceneId::MapSegment(0), SceneId::MapSegment(7)]
    );
}

#[test]
fn zoomed_out_copies_of_a_segment_its_dots_and_labels_are_drawn_once() {
    let mut f = fixture();
    // Fifty copies of one wall, 0.2 mm apart.
    f.after = Map::from_segments(
        (0..50)
            .map(|i| seg(i, (1.0 + 0.0002 * f64::from(i), -1.0), (1.0, 1.0)))
            .collect(),
    );
    let zoomed_out = ViewOptions {
        world_per_px: 0.01,
        ..ViewOptions::all()
    };
    let scene = build(&f, &zoomed_out, true);
    let dots = scene
        .layer(Layer::Map)
        .filter(|p| p.role == Role::MapEndPoint)
        .count();
    assert_eq!(dots, 2, "one dot per end at 1 cm per pixel");
    let lines = scene
        .layer(Layer::Map)
        .filter(|p| p.role == Role::MapFitted)
        .count();
    assert_eq!(lines, 1, "the copies coincide on screen");
    let labels = scene
        .layer(Layer::Labels)
        .filter(|p| matches!(p.id, SceneId::MapSegment(_)))
        .count();
    assert_eq!(labels, 1);
    let close_up = build(&f, &ViewOptions::all(), true);
    assert_eq!(
        close_up
            .layer(Layer::Map)
            .filter(|p| p.role == Role::MapEndPoint)
            .count(),
        100
    );
}

#[test]
fn a_view_rectangle_keeps_only_the_map_segments_that_meet_it() {
    let mut f = fixture();
    // A wall inside the view, one crossing its edge, one outside; the step moved the outside one.
    let inside = seg(0, (0.0, 0.0), (1.0, 0.0));
    let crossing = seg(1, (1.5, -1.0), (3.0, -1.0));
    f.before = Map::from_segments(vec![
        inside.clone(),
        crossing.clone(),
        seg(2, (5.0, 5.0), (6.0, 5.0)),
    ]);
    f.after = Map::from_segments(vec![inside, crossing, seg(2, (5.0, 5.1), (6.0, 5.1))]);
    let view = ViewOptions {
        visible_m: Some([-1.0, -2.0, 2.0, 2.0]),
        ..ViewOptions::all()
    };
    let ids = |s: &Scene, layer| -> Vec<SceneId> { s.layer(layer).map(|p| p.id).collect() };
    let culled = build(&f, &view, true);
    let map: Vec<SceneId> = culled
        .layer(Layer::Map)
        .filter(|p| p.role == Role::MapFitted)
        .map(|p| p.id)
        .collect();
    assert_eq!(map, [SceneId::MapSegment(0), SceneId::MapSegment(1)]);
    assert!(
        ids(&culled, Layer::MapBefore).is_empty(),
        "the moved one is out of view"
    );
    assert!(!ids(&culled, Layer::Labels).contains(&SceneId::MapSegment(2)));
    let whole = build(&f, &ViewOptions::all(), true);
    assert_eq!(ids(&whole, Layer::MapBefore), [SceneId::MapSegment(2)]);
    // The bounds (and Fit) still take in what was left out.
    let map_only = LayerSet::empty().with(Layer::Map, true);
    assert_eq!(culled.bounds_of(map_only), whole.bounds_of(map_only));
    assert_eq!(
        culled.bounds_of(map_only).unwrap().max,
        Point::new(6.0, 5.1),
        "segment 2 after the step"
    );
}

#[test]
fn zoomed_out_a_path_over_the_same_ground_is_drawn_once_and_whole_without_a_view() {
    let mut f = fixture();
    // Out to 1 m and back in 10 cm steps, three times.
    let lap: Vec<f64> = (0..=10)
        .chain((1..10).rev())
        .map(|i| 0.1 * f64::from(i))
        .collect();
    f.run.snapshots = (lap.iter().cycle().take(3 * lap.len()).enumerate())
        .map(|(i, &x)| Snapshot {
            t: i as f64,
            pose: Pose::new(x, 0.0, 0.0),
            ranges_m: vec![None; 4],
            true_pose: None,
            reading_dt_s: Vec::new(),
        })
        .collect();
    let input = SceneInput {
        run: &f.run,
        snapshot: f.run.snapshots.len() - 1,
        step: &f.step,
        previous_step: None,
        map_before: &f.before,
        map_after: &f.after,
        truth: None,
        support_of: None,
        figure_labels: false,
        corrected_path: &[],
    };
    let path = |options: &ViewOptions| -> Vec<Vec<Point>> {
        (build_scene(&input, options).layer(Layer::Robot))
            .filter(|p| p.role == Role::RobotPath)
            .map(|p| match &p.shape {
                Shape::Polyline { points, .. } => points.clone(),
                other => panic!("the path is a polyline, not {other:?}"),
            })
            .collect()
    };
    let whole = path(&ViewOptions::all());
    let poses: Vec<Point> = f.run.snapshots.iter().map(|s| s.pose.position()).collect();
    assert_eq!(whole, vec![poses]);
    let zoomed_out = path(&ViewOptions {
        world_per_px: 0.01,
        ..ViewOptions::all()
    });
    let out: Vec<Point> = (0..=10)
        .map(|i| Point::new(0.1 * f64::from(i), 0.0))
        .collect();
    assert_eq!(zoomed_out, vec![out], "the first way out only");
}
