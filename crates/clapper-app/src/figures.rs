//! The paper's figures that the model computes (Figs 7, 9(a-d), 10, 11,
//! 12, 14, 15, 16), as data: each figure described for the plotting layer,
//! its CSV, and an index in Markdown and HTML saying in a line what each
//! shows. `clapper figures` draws them (SVG and PNG) and writes the files.

use std::fmt::Write as _;

use clapper_core::chart::{Chart, ChartSpec, Domain, Styles};
use clapper_core::prelude::*;
use clapper_core::stroke::Sample;
use clapper_plot::chart::{Marker, Series};
use clapper_plot::quantity::{self, Quantity};
use clapper_plot::{ChartFigure, RGBColor};

use crate::chart::settings_words;
use crate::AppError;

/// A figure to draw.
pub enum Drawing {
    /// A chart (heat maps with markers).
    Chart(ChartFigure),
    /// A stroke's time history (the paper's Fig 9).
    Stroke {
        /// Title.
        title: String,
        /// The trace.
        samples: Vec<Sample>,
        /// φ_max of the bell (deg).
        phi_max_deg: f64,
        /// When the strokes after the first begin (s).
        stroke_starts: Vec<f64>,
    },
    /// Curves and points.
    Lines {
        /// Title.
        title: String,
        /// x axis label.
        x_label: String,
        /// y axis label.
        y_label: String,
        /// The curves.
        series: Vec<Series>,
    },
}

/// Every file of the figures: drawings (to be drawn as `NAME.svg` and
/// `NAME.png`) and text files (CSV data, the index pages), by name.
#[derive(Default)]
pub struct FigureSet {
    /// Drawings by name (no extension).
    pub drawings: Vec<(String, Drawing)>,
    /// Text files by file name.
    pub files: Vec<(String, String)>,
    /// How many figures the index lists.
    pub count: usize,
}

/// Computes one chart for the figures, with the caller's thread pool and
/// progress: the chart and its wall time (s). `what` names it for progress.
pub type ChartRunner<'a> = dyn FnMut(&ChartSpec, &str) -> Result<(Chart, f64), AppError> + 'a;

fn csv_of<E: std::fmt::Display>(write: impl FnOnce(&mut Vec<u8>) -> Result<(), E>) -> Result<String, AppError> {
    let mut buf = Vec::new();
    write(&mut buf).map_err(|e| AppError::Request(format!("CSV: {e}")))?;
    Ok(String::from_utf8(buf).expect("CSV writers write UTF-8"))
}

/// One entry of the index.
struct Entry {
    name: String,
    title: String,
    says: String,
    data: Vec<String>,
}

fn fig9_bells() -> Vec<(&'static str, &'static str, Bell, Style)> {
    let c = ChartConstruction::default();
    vec![
        ("fig09a", "lab bell ringing right", Bell::lab(), Style::Right),
        ("fig09b", "lab bell ringing wrong", Bell::lab(), Style::Wrong),
        (
            "fig09c",
            "bell at (0.458, 0.732) ringing right",
            c.bell(0.458, 0.732).expect("valid chart point"),
            Style::Right,
        ),
        (
            "fig09d",
            "bell at (-0.005, 1.363) ringing right",
            c.bell(-0.005, 1.363).expect("valid chart point"),
            Style::Right,
        ),
    ]
}

fn markers() -> Vec<Marker> {
    let lab = Bell::lab();
    vec![
        Marker {
            x: lab.r_over_lc(),
            y: lab.lb_over_lc(),
            label: "lab, 9(a,b)".into(),
        },
        Marker {
            x: 0.458,
            y: 0.732,
            label: "9(c)".into(),
        },
        Marker {
            x: -0.005,
            y: 1.363,
            label: "9(d)".into(),
        },
    ]
}

/// Points where `style` is sustained, and their mean L_b/L_c.
fn region_stats(chart: &Chart, style: Style) -> (usize, f64) {
    let ys = chart.spec.ys();
    let mut n = 0;
    let mut sum = 0.0;
    for (j, y) in ys.iter().enumerate() {
        for i in 0..chart.spec.nx {
            if chart.cell(i, j, style).and_then(|c| c.sustained()).is_some() {
                n += 1;
                sum += y;
            }
        }
    }
    (n, if n > 0 { sum / n as f64 } else { f64::NAN })
}

