//! The angle read from the readings (docs/model.md §13 step 3): the first
//! pass from a free pendulum's start, the joint cubic fits, the sensor's
//! place fitted where not known.

use super::falls::{free_fall_angle, Falls};
use super::fits::{quadratic_fits, unwrap_fill};
use super::types::AccelLog;
use crate::median;
use clapper_core::bell::G;
use clapper_core::linalg::solve;
use clapper_core::sensor::{specific_force, SensorPlace};

/// The angle, method step 2: θ unwrapped (measured where good, fitted
/// across bursts), θ smoothed (the fits' values), θ', h, and whether h was
/// fitted.
pub(super) struct Angle {
    pub(super) theta: Vec<f64>,
    pub(super) smooth: Vec<f64>,
    pub(super) rate: Vec<f64>,
    /// θ' from the joint fits (rad/s): not smoothed over ±0.3 s, which
    /// reads a swing's fastest (at the bottom) slow.
    pub(super) joint_rate: Vec<f64>,
    /// θ'' from the joint fits (rad/s²).
    pub(super) acc: Vec<f64>,
    /// Whether the joint fit's cubic gave the sample's θ' and θ'' (not
    /// the fallback's, one-sided at a gap or the log's ends).
    pub(super) cubic: Vec<bool>,
    pub(super) h: f64,
    /// The sensor's distance across the axis (m), fitted.
    pub(super) d: f64,
    pub(super) fitted: bool,
    /// The median departure of the corrected force from g while the bell
    /// moves, over g: small when the angle is read right.
    pub(super) misfit: f64,
    /// Its 95th percentile.
    pub(super) tail: f64,
}

/// The angle (method step 2) from the samples not `bad`, those whose
/// radial axis alone is clipped (`rclip`) read from the tangential axis.
pub(super) fn angle(
    log: &AccelLog,
    (bad, rclip): (&[bool], &[bool]),
    given: Option<f64>,
    falls: Option<&Falls>,
    interval: f64,
) -> Angle {
    let n = log.t.len();
    // Where only one axis is read, the first pass (atan2 of both) bridges
    // as across a burst, the joint fits use the tangential axis, and the
    // place and misfit are judged without them.
    let both: Vec<bool> = (0..n).map(|k| bad[k] || rclip[k]).collect();
    // The place read from falls is kept (h given wins); else fitted.
    let known = match falls {
        Some(f) => Known {
            along: Some(given.unwrap_or(f.place().0)),
            across: Some(f.place().1),
        },
        None => Known {
            along: given,
            across: None,
        },
    };
    // From several starts (below), the one whose corrected force is
    // nearest g; the first (no correction) wins ties, so a log read well
    // without them reads the same. With falls read, their κ.
    let from_falls = falls.map(|f| [given.map_or(f.kappa, |h| h / f.length)]);
    let starts: &[f64] = match &from_falls {
        Some(k) => k,
        None => &STARTS,
    };
    let plain = starts
        .iter()
        .map(|&kappa| first_pass(log, &both, known, interval, kappa))
        .reduce(|best, a| if a.misfit < best.misfit - 1e-3 { a } else { best })
        .expect("STARTS is not empty");
    let read = |best: FirstPass| read_from(log, (bad, rclip, &both), best, (known, given), interval);
    match falls {
        // Far from the pivot, also from the tangential axis (see
        // FAR_KAPPA), and the reading whose corrected force is nearer g
        // at its worst (the 95th percentile: a few swings read wrong leave
        // the median as it was) kept: on a GSM tenor with its sensor 0.5 m up (κ = 0.4) the
        // first pass read every bottom within 0.4 ms and the tangential
        // one some 86 ms off; on the tester's far logs the other way about.
        Some(f) if f.kappa.abs() > FAR_KAPPA => {
            let place = (known.along.unwrap_or(0.0), known.across.unwrap_or(0.0));
            let far = FirstPass {
                theta: tangential_seed(log, (bad, &both), place, place.0 / f.length, interval),
                place,
                misfit: 0.0,
                window: (5.0 * interval).max(0.3),
            };
            let (a, b) = (read(plain), read(far));
            if b.tail < a.tail {
                b
            } else {
                a
            }
        }
        _ => read(plain),
    }
}

