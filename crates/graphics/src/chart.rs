//! Line charts (plotters; PNG and SVG with the DejaVu Sans font embedded in the binary).
//!
//! Every plot is described by a [`Chart`] (series of points, optional bands, axes, reference
//! lines) and drawn by [`draw`]. A chart is plain data: whoever has numbers (the harness's
//! statistics, a user's script) builds one; this module knows nothing about experiments.

use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::coord::ranged1d::{AsRangedCoord, ValueFormatter};
use plotters::prelude::*;

use crate::ImageFormat as PlotFormat;
use crate::files::{Figure, PlotError, write_png, write_svg};
pub use crate::legend::LegendEntry;
pub use crate::style::Style;

/// The tab10 palette (distinguishable, colour-blind friendlier than pure RGB).
pub const PALETTE: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];

/// Palette colour `i` (cycling).
pub fn color(i: usize) -> RGBColor {
    PALETTE[i % PALETTE.len()]
}

/// The palette of series that stand for configurations: Okabe and Ito's colour-blind-safe
/// colours (blue, vermillion, bluish green, reddish purple, orange, sky blue, black; their
/// yellow is too light on white).
pub const SERIES_PALETTE: [RGBColor; 7] = [
    RGBColor(0, 114, 178),
    RGBColor(213, 94, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(230, 159, 0),
    RGBColor(86, 180, 233),
    RGBColor(0, 0, 0),
];

/// The colour of series `i` (a configuration's index): [`SERIES_PALETTE`], cycling.
pub fn series_color(i: usize) -> RGBColor {
    SERIES_PALETTE[i % SERIES_PALETTE.len()]
}

/// The line style of series `i`: solid, dashed, dotted, long-dashed, cycling. Four styles and
/// seven colours: series 0 to 27 differ in their pair, so two never look alike, and a reader
/// who cannot tell two colours apart still tells their lines apart.
pub fn series_style(i: usize) -> Style {
    [Style::Line, Style::Dashed, Style::Dotted, Style::LongDashed][i % 4]
}

/// Solid for the first palette round, dashed after it, so curves stay distinguishable.
pub fn line_style(i: usize) -> Style {
    if i < PALETTE.len() {
        Style::Line
    } else {
        Style::Dashed
    }
}

/// Styles that stay tellable apart when curves lie on top of each other (solid, dashed, dotted,
/// solid with square markers), cycling: for series that may coincide, such as kernels whose
/// error histograms agree bin for bin.
pub fn distinct_style(i: usize) -> Style {
    [Style::Line, Style::Dashed, Style::Dotted, Style::Marked][i % 4]
}

/// One series of a chart.
#[derive(Clone, Debug)]
pub struct Series {
    /// Legend text (`None`: no legend entry).
    pub label: Option<String>,
    /// Points in data coordinates.
    pub points: Vec<(f64, f64)>,
    /// Drawing style.
    pub style: Style,
    /// Colour.
    pub color: RGBColor,
    /// Optional band `(x, lo, hi)` drawn shaded behind the series.
    pub band: Vec<(f64, f64, f64)>,
    /// What the series stands for (a configuration's label): series with one key share a
    /// colour in every figure of a page, and a page's legend names the key.
    pub key: Option<String>,
}

/// Where the legend goes: never inside the plotting area, where it would hide curves.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LegendAt {
    /// In rows under the plot (the image grows by the legend's height).
    Below,
    /// Not drawn: a page shows [`Chart::legend_entries`] beside the image itself.
    Hidden,
}

/// A chart ready to draw.
#[derive(Clone, Debug)]
pub struct Chart {
    /// Title.
    pub title: String,
    /// X axis label.
    pub x_label: String,
    /// Y axis label.
    pub y_label: String,
    /// Logarithmic x axis.
    pub x_log: bool,
    /// Logarithmic y axis.
    pub y_log: bool,
    /// Series in drawing order.
    pub series: Vec<Series>,
    /// Vertical reference lines `(x, label)` (grey, dashed).
    pub vlines: Vec<(f64, String)>,
    /// Horizontal reference lines `(y, label)` (grey, dashed; each line of a chart its own dash
    /// pattern, so the legend tells them apart).
    pub hlines: Vec<(f64, String)>,
    /// Whether reference lines with a non-empty label get a legend entry.
    pub legend_lines: bool,
    /// Names of the rows of a categorical y axis: the value `k` (1-based) is labelled
    /// `y_categories[k - 1]` and no other tick is labelled. Empty: a numeric axis.
    pub y_categories: Vec<String>,
    /// Fixed x range (default: from the data).
    pub x_range: Option<(f64, f64)>,
    /// Fixed y range (default: from the data).
    pub y_range: Option<(f64, f64)>,
    /// Legend position.
    pub legend: LegendAt,
    /// Opacity of the bands (lighter when many overlap).
    pub band_opacity: f64,
}

