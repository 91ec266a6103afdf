//! Colours and styles. The palette is Okabe–Ito (readable by colour-blind readers); every
//! colour used is mid-tone so it reads on light and dark backgrounds. Outcomes of matching
//! differ in dash pattern and marker as well as colour.

use super::layer::Layer;
use super::marker::MarkerShape;

/// An sRGB colour with straight alpha.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Rgba {
    /// Red.
    pub r: u8,
    /// Green.
    pub g: u8,
    /// Blue.
    pub b: u8,
    /// Alpha (255 opaque).
    pub a: u8,
}

impl Rgba {
    /// An opaque colour.
    pub const fn rgb(r: u8, g: u8, b: u8) -> Self {
        Rgba { r, g, b, a: 255 }
    }

    /// The same colour with alpha `a`.
    pub const fn with_alpha(self, a: u8) -> Self {
        Rgba { a, ..self }
    }

    /// `#rrggbb` (alpha left out).
    pub fn hex(self) -> String {
        format!("#{:02x}{:02x}{:02x}", self.r, self.g, self.b)
    }
}

/// The Okabe–Ito palette and a neutral grey.
pub mod palette {
    use super::Rgba;
    /// Orange.
    pub const ORANGE: Rgba = Rgba::rgb(0xE6, 0x9F, 0x00);
    /// Sky blue.
    pub const SKY_BLUE: Rgba = Rgba::rgb(0x56, 0xB4, 0xE9);
    /// Bluish green.
    pub const BLUISH_GREEN: Rgba = Rgba::rgb(0x00, 0x9E, 0x73);
    /// Yellow (only as a wide translucent highlight: too light for thin lines on white).
    pub const YELLOW: Rgba = Rgba::rgb(0xF0, 0xE4, 0x42);
    /// Blue: this snapshot (the paper's figures).
    pub const BLUE: Rgba = Rgba::rgb(0x00, 0x72, 0xB2);
    /// Vermillion: the previous snapshot (the paper's "red").
    pub const VERMILLION: Rgba = Rgba::rgb(0xD5, 0x5E, 0x00);
    /// Reddish purple.
    pub const REDDISH_PURPLE: Rgba = Rgba::rgb(0xCC, 0x79, 0xA7);
    /// Neutral mid grey (reads on white and on black).
    pub const GREY: Rgba = Rgba::rgb(0x88, 0x88, 0x88);
    /// Colours cycled through for clusters.
    pub const CLUSTERS: [Rgba; 5] = [ORANGE, SKY_BLUE, REDDISH_PURPLE, BLUISH_GREEN, VERMILLION];
}

/// How a primitive is drawn. Widths, dashes and sizes are in screen pixels.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Style {
    /// Outline / line colour; `None` draws no outline.
    pub stroke: Option<Rgba>,
    /// Fill colour; `None` leaves the inside empty.
    pub fill: Option<Rgba>,
    /// Line width, screen pixels.
    pub stroke_width_px: f32,
    /// Dash pattern (on, off, ...), screen pixels; empty is solid.
    pub dash_px: &'static [f32],
    /// Marker size (and text size for texts), screen pixels.
    pub marker_size_px: f32,
    /// Overall opacity in [0, 1], applied on top of the colours' alpha.
    pub opacity: f32,
}

impl Style {
    /// A solid line.
    pub const fn line(colour: Rgba, width_px: f32) -> Self {
        Style {
            stroke: Some(colour),
            fill: None,
            stroke_width_px: width_px,
            dash_px: &[],
            marker_size_px: 0.0,
            opacity: 1.0,
        }
    }

    /// The style with dash pattern `dash_px`.
    pub const fn dashed(self, dash_px: &'static [f32]) -> Self {
        Style { dash_px, ..self }
    }

    /// The style with fill `fill`.
    pub const fn filled(self, fill: Rgba) -> Self {
        Style {
            fill: Some(fill),
            ..self
        }
    }

    /// The style with marker (or text) size `size_px`.
    pub const fn sized(self, size_px: f32) -> Self {
        Style {
            marker_size_px: size_px,
            ..self
        }
    }

    /// The style with opacity `opacity`.
    pub const fn faded(self, opacity: f32) -> Self {
        Style { opacity, ..self }
    }
}

/// How a legend entry draws its sample.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Glyph {
    /// A short line in the style.
    Line,
    /// A short line with a marker in its middle.
    LineWithMarker(MarkerShape),
    /// A marker alone.
    Marker(MarkerShape),
    /// A filled circle or area.
    Area,
    /// No sample (texts).
    None,
}

