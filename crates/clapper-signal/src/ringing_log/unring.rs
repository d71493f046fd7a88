//! The headstock's ring taken out of the readings (docs/model.md §13 step
//! 4, "through the headstock's ringing"): after a strike the headstock
//! rings in a mode of its own for a second or more, on every axis at one
//! frequency, dying away. Where it rings through the next bottom (the
//! shorter swings of raising and lowering) the shaken samples left in the
//! angle's fits as noise threw the angle about by tens of degrees, and
//! bottoms were missed or read half a second off. Within each run of
//! bursts that rings ([`RINGING_S`] or longer), the mode's frequency is
//! the peak of the readings' spectrum (less their local trend), and at
//! each sample a quadratic (the swing) and a sinusoid of that frequency
//! with a linearly changing amplitude (the ring) are fitted by least
//! squares to each axis over a few of its cycles; the ring's share at the
//! sample is taken off. A run whose ring the mode does not explain (its
//! trend-less readings' power cut by less than [`EXPLAINED`]) is left as
//! it was. A clipped in-plane reading is missing data: the swing's
//! fitted value stands in for it where the fit agrees it clipped. A
//! strike while the ring before it still clips marks no onset: it is
//! found where the ring fitted before a sample and the ring fitted after
//! it differ ([`hidden_strikes`]), and no fit straddles it.

use super::bursts::{runs_of, RINGING_S};
use super::dying::{dying, quadratic_at, Dying, DECAYS};
use super::fits::quadratic_fits;
use super::types::AccelLog;
use std::f64::consts::TAU;

/// The share of a run's shaking (its readings less their local trend, in
/// power) the fitted mode must explain for the run to be taken as
/// cleaned: a headstock ringing in one mode leaves noise alone.
pub(super) const EXPLAINED: f64 = 0.8;

/// A clipped reading is read through (its swing's value fitted from the
/// samples about it) only where the fitted swing and ring together reach
/// within this (m/s²) of the clipped value, on its side.
const CLIP_SLACK: f64 = 2.0;

/// The trend the spectrum is taken about: a local quadratic over ± this (s).
const TREND_S: f64 = 0.1;

/// A rung run is judged (and its spectrum taken) in pieces of at most
/// this (s).
const PIECE_S: f64 = 0.5;

/// The lowest frequency taken for a ring (Hz): slower, it is the swing's.
const LOWEST_HZ: f64 = 8.0;

/// What [`unrung`] gives: the readings with the ring taken out, which
/// burst samples' tangential readings are still shaken (`burst` and not
/// cleaned), and which in-plane axes each sample may now be read on (0:
/// as before; 1: the tangential alone, the radial clipped; 2: both).
pub(super) struct Unrung {
    pub(super) log: AccelLog,
    pub(super) shaken: Vec<bool>,
    pub(super) usable: Vec<u8>,
}

