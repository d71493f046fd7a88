//! Clapping-chart heat maps (one or two panels, colour bar with units,
//! blank where a style is not sustained, region boundaries as lines, bells
//! marked and labelled) and simple line plots (Fig 7).

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::PlotError;

/// A bell to mark on a chart.
#[derive(Clone, Debug, PartialEq)]
pub struct Marker {
    /// r/L_c.
    pub x: f64,
    /// L_b/L_c.
    pub y: f64,
    /// Label drawn beside it.
    pub label: String,
}

/// One panel of a chart: a grid of values, row-major (row = L_b/L_c index).
#[derive(Clone, Debug, PartialEq)]
pub struct Panel {
    /// Panel title, e.g. "(a) ringing right".
    pub title: String,
    /// Column positions (r/L_c), ascending.
    pub xs: Vec<f64>,
    /// Row positions (L_b/L_c), ascending.
    pub ys: Vec<f64>,
    /// Value at `[j * xs.len() + i]`; `None` is drawn blank.
    pub values: Vec<Option<f64>>,
    /// The region whose boundary is drawn (where the style is sustained).
    pub region: Vec<bool>,
}

/// How values become colours.
#[derive(Clone, Debug, PartialEq)]
pub enum Scale {
    /// A continuous colour bar from `min` to `max` (values outside are
    /// clamped), labelled with quantity and units.
    Continuous {
        /// Low end.
        min: f64,
        /// High end.
        max: f64,
        /// Colour bar label, with units.
        label: String,
    },
    /// Categories: value k (0, 1, ...) takes colour k; a legend names them.
    Categories(Vec<(String, RGBColor)>),
}

/// A chart figure: title, panels side by side, scale, markers.
#[derive(Clone, Debug, PartialEq)]
pub struct ChartFigure {
    /// Title above the panels.
    pub title: String,
    /// Panels, left to right.
    pub panels: Vec<Panel>,
    /// Colour scale.
    pub scale: Scale,
    /// Bells to mark on every panel.
    pub markers: Vec<Marker>,
    /// Axis labels (x, y), with units.
    pub axes: (String, String),
    /// Curves drawn over every panel.
    pub lines: Vec<Curve>,
}

/// A labelled curve drawn over a chart: label, points, colour.
pub type Curve = (String, Vec<(f64, f64)>, RGBColor);

/// The axis labels of a clapping chart.
pub fn chart_axes() -> (String, String) {
    ("r / L_c".into(), "L_b / L_c".into())
}

/// Viridis, from five anchors: perceptually even and readable in grey.
pub fn viridis(t: f64) -> RGBColor {
    const A: [(u8, u8, u8); 5] = [
        (68, 1, 84),
        (59, 82, 139),
        (33, 145, 140),
        (94, 201, 98),
        (253, 231, 37),
    ];
    let t = if t.is_finite() { t.clamp(0.0, 1.0) } else { 0.0 };
    let s = t * 4.0;
    let k = (s.floor() as usize).min(3);
    let f = s - k as f64;
    let mix = |a: u8, b: u8| (a as f64 + (b as f64 - a as f64) * f).round() as u8;
    RGBColor(
        mix(A[k].0, A[k + 1].0),
        mix(A[k].1, A[k + 1].1),
        mix(A[k].2, A[k + 1].2),
    )
}

fn half_steps(v: &[f64], lo: f64, hi: f64) -> Vec<(f64, f64)> {
    let n = v.len();
    (0..n)
        .map(|i| {
            let left = if i > 0 {
                0.5 * (v[i - 1] + v[i])
            } else if n > 1 {
                v[0] - 0.5 * (v[1] - v[0])
            } else {
                lo
            };
            let right = if i + 1 < n {
                0.5 * (v[i] + v[i + 1])
            } else if n > 1 {
                v[n - 1] + 0.5 * (v[n - 1] - v[n - 2])
            } else {
                hi
            };
            (left, right)
        })
        .collect()
}

/// Draw a chart figure to `path` (.svg or .png).
pub fn chart_figure(path: &Path, fig: &ChartFigure) -> Result<(), PlotError> {
    if fig.panels.is_empty() || fig.panels.iter().any(|p| p.xs.is_empty() || p.ys.is_empty()) {
        return Err(PlotError::Empty("a chart needs at least one panel with points"));
    }
    for p in &fig.panels {
        if p.values.len() != p.xs.len() * p.ys.len() || p.region.len() != p.values.len() {
            return Err(PlotError::Empty("panel values do not match its grid"));
        }
    }
    let size = (80 + 720 * fig.panels.len() as u32 + 150, 760);
    render!(path, size, draw_chart(fig))
}

