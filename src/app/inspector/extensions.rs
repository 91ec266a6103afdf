//! What the flagged extensions of docs/algorithm.md §8 did in this step, with their
//! numbers: arcs filed as corners or edges, readings explained by a feature, segments a reading
//! saw past, plane support, the plane gate, echo placement (§8.10), corner diagonals (§8.11),
//! readings a confirmed wall settled (§8.12), pillars found among the diagonals' echoes
//! (§8.14), cluster links broken across a right angle (§8.20), where point memory cut a bent
//! group (§8.1), the stacks it let go (§8.15), the joints it kept (§8.16) and the readings much
//! shorter than their sensor's last echo (§8.21).

use super::context::InspectCtx;
use super::widgets::heading;
use crate::geometry::wrap_pi;
use crate::mapping::ext::beam_geometry::feature_tolerance_m;
use crate::mapping::ext::corner_diagonals::CORNER_WALL_REACH_M;
use crate::mapping::ext::point_memory::range_span_m;
use crate::mapping::model::ext_trace::SeenThroughCut;
use crate::mapping::model::map::ReadingRef;
use egui::RichText;

/// One line for each stack point memory let go this step (§8.15).
fn stacks(ctx: &InspectCtx, out: &mut Vec<RichText>) {
    let Some(memory) = &ctx.view.trace.memory else {
        return;
    };
    let xi = ctx.params.accuracy_pct;
    for group in &memory.groups {
        for &k in &group.stacks {
            let [first, last] = group.pieces[k];
            let readings = &group.points[first..=last];
            let centre = readings
                .iter()
                .map(|q| q.point.coords)
                .sum::<nalgebra::Vector2<f64>>()
                / readings.len() as f64;
            let (near_m, far_m) = range_span_m(readings);
            let names: Vec<String> = readings
                .iter()
                .map(|q| format!("{}/{}", q.reading.snapshot(), q.reading.sensor()))
                .collect();
            out.push(RichText::new(format!(
                "stack: readings {} (snapshot/sensor) lie at one place, {}, pairwise within \
                 ξ·(D1+D2)/100 = {} %, but read from {} to {}: the sonar moved along its beam, \
                 so their line has no direction; they leave point memory without a segment",
                names.join(", "),
                ctx.point(&nalgebra::Point2::from(centre)),
                2.0 * xi,
                ctx.len(near_m),
                ctx.len(far_m),
            )));
        }
    }
}

/// One line for each cluster link broken across a right angle that `t_gap` would have kept
/// (§8.20).
fn right_angle_breaks(ctx: &InspectCtx, out: &mut Vec<RichText>) {
    let mounts = &ctx.run.layout.mounts;
    let gaps = &ctx.view.trace.gaps;
    for (i, g) in gaps.iter().enumerate() {
        // A ring's chain of two readings links them both ways round: one line for the pair.
        let pair = |h: &crate::mapping::model::trace::GapTrace| {
            (
                h.from_sensor.min(h.to_sensor),
                h.from_sensor.max(h.to_sensor),
            )
        };
        let listed = gaps[..i].iter().any(|h| pair(h) == pair(g));
        if !g.across_right_angle || g.distance_m > g.t_gap_m || listed {
            continue;
        }
        let apart_deg = match (mounts.get(g.from_sensor), mounts.get(g.to_sensor)) {
            (Some(a), Some(b)) => format!(
                "{:.0}°",
                wrap_pi(a.heading_rad - b.heading_rad).abs().to_degrees()
            ),
            _ => "?".to_string(),
        };
        out.push(RichText::new(format!(
            "right-angle break: sensors {} and {}, axes {apart_deg} apart, read points {} apart \
             (within t_gap {}), but no plane echoes to both from inside their cones: two \
             clusters, not a chord across a corner",
            g.from_sensor,
            g.to_sensor,
            ctx.len(g.distance_m),
            ctx.len(g.t_gap_m),
        )));
    }
}

/// One line for each group whose axis order point memory cut before its fit (§8.1).
fn cuts(ctx: &InspectCtx, out: &mut Vec<RichText>) {
    let Some(memory) = &ctx.view.trace.memory else {
        return;
    };
    for group in &memory.groups {
        // Each cut: the readings either side of it and their distance.
        let pairs: Vec<_> = group
            .cuts
            .iter()
            .filter_map(|&k| Some((group.points.get(k.checked_sub(1)?)?, group.points.get(k)?)))
            .map(|(a, b)| (a, b, (b.point - a.point).norm()))
            .collect();
        let Some(&(a, b, _)) = pairs.first() else {
            continue;
        };
        let widest_m = pairs.iter().map(|p| p.2).fold(0.0, f64::max);
        out.push(RichText::new(format!(
            "point memory cut: a group of {} readings is cut in {} place(s) where readings next \
             along its axis lie more than memory_gap {} apart (first between {}/{} and {}/{}, \
             snapshot/sensor; widest {}): the group is bent (a corner), and its runs are fitted \
             apart, so no piece spans a gap",
            group.points.len(),
            pairs.len(),
            ctx.len(ctx.params.memory_gap_m),
            a.reading.snapshot(),
            a.reading.sensor(),
            b.reading.snapshot(),
            b.reading.sensor(),
            ctx.len(widest_m),
        )));
    }
}

