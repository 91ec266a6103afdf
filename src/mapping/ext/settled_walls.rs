//! Settled walls (docs/algorithm.md §8.12; beyond the paper).
//!
//! A robot that patrols its rooms reads the same walls thousands of times. Once a wall is
//! confirmed (§8.7: readings from two snapshots supported it as a plane), a reading it explains
//! as a plane echo, well inside its ends, adds nothing the map does not hold: the paper would
//! cluster it, fit it, match it to that wall and fuse it (§3.3.2), moving the wall by a fraction
//! of the tolerance. Such a reading is *settled*: it is kept out of the clusters, point memory and
//! the free-space sweep (§8.6), as §8.5 keeps out the readings a corner explains: the space in
//! front of a confirmed wall was swept by the readings that confirmed it and by every reading
//! that is not settled. A reading near either end of the wall, where the wall may go on, is
//! not settled: it must be able to extend the wall. A wall mapped as pieces that overlap, or
//! leave gaps within a reading's tolerance, counts as one: the margin is taken from the ends of
//! the chain.
//!
//! This is data association gating, as a feature-based map does it (Leonard and Durrant-Whyte):
//! a measurement the map predicts is consumed by the feature that predicted it.

use crate::geometry::{distance_to_line, Point};
use crate::mapping::ext::beam_geometry::feature_tolerance_m;
use crate::mapping::ext::beam_geometry::HalfCone;
use crate::mapping::ext::confirm::{plane_echo_in, PlaneEcho, PlaneEchoModel};
use crate::mapping::ext::free_space::cone_box_in;
use crate::mapping::model::beam::Beam;
use crate::mapping::model::map::{Map, SegmentId, SegmentKind};

/// How far inside a wall's ends its echo point must lie for the wall to settle a reading, in
/// memory gaps (`memory_gap`, 12 in): a chain of remembered readings that runs on past the end
/// keeps a link inside it. Measured on the suite (docs/algorithm.md §8.12): since the margin is
/// taken from the ends of a chain of pieces, half a gap maps as well as one on six seeds
/// (within a point of spurious segments and 0.01 of coverage, every model under 15 %) and
/// leaves a corridor lap run 40 % fewer instructions; a quarter gap lost coverage.
pub const SETTLED_END_MARGIN_GAPS: f64 = 0.5;

/// What a settling test takes besides the reading, the same for every reading of a step: the
/// sonar's accuracy and beam, whether the cone's edges echo, and the margin.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SettleRule {
    /// The sonar's accuracy ξ, percent.
    pub accuracy_pct: f64,
    /// Half the beam's opening, as its cosine and sine (computed once for the step).
    pub half: HalfCone,
    /// Where the plane test takes a plane's echo from (§8.7).
    pub echo: PlaneEchoModel,
    /// How far inside the ends of a wall (or of its chain) its echo point must lie, metres.
    pub end_margin_m: f64,
}

