//! A bell's accelerometer log read (`clapper ringing-log --plot`): the
//! whole session's angle with its phases shaded; a zoom of a few strokes
//! with bottom dead centre and each strike marked; and the amplitude of
//! each swing of the raising and lowering, marked by the stroke it struck
//! at.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::PlotError;

/// A phase to shade.
#[derive(Clone, Debug, PartialEq)]
pub struct LogPhase {
    /// "down", "raising", "up", "ringing" or "lowering".
    pub kind: &'static str,
    /// Start and end (s).
    pub span: (f64, f64),
}

/// A swing to mark.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LogSwing {
    /// Bottom dead centre (s).
    pub bdc: f64,
    /// The strike (s) and the bell's angle there (deg).
    pub strike: Option<(f64, f64)>,
    /// Its amplitude (deg).
    pub amplitude: f64,
    /// A handstroke.
    pub hand: bool,
    /// Raising or lowering (its amplitude is plotted).
    pub ringing_up_or_down: bool,
}

/// What the plot shows.
#[derive(Clone, Debug, PartialEq)]
pub struct LogPlot<'a> {
    /// Title line.
    pub title: &'a str,
    /// Sample times (s).
    pub t: &'a [f64],
    /// The bell's angle at each (deg).
    pub theta: &'a [f64],
    /// The phases.
    pub phases: &'a [LogPhase],
    /// The swings.
    pub swings: &'a [LogSwing],
}

fn shade(kind: &str) -> RGBColor {
    match kind {
        "down" => RGBColor(235, 235, 235),
        "raising" => RGBColor(220, 235, 250),
        "up" => RGBColor(255, 243, 205),
        "ringing" => RGBColor(220, 245, 220),
        _ => RGBColor(250, 225, 225),
    }
}

const HAND: RGBColor = RGBColor(31, 111, 180);
const BACK: RGBColor = RGBColor(194, 65, 12);

/// Draw to `path` (.svg or .png by its extension).
pub fn ringing_log_plot(path: &Path, p: &LogPlot<'_>) -> Result<(), PlotError> {
    if p.t.len() < 2 || p.t.len() != p.theta.len() {
        return Err(PlotError::Empty("a log of fewer than two samples"));
    }
    render!(path, (1300, 1100), draw(p))
}

type DrawResult<DB> = Result<(), DrawingAreaErrorKind<<DB as DrawingBackend>::ErrorType>>;
/// A chart of angle (deg) against time (s).
type AngleChart<'a, DB> =
    ChartContext<'a, DB, Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>>;

fn draw<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, p: &LogPlot<'_>) -> DrawResult<DB> {
    root.fill(&WHITE)?;
    let (top, rest) = root.split_vertically(400);
    let (mid, bottom) = rest.split_vertically(370);
    let (t0, t1) = (p.t[0], p.t[p.t.len() - 1]);
    whole(&top, p, (t0, t1))?;
    zoom(&mid, p)?;
    amplitudes(&bottom, p, (t0, t1))
}

/// Axes of time (s) against `y_desc` over `y`, with a caption.
fn axes<'a, DB: DrawingBackend>(
    area: &'a DrawingArea<DB, Shift>,
    caption: &str,
    (a, b): (f64, f64),
    y: std::ops::Range<f64>,
    y_desc: &str,
) -> Result<AngleChart<'a, DB>, DrawingAreaErrorKind<DB::ErrorType>> {
    let mut chart = ChartBuilder::on(area)
        .caption(caption, ("sans-serif", 18))
        .margin(10)
        .x_label_area_size(40)
        .y_label_area_size(55)
        .build_cartesian_2d(a..b, y)?;
    chart
        .configure_mesh()
        .x_desc("time (s)")
        .y_desc(y_desc)
        .y_labels(9)
        .x_label_formatter(&crate::tick)
        .y_label_formatter(&crate::tick)
        .light_line_style(WHITE)
        .bold_line_style(RGBColor(225, 225, 225))
        .label_style(("sans-serif", 14))
        .axis_desc_style(("sans-serif", 15))
        .draw()?;
    Ok(chart)
}

fn angle_axes<'a, DB: DrawingBackend>(
    area: &'a DrawingArea<DB, Shift>,
    caption: &str,
    span: (f64, f64),
) -> Result<AngleChart<'a, DB>, DrawingAreaErrorKind<DB::ErrorType>> {
    axes(area, caption, span, -190.0..190.0, "bell angle θ (deg)")
}

/// The whole log, phases shaded and named.
fn whole<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, p: &LogPlot<'_>, span: (f64, f64)) -> DrawResult<DB> {
    let mut chart = angle_axes(area, &crate::symbols(p.title), span)?;
    for ph in p.phases {
        chart.draw_series(std::iter::once(Rectangle::new(
            [(ph.span.0, -190.0), (ph.span.1, 190.0)],
            shade(ph.kind).filled(),
        )))?;
        chart.draw_series(std::iter::once(Text::new(
            ph.kind,
            (ph.span.0 + 0.01 * (span.1 - span.0), 175.0),
            ("sans-serif", 13).into_font(),
        )))?;
    }
    // At most about 4000 points: the eye sees no more in a row of pixels.
    let step = (p.t.len() / 4000).max(1);
    let idx: Vec<usize> = (0..p.t.len()).step_by(step).collect();
    trace(&mut chart, p, &idx, 1)
}