/// One line for each joint point memory kept this step (§8.16).
fn joints(ctx: &InspectCtx, out: &mut Vec<RichText>) {
    let Some(memory) = &ctx.view.trace.memory else {
        return;
    };
    let place = |reading: ReadingRef| {
        memory
            .groups
            .iter()
            .flat_map(|g| &g.points)
            .find(|q| q.reading == reading)
            .map_or_else(String::new, |q| format!(" at {}", ctx.point(&q.point)))
    };
    for &r in &memory.joints {
        out.push(RichText::new(format!(
            "joint: reading {}/{} (snapshot/sensor){}, the newest end of a piece that became a \
             segment, stays in point memory: the next piece along the chain shares it, so the \
             two overlap and match instead of leaving a reading's spacing between them",
            r.snapshot(),
            r.sensor(),
            place(r),
        )));
    }
}

/// One line for each of the step's arcs filed as point features (§8.5).
fn arcs(ctx: &InspectCtx, out: &mut Vec<RichText>) {
    let xi = ctx.params.accuracy_pct;
    for a in &ctx.view.trace.arcs {
        out.push(RichText::new(format!(
            "arc: cluster {} (sensors {:?}) ranges {} to {}, pairwise within ξ·(D1+D2)/100 = {} %: \
             one reflector at {} -> feature f{}{}{}",
            a.cluster,
            a.sensors,
            ctx.len(a.range_min_m),
            ctx.len(a.range_max_m),
            2.0 * xi,
            ctx.point(&a.at),
            a.feature,
            if a.new_feature { " (new)" } else { "" },
            if a.also_fitted {
                "; one plane explains the ranges as well (a wall seen square-on?): fitted too"
            } else {
                ""
            }
        )));
    }
}

/// One line for each of the step's readings a confirmed feature explained (§8.5).
fn explained(ctx: &InspectCtx, out: &mut Vec<RichText>) {
    for e in &ctx.view.trace.explained {
        // A pillar (§8.14) echoes from its surface, its radius short of its centre.
        let radius_m = ctx
            .view
            .map_before
            .feature(e.feature)
            .map_or(0.0, |f| f.radius_m);
        let surface = if radius_m > 0.0 {
            format!(
                " (a pillar of radius {}: its surface {} away)",
                ctx.len(radius_m),
                ctx.len(e.feature_distance_m - radius_m)
            )
        } else {
            String::new()
        };
        out.push(RichText::new(format!(
            "explained: sensor {} read {}; confirmed feature f{} lies {} away{}, {:.1}° off \
             the axis: its echo, kept out of the clusters",
            e.sensor,
            ctx.len(e.range_m),
            e.feature,
            ctx.len(e.feature_distance_m),
            surface,
            e.off_axis_rad.to_degrees()
        )));
    }
}

/// One line for each of the step's readings set aside as much shorter than their sensor's last
/// echo (§8.21).
fn shorter_than_last(ctx: &InspectCtx, out: &mut Vec<RichText>) {
    for r in &ctx.view.trace.readings {
        let (Some(s), Some(range_m)) = (r.shorter_than_last, r.range_m) else {
            continue;
        };
        out.push(RichText::new(format!(
            "echo agreement: sensor {} read {} after {}, {} shorter where {} may be: joins no \
             cluster (§8.21)",
            r.sensor,
            ctx.len(range_m),
            ctx.len(s.last_m),
            ctx.len(s.last_m - range_m),
            ctx.len(s.tolerance_m)
        )));
    }
}

/// One line for each of the step's readings a confirmed wall settled (§8.12).
fn settled(ctx: &InspectCtx, out: &mut Vec<RichText>) {
    let xi = ctx.params.accuracy_pct;
    for e in &ctx.view.trace.settled {
        out.push(RichText::new(format!(
            "settled: sensor {} read {}; confirmed wall s{} predicts {} (tolerance {}), its \
             echo {} inside the nearer end (of the wall and the confirmed pieces continuing it): \
             kept out of the clusters, point memory and the free-space sweep of §8.6 (§8.18 \
             still looks through it near an edge)",
            e.sensor,
            ctx.len(e.range_m),
            e.segment,
            ctx.len(e.predicted_m),
            ctx.len(feature_tolerance_m(xi, e.range_m)),
            ctx.len(e.inside_m)
        )));
    }
}

