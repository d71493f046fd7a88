//! Bottom dead centres, amplitudes and strikes (docs/model.md §13 step 4),
//! with the angle or, when it cannot be read, from the tangential zeros.

use super::fits::power_sums;
use super::reading::gravity_part;
use super::types::{AccelLog, LogStroke, PhaseKind};
use clapper_core::bell::G;
use clapper_core::linalg::solve;

/// Bottom dead centres, amplitudes and strikes (method step 3).
pub(super) fn strokes(
    log: &AccelLog,
    theta: &[f64],
    smooth: &[f64],
    (d1, j1, d2, h, across): (&[f64], &[f64], &[f64], f64, f64),
    (burst, shaken, onsets, cubic): (&[bool], &[bool], &[usize], &[bool]),
    rests: &[(f64, f64, f64)],
    (min_gap, interval, kappa): (f64, f64, f64),
) -> Vec<LogStroke> {
    let t = &log.t;
    let n = t.len();
    let resting = |time: f64| rests.iter().any(|r| time >= r.0 && time <= r.1);
    // The tangential reading is g sin θ less h θ'' less d θ'²; corrected
    // by both, its zero is the bottom. θ'' matters there: a rope's pull that
    // stops or starts at the bottom leaves h θ'' on one side only, which
    // moved a small swing's bottom 3 ms the way of the pull (θ'' from the
    // joint fits, smoothed across the step, takes off half of it on each
    // side, and what is left is odd about the bottom).
    let f: Vec<f64> = (0..n)
        .map(|j| gravity_part(log, j, (h, across), j1[j], d2[j])[0])
        .collect();
    let mut bdcs: Vec<(f64, usize)> = vec![];
    for k in 0..n - 1 {
        let (a, b) = (theta[k], theta[k + 1]);
        // A crossing of 0 while the bell moves.
        if a.signum() != b.signum() && a.abs() < 1.5 && b.abs() < 1.5 && (d1[k].abs() > 0.3 || d1[k + 1].abs() > 0.3) {
            let mut tc = t[k] + (t[k + 1] - t[k]) * a / (a - b);
            if resting(tc) || bdcs.last().is_some_and(|&(p, _)| tc - p < min_gap) {
                continue;
            }
            // The tangential reading's own zero, where clean (`f`).
            let near = (k.saturating_sub(4)..(k + 5).min(n - 1))
                .filter(|&j| !shaken[j] && !shaken[j + 1] && f[j].signum() != f[j + 1].signum() && f[j] != 0.0)
                .min_by_key(|&j| j.abs_diff(k));
            if let Some(j) = near {
                tc = t[j] + (t[j + 1] - t[j]) * f[j] / (f[j] - f[j + 1]);
                tc = bottom_time(t, &f, (shaken, cubic), (tc, interval), G * 0.5 * (d1[k] + d1[k + 1]));
            }
            bdcs.push((tc, k));
        }
    }
    let mut out = Vec::with_capacity(bdcs.len());
    for (i, &(bdc, k)) in bdcs.iter().enumerate() {
        // The turning point it fell from: the largest |θ| since the last
        // bottom (or in the 3 s before the first), on its side.
        let mut from = if i == 0 {
            t.partition_point(|&x| x < bdc - 3.0)
        } else {
            bdcs[i - 1].1 + 1
        };
        // After a rest (set at the balance, or a stand), it fell from where
        // it rested: the rest's mean angle, read while still (the samples
        // after a strike, while the headstock rings, overshoot).
        let side = theta[k].signum();
        let stood = rests.iter().rev().find(|r| r.1 < bdc && t[from] <= r.1);
        if let Some(r) = stood {
            from = from.max(t.partition_point(|&x| x < r.1 - 0.5));
        }
        // From the smoothed angle: the largest of noisy samples overshoots.
        // A stand's still samples first: a rest's mean angle, smoothed over
        // a second, mixes readings either side of the ±200 deg hold.
        // A still run at or past the balance is the bell on the stay; short
        // of it, a free swing's slow top, read from its clean samples.
        let still = stand_height(log, burst, (from, k), side).map(|s| s.height);
        let stand = match still {
            Some(h) if h >= std::f64::consts::PI => Some(h),
            _ => clean_top(log, burst, (from, k), side, kappa).or(still),
        }
        .or_else(|| short_stand(t, theta, burst, (from, k), side));
        let amplitude = match (stand, stood) {
            (Some(h), _) => h,
            (None, Some(r)) if r.2.signum() == side => r.2.abs(),
            _ => turning_height(t, theta, smooth, burst, (from, k), side),
        };
        let until = bdcs.get(i + 1).map_or(f64::INFINITY, |b| b.0);
        out.push(stroke_between(t, theta, onsets, (bdc, until), amplitude, side));
    }
    out
}

