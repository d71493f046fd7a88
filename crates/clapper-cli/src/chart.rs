//! `clapper chart`: sweep the chart plane, write CSV, draw a heat map.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{bail, Context, Result};
use clap::{Args, ValueEnum};
use clapper_core::chart::{sweep, Chart, ChartSpec, Styles};
use clapper_core::prelude::*;
use clapper_plot::chart::Marker;
use clapper_plot::quantity::{self, Quantity};
use indicatif::{ProgressBar, ProgressStyle};

use clapper_app::chart::{ChartRequest, StylesName, DEFAULT_PHI_MAX_DEG};
use clapper_app::simulate::{contact_words, ContactName, DEFAULT_RESTITUTION, DEFAULT_THETA0_DEG};

use crate::simulate::parse_point;

fn parse_grid(s: &str) -> std::result::Result<(usize, usize), String> {
    let num = |v: &str| {
        v.trim()
            .parse::<usize>()
            .map_err(|_| format!("'{s}' is not a grid: give N or NXxNY, e.g. 20 or 200x120"))
    };
    match s.split_once(['x', 'X']) {
        Some((a, b)) => Ok((num(a)?, num(b)?)),
        None => {
            let n = num(s)?;
            Ok((n, n))
        }
    }
}

#[derive(Clone, Copy, Debug, ValueEnum, PartialEq, Eq)]
pub enum QuantityArg {
    /// Where each style is sustained.
    Style,
    /// Bell angle at the first strike (deg), Fig 10.
    StrikeAngle,
    /// Clapper rate just before the first strike (rad/s), Fig 11.
    StrikeVelocity,
    /// Bell angle at lift-off (deg), Fig 12.
    Liftoff,
    /// Double strike index D, Figs 14 and 15.
    DoubleStrike,
}

impl QuantityArg {
    fn quantity(self) -> Quantity {
        match self {
            QuantityArg::Style => Quantity::Style,
            QuantityArg::StrikeAngle => Quantity::StrikeAngle,
            QuantityArg::StrikeVelocity => Quantity::StrikeVelocity,
            QuantityArg::Liftoff => Quantity::Liftoff,
            QuantityArg::DoubleStrike => Quantity::DoubleStrike,
        }
    }
}

/// Everything that shapes a chart, shared by `chart` and `figures`.
#[derive(Args, Debug, Clone)]
pub struct SweepArgs {
    /// Grid: N (N x N) or NXxNY (points along r/L_c x along L_b/L_c).
    #[arg(long, value_name = "N|NXxNY", value_parser = parse_grid, default_value = "20")]
    pub grid: (usize, usize),
    /// Range of r/L_c swept.
    #[arg(long, value_name = "A,B", value_parser = parse_point, default_value = "-0.3,0.7", allow_hyphen_values = true)]
    pub r_range: (f64, f64),
    /// Range of L_b/L_c swept.
    #[arg(long, value_name = "A,B", value_parser = parse_point, default_value = "0.5,2.5", allow_hyphen_values = true)]
    pub lb_range: (f64, f64),
    /// Starting angle of the bell (deg).
    #[arg(long, value_name = "DEG", default_value_t = DEFAULT_THETA0_DEG, allow_hyphen_values = true)]
    pub theta0: f64,
    /// Coefficient of restitution R.
    #[arg(long, value_name = "R", default_value_t = DEFAULT_RESTITUTION, allow_hyphen_values = true)]
    pub restitution: f64,
    /// Contact angle phi_max of every chart bell (deg).
    #[arg(long, value_name = "DEG", default_value_t = DEFAULT_PHI_MAX_DEG, allow_hyphen_values = true)]
    pub phi_max: f64,
    /// Contact model.
    #[arg(long, value_enum)]
    pub contact: Option<ContactName>,
    /// Penalty stiffness k (N m/rad); implies --contact penalty.
    #[arg(long, value_name = "K", allow_hyphen_values = true)]
    pub stiffness: Option<f64>,
    /// Worker threads (default: one per core). The output does not depend on it.
    #[arg(long, value_name = "N")]
    pub threads: Option<usize>,
}

impl SweepArgs {
    /// The options as the request the web API also takes.
    pub fn request(&self, styles: StylesName) -> ChartRequest {
        ChartRequest {
            grid: [self.grid.0, self.grid.1],
            r_range: [self.r_range.0, self.r_range.1],
            lb_range: [self.lb_range.0, self.lb_range.1],
            theta0: self.theta0,
            restitution: self.restitution,
            phi_max: self.phi_max,
            contact: self.contact,
            stiffness: self.stiffness,
            style: styles,
        }
    }

    /// The chart spec these options describe, for `styles`.
    pub fn spec(&self, styles: Styles) -> Result<ChartSpec> {
        let name = match styles {
            Styles::Right => StylesName::Right,
            Styles::Wrong => StylesName::Wrong,
            Styles::Both => StylesName::Both,
        };
        Ok(self.request(name).spec()?)
    }

    /// A thread pool of the requested size.
    pub fn pool(&self) -> Result<rayon::ThreadPool> {
        let mut b = rayon::ThreadPoolBuilder::new();
        if let Some(n) = self.threads {
            if n == 0 || n > 1024 {
                bail!("--threads {n} is out of range: 1 to 1024");
            }
            b = b.num_threads(n);
        }
        Ok(b.build()?)
    }
}

