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

use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;
use realfft::RealFftPlanner;

pub use crate::methods::PlainCourse;
use crate::synth::{synthesize, Strike, SynthMode, SynthSpec};
use crate::tower_effects::gaussian;
pub use crate::tower_effects::{Attack, Doublets, Noise, Scale, Swing, Voice, TUNED_PARTIALS};
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
    /// Doublets of unequal halves fixed per bell and partial; `None`: every
    /// partial a 0.5 Hz doublet of equal halves (the voice before issue 43).
    pub doublets: Option<Doublets>,
    /// The bells' swing heard (level and Doppler); `None`: bells heard still.
    pub swing: Option<Swing>,
    /// The bells' voice: tower bells (hum to upper partials) or handbells.
    pub voice: Voice,
    /// The noise heard at `snr_db`: white, wind or traffic.
    pub noise: Noise,
    /// The strike's broadband knock; `None`: strikes are ideal impulses.
    pub attack: Option<Attack>,
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
            doublets: None,
            swing: None,
            voice: Voice::Tower,
            noise: Noise::White,
            attack: None,
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
    /// Two rows of rounds, then the method's plain course over and over
    /// ([`PlainCourse`]: Plain Bob, Grandsire, Stedman).
    Course(PlainCourse),
}

impl Method {
    /// The method's name: "rounds", "plain hunt", "Plain Bob", ...
    pub fn name(&self) -> &'static str {
        match self {
            Method::Rounds => "rounds",
            Method::PlainHunt => "plain hunt",
            Method::Course(c) => c.name(),
        }
    }
}

