//! Bands: the recording decimated, each partial moved to 0 Hz and smoothed
//! by three boxes, and a band's change across a strike's rise.

use std::f64::consts::PI;

use super::heard::StrikeOptions;
use super::stats::{median, typical_peak};
use crate::Signal;

/// The rate the bands are kept at (Hz): onsets are interpolated within it.
pub(super) const BAND_RATE: f64 = 1000.0;

/// A band: one partial of one bell, moved to 0 Hz and smoothed.
pub(super) struct Band {
    /// Sample rate of `z` (Hz): about [`BAND_RATE`], a whole fraction of the signal's.
    pub(super) rate: f64,
    /// Weight in the bell's onset function.
    pub(super) weight: f64,
    /// Box length (s).
    pub(super) box_s: f64,
    /// The complex band signal at the band rate.
    pub(super) z: Vec<(f64, f64)>,
    /// Rise of a step (band samples, 3L rounded up).
    pub(super) rise: usize,
    /// Typical size of a strike's change in this band.
    pub(super) scale: f64,
}

/// Low-pass and keep every q-th sample, q as large as keeps `fmax` 20 %
/// below the new Nyquist frequency (a windowed-sinc filter).
pub(super) fn decimate(sig: &Signal, fmax: f64) -> Signal {
    let Some((q, h)) = decimator(sig.rate, fmax) else {
        return sig.clone();
    };
    let rate = sig.rate / q as f64;
    let half = h.len() / 2;
    let x = &sig.samples;
    let n_out = x.len().div_ceil(q);
    // Near the ends, the taps that fall inside the signal.
    let edge = |m: usize| -> f64 {
        let c = m * q;
        let (lo, hi) = (c.saturating_sub(half), (c + half).min(x.len() - 1));
        (lo..=hi).map(|i| x[i] * h[i + half - c]).sum()
    };
    // Inside, every tap: four outputs summed side by side, so that no
    // one's chain of additions waits on another's (each summed in the
    // same order as alone, bit for bit).
    let inner_end = if x.len() > half {
        (x.len() - 1 - half) / q + 1
    } else {
        0
    };
    let inner = half.div_ceil(q)..inner_end;
    let mut samples = Vec::with_capacity(n_out);
    let mut m = 0;
    while m < n_out {
        if inner.contains(&m) && inner.contains(&(m + 3)) {
            let at = |k: usize| &x[(m + k) * q - half..=(m + k) * q + half];
            let (a, b, c, d) = (at(0), at(1), at(2), at(3));
            let (mut s0, mut s1, mut s2, mut s3) = (a[0] * h[0], b[0] * h[0], c[0] * h[0], d[0] * h[0]);
            for ((((hj, aj), bj), cj), dj) in h.iter().zip(a).zip(b).zip(c).zip(d).skip(1) {
                s0 += aj * hj;
                s1 += bj * hj;
                s2 += cj * hj;
                s3 += dj * hj;
            }
            samples.extend_from_slice(&[s0, s1, s2, s3]);
            m += 4;
        } else {
            samples.push(edge(m));
            m += 1;
        }
    }
    Signal { rate, samples }
}

/// [`decimate`]'s step q and filter (2·half + 1 taps), or None where
/// nothing is dropped (q = 1).
fn decimator(sig_rate: f64, fmax: f64) -> Option<(usize, Vec<f64>)> {
    let q = ((sig_rate / (2.4 * fmax)).floor() as usize).max(1);
    if q == 1 {
        return None;
    }
    let rate = sig_rate / q as f64;
    let cutoff = (1.1 * fmax).min(0.45 * rate) / sig_rate;
    let transition = (0.5 * rate / sig_rate - cutoff).max(0.02 / q as f64);
    let half = ((2.0 / transition).ceil() as usize).clamp(8, 2000);
    // Blackman-windowed sinc, unit gain at 0 Hz.
    let mut h: Vec<f64> = (0..=2 * half)
        .map(|i| {
            let x = i as f64 - half as f64;
            let s = if x == 0.0 {
                2.0 * cutoff
            } else {
                (2.0 * PI * cutoff * x).sin() / (PI * x)
            };
            let w = 0.42 - 0.5 * (PI * i as f64 / half as f64).cos() + 0.08 * (2.0 * PI * i as f64 / half as f64).cos();
            s * w
        })
        .collect();
    let sum: f64 = h.iter().sum();
    h.iter_mut().for_each(|v| *v /= sum);
    Some((q, h))
}

/// The band of partial `f` (Hz): x e^{−iωt} through three boxes of
/// `len` samples, centred (no delay), kept at about [`BAND_RATE`].
#[cfg(test)]
pub(super) fn band(sig: &Signal, f: f64, weight: f64, len: usize) -> Band {
    bands(sig, &[(f, weight, len)]).remove(0)
}