fn chart_panels(chart: &Chart, q: Quantity) -> Vec<clapper_plot::Panel> {
    chart
        .spec
        .styles
        .list()
        .iter()
        .zip(["(a) ringing right", "(b) ringing wrong"])
        .filter_map(|(s, t)| {
            let title = if chart.spec.styles == Styles::Both { t } else { "" };
            quantity::panel(chart, *s, q, title)
        })
        .collect()
}

/// The figures for the chart settings `base` (both styles), each chart
/// computed by `run_chart`.
pub fn figures(base: &ChartSpec, run_chart: &mut ChartRunner<'_>) -> Result<FigureSet, AppError> {
    let base = *base;
    let mut set = FigureSet::default();
    let mut entries: Vec<Entry> = vec![];
    fig07(base, run_chart, &mut set, &mut entries)?;
    fig09(base, &mut set, &mut entries)?;
    let full = figs10_to_14(base, run_chart, &mut set, &mut entries)?;
    fig15(base, run_chart, &mut set, &mut entries)?;
    fig16(base, run_chart, &full, &mut set, &mut entries)?;
    let words = settings_words(&base);
    let (md, html) = index(&entries, &words, full.secs);
    set.files.push(("index.md".into(), md));
    set.files.push(("index.html".into(), html));
    set.count = entries.len();
    Ok(set)
}

/// What the fully-up chart of Figs 10-14 found, for Fig 16 to compare
/// with: the points sustaining right (their mean L_b/L_c) and wrong, and
/// the chart's wall time (s).
struct FullUp {
    nr: usize,
    yr: f64,
    nw: usize,
    secs: f64,
}

/// Whether the chart cell nearest the lab bell sustains `s`.
fn lab_cell(c: &Chart, s: Style) -> bool {
    let lab = Bell::lab();
    let xs = c.spec.xs();
    let ys = c.spec.ys();
    let near = |v: &[f64], t: f64| {
        (0..v.len())
            .min_by(|&a, &b| (v[a] - t).abs().total_cmp(&(v[b] - t).abs()))
            .unwrap_or(0)
    };
    c.cell(near(&xs, lab.r_over_lc()), near(&ys, lab.lb_over_lc()), s)
        .and_then(|c| c.sustained())
        .is_some()
}

/// Fig 7: lift-off at r = 0 by (15), (16), with the simulated r = 0 column.
fn fig07(
    base: ChartSpec,
    run_chart: &mut ChartRunner<'_>,
    set: &mut FigureSet,
    entries: &mut Vec<Entry>,
) -> Result<(), AppError> {
    let column = ChartSpec {
        domain: Domain {
            x: (0.0, 0.0),
            y: base.domain.y,
        },
        nx: 1,
        ..base
    };
    let (col, _) = run_chart(&column, "fig 7 (r = 0 column)")?;
    let phi = base.construction.phi_max;
    let (y0, y1) = base.domain.y;
    let formula: Vec<(f64, LiftoffAngles)> = (0..=200)
        .map(|k| {
            let y = y0 + (y1 - y0) * k as f64 / 200.0;
            (y, liftoff_angles(y, phi).expect("positive L_b/L_c"))
        })
        .collect();
    let sim = |style: Style| -> Vec<(f64, f64)> {
        col.cells
            .iter()
            .filter(|c| c.style == style)
            .filter_map(|c| Some((c.y, c.result.as_ref().ok()?.liftoff_theta?.to_degrees())))
            .collect()
    };
    let (sim_r, sim_w) = (sim(Style::Right), sim(Style::Wrong));
    let worst = sim_r
        .iter()
        .map(|&(y, t)| (t - liftoff_angles(y, phi).expect("valid").right.to_degrees()).abs())
        .chain(
            sim_w
                .iter()
                .map(|&(y, t)| (t - liftoff_angles(y, phi).expect("valid").wrong.to_degrees()).abs()),
        )
        .fold(0.0f64, f64::max);
    let series = fig07_series(&col, &formula, &sim_r, &sim_w);
    let title = format!("Fig 7: lift-off angle for r = 0, phi_max = {:.0} deg", phi.to_degrees());
    set.drawings.push((
        "fig07".into(),
        Drawing::Lines {
            title,
            x_label: "L_b / L_c".into(),
            y_label: "lift-off angle θ (deg)".into(),
            series: series.to_vec(),
        },
    ));
    let csv = fig07_csv(&col, phi);
    set.files.push(("fig07.csv".into(), csv));
    entries.push(Entry {
        name: "fig07".into(),
        title: "Fig 7: lift-off angle at r = 0".into(),
        says: format!(
            "As L_b/L_c grows, lift-off ringing right comes earlier in the swing (at a higher angle) and \
             ringing wrong later; dashed where the r = 0 bell cannot keep ringing in that style (Fig 12). \
             The {} simulated points lie on the curves of (15) and (16) to within {worst:.1e} deg.",
            sim_r.len() + sim_w.len()
        ),
        data: vec!["fig07.csv".into()],
    });
    Ok(())
}

