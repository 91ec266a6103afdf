//! The mapper's free-space stage: segments seen through leave the map (docs/algorithm.md §8.6),
//! and segment ends seen through are cut back (§8.18).

use crate::geometry::{Point, Vec2};
use crate::mapping::ext::beam_geometry::feature_tolerance_m;
use crate::mapping::ext::beam_geometry::HalfCone;
use crate::mapping::ext::free_space::{cone_box_in, refuted_segments};
use crate::mapping::ext::seen_through_ends::{cut_of, free_part_of_line, Cut};
use crate::mapping::model::beam::Beam;
use crate::mapping::model::ext_trace::{SeenThroughCut, SeenThroughTrace};
use crate::mapping::model::map::{EndPoint, SegmentId, SensorLooks, SupportPoint};
use crate::mapping::model::support_list::SupportList;
use crate::mapping::model::trace::{RefutedTrace, StepTrace};
use crate::mapping::Mapper;

/// The least overlap of a free part and a segment that cuts it, metres: a free part that only
/// touches an end cut there before changes nothing.
const MIN_CUT_M: f64 = 1e-6;

impl Mapper {
    /// §8.6 free space: the segments a kept reading of this snapshot saw past leave the map;
    /// §8.18: then the segment ends it saw through are cut back.
    pub(in crate::mapping) fn sweep_free_space(&mut self, trace: &mut StepTrace) {
        let (xi, half) = self.accuracy_and_half_beam();
        let mut found = Vec::new();
        // §8.12: a settled reading has left `kept`; the space in front of its wall was swept.
        let buffers = self.buffers.take().unwrap_or_default();
        if self.params.free_space {
            for q in &buffers.kept {
                let beam = self.step_beam_of(q);
                refuted_segments(&self.map, &beam, xi, half, &mut found);
                // Kept in the slim trace too: the lineage of a segment reads its removal there.
                for &(segment, distance_m, off_axis_rad) in &found {
                    self.map.remove_segment(segment);
                    trace.refuted.push(RefutedTrace {
                        segment,
                        sensor: q.reading.sensor(),
                        range_m: q.range_m,
                        distance_m,
                        off_axis_rad,
                    });
                }
            }
        }
        if self.trims_seen_through() {
            // A settled reading that looked into an opening saw through the walls' ends beside it.
            let kept = buffers.kept.iter().map(|q| (q, true));
            for (q, unsettled) in kept.chain(buffers.settled_readings.iter().map(|q| (q, false))) {
                let beam = self.step_beam_of(q);
                for look in self
                    .looks_seeing_through(&beam, q.reading.sensor(), unsettled)
                    .into_iter()
                    .flatten()
                {
                    self.trim_seen_through(&look, q.reading.sensor(), trace);
                }
            }
        }
        self.buffers = Some(buffers);
    }

    /// §8.18: the looks of `sensor` that cut what they saw through, now that it reads `beam`.
    /// Only near an edge: while the robot has driven less than two footprints' widths
    /// (`2·D·tan(β/2)`) since the sensor's range last jumped by more than `2·tol(D)` (a wall's
    /// end entered or left its cone; along an unbroken wall nothing is tested). There, its last
    /// long look past `beam` while the robot is still within that look's footprint
    /// (`D·tan(β/2)` driven since), and `beam` itself when the sensor's reading before bore it
    /// out, so that one stray echo (a ghost, a second bounce) cuts nothing. A reading borne out
    /// becomes the sensor's long look; one not, past no look, leaves it none.
    fn looks_seeing_through(
        &mut self,
        beam: &Beam,
        sensor: usize,
        unsettled: bool,
    ) -> [Option<Beam>; 2] {
        let (xi, half) = self.accuracy_and_half_beam();
        let travelled_m = self.map.travelled_m;
        if self.map.sensor_looks.len() <= sensor {
            self.map
                .sensor_looks
                .resize(sensor + 1, SensorLooks::default());
        }
        let looks = &mut self.map.sensor_looks[sensor];
        let tol_m = feature_tolerance_m(xi, beam.range_m);
        let borne_out = looks
            .last
            .is_some_and(|last| (last.range_m - beam.range_m).abs() <= 2.0 * tol_m);
        if let (Some(last), false) = (looks.last, borne_out) {
            let footprint_m = last.range_m.max(beam.range_m) * half.tan();
            looks.edge_until_m = travelled_m + 2.0 * footprint_m;
        }
        looks.last = Some(*beam);
        let past = looks.long.filter(|&(long, at_m)| {
            long.range_m > beam.range_m + 2.0 * feature_tolerance_m(xi, long.range_m)
                && travelled_m - at_m <= long.range_m * half.tan()
        });
        if past.is_none() {
            looks.long = borne_out.then_some((*beam, travelled_m));
        }
        if !unsettled && travelled_m > looks.edge_until_m {
            return [None, None];
        }
        [past.map(|(long, _)| long), borne_out.then_some(*beam)]
    }

