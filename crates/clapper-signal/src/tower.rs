//! A synthetic tower recording with known truth (synthetic, made by the
//! project): a ring of bells rung in rounds, handstroke and backstroke, each
//! strike's time known, with chosen odd-struckness, striking errors and
//! double strikes. The test data for finding strikes in a recording
//! (`clapper strikes`, issue 19); never a real tower's sound.
//!
//! Rows: `interval` between successive bells, and a handstroke gap of
//! `handstroke_gap` intervals before each handstroke row but the first.
//! Rows alternate handstroke (rows 0, 2, ...) and backstroke. The bells
//! ring rounds (bell 1, the treble, first in every row) or plain hunt.
//!
//! Each bell's voice is a tuned bell's partials (hum to the octave nominal
//! and two upper partials), each detuned and made louder or softer at
//! random within the spec's [`Variation`]; the ring can be heard in a
//! [`Room`] (an exponentially decaying reverberation) and with white noise
//! at a chosen signal-to-noise ratio.

use std::f64::consts::PI;

use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;
use realfft::RealFftPlanner;

use crate::synth::{synthesize, Strike, SynthMode, SynthSpec};
use crate::{Signal, SignalError};

/// One bell of the ring.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RingBell {
    /// Nominal frequency (Hz): the partials are [`typical_partials`](crate::synth::typical_partials) scaled to it.
    pub nominal_hz: f64,
    /// Mass (kg): sets the partials' effective masses and the strike's impulse.
    pub mass_kg: f64,
    /// Handstroke minus backstroke (ms): handstrokes come half of it late,
    /// backstrokes half of it early.
    pub odd_struck_ms: f64,
}

/// A double strike put in: the clapper strikes the bell again.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DoubleStrikeSpec {
    /// Bell, counting from 1 (the treble).
    pub bell: usize,
    /// Row, counting from 0 (a handstroke).
    pub row: usize,
    /// Delay after the strike (ms).
    pub delay_ms: f64,
    /// The second strike's impulse over the first's.
    pub amplitude_ratio: f64,
}

/// What to synthesise.
#[derive(Clone, Debug, PartialEq)]
pub struct TowerSpec {
    /// Sample rate (Hz).
    pub rate: f64,
    /// The bells, treble first.
    pub bells: Vec<RingBell>,
    /// Rows rung (handstroke first).
    pub rows: usize,
    /// Time between successive bells in a row (s); about 0.25 s for eight
    /// bells (a 2 s row with its gap at a tenor of about 15 cwt).
    pub interval: f64,
    /// The handstroke gap, in intervals (1 in good striking).
    pub handstroke_gap: f64,
    /// Striking errors: each strike moved by a uniform random amount within
    /// ± this (s), from `seed`.
    pub jitter: f64,
    /// The seed of the striking errors (the same seed, the same recording).
    pub seed: u64,
    /// Double strikes put in.
    pub doubles: Vec<DoubleStrikeSpec>,
    /// Silence before the first strike (s).
    pub lead_in: f64,
    /// Ringing after the last strike (s).
    pub tail: f64,
    /// What the bells ring.
    pub method: Method,
    /// How far each bell's partials stray from the typical tuned bell.
    pub variation: Variation,
    /// The room the ring is heard in; `None`: no reverberation.
    pub room: Option<Room>,
    /// Signal-to-noise ratio (dB): white noise whose power is this far
    /// below the mean power of the ringing; `None`: no noise.
    pub snr_db: Option<f64>,
}

impl TowerSpec {
    /// `bells` ringing rounds: 24 rows at 22.05 kHz (room for the upper
    /// partials of a 1.4 kHz treble), 0.22 s between bells and a handstroke
    /// gap of one interval (a good band on a light eight), striking errors
    /// within ±15 ms (seed 1), one second's silence before and two of ringing
    /// after, partials straying as tuned bells' do ([`Variation::TUNED`]), no
    /// double strikes, room or noise. Change what a test needs with
    /// `TowerSpec { rows: 40, ..TowerSpec::new(bells) }`.
    pub fn new(bells: Vec<RingBell>) -> Self {
        TowerSpec {
            rate: 22_050.0,
            bells,
            rows: 24,
            interval: 0.22,
            handstroke_gap: 1.0,
            jitter: 0.015,
            seed: 1,
            doubles: vec![],
            lead_in: 1.0,
            tail: 2.0,
            method: Method::Rounds,
            variation: Variation::TUNED,
            room: None,
            snr_db: None,
        }
    }
}