/// Fig 7's curves: each formula solid where its style is sustained and
/// dashed where not, and the simulated points.
fn fig07_series(
    col: &Chart,
    formula: &[(f64, LiftoffAngles)],
    sim_r: &[(f64, f64)],
    sim_w: &[(f64, f64)],
) -> [Series; 6] {
    let blue = RGBColor(31, 90, 180);
    let orange = RGBColor(220, 100, 20);
    // The paper draws each formula dashed where the r = 0 bell cannot keep
    // ringing in that style (Fig 12): here, where the nearest point of the
    // simulated column does not sustain it.
    let sustains = |style: Style, y: f64| {
        col.cells
            .iter()
            .filter(|c| c.style == style)
            .min_by(|a, b| (a.y - y).abs().total_cmp(&(b.y - y).abs()))
            .is_some_and(|c| c.result.as_ref().is_ok_and(|s| s.sustained))
    };
    // One formula curve as two series, solid where `style` is sustained and
    // dashed where not, each a gap (NaN) where the other is drawn; the two
    // share the point where they meet, so the curve is unbroken.
    let split = |style: Style, angle: fn(&LiftoffAngles) -> f64| -> [Vec<(f64, f64)>; 2] {
        let on: Vec<bool> = formula.iter().map(|(y, _)| sustains(style, *y)).collect();
        let mut parts = [vec![], vec![]];
        for (k, (y, a)) in formula.iter().enumerate() {
            let p = (*y, angle(a).to_degrees());
            let near =
                |want: bool| on[k] == want || on.get(k.wrapping_sub(1)) == Some(&want) || on.get(k + 1) == Some(&want);
            parts[0].push(if near(true) { p } else { (p.0, f64::NAN) });
            parts[1].push(if near(false) { p } else { (p.0, f64::NAN) });
        }
        parts
    };
    let [right_on, right_off] = split(Style::Right, |a| a.right);
    let [wrong_on, wrong_off] = split(Style::Wrong, |a| a.wrong);
    let line = |label: &str, points: Vec<(f64, f64)>, dashed: bool, colour: RGBColor| Series {
        label: label.into(),
        points,
        markers: false,
        dashed,
        colour,
    };
    [
        line("ringing right, formula (15)", right_on, false, blue),
        line("ringing right, not sustained", right_off, true, blue),
        line("ringing wrong, formula (16)", wrong_on, false, orange),
        line("ringing wrong, not sustained", wrong_off, true, orange),
        Series {
            label: "ringing right, simulated".into(),
            points: sim_r.to_vec(),
            markers: true,
            dashed: false,
            colour: blue,
        },
        Series {
            label: "ringing wrong, simulated".into(),
            points: sim_w.to_vec(),
            markers: true,
            dashed: false,
            colour: orange,
        },
    ]
}

/// Fig 7's data: the formulae and the simulated column, a row per L_b/L_c.
fn fig07_csv(col: &Chart, phi: f64) -> String {
    let mut csv =
        String::from("lb_over_lc,formula_right_deg,formula_wrong_deg,simulated_right_deg,simulated_wrong_deg\n");
    for c in col.cells.iter().filter(|c| c.style == Style::Right) {
        let a = liftoff_angles(c.y, phi).expect("valid");
        let s = |st: Style| {
            col.cells
                .iter()
                .find(|d| d.style == st && d.y == c.y)
                .and_then(|d| d.result.as_ref().ok()?.liftoff_theta)
                .map(|t| format!("{:.6}", t.to_degrees()))
                .unwrap_or_default()
        };
        let _ = writeln!(
            csv,
            "{:.6},{:.6},{:.6},{},{}",
            c.y,
            a.right.to_degrees(),
            a.wrong.to_degrees(),
            s(Style::Right),
            s(Style::Wrong)
        );
    }
    csv
}

