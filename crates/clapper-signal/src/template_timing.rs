//! Strikes timed against each bell's own recorded strike (issue 43): where
//! a template of the bell struck alone is known, each strike heard is
//! timed again by sliding the template over the recording near it. The
//! template's sound starts at a known point ([`sample_onset`]), so the lag
//! where it matches best is the start of the strike's sound, however slowly
//! the bell's partials build up: the band finder's timing, a fifth of the
//! way up each band's step, heard the recorded tower bells measured 15 to
//! 85 ms late, by an amount that changes with the room.
//!
//! The match is the cross-correlation of the recording with the first
//! 150 ms of the template's sound, and 40 ms of silence before it, over
//! the recording's level there (its
//! magnitude: a bell struck on the other side sounds with some partials'
//! signs turned), searched from 100 ms before to 40 ms after the strike's
//! time as the band finder heard it less the bell's lateness learned on a
//! ring of its templates ([`crate::lateness::from_templates`]), or from
//! 200 ms before to 100 ms after it where that lateness is not sure; the strike is the best match unless one at least 0.6 as good lies
//! 30 ms or more before it (a double strike's second blow, no louder,
//! matches later).

use realfft::num_complex::Complex;
use realfft::RealFftPlanner;

use crate::sampled_ring::sample_onset;
use crate::strikes::Heard;
use crate::{Signal, SignalError};

/// The length of template matched (s).
const MATCH_S: f64 = 0.15;
/// And the silence matched before it (s).
const PRE_S: f64 = 0.04;
/// How far before the strike's time as first heard, less its bell's
/// lateness, the match is searched (s): a double strike timed at its
/// second blow (up to 100 ms after the first).
const EARLY_S: f64 = 0.1;
/// How far after (s).
const LATE_S: f64 = 0.04;
/// Without a sure lateness, how far before the time heard (s): the band
/// finder heard the recorded bells measured up to 85 ms late.
const WIDE_EARLY_S: f64 = 0.2;
/// And after it (s).
const WIDE_LATE_S: f64 = 0.1;
/// A match this share of the best, 30 ms or more before it, is the strike:
/// a double strike's second blow (at most as loud) matches later.
const FIRST_SHARE: f64 = 0.6;
/// How far (s) before the best match such a match must lie: nearer ones
/// are the template's own partials coming back into step (on the recorded
/// tower bells, 12 ms before the true lag).
const GAP_S: f64 = 0.03;
/// The dip (a share of the earlier match) that parts two blows.
const DIP: f64 = 0.7;

/// Linear resampling of `s` to `rate` (Hz): templates recorded at another
/// rate than the recording.
fn resample(s: &Signal, rate: f64) -> Signal {
    if (s.rate - rate).abs() < 1e-9 {
        return s.clone();
    }
    let n = (s.samples.len() as f64 * rate / s.rate).floor() as usize;
    let samples = (0..n)
        .map(|k| {
            let x = k as f64 * s.rate / rate;
            let i = x.floor() as usize;
            let f = x - i as f64;
            let a = s.samples[i.min(s.samples.len() - 1)];
            let b = s.samples[(i + 1).min(s.samples.len() - 1)];
            a + f * (b - a)
        })
        .collect();
    Signal { rate, samples }
}

/// Time every strike of `heard` (as the band finder heard it) again
/// against its bell's template (`templates[0]` the treble's), near its
/// time less the bell's `lateness` (s, as learned on a ring of the
/// templates: [`crate::lateness::from_templates`]) where it is known, else
/// from 200 ms before to 100 ms after its time. Returns how far each bell's strikes moved (the median, s),
/// treble first; a bell whose template is too short keeps its times.
pub fn retime(
    sig: &Signal,
    heard: &mut Heard,
    templates: &[Signal],
    lateness: &[Option<f64>],
) -> Result<Vec<Option<f64>>, SignalError> {
    let moves = retime_each(sig, heard, templates, lateness)?;
    let mut moved: Vec<Vec<f64>> = vec![vec![]; templates.len()];
    for (s, m) in heard.strikes.iter().zip(moves) {
        if let Some(m) = m {
            moved[s.bell - 1].push(m);
        }
    }
    heard
        .strikes
        .sort_by(|a, b| a.t.total_cmp(&b.t).then(a.bell.cmp(&b.bell)));
    Ok(moved.into_iter().map(median_of).collect())
}