/// What the bells ring.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    /// Rounds in every row.
    Rounds,
    /// Two rows of rounds, then plain hunt (every bell moves one place a
    /// row, leading and lying behind for two), back to rounds and again.
    PlainHunt,
}

/// How far a bell's partials stray from the typical tuned bell, drawn per
/// bell and partial from the spec's seed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Variation {
    /// Each partial's frequency moved by a uniform amount within ± this
    /// (cents; the nominal too, but the nominal heard is the one stated).
    pub detune_cents: f64,
    /// Each partial's strength moved by a uniform amount within ± this (dB).
    pub strength_db: f64,
}

impl Variation {
    /// Every bell exactly the typical tuned bell.
    pub const NONE: Variation = Variation {
        detune_cents: 0.0,
        strength_db: 0.0,
    };
    /// As real tuned bells stray: partials within ±15 cents (a tuner's
    /// tolerance on the lower partials) and ±3 dB.
    pub const TUNED: Variation = Variation {
        detune_cents: 15.0,
        strength_db: 3.0,
    };
}

/// A ring of `bells` (1 to 16) tuned to a major scale down from the
/// treble's nominal `treble_hz` (Hz), heavier down the ring (mass as the
/// cube of size, 150 kg for the treble); none odd-struck. `None` for more
/// than 16 bells.
pub fn major_scale(bells: usize, treble_hz: f64) -> Option<Vec<RingBell>> {
    const SCALE: [i32; 16] = [0, 2, 4, 5, 7, 9, 11, 12, 14, 16, 17, 19, 21, 23, 24, 26];
    (bells <= SCALE.len()).then(|| {
        SCALE[..bells]
            .iter()
            .map(|&s| RingBell {
                nominal_hz: treble_hz * 2f64.powf(-f64::from(s) / 12.0),
                mass_kg: 150.0 * 2f64.powf(f64::from(s) / 4.0),
                odd_struck_ms: 0.0,
            })
            .collect()
    })
}

/// The room: an impulse response of the direct sound and, after a
/// pre-delay, exponentially decaying noise.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Room {
    /// Reverberation time (s): the tail falls 60 dB in this time.
    pub rt60_s: f64,
    /// Direct sound over reverberant sound, by energy (dB).
    pub direct_to_reverb_db: f64,
    /// Delay of the first reflection after the direct sound (ms).
    pub predelay_ms: f64,
}

impl Room {
    /// A ringing chamber of reverberation time `rt60_s` (s), heard a few
    /// metres from the bells: the direct sound 3 dB over the reverberant,
    /// the first reflection 15 ms after it (walls about 2.5 m away).
    pub fn chamber(rt60_s: f64) -> Self {
        Room {
            rt60_s,
            direct_to_reverb_db: 3.0,
            predelay_ms: 15.0,
        }
    }
}

/// A strike as put into the recording.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrueStrike {
    /// Bell, counting from 1.
    pub bell: usize,
    /// Row, counting from 0.
    pub row: usize,
    /// Place in the row, counting from 1.
    pub place: usize,
    /// Handstroke (else backstroke).
    pub hand: bool,
    /// Time of the strike (s).
    pub t: f64,
    /// The ideal time: the even rhythm without errors or odd-struckness (s).
    pub ideal_t: f64,
    /// A double strike: (delay s, amplitude ratio).
    pub double: Option<(f64, f64)>,
}

/// Most bells in a ring: beyond any tower.
pub const MAX_BELLS: usize = 64;

