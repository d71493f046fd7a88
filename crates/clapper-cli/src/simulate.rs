//! `clapper simulate` and `clapper liftoff`.

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Args;
use clapper_app::liftoff::{BellLiftoffReport, FormulaReport};
use clapper_app::simulate::{simulate_traced, summary, Preset, SimulateRequest, DEFAULT_STROKES, DEFAULT_THETA0_DEG};
use clapper_core::hanging::SwingLoss;
use clapper_core::prelude::*;
use clapper_core::stroke::{ContactModel, Integrator};
use clapper_io::LoadedBell;

pub fn parse_point(s: &str) -> std::result::Result<(f64, f64), String> {
    let (x, y) = s
        .split_once(',')
        .ok_or_else(|| format!("'{s}' is not X,Y (r/L_c,L_b/L_c), e.g. 0.45,1.68"))?;
    let num = |v: &str| {
        v.trim()
            .parse::<f64>()
            .map_err(|_| format!("'{v}' in '{s}' is not a number"))
    };
    Ok((num(x)?, num(y)?))
}

/// A parser for one of clapper-core's named choices: the names it lists
/// are the choices' own ([`Choice`]), so the command line, files and JSON
/// spell them alike.
pub fn choice<T: Choice + Send + Sync>() -> impl clap::builder::TypedValueParser<Value = T> {
    use clap::builder::TypedValueParser as _;
    clap::builder::PossibleValuesParser::new(T::ALL.iter().map(|v| v.name())).map(|name| {
        *T::ALL
            .iter()
            .find(|v| v.name() == name)
            .expect("the parser accepts only the names listed")
    })
}

/// Where the bell comes from: exactly one of these (default: the lab preset).
#[derive(Args, Debug)]
#[group(multiple = false)]
pub struct BellArgs {
    /// A bell of the paper's Table 1.
    #[arg(long, value_enum)]
    pub preset: Option<Preset>,
    /// A bell file (TOML): mass properties or tower measurements.
    #[arg(long, value_name = "FILE")]
    pub bell: Option<PathBuf>,
    /// A bell built as the paper builds chart points: X = r/L_c, Y = L_b/L_c.
    #[arg(long, value_name = "X,Y", value_parser = parse_point, allow_hyphen_values = true)]
    pub chart_point: Option<(f64, f64)>,
}

impl BellArgs {
    /// Whether a bell was named at all.
    pub fn given(&self) -> bool {
        self.preset.is_some() || self.bell.is_some() || self.chart_point.is_some()
    }

    /// The bell file of `--bell`, read.
    pub fn file(&self) -> Result<Option<LoadedBell>> {
        Ok(match &self.bell {
            Some(path) => Some(clapper_io::load_bell(path)?),
            None => None,
        })
    }
}

/// The contact model and the integrator's tolerance: shared by every
/// command that simulates.
#[derive(Args, Debug, Clone)]
pub struct SolverArgs {
    /// Contact model.
    #[arg(long, value_parser = choice::<ContactModel>())]
    pub contact: Option<ContactModel>,
    /// Contact stiffness k of the penalty model (N m/rad); implies --contact penalty.
    #[arg(long, value_name = "K", allow_hyphen_values = true)]
    pub stiffness: Option<f64>,
    /// Integrator tolerance, relative and absolute (default 3e-8; 1e-12 for
    /// a reference).
    #[arg(long, value_name = "TOL")]
    pub rtol: Option<f64>,
    /// Integrator: taylor (default, fastest) or dopri5 (Dormand-Prince, a
    /// cross-check).
    #[arg(long, value_parser = choice::<Integrator>())]
    pub integrator: Option<Integrator>,
    /// Coefficient of restitution R2 of every bounce after the first impact
    /// on a side (0 < R2 <= 1; default: R). `clapper restitution` measures
    /// both from clapper drops.
    #[arg(long, value_name = "R2")]
    pub restitution_later: Option<f64>,
    /// What the double strike's amplitude ratio A compares: rate (the
    /// clapper's, default), impulse (the synthesised strikes') or
    /// vibration (the energy each impact takes); docs/model.md section 4.1.
    #[arg(long, value_parser = choice::<StrikeAmplitude>())]
    pub strike_amplitude: Option<StrikeAmplitude>,
}