/// The angle from its first pass `best` (method step 2's second pass): the
/// joint fits, the place refitted where not `known`, and the misfit.
fn read_from(
    log: &AccelLog,
    (bad, rclip, both): (&[bool], &[bool], &[bool]),
    best: FirstPass,
    (known, given): (Known, Option<f64>),
    interval: f64,
) -> Angle {
    let n = log.t.len();
    let (mut theta, mut place) = (best.theta, best.place);
    // Then θ, θ', θ'' fitted to both readings at once over ±0.15 s (at
    // least 4 samples), and the sensor's place refitted from them; twice.
    let jw = (4.0 * interval).max(0.15);
    let mut derivatives = None;
    for _ in 0..2 {
        let (_, q1, q2) = quadratic_fits(&log.t, &theta, bad, best.window);
        let j = joint_fits(log, (bad, rclip), &theta, place, jw, (&q1, &q2));
        place = fit_sensor(log, both, &j.d1, &j.d2, known);
        theta = unwrap_fill(&log.t, &j.theta, bad);
        derivatives = Some((j.d1, j.d2, j.cubic));
    }
    let (d1, d2, cubic) = derivatives.expect("two passes");
    let misfit = misfit(log, both, place, &d1, &d2);
    let tail = {
        let mut m = departures(log, both, place, &d1, &d2);
        m.sort_by(f64::total_cmp);
        m.get(m.len() * 95 / 100).copied().unwrap_or(f64::INFINITY)
    };
    let (smooth, rate, _) = quadratic_fits(&log.t, &theta, bad, best.window);
    // Across a burst the fit bridges better than a straight line, unless
    // the burst is so long that the fit has little to stand on (then the
    // two disagree, and the line is kept).
    let theta: Vec<f64> = (0..n)
        .map(|k| {
            if bad[k] && (smooth[k] - theta[k]).abs() < 0.3 {
                smooth[k]
            } else {
                theta[k]
            }
        })
        .collect();
    Angle {
        theta,
        smooth,
        rate,
        joint_rate: d1,
        acc: d2,
        cubic,
        h: place.0,
        d: place.1,
        fitted: given.is_none(),
        misfit,
        tail,
    }
}

/// Gravity's part of the reading at sample `k`, g (sin θ, cos θ) (m/s²;
/// tangential, radial): the reading less the swing's own acceleration at
/// the sensor's place (h along, d across; m) with θ' = `rate` (rad/s) and
/// θ'' = `acc` (rad/s²). The forward formula is clapper_core::sensor's
/// (docs/model.md §13).
pub(super) fn gravity_part(log: &AccelLog, k: usize, (h, d): (f64, f64), rate: f64, acc: f64) -> [f64; 2] {
    let swing = specific_force(SensorPlace { along: h, across: d }, 0.0, rate, acc);
    [log.tangential[k] - swing[0], log.radial[k] - (swing[1] - G)]
}

/// The median departure of the corrected force from g while the bell
/// moves (|θ'| > 0.5 rad/s), over g.
pub(super) fn misfit(log: &AccelLog, bad: &[bool], place: (f64, f64), d1: &[f64], d2: &[f64]) -> f64 {
    median(&departures(log, bad, place, d1, d2))
}

/// Each moving good sample's departure of the corrected force from g,
/// over g.
fn departures(log: &AccelLog, bad: &[bool], place: (f64, f64), d1: &[f64], d2: &[f64]) -> Vec<f64> {
    (0..log.t.len())
        .filter(|&k| !bad[k] && d1[k].abs() > 0.5)
        .map(|k| {
            let [a, b] = gravity_part(log, k, place, d1[k], d2[k]);
            (a.hypot(b) - G).abs() / G
        })
        .collect()
}