/// Draw a chart figure as SVG text, to embed in a page.
pub fn chart_figure_svg(fig: &ChartFigure) -> Result<String, PlotError> {
    if fig.panels.is_empty() {
        return Err(PlotError::Empty("a chart needs at least one panel"));
    }
    let size = (80 + 720 * fig.panels.len() as u32 + 150, 760);
    render_svg!(size, draw_chart(fig))
}

type DrawResult<DB> = Result<(), DrawingAreaErrorKind<<DB as DrawingBackend>::ErrorType>>;

fn colour_of(scale: &Scale, v: f64) -> RGBColor {
    match scale {
        Scale::Continuous { min, max, .. } => viridis(if max > min { (v - min) / (max - min) } else { 0.5 }),
        Scale::Categories(c) => c
            .get(v.round().max(0.0) as usize)
            .map(|x| x.1)
            .unwrap_or(RGBColor(128, 128, 128)),
    }
}

fn draw_chart<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, fig: &ChartFigure) -> DrawResult<DB> {
    root.fill(&WHITE)?;
    let (w, _) = root.dim_in_pixel();
    // Sans-serif glyphs average about 0.55 em: shrink a long title to fit.
    let title_px = (f64::from(w) * 0.95 / (0.55 * fig.title.chars().count().max(1) as f64)).min(24.0);
    let titled = root.titled(&crate::symbols(&fig.title), ("sans-serif", title_px))?;
    let (panels_area, bar_area) = titled.split_horizontally(w - 160);
    let areas = panels_area.split_evenly((1, fig.panels.len()));
    for (panel, area) in fig.panels.iter().zip(areas.iter()) {
        draw_panel(area, panel, fig)?;
    }
    match &fig.scale {
        Scale::Continuous { min, max, label } => draw_colour_bar(&bar_area, *min, *max, label)?,
        Scale::Categories(c) => draw_legend(&bar_area, c)?,
    }
    Ok(())
}

/// The region's boundary in `p`: every cell edge with the region on one
/// side only, as segments in chart coordinates (`xr`, `yr`: each cell's
/// extent along x and y).
fn region_edges(p: &Panel, xr: &[(f64, f64)], yr: &[(f64, f64)]) -> Vec<[(f64, f64); 2]> {
    let nx = p.xs.len();
    let inside = |i: isize, j: isize| -> bool {
        i >= 0 && j >= 0 && (i as usize) < nx && (j as usize) < p.ys.len() && p.region[j as usize * nx + i as usize]
    };
    let mut edges = Vec::new();
    for j in 0..p.ys.len() as isize {
        for i in 0..=nx as isize {
            if inside(i - 1, j) != inside(i, j) {
                let x = if i == 0 { xr[0].0 } else { xr[i as usize - 1].1 };
                edges.push([(x, yr[j as usize].0), (x, yr[j as usize].1)]);
            }
        }
    }
    for i in 0..nx as isize {
        for j in 0..=p.ys.len() as isize {
            if inside(i, j - 1) != inside(i, j) {
                let y = if j == 0 { yr[0].0 } else { yr[j as usize - 1].1 };
                edges.push([(xr[i as usize].0, y), (xr[i as usize].1, y)]);
            }
        }
    }
    edges
}

