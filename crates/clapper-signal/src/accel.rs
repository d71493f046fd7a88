//! Velocity jumps from an accelerometer on a dropped clapper (Section 3.2):
//! each impact is a short spike of acceleration; its velocity jump is the
//! integral across the spike with the local baseline (sensor offset, drift)
//! removed.

use crate::median;
use crate::{Signal, SignalError};

/// Options of [`velocity_jumps`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JumpOptions {
    /// A spike is where |a − baseline| exceeds this fraction of its largest
    /// value. Default 0.05.
    pub threshold: f64,
    /// Integrate this far either side of a spike's peak (s). Default 2 ms,
    /// several times the 0.2 to 0.5 ms contacts the paper measured.
    pub half_width_s: f64,
}

impl Default for JumpOptions {
    fn default() -> Self {
        Self {
            threshold: 0.05,
            half_width_s: 2e-3,
        }
    }
}

/// One impact.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Jump {
    /// Time of the spike's peak (s).
    pub t: f64,
    /// Velocity jump (signal units × s), signed.
    pub dv: f64,
}

/// The velocity: the integral of the acceleration less its median, with the
/// straight-line trend removed (for plots; the jumps do not need it).
pub fn velocity(sig: &Signal) -> Vec<f64> {
    let base = median(&sig.samples);
    let dt = 1.0 / sig.rate;
    let mut v = Vec::with_capacity(sig.samples.len());
    let mut acc = 0.0;
    for a in &sig.samples {
        acc += (a - base) * dt;
        v.push(acc);
    }
    let n = v.len() as f64;
    let mx = (n - 1.0) / 2.0;
    let my = v.iter().sum::<f64>() / n;
    let sxy: f64 = v.iter().enumerate().map(|(i, y)| (i as f64 - mx) * (y - my)).sum();
    let sxx: f64 = (0..v.len()).map(|i| (i as f64 - mx).powi(2)).sum();
    let b = if sxx > 0.0 { sxy / sxx } else { 0.0 };
    v.iter()
        .enumerate()
        .map(|(i, y)| y - my - b * (i as f64 - mx))
        .collect()
}

/// Find the impacts and their velocity jumps. Validated on synthetic drops
/// with sensor offset, drift and noise of known R (see the tests).
pub fn velocity_jumps(sig: &Signal, opts: &JumpOptions) -> Result<Vec<Jump>, SignalError> {
    sig.validate()?;
    let hw = (opts.half_width_s * sig.rate).round() as usize;
    if hw == 0 || sig.samples.len() < 8 * hw {
        return Err(SignalError::TooShort(format!(
            "{} samples at {} Hz for a {} s half-width",
            sig.samples.len(),
            sig.rate,
            opts.half_width_s
        )));
    }
    let base = median(&sig.samples);
    let dev: Vec<f64> = sig.samples.iter().map(|a| (a - base).abs()).collect();
    let peak = dev.iter().cloned().fold(0.0, f64::max);
    if peak == 0.0 {
        return Err(SignalError::Invalid("no impacts: the signal is constant".into()));
    }
    let thr = opts.threshold * peak;
    let dt = 1.0 / sig.rate;
    let mut jumps = vec![];
    let mut i = 0;
    while i < dev.len() {
        if dev[i] <= thr {
            i += 1;
            continue;
        }
        // The spike: its peak within the next half-width.
        let end = (i + hw).min(dev.len());
        let c = (i..end).max_by(|&a, &b| dev[a].total_cmp(&dev[b])).unwrap_or(i);
        let (a, b) = (c.saturating_sub(hw), (c + hw).min(dev.len()));
        // Local baseline from the flanks, where the clapper is in flight.
        let left = &sig.samples[a.saturating_sub(2 * hw)..a];
        let right = &sig.samples[b..(b + 2 * hw).min(dev.len())];
        let flank: Vec<f64> = left.iter().chain(right).copied().collect();
        let lb = if flank.is_empty() { base } else { median(&flank) };
        // Integrate over the spike itself (where it stands above a tenth of its
        // own height, plus two samples), not the whole window: less noise.
        let height = (sig.samples[c] - lb).abs();
        let above = |k: usize| (sig.samples[k] - lb).abs() > 0.1 * height;
        let mut lo = c;
        while lo > a && above(lo - 1) {
            lo -= 1;
        }
        let mut hi = c + 1;
        while hi < b && above(hi) {
            hi += 1;
        }
        let (lo, hi) = (lo.saturating_sub(2).max(a), (hi + 2).min(b));
        let dv: f64 = sig.samples[lo..hi].iter().map(|x| (x - lb) * dt).sum();
        jumps.push(Jump { t: c as f64 * dt, dv });
        i = b + hw;
    }
    Ok(jumps)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// A clapper dropped onto a still bell, bouncing with equal losses R,
    /// recorded with offset, drift and noise.
    pub fn synthetic_drop(r: f64, rate: f64, noise: f64) -> Signal {
        let e = r.sqrt();
        let g = 5.0; // effective gravity of the pendulum clapper near the bell (m/s²)
        let pulse = 4e-4; // contact time (s)
        let mut v = 0.5; // first impact speed (m/s)
        let mut t = 0.05;
        let mut impacts = vec![];
        for _ in 0..6 {
            let after = e * v;
            impacts.push((t, v + after));
            t += 2.0 * after / g;
            v = after;
        }
        let n = ((t + 0.05) * rate) as usize;
        let mut rng = <rand_pcg::Pcg64 as rand::SeedableRng>::seed_from_u64(11);
        let samples = (0..n)
            .map(|i| {
                let tt = i as f64 / rate;
                let nz = noise * rand::Rng::random_range(&mut rng, -1.0..1.0);
                let mut a = 0.3 + 0.2 * tt + nz; // offset and drift
                for &(ti, dv) in &impacts {
                    if tt >= ti && tt < ti + pulse {
                        // Half-sine with area dv.
                        a += dv * PI / (2.0 * pulse) * (PI * (tt - ti) / pulse).sin();
                    }
                }
                a
            })
            .collect();
        Signal { rate, samples }
    }

    #[test]
    fn noisy_synthetic_drop_gives_r_within_10_percent() {
        for r in [0.05, 0.12, 0.3] {
            let sig = synthetic_drop(r, 50000.0, 40.0);
            let jumps = velocity_jumps(&sig, &JumpOptions::default()).unwrap();
            assert!(jumps.len() >= 3, "{r}: {jumps:?}");
            let dv: Vec<f64> = jumps.iter().map(|j| j.dv.abs()).collect();
            let est = clapper_core::restitution::estimate(std::slice::from_ref(&dv))
                .unwrap()
                .r_equal_loss;
            assert!((est - r).abs() / r < 0.10, "R {r}: estimated {est} from {dv:?}");
        }
    }

    #[test]
    fn velocity_has_no_trend() {
        let sig = synthetic_drop(0.1, 20000.0, 1.0);
        let v = velocity(&sig);
        let n = v.len();
        let head: f64 = v[..n / 10].iter().sum::<f64>() / (n / 10) as f64;
        let tail: f64 = v[n - n / 10..].iter().sum::<f64>() / (n / 10) as f64;
        assert!((head - tail).abs() < 0.5, "{head} {tail}");
    }
}