/// Starting guesses of κ = h/L (sensor height over the bell's equivalent
/// pendulum length) for the angle's first pass. With the sensor well above
/// the pivot (κ ≳ 0.25) the uncorrected angle is wrong in kind, not just
/// in size: at the bottom of a full swing the centripetal term outweighs
/// gravity, the radial reading goes negative, atan2 says "at the top", and
/// the derivatives that would correct it are taken from that wrong angle,
/// so the correction never gets started. A free pendulum has
/// g sin θ = f_t / (1 + κ) and, swinging from the balance,
/// g cos θ = (f_r + 2 g κ) / (1 − 2 κ); that first guess passes through
/// the bottom where it should (for smaller swings it reads them smaller,
/// but on the right side of the horizontal), and the correction refines it.
pub(super) const STARTS: [f64; 5] = [0.0, 0.1, 0.2, 0.3, 0.4];

/// Above this κ = h/L (the sensor's height over the bell's equivalent
/// pendulum length) the angle's first pass is read from the tangential
/// axis ([`tangential_seed`]): the radial reading's centripetal part,
/// h θ'², is then as large as gravity's (at the bottom of a full swing
/// 4κ g against g), and at κ = 1/2 a free fall's radial reading is the
/// same at every angle, so the first pass's (f_r + 2gκ)/(1 − 2κ) is noise
/// over nothing, and θ'² from the smoothed angle (±0.3 s) reads the fast
/// bottom slow, which turned the corrected angle over there. Below it
/// (|1 − 2κ| over 0.1) the first pass reads well enough: Data141's
/// sensor, at κ = 0.32, read from the tangential axis, found two swings
/// that were not there, and a GSM tenor's at 0.5 m (κ = 0.4) three
/// bottoms 48-86 ms off that the first pass read within 0.4 ms.
pub(super) const FAR_KAPPA: f64 = 0.45;

/// The first pass for a sensor far from the pivot (κ = `kappa` over
/// [`FAR_KAPPA`], at `place` = (h, d), m), as a free pendulum's:
/// θ'' = −(g/L) sin θ makes f_t = g (1 + κ) sin θ − d θ'² and
/// f_r = g cos θ − h θ'² − δ g sin θ (δ = d/L); the combination
/// f_t − (d/h) f_r = g ((1 + κ + δ²/κ) sin θ − (δ/κ) cos θ) holds no θ'²,
/// and gives θ up to its mirror about the horizontal. Which side: the
/// radial reading with the centripetal part put back,
/// g cos θ = f_r + h θ'² + δ g sin θ, θ'² from the first solution's rate
/// (the mirror's is the same). cos θ changes sign only near 90 deg, so
/// the side is voted on over each run of samples clear of it and of `bad`
/// (bursts): one sample's radial reading is noisy where the bell is fast,
/// a run's vote is not. Samples in `both` (bursts, and a clipped radial
/// axis) do not vote.
fn tangential_seed(
    log: &AccelLog,
    (bad, both): (&[bool], &[bool]),
    (h, d): (f64, f64),
    kappa: f64,
    interval: f64,
) -> Vec<f64> {
    let n = log.t.len();
    let (delta, ratio) = (kappa * d / h, d / h);
    let (a, b) = (G * (1.0 + kappa + delta * ratio), G * ratio);
    let (r, phi) = (a.hypot(b), b.atan2(a));
    let s: Vec<f64> = (0..n)
        .map(|k| ((log.tangential[k] - ratio * log.radial[k]) / r).clamp(-1.0, 1.0))
        .collect();
    let first: Vec<f64> = s.iter().map(|v| phi + v.asin()).collect();
    let (_, rate, _) = quadratic_fits(&log.t, &first, bad, (3.0 * interval).max(0.04));
    let cos_est: Vec<f64> = (0..n)
        .map(|k| log.radial[k] + h * rate[k] * rate[k] + delta * G * first[k].sin())
        .collect();
    let near_90 = |k: usize| s[k].abs() >= 0.95;
    let mut side = vec![1.0f64; n];
    let mut lo = 0;
    while lo < n {
        let mut hi = lo + 1;
        while hi < n && bad[hi] == bad[lo] && near_90(hi) == near_90(lo) {
            hi += 1;
        }
        let vote: f64 = (lo..hi).filter(|&k| !both[k]).map(|k| cos_est[k].signum()).sum();
        let sign = if vote < 0.0 { -1.0 } else { 1.0 };
        side[lo..hi].iter_mut().for_each(|v| *v = sign);
        lo = hi;
    }
    let plain: Vec<f64> = (0..n)
        .map(|k| {
            if side[k] > 0.0 {
                first[k]
            } else {
                2.0 * phi + std::f64::consts::PI - first[k]
            }
        })
        .collect();
    unwrap_fill(&log.t, &plain, bad)
}

