//! Rounded reflectors: pillars from the echoes of removed corner diagonals (docs/algorithm.md
//! §8.14; beyond the paper).
//!
//! A round pillar echoes a specular sonar along its normal, the ray through its centre, so a
//! reading of it is the sensor's distance from the centre less the radius (Leonard and
//! Durrant-Whyte's cylinder, beside planes, corners and edges). Placed on the beam axes, a few
//! such readings of nearby snapshots fit a short line as well as they fit the pillar: a piece of
//! three to five readings cannot tell them apart. Beside other pillars and short confirmed
//! pieces those lines stand across "corners" and leave the map at once as diagonals (§8.11),
//! every time the robot passes: the map never holds the pillar, so its echoes are never
//! explained (§8.5) and make pieces again on every lap.
//!
//! The readings of the removed diagonals are kept as evidence, each with its sensor's pose.
//! When the evidence gathered near a new diagonal holds readings enough, from sensors standing
//! apart, and one cylinder explains every one of them within its tolerance, the pillar is filed
//! as a rounded feature (an edge with a radius), confirmed by that baseline; from then on it
//! explains its echoes before they are clustered.

use crate::geometry::{Point, Vec2};
use crate::mapping::ext::echo_fit::fit_round_reflector;
use crate::mapping::ext::point_features::{explains_round, merge_radius_m, nearest_feature_within};
use crate::mapping::model::beam::Beam;
use crate::mapping::model::ext_trace::RoundTrace;
use crate::mapping::model::features::MAX_ROUND_RADIUS_M;
use crate::mapping::model::features::ROUND_EVIDENCE_KEPT;
use crate::mapping::model::features::{FeatureKind, PointFeature, CONFIRMING_BASELINE_M};
use crate::mapping::model::map::Map;

/// Fewest readings of evidence before a pillar is fitted to them: twice the unknowns of a
/// cylinder (its centre and radius).
pub const MIN_ROUND_EVIDENCE: usize = 6;

/// Keeps `beams` (the readings of a diagonal just removed) as evidence, then fits a pillar to
/// the evidence whose axis points lie within a pillar's reach of theirs
/// ([`fit_round_reflector`]); when one explains at least [`MIN_ROUND_EVIDENCE`] of them, from
/// sensors at least [`CONFIRMING_BASELINE_M`] apart, it is filed (or moves the rounded feature
/// within [`merge_radius_m`] of its centre) and that evidence is spent.
pub fn note_removed_echoes(
    map: &mut Map,
    beams: &[Beam],
    snapshot: usize,
    accuracy_pct: f64,
    half_beam_rad: f64,
) -> Option<RoundTrace> {
    if beams.is_empty() {
        return None;
    }
    map.round_evidence.extend_from_slice(beams);
    let excess = map.round_evidence.len().saturating_sub(ROUND_EVIDENCE_KEPT);
    map.round_evidence.drain(..excess);
    let here =
        Point::from(beams.iter().map(|b| b.axis_point().coords).sum::<Vec2>() / beams.len() as f64);
    // A pillar's echoes lie on its near side, within its radius of the middle of them; pillars
    // stand closer than their reach to each other, so the fit starts from the evidence nearest
    // the diagonal and then takes in what the pillar found explains.
    let mut near: Vec<(f64, usize)> = (0..map.round_evidence.len())
        .map(|i| ((map.round_evidence[i].axis_point() - here).norm(), i))
        .filter(|&(d, _)| d <= MAX_ROUND_RADIUS_M)
        .collect();
    if near.len() < MIN_ROUND_EVIDENCE {
        return None;
    }
    near.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    let beam_of = |i: usize| map.round_evidence[i];
    let seed: Vec<Beam> = near[..MIN_ROUND_EVIDENCE]
        .iter()
        .map(|&(_, i)| beam_of(i))
        .collect();
    let (centre, radius_m, _) = fit_round_reflector(&seed, here, accuracy_pct, half_beam_rad)?;
    let mut inliers: Vec<usize> = near
        .iter()
        .map(|&(_, i)| i)
        .filter(|&i| explains_round(&centre, radius_m, &beam_of(i), accuracy_pct, half_beam_rad))
        .collect();
    inliers.sort_unstable();
    let evidence: Vec<Beam> = inliers.iter().map(|&i| beam_of(i)).collect();
    if evidence.len() < MIN_ROUND_EVIDENCE {
        return None;
    }
    let baseline_m = widest_apart_m(&evidence);
    if baseline_m < CONFIRMING_BASELINE_M {
        return None;
    }
    let (centre, radius_m, _) = fit_round_reflector(&evidence, here, accuracy_pct, half_beam_rad)?;
    let range_m = evidence
        .iter()
        .map(|b| b.range_m)
        .fold(f64::INFINITY, f64::min);
    let seen_from = evidence[0].origin;
    let feature = file_round(
        map,
        centre,
        radius_m,
        range_m,
        seen_from,
        baseline_m,
        snapshot,
        accuracy_pct,
    );
    let mut k = 0;
    map.round_evidence.retain(|_| {
        let keep = inliers.binary_search(&k).is_err();
        k += 1;
        keep
    });
    Some(RoundTrace {
        feature,
        centre,
        radius_m,
        readings: evidence.len(),
        baseline_m,
    })
}

