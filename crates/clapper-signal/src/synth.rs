//! Modal synthesis of a struck bell: each strike adds velocity to every
//! mode in proportion to its impulse, the mode's receptance at the strike
//! point (1/M_n) and the contact pulse's spectrum; each mode rings down as
//! exp(−π f t / Q), faster while the clapper rests against the bell
//! (friction, the paper's Figs 3 and 4). Close doublets beat.

use std::f64::consts::PI;

use crate::{Signal, SignalError};

/// A mode of the bell as heard.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SynthMode {
    /// Frequency (Hz).
    pub freq_hz: f64,
    /// Q factor with the clapper off the bell.
    pub q: f64,
    /// Effective mass at the strike point (kg).
    pub effective_mass: f64,
    /// Split of the doublet (Hz): the mode is two equal components at
    /// f ± split/2 that beat at `split` Hz; 0 for a single mode.
    pub doublet_split_hz: f64,
}

/// One strike: time (s), impulse at the strike point (N s), contact pulse
/// length (s; 0 for an ideal impulse).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Strike {
    /// Time (s).
    pub t: f64,
    /// Impulse (N s).
    pub impulse: f64,
    /// Half-sine contact pulse length (s).
    pub pulse: f64,
}

/// What to synthesise.
#[derive(Clone, Debug, PartialEq)]
pub struct SynthSpec {
    /// Sample rate (Hz).
    pub rate: f64,
    /// Length (s).
    pub duration: f64,
    /// The modes.
    pub modes: Vec<SynthMode>,
    /// The strikes, in any order.
    pub strikes: Vec<Strike>,
    /// Intervals (s) while the clapper rests on the bell.
    pub rests: Vec<(f64, f64)>,
    /// How many times faster the modes decay while the clapper rests
    /// (friction between clapper and bell). Default 8: the paper's Fig 4
    /// falls roughly that much faster after rest than before.
    pub rest_damping: f64,
    /// Output the acceleration of the bell surface (an accelerometer) rather
    /// than its velocity (closer to the radiated sound).
    pub acceleration: bool,
}

use clapper_core::vibration::half_sine_spectrum as pulse_spectrum;

/// The most samples one synthesis may produce: ten minutes at 96 kHz.
pub const MAX_SAMPLES: usize = 96_000 * 600;

/// Every mode positive, finite and below half the sample rate.
fn check_modes(spec: &SynthSpec) -> Result<(), SignalError> {
    for m in &spec.modes {
        let ok = m.freq_hz > 0.0
            && m.freq_hz < spec.rate / 2.0
            && m.q > 0.0
            && m.effective_mass > 0.0
            && m.doublet_split_hz >= 0.0
            && m.freq_hz.is_finite()
            && m.q.is_finite()
            && m.effective_mass.is_finite();
        if !ok {
            return Err(SignalError::Option(format!(
                "a mode at {} Hz, Q {}, effective mass {} kg, doublet split {} Hz: positive values, the frequency below half the sample rate ({} Hz)",
                m.freq_hz,
                m.q,
                m.effective_mass,
                m.doublet_split_hz,
                spec.rate / 2.0
            )));
        }
    }
    Ok(())
}