/// Fig 9: time histories.
fn fig09(base: ChartSpec, set: &mut FigureSet, entries: &mut Vec<Entry>) -> Result<(), AppError> {
    for (name, what, bell, style) in fig9_bells() {
        // The charts' settings, solver options included (--rtol, --integrator).
        let cfg = base.config;
        let mut rec = TraceRecorder::new(5e-4);
        let r = ring(&bell, &cfg, style, Protocol::Restart, 2, &mut rec)?;
        let s = &r.strokes[0];
        let title = format!(
            "Fig {}: {what} (r/L_c = {:.3}, L_b/L_c = {:.3})",
            &name[3..],
            bell.r_over_lc(),
            bell.lb_over_lc()
        );
        let csv = csv_of(|buf| clapper_io::write_trace_csv(buf, &rec.samples))?;
        set.files.push((format!("{name}.csv"), csv));
        entries.push(Entry {
            name: name.into(),
            title: title.clone(),
            says: match s.first_strike() {
                Some(fs) => format!(
                    "{}: lift-off at {:.1} deg, first strike at {:.1} deg with phi' = {:.2} rad/s, {} impacts, \
                     style {}.",
                    what,
                    s.liftoff_angle().map_or(f64::NAN, f64::to_degrees),
                    fs.theta.to_degrees(),
                    fs.phi_dot_before,
                    s.impacts.len(),
                    if r.sustained() { "sustained" } else { "not sustained" }
                ),
                None => format!("{what}: no strike."),
            },
            data: vec![format!("{name}.csv")],
        });
        set.drawings.push((
            name.into(),
            Drawing::Stroke {
                title,
                samples: rec.samples,
                phi_max_deg: bell.phi_max.to_degrees(),
                stroke_starts: r.strokes.iter().skip(1).map(|s| s.start.t).collect(),
            },
        ));
    }
    Ok(())
}

/// Figs 10, 11, 12, 14: one sweep of both styles at the base settings.
fn figs10_to_14(
    base: ChartSpec,
    run_chart: &mut ChartRunner<'_>,
    set: &mut FigureSet,
    entries: &mut Vec<Entry>,
) -> Result<FullUp, AppError> {
    let (chart, secs) = run_chart(&base, "figs 10-12, 14")?;
    set.files.push(("chart-base.csv".into(), chart_csv(&chart)?));
    let (nr, yr) = region_stats(&chart, Style::Right);
    let (nw, yw) = region_stats(&chart, Style::Wrong);
    let words = settings_words(&base);
    for (name, q, title, says) in [
        (
            "fig10",
            Quantity::StrikeAngle,
            "Fig 10: bell angle at the first strike",
            format!(
                "Right is sustained at {nr} points (mean L_b/L_c {yr:.2}), wrong at {nw} (mean {yw:.2}): right \
                 in the lower part of the chart, wrong in the upper; near the curved left edge of the right \
                 region the first strike comes late, towards -180 deg. The lab bell's cell rings right: {}, \
                 wrong: {}.",
                lab_cell(&chart, Style::Right),
                lab_cell(&chart, Style::Wrong)
            ),
        ),
        (
            "fig11",
            Quantity::StrikeVelocity,
            "Fig 11: clapper rate at the first strike",
            "Negative ringing right, positive ringing wrong; its size stands for loudness, and it grows \
             towards the lower right of the right region (the 9(c) bell strikes much harder than the lab bell)."
                .to_string(),
        ),
        (
            "fig12",
            Quantity::Liftoff,
            "Fig 12: bell angle at lift-off",
            "Late lift-off ringing right at the bottom of the chart and early at the top, the reverse ringing \
             wrong; early lift-off marks a style that reverses itself."
                .to_string(),
        ),
        (
            "fig14",
            Quantity::DoubleStrike,
            "Fig 14: double strike index D, R = 0.2",
            "With R = 0.2 almost every ringable bell has D well above 1, most above 10: an audible double strike."
                .to_string(),
        ),
    ] {
        let fig = quantity::figure(format!("{title} ({words})"), q, chart_panels(&chart, q), markers());
        set.drawings.push((name.into(), Drawing::Chart(fig)));
        entries.push(Entry {
            name: name.into(),
            title: title.into(),
            says,
            data: vec!["chart-base.csv".into()],
        });
    }
    Ok(FullUp { nr, yr, nw, secs })
}

