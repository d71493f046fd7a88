//! A recording's striking (`clapper strikes --plot`, docs/strikes.md): the
//! striking diagram (each bell's line through the places, row by row, drawn
//! where it struck, so a late or early strike leans off its place) over a
//! spectrogram strip of the recording's opening seconds with the strikes
//! heard marked on it.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::{PlotError, SpectrogramPlot};

/// One strike to draw.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlotStrike {
    /// Bell, counting from 1 (the treble).
    pub bell: usize,
    /// Onset (s from the start of the recording).
    pub t_s: f64,
    /// Row, counting from 0, and place in it (from 1), when placed.
    pub row_place: Option<(usize, usize)>,
    /// Onset less its ideal time (ms): positive is late.
    pub error_ms: Option<f64>,
    /// Handstroke (true), backstroke (false), or not known.
    pub hand: Option<bool>,
    /// The clapper struck twice.
    pub double: bool,
}

/// What a striking plot shows.
#[derive(Clone, Debug, PartialEq)]
pub struct StrikingPlot<'a> {
    /// Title line.
    pub title: &'a str,
    /// Bells in the ring.
    pub bells: usize,
    /// The mean interval between successive bells (ms): one place's width.
    pub interval_ms: f64,
    /// Every strike, in time order.
    pub strikes: &'a [PlotStrike],
    /// The spectrogram strip (its times a window of the recording).
    pub spectrogram: SpectrogramPlot<'a>,
}

/// A bell's colour: spread round the hue circle so neighbours differ.
fn bell_colour(bell: usize, bells: usize) -> RGBColor {
    let t = ((bell.saturating_sub(1)) * 5 % bells.max(1)) as f64 / bells.max(1) as f64;
    let h = t * 6.0;
    let x = 1.0 - (h % 2.0 - 1.0).abs();
    let (r, g, b) = match h as usize {
        0 => (1.0, x, 0.0),
        1 => (x, 1.0, 0.0),
        2 => (0.0, 1.0, x),
        3 => (0.0, x, 1.0),
        4 => (x, 0.0, 1.0),
        _ => (1.0, 0.0, x),
    };
    // Darkened, to read on white.
    let c = |v: f64| (40.0 + 170.0 * v) as u8;
    RGBColor(c(r), c(g), c(b))
}

/// Draw the striking diagram over the spectrogram strip, to `path` (.svg
/// or .png by its extension).
pub fn striking_plot(path: &Path, p: &StrikingPlot<'_>) -> Result<(), PlotError> {
    check(p)?;
    render!(path, (1200, 1150), draw(p))
}

/// The same plot as SVG text.
pub fn striking_plot_svg(p: &StrikingPlot<'_>) -> Result<String, PlotError> {
    check(p)?;
    render_svg!((1200, 1150), draw(p))
}

fn check(p: &StrikingPlot<'_>) -> Result<(), PlotError> {
    if p.bells == 0 {
        return Err(PlotError::Empty("a ring without bells"));
    }
    let s = &p.spectrogram;
    if s.times.is_empty() || s.freqs.len() < 2 || s.db.len() != s.times.len() * s.freqs.len() {
        return Err(PlotError::Empty("spectrogram without frames"));
    }
    Ok(())
}

type DrawResult<DB> = Result<(), DrawingAreaErrorKind<<DB as DrawingBackend>::ErrorType>>;

fn draw<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, p: &StrikingPlot<'_>) -> DrawResult<DB> {
    root.fill(&WHITE)?;
    let (top, bottom) = root.split_vertically(760);
    diagram(&top, p)?;
    strip(&bottom, p)
}