/// The readings with the headstock's ring taken out of the rung runs of
/// bursts. `bad`: the samples the angle's fits leave out (clipped, a
/// strike's first moments); `clipped`: each axis's clipped samples
/// (radial, tangential, axle; an axis is fitted and cleaned where it is
/// not, the others' clipping notwithstanding: near a bottom the radial
/// axis, reading g and more, clips where the tangential does not);
/// `onsets`: the bursts' first samples (each strike starts the ring
/// afresh, at a phase of its own).
pub(super) fn unrung(
    log: &AccelLog,
    (burst, bad): (&[bool], &[bool]),
    clipped: &[Vec<bool>; 3],
    onsets: &[usize],
) -> Unrung {
    let n = log.t.len();
    let mut out = log.clone();
    let mut shaken = burst.to_vec();
    let mut usable = vec![0u8; n];
    // A strike's first moments (or a short burst): no axis is used there.
    let struck: Vec<bool> = (0..n).map(|k| bad[k] && !clipped.iter().any(|c| c[k])).collect();
    let masks: [Vec<bool>; 3] = [0, 1, 2].map(|a| (0..n).map(|k| struck[k] || clipped[a][k]).collect());
    let axes = [&log.radial, &log.tangential, &log.axle];
    let trends = [0, 1, 2].map(|a| quadratic_fits(&log.t, axes[a], &masks[a], TREND_S).0);
    let pieces = rung_pieces(&log.t, burst, &struck, onsets);
    // One mode for the log: the headstock's, whatever struck it.
    let resid = |j: usize| [0, 1, 2].map(|a| if masks[a][j] { 0.0 } else { axes[a][j] - trends[a][j] });
    let Some(hz) = peak_frequency(&log.t, &pieces, &resid) else {
        return Unrung {
            log: out,
            shaken,
            usable,
        };
    };
    // A strike while the last still rings (no onset: the burst never
    // ended) starts the ring afresh at a phase of its own: the pieces cut
    // there too, so that no fit straddles it.
    let hidden = hidden_strikes(log, &masks, &pieces, hz);
    let pieces = if hidden.is_empty() {
        pieces
    } else {
        let mut starts: Vec<usize> = onsets.iter().copied().chain(hidden).collect();
        starts.sort_unstable();
        starts.dedup();
        rung_pieces(&log.t, burst, &struck, &starts)
    };
    // The ring as one dying oscillation from each strike to the next
    // (`dying.rs`), where that explains it: it reads the samples the local
    // fits have too few about to read, and whole pieces they do not
    // explain.
    let told = dying_rings(log, &masks, &pieces, hz);
    for p in &pieces {
        let (mut cleaned, before, after) = clean_run(log, &masks, p, hz);
        let local = before > 0.0 && after <= (1.0 - EXPLAINED) * before;
        for (&j, c) in p.run.iter().zip(cleaned.iter_mut()) {
            if !local {
                *c = [None; 3];
            }
            for (a, x) in c.iter_mut().enumerate() {
                *x = x.or(told[j][a]);
            }
        }
        for (&j, c) in p.run.iter().zip(&cleaned) {
            let [r, tg, ax] = c.map(|x| x.unwrap_or(f64::NAN));
            if c[1].is_some() {
                out.tangential[j] = tg;
                shaken[j] = false;
                usable[j] = if c[0].is_some() { 2 } else { 1 };
            }
            if c[0].is_some() {
                out.radial[j] = r;
            }
            if c[2].is_some() {
                out.axle[j] = ax;
            }
        }
    }
    Unrung {
        log: out,
        shaken,
        usable,
    }
}

/// A piece of a rung run of bursts between two strikes: its samples a fit
/// may use (`run`), and the span (sample indices, end exclusive) from its
/// strike to the next, which a fit about any of them may reach into.
struct Piece {
    run: Vec<usize>,
    span: (usize, usize),
}

/// The runs of bursts lasting over [`RINGING_S`], cut at each strike, of
/// the samples not `struck` (a strike's first moments).
fn rung_pieces(t: &[f64], burst: &[bool], struck: &[bool], onsets: &[usize]) -> Vec<Piece> {
    let n = t.len();
    let mut pieces = vec![];
    for (start, k) in runs_of(burst) {
        if t[k - 1] - t[start] <= RINGING_S {
            continue;
        }
        let mut cuts: Vec<usize> = onsets.iter().copied().filter(|&j| j > start && j < k).collect();
        cuts.insert(0, start);
        cuts.push(k);
        for w in cuts.windows(2) {
            let next = onsets.iter().copied().find(|&j| j >= w[1]).unwrap_or(n);
            // In pieces of at most PIECE_S: a strike inside a run of bursts
            // (no onset) starts the ring afresh, which a piece's spectrum
            // and its judgement should not straddle for long.
            let mut a = w[0];
            while a < w[1] {
                let b = (a..w[1]).find(|&j| t[j] - t[a] >= PIECE_S).unwrap_or(w[1]);
                let run: Vec<usize> = (a..b).filter(|&j| !struck[j]).collect();
                if run.len() >= 10 {
                    pieces.push(Piece {
                        run,
                        span: (w[0], next),
                    });
                }
                a = b;
            }
        }
    }
    pieces
}