/// A stand on the stay (at or past the balance) read through the
/// headstock's ringing: on the stay the bell is still, so the readings are
/// gravity alone and its angle is atan2(tangential, radial) of the
/// calibrated readings, without the swing's corrections (which, from θ''
/// fitted through the shaking, threw the angle about by 40 deg on
/// Data141's stands). Of the samples `from..=k` that are not bursts nor
/// clipped and whose force is within [`STAND_FORCE`] of g (the shaking
/// moves the rest), each one's height on `side` (as in [`short_stand`])
/// smoothed by the median over ±[`STAND_SMOOTH_S`]; the highest still
/// run of them (below), at its highest, and how long the smoothed heights
/// stayed within [`STAND_NEAR`] of that around the run.
pub(super) fn stand_height(log: &AccelLog, burst: &[bool], (from, k): (usize, usize), side: f64) -> Option<StandRead> {
    let t = &log.t;
    let height = |j: usize| side_height(log, j, side);
    let good: Vec<usize> = (from..=k)
        .filter(|&j| !burst[j] && (log.tangential[j].hypot(log.radial[j]) - G).abs() <= STAND_FORCE * G)
        .collect();
    let raw: Vec<f64> = good.iter().map(|&j| height(j)).collect();
    // Each sample's median and median absolute deviation over the window.
    let (mut lo, mut hi) = (0, 0);
    let (smooth, spread): (Vec<f64>, Vec<f64>) = (0..good.len())
        .map(|i| {
            while t[good[i]] - t[good[lo]] > STAND_SMOOTH_S {
                lo += 1;
            }
            while hi + 1 < good.len() && t[good[hi + 1]] - t[good[i]] <= STAND_SMOOTH_S {
                hi += 1;
            }
            let mut v = raw[lo..=hi].to_vec();
            v.sort_by(f64::total_cmp);
            let m = v[v.len() / 2];
            let mut d: Vec<f64> = v.iter().map(|x| (x - m).abs()).collect();
            d.sort_by(f64::total_cmp);
            (m, d[d.len() / 2])
        })
        .unzip();
    // The stand: runs of samples high enough, where the shaking has died
    // down (the heights' spread under [`STAND_SPREAD`]: through the
    // ringing it is 4-17 deg on Data141), whose smoothed heights stay
    // within [`STAND_NEAR`] of each other, lasting [`SHORT_STAND_S`]; of
    // those the highest (the bell pulled back over the balance, or slow to
    // start its fall, is lower), read at its highest smoothed height (a
    // swing's slow top, not still, at its top).
    let still = |i: usize| (STAND_MIN..=200f64.to_radians()).contains(&smooth[i]) && spread[i] <= STAND_SPREAD;
    let mut best: Option<(f64, usize, usize)> = None;
    let mut i = 0;
    while i < good.len() {
        if !still(i) {
            i += 1;
            continue;
        }
        let a = i;
        let (mut lo, mut hi) = (smooth[i], smooth[i]);
        while i < good.len() && still(i) && smooth[i].max(hi) - smooth[i].min(lo) <= STAND_NEAR {
            (lo, hi) = (smooth[i].min(lo), smooth[i].max(hi));
            i += 1;
        }
        if t[good[i - 1]] - t[good[a]] >= SHORT_STAND_S && best.is_none_or(|b| hi > b.0) {
            best = Some((hi, a, i - 1));
        }
        // The next run may start inside this one.
        i = i.max(a + 1);
    }
    // On the stay from arriving to leaving: the smoothed heights near the
    // stand's on either side of the still run (the shaking at its start
    // left in).
    best.map(|(height, mut a, mut b)| {
        let near = |i: usize| (smooth[i] - height).abs() <= STAND_NEAR;
        while a > 0 && near(a - 1) {
            a -= 1;
        }
        while b + 1 < good.len() && near(b + 1) {
            b += 1;
        }
        StandRead {
            height,
            on: t[good[a]],
            off: t[good[b]],
        }
    })
}

/// A swing's top near the balance (at least [`STAND_MIN`]) read through
/// the headstock's ringing: the highest of the robust means (Tukey's
/// biweight) of the clean samples' gravity heights on `side` over
/// ±[`TOP_WINDOW_S`], the bell's own swing's share taken out (near the
/// balance a free swing's θ'' is (g/L) ε, ε its distance short of the
/// balance, which the sensor `kappa` = h/L up reads as ε (1 + κ)); `None`
/// below [`STAND_MIN`] or with too few clean samples. The samples are
/// those of [`stand_height`] (no bursts, force within [`STAND_FORCE`] of
/// g) between 160 and 200 deg. A top's own samples shaken by the ringing
/// but under the burst threshold (±4 deg for a second on a headstock that
/// clips) made the smoothed angle peak read up to 200 deg, and a median's
/// spread too wide for a still run: of 480 ringing tops of the clipping
/// test's 30 logs, 31 read over 2 deg off (up to 21), none with this.
fn clean_top(log: &AccelLog, burst: &[bool], (from, k): (usize, usize), side: f64, kappa: f64) -> Option<f64> {
    let t = &log.t;
    let pts: Vec<(f64, f64)> = (from..=k)
        .filter(|&j| !burst[j] && (log.tangential[j].hypot(log.radial[j]) - G).abs() <= STAND_FORCE * G)
        .map(|j| (t[j], side_height(log, j, side)))
        .filter(|p| (160f64.to_radians()..=200f64.to_radians()).contains(&p.1))
        .collect();
    let (mut lo, mut hi) = (0, 0);
    let mut best: Option<f64> = None;
    for i in 0..pts.len() {
        while pts[i].0 - pts[lo].0 > TOP_WINDOW_S {
            lo += 1;
        }
        while hi + 1 < pts.len() && pts[hi + 1].0 - pts[i].0 <= TOP_WINDOW_S {
            hi += 1;
        }
        if hi + 1 - lo >= TOP_MIN_SAMPLES {
            let m = biweight_mean(pts[lo..=hi].iter().map(|p| p.1).collect());
            best = Some(best.map_or(m, |b| b.max(m)));
        }
    }
    let pi = std::f64::consts::PI;
    best.map(|h| pi - (pi - h) / (1.0 + kappa)).filter(|&h| h >= STAND_MIN)
}

