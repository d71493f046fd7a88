//! A ring built from recorded strikes (issue 43): one recording of each
//! bell struck once, placed at the strike times of a [`TowerSpec`] (rounds
//! or plain hunt, the band's errors, odd-struck bells, double strikes),
//! summed (a bell is linear: two strikes sound as the sum of each), heard
//! in a [`Room`](crate::tower::Room) and with white noise, with the truth.
//!
//! The truth of each strike is the start of its sound: each recording's
//! own onset ([`sample_onset`]) is found once and the recording placed so
//! that it falls on the strike's time. No recordings ship with the project:
//! the benchmark reads them from a folder (`clapper-app`'s example
//! `real_rings`, docs/strikes.md), the tests use the project's synthetic
//! strikes.

use crate::tower::{tower_strikes, TowerSpec, TrueStrike};
use crate::{Signal, SignalError};

/// Partials of a recorded tower bell (Ringing Room's d1): each one's ratio
/// to its strongest partial, which the project first took for its nominal,
/// and its strength (docs/strikes.md, "What real bells sound like"). Seen
/// from that partial they are not a tuned bell's nominal-based ratios; but
/// an independent measurement (docs/strikes.md, issue 43's shortfalls)
/// showed that partial is the bell's prime: 0.5 the hum, 1.18 the tierce,
/// 2.0037 the true nominal, 2.98 the superquint. The tests that ring it
/// give the prime as the bell's `--nominals` frequency, a bell whose given
/// frequency is not a tuned nominal.
pub const RECORDED_PARTIALS: [(f64, f64); 7] = [
    (0.5003, 0.32),
    (1.0, 1.0),
    (1.1837, 0.45),
    (1.5628, 0.24),
    (2.0037, 0.30),
    (2.712, 0.17),
    (2.979, 0.45),
];

/// The clapper's blow in an [`UntunedStrike`]: broadband noise dying away.
#[derive(Clone, Copy, Debug)]
pub struct Blow {
    /// Its peak, against the nominal's peak of 1.
    pub amplitude: f64,
    /// Its decay time (s): recorded strikes' blows die in 2-30 ms.
    pub decay_s: f64,
    /// The noise's seed.
    pub seed: u64,
}

/// A synthetic strike of a bell with a recorded tower bell's partials
/// ([`RECORDED_PARTIALS`]), as the tests of the untuned-bell paths use it:
/// 20 ms of silence, then partials stepping to a tenth of their peak at the
/// blow (recorded bells jump to -20 dB of it) and building up over
/// `rise_s`, all dying away over `decay_s`.
#[derive(Clone, Copy, Debug)]
pub struct UntunedStrike {
    /// The frequency the partials' ratios are taken from (Hz): called the
    /// nominal by the tests, the recorded bell's prime (see
    /// [`RECORDED_PARTIALS`]).
    pub nominal_hz: f64,
    /// The partials' build-up time (s).
    pub rise_s: f64,
    /// Their decay time (s).
    pub decay_s: f64,
    /// The strike's length after the silence (s).
    pub length_s: f64,
    /// The clapper's blow, if heard.
    pub blow: Option<Blow>,
}

impl UntunedStrike {
    /// The self-calibration tests' bell (library and CLI): its blow
    /// broadband noise at 0.3 of the peak dying away over 30 ms, its
    /// partials building up over `rise_s` (s) and dying away over 0.9 s,
    /// 1.6 s long; `nominal_hz` as in [`UntunedStrike::nominal_hz`].
    pub fn with_noisy_blow(nominal_hz: f64, rise_s: f64) -> Self {
        UntunedStrike {
            nominal_hz,
            rise_s,
            decay_s: 0.9,
            length_s: 1.6,
            blow: Some(Blow {
                amplitude: 0.3,
                decay_s: 0.03,
                seed: (nominal_hz * 7.0) as u64 | 1,
            }),
        }
    }