impl Chart {
    /// An empty chart with titles.
    pub fn new(
        title: impl Into<String>,
        x_label: impl Into<String>,
        y_label: impl Into<String>,
    ) -> Self {
        Chart {
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            x_log: false,
            y_log: false,
            series: Vec::new(),
            vlines: Vec::new(),
            hlines: Vec::new(),
            legend_lines: true,
            y_categories: Vec::new(),
            x_range: None,
            y_range: None,
            legend: LegendAt::Below,
            band_opacity: 0.18,
        }
    }

    fn data_range(&self, axis: usize, log: bool) -> (f64, f64) {
        let mut lo = f64::INFINITY;
        let mut hi = f64::NEG_INFINITY;
        let mut take = |v: f64| {
            if v.is_finite() && (!log || v > 0.0) {
                lo = lo.min(v);
                hi = hi.max(v);
            }
        };
        for s in &self.series {
            for p in &s.points {
                take(if axis == 0 { p.0 } else { p.1 });
            }
            for b in &s.band {
                if axis == 0 {
                    take(b.0);
                } else {
                    take(b.1);
                    take(b.2);
                }
            }
        }
        if axis == 0 {
            self.vlines.iter().for_each(|l| take(l.0));
        } else {
            self.hlines.iter().for_each(|l| take(l.0));
        }
        if !lo.is_finite() {
            return if log { (0.1, 10.0) } else { (0.0, 1.0) };
        }
        if log {
            if hi <= lo * 1.0001 {
                (lo / 2.0, hi * 2.0)
            } else {
                let r = (hi / lo).powf(0.05);
                (lo / r, hi * r)
            }
        } else if hi <= lo {
            (lo - 0.5 - lo.abs() * 0.1, hi + 0.5 + hi.abs() * 0.1)
        } else {
            let pad = (hi - lo) * 0.05;
            (lo - pad, hi + pad)
        }
    }
}

/// Tick label on a log axis: only values with mantissa 1, 2 or 5 are labelled. Over about one
/// decade plotters puts a key point at every integer mantissa, and at 1-9 labels per decade
/// the wide ones run into each other (`90` and `100`).
pub fn log_tick(v: f64) -> String {
    if !(v.is_finite() && v > 0.0) {
        return tick(v);
    }
    let m = v / 10f64.powf(v.log10().floor());
    if [1.0, 2.0, 5.0, 10.0]
        .iter()
        .any(|k| (m - k).abs() < 1e-6 * k)
    {
        tick(v)
    } else {
        String::new()
    }
}

/// Tick label on a categorical axis: the name of row `v` (1-based) when `v` is that row's
/// integer, else blank (ticks between rows mean nothing).
fn category_tick(names: &[String], v: f64) -> String {
    let k = v.round();
    if (v - k).abs() > 1e-9 || k < 1.0 || k > names.len() as f64 {
        return String::new();
    }
    names[k as usize - 1].clone()
}

/// Compact tick labels: 0.001, 0.5, 12, 3.4k, 1.2M, 1e9.
pub fn tick(v: f64) -> String {
    let a = v.abs();
    if a == 0.0 {
        "0".into()
    } else if !(1e-3..1e9).contains(&a) {
        let e = a.log10().floor();
        let m = v / 10f64.powf(e);
        if (m.round() - m).abs() < 1e-9 {
            format!("{}e{}", m.round(), e)
        } else {
            format!("{m:.1}e{e}")
        }
    } else if a >= 1e6 {
        trim(format!("{:.1}", v / 1e6)) + "M"
    } else if a >= 1e4 {
        trim(format!("{:.1}", v / 1e3)) + "k"
    } else if a >= 10.0 {
        trim(format!("{v:.1}"))
    } else {
        // Four significant digits, so neighbouring ticks never print alike.
        let decimals = (3 - a.log10().floor() as i32).max(0) as usize;
        trim(format!("{v:.decimals$}"))
    }
}