/// The clean top's robust means span ± this (s).
const TOP_WINDOW_S: f64 = 0.2;

/// A clean top's robust mean needs at least this many samples.
const TOP_MIN_SAMPLES: usize = 10;

/// Tukey's biweight mean of `v` (tuning 4.685 robust deviations, from the
/// median; five reweightings).
fn biweight_mean(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    let median = v[v.len() / 2];
    let mut d: Vec<f64> = v.iter().map(|x| (x - median).abs()).collect();
    d.sort_by(f64::total_cmp);
    let scale = 4.685 * (1.4826 * d[d.len() / 2]).max(1e-6);
    let mut m = median;
    for _ in 0..5 {
        let (mut sw, mut sx) = (0.0, 0.0);
        for &x in &v {
            let u = (x - m) / scale;
            if u.abs() < 1.0 {
                let w = (1.0 - u * u).powi(2);
                sw += w;
                sx += w * x;
            }
        }
        if sw > 0.0 {
            m = sx / sw;
        }
    }
    m
}

/// Sample `j`'s gravity angle's height on `side` (rad): |atan2| on that
/// side, else a full turn less it (past the balance).
fn side_height(log: &AccelLog, j: usize, side: f64) -> f64 {
    let p = log.tangential[j].atan2(log.radial[j]);
    if p.signum() == side {
        p.abs()
    } else {
        std::f64::consts::TAU - p.abs()
    }
}

/// A stand on the stay as [`stand_height`] reads it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct StandRead {
    /// Its height on the side the stroke falls to (rad).
    pub height: f64,
    /// When the bell came onto the stay (s).
    pub on: f64,
    /// When it left (s).
    pub off: f64,
}

/// A stand's heights' median absolute deviation over ±[`STAND_SMOOTH_S`]
/// is at most this (rad): 2.5 deg.
const STAND_SPREAD: f64 = 2.5 * std::f64::consts::PI / 180.0;

/// A stand's smoothed heights lie within this (rad) of each other: 3 deg
/// (the shaking moves a median over ±0.15 s by a degree or two).
const STAND_NEAR: f64 = 3.0 * std::f64::consts::PI / 180.0;

/// A stand's samples read a force within this fraction of g.
const STAND_FORCE: f64 = 0.2;

/// A stand's heights are smoothed by their median over ± this (s).
const STAND_SMOOTH_S: f64 = 0.15;

/// A stand is at least this high (rad): 172 deg (Data141's backstroke
/// stands read 176-184 deg, its handstroke stands 186-188: the stay meets
/// the slider a few degrees either side of the balance). A swing's slow top
/// read so reads high by h θ''/g, the swing's own acceleration left in: 1.2
/// deg at 175 for a sensor 0.15 m above the pivot; below 172 deg a top is
/// not still long enough to be read so.
const STAND_MIN: f64 = 172.0 * std::f64::consts::PI / 180.0;

/// A stand too short to be read as a rest (Data141's last about 2 s, the
/// first second of it with the headstock still ringing from the strike):
/// the longest run of clean samples among `from..=k` at the balance (over
/// 150 deg, under 200 on `side`), still (|θ'| under 0.1 rad/s), lasting at least
/// [`SHORT_STAND_S`]; its median |θ| (rad).
fn short_stand(t: &[f64], theta: &[f64], burst: &[bool], (from, k): (usize, usize), side: f64) -> Option<f64> {
    // Past the balance the angle may read on the other side (θ is held
    // within ±200 deg, and a stand at 189 deg reached through the ringing
    // reads −171): its height on `side` is then 360 deg less |θ|.
    let height = |j: usize| {
        if theta[j].signum() == side {
            theta[j].abs()
        } else {
            std::f64::consts::TAU - theta[j].abs()
        }
    };
    let valid = |j: usize| !burst[j] && theta[j].abs() > 150f64.to_radians() && height(j) < 200f64.to_radians();
    // Runs of valid samples whose heights stay within [`STAND_RANGE`] of each other
    // (the headstock's shaking and noise, not motion); the longest.
    let mut best: Option<(usize, usize)> = None;
    let mut j = from;
    while j <= k {
        if !valid(j) {
            j += 1;
            continue;
        }
        let a = j;
        let (mut lo, mut hi) = (height(j), height(j));
        while j <= k && valid(j) {
            let h = height(j);
            if h.max(hi) - h.min(lo) > STAND_RANGE {
                break;
            }
            (lo, hi) = (h.min(lo), h.max(hi));
            j += 1;
        }
        if best.is_none_or(|(p, q)| t[j - 1] - t[a] > t[q] - t[p]) {
            best = Some((a, j - 1));
        }
        // The next run may start inside this one.
        j = j.max(a + 1);
    }
    let (a, b) = best.filter(|&(a, b)| t[b] - t[a] >= SHORT_STAND_S)?;
    let mut v: Vec<f64> = (a..=b).map(height).collect();
    v.sort_by(f64::total_cmp);
    Some(v[v.len() / 2])
}

