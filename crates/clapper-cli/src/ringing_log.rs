//! `clapper ringing-log`: a bell's accelerometer log read into swings,
//! strikes, odd-struckness and phases, beside the model with `--bell`; and
//! `clapper synth-log`: a synthetic log with known truth.

use std::path::PathBuf;

use anyhow::{bail, Result};
use clap::Args;
use clapper_app::ringing_log::{read_log, text, LogReading, LogReport};
use clapper_app::simulate::{Preset, SimulateRequest};
use clapper_core::bell::G;
use clapper_core::sensor::SensorPlace;
use clapper_io::accel_log::{load_accel_log, write_sleuth_log, Axes, LogFileError};
use clapper_io::text_file::MAX_TEXT_BYTES;
use clapper_plot::ringing_log::{ringing_log_plot, LogPhase, LogPlot, LogSwing};
use clapper_signal::ringing_log::{AccelLog, LogOptions, PhaseKind};
use clapper_signal::ringing_log_synth::{plan_log, render_log, LogSpec, LogTruth};
use serde_json::json;

use crate::files::write_bytes;
use crate::simulate::BellArgs;

/// How far from the pivot (m, above or below) a sensor on a bell can be:
/// the largest bells are about 2 m across.
const SENSOR_REACH_M: f64 = 2.0;

/// `--sensor-m M` refused unless the sensor is on the bell, within
/// [`SENSOR_REACH_M`] of the pivot.
fn check_sensor_m(m: f64) -> anyhow::Result<()> {
    if !(-SENSOR_REACH_M..=SENSOR_REACH_M).contains(&m) {
        anyhow::bail!("--sensor-m {m} m: a sensor on the bell, within {SENSOR_REACH_M} m of the pivot");
    }
    Ok(())
}

#[derive(Args, Debug)]
pub struct RingingLogArgs {
    /// The log: belfry-sleuth text (x y z in m/s², time in ms, a line a
    /// sample, `Bell 3` after) or CSV with a header t_s, ax, ay, az.
    pub file: PathBuf,
    /// Which sensor axis lies along the bell's axis (toward the crown) and
    /// which is tangential: RADIAL,TANGENTIAL, each x, y or z with an
    /// optional sign (the third lies along the pivot). Default y,z, turned
    /// over if the log reads the bell upside down (which way is down is read
    /// from its small swings); given, the axes are taken as they are.
    #[arg(long, allow_hyphen_values = true)]
    pub axes: Option<String>,
    /// The sensor's distance above the pivot along the bell's axis (m), if
    /// known; fitted from the log otherwise.
    #[arg(long, value_name = "M", allow_hyphen_values = true)]
    pub sensor_m: Option<f64>,
    /// The sensor's range (g): readings at it are clipped. Default ±2 g.
    #[arg(long, default_value_t = 2.0, value_name = "G")]
    pub clip_g: f64,
    /// A bell file: the model's BDC-to-strike at each measured amplitude,
    /// the pivot offset that gives the log's odd-struckness, and the
    /// pendulum period against the log's.
    #[arg(long, value_name = "FILE")]
    pub bell: Option<PathBuf>,
    /// Print the report as JSON.
    #[arg(long)]
    pub json: bool,
    /// Write every swing as CSV.
    #[arg(long, value_name = "FILE.csv")]
    pub csv: Option<PathBuf>,
    /// Plot: the log with its phases, a zoom of strokes, the amplitudes
    /// ringing up and down (.png or .svg).
    #[arg(long, value_name = "FILE")]
    pub plot: Option<PathBuf>,
}

