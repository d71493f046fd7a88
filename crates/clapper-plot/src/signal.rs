//! Time-frequency pictures: a spectrogram as a heat map (the paper's Fig 3).

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::chart::viridis;
use crate::PlotError;

/// A spectrogram to draw.
#[derive(Clone, Debug, PartialEq)]
pub struct SpectrogramPlot<'a> {
    /// Title.
    pub title: &'a str,
    /// Frame times (s).
    pub times: &'a [f64],
    /// Bin frequencies (Hz).
    pub freqs: &'a [f64],
    /// dB re maximum, frame-major.
    pub db: &'a [f64],
    /// Highest frequency drawn (Hz).
    pub fmax: f64,
    /// dB range shown (the floor is −range).
    pub range_db: f64,
}

/// Draw a spectrogram; cells are max-pooled to at most 900 x 500 so that
/// long recordings stay light.
pub fn spectrogram_plot(path: &Path, p: &SpectrogramPlot<'_>) -> Result<(), PlotError> {
    if p.times.is_empty() || p.freqs.len() < 2 || p.db.len() != p.times.len() * p.freqs.len() {
        return Err(PlotError::Empty("spectrogram without frames"));
    }
    let size = (1200, 700);
    render!(path, size, draw(p))
}

type DrawResult<DB> = Result<(), DrawingAreaErrorKind<<DB as DrawingBackend>::ErrorType>>;

fn draw<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, p: &SpectrogramPlot<'_>) -> DrawResult<DB> {
    root.fill(&WHITE)?;
    let (w, _) = root.dim_in_pixel();
    let (main, bar) = root.split_horizontally(w - 130);
    frame(&main, p, (900, 500), 20)?;
    let mut cb = ChartBuilder::on(&bar)
        .margin_top(50)
        .margin_bottom(57)
        .margin_right(10)
        .right_y_label_area_size(60)
        .build_cartesian_2d(0.0..1.0, -p.range_db..0.0)?;
    cb.configure_mesh()
        .disable_mesh()
        .disable_x_axis()
        .y_desc("level (dB re max)")
        .y_label_formatter(&crate::tick)
        .label_style(("sans-serif", 14))
        .draw()?;
    cb.draw_series((0..100).map(|k| {
        let a = -p.range_db + p.range_db * k as f64 / 100.0;
        let b = a + p.range_db / 100.0;
        Rectangle::new([(0.0, a), (1.0, b)], viridis((k as f64 + 0.5) / 100.0).filled())
    }))?;
    Ok(())
}

/// A spectrogram's extent and its cells, max-pooled to at most `nx` by
/// `ny` so that long recordings stay light.
pub(crate) struct Grid {
    /// Time range (s).
    pub t0: f64,
    pub t1: f64,
    /// Highest frequency drawn (Hz).
    pub fmax: f64,
    /// Coloured cells in (time s, frequency Hz).
    pub cells: Vec<Rectangle<(f64, f64)>>,
}

/// A chart over time (s) and frequency (Hz).
pub(crate) type TimeFrequency<'a, DB> =
    ChartContext<'a, DB, Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>>;

/// The spectrogram `p` drawn on `area`, max-pooled to at most `cells`
/// (time x frequency), with its title at `caption_px`: axes, labels and
/// cells, the one frame of both the spectrogram and the striking
/// diagram's strip. Returns the chart, to draw on.
pub(crate) fn frame<'a, DB: DrawingBackend>(
    area: &'a DrawingArea<DB, Shift>,
    p: &SpectrogramPlot<'_>,
    cells: (usize, usize),
    caption_px: u32,
) -> Result<TimeFrequency<'a, DB>, DrawingAreaErrorKind<DB::ErrorType>> {
    let g = grid(p, cells.0, cells.1);
    let mut chart = ChartBuilder::on(area)
        .caption(crate::symbols(p.title), ("sans-serif", caption_px))
        .margin(12)
        .x_label_area_size(45)
        .y_label_area_size(70)
        .build_cartesian_2d(g.t0..g.t1, 0.0..g.fmax)?;
    chart
        .configure_mesh()
        .disable_mesh()
        .x_desc("time (s)")
        .y_desc("frequency (Hz)")
        .x_label_formatter(&crate::tick)
        .y_label_formatter(&crate::tick)
        .label_style(("sans-serif", 15))
        .axis_desc_style(("sans-serif", 17))
        .draw()?;
    chart.draw_series(g.cells)?;
    Ok(chart)
}

/// The grid of `p` (its frames and bins checked non-empty by the caller).
pub(crate) fn grid(p: &SpectrogramPlot<'_>, nx: usize, ny: usize) -> Grid {
    let nb = p.freqs.len();
    let df = p.freqs[1] - p.freqs[0];
    let bins = ((p.fmax / df).ceil() as usize + 1).min(nb);
    let nt = p.times.len();
    let dt = if nt > 1 { p.times[1] - p.times[0] } else { 1.0 };
    let (pt, pf) = (nt.div_ceil(nx), bins.div_ceil(ny));
    let mut cells = vec![];
    for ft in (0..nt).step_by(pt) {
        for fb in (0..bins).step_by(pf) {
            let mut m = f64::NEG_INFINITY;
            for a in ft..(ft + pt).min(nt) {
                for b in fb..(fb + pf).min(bins) {
                    m = m.max(p.db[a * nb + b]);
                }
            }
            let x0 = p.times[ft] - 0.5 * dt;
            let x1 = p.times[(ft + pt - 1).min(nt - 1)] + 0.5 * dt;
            let y0 = (p.freqs[fb] - 0.5 * df).max(0.0);
            let y1 = p.freqs[(fb + pf - 1).min(bins - 1)] + 0.5 * df;
            let c = viridis((m + p.range_db) / p.range_db);
            cells.push(Rectangle::new([(x0, y0), (x1, y1)], c.filled()));
        }
    }
    Grid {
        t0: p.times[0] - 0.5 * dt,
        t1: p.times[nt - 1] + 0.5 * dt,
        fmax: p.freqs[bins - 1] + 0.5 * df,
        cells,
    }
}
