//! A double strike judged by the template match itself: the recording
//! after a strike explained by two copies of its bell's whole template
//! (its sound as long as it was recorded), the second `d` later, against
//! one copy. The two copies' gains are the least squares fit of both at
//! once (the copies overlap: the template's correlation with itself at
//! `d` comes in), and the strike is double where the second copy, at the
//! delay where it stands out most, is at least the least ratio asked of the
//! first, less the same ratio's median over the bell's strikes at that
//! delay (the room's own echo of the bell, which every strike has: in a
//! room each bell's single strikes showed a second copy at one delay of
//! its own, 20-60 ms, at 0.3-0.6 of the first). The whole template, not its first 150 ms: a shorter first copy
//! leaves the bell's own sound after it unexplained, and a second copy
//! then explains that (on the recorded bells every single strike was
//! called double).

use realfft::num_complex::Complex;
use realfft::{ComplexToReal, RealFftPlanner, RealToComplex};
use std::sync::Arc;

use super::matcher::at;
use crate::strikes::HeardDouble;
use crate::SignalError;

/// A second copy is not judged where the template matches itself this
/// well at its delay (a share of its energy): the two copies are then
/// nearly the same sound, and the fit cannot part them.
const SELF_SHARE: f64 = 0.5;
/// The longest template sound used (s).
const LONGEST_S: f64 = 2.5;

/// One bell's whole template.
struct Long {
    spec: Vec<Complex<f64>>,
    energy: f64,
    /// Its correlation with itself at lags 0, 1, ... samples.
    auto: Vec<f64>,
}

/// The bells' whole templates and a transform long enough for them and
/// the double-strike window.
pub(super) struct Pairs {
    rate: f64,
    /// The longest lag judged (samples).
    reach: usize,
    n: usize,
    fwd: Arc<dyn RealToComplex<f64>>,
    inv: Arc<dyn ComplexToReal<f64>>,
    bells: Vec<Option<Long>>,
    buf: Vec<f64>,
    spec: Vec<Complex<f64>>,
    out: Vec<f64>,
}

impl Pairs {
    /// For the templates' sounds `sounds` (each from its onset, at
    /// `rate`), second blows up to `reach_s` (s) after the first.
    pub fn new(rate: f64, sounds: &[Option<&[f64]>], reach_s: f64) -> Result<Self, SignalError> {
        let longest = (LONGEST_S * rate) as usize;
        let most = sounds.iter().flatten().map(|s| s.len().min(longest)).max().unwrap_or(1);
        let reach = (reach_s * rate).round() as usize;
        let n = (most + reach + 1).next_power_of_two();
        let mut planner = RealFftPlanner::<f64>::new();
        let (fwd, inv) = (planner.plan_fft_forward(n), planner.plan_fft_inverse(n));
        let mut p = Pairs {
            rate,
            reach,
            n,
            buf: fwd.make_input_vec(),
            spec: fwd.make_output_vec(),
            out: inv.make_output_vec(),
            fwd,
            inv,
            bells: vec![],
        };
        for s in sounds {
            let b = s.map(|s| p.long(&s[..s.len().min(longest)])).transpose()?;
            p.bells.push(b);
        }
        Ok(p)
    }

    fn long(&mut self, sound: &[f64]) -> Result<Long, SignalError> {
        self.buf.fill(0.0);
        self.buf[..sound.len()].copy_from_slice(sound);
        let energy = sound.iter().map(|v| v * v).sum();
        self.fwd
            .process(&mut self.buf, &mut self.spec)
            .map_err(|e| SignalError::Invalid(e.to_string()))?;
        let spec: Vec<Complex<f64>> = self.spec.iter().map(|c| c.conj()).collect();
        let mut pow: Vec<Complex<f64>> = spec.iter().map(|c| Complex::new(c.norm_sqr(), 0.0)).collect();
        self.inv
            .process(&mut pow, &mut self.out)
            .map_err(|e| SignalError::Invalid(e.to_string()))?;
        let auto = self.out[..=self.reach].iter().map(|v| v / self.n as f64).collect();
        Ok(Long { spec, energy, auto })
    }