    /// The strike sampled at `rate` (Hz); its sound starts at 20 ms.
    pub fn signal(&self, rate: f64) -> Signal {
        let mut samples = vec![0.0; (0.02 * rate) as usize];
        let mut seed = self.blow.map_or(0, |b| b.seed);
        samples.extend((0..(self.length_s * rate) as usize).map(|k| {
            let t = k as f64 / rate;
            let env = (0.1 + 0.9 * (1.0 - (-t / self.rise_s).exp())) * (-t / self.decay_s).exp();
            let tone = RECORDED_PARTIALS
                .iter()
                .map(|&(r, a)| a * (2.0 * std::f64::consts::PI * r * self.nominal_hz * t + r).sin())
                .sum::<f64>()
                * env;
            match self.blow {
                Some(b) => tone + b.amplitude * blow_noise(&mut seed) * (-t / b.decay_s).exp(),
                None => tone,
            }
        }));
        Signal { rate, samples }
    }
}

/// A strike of a bell with a recorded tower bell's partial ratios
/// ([`RECORDED_PARTIALS`], ratios to the prime, half the nominal
/// `nominal_hz`, Hz), its nominal `octave` times as strong as the table has
/// it and its tierce the root of that (the recorded ring's lowest bells are
/// heard most at their nominal, not their prime), a noisy blow of 4 ms
/// from the LCG seeded by `seed`, sampled at `rate` (Hz) after 20 ms of
/// silence. Test material for the learner (`--bells N`).
pub fn octave_heavy_strike(nominal_hz: f64, octave: f64, rate: f64, seed: u64) -> Signal {
    let prime = nominal_hz / 2.0;
    let mut samples = vec![0.0; (0.02 * rate) as usize];
    let mut noise = seed;
    samples.extend((0..(1.6 * rate) as usize).map(|k| {
        let t = k as f64 / rate;
        let tone: f64 = RECORDED_PARTIALS
            .iter()
            .map(|&(r, a)| {
                let a = match r {
                    _ if (r - 2.0).abs() < 0.1 => a * octave,
                    _ if (r - 1.18).abs() < 0.05 => a * octave.sqrt(),
                    _ => a,
                };
                a * (2.0 * std::f64::consts::PI * r * prime * t + r).sin()
            })
            .sum();
        let blow = blow_noise(&mut noise) * 0.3 * (-t / 0.004).exp();
        (tone * (0.1 + 0.9 * (1.0 - (-t / 0.02).exp())) + blow) * (-t / 0.9).exp()
    }));
    Signal { rate, samples }
}

/// The next sample of a clapper's blow's noise, uniform in [-0.5, 0.5),
/// from a small linear congruential generator whose state is `state`
/// (the synthetic strikes' noise, the same from the same seed).
pub(crate) fn blow_noise(state: &mut u64) -> f64 {
    *state = state
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    (*state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
}

/// Where a recorded strike's sound starts (s from the recording's start).
/// [`sample_onset_checked`]'s time.
pub fn sample_onset(sig: &Signal) -> Result<f64, SignalError> {
    Ok(sample_onset_checked(sig)?.t_s)
}

/// A recorded strike's start ([`sample_onset_checked`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SampleOnset {
    /// Where its sound starts (s from the recording's start).
    pub t_s: f64,
    /// Whether a whole millisecond quieter than the sound lies before it:
    /// without one the recording starts at its sound, or was cut into it
    /// (then its strikes are timed late by as much as was cut).
    pub quiet_before: bool,
}