fn draw_panel<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, p: &Panel, fig: &ChartFigure) -> DrawResult<DB> {
    let xr = half_steps(&p.xs, p.xs[0] - 0.5, p.xs[0] + 0.5);
    let yr = half_steps(&p.ys, p.ys[0] - 0.5, p.ys[0] + 0.5);
    let (x0, x1) = (xr[0].0, xr[xr.len() - 1].1);
    let (y0, y1) = (yr[0].0, yr[yr.len() - 1].1);
    let mut chart = ChartBuilder::on(area)
        .caption(crate::symbols(&p.title), ("sans-serif", 22))
        .margin(12)
        .x_label_area_size(45)
        .y_label_area_size(60)
        .build_cartesian_2d(x0..x1, y0..y1)?;
    chart
        .configure_mesh()
        .disable_mesh()
        .x_desc(crate::symbols(&fig.axes.0))
        .y_desc(crate::symbols(&fig.axes.1))
        .x_label_formatter(&crate::tick)
        .y_label_formatter(&crate::tick)
        .label_style(("sans-serif", 15))
        .axis_desc_style(("sans-serif", 17))
        .draw()?;
    let nx = p.xs.len();
    chart.draw_series(p.values.iter().enumerate().filter_map(|(k, v)| {
        let v = (*v)?;
        let (i, j) = (k % nx, k / nx);
        Some(Rectangle::new(
            [(xr[i].0, yr[j].0), (xr[i].1, yr[j].1)],
            colour_of(&fig.scale, v).filled(),
        ))
    }))?;
    let edges = region_edges(p, &xr, &yr);
    chart.draw_series(edges.into_iter().map(|e| PathElement::new(e, BLACK.stroke_width(2))))?;
    let within = |&(x, y): &(f64, f64)| x >= x0 && x <= x1 && y >= y0 && y <= y1;
    let markers: Vec<&Marker> = fig.markers.iter().filter(|m| within(&(m.x, m.y))).collect();
    // Labels: each line's at its last point inside, each marker's beside
    // it, placed so that none runs off the plot or over another.
    let font = ("sans-serif", 16);
    let mut labels: Vec<(String, (f64, f64), RGBColor)> = vec![];
    for (label, pts, colour) in &fig.lines {
        let inside: Vec<(f64, f64)> = pts.iter().copied().filter(within).collect();
        if let Some(&last) = inside.last() {
            chart.draw_series(std::iter::once(PathElement::new(inside, colour.stroke_width(3))))?;
            labels.push((label.clone(), last, *colour));
        }
    }
    labels.extend(markers.iter().map(|m| (m.label.clone(), (m.x, m.y), BLACK)));
    let px = |p: &(f64, f64)| chart.backend_coord(p);
    let (bx, by) = chart.plotting_area().get_pixel_range();
    let sizes: Vec<(i32, i32)> = labels
        .iter()
        .map(|(t, _, _)| {
            let (w, h) = font.into_font().box_size(t).unwrap_or((9 * t.len() as u32, 16));
            (w as i32, h as i32)
        })
        .collect();
    let anchors: Vec<(i32, i32)> = labels.iter().map(|l| px(&l.1)).collect();
    let dots: Vec<(i32, i32)> = markers.iter().map(|m| px(&(m.x, m.y))).collect();
    // A little inside the frame, clear of its line.
    let bounds = ((bx.start + 4, by.start + 4), (bx.end - 4, by.end - 4));
    let offsets = place_labels(&anchors, &sizes, bounds, &dots);
    for m in &markers {
        chart.draw_series(std::iter::once(
            EmptyElement::at((m.x, m.y))
                + Circle::new((0, 0), 7, WHITE.filled())
                + Circle::new((0, 0), 7, BLACK.stroke_width(2)),
        ))?;
    }
    for ((text, at, colour), off) in labels.into_iter().zip(offsets) {
        chart.draw_series(std::iter::once(
            EmptyElement::at(at) + Text::new(text, off, font.into_font().color(&colour)),
        ))?;
    }
    Ok(())
}