/// One band being made: its phasor's step, what entered its three boxes
/// and its output ([`Run`] holds what changes every sample).
struct Making {
    w: f64,
    /// e^{−iω} per sample.
    c: (f64, f64),
    /// What entered each box at each slot (slot = sample mod `len`).
    hist: Vec<[(f64, f64); 3]>,
    len: usize,
    /// Input samples to run past the signal's end (to flush the boxes).
    end: usize,
    norm: f64,
    z: Vec<(f64, f64)>,
}

/// What of a band changes every sample: its phasor, its boxes' running
/// sums, the slot written next, the next input sample whose output is
/// kept and where. A copy, held in registers while a stretch is made.
#[derive(Clone, Copy)]
struct Run {
    p: (f64, f64),
    sum: [(f64, f64); 3],
    slot: usize,
    next: usize,
    out: usize,
}

/// The exact phasor is set every this many samples, so rounding never
/// builds up.
const EXACT: usize = 4096;

impl Making {
    /// The state before the first sample: output i is centred on input
    /// i − delay, the first kept at the delay.
    fn start(&self) -> Run {
        Run {
            p: (1.0, 0.0),
            sum: [(0.0, 0.0); 3],
            slot: 0,
            next: 3 * (self.len - 1) / 2,
            out: 0,
        }
    }

    /// The exact phasor at sample `i`, where `i` is a multiple of
    /// [`EXACT`].
    fn exact(&self, r: &mut Run, i: usize) {
        if i % EXACT == 0 {
            let a = -self.w * i as f64;
            r.p = (a.cos(), a.sin());
        }
    }

    /// Input sample `i` (value `v`) through the band: the same operations
    /// in the same order whatever band runs beside it. No call is made
    /// (the output is written to its place, made beforehand), so the
    /// state need not leave the registers.
    #[inline(always)]
    fn step(&mut self, r: &mut Run, i: usize, v: f64, hop: usize) {
        let p = r.p;
        let mut input = (v * p.0, v * p.1);
        r.p = (p.0 * self.c.0 - p.1 * self.c.1, p.0 * self.c.1 + p.1 * self.c.0);
        let h = &mut self.hist[r.slot];
        for (old, sum) in h.iter_mut().zip(r.sum.iter_mut()) {
            let o = *old;
            *old = input;
            *sum = (sum.0 + input.0 - o.0, sum.1 + input.1 - o.1);
            input = *sum;
        }
        r.slot += 1;
        if r.slot == self.len {
            r.slot = 0;
        }
        if i == r.next {
            if let Some(z) = self.z.get_mut(r.out) {
                *z = (input.0 * self.norm, input.1 * self.norm);
            }
            r.out += 1;
            r.next += hop;
        }
    }

    /// The band from sample `from` to its end, alone.
    fn finish(&mut self, mut r: Run, from: usize, x: &[f64], hop: usize) {
        let mut i = from;
        while i < self.end {
            let stop = ((i / EXACT + 1) * EXACT).min(self.end);
            self.exact(&mut r, i);
            for j in i..stop {
                self.step(&mut r, j, input_at(x, j), hop);
            }
            i = stop;
        }
        self.z.truncate(r.out);
    }
}

/// The input sample `i` of `x`, 0 past its end (the boxes flushed).
fn input_at(x: &[f64], i: usize) -> f64 {
    x.get(i).copied().unwrap_or(0.0)
}

/// Two bands made side by side over `x`, each to its own end: their
/// chains of dependent sums interleave, and their states stay in
/// registers (made in one pass over all the bands, each band's state was
/// stored and loaded again every sample: speed-6).
fn make_pair(a: &mut Making, b: &mut Making, x: &[f64], hop: usize) {
    let (mut ra, mut rb) = (a.start(), b.start());
    let both = a.end.min(b.end);
    let mut i = 0;
    while i < both {
        let stop = ((i / EXACT + 1) * EXACT).min(both);
        a.exact(&mut ra, i);
        b.exact(&mut rb, i);
        for j in i..stop {
            let v = input_at(x, j);
            a.step(&mut ra, j, v, hop);
            b.step(&mut rb, j, v, hop);
        }
        i = stop;
    }
    a.finish(ra, both, x, hop);
    b.finish(rb, both, x, hop);
}

