//! `clapper simulate` and `clapper liftoff`.

use std::fmt::Write as _;
use std::path::PathBuf;

use anyhow::{bail, Context, Result};
use clap::{Args, ValueEnum};
use clapper_core::prelude::*;
use clapper_io::bell_file::BellSource;
use clapper_io::report::{style_name, BellReport, SimulationReport, SimulationSettings};

/// Trace sampling interval (s): fine enough to show each bounce of the
/// clapper (flights of a few ms), coarse enough for a small file.
const TRACE_INTERVAL_S: f64 = 5e-4;
/// Most strokes one run may ask for; a free-protocol history longer than
/// this has long since decayed.
const MAX_STROKES: usize = 10_000;

#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum Preset {
    /// The laboratory bell of Table 1.
    Lab,
    /// The old tenor of Great St Mary's, Cambridge, Table 1.
    GsmTenor,
}

#[derive(Clone, Copy, Debug, ValueEnum, PartialEq, Eq)]
pub enum StyleArg {
    Right,
    Wrong,
}

impl StyleArg {
    pub fn style(self) -> Style {
        match self {
            StyleArg::Right => Style::Right,
            StyleArg::Wrong => Style::Wrong,
        }
    }
}

#[derive(Clone, Copy, Debug, ValueEnum, PartialEq, Eq)]
pub enum ProtocolArg {
    /// Every stroke starts from rest at +-theta0 (the ringer restores the swing).
    Restart,
    /// Strokes follow one another with no energy input.
    Free,
}

#[derive(Clone, Copy, Debug, ValueEnum, PartialEq, Eq)]
pub enum ContactArg {
    /// Rigid impacts with restitution (default).
    Impact,
    /// The paper's contact spring.
    Penalty,
}

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

#[derive(Args, Debug)]
pub struct SimulateArgs {
    #[command(flatten)]
    pub source: BellArgs,
    /// How the clapper starts: right (on the trailing side) or wrong.
    #[arg(long, value_enum, default_value = "right")]
    pub style: StyleArg,
    /// Starting angle of the bell, at rest (deg, 0 < theta0 < 180).
    #[arg(long, value_name = "DEG", default_value_t = 171.0, allow_hyphen_values = true)]
    pub theta0: f64,
    /// Stronge's energy coefficient of restitution R (0 < R <= 1).
    #[arg(long, value_name = "R", default_value_t = 0.2, allow_hyphen_values = true)]
    pub restitution: f64,
    /// Override the bell's contact angle phi_max (deg, 0 < phi_max < 90).
    #[arg(long, value_name = "DEG", allow_hyphen_values = true)]
    pub phi_max: Option<f64>,
    /// Number of strokes (handstroke, backstroke, ...).
    #[arg(long, value_name = "N", default_value_t = 2)]
    pub strokes: usize,
    /// How one stroke leads to the next.
    #[arg(long, value_enum, default_value = "restart")]
    pub protocol: ProtocolArg,
    /// Contact model.
    #[arg(long, value_enum)]
    pub contact: Option<ContactArg>,
    /// Contact stiffness k of the penalty model (N m/rad); implies --contact penalty.
    #[arg(long, value_name = "K", allow_hyphen_values = true)]
    pub stiffness: Option<f64>,
    /// Print the full result as one JSON object.
    #[arg(long)]
    pub json: bool,
    /// Write a trace (t, theta, phi, theta', phi', contact force) as CSV.
    #[arg(long, value_name = "FILE.csv")]
    pub trace: Option<PathBuf>,
    /// Plot theta, phi and phi' against time (the paper's Fig 9), .svg or .png.
    #[arg(long, value_name = "FILE")]
    pub plot: Option<PathBuf>,
}

#[derive(Args, Debug)]
pub struct LiftoffArgs {
    /// L_b/L_c of the bell.
    #[arg(long, value_name = "X", allow_hyphen_values = true)]
    pub lb_over_lc: f64,
    /// Contact angle phi_max (deg).
    #[arg(long, value_name = "DEG", default_value_t = 26.0, allow_hyphen_values = true)]
    pub phi_max: f64,
    /// Print JSON.
    #[arg(long)]
    pub json: bool,
}