/// Where each label goes: the offset (pixels) of its top-left corner from
/// its anchor, chosen from places around the anchor (beside a marker's
/// circle of radius 7 px, nearer first), each pushed inside `bounds`
/// (top-left, bottom-right) where it would stick out, so that the label is
/// clear of the labels placed before it and of every marker in `dots`.
/// Where no place is clear, the one that overlaps least.
fn place_labels(
    anchors: &[(i32, i32)],
    sizes: &[(i32, i32)],
    bounds: ((i32, i32), (i32, i32)),
    dots: &[(i32, i32)],
) -> Vec<(i32, i32)> {
    type Boxed = (i32, i32, i32, i32);
    let overlap = |a: Boxed, b: Boxed| {
        let w = (a.2.min(b.2) - a.0.max(b.0)).max(0);
        let h = (a.3.min(b.3) - a.1.max(b.1)).max(0);
        w * h
    };
    let mut placed: Vec<Boxed> = vec![];
    let mut out = vec![];
    for (&(x, y), &(w, h)) in anchors.iter().zip(sizes) {
        let mut best = (i32::MAX, (10, -h - 2));
        'places: for gap in [10, 22, 40] {
            for (dx, dy) in [
                (gap, -h - gap / 5),
                (gap, gap / 5),
                (-gap - w, -h - gap / 5),
                (-gap - w, gap / 5),
                (-w / 2, -h - gap),
                (-w / 2, gap),
                (gap + 2, -h / 2),
                (-gap - 2 - w, -h / 2),
            ] {
                // Pushed back inside the plot where it would stick out.
                let (dx, dy) = (
                    dx.min(bounds.1 .0 - w - x).max(bounds.0 .0 - x),
                    dy.min(bounds.1 .1 - h - y).max(bounds.0 .1 - y),
                );
                let b = (x + dx, y + dy, x + dx + w, y + dy + h);
                let cost: i32 = placed.iter().map(|&p| overlap(b, p)).sum::<i32>()
                    + dots
                        .iter()
                        .map(|&(cx, cy)| overlap(b, (cx - 8, cy - 8, cx + 8, cy + 8)))
                        .sum::<i32>();
                if cost < best.0 {
                    best = (cost, (dx, dy));
                }
                if cost == 0 {
                    break 'places;
                }
            }
        }
        let (dx, dy) = best.1;
        placed.push((x + dx, y + dy, x + dx + w, y + dy + h));
        out.push((dx, dy));
    }
    out
}

fn draw_colour_bar<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    min: f64,
    max: f64,
    label: &str,
) -> DrawResult<DB> {
    let (lo, hi) = if max > min { (min, max) } else { (min - 1.0, min + 1.0) };
    let mut bar = ChartBuilder::on(area)
        .margin_top(60)
        .margin_bottom(57)
        .margin_right(10)
        .y_label_area_size(0)
        .right_y_label_area_size(60)
        .build_cartesian_2d(0.0..1.0, lo..hi)?;
    bar.configure_mesh()
        .disable_mesh()
        .disable_x_axis()
        .y_desc(crate::symbols(label))
        .y_label_formatter(&crate::tick)
        .label_style(("sans-serif", 14))
        .axis_desc_style(("sans-serif", 16))
        .draw()?;
    let n = 200;
    bar.draw_series((0..n).map(|k| {
        let a = lo + (hi - lo) * k as f64 / n as f64;
        let b = lo + (hi - lo) * (k + 1) as f64 / n as f64;
        Rectangle::new([(0.0, a), (1.0, b)], viridis((k as f64 + 0.5) / n as f64).filled())
    }))?;
    Ok(())
}

fn draw_legend<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, cats: &[(String, RGBColor)]) -> DrawResult<DB> {
    for (k, (name, colour)) in cats.iter().enumerate() {
        let y = 90 + 34 * k as i32;
        area.draw(&Rectangle::new([(8, y), (30, y + 22)], colour.filled()))?;
        area.draw(&Rectangle::new([(8, y), (30, y + 22)], BLACK.stroke_width(1)))?;
        area.draw(&Text::new(name.clone(), (38, y + 4), ("sans-serif", 16)))?;
    }
    Ok(())
}

/// One line or set of points of a line plot.
#[derive(Clone, Debug, PartialEq)]
pub struct Series {
    /// Legend label.
    pub label: String,
    /// The points.
    pub points: Vec<(f64, f64)>,
    /// Draw as markers instead of a line.
    pub markers: bool,
    /// Draw the line dashed (e.g. where a style cannot be sustained, as the
    /// paper's Fig 7 does).
    pub dashed: bool,
    /// Colour.
    pub colour: RGBColor,
}

/// A plain x-y plot with axis labels (with units) and a legend. A point
/// with a y that is not finite is a gap: the line stops there and starts
/// again after it (a level below a spectrogram's floor, say).
pub fn line_plot(path: &Path, title: &str, x_label: &str, y_label: &str, series: &[Series]) -> Result<(), PlotError> {
    line_plot_scaled(path, title, x_label, y_label, series, false)
}

