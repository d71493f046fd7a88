//! The tower under a ring (`clapper tower --plot`): three panels, the
//! horizontal forces on the frame against time, the bell chamber's sway
//! against time, and the forces' spectra with the tower's frequencies
//! marked.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::PlotError;

type DrawResult<DB> = Result<(), DrawingAreaErrorKind<<DB as DrawingBackend>::ErrorType>>;

/// One curve of a panel.
#[derive(Clone, Debug, PartialEq)]
pub struct Curve {
    /// Legend label.
    pub label: String,
    /// (x, y) points.
    pub points: Vec<(f64, f64)>,
    /// Colour.
    pub colour: RGBColor,
}

/// What the tower plot shows.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TowerPlot {
    /// Title line.
    pub title: String,
    /// Forces against time (s, kN).
    pub forces: Vec<Curve>,
    /// Sway against time (s, mm); empty without a tower.
    pub sway: Vec<Curve>,
    /// Spectra (Hz, kN).
    pub spectra: Vec<Curve>,
    /// The tower's frequencies (Hz) with their labels, drawn as vertical lines.
    pub marks: Vec<(String, f64)>,
}

/// Size of the plot (px).
const SIZE: (u32, u32) = (1200, 1100);

/// Draw `plot` to `path` (.svg or .png).
pub fn tower_plot(path: &Path, plot: &TowerPlot) -> Result<(), PlotError> {
    if plot.forces.iter().all(|c| c.points.len() < 2) {
        return Err(PlotError::Empty("no force history"));
    }
    render!(path, SIZE, draw(plot))
}

/// At most `max` points of `points`, keeping each stretch's lowest and
/// highest (a peal's million samples drawn as its envelope).
pub fn thin(points: &[(f64, f64)], max: usize) -> Vec<(f64, f64)> {
    if points.len() <= max || max < 4 {
        return points.to_vec();
    }
    let chunk = points.len().div_ceil(max / 2);
    points
        .chunks(chunk)
        .flat_map(|c| {
            let lo = c.iter().copied().min_by(|a, b| a.1.total_cmp(&b.1)).unwrap_or(c[0]);
            let hi = c.iter().copied().max_by(|a, b| a.1.total_cmp(&b.1)).unwrap_or(c[0]);
            if lo.0 <= hi.0 {
                [lo, hi]
            } else {
                [hi, lo]
            }
        })
        .collect()
}

fn range(curves: &[Curve], extra_x: &[f64]) -> (f64, f64, f64, f64) {
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for &(x, y) in curves.iter().flat_map(|c| c.points.iter()) {
        if x.is_finite() && y.is_finite() {
            x0 = x0.min(x);
            x1 = x1.max(x);
            y0 = y0.min(y);
            y1 = y1.max(y);
        }
    }
    for &x in extra_x {
        x0 = x0.min(x);
        x1 = x1.max(x);
    }
    if x0 > x1 {
        return (0.0, 1.0, 0.0, 1.0);
    }
    let dy = (y1 - y0).max(1e-9);
    (x0, x1.max(x0 + 1e-9), y0 - 0.05 * dy, y1 + 0.2 * dy)
}

fn panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    title: &str,
    x_label: &str,
    y_label: &str,
    curves: &[Curve],
    marks: &[(String, f64)],
) -> DrawResult<DB> {
    let xs: Vec<f64> = marks.iter().map(|m| m.1).collect();
    let (x0, x1, y0, y1) = range(curves, &xs);
    let mut chart = ChartBuilder::on(area)
        .caption(crate::symbols(title), ("sans-serif", 20))
        .margin(12)
        .x_label_area_size(45)
        .y_label_area_size(75)
        .build_cartesian_2d(x0..x1, y0..y1)?;
    chart
        .configure_mesh()
        .x_desc(crate::symbols(x_label))
        .y_desc(crate::symbols(y_label))
        .x_label_formatter(&crate::tick)
        .y_label_formatter(&crate::tick)
        .light_line_style(RGBColor(235, 235, 235))
        .label_style(("sans-serif", 15))
        .axis_desc_style(("sans-serif", 16))
        .draw()?;
    for c in curves {
        let colour = c.colour;
        chart
            .draw_series(LineSeries::new(c.points.iter().copied(), colour.stroke_width(1)))?
            .label(c.label.clone())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(2)));
    }
    for (label, f) in marks {
        let grey = RGBColor(200, 40, 40);
        chart
            .draw_series(plotters::series::DashedLineSeries::new(
                vec![(*f, y0), (*f, y1)],
                6,
                4,
                grey.stroke_width(2),
            ))?
            .label(label.clone())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], grey.stroke_width(2)));
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font(("sans-serif", 15))
        .draw()?;
    Ok(())
}

fn draw<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, p: &TowerPlot) -> DrawResult<DB> {
    root.fill(&WHITE)?;
    let (head, body) = root.split_vertically(40);
    head.draw(&Text::new(crate::symbols(&p.title), (15, 10), ("sans-serif", 22)))?;
    let parts = body.split_evenly((3, 1));
    panel(
        &parts[0],
        "horizontal force on the frame",
        "time (s)",
        "force (kN)",
        &p.forces,
        &[],
    )?;
    if p.sway.is_empty() {
        parts[1].draw(&Text::new(
            "no tower given (--tower FILE or a [tower] table): no sway",
            (90, 150),
            ("sans-serif", 18),
        ))?;
    } else {
        panel(
            &parts[1],
            "sway of the bell chamber",
            "time (s)",
            "displacement (mm)",
            &p.sway,
            &[],
        )?;
    }
    panel(
        &parts[2],
        "spectrum of the horizontal force",
        "frequency (Hz)",
        "amplitude (kN)",
        &p.spectra,
        &p.marks,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thinning_keeps_the_extremes() {
        let pts: Vec<(f64, f64)> = (0..10_000).map(|i| (i as f64, ((i * 37) % 101) as f64)).collect();
        let t = thin(&pts, 1000);
        assert!(t.len() <= 1000);
        assert_eq!(t.iter().map(|p| p.1).fold(f64::MIN, f64::max), 100.0);
        assert_eq!(t.iter().map(|p| p.1).fold(f64::MAX, f64::min), 0.0);
    }
}