/// The angle through the samples `idx`, broken where it passes the
/// balance (from past +180 deg to past −180, the same place) and kept
/// inside the plot.
fn trace<DB: DrawingBackend>(
    chart: &mut ChartContext<
        '_,
        DB,
        Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
    >,
    p: &LogPlot<'_>,
    idx: &[usize],
    width: u32,
) -> DrawResult<DB> {
    let mut run: Vec<(f64, f64)> = vec![];
    let mut runs = vec![];
    for &k in idx {
        let v = p.theta[k];
        if !v.is_finite() {
            continue;
        }
        if run.last().is_some_and(|&(_, u): &(f64, f64)| (u - v).abs() > 180.0) {
            runs.push(std::mem::take(&mut run));
        }
        run.push((p.t[k], v.clamp(-189.0, 189.0)));
    }
    runs.push(run);
    for r in runs {
        chart.draw_series(LineSeries::new(r, RGBColor(40, 40, 40).stroke_width(width)))?;
    }
    Ok(())
}

/// A few strokes of the ringing (or the first swings): BDC and strikes.
fn zoom<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, p: &LogPlot<'_>) -> DrawResult<DB> {
    let ringing = p.phases.iter().find(|ph| ph.kind == "ringing").map(|ph| ph.span);
    let pick: Vec<&LogSwing> = match ringing {
        Some((a, b)) => p.swings.iter().filter(|s| s.bdc >= a && s.bdc <= b).take(4).collect(),
        None => p.swings.iter().take(4).collect(),
    };
    let (a, b) = match (pick.first(), pick.last()) {
        (Some(f), Some(l)) => (f.bdc - 1.2, l.bdc + 1.2),
        _ => (p.t[0], p.t[p.t.len() - 1].min(p.t[0] + 10.0)),
    };
    let mut chart = angle_axes(
        area,
        "four strokes: bottom dead centre (dashed) and the strike (dot)",
        (a, b),
    )?;
    let (i, j) = (p.t.partition_point(|&x| x < a), p.t.partition_point(|&x| x <= b));
    trace(&mut chart, p, &(i..j).collect::<Vec<_>>(), 2)?;
    for s in &pick {
        let colour = if s.hand { HAND } else { BACK };
        chart.draw_series(DashedLineSeries::new(
            vec![(s.bdc, -190.0), (s.bdc, 190.0)],
            6,
            4,
            colour.stroke_width(1),
        ))?;
        if let Some((ts, th)) = s.strike {
            chart.draw_series(std::iter::once(Circle::new((ts, th), 6, colour.filled())))?;
            chart.draw_series(std::iter::once(Text::new(
                format!("{} {:.0} ms", if s.hand { "hand" } else { "back" }, (ts - s.bdc) * 1e3),
                (ts, th + if th > 0.0 { -25.0 } else { 15.0 }),
                ("sans-serif", 13).into_font(),
            )))?;
        }
    }
    Ok(())
}

/// Amplitude against time while raising and lowering, by the stroke struck.
fn amplitudes<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, p: &LogPlot<'_>, span: (f64, f64)) -> DrawResult<DB> {
    let mut chart = axes(
        area,
        "amplitude of each swing ringing up and down (filled: the clapper struck; hand blue, back orange)",
        span,
        0.0..185.0,
        "amplitude (deg)",
    )?;
    for s in p.swings.iter().filter(|s| s.ringing_up_or_down) {
        let colour = if s.hand { HAND } else { BACK };
        let style = if s.strike.is_some() {
            colour.filled()
        } else {
            colour.stroke_width(1)
        };
        chart.draw_series(std::iter::once(Circle::new((s.bdc, s.amplitude), 4, style)))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_log_plot_is_drawn_and_an_empty_one_refused() {
        let t: Vec<f64> = (0..2000).map(|k| k as f64 * 0.01).collect();
        let theta: Vec<f64> = t.iter().map(|x| 170.0 * (x * 2.5).cos()).collect();
        let phases = [LogPhase {
            kind: "ringing",
            span: (0.0, 20.0),
        }];
        let swings: Vec<LogSwing> = (0..6)
            .map(|k| LogSwing {
                bdc: 0.63 + 1.257 * k as f64,
                strike: Some((0.8 + 1.257 * k as f64, -40.0)),
                amplitude: 170.0,
                hand: k % 2 == 0,
                ringing_up_or_down: false,
            })
            .collect();
        let dir = tempfile::tempdir().expect("dir");
        let path = dir.path().join("log.svg");
        let p = LogPlot {
            title: "a bell",
            t: &t,
            theta: &theta,
            phases: &phases,
            swings: &swings,
        };
        ringing_log_plot(&path, &p).expect("drawn");
        let svg = std::fs::read_to_string(&path).expect("written");
        assert!(svg.contains("hand") && svg.contains("ringing"));
        let empty = LogPlot {
            t: &[],
            theta: &[],
            ..p
        };
        assert!(ringing_log_plot(&path, &empty).is_err());
    }
}
