//! Local fits and angle series shared by the reading's steps: local
//! quadratic fits, wrapping, unwrapping across bursts, and the angle held
//! within ±200 deg of the bottom.

use clapper_core::linalg::solve;

/// Local quadratic fits of `y` (on samples not in `bad`) over ±`w` s:
/// the value, first and second derivative at every sample.
pub(super) fn quadratic_fits(t: &[f64], y: &[f64], bad: &[bool], w: f64) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let n = t.len();
    let (mut v, mut d1, mut d2) = (y.to_vec(), vec![0.0; n], vec![0.0; n]);
    let per_window = if n > 1 {
        2.0 * w * (n - 1) as f64 / (t[n - 1] - t[0])
    } else {
        0.0
    };
    let mut sliding = (per_window > SLIDING_ABOVE).then(Sliding::default);
    let mut lo = 0;
    let mut hi = 0;
    for k in 0..n {
        while t[k] - t[lo] > w {
            lo += 1;
        }
        while hi + 1 < n && t[hi + 1] - t[k] <= w {
            hi += 1;
        }
        // Normal equations of a + b x + c x², x = t - t_k.
        let (s, r) = match &mut sliding {
            Some(sums) => sums.about(t, y, bad, (lo, hi), k, w),
            None => afresh(t, y, bad, (lo, hi), t[k]),
        };
        if s[0] < 4.0 {
            continue;
        }
        let a = [[s[0], s[1], s[2]], [s[1], s[2], s[3]], [s[2], s[3], s[4]]];
        if let Some(sol) = solve(a, r) {
            v[k] = sol[0];
            d1[k] = sol[1];
            d2[k] = 2.0 * sol[2];
        }
    }
    (v, d1, d2)
}

/// Windows of more samples than this (on average) are summed as they
/// slide, each sample added once and taken away once, not afresh at every
/// sample: at 10 kHz a ±0.5 s window holds 10,000 samples, and summing
/// each afresh made a log's reading cost grow with its rate squared. A
/// 100 Hz log's windows (at most 101 samples) are summed afresh.
const SLIDING_ABOVE: f64 = 256.0;

/// The sums Σ (t_j − t_k)^m (m = 0..4) and Σ y_j (t_j − t_k)^m (m = 0..2)
/// over the good samples `lo..=hi`, summed afresh.
fn afresh(t: &[f64], y: &[f64], bad: &[bool], (lo, hi): (usize, usize), tk: f64) -> ([f64; 5], [f64; 3]) {
    power_sums(t, y, (lo..=hi).filter(|&j| !bad[j]), tk)
}

/// The sums Σ (t_j − `at`)^m (m = 0..4) and Σ y_j (t_j − `at`)^m (m = 0..2)
/// over the samples `pts`: a least-squares parabola's normal equations.
pub(super) fn power_sums(t: &[f64], y: &[f64], pts: impl Iterator<Item = usize>, at: f64) -> ([f64; 5], [f64; 3]) {
    let mut s = [0.0f64; 5];
    let mut r = [0.0f64; 3];
    for j in pts {
        let x = t[j] - at;
        let mut p = 1.0;
        for m in s.iter_mut() {
            *m += p;
            p *= x;
        }
        r[0] += y[j];
        r[1] += y[j] * x;
        r[2] += y[j] * x * x;
    }
    (s, r)
}

/// The same sums kept as the window slides: moments about a reference
/// time `at`, re-based (summed afresh about the sample) once the sample is
/// a window's half-width past it, so that the powers stay of the window's
/// size and rounding does not build up.
#[derive(Default)]
struct Sliding {
    /// Whether the sums hold a window yet.
    started: bool,
    /// The reference time (s).
    at: f64,
    /// The samples summed: `lo..end`.
    lo: usize,
    end: usize,
    /// Σ u^m (m = 0..4) and Σ y u^m (m = 0..2), u = t − `at`.
    u: [f64; 5],
    v: [f64; 3],
}

impl Sliding {
    /// Add (`sign` +1) or take away (−1) sample `j`, if good.
    fn add(&mut self, t: &[f64], y: &[f64], bad: &[bool], j: usize, sign: f64) {
        if bad[j] {
            return;
        }
        let x = t[j] - self.at;
        let mut p = sign;
        for m in 0..5 {
            self.u[m] += p;
            if m < 3 {
                self.v[m] += y[j] * p;
            }
            p *= x;
        }
    }

