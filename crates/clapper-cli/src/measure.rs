//! The measurement commands: restitution, contacts, spectrogram, decay,
//! modes, impulse (the paper's Sections 2, 3.2 and 3.3).

use std::path::PathBuf;

use anyhow::{bail, Context, Result};
use clap::Args;
use clapper_app::measure::{ContactsReport, DecayReport, ImpulseReport, ModesReport, RestitutionReport};
use clapper_core::vibration::Mode;
use clapper_io::signal_file::{read_modes, read_signal};
use clapper_plot::chart::Series;
use clapper_plot::RGBColor;
use clapper_signal::accel::{velocity_jumps, JumpOptions};
use clapper_signal::spectrogram::spectrogram_columns;

fn line_plot(path: &std::path::Path, title: &str, x: &str, y: &str, series: &[Series]) -> Result<()> {
    line_plot_scaled(path, title, x, y, series, false)
}

/// [`line_plot`], with a logarithmic x axis if `log_x`.
fn line_plot_scaled(
    path: &std::path::Path,
    title: &str,
    x: &str,
    y: &str,
    series: &[Series],
    log_x: bool,
) -> Result<()> {
    crate::files::write_atomically(path, |tmp| {
        Ok(clapper_plot::line_plot_scaled(tmp, title, x, y, series, log_x)?)
    })
}

/// The jumps of one or more drops (a newtype, so clap takes it as one value).
#[derive(Clone, Debug)]
pub struct Drops(pub Vec<Vec<f64>>);

/// A channel (or a CSV's value column) as the readers take it, counted
/// from 0; a type of its own, so that the command line's check of plain
/// counts (`main.rs`, `command_line`) leaves [`parse_channel`] in place.
#[derive(Clone, Copy, Debug)]
pub struct ChannelIndex(pub usize);

/// `--channel N`: a channel's number as a user counts it (1 the first, as
/// `strikes --channel` and the report's words count), as the index from 0
/// that the readers take; 0 is refused with why.
pub(crate) fn parse_channel(s: &str) -> std::result::Result<ChannelIndex, String> {
    match s.trim().parse::<usize>() {
        Ok(0) => Err("channel 0: channels (and a CSV's value columns) count from 1, the first".into()),
        Ok(k) => Ok(ChannelIndex(k - 1)),
        Err(_) => Err(format!("channel '{s}': a channel's number, counted from 1 (the first)")),
    }
}

fn parse_jumps(s: &str) -> std::result::Result<Drops, String> {
    s.split(';')
        .map(|drop| {
            drop.split(',')
                .map(|v| {
                    v.trim()
                        .parse::<f64>()
                        .map_err(|_| format!("'{v}' in --jumps is not a number"))
                })
                .collect()
        })
        .collect::<std::result::Result<Vec<Vec<f64>>, String>>()
        .map(Drops)
}

#[derive(Args, Debug)]
pub struct RestitutionArgs {
    /// Velocity jumps of one drop, comma-separated; several drops separated by ';'.
    #[arg(long, value_name = "LIST", value_parser = parse_jumps, conflicts_with = "accel", required_unless_present = "accel")]
    pub jumps: Option<Drops>,
    /// An accelerometer recording of clapper drops (.wav or .csv).
    #[arg(long, value_name = "FILE")]
    pub accel: Option<PathBuf>,
    /// WAV channel or CSV value column after the time column, counted from 1 (the first), as `strikes --channel` counts.
    #[arg(long, default_value = "1", value_parser = parse_channel)]
    pub channel: ChannelIndex,
    /// Print JSON.
    #[arg(long)]
    pub json: bool,
    /// Plot the ratios of adjacent jumps (the paper's Fig 8), .svg or .png.
    #[arg(long, value_name = "FILE")]
    pub plot: Option<PathBuf>,
}

pub fn restitution(args: RestitutionArgs) -> Result<()> {
    let (drops, times) = match (&args.jumps, &args.accel) {
        (Some(j), _) => (j.0.clone(), None),
        (None, Some(p)) => {
            let sig = read_signal(p, args.channel.0)?;
            let j = velocity_jumps(&sig, &JumpOptions::default()).with_context(|| p.display().to_string())?;
            if j.len() < 2 {
                bail!("{}: found {} impact(s); at least two are needed", p.display(), j.len());
            }
            (
                vec![j.iter().map(|x| x.dv.abs()).collect()],
                Some(j.iter().map(|x| x.t).collect::<Vec<f64>>()),
            )
        }
        _ => bail!("give --jumps or --accel"),
    };
    let report = RestitutionReport::new(drops, times)?;
    if let Some(path) = &args.plot {
        let (stars, means) = report.fig8_points();
        line_plot(
            path,
            "Fig 8: ratios of adjacent velocity jumps (pair 1 = jumps 2/1, 2 = 3/2, ...)",
            "pair of impacts",
            "velocity jump ratio",
            &[
                Series {
                    label: "each drop".into(),
                    points: stars,
                    markers: true,
                    dashed: false,
                    colour: RGBColor(120, 120, 120),
                },
                Series {
                    label: "mean of each pair (the paper's circles)".into(),
                    points: means,
                    markers: true,
                    dashed: false,
                    colour: RGBColor(210, 40, 40),
                },
            ],
        )?;
    }
    print_report(&report, args.json, || report.text())
}