fn trim(s: String) -> String {
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// `base` with `.ext` appended (not `with_extension`: a base like `rtd-q0.11` has a dot).
fn with_ext(base: &Path, ext: &str) -> PathBuf {
    let mut s = base.as_os_str().to_os_string();
    s.push(".");
    s.push(ext);
    PathBuf::from(s)
}

/// Image size in pixels.
pub const SIZE: (u32, u32) = (960, 640);

/// Draws `chart` to `<base>.png` and/or `<base>.svg` (atomically), returning the files written.
pub fn draw(chart: &Chart, base: &Path, formats: &[PlotFormat]) -> Result<Vec<PathBuf>, PlotError> {
    let mut written = Vec::new();
    if let Some(dir) = base.parent() {
        std::fs::create_dir_all(dir).map_err(|source| PlotError::Io {
            path: dir.to_path_buf(),
            source,
        })?;
    }
    for f in formats {
        let path = match f {
            PlotFormat::Png => with_ext(base, "png"),
            PlotFormat::Svg => with_ext(base, "svg"),
        };
        match f {
            PlotFormat::Png => write_png(chart, chart.size(), &path)?,
            PlotFormat::Svg => write_svg(chart, chart.size(), &path)?,
        }
        written.push(path);
    }
    Ok(written)
}

impl Figure for Chart {
    fn draw_on<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        render_any(root, self).map(|_| ())
    }
}

/// The colour of reference lines.
const GREY: RGBColor = RGBColor(110, 110, 110);

/// (dash, gap) per reference line, so two lines of one chart differ in the legend too.
const DASHES: [(u32, u32); 3] = [(6, 4), (2, 3), (12, 4)];

/// A reference line as drawn: its two ends, its label and its dash pattern (dash, gap).
type Reference<'a> = ([(f64, f64); 2], &'a str, (u32, u32));

/// The largest magnitude an axis reaches, and the widest ratio of a log axis: plotters'
/// tick loops never end over an infinite or subnormal range and take a huge time near f64's
/// limits, so ranges are brought inside these bounds (a point beyond is drawn at the edge).
const AXIS_LIMIT: f64 = 1e300;

/// `(lo, hi)` as a range plotters can draw: finite, increasing, within [`AXIS_LIMIT`] and, on a
/// log axis, positive and at most 300 decades wide.
fn drawable((lo, hi): (f64, f64), log: bool) -> (f64, f64) {
    if log {
        let hi = if hi.is_finite() && hi > 0.0 {
            hi.clamp(1.0 / AXIS_LIMIT, AXIS_LIMIT)
        } else {
            AXIS_LIMIT
        };
        // A padded range may reach 0 below the smallest value: the widest range then.
        let lo = if lo.is_finite() && lo > 0.0 { lo } else { 0.0 };
        let lo = lo.max(hi / AXIS_LIMIT).max(1.0 / AXIS_LIMIT);
        if lo < hi { (lo, hi) } else { (hi / 10.0, hi) }
    } else {
        let bound = |v: f64, or: f64| {
            if v.is_nan() {
                or
            } else {
                v.clamp(-AXIS_LIMIT, AXIS_LIMIT)
            }
        };
        let (lo, hi) = (bound(lo, 0.0), bound(hi, 1.0));
        if lo < hi {
            (lo, hi)
        } else {
            (lo - 0.5 - lo.abs() * 0.1, hi + 0.5 + hi.abs() * 0.1)
        }
    }
}

impl Chart {
    /// The chart as it is drawn: both ranges fixed (from the data unless set) and drawable,
    /// and a log axis spanning less than a decade drawn linear (plotters' log axis labels only
    /// powers of ten, so it would show no tick label), its " (log scale)" dropped from the
    /// label. Captions should describe this chart, not the one asked for.
    pub fn resolved(&self) -> Chart {
        let mut c = self.clone();
        let (x0, x1) = drawable(
            self.x_range
                .unwrap_or_else(|| self.data_range(0, self.x_log)),
            self.x_log,
        );
        let (y0, y1) = drawable(
            self.y_range
                .unwrap_or_else(|| self.data_range(1, self.y_log)),
            self.y_log,
        );
        c.x_log = self.x_log && x1 / x0 >= 10.0;
        c.y_log = self.y_log && y1 / y0 >= 10.0;
        if !c.x_log {
            c.x_label = c.x_label.replace(" (log scale)", "");
        }
        if !c.y_log {
            c.y_label = c.y_label.replace(" (log scale)", "");
        }
        c.x_range = Some((x0, x1));
        c.y_range = Some((y0, y1));
        c
    }