/// The angle's first pass from start κ: θ unwrapped, the sensor's place,
/// the misfit, and the smoothing window used (s).
pub(super) struct FirstPass {
    pub(super) theta: Vec<f64>,
    pub(super) place: (f64, f64),
    pub(super) misfit: f64,
    pub(super) window: f64,
}

pub(super) fn first_pass(log: &AccelLog, bad: &[bool], known: Known, interval: f64, kappa: f64) -> FirstPass {
    let n = log.t.len();
    let (ft, fr) = (&log.tangential, &log.radial);
    let raw = |place: (f64, f64), d1: &[f64], d2: &[f64], k: usize| {
        let [s, c] = gravity_part(log, k, place, d1[k], d2[k]);
        s.atan2(c)
    };
    let first: Vec<f64> = (0..n).map(|k| free_fall_angle(ft[k], fr[k], kappa, -1.0, G)).collect();
    let mut theta = unwrap_fill(&log.t, &first, bad);
    // ±0.3 s: θ'' from a narrower fit is so noisy that the correction
    // (h θ'', fed back) amplifies the noise (at 100 Hz and ±0.12 s by 4.5 a
    // pass); over ±0.3 s the gain is 0.15, and a swing (seconds long) is
    // still a parabola there. (The joint fits that follow have no such
    // feedback.)
    let window = (5.0 * interval).max(0.3);
    let mut place = (known.along.unwrap_or(0.0), known.across.unwrap_or(0.0));
    for _ in 0..3 {
        let (_, d1, d2) = quadratic_fits(&log.t, &theta, bad, window);
        place = fit_sensor(log, bad, &d1, &d2, known);
        let corrected: Vec<f64> = (0..n).map(|k| raw(place, &d1, &d2, k)).collect();
        theta = unwrap_fill(&log.t, &corrected, bad);
    }
    let (_, d1, d2) = quadratic_fits(&log.t, &theta, bad, window);
    FirstPass {
        misfit: misfit(log, bad, place, &d1, &d2),
        theta,
        place,
        window,
    }
}

