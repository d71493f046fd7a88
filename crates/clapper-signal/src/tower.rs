//! A synthetic tower recording with known truth (synthetic, made by the
//! project): a ring of bells rung in rounds, handstroke and backstroke, each
//! strike's time known, with chosen odd-struckness, striking errors and
//! double strikes. The test data for finding strikes in a recording
//! (`clapper strikes`, issue 19); never a real tower's sound.
//!
//! Rounds: bell 1 (the treble) first in every row, `interval` between
//! successive bells, and a handstroke gap of `handstroke_gap` intervals
//! before each handstroke row but the first. Rows alternate handstroke
//! (rows 0, 2, ...) and backstroke.

use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;

use crate::synth::{synthesize, typical_partials, Strike, SynthSpec};
use crate::{Signal, SignalError};

/// One bell of the ring.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RingBell {
    /// Nominal frequency (Hz): the partials are [`typical_partials`] scaled to it.
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
}

/// A strike as put into the recording.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrueStrike {
    /// Bell, counting from 1.
    pub bell: usize,
    /// Row, counting from 0.
    pub row: usize,
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
    for row in 0..spec.rows {
        let hand = row % 2 == 0;
        let row_start = spec.lead_in + spec.interval * ((row * n) as f64 + (row / 2) as f64 * spec.handstroke_gap);
        for (i, b) in spec.bells.iter().enumerate() {
            let ideal_t = row_start + i as f64 * spec.interval;
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

/// The recording (the sum of every bell's sound, its peak scaled to 0.5)
/// and the strikes in it, in time order.
pub fn tower_recording(spec: &TowerSpec) -> Result<(Signal, Vec<TrueStrike>), SignalError> {
    let strikes = tower_strikes(spec)?;
    let end = strikes
        .iter()
        .map(|s| s.t + s.double.map_or(0.0, |d| d.0))
        .fold(0.0, f64::max)
        + spec.tail;
    let mut mix: Vec<f64> = vec![];
    for (i, b) in spec.bells.iter().enumerate() {
        // An impulse of a tenth of the bell's mass (N s) sets its partials
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
            modes: typical_partials(b.nominal_hz, b.mass_kg),
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