    /// The reference lines drawn (inside the resolved ranges).
    fn references(&self) -> Vec<Reference<'_>> {
        let (xs, ys) = (
            self.x_range.unwrap_or((0.0, 1.0)),
            self.y_range.unwrap_or((0.0, 1.0)),
        );
        let v = self
            .vlines
            .iter()
            .filter(|(x, _)| *x >= xs.0 && *x <= xs.1)
            .map(|(x, l)| ([(*x, ys.0), (*x, ys.1)], l.as_str()));
        let h = self
            .hlines
            .iter()
            .filter(|(y, _)| *y >= ys.0 && *y <= ys.1)
            .map(|(y, l)| ([(xs.0, *y), (xs.1, *y)], l.as_str()));
        v.chain(h)
            .enumerate()
            .map(|(k, (ends, l))| (ends, l, DASHES[k % DASHES.len()]))
            .collect()
    }

    /// The legend's entries: the labelled reference lines drawn, then the labelled series.
    pub fn legend_entries(&self) -> Vec<LegendEntry> {
        let r = self.resolved();
        let mut out = Vec::new();
        if r.legend_lines {
            for (_, label, dash) in r.references() {
                if !label.is_empty() {
                    out.push(LegendEntry {
                        label: label.to_string(),
                        key: None,
                        color: GREY,
                        style: Style::Line,
                        reference_dash: Some(dash),
                    });
                }
            }
        }
        for s in &r.series {
            if let Some(label) = &s.label {
                out.push(LegendEntry {
                    label: label.clone(),
                    key: s.key.clone(),
                    color: s.color,
                    style: s.style,
                    reference_dash: None,
                });
            }
        }
        out
    }

    /// The image's size in pixels: [`SIZE`], taller by the legend under it.
    pub fn size(&self) -> (u32, u32) {
        let legend = match self.legend {
            LegendAt::Below => crate::legend::height(&self.legend_entries(), SIZE.0),
            LegendAt::Hidden => 0,
        };
        (SIZE.0, SIZE.1 + legend)
    }
}

/// A chart as SVG text, with where its plotting area lies.
#[derive(Clone, Debug)]
pub struct ChartSvg {
    /// The SVG document.
    pub text: String,
    /// Its size in pixels.
    pub size: (u32, u32),
    /// The plotting area in pixels: left, top, right, bottom.
    pub plot_area: [i32; 4],
}

/// `chart` as SVG (at [`Chart::size`]) with its plotting area, for pages.
pub fn chart_svg(chart: &Chart) -> Result<ChartSvg, String> {
    crate::files::register_fonts();
    let size = chart.size();
    let mut text = String::new();
    let plot_area = {
        let root = SVGBackend::with_string(&mut text, size).into_drawing_area();
        let area = render_any(&root, chart)?;
        root.present().map_err(|e| e.to_string())?;
        area
    };
    Ok(ChartSvg {
        text: crate::files::with_font_family(text),
        size,
        plot_area,
    })
}

/// Draws `c` on `root` (of [`Chart::size`]): the plot, and the legend under it; returns the
/// plotting area in pixels.
fn render_any<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    c: &Chart,
) -> Result<[i32; 4], String> {
    let c = &c.resolved();
    let height = root.dim_in_pixel().1;
    let plot_height = height.min(SIZE.1);
    let (root, legend_area) = root.split_vertically(plot_height);
    if c.legend == LegendAt::Below && height > plot_height {
        legend_area.fill(&WHITE).map_err(|e| e.to_string())?;
        crate::legend::draw(&legend_area, &c.legend_entries())?;
    }
    let root = &root;
    let ((x0, x1), (y0, y1)) = (
        c.x_range.unwrap_or((0.0, 1.0)),
        c.y_range.unwrap_or((0.0, 1.0)),
    );
    match (c.x_log, c.y_log) {
        (false, false) => render(root, c, x0..x1, y0..y1),
        (true, false) => render(root, c, (x0..x1).log_scale(), y0..y1),
        (false, true) => render(root, c, x0..x1, (y0..y1).log_scale()),
        (true, true) => render(root, c, (x0..x1).log_scale(), (y0..y1).log_scale()),
    }
}

