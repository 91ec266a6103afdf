//! The mapper's point-feature stages (docs/algorithm.md §8.5): readings a confirmed feature
//! explains, and the arc rule on a cluster.

use crate::geometry::Point;
use crate::mapping::ext::beam_geometry::mean_origin;
use crate::mapping::ext::echo_fit::{fit_echo_line, reflector_beating_line};
use crate::mapping::ext::point_features::{
    arc_point, explaining_feature, explaining_feature_among, file_arc,
};
use crate::mapping::model::beam::Beam;
use crate::mapping::model::ext_trace::ArcTrace;
use crate::mapping::model::ids::FeatureId;
use crate::mapping::model::map::SupportPoint;
use crate::mapping::model::trace::{ExplainedTrace, StepTrace};
use crate::mapping::Mapper;
use crate::sonar::EchoModel;

/// Most confirmed point features §8.5's explained readings search one by one; more are
/// searched through the map's grid.
const MAX_FEATURES_SEARCHED_DIRECTLY: usize = 64;

impl Mapper {
    /// §8.5 explained readings: the kept points a confirmed point feature explains leave
    /// `kept` (each looks only at the features filed near its own point).
    pub(in crate::mapping) fn drop_explained_readings(
        &self,
        trace: &mut StepTrace,
        kept: &mut Vec<SupportPoint>,
        confirmed: &mut Vec<(FeatureId, Point, f64)>,
    ) {
        // Only a confirmed feature explains a reading. A few are searched through directly,
        // many through the grid (gathered no further than one past the few: the grid's turn).
        confirmed.clear();
        if kept.is_empty() {
            return;
        }
        confirmed.extend(
            self.map
                .confirmed_features()
                .map(|f| (f.id, f.at, f.radius_m))
                .take(MAX_FEATURES_SEARCHED_DIRECTLY + 1),
        );
        if confirmed.is_empty() {
            return;
        }
        let (xi, half) = self.accuracy_and_half_beam();
        let mut scratch = Vec::new();
        kept.retain(|q| {
            let beam = self.step_beam_of(q);
            let id = if confirmed.len() <= MAX_FEATURES_SEARCHED_DIRECTLY {
                explaining_feature_among(confirmed, &beam, xi, half)
            } else {
                explaining_feature(&self.map, &beam, xi, half, &mut scratch)
            };
            let Some(id) = id else {
                return true;
            };
            if self.record_trace {
                let at = self.map.feature(id).map_or(beam.origin, |f| f.at);
                let v = at - beam.origin;
                trace.explained.push(ExplainedTrace {
                    sensor: q.reading.sensor(),
                    range_m: q.range_m,
                    feature: id,
                    feature_distance_m: v.norm(),
                    off_axis_rad: (v.dot(&beam.direction) / v.norm().max(1e-12))
                        .clamp(-1.0, 1.0)
                        .acos(),
                });
            }
            false
        });
    }

    /// §8.5 arc rule on cluster `ci` (`chain` in order): when it is an arc, its point is filed
    /// as a point feature; true when the cluster is then not fitted (one plane does not explain
    /// its ranges as well).
    pub(in crate::mapping) fn file_if_arc(
        &mut self,
        ci: usize,
        chain: &[SupportPoint],
        trace: &mut StepTrace,
    ) -> bool {
        if trace.pose.is_none() {
            return false;
        }
        // An arc takes two readings at least (`arc_point`); most clusters are one.
        if chain.len() < 2 {
            return false;
        }
        let beams: Vec<Beam> = chain.iter().map(|q| self.step_beam_of(q)).collect();
        let sensors: Vec<usize> = chain.iter().map(|q| q.reading.sensor()).collect();
        let Some((at, range_m)) = arc_point(&beams, &sensors, self.params.accuracy_pct) else {
            return false;
        };
        // A plane facing the sensors' bisector reads the same range to each of them too: an
        // arc whose chord a reading supports as a plane stays a line.
        let (first, last) = (chain[0].point, chain[chain.len() - 1].point);
        if self.supports_as_plane_now(chain, &first, &last) {
            return false;
        }
        // With echo placement (§8.10) on for a cone sensor: a plane seen square-on by
        // neighbouring sonars reads (nearly) one range to each, at its foot or its cone's edge.
        // When one plane explains every range at least as well as one reflector point, the
        // cluster is both: filed as a reflector observation (its feature is confirmed only if
        // it stays put as the robot moves, as a corner does) and fitted.
        let mut also_fitted = false;
        if self.params.echo_fit && self.sensor.echo == EchoModel::Cone {
            let (xi, half) = self.accuracy_and_half_beam();
            let axis_points: Vec<Point> = chain.iter().map(|q| q.point).collect();
            let turn = self.params.orientation_rad;
            if let Some(line) = fit_echo_line(&beams, &axis_points, xi, half, turn) {
                also_fitted = reflector_beating_line(&beams, &line, at, xi, half).is_none();
            }
        }
        let origin = mean_origin(&beams);
        let (feature, new_feature) = file_arc(
            &mut self.map,
            at,
            range_m,
            &origin,
            trace.snapshot,
            self.params.accuracy_pct,
        );
        if self.record_trace {
            trace.arcs.push(ArcTrace {
                cluster: ci,
                sensors,
                range_min_m: beams
                    .iter()
                    .map(|b| b.range_m)
                    .fold(f64::INFINITY, f64::min),
                range_max_m: beams.iter().map(|b| b.range_m).fold(0.0, f64::max),
                at,
                feature,
                new_feature,
                also_fitted,
            });
        }
        !also_fitted
    }
}
