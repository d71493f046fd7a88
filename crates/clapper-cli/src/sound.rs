//! `clapper synth`: the sound of a rung bell, from the simulation.

use std::path::PathBuf;

use anyhow::{bail, Result};
use clap::Args;
use clapper_app::sound::{synth, Partials, SynthOptions};

use crate::simulate::SimulateArgs;

#[derive(Args, Debug)]
pub struct SynthArgs {
    /// The bell and its ringing: every option of `clapper simulate`.
    #[command(flatten)]
    pub sim: SimulateArgs,
    /// Output WAV (16-bit mono); `-` is standard output (`| aplay`).
    #[arg(long, value_name = "FILE.wav")]
    pub out: PathBuf,
    /// Sample rate (Hz).
    #[arg(long, default_value_t = SynthOptions::default().rate)]
    pub rate: f64,
    /// The handstroke gap: an extra pause before each handstroke after the
    /// first (s). Default 0.25 s, about one blow in a ring of eight.
    #[arg(long, default_value_t = SynthOptions::default().gap)]
    pub gap: f64,
    /// Which partials ring.
    #[arg(long, value_enum, default_value = "lab")]
    pub partials: Partials,
    /// Nominal of the typical partials (Hz).
    #[arg(long, default_value_t = SynthOptions::default().nominal)]
    pub nominal: f64,
    /// Contact pulse length (ms). Default 0.3 ms: the paper measured 0.2 to 0.5 ms.
    #[arg(long, default_value_t = SynthOptions::default().pulse_ms)]
    pub pulse_ms: f64,
    /// How many times faster the bell's modes decay while the clapper rests on it.
    #[arg(long, default_value_t = SynthOptions::default().rest_damping)]
    pub rest_damping: f64,
    /// Output the bell's acceleration (like an accelerometer) instead of its velocity.
    #[arg(long)]
    pub accelerometer: bool,
    /// A single chimed strike (no bounces, no resting clapper) for comparison.
    #[arg(long)]
    pub chime: bool,
    /// Sound after the last stroke (s).
    #[arg(long, default_value_t = SynthOptions::default().tail)]
    pub tail: f64,
}

pub fn run(args: SynthArgs) -> Result<()> {
    crate::files::claim_stdout(&[("--out", Some(&args.out))], args.sim.json)?;
    if !crate::files::is_stdout(&args.out) && !args.out.extension().is_some_and(|e| e.eq_ignore_ascii_case("wav")) {
        bail!(
            "output {} must end in .wav (or be -, standard output)",
            args.out.display()
        );
    }
    // In the option's words, before the synthesis counts samples.
    let rates = clapper_app::strikes::RECORDING_RATES_HZ;
    if !rates.contains(&args.rate) {
        bail!(
            "--rate {} Hz: a sample rate from {} to {} Hz",
            args.rate,
            rates.start(),
            rates.end()
        );
    }
    let opts = SynthOptions {
        rate: args.rate,
        gap: args.gap,
        partials: args.partials,
        nominal: args.nominal,
        pulse_ms: args.pulse_ms,
        rest_damping: args.rest_damping,
        accelerometer: args.accelerometer,
        chime: args.chime,
        tail: args.tail,
    };
    let sound = synth(&args.sim.request(), args.sim.bell_file()?, &opts)?;
    let out = &args.out;
    crate::files::write_atomically(out, |tmp| {
        Ok(clapper_io::signal_file::write_wav(tmp, &sound.signal, 0.9)?)
    })?;
    if args.sim.json {
        crate::say!("{}", serde_json::to_string(&sound.report)?);
    } else {
        crate::say_text!("{}", sound.text(&out.display().to_string()));
    }
    Ok(())
}