/// Whether the confirmed wall `a`–`b` settles `beam`'s reading: the wall explains it as a plane
/// echo (the test a reading takes to confirm it, §8.7, the echo taken where `rule.echo`
/// says) and the echo point lies at least `rule.end_margin_m` inside both ends.
/// Returns the predicted range and the echo point's distance from the nearer end.
///
/// ```
/// use sonarmap::geometry::{Point, Vec2};
/// use sonarmap::mapping::model::beam::Beam;
/// use sonarmap::mapping::ext::confirm::PlaneEchoModel;
/// use sonarmap::mapping::ext::settled_walls::{settles, SettleRule};
/// // A sensor at (1, 0) looking along +y reads 2.03 m; the wall runs from (0, 2) to (3, 2):
/// // the foot (1, 2) is on the axis, |2 − 2.03| = 0.03 ≤ 0.0609 (3 % of 2.03), and it lies 1 m
/// // from the nearer end (a), more than the 0.3048 m margin (one memory gap): settled.
/// let beam = Beam { origin: Point::new(1.0, 0.0), direction: Vec2::new(0.0, 1.0), range_m: 2.03 };
/// let rule = SettleRule::new(3.0, 12.5f64.to_radians(), PlaneEchoModel::Foot, 0.3048);
/// let (predicted, inside) = settles(&beam, &Point::new(0.0, 2.0), &Point::new(3.0, 2.0), &rule).unwrap();
/// assert!((predicted - 2.0).abs() < 1e-12 && (inside - 1.0).abs() < 1e-12);
/// // The same reading with the wall ending at x = 1.2: the foot is 0.2 m from that end, where
/// // the wall may go on: not settled.
/// assert!(settles(&beam, &Point::new(-2.0, 2.0), &Point::new(1.2, 2.0), &rule).is_none());
/// // Read at 2.2 m (something behind the wall's line): not explained, not settled.
/// let far = Beam { range_m: 2.2, ..beam };
/// assert!(settles(&far, &Point::new(0.0, 2.0), &Point::new(3.0, 2.0), &rule).is_none());
/// ```
pub fn settles(beam: &Beam, a: &Point, b: &Point, rule: &SettleRule) -> Option<(f64, f64)> {
    let echo = rule.plane_echo(beam, a, b)?;
    let inside_m = inside_ends_m(echo.along, (b - a).norm());
    (inside_m >= rule.end_margin_m).then_some((echo.range_m, inside_m))
}

/// Where the wall `a`–`b` sent `beam`'s echo from, at the measured range: the beam's origin
/// plus its range towards the wall's echo point under `rule` (the foot of the perpendicular, or
/// where the cone's edge meets the wall). A wall's echoes placed so lie on a line parallel to
/// it whichever sensor read them, where points on the beams' axes would not (docs/algorithm.md
/// §8.17, `wall_windows`).
///
/// ```
/// use sonarmap::geometry::{Point, Vec2};
/// use sonarmap::mapping::ext::settled_walls::{echo_at_range, SettleRule};
/// use sonarmap::mapping::ext::confirm::PlaneEchoModel;
/// use sonarmap::mapping::model::beam::Beam;
/// // The wall y = 2 read 10° off its normal at 2.01 m: the echo comes from the foot (0, 2),
/// // so the point lies straight ahead of the sensor at the range read, not on the axis.
/// let dir = Vec2::new(80f64.to_radians().cos(), 80f64.to_radians().sin());
/// let beam = Beam { origin: Point::origin(), direction: dir, range_m: 2.01 };
/// let rule = SettleRule::new(3.0, 12.5f64.to_radians(), PlaneEchoModel::Foot, 0.3);
/// let p = echo_at_range(&beam, &Point::new(-2.0, 2.0), &Point::new(2.0, 2.0), &rule).unwrap();
/// assert!(p.x.abs() < 1e-12 && (p.y - 2.01).abs() < 1e-12);
/// ```
pub fn echo_at_range(beam: &Beam, a: &Point, b: &Point, rule: &SettleRule) -> Option<Point> {
    let echo = rule.plane_echo(beam, a, b)?;
    let towards = (a + (b - a) * echo.along) - beam.origin;
    let distance_m = towards.norm();
    (distance_m > 0.0).then(|| beam.origin + towards * (beam.range_m / distance_m))
}

impl SettleRule {
    /// The rule for a sonar of accuracy `accuracy_pct` (ξ, percent) whose beam opens
    /// `2·half_beam_rad`, a plane's echo taken as `echo` says, with the margin
    /// `end_margin_m`.
    pub fn new(
        accuracy_pct: f64,
        half_beam_rad: f64,
        echo: PlaneEchoModel,
        end_margin_m: f64,
    ) -> Self {
        Self {
            accuracy_pct,
            half: HalfCone::new(half_beam_rad),
            echo,
            end_margin_m,
        }
    }

    /// [`plane_echo`](crate::mapping::ext::confirm::plane_echo) of `beam` off the wall `a`–`b` under this rule.
    fn plane_echo(&self, beam: &Beam, a: &Point, b: &Point) -> Option<PlaneEcho> {
        plane_echo_in(beam, a, b, self.accuracy_pct, self.half, self.echo)
    }
}