/// Where a recorded strike's sound starts, found the same whatever the
/// lead-in before it (4 ms of a recording's own noise or 100 ms: within
/// 0.4 ms on the recorded tower bells, where the noise measured over the
/// first 5 ms moved d1's start 17 ms and d9's 4.7 ms).
///
/// After any digital silence the file starts with (a millisecond or more
/// of zeros: a recording padded before its own noise), the strike is the
/// first sample at a tenth of the recording's peak; the noise is the
/// median of the peaks of the whole 1 ms blocks before it, 2 ms before it
/// left out (the sound's rise), none where there are none; the sound starts
/// after the last whole millisecond before the strike at or under both 4
/// times that noise and 1/300 (−50 dB) of the peak, moved back (2 ms at
/// most) to the last sample at or under twice the noise. Where no such
/// millisecond lies before the strike, at the file's start (after its
/// zeros), and not [`SampleOnset::quiet_before`]. A bell's strike rises to
/// its peak within a few ms, so this is within a millisecond of where the
/// clapper met the bell.
pub fn sample_onset_checked(sig: &Signal) -> Result<SampleOnset, SignalError> {
    sig.validate()?;
    let x = &sig.samples;
    let peak = x.iter().fold(0.0f64, |p, v| p.max(v.abs()));
    if peak == 0.0 {
        return Err(SignalError::Invalid("the recorded strike is silent".into()));
    }
    let ms = ((sig.rate * 1e-3).round() as usize).max(1);
    // Padding is a millisecond or more of zeros (a waveform crosses zero too).
    let pad = x.iter().position(|v| *v != 0.0).filter(|&p| p >= ms).unwrap_or(0);
    let strike = pad
        + x[pad..]
            .iter()
            .position(|v| v.abs() >= 0.1 * peak)
            .ok_or_else(|| SignalError::Invalid("no strike in the recording".into()))?;
    // The median block, not the loudest: a recording faded in over its
    // first ms, or a lead-in shorter than the old 5 ms that took in the
    // sound's start, moved the level by the lead-in's length.
    let mut blocks: Vec<f64> = x[pad..strike.saturating_sub(2 * ms).max(pad)]
        .chunks_exact(ms)
        .map(|b| b.iter().fold(0.0f64, |p, v| p.max(v.abs())))
        .collect();
    blocks.sort_by(f64::total_cmp);
    let noise = blocks.get(blocks.len().saturating_sub(1) / 2).copied().unwrap_or(0.0);
    let level = (4.0 * noise).max(peak / 300.0);
    // Back from the strike to the last whole millisecond at or under the level.
    let (mut run, mut first, mut quiet_before) = (0, strike, false);
    for i in (pad..strike).rev() {
        if x[i].abs() > level {
            (run, first) = (0, i);
        } else {
            run += 1;
            if run >= ms {
                quiet_before = true;
                break;
            }
        }
    }
    if !quiet_before {
        return Ok(SampleOnset {
            t_s: pad as f64 / sig.rate,
            quiet_before,
        });
    }
    // Back to where the waveform last sat at the noise before the loud sample.
    let quiet = (2.0 * noise).max(peak / 3000.0);
    let mut i = first;
    while i > pad && first - i < 2 * ms && x[i - 1].abs() > quiet {
        i -= 1;
    }
    Ok(SampleOnset {
        t_s: i as f64 / sig.rate,
        quiet_before,
    })
}