/// Synthesise. The output is the bell's surface velocity (m/s) or
/// acceleration (m/s²) at the strike point.
pub fn synthesize(spec: &SynthSpec) -> Result<Signal, SignalError> {
    if !(spec.rate.is_finite() && spec.rate >= 1000.0) {
        return Err(SignalError::Option(format!(
            "sample rate {} Hz: at least 1000",
            spec.rate
        )));
    }
    let n = (spec.duration * spec.rate).round();
    if !(n.is_finite() && n >= 1.0 && n <= MAX_SAMPLES as f64) {
        return Err(SignalError::Option(format!(
            "{} s at {} Hz: from one sample to {MAX_SAMPLES} samples",
            spec.duration, spec.rate
        )));
    }
    if !(spec.rest_damping.is_finite() && spec.rest_damping >= 1.0) {
        return Err(SignalError::Option(format!(
            "rest damping {}: at least 1",
            spec.rest_damping
        )));
    }
    check_modes(spec)?;
    let n = n as usize;
    let dt = 1.0 / spec.rate;
    // Components: (ω, α, receptance weight).
    let mut comps: Vec<(f64, f64, f64)> = vec![];
    for m in &spec.modes {
        let alpha = PI * m.freq_hz / m.q;
        if m.doublet_split_hz > 0.0 {
            for s in [-0.5, 0.5] {
                let f = m.freq_hz + s * m.doublet_split_hz;
                comps.push((2.0 * PI * f, alpha, 0.5 / m.effective_mass));
            }
        } else {
            comps.push((2.0 * PI * m.freq_hz, alpha, 1.0 / m.effective_mass));
        }
    }
    let mut strikes = spec.strikes.clone();
    strikes.sort_by(|a, b| a.t.total_cmp(&b.t));
    let resting = |t: f64| spec.rests.iter().any(|&(a, b)| t >= a && t < b);
    // Each component is a phasor z = velocity amplitude e^{iφ}; per sample it
    // turns by ω dt and shrinks by e^{−α dt} (or e^{−k α dt} at rest).
    let mut z: Vec<(f64, f64)> = vec![(0.0, 0.0); comps.len()];
    let turn: Vec<(f64, f64)> = comps.iter().map(|c| ((c.0 * dt).cos(), (c.0 * dt).sin())).collect();
    let free: Vec<f64> = comps.iter().map(|c| (-c.1 * dt).exp()).collect();
    let rest: Vec<f64> = comps.iter().map(|c| (-c.1 * spec.rest_damping * dt).exp()).collect();
    let mut next = 0;
    let mut out = Vec::with_capacity(n);
    for i in 0..n {
        let t = i as f64 * dt;
        while next < strikes.len() && strikes[next].t <= t {
            let s = strikes[next];
            for (k, c) in comps.iter().enumerate() {
                // An impulse sets the mode moving with velocity I/M_n (sine phase).
                z[k].1 += s.impulse * c.2 * pulse_spectrum(c.0, s.pulse);
            }
            next += 1;
        }
        let decay = if resting(t) { &rest } else { &free };
        let mut y = 0.0;
        for k in 0..z.len() {
            let (re, im) = z[k];
            let (c, s) = turn[k];
            let d = decay[k];
            z[k] = ((re * c - im * s) * d, (re * s + im * c) * d);
            // Velocity is the imaginary part; acceleration its derivative ω Re.
            y += if spec.acceleration { comps[k].0 * z[k].0 } else { z[k].1 };
        }
        out.push(y);
    }
    Ok(Signal {
        rate: spec.rate,
        samples: out,
    })
}

/// The lab bell's three strongest partials (Section 2.1, Fig 3(b)): 624 Hz
/// Q 1300, 981 Hz Q 1000, 1310 Hz Q 2000. Their effective masses are not
/// measured; the paper's estimate, a third of the bell's 45.8 kg, is used for
/// all. Doublet splits of 0.5 to 1 Hz, typical of a slightly asymmetric bell
/// (assumed; Fig 3 shows beating).
pub fn lab_partials() -> Vec<SynthMode> {
    [(624.0, 1300.0, 0.7), (981.0, 1000.0, 0.5), (1310.0, 2000.0, 0.9)]
        .iter()
        .map(|&(f, q, d)| SynthMode {
            freq_hz: f,
            q,
            effective_mass: 45.8 / 3.0,
            doublet_split_hz: d,
        })
        .collect()
}

/// A typical tuned English bell scaled to `nominal_hz`: hum, prime, tierce,
/// quint, nominal, superquint, octave nominal at the ratios 0.25, 0.5, 0.6,
/// 0.75, 1, 1.5, 2 of the nominal, Q falling from 3000 (hum) to 1000, each
/// with an effective mass of a third of `bell_mass` and a 0.5 Hz doublet.
pub fn typical_partials(nominal_hz: f64, bell_mass: f64) -> Vec<SynthMode> {
    [
        (0.25, 3000.0),
        (0.5, 2500.0),
        (0.6, 2000.0),
        (0.75, 1800.0),
        (1.0, 1500.0),
        (1.5, 1200.0),
        (2.0, 1000.0),
    ]
    .iter()
    .map(|&(r, q)| SynthMode {
        freq_hz: r * nominal_hz,
        q,
        effective_mass: bell_mass / 3.0,
        doublet_split_hz: 0.5,
    })
    .collect()
}

