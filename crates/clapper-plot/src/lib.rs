//! # clapper-plot
//!
//! Plots for people who would rather look than read. The file type follows
//! the extension: `.svg` or `.png`. Text is set in DejaVu Sans, carried
//! inside the binary (`src/fonts.rs`): no system font or fontconfig needed.

#![warn(missing_docs)]

/// Words as a plot shows them: the model's names in ASCII (as the command
/// line and CSV headers spell them) turned into its symbols: `theta0` θ₀,
/// `theta` θ, `phi_max` φₘₐₓ, `phi` φ, `R2` R₂, and a number's ` deg` °.
/// Only whole words change (`theta_r` stays as it is).
pub(crate) fn symbols(text: &str) -> String {
    let word = |c: char| c.is_ascii_alphanumeric() || c == '_';
    let mut out = String::with_capacity(text.len() + 8);
    let mut rest = text;
    let mut prev: Option<char> = None;
    while let Some(c) = rest.chars().next() {
        if word(c) && !prev.is_some_and(word) {
            let end = rest.find(|c: char| !word(c)).unwrap_or(rest.len());
            let w = &rest[..end];
            let sym = match w {
                "theta0" => Some("θ₀"),
                "theta" => Some("θ"),
                "phi_max" => Some("φₘₐₓ"),
                "phi" => Some("φ"),
                "R2" => Some("R₂"),
                "deg" if prev == Some(' ') && out.trim_end().ends_with(|c: char| c.is_ascii_digit()) => {
                    // "171 deg" -> "171°": the space goes too.
                    out.pop();
                    Some("°")
                }
                _ => None,
            };
            out.push_str(sym.unwrap_or(w));
            prev = w.chars().last();
            rest = &rest[end..];
        } else {
            out.push(c);
            prev = Some(c);
            rest = &rest[c.len_utf8()..];
        }
    }
    out
}

/// A tick label: the shortest decimal of the value rounded to 1e-6 ("150",
/// "0.25", "0", never "150.0" or "-0.0").
pub(crate) fn tick(v: &f64) -> String {
    let r = (v * 1e6).round() / 1e6;
    if r == 0.0 {
        "0".into()
    } else {
        format!("{r}")
    }
}

/// Draw to `path` as SVG or PNG by its extension: `$draw(&root, args..)` is
/// called on a drawing area of either backend, then presented. A macro
/// because the two backends are different types.
macro_rules! render {
    ($path:expr, $size:expr, $draw:ident ( $($arg:expr),* )) => {{
        let path: &std::path::Path = $path;
        crate::fonts::ensure();
        match crate::format_of(path)? {
            crate::Format::Svg => {
                let root = plotters::prelude::SVGBackend::new(path, $size).into_drawing_area();
                $draw(&root, $($arg),*).map_err(|e| crate::draw_err(path, e))?;
                root.present().map_err(|e| crate::draw_err(path, e))
            }
            crate::Format::Png => {
                let root = crate::bitmap_text::Bitmap::new(path, $size).into_drawing_area();
                $draw(&root, $($arg),*).map_err(|e| crate::draw_err(path, e))?;
                root.present().map_err(|e| crate::draw_err(path, e))
            }
        }
    }};
}

/// Draw as SVG text: `$draw(&root, args..)` on an SVG drawing area that
/// writes into a string, for pages that embed their plots.
macro_rules! render_svg {
    ($size:expr, $draw:ident ( $($arg:expr),* )) => {{
        let mut out = String::new();
        crate::fonts::ensure();
        {
            let root = plotters::prelude::SVGBackend::with_string(&mut out, $size).into_drawing_area();
            let here = std::path::Path::new("(svg)");
            $draw(&root, $($arg),*).map_err(|e| crate::draw_err(here, e))?;
            root.present().map_err(|e| crate::draw_err(here, e))?;
        }
        Ok(out)
    }};
}

pub mod animation;
mod bitmap_text;
pub mod chart;
mod fonts;
pub mod quantity;
pub mod ringing_log;
pub mod signal;
pub mod striking;
pub mod tower;

pub use chart::{
    chart_figure, chart_figure_svg, line_plot, line_plot_scaled, ChartFigure, Marker, Panel, Scale, Series,
};
pub use plotters::style::RGBColor;
pub use quantity::Quantity;
pub use signal::{spectrogram_plot, SpectrogramPlot};
pub use striking::{striking_plot, striking_plot_svg, PlotStrike, StrikingPlot};