/// The median of `v` (the upper of the middle two), if any.
pub fn median_of(mut v: Vec<f64>) -> Option<f64> {
    v.sort_by(f64::total_cmp);
    v.get(v.len() / 2).copied()
}

/// [`retime`] without the order and the medians: each strike of `heard`
/// timed again where its template matches, in place (the strikes then
/// out of time order), and how far each moved (s; none where its bell's
/// template is too short or nothing matched). For a recording heard in
/// windows ([`crate::strikes::find_strikes_streamed`]): `sig` is the
/// window's audio, the strikes' times from its start.
pub fn retime_each(
    sig: &Signal,
    heard: &mut Heard,
    templates: &[Signal],
    lateness: &[Option<f64>],
) -> Result<Vec<Option<f64>>, SignalError> {
    sig.validate()?;
    let m = Matcher::new(sig.rate, templates)?;
    let mut scratch = m.scratch();
    let mut moves = vec![];
    for s in &mut heard.strikes {
        let Some(Some(tspec)) = m.spectra.get(s.bell - 1) else {
            moves.push(None);
            continue;
        };
        // Near the time less the bell's lateness where that is sure, else
        // widely about the time heard.
        let (from, to) = match lateness.get(s.bell - 1).copied().flatten() {
            Some(late) => (s.t - late.max(0.0) - EARLY_S, s.t - late.max(0.0) + LATE_S),
            None => (s.t - WIDE_EARLY_S, s.t + WIDE_LATE_S),
        };
        let t = m.best_match(&sig.samples, tspec, from, to, &mut scratch)?;
        moves.push(t.map(|t| t - s.t));
        if let Some(t) = t {
            s.t = t;
        }
    }
    Ok(moves)
}

/// The templates' spectra and the transforms, at the recording's rate.
struct Matcher {
    rate: f64,
    /// Silence matched before the template's sound (samples).
    pre: usize,
    /// Length matched (samples, `pre` included).
    len: usize,
    /// Transform length.
    n: usize,
    fwd: std::sync::Arc<dyn realfft::RealToComplex<f64>>,
    inv: std::sync::Arc<dyn realfft::ComplexToReal<f64>>,
    /// Each bell's template spectrum, conjugated; none if it is too short.
    spectra: Vec<Option<Vec<Complex<f64>>>>,
}

/// The buffers one match works in.
struct Scratch {
    buf: Vec<f64>,
    spec: Vec<Complex<f64>>,
    out: Vec<f64>,
}

impl Matcher {
    fn new(rate: f64, templates: &[Signal]) -> Result<Self, SignalError> {
        let pre = (PRE_S * rate).round() as usize;
        let len = (MATCH_S * rate).round() as usize + pre;
        let lags = ((WIDE_EARLY_S + WIDE_LATE_S) * rate).round() as usize;
        let n = (len + lags + 1).next_power_of_two();
        let mut planner = RealFftPlanner::<f64>::new();
        let fwd = planner.plan_fft_forward(n);
        let inv = planner.plan_fft_inverse(n);
        // Each bell's template spectrum, conjugated: from its onset, `len` long.
        let mut spectra: Vec<Option<Vec<Complex<f64>>>> = vec![];
        for t in templates {
            let t = resample(t, rate);
            let o = (sample_onset(&t)? * rate).round() as usize;
            if t.samples.len() < o + len - pre {
                spectra.push(None);
                continue;
            }
            // The template from `pre` before its sound starts (silence: a lag
            // where the bell already sounds there matches worse).
            let mut buf = fwd.make_input_vec();
            buf[pre..len].copy_from_slice(&t.samples[o..o + len - pre]);
            let mut spec = fwd.make_output_vec();
            fwd.process(&mut buf, &mut spec)
                .map_err(|e| SignalError::Invalid(e.to_string()))?;
            spectra.push(Some(spec.into_iter().map(|c| c.conj()).collect()));
        }
        Ok(Matcher {
            rate,
            pre,
            len,
            n,
            fwd,
            inv,
            spectra,
        })
    }