/// A short stand lasts at least this (s) of clean, still samples.
const SHORT_STAND_S: f64 = 0.3;

/// A short stand's heights lie within this of each other (rad): 2 deg (a
/// swing's slow top, not stopped, reads a degree or so low over 3 deg).
const STAND_RANGE: f64 = 2.0 * std::f64::consts::PI / 180.0;

/// The bottom's window is at most ± this (s).
pub(super) const BOTTOM_HALF_MAX: f64 = 0.12;

/// The height |θ| (rad) of the turning point on `side` among samples
/// `from..=k`: where the smoothed angle peaks, a parabola through the
/// angle's clean samples within ±0.2 s, refitted without those more than
/// three robust deviations (and 0.5 deg) off it. A sample a strike's
/// shaking moved that the burst test let through (at 50 Hz, one between
/// two bursts at a raising swing's top read 18 deg high) pulled the
/// smoothed angle's peak 4.3 deg up; the refit leaves it out.
/// The turning point's parabola spans ± this (s).
const TURN_HALF: f64 = 0.3;

/// The parabola's height replaces the smoothed peak's only within this (rad): 6 deg.
const TURN_MAX_CHANGE: f64 = 6.0 * std::f64::consts::PI / 180.0;

fn turning_height(
    t: &[f64],
    theta: &[f64],
    smooth: &[f64],
    burst: &[bool],
    (from, k): (usize, usize),
    side: f64,
) -> f64 {
    let Some(peak) = (from..=k)
        .filter(|&j| smooth[j].signum() == side)
        .max_by(|&a, &b| smooth[a].abs().total_cmp(&smooth[b].abs()))
    else {
        return 0.0;
    };
    let plain = smooth[peak].abs();
    let (a, b) = (
        t.partition_point(|&x| x < t[peak] - TURN_HALF),
        t.partition_point(|&x| x <= t[peak] + TURN_HALF),
    );
    let mut pts: Vec<usize> = (a..b).filter(|&j| !burst[j]).collect();
    for round in 0..2 {
        if pts.len() < 5 {
            return plain;
        }
        let Some(c) = parabola(t, theta, &pts, t[peak]) else {
            return plain;
        };
        let resid: Vec<f64> = pts
            .iter()
            .map(|&j| {
                let x = t[j] - t[peak];
                theta[j] - (c[0] + x * (c[1] + x * c[2]))
            })
            .collect();
        let mut abs: Vec<f64> = resid.iter().map(|r| r.abs()).collect();
        abs.sort_by(f64::total_cmp);
        let limit = (3.0 * 1.4826 * abs[abs.len() / 2]).max(0.5f64.to_radians());
        if round == 1 || resid.iter().all(|r| r.abs() <= limit) {
            // The parabola's top, if within the window; else its value at the peak.
            let top = if c[2] != 0.0 {
                -c[1] / (2.0 * c[2])
            } else {
                f64::INFINITY
            };
            let x = if top.abs() <= TURN_HALF { top } else { 0.0 };
            let height = (c[0] + x * (c[1] + x * c[2])).abs();
            // Only what a few shaken samples can do to the smoothed peak: a
            // larger disagreement is a top that is no parabola (a stand, a
            // check), where the smoothed peak is kept.
            return if (height - plain).abs() <= TURN_MAX_CHANGE {
                height
            } else {
                plain
            };
        }
        pts = pts
            .iter()
            .zip(&resid)
            .filter(|(_, r)| r.abs() <= limit)
            .map(|(&j, _)| j)
            .collect();
    }
    plain
}

/// Least-squares parabola c0 + c1 x + c2 x² through `y` at `pts`, x = t − `at`.
fn parabola(t: &[f64], y: &[f64], pts: &[usize], at: f64) -> Option<[f64; 3]> {
    let (s, r) = power_sums(t, y, pts.iter().copied(), at);
    solve([[s[0], s[1], s[2]], [s[1], s[2], s[3]], [s[2], s[3], s[4]]], r)
}

