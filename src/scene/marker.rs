//! The marker glyphs: drawn by shapes, named by styles and legend entries, drawn alike by
//! both renderers.

/// A marker glyph drawn at a point with a size in screen pixels.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum MarkerShape {
    /// Filled disc.
    Dot,
    /// Hollow circle.
    Ring,
    /// Diagonal cross (×).
    Cross,
    /// Upright cross (+).
    Plus,
    /// Square.
    Square,
    /// Triangle pointing up.
    Triangle,
    /// Diamond.
    Diamond,
}

impl MarkerShape {
    /// True for glyphs drawn as lines only (no fill).
    pub fn is_open(self) -> bool {
        matches!(
            self,
            MarkerShape::Ring | MarkerShape::Cross | MarkerShape::Plus
        )
    }
}