/// The bell, its name and source, with any phi_max override applied.
pub fn load(args: &SimulateArgs) -> Result<(String, Bell, BellSource)> {
    let (name, bell, source) = match (&args.source.preset, &args.source.bell, &args.source.chart_point) {
        (_, Some(path), _) => {
            let b = clapper_io::load_bell(path)?;
            (b.name, b.bell, b.source)
        }
        (_, _, Some((x, y))) => {
            let c = ChartConstruction::default();
            let b = c.bell(*x, *y)?;
            (format!("chart point ({x}, {y})"), b, BellSource::MassProperties)
        }
        (Some(Preset::GsmTenor), _, _) => ("GSM tenor".into(), Bell::gsm_tenor(), BellSource::MassProperties),
        _ => ("lab bell".into(), Bell::lab(), BellSource::MassProperties),
    };
    let bell = match args.phi_max {
        Some(deg) => bell.with_phi_max(deg.to_radians())?,
        None => bell,
    };
    Ok((name, bell, source))
}

/// The contact model from `--contact` and `--stiffness`.
pub fn contact_model(contact: Option<ContactArg>, stiffness: Option<f64>) -> Result<ContactModel> {
    Ok(match (contact, stiffness) {
        (Some(ContactArg::Impact), Some(_)) => {
            bail!("--stiffness applies to the penalty model; drop it or use --contact penalty")
        }
        (Some(ContactArg::Impact), None) | (None, None) => ContactModel::Impact,
        (_, k) => ContactModel::Penalty {
            stiffness: k.unwrap_or(clapper_core::stroke::DEFAULT_STIFFNESS),
        },
    })
}

pub fn config(args: &SimulateArgs) -> Result<SimConfig> {
    let contact = contact_model(args.contact, args.stiffness)?;
    let cfg = SimConfig {
        theta0: args.theta0.to_radians(),
        restitution: args.restitution,
        contact,
        ..SimConfig::default()
    };
    cfg.validate()?;
    if args.strokes == 0 || args.strokes > MAX_STROKES {
        bail!("--strokes {} is out of range: 1 to {MAX_STROKES}", args.strokes);
    }
    Ok(cfg)
}

pub fn run(args: SimulateArgs) -> Result<()> {
    let (name, bell, source) = load(&args)?;
    let cfg = config(&args)?;
    if let Some(p) = &args.plot {
        clapper_plot::format_of(p)?;
    }
    let style = args.style.style();
    let protocol = match args.protocol {
        ProtocolArg::Restart => Protocol::Restart,
        ProtocolArg::Free => Protocol::Free,
    };
    let want_trace = args.trace.is_some() || args.plot.is_some();
    let mut recorder = TraceRecorder::new(TRACE_INTERVAL_S);
    let ringing = if want_trace {
        ring(&bell, &cfg, style, protocol, args.strokes, &mut recorder)
    } else {
        ring(&bell, &cfg, style, protocol, args.strokes, &mut ())
    }
    .context("simulation failed")?;

    if let Some(path) = &args.trace {
        crate::files::write_atomically(path, |tmp| {
            let f = std::fs::File::create(tmp).with_context(|| format!("cannot create {}", path.display()))?;
            clapper_io::write_trace_csv(std::io::BufWriter::new(f), &recorder.samples)
                .with_context(|| format!("cannot write {}", path.display()))
        })?;
    }
    if let Some(path) = &args.plot {
        let title = format!(
            "{name}: ringing {} from {:.0} deg, R = {}, {} contact  (r/L_c = {:.3}, L_b/L_c = {:.3})",
            style_name(style),
            args.theta0,
            args.restitution,
            contact_name(&cfg),
            bell.r_over_lc(),
            bell.lb_over_lc()
        );
        let plot = clapper_plot::StrokePlot {
            title: &title,
            phi_max_deg: bell.phi_max.to_degrees(),
            stroke_starts: ringing.strokes.iter().skip(1).map(|s| s.start.t).collect(),
        };
        crate::files::write_atomically(path, |tmp| {
            Ok(clapper_plot::stroke_plot(tmp, &recorder.samples, &plot)?)
        })?;
    }

    let report = SimulationReport::new(
        BellReport::new(&name, &bell, &source),
        SimulationSettings::new(&cfg, protocol, args.strokes),
        &ringing,
    );
    if args.json {
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        for w in bell.warnings() {
            eprintln!("warning: {w}");
        }
        print!("{}", summary(&report));
    }
    Ok(())
}

pub fn contact_name(cfg: &SimConfig) -> String {
    match cfg.contact {
        ContactModel::Impact => "impact".into(),
        ContactModel::Penalty { stiffness } => format!("penalty (k = {stiffness:e} N m/rad)"),
    }
}