/// [`line_plot`] with a logarithmic x axis (`log_x`): every x must then be
/// greater than 0.
pub fn line_plot_scaled(
    path: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[Series],
    log_x: bool,
) -> Result<(), PlotError> {
    let pts = || {
        series
            .iter()
            .flat_map(|s| s.points.iter())
            .filter(|p| p.0.is_finite() && p.1.is_finite() && (!log_x || p.0 > 0.0))
    };
    if pts().next().is_none() {
        return Err(PlotError::Empty("no points"));
    }
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for &(x, y) in pts() {
        x0 = x0.min(x);
        x1 = x1.max(x);
        y0 = y0.min(y);
        y1 = y1.max(y);
    }
    let pad = |a: f64, b: f64| {
        let d = (b - a).max(1e-9) * 0.05;
        (a - d, b + d)
    };
    let (x0, x1) = if log_x {
        // 5 % of the decades either side.
        let (a, b) = pad(x0.log10(), x1.log10());
        (10f64.powf(a), 10f64.powf(b))
    } else {
        pad(x0, x1)
    };
    let (y0, y1) = pad(y0, y1);
    // Headroom for the legend in the upper right.
    let y1 = y1 + 0.15 * (y1 - y0);
    let spec = LineSpec {
        title,
        x_label,
        y_label,
        series,
        range: (x0, x1, y0, y1),
    };
    let size = (1000, 700);
    if log_x {
        render!(path, size, draw_lines_log_x(&spec))
    } else {
        render!(path, size, draw_lines(&spec))
    }
}

struct LineSpec<'a> {
    title: &'a str,
    x_label: &'a str,
    y_label: &'a str,
    series: &'a [Series],
    range: (f64, f64, f64, f64),
}

fn draw_lines<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, spec: &LineSpec<'_>) -> DrawResult<DB> {
    let (x0, x1, y0, y1) = spec.range;
    root.fill(&WHITE)?;
    let chart = line_frame(root, spec).build_cartesian_2d(x0..x1, y0..y1)?;
    draw_line_series(chart, spec)
}

fn draw_lines_log_x<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, spec: &LineSpec<'_>) -> DrawResult<DB> {
    let (x0, x1, y0, y1) = spec.range;
    root.fill(&WHITE)?;
    let chart = line_frame(root, spec).build_cartesian_2d((x0..x1).log_scale(), y0..y1)?;
    draw_line_series(chart, spec)
}

fn line_frame<'a, 'b, DB: DrawingBackend>(
    root: &'a DrawingArea<DB, Shift>,
    spec: &LineSpec<'_>,
) -> ChartBuilder<'a, 'b, DB> {
    let mut b = ChartBuilder::on(root);
    b.caption(crate::symbols(spec.title), ("sans-serif", 24))
        .margin(15)
        .x_label_area_size(50)
        .y_label_area_size(70);
    b
}