/// The bells in the order they strike (from 0, the treble) in each of
/// `rows` rows of `method` on `n` bells.
fn method_rows(method: Method, n: usize, rows: usize) -> Result<Vec<Vec<usize>>, SignalError> {
    let mut order: Vec<usize> = (0..n).collect();
    let course = match method {
        Method::Course(c) => c.course(n)?,
        _ => vec![],
    };
    let mut out = Vec::with_capacity(rows);
    for row in 0..rows {
        match method {
            Method::Rounds => {}
            Method::PlainHunt if row >= 2 => {
                // Swap pairs from the lead on even changes, from second place on odd.
                for k in ((row % 2)..n.saturating_sub(1)).step_by(2) {
                    order.swap(k, k + 1);
                }
            }
            Method::PlainHunt => {}
            // Rows 0 and 1 rounds, then the course from its first change,
            // round to rounds and on.
            Method::Course(_) if row >= 2 => order = course[(row - 1) % course.len()].clone(),
            Method::Course(_) => {}
        }
        out.push(order.clone());
    }
    Ok(out)
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

/// A ring of `bells` (1 to 16) tuned to `scale` up from the tenor's
/// nominal `tenor_hz` (Hz): the tenor the key note, the treble highest, as
/// rings are hung (an eight the octave; ten and twelve going on above it).
/// Masses as [`major_scale`]'s: a bell's as the cube of its size, 150 kg at
/// a 1400 Hz nominal. `None` for more than 16 bells.
pub fn tuned_ring(bells: usize, tenor_hz: f64, scale: Scale) -> Option<Vec<RingBell>> {
    let steps = scale.semitones();
    (bells <= steps.len()).then(|| {
        (0..bells)
            .map(|i| {
                let f = tenor_hz * 2f64.powf(f64::from(steps[bells - 1 - i]) / 12.0);
                RingBell {
                    nominal_hz: f,
                    mass_kg: 150.0 * (1400.0 / f).powi(3),
                    odd_struck_ms: 0.0,
                }
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
    /// Discrete early reflections (delay ms after the direct sound, gain
    /// against it), on top of the diffuse tail: walls 1-4 m away give
    /// 7-25 ms. A gain of 0 is none; [`Room::chamber`] has none.
    pub reflections: [(f64, f64); MAX_REFLECTIONS],
    /// How much darker the diffuse tail is than the direct sound: its
    /// noise filtered `y[n] = x[n] + d y[n-1]` (d from 0, white, to under 1)
    /// before the ratio is set, so that its low frequencies carry more of
    /// its energy (a real room's high frequencies die first). 0 in
    /// [`Room::chamber`]; 0.6 puts the tail about 5 dB over the direct
    /// sound at a bell's low partials at 0 dB direct-to-reverberant.
    pub tail_darkening: f64,
}

/// The most discrete early reflections a [`Room`] holds.
pub const MAX_REFLECTIONS: usize = 4;

impl Room {
    /// Refuses a room that cannot be built: RT60 over 0 and up to 10 s
    /// (0 with early reflections alone), pre-delay 0 to 200 ms, a finite
    /// direct-to-reverberant ratio, each reflection's delay 0 to 200 ms and
    /// gain within ±2.
    pub fn check(&self) -> Result<(), SignalError> {
        let bad = |what: String| Err(SignalError::Option(what));
        // A room of reflections alone may have no tail (RT60 0).
        let tail_ok = self.rt60_s > 0.0 || (self.rt60_s == 0.0 && self.reflects());
        let refl_ok = self
            .reflections
            .iter()
            .all(|&(d, g)| d.is_finite() && (0.0..=200.0).contains(&d) && g.is_finite() && g.abs() <= 2.0);
        if !refl_ok {
            return bad(format!(
                "early reflections {}: each delay 0 to 200 ms, each gain within ±2",
                self.reflections
                    .iter()
                    .filter(|x| x.1 != 0.0)
                    .map(|(d, g)| format!("{d} ms at {g}"))
                    .collect::<Vec<_>>()
                    .join(", ")
            ));
        }
        let ok = self.rt60_s.is_finite()
            && tail_ok
            && (0.0..0.99).contains(&self.tail_darkening)
            && self.rt60_s <= 10.0
            && self.direct_to_reverb_db.is_finite()
            && self.predelay_ms.is_finite()
            && (0.0..=200.0).contains(&self.predelay_ms);
        if !ok {
            return bad(format!(
                "a room of RT60 {} s, pre-delay {} ms, direct-to-reverberant {} dB, tail darkened by {}: RT60 over 0 and up to 10 s, pre-delay 0 to 200 ms, a finite direct-to-reverberant ratio, a darkening from 0 to under 0.99",
                self.rt60_s, self.predelay_ms, self.direct_to_reverb_db, self.tail_darkening
            ));
        }
        Ok(())
    }

    /// A ringing chamber of reverberation time `rt60_s` (s), heard a few
    /// metres from the bells: the direct sound 3 dB over the reverberant,
    /// the first reflection 15 ms after it (walls about 2.5 m away).
    pub fn chamber(rt60_s: f64) -> Self {
        Room {
            rt60_s,
            direct_to_reverb_db: 3.0,
            predelay_ms: 15.0,
            reflections: [(0.0, 0.0); MAX_REFLECTIONS],
            tail_darkening: 0.0,
        }
    }

    /// The room with its diffuse tail darkened by `d` ([`Room::tail_darkening`])
    /// and the direct sound `direct_to_reverb_db` (dB) over it.
    pub fn with_dark_tail(mut self, d: f64, direct_to_reverb_db: f64) -> Self {
        self.tail_darkening = d;
        self.direct_to_reverb_db = direct_to_reverb_db;
        self
    }

    /// The room with discrete early reflections `refl` (delay ms, gain)
    /// added (the first [`MAX_REFLECTIONS`]; the rest are refused by the
    /// spec's check). An `rt60_s` of 0 is then a room with no diffuse tail:
    /// only the reflections.
    pub fn with_reflections(mut self, refl: &[(f64, f64)]) -> Self {
        for (slot, r) in self.reflections.iter_mut().zip(refl) {
            *slot = *r;
        }
        self
    }

    /// Whether the room has a discrete reflection (a gain not 0).
    pub fn reflects(&self) -> bool {
        self.reflections.iter().any(|r| r.1 != 0.0)
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

/// The longest synthetic recording (s): four hours, past a peal's three.
pub const MAX_RECORDING_S: f64 = 4.0 * 3600.0;

/// The recording's length (bounded before anything is allocated: at most
/// [`MAX_RECORDING_S`], a peal being about three hours) and each bell.
fn check_length_and_bells(spec: &TowerSpec) -> Result<(), SignalError> {
    let bad = |what: String| Err(SignalError::Option(what));
    let seconds = spec.rows as f64 * (spec.bells.len() as f64 + spec.handstroke_gap) * spec.interval;
    if seconds > MAX_RECORDING_S {
        return bad(format!(
            "{} rows of {} bells at {:.0} ms: {:.1} hours of sound, at most {:.0} (a peal is about 3)",
            spec.rows,
            spec.bells.len(),
            spec.interval * 1e3,
            seconds / 3600.0,
            MAX_RECORDING_S / 3600.0
        ));
    }
    for (i, b) in spec.bells.iter().enumerate() {
        if !(b.nominal_hz > 0.0 && b.mass_kg > 0.0 && b.odd_struck_ms.is_finite()) {
            return bad(format!(
                "bell {}: nominal {} Hz and mass {} kg: both must be more than 0",
                i + 1,
                b.nominal_hz,
                b.mass_kg
            ));
        }
        if b.odd_struck_ms.abs() * 1e-3 >= spec.interval {
            return bad(format!("odd-struckness {} ms: under the interval", b.odd_struck_ms));
        }
    }
    Ok(())
}

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
    check_length_and_bells(spec)?;
    let v = spec.variation;
    let detune_ok = v.detune_cents.is_finite() && (0.0..=100.0).contains(&v.detune_cents);
    let strength_ok = v.strength_db.is_finite() && (0.0..=20.0).contains(&v.strength_db);
    if !(detune_ok && strength_ok) {
        return bad(format!(
            "bell-to-bell variation of {} cents and {} dB: 0 to 100 cents and 0 to 20 dB",
            v.detune_cents, v.strength_db
        ));
    }
    if let Some(r) = spec.room {
        r.check()?;
    }
    if let Some(snr) = spec.snr_db {
        if !(snr.is_finite() && snr > -20.0) {
            return bad(format!("SNR {snr} dB: above -20 dB"));
        }
    }
    if let Some(d) = spec.doublets {
        d.check()?;
    }
    if let Some(s) = spec.swing {
        s.check()?;
    }
    if let Some(a) = spec.attack {
        a.check()?;
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
                "a double strike of bell {} in row {} after {} ms at {} of the strike: a bell and row of the ring ({} bells, {} rows), delay over 0 and under 1000 ms, ratio in (0, 1]",
                d.bell, d.row, d.delay_ms, d.amplitude_ratio, spec.bells.len(), spec.rows
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
    let orders = method_rows(spec.method, n, spec.rows)?;
    for (row, order) in orders.iter().enumerate() {
        let hand = row % 2 == 0;
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

/// One bell's partials as heard: [`TUNED_PARTIALS`] scaled to the nominal,
/// each moved within `variation` by `rng`; partials at or above 0.45 of
/// the sample rate are left out. Strength is set through the effective
/// mass (a third of the bell's mass for the nominal).
pub fn bell_voice(b: &RingBell, variation: Variation, rate: f64, rng: &mut Pcg64) -> Vec<SynthMode> {
    voice_of(&TUNED_PARTIALS, b, variation, rate, rng)
}

/// One bell's partials `partials` (ratio to the nominal, Q, strength to
/// the nominal's) as heard, as [`bell_voice`] makes them.
pub fn voice_of(
    partials: &[(f64, f64, f64)],
    b: &RingBell,
    variation: Variation,
    rate: f64,
    rng: &mut Pcg64,
) -> Vec<SynthMode> {
    let mut out = vec![];
    for &(ratio, q, strength) in partials {
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

/// What a ring's direct sound becomes on the recording: the room's
/// response (cut to `len` samples), the noise at the spec's SNR against the
/// ringing's mean power from `first_strike` (s) on, and the peak scaled to
/// 0.5. Shared by the synthetic ring and the ring of recorded strikes.
pub(crate) fn in_the_room(mut mix: Vec<f64>, spec: &TowerSpec, first_strike: f64, len: usize) -> Vec<f64> {
    if let Some(room) = spec.room {
        let ir = room_response(room, spec.rate, &mut Pcg64::seed_from_u64(spec.seed ^ 0x5eed_0002));
        mix = convolve(&mix, &ir);
        mix.truncate(len);
    }
    if let Some(snr) = spec.snr_db {
        let from = (first_strike * spec.rate) as usize;
        let ringing = &mix[from.min(mix.len())..];
        let power = ringing.iter().map(|v| v * v).sum::<f64>() / ringing.len().max(1) as f64;
        let sd = (power / 10f64.powf(snr / 10.0)).sqrt();
        let mut rng = Pcg64::seed_from_u64(spec.seed ^ 0x5eed_0003);
        match spec.noise {
            Noise::White => {
                for m in &mut mix {
                    *m += sd * gaussian(&mut rng);
                }
            }
            kind => {
                let noise = kind.make(mix.len(), spec.rate, &mut rng);
                for (m, v) in mix.iter_mut().zip(noise) {
                    *m += sd * v;
                }
            }
        }
    }
    let peak = mix.iter().fold(0.0f64, |p, v| p.max(v.abs()));
    if peak > 0.0 {
        for m in &mut mix {
            *m *= 0.5 / peak;
        }
    }
    mix
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
    let mut doublet_rng = Pcg64::seed_from_u64(spec.seed ^ 0x5eed_0004);
    let mut attack_rng = Pcg64::seed_from_u64(spec.seed ^ 0x5eed_0005);
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
        let mut modes = voice_of(spec.voice.partials(), b, spec.variation, spec.rate, &mut voice_rng);
        if let Some(d) = spec.doublets {
            modes = crate::tower_effects::split_doublets(&modes, d, &mut doublet_rng).0;
        }
        // The swing turns from strike to strike; a double strike is within one stroke.
        let strike_times: Vec<f64> = strikes.iter().filter(|s| s.bell == i + 1).map(|s| s.t).collect();
        let mut sound = synthesize(&SynthSpec {
            rate: spec.rate,
            duration: end,
            modes,
            strikes: hits,
            rests: vec![],
            rest_damping: 1.0,
            acceleration: false,
        })?;
        if let Some(attack) = spec.attack {
            let knocks: Vec<(f64, f64)> = strikes
                .iter()
                .filter(|s| s.bell == i + 1)
                .flat_map(|s| std::iter::once((s.t, 1.0)).chain(s.double.map(|(d, r)| (s.t + d, r))))
                .collect();
            attack.add(&mut sound.samples, spec.rate, &knocks, &mut attack_rng);
        }
        if let Some(swing) = spec.swing {
            sound.samples = swing.apply(&sound.samples, spec.rate, &strike_times);
        }
        if mix.is_empty() {
            mix = sound.samples;
        } else {
            for (m, s) in mix.iter_mut().zip(&sound.samples) {
                *m += s;
            }
        }
    }
    let first = strikes.first().map_or(0.0, |s| s.t);
    let mix = in_the_room(mix, spec, first, (end * spec.rate).round() as usize);
    Ok((
        Signal {
            rate: spec.rate,
            samples: mix,
        },
        strikes,
    ))
}

/// The room's impulse response: 1 at time 0, then from the pre-delay
/// Gaussian noise under an envelope falling 60 dB in RT60, scaled so that
/// its energy is the direct sound's less the direct-to-reverberant ratio,
/// and each discrete reflection's gain at its delay (on top of the tail).
pub(crate) fn room_response(room: Room, rate: f64, rng: &mut Pcg64) -> Vec<f64> {
    let mut ir = diffuse_response(room, rate, rng);
    for &(d, g) in room.reflections.iter().filter(|r| r.1 != 0.0) {
        let k = (d * 1e-3 * rate).round() as usize;
        if k >= ir.len() {
            ir.resize(k + 1, 0.0);
        }
        ir[k] += g;
    }
    ir
}

/// [`room_response`] without the discrete reflections (the direct sound
/// alone where RT60 is 0).
fn diffuse_response(room: Room, rate: f64, rng: &mut Pcg64) -> Vec<f64> {
    if room.rt60_s <= 0.0 {
        return vec![1.0];
    }
    let start = (room.predelay_ms * 1e-3 * rate).round().max(1.0) as usize;
    let len = start + (room.rt60_s * rate).ceil() as usize;
    let mut ir = vec![0.0; len];
    ir[0] = 1.0;
    // Amplitude falls 60 dB (a factor 1000) in RT60.
    let k = 1000f64.ln() / (room.rt60_s * rate);
    // The tail's noise, darkened (one pole), under its envelope.
    let mut dark = 0.0;
    for (i, v) in ir.iter_mut().enumerate().skip(start) {
        dark = gaussian(rng) + room.tail_darkening * dark;
        *v = dark * (-k * (i - start) as f64).exp();
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
    use std::f64::consts::PI;

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
            doublets: None,
            swing: None,
            voice: Voice::Tower,
            noise: Noise::White,
            attack: None,
        }
    }

    /// A refused ring says its values in words with their units, never as a
    /// Rust struct (issue 46's messages).
    #[test]
    fn refusals_say_their_values_in_words() {
        let mut spec = ring(4);
        spec.room = Some(Room {
            rt60_s: 20.0,
            direct_to_reverb_db: 0.0,
            predelay_ms: 10.0,
            reflections: [(0.0, 0.0); MAX_REFLECTIONS],
            tail_darkening: 0.0,
        });
        let e = check(&spec).unwrap_err().to_string();
        assert!(e.contains("RT60 20 s") && !e.contains('{'), "{e}");
        let mut spec = ring(4);
        spec.variation = Variation {
            detune_cents: 500.0,
            strength_db: 1.0,
        };
        let e = check(&spec).unwrap_err().to_string();
        assert!(e.contains("500 cents") && !e.contains('{'), "{e}");
        let mut spec = ring(4);
        spec.doubles = vec![DoubleStrikeSpec {
            bell: 9,
            row: 0,
            delay_ms: 60.0,
            amplitude_ratio: 0.5,
        }];
        let e = check(&spec).unwrap_err().to_string();
        assert!(e.contains("bell 9") && e.contains("4 bells") && !e.contains('{'), "{e}");
    }

    /// One bell of nominal 1000 Hz struck on every stroke, its partials
    /// single components unless a test says otherwise.
    fn one_bell(rows: usize) -> TowerSpec {
        let mut spec = ring(1);
        spec.bells[0].nominal_hz = 1000.0;
        spec.rows = rows;
        spec.interval = 1.0;
        spec.tail = 3.0;
        spec.doublets = Some(Doublets::NONE);
        spec
    }

    /// The band about `f` (Hz): the signal turned down by `f` and averaged
    /// over Hann windows `win` (s) long a hop of `win`/4 apart (the other
    /// partials, 250 Hz and more away, left out): (time s, re, im).
    fn band(sig: &Signal, f: f64, win: f64) -> Vec<(f64, f64, f64)> {
        let n = (win * sig.rate) as usize;
        let w = 2.0 * PI * f / sig.rate;
        (0..(sig.samples.len() - n) / (n / 4))
            .map(|k| {
                let a = k * n / 4;
                let (mut re, mut im) = (0.0, 0.0);
                for i in a..a + n {
                    let hann = 1.0 - (2.0 * PI * (i - a) as f64 / n as f64).cos();
                    re += hann * sig.samples[i] * (w * i as f64).cos();
                    im -= hann * sig.samples[i] * (w * i as f64).sin();
                }
                ((a as f64 + n as f64 / 2.0) / sig.rate, re / n as f64, im / n as f64)
            })
            .collect()
    }

    #[test]
    fn a_doublet_beats_at_its_split_with_the_depth_its_shares_give() {
        let mut spec = one_bell(1);
        spec.tail = 3.0;
        spec.doublets = Some(Doublets {
            split_hz: (1.25, 1.25),
            share: (0.3, 0.3),
        });
        let (sig, truth) = tower_recording(&spec).unwrap();
        // The nominal's envelope (dB), its exponential decay taken out by a
        // straight line through it: what is left is the beat.
        // Three seconds of it, while the nominal is 50 dB above the others' leak.
        let env: Vec<(f64, f64)> = band(&sig, 1000.0, 0.05)
            .into_iter()
            .filter(|p| p.0 > truth[0].t + 0.05 && p.0 < truth[0].t + 3.0)
            .map(|(t, re, im)| (t, 20.0 * re.hypot(im).log10()))
            .collect();
        let n = env.len() as f64;
        let (mt, my) = (
            env.iter().map(|p| p.0).sum::<f64>() / n,
            env.iter().map(|p| p.1).sum::<f64>() / n,
        );
        let slope = env.iter().map(|p| (p.0 - mt) * (p.1 - my)).sum::<f64>()
            / env.iter().map(|p| (p.0 - mt).powi(2)).sum::<f64>();
        let rest: Vec<(f64, f64)> = env.iter().map(|p| (p.0, p.1 - my - slope * (p.0 - mt))).collect();
        // The beat's frequency: the strongest line of the residue from 0.2 to 5 Hz.
        let power = |f: f64| {
            let (c, s) = rest.iter().fold((0.0, 0.0), |(c, s), p| {
                (
                    c + p.1 * (2.0 * PI * f * p.0).cos(),
                    s + p.1 * (2.0 * PI * f * p.0).sin(),
                )
            });
            c * c + s * s
        };
        let beat = (20..=500)
            .map(|k| k as f64 / 100.0)
            .max_by(|a, b| power(*a).total_cmp(&power(*b)))
            .unwrap();
        assert!((1.0 / beat - 0.8).abs() < 0.03, "beat period {} s", 1.0 / beat);
        let depth =
            rest.iter().map(|p| p.1).fold(f64::MIN, f64::max) - rest.iter().map(|p| p.1).fold(f64::MAX, f64::min);
        let want = crate::tower_effects::beat_depth_db(0.3);
        assert!(
            (depth - want).abs() < 1.5,
            "beats {depth:.1} dB deep, shares give {want:.1} dB"
        );
    }

    #[test]
    fn the_swing_changes_the_level_by_the_range_asked_and_keeps_the_strike_times() {
        let still = one_bell(3);
        let swing = TowerSpec {
            swing: Some(Swing {
                level_db: 12.0,
                doppler: 0.0,
            }),
            ..still.clone()
        };
        let (a, truth) = tower_recording(&still).unwrap();
        let (b, truth_b) = tower_recording(&swing).unwrap();
        assert_eq!(truth, truth_b, "the truth is the same");
        // The nominal's level swinging over still, through the second stroke.
        let (ea, eb) = (band(&a, 1000.0, 0.02), band(&b, 1000.0, 0.02));
        let db: Vec<f64> = ea
            .iter()
            .zip(&eb)
            .filter(|(p, _)| p.0 > truth[1].t + 0.02 && p.0 < truth[2].t - 0.02)
            .map(|(p, q)| 20.0 * (q.1.hypot(q.2) / p.1.hypot(p.2)).log10())
            .collect();
        let hi = db.iter().copied().fold(f64::MIN, f64::max);
        let lo = db.iter().copied().fold(f64::MAX, f64::min);
        // Peak normalising scales the whole recording: the range is what counts.
        assert!((hi - lo - 12.0).abs() < 0.5, "the level ranges over {:.2} dB", hi - lo);
        // The strike is heard when it was made: the first sound of the
        // recording within a millisecond of the first strike.
        let first = b.samples.iter().position(|v| v.abs() > 1e-3).unwrap() as f64 / b.rate;
        assert!(
            (first - truth[0].t).abs() < 1e-3,
            "heard at {first}, struck at {}",
            truth[0].t
        );
    }

    #[test]
    fn the_swing_shifts_the_frequency_by_the_doppler_asked() {
        let spec = TowerSpec {
            swing: Some(Swing {
                level_db: 0.0,
                doppler: 0.01,
            }),
            ..one_bell(3)
        };
        let (sig, truth) = tower_recording(&spec).unwrap();
        // The nominal's frequency from its phase's turn from one window to
        // the next (a hop of 10 ms), through the second stroke.
        let e = band(&sig, 1000.0, 0.04);
        let hop = e[1].0 - e[0].0;
        let shift: Vec<(f64, f64)> = e
            .windows(2)
            .filter(|w| w[0].0 > truth[1].t + 0.03 && w[1].0 < truth[2].t - 0.03)
            .map(|w| {
                let turn = (w[1].2 * w[0].1 - w[1].1 * w[0].2).atan2(w[1].1 * w[0].1 + w[1].2 * w[0].2);
                (w[0].0, turn / (2.0 * PI * hop) / 1000.0)
            })
            .collect();
        let hi = shift.iter().map(|p| p.1).fold(f64::MIN, f64::max);
        let lo = shift.iter().map(|p| p.1).fold(f64::MAX, f64::min);
        assert!(
            (hi - 0.01).abs() < 0.0005 && (lo + 0.01).abs() < 0.0005,
            "shifts {hi} and {lo}"
        );
        // Up while the bell comes nearer (the first half of the stroke).
        let mid = 0.5 * (truth[1].t + truth[2].t);
        assert!(shift.iter().filter(|p| p.0 < mid - 0.2).all(|p| p.1 > -0.002));
    }

    #[test]
    fn tuned_rings_are_major_and_minor_scales_up_from_the_tenor() {
        let semis = |r: &[RingBell], a: usize, b: usize| 12.0 * (r[a].nominal_hz / r[b].nominal_hz).log2();
        let major = tuned_ring(8, 250.0, Scale::Major).unwrap();
        assert!((major[7].nominal_hz - 250.0).abs() < 1e-9 && (semis(&major, 0, 7) - 12.0).abs() < 1e-9);
        // Up from the tenor: tone, tone, semitone (the fourth bell from the back a major third up).
        assert!((semis(&major, 6, 7) - 2.0).abs() < 1e-9 && (semis(&major, 4, 7) - 5.0).abs() < 1e-9);
        let minor = tuned_ring(6, 250.0, Scale::Minor).unwrap();
        assert!(
            (semis(&minor, 3, 5) - 3.0).abs() < 1e-9,
            "a minor third above the tenor"
        );
        let twelve = tuned_ring(12, 300.0, Scale::Major).unwrap();
        assert!(
            (semis(&twelve, 0, 11) - 19.0).abs() < 1e-9,
            "twelve bells span an octave and a fifth"
        );
        assert!(twelve
            .windows(2)
            .all(|w| w[0].nominal_hz > w[1].nominal_hz && w[0].mass_kg < w[1].mass_kg));
        assert!(tuned_ring(17, 300.0, Scale::Minor).is_none());
    }

    #[test]
    fn methods_ring_their_plain_courses_after_two_rows_of_rounds() {
        for (course, n) in [
            (PlainCourse::PlainBob, 6),
            (PlainCourse::Grandsire, 8),
            (PlainCourse::Stedman, 7),
        ] {
            let mut spec = ring(n);
            spec.method = Method::Course(course);
            spec.rows = 40;
            let s = tower_strikes(&spec).unwrap();
            let rows = course.course(n).unwrap();
            for row in 0..40 {
                let mut r: Vec<&TrueStrike> = s.iter().filter(|x| x.row == row).collect();
                r.sort_by_key(|x| x.place);
                let heard: Vec<usize> = r.iter().map(|x| x.bell - 1).collect();
                let want = if row < 2 {
                    (0..n).collect()
                } else {
                    rows[(row - 1) % rows.len()].clone()
                };
                assert_eq!(heard, want, "{} row {row}", course.name());
            }
        }
        let mut spec = ring(4);
        spec.method = Method::Course(PlainCourse::Stedman);
        assert!(tower_strikes(&spec)
            .unwrap_err()
            .to_string()
            .contains("Stedman on 4 bells"));
    }

    #[test]
    fn a_peal_speed_twelve_keeps_its_rhythm() {
        let mut spec = ring(12);
        spec.interval = 0.15;
        spec.jitter = 0.01;
        spec.method = Method::PlainHunt;
        let s = tower_strikes(&spec).unwrap();
        assert_eq!(s.len(), 48);
        assert!(s.iter().all(|x| (x.t - x.ideal_t).abs() <= 0.01));
        assert!(s.windows(2).all(|w| w[1].t - w[0].t > 0.15 - 0.02 - 1e-9));
        spec.jitter = 0.08;
        assert!(
            tower_strikes(&spec).is_err(),
            "errors of half an interval mix places up"
        );
    }

    #[test]
    fn a_handbell_has_no_hum_and_dies_away_in_seconds() {
        let tower = TowerSpec {
            tail: 4.0,
            ..one_bell(1)
        };
        let hand = TowerSpec {
            voice: Voice::Handbell,
            ..tower.clone()
        };
        let (a, ta) = tower_recording(&tower).unwrap();
        let (b, _) = tower_recording(&hand).unwrap();
        let level = |sig: &Signal, f: f64, t: f64| {
            band(sig, f, 0.1)
                .iter()
                .filter(|p| (p.0 - t).abs() < 0.05)
                .map(|p| 20.0 * p.1.hypot(p.2).log10())
                .fold(f64::MIN, f64::max)
        };
        let t0 = ta[0].t;
        // The hum (250 Hz) 30 dB or more under the strike note in the
        // handbell, within 20 dB in the tower bell.
        assert!(level(&b, 250.0, t0 + 0.2) < level(&b, 1000.0, t0 + 0.2) - 30.0);
        assert!(level(&a, 250.0, t0 + 0.2) > level(&a, 1000.0, t0 + 0.2) - 20.0);
        // Three seconds on, the tower bell's hum still rings: the whole
        // sound has fallen far less than the handbell's.
        let rms = |sig: &Signal, t: f64| {
            let i = (t * sig.rate) as usize;
            (sig.samples[i..i + 2000].iter().map(|v| v * v).sum::<f64>() / 2000.0).sqrt()
        };
        let fall = |sig: &Signal| 20.0 * (rms(sig, t0 + 0.1) / rms(sig, t0 + 2.9)).log10();
        assert!(
            fall(&b) > 35.0 && fall(&a) < 25.0,
            "fell {:.1} dB, tower {:.1} dB",
            fall(&b),
            fall(&a)
        );
        // A handbell's twelfth: a partial at 2.95 times the strike note.
        assert!(level(&b, 2950.0, t0 + 0.2) > level(&b, 2000.0, t0 + 0.2) + 30.0);
    }

    #[test]
    fn wind_and_traffic_are_low_and_come_and_go() {
        let rate = 8000.0;
        let n = 60 * 8000;
        for kind in [Noise::White, Noise::Wind, Noise::Traffic] {
            let x = kind.make(n, rate, &mut Pcg64::seed_from_u64(5));
            let p: f64 = x.iter().map(|v| v * v).sum::<f64>() / n as f64;
            assert!((p - 1.0).abs() < 1e-9, "{kind:?}: mean power 1");
            // Power below 500 Hz: a one-pole high-pass at 500 Hz leaves the rest.
            let a = (-2.0 * PI * 500.0 / rate).exp();
            let (mut lp, mut high) = (0.0, 0.0);
            for v in &x {
                lp = a * lp + (1.0 - a) * v;
                high += (v - lp) * (v - lp);
            }
            let above = high / n as f64;
            // Its level in half-second windows: the loudest over the quietest.
            let w: Vec<f64> = x.chunks(4000).map(|c| c.iter().map(|v| v * v).sum::<f64>()).collect();
            let swing = 10.0
                * (w.iter().copied().fold(f64::MIN, f64::max) / w.iter().copied().fold(f64::MAX, f64::min)).log10();
            match kind {
                Noise::White => assert!(above > 0.4 && swing < 1.0, "{kind:?}: {above} {swing}"),
                _ => assert!(
                    above < 0.25 && swing > 6.0,
                    "{kind:?}: {above} above 500 Hz, level swings {swing:.1} dB"
                ),
            }
        }
        // In a recording, at the SNR asked (on average over the recording).
        let mut spec = ring(3);
        spec.snr_db = Some(10.0);
        spec.noise = Noise::Traffic;
        assert!(tower_recording(&spec).is_ok());
    }

    #[test]
    fn the_knock_is_as_loud_and_as_long_as_asked() {
        let plain = TowerSpec {
            rate: 22_050.0,
            ..one_bell(1)
        };
        let knock = TowerSpec {
            attack: Some(Attack {
                level_db: -20.0,
                length_ms: 30.0,
            }),
            ..plain.clone()
        };
        let (a, truth) = tower_recording(&plain).unwrap();
        let (b, _) = tower_recording(&knock).unwrap();
        // The two agree but for scale once the knock has died (80 dB down
        // after 120 ms): find the scale there, and the knock is the rest.
        let late = ((truth[0].t + 0.3) * a.rate) as usize;
        let k = b.samples[late..]
            .iter()
            .zip(&a.samples[late..])
            .map(|(x, y)| x * y)
            .sum::<f64>()
            / a.samples[late..].iter().map(|y| y * y).sum::<f64>();
        let plain: Vec<f64> = a.samples.iter().map(|v| k * v).collect();
        let burst: Vec<f64> = b.samples.iter().zip(&plain).map(|(x, y)| x - y).collect();
        let frame = (crate::tower_effects::ATTACK_FRAME_S * a.rate).round() as usize;
        let energy = |x: &[f64], from: usize| x[from..from + frame].iter().map(|v| v * v).sum::<f64>();
        let at = (truth[0].t * a.rate).ceil() as usize;
        let loudest = (at..at + 2000).map(|i| energy(&plain, i)).fold(0.0, f64::max);
        let level = 10.0 * (energy(&burst, at) / loudest).log10();
        assert!((level + 20.0).abs() < 1.5, "knock {level:.1} dB");
        // 20 dB down 30 ms on, over a few frames.
        let later = (0..4)
            .map(|j| energy(&burst, at + (0.03 * a.rate) as usize + j * frame))
            .sum::<f64>();
        let first = (0..4).map(|j| energy(&burst, at + j * frame)).sum::<f64>();
        let fall = 10.0 * (first / later).log10();
        assert!((fall - 20.0).abs() < 2.0, "falls {fall:.1} dB in 30 ms");
        assert!(burst[..at].iter().all(|v| v.abs() < 1e-12), "nothing before the strike");
        assert!(Attack {
            level_db: 5.0,
            length_ms: 30.0
        }
        .check()
        .is_err());
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

    /// Discrete early reflections sit at their delays with their gains,
    /// on the diffuse tail or alone (RT60 0); a room of neither is refused.
    #[test]
    fn early_reflections_are_at_their_delays() {
        let refl = [(7.0, 0.5), (13.0, 0.35), (21.0, 0.3)];
        let dry = Room::chamber(0.0).with_reflections(&refl);
        let ir = room_response(dry, 8000.0, &mut Pcg64::seed_from_u64(3));
        assert_eq!(ir.len(), 169);
        for (k, v) in ir.iter().enumerate() {
            let want = match k {
                0 => 1.0,
                56 => 0.5,
                104 => 0.35,
                168 => 0.3,
                _ => 0.0,
            };
            assert_eq!(*v, want, "sample {k}");
        }
        let mut spec = ring(3);
        spec.room = Some(dry);
        assert!(check(&spec).is_ok());
        spec.room = Some(Room::chamber(0.0));
        assert!(check(&spec).is_err());
        spec.room = Some(Room::chamber(0.5).with_reflections(&[(300.0, 0.5)]));
        assert!(check(&spec).is_err());
        // On the tail: the same tail, the reflections added.
        let wet = Room::chamber(0.5);
        let a = room_response(wet, 8000.0, &mut Pcg64::seed_from_u64(3));
        let b = room_response(wet.with_reflections(&refl), 8000.0, &mut Pcg64::seed_from_u64(3));
        assert!((b[104] - a[104] - 0.35).abs() < 1e-12 && b[105] == a[105]);
    }

    /// The darkened tail is a one-pole (AR(1)) noise under its envelope:
    /// its lag-one autocorrelation is the pole `d` (the envelope moves by
    /// 1e-3 of itself a sample at RT60 1 s, 8 kHz), 0 for white noise; and
    /// it holds the direct-to-reverberant ratio asked whatever `d`.
    #[test]
    fn a_darkened_tail_is_one_pole_noise_at_the_ratio_asked() {
        let lag_one = |d: f64| {
            let room = Room::chamber(1.0).with_dark_tail(d, 0.0);
            let ir = room_response(room, 8000.0, &mut Pcg64::seed_from_u64(5));
            let start = ir.iter().skip(1).position(|v| *v != 0.0).unwrap() + 1;
            let t = &ir[start..];
            let r1: f64 = t.windows(2).map(|w| w[0] * w[1]).sum();
            let tail: f64 = t.iter().map(|v| v * v).sum();
            assert!((10.0 * (1.0 / tail).log10()).abs() < 1e-9, "d {d}: ratio");
            r1 / tail
        };
        for d in [0.0, 0.3, 0.6, 0.9] {
            let r = lag_one(d);
            assert!((r - d).abs() < 0.04, "d {d}: lag-one autocorrelation {r:.3}");
        }
        assert!(Room::chamber(1.0).with_dark_tail(0.99, 0.0).check().is_err());
        assert!(Room::chamber(1.0).with_dark_tail(-0.1, 0.0).check().is_err());
    }

    #[test]
    fn room_and_noise_are_as_asked() {
        let room = Room {
            rt60_s: 1.0,
            direct_to_reverb_db: 3.0,
            predelay_ms: 10.0,
            reflections: [(0.0, 0.0); MAX_REFLECTIONS],
            tail_darkening: 0.0,
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