fn check(spec: &TowerSpec) -> Result<(), SignalError> {
    let bad = |what: String| Err(SignalError::Option(what));
    if spec.bells.is_empty() || spec.bells.len() > MAX_BELLS {
        return bad(format!("{} bells: 1 to {MAX_BELLS}", spec.bells.len()));
    }
    if spec.rows == 0 {
        return bad("0 rows: at least one".into());
    }
    let nonneg = [spec.handstroke_gap, spec.jitter, spec.lead_in, spec.tail];
    if !(spec.interval.is_finite() && spec.interval > 0.0) || nonneg.iter().any(|v| !(v.is_finite() && *v >= 0.0)) {
        return bad("interval > 0 s; handstroke gap, jitter, lead-in and tail >= 0".into());
    }
    if 2.0 * spec.jitter >= spec.interval {
        return bad(format!(
            "jitter {} s: under half the interval, so bells keep their places",
            spec.jitter
        ));
    }
    for b in &spec.bells {
        if !(b.nominal_hz > 0.0 && b.mass_kg > 0.0 && b.odd_struck_ms.is_finite()) {
            return bad(format!("bell {b:?}: nominal and mass > 0"));
        }
        if b.odd_struck_ms.abs() * 1e-3 >= spec.interval {
            return bad(format!("odd-struckness {} ms: under the interval", b.odd_struck_ms));
        }
    }
    let v = spec.variation;
    let detune_ok = v.detune_cents.is_finite() && (0.0..=100.0).contains(&v.detune_cents);
    let strength_ok = v.strength_db.is_finite() && (0.0..=20.0).contains(&v.strength_db);
    if !(detune_ok && strength_ok) {
        return bad(format!("variation {v:?}: 0 to 100 cents and 0 to 20 dB"));
    }
    if let Some(r) = spec.room {
        let ok = r.rt60_s.is_finite()
            && r.rt60_s > 0.0
            && r.rt60_s <= 10.0
            && r.direct_to_reverb_db.is_finite()
            && r.predelay_ms.is_finite()
            && (0.0..=200.0).contains(&r.predelay_ms);
        if !ok {
            return bad(format!(
                "room {r:?}: reverberation 0 to 10 s, pre-delay 0 to 200 ms, a finite direct-to-reverberant ratio"
            ));
        }
    }
    if let Some(snr) = spec.snr_db {
        if !(snr.is_finite() && snr > -20.0) {
            return bad(format!("SNR {snr} dB: above -20 dB"));
        }
    }
    for d in &spec.doubles {
        let ok = (1..=spec.bells.len()).contains(&d.bell)
            && d.row < spec.rows
            && d.delay_ms > 0.0
            && d.delay_ms < 1000.0
            && d.amplitude_ratio > 0.0
            && d.amplitude_ratio <= 1.0;
        if !ok {
            return bad(format!(
                "double strike {d:?}: a bell and row of the ring, delay 0 to 1000 ms, ratio in (0, 1]"
            ));
        }
    }
    Ok(())
}

/// The strikes of `spec`, in time order.
pub fn tower_strikes(spec: &TowerSpec) -> Result<Vec<TrueStrike>, SignalError> {
    check(spec)?;
    let n = spec.bells.len();
    let mut rng = Pcg64::seed_from_u64(spec.seed);
    let mut out = vec![];
    let mut order: Vec<usize> = (0..n).collect();
    for row in 0..spec.rows {
        let hand = row % 2 == 0;
        if spec.method == Method::PlainHunt && row >= 2 {
            // Swap pairs from the lead on even changes, from second place on odd.
            for k in ((row % 2)..n.saturating_sub(1)).step_by(2) {
                order.swap(k, k + 1);
            }
        }
        let row_start = spec.lead_in + spec.interval * ((row * n) as f64 + (row / 2) as f64 * spec.handstroke_gap);
        for (i, b) in spec.bells.iter().enumerate() {
            let place = order.iter().position(|&x| x == i).unwrap_or(i);
            let ideal_t = row_start + place as f64 * spec.interval;
            let odd = 0.5e-3 * b.odd_struck_ms * if hand { 1.0 } else { -1.0 };
            let error = if spec.jitter > 0.0 {
                rng.random_range(-spec.jitter..spec.jitter)
            } else {
                0.0
            };
            let double = spec
                .doubles
                .iter()
                .find(|d| d.bell == i + 1 && d.row == row)
                .map(|d| (d.delay_ms * 1e-3, d.amplitude_ratio));
            out.push(TrueStrike {
                bell: i + 1,
                row,
                place: place + 1,
                hand,
                t: ideal_t + odd + error,
                ideal_t,
                double,
            });
        }
    }
    out.sort_by(|a, b| a.t.total_cmp(&b.t));
    Ok(out)
}