/// The frequency (Hz) at which the three axes' residuals `resid` hold the
/// most power over the `pieces` (each piece's own spectrum, added: a
/// strike starts the ring at a phase of its own), from [`LOWEST_HZ`] to
/// just short of half the sample rate, in steps of a quarter of one over
/// the longest piece.
fn peak_frequency(t: &[f64], pieces: &[Piece], resid: &dyn Fn(usize) -> [f64; 3]) -> Option<f64> {
    let spans: Vec<f64> = pieces.iter().map(|p| t[p.run[p.run.len() - 1]] - t[p.run[0]]).collect();
    let longest = spans.iter().copied().fold(0.0, f64::max);
    if longest <= 0.0 {
        return None;
    }
    let samples: usize = pieces.iter().map(|p| p.run.len() - 1).sum();
    let rate = samples as f64 / spans.iter().sum::<f64>();
    let (top, step) = (0.48 * rate, 0.25 / longest);
    let r: Vec<Vec<[f64; 3]>> = pieces
        .iter()
        .map(|p| p.run.iter().map(|&j| resid(j)).collect())
        .collect();
    let power = |hz: f64| {
        let w = TAU * hz;
        let mut power = 0.0;
        for (p, r) in pieces.iter().zip(&r) {
            let first = t[p.run[0]];
            let mut c = [0.0; 3];
            let mut s = [0.0; 3];
            for (&j, v) in p.run.iter().zip(r) {
                let (sn, cs) = (w * (t[j] - first)).sin_cos();
                for a in 0..3 {
                    c[a] += v[a] * cs;
                    s[a] += v[a] * sn;
                }
            }
            power += (0..3).map(|a| c[a] * c[a] + s[a] * s[a]).sum::<f64>();
        }
        power
    };
    // The peak on a coarse grid, then a finer one about it.
    let peak = |from: f64, to: f64, step: f64| {
        let mut best: Option<(f64, f64)> = None;
        let mut hz = from;
        while hz < to {
            let p = power(hz);
            if best.is_none_or(|b| p > b.1) {
                best = Some((hz, p));
            }
            hz += step;
        }
        best.map(|b| b.0)
    };
    let coarse = peak(LOWEST_HZ, top, step)?;
    peak(coarse - step, coarse + step, step / 20.0)
}

/// The strikes inside rung runs that no onset marks (the burst before
/// still ringing, often clipped, when the clapper struck again: a
/// raising's second blow, 0.3 s before the next bottom, restarted the ring
/// at full strength there): at each sample of the `pieces`, the ring at
/// `hz` fitted (as [`clean_run`]'s) on each axis over the ring's six
/// cycles before it and, apart, over the six after, and the two fits'
/// ring there compared. A ring running on is the same either side; a
/// strike adds a ring of its own. The samples where the change in the
/// ring (its power summed over the axes) passes the ring before it
/// ([`CHANGE`] times) and [`CHANGE_MIN`], the most there within half the
/// window either way.
fn hidden_strikes(log: &AccelLog, masks: &[Vec<bool>; 3], pieces: &[Piece], hz: f64) -> Vec<usize> {
    let t = &log.t;
    let axes = [&log.radial, &log.tangential, &log.axle];
    let half = (6.0 / hz).max(0.15);
    let basis = ring_basis(hz);
    let mut found = vec![];
    for p in pieces {
        let score: Vec<Option<f64>> = p
            .run
            .iter()
            .map(|&k| {
                let lo = t.partition_point(|&x| x < t[k] - half).max(p.span.0);
                let hi = t.partition_point(|&x| x < t[k] + half).min(p.span.1);
                let (mut change, mut before) = (0.0, 0.0);
                let mut any = false;
                for a in 0..3 {
                    let left: Vec<usize> = (lo..k).filter(|&j| !masks[a][j]).collect();
                    let right: Vec<usize> = (k..hi).filter(|&j| !masks[a][j]).collect();
                    if left.len() < CHANGE_SAMPLES || right.len() < CHANGE_SAMPLES {
                        continue;
                    }
                    let (Some(l), Some(r)) = (
                        fit(t, axes[a], &left, t[k], &basis).1,
                        fit(t, axes[a], &right, t[k], &basis).1,
                    ) else {
                        continue;
                    };
                    change += (r[3] - l[3]).powi(2) + (r[5] - l[5]).powi(2);
                    before += l[3].powi(2) + l[5].powi(2);
                    any = true;
                }
                (any && change > CHANGE * before && change > CHANGE_MIN * CHANGE_MIN)
                    .then_some(change / before.max(1e-12))
            })
            .collect();
        for (i, &k) in p.run.iter().enumerate() {
            let Some(s) = score[i] else { continue };
            let best = p
                .run
                .iter()
                .zip(&score)
                .all(|(&j, o)| (t[j] - t[k]).abs() > 0.5 * half || o.is_none_or(|x| x < s || (x == s && j >= k)));
            if best {
                found.push(k);
            }
        }
    }
    found
}

/// A strike inside a rung run changes the ring's power at least this many
/// times the ring's before it ...
const CHANGE: f64 = 1.0;