pub fn ringing_log(args: RingingLogArgs) -> Result<()> {
    crate::files::claim_stdout(&[("--csv", args.csv.as_deref())], args.json)?;
    if let Some(p) = &args.plot {
        clapper_plot::format_of(p)?;
    }
    if !(args.clip_g.is_finite() && args.clip_g > 0.0) {
        bail!("--clip-g {} must be a number of g above 0", args.clip_g);
    }
    if let Some(m) = args.sensor_m {
        check_sensor_m(m)?;
    }
    let axes = match &args.axes {
        Some(a) => Axes::parse(a)?,
        None => Axes::default(),
    };
    let log = load_accel_log(&args.file, axes).map_err(|e| match e {
        // Names the file itself.
        e @ (LogFileError::NotText(_) | LogFileError::Read { .. }) => anyhow::Error::from(e),
        e => anyhow::Error::from(e).context(format!("reading {}", args.file.display())),
    })?;
    let bell = match &args.bell {
        Some(p) => Some(clapper_io::load_bell(p)?),
        None => None,
    };
    let opts = LogOptions {
        sensor_along: args.sensor_m,
        clip: args.clip_g * G,
        find_down: args.axes.is_none(),
        ..LogOptions::default()
    };
    let reading = read_log(&log, &opts, bell)?;
    let r = &reading.report;
    if let Some(path) = &args.csv {
        write_bytes(path, csv(r)?)?;
    }
    if let Some(path) = &args.plot {
        plot_reading(path, &reading, &log, &args.file)?;
    }
    if args.json {
        crate::say!("{}", serde_json::to_string(r)?);
    } else {
        crate::say_text!("{}", text(r));
    }
    Ok(())
}

/// The log's angle, phases and swings drawn to `path` (SVG or PNG).
fn plot_reading(path: &std::path::Path, reading: &LogReading, log: &AccelLog, file: &std::path::Path) -> Result<()> {
    let r = &reading.report;
    let a = &reading.analysis;
    let theta: Vec<f64> = a.theta.iter().map(|x| x.to_degrees()).collect();
    let phases: Vec<LogPhase> = a
        .phases
        .iter()
        .map(|p| LogPhase {
            kind: p.kind.name(),
            span: (p.start, p.end),
        })
        .collect();
    let swings: Vec<LogSwing> = a
        .strokes
        .iter()
        .map(|s| LogSwing {
            bdc: s.bdc,
            strike: s.strike.zip(s.strike_theta.map(f64::to_degrees)),
            amplitude: s.amplitude.to_degrees(),
            hand: s.hand,
            ringing_up_or_down: matches!(s.phase, PhaseKind::Raising | PhaseKind::Lowering),
        })
        .collect();
    let title = format!(
        "{}: {} swings, odd-struck {}",
        r.bell.as_deref().unwrap_or(&file.display().to_string()),
        r.strokes.len(),
        r.odd_struck_ms.map_or("unknown".into(), |o| format!("{o:+.1} ms"))
    );
    crate::files::write_atomically(path, |tmp| {
        Ok(ringing_log_plot(
            tmp,
            &LogPlot {
                title: &title,
                t: &log.t,
                theta: &theta,
                phases: &phases,
                swings: &swings,
            },
        )?)
    })?;
    Ok(())
}

fn csv(r: &LogReport) -> Result<String> {
    let mut rows = vec![[
        "bdc_s",
        "stroke",
        "phase",
        "amplitude_deg",
        "strike_s",
        "bdc_to_strike_ms",
        "strike_theta_deg",
        "model_bdc_to_strike_ms",
        "strike_hidden",
        "stand_deg",
        "stand_s",
        "set",
        "amplitude_timed",
    ]
    .map(String::from)];
    let f = |v: Option<f64>, d: usize| v.map_or(String::new(), |x| format!("{x:.d$}"));
    for s in &r.strokes {
        rows.push([
            format!("{:.4}", s.bdc_s),
            s.stroke.to_string(),
            s.phase.to_string(),
            format!("{:.2}", s.amplitude_deg),
            f(s.strike_s, 4),
            f(s.bdc_to_strike_ms, 1),
            f(s.strike_theta_deg, 2),
            f(s.model_bdc_to_strike_ms, 1),
            s.strike_hidden.to_string(),
            f(s.stand.as_ref().map(|x| x.angle_deg), 2),
            f(s.stand.as_ref().and_then(|x| x.duration_s), 2),
            s.stand.as_ref().is_some_and(|x| x.set).to_string(),
            s.amplitude_timed.to_string(),
        ]);
    }
    clapper_io::strike_file::csv_text(&rows).map_err(anyhow::Error::msg)
}