/// How far a point at `along` (0 at one end, 1 at the other) of a wall `length_m` long lies
/// inside its nearer end, metres (negative past it).
fn inside_ends_m(along: f64, length_m: f64) -> f64 {
    (along * length_m).min((1.0 - along) * length_m)
}

/// A confirmed fitted wall near a reading, as [`settling_wall`] gathers them.
#[derive(Clone, Copy, Debug)]
pub struct NearWall {
    id: SegmentId,
    a: Point,
    b: Point,
}

/// How far the wall `w` (which explains the reading, its echo point at `x` along it) and the
/// confirmed walls that continue it reach past the echo point on either side, metres (the
/// smaller of the two). A wall continues the chain when both its ends lie within `tolerance_m`
/// of `w`'s line and it overlaps the chain so far or ends within `tolerance_m` of it: walls are
/// mapped as chains of overlapping pieces (§8.13), and end-points are placed within the
/// tolerance, so a gap inside it is no gap the readings resolve; a wider gap may stand across a
/// door or past a true end.
fn chained_inside_m(w: &NearWall, x: f64, walls: &[NearWall], tolerance_m: f64) -> f64 {
    let length_m = (w.b - w.a).norm();
    let u = (w.b - w.a) / length_m;
    // Reaches past the echo point, towards a and towards b.
    let (mut back_m, mut ahead_m) = (x * length_m, (1.0 - x) * length_m);
    let origin = w.a + (w.b - w.a) * x;
    let on_line = |c: &NearWall| {
        distance_to_line(&c.a, &w.a, &w.b) <= tolerance_m
            && distance_to_line(&c.b, &w.a, &w.b) <= tolerance_m
    };
    // A chain of n pieces takes at most n passes.
    for _ in 0..walls.len() {
        let mut grew = false;
        for c in walls.iter().filter(|c| c.id != w.id && on_line(c)) {
            let (p, q) = ((c.a - origin).dot(&u), (c.b - origin).dot(&u));
            let (low, high) = (p.min(q), p.max(q));
            if low <= ahead_m + tolerance_m && high > ahead_m {
                ahead_m = high;
                grew = true;
            }
            if high >= -back_m - tolerance_m && -low > back_m {
                back_m = -low;
                grew = true;
            }
        }
        if !grew {
            break;
        }
    }
    back_m.min(ahead_m)
}

/// How far the echo point at `along` lies inside the ends of wall `w`, metres, or, when that is
/// less than `end_margin_m`, inside the ends of the chain of the walls of `walls` continuing it
/// ([`chained_inside_m`]).
fn inside_wall_or_chain_m(
    w: &NearWall,
    along: f64,
    walls: &[NearWall],
    tolerance_m: f64,
    end_margin_m: f64,
) -> f64 {
    let alone_m = inside_ends_m(along, (w.b - w.a).norm());
    if alone_m >= end_margin_m {
        alone_m
    } else {
        chained_inside_m(w, along, walls, tolerance_m)
    }
}

/// The confirmed fitted walls the grid files in the box of `beam`'s cone within one tolerance of
/// the range (where the echo point of a wall that explains it lies), widened by the margin,
/// into `near`; returns the tolerance.
fn gather_near_walls(map: &Map, beam: &Beam, rule: &SettleRule, near: &mut Vec<NearWall>) -> f64 {
    let tolerance_m = feature_tolerance_m(rule.accuracy_pct, beam.range_m);
    let (low, high, bulge_m) = cone_box_in(
        beam,
        rule.half,
        (beam.range_m - tolerance_m).max(0.0),
        beam.range_m + tolerance_m,
    );
    near.clear();
    map.visit_segments_along(&low, &high, bulge_m + rule.end_margin_m, |id, s| {
        if !s.fitted || !map.is_confirmed(id) {
            return;
        }
        let (a, b) = (s.a.point, s.b.point);
        near.push(NearWall { id, a, b });
    });
    tolerance_m
}

