//! From computed charts to chart figures: which number each quantity
//! shows, in which units, on which scale.

use clapper_core::chart::{Chart, StrokeSummary};
use clapper_core::stroke::Style;
use plotters::style::RGBColor;

use crate::chart::{ChartFigure, Marker, Panel, Scale};

/// What a chart shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Quantity {
    /// Which styles are sustained: right, wrong, both, neither.
    Style,
    /// θ at the first strike (deg), Fig 10 and 16.
    StrikeAngle,
    /// φ' just before the first strike (rad/s), Fig 11.
    StrikeVelocity,
    /// Lift-off angle (deg), Fig 12.
    Liftoff,
    /// Double strike index D, Fig 14 and 15 (scale truncated at 60 as in the paper).
    DoubleStrike,
    /// Odd-struckness (ms): handstroke minus backstroke time from bottom dead
    /// centre to the strike; 0 everywhere for a symmetric bell.
    OddStruck,
}

/// The paper truncates its D scale at 60 so that the charts of different R compare.
pub const D_SCALE_MAX: f64 = 60.0;

impl Quantity {
    /// The number shown for one sustained stroke, in display units.
    pub fn value(self, s: &StrokeSummary) -> Option<f64> {
        match self {
            Quantity::Style => None,
            Quantity::StrikeAngle => s.strike_theta.map(f64::to_degrees),
            Quantity::StrikeVelocity => s.strike_phidot,
            Quantity::Liftoff => s.liftoff_theta.map(f64::to_degrees),
            Quantity::DoubleStrike => s.double_strike_index,
            Quantity::OddStruck => s.odd_struck.map(|t| t * 1e3),
        }
    }

    /// Words and units, for titles and colour bars.
    pub fn label(self) -> &'static str {
        match self {
            Quantity::Style => "styles sustained",
            Quantity::StrikeAngle => "first strike angle theta (deg)",
            Quantity::StrikeVelocity => "strike velocity phi' (rad/s)",
            Quantity::Liftoff => "lift-off angle theta (deg)",
            Quantity::DoubleStrike => "double strike index D (scale cut at 60)",
            Quantity::OddStruck => "odd-struckness, handstroke minus backstroke (ms)",
        }
    }
}

/// The categories of [`Quantity::Style`], in value order.
pub fn style_categories() -> Vec<(String, RGBColor)> {
    vec![
        ("neither".into(), RGBColor(255, 255, 255)),
        ("right only".into(), RGBColor(49, 130, 189)),
        ("wrong only".into(), RGBColor(230, 85, 13)),
        ("right and wrong".into(), RGBColor(116, 196, 118)),
    ]
}

fn style_title(style: Style) -> &'static str {
    match style {
        Style::Right => "ringing right",
        Style::Wrong => "ringing wrong",
    }
}

/// A panel of `quantity` for `style` of `chart`, blank where the style is
/// not sustained. `None` if the chart lacks that style.
pub fn panel(chart: &Chart, style: Style, quantity: Quantity, title: &str) -> Option<Panel> {
    let (nx, ny) = (chart.spec.nx, chart.spec.ny);
    let mut values = Vec::with_capacity(nx * ny);
    let mut region = Vec::with_capacity(nx * ny);
    for j in 0..ny {
        for i in 0..nx {
            let s = chart.cell(i, j, style)?.sustained();
            region.push(s.is_some());
            values.push(s.and_then(|s| quantity.value(s)));
        }
    }
    Some(Panel {
        title: if title.is_empty() {
            style_title(style).into()
        } else {
            title.into()
        },
        xs: chart.spec.xs(),
        ys: chart.spec.ys(),
        values,
        region,
    })
}

/// The one-panel map of which styles a chart of both styles sustains; the
/// boundary drawn is the right region's.
pub fn style_panel(chart: &Chart, title: &str) -> Option<Panel> {
    let (nx, ny) = (chart.spec.nx, chart.spec.ny);
    let mut values = Vec::with_capacity(nx * ny);
    let mut region = Vec::with_capacity(nx * ny);
    for j in 0..ny {
        for i in 0..nx {
            let r = chart.cell(i, j, Style::Right)?.sustained().is_some();
            let w = chart.cell(i, j, Style::Wrong)?.sustained().is_some();
            region.push(r);
            values.push(Some(f64::from(u8::from(r) + 2 * u8::from(w))));
        }
    }
    Some(Panel {
        title: title.into(),
        xs: chart.spec.xs(),
        ys: chart.spec.ys(),
        values,
        region,
    })
}

/// The colour scale for `quantity` over `panels`: fixed where the paper's is
/// (angles, D), from the data otherwise.
pub fn scale(quantity: Quantity, panels: &[Panel]) -> Scale {
    let vals = || panels.iter().flat_map(|p| p.values.iter().flatten().copied());
    let (lo, hi) = vals().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| (a.min(v), b.max(v)));
    let (min, max) = match quantity {
        Quantity::Style => return Scale::Categories(style_categories()),
        Quantity::StrikeAngle => (-180.0, 0.0f64.max(hi)),
        Quantity::Liftoff => (0.0, 180.0),
        Quantity::DoubleStrike => (0.0, D_SCALE_MAX),
        Quantity::StrikeVelocity if lo.is_finite() => (lo, hi),
        Quantity::StrikeVelocity => (-1.0, 1.0),
        // Symmetric about zero, so that the sign reads at a glance.
        Quantity::OddStruck => {
            let m = lo.abs().max(hi.abs());
            if m.is_finite() && m > 0.0 {
                (-m, m)
            } else {
                (-1.0, 1.0)
            }
        }
    };
    Scale::Continuous {
        min,
        max,
        label: quantity.label().into(),
    }
}

/// A whole figure from panels.
pub fn figure(title: String, quantity: Quantity, panels: Vec<Panel>, markers: Vec<Marker>) -> ChartFigure {
    let scale = scale(quantity, &panels);
    ChartFigure {
        title,
        panels,
        scale,
        markers,
        axes: crate::chart::chart_axes(),
        lines: vec![],
    }
}