/// `--json`: the report; otherwise its text.
pub fn print_report<T: serde::Serialize>(report: &T, json: bool, text: impl FnOnce() -> String) -> Result<()> {
    if json {
        crate::say!("{}", serde_json::to_string(report)?);
    } else {
        crate::say_text!("{}", text());
    }
    Ok(())
}

#[derive(Args, Debug)]
pub struct ContactsArgs {
    /// A contact-detector recording (.wav or .csv).
    pub file: PathBuf,
    /// WAV channel or CSV value column after the time column, counted from 1 (the first).
    #[arg(long, default_value = "1", value_parser = parse_channel)]
    pub channel: ChannelIndex,
    /// The higher level means "in contact" (the paper's circuit: the lower).
    #[arg(long)]
    pub contact_high: bool,
    /// Out-of-contact gaps shorter than this are noise (ms).
    #[arg(long, default_value_t = 1.0)]
    pub min_gap_ms: f64,
    /// Print JSON.
    #[arg(long)]
    pub json: bool,
}

pub fn contacts(args: ContactsArgs) -> Result<()> {
    let sig = read_signal(&args.file, args.channel.0)?;
    let report = ContactsReport::new(&sig, args.contact_high, args.min_gap_ms)
        .with_context(|| args.file.display().to_string())?;
    print_report(&report, args.json, || report.text(&args.file.display().to_string()))
}

#[derive(Args, Debug)]
pub struct SpectrogramArgs {
    /// A recording (.wav or .csv).
    pub file: PathBuf,
    /// Output picture (.svg or .png).
    #[arg(long, value_name = "FILE")]
    pub out: PathBuf,
    /// Window length (samples).
    #[arg(long, default_value_t = 2048)]
    pub window: usize,
    /// Overlap of successive windows (fraction).
    #[arg(long, default_value_t = 0.75)]
    pub overlap: f64,
    /// Range shown below the maximum (dB).
    #[arg(long, default_value_t = 40.0)]
    pub range_db: f64,
    /// Highest frequency shown (Hz).
    #[arg(long, default_value_t = 3000.0)]
    pub fmax: f64,
    /// WAV channel or CSV value column after the time column, counted from 1 (the first).
    #[arg(long, default_value = "1", value_parser = parse_channel)]
    pub channel: ChannelIndex,
}

/// Most columns of a drawn spectrogram: more than a picture's pixels across.
const SPECTROGRAM_COLUMNS: usize = 2048;

pub fn spectrogram_cmd(args: SpectrogramArgs) -> Result<()> {
    clapper_plot::format_of(&args.out)?;
    let sig = read_signal(&args.file, args.channel.0)?;
    // A picture has no use for more columns than pixels: a long recording's
    // frames are merged (the loudest of each run), so that memory does not
    // grow with it.
    let s = spectrogram_columns(&sig, args.window, args.overlap, args.range_db, SPECTROGRAM_COLUMNS)?;
    let hop = ((args.window as f64 * (1.0 - args.overlap)).round() as usize).max(1);
    let frames = (sig.samples.len().saturating_sub(args.window)) / hop + 1;
    let title = format!(
        "{}: {} sample windows, {:.0} % overlap, {} dB",
        crate::files::title_name(&args.file),
        args.window,
        args.overlap * 100.0,
        args.range_db
    );
    if args.fmax <= 0.0 {
        anyhow::bail!(
            "--fmax {}: the highest frequency shown must be more than 0 Hz",
            args.fmax
        );
    }
    let p = clapper_plot::SpectrogramPlot {
        title: &title,
        times: &s.times,
        freqs: &s.freqs,
        db: &s.db,
        fmax: args.fmax.min(sig.rate / 2.0),
        range_db: args.range_db,
    };
    crate::files::write_atomically(&args.out, |tmp| Ok(clapper_plot::spectrogram_plot(tmp, &p)?))?;
    let merged = if frames > s.times.len() {
        format!(
            ", drawn as {} columns of the loudest of {}",
            s.times.len(),
            frames.div_ceil(s.times.len())
        )
    } else {
        String::new()
    };
    crate::say!(
        "{frames} frames{merged} x {} bins ({:.1} Hz, {:.1} ms per frame) written to {}",
        s.freqs.len(),
        sig.rate / args.window as f64,
        args.window as f64 / sig.rate * 1e3,
        args.out.display()
    );
    Ok(())
}