impl SolverArgs {
    /// Copy these options into a simulate request.
    pub fn set(&self, req: &mut SimulateRequest) {
        req.restitution_later = self.restitution_later;
        req.strike_amplitude = self.strike_amplitude;
        req.contact = self.contact;
        req.stiffness = self.stiffness;
        req.rtol = self.rtol;
        req.integrator = self.integrator;
    }
}

/// How the bell departs from the ideal: pivot offset, unequal contact
/// angles (or the tape's gaps), friction. Every option overrides the bell
/// file's (docs/model.md §10).
#[derive(Args, Debug, Clone, Default)]
pub struct HangingArgs {
    /// Sideways offset d of the clapper pivot (m), positive toward the side
    /// the clapper rests on before a handstroke.
    #[arg(long, value_name = "M", allow_hyphen_values = true)]
    pub pivot_offset: Option<f64>,
    /// Contact angle of the side struck at handstroke (deg).
    #[arg(long, value_name = "DEG", allow_hyphen_values = true)]
    pub phi_max_hand: Option<f64>,
    /// Contact angle of the side struck at backstroke (deg).
    #[arg(long, value_name = "DEG", allow_hyphen_values = true)]
    pub phi_max_back: Option<f64>,
    /// Tape: ball-to-rim gap on the handstroke side, bell down (mm).
    #[arg(long, value_name = "MM", allow_hyphen_values = true, requires_all = ["gap_back", "ball_below_pivot"])]
    pub gap_hand: Option<f64>,
    /// Tape: ball-to-rim gap on the backstroke side, bell down (mm).
    #[arg(long, value_name = "MM", allow_hyphen_values = true, requires_all = ["gap_hand", "ball_below_pivot"])]
    pub gap_back: Option<f64>,
    /// The ball's centre below the clapper pivot (m), for the gaps.
    #[arg(long, value_name = "M", allow_hyphen_values = true, requires_all = ["gap_hand", "gap_back"])]
    pub ball_below_pivot: Option<f64>,
    /// Viscous damping at the bell's bearings (N m s/rad).
    #[arg(long, value_name = "N_M_S", allow_hyphen_values = true)]
    pub bell_damping: Option<f64>,
    /// Coulomb friction torque at the bell's bearings (N m).
    #[arg(long, value_name = "N_M", allow_hyphen_values = true)]
    pub bell_friction: Option<f64>,
    /// Viscous damping at the clapper's pivot (N m s/rad).
    #[arg(long, value_name = "N_M_S", allow_hyphen_values = true)]
    pub clapper_damping: Option<f64>,
    /// Coulomb friction torque at the clapper's pivot (N m).
    #[arg(long, value_name = "N_M", allow_hyphen_values = true)]
    pub clapper_friction: Option<f64>,
    /// King's timing: swings (strokes) for the bell's small swing, clapper
    /// tied, to halve; sets the bell's damping (or friction, with
    /// `--swing-loss coulomb`).
    #[arg(long, value_name = "N", allow_hyphen_values = true, conflicts_with_all = ["bell_damping", "bell_friction"])]
    pub bell_swings_to_halve: Option<f64>,
    /// King's timing: swings for the clapper's small swing in a still bell
    /// to halve; sets the clapper's damping (or friction).
    #[arg(long, value_name = "N", allow_hyphen_values = true, conflicts_with_all = ["clapper_damping", "clapper_friction"])]
    pub clapper_swings_to_halve: Option<f64>,
    /// What the swing timings measure: viscous damping, or Coulomb friction
    /// (which needs --swing-amplitude) [default: viscous].
    #[arg(long, value_parser = choice::<SwingLoss>())]
    pub swing_loss: Option<SwingLoss>,
    /// The timed swing's amplitude when the count began (deg), for
    /// `--swing-loss coulomb`.
    #[arg(long, value_name = "DEG", allow_hyphen_values = true)]
    pub swing_amplitude: Option<f64>,
}

