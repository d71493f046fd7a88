//! The sound of a bell rung full circle, from the simulation: every impact
//! gives the bell an impulse, its modes ring, and a resting clapper damps
//! them (`clapper synth`). The stroke-to-impulse physics lives here; the
//! caller writes the signal.

use std::fmt::Write as _;

use clapper_core::prelude::*;
use clapper_core::stroke::Sample;
use clapper_io::LoadedBell;
use clapper_signal::synth::{lab_partials, synthesize, typical_partials, Strike, SynthMode, SynthSpec};
use clapper_signal::Signal;
use serde::{Deserialize, Serialize};

use crate::simulate::SimulateRequest;
use crate::AppError;

/// Lead-in before the first sound (s).
pub(crate) const LEAD_S: f64 = 0.2;

/// Which partials ring.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum Partials {
    /// The lab bell's three measured partials (624, 981, 1310 Hz).
    #[default]
    Lab,
    /// A typical tuned bell (hum to octave nominal) scaled to the nominal.
    Typical,
}

/// What to synthesise besides the simulation.
#[derive(Clone, Debug, PartialEq)]
pub struct SynthOptions {
    /// Sample rate (Hz).
    pub rate: f64,
    /// The handstroke gap: an extra pause before each handstroke after the
    /// first (s). 0.25 s is about one blow in a ring of eight.
    pub gap: f64,
    /// Which partials ring.
    pub partials: Partials,
    /// Nominal of the typical partials (Hz).
    pub nominal: f64,
    /// Contact pulse length (ms); the paper measured 0.2 to 0.5 ms.
    pub pulse_ms: f64,
    /// How many times faster the modes decay while the clapper rests.
    pub rest_damping: f64,
    /// The bell's acceleration (an accelerometer) instead of its velocity.
    pub accelerometer: bool,
    /// A single chimed strike (no bounces, no resting clapper).
    pub chime: bool,
    /// Sound after the last stroke (s).
    pub tail: f64,
}

impl Default for SynthOptions {
    /// `clapper synth`'s defaults: CD rate; a 0.25 s handstroke gap, about
    /// one blow in a ring of eight; the lab bell's partials, with 1310 Hz
    /// (its third partial) as the nominal of the typical ones; a 0.3 ms
    /// pulse (the paper measured 0.2 to 0.5 ms); modes damped 8 times
    /// faster under a resting clapper (Figs 3, 4); 2 s of tail.
    fn default() -> Self {
        Self {
            rate: 44100.0,
            gap: 0.25,
            partials: Partials::Lab,
            nominal: 1310.0,
            pulse_ms: 0.3,
            rest_damping: 8.0,
            accelerometer: false,
            chime: false,
            tail: 2.0,
        }
    }
}

impl SynthOptions {
    /// Refuse a gap, pulse or tail outside 0-600 (s or ms), a nominal
    /// outside 20-20,000 Hz, rest damping outside 1-10,000.
    pub fn check(&self) -> Result<(), AppError> {
        for (flag, v) in [
            ("--gap", self.gap),
            ("--pulse-ms", self.pulse_ms),
            ("--tail", self.tail),
        ] {
            if !(v.is_finite() && (0.0..=600.0).contains(&v)) {
                return Err(AppError::Request(format!("{flag} {v} must be between 0 and 600")));
            }
        }
        // Heard partials: a nominal from a handbell's top to a bourdon's.
        if !(20.0..=20_000.0).contains(&self.nominal) {
            return Err(AppError::Request(format!(
                "--nominal {} Hz: a bell's nominal is from 20 to 20,000 Hz",
                self.nominal
            )));
        }
        if !(1.0..=1e4).contains(&self.rest_damping) {
            return Err(AppError::Request(format!(
                "--rest-damping {}: from 1 (a resting clapper damps nothing) to 10,000 times faster",
                self.rest_damping
            )));
        }
        Ok(())
    }

    /// The modes that ring for `bell`.
    pub fn modes(&self, bell: &Bell) -> Vec<SynthMode> {
        match self.partials {
            Partials::Lab => lab_partials(),
            Partials::Typical => typical_partials(self.nominal, bell.bell_mass),
        }
    }
}

/// One impulse, as reported.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct StrikeReport {
    /// m b |Δφ'| (N s).
    pub impulse_n_s: f64,
    /// When it is heard (s).
    pub t_s: f64,
}

/// One mode, as reported.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ModeReport {
    /// Split of the doublet (Hz).
    pub doublet_split_hz: f64,
    /// Frequency (Hz).
    pub freq_hz: f64,
    /// Q factor.
    pub q: f64,
}

/// What `clapper synth --json` prints (keys alphabetical, as always).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SynthReport {
    /// The bell's name.
    pub bell: String,
    /// Whether it is one chimed strike.
    pub chime: bool,
    /// Length of the sound (s).
    pub duration_s: f64,
    /// When the first strike is heard (s).
    pub first_strike_s: Option<f64>,
    /// The modes that ring.
    pub modes: Vec<ModeReport>,
    /// When the clapper comes to rest after each stroke's first strike (s).
    pub rest_after_first_strike_s: Vec<f64>,
    /// Intervals with the clapper resting on the bell (s).
    pub rests: Vec<[f64; 2]>,
    /// Sample rate (Hz).
    pub sample_rate_hz: f64,
    /// Every impulse.
    pub strikes: Vec<StrikeReport>,
}

/// A synthesised sound and what it holds.
pub struct Synthesis {
    /// The sound.
    pub signal: Signal,
    /// The report.
    pub report: SynthReport,
    /// Strokes simulated.
    pub strokes: usize,
}