/// A tuned bell's partials as (ratio to the nominal, Q, strength relative
/// to the nominal's): hum, prime, tierce, quint, nominal, superquint,
/// octave nominal, and two upper partials. The nominal dominates a strike's
/// sound and the quint is weak, as in a typical English bell; the upper
/// partials die away fastest.
pub const TUNED_PARTIALS: [(f64, f64, f64); 9] = [
    (0.25, 3000.0, 0.35),
    (0.5, 2500.0, 0.45),
    (0.5946, 2000.0, 0.55),
    (0.75, 1800.0, 0.2),
    (1.0, 1500.0, 1.0),
    (1.5, 1200.0, 0.45),
    (2.0, 1000.0, 0.35),
    (2.52, 800.0, 0.25),
    (3.0, 600.0, 0.2),
];

/// One bell's partials as heard: [`TUNED_PARTIALS`] scaled to the nominal,
/// each moved within `variation` by `rng`; partials at or above 0.45 of
/// the sample rate are left out. Strength is set through the effective
/// mass (a third of the bell's mass for the nominal).
pub fn bell_voice(b: &RingBell, variation: Variation, rate: f64, rng: &mut Pcg64) -> Vec<SynthMode> {
    let mut out = vec![];
    for &(ratio, q, strength) in &TUNED_PARTIALS {
        let cents = if variation.detune_cents > 0.0 && ratio != 1.0 {
            rng.random_range(-variation.detune_cents..variation.detune_cents)
        } else {
            0.0
        };
        let db = if variation.strength_db > 0.0 {
            rng.random_range(-variation.strength_db..variation.strength_db)
        } else {
            0.0
        };
        let freq_hz = b.nominal_hz * ratio * 2f64.powf(cents / 1200.0);
        if freq_hz >= 0.45 * rate {
            continue;
        }
        out.push(SynthMode {
            freq_hz,
            q,
            effective_mass: b.mass_kg / 3.0 / (strength * 10f64.powf(db / 20.0)),
            doublet_split_hz: 0.5,
        });
    }
    out
}

/// The recording (the sum of every bell's sound, in its room, with its
/// noise, its peak scaled to 0.5) and the strikes in it, in time order.
pub fn tower_recording(spec: &TowerSpec) -> Result<(Signal, Vec<TrueStrike>), SignalError> {
    let strikes = tower_strikes(spec)?;
    let end = strikes
        .iter()
        .map(|s| s.t + s.double.map_or(0.0, |d| d.0))
        .fold(0.0, f64::max)
        + spec.tail;
    // Voices, room and noise draw from their own streams, so changing one
    // leaves the others (and the strike times) as they were.
    let mut voice_rng = Pcg64::seed_from_u64(spec.seed ^ 0x5eed_0001);
    let mut mix: Vec<f64> = vec![];
    for (i, b) in spec.bells.iter().enumerate() {
        // An impulse of a tenth of the bell's mass (N s) sets its nominal
        // moving at 0.3 m/s, whatever the bell's size.
        let impulse = 0.1 * b.mass_kg;
        let mut hits = vec![];
        for s in strikes.iter().filter(|s| s.bell == i + 1) {
            hits.push(Strike {
                t: s.t,
                impulse,
                pulse: 0.0,
            });
            if let Some((delay, ratio)) = s.double {
                hits.push(Strike {
                    t: s.t + delay,
                    impulse: impulse * ratio,
                    pulse: 0.0,
                });
            }
        }
        let sound = synthesize(&SynthSpec {
            rate: spec.rate,
            duration: end,
            modes: bell_voice(b, spec.variation, spec.rate, &mut voice_rng),
            strikes: hits,
            rests: vec![],
            rest_damping: 1.0,
            acceleration: false,
        })?;
        if mix.is_empty() {
            mix = sound.samples;
        } else {
            for (m, s) in mix.iter_mut().zip(&sound.samples) {
                *m += s;
            }
        }
    }
    if let Some(room) = spec.room {
        let ir = room_response(room, spec.rate, &mut Pcg64::seed_from_u64(spec.seed ^ 0x5eed_0002));
        mix = convolve(&mix, &ir);
        mix.truncate((end * spec.rate).round() as usize);
    }
    if let Some(snr) = spec.snr_db {
        // The ringing's mean power, from the first strike on.
        let from = ((strikes.first().map_or(0.0, |s| s.t)) * spec.rate) as usize;
        let ringing = &mix[from.min(mix.len())..];
        let power = ringing.iter().map(|v| v * v).sum::<f64>() / ringing.len().max(1) as f64;
        let sd = (power / 10f64.powf(snr / 10.0)).sqrt();
        let mut rng = Pcg64::seed_from_u64(spec.seed ^ 0x5eed_0003);
        for m in &mut mix {
            *m += sd * gaussian(&mut rng);
        }
    }
    let peak = mix.iter().fold(0.0f64, |p, v| p.max(v.abs()));
    if peak > 0.0 {
        for m in &mut mix {
            *m *= 0.5 / peak;
        }
    }
    Ok((
        Signal {
            rate: spec.rate,
            samples: mix,
        },
        strikes,
    ))
}