/// ... and its amplitude by at least this (m/s²).
const CHANGE_MIN: f64 = 2.0;

/// The ring's fits either side of a sample need this many samples each.
const CHANGE_SAMPLES: usize = 10;

/// Each sample of the piece `p` with the ring at `hz` taken off each
/// axis not masked there (`masks`: each axis's samples left out; `None`
/// where it is, or too few samples about it), and the piece's power
/// about the local fits' swing before (the readings less the quadratic)
/// and after (less the ring as well).
#[allow(clippy::type_complexity)]
fn clean_run(log: &AccelLog, masks: &[Vec<bool>; 3], p: &Piece, hz: f64) -> (Vec<[Option<f64>; 3]>, f64, f64) {
    let t = &log.t;
    let axes = [&log.radial, &log.tangential, &log.axle];
    // Six of the ring's cycles each side, and at least ±0.15 s.
    let half = (6.0 / hz).max(0.15);
    let basis = ring_basis(hz);
    let (mut before, mut after) = (0.0, 0.0);
    let mut cleaned = Vec::with_capacity(p.run.len());
    for &k in &p.run {
        // Not across a strike: the next starts the ring afresh.
        let (lo, hi) = (
            t.partition_point(|&x| x < t[k] - half).max(p.span.0),
            t.partition_point(|&x| x <= t[k] + half).min(p.span.1),
        );
        let mut c = [None; 3];
        for a in 0..3 {
            // A clipped in-plane reading is missing, not wrong: the swing
            // is read through it from the samples about it (below).
            let missing = masks[a][k];
            if missing && a == 2 {
                continue;
            }
            let pts: Vec<usize> = (lo..hi).filter(|&j| !masks[a][j]).collect();
            // Seven terms: well over twice as many samples, some on each side.
            let left = pts.iter().filter(|&&j| j < k).count();
            let right = pts.iter().filter(|&&j| j > k).count();
            if pts.len() < 16 || left < 4 || right < 4 {
                continue;
            }
            let (swing, ring) = fit(t, axes[a], &pts, t[k], &basis);
            let y = axes[a][k];
            if missing {
                // The swing's value there, when the fit agrees that the
                // reading clipped: swing and ring together past the
                // range, on the side it clipped.
                if let Some(r) = ring.filter(|r| (r[0] + r[3]) * y.signum() >= y.abs() - CLIP_SLACK) {
                    c[a] = Some(r[0]);
                }
                continue;
            }
            // The swing's quadratic alone, and with the ring.
            if let (Some(q), Some(r)) = (swing, ring) {
                before += (y - q).powi(2);
                after += (y - r[0] - r[3]).powi(2);
                c[a] = Some(y - r[3]);
            }
        }
        cleaned.push(c);
    }
    (cleaned, before, after)
}

/// The local model's terms at `x` s from the sample: the swing (a
/// quadratic) and the ring at `hz` Hz, its amplitude changing linearly.
fn ring_basis(hz: f64) -> impl Fn(f64) -> [f64; 7] {
    let w = TAU * hz;
    move |x: f64| {
        let (sn, cs) = (w * x).sin_cos();
        [1.0, x, x * x, cs, x * cs, sn, x * sn]
    }
}

/// Least squares at `pts` about `at`: a quadratic alone (its value at
/// `at`), and the seven terms of `basis` (their coefficients).
#[allow(clippy::type_complexity)]
fn fit(
    t: &[f64],
    y: &[f64],
    pts: &[usize],
    at: f64,
    basis: &dyn Fn(f64) -> [f64; 7],
) -> (Option<f64>, Option<[f64; 7]>) {
    let mut m = [[0.0; 7]; 7];
    let mut v = [0.0; 7];
    for &j in pts {
        let b = basis(t[j] - at);
        for r in 0..7 {
            v[r] += b[r] * y[j];
            for c in 0..7 {
                m[r][c] += b[r] * b[c];
            }
        }
    }
    let q = clapper_core::linalg::solve(
        [
            [m[0][0], m[0][1], m[0][2]],
            [m[1][0], m[1][1], m[1][2]],
            [m[2][0], m[2][1], m[2][2]],
        ],
        [v[0], v[1], v[2]],
    );
    (q.map(|q| q[0]), clapper_core::linalg::solve(m, v))
}

/// The longest stretch (s) from a strike a dying ring is fitted over.
const DYING_SPAN_S: f64 = 2.5;