/// What a primitive depicts. Each role has one default style and one legend entry; the order
/// of the variants is the legend's order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Role {
    /// A ground-truth wall or pillar.
    FloorPlan,
    /// A map segment as it stood before the step.
    MapBefore,
    /// A sonar beam wedge.
    Beam,
    /// A ray from a transducer to its echo.
    Ray,
    /// An uncertainty ball.
    Ball,
    /// The chain of a cluster's points (colour varies per cluster).
    Cluster,
    /// Where a cluster ended (gap above `t_gap`).
    ClusterBreak,
    /// An updated segment's geometry before the update.
    UpdateBefore,
    /// An updated segment's geometry after the update (highlight).
    UpdateAfter,
    /// A lower-confidence end-point's projection onto the updated line.
    UpdateProjection,
    /// A fitted map segment after the step.
    MapFitted,
    /// A fitted map segment not yet confirmed (docs/algorithm.md §8.7), dimmed.
    MapTentative,
    /// A point feature judged a corner (docs/algorithm.md §8.5).
    FeatureCorner,
    /// A point feature judged an edge (docs/algorithm.md §8.5).
    FeatureEdge,
    /// A rounded feature, a pillar, drawn at its radius (docs/algorithm.md §8.14).
    FeaturePillar,
    /// An interpolated (connecting) map segment after the step.
    MapInterpolated,
    /// A map segment's end-point.
    MapEndPoint,
    /// A supporting reading of the selected map segment, from whichever snapshot it came.
    SupportPoint,
    /// A map segment on a wall or pillar of the floor plan (`eval`).
    TruthTrue,
    /// A map segment on no wall or pillar (`eval`).
    TruthSpurious,
    /// A segment fitted in this snapshot.
    NewSegment,
    /// A point of the previous snapshot.
    PreviousPoint,
    /// A segment fitted in the previous snapshot.
    PreviousSegment,
    /// A kept point of this snapshot.
    CurrentPoint,
    /// A discarded reading.
    Discarded,
    /// Decision: matched (MPC) with this candidate.
    DecisionMatch,
    /// Decision: extended this candidate (EPC).
    DecisionExtension,
    /// Decision: dismissed because of this candidate (failed only the orientation test).
    DecisionDismissed,
    /// Decision: kept as a new face.
    DecisionNewFace,
    /// A candidate tested that did not decide the outcome.
    DecisionFailed,
    /// A corner made by correlation.
    Corner,
    /// The robot at this snapshot.
    Robot,
    /// The robot at the previous snapshot.
    RobotPrevious,
    /// The path so far (odometry).
    RobotPath,
    /// The path so far as pose correction placed it (docs/algorithm.md §8.17).
    RobotPathCorrected,
    /// The true path so far, when the run keeps it.
    RobotPathTrue,
    /// A label (segment id, gap distance).
    Label,
}

const DASH: &[f32] = &[8.0, 4.0];
const DOT: &[f32] = &[2.0, 3.0];
const DASH_DOT: &[f32] = &[8.0, 3.0, 2.0, 3.0];
const SPARSE_DOT: &[f32] = &[1.5, 4.0];
const GHOST_DASH: &[f32] = &[6.0, 4.0];

impl Role {
    /// The layer primitives of this role go to.
    pub fn layer(self) -> Layer {
        match self {
            Role::FloorPlan => Layer::FloorPlan,
            Role::MapBefore => Layer::MapBefore,
            Role::Beam | Role::Ray => Layer::Beams,
            Role::Ball => Layer::Balls,
            Role::Cluster | Role::ClusterBreak => Layer::Clusters,
            Role::UpdateBefore | Role::UpdateAfter | Role::UpdateProjection => Layer::Updates,
            Role::MapFitted
            | Role::MapTentative
            | Role::MapInterpolated
            | Role::MapEndPoint
            | Role::SupportPoint => Layer::Map,
            Role::FeatureCorner | Role::FeatureEdge | Role::FeaturePillar => Layer::Features,
            Role::TruthTrue | Role::TruthSpurious => Layer::Truth,
            Role::NewSegment => Layer::NewSegments,
            Role::PreviousPoint | Role::PreviousSegment => Layer::PreviousSnapshot,
            Role::CurrentPoint => Layer::CurrentPoints,
            Role::Discarded => Layer::Discarded,
            Role::DecisionMatch
            | Role::DecisionExtension
            | Role::DecisionDismissed
            | Role::DecisionNewFace
            | Role::DecisionFailed => Layer::Decisions,
            Role::Corner => Layer::Correlations,
            Role::Robot
            | Role::RobotPrevious
            | Role::RobotPath
            | Role::RobotPathCorrected
            | Role::RobotPathTrue => Layer::Robot,
            Role::Label => Layer::Labels,
        }
    }

