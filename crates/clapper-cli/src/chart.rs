//! `clapper chart`: sweep the chart plane, write CSV, draw a heat map.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{bail, Context, Result};
use clap::{Args, ValueEnum};
use clapper_core::chart::{sweep_cells_counting, Chart, ChartSpec, Styles};
use clapper_core::prelude::*;
use clapper_plot::chart::Marker;
use clapper_plot::quantity::{self, Quantity};
use std::sync::atomic::AtomicU64;

use std::sync::LazyLock;

use clapper_app::chart::{
    settings_words, ChartRequest, DEFAULT_GRID, DEFAULT_LB_RANGE, DEFAULT_PHI_MAX_DEG, DEFAULT_R_RANGE,
};
use clapper_app::simulate::{DEFAULT_RESTITUTION, DEFAULT_THETA0_DEG};
use clapper_app::sweep::SweepPlan;

use crate::simulate::{parse_point, SolverArgs};
use clapper_app::sweep::{join_shards, Shard, SweepMeta};

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
    /// Odd-struckness (ms), handstroke minus backstroke, with a pivot
    /// offset or unequal contact angles set.
    OddStruck,
    /// Whether the bell goes up right or wrong, rung up from rest (each
    /// point a whole ring-up), with the CCCBR rule of thumb beside it.
    GoesUp,
}

impl QuantityArg {
    fn quantity(self) -> Quantity {
        match self {
            QuantityArg::Style => Quantity::Style,
            QuantityArg::StrikeAngle => Quantity::StrikeAngle,
            QuantityArg::StrikeVelocity => Quantity::StrikeVelocity,
            QuantityArg::Liftoff => Quantity::Liftoff,
            QuantityArg::DoubleStrike => Quantity::DoubleStrike,
            QuantityArg::OddStruck => Quantity::OddStruck,
            // Not a quantity of one stroke: main hands it to goes_up.
            QuantityArg::GoesUp => Quantity::Style,
        }
    }
}

/// The chart's defaults (clapper-core's) as option text, "A,B" or "N".
static R_RANGE_TEXT: LazyLock<String> = LazyLock::new(|| format!("{},{}", DEFAULT_R_RANGE[0], DEFAULT_R_RANGE[1]));
static LB_RANGE_TEXT: LazyLock<String> = LazyLock::new(|| format!("{},{}", DEFAULT_LB_RANGE[0], DEFAULT_LB_RANGE[1]));
static GRID_TEXT: LazyLock<String> = LazyLock::new(|| format!("{}x{}", DEFAULT_GRID[0], DEFAULT_GRID[1]));

/// How far the chart's axes reach: r/L_c within ± this, L_b/L_c up to
/// it. Real bells lie within about -0.5..1 and 0.5..3; beyond ten times
/// that a sweep is of no bell (and 1e300 was drawn as a 301-digit label).
const AXIS_REACH: f64 = 10.0;

/// `--r-range A,B`: two numbers within ±[`AXIS_REACH`], the low end
/// first; refused in words of the option ("a range of r/L_c ..."), which
/// main puts after the option and its value as written.
fn parse_r_range(s: &str) -> std::result::Result<(f64, f64), String> {
    let within = |v: f64| v.abs() <= AXIS_REACH;
    parse_point(s)
        .ok()
        .filter(|&(a, b)| within(a) && within(b) && a <= b)
        .ok_or_else(|| {
            format!(
                "a range of r/L_c: two numbers from -{AXIS_REACH} to {AXIS_REACH}, the low end first (e.g. {})",
                R_RANGE_TEXT.as_str()
            )
        })
}

/// `--lb-range A,B`: two numbers above 0 and up to [`AXIS_REACH`], the
/// low end first, as [`parse_r_range`].
fn parse_lb_range(s: &str) -> std::result::Result<(f64, f64), String> {
    let within = |v: f64| v > 0.0 && v <= AXIS_REACH;
    parse_point(s)
        .ok()
        .filter(|&(a, b)| within(a) && within(b) && a <= b)
        .ok_or_else(|| {
            format!(
                "a range of L_b/L_c: two numbers above 0 and up to {AXIS_REACH}, the low end first (e.g. {})",
                LB_RANGE_TEXT.as_str()
            )
        })
}