/// A standard normal deviate (Box–Muller).
pub(crate) fn gaussian(rng: &mut Pcg64) -> f64 {
    let u: f64 = 1.0 - rng.random::<f64>();
    let v: f64 = rng.random::<f64>();
    (-2.0 * u.ln()).sqrt() * (2.0 * PI * v).cos()
}

/// The room's impulse response: 1 at time 0, then from the pre-delay
/// Gaussian noise under an envelope falling 60 dB in RT60, scaled so that
/// its energy is the direct sound's less the direct-to-reverberant ratio.
pub(crate) fn room_response(room: Room, rate: f64, rng: &mut Pcg64) -> Vec<f64> {
    let start = (room.predelay_ms * 1e-3 * rate).round().max(1.0) as usize;
    let len = start + (room.rt60_s * rate).ceil() as usize;
    let mut ir = vec![0.0; len];
    ir[0] = 1.0;
    // Amplitude falls 60 dB (a factor 1000) in RT60.
    let k = 1000f64.ln() / (room.rt60_s * rate);
    for (i, v) in ir.iter_mut().enumerate().skip(start) {
        *v = gaussian(rng) * (-k * (i - start) as f64).exp();
    }
    let tail: f64 = ir[start..].iter().map(|v| v * v).sum();
    let want = 10f64.powf(-room.direct_to_reverb_db / 10.0);
    if tail > 0.0 {
        let g = (want / tail).sqrt();
        for v in &mut ir[start..] {
            *v *= g;
        }
    }
    ir
}

/// Linear convolution by FFT, in blocks (overlap-add).
pub(crate) fn convolve(x: &[f64], h: &[f64]) -> Vec<f64> {
    if x.is_empty() || h.is_empty() {
        return vec![];
    }
    let n = (2 * h.len()).next_power_of_two().max(4096);
    let block = n - h.len() + 1;
    let mut planner = RealFftPlanner::<f64>::new();
    let fwd = planner.plan_fft_forward(n);
    let inv = planner.plan_fft_inverse(n);
    let mut hbuf = fwd.make_input_vec();
    hbuf[..h.len()].copy_from_slice(h);
    let mut hspec = fwd.make_output_vec();
    fwd.process(&mut hbuf, &mut hspec).expect("sizes from the planner");
    let mut out = vec![0.0; x.len() + h.len() - 1];
    let mut buf = fwd.make_input_vec();
    let mut spec = fwd.make_output_vec();
    for (b, chunk) in x.chunks(block).enumerate() {
        buf.iter_mut().for_each(|v| *v = 0.0);
        buf[..chunk.len()].copy_from_slice(chunk);
        fwd.process(&mut buf, &mut spec).expect("sizes from the planner");
        for (s, hs) in spec.iter_mut().zip(&hspec) {
            *s *= hs;
        }
        // The product of two real signals' spectra is real at 0 and Nyquist.
        spec[0].im = 0.0;
        if let Some(last) = spec.last_mut() {
            last.im = 0.0;
        }
        inv.process(&mut spec, &mut buf).expect("sizes from the planner");
        let at = b * block;
        let take = (chunk.len() + h.len() - 1).min(out.len() - at);
        for (o, v) in out[at..at + take].iter_mut().zip(&buf) {
            *o += v / n as f64;
        }
    }
    out
}

