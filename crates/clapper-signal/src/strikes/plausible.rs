//! Whether what was heard sounds like bells struck (issue 46): a bell's
//! strike starts its partials, so across a strike's onset its bell's
//! strongest partial (with a measured voice, its highest strong one:
//! [`RisePartial`]) rises, many times over, and then decays. A steady
//! tone (a square wave on a bell's nominal) or noise gives "strikes" where
//! the level only wanders: the partial is as loud before as after. And a
//! bell's partial rings on for seconds after its strike, where a syllable
//! of speech stops within a fifth of a second ([`RING_ON_FALL`]).

use std::f64::consts::PI;

use super::heard::HeardStrike;
use super::voice::BellVoice;
use crate::Signal;

/// The stretch listened to before a strike's time, ending this long
/// before it (s): the band finder hears recorded tower bells up to 85 ms
/// late, so their sound may start 85 ms before the time heard.
const BEFORE_END_S: f64 = 0.1;
/// The stretch listened to after it, starting this long after (s): a
/// strike is timed at a fifth of its rise, the rise done by then.
const AFTER_START_S: f64 = 0.02;
/// The length of each stretch (s): 10 Hz apart in frequency, so the next
/// bell's partial a semitone away (6 %, 40 Hz at 700 Hz) hardly leaks in.
const STRETCH_S: f64 = 0.1;
/// A strike rises if its partial's power after is this many times its
/// power before (3 dB). A bell's strongest partial (often its hum) may
/// still ring from its last strike two seconds before: on a ring built
/// from recorded tower bells (docs/reliability.md) 86 % of the strikes
/// heard with templates rose by this much, 72 % by 6 dB.
pub const RISE_POWER: f64 = 2.0;
/// Under this share of strikes rising, the recording does not sound like
/// bells struck (see [`rising`]). On synthetic rings (RT60 1.2 s, 20 dB
/// SNR) all strikes rise, on the recorded bells 69 to 86 %, on a square
/// wave none; on noise a strike would rise by chance one time in three
/// (the ratio of two exponentially distributed powers over 2).
pub const PLAUSIBLE_SHARE: f64 = 0.5;

/// A struck bell's partial, after the stretch a strike's rise is heard
/// in, stays above this share of that stretch's power (40 dB under it)
/// in every stretch from [`RING_ON_FROM_S`] to [`RING_ON_TO_S`] after the
/// strike: a tower bell's nominal falls 60 dB in seconds, a handbell's
/// strike note in about five (12 dB/s), while a syllable of speech stops
/// and its partial falls into the gap before the next. Chosen 2026-11-27
/// on the benchmark's seeds 1-4 and an independent tester's rings of
/// recorded tower bells and its speech-like sound: at 30 dB a beating
/// doublet's dip or a room's noise cut 1-4 % of a ring's strikes; at 40
/// dB at most 1 % of any ring's (docs/strikes.md, "Speech is not a
/// ring"), and none of the speech-like sound's strikes rang on.
pub const RING_ON_FALL: f64 = 1e-4;
/// The first stretch (s after the strike) [`RING_ON_FALL`] is judged in:
/// past the rise, so that the stretch ends a quarter second on, beyond
/// the shortest syllable.
pub const RING_ON_FROM_S: f64 = 0.15;
/// The last stretch's start (s after the strike): a gap between
/// syllables falls before it, and a fast ring's next strike of the same
/// bell (two intervals of 0.15 s at least a row apart) does not.
pub const RING_ON_TO_S: f64 = 0.45;
/// The step between stretches (s): half a stretch, so that a gap of a
/// tenth of a second fills most of one.
const RING_ON_STEP_S: f64 = 0.05;