    fn scratch(&self) -> Scratch {
        Scratch {
            buf: self.fwd.make_input_vec(),
            spec: self.fwd.make_output_vec(),
            out: self.inv.make_output_vec(),
        }
    }

    /// The strike's time (s) where template `tspec` matches the recording
    /// `x` best from `from` to `to` (s), or None where the recording is
    /// silent there.
    fn best_match(
        &self,
        x: &[f64],
        tspec: &[Complex<f64>],
        from: f64,
        to: f64,
        sc: &mut Scratch,
    ) -> Result<Option<f64>, SignalError> {
        let (rate, n, len) = (self.rate, self.n, self.len);
        let start = (from * rate).round() as i64;
        let lags = (((to - from) * rate).round() as usize).min(n - len - 1);
        let at = |k: usize| {
            let j = start + k as i64;
            if j >= 0 && (j as usize) < x.len() {
                x[j as usize]
            } else {
                0.0
            }
        };
        for (k, b) in sc.buf.iter_mut().enumerate() {
            *b = at(k);
        }
        self.fwd
            .process(&mut sc.buf, &mut sc.spec)
            .map_err(|e| SignalError::Invalid(e.to_string()))?;
        for (a, b) in sc.spec.iter_mut().zip(tspec) {
            *a *= b;
        }
        sc.spec[0].im = 0.0;
        if let Some(l) = sc.spec.last_mut() {
            l.im = 0.0;
        }
        self.inv
            .process(&mut sc.spec, &mut sc.out)
            .map_err(|e| SignalError::Invalid(e.to_string()))?;
        let out = &mut sc.out;
        // out[k]: the recording from start + k against the template, over
        // the recording's level there (a normalised match: unnormalised, a
        // lag where the bell has grown louder matches better than the lag
        // where its sound starts).
        // (The forward transform used `buf` as scratch: read the recording.)
        let mut energy = vec![0.0; n + 1];
        for k in 0..n {
            let v = at(k);
            energy[k + 1] = energy[k] + v * v;
        }
        for (k, o) in out.iter_mut().enumerate().take(lags + 1) {
            let e = energy[(k + len).min(n)] - energy[k];
            *o = if e > 0.0 { *o / e.sqrt() } else { 0.0 };
        }
        let top = (0..=lags).map(|k| out[k].abs()).fold(0.0, f64::max);
        if top == 0.0 {
            return Ok(None);
        }
        let best = first_blow(out, lags, top, rate);
        // The peak between samples, from the parabola through its neighbours.
        let off = if best > 0 && best < lags {
            let (a, b, c) = (out[best - 1].abs(), out[best].abs(), out[best + 1].abs());
            let den = a - 2.0 * b + c;
            if den < 0.0 {
                (0.5 * (a - c) / den).clamp(-0.5, 0.5)
            } else {
                0.0
            }
        } else {
            0.0
        };
        Ok(Some((start as f64 + (best + self.pre) as f64 + off) / rate))
    }
}