/// Run a sweep with a progress bar on the terminal (none when stderr is
/// not one). Returns the chart and the wall time (s).
pub fn run_sweep(spec: &ChartSpec, pool: &rayon::ThreadPool, what: &str) -> Result<(Chart, f64)> {
    let total = (spec.nx * spec.ny * spec.styles.list().len()) as u64;
    let bar = ProgressBar::new(total);
    bar.set_style(
        ProgressStyle::with_template("{msg:>24} [{bar:40}] {pos}/{len} strokes, {per_sec}, eta {eta}")
            .expect("valid template")
            .progress_chars("=> "),
    );
    bar.set_message(what.to_string());
    let start = Instant::now();
    let chart = pool.install(|| sweep(spec, &|done| bar.set_position(done)))?;
    bar.finish_and_clear();
    Ok((chart, start.elapsed().as_secs_f64()))
}

/// Short words for a chart's settings, for titles.
pub fn settings_words(spec: &ChartSpec) -> String {
    format!(
        "theta0 = {:.0} deg, R = {}, phi_max = {:.0} deg, {} contact, {} x {}",
        spec.config.theta0.to_degrees(),
        spec.config.restitution,
        spec.construction.phi_max.to_degrees(),
        contact_words(&spec.config),
        spec.nx,
        spec.ny
    )
}

#[derive(Args, Debug)]
pub struct ChartArgs {
    #[command(flatten)]
    pub sweep: SweepArgs,
    /// What the chart shows.
    #[arg(long, value_enum, default_value = "style")]
    pub quantity: QuantityArg,
    /// Which styles to compute and show (style maps need both).
    #[arg(long, value_enum, default_value = "both")]
    pub style: StylesName,
    /// Write every point and style as long-form CSV.
    #[arg(long, value_name = "FILE.csv")]
    pub csv: Option<PathBuf>,
    /// Draw the chart (.svg or .png).
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// Mark these bells on the chart (a bell file, or [[bell]] tables).
    #[arg(long, value_name = "FILE")]
    pub bells: Option<PathBuf>,
}

/// Write a chart CSV atomically.
pub fn write_csv(path: &Path, chart: &Chart) -> Result<()> {
    crate::files::write_atomically(path, |tmp| {
        let f = std::fs::File::create(tmp).with_context(|| format!("cannot create {}", path.display()))?;
        clapper_io::write_chart_csv(std::io::BufWriter::new(f), chart)
            .with_context(|| format!("cannot write {}", path.display()))
    })
}

/// Draw a figure atomically.
pub fn draw(path: &Path, fig: &clapper_plot::ChartFigure) -> Result<()> {
    crate::files::write_atomically(path, |tmp| Ok(clapper_plot::chart_figure(tmp, fig)?))
}

pub fn run(args: ChartArgs) -> Result<()> {
    let quantity = args.quantity.quantity();
    let styles: Styles = args.style.into();
    if quantity == Quantity::Style && styles != Styles::Both {
        bail!("--quantity style needs --style both (it shows where each style is sustained)");
    }
    if let Some(p) = &args.out {
        clapper_plot::format_of(p)?;
    }
    let markers: Vec<Marker> = match &args.bells {
        Some(p) => clapper_io::load_bells(p)?
            .into_iter()
            .map(|b| Marker {
                x: b.bell.r_over_lc(),
                y: b.bell.lb_over_lc(),
                label: b.name,
            })
            .collect(),
        None => vec![],
    };
    let spec = args.sweep.spec(styles)?;
    let pool = args.sweep.pool()?;
    let (chart, secs) = run_sweep(&spec, &pool, "chart")?;
    let strokes = chart.cells.len();

    if let Some(path) = &args.csv {
        write_csv(path, &chart)?;
    }
    if let Some(path) = &args.out {
        let panels = if quantity == Quantity::Style {
            vec![quantity::style_panel(&chart, "").context("chart lacks a style")?]
        } else {
            styles
                .list()
                .iter()
                .filter_map(|s| quantity::panel(&chart, *s, quantity, ""))
                .collect()
        };
        let title = format!("Clapping chart: {} ({})", quantity.label(), settings_words(&spec));
        draw(path, &quantity::figure(title, quantity, panels, markers.clone()))?;
    }

    println!("clapping chart, {}", settings_words(&spec));
    println!(
        "  r/L_c {} to {}, L_b/L_c {} to {}",
        spec.domain.x.0, spec.domain.x.1, spec.domain.y.0, spec.domain.y.1
    );
    println!(
        "  {strokes} strokes in {secs:.2} s on {} threads ({:.0} strokes/s)",
        pool.current_num_threads(),
        strokes as f64 / secs.max(1e-9)
    );
    for style in styles.list() {
        let n = (0..spec.ny)
            .flat_map(|j| (0..spec.nx).map(move |i| (i, j)))
            .filter(|&(i, j)| chart.cell(i, j, *style).and_then(|c| c.sustained()).is_some())
            .count();
        println!(
            "  sustains ringing {}: {n} of {} points",
            clapper_io::report::style_name(*style),
            spec.nx * spec.ny
        );
    }
    if chart.errors() > 0 {
        eprintln!(
            "warning: {} strokes failed to simulate (left empty in the CSV)",
            chart.errors()
        );
    }
    if styles == Styles::Both && spec.nx <= 60 {
        println!("  map (R right only, W wrong only, B both, . neither; L_b/L_c up, r/L_c across):");
        let ys = spec.ys();
        for j in (0..spec.ny).rev() {
            let row: String = (0..spec.nx)
                .map(|i| {
                    let r = chart.cell(i, j, Style::Right).and_then(|c| c.sustained()).is_some();
                    let w = chart.cell(i, j, Style::Wrong).and_then(|c| c.sustained()).is_some();
                    match (r, w) {
                        (true, true) => 'B',
                        (true, false) => 'R',
                        (false, true) => 'W',
                        _ => '.',
                    }
                })
                .collect();
            println!("  {:6.3} {row}", ys[j]);
        }
    }
    for m in &markers {
        println!("  bell {}: r/L_c = {:.3}, L_b/L_c = {:.3}", m.label, m.x, m.y);
    }
    Ok(())
}