#[derive(Args, Debug)]
pub struct SynthLogArgs {
    /// The bell (default the Great St Mary's tenor).
    #[command(flatten)]
    pub source: BellArgs,
    /// Output log (belfry-sleuth text: x y z in m/s², time in ms).
    #[arg(long, value_name = "FILE")]
    pub out: PathBuf,
    /// The truth as JSON (phases, swings, odd-struckness), beside it.
    #[arg(long, value_name = "FILE.json")]
    pub truth: Option<PathBuf>,
    /// Sample rate (Hz), 5 to 10,000.
    #[arg(long, default_value_t = 100.0)]
    pub rate: f64,
    /// Noise (m/s², standard deviation).
    #[arg(long, default_value_t = 0.04)]
    pub noise: f64,
    /// Strokes rung full circle between raising and lowering (even).
    #[arg(long, default_value_t = 40)]
    pub strokes: usize,
    /// The clapper pivot's offset across the bell's axis (mm): an
    /// odd-struck bell.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub offset_mm: f64,
    /// Runs of lost samples.
    #[arg(long, default_value_t = 0)]
    pub gaps: usize,
    /// The sensor's distance above the pivot (m).
    #[arg(long, default_value_t = 0.15)]
    pub sensor_m: f64,
    /// Seed.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// The bell's name, written after the samples.
    #[arg(long, default_value = "synthetic")]
    pub name: String,
}

/// Most strokes of a synthetic log: a peal's worth for one bell, twice.
const MAX_LOG_STROKES: usize = 10_000;
/// Most runs of lost samples in a synthetic log.
const MAX_LOG_GAPS: usize = 1_000;

/// The truth of a synthetic log at `rate` (Hz) as JSON.
fn truth_json(rate: f64, truth: &LogTruth) -> serde_json::Value {
    json!({
        "synthetic": true,
        "rate_hz": rate,
        "odd_struck_ms": truth.odd_struck.map(|x| x * 1e3),
        "phases": truth.phases.iter().map(|p| json!({"kind": p.kind.name(), "start_s": p.start, "end_s": p.end})).collect::<Vec<_>>(),
        "strokes": truth.strokes.iter().map(|s| json!({
            "bdc_s": s.bdc,
            "stroke": if s.hand { "hand" } else { "back" },
            "strike_s": s.strike,
            "amplitude_deg": s.amplitude.to_degrees(),
            "phase": s.phase.name(),
            "hidden_by_a_gap": s.hidden,
        })).collect::<Vec<_>>(),
    })
}

/// About how many bytes a log `seconds` long at `rate` (Hz) takes as text,
/// a little over: a line a sample, three readings of 6.5 characters and a
/// space each (5 to 7: "9.848", "-0.077", "-12.345") and the time in ms,
/// with 3 decimals when samples fall within a millisecond. (A 10 kHz log
/// of 300 s measured 30.4 bytes a sample; this says 33.5.)
fn log_bytes_estimate(rate: f64, seconds: f64) -> f64 {
    let ms_digits = (seconds * 1e3).max(1.0).log10().floor() + 1.0;
    let decimals = if rate > 1000.0 { 4.0 } else { 0.0 };
    (seconds * rate + 1.0) * (3.0 * 7.5 + ms_digits + decimals + 1.0)
}

/// The refusal of a log `seconds` long, `bytes` as text, said in the
/// options' words.
fn too_long(args: &SynthLogArgs, seconds: f64, bytes: f64) -> String {
    let per_second = bytes / (seconds * args.rate).max(1.0);
    let fits_hz = (MAX_TEXT_BYTES as f64 / (per_second * seconds)).floor();
    format!(
        "--rate {} Hz over the {:.0} s this log lasts (--strokes {} rung, with raising and lowering) is about {} MiB \
         of text, more than the {} MiB ringing-log reads: lower --rate (at most about {fits_hz} Hz here) or --strokes",
        args.rate,
        seconds,
        args.strokes,
        (bytes / (1u64 << 20) as f64).ceil(),
        MAX_TEXT_BYTES >> 20
    )
}