/// The bands `specs` (partial Hz, weight, box length in samples) of one
/// signal, each as [`band`] makes it alone, bit for bit: made two side by
/// side, so that no band's chain of sums waits on another's (each band's
/// phasor and boxes are a chain of dependent additions; alone, the
/// processor idles between its steps).
pub(super) fn bands(sig: &Signal, specs: &[(f64, f64, usize)]) -> Vec<Band> {
    let hop = ((sig.rate / BAND_RATE).round() as usize).max(1);
    let x = &sig.samples;
    let n = x.len();
    let mut making: Vec<Making> = specs
        .iter()
        .map(|&(f, _, len)| {
            let w = 2.0 * PI * f / sig.rate;
            Making {
                w,
                c: (w.cos(), -w.sin()),
                hist: vec![[(0.0, 0.0); 3]; len],
                len,
                end: n + 3 * (len - 1) / 2,
                norm: 2.0 / (len as f64).powi(3),
                z: vec![(0.0, 0.0); n.div_ceil(hop)],
            }
        })
        .collect();
    for pair in making.chunks_mut(2) {
        match pair {
            [a, b] => make_pair(a, b, x, hop),
            [a] => {
                let r = a.start();
                a.finish(r, 0, x, hop);
            }
            _ => {}
        }
    }
    making
        .into_iter()
        .zip(specs)
        .map(|(m, &(_, weight, len))| Band {
            rate: sig.rate / hop as f64,
            weight,
            box_s: len as f64 / sig.rate,
            z: m.z,
            rise: (3 * len).div_ceil(hop).max(2),
            scale: 1.0,
        })
        .collect()
}

pub(super) fn diff(a: (f64, f64), b: (f64, f64)) -> f64 {
    super::stats::hypot(a.0 - b.0, a.1 - b.1)
}

/// Each bell's bands as (frequency Hz, weight, box length in samples).
/// A shared band is fitted for a double strike only where what rings in
/// it before the strike is below this fraction of the strike's step.
pub(super) const SHARED_BAND_QUIET: f64 = 0.2;

/// A band of a bell's partial that other bells (`with`) share: its change
/// ([`change`]) and typical step kept, for timing and double strikes
/// between the sharers' strikes.
pub(super) struct SharedBand {
    pub(super) band: Band,
    pub(super) change: Vec<f64>,
    pub(super) with: Vec<usize>,
}

impl SharedBand {
    pub(super) fn new(mut band: Band, with: Vec<usize>, opts: &StrikeOptions) -> Self {
        let change = change(&band);
        band.scale = typical_peak(&change, (opts.min_separation_s * band.rate) as usize);
        SharedBand { band, change, with }
    }
}

/// The band's change across a rise at each sample: the mean of `z` over
/// a rise's length just after the rise centred there, less its mean over
/// as long just before. A strike of this bell is a lasting step and gives
/// its full size, at its onset; another bell's strike only passes through
/// the band for the length of the smoothing (its partials switching on),
/// and averages away.
pub(super) fn change(b: &Band) -> Vec<f64> {
    let n = b.z.len();
    let g = b.rise.div_ceil(2);
    let w = b.rise;
    let mut cum = vec![(0.0, 0.0); n + 1];
    for (k, z) in b.z.iter().enumerate() {
        cum[k + 1] = (cum[k].0 + z.0, cum[k].1 + z.1);
    }
    // Mean of z[a..b].
    let mean = |a: usize, e: usize| {
        let d = (e - a) as f64;
        ((cum[e].0 - cum[a].0) / d, (cum[e].1 - cum[a].1) / d)
    };
    let valid = |m: usize| m + 1 >= g + w && m + g + w <= n;
    let pairs: Vec<((f64, f64), (f64, f64))> = (0..n)
        .map(|m| {
            if valid(m) {
                (mean(m + g, m + g + w), mean(m + 1 - g - w, m + 1 - g))
            } else {
                ((0.0, 0.0), (0.0, 0.0))
            }
        })
        .collect();
    let rho = decay_ratio(&pairs);
    pairs
        .iter()
        .map(|&(after, before)| {
            let pred = (rho.0 * before.0 - rho.1 * before.1, rho.0 * before.1 + rho.1 * before.0);
            diff(after, pred)
        })
        .collect()
}

/// A complex number as (re, im).
pub(super) type C = (f64, f64);