/// For each of `strikes` (times from the start of `sig`; bell `b` is
/// `voices[b - 1]`): whether its bell's strongest partial rises across
/// its onset by [`RISE_POWER`] or more and rings on after it
/// ([`RING_ON_FALL`], always heard at the strongest) ([`rising_at`] with
/// [`RisePartial::Strongest`]), or None where the recording does
/// not reach both sides (the first or last tenths of a second). (The
/// geometric mean over all its partials read a ring of recorded bells
/// heard by assumed nominals as 42 %: partials assumed where the bells had
/// none rise no more than noise.)
pub fn rising(sig: &Signal, strikes: &[HeardStrike], voices: &[BellVoice]) -> Vec<Option<bool>> {
    rising_at(sig, strikes, voices, RisePartial::Strongest)
}

/// Which partial of a bell's voice [`rising_at`] listens to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RisePartial {
    /// Its strongest: a tuned bell's nominal, where the voice's partials
    /// are assumed (a partial assumed that the bell lacks rises no more
    /// than noise).
    Strongest,
    /// The highest of those at least [`RISE_SHARE`] of its strongest,
    /// where the voice's partials were measured on the bell's own strike
    /// (a template). An upper partial dies within a second or two and
    /// starts afresh at every strike; a recorded bell's strongest is often
    /// its hum or prime, still ringing from its last strike. On an
    /// independent tester's five rings of recorded tower bells heard with
    /// their templates the strongest read 0.43-0.70 of the strikes
    /// rising, this 0.70-0.98; heard with assumed partials this read
    /// 0.54-0.74 against the strongest's 0.87-0.93 (the octave nominal
    /// assumed is not in those bells).
    HighestStrong,
}

/// How strong, against its bell's strongest, a partial must be for
/// [`RisePartial::HighestStrong`] to listen to it.
pub const RISE_SHARE: f64 = 0.3;

/// [`rising`], listening to the partial `which` of each bell's voice.
pub fn rising_at(sig: &Signal, strikes: &[HeardStrike], voices: &[BellVoice], which: RisePartial) -> Vec<Option<bool>> {
    let window = stretch_window(sig.rate);
    strikes
        .iter()
        .map(|s| {
            let (x0, x1, strongest) = either_side(sig, s, voices, window.len())?;
            let top = match which {
                RisePartial::Strongest => strongest,
                RisePartial::HighestStrong => highest_strong(voices.get(s.bell.checked_sub(1)?)?, sig.rate)?,
            };
            // Silence in a partial's bin (a square wave has no even
            // harmonics) is lifted to a floor far below the stretch's level.
            let floor = 1e-9 * x0.iter().chain(x1).map(|v| v * v).sum::<f64>() * window.len() as f64 + 1e-300;
            let p0 = near_power(x0, &window, top, sig.rate);
            let (p1, f) = near_peak(x1, &window, top, sig.rate);
            let rises = p1 + floor >= RISE_POWER * (p0 + floor);
            // It rings on at its strongest partial, the longest to ring: a
            // recorded bell's highest strong one may fall 30 dB in half a second.
            let (p, f) = if top == strongest {
                (p1, f)
            } else {
                near_peak(x1, &window, strongest, sig.rate)
            };
            // Where the recording ends before the last stretch, the rise alone judges.
            Some(rises && rings_on(sig, s.t, f, RING_ON_FALL * (p + floor) - floor, &window).unwrap_or(true))
        })
        .collect()
}

/// Whether the power at `f` (Hz) stays at or above `least` in every
/// stretch (windowed by `window`) from [`RING_ON_FROM_S`] to
/// [`RING_ON_TO_S`] after the strike at `t` (s); `None` where the
/// recording ends first.
fn rings_on(sig: &Signal, t: f64, f: f64, least: f64, window: &[f64]) -> Option<bool> {
    let steps = ((RING_ON_TO_S - RING_ON_FROM_S) / RING_ON_STEP_S).round() as usize;
    let turn = phasor(f, sig.rate);
    let start = |k: usize| ((t + RING_ON_FROM_S + k as f64 * RING_ON_STEP_S) * sig.rate).round() as usize;
    if start(steps) + window.len() > sig.samples.len() {
        return None;
    }
    if steps + 1 == RING_ON_STRETCHES {
        // All the stretches side by side, each's power as alone.
        let xs: [&[f64]; RING_ON_STRETCHES] = std::array::from_fn(|k| &sig.samples[start(k)..start(k) + window.len()]);
        return Some(powers_at(xs, window, turn).iter().all(|&p| p >= least));
    }
    Some((0..=steps).all(|k| power_at(&sig.samples[start(k)..start(k) + window.len()], window, turn) >= least))
}