/// The zero of the corrected tangential reading `f` near `tc` (s), where
/// it moves at about `slope` (m/s³, g θ'): a straight line through the
/// clean samples while |f| is within [`BOTTOM_SPAN`] (at least ±5 ms and
/// 1.5 samples, at most ±0.12 s). Through the bottom f is g sin θ, odd
/// about it, so a symmetric window adds no bias, and a long one averages
/// the noise down where a small swing moves slowly (at 400 Hz a 20 deg
/// swing's bottom moved 2 samples either way in a ±5 ms window). A gap in
/// the log ([`GAP`]) narrows the window on both sides, and so does a clean
/// sample whose θ'' is not the angle's cubic (`cubic` false: the fallback,
/// one-sided, near a gap or the log's ends): one-sided, the curve of f
/// beyond the line (sin θ, a rope's pull) put a slow swing's bottom, 60 ms
/// before a gap, 7.2 ms early (1.8 samples at 250 Hz); symmetric at the
/// gap, 4.9 ms, its last samples corrected by the fallback's θ'';
/// symmetric short of those, 0.04 ms.
pub(super) fn bottom_time(
    t: &[f64],
    f: &[f64],
    (burst, cubic): (&[bool], &[bool]),
    (tc, interval): (f64, f64),
    slope: f64,
) -> f64 {
    let n = t.len();
    let k = t.partition_point(|&x| x < tc).clamp(1, n - 1);
    let dt = t[k] - t[k - 1];
    // (At a gap the interval is long: the window stays within ±0.12 s.)
    let shortest = 0.005f64.max(1.5 * dt).min(BOTTOM_HALF_MAX);
    let mut half = (BOTTOM_SPAN / slope.abs().max(1e-9)).clamp(shortest, BOTTOM_HALF_MAX);
    let gap = |q: usize| t[q] - t[q - 1] > GAP * interval;
    // A clean sample whose θ'' is not the cubic's is one-sided: an edge.
    let edge = |q: usize| !burst[q] && !cubic[q];
    let (mut lo, mut hi) = (k - 1, k);
    while lo > 0 && tc - t[lo] < half && !gap(lo) && !edge(lo - 1) {
        lo -= 1;
    }
    while hi + 1 < n && t[hi] - tc < half && !gap(hi + 1) && !edge(hi + 1) {
        hi += 1;
    }
    half = half.min(tc - t[lo]).min(t[hi] - tc);
    let (a, b) = (
        t.partition_point(|&x| x < tc - half),
        t.partition_point(|&x| x <= tc + half),
    );
    let pts: Vec<usize> = (a..b).filter(|&q| !burst[q]).collect();
    if pts.len() < 3 {
        return tc;
    }
    let m = pts.len() as f64;
    let (sx, sy) = pts.iter().fold((0.0, 0.0), |a, &q| (a.0 + t[q] - tc, a.1 + f[q]));
    let (mx, my) = (sx / m, sy / m);
    let (sxy, sxx) = pts.iter().fold((0.0, 0.0), |a, &q| {
        (a.0 + (t[q] - tc - mx) * (f[q] - my), a.1 + (t[q] - tc - mx).powi(2))
    });
    if sxx <= 0.0 || sxy == 0.0 {
        return tc;
    }
    let zero = tc + mx - my * sxx / sxy;
    if (zero - tc).abs() <= half {
        zero
    } else {
        tc
    }
}

/// An interval over this many times the median is a gap (samples lost):
/// past the 2 % jitter of a logger like belfry-sleuth's with room to
/// spare, short of one lost sample (2).
pub const GAP: f64 = 1.75;

/// The reading's span either side of a bottom that [`bottom_time`] fits a
/// line over (m/s²): 2 m/s² is g sin θ within ±12 deg of the bottom, where
/// sin θ departs from a line by 0.7 %, and that symmetrically.
pub(super) const BOTTOM_SPAN: f64 = 2.0;

/// The stroke with bottom dead centre `bdc`, struck at the first burst
/// onset before `until` (the next bottom); its hand set later.
pub(super) fn stroke_between(
    t: &[f64],
    theta: &[f64],
    onsets: &[usize],
    (bdc, until): (f64, f64),
    amplitude: f64,
    from_side: f64,
) -> LogStroke {
    let strike_at = onsets.iter().copied().find(|&j| t[j] > bdc && t[j] < until);
    LogStroke {
        bdc,
        hand: true,
        strike: strike_at.map(|j| t[j]),
        strike_hidden: false,
        strike_theta: strike_at.map(|j| theta[j]),
        amplitude,
        from_side,
        phase: PhaseKind::Ringing,
        speed_peak: None,
        bdc_se: None,
        stand: None,
        amplitude_timed: false,
    }
}

/// Above this misfit (the corrected force's median departure from g, over
/// g) the angle is not trusted: 0.1 g. Logs the model makes read about
/// 0.01; a light bell with the sensor well off its pivot, whose
/// centripetal acceleration at the bottom passes g, reads far more.
pub(super) const MAX_MISFIT: f64 = 0.1;

