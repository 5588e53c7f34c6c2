//! How a series of a chart is drawn: its line or marker style and dash pattern.

/// How a series is drawn.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Style {
    /// A solid polyline.
    Line,
    /// A dashed polyline.
    Dashed,
    /// A dotted polyline.
    Dotted,
    /// A polyline of long dashes.
    LongDashed,
    /// A thin solid polyline with hollow square markers at the points.
    Marked,
    /// Markers only (filled circles).
    Points,
    /// Markers only (hollow circles).
    HollowPoints,
}

impl Style {
    /// The dash pattern (dash, gap) in pixels of a dashed style.
    pub fn dash(self) -> Option<(u32, u32)> {
        match self {
            Style::Dashed => Some((8, 5)),
            Style::Dotted => Some((2, 4)),
            Style::LongDashed => Some((16, 6)),
            _ => None,
        }
    }
}