#[derive(Args, Debug)]
pub struct DecayArgs {
    /// A recording (.wav or .csv).
    pub file: PathBuf,
    /// The frequency followed (Hz).
    #[arg(long, value_name = "HZ")]
    pub freq: f64,
    /// Window length (samples).
    #[arg(long, default_value_t = 2048)]
    pub window: usize,
    /// Overlap (fraction).
    #[arg(long, default_value_t = 0.75)]
    pub overlap: f64,
    /// Plot the level against time (.svg or .png).
    #[arg(long, value_name = "FILE")]
    pub plot: Option<PathBuf>,
    /// Write the level against time as CSV (`t_s,level_db`); `-` is
    /// standard output.
    #[arg(long, value_name = "FILE")]
    pub csv: Option<PathBuf>,
    /// WAV channel or CSV value column after the time column, counted from 1 (the first).
    #[arg(long, default_value = "1", value_parser = parse_channel)]
    pub channel: ChannelIndex,
    /// Print JSON, with the moment the decay rate changes most (after the
    /// loudest frame): where a resting clapper starts to damp the bell.
    #[arg(long)]
    pub json: bool,
}

pub fn decay(args: DecayArgs) -> Result<()> {
    crate::files::claim_stdout(&[("--csv", args.csv.as_deref())], args.json)?;
    let sig = read_signal(&args.file, args.channel.0)?;
    let report = DecayReport::new(&sig, args.freq, args.window, args.overlap)?;
    if let Some(p) = &args.plot {
        let bin = report.bin_hz;
        line_plot(
            p,
            &format!("Level of the {bin:.1} Hz bin against time (Fig 4)"),
            "time (s)",
            "level (dB re spectrogram maximum)",
            &[Series {
                label: format!("{bin:.1} Hz"),
                // Below the floor is silence, not a level: a gap, not a line at the floor.
                points: report
                    .points
                    .iter()
                    .map(|p| (p[0], if p[1] > report.floor_db { p[1] } else { f64::NAN }))
                    .collect(),
                markers: false,
                dashed: false,
                colour: RGBColor(31, 90, 180),
            }],
        )?;
    }
    if let Some(p) = &args.csv {
        crate::files::write_bytes(p, report.csv())?;
    }
    print_report(&report, args.json, || report.text())
}

#[derive(Args, Debug)]
pub struct ModesArgs {
    /// A recording of a single strike (.wav or .csv).
    pub file: PathBuf,
    /// Report partials within this many dB of the strongest.
    #[arg(long, default_value_t = clapper_app::measure::DEFAULT_MODES_RANGE_DB)]
    pub range_db: f64,
    /// Print JSON.
    #[arg(long)]
    pub json: bool,
    /// WAV channel or CSV value column after the time column, counted from 1 (the first).
    #[arg(long, default_value = "1", value_parser = parse_channel)]
    pub channel: ChannelIndex,
}

pub fn modes(args: ModesArgs) -> Result<()> {
    let sig = read_signal(&args.file, args.channel.0)?;
    let report = ModesReport::new(&sig, args.range_db).with_context(|| args.file.display().to_string())?;
    print_report(&report, args.json, || report.text(&args.file.display().to_string()))
}

#[derive(Args, Debug)]
pub struct ImpulseArgs {
    /// Modes at the strike point: CSV with columns freq_hz,effective_mass_kg.
    #[arg(long, value_name = "FILE")]
    pub modes: PathBuf,
    /// Mass of the clapper ball or hammer (kg).
    #[arg(long, value_name = "KG")]
    pub clapper_mass: f64,
    /// Length of a half-sine contact pulse (ms); default: an ideal impulse.
    #[arg(long, value_name = "T")]
    pub pulse_ms: Option<f64>,
    /// Impulse-hammer aside: the frequency (Hz) a hit must reach cleanly.
    #[arg(long, value_name = "HZ")]
    pub hammer_fmax: Option<f64>,
    /// Plot K against pulse length (.svg or .png).
    #[arg(long, value_name = "FILE")]
    pub plot: Option<PathBuf>,
    /// Print JSON.
    #[arg(long)]
    pub json: bool,
}

pub fn impulse(args: ImpulseArgs) -> Result<()> {
    let modes: Vec<Mode> = read_modes(&args.modes)?;
    let m = args.clapper_mass;
    let report = ImpulseReport::new(&modes, m, args.pulse_ms, args.hammer_fmax)?;
    if let Some(p) = &args.plot {
        let pts = ImpulseReport::k_curve(&modes, m);
        let (x0, x1) = (pts[0].0, pts[pts.len() - 1].0);
        let (title, x, y) = (
            format!("K against pulse length, striker {m} kg ({} modes)", modes.len()),
            "half-sine pulse length (ms, log scale)",
            "K = Σ m/Mₙ |F|² (a clean rebound needs K < 1)",
        );
        let series = [
            Series {
                label: "K".into(),
                points: pts,
                markers: false,
                dashed: false,
                colour: RGBColor(31, 90, 180),
            },
            Series {
                label: "K = 1".into(),
                points: vec![(x0, 1.0), (x1, 1.0)],
                markers: false,
                dashed: false,
                colour: RGBColor(210, 40, 40),
            },
        ];
        line_plot_scaled(p, &title, x, y, &series, true)?;
    }
    print_report(&report, args.json, || report.text())
}