/// Copy `HangingArgs` into a request's flat fields of the same names.
macro_rules! set_hanging {
    ($req:expr, $h:expr) => {{
        let h = &$h;
        $req.pivot_offset = h.pivot_offset;
        $req.phi_max_hand = h.phi_max_hand;
        $req.phi_max_back = h.phi_max_back;
        $req.gap_hand = h.gap_hand;
        $req.gap_back = h.gap_back;
        $req.ball_below_pivot = h.ball_below_pivot;
        $req.bell_damping = h.bell_damping;
        $req.bell_friction = h.bell_friction;
        $req.clapper_damping = h.clapper_damping;
        $req.clapper_friction = h.clapper_friction;
        $req.bell_swings_to_halve = h.bell_swings_to_halve;
        $req.clapper_swings_to_halve = h.clapper_swings_to_halve;
        $req.swing_loss = h.swing_loss;
        $req.swing_amplitude = h.swing_amplitude;
    }};
}
pub(crate) use set_hanging;

#[derive(Args, Debug)]
pub struct SimulateArgs {
    #[command(flatten)]
    pub source: BellArgs,
    /// How the clapper starts: right (on the trailing side) or wrong.
    #[arg(long, value_parser = choice::<Style>(), default_value = "right")]
    pub style: Style,
    /// Starting angle of the bell, at rest (deg, 0 < theta0 < 180).
    #[arg(long, value_name = "DEG", default_value_t = DEFAULT_THETA0_DEG, allow_hyphen_values = true)]
    pub theta0: f64,
    /// Stronge's energy coefficient of restitution R (0 < R <= 1) of the
    /// first impact on a side [default: the bell file's `restitution`, else
    /// 0.2]
    #[arg(long, value_name = "R", allow_hyphen_values = true)]
    pub restitution: Option<f64>,
    /// Override the bell's contact angle phi_max (deg, 0 < phi_max < 90).
    #[arg(long, value_name = "DEG", allow_hyphen_values = true)]
    pub phi_max: Option<f64>,
    /// Number of strokes (handstroke, backstroke, ...).
    #[arg(long, value_name = "N", default_value_t = DEFAULT_STROKES)]
    pub strokes: usize,
    /// How one stroke leads to the next.
    #[arg(long, value_parser = choice::<Protocol>(), default_value = "restart")]
    pub protocol: Protocol,
    #[command(flatten)]
    pub solver: SolverArgs,
    #[command(flatten)]
    pub hanging: HangingArgs,
    /// Print the full result as one JSON object.
    #[arg(long)]
    pub json: bool,
    /// Write a trace (t, theta, phi, theta', phi', contact force) as CSV;
    /// `-` is standard output (the summary then goes to standard error).
    #[arg(long, value_name = "FILE.csv")]
    pub trace: Option<PathBuf>,
    /// Plot theta, phi and phi' against time (the paper's Fig 9), .svg or .png.
    #[arg(long, value_name = "FILE")]
    pub plot: Option<PathBuf>,
}

#[derive(Args, Debug)]
pub struct LiftoffArgs {
    /// L_b/L_c of a bell with r = 0: the paper's formula (15), (16).
    #[arg(long, value_name = "X", allow_hyphen_values = true)]
    pub lb_over_lc: Option<f64>,
    /// Or a bell of any r, released from rest at --theta0: the exact
    /// lift-off of the closed-form swing.
    #[command(flatten)]
    pub source: BellArgs,
    /// Angle the bell is released from, at rest (deg; with a bell).
    #[arg(long, value_name = "DEG", default_value_t = DEFAULT_THETA0_DEG, allow_hyphen_values = true)]
    pub theta0: f64,
    /// Contact angle phi_max (deg): 26 for the formula; for a bell, its
    /// own unless given.
    #[arg(long, value_name = "DEG", allow_hyphen_values = true)]
    pub phi_max: Option<f64>,
    /// Print JSON.
    #[arg(long)]
    pub json: bool,
}