/// Everything that shapes a chart, shared by `chart` and `figures`.
#[derive(Args, Debug, Clone)]
pub struct SweepArgs {
    /// Grid: N (N x N) or NXxNY (points along r/L_c x along L_b/L_c).
    #[arg(long, value_name = "N|NXxNY", value_parser = parse_grid, default_value = GRID_TEXT.as_str())]
    pub grid: (usize, usize),
    /// Range of r/L_c swept.
    #[arg(long, value_name = "A,B", value_parser = parse_r_range, default_value = R_RANGE_TEXT.as_str(), allow_hyphen_values = true)]
    pub r_range: (f64, f64),
    /// Range of L_b/L_c swept.
    #[arg(long, value_name = "A,B", value_parser = parse_lb_range, default_value = LB_RANGE_TEXT.as_str(), allow_hyphen_values = true)]
    pub lb_range: (f64, f64),
    /// Starting angle of the bell (deg). `chart` takes a list (90,120,171)
    /// to sweep it as an extra axis.
    #[arg(long, value_name = "DEG[,DEG..]", value_delimiter = ',', default_values_t = [DEFAULT_THETA0_DEG], allow_hyphen_values = true)]
    pub theta0: Vec<f64>,
    /// Coefficient of restitution R (a list sweeps it).
    #[arg(long, value_name = "R[,R..]", value_delimiter = ',', default_values_t = [DEFAULT_RESTITUTION], allow_hyphen_values = true)]
    pub restitution: Vec<f64>,
    /// Contact angle phi_max of every chart bell (deg; a list sweeps it).
    #[arg(long, value_name = "DEG[,DEG..]", value_delimiter = ',', default_values_t = [DEFAULT_PHI_MAX_DEG], allow_hyphen_values = true)]
    pub phi_max: Vec<f64>,
    #[command(flatten)]
    pub solver: SolverArgs,
    #[command(flatten)]
    pub hanging: crate::simulate::HangingArgs,
    /// Worker threads (default: one per core). The output does not depend on it.
    #[arg(long, value_name = "N")]
    pub threads: Option<usize>,
}

impl SweepArgs {
    /// The options as the request the web API also takes (the first value
    /// of each extra axis).
    pub fn request(&self, styles: Styles) -> ChartRequest {
        let mut req = ChartRequest {
            grid: [self.grid.0, self.grid.1],
            r_range: [self.r_range.0, self.r_range.1],
            lb_range: [self.lb_range.0, self.lb_range.1],
            theta0: self.theta0[0],
            restitution: Some(self.restitution[0]),
            restitution_later: self.solver.restitution_later,
            strike_amplitude: self.solver.strike_amplitude,
            phi_max: self.phi_max[0],
            contact: self.solver.contact,
            stiffness: self.solver.stiffness,
            style: styles,
            rtol: self.solver.rtol,
            integrator: self.solver.integrator,
            ..ChartRequest::default()
        };
        crate::simulate::set_hanging!(req, self.hanging);
        req
    }

    /// The chart spec these options describe, for `styles` (one value per
    /// extra axis).
    pub fn spec(&self, styles: Styles) -> Result<ChartSpec> {
        if self.theta0.len() > 1 || self.restitution.len() > 1 || self.phi_max.len() > 1 {
            bail!("give one value each of --theta0, --restitution and --phi-max here (lists are for `clapper chart`)");
        }
        Ok(self.request(styles).spec()?)
    }

