//! The chart of styles with a ring's bells marked, for the report page.

use clapper_core::chart::{ChartSpec, Styles};
use clapper_io::bell_file::LoadedBell;
use clapper_plot::chart::Marker;
use clapper_plot::quantity;

use crate::AppError;

/// The chart of styles with `bells` marked, and a close-up around them,
/// as SVG text (two 40 x 40 sweeps, about 0.3 s on two cores).
pub fn chart_svg(bells: &[LoadedBell]) -> Result<String, AppError> {
    // The chart is drawn for the bells' own contact angle (their median),
    // not the paper's 26 deg: a ring of 28-30 deg was drawn on a 26 deg chart.
    let mut phis: Vec<f64> = bells.iter().map(|b| b.bell.phi_max).collect();
    phis.sort_by(f64::total_cmp);
    let phi_max = match phis.len() {
        0 => clapper_core::bell::CHART_PHI_MAX_DEG.to_radians(),
        n if n % 2 == 1 => phis[n / 2],
        n => 0.5 * (phis[n / 2 - 1] + phis[n / 2]),
    };
    let spec = ChartSpec {
        nx: 40,
        ny: 40,
        styles: Styles::Both,
        construction: clapper_core::bell::ChartConstruction {
            phi_max,
            ..Default::default()
        },
        ..ChartSpec::default()
    };
    let phi_words = match (phis.first(), phis.last()) {
        (Some(lo), Some(hi)) if hi - lo > 0.05f64.to_radians() => format!(
            "phi_max = {:.1} deg, the bells' median; theirs {:.1} to {:.1} deg",
            phi_max.to_degrees(),
            lo.to_degrees(),
            hi.to_degrees()
        ),
        _ if bells.len() == 1 => format!("phi_max = {:.1} deg, the bell's", phi_max.to_degrees()),
        _ => format!("phi_max = {:.1} deg, the bells'", phi_max.to_degrees()),
    };
    let chart = clapper_core::chart::sweep(&spec, &|_| {})?;
    let markers: Vec<Marker> = bells
        .iter()
        .map(|b| Marker {
            x: b.bell.r_over_lc(),
            y: b.bell.lb_over_lc(),
            label: b.name.clone(),
        })
        .collect();
    let no_style = || AppError::Request("the chart has no style to show".into());
    let panel = quantity::style_panel(&chart, "").ok_or_else(no_style)?;
    let fig = quantity::figure(
        format!("Styles sustained (theta0 = 171 deg, R = 0.2, {phi_words})"),
        clapper_plot::Quantity::Style,
        vec![panel],
        markers.clone(),
    );
    let mut svg = clapper_plot::chart_figure_svg(&fig)?;
    // A close-up around the bells, where a ring's labels would crowd.
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for b in bells {
        x0 = x0.min(b.bell.r_over_lc());
        x1 = x1.max(b.bell.r_over_lc());
        y0 = y0.min(b.bell.lb_over_lc());
        y1 = y1.max(b.bell.lb_over_lc());
    }
    let zoom = ChartSpec {
        domain: clapper_core::chart::Domain {
            x: (x0 - 0.1, x1 + 0.1),
            y: ((y0 - 0.1).max(0.05), y1 + 0.1),
        },
        ..spec
    };
    let zc = clapper_core::chart::sweep(&zoom, &|_| {})?;
    let zfig = quantity::figure(
        "Close-up around the bells".into(),
        clapper_plot::Quantity::Style,
        vec![quantity::style_panel(&zc, "").ok_or_else(no_style)?],
        markers,
    );
    svg.push_str(&clapper_plot::chart_figure_svg(&zfig)?);
    Ok(svg)
}