    /// The default style.
    pub fn style(self) -> Style {
        use palette::*;
        match self {
            Role::FloorPlan => Style::line(GREY, 1.5).faded(0.8),
            Role::MapBefore => Style::line(BLUISH_GREEN, 2.0).dashed(GHOST_DASH).faded(0.4),
            Role::Beam => {
                Style::line(SKY_BLUE.with_alpha(90), 0.75).filled(SKY_BLUE.with_alpha(22))
            }
            Role::Ray => Style::line(GREY, 0.75).faded(0.5),
            Role::Ball => Style::line(BLUE.with_alpha(160), 1.0).filled(BLUE.with_alpha(40)),
            Role::Cluster => Style::line(ORANGE, 7.0).faded(0.35),
            Role::ClusterBreak => Style::line(GREY, 1.5).sized(9.0),
            Role::UpdateBefore => Style::line(ORANGE, 2.0).dashed(DOT).faded(0.8),
            Role::UpdateAfter => Style::line(YELLOW, 10.0).faded(0.55),
            Role::UpdateProjection => Style::line(ORANGE, 1.0).dashed(DOT),
            Role::MapFitted => Style::line(BLUISH_GREEN, 3.0),
            Role::MapTentative => Style::line(BLUISH_GREEN, 2.0).faded(0.35),
            Role::FeatureCorner => Style::line(REDDISH_PURPLE, 1.5)
                .filled(REDDISH_PURPLE)
                .sized(9.0),
            Role::FeatureEdge => Style::line(ORANGE, 1.5).filled(ORANGE).sized(9.0),
            Role::FeaturePillar => Style::line(ORANGE, 2.0),
            Role::MapInterpolated => Style::line(BLUISH_GREEN, 2.0).dashed(DASH),
            Role::MapEndPoint => Style::line(BLUISH_GREEN, 1.0)
                .filled(BLUISH_GREEN)
                .sized(5.0),
            Role::TruthTrue => Style::line(BLUISH_GREEN, 7.0).faded(0.45),
            Role::TruthSpurious => Style::line(VERMILLION, 7.0).faded(0.6),
            Role::SupportPoint => Style::line(YELLOW, 1.5).sized(8.0),
            Role::NewSegment => Style::line(BLUE, 2.0),
            Role::PreviousPoint => Style::line(VERMILLION, 1.0).filled(VERMILLION).sized(6.0),
            Role::PreviousSegment => Style::line(VERMILLION, 1.5).faded(0.8),
            Role::CurrentPoint => Style::line(BLUE, 1.0).filled(BLUE).sized(6.0),
            Role::Discarded => Style::line(GREY, 1.5).sized(7.0).faded(0.7),
            Role::DecisionMatch => Style::line(SKY_BLUE, 1.5).filled(SKY_BLUE).sized(9.0),
            Role::DecisionExtension => Style::line(ORANGE, 1.5)
                .dashed(DASH)
                .filled(ORANGE)
                .sized(9.0),
            Role::DecisionDismissed => Style::line(VERMILLION, 1.5).dashed(DOT).sized(9.0),
            Role::DecisionNewFace => Style::line(REDDISH_PURPLE, 1.5)
                .dashed(DASH_DOT)
                .filled(REDDISH_PURPLE)
                .sized(8.0),
            Role::DecisionFailed => Style::line(GREY, 1.0)
                .dashed(SPARSE_DOT)
                .sized(6.0)
                .faded(0.8),
            Role::Corner => Style::line(REDDISH_PURPLE, 2.0).sized(11.0),
            Role::Robot => Style::line(BLUE, 2.0).filled(BLUE.with_alpha(30)),
            Role::RobotPrevious => Style::line(VERMILLION, 1.0).dashed(DOT).faded(0.8),
            Role::RobotPath => Style::line(GREY, 1.5).sized(4.0).filled(GREY),
            Role::RobotPathCorrected => Style::line(BLUE, 1.5),
            Role::RobotPathTrue => Style::line(BLUISH_GREEN, 1.5).dashed(DASH),
            Role::Label => Style {
                fill: Some(GREY),
                ..Style::line(GREY, 0.0)
            }
            .sized(11.0),
        }
    }