/// The recording of `spec`'s ring (its strike times, method, doubles,
/// room and noise; its bells' nominals and masses are not used) from one
/// recorded strike per bell, `strikes[0]` the treble's, each at the spec's
/// rate. A double strike is the recording again, scaled by its ratio. The
/// recording's peak is scaled to 0.5.
pub fn sampled_ring(spec: &TowerSpec, strikes: &[Signal]) -> Result<(Signal, Vec<TrueStrike>), SignalError> {
    if strikes.len() != spec.bells.len() {
        return Err(SignalError::Option(format!(
            "{} recorded strikes for {} bells: one each",
            strikes.len(),
            spec.bells.len()
        )));
    }
    let mut onsets = vec![];
    for (i, s) in strikes.iter().enumerate() {
        if (s.rate - spec.rate).abs() > 1e-6 {
            return Err(SignalError::Option(format!(
                "bell {}'s strike at {} Hz, the ring at {} Hz",
                i + 1,
                s.rate,
                spec.rate
            )));
        }
        onsets.push(sample_onset(s).map_err(|e| SignalError::Invalid(format!("bell {}: {e}", i + 1)))?);
    }
    let truth = tower_strikes(spec)?;
    let end = truth
        .iter()
        .map(|s| s.t + s.double.map_or(0.0, |d| d.0))
        .fold(0.0, f64::max)
        + spec.tail;
    let n = (end * spec.rate).round() as usize;
    let mut mix = vec![0.0; n];
    let mut add = |at: f64, bell: usize, gain: f64| {
        let s = &strikes[bell];
        // Fractional placement by linear interpolation keeps the onset exact.
        let start = (at - onsets[bell]) * spec.rate;
        let i0 = start.floor();
        let frac = start - i0;
        for (k, v) in s.samples.iter().enumerate() {
            let j = i0 as i64 + k as i64;
            for (jj, w) in [(j, 1.0 - frac), (j + 1, frac)] {
                if jj >= 0 && (jj as usize) < n {
                    mix[jj as usize] += gain * w * v;
                }
            }
        }
    };
    for t in &truth {
        add(t.t, t.bell - 1, 1.0);
        if let Some((delay, ratio)) = t.double {
            add(t.t + delay, t.bell - 1, ratio);
        }
    }
    let first = truth.first().map_or(0.0, |s| s.t);
    let mix = crate::tower::in_the_room(mix, spec, first, n);
    Ok((
        Signal {
            rate: spec.rate,
            samples: mix,
        },
        truth,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tower::{major_scale, Method};

    fn strike(rate: f64, lead: usize, f: f64) -> Signal {
        let mut samples = vec![0.0; lead];
        samples.extend((0..(0.5 * rate) as usize).map(|k| {
            let t = k as f64 / rate;
            (2.0 * std::f64::consts::PI * f * t).sin() * (-t / 0.2).exp()
        }));
        Signal { rate, samples }
    }

    #[test]
    fn a_recorded_strike_starts_where_its_sound_does() {
        let s = strike(8000.0, 400, 700.0);
        let t = sample_onset(&s).unwrap();
        assert!((t - 0.05).abs() < 0.5e-3, "{t}");
        assert_eq!(sample_onset(&strike(8000.0, 0, 700.0)).unwrap(), 0.0);
        assert!(sample_onset(&Signal {
            rate: 8000.0,
            samples: vec![0.0; 100]
        })
        .is_err());
    }

    /// Zeros, then the room's noise, then the strike: the sound starts at
    /// the strike, not where the noise does.
    #[test]
    fn a_strike_padded_with_zeros_before_its_noise_starts_at_its_sound() {
        let rate = 8000.0;
        let mut s = strike(rate, 800, 700.0);
        let mut rng = <rand_pcg::Pcg64 as rand::SeedableRng>::seed_from_u64(7);
        for v in &mut s.samples[400..] {
            *v += 2e-2 * rand::Rng::random_range(&mut rng, -0.5..0.5);
        }
        let t = sample_onset(&s).unwrap();
        assert!((t - 0.1).abs() < 0.5e-3, "{t}");
    }

    #[test]
    fn each_strike_sounds_at_its_true_time() {
        let rate = 8000.0;
        let spec = TowerSpec {
            rate,
            rows: 4,
            method: Method::PlainHunt,
            ..TowerSpec::new(major_scale(4, 1000.0).unwrap())
        };
        let strikes: Vec<Signal> = (0..4)
            .map(|i| strike(rate, 100 * (i + 1), 500.0 + 100.0 * i as f64))
            .collect();
        let (sig, truth) = sampled_ring(&spec, &strikes).unwrap();
        assert_eq!(truth.len(), 16);
        // The first strike: silence before it, sound from it.
        let first = truth[0].t;
        let k = (first * rate).round() as usize;
        assert!(sig.samples[..k - 2].iter().all(|v| *v == 0.0));
        assert!(sig.samples[k..k + 8].iter().any(|v| *v != 0.0));
        assert!(sampled_ring(&spec, &strikes[..3]).is_err());
    }
}
