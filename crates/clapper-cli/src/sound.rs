//! `clapper synth`: the sound of a rung bell, from the simulation.

use std::path::PathBuf;

use anyhow::{bail, Context, Result};
use clap::{Args, ValueEnum};
use clapper_core::prelude::*;
use clapper_signal::synth::{lab_partials, synthesize, typical_partials, Strike, SynthMode, SynthSpec};

use crate::simulate::SimulateArgs;

/// Lead-in before the first sound (s).
const LEAD_S: f64 = 0.2;

#[derive(Clone, Copy, Debug, ValueEnum, PartialEq, Eq)]
pub enum PartialsArg {
    /// The lab bell's three measured partials (624, 981, 1310 Hz).
    Lab,
    /// A typical tuned bell (hum to octave nominal) scaled to --nominal.
    Typical,
}

#[derive(Args, Debug)]
pub struct SynthArgs {
    /// The bell and its ringing: every option of `clapper simulate`.
    #[command(flatten)]
    pub sim: SimulateArgs,
    /// Output WAV (16-bit mono).
    #[arg(long, value_name = "FILE.wav")]
    pub out: PathBuf,
    /// Sample rate (Hz).
    #[arg(long, default_value_t = 44100.0)]
    pub rate: f64,
    /// The handstroke gap: an extra pause before each handstroke after the
    /// first (s). Default 0.25 s, about one blow in a ring of eight.
    #[arg(long, default_value_t = 0.25)]
    pub gap: f64,
    /// Which partials ring.
    #[arg(long, value_enum, default_value = "lab")]
    pub partials: PartialsArg,
    /// Nominal of the typical partials (Hz).
    #[arg(long, default_value_t = 1310.0)]
    pub nominal: f64,
    /// Contact pulse length (ms). Default 0.3 ms: the paper measured 0.2 to 0.5 ms.
    #[arg(long, default_value_t = 0.3)]
    pub pulse_ms: f64,
    /// How many times faster the bell's modes decay while the clapper rests on it.
    #[arg(long, default_value_t = 8.0)]
    pub rest_damping: f64,
    /// Output the bell's acceleration (like an accelerometer) instead of its velocity.
    #[arg(long)]
    pub accelerometer: bool,
    /// A single chimed strike (no bounces, no resting clapper) for comparison.
    #[arg(long)]
    pub chime: bool,
    /// Sound after the last stroke (s).
    #[arg(long, default_value_t = 2.0)]
    pub tail: f64,
}