/// The stretches [`rings_on`] weighs: from [`RING_ON_FROM_S`] to
/// [`RING_ON_TO_S`] every [`RING_ON_STEP_S`].
const RING_ON_STRETCHES: usize = 7;

/// [`power_at`] of each of `xs` (each as long as `w`), side by side: each
/// one's chain of products and sums waits on itself only (its numbers
/// those of [`power_at`] alone, bit for bit).
fn powers_at<const K: usize>(xs: [&[f64]; K], w: &[f64], (c, si): (f64, f64)) -> [f64; K] {
    let n = w.len();
    if xs.iter().any(|x| x.len() != n) {
        return xs.map(|x| power_at(x, w, (c, si)));
    }
    let (mut p, mut sum) = ([(1.0f64, 0.0f64); K], [(0.0f64, 0.0f64); K]);
    for (i, wi) in w.iter().enumerate() {
        for ((s, p), x) in sum.iter_mut().zip(p.iter_mut()).zip(&xs) {
            let a = x[i] * wi;
            *s = (s.0 + a * p.0, s.1 + a * p.1);
            *p = (p.0 * c - p.1 * si, p.0 * si + p.1 * c);
        }
    }
    sum.map(|s| s.0 * s.0 + s.1 * s.1)
}

/// The phasor one sample turns at `f` (Hz) at `rate` (Hz).
fn phasor(f: f64, rate: f64) -> (f64, f64) {
    let om = 2.0 * PI * f / rate;
    (om.cos(), -om.sin())
}

/// The power of `x` windowed by `w` at the frequency one sample turns by
/// `turn` ([`phasor`]).
fn power_at(x: &[f64], w: &[f64], (c, si): (f64, f64)) -> f64 {
    let (mut p, mut sum) = ((1.0f64, 0.0f64), (0.0f64, 0.0f64));
    for (v, wi) in x.iter().zip(w) {
        let a = v * wi;
        sum = (sum.0 + a * p.0, sum.1 + a * p.1);
        p = (p.0 * c - p.1 * si, p.0 * si + p.1 * c);
    }
    sum.0 * sum.0 + sum.1 * sum.1
}

/// The highest partial of `v` at least [`RISE_SHARE`] of its strongest,
/// under 0.45 of the sample rate `rate` (Hz).
fn highest_strong(v: &BellVoice, rate: f64) -> Option<f64> {
    let top = v.partials.iter().map(|p| p.strength).fold(0.0, f64::max);
    v.partials
        .iter()
        .filter(|p| p.strength >= RISE_SHARE * top && p.freq_hz < 0.45 * rate)
        .map(|p| p.freq_hz)
        .reduce(f64::max)
}

/// The Hann window of a stretch before or after an onset.
fn stretch_window(rate: f64) -> Vec<f64> {
    let len = (STRETCH_S * rate).round() as usize;
    (0..len)
        .map(|i| 0.5 - 0.5 * (2.0 * PI * i as f64 / len as f64).cos())
        .collect()
}

/// The stretches of `len` samples before and after strike `s`, and the
/// frequency (Hz) of its bell's strongest partial; `None` where the
/// recording does not reach both sides or the bell has no partial.
fn either_side<'a>(
    sig: &'a Signal,
    s: &HeardStrike,
    voices: &[BellVoice],
    len: usize,
) -> Option<(&'a [f64], &'a [f64], f64)> {
    let v = voices.get(s.bell.checked_sub(1)?)?;
    let before = ((s.t - BEFORE_END_S - STRETCH_S) * sig.rate).round();
    let after = ((s.t + AFTER_START_S) * sig.rate).round();
    if before < 0.0 || after as usize + len > sig.samples.len() {
        return None;
    }
    let top = v.partials.iter().max_by(|a, b| a.strength.total_cmp(&b.strength))?;
    Some((
        &sig.samples[before as usize..before as usize + len],
        &sig.samples[after as usize..after as usize + len],
        top.freq_hz,
    ))
}