/// θ, θ' and θ'' at every sample from a local cubic θ(t) over ±`w` s
/// fitted to both readings at once (Gauss-Newton from `theta`), the
/// readings being g (sin θ, cos θ) less the swing's accelerations at the
/// sensor's `place` (h along, d across). Unlike differentiating a
/// smoothed θ, nothing is fed back, so the window can be short enough to
/// follow a light bell's fast swing through the bottom. Samples with too
/// few good neighbours keep `theta` and the derivatives `fallback`. The
/// samples `rclip` (radial axis clipped) are fitted on the tangential
/// reading alone.
pub(super) fn joint_fits(
    log: &AccelLog,
    (bad, rclip): (&[bool], &[bool]),
    theta: &[f64],
    (h, d): (f64, f64),
    w: f64,
    fallback: (&[f64], &[f64]),
) -> JointFits {
    let n = log.t.len();
    let t = &log.t;
    let (mut th, mut d1, mut d2) = (theta.to_vec(), fallback.0.to_vec(), fallback.1.to_vec());
    let mut cubic = vec![false; n];
    let (mut lo, mut hi) = (0, 0);
    // The last cubic fitted: its sample, coefficients, and the stride its
    // window was taken at.
    let mut last: Option<(usize, [f64; 4], usize)> = None;
    for k in 0..n {
        while t[k] - t[lo] > w {
            lo += 1;
        }
        while hi + 1 < n && t[hi + 1] - t[k] <= w {
            hi += 1;
        }
        // At most some 40 samples a window: more adds time, not accuracy.
        let stride = (hi + 1 - lo).div_ceil(40).max(1);
        // Where a window holds many times that (a log of 1 kHz or more), the
        // cubic fitted at one sample serves the stride's samples after it:
        // fitting at every sample made a 10 kHz log's reading 70 times the
        // work. (Slower logs fit at every sample: at 400 Hz a cubic taken 3
        // samples from its centre moved a small swing's bottom 1.2 samples.)
        let (a, x) = match last {
            Some((kc, a, sc)) if stride >= SHARED_STRIDE && sc == stride && k - kc < stride => (a, t[k] - t[kc]),
            _ => {
                // Every stride-th sample from k either way (k itself among
                // them), stepped to rather than filtered from the window.
                let first = k - (k - lo) / stride * stride;
                let good: Vec<usize> = (first..=hi).step_by(stride).filter(|&j| !bad[j]).collect();
                // A cubic with samples on one side only (at a gap's edge, or
                // the log's) extrapolates: there `theta` is kept (at a gap in
                // a swing's top it read 5 deg past the balance).
                let before = good.iter().filter(|&&j| j < k).count();
                if good.len() < 8 || before < 3 || good.len() - before < 4 {
                    continue;
                }
                let Some(a) = cubic_at(log, (theta, rclip), &good, k, (h, d)) else {
                    continue;
                };
                last = Some((k, a, stride));
                (a, 0.0)
            }
        };
        let value = a[0] + x * (a[1] + x * (a[2] + x * a[3]));
        if a.iter().all(|v| v.is_finite()) && (value - theta[k]).abs() < 1.0 {
            th[k] = value;
            d1[k] = a[1] + x * (2.0 * a[2] + 3.0 * x * a[3]);
            d2[k] = 2.0 * a[2] + 6.0 * x * a[3];
            cubic[k] = true;
        }
    }
    JointFits {
        theta: th,
        d1,
        d2,
        cubic,
    }
}

/// A window sampled at this stride or more (over 280 samples: a log of
/// 1 kHz or more) shares each cubic among the stride's samples.
const SHARED_STRIDE: usize = 8;

/// The joint fits' cubic at sample `k` (coefficients of θ in powers of
/// t − t_k; rad, rad/s, ...) over the samples `good`: the cubic through
/// `theta`, then Gauss-Newton on both readings (the sensor at `(h, d)`, m).
fn cubic_at(
    log: &AccelLog,
    (theta, rclip): (&[f64], &[bool]),
    good: &[usize],
    k: usize,
    (h, d): (f64, f64),
) -> Option<[f64; 4]> {
    let (t, ft, fr) = (&log.t, &log.tangential, &log.radial);
    // Start: the cubic through `theta` (linear least squares).
    let mut ata = [[0.0f64; 4]; 4];
    let mut atb = [0.0f64; 4];
    for &j in good {
        let x = t[j] - t[k];
        let p = [1.0, x, x * x, x * x * x];
        for i in 0..4 {
            atb[i] += p[i] * theta[j];
            for l in 0..4 {
                ata[i][l] += p[i] * p[l];
            }
        }
    }
    let mut a = solve(ata, atb)?;
    for _ in 0..4 {
        let mut jtj = [[0.0f64; 4]; 4];
        let mut jtr = [0.0f64; 4];
        for &j in good {
            let x = t[j] - t[k];
            let q = a[0] + x * (a[1] + x * (a[2] + x * a[3]));
            let q1 = a[1] + x * (2.0 * a[2] + 3.0 * x * a[3]);
            let q2 = 2.0 * a[2] + 6.0 * x * a[3];
            let (sn, cs) = q.sin_cos();
            let model = specific_force(SensorPlace { along: h, across: d }, q, q1, q2);
            // A clipped radial reading says only that it is past the range.
            let radial = if rclip[j] { 0.0 } else { 1.0 };
            let (rt, rr) = (model[0] - ft[j], radial * (model[1] - fr[j]));
            let p = [1.0, x, x * x, x * x * x];
            let p1 = [0.0, 1.0, 2.0 * x, 3.0 * x * x];
            let p2 = [0.0, 0.0, 2.0, 6.0 * x];
            let mut jt = [0.0; 4];
            let mut jr = [0.0; 4];
            for i in 0..4 {
                jt[i] = G * cs * p[i] - h * p2[i] - 2.0 * d * q1 * p1[i];
                jr[i] = radial * (-G * sn * p[i] - 2.0 * h * q1 * p1[i] + d * p2[i]);
            }
            for i in 0..4 {
                jtr[i] -= jt[i] * rt + jr[i] * rr;
                for l in 0..4 {
                    jtj[i][l] += jt[i] * jt[l] + jr[i] * jr[l];
                }
            }
        }
        let Some(step) = solve(jtj, jtr) else { break };
        for i in 0..4 {
            a[i] += step[i];
        }
        if step[0].abs() < 1e-7 {
            break;
        }
    }
    Some(a)
}