/// The confirmed fitted wall of `map` that settles `beam`'s reading, the one whose prediction is
/// nearest the range (the lower id on a tie), with its predicted range and how far the echo
/// point lies inside the ends of the wall and the confirmed pieces that continue it. A wall
/// settles the reading when it explains it as a plane echo
/// ([`plane_echo`](crate::mapping::ext::confirm::plane_echo), the test a reading takes to confirm it, §8.7,
/// the echo taken where `rule.echo` says) and the echo point lies at least
/// `rule.end_margin_m` inside both ends of the chain of confirmed walls along its line that
/// overlap or leave gaps within the tolerance (`chained_inside_m`): a wall mapped as pieces
/// settles readings near the joints of its pieces, not at its ends. The walls are those the
/// grid files in the box of the beam's cone within one tolerance of the range (where the echo
/// point of a wall that explains it lies), widened by the margin; `near` is scratch.
pub fn settling_wall(
    map: &Map,
    beam: &Beam,
    rule: &SettleRule,
    near: &mut Vec<NearWall>,
) -> Option<(SegmentId, f64, f64)> {
    let settling = settling_walls(map, beam, rule, near);
    let residual = |p: f64| (p - beam.range_m).abs();
    settling.fold(None, |best, (id, predicted_m, inside_m)| {
        let better =
            best.is_none_or(|(bid, bp, _)| (residual(predicted_m), id) < (residual(bp), bid));
        if better {
            Some((id, predicted_m, inside_m))
        } else {
            best
        }
    })
}

/// The confirmed fitted walls near `beam` (gathered into `near`, see [`gather_near_walls`])
/// that settle its reading, in the order gathered, each with its predicted range and how far
/// its echo point lies inside its ends or its chain's ([`inside_wall_or_chain_m`]), at least
/// `rule.end_margin_m`. Lazy: a caller that needs one stops at the first, and a wall's echo is
/// found only when the search comes to it.
fn settling_walls<'a>(
    map: &Map,
    beam: &'a Beam,
    rule: &'a SettleRule,
    near: &'a mut Vec<NearWall>,
) -> impl Iterator<Item = (SegmentId, f64, f64)> + 'a {
    let tolerance_m = gather_near_walls(map, beam, rule, near);
    let near: &'a [NearWall] = near;
    let end_margin_m = rule.end_margin_m;
    near.iter().filter_map(move |w| {
        let echo = rule.plane_echo(beam, &w.a, &w.b)?;
        let inside_m = inside_wall_or_chain_m(w, echo.along, near, tolerance_m, end_margin_m);
        (inside_m >= end_margin_m).then_some((w.id, echo.range_m, inside_m))
    })
}