    /// §8.18: cuts away the parts of fitted segments that `beam` saw through, in id order.
    fn trim_seen_through(&mut self, beam: &Beam, sensor: usize, trace: &mut StepTrace) {
        let (xi, half_beam_rad) = self.accuracy_and_half_beam();
        let half = HalfCone::new(half_beam_rad);
        let tol_m = feature_tolerance_m(xi, beam.range_m);
        let shortest_left_m = 2.0 * tol_m;
        let mut cuts: Vec<(SegmentId, (f64, f64))> = Vec::new();
        // The free part lies inside the cone, short of the range by 2·tol.
        let (low, high, bulge_m) = cone_box_in(beam, half, 0.0, beam.range_m - 2.0 * tol_m);
        self.map
            .visit_segments_along(&low, &high, bulge_m, |id, s| {
                if !s.fitted {
                    return;
                }
                if let Some(free) = free_part_of_line(beam, &s.a.point, &s.b.point, xi, half) {
                    let length_m = (s.b.point - s.a.point).norm();
                    if free.1 > MIN_CUT_M && free.0 < length_m - MIN_CUT_M {
                        cuts.push((id, free));
                    }
                }
            });
        cuts.sort_unstable_by_key(|&(id, _)| id);
        for (id, free) in cuts {
            if let Some(record) = self.cut_seen_through(id, free, shortest_left_m, sensor, beam) {
                trace.seen_through.push(record);
            }
        }
    }

    /// Cuts the part `free` (distances from `a` along segment `id`) that `beam` of `sensor` saw
    /// through away from it (§8.18, [`cut_of`]): an end moves, the segment splits in two, or it
    /// goes. The readings placed in the part cut go with it (a refit, §5, would bring it back),
    /// and so do point memory's there ([`Self::forget_memory_in`]).
    fn cut_seen_through(
        &mut self,
        id: SegmentId,
        (near, far): (f64, f64),
        shortest_left_m: f64,
        sensor: usize,
        beam: &Beam,
    ) -> Option<SeenThroughTrace> {
        let s = self.map.segment(id)?;
        let (a, b) = (s.a, s.b);
        let length_m = (b.point - a.point).norm();
        let along = (b.point - a.point) / length_m;
        let at = |d: f64| a.point + along * d.clamp(0.0, length_m);
        let from_a = |p: &SupportPoint| (p.point - a.point).dot(&along);
        let before: Vec<SupportPoint> = s
            .points
            .iter()
            .filter(|p| from_a(p) <= near)
            .copied()
            .collect();
        let after: Vec<SupportPoint> = s
            .points
            .iter()
            .filter(|p| from_a(p) >= far)
            .copied()
            .collect();
        let dropped_points = s.points.len() - before.len() - after.len();
        self.forget_memory_in(a.point, along, (near, far));
        let cut = match cut_of(
            (near, far),
            length_m,
            shortest_left_m,
            before.len(),
            after.len(),
        ) {
            Cut::Remove => {
                self.map.remove_segment(id);
                SeenThroughCut::Removed
            }
            Cut::EndB(d) => {
                self.set_piece(id, a, EndPoint { point: at(d), ..b }, before);
                SeenThroughCut::EndB
            }
            Cut::EndA(d) => {
                self.set_piece(id, EndPoint { point: at(d), ..a }, b, after);
                SeenThroughCut::EndA
            }
            Cut::Hole(near, far) => {
                let piece = self.split_off(
                    id,
                    EndPoint {
                        point: at(far),
                        ..a
                    },
                    b,
                    after,
                );
                self.set_piece(
                    id,
                    a,
                    EndPoint {
                        point: at(near),
                        ..b
                    },
                    before,
                );
                SeenThroughCut::Split { piece }
            }
        };
        Some(SeenThroughTrace {
            segment: id,
            sensor,
            range_m: beam.range_m,
            free_part: [at(near).into(), at(far).into()],
            cut,
            dropped_points,
        })
    }

    /// Point memory (§8.1) forgets the readings it holds in the part `(near, far)` of the line
    /// from `a` along the unit vector `along` that a look saw through (within `tol(D)` of the
    /// line), as the segment cut loses its own: held, they would fit a piece that a MATCH
    /// carries back over the part cut (a jamb's echoes, laid on the beam's axis, reach into a
    /// door recess's mouth).
    fn forget_memory_in(&mut self, a: Point, along: Vec2, (near, far): (f64, f64)) {
        let (xi, _) = self.accuracy_and_half_beam();
        let normal = Vec2::new(-along.y, along.x);
        self.map.memory.retain(|m| {
            let from_a = m.support.point - a;
            let (d, off) = (from_a.dot(&along), from_a.dot(&normal).abs());
            !(d > near && d < far && off <= feature_tolerance_m(xi, m.support.range_m))
        });
    }

    /// Segment `id` becomes `a`–`b`, supported by `points`.
    fn set_piece(&mut self, id: SegmentId, a: EndPoint, b: EndPoint, points: Vec<SupportPoint>) {
        if let Some(s) = self.map.segment_mut(id) {
            s.points = SupportList::from_vec(points);
        }
        self.map.set_ends(id, a, b);
    }

    /// A new segment `a`–`b` beside segment `id` (a piece of it, after it in its face, with
    /// its plane support), supported by `points`; returns its id.
    fn split_off(
        &mut self,
        id: SegmentId,
        a: EndPoint,
        b: EndPoint,
        points: Vec<SupportPoint>,
    ) -> SegmentId {
        let piece = self
            .map
            .push_piece_of(id, a, b, SupportList::from_vec(points))
            .expect("the segment cut is in the map");
        if let Some(support) = self.map.plane_support.get(&id).cloned() {
            self.map.plane_support.insert(piece, support);
        }
        self.map.place_after_in_face(id, &[piece]);
        piece
    }
}
