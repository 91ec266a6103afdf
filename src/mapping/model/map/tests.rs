//! Unit tests of `map.rs`.

use super::*;

fn segment(id: SegmentId) -> Segment {
    test_wall(id, (0.0, f64::from(id)), (1.0, f64::from(id)), 1.0)
}

#[test]
fn lookups_find_every_segment_through_many_removals_and_pushes() {
    let mut map = Map::from_segments((0..200).map(segment).collect());
    let mut present: Vec<SegmentId> = (0..200).collect();
    let mut next = 200;
    // Remove every third segment from the front half, push a new one now and then, and
    // check every id after each change against a plain search.
    for round in 0..60 {
        let victim = present[(round * 3) % (present.len() / 2)];
        map.remove_segment(victim);
        present.retain(|&id| id != victim);
        if round % 4 == 0 {
            map.next_segment_id = next + 1;
            map.push_segment(segment(next));
            present.push(next);
            next += 1;
        }
        for id in 0..next {
            let expected = present.binary_search(&id).ok();
            assert_eq!(map.position(id), expected, "id {id} after round {round}");
            assert_eq!(map.segment(id).map(|s| s.id), expected.map(|_| id));
        }
    }
    assert_eq!(map.segments.len(), present.len());
}

#[test]
fn the_laps_driven_are_the_distance_over_the_larger_of_the_walls_and_the_paths_perimeters() {
    use crate::mapping::model::plane_supports::{PlaneSupport, CONFIRMING_SNAPSHOTS};
    // Walls along two sides of a 4 m × 2 m room (perimeter 12 m) confirmed, a tentative one
    // outside it and a confirmed connecting segment outside it; 30 m driven: 2.5 laps.
    let connecting = Segment {
        kind: SegmentKind::Interpolated,
        ..test_wall(3, (-5.0, -5.0), (-4.0, -5.0), 1.0)
    };
    let mut map = Map::from_segments(vec![
        test_wall(0, (0.0, 0.0), (4.0, 0.0), 1.0),
        test_wall(1, (4.0, 0.0), (4.0, 2.0), 1.0),
        test_wall(2, (9.0, 9.0), (10.0, 9.0), 1.0),
        connecting,
    ]);
    map.travelled_m = 30.0;
    assert_eq!(map.laps_driven(), None);
    for id in [0, 1, 3] {
        let support = PlaneSupport {
            snapshots: CONFIRMING_SNAPSHOTS,
            ..Default::default()
        };
        map.plane_support.insert(id, support);
    }
    assert_eq!(map.laps_driven(), Some(2.5));
    // Poses driven inside the room leave the walls' perimeter the larger one.
    map.note_driven(&Pose::new(1.0, 0.5, 0.0));
    map.note_driven(&Pose::new(3.0, 1.5, 0.0));
    assert_eq!(map.laps_driven(), Some(2.5));
    // A pass 10 m along and 1 m across (perimeter 22 m) counts over its own box: 30/22 laps.
    map.note_driven(&Pose::new(11.0, 0.5, 0.0));
    assert_eq!(map.laps_driven(), Some(30.0 / 22.0));
}
