//! Layers of the scene: what the user can switch on and off, in drawing order.

/// A switchable group of primitives. The order of [`Layer::ALL`] is the drawing order
/// (first is painted first, so it ends up at the bottom).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Layer {
    /// Ground-truth walls and pillars, when the run has a floor plan.
    FloorPlan,
    /// The map as it stood before this step, ghosted.
    MapBefore,
    /// Sonar beams (wedges of the beam width) and rays of this snapshot.
    Beams,
    /// Uncertainty balls of this snapshot's kept readings (world radius `ξ·D/100`).
    Balls,
    /// Clusters of this snapshot, one colour each, with their break points.
    Clusters,
    /// Segments updated in this step: before-geometry ghosted, after-geometry highlighted.
    Updates,
    /// The map after this step (the current map); tentative segments dimmed.
    Map,
    /// Point features of the map: corners (triangles) and edges (diamonds).
    Features,
    /// The map's fitted segments coloured by `eval`'s verdict against the floor plan (on a
    /// wall or pillar, or spurious), when the run has one.
    Truth,
    /// Segments fitted in this snapshot, before matching.
    NewSegments,
    /// Points and fitted segments of the previous snapshot (red, as the paper's figures).
    PreviousSnapshot,
    /// Kept points of this snapshot (blue, as the paper's figures).
    CurrentPoints,
    /// Discarded readings of this snapshot, marked and dimmed.
    Discarded,
    /// Links from each new segment to every candidate it was tested against, by outcome.
    Decisions,
    /// Corners and interpolated links made by correlation.
    Correlations,
    /// The robot at this snapshot and its path so far.
    Robot,
    /// Segment ids and new-segment indices.
    Labels,
}

impl Layer {
    /// Every layer, in drawing order.
    pub const ALL: [Layer; 17] = [
        Layer::FloorPlan,
        Layer::MapBefore,
        Layer::Beams,
        Layer::Balls,
        Layer::Clusters,
        Layer::Updates,
        Layer::Map,
        Layer::Features,
        Layer::Truth,
        Layer::NewSegments,
        Layer::PreviousSnapshot,
        Layer::CurrentPoints,
        Layer::Discarded,
        Layer::Decisions,
        Layer::Correlations,
        Layer::Robot,
        Layer::Labels,
    ];

    /// Stable machine name (SVG group id, settings key). Never renamed.
    pub fn name(self) -> &'static str {
        match self {
            Layer::FloorPlan => "floor-plan",
            Layer::MapBefore => "map-before",
            Layer::Beams => "beams",
            Layer::Balls => "balls",
            Layer::Clusters => "clusters",
            Layer::Updates => "updates",
            Layer::Map => "map",
            Layer::Features => "features",
            Layer::Truth => "truth",
            Layer::NewSegments => "new-segments",
            Layer::PreviousSnapshot => "previous-snapshot",
            Layer::CurrentPoints => "current-points",
            Layer::Discarded => "discarded",
            Layer::Decisions => "decisions",
            Layer::Correlations => "correlations",
            Layer::Robot => "robot",
            Layer::Labels => "labels",
        }
    }

    /// Human-readable label for the UI.
    pub fn label(self) -> &'static str {
        match self {
            Layer::FloorPlan => "Floor plan",
            Layer::MapBefore => "Map before step",
            Layer::Beams => "Sonar beams",
            Layer::Balls => "Uncertainty balls",
            Layer::Clusters => "Clusters",
            Layer::Updates => "Updates",
            Layer::Map => "Map",
            Layer::Features => "Corners and edges",
            Layer::Truth => "Truth (eval verdicts)",
            Layer::NewSegments => "New segments",
            Layer::PreviousSnapshot => "Previous snapshot",
            Layer::CurrentPoints => "Current points",
            Layer::Discarded => "Discarded readings",
            Layer::Decisions => "Decisions",
            Layer::Correlations => "Correlations",
            Layer::Robot => "Robot and path",
            Layer::Labels => "Labels",
        }
    }

    /// The layer with machine name `name`.
    pub fn from_name(name: &str) -> Option<Layer> {
        Layer::ALL.into_iter().find(|l| l.name() == name)
    }

    /// Position in [`Layer::ALL`].
    pub fn index(self) -> usize {
        self as usize
    }

    fn bit(self) -> u32 {
        1 << self.index()
    }
}

/// A set of layers (a bit set; cheap to copy).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct LayerSet(u32);

impl LayerSet {
    /// No layer.
    pub const fn empty() -> Self {
        LayerSet(0)
    }

    /// Every layer.
    pub fn all() -> Self {
        Layer::ALL
            .into_iter()
            .fold(LayerSet::empty(), |s, l| s.with(l, true))
    }

    /// True when `layer` is in the set.
    pub fn contains(self, layer: Layer) -> bool {
        self.0 & layer.bit() != 0
    }

    /// Adds (`on`) or removes `layer`.
    pub fn set(&mut self, layer: Layer, on: bool) {
        if on {
            self.0 |= layer.bit();
        } else {
            self.0 &= !layer.bit();
        }
    }

    /// The set with `layer` added (`on`) or removed.
    pub fn with(mut self, layer: Layer, on: bool) -> Self {
        self.set(layer, on);
        self
    }

    /// The layers in the set, in drawing order.
    pub fn iter(self) -> impl Iterator<Item = Layer> {
        Layer::ALL.into_iter().filter(move |l| self.contains(*l))
    }
}

impl Default for LayerSet {
    fn default() -> Self {
        LayerSet::all()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_unique_and_round_trip() {
        for (i, l) in Layer::ALL.into_iter().enumerate() {
            assert_eq!(l.index(), i);
            assert_eq!(Layer::from_name(l.name()), Some(l));
        }
    }

    #[test]
    fn layer_set_toggles() {
        let s = LayerSet::all().with(Layer::Beams, false);
        assert!(!s.contains(Layer::Beams));
        assert!(s.contains(Layer::Map));
        assert_eq!(s.iter().count(), Layer::ALL.len() - 1);
        assert_eq!(LayerSet::empty().iter().count(), 0);
    }
}