/// Bells' lines through the places (x: place plus error in places),
/// rows down the page.
fn diagram<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, p: &StrikingPlot<'_>) -> DrawResult<DB> {
    let placed: Vec<(&PlotStrike, usize, f64)> = p
        .strikes
        .iter()
        .filter_map(|s| {
            let (row, place) = s.row_place?;
            let lean = s.error_ms.unwrap_or(0.0) / p.interval_ms.max(1.0);
            Some((s, row, place as f64 + lean))
        })
        .collect();
    let rows = placed.iter().map(|x| x.1).max().map_or(1, |r| r + 1);
    let n = p.bells as f64;
    let mut chart = ChartBuilder::on(area)
        .caption(crate::symbols(p.title), ("sans-serif", 22))
        .margin(12)
        .x_label_area_size(45)
        .y_label_area_size(60)
        .build_cartesian_2d(0.4..n + 0.6, (rows as f64 - 0.5)..-0.5)?;
    chart
        .configure_mesh()
        .x_labels(p.bells.min(16))
        .x_label_formatter(&|v| format!("{:.0}", v))
        .y_labels(12)
        .y_label_formatter(&|v| format!("{:.0}", v))
        .x_desc(format!(
            "place (a strike leans off its place by its error; one place = {:.0} ms)",
            p.interval_ms
        ))
        .y_desc("row")
        .light_line_style(WHITE)
        .bold_line_style(RGBColor(225, 225, 225))
        .label_style(("sans-serif", 15))
        .axis_desc_style(("sans-serif", 16))
        .draw()?;
    // Handstroke rows lightly shaded.
    let hands: Vec<usize> = {
        let mut v: Vec<usize> = placed.iter().filter(|x| x.0.hand == Some(true)).map(|x| x.1).collect();
        v.dedup();
        v
    };
    chart.draw_series(hands.iter().map(|&r| {
        Rectangle::new(
            [(0.4, r as f64 - 0.5), (n + 0.6, r as f64 + 0.5)],
            RGBColor(244, 244, 250).filled(),
        )
    }))?;
    for bell in 1..=p.bells {
        let colour = bell_colour(bell, p.bells);
        let line: Vec<(f64, f64)> = placed
            .iter()
            .filter(|x| x.0.bell == bell)
            .map(|x| (x.2, x.1 as f64))
            .collect();
        chart
            .draw_series(LineSeries::new(line.iter().copied(), colour.stroke_width(2)))?
            .label(format!("bell {bell}"))
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], colour.stroke_width(3)));
        chart.draw_series(line.iter().map(|&(x, y)| Circle::new((x, y), 2, colour.filled())))?;
    }
    // Double strikes ringed in black.
    chart.draw_series(
        placed
            .iter()
            .filter(|x| x.0.double)
            .map(|x| Circle::new((x.2, x.1 as f64), 7, BLACK.stroke_width(2))),
    )?;
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .background_style(WHITE.mix(0.85))
        .border_style(RGBColor(200, 200, 200))
        .label_font(("sans-serif", 13))
        .draw()?;
    Ok(())
}

/// The opening seconds' spectrogram with each strike heard marked at its
/// onset (its bell's colour; doubles dashed to the second strike).
fn strip<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, p: &StrikingPlot<'_>) -> DrawResult<DB> {
    let mut chart = crate::signal::frame(area, &p.spectrogram, (1100, 300), 17)?;
    let (x, y) = (chart.x_range(), chart.y_range());
    let (t0, t1, fmax) = (x.start, x.end, y.end);
    for st in p.strikes.iter().filter(|st| st.t_s >= t0 && st.t_s <= t1) {
        let colour = bell_colour(st.bell, p.bells);
        chart.draw_series(std::iter::once(PathElement::new(
            vec![(st.t_s, 0.0), (st.t_s, 0.9 * fmax)],
            colour.stroke_width(1),
        )))?;
        chart.draw_series(std::iter::once(Text::new(
            st.bell.to_string(),
            (st.t_s, 0.97 * fmax),
            ("sans-serif", 14).into_font().color(&WHITE),
        )))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn plot<'a>(strikes: &'a [PlotStrike], times: &'a [f64], freqs: &'a [f64], db: &'a [f64]) -> StrikingPlot<'a> {
        StrikingPlot {
            title: "test ring",
            bells: 3,
            interval_ms: 200.0,
            strikes,
            spectrogram: SpectrogramPlot {
                title: "opening seconds",
                times,
                freqs,
                db,
                fmax: 3000.0,
                range_db: 60.0,
            },
        }
    }

    #[test]
    fn the_diagram_draws_every_bell_and_rings_a_double() {
        let strikes: Vec<PlotStrike> = (0..12)
            .map(|k| PlotStrike {
                bell: k % 3 + 1,
                t_s: 0.2 * k as f64,
                row_place: Some((k / 3, k % 3 + 1)),
                error_ms: Some(if k == 4 { 40.0 } else { 0.0 }),
                hand: Some(k / 3 % 2 == 0),
                double: k == 7,
            })
            .collect();
        let times: Vec<f64> = (0..50).map(|i| i as f64 * 0.05).collect();
        let freqs: Vec<f64> = (0..100).map(|i| i as f64 * 40.0).collect();
        let db = vec![-30.0; 5000];
        let svg = striking_plot_svg(&plot(&strikes, &times, &freqs, &db)).unwrap();
        for b in 1..=3 {
            assert!(svg.contains(&format!("bell {b}")), "bell {b} missing");
        }
        // One double ringed: a circle of radius 7.
        assert_eq!(svg.matches("r=\"7\"").count(), 1);
        let empty = plot(&strikes, &[], &freqs, &db);
        assert!(striking_plot_svg(&empty).is_err());
    }
}