    /// The sums over `lo..=hi` about t_k (as [`afresh`]).
    fn about(
        &mut self,
        t: &[f64],
        y: &[f64],
        bad: &[bool],
        (lo, hi): (usize, usize),
        k: usize,
        w: f64,
    ) -> ([f64; 5], [f64; 3]) {
        if !self.started || t[k] - self.at > w || lo >= self.end {
            *self = Sliding {
                started: true,
                at: t[k],
                lo,
                end: lo,
                ..Sliding::default()
            };
        }
        while self.end <= hi {
            self.add(t, y, bad, self.end, 1.0);
            self.end += 1;
        }
        while self.lo < lo {
            self.add(t, y, bad, self.lo, -1.0);
            self.lo += 1;
        }
        // Moments about t_k from those about `at`: Σ (u − c)^m by the
        // binomial theorem, c = t_k − at.
        const C: [[f64; 5]; 5] = [
            [1.0, 0.0, 0.0, 0.0, 0.0],
            [1.0, 1.0, 0.0, 0.0, 0.0],
            [1.0, 2.0, 1.0, 0.0, 0.0],
            [1.0, 3.0, 3.0, 1.0, 0.0],
            [1.0, 4.0, 6.0, 4.0, 1.0],
        ];
        let c = -(t[k] - self.at);
        let pow = [1.0, c, c * c, c * c * c, c * c * c * c];
        let s: [f64; 5] = std::array::from_fn(|m| (0..=m).map(|i| C[m][i] * self.u[i] * pow[m - i]).sum());
        let r: [f64; 3] = std::array::from_fn(|m| (0..=m).map(|i| C[m][i] * self.v[i] * pow[m - i]).sum());
        (s, r)
    }
}

pub(super) fn wrap(a: f64) -> f64 {
    let x = (a + std::f64::consts::PI).rem_euclid(2.0 * std::f64::consts::PI) - std::f64::consts::PI;
    if x == -std::f64::consts::PI {
        std::f64::consts::PI
    } else {
        x
    }
}

/// `a` made continuous sample to sample, but never more than 200 deg from
/// the bottom: each value the turn of it nearest the last one, else the
/// one in (−180, 180] deg.
pub(super) fn bounded(a: &[f64]) -> Vec<f64> {
    let limit = 200f64.to_radians();
    let mut out = Vec::with_capacity(a.len());
    let mut prev = a.first().map_or(0.0, |&x| wrap(x));
    for &x in a {
        let near = prev + wrap(x - prev);
        let v = if near.abs() <= limit { near } else { wrap(x) };
        out.push(v);
        prev = v;
    }
    out
}

/// Unwrap `a` over the good samples and fill the bad ones by linear
/// interpolation in time.
pub(super) fn unwrap_fill(t: &[f64], a: &[f64], bad: &[bool]) -> Vec<f64> {
    let n = t.len();
    let mut out = vec![f64::NAN; n];
    let mut bad = bad.to_vec();
    let mut prev: Option<(f64, f64)> = None;
    let mut refused_since: Option<f64> = None;
    for k in 0..n {
        if bad[k] {
            continue;
        }
        let mut v = a[k];
        if let Some((p, tp)) = prev {
            let step = wrap(v - p);
            // A bell turns at most some 6 rad/s: a sample further off is
            // a strike's shaking that the burst test let through; but a
            // quarter of a second of such samples means the last one
            // trusted was the odd one out.
            let since = *refused_since.get_or_insert(t[k]);
            if step.abs() > (8.0 * (t[k] - tp)).max(0.35) && t[k] - since < 0.25 {
                bad[k] = true;
                continue;
            }
            refused_since = None;
            v = p + step;
        }
        out[k] = v;
        prev = Some((v, t[k]));
    }
    let good: Vec<usize> = (0..n).filter(|&k| !bad[k]).collect();
    if good.is_empty() {
        return a.to_vec();
    }
    let mut g = 0;
    for k in 0..n {
        if !bad[k] {
            continue;
        }
        while g + 1 < good.len() && good[g + 1] < k {
            g += 1;
        }
        let (i, j) = (good[g], good.get(g + 1).copied().unwrap_or(good[g]));
        out[k] = if i >= k || j == i {
            out[i.min(j)]
        } else {
            out[i] + (out[j] - out[i]) * (t[k] - t[i]) / (t[j] - t[i])
        };
    }
    out
}