    /// The legend's text; `None` keeps the role out of the legend.
    pub fn legend_label(self) -> Option<&'static str> {
        Some(match self {
            Role::FloorPlan => "floor plan (ground truth)",
            Role::MapBefore => "map before this step",
            Role::Beam => "sonar beam",
            Role::Ray => "ray",
            Role::Ball => "uncertainty ball",
            Role::Cluster => "cluster",
            Role::ClusterBreak => "cluster break (gap)",
            Role::UpdateBefore => "updated: before",
            Role::UpdateAfter => "updated: after",
            Role::UpdateProjection => "end-point projection",
            Role::MapFitted => "map segment",
            Role::MapTentative => "tentative segment (unconfirmed)",
            Role::FeatureCorner => "corner (point feature)",
            Role::FeatureEdge => "edge (point feature)",
            Role::FeaturePillar => "pillar (rounded feature)",
            Role::MapInterpolated => "interpolated link",
            Role::MapEndPoint => return None,
            Role::SupportPoint => "supporting reading (selected segment)",
            Role::TruthTrue => "on a wall (eval)",
            Role::TruthSpurious => "spurious (eval)",
            Role::NewSegment => "fitted this snapshot",
            Role::PreviousPoint => "previous snapshot",
            Role::PreviousSegment => "previous snapshot's fit",
            Role::CurrentPoint => "this snapshot",
            Role::Discarded => "discarded reading",
            Role::DecisionMatch => "match",
            Role::DecisionExtension => "extension",
            Role::DecisionDismissed => "dismissed",
            Role::DecisionNewFace => "new face",
            Role::DecisionFailed => "failed test",
            Role::Corner => "corner",
            Role::Robot => "robot",
            Role::RobotPrevious => "robot, previous",
            Role::RobotPath => "path (odometry)",
            Role::RobotPathCorrected => "path, corrected",
            Role::RobotPathTrue => "path, true",
            Role::Label => return None,
        })
    }

    /// The legend's sample glyph.
    pub fn glyph(self) -> Glyph {
        match self {
            Role::Ball | Role::Beam | Role::Robot | Role::UpdateAfter => Glyph::Area,
            Role::PreviousPoint | Role::CurrentPoint | Role::MapEndPoint => {
                Glyph::Marker(MarkerShape::Dot)
            }
            Role::Discarded => Glyph::Marker(MarkerShape::Cross),
            Role::ClusterBreak => Glyph::Marker(MarkerShape::Plus),
            Role::Corner => Glyph::Marker(MarkerShape::Square),
            Role::FeatureCorner => Glyph::Marker(MarkerShape::Triangle),
            Role::FeatureEdge => Glyph::Marker(MarkerShape::Diamond),
            Role::RobotPath => Glyph::LineWithMarker(MarkerShape::Dot),
            Role::DecisionMatch
            | Role::DecisionExtension
            | Role::DecisionDismissed
            | Role::DecisionNewFace
            | Role::DecisionFailed => Glyph::LineWithMarker(decision_marker(self)),
            Role::Label => Glyph::None,
            _ => Glyph::Line,
        }
    }
}

/// The marker that ends a decision link of role `role` (and marks its new segment).
pub fn decision_marker(role: Role) -> MarkerShape {
    match role {
        Role::DecisionMatch => MarkerShape::Diamond,
        Role::DecisionExtension => MarkerShape::Triangle,
        Role::DecisionDismissed => MarkerShape::Cross,
        Role::DecisionNewFace => MarkerShape::Square,
        _ => MarkerShape::Ring,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decision_roles_differ_beyond_colour() {
        let roles = [
            Role::DecisionMatch,
            Role::DecisionExtension,
            Role::DecisionDismissed,
            Role::DecisionNewFace,
            Role::DecisionFailed,
        ];
        for (i, a) in roles.iter().enumerate() {
            for b in &roles[i + 1..] {
                let (sa, sb) = (a.style(), b.style());
                assert_ne!(sa.stroke, sb.stroke, "{a:?} {b:?} colour");
                assert!(
                    sa.dash_px != sb.dash_px || decision_marker(*a) != decision_marker(*b),
                    "{a:?} and {b:?} differ only in colour"
                );
                assert_ne!(decision_marker(*a), decision_marker(*b));
            }
        }
    }
}