/// Fig 15: D ringing right for R = 0.1 and 0.05.
fn fig15(
    base: ChartSpec,
    run_chart: &mut ChartRunner<'_>,
    set: &mut FigureSet,
    entries: &mut Vec<Entry>,
) -> Result<(), AppError> {
    let mut panels = vec![];
    let mut data = vec![];
    let mut d_counts = vec![];
    for (r, title) in [(0.1, "(a) R = 0.1"), (0.05, "(b) R = 0.05")] {
        let spec = ChartSpec {
            config: SimConfig {
                restitution: r,
                ..base.config
            },
            styles: Styles::Right,
            ..base
        };
        let (c, _) = run_chart(&spec, &format!("fig 15, R = {r}"))?;
        let file = format!("chart-right-R{r}.csv");
        set.files.push((file.clone(), chart_csv(&c)?));
        data.push(file);
        let p = quantity::panel(&c, Style::Right, Quantity::DoubleStrike, title)
            .ok_or_else(|| AppError::Request("the chart has no right panel".into()))?;
        let above = p.values.iter().flatten().filter(|d| **d > 1.0).count();
        let above10 = p.values.iter().flatten().filter(|d| **d > 10.0).count();
        let sustained = p.region.iter().filter(|r| **r).count();
        d_counts.push((r, above, above10, sustained));
        panels.push(p);
    }
    let fig = quantity::figure(
        format!(
            "Fig 15: double strike index D ringing right (theta0 = {:.0} deg, {} x {})",
            base.config.theta0.to_degrees(),
            base.nx,
            base.ny
        ),
        Quantity::DoubleStrike,
        panels,
        markers(),
    );
    set.drawings.push(("fig15".into(), Drawing::Chart(fig)));
    entries.push(Entry {
        name: "fig15".into(),
        title: "Fig 15: double strike index ringing right, R = 0.1 and 0.05".into(),
        says: d_counts
            .iter()
            .map(|(r, above, above10, n)| {
                format!("R = {r}: D > 1 at {above} and D > 10 at {above10} of {n} right-ringing points")
            })
            .collect::<Vec<_>>()
            .join("; ")
            + ". The double-strike region shrinks as R falls and what stays is near the lab bell, as the paper                says; but the paper reports D > 1 in only a small region at R = 0.05, where here D stays above 1                over much of the right region (in the 1 to 10 band).",
        data,
    });
    Ok(())
}

/// Fig 16: half-up (theta0 = 90 deg), beside the fully-up chart.
fn fig16(
    base: ChartSpec,
    run_chart: &mut ChartRunner<'_>,
    full: &FullUp,
    set: &mut FigureSet,
    entries: &mut Vec<Entry>,
) -> Result<(), AppError> {
    let FullUp { nr, yr, nw, .. } = *full;
    let half = ChartSpec {
        config: SimConfig {
            theta0: 90f64.to_radians(),
            ..base.config
        },
        ..base
    };
    let (hc, _) = run_chart(&half, "fig 16 (theta0 = 90)")?;
    set.files.push(("chart-theta0-90.csv".into(), chart_csv(&hc)?));
    let (hr, hyr) = region_stats(&hc, Style::Right);
    let (hw, _) = region_stats(&hc, Style::Wrong);
    let fig = quantity::figure(
        format!(
            "Fig 16: bell angle at the first strike, half up ({})",
            settings_words(&half)
        ),
        Quantity::StrikeAngle,
        chart_panels(&hc, Quantity::StrikeAngle),
        markers(),
    );
    set.drawings.push(("fig16".into(), Drawing::Chart(fig)));
    entries.push(Entry {
        name: "fig16".into(),
        title: "Fig 16: first strike angle when rung from 90 deg".into(),
        says: format!(
            "Half up, right is sustained at {hr} points (mean L_b/L_c {hyr:.2}, against {nr} and {yr:.2} fully \
             up) and wrong at {hw} (against {nw}): the right region's upper boundary moves down, the wrong \
             region spreads. The lab bell's cell rings right: {}.",
            lab_cell(&hc, Style::Right)
        ),
        data: vec!["chart-theta0-90.csv".into()],
    });
    Ok(())
}

