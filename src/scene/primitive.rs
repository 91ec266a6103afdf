//! The scene's vocabulary: world-space shapes with a layer, a style, a role and an id.

use super::layer::Layer;
use super::marker::MarkerShape;
use super::style::{Role, Style};
use crate::geometry::Point;
use crate::mapping::SegmentId;

/// What a primitive shows; the app uses it for hover and selection.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
pub enum SceneId {
    /// Nothing selectable.
    #[default]
    None,
    /// The robot (body, heading, path).
    Robot,
    /// Ground truth.
    FloorPlan,
    /// A reading: snapshot index and sensor index.
    Reading {
        /// Snapshot index.
        snapshot: usize,
        /// Sensor index.
        sensor: usize,
    },
    /// Cluster `i` of this step (`StepTrace::clusters`).
    Cluster(usize),
    /// New segment `i` of this step (`StepTrace::new_segments`).
    NewSegment(usize),
    /// A map segment.
    MapSegment(SegmentId),
    /// The decision on new segment `new_segment`; `existing` is the candidate a link leads to
    /// (`None` for the outcome marker itself).
    Decision {
        /// Index into `StepTrace::new_segments`.
        new_segment: usize,
        /// The candidate tested, when the primitive is a link.
        existing: Option<SegmentId>,
    },
    /// The update of a map segment in this step.
    Update(SegmentId),
    /// Correlation `i` of this step (`StepTrace::correlations`).
    Correlation(usize),
}

/// Horizontal alignment of a text about its anchor.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum TextAlign {
    /// Text starts at the anchor.
    Start,
    /// Text is centred on the anchor.
    Middle,
    /// Text ends at the anchor.
    End,
}

/// A shape in world coordinates (metres, y up). Sizes that must stay readable when zooming
/// (stroke widths, marker and text sizes, offsets) are in screen pixels, in the style or here.
#[derive(Clone, Debug, PartialEq)]
pub enum Shape {
    /// A circle with a world radius (an uncertainty ball, the robot body, a pillar).
    Circle {
        /// Centre, world.
        centre: Point,
        /// Radius, metres.
        radius_m: f64,
    },
    /// A straight line between two world points.
    Segment {
        /// First end, world.
        a: Point,
        /// Second end, world.
        b: Point,
    },
    /// Connected straight lines through world points.
    Polyline {
        /// Vertices, world.
        points: Vec<Point>,
        /// Joins the last vertex to the first.
        closed: bool,
    },
    /// A sonar beam: a circular sector.
    Wedge {
        /// Apex (the transducer), world.
        apex: Point,
        /// Direction of the beam axis against the world x axis, radians.
        heading_rad: f64,
        /// Half the beam width, radians.
        half_angle_rad: f64,
        /// Radius, metres.
        radius_m: f64,
    },
    /// A text anchored at a world point (its baseline's start, middle or end).
    Text {
        /// Anchor, world.
        anchor: Point,
        /// The text (plain; renderers escape it).
        text: String,
        /// Offset from the anchor in screen pixels, x right and y up.
        offset_px: [f32; 2],
        /// Alignment about the anchor.
        align: TextAlign,
    },
    /// A marker glyph of `style.marker_size_px` at a world point.
    Marker {
        /// Position, world.
        at: Point,
        /// Glyph.
        shape: MarkerShape,
    },
}

/// One item of the display list.
#[derive(Clone, Debug, PartialEq)]
pub struct Primitive {
    /// The layer it belongs to.
    pub layer: Layer,
    /// What it depicts (legend entry; determines the default style).
    pub role: Role,
    /// How to draw it.
    pub style: Style,
    /// What it shows, for hit-testing.
    pub id: SceneId,
    /// The geometry.
    pub shape: Shape,
}

impl SceneId {
    /// True when a primitive with id `id` belongs to this selection (a new segment owns its
    /// "new face" decision; a map segment its update).
    pub fn selects(self, id: SceneId) -> bool {
        if self == SceneId::None || id == SceneId::None {
            return false;
        }
        match (self, id) {
            (
                SceneId::NewSegment(i),
                SceneId::Decision {
                    new_segment,
                    existing: None,
                },
            ) => i == new_segment,
            (SceneId::MapSegment(a), SceneId::Update(b)) => a == b,
            _ => id == self,
        }
    }
}