    /// The recording `x`'s correlation with bell `bell`'s whole template
    /// (from 1), its sound from sample `i1` and from each lag up to the
    /// double-strike window's end after it. None without a template.
    pub fn correlations(&mut self, x: &[f64], bell: usize, i1: i64) -> Result<Option<Vec<f64>>, SignalError> {
        let Some(Some(t)) = self.bells.get(bell - 1) else {
            return Ok(None);
        };
        for (k, b) in self.buf.iter_mut().enumerate() {
            *b = at(x, i1 + k as i64);
        }
        self.fwd
            .process(&mut self.buf, &mut self.spec)
            .map_err(|e| SignalError::Invalid(e.to_string()))?;
        for (a, b) in self.spec.iter_mut().zip(&t.spec) {
            *a *= b;
        }
        self.spec[0].im = 0.0;
        if let Some(l) = self.spec.last_mut() {
            l.im = 0.0;
        }
        self.inv
            .process(&mut self.spec, &mut self.out)
            .map_err(|e| SignalError::Invalid(e.to_string()))?;
        let scale = 1.0 / self.n as f64;
        Ok(Some(self.out[..=self.reach].iter().map(|v| v * scale).collect()))
    }

    /// The first copy's gain alone, from the correlations `c` of bell
    /// `bell` ([`Self::correlations`]).
    pub fn gain(&self, bell: usize, c: &[f64]) -> f64 {
        match self.bells.get(bell - 1) {
            Some(Some(t)) if t.energy > 0.0 => c[0] / t.energy,
            _ => 0.0,
        }
    }

    /// Each strike's double judged (`strikes`: bell and correlations), a
    /// bell's strikes against one another: a second copy's gain over the
    /// first's at each delay, less the median of that over the bell's
    /// strikes (the room's own echo of the bell, which every strike has),
    /// must reach `min_ratio` somewhere in `window` (s). The second blows,
    /// one a strike.
    pub fn judge(&self, strikes: &[(usize, Vec<f64>)], window: (f64, f64), min_ratio: f64) -> Vec<Option<HeardDouble>> {
        let lo = ((window.0 * self.rate).round() as usize).max(1);
        let hi = ((window.1 * self.rate).round() as usize).min(self.reach);
        let curves: Vec<Vec<(f64, f64)>> = strikes
            .iter()
            .map(|(b, c)| match self.bells.get(b - 1) {
                Some(Some(t)) => ratios(c, t, lo, hi),
                _ => vec![],
            })
            .collect();
        let mut room: Vec<Vec<f64>> = vec![vec![]; self.bells.len()];
        for (b, r) in room.iter_mut().enumerate() {
            let mine: Vec<&Vec<(f64, f64)>> = strikes
                .iter()
                .zip(&curves)
                .filter(|((bb, _), c)| *bb == b + 1 && !c.is_empty())
                .map(|(_, c)| c)
                .collect();
            if mine.len() >= MIN_STRIKES {
                *r = (0..=hi - lo)
                    .map(|k| crate::median(&mine.iter().map(|c| c[k].1).collect::<Vec<_>>()))
                    .collect();
            }
        }
        strikes
            .iter()
            .zip(&curves)
            .map(|((b, _), curve)| self.one(curve, &room[b - 1], lo, min_ratio))
            .collect()
    }

    /// One strike's second blow from its curve (the second copy's gain
    /// over the first's at each delay from `lo` samples) and its bell's
    /// room's (the median curve; empty where not learned).
    fn one(&self, curve: &[(f64, f64)], room: &[f64], lo: usize, min_ratio: f64) -> Option<HeardDouble> {
        let excess = |k: usize| curve[k].1 - room.get(k).copied().unwrap_or(0.0);
        let k = (0..curve.len()).max_by(|&a, &b| excess(a).total_cmp(&excess(b)))?;
        (curve[k].1 > 0.0 && excess(k) >= min_ratio).then(|| HeardDouble {
            delay_s: (k + lo) as f64 / self.rate,
            amplitude_ratio: curve[k].1,
        })
    }
}

/// A bell's room echo is learned from this many of its strikes or more.
const MIN_STRIKES: usize = 5;

/// At each delay from `lo` to `hi` samples, the two copies' least squares
/// gains from the correlations `c` (the recording with the template at
/// the first blow, `c[0]`, and `d` samples after it): the first's, and
/// the second's over the first's (0 where the fit has no meaning: the
/// copies nearly one sound, or a gain not positive).
fn ratios(c: &[f64], t: &Long, lo: usize, hi: usize) -> Vec<(f64, f64)> {
    let e = t.energy;
    let c1 = c[0];
    let single = if e > 0.0 { c1 / e } else { 0.0 };
    (lo..=hi)
        .map(|d| {
            let a = t.auto[d];
            if e <= 0.0 || c1 <= 0.0 || a.abs() > SELF_SHARE * e {
                return (single, 0.0);
            }
            let det = e * e - a * a;
            let g1 = (e * c1 - a * c[d]) / det;
            let g2 = (e * c[d] - a * c1) / det;
            if g1 <= 0.0 || g2 <= 0.0 {
                (single, 0.0)
            } else {
                (g1, g2 / g1)
            }
        })
        .collect()
}
