//! Segment lineage against the map it describes, on generated lap runs in both presets.

use sonarmap::lineage::LineageEvent;
use sonarmap::mapping::Params;
use sonarmap::replay::Replay;
use sonarmap::sim::SceneKind;
use std::sync::Arc;

#[test]
fn every_segment_of_the_map_was_made_or_split_off_and_every_merged_one_says_where_it_went() {
    for (kind, params) in [
        (SceneKind::CorridorWithDoors, Params::extended()),
        (SceneKind::LRoom, Params::paper()),
    ] {
        let run = sonarmap::soak::family_run(kind, 5, 600);
        let replay = Replay::new(Arc::new(run), params);
        let last = replay.len() - 1;
        let lineage = replay.lineage();
        let map = replay.final_map();
        assert!(!map.segments.is_empty());
        for s in map
            .segments
            .iter()
            .filter(|s| s.kind == sonarmap::mapping::SegmentKind::Fitted)
        {
            let events = lineage.of(s.id, last);
            match events.first() {
                Some(LineageEvent::Created { snapshot, .. })
                | Some(LineageEvent::SplitFrom { snapshot, .. }) => {
                    assert_eq!(*snapshot, s.created.max(*snapshot), "#{}", s.id);
                }
                other => panic!("#{} begins with {other:?}", s.id),
            }
            assert!(
                events
                    .windows(2)
                    .all(|w| w[0].snapshot() <= w[1].snapshot()),
                "#{} in order",
                s.id
            );
            assert!(
                !events
                    .iter()
                    .any(|e| matches!(e, LineageEvent::AbsorbedInto { .. })),
                "#{} is still in the map",
                s.id
            );
            // Its last update is the map's last record of one (refit pieces inherit their
            // parent's record, so only for segments made by a decision).
            if !matches!(events.first(), Some(LineageEvent::Created { .. })) {
                continue;
            }
            let updated = events
                .iter()
                .filter_map(|e| match e {
                    LineageEvent::Updated { snapshot, .. } => Some(*snapshot),
                    _ => None,
                })
                .next_back();
            assert_eq!(updated, s.updated.last().map(|&k| k as usize), "#{}", s.id);
        }
        // A segment that left the map was merged away, seen through or found to stand across a
        // corner (only merging, free space and corner diagonals remove segments), or was a
        // connecting segment that left with one it joined; nothing happens to it after that.
        let gone: Vec<u32> = (0..map.next_segment_id)
            .filter(|&id| map.segment(id).is_none())
            .collect();
        for id in gone {
            let events = lineage.of(id, last);
            assert!(
                matches!(
                    events.last(),
                    Some(
                        LineageEvent::AbsorbedInto { .. }
                            | LineageEvent::Refuted { .. }
                            | LineageEvent::CornerDiagonal { .. }
                            | LineageEvent::LinkDropped { .. }
                    )
                ),
                "#{id} left the map: {events:?}"
            );
        }
    }
}

#[test]
fn a_refit_that_loses_its_confirmation_says_so_in_the_lineage() {
    // Over the generated lap runs of every scene kind in `extended`, each segment a refit made
    // tentative again (§8.7 refit_unconfirms) has that step in its lineage.
    let mut found = 0;
    for kind in SceneKind::ALL {
        let run = sonarmap::soak::family_run(kind, 5, 600);
        let mut mapper =
            sonarmap::mapping::Mapper::new(Params::extended(), run.layout.clone(), run.sensor)
                .with_trace(false);
        let mut lineage = sonarmap::lineage::Lineage::default();
        for (k, s) in run.snapshots.iter().enumerate() {
            let trace = mapper.step(s);
            lineage.record(&trace);
            for u in trace.unconfirmed.iter().filter(|u| !u.tentative) {
                found += 1;
                assert!(
                    lineage
                        .of(u.segment, k)
                        .contains(&LineageEvent::Unconfirmed { snapshot: k }),
                    "{kind:?} #{} at {k}",
                    u.segment
                );
            }
        }
    }
    assert!(found > 0, "no refit lost its confirmation on these runs");
}