impl SimulateArgs {
    /// The options as the request the web API also takes.
    pub fn request(&self) -> SimulateRequest {
        let mut req = SimulateRequest {
            preset: self.source.preset,
            bell: None,
            chart_point: self.source.chart_point.map(|(x, y)| [x, y]),
            style: self.style,
            theta0: self.theta0,
            restitution: self.restitution,
            phi_max: self.phi_max,
            strokes: self.strokes,
            protocol: self.protocol,
            ..SimulateRequest::default()
        };
        self.solver.set(&mut req);
        set_hanging!(req, self.hanging);
        req
    }

    /// The bell file of `--bell`, read.
    pub fn bell_file(&self) -> Result<Option<LoadedBell>> {
        self.source.file()
    }
}

pub fn run(args: SimulateArgs) -> Result<()> {
    crate::files::claim_stdout(&[("--trace", args.trace.as_deref())], args.json)?;
    if let Some(p) = &args.plot {
        clapper_plot::format_of(p)?;
    }
    let sim = match (&args.trace, &args.plot) {
        // A trace alone is written as it is computed: any number of
        // strokes in constant memory.
        (Some(path), None) => {
            let mut sim = None;
            crate::files::write_atomically(path, |tmp| {
                let f = std::fs::File::create(tmp).with_context(|| format!("cannot create {}", path.display()))?;
                let mut w = clapper_io::TraceWriter::new(std::io::BufWriter::new(f))
                    .with_context(|| format!("cannot write {}", path.display()))?;
                let mut failed = None;
                let s = clapper_app::simulate::simulate_streamed(&args.request(), args.bell_file()?, |x| {
                    if failed.is_none() {
                        failed = w.write(x).err();
                    }
                })?;
                if let Some(e) = failed {
                    return Err(e).with_context(|| format!("cannot write {}", path.display()));
                }
                w.finish().with_context(|| format!("cannot write {}", path.display()))?;
                sim = Some(s);
                Ok(())
            })?;
            sim.expect("written")
        }
        _ => {
            let sim = simulate_traced(&args.request(), args.bell_file()?, None)?;
            if let Some(path) = &args.trace {
                crate::files::write_atomically(path, |tmp| {
                    let f = std::fs::File::create(tmp).with_context(|| format!("cannot create {}", path.display()))?;
                    clapper_io::write_trace_csv(std::io::BufWriter::new(f), &sim.samples)
                        .with_context(|| format!("cannot write {}", path.display()))
                })?;
            }
            sim
        }
    };
    if let Some(path) = &args.plot {
        crate::files::write_atomically(path, |tmp| {
            Ok(clapper_plot::stroke_plot(tmp, &sim.samples, &sim.plot())?)
        })?;
    }
    if args.json {
        crate::say!("{}", serde_json::to_string_pretty(&sim.report)?);
    } else {
        for w in &sim.warnings {
            eprintln!("warning: {w}");
        }
        crate::say_text!("{}", summary(&sim.report));
    }
    Ok(())
}

pub fn liftoff(args: LiftoffArgs) -> Result<()> {
    match (args.lb_over_lc, args.source.given()) {
        (Some(x), false) => liftoff_formula(
            x,
            args.phi_max.unwrap_or(clapper_core::bell::CHART_PHI_MAX_DEG),
            args.json,
        ),
        (None, true) => liftoff_of_bell(&args),
        _ => anyhow::bail!(
            "give either --lb-over-lc (r = 0, the paper's formula) or a bell (--preset, --bell or --chart-point)"
        ),
    }
}

fn liftoff_formula(lb_over_lc: f64, phi_max: f64, json: bool) -> Result<()> {
    let report = FormulaReport::new(lb_over_lc, phi_max)?;
    crate::measure::print_report(&report, json, || report.text())
}

/// The exact lift-off of a bell of any r released from rest, both styles.
fn liftoff_of_bell(args: &LiftoffArgs) -> Result<()> {
    let request = SimulateRequest {
        preset: args.source.preset,
        chart_point: args.source.chart_point.map(|(x, y)| [x, y]),
        phi_max: args.phi_max,
        ..SimulateRequest::default()
    };
    let loaded = request.bell(args.source.file()?)?;
    let report = BellLiftoffReport::new(&loaded, args.theta0)?;
    crate::measure::print_report(&report, args.json, || report.text())
}