/// The best match in `out[..=lags]` (its largest `top`), unless a match at
/// least 0.6 as good lies 30 ms or more before it with a dip between (a
/// double strike's first blow): then the best within 10 ms of the earliest
/// such. Without the dip it is the same strike matching broadly (partials
/// near whole ratios keep in step with themselves for tens of ms).
fn first_blow(out: &[f64], lags: usize, top: f64, rate: f64) -> usize {
    let top_k = (0..=lags)
        .max_by(|&a, &b| out[a].abs().total_cmp(&out[b].abs()))
        .unwrap_or(0);
    let gap = (GAP_S * rate).round() as usize;
    let half = (0.0015 * rate).round() as usize;
    let env = |k: usize| {
        out[k.saturating_sub(half)..=(k + half).min(lags)]
            .iter()
            .fold(0.0f64, |m, v| m.max(v.abs()))
    };
    let first = (0..top_k.saturating_sub(gap)).find(|&k| {
        let e = env(k);
        e >= FIRST_SHARE * top && (k..top_k).step_by(half.max(1)).any(|j| env(j) < DIP * e)
    });
    match first {
        Some(first) => {
            let reach = (first + (0.01 * rate).round() as usize).min(lags);
            (first..=reach)
                .max_by(|&a, &b| out[a].abs().total_cmp(&out[b].abs()))
                .unwrap_or(first)
        }
        None => top_k,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampled_ring::sampled_ring;
    use crate::strikes::{find_strikes, BellVoice, StrikeOptions};
    use crate::tower::{major_scale, score, Method, TowerSpec};

    /// A bell struck alone, after 20 ms of silence, whose partials start at
    /// a tenth of their peak and build up over `rise_s` (s), as recorded
    /// tower bells' do, with the clapper's blow a broadband click at its
    /// start.
    pub(crate) fn slow_bell(rate: f64, nominal: f64, rise_s: f64) -> Signal {
        // Partials at the ratios (to the strongest) and strengths measured
        // on a recorded tower bell (docs/strikes.md): not whole ratios.
        let parts = [
            (0.5003, 0.32),
            (1.0, 1.0),
            (1.1837, 0.45),
            (1.5628, 0.24),
            (2.0037, 0.30),
            (2.712, 0.17),
            (2.979, 0.45),
        ];
        let lead = (0.02 * rate) as usize;
        let mut samples = vec![0.0; lead];
        let mut seed = (nominal * 1000.0) as u64 | 1;
        samples.extend((0..(1.5 * rate) as usize).map(|k| {
            let t = k as f64 / rate;
            // A step to a tenth (the recorded bells jump to -20 dB of their
            // peak at the blow), then the rise.
            let env = (0.1 + 0.9 * (1.0 - (-t / rise_s).exp())) * (-t / 0.8).exp();
            // A small linear congruential generator: the click's noise.
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            let noise = (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
            let click = 0.6 * noise * (-t / 0.002).exp();
            parts
                .iter()
                .map(|&(r, a)| a * (2.0 * std::f64::consts::PI * r * nominal * t + r).sin())
                .sum::<f64>()
                * env
                + click
        }));
        Signal { rate, samples }
    }

    /// The median error (ms) and the share of strikes within 2 ms.
    fn errors(heard: &Heard, truth: &[crate::tower::TrueStrike]) -> (f64, f64) {
        let sc = score(&heard.times(), truth, 0.1);
        let mut e: Vec<f64> = sc.onset_errors.iter().map(|v| v.abs() * 1e3).collect();
        e.sort_by(f64::total_cmp);
        let near = e.iter().filter(|v| **v <= 2.0).count();
        (e[e.len() / 2], near as f64 / truth.len() as f64)
    }

    #[test]
    fn a_slowly_rising_bell_is_timed_at_the_start_of_its_sound() {
        let rate = 16_000.0;
        let bells = major_scale(4, 1000.0).unwrap();
        let templates: Vec<Signal> = bells.iter().map(|b| slow_bell(rate, b.nominal_hz, 0.03)).collect();
        let spec = TowerSpec {
            rate,
            rows: 12,
            method: Method::PlainHunt,
            snr_db: Some(30.0),
            ..TowerSpec::new(bells)
        };
        let (sig, truth) = sampled_ring(&spec, &templates).unwrap();
        let voices: Vec<BellVoice> = templates.iter().map(|t| BellVoice::from_template(t).unwrap()).collect();
        let mut heard = find_strikes(&sig, &voices, &StrikeOptions::default()).unwrap();
        let (before, near_before) = errors(&heard, &truth);
        // The band finder hears a bell rising over 30 ms late.
        assert!(
            before > 5.0 && near_before < 0.2,
            "as heard: median {before:.2} ms, {near_before:.2} within 2 ms"
        );
        let late = crate::lateness::from_templates(&templates, &voices, &StrikeOptions::default()).unwrap();
        let l: Vec<Option<f64>> = late.bells.iter().map(|b| b.sure().then_some(b.lateness_s)).collect();
        let moved = retime(&sig, &mut heard, &templates, &l).unwrap();
        let (after, near) = errors(&heard, &truth);
        // Half the strikes now to within 2 ms, the median exact; the rest
        // matched another bell's partials or this bell's previous strike
        // still ringing (a limit: docs/strikes.md).
        assert!(
            after < 0.5 && near > 0.5,
            "timed on the templates: median {after:.2} ms, {near:.2} within 2 ms"
        );
        assert!(moved.iter().all(|m| m.is_some_and(|m| m < -0.003)), "{moved:?}");
    }
}