/// One line for each of the step's segments a reading saw past (§8.6).
fn refuted(ctx: &InspectCtx, out: &mut Vec<RichText>) {
    for r in &ctx.view.trace.refuted {
        out.push(RichText::new(format!(
            "free space: sensor {} read {} but s{} lies {} away, {:.1}° off the axis (a plane \
             there echoes from that foot): removed",
            r.sensor,
            ctx.len(r.range_m),
            r.segment,
            ctx.len(r.distance_m),
            r.off_axis_rad.to_degrees()
        )));
    }
}

/// One line for each segment part the step's readings saw through and cut away (§8.18).
fn seen_through(ctx: &InspectCtx, out: &mut Vec<RichText>) {
    for c in &ctx.view.trace.seen_through {
        let [from, to] = c.free_part;
        let what = match c.cut {
            SeenThroughCut::EndA => "its end a moved to the free part's edge".to_string(),
            SeenThroughCut::EndB => "its end b moved to the free part's edge".to_string(),
            SeenThroughCut::Split { piece } => format!("a hole: s{piece} is the part beyond it"),
            SeenThroughCut::Removed => "too little was left: removed".to_string(),
        };
        out.push(RichText::new(format!(
            "seen through: sensor {} read {}, past s{} from ({}, {}) to ({}, {}) inside its \
             beam ({} readings dropped): {what}",
            c.sensor,
            ctx.len(c.range_m),
            c.segment,
            ctx.len(from[0]),
            ctx.len(from[1]),
            ctx.len(to[0]),
            ctx.len(to[1]),
            c.dropped_points,
        )));
    }
}

/// One line for each of the step's segments a refit moved off their line (§8.7).
fn unconfirmed(ctx: &InspectCtx, out: &mut Vec<RichText>) {
    for u in &ctx.view.trace.unconfirmed {
        let outcome = if u.tentative {
            "the support counted for its old line is dropped (refit_recounts)"
        } else {
            "tentative again"
        };
        out.push(RichText::new(format!(
            "refit moved s{} off its line (turned {:.1}°, limit {:.1}°; ends {} and {} off it, \
             limits {} and {}): {outcome}",
            u.segment,
            u.turn_rad.to_degrees(),
            ctx.params.orientation_rad.to_degrees(),
            ctx.len(u.off_line_m[0]),
            ctx.len(u.off_line_m[1]),
            ctx.len(u.limits_m[0]),
            ctx.len(u.limits_m[1]),
        )));
    }
}

/// One line for each of the step's plane and baseline support (§8.7).
fn plane_support(ctx: &InspectCtx, out: &mut Vec<RichText>) {
    for p in &ctx.view.trace.plane_support {
        if let Some(b) = &p.baseline {
            out.push(RichText::new(format!(
                "baseline confirmation: readings of snapshots {} (sensor {}) and {} (sensor {}) \
                 support s{} as a plane, their sensors {} apart along it and {} across: confirmed",
                b.readings[0].snapshot,
                b.readings[0].sensor,
                b.readings[1].snapshot,
                b.readings[1].sensor,
                p.segment,
                ctx.len(b.along_m),
                ctx.len(b.across_m),
            )));
            continue;
        }
        let state = if p.confirmed {
            "confirmed"
        } else {
            "tentative"
        };
        if let Some(off_deg) = p.off_axis_deg {
            out.push(RichText::new(format!(
                "plane support not counted: sensor {} read {}, s{} lies {} away, but only off \
                 the cone's edge, and s{} is {off_deg:.1}° off the map's axes, more than θ_o \
                 (off_axis_square_on: it must be seen square on); {} view(s), {state}",
                p.sensor,
                ctx.len(p.range_m),
                p.segment,
                ctx.len(p.distance_m),
                p.segment,
                p.snapshots,
            )));
            continue;
        }
        if let Some(moved_m) = p.same_view_moved_m {
            out.push(RichText::new(format!(
                "plane support not counted: sensor {} read {}, s{} lies {} away, but the robot \
                 stood {} from the last view's place, under confirm_spacing: the same view; {} \
                 view(s), {state}",
                p.sensor,
                ctx.len(p.range_m),
                p.segment,
                ctx.len(p.distance_m),
                ctx.len(moved_m),
                p.snapshots,
            )));
            continue;
        }
        out.push(RichText::new(format!(
            "plane support: sensor {} read {}, s{} lies {} away: {} view(s), {state}",
            p.sensor,
            ctx.len(p.range_m),
            p.segment,
            ctx.len(p.distance_m),
            p.snapshots,
        )));
    }
}