/// synth-log's counts, noise, sensor and name refused before anything is
/// simulated or allocated for them.
fn check_synth_args(args: &SynthLogArgs) -> Result<()> {
    if args.strokes > MAX_LOG_STROKES {
        anyhow::bail!(
            "--strokes {}: at most {MAX_LOG_STROKES} (a peal is about 5,000)",
            args.strokes
        );
    }
    if args.gaps > MAX_LOG_GAPS {
        anyhow::bail!("--gaps {}: at most {MAX_LOG_GAPS} runs of lost samples", args.gaps);
    }
    if !(0.0..=100.0).contains(&args.noise) {
        anyhow::bail!("--noise {} m/s²: from 0 to 100 (a sensor's is about 0.04)", args.noise);
    }
    check_sensor_m(args.sensor_m)?;
    if !clapper_io::accel_log::name_reads_back(&args.name) {
        anyhow::bail!(
            "--name {:?}: a log's name is written on one line after its samples and must not be blank \
             or begin with a number (ringing-log would read it as a sample); e.g. --name \"Bell {}\"",
            args.name,
            args.name.trim()
        );
    }
    Ok(())
}

pub fn synth_log_cmd(args: SynthLogArgs) -> Result<()> {
    check_synth_args(&args)?;
    // The bell as `simulate` names it, the tenor when none is named.
    let file = args.source.file()?;
    let preset = match (args.source.given(), args.source.preset) {
        (false, _) => Some(Preset::GsmTenor),
        (true, p) => p,
    };
    let req = SimulateRequest {
        preset,
        chart_point: args.source.chart_point.map(|(x, y)| [x, y]),
        ..SimulateRequest::default()
    };
    let mut bell = req.bell(file)?.bell;
    // The bell's own bound (a quarter of L_c), said in the option's unit.
    let most_mm = 0.25 * bell.lc() * 1e3;
    if !(args.offset_mm.is_finite() && args.offset_mm.abs() <= most_mm) {
        anyhow::bail!(
            "--offset-mm {} mm: within {most_mm:.0} mm either way for this bell, a quarter of its clapper's L_c \
             (a real bell's offset is a few millimetres)",
            clapper_core::param::readable(args.offset_mm)
        );
    }
    bell.hanging.pivot_offset = args.offset_mm * 1e-3;
    let mut spec = LogSpec::new(bell, args.seed);
    spec.rate = args.rate;
    spec.noise = args.noise;
    spec.strokes = args.strokes;
    spec.gaps = args.gaps;
    spec.sensor = SensorPlace {
        along: args.sensor_m,
        across: 0.0,
    };
    // The bell's swings simulated, the log's length is known before its
    // samples are drawn: one too long for ringing-log is refused here.
    let plan = plan_log(&spec)?;
    let bytes = log_bytes_estimate(args.rate, plan.seconds());
    if bytes > MAX_TEXT_BYTES as f64 {
        anyhow::bail!("{}", too_long(&args, plan.seconds(), bytes));
    }
    let (mut log, truth) = render_log(&spec, &plan)?;
    log.name = Some(args.name.clone());
    let text = write_sleuth_log(&log);
    if text.len() > MAX_TEXT_BYTES {
        anyhow::bail!("{}", too_long(&args, plan.seconds(), text.len() as f64));
    }
    write_bytes(&args.out, text)?;
    if let Some(path) = &args.truth {
        let v = truth_json(args.rate, &truth);
        write_bytes(path, serde_json::to_string_pretty(&v)? + "\n")?;
    }
    crate::say!(
        "synthetic log: {} samples at {} Hz over {:.0} s, {} swings, odd-struck {}, written to {}",
        log.t.len(),
        args.rate,
        log.t.last().copied().unwrap_or(0.0),
        truth.strokes.len(),
        truth
            .odd_struck
            .map_or("none".into(), |o| format!("{:+.1} ms", o * 1e3)),
        args.out.display()
    );
    Ok(())
}