/// Each sample's readings (radial, tangential, axle) with the ring taken
/// out as one dying oscillation per strike ([`dying`]), where told: over
/// the samples of each span of `pieces` (strike to next, at most
/// [`DYING_SPAN_S`]) that it explains to [`EXPLAINED`] on the axes
/// together, the log's decay time the one of [`DECAYS`] that leaves least
/// over all spans.
fn dying_rings(log: &AccelLog, masks: &[Vec<bool>; 3], pieces: &[Piece], hz: f64) -> Vec<[Option<f64>; 3]> {
    let t = &log.t;
    let mut told = vec![[None; 3]; t.len()];
    let axes = [&log.radial, &log.tangential, &log.axle];
    let mut spans: Vec<(usize, usize)> = pieces
        .iter()
        .map(|p| {
            let end = t.partition_point(|&x| x <= t[p.span.0] + DYING_SPAN_S);
            (p.span.0, p.span.1.min(end))
        })
        .collect();
    spans.sort_unstable();
    spans.dedup();
    let pts = |a: usize, (lo, hi): (usize, usize)| -> Vec<usize> { (lo..hi).filter(|&j| !masks[a][j]).collect() };
    let fits = |decay: f64| -> Vec<[Option<Dying>; 3]> {
        spans
            .iter()
            .map(|&sp| [0, 1, 2].map(|a| dying(t, axes[a], &pts(a, sp), sp, hz, decay)))
            .collect()
    };
    let left = |f: &[[Option<Dying>; 3]]| -> f64 { f.iter().flatten().flatten().map(|d| d.after).sum() };
    let Some(decay) = DECAYS
        .iter()
        .map(|&d| (d, left(&fits(d))))
        .min_by(|x, y| x.1.total_cmp(&y.1))
        .map(|x| x.0)
    else {
        return told;
    };
    let fitted = fits(decay);
    for (&sp, f) in spans.iter().zip(&fitted) {
        let (before, after) = f
            .iter()
            .flatten()
            .fold((0.0, 0.0), |s, d| (s.0 + d.before, s.1 + d.after));
        if before <= 0.0 || after > (1.0 - EXPLAINED) * before {
            continue;
        }
        // Each axis's cleaned value at each sample of the span, where told.
        let cleaned: [Vec<Option<f64>>; 3] = [0, 1, 2].map(|a| {
            let mut v = vec![None; sp.1 - sp.0];
            let Some(d) = &f[a] else { return v };
            let p = pts(a, sp);
            for (&j, q) in p.iter().zip(&d.swing) {
                if q.is_some() {
                    v[j - sp.0] = Some(axes[a][j] - d.ring[j - sp.0]);
                }
            }
            if a == 2 {
                return v;
            }
            read_through(t, (axes[a], &masks[a]), sp, &d.ring, &mut v);
            v
        });
        for j in sp.0..sp.1 {
            told[j] = [0, 1, 2].map(|a| cleaned[a][j - sp.0]);
        }
    }
    told
}

/// A clipped reading (`mask`, of the readings `y`) is missing: the swing
/// read through it from the cleaned samples `v` about it (2 each side
/// within ±0.1 s, a quadratic), where that swing and the `ring` together
/// reach the clipped value on its side; `v` and `ring` from the span
/// `sp`'s first sample.
fn read_through(t: &[f64], (y, mask): (&[f64], &[bool]), sp: (usize, usize), ring: &[f64], v: &mut [Option<f64>]) {
    let known: Vec<usize> = (sp.0..sp.1).filter(|&j| v[j - sp.0].is_some()).collect();
    let vals: Vec<f64> = known.iter().map(|&j| v[j - sp.0].unwrap_or(0.0)).collect();
    for j in (sp.0..sp.1).filter(|&j| mask[j]) {
        let lo = known.partition_point(|&k| t[k] < t[j] - 0.1);
        let hi = known.partition_point(|&k| t[k] <= t[j] + 0.1);
        let mid = known.partition_point(|&k| k < j);
        if mid - lo < 2 || hi - mid < 2 {
            continue;
        }
        if let Some(q) = quadratic_at(t, &known[lo..hi], &vals[lo..hi], t[j]) {
            if (q + ring[j - sp.0]) * y[j].signum() >= y[j].abs() - CLIP_SLACK {
                v[j - sp.0] = Some(q);
            }
        }
    }
}