fn chart_csv(chart: &Chart) -> Result<String, AppError> {
    csv_of(|buf| clapper_io::write_chart_csv(buf, chart))
}

/// Data file names as links, each written by `link`, comma-separated.
fn links(data: &[String], link: impl Fn(&str) -> String) -> String {
    data.iter().map(|d| link(d)).collect::<Vec<_>>().join(", ")
}

/// The index as Markdown and HTML.
fn index(entries: &[Entry], words: &str, secs: f64) -> (String, String) {
    let mut md = format!(
        "# Figures of Woodhouse et al. (2012), recomputed by clapper\n\nCharts: {words}. The base chart took \
         {secs:.2} s. White marks: the Fig 9 bells. Each figure is here as SVG and PNG; its data is the CSV \
         named below it.\n\n"
    );
    let mut html = String::from(
        "<!doctype html><html><head><meta charset=\"utf-8\"><title>clapper: figures</title>\
         <style>body{font-family:sans-serif;max-width:1400px;margin:auto}img{max-width:100%;border:1px solid #ccc}</style>\
         </head><body><h1>Figures of Woodhouse et al. (2012), recomputed by clapper</h1>",
    );
    let _ = write!(html, "<p>Charts: {words}. Base chart: {secs:.2} s.</p>");
    for e in entries {
        let data = links(&e.data, |d| format!("[{d}]({d})"));
        let _ = write!(
            md,
            "## {}\n\n{}\n\n![{}]({}.png)\n\nData: {data}; vector: [{}.svg]({}.svg)\n\n",
            e.title, e.says, e.title, e.name, e.name, e.name
        );
        let hdata = links(&e.data, |d| format!("<a href=\"{d}\">{d}</a>"));
        let _ = write!(
            html,
            "<h2>{}</h2><p>{}</p><img src=\"{}.png\" alt=\"{}\"><p>Data: {hdata}; vector: <a href=\"{}.svg\">{}.svg</a></p>",
            e.title, e.says, e.name, e.title, e.name, e.name
        );
    }
    html.push_str("</body></html>\n");
    (md, html)
}

#[cfg(test)]
mod tests {
    use super::*;
    use clapper_core::chart::sweep;

    #[test]
    fn fig7_dashes_the_styles_that_cannot_be_kept_and_its_caption_reads_the_curves_rightly() {
        let base = crate::chart::ChartRequest {
            grid: [4, 12],
            ..Default::default()
        }
        .spec()
        .unwrap();
        let set = figures(&base, &mut |spec, _| Ok((sweep(spec, &|_| {})?, 0.0))).unwrap();
        let Some((_, Drawing::Lines { series, .. })) = set.drawings.iter().find(|(n, _)| n == "fig07") else {
            panic!("no fig07")
        };
        let by = |label: &str| series.iter().find(|s| s.label == label).unwrap();
        let (solid, dashed) = (by("ringing right, formula (15)"), by("ringing right, not sustained"));
        assert!(dashed.dashed && !solid.dashed);
        // At r = 0 a bell of L_b/L_c 2.4 cannot keep ringing right (Fig 12),
        // one of 1.2 can: dashed there, solid here.
        let at = |s: &Series, y: f64| {
            s.points
                .iter()
                .min_by(|a, b| (a.0 - y).abs().total_cmp(&(b.0 - y).abs()))
                .unwrap()
                .1
        };
        assert!(at(dashed, 2.4).is_finite() && at(solid, 2.4).is_nan());
        assert!(at(solid, 1.2).is_finite() && at(dashed, 1.2).is_nan());
        // As L_b/L_c grows, ringing right lifts off at a higher angle: sooner
        // after the balance, not later.
        assert!(at(solid, 1.5) > at(solid, 1.0));
        let md = &set.files.iter().find(|(n, _)| n == "index.md").unwrap().1;
        assert!(md.contains("lift-off ringing right comes earlier"), "{md}");
    }
}