/// One line for each of the step's echo placement (§8.10).
fn echo_fits(ctx: &InspectCtx, out: &mut Vec<RichText>) {
    for e in &ctx.view.trace.echo_fits {
        out.push(RichText::new(format!(
            "echo placement: {}: one plane explains its ranges (worst {:.2} of the tolerance): \
             its normal at {:.1}°; {} reading(s) moved to the foot of the perpendicular, {} to \
             the cone's edge, by up to {}",
            if e.dropped {
                "a piece".to_string()
            } else {
                format!("n{}", e.new_segment)
            },
            e.line.worst_residual_over_tolerance,
            e.line.normal.y.atan2(e.line.normal.x).to_degrees(),
            e.at_foot,
            e.at_cone_edge,
            ctx.len(e.moved_max_m)
        )));
        if let Some(at) = e.reflector {
            out.push(RichText::new(format!(
                "  one reflector at {} explains its ranges better than the line: a corner or an \
                 edge, filed as a point feature and not added as a segment",
                ctx.point(&at)
            )));
        }
        if e.behind_confirmed_wall > 0 {
            out.push(RichText::new(format!(
                "  {} of its echo points lie behind a confirmed wall{}",
                e.behind_confirmed_wall,
                if e.dropped && e.reflector.is_none() {
                    ": more than half, so it was not added"
                } else {
                    ""
                }
            )));
        }
    }
}

/// One line for each of the step's corner diagonals removed (§8.11).
fn diagonals(ctx: &InspectCtx, out: &mut Vec<RichText>) {
    for d in &ctx.view.trace.diagonals {
        out.push(RichText::new(format!(
            "corner diagonal: s{} ({} to {}) lies {} and {} from the junction {} of s{} and s{} \
             ({:.1} deg apart; within {} of each), turned {:.1} and {:.1} deg from them \
             (at least {:.1}): a corner's echoes, not a wall: removed",
            d.segment,
            ctx.point(&d.ends[0]),
            ctx.point(&d.ends[1]),
            ctx.len(d.end_distances_m[0]),
            ctx.len(d.end_distances_m[1]),
            ctx.point(&d.junction),
            d.walls[0],
            d.walls[1],
            d.corner_angle_rad.to_degrees(),
            ctx.len(CORNER_WALL_REACH_M),
            d.angles_rad[0].to_degrees(),
            d.angles_rad[1].to_degrees(),
            ctx.params.orientation_rad.to_degrees()
        )));
    }
}

/// One line for each of the step's pillars filed (§8.14).
fn pillars(ctx: &InspectCtx, out: &mut Vec<RichText>) {
    for r in &ctx.view.trace.round_reflectors {
        out.push(RichText::new(format!(
            "pillar: one cylinder, centre {} radius {}, explains {} readings of removed \
             diagonals (each |c - o| - r within its tolerance), heard from sensors {} apart: \
             feature f{}",
            ctx.point(&r.centre),
            ctx.len(r.radius_m),
            r.readings,
            ctx.len(r.baseline_m),
            r.feature
        )));
    }
}

/// One line for each of the step's new faces the plane gate refused (§8.7).
fn gated(ctx: &InspectCtx, out: &mut Vec<RichText>) {
    for n in &ctx.view.trace.gated {
        out.push(
            RichText::new(format!(
                "plane gate: n{n} would be a new face, but no reading of it lies at its range \
                 from the line inside its beam: not added"
            ))
            .weak(),
        );
    }
}

/// Each extension's lines, in the order they are shown.
const EXTENSION_LINES: &[fn(&InspectCtx, &mut Vec<RichText>)] = &[
    shorter_than_last,
    arcs,
    explained,
    settled,
    right_angle_breaks,
    cuts,
    stacks,
    joints,
    refuted,
    seen_through,
    unconfirmed,
    plane_support,
    echo_fits,
    diagonals,
    pillars,
    gated,
];

/// The step's extension records; nothing when none acted.
pub(super) fn extensions_ui(ui: &mut egui::Ui, ctx: &InspectCtx) {
    let mut lines = Vec::new();
    for extension in EXTENSION_LINES {
        extension(ctx, &mut lines);
    }
    if lines.is_empty() {
        return;
    }
    heading(ui, "Extensions this step");
    for line in lines {
        ui.label(line);
    }
}