    /// The sweep these options describe: a chart per combination of the
    /// extra axes.
    pub fn plan(&self, styles: Styles) -> Result<SweepPlan> {
        Ok(SweepPlan::new(
            &self.request(styles),
            &self.theta0,
            &self.restitution,
            &self.phi_max,
        )?)
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
    run_sweep_counting(spec, pool, what).map(|(chart, secs, _)| (chart, secs))
}

/// [`run_sweep`], with the strokes it simulated (a bell off the ideal
/// rings its backstroke too).
fn run_sweep_counting(spec: &ChartSpec, pool: &rayon::ThreadPool, what: &str) -> Result<(Chart, f64, u64)> {
    let bar = crate::progress::bar(spec.cell_count() as u64, what);
    let start = Instant::now();
    let rung = AtomicU64::new(0);
    let cells = pool.install(|| {
        sweep_cells_counting(
            spec,
            0..spec.cell_count(),
            &|done| bar.set_position(done),
            &|| false,
            &rung,
        )
    })?;
    bar.finish_and_clear();
    let chart = Chart {
        spec: *spec,
        cells: cells.unwrap_or_default(),
    };
    Ok((chart, start.elapsed().as_secs_f64(), rung.into_inner()))
}

#[derive(Args, Debug)]
pub struct ChartArgs {
    #[command(flatten)]
    pub sweep: SweepArgs,
    /// What the chart shows.
    #[arg(long, value_enum, default_value = "style")]
    pub quantity: QuantityArg,
    /// Which styles to compute and show (style maps need both).
    #[arg(long, value_parser = crate::simulate::choice::<Styles>(), default_value = "both")]
    pub style: Styles,
    /// Write every point and style as long-form CSV; `-` is standard
    /// output (the summary then goes to standard error).
    #[arg(long, value_name = "FILE.csv")]
    pub csv: Option<PathBuf>,
    /// Print the chart as JSON in place of the summary: the settings, the
    /// axes and every point and style with the values of --csv's columns.
    #[arg(long)]
    pub json: bool,
    /// Draw the chart (.svg or .png).
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// Mark these bells on the chart (a bell file, or `[[bell]]` tables).
    #[arg(long, value_name = "FILE")]
    pub bells: Option<PathBuf>,
    /// Compute only shard I of N (1-based) of the sweep, into --csv, for a
    /// batch scheduler; `clapper merge` joins the shards' CSVs.
    #[arg(long, value_name = "I/N", value_parser = parse_shard)]
    pub shard: Option<(usize, usize)>,
    /// Strokes per checkpoint of a run writing --csv: an interrupted run,
    /// started again with the same options, resumes from its last checkpoint.
    #[arg(long, value_name = "N", default_value_t = 20_000)]
    pub block: usize,
}

fn parse_shard(s: &str) -> std::result::Result<(usize, usize), String> {
    let bad = || format!("'{s}' is not a shard: give I/N with 1 <= I <= N, e.g. 3/16");
    let (i, n) = s.split_once('/').ok_or_else(bad)?;
    let (i, n): (usize, usize) = (
        i.trim().parse().map_err(|_| bad())?,
        n.trim().parse().map_err(|_| bad())?,
    );
    if i == 0 || i > n {
        return Err(bad());
    }
    Ok((i - 1, n))
}

impl ChartArgs {
    /// What a CSV of this run is part of.
    fn meta(&self, plan: &SweepPlan, shard: (usize, usize)) -> Result<SweepMeta> {
        let range = plan.shard(shard.0, shard.1)?;
        Ok(SweepMeta {
            format: clapper_app::sweep::FORMAT,
            request: self.sweep.request(self.style),
            theta0: self.sweep.theta0.clone(),
            restitution: self.sweep.restitution.clone(),
            phi_max: self.sweep.phi_max.clone(),
            key: plan.key(),
            total: plan.total(),
            shard: [shard.0, shard.1],
            range: [range.start, range.end],
        })
    }
}

/// Draw a figure atomically.
pub fn draw(path: &Path, fig: &clapper_plot::ChartFigure) -> Result<()> {
    crate::files::write_atomically(path, |tmp| Ok(clapper_plot::chart_figure(tmp, fig)?))
}

/// `clapper chart` for the quantities of one stroke (main hands
/// `--quantity goes-up` to [`crate::goes_up`]).
pub fn run(args: ChartArgs) -> Result<()> {
    crate::files::claim_stdout(&[("--csv", args.csv.as_deref())], args.json)?;
    let quantity = args.quantity.quantity();
    let styles = args.style;
    // The quantity matters for what is shown, not for a CSV alone.
    if (args.out.is_some() || args.csv.is_none()) && quantity == Quantity::Style && styles != Styles::Both {
        bail!("--quantity style needs --style both (it shows where each style is sustained)");
    }
    if let Some(p) = &args.out {
        clapper_plot::format_of(p)?;
    }
    if args.block == 0 {
        bail!("--block must be at least 1");
    }
    let plan = args.sweep.plan(styles)?;
    let pool = args.sweep.pool()?;
    let threads = pool.current_num_threads();
    if args.shard.is_some() || plan.charts.len() > 1 {
        return run_to_file(&args, &plan, &pool);
    }
    let markers = markers(args.bells.as_deref())?;
    let (chart, secs, strokes, rung) = one_chart(&args, &plan, &pool)?;
    if args.json {
        if let Some(path) = &args.out {
            draw_chart(quantity, &chart, &markers, path)?;
        }
        println!("{}", clapper_app::chart::chart_json(&chart));
        return Ok(());
    }
    report_chart(&args, quantity, styles, &chart, &markers)?;
    // A bell off the ideal rings its backstroke too where its handstroke
    // keeps the style: the strokes simulated, where they are more.
    let simulated = if rung > strokes as u64 {
        format!(", {rung} strokes simulated")
    } else {
        String::new()
    };
    crate::say!(
        "  {strokes} strokes in {secs:.4} s on {} ({:.0} strokes/s{simulated})",
        threads_words(threads),
        strokes as f64 / secs.max(1e-9)
    );
    Ok(())
}

/// A shard, or a sweep of several charts: computed into its --csv file
/// (resumable), nothing drawn.
fn run_to_file(args: &ChartArgs, plan: &SweepPlan, pool: &rayon::ThreadPool) -> Result<()> {
    let csv = args
        .csv
        .as_deref()
        .context("a shard, or a sweep over several theta0, R or phi_max, is written with --csv FILE")?;
    if crate::files::is_stdout(csv) || args.json {
        bail!(
            "a shard, or a sweep over several theta0, R or phi_max, is written to a file it can resume \
             (give --csv a file name, without --json); `clapper merge --csv -` prints the whole"
        );
    }
    if args.out.is_some() {
        bail!("--out draws one whole chart: draw a shard's after `clapper merge`, or sweep one theta0, R and phi_max");
    }
    let shard = args.shard.unwrap_or((0, 1));
    let meta = args.meta(plan, shard)?;
    let range = meta.range;
    let o = crate::sweep_file::run(
        crate::sweep_file::RunFile {
            csv,
            meta,
            block: args.block,
            keep: false,
        },
        plan,
        pool,
    )?;
    if let Some(from) = o.resumed_from {
        crate::say!("resumed at stroke {} of {}..{}", from, range[0], range[1]);
    }
    crate::say!(
        "{} chart(s) of {} strokes; {}strokes {}..{} of {}: {} computed in {:.2} s on {}, written to {}",
        plan.charts.len(),
        plan.per_chart(),
        args.shard
            .map_or(String::new(), |(i, n)| format!("shard {} of {n}, ", i + 1)),
        range[0],
        range[1],
        plan.total(),
        o.computed,
        o.seconds,
        threads_words(pool.current_num_threads()),
        csv.display()
    );
    if args.shard.is_some() {
        crate::say!("when every shard is done: clapper merge --csv ALL.csv SHARD.csv ...");
    }
    Ok(())
}

/// The bells of `--bells` as markers on the chart.
fn markers(bells: Option<&Path>) -> Result<Vec<Marker>> {
    Ok(match bells {
        Some(p) => clapper_io::load_bells(p)?
            .into_iter()
            .map(|b| Marker {
                x: b.bell.r_over_lc(),
                y: b.bell.lb_over_lc(),
                label: b.name,
            })
            .collect(),
        None => vec![],
    })
}

/// The one chart of `plan`, computed (into --csv, resuming a run stopped
/// part-way, when --csv names a file), with the seconds it took and the
/// strokes computed.
fn one_chart(args: &ChartArgs, plan: &SweepPlan, pool: &rayon::ThreadPool) -> Result<(Chart, f64, usize, u64)> {
    let spec = plan.charts[0].1;
    Ok(match args.csv.as_deref().filter(|p| !crate::files::is_stdout(p)) {
        Some(csv) => {
            let o = crate::sweep_file::run(
                crate::sweep_file::RunFile {
                    csv,
                    meta: args.meta(plan, (0, 1))?,
                    block: args.block,
                    keep: true,
                },
                plan,
                pool,
            )?;
            let n = o.computed;
            let chart = match o.resumed_from {
                None => Chart {
                    spec,
                    cells: o.cells.into_iter().map(|(_, c)| c).collect(),
                },
                Some(from) => {
                    crate::say!("resumed at stroke {from} of {}", plan.total());
                    read_chart(csv, spec)?
                }
            };
            (chart, o.seconds, n, o.rung)
        }
        None => {
            let (chart, secs, rung) = run_sweep_counting(&spec, pool, "chart")?;
            let n = chart.cells.len();
            if let Some(dash) = &args.csv {
                let mut text = vec![];
                clapper_io::write_chart_csv(&mut text, &chart)?;
                crate::files::write_bytes(dash, text)?;
            }
            (chart, secs, n, rung)
        }
    })
}

/// A chart read back from its CSV (values to the file's six decimals).
pub fn read_chart(csv: &Path, spec: ChartSpec) -> Result<Chart> {
    let text = crate::files::read_text(csv, "a chart CSV")?;
    chart_of_csv(&text, &csv.display().to_string(), spec)
}

/// A chart from the text of its CSV, `name` naming it in errors.
fn chart_of_csv(text: &str, name: &str, spec: ChartSpec) -> Result<Chart> {
    let cells: Vec<_> = clapper_io::read_chart_csv(text, name)?
        .into_iter()
        .map(|(_, c)| c)
        .collect();
    if cells.len() != spec.cell_count() {
        bail!(
            "{name} has {} rows; the chart has {} strokes",
            cells.len(),
            spec.cell_count()
        );
    }
    Ok(Chart { spec, cells })
}

/// The panels that show `quantity`: one map of styles, or one per style.
fn panels(chart: &Chart, quantity: Quantity) -> Result<Vec<clapper_plot::Panel>> {
    Ok(if quantity == Quantity::Style {
        vec![quantity::style_panel(chart, "").context("--quantity style needs both styles")?]
    } else {
        chart
            .spec
            .styles
            .list()
            .iter()
            .filter_map(|s| quantity::panel(chart, *s, quantity, ""))
            .collect()
    })
}

/// Draw one chart as `--quantity` asks.
fn draw_chart(quantity: Quantity, chart: &Chart, markers: &[Marker], path: &Path) -> Result<()> {
    let panels = panels(chart, quantity)?;
    let title = format!("Clapping chart: {} ({})", quantity.label(), settings_words(&chart.spec));
    draw(path, &quantity::figure(title, quantity, panels, markers.to_vec()))
}

/// Draw and summarise one chart.
fn report_chart(args: &ChartArgs, quantity: Quantity, styles: Styles, chart: &Chart, markers: &[Marker]) -> Result<()> {
    let spec = chart.spec;
    if let Some(path) = &args.out {
        draw_chart(quantity, chart, markers, path)?;
    }

    crate::say!("clapping chart, {}", settings_words(&spec));
    crate::say!(
        "  r/L_c {} to {}, L_b/L_c {} to {}",
        spec.domain.x.0,
        spec.domain.x.1,
        spec.domain.y.0,
        spec.domain.y.1
    );
    for style in styles.list() {
        let n = (0..spec.ny)
            .flat_map(|j| (0..spec.nx).map(move |i| (i, j)))
            .filter(|&(i, j)| chart.cell(i, j, *style).and_then(|c| c.sustained()).is_some())
            .count();
        crate::say!(
            "  sustains ringing {}: {n} of {} points",
            style.name(),
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
        crate::say!("  map (R right only, W wrong only, B both, . neither; L_b/L_c up, r/L_c across):");
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
            crate::say!("  {:6.3} {row}", ys[j]);
        }
    }
    for m in markers {
        crate::say!("  bell {}: r/L_c = {:.3}, L_b/L_c = {:.3}", m.label, m.x, m.y);
    }
    Ok(())
}

#[derive(Args, Debug)]
pub struct MergeArgs {
    /// The shards' CSV files (each with its .shard.json beside it), in any order.
    #[arg(required = true, value_name = "SHARD.csv")]
    pub shards: Vec<PathBuf>,
    /// The joined CSV: the same bytes as one run of the whole sweep; `-`
    /// is standard output.
    #[arg(long, value_name = "FILE.csv")]
    pub csv: PathBuf,
    /// Draw the joined chart (.svg or .png; a sweep of one chart).
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// What the drawing shows.
    #[arg(long, value_enum, default_value = "style")]
    pub quantity: QuantityArg,
    /// Keep each shard's .shard.json description. Without it they are
    /// removed once the joined CSV is written (the shards' CSVs are kept;
    /// merging them again needs the descriptions).
    #[arg(long)]
    pub keep_shard_json: bool,
}

/// `clapper merge`: join the shards of a sweep.
pub fn merge(args: MergeArgs) -> Result<()> {
    crate::files::claim_stdout(&[("--csv", Some(&args.csv))], false)?;
    if let Some(p) = &args.out {
        clapper_plot::format_of(p)?;
    }
    let mut metas = vec![];
    let mut texts = vec![];
    for csv in &args.shards {
        let meta_path = crate::sweep_file::shard_meta_path(csv);
        let text = std::fs::read_to_string(&meta_path).with_context(|| {
            format!(
                "cannot read {} (is {} a finished shard of `clapper chart --shard`? \
                 A merge removes the descriptions of the shards it joined, unless --keep-shard-json)",
                meta_path.display(),
                csv.display()
            )
        })?;
        let meta: SweepMeta = serde_json::from_str(&text)
            .with_context(|| format!("{} is not a shard description", meta_path.display()))?;
        metas.push(meta);
        texts.push(crate::files::read_text(csv, "a shard's CSV")?);
    }
    let parts = metas
        .into_iter()
        .zip(&texts)
        .zip(&args.shards)
        .map(|((meta, csv), path)| Shard {
            meta,
            csv,
            name: path.display().to_string(),
        })
        .collect();
    let (plan, joined) = join_shards(parts)?;
    let n = args.shards.len();
    crate::files::write_atomically(&args.csv, |tmp| {
        std::fs::write(tmp, joined.as_bytes()).with_context(|| format!("cannot create {}", args.csv.display()))
    })?;
    crate::say!(
        "merged {n} shards: {} strokes of {} chart(s) into {}",
        plan.total(),
        plan.charts.len(),
        args.csv.display()
    );
    if let Some(path) = &args.out {
        if plan.charts.len() > 1 {
            bail!("--out draws one chart; this sweep has {}", plan.charts.len());
        }
        let quantity = args.quantity.quantity();
        let chart = chart_of_csv(&joined, &args.csv.display().to_string(), plan.charts[0].1)?;
        let panels = panels(&chart, quantity)?;
        let title = format!("Clapping chart: {} ({})", quantity.label(), settings_words(&chart.spec));
        draw(path, &quantity::figure(title, quantity, panels, vec![]))?;
        crate::say!("drawn to {}", path.display());
    }
    // All written: the shards' descriptions are no longer needed (and
    // would be left lying about after every sharded run). Kept on any
    // failure above, so that the same merge can be run again.
    let mut removed = 0;
    if !args.keep_shard_json {
        for csv in &args.shards {
            let meta_path = crate::sweep_file::shard_meta_path(csv);
            match std::fs::remove_file(&meta_path) {
                Ok(()) => removed += 1,
                Err(e) => eprintln!("warning: could not remove {}: {e}", meta_path.display()),
            }
        }
    }
    if removed > 0 {
        crate::say!("removed the shards' {removed} .shard.json files (--keep-shard-json keeps them)");
    }
    Ok(())
}

/// "1 thread", "2 threads".
pub(crate) fn threads_words(n: usize) -> String {
    format!("{n} thread{}", if n == 1 { "" } else { "s" })
}