use std::path::Path;

use clapper_core::stroke::Sample;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::series::DashedLineSeries;

/// Why a plot could not be drawn.
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    /// The extension is neither `.svg` nor `.png`.
    #[error("plot file {0} must end in .svg or .png")]
    Format(String),
    /// `-` given where a plot file is wanted.
    #[error("a plot is drawn to a file: give a name ending in .svg or .png, not - (standard output)")]
    Stdout,
    /// Nothing to draw.
    #[error("nothing to plot: {0}")]
    Empty(&'static str),
    /// The drawing backend failed (file not writable, no font, ...).
    #[error("could not draw {path}: {message}")]
    Draw {
        /// The file.
        path: String,
        /// The backend's message.
        message: String,
    },
}

/// One plot's file format.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// Scalable vector graphics.
    Svg,
    /// Portable network graphics.
    Png,
}

/// The format of `path` by its extension.
pub fn format_of(path: &Path) -> Result<Format, PlotError> {
    match path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .as_deref()
    {
        Some("svg") => Ok(Format::Svg),
        Some("png") => Ok(Format::Png),
        _ if path.as_os_str() == "-" => Err(PlotError::Stdout),
        _ => Err(PlotError::Format(path.display().to_string())),
    }
}

/// What a stroke plot shows besides the trace.
#[derive(Clone, Debug, Default)]
pub struct StrokePlot<'a> {
    /// Title line (bell, style, settings).
    pub title: &'a str,
    /// φ_max (deg), drawn as two faint lines.
    pub phi_max_deg: f64,
    /// Times (s) at which strokes begin, drawn as vertical lines.
    pub stroke_starts: Vec<f64>,
}

fn draw_err(path: &Path, e: impl std::fmt::Display) -> PlotError {
    PlotError::Draw {
        path: path.display().to_string(),
        message: e.to_string(),
    }
}

/// The paper's Fig 9: θ and φ (deg, left axis) and φ' (rad/s, right axis)
/// against time (s), over the strokes in `samples`.
pub fn stroke_plot(path: &Path, samples: &[Sample], plot: &StrokePlot<'_>) -> Result<(), PlotError> {
    if samples.len() < 2 {
        return Err(PlotError::Empty("fewer than two samples"));
    }
    render!(path, STROKE_PLOT_SIZE, draw_strokes(samples, plot))
}

/// Size of the stroke plot (px).
const STROKE_PLOT_SIZE: (u32, u32) = (1200, 700);

/// [`stroke_plot`] as SVG text, to embed in a page.
pub fn stroke_plot_svg(samples: &[Sample], plot: &StrokePlot<'_>) -> Result<String, PlotError> {
    if samples.len() < 2 {
        return Err(PlotError::Empty("fewer than two samples"));
    }
    render_svg!(STROKE_PLOT_SIZE, draw_strokes(samples, plot))
}

type DrawResult<DB> = Result<(), DrawingAreaErrorKind<<DB as DrawingBackend>::ErrorType>>;

