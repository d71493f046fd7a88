//! The measurement commands: restitution, contacts, spectrogram, decay,
//! modes, impulse (the paper's Sections 2, 3.2 and 3.3).

use std::path::PathBuf;

use anyhow::{bail, Context, Result};
use clap::Args;
use clapper_core::restitution;
use clapper_core::vibration::{self, Mode};
use clapper_io::signal_file::{read_modes, read_signal};
use clapper_plot::chart::Series;
use clapper_plot::RGBColor;
use clapper_signal::accel::{velocity_jumps, JumpOptions};
use clapper_signal::contacts::{detect, ContactOptions};
use clapper_signal::modes::{find_modes, ModeOptions};
use clapper_signal::spectrogram::spectrogram;

fn line_plot(path: &std::path::Path, title: &str, x: &str, y: &str, series: &[Series]) -> Result<()> {
    crate::files::write_atomically(path, |tmp| Ok(clapper_plot::line_plot(tmp, title, x, y, series)?))
}

/// The jumps of one or more drops (a newtype, so clap takes it as one value).
#[derive(Clone, Debug)]
pub struct Drops(pub Vec<Vec<f64>>);

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
    /// WAV channel (from 0) or CSV value column (from 0 after the time column).
    #[arg(long, default_value_t = 0)]
    pub channel: usize,
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
            let sig = read_signal(p, args.channel)?;
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
    let est = restitution::estimate(&drops)?;
    if let Some(path) = &args.plot {
        let stars: Vec<(f64, f64)> = est
            .ratios
            .iter()
            .flat_map(|r| r.iter().enumerate().map(|(k, v)| (k as f64 + 1.0, *v)))
            .collect();
        let means: Vec<(f64, f64)> = est
            .mean_ratios
            .iter()
            .enumerate()
            .map(|(k, v)| (k as f64 + 1.0, *v))
            .collect();
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
                    colour: RGBColor(120, 120, 120),
                },
                Series {
                    label: "mean of each pair (the paper's circles)".into(),
                    points: means,
                    markers: true,
                    colour: RGBColor(210, 40, 40),
                },
            ],
        )?;
    }
    if args.json {
        println!(
            "{}",
            serde_json::json!({
                "jumps": drops,
                "impact_times_s": times,
                "ratios": est.ratios,
                "mean_ratios": est.mean_ratios,
                "r_equal_loss": est.r_equal_loss,
                "r_lossless_later": est.r_lossless_later,
            })
        );
    } else {
        println!("velocity jumps of {} drop(s)", drops.len());
        for (k, m) in est.mean_ratios.iter().enumerate() {
            println!("  mean ratio dv{}/dv{} = {m:.4}", k + 2, k + 1);
        }
        println!(
            "R if every impact loses the same fraction (21):   {:.4}",
            est.r_equal_loss
        );
        println!(
            "R if the impacts after the first are lossless (23): {:.4}",
            est.r_lossless_later
        );
        println!("(the paper: the truth lies between, probably nearer the second)");
    }
    Ok(())
}

#[derive(Args, Debug)]
pub struct ContactsArgs {
    /// A contact-detector recording (.wav or .csv).
    pub file: PathBuf,
    /// WAV channel or CSV value column.
    #[arg(long, default_value_t = 0)]
    pub channel: usize,
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
    let sig = read_signal(&args.file, args.channel)?;
    if !(args.min_gap_ms.is_finite() && args.min_gap_ms >= 0.0) {
        bail!("--min-gap-ms {} must be >= 0", args.min_gap_ms);
    }
    let opts = ContactOptions {
        contact_is_low: !args.contact_high,
        min_gap_s: args.min_gap_ms * 1e-3,
        ..ContactOptions::default()
    };
    let c = detect(&sig, &opts).with_context(|| args.file.display().to_string())?;
    let n = sig.samples.len();
    let t = |i: usize| c.time(i);
    if args.json {
        println!(
            "{}",
            serde_json::json!({
                "sample_rate_hz": sig.rate,
                "contacts": c.intervals.iter().map(|&(a, b)| serde_json::json!({
                    "contact_s": t(a), "separation_s": if b < n { Some(t(b)) } else { None },
                    "duration_ms": (b - a) as f64 / sig.rate * 1e3,
                })).collect::<Vec<_>>(),
                "bounces": c.bounces().len(),
                "time_to_rest_s": c.time_to_rest(),
                "liftoff_s": c.liftoff(n),
            })
        );
    } else {
        println!(
            "{}: {} contact(s) at {} Hz",
            args.file.display(),
            c.intervals.len(),
            sig.rate
        );
        for (k, &(a, b)) in c.intervals.iter().enumerate() {
            let tag = if Some(k) == c.rest { "  <- at rest" } else { "" };
            let sep = if b < n {
                format!("{:.5} s", t(b))
            } else {
                "end of recording".into()
            };
            println!(
                "  contact {:>3}: {:.5} s to {sep} ({:.2} ms){tag}",
                k + 1,
                t(a),
                (b - a) as f64 / sig.rate * 1e3
            );
        }
        println!("bounces before rest: {}", c.bounces().len());
        match c.time_to_rest() {
            Some(r) => println!("time to rest: {r:.4} s after the first contact"),
            None => println!("time to rest: the clapper did not come to rest"),
        }
        if let Some(l) = c.liftoff(n) {
            println!("lift-off: {l:.4} s");
        }
    }
    Ok(())
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
    /// WAV channel or CSV value column.
    #[arg(long, default_value_t = 0)]
    pub channel: usize,
}