fn draw_line_series<'a, DB, X>(
    mut chart: ChartContext<'a, DB, Cartesian2d<X, plotters::coord::types::RangedCoordf64>>,
    spec: &LineSpec<'_>,
) -> DrawResult<DB>
where
    DB: DrawingBackend + 'a,
    X: Ranged<ValueType = f64> + plotters::coord::ranged1d::ValueFormatter<f64>,
{
    chart
        .configure_mesh()
        .x_desc(crate::symbols(spec.x_label))
        .y_desc(crate::symbols(spec.y_label))
        .x_label_formatter(&crate::tick)
        .y_label_formatter(&crate::tick)
        .light_line_style(RGBColor(235, 235, 235))
        .label_style(("sans-serif", 16))
        .axis_desc_style(("sans-serif", 18))
        .draw()?;
    for s in spec.series {
        let c = s.colour;
        let finite = |p: &&(f64, f64)| p.0.is_finite() && p.1.is_finite();
        if s.markers {
            chart
                .draw_series(
                    s.points
                        .iter()
                        .filter(finite)
                        .map(|&p| Circle::new(p, 5, c.stroke_width(2))),
                )?
                .label(s.label.clone())
                .legend(move |(x, y)| Circle::new((x + 10, y), 5, c.stroke_width(2)));
        } else {
            // One line per run of finite points: a gap where a y is not.
            let runs = s.points.split(|p| !(p.0.is_finite() && p.1.is_finite()));
            let mut labelled = false;
            for run in runs.filter(|r| !r.is_empty()) {
                let drawn = if s.dashed {
                    chart.draw_series(DashedLineSeries::new(run.iter().copied(), 8, 6, c.stroke_width(2)))?
                } else {
                    chart.draw_series(LineSeries::new(run.iter().copied(), c.stroke_width(2)))?
                };
                if !labelled {
                    let dashed = s.dashed;
                    drawn.label(s.label.clone()).legend(move |(x, y)| {
                        // A dashed legend: two short strokes.
                        let pts = if dashed {
                            vec![(x, y), (x + 9, y)]
                        } else {
                            vec![(x, y), (x + 25, y)]
                        };
                        EmptyElement::at((0, 0))
                            + PathElement::new(pts, c.stroke_width(2))
                            + PathElement::new(
                                if dashed { vec![(x + 15, y), (x + 25, y)] } else { vec![] },
                                c.stroke_width(2),
                            )
                    });
                    labelled = true;
                }
            }
        }
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font(("sans-serif", 16))
        .draw()?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn labels_of_markers_on_one_spot_do_not_overlap_or_leave_the_plot() {
        // Two bells at almost the same point near the top right corner, and
        // a line's label at the top edge.
        let anchors = [(395, 12), (397, 14), (200, 0)];
        let sizes = [(60, 16), (12, 16), (110, 16)];
        let bounds = ((0, 0), (400, 300));
        let dots = [(395, 12), (397, 14)];
        let off = place_labels(&anchors, &sizes, bounds, &dots);
        let boxes: Vec<(i32, i32, i32, i32)> = anchors
            .iter()
            .zip(&sizes)
            .zip(&off)
            .map(|((a, s), o)| (a.0 + o.0, a.1 + o.1, a.0 + o.0 + s.0, a.1 + o.1 + s.1))
            .collect();
        for (k, b) in boxes.iter().enumerate() {
            assert!(
                b.0 >= 0 && b.1 >= 0 && b.2 <= 400 && b.3 <= 300,
                "label {k} leaves the plot: {b:?}"
            );
            for c in &boxes[k + 1..] {
                assert!(
                    b.2 <= c.0 || c.2 <= b.0 || b.3 <= c.1 || c.3 <= b.1,
                    "{b:?} overlaps {c:?}"
                );
            }
            for d in &dots {
                assert!(
                    b.2 <= d.0 - 8 || d.0 + 8 <= b.0 || b.3 <= d.1 - 8 || d.1 + 8 <= b.1,
                    "label {k} {b:?} covers the marker at {d:?}"
                );
            }
        }
    }

    fn fig(n: usize) -> ChartFigure {
        let xs: Vec<f64> = (0..n).map(|i| i as f64 / n as f64).collect();
        let ys = xs.clone();
        let values: Vec<Option<f64>> = (0..n * n)
            .map(|k| if k % 3 == 0 { None } else { Some(k as f64) })
            .collect();
        let region = values.iter().map(Option::is_some).collect();
        ChartFigure {
            title: "test chart".into(),
            panels: vec![Panel {
                title: "(a)".into(),
                xs,
                ys,
                values,
                region,
            }],
            scale: Scale::Continuous {
                min: 0.0,
                max: (n * n) as f64,
                label: "value (units)".into(),
            },
            markers: vec![Marker {
                x: 0.5,
                y: 0.5,
                label: "bell".into(),
            }],
            axes: chart_axes(),
            lines: vec![],
        }
    }

    #[test]
    fn draws_svg_and_png_with_labels() {
        let dir = tempfile::tempdir().unwrap();
        let svg = dir.path().join("c.svg");
        chart_figure(&svg, &fig(5)).unwrap();
        let text = std::fs::read_to_string(&svg).unwrap();
        for needle in ["r / L_c", "L_b / L_c", "value (units)", "bell", "test chart"] {
            assert!(text.contains(needle), "{needle}");
        }
        let png = dir.path().join("c.png");
        chart_figure(&png, &fig(1)).unwrap();
        assert_eq!(&std::fs::read(&png).unwrap()[1..4], b"PNG");
    }

    #[test]
    fn mismatched_panels_are_refused() {
        let mut f = fig(3);
        f.panels[0].values.pop();
        assert!(chart_figure(Path::new("x.svg"), &f).is_err());
    }

    #[test]
    fn viridis_ends() {
        assert_eq!(viridis(0.0), RGBColor(68, 1, 84));
        assert_eq!(viridis(1.0), RGBColor(253, 231, 37));
        assert_eq!(viridis(f64::NAN), viridis(0.0));
    }
}