fn draw_strokes<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    samples: &[Sample],
    plot: &StrokePlot<'_>,
) -> DrawResult<DB> {
    root.fill(&WHITE)?;
    let t0 = samples.first().map_or(0.0, |s| s.t);
    let t1 = samples.last().map_or(1.0, |s| s.t).max(t0 + 1e-3);
    let vmax = samples.iter().map(|s| s.y[3].abs()).fold(0.0f64, f64::max).max(0.1) * 1.1;
    let mut chart = ChartBuilder::on(root)
        .caption(crate::symbols(plot.title), ("sans-serif", 24))
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(60)
        .right_y_label_area_size(70)
        .build_cartesian_2d(t0..t1, -190.0f64..190.0)?
        .set_secondary_coord(t0..t1, -vmax..vmax);
    chart
        .configure_mesh()
        .x_desc("time (s)")
        .y_desc("angle (deg)")
        .y_labels(9)
        .x_label_formatter(&tick)
        .y_label_formatter(&tick)
        .light_line_style(RGBColor(235, 235, 235))
        .label_style(("sans-serif", 15))
        .axis_desc_style(("sans-serif", 17))
        .draw()?;
    chart
        .configure_secondary_axes()
        .y_desc("clapper rate φ' (rad/s)")
        .y_label_formatter(&tick)
        .label_style(("sans-serif", 15))
        .axis_desc_style(("sans-serif", 17))
        .draw()?;
    let grey = RGBColor(170, 170, 170);
    for &m in &[plot.phi_max_deg, -plot.phi_max_deg] {
        if m != 0.0 {
            chart.draw_series(LineSeries::new([(t0, m), (t1, m)], grey.stroke_width(1)))?;
        }
    }
    for &ts in &plot.stroke_starts {
        chart.draw_series(LineSeries::new([(ts, -190.0), (ts, 190.0)], grey.stroke_width(1)))?;
    }
    let blue = RGBColor(31, 90, 180);
    let green = RGBColor(20, 140, 60);
    let red = RGBColor(210, 40, 40);
    chart
        .draw_series(DashedLineSeries::new(
            samples.iter().map(|s| (s.t, s.y[0].to_degrees())),
            8,
            5,
            blue.stroke_width(2),
        ))?
        .label("bell angle θ (deg)")
        .legend(move |(x, y)| PathElement::new([(x, y), (x + 25, y)], blue.stroke_width(2)));
    chart
        .draw_series(LineSeries::new(
            samples.iter().map(|s| (s.t, s.y[1].to_degrees())),
            green.stroke_width(2),
        ))?
        .label("clapper angle φ (deg)")
        .legend(move |(x, y)| PathElement::new([(x, y), (x + 25, y)], green.stroke_width(2)));
    chart
        .draw_secondary_series(LineSeries::new(
            samples.iter().map(|s| (s.t, s.y[3])),
            red.stroke_width(1),
        ))?
        .label("clapper rate φ' (rad/s, right axis)")
        .legend(move |(x, y)| PathElement::new([(x, y), (x + 25, y)], red.stroke_width(2)));
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::LowerRight)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font(("sans-serif", 15))
        .draw()?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn samples() -> Vec<Sample> {
        (0..200)
            .map(|k| {
                let t = k as f64 * 0.01;
                Sample {
                    t,
                    y: [3.0 * (t * 2.0).cos(), 0.4 * (t * 5.0).sin(), 0.0, (t * 7.0).sin()],
                    contact_force: 0.0,
                    friction: [0.0; 2],
                }
            })
            .collect()
    }

    #[test]
    fn writes_svg_and_png() {
        let dir = tempfile::tempdir().unwrap();
        let p = StrokePlot {
            title: "test",
            phi_max_deg: 26.0,
            stroke_starts: vec![1.0],
        };
        let svg = dir.path().join("a.svg");
        stroke_plot(&svg, &samples(), &p).unwrap();
        let text = std::fs::read_to_string(&svg).unwrap();
        assert!(text.contains("<svg") && text.contains("time (s)"));
        let png = dir.path().join("a.png");
        stroke_plot(&png, &samples(), &p).unwrap();
        let bytes = std::fs::read(&png).unwrap();
        assert_eq!(&bytes[1..4], b"PNG");
    }

    #[test]
    fn refuses_other_formats_and_empty_traces() {
        let p = StrokePlot::default();
        assert!(matches!(
            stroke_plot(Path::new("x.jpg"), &samples(), &p),
            Err(PlotError::Format(_))
        ));
        assert!(matches!(
            stroke_plot(Path::new("x.svg"), &[], &p),
            Err(PlotError::Empty(_))
        ));
    }
}

#[cfg(test)]
mod tick_tests {
    #[test]
    fn plots_show_symbols_for_the_ascii_names() {
        assert_eq!(
            super::symbols("Fig 10 (theta0 = 171 deg, R = 0.2, R2 = 0.3, phi_max = 26 deg, 20 x 20)"),
            "Fig 10 (θ₀ = 171°, R = 0.2, R₂ = 0.3, φₘₐₓ = 26°, 20 x 20)"
        );
        assert_eq!(
            super::symbols("first strike angle theta (deg)"),
            "first strike angle θ (deg)"
        );
        assert_eq!(
            super::symbols("phi' (rad/s), theta_r, phi_maximum, 3 degrees"),
            "φ' (rad/s), theta_r, phi_maximum, 3 degrees"
        );
    }

    #[test]
    fn ticks_are_short_and_never_negative_zero() {
        assert_eq!(super::tick(&150.0), "150");
        assert_eq!(super::tick(&-0.0), "0");
        assert_eq!(super::tick(&(0.1 + 0.2)), "0.3");
        assert_eq!(super::tick(&-2.5), "-2.5");
    }
}
