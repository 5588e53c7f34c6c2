//! Charts inlined in a page as SVG (drawn by `brdf_graphics` with its embedded font metrics),
//! each with its legend as HTML under the image (outside the plotting area, searchable, at the
//! text's size) and a caption saying what it shows and how to read it.
//!
//! The `<svg>` carries `data-plot-area="left top right bottom"` (its plotting area in the
//! image's pixels) and each legend entry `data-key` (the configuration it stands for), so a
//! browser check can verify that no legend overlaps a plot and that a configuration keeps its
//! colour across the figures of a page.

use brdf_graphics::RGBColor;
use brdf_graphics::chart::{Chart, LegendAt, LegendEntry, Style, chart_svg};
use brdf_graphics::legend::{SWATCH, segments};

use super::{PageError, escape};

/// `#rrggbb`.
pub fn hex(c: RGBColor) -> String {
    format!("#{:02x}{:02x}{:02x}", c.0, c.1, c.2)
}

/// A legend entry's swatch as a small inline SVG.
fn swatch(e: &LegendEntry) -> String {
    let col = hex(e.color);
    let (w, mid) = (SWATCH as i32, SWATCH as i32 / 2);
    let shape = match e.style {
        Style::Points => format!("<circle cx=\"{mid}\" cy=\"6\" r=\"4\" fill=\"{col}\"/>"),
        Style::HollowPoints => {
            format!("<circle cx=\"{mid}\" cy=\"6\" r=\"4\" fill=\"none\" stroke=\"{col}\"/>")
        }
        _ => {
            let mut s: String = segments(w, e.dash())
                .into_iter()
                .map(|(a, b)| {
                    format!(
                        "<line x1=\"{a}\" y1=\"6\" x2=\"{b}\" y2=\"6\" stroke=\"{col}\" \
                         stroke-width=\"{}\"/>",
                        e.width()
                    )
                })
                .collect();
            if e.style == Style::Marked {
                s.push_str(&format!(
                    "<rect x=\"{}\" y=\"2\" width=\"8\" height=\"8\" fill=\"none\" stroke=\"{col}\"/>",
                    mid - 4
                ));
            }
            s
        }
    };
    format!(
        "<svg class=\"swatch\" width=\"{w}\" height=\"12\" viewBox=\"0 0 {w} 12\" \
         aria-hidden=\"true\">{shape}</svg>"
    )
}

/// The legend of `chart` as an HTML list (empty without entries).
pub fn legend(chart: &Chart) -> String {
    let entries = chart.legend_entries();
    if entries.is_empty() {
        return String::new();
    }
    let mut s = String::from("<ul class=\"legend\">");
    for e in &entries {
        let key = e
            .key
            .as_deref()
            .map(|k| format!(" data-key=\"{}\"", escape(k)))
            .unwrap_or_default();
        s.push_str(&format!(
            "<li{key}>{}<span class=\"label\">{}</span></li>",
            swatch(e),
            escape(&e.label)
        ));
    }
    s.push_str("</ul>\n");
    s
}

/// A `<figure>` holding `chart` as inline SVG, its legend and `caption` (plain text), under
/// its title.
pub fn figure(chart: &Chart, id: &str, caption: &str) -> Result<String, PageError> {
    let mut drawn = chart.clone();
    drawn.legend = LegendAt::Hidden;
    let svg = chart_svg(&drawn).map_err(|message| PageError::Chart {
        title: chart.title.clone(),
        message,
    })?;
    let [l, t, r, b] = svg.plot_area;
    // The SVG's own attributes fix its size; the style sheet scales it to the text width.
    let text = svg.text.replacen(
        "<svg ",
        &format!(
            "<svg role=\"img\" aria-label=\"{}\" data-plot-area=\"{l} {t} {r} {b}\" ",
            escape(&chart.title)
        ),
        1,
    );
    Ok(format!(
        "<figure class=\"chart\" id=\"{}\">\n{}\n{}<figcaption><strong>{}.</strong> {}</figcaption>\n</figure>\n",
        escape(id),
        text.trim_end(),
        legend(chart),
        escape(&chart.title),
        escape(caption)
    ))
}
