//! The mapper's echo placement stage (docs/algorithm.md §8.10).

use crate::geometry::{Point, Vec2};
use crate::mapping::ext::beam_geometry::mean_origin;
use crate::mapping::ext::beam_geometry::mean_range_m;
use crate::mapping::ext::echo_fit::{
    echo_behind_confirmed_wall, fit_echo_line, order_along_line, place_echoes,
    reflector_beating_line, MIN_ECHO_FIT_READINGS,
};
use crate::mapping::ext::point_features::file_arc;
use crate::mapping::model::beam::Beam;
use crate::mapping::model::ext_trace::EchoFitTrace;
use crate::mapping::model::trace::{NewSegmentTrace, StepTrace};
use crate::mapping::paper::fit::piece_end_points;
use crate::mapping::Mapper;
use crate::sonar::EchoModel;

impl Mapper {
    /// §8.10 echo placement: when one plane's echoes explain the readings of `new` (the
    /// `index`-th new segment of the step), they move to where those echoes came from and its
    /// end-points are taken again from them (§3's fit of the moved piece).
    /// A sensor whose echoes come from its axis ([`EchoModel::Axis`]) keeps the paper's
    /// placement.
    /// Returns false when the piece must not become a segment: most of its echo points lie
    /// behind confirmed walls.
    pub(in crate::mapping) fn place_echoes(
        &mut self,
        new: &mut NewSegmentTrace,
        index: usize,
        trace: &mut StepTrace,
    ) -> bool {
        if new.points.len() < MIN_ECHO_FIT_READINGS || self.sensor.echo == EchoModel::Axis {
            return true;
        }
        let beams: Option<Vec<Beam>> = new.points.iter().map(|q| self.recent_beam_of(q)).collect();
        let Some(beams) = beams else {
            return true;
        };
        let axis_points: Vec<Point> = new.points.iter().map(|q| q.point).collect();
        let (xi, half) = self.accuracy_and_half_beam();
        let turn = self.params.orientation_rad;
        let Some(line) = fit_echo_line(&beams, &axis_points, xi, half, turn) else {
            return true;
        };
        let mut placed = place_echoes(&new.points, &beams, &line, half);
        let behind_confirmed_wall = placed
            .points
            .iter()
            .zip(&beams)
            .filter(|(q, beam)| echo_behind_confirmed_wall(&self.map, beam, &q.point, xi))
            .count();
        let (first, last) = (new.points[0], new.points[new.points.len() - 1]);
        order_along_line(&mut placed.points, &line, &first, &last);
        // A corner or an edge: one reflector point explains the ranges better than the line.
        let centre =
            placed.points.iter().map(|q| q.point.coords).sum::<Vec2>() / placed.points.len() as f64;
        let reflector = reflector_beating_line(&beams, &line, Point::from(centre), xi, half);
        if let Some(at) = reflector {
            let origin = mean_origin(&beams);
            file_arc(
                &mut self.map,
                at,
                mean_range_m(&beams),
                &origin,
                trace.snapshot,
                xi,
            );
        }
        let keep = reflector.is_none() && 2 * behind_confirmed_wall <= new.points.len();
        let (a, b) = piece_end_points(&placed.points, 0, placed.points.len() - 1, self.params.fit);
        new.a = a;
        new.b = b;
        new.points = placed.points;
        if self.record_trace {
            trace.echo_fits.push(EchoFitTrace {
                new_segment: index,
                dropped: !keep,
                reflector,
                line,
                at_foot: placed.at_foot,
                at_cone_edge: placed.at_cone_edge,
                moved_max_m: placed.moved_max_m,
                behind_confirmed_wall,
            });
        }
        keep
    }
}
