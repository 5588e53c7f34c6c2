//! Charts inlined in a page as SVG (drawn by `brdf_graphics` with its embedded font metrics).

use brdf_graphics::chart::{Chart, SIZE};
use brdf_graphics::files::svg_text;

use super::{PageError, escape};

/// A `<figure>` holding `chart` as inline SVG, captioned with its title and x axis (an RTD
/// in CPU seconds and one in sample-evaluations share a title).
pub fn figure(chart: &Chart, id: &str) -> Result<String, PageError> {
    let svg = svg_text(chart, SIZE).map_err(|message| PageError::Chart {
        title: chart.title.clone(),
        message,
    })?;
    // The SVG's own attributes fix its size; the style sheet scales it to the text width.
    let svg = svg.replacen(
        "<svg ",
        &format!("<svg role=\"img\" aria-label=\"{}\" ", escape(&chart.title)),
        1,
    );
    Ok(format!(
        "<figure class=\"chart\" id=\"{}\">\n{}\n<figcaption>{}</figcaption>\n</figure>\n",
        escape(id),
        svg.trim_end(),
        escape(&format!("{}; x axis: {}", chart.title, chart.x_label))
    ))
}