fn opt(v: Option<f64>, digits: usize, unit: &str) -> String {
    match v {
        Some(x) => format!("{x:.digits$} {unit}"),
        None => "none".into(),
    }
}

/// The short readable summary printed by default.
fn summary(r: &SimulationReport) -> String {
    let b = &r.bell;
    let s = &r.settings;
    let mut o = String::new();
    let _ = writeln!(o, "bell: {}", b.name);
    let _ = writeln!(
        o,
        "  chart position   r/L_c = {:.3}, L_b/L_c = {:.3}",
        b.r_over_lc, b.lb_over_lc
    );
    let _ = writeln!(
        o,
        "  pendulum lengths L_b = {:.3} m, L_c = {:.3} m; periods T_b = {:.3} s, T_c = {:.3} s; phi_max = {:.1} deg",
        b.lb_m, b.lc_m, b.tb_s, b.tc_s, b.phi_max_deg
    );
    if !b.assumed.is_empty() {
        let _ = writeln!(o, "  assumed (not measured): {}", b.assumed.join(", "));
    }
    let stiffness = s
        .stiffness_n_m_per_rad
        .map(|k| format!(" (k = {k:e} N m/rad)"))
        .unwrap_or_default();
    let _ = writeln!(
        o,
        "settings: ringing {} from theta0 = {:.1} deg, R = {}, {} contact{stiffness}, {} protocol",
        r.style, s.theta0_deg, s.restitution, s.contact, s.protocol
    );
    for st in &r.strokes {
        let kind = if st.number % 2 == 1 { "handstroke" } else { "backstroke" };
        let _ = writeln!(
            o,
            "\nstroke {} ({kind}, {} style, from {:+.1} deg)",
            st.number, st.style, st.start_theta_deg
        );
        let _ = writeln!(o, "  lift-off         {}", opt(st.liftoff_theta_deg, 2, "deg"));
        match &st.first_strike {
            Some(f) => {
                let _ = writeln!(
                    o,
                    "  first strike     {:.2} deg, {:.3} s into the stroke, clapper rate {:.3} rad/s",
                    f.theta_deg, f.t_s, f.phidot_rad_s
                );
                match (st.second_strike_delay_ms, st.amplitude_ratio) {
                    (Some(dt), Some(a)) => {
                        let _ = writeln!(
                            o,
                            "  second impact    {dt:.1} ms later, amplitude ratio {a:.3}; double strike index D = {:.2}",
                            st.double_strike_index.unwrap_or(0.0)
                        );
                    }
                    _ => {
                        let _ = writeln!(o, "  second impact    none; double strike index D = 0");
                    }
                }
                let _ = writeln!(
                    o,
                    "  bouncing         {} impacts; clapper at rest {}",
                    st.impacts.len(),
                    match st.bounce_time_s {
                        Some(t) => format!("{t:.3} s after the first strike"),
                        None => "only after the stroke ended".into(),
                    }
                );
            }
            None => {
                let _ = writeln!(o, "  first strike     none: the clapper never struck the other side");
            }
        }
        let _ = writeln!(
            o,
            "  end              {:.2} deg after {:.3} s ({}), clapper {} on side {:+}; next stroke starts {}",
            st.end_theta_deg, st.duration_s, st.end_reason, st.end_clapper, st.end_side, st.continues_as
        );
    }
    let _ = writeln!(
        o,
        "\nverdict: {}",
        if r.sustained {
            format!("the bell sustains ringing {} (first stroke, restart protocol)", r.style)
        } else {
            format!(
                "the bell does not sustain ringing {} (first stroke, restart protocol)",
                r.style
            )
        }
    );
    o
}

pub fn liftoff(args: LiftoffArgs) -> Result<()> {
    let a = liftoff_angles(args.lb_over_lc, args.phi_max.to_radians())?;
    if args.json {
        println!(
            "{}",
            serde_json::json!({
                "lb_over_lc": args.lb_over_lc,
                "phi_max_deg": args.phi_max,
                "right_deg": a.right.to_degrees(),
                "wrong_deg": a.wrong.to_degrees(),
            })
        );
    } else {
        println!(
            "lift-off for r = 0, L_b/L_c = {}, phi_max = {} deg (equations 15, 16):\n  ringing right  theta_r = {:.2} deg\n  ringing wrong  theta_w = {:.2} deg",
            args.lb_over_lc,
            args.phi_max,
            a.right.to_degrees(),
            a.wrong.to_degrees()
        );
    }
    Ok(())
}