/// Where the decay of a partial changes rate most: the breakpoint of the
/// best two-line fit to its level (dB) against time, searched over the
/// points from `from` on until the level has fallen 60 dB. Returns (time s, slope before, slope after) in
/// dB/s. For the moment the clapper comes to rest.
pub fn decay_change(level: &[(f64, f64)], from: f64) -> Option<(f64, f64, f64)> {
    // From `from` until the level has fallen 60 dB: below that a recording
    // (or the spectrogram's floor) no longer follows the decay.
    let after: Vec<(f64, f64)> = level.iter().copied().filter(|p| p.0 >= from).collect();
    let top = after.iter().map(|p| p.1).fold(f64::NEG_INFINITY, f64::max);
    let pts: Vec<(f64, f64)> = after.into_iter().take_while(|p| p.1 > top - 60.0).collect();
    if pts.len() < 8 {
        return None;
    }
    // A line y = a + b t through the points, and its squared error.
    let fit = |s: &[(f64, f64)]| -> (f64, f64, f64) {
        let n = s.len() as f64;
        let mx = s.iter().map(|p| p.0).sum::<f64>() / n;
        let my = s.iter().map(|p| p.1).sum::<f64>() / n;
        let sxx: f64 = s.iter().map(|p| (p.0 - mx).powi(2)).sum();
        let sxy: f64 = s.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
        let b = if sxx > 0.0 { sxy / sxx } else { 0.0 };
        let sse = s.iter().map(|p| (p.1 - my - b * (p.0 - mx)).powi(2)).sum();
        (my - b * mx, b, sse)
    };
    (3..pts.len() - 3)
        .map(|k| {
            let (a1, b1, e1) = fit(&pts[..k]);
            let (a2, b2, e2) = fit(&pts[k..]);
            // Frames straddling the change blur it: take where the lines meet,
            // if that lies between the neighbouring frames.
            let meet = if b1 != b2 { (a2 - a1) / (b1 - b2) } else { pts[k].0 };
            let t = if meet >= pts[k - 1].0 - 1e-12 && meet <= pts[k].0 + 1e-12 {
                meet
            } else {
                0.5 * (pts[k - 1].0 + pts[k].0)
            };
            (e1 + e2, t, b1, b2)
        })
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .map(|(_, t, b1, b2)| (t, b1, b2))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::modes::{find_modes, ModeOptions};
    use crate::spectrogram::spectrogram;

    #[test]
    fn a_chime_rings_at_its_modes_and_qs() {
        let modes = vec![
            SynthMode {
                freq_hz: 624.0,
                q: 1300.0,
                effective_mass: 15.0,
                doublet_split_hz: 0.0,
            },
            SynthMode {
                freq_hz: 981.0,
                q: 1000.0,
                effective_mass: 15.0,
                doublet_split_hz: 0.0,
            },
        ];
        let spec = SynthSpec {
            rate: 22050.0,
            duration: 3.0,
            modes,
            strikes: vec![Strike {
                t: 0.1,
                impulse: 1.0,
                pulse: 3e-4,
            }],
            rests: vec![],
            rest_damping: 8.0,
            acceleration: false,
        };
        let sig = synthesize(&spec).unwrap();
        let found = find_modes(&sig, &ModeOptions::default()).unwrap();
        assert_eq!(found.len(), 2);
        assert!((found[0].freq_hz - 624.0).abs() < 0.624 * 0.1);
        assert!((found[0].q.unwrap() - 1300.0).abs() / 1300.0 < 0.05);
        assert!((found[1].q.unwrap() - 1000.0).abs() / 1000.0 < 0.05);
    }

    #[test]
    fn resting_clapper_speeds_the_decay_from_that_moment() {
        let spec = SynthSpec {
            rate: 16000.0,
            duration: 3.0,
            modes: vec![SynthMode {
                freq_hz: 624.0,
                q: 1300.0,
                effective_mass: 15.0,
                doublet_split_hz: 0.0,
            }],
            strikes: vec![Strike {
                t: 0.1,
                impulse: 1.0,
                pulse: 0.0,
            }],
            rests: vec![(1.0, 3.0)],
            rest_damping: 8.0,
            acceleration: false,
        };
        let sig = synthesize(&spec).unwrap();
        let s = spectrogram(&sig, 512, 0.75, 200.0).unwrap();
        let (t, b1, b2) = decay_change(&s.decay(624.0), 0.15).unwrap();
        assert!((t - 1.0).abs() < 0.02, "rest found at {t}");
        assert!(b2 < 4.0 * b1, "{b1} {b2}");
    }

    #[test]
    fn bad_specs_are_refused() {
        let ok = SynthSpec {
            rate: 8000.0,
            duration: 1.0,
            modes: lab_partials(),
            strikes: vec![],
            rests: vec![],
            rest_damping: 8.0,
            acceleration: false,
        };
        assert!(synthesize(&ok).is_ok());
        assert!(synthesize(&SynthSpec {
            rate: 10.0,
            ..ok.clone()
        })
        .is_err());
        assert!(synthesize(&SynthSpec {
            duration: 1e9,
            ..ok.clone()
        })
        .is_err());
        assert!(synthesize(&SynthSpec {
            rest_damping: 0.5,
            ..ok.clone()
        })
        .is_err());
        // 1310 Hz is above half of 2000 Hz.
        assert!(synthesize(&SynthSpec { rate: 2000.0, ..ok }).is_err());
    }
}