/// Strokes without the angle (when it cannot be read): a bottom dead
/// centre is a zero of the tangential reading while it changes fast (at
/// least 5 m/s³; at the bottom θ'' is near zero and the reading moves as g
/// θ') and swings past 0.15 g on both sides within 0.25 s; the side it
/// fell from is the slope's sign, and sides alternate (of two in a row
/// from one side, the bottom is the one the reading swings further about); the amplitude is read
/// at the turning point, halfway between bottoms, where θ' = 0 and the
/// radial reading is exactly g cos A.
pub(super) fn strokes_by_zeros(
    log: &AccelLog,
    theta: &[f64],
    (burst, onsets): (&[bool], &[usize]),
    rests: &[(f64, f64, f64)],
) -> Vec<LogStroke> {
    let (t, f) = (&log.t, &log.tangential);
    let n = t.len();
    let resting = |time: f64| rests.iter().any(|r| time >= r.0 && time <= r.1);
    let mut cands: Vec<(f64, f64, f64)> = vec![];
    for j in 0..n - 1 {
        if burst[j] || burst[j + 1] || f[j] == 0.0 || f[j].signum() == f[j + 1].signum() {
            continue;
        }
        let slope = (f[j + 1] - f[j]) / (t[j + 1] - t[j]);
        let tc = t[j] + (t[j + 1] - t[j]) * f[j] / (f[j] - f[j + 1]);
        if slope.abs() < 5.0 || resting(tc) {
            continue;
        }
        // Through the bottom the reading swings well away from zero on both
        // sides within a quarter of a second; a bell wobbling at the
        // balance (the ringer holding it) only flickers across.
        let reach =
            |range: std::ops::Range<usize>| range.filter(|&q| !burst[q]).map(|q| f[q].abs()).fold(0.0, f64::max);
        let (a, b) = (
            t.partition_point(|&x| x < tc - 0.25),
            t.partition_point(|&x| x <= tc + 0.25),
        );
        let swing = reach(a..j + 1).min(reach(j + 1..b));
        if swing < 0.15 * G {
            continue;
        }
        // Rising through zero: moving toward θ > 0, so it fell from θ < 0.
        cands.push((tc, -slope.signum(), swing));
    }
    // Swings alternate: a bottom falls from the side the last one rose to.
    // Two in a row from one side are a bottom and a wobble at the balance
    // (the ringer holding the bell jolts the reading, faster than through
    // the bottom): keep the one the reading swings further about.
    let mut kept: Vec<(f64, f64, f64)> = vec![];
    for &c in &cands {
        match kept.last_mut() {
            Some(last) if c.0 - last.0 < 0.3 => {}
            Some(last) if last.1 == c.1 && c.0 - last.0 < 4.0 => {
                if c.2 > last.2 {
                    *last = c;
                }
            }
            _ => kept.push(c),
        }
    }
    let bdcs: Vec<(f64, f64)> = kept.iter().map(|c| (c.0, c.1)).collect();
    let angle_at = |time: f64| {
        let k = t.partition_point(|&x| x < time).min(n - 1);
        let pts: Vec<usize> = (k.saturating_sub(2)..(k + 3).min(n)).filter(|&q| !burst[q]).collect();
        let m = pts.len().max(1) as f64;
        let (ft, fr) = pts.iter().fold((0.0, 0.0), |a, &q| (a.0 + f[q], a.1 + log.radial[q]));
        (ft / m).atan2(fr / m).abs()
    };
    let mut out = Vec::with_capacity(bdcs.len());
    for (i, &(bdc, side)) in bdcs.iter().enumerate() {
        let before = if i == 0 { bdc - 1.5 } else { bdcs[i - 1].0 };
        let amplitude = match rests.iter().rev().find(|r| r.1 < bdc && r.1 > before) {
            Some(r) => r.2.abs(),
            None => angle_at(0.5 * (before + bdc)),
        };
        let until = bdcs.get(i + 1).map_or(f64::INFINITY, |b| b.0);
        out.push(stroke_between(t, theta, onsets, (bdc, until), amplitude, side));
    }
    out
}

