//! Legends drawn outside the plotting area: a chart's entries (its labelled series and
//! reference lines) flow in rows under the plot, so no legend hides a curve. A page may draw
//! the same entries as HTML instead ([`crate::chart::LegendAt::Hidden`]).

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::style::Style;

/// Font size of legend text, in pixels.
pub const FONT: u32 = 15;
/// Height of one row of entries.
const ROW: u32 = 22;
/// Space above the first row and below the last.
const PAD: u32 = 8;
/// Width of a swatch.
pub const SWATCH: u32 = 26;
/// Space between a swatch and its text, and after an entry.
const GAP: u32 = 6;
const SPACING: u32 = 22;
/// Left and right margin (the chart's own margin).
const MARGIN: u32 = 18;

/// One entry of a legend.
#[derive(Clone, Debug, PartialEq)]
pub struct LegendEntry {
    /// Its text.
    pub label: String,
    /// What the series stands for (a configuration), when it has a key.
    pub key: Option<String>,
    /// Its colour.
    pub color: RGBColor,
    /// How its series is drawn.
    pub style: Style,
    /// The dash pattern (dash, gap) of a reference line (drawn thin and grey).
    pub reference_dash: Option<(u32, u32)>,
}

impl LegendEntry {
    /// The entry's dash pattern (dash, gap) in pixels, `None` for a solid line or markers.
    pub fn dash(&self) -> Option<(u32, u32)> {
        self.reference_dash.or_else(|| self.style.dash())
    }

    /// The stroke width of its line.
    pub fn width(&self) -> u32 {
        if self.reference_dash.is_some() { 1 } else { 2 }
    }
}

/// The width of `text` in the legend's font (an estimate when the font cannot lay it out).
fn text_width(text: &str) -> u32 {
    crate::files::register_fonts();
    ("sans-serif", FONT)
        .into_font()
        .box_size(text)
        .map_or(text.chars().count() as u32 * 9, |(w, _)| w)
}

/// Where each entry goes: `(x, row)` in a legend `width` pixels wide, entries flowing left to
/// right and wrapping to the next row.
fn positions(entries: &[LegendEntry], width: u32) -> Vec<(u32, u32)> {
    let usable = width.saturating_sub(2 * MARGIN).max(1);
    let (mut x, mut row) = (0u32, 0u32);
    let mut out = Vec::with_capacity(entries.len());
    for e in entries {
        let w = SWATCH + GAP + text_width(&e.label);
        if x > 0 && x + w > usable {
            row += 1;
            x = 0;
        }
        out.push((MARGIN + x, row));
        x += w + SPACING;
    }
    out
}

/// The height of the legend of `entries` under a chart `width` pixels wide (0 without entries).
pub fn height(entries: &[LegendEntry], width: u32) -> u32 {
    match positions(entries, width).last() {
        None => 0,
        Some(&(_, row)) => 2 * PAD + (row + 1) * ROW,
    }
}

/// Draws the entries on `area` (as wide as the chart, [`height`] high).
pub fn draw<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    entries: &[LegendEntry],
) -> Result<(), String> {
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    let width = area.dim_in_pixel().0;
    let font = ("sans-serif", FONT).into_font().color(&BLACK);
    for (entry, (x, row)) in entries.iter().zip(positions(entries, width)) {
        let (x, y) = (x as i32, (PAD + row * ROW + ROW / 2) as i32);
        let col = entry.color;
        let stroke = col.stroke_width(entry.width());
        match entry.style {
            Style::Points => area
                .draw(&Circle::new((x + SWATCH as i32 / 2, y), 4, col.filled()))
                .map_err(e)?,
            Style::HollowPoints => area
                .draw(&Circle::new(
                    (x + SWATCH as i32 / 2, y),
                    4,
                    col.stroke_width(1),
                ))
                .map_err(e)?,
            _ => {
                for (from, to) in segments(SWATCH as i32, entry.dash()) {
                    area.draw(&PathElement::new(vec![(x + from, y), (x + to, y)], stroke))
                        .map_err(e)?;
                }
                if entry.style == Style::Marked {
                    let mid = x + SWATCH as i32 / 2;
                    let square = [(mid - 4, y - 4), (mid + 4, y + 4)];
                    area.draw(&Rectangle::new(square, col.stroke_width(1)))
                        .map_err(e)?;
                }
            }
        }
        let pos = (x + (SWATCH + GAP) as i32, y - FONT as i32 / 2 - 1);
        area.draw(&Text::new(entry.label.clone(), pos, font.clone()))
            .map_err(e)?;
    }
    Ok(())
}

/// The pieces `(from, to)` of a swatch `len` pixels long in a dash pattern (one piece when
/// solid).
pub fn segments(len: i32, dash: Option<(u32, u32)>) -> Vec<(i32, i32)> {
    let Some((d, g)) = dash else {
        return vec![(0, len)];
    };
    let mut out = Vec::new();
    let mut at = 0;
    while at < len {
        out.push((at, (at + d as i32).min(len)));
        at += (d + g) as i32;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn entry(label: &str) -> LegendEntry {
        LegendEntry {
            label: label.into(),
            key: None,
            color: BLACK,
            style: Style::Line,
            reference_dash: None,
        }
    }

    #[test]
    fn entries_wrap_into_rows_within_the_width() {
        let few = vec![entry("AED"), entry("AERS")];
        assert_eq!(height(&few, 960), 2 * PAD + ROW);
        let many: Vec<LegendEntry> = (0..12)
            .map(|i| entry(&format!("a rather long configuration label {i}")))
            .collect();
        let pos = positions(&many, 960);
        assert!(pos.iter().all(|&(x, _)| x + SWATCH < 960 - MARGIN));
        assert!(pos.last().unwrap().1 >= 3, "{pos:?}");
        assert_eq!(height(&[], 960), 0);
    }

    #[test]
    fn dashes_cut_the_swatch() {
        assert_eq!(segments(26, None), vec![(0, 26)]);
        assert_eq!(segments(10, Some((4, 2))), vec![(0, 4), (6, 10)]);
    }
}