/// For each of `strikes` (as [`rising`]): how much its bell's sound
/// rises an octave and two octaves below its strongest partial (where a
/// tower bell's prime and hum are, and a handbell has nothing), against
/// the rise at that partial, in power: the greater of the two rises over
/// the partial's; `None` where the partial does not rise or the
/// recording does not reach both sides. A tower bell's hum and prime rise
/// with its nominal; a handbell's strike note rises alone (see
/// [`TOWER_BELOW`]).
pub fn below_nominal(sig: &Signal, strikes: &[HeardStrike], voices: &[BellVoice]) -> Vec<Option<f64>> {
    let window = stretch_window(sig.rate);
    strikes
        .iter()
        .map(|s| {
            let (x0, x1, top) = either_side(sig, s, voices, window.len())?;
            let rise = |f: f64| {
                if f < 40.0 {
                    return 0.0;
                }
                (near_power(x1, &window, f, sig.rate) - near_power(x0, &window, f, sig.rate)).max(0.0)
            };
            let at = rise(top);
            (at > 0.0).then(|| rise(0.5 * top).max(rise(0.25 * top)) / at)
        })
        .collect()
}

/// The median rise below the strongest partial ([`below_nominal`]) over
/// which what is heard is a tower bell's (its hum or prime rising with
/// its nominal), not a handbell's, and under which ([`HANDBELL_BELOW`])
/// a handbell's. Measured 2026-11-26 on the strikes heard (median over a
/// recording): see docs/strikes.md, "Handbells heard as handbells".
pub const TOWER_BELOW: f64 = 0.01;
/// See [`TOWER_BELOW`].
pub const HANDBELL_BELOW: f64 = 0.001;

/// The largest power of `x` (windowed by `w`) within 1.5 % of `f` (Hz):
/// a real bell's partial may lie a little off where it is assumed.
fn near_power(x: &[f64], w: &[f64], f: f64, rate: f64) -> f64 {
    near_peak(x, w, f, rate).0
}