pub fn spectrogram_cmd(args: SpectrogramArgs) -> Result<()> {
    clapper_plot::format_of(&args.out)?;
    let sig = read_signal(&args.file, args.channel)?;
    let s = spectrogram(&sig, args.window, args.overlap, args.range_db)?;
    let title = format!(
        "{}: {} sample windows, {:.0} % overlap, {} dB",
        args.file.display(),
        args.window,
        args.overlap * 100.0,
        args.range_db
    );
    let p = clapper_plot::SpectrogramPlot {
        title: &title,
        times: &s.times,
        freqs: &s.freqs,
        db: &s.db,
        fmax: args.fmax.min(sig.rate / 2.0),
        range_db: args.range_db,
    };
    crate::files::write_atomically(&args.out, |tmp| Ok(clapper_plot::spectrogram_plot(tmp, &p)?))?;
    println!(
        "{} frames x {} bins ({:.1} Hz, {:.1} ms per frame) written to {}",
        s.times.len(),
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
    /// WAV channel or CSV value column.
    #[arg(long, default_value_t = 0)]
    pub channel: usize,
    /// Print JSON, with the moment the decay rate changes most (after the
    /// loudest frame): where a resting clapper starts to damp the bell.
    #[arg(long)]
    pub json: bool,
}

pub fn decay(args: DecayArgs) -> Result<()> {
    let sig = read_signal(&args.file, args.channel)?;
    if !(args.freq.is_finite() && args.freq > 0.0 && args.freq < sig.rate / 2.0) {
        bail!(
            "--freq {} Hz must lie between 0 and {} Hz (half the sample rate)",
            args.freq,
            sig.rate / 2.0
        );
    }
    let s = spectrogram(&sig, args.window, args.overlap, 120.0)?;
    let d = s.decay(args.freq);
    let bin = s.freqs[s.bin_of(args.freq)];
    if let Some(p) = &args.plot {
        line_plot(
            p,
            &format!("Level of the {bin:.1} Hz bin against time (Fig 4)"),
            "time (s)",
            "level (dB re spectrogram maximum)",
            &[Series {
                label: format!("{bin:.1} Hz"),
                points: d.clone(),
                markers: false,
                colour: RGBColor(31, 90, 180),
            }],
        )?;
    }
    let loudest = d.iter().max_by(|a, b| a.1.total_cmp(&b.1)).map_or(0.0, |p| p.0);
    let change = clapper_signal::synth::decay_change(&d, loudest);
    if args.json {
        println!(
            "{}",
            serde_json::json!({
                "bin_hz": bin,
                "points": d.iter().map(|p| [p.0, p.1]).collect::<Vec<_>>(),
                "rate_change": change.map(|(t, a, b)| serde_json::json!({"t_s": t, "before_db_per_s": a, "after_db_per_s": b})),
            })
        );
        return Ok(());
    }
    println!("t_s,level_db  # bin {bin:.2} Hz");
    for (t, l) in &d {
        println!("{t:.5},{l:.2}");
    }
    if let Some((t, a, b)) = change {
        println!("# the decay changes most at {t:.3} s: from {a:.1} to {b:.1} dB/s");
    }
    Ok(())
}

#[derive(Args, Debug)]
pub struct ModesArgs {
    /// A recording of a single strike (.wav or .csv).
    pub file: PathBuf,
    /// Report partials within this many dB of the strongest.
    #[arg(long, default_value_t = 30.0)]
    pub range_db: f64,
    /// Print JSON.
    #[arg(long)]
    pub json: bool,
    /// WAV channel or CSV value column.
    #[arg(long, default_value_t = 0)]
    pub channel: usize,
}

pub fn modes(args: ModesArgs) -> Result<()> {
    let sig = read_signal(&args.file, args.channel)?;
    let opts = ModeOptions {
        range_db: args.range_db,
        ..ModeOptions::default()
    };
    let m = find_modes(&sig, &opts).with_context(|| args.file.display().to_string())?;
    if args.json {
        println!(
            "{}",
            serde_json::json!({
                "modes": m.iter().map(|p| serde_json::json!({
                    "freq_hz": p.freq_hz, "q": p.q, "level_db": p.level_db, "doublet_with_hz": p.doublet_with,
                })).collect::<Vec<_>>()
            })
        );
    } else {
        println!("{} partial(s) of {}:", m.len(), args.file.display());
        println!("  {:>10} {:>8} {:>9}  note", "freq (Hz)", "Q", "level dB");
        for p in &m {
            println!(
                "  {:>10.2} {:>8} {:>9.1}  {}",
                p.freq_hz,
                p.q.map_or("-".into(), |q| format!("{q:.0}")),
                p.level_db,
                p.doublet_with.map_or(String::new(), |f| format!(
                    "doublet with {f:.2} Hz: beats at {:.2} Hz",
                    (f - p.freq_hz).abs()
                ))
            );
        }
    }
    Ok(())
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
    if !(m.is_finite() && m > 0.0) {
        bail!("--clapper-mass {m} kg must be a finite number > 0");
    }
    let tau = match args.pulse_ms {
        Some(t) if t.is_finite() && t >= 0.0 => t * 1e-3,
        Some(t) => bail!("--pulse-ms {t} must be >= 0"),
        None => 0.0,
    };
    let k = vibration::k_factor(&modes, m, tau);
    let shortest = vibration::shortest_clean_pulse(&modes, m);
    let strong = vibration::strongly_excited(&modes, tau);
    let hammer = args.hammer_fmax.map(|f| {
        let t = vibration::longest_pulse_for(f);
        (f, t, vibration::heaviest_clean_hammer(&modes, t))
    });
    if let Some(p) = &args.plot {
        // Log axis by hand: x is log10 of the pulse length in ms, 1 µs to 10 ms.
        let pts: Vec<(f64, f64)> = (0..=400)
            .map(|i| {
                let lg = -3.0 + 4.0 * i as f64 / 400.0;
                (lg, vibration::k_factor(&modes, m, 10f64.powf(lg) * 1e-3).min(10.0))
            })
            .collect();
        let (x0, x1) = (pts[0].0, pts[pts.len() - 1].0);
        line_plot(
            p,
            &format!("K against pulse length, striker {m} kg ({} modes)", modes.len()),
            "log10 of the half-sine pulse length in ms (-3 = 1 us, 0 = 1 ms)",
            "K = sum of m/M_n |F|^2 (clean rebound needs K < 1)",
            &[
                Series {
                    label: "K".into(),
                    points: pts,
                    markers: false,
                    colour: RGBColor(31, 90, 180),
                },
                Series {
                    label: "K = 1".into(),
                    points: vec![(x0, 1.0), (x1, 1.0)],
                    markers: false,
                    colour: RGBColor(210, 40, 40),
                },
            ],
        )?;
    }
    let lambda = vibration::lambda(k);
    if args.json {
        println!(
            "{}",
            serde_json::json!({
                "pulse_ms": tau * 1e3, "k": k, "lambda": lambda, "r": vibration::restitution(k),
                "clean_rebound": lambda >= 0.0,
                "shortest_clean_pulse_ms": shortest.map(|s| s * 1e3),
                "strongly_excited_modes": strong,
                "hammer": hammer.map(|(f, t, mh)| serde_json::json!({"fmax_hz": f, "longest_pulse_ms": t * 1e3, "heaviest_clean_hammer_kg": mh})),
            })
        );
    } else {
        println!(
            "{} mode(s), striker {m} kg, pulse {:.3} ms (half-sine; 0 = ideal impulse)",
            modes.len(),
            tau * 1e3
        );
        println!(
            "  K = {k:.4}, lambda = v1/v0 = {lambda:.4}, R = {:.4}{}",
            vibration::restitution(k),
            if lambda < 0.0 { " (no clean rebound: K > 1)" } else { "" }
        );
        println!("  modes strongly excited (|F|^2 >= 1/2): {strong}");
        match shortest {
            Some(0.0) => println!("  any pulse, even an ideal impulse, rebounds cleanly (K <= 1)"),
            Some(s) => println!("  shortest pulse for a clean rebound: {:.4} ms", s * 1e3),
            None => println!("  no pulse length gives a clean rebound: the striker is too heavy"),
        }
        if let Some((f, t, mh)) = hammer {
            println!("  hammer to reach {f} Hz: pulse at most {:.4} ms (a hard tip), hammer at most {mh:.3} kg for a clean single hit", t * 1e3);
        }
    }
    Ok(())
}