fn render<DB, XR, YR>(
    root: &DrawingArea<DB, Shift>,
    c: &Chart,
    xr: XR,
    yr: YR,
) -> Result<[i32; 4], String>
where
    DB: DrawingBackend,
    XR: AsRangedCoord<Value = f64>,
    YR: AsRangedCoord<Value = f64>,
    XR::CoordDescType: ValueFormatter<f64>,
    YR::CoordDescType: ValueFormatter<f64>,
{
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    root.fill(&WHITE).map_err(e)?;
    let mut chart = ChartBuilder::on(root)
        .caption(&c.title, ("sans-serif", 22).into_font())
        .margin(18)
        .x_label_area_size(52)
        .y_label_area_size(78)
        .build_cartesian_2d(xr, yr)
        .map_err(e)?;
    let x_fmt = |v: &f64| if c.x_log { log_tick(*v) } else { tick(*v) };
    let y_fmt = |v: &f64| {
        if !c.y_categories.is_empty() {
            category_tick(&c.y_categories, *v)
        } else if c.y_log {
            log_tick(*v)
        } else {
            tick(*v)
        }
    };
    chart
        .configure_mesh()
        .x_desc(c.x_label.as_str())
        .y_desc(c.y_label.as_str())
        .x_label_formatter(&x_fmt)
        .y_label_formatter(&y_fmt)
        .x_labels(10)
        .y_labels(10)
        .label_style(("sans-serif", 15))
        .axis_desc_style(("sans-serif", 17))
        .light_line_style(RGBColor(235, 235, 235))
        .bold_line_style(RGBColor(205, 205, 205))
        .draw()
        .map_err(e)?;
    let (xs, ys) = (chart.x_range(), chart.y_range());
    let clamp = |p: (f64, f64)| (p.0.clamp(xs.start, xs.end), p.1.clamp(ys.start, ys.end));
    for (ends, _, (dash, gap)) in c.references() {
        chart
            .draw_series(DashedLineSeries::new(ends, dash, gap, GREY.stroke_width(1)))
            .map_err(e)?;
    }
    for s in &c.series {
        if s.band.len() >= 2 {
            let mut poly: Vec<(f64, f64)> = s.band.iter().map(|b| clamp((b.0, b.2))).collect();
            poly.extend(s.band.iter().rev().map(|b| clamp((b.0, b.1))));
            chart
                .draw_series(std::iter::once(Polygon::new(
                    poly,
                    s.color.mix(c.band_opacity).filled(),
                )))
                .map_err(e)?;
        }
    }
    for s in &c.series {
        let pts: Vec<(f64, f64)> = s
            .points
            .iter()
            .copied()
            .filter(|p| p.0.is_finite() && p.1.is_finite())
            .map(clamp)
            .collect();
        let col = s.color;
        match s.style {
            Style::Line => {
                chart
                    .draw_series(LineSeries::new(pts, col.stroke_width(2)))
                    .map_err(e)?;
            }
            Style::Dashed | Style::Dotted | Style::LongDashed => {
                let (dash, gap) = s.style.dash().unwrap_or((8, 5));
                chart
                    .draw_series(DashedLineSeries::new(pts, dash, gap, col.stroke_width(2)))
                    .map_err(e)?;
            }
            Style::Marked => {
                chart
                    .draw_series(LineSeries::new(pts.clone(), col.stroke_width(1)))
                    .map_err(e)?;
                chart
                    .draw_series(pts.into_iter().map(|p| {
                        EmptyElement::at(p)
                            + Rectangle::new([(-4, -4), (4, 4)], col.stroke_width(1))
                    }))
                    .map_err(e)?;
            }
            Style::Points => {
                chart
                    .draw_series(pts.into_iter().map(|p| Circle::new(p, 4, col.filled())))
                    .map_err(e)?;
            }
            Style::HollowPoints => {
                chart
                    .draw_series(
                        pts.into_iter()
                            .map(|p| Circle::new(p, 4, col.stroke_width(1))),
                    )
                    .map_err(e)?;
            }
        }
    }
    let (px, py) = chart.plotting_area().get_pixel_range();
    Ok([px.start, py.start, px.end, py.end])
}

/// Step-function points of a CDF from `x_start` to `x_end` (left-continuous drawing).
pub fn step_points(curve: &[(f64, f64)], x_start: f64, x_end: f64) -> Vec<(f64, f64)> {
    let mut pts = vec![(x_start, 0.0)];
    let mut last = 0.0;
    for &(t, f) in curve {
        pts.push((t, last));
        pts.push((t, f));
        last = f;
    }
    pts.push((x_end.max(curve.last().map_or(x_start, |c| c.0)), last));
    pts
}

