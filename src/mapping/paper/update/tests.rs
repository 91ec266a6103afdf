//! Unit tests of `update.rs`.

use super::*;
use crate::mapping::model::map::ReadingRef;
use crate::mapping::model::trace::{EndOrigin, EndRole};
use crate::mapping::paper::support_points::*;
use crate::mapping::paper::update_geometry::*;
use proptest::prelude::*;

/// The specification: keep the most recent, then a stable sort by (position, reading).
fn merged_by_sorting(
    old: &[SupportPoint],
    new: &[SupportPoint],
    a: &EndPoint,
    b: &EndPoint,
    cap: usize,
) -> Vec<SupportPoint> {
    let mut all: Vec<SupportPoint> = old.iter().chain(new).copied().collect();
    let mut newest: Vec<ReadingRef> = all.iter().map(|q| q.reading).collect();
    newest.sort_unstable_by(|x, y| y.cmp(x));
    if let Some(&oldest) = cap.checked_sub(1).and_then(|i| newest.get(i)) {
        all.retain(|q| q.reading >= oldest);
    }
    let key = |q: &SupportPoint| projection_param(&q.point, &a.point, &b.point) + 0.0;
    all.sort_by(|x, y| key(x).total_cmp(&key(y)).then(x.reading.cmp(&y.reading)));
    all
}

fn support_points(xs: Vec<(i8, u8)>, first_snapshot: usize) -> Vec<SupportPoint> {
    xs.into_iter()
        .enumerate()
        .map(|(i, (x, sensor))| SupportPoint {
            // Few positions and readings, so that ties are common.
            point: Point::new(f64::from(x) / 8.0, 0.01 * f64::from(sensor)),
            range_m: 1.0,
            reading: ReadingRef::new(first_snapshot + i / 8, usize::from(sensor % 3)),
        })
        .collect()
}

proptest! {
    #[test]
    fn merging_support_points_or_lists_equals_keeping_the_newest_and_sorting(
        old in proptest::collection::vec((-8i8..8, 0u8..6), 0..400),
        new in proptest::collection::vec((-8i8..8, 0u8..6), 0..70),
        old_order in 0u8..3,
        new_order in 0u8..3,
        interleave in any::<bool>(),
        cap in prop_oneof![Just(0usize), Just(64), 1usize..80],
    ) {
        let (a, b) = (ep(-3.0, 0.0, 1.0), ep(3.0, 0.0, 1.0));
        // 0: as drawn, 1: along a→b, 2: against it.
        let arrange = |points: Vec<SupportPoint>, how: u8| match how {
            0 => points,
            1 => merged_by_sorting(&points, &[], &a, &b, 0),
            _ => merged_by_sorting(&points, &[], &a, &b, 0).into_iter().rev().collect(),
        };
        let old = arrange(support_points(old, 0), old_order);
        let new = arrange(
            support_points(new, if interleave { 3 } else { 100 }),
            new_order,
        );
        let expected = merged_by_sorting(&old, &new, &a, &b, cap);
        prop_assert_eq!(merge_support_points(&old, &new, &a, &b, cap), expected.clone());
        // The same points from the chunked list (several chunks past 128 points).
        let chunked = merge_support_list(&SupportList::from_vec(old), &new, &a, &b, cap);
        prop_assert_eq!(chunked.to_vec(), expected);
    }

    #[test]
    fn a_search_from_a_guess_finds_the_first_index_past_the_turn(
        high in 0usize..300,
        turn in 0usize..300,
        low in 0usize..300,
        guess in 0usize..400,
    ) {
        let (low, turn) = (low.min(high), turn.min(high));
        let found = partition_point_near(low, high, guess, |m| m < turn);
        prop_assert_eq!(found, turn.max(low));
    }
}

fn ep(x: f64, y: f64, d: f64) -> EndPoint {
    EndPoint {
        point: Point::new(x, y),
        range_m: d,
    }
}

fn role(g: &UpdateGeometry, o: EndOrigin) -> EndRole {
    g.fates.iter().find(|f| f.origin == o).unwrap().role
}