/// Whether some confirmed fitted wall of `map` settles `beam`'s reading ([`settling_wall`]
/// finds one), and which: the first found, not the best. Whether a reading is settled is all a
/// step needs of it untraced (a settled reading only leaves the step), and the wall that
/// settled the sensor's previous reading (`hint`) is tried first, by itself: it settles most
/// readings of a wall read again, without a query of the grid. `near` is scratch.
pub fn any_settling_wall(
    map: &Map,
    beam: &Beam,
    rule: &SettleRule,
    hint: Option<SegmentId>,
    near: &mut Vec<NearWall>,
) -> Option<SegmentId> {
    // The hint alone ([`settles`]: its echo point at least the margin inside its own ends; a
    // chain only reaches further). Such an echo point lies in the query's box, so the search
    // below would find the wall too.
    if let Some(id) = hint.filter(|&id| map.is_confirmed(id)) {
        if let Some(s) = map.segment(id).filter(|s| s.kind == SegmentKind::Fitted) {
            let (a, b) = (&s.a.point, &s.b.point);
            if settles(beam, a, b, rule).is_some() {
                return Some(id);
            }
        }
    }
    settling_walls(map, beam, rule, near)
        .next()
        .map(|(id, _, _)| id)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Vec2;
    use crate::mapping::model::map::{test_wall, Segment};
    use crate::mapping::model::plane_supports::PlaneSupport;

    const HALF: f64 = 0.218_166_156_499_291_6; // 12.5°
    /// ξ 3 %, that half beam, the echo at the foot, a 0.3 m margin.
    fn rule() -> SettleRule {
        SettleRule::new(3.0, HALF, PlaneEchoModel::Foot, 0.3)
    }

    /// [`rule`] with the cone's edges.
    fn edges() -> SettleRule {
        SettleRule {
            echo: PlaneEchoModel::NearestInCone,
            ..rule()
        }
    }

    fn confirmed(map: &mut Map, id: SegmentId) {
        map.plane_support.insert(
            id,
            PlaneSupport {
                snapshots: 2,
                last_snapshot: 1,
                ..Default::default()
            },
        );
    }

    /// A map of `walls`, those with ids in `confirmed_ids` confirmed.
    fn map_of(walls: Vec<Segment>, confirmed_ids: &[SegmentId]) -> Map {
        let mut map = Map::from_segments(walls);
        for &id in confirmed_ids {
            confirmed(&mut map, id);
        }
        map
    }

    /// A test wall's end-points, (x, y) metres.
    type Ends = ((f64, f64), (f64, f64));

    /// The pieces' test wall: s0 from x = 0.2 to 1.1 along y = 2, then `rest` (ids 1, 2, …,
    /// each from and to the points given), all read at 2 m; s0 and s1 confirmed.
    fn s0_then(rest: &[Ends]) -> Map {
        let s0 = test_wall(0, (0.2, 2.0), (1.1, 2.0), 2.0);
        let later = rest
            .iter()
            .zip(1..)
            .map(|(&(a, b), id)| test_wall(id, a, b, 2.0));
        map_of(std::iter::once(s0).chain(later).collect(), &[0, 1])
    }

    fn looking_up_from(x: f64, range_m: f64) -> Beam {
        Beam {
            origin: Point::new(x, 0.0),
            direction: Vec2::new(0.0, 1.0),
            range_m,
        }
    }

    #[test]
    fn only_a_confirmed_wall_settles_a_reading() {
        let mut map = Map::from_segments(vec![test_wall(0, (0.0, 2.0), (3.0, 2.0), 2.0)]);
        let beam = looking_up_from(1.5, 2.03);
        assert_eq!(settling_wall(&map, &beam, &rule(), &mut Vec::new()), None);
        confirmed(&mut map, 0);
        let (id, predicted, inside) = settling_wall(&map, &beam, &rule(), &mut Vec::new()).unwrap();
        assert_eq!(id, 0);
        assert!((predicted - 2.0).abs() < 1e-12);
        // The foot (1.5, 2) is 1.5 m from either end.
        assert!((inside - 1.5).abs() < 1e-12);
    }

    #[test]
    fn a_wall_mapped_as_overlapping_pieces_settles_readings_at_its_joints_not_at_its_ends() {
        // s0 runs from x = 0.2 to 1.1 along y = 2, s1 from 1.05 to 2.0: they overlap by 5 cm.
        // A 2.03 m reading from (1, 0) has its foot at x = 1, 0.1 m from s0's end (less than
        // the 0.3 m margin), but s1 carries the wall on to x = 2: the chain reaches 0.8 m back
        // and 1.0 m ahead of the foot. Both pieces predict 2.0 m; the lower id settles it.
        let map = s0_then(&[((1.05, 2.0), (2.0, 2.0))]);
        let settle = |map: &Map, x: f64| {
            settling_wall(map, &looking_up_from(x, 2.03), &rule(), &mut Vec::new())
        };
        let (id, predicted, inside) = settle(&map, 1.0).unwrap();
        assert_eq!(id, 0);
        assert!((predicted - 2.0).abs() < 1e-12);
        assert!((inside - 0.8).abs() < 1e-12, "{inside}");
        // At x = 1.9 the foot is 0.1 m from the chain's end: it may go on, not settled.
        assert_eq!(settle(&map, 1.9), None);
        // With s1 starting 5 cm past s0's end, a gap within the reading's 6.09 cm tolerance
        // (3 % of 2.03 m), the chain goes on across it: the foot at x = 1 is settled, 0.8 m
        // from the chain's nearer end.
        let within = s0_then(&[((1.15, 2.0), (2.0, 2.0))]);
        let (_, _, inside) = settle(&within, 1.0).unwrap();
        assert!((inside - 0.8).abs() < 1e-12, "{inside}");
        // Starting 7 cm past it (a gap wider than the tolerance, perhaps a door), s1 does not
        // continue s0 (nor explain the reading: its foot lies 0.17 m before it, past the 10 %
        // slack), and the foot is 0.1 m from the end of s0: not settled.
        let gapped = s0_then(&[((1.17, 2.0), (2.0, 2.0))]);
        assert_eq!(settle(&gapped, 1.0), None);
        // A piece off the line (7 cm, past the 6.09 cm tolerance) does not continue it either.
        let off = s0_then(&[((1.05, 2.07), (2.0, 2.07))]);
        assert_eq!(settle(&off, 1.0), None);
    }

    #[test]
    fn any_settling_wall_settles_what_the_best_one_settles_whatever_the_hint() {
        // The chain of the test above (s0 0.2–1.1, s1 1.05–2.0 along y = 2, both confirmed)
        // and a tentative s2 (2.2–3.0), read every 5 cm from x = 0.025 to 3.175 at 2.03 m (and
        // at 2.2 m, explained by nothing), with each hint: settled exactly when the best-wall
        // search settles, and by a wall that settles the reading.
        let map = s0_then(&[((1.05, 2.0), (2.0, 2.0)), ((2.2, 2.0), (3.0, 2.0))]);
        let mut settled = 0;
        for i in 0..64 {
            for range_m in [2.03, 2.2] {
                let beam = looking_up_from(0.025 + i as f64 * 0.05, range_m);
                let best = settling_wall(&map, &beam, &rule(), &mut Vec::new());
                for hint in [None, Some(0), Some(1), Some(2), Some(9)] {
                    let any = any_settling_wall(&map, &beam, &rule(), hint, &mut Vec::new());
                    assert_eq!(any.is_some(), best.is_some(), "reading {i}, hint {hint:?}");
                    if let Some(id) = any {
                        // The wall found settles the reading by itself, or as part of the chain.
                        assert!(id == 0 || id == 1, "{id}");
                    }
                }
                settled += usize::from(best.is_some());
            }
        }
        // From x = 0.525 to 1.675 (more than 0.3 m inside the chain's ends): 24 of the 128.
        assert_eq!(settled, 24);
    }

    #[test]
    fn of_two_confirmed_walls_the_one_predicting_the_range_best_settles_it() {
        // Two confirmed walls 4 cm apart, both within the tolerance of a 2.03 m reading
        // (0.0609 m): the one at 2.04 m (residual 0.01) wins over the one at 2.00 (0.03).
        let map = map_of(
            vec![
                test_wall(0, (0.0, 2.0), (3.0, 2.0), 2.0),
                test_wall(1, (0.0, 2.04), (3.0, 2.04), 2.0),
            ],
            &[0, 1],
        );
        let (id, predicted, _) =
            settling_wall(&map, &looking_up_from(1.0, 2.03), &rule(), &mut Vec::new()).unwrap();
        assert_eq!(id, 1);
        assert!((predicted - 2.04).abs() < 1e-12);
    }

    #[test]
    fn an_oblique_wall_settles_its_cone_edge_echo_only_with_cone_edges() {
        // The wall y = 2 from x = -1 to 3, seen from the origin 30° off its normal: the cone's
        // edge meets it 17.5° off the normal, at 2 / cos 17.5° = 2.0971 m, at x = 0.6306.
        let mut map = Map::from_segments(vec![test_wall(0, (-1.0, 2.0), (3.0, 2.0), 2.0)]);
        confirmed(&mut map, 0);
        let dir = Vec2::new(60f64.to_radians().cos(), 60f64.to_radians().sin());
        let beam = Beam {
            origin: Point::origin(),
            direction: dir,
            range_m: 2.10,
        };
        assert_eq!(settling_wall(&map, &beam, &rule(), &mut Vec::new()), None);
        let (_, predicted, inside) = settling_wall(&map, &beam, &edges(), &mut Vec::new()).unwrap();
        assert!((predicted - 2.0971).abs() < 1e-4);
        // 1.6306 m from the end at x = -1.
        assert!((inside - 1.6306).abs() < 1e-4);
    }
}
