//! What each layer draws, in which style and order.

use super::*;

#[test]
fn discarded_reading_is_only_in_the_discarded_layer() {
    let f = fixture();
    let scene = build(&f, &ViewOptions::all(), true);
    let id = SceneId::Reading {
        snapshot: 1,
        sensor: 2,
    };
    let layers: Vec<Layer> = scene
        .primitives
        .iter()
        .filter(|p| p.id == id)
        .map(|p| p.layer)
        .collect();
    assert!(layers.contains(&Layer::Discarded));
    for l in &layers {
        assert!(
            matches!(l, Layer::Discarded | Layer::Beams),
            "discarded reading drawn in {l:?}"
        );
    }
    // The no-echo reading has no point: nothing but nothing.
    assert!(!scene.primitives.iter().any(|p| p.id
        == SceneId::Reading {
            snapshot: 1,
            sensor: 3
        }));
}

#[test]
fn kept_readings_are_blue_points_with_balls_and_previous_ones_red() {
    let f = fixture();
    let scene = build(&f, &ViewOptions::all(), true);
    let kept = SceneId::Reading {
        snapshot: 1,
        sensor: 0,
    };
    let roles: Vec<Role> = scene
        .primitives
        .iter()
        .filter(|p| p.id == kept)
        .map(|p| p.role)
        .collect();
    assert!(roles.contains(&Role::CurrentPoint) && roles.contains(&Role::Ball));
    let prev = scene
        .primitives
        .iter()
        .find(|p| {
            p.id == SceneId::Reading {
                snapshot: 0,
                sensor: 0,
            }
        })
        .unwrap();
    assert_eq!(prev.layer, Layer::PreviousSnapshot);
    assert_eq!(prev.style.fill, Some(palette::VERMILLION));
    let cur = scene
        .primitives
        .iter()
        .find(|p| p.role == Role::CurrentPoint)
        .unwrap();
    assert_eq!(cur.style.fill, Some(palette::BLUE));
}

#[test]
fn decision_links_carry_their_outcome_style() {
    let f = fixture();
    let scene = build(&f, &ViewOptions::all(), true);
    let link = |n: usize| {
        scene
            .primitives
            .iter()
            .find(|p| {
                p.id == SceneId::Decision {
                    new_segment: n,
                    existing: Some(0),
                } && matches!(p.shape, Shape::Segment { .. })
            })
            .unwrap()
    };
    assert_eq!(link(0).role, Role::DecisionMatch);
    assert_eq!(link(0).style, Role::DecisionMatch.style());
    assert_eq!(link(1).role, Role::DecisionFailed);
    assert_ne!(link(0).style.dash_px, link(1).style.dash_px);
    // The new face's own marker: a square in the new-face style at its mid-point.
    let own = scene
        .primitives
        .iter()
        .find(|p| {
            p.id == SceneId::Decision {
                new_segment: 1,
                existing: None,
            }
        })
        .unwrap();
    assert_eq!(own.role, Role::DecisionNewFace);
    assert_eq!(
        own.shape,
        Shape::Marker {
            at: Point::new(0.25, 1.5),
            shape: MarkerShape::Square
        }
    );
    // The link ends on the candidate (map before), at the foot of the perpendicular.
    assert_eq!(
        link(0).shape,
        Shape::Segment {
            a: Point::new(1.5, 0.0),
            b: Point::new(1.45, 0.0)
        }
    );
}

#[test]
fn legend_lists_only_what_is_drawn() {
    let f = fixture();
    let options = ViewOptions::all().with_layer(Layer::Balls, false);
    let scene = build(&f, &options, false);
    let legend = scene.legend();
    let roles: Vec<Role> = legend.iter().map(|e| e.role).collect();
    assert!(!roles.contains(&Role::Ball));
    assert!(
        !roles.contains(&Role::PreviousPoint),
        "no previous step given"
    );
    assert!(!roles.contains(&Role::DecisionExtension) && !roles.contains(&Role::DecisionDismissed));
    assert!(roles.contains(&Role::DecisionMatch) && roles.contains(&Role::DecisionNewFace));
    assert!(roles.contains(&Role::FloorPlan) && roles.contains(&Role::Corner));
    assert!(
        roles.windows(2).all(|w| w[0] < w[1]),
        "legend in role order, no duplicates"
    );
    assert!(!scene.layers_present().contains(Layer::Balls));
}

#[test]
fn layers_come_in_drawing_order_and_switch_off() {
    let f = fixture();
    let scene = build(&f, &ViewOptions::all(), true);
    assert!(scene
        .primitives
        .windows(2)
        .all(|w| w[0].layer <= w[1].layer));
    for layer in Layer::ALL {
        let off = build(&f, &ViewOptions::all().with_layer(layer, false), true);
        assert_eq!(off.layer(layer).count(), 0, "{layer:?}");
    }
    assert_eq!(build(&f, &ViewOptions::all(), true), scene, "deterministic");
    assert_eq!(scene.title, "Test <room> & co — snapshot 1");
}

#[test]
fn cluster_breaks_carry_the_gap_in_the_log_units() {
    let f = fixture();
    let scene = build(&f, &ViewOptions::all(), true);
    let texts: Vec<&str> = scene
        .layer(Layer::Clusters)
        .filter_map(|p| match &p.shape {
            Shape::Text { text, .. } => Some(text.as_str()),
            _ => None,
        })
        .collect();
    assert_eq!(texts, ["gap 2.1 m"]);
}