pub fn run(args: SynthArgs) -> Result<()> {
    let req = args.sim.request();
    let loaded = req.bell(args.sim.bell_file()?)?;
    let cfg = req.config()?;
    let (name, bell) = (loaded.name, loaded.bell);
    if !args.out.extension().is_some_and(|e| e.eq_ignore_ascii_case("wav")) {
        bail!("output {} must end in .wav", args.out.display());
    }
    for (flag, v, lo) in [
        ("--gap", args.gap, 0.0),
        ("--pulse-ms", args.pulse_ms, 0.0),
        ("--tail", args.tail, 0.0),
    ] {
        if !(v.is_finite() && v >= lo && v <= 600.0) {
            bail!("{flag} {v} must be between {lo} and 600");
        }
    }
    let protocol = args.sim.protocol;
    let mut rec = TraceRecorder::new(1e-3);
    let ringing =
        ring(&bell, &cfg, args.sim.style, protocol, args.sim.strokes, &mut rec).context("simulation failed")?;
    // Stroke k (from 0) is heard later by the handstroke gaps before it.
    let offset = |k: usize| LEAD_S + args.gap * (k / 2) as f64;
    let stroke_of = |t: f64| {
        ringing
            .strokes
            .iter()
            .rposition(|s| s.start.t <= t + 1e-12)
            .unwrap_or(0)
    };
    let heard = |t: f64| t + offset(stroke_of(t));
    let pulse = args.pulse_ms * 1e-3;
    // The impulse at the strike point: the clapper's momentum change m b |Δφ'|.
    let strikes: Vec<Strike> = ringing
        .strokes
        .iter()
        .enumerate()
        .flat_map(|(k, s)| s.impacts.iter().map(move |i| (k, *i)))
        .map(|(k, i)| Strike {
            t: i.t + offset(k),
            impulse: bell.clapper_mass * bell.b * (i.phi_dot_before - i.phi_dot_after.unwrap_or(0.0)).abs(),
            pulse,
        })
        .collect();
    let first = *strikes
        .first()
        .context("the clapper never struck the bell: nothing to hear")?;
    let end = ringing.strokes.last().map_or(0.0, |s| heard(s.end.t));
    let duration = end + args.tail;
    // Rests: runs of trace samples with a holding force (the clapper on the bell).
    let mut rests: Vec<(f64, f64)> = vec![];
    let mut open: Option<f64> = None;
    for smp in &rec.samples {
        let t = heard(smp.t);
        match (smp.contact_force != 0.0, open) {
            (true, None) => open = Some(t),
            (false, Some(a)) => {
                rests.push((a, t));
                open = None;
            }
            _ => {}
        }
    }
    if let Some(a) = open {
        rests.push((a, duration));
    }
    let modes: Vec<SynthMode> = match args.partials {
        PartialsArg::Lab => lab_partials(),
        PartialsArg::Typical => typical_partials(args.nominal, bell.bell_mass),
    };
    let spec = if args.chime {
        SynthSpec {
            rate: args.rate,
            duration: LEAD_S + 3.0 + args.tail,
            modes,
            strikes: vec![Strike { t: LEAD_S, ..first }],
            rests: vec![],
            rest_damping: args.rest_damping,
            acceleration: args.accelerometer,
        }
    } else {
        SynthSpec {
            rate: args.rate,
            duration,
            modes,
            strikes: strikes.clone(),
            rests: rests.clone(),
            rest_damping: args.rest_damping,
            acceleration: args.accelerometer,
        }
    };
    let sig = synthesize(&spec)?;
    let out = &args.out;
    crate::files::write_atomically(out, |tmp| Ok(clapper_io::signal_file::write_wav(tmp, &sig, 0.9)?))?;
    let rest_after: Vec<f64> = ringing
        .strokes
        .iter()
        .enumerate()
        .filter_map(|(k, s)| s.rest_after_strike.map(|m| m.t + offset(k)))
        .collect();
    if args.sim.json {
        println!(
            "{}",
            serde_json::json!({
                "bell": name, "chime": args.chime, "sample_rate_hz": args.rate, "duration_s": spec.duration,
                "strikes": spec.strikes.iter().map(|s| serde_json::json!({"t_s": s.t, "impulse_n_s": s.impulse})).collect::<Vec<_>>(),
                "rests": spec.rests.iter().map(|r| [r.0, r.1]).collect::<Vec<_>>(),
                "first_strike_s": spec.strikes.first().map(|s| s.t),
                "rest_after_first_strike_s": if args.chime { vec![] } else { rest_after },
                "modes": spec.modes.iter().map(|m| serde_json::json!({"freq_hz": m.freq_hz, "q": m.q, "doublet_split_hz": m.doublet_split_hz})).collect::<Vec<_>>(),
            })
        );
    } else {
        println!(
            "{}: {} of {name}, {} strike(s) over {:.2} s at {} Hz, written to {}",
            if args.chime {
                "chimed strike"
            } else {
                "rung full circle"
            },
            if args.chime { 1 } else { ringing.strokes.len() },
            spec.strikes.len(),
            spec.duration,
            args.rate,
            out.display()
        );
        for (k, t) in rest_after.iter().enumerate().filter(|_| !args.chime) {
            println!("  stroke {}: clapper at rest from {t:.3} s", k + 1);
        }
    }
    Ok(())
}
