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
    // Inside, every tap: outputs summed side by side in blocks
    // ([`inner_block`]), each in the same order as alone, bit for bit.
    let inner_end = if x.len() > half {
        (x.len() - 1 - half) / q + 1
    } else {
        0
    };
    let inner = half.div_ceil(q)..inner_end.max(half.div_ceil(q));
    let mut samples = Vec::with_capacity(n_out);
    samples.extend((0..inner.start.min(n_out)).map(edge));
    let mut phases = Phases::new(q, half);
    let mut m = inner.start;
    while m + LANES <= inner.end {
        let end = (m + CHUNK).min(inner.end - (inner.end - m) % LANES);
        phases.lay_out(x, m, end - m);
        for b in (m..end).step_by(LANES) {
            samples.extend_from_slice(&phases.inner_block(&h, b - m));
        }
        m = end;
    }
    samples.extend((m.min(n_out)..n_out).map(edge));
    Signal { rate, samples }
}

/// Outputs of [`decimate`] summed side by side: as many independent
/// chains of additions as keep the processor's adders busy, a multiple
/// of the vector width, so the compiler sums them in vectors (each
/// lane's sums in the same order as one output's alone), and few enough
/// that they stay in registers (sixteen were kept on the stack).
const LANES: usize = 8;
/// Outputs whose inputs [`Phases`] lays out at a time (a multiple of
/// [`LANES`]): their inputs, about `q` times as many, stay in cache.
const CHUNK: usize = 1024;

/// The inputs of a stretch of [`decimate`]'s outputs laid out by phase:
/// input `i = m q + d` (output `m`, tap offset `d` from its centre) lies
/// in phase `d mod q`, and at one tap consecutive outputs read
/// consecutive inputs of one phase. Read so, a block of outputs takes
/// each tap's inputs in one contiguous load rather than `q` apart (the
/// four side by side of speed-2 loaded each alone: 5.8 % of the ten
/// minutes with templates).
struct Phases {
    q: usize,
    /// Each tap's place in `laid`, less the block's first output's.
    taps: Vec<usize>,
    /// The lowest tap's whole step: `(-half).div_euclid(q)`.
    lowest: i64,
    /// Samples laid out per phase.
    stride: usize,
    laid: Vec<f64>,
}

impl Phases {
    fn new(q: usize, half: usize) -> Self {
        let (qi, hi) = (q as i64, half as i64);
        let lowest = (-hi).div_euclid(qi);
        let highest = hi.div_euclid(qi);
        let stride = CHUNK + (highest - lowest) as usize + 1;
        let taps = (-hi..=hi)
            .map(|d| d.rem_euclid(qi) as usize * stride + (d.div_euclid(qi) - lowest) as usize)
            .collect();
        Phases {
            q,
            taps,
            lowest,
            stride,
            laid: vec![0.0; q * stride],
        }
    }

    /// Lay out the inputs of outputs `first..first + count` (`count` at
    /// most [`CHUNK`]): phase `r`'s `k`-th is input `(first + lowest +
    /// k) q + r` (0 outside `x`: such a place is read by no inner output).
    fn lay_out(&mut self, x: &[f64], first: usize, count: usize) {
        let reach = count + (self.stride - CHUNK);
        let base = (first as i64 + self.lowest) * self.q as i64;
        let inside = base >= 0 && base as usize + reach * self.q <= x.len();
        for r in 0..self.q {
            let row = &mut self.laid[r * self.stride..r * self.stride + reach];
            if inside {
                let from = &x[base as usize + r..];
                row.iter_mut()
                    .zip(from.iter().step_by(self.q))
                    .for_each(|(v, &s)| *v = s);
                continue;
            }
            for (k, v) in row.iter_mut().enumerate() {
                let i = base + (k * self.q + r) as i64;
                *v = usize::try_from(i).ok().and_then(|i| x.get(i)).copied().unwrap_or(0.0);
            }
        }
    }