#[test]
fn figure_1_match_keeps_the_closer_ends_and_extends_to_a_projection() {
    // Existing (0,0)-(10,0) read at 60/40; new (-4,1)-(8,0.2) read at 50/45.
    // u_L = n_L? D(n_L)=50 vs D(e_L)=60 → n_L. u_R: D(e_R)=40 vs D(n_R)=45 → e_R.
    let e = [ep(0.0, 0.0, 60.0), ep(10.0, 0.0, 40.0)];
    let g = update_match(e, ep(-4.0, 1.0, 50.0), ep(8.0, 0.2, 45.0));
    assert_eq!(role(&g, EndOrigin::NewLeft), EndRole::Kept);
    assert_eq!(role(&g, EndOrigin::ExistingRight), EndRole::Kept);
    assert_eq!(role(&g, EndOrigin::ExistingLeft), EndRole::Projected);
    assert_eq!(role(&g, EndOrigin::NewRight), EndRole::Projected);
    assert!(!g.fallback_tls);
    // Both projections fall inside [u_L, u_R]: the result is u_L–u_R.
    assert_eq!(g.ends[0], ep(-4.0, 1.0, 50.0));
    assert_eq!(g.ends[1], ep(10.0, 0.0, 40.0));

    // Now e_L is far left but less confident: its projection extends the segment (Figure 1).
    let e = [ep(-10.0, 0.0, 80.0), ep(10.0, 0.0, 40.0)];
    let g = update_match(e, ep(-4.0, 1.0, 50.0), ep(8.0, 0.2, 45.0));
    // l_u: y = 1 - (x + 4)/14. Projection of (-10, 0) onto it.
    let dir = Point::new(10.0, 0.0) - Point::new(-4.0, 1.0);
    let t = (Point::new(-10.0, 0.0) - Point::new(-4.0, 1.0)).dot(&dir) / dir.norm_squared();
    let expect = Point::new(-4.0, 1.0) + dir * t;
    assert!((g.ends[0].point - expect).norm() < 1e-12);
    assert_eq!(
        g.ends[0].range_m, 80.0,
        "a projected end keeps its reading's range"
    );
    let f = g
        .fates
        .iter()
        .find(|f| f.origin == EndOrigin::ExistingLeft)
        .unwrap();
    assert!(f.is_end_after && f.role == EndRole::Projected);
}

#[test]
fn ties_keep_the_existing_end_point() {
    let e = [ep(0.0, 0.0, 50.0), ep(10.0, 0.0, 50.0)];
    let g = update_match(e, ep(1.0, 0.5, 50.0), ep(9.0, 0.5, 50.0));
    assert_eq!(role(&g, EndOrigin::ExistingLeft), EndRole::Kept);
    assert_eq!(role(&g, EndOrigin::ExistingRight), EndRole::Kept);
    assert_eq!(g.ends, e);
}

#[test]
fn figure_2_extension_keeps_the_middle_and_projects_the_weaker_outer_end() {
    // Existing (0,0)-(10,0) at 40/60; new (8,0.3)-(20,1) at 50/70; n_L inside l_e.
    // M = n_L (50 < 60). Outer: e_L 40 vs n_R 70 → e_L kept, n_R projected on e_L–M.
    let e = [ep(0.0, 0.0, 40.0), ep(10.0, 0.0, 60.0)];
    let g = update_extension(e, ep(8.0, 0.3, 50.0), ep(20.0, 1.0, 70.0), Side::Left);
    assert_eq!(role(&g, EndOrigin::NewLeft), EndRole::Middle);
    assert_eq!(role(&g, EndOrigin::ExistingRight), EndRole::Dropped);
    assert_eq!(role(&g, EndOrigin::ExistingLeft), EndRole::Kept);
    assert_eq!(role(&g, EndOrigin::NewRight), EndRole::Projected);
    assert_eq!(g.ends[0], ep(0.0, 0.0, 40.0));
    // Projection of (20, 1) on the line through (0,0) and (8, 0.3).
    let dir = Point::new(8.0, 0.3) - Point::new(0.0, 0.0);
    let t = Point::new(20.0, 1.0).coords.dot(&dir) / dir.norm_squared();
    assert!((g.ends[1].point - Point::from(dir * t)).norm() < 1e-12);
    assert_eq!(g.ends[1].range_m, 70.0);

    // Symmetric: n_R inside, the new outer end more confident than e_R.
    let g = update_extension(e, ep(-12.0, 0.5, 30.0), ep(2.0, 0.1, 45.0), Side::Right);
    // M = e_L (40 < 45); outer n_L (30) beats e_R (60): l_u through n_L and e_L.
    assert_eq!(role(&g, EndOrigin::ExistingLeft), EndRole::Middle);
    assert_eq!(role(&g, EndOrigin::NewLeft), EndRole::Kept);
    assert_eq!(role(&g, EndOrigin::ExistingRight), EndRole::Projected);
    assert_eq!(g.ends[0], ep(-12.0, 0.5, 30.0));
    assert_eq!(g.ends[1].range_m, 60.0);
}

#[test]
fn coinciding_defining_points_fall_back_to_total_least_squares() {
    let e = [ep(0.0, 0.0, 40.0), ep(10.0, 0.0, 40.0)];
    let g = update_extension(e, ep(0.0, 0.0, 30.0), ep(0.0, 0.0, 30.0), Side::Left);
    assert!(g.fallback_tls);
    assert!(g
        .ends
        .iter()
        .all(|e| e.point.x.is_finite() && e.point.y.is_finite()));
}
