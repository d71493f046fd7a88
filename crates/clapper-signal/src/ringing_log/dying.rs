//! The headstock's ring as one dying oscillation from each strike to the
//! next (docs/model.md §13 step 4, "the ring taken out"): on each axis
//! e^(−(t − t₀)/τ) (C cos ω(t − t₀) + S sin ω(t − t₀)), ω the log's mode
//! and τ its decay time, both one for the log; only C and S are the
//! piece's own. Fitted over the whole time from one strike to the next,
//! the ring is told by every unclipped sample of it, where the local fits
//! of `unring.rs` (a ring whose amplitude changes linearly, over a few of
//! its cycles) need 16 unclipped samples about each one: where the ring
//! clips most samples of a 100 Hz log for a few tenths of a second they
//! have too few, and the swing was left shaken there.

use std::f64::consts::TAU;

/// The swing under the ring: a local quadratic over ± this (s).
const SWING_S: f64 = 0.1;

/// Rounds of (the ring given the swing, the swing given the ring).
const ROUNDS: usize = 4;

/// The decay times (s) tried for the log's ring.
pub(super) const DECAYS: [f64; 10] = [0.08, 0.12, 0.18, 0.25, 0.35, 0.5, 0.7, 1.0, 1.5, 2.5];

/// One axis's samples from a strike to the next, with the ring taken out.
pub(super) struct Dying {
    /// The swing at each sample of `pts` (the readings less the ring).
    pub(super) swing: Vec<Option<f64>>,
    /// The ring at every sample of the span (from its first sample).
    pub(super) ring: Vec<f64>,
    /// The power of the readings about their local quadratic alone, and
    /// about the swing and ring together.
    pub(super) before: f64,
    pub(super) after: f64,
}

/// The ring fitted on `y` at the samples `pts` (unclipped, in time
/// order) of the span `(a, b)` (sample indices, end exclusive), at `hz`
/// dying over `decay` s from the span's first sample.
pub(super) fn dying(t: &[f64], y: &[f64], pts: &[usize], (a, b): (usize, usize), hz: f64, decay: f64) -> Option<Dying> {
    if pts.len() < 12 {
        return None;
    }
    let w = TAU * hz;
    let t0 = t[a];
    let basis = |j: usize| {
        let x = t[j] - t0;
        let e = (-x / decay).exp();
        let (s, c) = (w * x).sin_cos();
        (e * c, e * s)
    };
    let plain = local_quadratic(t, pts, &|j| y[j]);
    let before: f64 = pts
        .iter()
        .zip(&plain)
        .filter_map(|(&j, q)| q.map(|q| (y[j] - q).powi(2)))
        .sum();
    let mut swing = plain;
    let mut coef = (0.0, 0.0);
    for _ in 0..ROUNDS {
        // The ring given the swing: two terms by least squares.
        let (mut cc, mut cs, mut ss, mut rc, mut rs) = (0.0, 0.0, 0.0, 0.0, 0.0);
        for (&j, q) in pts.iter().zip(&swing) {
            let Some(q) = q else { continue };
            let (c, s) = basis(j);
            let r = y[j] - q;
            cc += c * c;
            cs += c * s;
            ss += s * s;
            rc += r * c;
            rs += r * s;
        }
        let det = cc * ss - cs * cs;
        if det <= 1e-12 * (cc * ss).max(1e-300) {
            return None;
        }
        coef = ((rc * ss - rs * cs) / det, (rs * cc - rc * cs) / det);
        let ring = |j: usize| {
            let (c, s) = basis(j);
            coef.0 * c + coef.1 * s
        };
        // The swing given the ring.
        swing = local_quadratic(t, pts, &|j| y[j] - ring(j));
    }
    let ring_at = |j: usize| {
        let (c, s) = basis(j);
        coef.0 * c + coef.1 * s
    };
    let after: f64 = pts
        .iter()
        .zip(&swing)
        .filter_map(|(&j, q)| q.map(|q| (y[j] - q - ring_at(j)).powi(2)))
        .sum();
    Some(Dying {
        swing,
        ring: (a..b).map(ring_at).collect(),
        before,
        after,
    })
}

/// At each of `pts`, the value at it of a quadratic fitted by least
/// squares to `v` at the samples of `pts` within ± [`SWING_S`] (`None`
/// with fewer than 4 of them, or not 2 on each side).
pub(super) fn local_quadratic(t: &[f64], pts: &[usize], v: &dyn Fn(usize) -> f64) -> Vec<Option<f64>> {
    let vals: Vec<f64> = pts.iter().map(|&j| v(j)).collect();
    let mut out = Vec::with_capacity(pts.len());
    let (mut lo, mut hi) = (0usize, 0usize);
    for (i, &k) in pts.iter().enumerate() {
        while t[k] - t[pts[lo]] > SWING_S {
            lo += 1;
        }
        while hi + 1 < pts.len() && t[pts[hi + 1]] - t[k] <= SWING_S {
            hi += 1;
        }
        out.push(quadratic_at(t, &pts[lo..=hi], &vals[lo..=hi], t[k]).filter(|_| i - lo >= 2 && hi - i >= 2));
    }
    out
}

/// The value at `at` of a quadratic fitted to `vals` at the samples `idx`.
pub(super) fn quadratic_at(t: &[f64], idx: &[usize], vals: &[f64], at: f64) -> Option<f64> {
    if idx.len() < 4 {
        return None;
    }
    let mut s = [0.0; 5];
    let mut r = [0.0; 3];
    for (&j, &y) in idx.iter().zip(vals) {
        let x = t[j] - at;
        let mut p = 1.0;
        for (m, sm) in s.iter_mut().enumerate() {
            *sm += p;
            if m < 3 {
                r[m] += p * y;
            }
            p *= x;
        }
    }
    let a = [[s[0], s[1], s[2]], [s[1], s[2], s[3]], [s[2], s[3], s[4]]];
    clapper_core::linalg::solve(a, r).map(|q| q[0])
}