    /// The [`LANES`] outputs from the `at`-th laid out, every tap inside
    /// `x`: each the sum of its taps' products in tap order, the first
    /// product its start (as alone).
    fn inner_block(&self, h: &[f64], at: usize) -> [f64; LANES] {
        let lane = |j: usize| -> &[f64; LANES] {
            let o = self.taps[j] + at;
            self.laid[o..o + LANES].try_into().expect("LANES long")
        };
        let mut s = [0.0; LANES];
        let (first, h0) = (lane(0), h[0]);
        for l in 0..LANES {
            s[l] = first[l] * h0;
        }
        for (j, &hj) in h.iter().enumerate().skip(1) {
            let v = lane(j);
            for l in 0..LANES {
                s[l] += v[l] * hj;
            }
        }
        s
    }
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

#[cfg(test)]
fn diff(a: (f64, f64), b: (f64, f64)) -> f64 {
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
///
/// Made part by part in arrays (speed-8; the numbers as [`change_each`]
/// makes them, bit for bit): each window's mean once (a sample's after
/// and a later one's before are the same window's), the parts apart so
/// that the compiler divides, turns and takes the magnitudes in vectors.
pub(super) fn change(b: &Band) -> Vec<f64> {
    let n = b.z.len();
    let (g, w) = (b.rise.div_ceil(2), b.rise);
    // Samples m from `lo` to `hi` have both windows inside `z`; `before`
    // of m is the window from m - lo, `after` the window from m - lo + gap.
    let (lo, gap) = (g + w - 1, 2 * g + w - 1);
    let (mre, mim) = window_means(&b.z, w);
    let hi = (n + 1).saturating_sub(g + w).max(lo);
    let count = hi - lo;
    let part = |v: &[f64], from: usize| -> Vec<f64> {
        let mut out = vec![0.0; n];
        if count > 0 {
            out[lo..hi].copy_from_slice(&v[from..from + count]);
        }
        out
    };
    let (bre, bim) = (part(&mre, 0), part(&mim, 0));
    let (are, aim) = (part(&mre, gap), part(&mim, gap));
    let rho = decay_ratio_parts(&are, &aim, &bre, &bim);
    let mut out = vec![0.0; n];
    let mut k = 0;
    while k < n {
        let l = (n - k).min(LANES);
        let (mut dx, mut dy) = ([0.0; LANES], [0.0; LANES]);
        for j in 0..l {
            let (b0, b1) = (bre[k + j], bim[k + j]);
            let pred = (rho.0 * b0 - rho.1 * b1, rho.0 * b1 + rho.1 * b0);
            (dx[j], dy[j]) = (are[k + j] - pred.0, aim[k + j] - pred.1);
        }
        out[k..k + l].copy_from_slice(&hypot_lanes(&dx, &dy)[..l]);
        k += l;
    }
    out
}

/// The mean of `z` over each window of `w` samples (from 0 to the last
/// that fits), real and imaginary parts apart: from the running sums, as
/// [`change_each`] takes them.
fn window_means(z: &[(f64, f64)], w: usize) -> (Vec<f64>, Vec<f64>) {
    let n = z.len();
    let (mut cre, mut cim) = (vec![0.0; n + 1], vec![0.0; n + 1]);
    for (k, v) in z.iter().enumerate() {
        cre[k + 1] = cre[k] + v.0;
        cim[k + 1] = cim[k] + v.1;
    }
    let d = w as f64;
    let mean = |c: &[f64]| -> Vec<f64> { c.iter().zip(c.iter().skip(w)).map(|(a, e)| (e - a) / d).collect() };
    (mean(&cre), mean(&cim))
}

/// `hypot` ([`super::stats::hypot`]) of each pair of `x` and `y`, to the
/// bit: both of its corrections made and the one it takes kept, so that
/// lanes run side by side (the compiler puts them in vectors; the branch
/// between the corrections, taken at random, missed often); where a lane
/// is one that function hands to `f64::hypot`, each lane by it alone.
fn hypot_lanes(x: &[f64; LANES], y: &[f64; LANES]) -> [f64; LANES] {
    const LARGE: f64 = f64::from_bits((1023 + 511) << 52);
    const TINY: f64 = f64::from_bits((1023 - 459) << 52);
    const EPS: f64 = f64::from_bits((1023 - 54) << 52);
    let mut out = [0.0; LANES];
    let mut special = [false; LANES];
    for l in 0..LANES {
        let (x, y) = (x[l].abs(), y[l].abs());
        let (ax, ay) = if x < y { (y, x) } else { (x, y) };
        special[l] = ax.is_nan() || ay.is_nan() || ax > LARGE || ay < TINY;
        let h = (ax * ax + ay * ay).sqrt();
        let (d, e) = (h - ay, h - ax);
        let near = (ax * (2.0 * d - ax), (d - 2.0 * (ax - ay)) * d);
        let far = (2.0 * e * (ax - 2.0 * ay), (4.0 * e - ay) * ay + e * e);
        let (t1, t2) = if h <= 2.0 * ay { near } else { far };
        let r = h - (t1 + t2) / (2.0 * h);
        out[l] = if ay <= ax * EPS { ax + ay } else { r };
    }
    if special.iter().any(|&s| s) {
        for l in 0..LANES {
            out[l] = super::stats::hypot(x[l], y[l]);
        }
    }
    out
}

/// [`change`] as it was made sample by sample (the reference its parts
/// are tested against).
#[cfg(test)]
fn change_each(b: &Band) -> Vec<f64> {
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
#[cfg(test)]
fn decay_ratio(pairs: &[(C, C)]) -> C {
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

/// [`decay_ratio`] of the means after (`are`, `aim`) and before (`bre`,
/// `bim`) held part by part: the same numbers.
fn decay_ratio_parts(are: &[f64], aim: &[f64], bre: &[f64], bim: &[f64]) -> C {
    let level2: Vec<f64> = bre.iter().zip(bim).map(|(r, i)| r * r + i * i).collect();
    let floor = median(level2.clone()).unwrap_or(0.0);
    let (mut re, mut im) = (vec![], vec![]);
    if floor > 0.0 {
        for (k, &l2) in level2.iter().enumerate() {
            if l2 > floor {
                let (a, b) = ((are[k], aim[k]), (bre[k], bim[k]));
                let d = b.0 * b.0 + b.1 * b.1;
                re.push((a.0 * b.0 + a.1 * b.1) / d);
                im.push((a.1 * b.0 - a.0 * b.1) / d);
            }
        }
    }
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

    /// A band's change made part by part is the change made sample by
    /// sample, to the bit: bands of several rises and lengths (shorter
    /// than the windows too), a stretch of silence (lanes `hypot` hands
    /// to `f64::hypot`), levels of every size.
    #[test]
    fn a_change_made_part_by_part_is_the_change_made_sample_by_sample() {
        let z: Vec<(f64, f64)> = (0..5_000)
            .map(|i| {
                let t = i as f64;
                let level = if (1_200..1_500).contains(&i) {
                    0.0
                } else {
                    1.0 + (t * 0.003).sin()
                };
                let scale = 10f64.powi((i % 37) / 4 - 4);
                (
                    level * scale * (t * 0.21).cos() * (-(t % 400.0) / 150.0).exp(),
                    level * scale * (((i * 7919) % 1009) as f64 / 1009.0 - 0.5),
                )
            })
            .collect();
        for (len, rise) in [(5_000, 6), (5_000, 25), (4_321, 7), (40, 6), (12, 6), (3, 2)] {
            let b = Band {
                rate: 1000.0,
                weight: 1.0,
                box_s: 0.002,
                z: z[..len].to_vec(),
                rise,
                scale: 1.0,
            };
            let (got, want) = (change(&b), change_each(&b));
            assert_eq!(got.len(), want.len());
            for (k, (a, e)) in got.iter().zip(&want).enumerate() {
                assert_eq!(a.to_bits(), e.to_bits(), "{len} samples, rise {rise}, at {k}");
            }
            assert!(len < 40 || want.iter().any(|v| *v > 0.0));
        }
    }

    /// Decimating sums inner outputs side by side, their inputs laid out
    /// by phase: each the sum of its taps in order, bit for bit, at the
    /// ends and inside, over chunks and the odd outputs after the last
    /// whole block, at several steps q, and on signals shorter than a
    /// chunk or than the filter.
    #[test]
    fn decimation_sums_each_output_over_its_taps_in_order() {
        let rate = 44_100.0;
        for (len, fmax) in [
            (20_003, 3000.0),
            (9_001, 1200.0),
            (5_000, 4500.0),
            (700, 3000.0),
            (100, 3000.0),
        ] {
            let x: Vec<f64> = (0..len)
                .map(|i| ((i * 7919) % 1009) as f64 / 1009.0 - 0.5 + (i as f64 * 0.37).sin())
                .collect();
            let low = decimate(
                &Signal {
                    rate,
                    samples: x.clone(),
                },
                fmax,
            );
            let (q, h) = decimator(rate, fmax).unwrap();
            let half = h.len() / 2;
            assert_eq!(low.samples.len(), x.len().div_ceil(q));
            for (m, got) in low.samples.iter().enumerate() {
                let c = m * q;
                let (lo, hi) = (c.saturating_sub(half), (c + half).min(x.len() - 1));
                let want: f64 = (lo..=hi).map(|i| x[i] * h[i + half - c]).sum();
                assert_eq!(got.to_bits(), want.to_bits(), "{len} samples, q {q}, output {m}");
            }
        }
    }
}