/// After a gap between bottom dead centre and the first burst read, the
/// clapper may have struck in the gap (and its burst died away there, so
/// the burst read is a bounce): the strike's time is not known, and a
/// stroke timed from it moves the odd-struckness (one such stroke in 20
/// moved a synthetic log's by 30 ms).
pub(super) fn hide_strikes_after_gaps(t: &[f64], interval: f64, strokes: &mut [LogStroke], warnings: &mut Vec<String>) {
    let mut hidden = 0;
    for s in strokes.iter_mut() {
        let Some(ts) = s.strike else { continue };
        let (a, b) = (
            t.partition_point(|&x| x <= s.bdc).max(1),
            t.partition_point(|&x| x <= ts),
        );
        if (a..b).any(|k| t[k] - t[k - 1] > GAP * interval) {
            s.strike = None;
            s.strike_theta = None;
            s.strike_hidden = true;
            hidden += 1;
        }
    }
    if hidden > 0 {
        warnings.push(format!(
            "{hidden} strike(s) not timed: a gap in the log lies between the bottom and the first burst after it"
        ));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use clapper_core::bell::G;

    /// A reading odd about its zero (a x + b x|x|: the part of a rope's
    /// pull the θ'' fits leave) is read at its zero exactly when a gap cuts
    /// the window on one side: the window is cut on the other side too
    /// (one-sided, the line through it misses the zero by 0.7 ms here).
    #[test]
    fn a_gap_beside_a_bottom_keeps_its_window_symmetric() {
        let t0 = 1.005;
        let t: Vec<f64> = (0..300)
            .map(|k| k as f64 * 0.01)
            .filter(|&x| !(t0 + 0.04..t0 + 0.5).contains(&x))
            .collect();
        let f: Vec<f64> = t
            .iter()
            .map(|&x| 2.0 * (x - t0) + 60.0 * (x - t0) * (x - t0).abs())
            .collect();
        let burst = vec![false; t.len()];
        let cubic = vec![true; t.len()];
        let got = bottom_time(&t, &f, (&burst, &cubic), (t0, 0.01), 2.0);
        assert!((got - t0).abs() < 1e-9, "{got}");
    }

    /// Two bottoms come at least `min_gap` apart: the angle shaken back
    /// across zero 0.1 s after a bottom (as a strike's burst can read) is
    /// not taken for two more bottoms.
    #[test]
    fn a_crossing_soon_after_a_bottom_is_not_a_bottom() {
        // A 1 rad swing of period 2 s (bottoms at 1, 2, 3, 4 s), 100 Hz,
        // the sensor at the pivot.
        let t: Vec<f64> = (0..500).map(|k| k as f64 * 0.01).collect();
        let w = std::f64::consts::PI;
        let mut theta: Vec<f64> = t.iter().map(|&x| (w * x).sin()).collect();
        let d1: Vec<f64> = t.iter().map(|&x| w * (w * x).cos()).collect();
        let d2: Vec<f64> = theta.iter().map(|&q| -w * w * q).collect();
        let log = AccelLog {
            name: None,
            radial: theta.iter().map(|q| G * q.cos()).collect(),
            tangential: theta.iter().map(|q| G * q.sin()).collect(),
            axle: vec![0.0; t.len()],
            t: t.clone(),
        };
        // Shaken back below zero for two samples 0.1 s after the bottom at 2 s.
        theta[210] = -0.02;
        theta[211] = -0.01;
        let (burst, cubic) = (vec![false; t.len()], vec![true; t.len()]);
        let bottoms = |min_gap: f64| -> Vec<f64> {
            strokes(
                &log,
                &theta,
                &theta,
                (&d1, &d1, &d2, 0.0, 0.0),
                (&burst, &burst, &[], &cubic),
                &[],
                (min_gap, 0.01, 0.0),
            )
            .iter()
            .map(|s| s.bdc)
            .collect()
        };
        let got = bottoms(0.3);
        assert_eq!(got.len(), 4, "{got:?}");
        for (b, want) in got.iter().zip([1.0, 2.0, 3.0, 4.0]) {
            assert!((b - want).abs() < 1e-3, "{got:?}");
        }
        // Without the rule the shaking reads as two more bottoms.
        assert_eq!(bottoms(0.0).len(), 6);
    }

    /// Where the angle's cubic could not be fitted (near the log's end, a
    /// gap's edge) θ'' is one-sided and the reading there is not trusted:
    /// the bottom's window stops short of it on both sides, as at a gap.
    #[test]
    fn samples_without_the_cubic_cut_a_bottoms_window_on_both_sides() {
        let t0 = 1.005;
        let t: Vec<f64> = (0..300).map(|k| k as f64 * 0.01).collect();
        // The reading odd about t0 up to t0 + 0.04 s, then skewed.
        let f: Vec<f64> = t
            .iter()
            .map(|&x| {
                2.0 * (x - t0)
                    + if x > t0 + 0.04 {
                        3.0
                    } else {
                        60.0 * (x - t0) * (x - t0).abs()
                    }
            })
            .collect();
        let burst = vec![false; t.len()];
        let mut cubic: Vec<bool> = t.iter().map(|&x| x < t0 + 0.04).collect();
        let got = bottom_time(&t, &f, (&burst, &cubic), (t0, 0.01), 2.0);
        assert!((got - t0).abs() < 1e-9, "{got}");
        // Trusted everywhere, the skewed samples pull the line off.
        cubic.fill(true);
        let all = bottom_time(&t, &f, (&burst, &cubic), (t0, 0.01), 2.0);
        assert!((all - t0).abs() > 1e-3, "{all}");
    }

    /// A gap between a bottom and the burst read after it leaves the
    /// strike untimed (it may have come in the gap); a gap before the
    /// bottom, or after the burst, does not.
    #[test]
    fn a_strike_after_a_gap_is_not_timed() {
        // 100 Hz, with 0.3 s lost after 1.05 s and after 3.05 s.
        let t: Vec<f64> = (0..500)
            .map(|k| k as f64 * 0.01)
            .filter(|&x| !(1.05..1.35).contains(&x) && !(3.05..3.35).contains(&x))
            .collect();
        let stroke = |bdc: f64, strike: f64| LogStroke {
            bdc,
            hand: true,
            strike: Some(strike),
            strike_hidden: false,
            strike_theta: Some(0.5),
            amplitude: 3.0,
            from_side: 1.0,
            phase: PhaseKind::Ringing,
            speed_peak: None,
            bdc_se: None,
            stand: None,
            amplitude_timed: false,
        };
        let mut strokes = [stroke(1.0, 1.4), stroke(2.0, 2.4), stroke(3.4, 3.8)];
        let mut warnings = vec![];
        hide_strikes_after_gaps(&t, 0.01, &mut strokes, &mut warnings);
        assert!(strokes[0].strike_hidden && strokes[0].strike.is_none() && strokes[0].strike_theta.is_none());
        assert!(!strokes[1].strike_hidden && strokes[1].strike == Some(2.4));
        assert!(!strokes[2].strike_hidden && strokes[2].strike == Some(3.8));
        assert_eq!(warnings.len(), 1);
        assert!(warnings[0].starts_with("1 strike(s) not timed"), "{warnings:?}");
        // Without strikes timed, odd-struckness leaves the stroke out.
        assert_eq!(strokes[0].bdc_to_strike(), None);
    }

    /// A stand past the balance, reached through the headstock's shaking
    /// (Data141: the angle, held within ±200 deg, overshoots to 198 deg and
    /// wraps; the stand at 189 deg reads −171 deg), then the fall back on
    /// the + side: the stand is read at 189 deg, where the smoothed peak
    /// read 199-200 deg.
    #[test]
    fn a_short_stand_past_the_balance_is_read_at_its_angle() {
        let t: Vec<f64> = (0..300).map(|k| k as f64 * 0.01).collect();
        let deg = |x: f64| x.to_radians();
        let theta: Vec<f64> = t
            .iter()
            .enumerate()
            .map(|(k, &x)| match x {
                // Rising, then shaken about the top (wrapped past 200 deg).
                x if x < 0.5 => deg(120.0 + 150.0 * x),
                x if x < 1.0 => deg(if k % 2 == 0 { 198.0 } else { -165.0 }),
                // On the stay, 189 deg, read on the other side; noise 0.3 deg.
                x if x < 1.8 => deg(-171.0 + if k % 3 == 0 { 0.3 } else { -0.3 }),
                // Falling back on the + side.
                x => deg(189.0 - 120.0 * (x - 1.8).powi(2)),
            })
            .collect();
        let burst: Vec<bool> = t
            .iter()
            .map(|&x| (0.5..1.0).contains(&x) && (x * 100.0) as usize % 4 == 0)
            .collect();
        let h = short_stand(&t, &theta, &burst, (0, 299), 1.0).expect("a stand");
        assert!((h.to_degrees() - 189.0).abs() < 0.5, "{}", h.to_degrees());
    }

    /// A stand on the stay 6 deg past the balance, the headstock shaking
    /// through its first 0.9 s (37 Hz, 25 m/s² dying to 1, clipped at
    /// ±2 g; the unclipped samples left in), then the bell pulled back
    /// over the balance and falling: read at 186 deg from the calibrated
    /// gravity angle, on the side it falls to.
    #[test]
    fn a_stand_shaken_by_the_headstock_is_read_from_its_still_part() {
        let deg = |x: f64| x.to_radians();
        let mut log = AccelLog::default();
        let mut burst = vec![];
        for k in 0..300 {
            let x = k as f64 * 0.01;
            // Rising onto the stay, standing, pulled back to 180, falling.
            let th = match x {
                x if x < 0.3 => deg(178.0 + 8.0 * x / 0.3),
                x if x < 2.0 => deg(186.0),
                x if x < 2.3 => deg(186.0 - 6.0 * (x - 2.0) / 0.3),
                x => deg(180.0 - 60.0 * (x - 2.3).powi(2)),
            };
            let shake = if x < 0.9 { 25.0 * (-x / 0.25).exp() } else { 0.0 };
            let v = |phase: f64| shake * (2.0 * std::f64::consts::PI * 37.0 * x + phase).sin();
            let reading = [G * th.sin() + v(0.0), G * th.cos() + v(2.0), v(4.0)];
            let clipped = reading.iter().any(|r| r.abs() >= 0.99 * 2.0 * G);
            let reading = reading.map(|r| r.clamp(-2.0 * G, 2.0 * G));
            log.t.push(x);
            log.tangential.push(reading[0]);
            log.radial.push(reading[1]);
            log.axle.push(reading[2]);
            burst.push(clipped);
        }
        let n = log.t.len();
        let h = stand_height(&log, &burst, (0, n - 1), 1.0).expect("a stand").height;
        assert!((h.to_degrees() - 186.0).abs() < 1.0, "{}", h.to_degrees());
    }
}