/// What a freely ringing partial's mean after becomes of its mean before:
/// the complex ratio (its decay and its small turning, the band being a
/// little off its frequency), as the median over the loudest half of the
/// recording, where the bell is ringing and not struck.
pub(super) fn decay_ratio(pairs: &[(C, C)]) -> C {
    // Squared levels: the same order as levels, without a square root each.
    let level2 = |p: &(C, C)| p.1 .0 * p.1 .0 + p.1 .1 * p.1 .1;
    let floor = median(pairs.iter().map(level2).collect()).unwrap_or(0.0);
    let (re, im): (Vec<f64>, Vec<f64>) = pairs
        .iter()
        .filter(|p| level2(p) > floor && floor > 0.0)
        .map(|&(a, b)| {
            let d = b.0 * b.0 + b.1 * b.1;
            ((a.0 * b.0 + a.1 * b.1) / d, (a.1 * b.0 - a.0 * b.1) / d)
        })
        .unzip();
    match (median(re), median(im)) {
        (Some(re), Some(im)) => (re, im),
        _ => (1.0, 0.0),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_band_is_centred_and_reads_a_tone_at_its_amplitude() {
        // A 1000 Hz tone switched on at 0.5 s: its band holds the tone's
        // amplitude, and is half-way up at the switch (no delay).
        let rate = 8000.0;
        let on = 4000;
        let samples: Vec<f64> = (0..16_000)
            .map(|i| {
                if i >= on {
                    0.3 * (2.0 * PI * 1000.0 * i as f64 / rate).sin()
                } else {
                    0.0
                }
            })
            .collect();
        let b = band(&Signal { rate, samples }, 1000.0, 1.0, 81);
        let at = |t: f64| {
            let z = b.z[(t * b.rate).round() as usize];
            z.0.hypot(z.1)
        };
        assert!((at(1.5) - 0.3).abs() < 1e-6, "{}", at(1.5));
        assert!((at(0.5) - 0.15).abs() < 0.3 * 0.02, "{}", at(0.5));
        assert!(at(0.45) < 1e-9);
    }

    /// The one-band loop as it was before bands were made side by side
    /// (a reference for the test below).
    #[allow(clippy::needless_range_loop)]
    fn band_alone(sig: &Signal, f: f64, len: usize) -> Vec<(f64, f64)> {
        let hop = ((sig.rate / BAND_RATE).round() as usize).max(1);
        let x = &sig.samples;
        let n = x.len();
        let w = 2.0 * PI * f / sig.rate;
        let delay = 3 * (len - 1) / 2;
        let mut z = vec![];
        let mut hist = [vec![(0.0, 0.0); len], vec![(0.0, 0.0); len], vec![(0.0, 0.0); len]];
        let mut sum = [(0.0f64, 0.0f64); 3];
        let norm = 2.0 / (len as f64).powi(3);
        let (cr, ci) = (w.cos(), -w.sin());
        let mut p = (1.0f64, 0.0f64);
        for i in 0..n + delay {
            if i % 4096 == 0 {
                let a = -w * i as f64;
                p = (a.cos(), a.sin());
            }
            let v = if i < n { x[i] } else { 0.0 };
            let mut input = (v * p.0, v * p.1);
            p = (p.0 * cr - p.1 * ci, p.0 * ci + p.1 * cr);
            let slot = i % len;
            for s in 0..3 {
                let old = hist[s][slot];
                hist[s][slot] = input;
                sum[s] = (sum[s].0 + input.0 - old.0, sum[s].1 + input.1 - old.1);
                input = sum[s];
            }
            if i >= delay && (i - delay) % hop == 0 {
                z.push((input.0 * norm, input.1 * norm));
            }
        }
        z
    }

    /// Bands made side by side (boxes of different lengths, so each runs
    /// on past the signal's end by its own delay; two by two, the fifth
    /// alone) are each the band made alone, to the bit.
    #[test]
    fn bands_made_side_by_side_are_each_the_band_made_alone() {
        let rate = 11_025.0;
        let samples: Vec<f64> = (0..30_000)
            .map(|i| {
                let t = i as f64 / rate;
                (2.0 * PI * 523.0 * t).sin() * (-t).exp() + 0.3 * (2.0 * PI * 1187.0 * t + 0.4).cos()
            })
            .collect();
        let sig = Signal { rate, samples };
        let specs = [
            (523.0, 1.0, 81),
            (1187.0, 0.5, 33),
            (260.0, 0.2, 551),
            (2050.0, 0.1, 35),
            (731.0, 0.3, 57),
        ];
        let made = bands(&sig, &specs);
        for (b, &(f, _, len)) in made.iter().zip(&specs) {
            assert_eq!(b.z, band_alone(&sig, f, len), "band at {f} Hz");
        }
    }

    /// Decimating sums four inner outputs side by side: each the sum of
    /// its taps in order, bit for bit, at the ends and inside.
    #[test]
    fn decimation_sums_each_output_over_its_taps_in_order() {
        let rate = 44_100.0;
        let x: Vec<f64> = (0..20_003)
            .map(|i| ((i * 7919) % 1009) as f64 / 1009.0 - 0.5 + (i as f64 * 0.37).sin())
            .collect();
        let low = decimate(
            &Signal {
                rate,
                samples: x.clone(),
            },
            3000.0,
        );
        let (q, h) = decimator(rate, 3000.0).unwrap();
        let half = h.len() / 2;
        assert_eq!(low.samples.len(), x.len().div_ceil(q));
        for (m, got) in low.samples.iter().enumerate() {
            let c = m * q;
            let (lo, hi) = (c.saturating_sub(half), (c + half).min(x.len() - 1));
            let want: f64 = (lo..=hi).map(|i| x[i] * h[i + half - c]).sum();
            assert_eq!(got.to_bits(), want.to_bits(), "output {m}");
        }
    }
}