/// How well strikes heard match the truth.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Score {
    /// True strikes heard as their own bell within the tolerance.
    pub found: usize,
    /// True strikes not heard.
    pub missed: usize,
    /// Strikes heard that match no true strike of their bell.
    pub false_strikes: usize,
    /// Strikes heard near a true strike of another bell only (a wrong label).
    pub wrong_bell: usize,
    /// Onset errors of the strikes found (heard − true, s).
    pub onset_errors: Vec<f64>,
    /// Double strikes put in and heard.
    pub doubles_found: usize,
    /// Double strikes put in.
    pub doubles_put: usize,
    /// Double strikes heard where none was put.
    pub false_doubles: usize,
    /// Errors of the doubles found: (delay heard − true, s; ratio heard − true).
    pub double_errors: Vec<(f64, f64)>,
}

impl Score {
    /// Strikes found over strikes put in.
    pub fn recall(&self) -> f64 {
        self.found as f64 / (self.found + self.missed).max(1) as f64
    }
    /// Strikes heard that are right over strikes heard.
    pub fn precision(&self) -> f64 {
        self.found as f64 / (self.found + self.false_strikes).max(1) as f64
    }
}

/// A strike heard, to score: bell, onset (s), double (delay s, ratio).
pub type HeardTimes = (usize, f64, Option<(f64, f64)>);