/// [`near_power`], and the frequency (Hz) it is at.
fn near_peak(x: &[f64], w: &[f64], f: f64, rate: f64) -> (f64, f64) {
    // Each frequency's phasor turned a step at a time (a tenth of a
    // second: no rounding to speak of), the seven side by side so that no
    // one's chain of products waits on another's (each as alone, bit for
    // bit). Held as eight lanes of each part (the eighth a copy of the
    // seventh, not read), four at a time, so the compiler turns and sums
    // them in vectors (speed-8: as seven (re, im) pairs it did not, 3.3 %
    // of the ten minutes with templates).
    let at = |k: i32| f * (1.0 + 0.005 * f64::from(k));
    let mut turn = ([0.0f64; 8], [0.0f64; 8]);
    for (l, k) in (0..8).zip((-3..=3).chain([3])) {
        let om = 2.0 * PI * f * (1.0 + 0.005 * f64::from(k)) / rate;
        (turn.0[l], turn.1[l]) = (om.cos(), -om.sin());
    }
    // Four lanes at a time (eight held all at once left the registers).
    let (mut sr, mut sim) = ([0.0f64; 8], [0.0f64; 8]);
    for h in [0, 4] {
        let c: [f64; 4] = turn.0[h..h + 4].try_into().expect("four");
        let si: [f64; 4] = turn.1[h..h + 4].try_into().expect("four");
        let (mut pr, mut pi) = ([1.0f64; 4], [0.0f64; 4]);
        let (mut r, mut i) = ([0.0f64; 4], [0.0f64; 4]);
        for (v, wi) in x.iter().zip(w) {
            let a = v * wi;
            for l in 0..4 {
                r[l] += a * pr[l];
                i[l] += a * pi[l];
                let (p0, p1) = (pr[l], pi[l]);
                pr[l] = p0 * c[l] - p1 * si[l];
                pi[l] = p0 * si[l] + p1 * c[l];
            }
        }
        sr[h..h + 4].copy_from_slice(&r);
        sim[h..h + 4].copy_from_slice(&i);
    }
    // The first of equal powers, as a fold of max kept the value.
    let mut best = (0.0, f);
    for (l, k) in (-3..=3).enumerate() {
        let p = sr[l] * sr[l] + sim[l] * sim[l];
        if p > best.0 {
            best = (p, at(k));
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::strikes::VoicePartial;

    #[test]
    fn stretches_weighed_side_by_side_are_each_weighed_alone() {
        let rate = 44_100.0;
        let x: Vec<f64> = (0..40_000)
            .map(|i| ((i * 7919) % 2003) as f64 / 1001.5 - 1.0 + (0.07 * i as f64).sin())
            .collect();
        let w = stretch_window(rate);
        let turn = phasor(1234.5, rate);
        let xs: [&[f64]; RING_ON_STRETCHES] = std::array::from_fn(|k| &x[k * 2205..k * 2205 + w.len()]);
        let each = xs.map(|x| power_at(x, &w, turn).to_bits());
        assert_eq!(powers_at(xs, &w, turn).map(f64::to_bits), each);
        assert_eq!(
            ((RING_ON_TO_S - RING_ON_FROM_S) / RING_ON_STEP_S).round() as usize + 1,
            RING_ON_STRETCHES
        );
    }

    fn strike(t: f64) -> HeardStrike {
        HeardStrike {
            bell: 1,
            t,
            strength: 1.0,
            double: None,
        }
    }

    /// A partial struck at 1 s rises; a steady tone at the same frequency
    /// does not; a strike too near the start cannot be judged.
    #[test]
    fn a_strike_rises_and_a_steady_tone_does_not() {
        let rate = 8000.0;
        let voices = [BellVoice::from_nominal(1000.0)];
        let struck = Signal {
            rate,
            samples: (0..16_000)
                .map(|i| {
                    let t = i as f64 / rate;
                    let tone = 0.01 * (2.0 * PI * 1000.0 * t).sin();
                    tone + if t >= 1.0 {
                        (2.0 * PI * 1000.0 * t).sin() * (-(t - 1.0) / 0.5).exp()
                    } else {
                        0.0
                    }
                })
                .collect(),
        };
        let steady = Signal {
            rate,
            samples: (0..16_000)
                .map(|i| (2.0 * PI * 1000.0 * i as f64 / rate).sin())
                .collect(),
        };
        assert_eq!(
            rising(&struck, &[strike(1.0), strike(0.05)], &voices),
            vec![Some(true), None]
        );
        assert_eq!(rising(&steady, &[strike(1.0)], &voices), vec![Some(false)]);
    }

    /// Syllables of speech on a bell's partial: each starts the partial
    /// (it rises) and stops 0.15 s on, the next 0.25 s after the last;
    /// a bell's strike rings on, a handbell's too (falling 12 dB/s).
    #[test]
    fn a_syllable_rises_but_does_not_ring_on_as_a_bell_does() {
        let rate = 8000.0;
        let voices = [BellVoice::from_nominal(1000.0)];
        let tone = |t: f64| (2.0 * PI * 1000.0 * t).sin();
        let of = |level: &dyn Fn(f64) -> f64| Signal {
            rate,
            samples: (0..24_000)
                .map(|i| {
                    let t = i as f64 / rate;
                    1e-4 * tone(t) + level(t) * tone(t)
                })
                .collect(),
        };
        let syllables = of(&|t| {
            let into = (t - 1.0).rem_euclid(0.25);
            if t >= 1.0 && into < 0.15 {
                1.0
            } else {
                0.0
            }
        });
        let bell = of(&|t| if t >= 1.0 { (-(t - 1.0) / 0.5).exp() } else { 0.0 });
        // 12 dB/s in amplitude: 10^(-12/20) a second.
        let handbell = of(&|t| if t >= 1.0 { 10f64.powf(-0.6 * (t - 1.0)) } else { 0.0 });
        assert_eq!(rising(&syllables, &[strike(1.0)], &voices), vec![Some(false)]);
        assert_eq!(rising(&bell, &[strike(1.0)], &voices), vec![Some(true)]);
        assert_eq!(rising(&handbell, &[strike(1.0)], &voices), vec![Some(true)]);
        // Too near the end to hear it ring on: the rise alone judges.
        let last = of(&|t| if (2.6..2.75).contains(&t) { 1.0 } else { 0.0 });
        assert_eq!(rising(&last, &[strike(2.6)], &voices), vec![Some(true)]);
    }

    /// A recorded bell's voice measured on its template: its strongest
    /// partial (a hum at 300 Hz) still rings from the strike before, its
    /// upper partial (2100 Hz, 0.5 of it) starts afresh at each strike.
    /// Listened to at the strongest the strike does not rise; at the
    /// highest strong partial it does; a steady tone on both does neither.
    #[test]
    fn a_bells_own_upper_partial_rises_where_its_ringing_hum_does_not() {
        let rate = 8000.0;
        let voices = [BellVoice {
            partials: vec![
                VoicePartial {
                    freq_hz: 300.0,
                    strength: 1.0,
                    uncertainty: 0.005,
                },
                VoicePartial {
                    freq_hz: 2100.0,
                    strength: 0.5,
                    uncertainty: 0.005,
                },
                VoicePartial {
                    freq_hz: 3000.0,
                    strength: 0.1,
                    uncertainty: 0.005,
                },
            ],
        }];
        let hum = |t: f64| (2.0 * PI * 300.0 * t).sin();
        let struck = Signal {
            rate,
            samples: (0..16_000)
                .map(|i| {
                    let t = i as f64 / rate;
                    let upper = if t >= 1.0 {
                        (2.0 * PI * 2100.0 * t).sin() * (-(t - 1.0) / 0.3).exp()
                    } else {
                        0.0
                    };
                    hum(t) + 0.5 * upper
                })
                .collect(),
        };
        let steady = Signal {
            rate,
            samples: (0..16_000)
                .map(|i| {
                    let t = i as f64 / rate;
                    hum(t) + 0.5 * (2.0 * PI * 2100.0 * t).sin()
                })
                .collect(),
        };
        let at = |sig: &Signal, which| rising_at(sig, &[strike(1.0)], &voices, which);
        assert_eq!(at(&struck, RisePartial::Strongest), vec![Some(false)]);
        assert_eq!(at(&struck, RisePartial::HighestStrong), vec![Some(true)]);
        assert_eq!(at(&steady, RisePartial::HighestStrong), vec![Some(false)]);
    }

    /// The seven frequencies turned side by side give each one's power
    /// as turned alone (the loop as it was), bit for bit.
    #[test]
    fn the_power_near_a_partial_is_each_frequencys_as_alone() {
        let rate = 44_100.0;
        let x: Vec<f64> = (0..4410)
            .map(|i| (i as f64 * 0.11).sin() + ((i * 31) % 17) as f64 * 0.01)
            .collect();
        let w: Vec<f64> = (0..4410)
            .map(|i| 0.5 - 0.5 * (2.0 * PI * i as f64 / 4410.0).cos())
            .collect();
        let f = 771.3;
        let alone = (-3..=3)
            .map(|k| {
                let om = 2.0 * PI * f * (1.0 + 0.005 * f64::from(k)) / rate;
                let (c, s) = (om.cos(), -om.sin());
                let (mut p, mut sum) = ((1.0f64, 0.0f64), (0.0, 0.0));
                for (v, wi) in x.iter().zip(&w) {
                    let a = v * wi;
                    sum = (sum.0 + a * p.0, sum.1 + a * p.1);
                    p = (p.0 * c - p.1 * s, p.0 * s + p.1 * c);
                }
                sum.0 * sum.0 + sum.1 * sum.1
            })
            .fold(0.0, f64::max);
        assert_eq!(near_power(&x, &w, f, rate).to_bits(), alone.to_bits());
    }
}