/// The largest distance between two of the sensors of `beams`, metres.
fn widest_apart_m(beams: &[Beam]) -> f64 {
    let mut widest: f64 = 0.0;
    for (i, a) in beams.iter().enumerate() {
        for b in &beams[i + 1..] {
            widest = widest.max((a.origin - b.origin).norm());
        }
    }
    widest
}

/// Files the pillar of centre `centre` and radius `radius_m`: it moves the rounded feature
/// within [`merge_radius_m`] of the centre to the observations' mean (centre and radius), or
/// makes a new one, confirmed by `baseline_m`. Returns its id.
#[allow(clippy::too_many_arguments)]
fn file_round(
    map: &mut Map,
    centre: Point,
    radius_m: f64,
    range_m: f64,
    seen_from: Point,
    baseline_m: f64,
    snapshot: usize,
    accuracy_pct: f64,
) -> u32 {
    let merge_m = merge_radius_m(accuracy_pct, range_m);
    let nearest = nearest_feature_within(map, &centre, merge_m, true)
        .and_then(|id| map.feature(id))
        .cloned();
    match nearest {
        Some(f) => {
            let n = f.observations as f64;
            let id = f.id;
            let moved = PointFeature {
                at: Point::from((f.at.coords * n + centre.coords) / (n + 1.0)),
                radius_m: (f.radius_m * n + radius_m) / (n + 1.0),
                range_m: f.range_m.min(range_m),
                observations: f.observations + 1,
                baseline_m: f.baseline_m.max(baseline_m),
                ..f
            };
            map.replace_feature(moved, snapshot);
            id
        }
        None => map.push_feature(PointFeature {
            radius_m,
            baseline_m,
            ..PointFeature::seen_once(FeatureKind::Edge, centre, range_m, seen_from, snapshot)
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mapping::ext::point_features::beams_at_reflector;
    use crate::mapping::model::features::MIN_ROUND_RADIUS_M;

    const HALF: f64 = 12.5 * std::f64::consts::PI / 180.0;

    /// Readings of a pillar of radius 0.2 m at (2, 3) from sensors along y = 0 at `xs`, each
    /// looking at its centre.
    fn pillar_beams(xs: &[f64]) -> Vec<Beam> {
        beams_at_reflector(Point::new(2.0, 3.0), 0.2, xs)
    }

    #[test]
    fn the_echoes_of_removed_diagonals_file_a_pillar_once_they_are_enough_and_spread() {
        let mut map = Map::default();
        // Two diagonals of three readings each, from x = 1.4–1.6 and 2.4–2.6: the first alone is
        // too little evidence; with the second there are six, from sensors 1.2 m apart.
        let first = pillar_beams(&[1.4, 1.5, 1.6]);
        assert_eq!(note_removed_echoes(&mut map, &first, 7, 1.0, HALF), None);
        assert_eq!(map.round_evidence.len(), 3);
        let second = pillar_beams(&[2.4, 2.5, 2.6]);
        let t = note_removed_echoes(&mut map, &second, 9, 1.0, HALF).unwrap();
        assert!(
            (t.centre - Point::new(2.0, 3.0)).norm() < 1e-6,
            "{:?}",
            t.centre
        );
        assert!((t.radius_m - 0.2).abs() < 1e-6);
        assert_eq!(t.readings, 6);
        assert!((t.baseline_m - 1.2).abs() < 1e-9);
        // The evidence is spent, and the pillar, confirmed, explains a reading of it from
        // (2, 0): 3 − 0.2 = 2.8 m.
        assert!(map.round_evidence.is_empty());
        let f = map.feature(t.feature).unwrap();
        assert!(f.is_confirmed() && f.kind == FeatureKind::Edge);
        let beam = Beam {
            origin: Point::new(2.0, 0.0),
            direction: Vec2::new(0.0, 1.0),
            range_m: 2.8,
        };
        assert!(explains_round(&f.at, f.radius_m, &beam, 1.0, HALF));
    }

    #[test]
    fn the_echoes_of_a_corner_file_no_pillar() {
        // A corner at (2, 3): every reading its distance from the vertex, a radius of 0.
        let beams = beams_at_reflector(Point::new(2.0, 3.0), 0.0, &[1.4, 1.5, 1.6, 2.4, 2.5, 2.6]);
        let mut map = Map::default();
        assert_eq!(note_removed_echoes(&mut map, &beams, 3, 1.0, HALF), None);
        assert!(map.features.is_empty());
        assert_eq!(map.round_evidence.len(), 6);
    }

    #[test]
    fn evidence_from_one_place_files_no_pillar() {
        // Six readings from sensors within 5 cm: the radius cannot be told from the distance.
        let mut map = Map::default();
        let beams = pillar_beams(&[1.98, 1.99, 2.0, 2.01, 2.02, 2.03]);
        assert_eq!(note_removed_echoes(&mut map, &beams, 3, 1.0, HALF), None);
        assert!(map.features.is_empty());
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(64))]
        /// Whatever the diagonals' readings (some a pillar's, some anything), the evidence stays
        /// within its bound, the map within its invariants, and every pillar filed has a
        /// pillar's radius, at least the evidence it needs, and is confirmed.
        #[test]
        fn any_evidence_keeps_the_map_sound(
            pillar in (0.0..4.0f64, 2.0..5.0f64, 0.06..0.5f64),
            batches in proptest::collection::vec(
                proptest::collection::vec((-2.0..6.0f64, -1.0..1.0f64, 0.0..std::f64::consts::TAU, 0.2..5.0f64, proptest::bool::ANY), 1..6),
                1..30,
            ),
        ) {
            let (px, py, pr) = pillar;
            let centre = Point::new(px, py);
            let mut map = Map::default();
            for (k, batch) in batches.iter().enumerate() {
                let beams: Vec<Beam> = batch
                    .iter()
                    .map(|&(x, y, dir, range_m, aimed)| {
                        let origin = Point::new(x, y);
                        let v = centre - origin;
                        if aimed && v.norm() > pr + 0.1 {
                            Beam { origin, direction: v / v.norm(), range_m: v.norm() - pr }
                        } else {
                            Beam { origin, direction: Vec2::new(dir.cos(), dir.sin()), range_m }
                        }
                    })
                    .collect();
                let filed = note_removed_echoes(&mut map, &beams, k, 1.0, HALF);
                proptest::prop_assert!(map.round_evidence.len() <= ROUND_EVIDENCE_KEPT);
                proptest::prop_assert_eq!(map.check_invariants(0), Ok(()));
                if let Some(t) = filed {
                    proptest::prop_assert!((MIN_ROUND_RADIUS_M..=MAX_ROUND_RADIUS_M).contains(&t.radius_m));
                    proptest::prop_assert!(t.readings >= MIN_ROUND_EVIDENCE);
                    proptest::prop_assert!(t.baseline_m >= CONFIRMING_BASELINE_M);
                    let f = map.feature(t.feature).unwrap();
                    proptest::prop_assert!(f.is_confirmed() && f.radius_m > 0.0);
                }
            }
        }
    }

    #[test]
    fn only_the_most_recent_evidence_is_kept() {
        let mut map = Map::default();
        for k in 0..30 {
            // Corner-like readings far apart from each other (no pillar).
            let b = Beam {
                origin: Point::new(k as f64 * 5.0, 0.0),
                direction: Vec2::new(0.0, 1.0),
                range_m: 2.0,
            };
            note_removed_echoes(&mut map, &[b, b, b], k, 1.0, HALF);
        }
        assert_eq!(map.round_evidence.len(), ROUND_EVIDENCE_KEPT);
        assert_eq!(map.round_evidence[ROUND_EVIDENCE_KEPT - 1].origin.x, 145.0);
    }
}