/// A file-name-safe version of a label.
pub fn slug(s: &str) -> String {
    let mut out = String::new();
    for c in s.chars() {
        if c.is_ascii_alphanumeric() || c == '.' || c == '-' || c == '_' {
            out.push(c);
        } else if c == '=' {
            out.push('-');
        } else if !out.ends_with('_') {
            out.push('_');
        }
    }
    out.trim_matches('_').to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_and_slugs() {
        assert_eq!(tick(0.5), "0.5");
        assert_eq!(tick(12.0), "12");
        assert_eq!(tick(25000.0), "25k");
        assert_eq!(tick(2.5e6), "2.5M");
        assert_eq!(tick(1e10), "1e10");
        assert_eq!(tick(0.0045), "0.0045");
        assert_eq!(tick(0.0035), "0.0035");
        assert_eq!(tick(3.5), "3.5");
        assert_eq!(log_tick(100.0), "100");
        assert_eq!(log_tick(20.0), "20");
        assert_eq!(log_tick(5e-4), "5e-4");
        assert_eq!(log_tick(90.0), "");
        assert_eq!(log_tick(0.003), "");
        assert_eq!(slug("AED phi=1.2"), "AED_phi-1.2");
        let s = step_points(&[(1.0, 0.5), (2.0, 1.0)], 0.5, 3.0);
        assert_eq!(
            s,
            vec![
                (0.5, 0.0),
                (1.0, 0.0),
                (1.0, 0.5),
                (2.0, 0.5),
                (2.0, 1.0),
                (3.0, 1.0)
            ]
        );
    }

    /// plotters' tick loops hang over an infinite or subnormal range: times of 1e300 and more
    /// (the range is padded past f64's limit) or subnormal ones must still draw, at once.
    #[test]
    fn extreme_values_draw_within_bounds() {
        for (x_log, y_log) in [(true, true), (false, false), (true, false)] {
            for pts in [
                vec![(1e-3, 0.5), (1e300, 1.0)],
                vec![(1e-3, 0.5), (1e306, 1e306)],
                vec![(5e-324, 1e-310), (1.0, 1.0)],
                vec![(f64::MAX, 0.5), (f64::MIN_POSITIVE, 2.0)],
            ] {
                let mut c = Chart::new("extreme", "x (log scale)", "y");
                c.x_log = x_log;
                c.y_log = y_log;
                c.series.push(Series {
                    label: Some("a".into()),
                    points: pts.clone(),
                    style: Style::Line,
                    color: color(0),
                    band: Vec::new(),
                    key: None,
                });
                let start = std::time::Instant::now();
                let svg = crate::files::svg_text(&c, SIZE).unwrap();
                assert!(svg.contains("extreme"));
                assert!(start.elapsed().as_secs() < 10, "{pts:?}");
                let r = c.resolved();
                let ((x0, x1), (y0, y1)) = (r.x_range.unwrap(), r.y_range.unwrap());
                assert!(x0.is_finite() && x1.is_finite() && x0 < x1, "{pts:?}");
                assert!(y0.is_finite() && y1.is_finite() && y0 < y1, "{pts:?}");
            }
        }
        // A log axis within one decade is drawn linear, and its label says so.
        let mut c = Chart::new("narrow", "x (log scale)", "y");
        c.x_log = true;
        c.x_range = Some((2.0, 5.0));
        let r = c.resolved();
        assert!(!r.x_log && r.x_label == "x", "{}", r.x_label);
    }

    #[test]
    fn draws_png_and_svg() {
        let dir = tempfile::tempdir().unwrap();
        let mut c = Chart::new("Test chart", "x", "y");
        c.x_log = true;
        c.series.push(Series {
            label: Some("a".into()),
            points: vec![(0.1, 0.0), (1.0, 0.5), (10.0, 1.0)],
            style: Style::Line,
            color: color(0),
            band: vec![(0.1, -0.1, 0.1), (10.0, 0.9, 1.1)],
            key: None,
        });
        c.vlines.push((5.0, "cutoff".into()));
        let files = draw(
            &c,
            &dir.path().join("t"),
            &[PlotFormat::Png, PlotFormat::Svg],
        )
        .unwrap();
        assert_eq!(files.len(), 2);
        let png = std::fs::read(&files[0]).unwrap();
        assert!(png.len() > 1000 && png.starts_with(b"\x89PNG"));
        let svg = std::fs::read_to_string(&files[1]).unwrap();
        assert!(svg.contains("<svg") && svg.contains("Test chart"));
        // No temporary files left behind.
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 2);
    }
}