/// Match heard strikes (bell, onset s, double (delay s, ratio)) to the
/// truth: a heard strike matches the nearest true strike of its bell
/// within `tolerance` (s), each true strike at most once.
pub fn score(heard: &[HeardTimes], truth: &[TrueStrike], tolerance: f64) -> Score {
    let mut sc = Score::default();
    let mut used = vec![false; truth.len()];
    for &(bell, t, double) in heard {
        let best = truth
            .iter()
            .enumerate()
            .filter(|(k, s)| s.bell == bell && !used[*k] && (s.t - t).abs() <= tolerance)
            .min_by(|a, b| (a.1.t - t).abs().total_cmp(&(b.1.t - t).abs()));
        match best {
            Some((k, s)) => {
                used[k] = true;
                sc.found += 1;
                sc.onset_errors.push(t - s.t);
                match (s.double, double) {
                    (Some(d), Some(h)) => {
                        sc.doubles_found += 1;
                        sc.double_errors.push((h.0 - d.0, h.1 - d.1));
                    }
                    (None, Some(_)) => sc.false_doubles += 1,
                    _ => {}
                }
            }
            None => {
                sc.false_strikes += 1;
                if truth.iter().any(|s| s.bell != bell && (s.t - t).abs() <= tolerance) {
                    sc.wrong_bell += 1;
                }
            }
        }
    }
    sc.missed = used.iter().filter(|u| !**u).count();
    sc.doubles_put = truth.iter().filter(|s| s.double.is_some()).count();
    sc
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ring(n: usize) -> TowerSpec {
        TowerSpec {
            rate: 16_000.0,
            bells: (0..n)
                .map(|i| RingBell {
                    // A major scale down from the treble.
                    nominal_hz: 1200.0 * 2f64.powf(-[0, 2, 4, 5, 7, 9, 11, 12][i % 8] as f64 / 12.0),
                    mass_kg: 200.0 * (1.0 + i as f64),
                    odd_struck_ms: 0.0,
                })
                .collect(),
            rows: 4,
            interval: 0.25,
            handstroke_gap: 1.0,
            jitter: 0.0,
            seed: 1,
            doubles: vec![],
            lead_in: 0.5,
            tail: 1.0,
            method: Method::Rounds,
            variation: Variation::NONE,
            room: None,
            snr_db: None,
        }
    }

    #[test]
    fn rounds_keep_their_rhythm_and_the_handstroke_gap() {
        let spec = ring(6);
        let s = tower_strikes(&spec).unwrap();
        assert_eq!(s.len(), 24);
        // Bells in order within each row, rows alternating hand and back.
        for (k, st) in s.iter().enumerate() {
            assert_eq!((st.bell, st.row, st.hand), (k % 6 + 1, k / 6, (k / 6) % 2 == 0));
        }
        let gap = |a: usize| s[a + 1].t - s[a].t;
        assert!((gap(0) - 0.25).abs() < 1e-12);
        // Backstroke row follows straight on; the handstroke row after a gap.
        assert!((gap(5) - 0.25).abs() < 1e-12);
        assert!((gap(11) - 0.5).abs() < 1e-12);
    }

    #[test]
    fn odd_struckness_and_errors_are_as_asked_and_seeded() {
        let mut spec = ring(4);
        spec.bells[2].odd_struck_ms = 30.0;
        spec.jitter = 0.01;
        let s = tower_strikes(&spec).unwrap();
        let again = tower_strikes(&spec).unwrap();
        assert_eq!(s, again, "the same seed, the same strikes");
        spec.seed = 2;
        assert_ne!(s, tower_strikes(&spec).unwrap());
        assert!(s.iter().all(|x| (x.t - x.ideal_t).abs() <= 0.01 + 0.015 + 1e-12));
        // With no jitter, bell 3's handstroke is 15 ms late and backstroke 15 ms early.
        spec.jitter = 0.0;
        let s = tower_strikes(&spec).unwrap();
        for x in s.iter().filter(|x| x.bell == 3) {
            let want = if x.hand { 0.015 } else { -0.015 };
            assert!((x.t - x.ideal_t - want).abs() < 1e-12);
        }
    }

    #[test]
    fn a_double_strike_is_heard_where_it_was_put() {
        let mut spec = ring(2);
        spec.rows = 2;
        spec.doubles = vec![DoubleStrikeSpec {
            bell: 2,
            row: 1,
            delay_ms: 60.0,
            amplitude_ratio: 0.7,
        }];
        let (sig, s) = tower_recording(&spec).unwrap();
        let d = s.iter().find(|x| x.double.is_some()).unwrap();
        assert_eq!((d.bell, d.row), (2, 1));
        let peak = sig.samples.iter().fold(0.0f64, |p, v| p.max(v.abs()));
        assert!((peak - 0.5).abs() < 1e-12);
        // The signal's energy jumps at the second strike: compare 20 ms
        // windows just before and just after it.
        let at = |t: f64| (t * sig.rate) as usize;
        let energy = |a: usize| sig.samples[a..a + 320].iter().map(|v| v * v).sum::<f64>();
        let t2 = d.t + 0.060;
        assert!(
            energy(at(t2)) > 1.3 * energy(at(t2) - 400),
            "the second strike adds sound"
        );
        // Silence before the first strike.
        assert!(sig.samples[..at(0.45)].iter().all(|v| *v == 0.0));
    }

    #[test]
    fn plain_hunt_moves_every_bell_one_place_a_row() {
        let mut spec = ring(6);
        spec.method = Method::PlainHunt;
        spec.rows = 16;
        let s = tower_strikes(&spec).unwrap();
        let place = |bell: usize, row: usize| s.iter().find(|x| x.bell == bell && x.row == row).unwrap().place;
        for bell in 1..=6 {
            for row in 2..15 {
                let step = place(bell, row + 1).abs_diff(place(bell, row));
                assert!(step <= 1, "bell {bell} row {row}");
            }
        }
        // Rows 0 and 1 rounds; row 2 the first change; back to rounds after 12 changes.
        assert_eq!((place(1, 2), place(2, 2), place(3, 2)), (2, 1, 4));
        assert!((1..=6).all(|b| place(b, 13) == b));
        // Every row holds each place once, in time order.
        for row in 0..16 {
            let mut r: Vec<_> = s.iter().filter(|x| x.row == row).collect();
            r.sort_by(|a, b| a.t.total_cmp(&b.t));
            assert!(r.iter().enumerate().all(|(k, x)| x.place == k + 1));
        }
    }

    #[test]
    fn convolution_matches_the_direct_sum() {
        let x: Vec<f64> = (0..5000).map(|i| ((i * 7919) % 97) as f64 - 48.0).collect();
        let h: Vec<f64> = (0..300).map(|i| (-(i as f64) / 50.0).exp()).collect();
        let y = convolve(&x, &h);
        assert_eq!(y.len(), x.len() + h.len() - 1);
        for n in [0, 1, 299, 300, 2500, 4095, 4096, 5298] {
            let direct: f64 = (0..h.len())
                .filter(|&k| k <= n && n - k < x.len())
                .map(|k| h[k] * x[n - k])
                .sum();
            assert!((y[n] - direct).abs() < 1e-9 * (1.0 + direct.abs()), "{n}");
        }
    }

    #[test]
    fn room_and_noise_are_as_asked() {
        let room = Room {
            rt60_s: 1.0,
            direct_to_reverb_db: 3.0,
            predelay_ms: 10.0,
        };
        let ir = room_response(room, 8000.0, &mut Pcg64::seed_from_u64(3));
        let tail: f64 = ir[1..].iter().map(|v| v * v).sum();
        assert!((10.0 * (1.0 / tail).log10() - 3.0).abs() < 1e-9);
        assert!(ir[1..80].iter().all(|v| *v == 0.0), "nothing before the pre-delay");
        // Noise: silence before the first strike carries noise at the SNR asked.
        let mut spec = ring(3);
        spec.snr_db = Some(20.0);
        spec.lead_in = 1.0;
        let (sig, s) = tower_recording(&spec).unwrap();
        let first = (s[0].t * sig.rate) as usize;
        let p = |a: &[f64]| a.iter().map(|v| v * v).sum::<f64>() / a.len() as f64;
        let snr = 10.0 * (p(&sig.samples[first..]) / p(&sig.samples[..first - 10])).log10();
        assert!((snr - 20.0).abs() < 0.5, "SNR {snr} dB");
    }

    #[test]
    fn voices_vary_within_their_bounds() {
        let b = RingBell {
            nominal_hz: 1000.0,
            mass_kg: 300.0,
            odd_struck_ms: 0.0,
        };
        let v = Variation {
            detune_cents: 20.0,
            strength_db: 3.0,
        };
        let voice = bell_voice(&b, v, 44_100.0, &mut Pcg64::seed_from_u64(9));
        assert_eq!(voice.len(), TUNED_PARTIALS.len());
        for (m, &(ratio, _, strength)) in voice.iter().zip(&TUNED_PARTIALS) {
            let cents = 1200.0 * (m.freq_hz / (1000.0 * ratio)).log2();
            assert!(cents.abs() <= 20.0);
            let db = 20.0 * (100.0 / m.effective_mass / strength).log10();
            assert!(db.abs() <= 3.0 + 1e-9, "{db}");
        }
        assert_eq!(voice[4].freq_hz, 1000.0, "the nominal is the one stated");
        // At 5 kHz the partials from 2250 Hz up are left out.
        assert_eq!(bell_voice(&b, v, 5000.0, &mut Pcg64::seed_from_u64(9)).len(), 7);
    }

    #[test]
    fn bad_specs_are_refused_with_a_reason() {
        let mut spec = ring(3);
        spec.jitter = 0.2;
        assert!(tower_strikes(&spec).unwrap_err().to_string().contains("jitter"));
        let mut spec = ring(3);
        spec.doubles = vec![DoubleStrikeSpec {
            bell: 4,
            row: 0,
            delay_ms: 50.0,
            amplitude_ratio: 0.5,
        }];
        assert!(tower_strikes(&spec).unwrap_err().to_string().contains("double strike"));
        let mut spec = ring(3);
        spec.bells.clear();
        assert!(tower_strikes(&spec).is_err());
    }
}