/// The sensor's place where known (m): given, or read from the falls.
#[derive(Clone, Copy)]
pub(super) struct Known {
    pub(super) along: Option<f64>,
    pub(super) across: Option<f64>,
}

/// What [`joint_fits`] gives: θ, θ', θ'' at every sample (rad, rad/s,
/// rad/s²).
pub(super) struct JointFits {
    pub(super) theta: Vec<f64>,
    pub(super) d1: Vec<f64>,
    pub(super) d2: Vec<f64>,
    /// Whether the cubic was fitted at the sample (else the fallback).
    pub(super) cubic: Vec<bool>,
}

/// The sensor's place (h along the axis above the pivot, d across it; m)
/// that makes the corrected force g throughout: least squares over the
/// moving, good samples by Gauss-Newton from the middle, each within
/// ±1 m; h (and d) held where known.
pub(super) fn fit_sensor(log: &AccelLog, bad: &[bool], d1: &[f64], d2: &[f64], known: Known) -> (f64, f64) {
    if let Known {
        along: Some(h),
        across: Some(d),
    } = known
    {
        return (h, d);
    }
    let given = known.along;
    let moving: Vec<usize> = (0..log.t.len()).filter(|&k| !bad[k] && d1[k].abs() > 0.5).collect();
    let (mut h, mut d) = (given.unwrap_or(0.0), 0.0);
    // A handful of steps: the residual is nearly linear in (h, d).
    for _ in 0..20 {
        // Normal equations J'J δ = −J'r, r = |F| − g.
        let (mut a, mut b) = ([[0.0f64; 2]; 2], [0.0f64; 2]);
        for &k in &moving {
            let w2 = d1[k] * d1[k];
            let [x, y] = gravity_part(log, k, (h, d), d1[k], d2[k]);
            let m = x.hypot(y);
            if m < 1e-9 {
                continue;
            }
            let r = m - G;
            let j = [(x * d2[k] + y * w2) / m, (x * w2 - y * d2[k]) / m];
            for i in 0..2 {
                b[i] -= j[i] * r;
                for l in 0..2 {
                    a[i][l] += j[i] * j[l];
                }
            }
        }
        let step = if given.is_some() {
            if a[1][1] > 0.0 {
                (0.0, b[1] / a[1][1])
            } else {
                (0.0, 0.0)
            }
        } else {
            let det = a[0][0] * a[1][1] - a[0][1] * a[1][0];
            if det.abs() < 1e-12 * (a[0][0] * a[1][1]).abs().max(1e-300) {
                break;
            }
            (
                (b[0] * a[1][1] - b[1] * a[0][1]) / det,
                (a[0][0] * b[1] - a[1][0] * b[0]) / det,
            )
        };
        h = (h + step.0).clamp(-1.0, 1.0);
        d = (d + step.1).clamp(-1.0, 1.0);
        if step.0.abs().max(step.1.abs()) < 1e-6 {
            break;
        }
    }
    (h, d)
}