impl Synthesis {
    /// The readable summary, for the output file `out`.
    pub fn text(&self, out: &str) -> String {
        let r = &self.report;
        // "2 of lab bell" read as nonsense: the bell first, then what it did.
        let how = if r.chime {
            "chimed once".to_string()
        } else {
            format!(
                "rung full circle, {} stroke{}",
                self.strokes,
                if self.strokes == 1 { "" } else { "s" }
            )
        };
        let mut o = format!(
            "{} {how}: {} impact(s), strikes and bounces, over {:.2} s at {} Hz, written to {out}\n",
            r.bell,
            r.strikes.len(),
            r.duration_s,
            r.sample_rate_hz,
        );
        for (k, t) in r.rest_after_first_strike_s.iter().enumerate() {
            let _ = writeln!(o, "  stroke {}: clapper at rest from {t:.3} s", k + 1);
        }
        o
    }
}

/// Simulate `req` (with the bell file `file` if the caller read one) and
/// synthesise its sound.
pub fn synth(req: &SimulateRequest, file: Option<LoadedBell>, opts: &SynthOptions) -> Result<Synthesis, AppError> {
    let loaded = req.bell(file)?;
    let cfg = req.config_for(&loaded)?;
    let (name, bell) = (loaded.name, loaded.bell);
    opts.check()?;
    let mut rec = TraceRecorder::new(1e-3);
    let ringing = ring(&bell, &cfg, req.style, req.protocol, req.strokes, &mut rec)?;
    // Stroke k (from 0) is heard later by the handstroke gaps before it.
    let offsets: Vec<f64> = (0..ringing.strokes.len())
        .map(|k| LEAD_S + opts.gap * (k / 2) as f64)
        .collect();
    let strikes = heard_strikes(&bell, &ringing, &offsets, opts.pulse_ms * 1e-3);
    let first = *strikes
        .first()
        .ok_or_else(|| AppError::Request("the clapper never struck the bell: nothing to hear".into()))?;
    let end = ringing
        .strokes
        .last()
        .map_or(0.0, |s| s.end.t + offsets[offsets.len() - 1]);
    let duration = end + opts.tail;
    let rests = heard_rests(&rec.samples, &ringing, &offsets, duration);
    let modes = opts.modes(&bell);
    let (strikes, rests, duration) = if opts.chime {
        (vec![Strike { t: LEAD_S, ..first }], vec![], LEAD_S + 3.0 + opts.tail)
    } else {
        (strikes, rests, duration)
    };
    let spec = SynthSpec {
        rate: opts.rate,
        duration,
        modes,
        strikes,
        rests,
        rest_damping: opts.rest_damping,
        acceleration: opts.accelerometer,
    };
    let signal = synthesize(&spec).map_err(|e| AppError::Sound(e.to_string()))?;
    let rest_after: Vec<f64> = ringing
        .strokes
        .iter()
        .enumerate()
        .filter_map(|(k, s)| s.rest_after_strike.map(|m| m.t + offsets[k]))
        .collect();
    let report = SynthReport {
        bell: name,
        chime: opts.chime,
        duration_s: spec.duration,
        first_strike_s: spec.strikes.first().map(|s| s.t),
        modes: spec
            .modes
            .iter()
            .map(|m| ModeReport {
                doublet_split_hz: m.doublet_split_hz,
                freq_hz: m.freq_hz,
                q: m.q,
            })
            .collect(),
        rest_after_first_strike_s: if opts.chime { vec![] } else { rest_after },
        rests: spec.rests.iter().map(|r| [r.0, r.1]).collect(),
        sample_rate_hz: opts.rate,
        strikes: spec
            .strikes
            .iter()
            .map(|s| StrikeReport {
                impulse_n_s: s.impulse,
                t_s: s.t,
            })
            .collect(),
    };
    Ok(Synthesis {
        signal,
        report,
        strokes: ringing.strokes.len(),
    })
}

/// Every impact of `ringing` as a strike heard at its time plus its
/// stroke's offset (`offsets[k]` for stroke k, s): the impulse at the strike
/// point is the clapper's momentum change m b |Δφ'|.
pub(crate) fn heard_strikes(bell: &Bell, ringing: &Ringing, offsets: &[f64], pulse: f64) -> Vec<Strike> {
    ringing
        .strokes
        .iter()
        .enumerate()
        .flat_map(|(k, s)| s.impacts.iter().map(move |i| (k, *i)))
        .map(|(k, i)| Strike {
            t: i.t + offsets[k],
            impulse: bell.clapper_mass * bell.b * (i.phi_dot_before - i.phi_dot_after.unwrap_or(0.0)).abs(),
            pulse,
        })
        .collect()
}

/// The intervals with the clapper resting on the bell, as heard (each
/// sample shifted by its stroke's offset), closed at `end` (s).
pub(crate) fn heard_rests(samples: &[Sample], ringing: &Ringing, offsets: &[f64], end: f64) -> Vec<(f64, f64)> {
    let stroke_of = |t: f64| {
        ringing
            .strokes
            .iter()
            .rposition(|s| s.start.t <= t + 1e-12)
            .unwrap_or(0)
    };
    rests(samples, |t| t + offsets[stroke_of(t)], end)
}

/// Runs of trace samples with a holding force (the clapper on the bell), as
/// heard (`heard` maps simulated time to heard time), closed at `end`.
fn rests(samples: &[Sample], heard: impl Fn(f64) -> f64, end: f64) -> Vec<(f64, f64)> {
    let mut rests: Vec<(f64, f64)> = vec![];
    let mut open: Option<f64> = None;
    for smp in samples {
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
        rests.push((a, end));
    }
    rests
}
