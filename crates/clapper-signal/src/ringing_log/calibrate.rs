//! The sensor calibrated from the log itself (docs/model.md §13.2): each
//! in-plane axis's gain and zero offset, the sensor's tilt on the
//! headstock and its place (along and across the bell's axis, over the
//! bell's equivalent pendulum length), fitted jointly on the log's quiet
//! stretches, where the bell's motion is known in kind:
//!
//! - **rests** (down, or set at the balance): the reading is gravity
//!   alone, g (sin θ, cos θ), θ fitted when set, and θ = 0 when down (a
//!   bell at rest hangs plumb);
//! - **free swings** (half swings clear of any strike, and of the
//!   headstock's ringing after one, for a second): a pendulum with energy
//!   of its own, θ'' = −(g/L) sin θ and θ'² = (2g/L)(cos θ − c₀), so each
//!   reading is a function of θ alone: f_t = (1 + κ) sin θ − 2δ (cos θ −
//!   c₀), f_r = cos θ − 2κ (cos θ − c₀) − δ sin θ (κ = h/L, δ = d/L);
//! - **falls from the balance** (from a set bell's release to its first
//!   strike): the same, c₀ near −1.
//!
//! The sensor reads R(α) f, each axis times its gain plus its offset:
//! t = g G_t (cos α f_t + sin α f_r) + o_t, r = g G_r (cos α f_r − sin α
//! f_t) + o_r. Every sample's angle is fitted too (eliminated from the
//! normal equations: each touches only its own two readings). The tilt α
//! is where the free swings centre: a bell swings about its bottom. A
//! rest's reading alone cannot tell a tilt from a zero offset (an ADXL345
//! may read up to ~1 m/s² at zero); the free swings can. Half swings count
//! as free only when the swing neither grows nor dies from one to the
//! next by more than 3 % (a ringer's pull does one or the other). Stretches that
//! do not fit (a ringer's pull, the clapper moving) are dropped and the fit
//! repeated.

use super::falls::{free_fall_angle, length_of_fall};
use super::fits::wrap;
use super::types::AccelLog;
use crate::median;
use clapper_core::bell::G;

/// What the calibration found, with standard errors (the fit's, the
/// residuals' correlation from sample to sample allowed for).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Calibration {
    /// Each axis's gain (tangential, radial): the reading of g over g.
    pub gain: [f64; 2],
    /// Each axis's zero offset (tangential, radial; m/s²).
    pub offset: [f64; 2],
    /// The sensor's tilt on the headstock (rad): the bell's bottom reads at
    /// this angle on the sensor's axes.
    pub tilt: f64,
    /// κ = h/L: the sensor's distance above the pivot over the bell's
    /// equivalent pendulum length.
    pub kappa: f64,
    /// δ = d/L: across the bell's axis.
    pub delta: f64,
    /// The equivalent pendulum length L (m), from the free swings' timing.
    pub length: Option<f64>,
    /// Standard errors of gain, offset (m/s²), tilt (rad), κ, δ.
    pub se: CalibrationSe,
    /// The covariance of (tilt, δ, o_t) (rad, 1, m/s²), for what depends
    /// on them (a bottom's time).
    pub cov_bottom: [[f64; 3]; 3],
    /// Rests and free stretches (swings and falls) fitted.
    pub rests: usize,
    /// Free stretches fitted (and how many were dropped as not free).
    pub free: usize,
    /// Free stretches left out (they did not fit a free pendulum).
    pub dropped: usize,
    /// The rms misfit of the fitted samples (m/s²).
    pub rms: f64,
    /// The largest angle the free stretches reached (rad): small swings
    /// alone tell the gains and place poorly.
    pub reach: f64,
}

/// Standard errors of [`Calibration`]'s parameters.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct CalibrationSe {
    /// Gains (tangential, radial).
    pub gain: [f64; 2],
    /// Offsets (m/s²).
    pub offset: [f64; 2],
    /// Tilt (rad).
    pub tilt: f64,
    /// κ.
    pub kappa: f64,
    /// δ.
    pub delta: f64,
}

impl Calibration {
    /// The readings in the bell's frame, the sensor's gains, offsets and
    /// tilt taken out: (tangential, radial), m/s².
    pub fn apply(&self, t: f64, r: f64) -> (f64, f64) {
        let tc = (t - self.offset[0]) / self.gain[0];
        let rc = (r - self.offset[1]) / self.gain[1];
        let (s, c) = self.tilt.sin_cos();
        (c * tc - s * rc, s * tc + c * rc)
    }
}

/// A quiet stretch: samples `a..b`; `free` a swinging one (else a rest).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Stretch {
    pub a: usize,
    pub b: usize,
    pub free: bool,
}

/// Global parameters: α, κ, δ, G_t, G_r, o_t, o_r.
const NG: usize = 7;

/// The model's readings (m/s²) at angle `th` with parameters `p` (the
/// globals) and the stretch's energy `c0` (`None`: at rest).
fn model(p: &[f64], c0: Option<f64>, th: f64) -> [f64; 2] {
    let (s, c) = th.sin_cos();
    let (ft, fr) = match c0 {
        Some(c0) => (
            (1.0 + p[1]) * s - 2.0 * p[2] * (c - c0),
            c - 2.0 * p[1] * (c - c0) - p[2] * s,
        ),
        None => (s, c),
    };
    let (sa, ca) = p[0].sin_cos();
    [
        G * p[3] * (ca * ft + sa * fr) + p[5],
        G * p[4] * (ca * fr - sa * ft) + p[6],
    ]
}

/// One sample to fit: its readings, weight, stretch (index into the
/// free stretches' c₀, or none for a rest) and angle.
#[derive(Clone, Copy)]
struct Obs {
    t: f64,
    r: f64,
    w: f64,
    free: Option<usize>,
    /// A rest down: the bell hangs plumb, θ = 0 (held, not fitted).
    plumb: bool,
}

/// Invert a square matrix (Gauss-Jordan with partial pivoting).
fn invert(mut a: Vec<Vec<f64>>) -> Option<Vec<Vec<f64>>> {
    let n = a.len();
    let mut inv: Vec<Vec<f64>> = (0..n)
        .map(|i| (0..n).map(|j| f64::from(u8::from(i == j))).collect())
        .collect();
    for col in 0..n {
        let piv = (col..n).max_by(|&x, &y| a[x][col].abs().total_cmp(&a[y][col].abs()))?;
        if a[piv][col].abs() < 1e-300 {
            return None;
        }
        a.swap(col, piv);
        inv.swap(col, piv);
        let d = a[col][col];
        for j in 0..n {
            a[col][j] /= d;
            inv[col][j] /= d;
        }
        for i in 0..n {
            if i != col && a[i][col] != 0.0 {
                let f = a[i][col];
                for j in 0..n {
                    a[i][j] -= f * a[col][j];
                    inv[i][j] -= f * inv[col][j];
                }
            }
        }
    }
    Some(inv)
}

/// The fit's state: globals and each free stretch's c₀, and every
/// observation's angle.
struct Fit {
    p: Vec<f64>,
    th: Vec<f64>,
    cost: f64,
    /// The reduced normal matrix's inverse at the end (the globals' and
    /// c₀'s covariance over σ²).
    inv: Vec<Vec<f64>>,
}

fn cost_of(obs: &[Obs], p: &[f64], th: &[f64]) -> f64 {
    obs.iter()
        .zip(th)
        .map(|(o, &q)| {
            let m = model(&p[..NG], o.free.map(|j| p[NG + j]), q);
            o.w * ((m[0] - o.t).powi(2) + (m[1] - o.r).powi(2))
        })
        .sum()
}

/// Each observation's (a, b, g, indices) in the reduced normal equations:
/// its angle's own curvature a, its coupling b to the parameters it
/// touches (indices), and its gradient g (a = ∞ for a rest held plumb).
type Local = (f64, Vec<f64>, f64, Vec<usize>);

/// The normal equations reduced to the parameters (every sample's angle
/// eliminated: each touches only its own two readings), their right-hand
/// side, and each observation's part ([`Local`]) to recover its angle's step.
#[allow(clippy::type_complexity)]
fn normal_equations(obs: &[Obs], p: &[f64], th: &[f64]) -> (Vec<Vec<f64>>, Vec<f64>, Vec<Local>) {
    let np = p.len();
    let mut s = vec![vec![0.0; np]; np];
    let mut rhs = vec![0.0; np];
    let mut local = Vec::with_capacity(obs.len());
    for (o, &q) in obs.iter().zip(th) {
        let idx: Vec<usize> = (0..NG).chain(o.free.map(|j| NG + j)).collect();
        let c0 = o.free.map(|j| p[NG + j]);
        let m = model(&p[..NG], c0, q);
        let r = [m[0] - o.t, m[1] - o.r];
        let eps = 1e-6;
        let mp = model(&p[..NG], c0, q + eps);
        let jt = [(mp[0] - m[0]) / eps, (mp[1] - m[1]) / eps];
        let jp: Vec<[f64; 2]> = idx
            .iter()
            .map(|&i| {
                let mut gl: [f64; NG] = std::array::from_fn(|x| p[x]);
                let mut c = c0;
                if i < NG {
                    gl[i] += eps;
                } else {
                    c = c.map(|v| v + eps);
                }
                let mm = model(&gl, c, q);
                [(mm[0] - m[0]) / eps, (mm[1] - m[1]) / eps]
            })
            .collect();
        let a = o.w * (jt[0] * jt[0] + jt[1] * jt[1]);
        if o.plumb {
            // θ held at 0: the globals alone.
            for (x, &i) in idx.iter().enumerate() {
                rhs[i] -= o.w * (jp[x][0] * r[0] + jp[x][1] * r[1]);
                for (y, &l) in idx.iter().enumerate() {
                    s[i][l] += o.w * (jp[x][0] * jp[y][0] + jp[x][1] * jp[y][1]);
                }
            }
            local.push((f64::INFINITY, vec![0.0; idx.len()], 0.0, idx));
            continue;
        }
        if a < 1e-12 {
            local.push((1.0, vec![0.0; idx.len()], 0.0, idx));
            continue;
        }
        let b: Vec<f64> = jp.iter().map(|j| o.w * (jt[0] * j[0] + jt[1] * j[1])).collect();
        let g = o.w * (jt[0] * r[0] + jt[1] * r[1]);
        for (x, &i) in idx.iter().enumerate() {
            rhs[i] -= o.w * (jp[x][0] * r[0] + jp[x][1] * r[1]) - b[x] * g / a;
            for (y, &l) in idx.iter().enumerate() {
                s[i][l] += o.w * (jp[x][0] * jp[y][0] + jp[x][1] * jp[y][1]) - b[x] * b[y] / a;
            }
        }
        local.push((a, b, g, idx));
    }
    (s, rhs, local)
}

/// Gauss-Newton (halving steps that do not lower the cost) from `p`, `th`,
/// for at most `iters` steps.
fn solve_fit(obs: &[Obs], mut p: Vec<f64>, mut th: Vec<f64>, iters: usize) -> Option<Fit> {
    let np = p.len();
    let mut cost = cost_of(obs, &p, &th);
    let mut inv = vec![];
    for iter in 0..iters {
        let (s, rhs, local) = normal_equations(obs, &p, &th);
        inv = invert(s.clone())?;
        let mut accepted = false;
        let mut small = true;
        // Gauss-Newton's step, halved until it lowers the cost; where it
        // will not (the normal equations near singular: on a log shaped like
        // Data141 a first step moved the gains by 7 and an offset by 70
        // m/s², and no halving helped), damped (Levenberg-Marquardt) more
        // and more.
        for damp in DAMPING {
            let m = if damp == 0.0 {
                inv.clone()
            } else {
                let mut d = s.clone();
                for (i, row) in d.iter_mut().enumerate() {
                    row[i] *= 1.0 + damp;
                }
                let Some(m) = invert(d) else { continue };
                m
            };
            let dp: Vec<f64> = (0..np).map(|i| (0..np).map(|l| m[i][l] * rhs[l]).sum()).collect();
            let dth: Vec<f64> = local
                .iter()
                .map(|(a, b, g, idx)| -(g + b.iter().zip(idx).map(|(bx, &i)| bx * dp[i]).sum::<f64>()) / a)
                .collect();
            small = dp.iter().take(NG).all(|v| v.abs() < 1e-9);
            let mut scale = 1.0;
            for _ in 0..8 {
                let q: Vec<f64> = p.iter().zip(&dp).map(|(x, d)| x + scale * d).collect();
                let t2: Vec<f64> = th.iter().zip(&dth).map(|(x, d)| x + scale * d).collect();
                let c2 = cost_of(obs, &q, &t2);
                if c2 <= cost {
                    p = q;
                    th = t2;
                    cost = c2;
                    accepted = true;
                    break;
                }
                scale *= 0.5;
            }
            if accepted || small {
                break;
            }
        }
        if (!accepted || small) && iter > 0 {
            break;
        }
    }
    p.iter().all(|v| v.is_finite()).then_some(Fit { p, th, cost, inv })
}

/// Gauss-Newton's steps at most for one fit.
const MAX_STEPS: usize = 40;

/// The steps each start is taken before the best [`CARRIED`] go on.
const EARLY_STEPS: usize = 8;

/// The starts taken on to the end.
const CARRIED: usize = 3;

/// The starting κ = h/L for a sensor above the pivot (on the headstock).
const STARTS: [f64; 7] = [0.0, 0.15, 0.3, 0.45, 0.6, 0.8, 1.0];

/// The starting κ for a sensor below the pivot ([`below`]). Started from
/// κ ≥ 0 only, the calibration of a sensor 0.3-0.7 m below the pivot
/// converged on a place 0.16-0.41 m above it on five of fifteen synthetic
/// logs (tests/ringing_log_far.rs); from these, within 1.5 cm. (From
/// both, an independent tester's log with its sensor 0.54 m above the
/// pivot, κ near 1/2, where the fit is poorly determined, read it 0.13 m
/// below.)
const STARTS_BELOW: [f64; 5] = [0.0, -0.15, -0.3, -0.45, -0.6];

/// Whether the sensor is below the pivot: a free stretch's radial reading
/// passes 1.25 g. Below, it reads g cos θ + |h| θ'², g (1 + 4|κ|) at the
/// bottom of a fall from the balance; above, g (1 − 4κ) there, and at
/// most g (and an offset, a gain) anywhere.
fn below(obs: &[Obs]) -> bool {
    obs.iter().filter(|o| o.free.is_some()).any(|o| o.r > 1.25 * G)
}

/// The damping tried in turn (each diagonal term of the normal equations
/// times 1 + this) when a step will not lower the cost.
const DAMPING: [f64; 7] = [0.0, 1e-3, 1e-2, 0.1, 1.0, 10.0, 100.0];

/// Calibrate from `stretches` of `log` (readings as oriented). `None`
/// without a free stretch that fits.
pub(crate) fn calibrate(log: &AccelLog, stretches: &[Stretch]) -> Option<Calibration> {
    let mut keep: Vec<Stretch> = stretches.to_vec();
    let mut dropped = 0;
    let mut best_kappa: Option<f64> = None;
    for round in 0..3 {
        if !keep.iter().any(|s| s.free) {
            return None;
        }
        let (obs, owner, c0s) = observations(log, &keep);
        // From a few starting κ, the best (after the first round, from
        // where it ended).
        let starts: Vec<f64> = match best_kappa {
            Some(k) => vec![k],
            None if below(&obs) => STARTS_BELOW.to_vec(),
            None => STARTS.to_vec(),
        };
        // Each start a few steps, the best few of them on to the end (as
        // many steps in all as one fit's): twice the starts at the cost of
        // one and a half as many.
        let mut early: Vec<Fit> = starts
            .iter()
            .filter_map(|&kappa0| fit_from(&obs, &c0s, kappa0, EARLY_STEPS))
            .collect();
        early.sort_by(|a, b| a.cost.total_cmp(&b.cost));
        let fit = early
            .into_iter()
            .take(CARRIED)
            .filter_map(|f| solve_fit(&obs, f.p, f.th, MAX_STEPS - EARLY_STEPS))
            .min_by(|a, b| a.cost.total_cmp(&b.cost))?;
        best_kappa = Some(fit.p[1]);
        // Each free stretch's rms misfit: those well above the rest's are
        // not free (a ringer's pull, the clapper moving).
        let per = free_misfits(&keep, &obs, &owner, &fit);
        let bad = not_free(&per);
        if bad.is_empty() || round == 2 {
            return Some(finish(log, &keep, &obs, &owner, &fit, dropped));
        }
        dropped += bad.len();
        keep = keep
            .iter()
            .enumerate()
            .filter(|(i, _)| !bad.contains(i))
            .map(|(_, s)| *s)
            .collect();
    }
    None
}

/// The observations of the stretches `keep`: every free sample; each rest
/// averaged into one, weighed as up to 50 samples. With each its stretch
/// (index into `keep`), and each free stretch's first c₀ (from its widest
/// angle read plainly).
fn observations(log: &AccelLog, keep: &[Stretch]) -> (Vec<Obs>, Vec<usize>, Vec<f64>) {
    let mut obs: Vec<Obs> = vec![];
    let mut owner: Vec<usize> = vec![];
    let mut c0s: Vec<f64> = vec![];
    for (i, s) in keep.iter().enumerate() {
        if s.free {
            let j = c0s.len();
            let widest = (s.a..s.b)
                .map(|k| log.tangential[k].atan2(log.radial[k]).abs())
                .fold(0.0, f64::max);
            c0s.push(widest.cos());
            for k in s.a..s.b {
                obs.push(Obs {
                    t: log.tangential[k],
                    r: log.radial[k],
                    w: 1.0,
                    free: Some(j),
                    plumb: false,
                });
                owner.push(i);
            }
        } else {
            let n = (s.b - s.a) as f64;
            let (t, r) = (
                log.tangential[s.a..s.b].iter().sum::<f64>() / n,
                log.radial[s.a..s.b].iter().sum::<f64>() / n,
            );
            obs.push(Obs {
                t,
                r,
                w: n.min(50.0),
                free: None,
                plumb: r > 0.0 && t.abs() < 0.5 * r,
            });
            owner.push(i);
        }
    }
    (obs, owner, c0s)
}

/// The fit from a start at κ = `kappa0` (no tilt, δ, or offsets, unit
/// gains; each free stretch's c₀ from `c0s`), every sample's angle from
/// the free pendulum's readings.
fn fit_from(obs: &[Obs], c0s: &[f64], kappa0: f64, iters: usize) -> Option<Fit> {
    let mut p = vec![0.0, kappa0, 0.0, 1.0, 1.0, 0.0, 0.0];
    p.extend(c0s);
    let mut last = 0.0;
    let th: Vec<f64> = obs
        .iter()
        .map(|o| {
            let v = match o.free {
                Some(j) => free_fall_angle(o.t / G, o.r / G, kappa0, c0s[j], 1.0),
                None if o.plumb => 0.0,
                None => o.t.atan2(o.r),
            };
            last += wrap(v - last);
            if o.free.is_some() {
                last
            } else {
                v
            }
        })
        .collect();
    solve_fit(obs, p, th, iters)
}

/// The free stretches (of [`free_misfits`]) that are not free: their rms
/// misfit over 2.5 times the median of their kind's (at least 0.08
/// m/s²), a kind being those that swing past the horizontal (falls from
/// the balance, c₀ < 0) and those that do not. Judged against all, the
/// falls of a synthetic log with its sensor 0.74 m above the pivot, each
/// 0.18 m/s² off (a far sensor reads whatever in them is not a free
/// pendulum's, h θ'', large), were all dropped beside twenty free swings
/// of 11 deg 0.03 off, which alone left the tangential gain at 35; judged
/// among falls, those 0.18 off are kept and two lowering swings 1.3 off
/// dropped, and the gains read within 0.001.
fn not_free(per: &[(usize, f64, usize, f64)]) -> Vec<usize> {
    let kind = |x: &(usize, f64, usize, f64)| x.3 < 0.0;
    let typical = |k: bool| median(&per.iter().filter(|x| kind(x) == k).map(|x| x.1).collect::<Vec<_>>());
    let limit = [false, true].map(|k| (2.5 * typical(k)).max(0.08));
    per.iter()
        .filter(|x| x.1 > limit[usize::from(kind(x))])
        .map(|x| x.0)
        .collect()
}

/// Each free stretch of `keep`: its index, rms misfit (m/s²), samples and
/// fitted c₀.
fn free_misfits(keep: &[Stretch], obs: &[Obs], owner: &[usize], fit: &Fit) -> Vec<(usize, f64, usize, f64)> {
    let mut per: Vec<(usize, f64, usize, f64)> = vec![];
    for (i, s) in keep.iter().enumerate() {
        if !s.free {
            continue;
        }
        let c0 = fit.p[NG + per.len()];
        let (mut sum, mut n) = (0.0, 0);
        for (o, (&q, &w)) in obs.iter().zip(fit.th.iter().zip(owner)) {
            if w == i {
                let m = model(&fit.p[..NG], o.free.map(|j| fit.p[NG + j]), q);
                sum += (m[0] - o.t).powi(2) + (m[1] - o.r).powi(2);
                n += 1;
            }
        }
        per.push((i, (sum / (2 * n.max(1)) as f64).sqrt(), n, c0));
    }
    per
}

/// The calibration from a converged fit: standard errors (σ² from the
/// residuals, times (1 + ρ)/(1 − ρ) for their correlation ρ from sample
/// to sample) and L from the free stretches' timing.
fn finish(log: &AccelLog, keep: &[Stretch], obs: &[Obs], owner: &[usize], fit: &Fit, dropped: usize) -> Calibration {
    let resid: Vec<[f64; 2]> = obs
        .iter()
        .zip(&fit.th)
        .map(|(o, &q)| {
            let m = model(&fit.p[..NG], o.free.map(|j| fit.p[NG + j]), q);
            [m[0] - o.t, m[1] - o.r]
        })
        .collect();
    let n = obs.len() as f64;
    let dof = (2.0 * n - n - fit.p.len() as f64).max(1.0);
    let sigma2 = fit.cost / dof;
    // Lag-one correlation of the residuals within free stretches.
    let (mut num, mut den) = (0.0, 0.0);
    for k in 1..obs.len() {
        if obs[k].free.is_some() && owner[k] == owner[k - 1] {
            for (x, y) in resid[k].iter().zip(&resid[k - 1]) {
                num += x * y;
                den += x * x;
            }
        }
    }
    let rho = if den > 0.0 { (num / den).clamp(0.0, 0.95) } else { 0.0 };
    let scale = sigma2 * (1.0 + rho) / (1.0 - rho);
    let var = |i: usize| (scale * fit.inv[i][i]).max(0.0);
    let cov = |i: usize, l: usize| scale * fit.inv[i][l];
    let p = &fit.p;
    let ix = [0, 2, 5];
    let cov_bottom: [[f64; 3]; 3] = std::array::from_fn(|a| std::array::from_fn(|b| cov(ix[a], ix[b])));
    // L from each free stretch's timing; the median.
    let mut lengths = vec![];
    let mut reach = 0.0f64;
    for (i, s) in keep.iter().enumerate() {
        if !s.free {
            continue;
        }
        let ks: Vec<usize> = (0..obs.len()).filter(|&k| owner[k] == i).collect();
        let Some(j) = obs[ks[0]].free else { continue };
        let th: Vec<f64> = ks.iter().map(|&k| fit.th[k]).collect();
        reach = reach.max(th.iter().map(|v| wrap(*v).abs()).fold(0.0, f64::max));
        if let Some(l) = length_of_fall(&log.t[s.a..s.b], &th, p[NG + j]) {
            if (0.05..10.0).contains(&l) {
                lengths.push(l);
            }
        }
    }
    let rms = (fit.cost / (2.0 * obs.iter().map(|o| o.w).sum::<f64>())).sqrt();
    Calibration {
        gain: [p[3], p[4]],
        offset: [p[5], p[6]],
        tilt: wrap(p[0]),
        kappa: p[1],
        delta: p[2],
        length: (!lengths.is_empty()).then(|| median(&lengths)),
        se: CalibrationSe {
            gain: [var(3).sqrt(), var(4).sqrt()],
            offset: [var(5).sqrt(), var(6).sqrt()],
            tilt: var(0).sqrt(),
            kappa: var(1).sqrt(),
            delta: var(2).sqrt(),
        },
        cov_bottom,
        rests: keep.iter().filter(|s| !s.free).count(),
        free: keep.iter().filter(|s| s.free).count(),
        dropped,
        rms,
        reach,
    }
}

/// Falls from short stands (a turn of the plain angle `level` past the
/// balance, outside the `rests`: on the stay, too short to be a rest):
/// from [`FALL_LEFT`] below the top to the first burst (at most 3 s),
/// each not already among `out` (a fall from a rest's end), added to it.
fn falls_from_stands(
    log: &AccelLog,
    bad: &[bool],
    rests: &[(f64, f64, f64)],
    (level, turns): (&[f64], &[usize]),
    out: &mut Vec<Stretch>,
) {
    let t = &log.t;
    let n = t.len();
    let clean = |a: usize, b: usize| !bad[a..b].iter().any(|&x| x);
    for (i, &w) in turns.iter().enumerate() {
        let top = level[w];
        if wrap(top).abs() <= 150f64.to_radians() || rests.iter().any(|r| t[w] >= r.0 - 0.1 && t[w] <= r.1 + 1.0) {
            continue;
        }
        let until = turns.get(i + 1).copied().unwrap_or(n);
        let Some(a) = (w..until).find(|&k| (level[k] - top).abs() >= FALL_LEFT) else {
            continue;
        };
        // On the stay: past the balance on the side it falls to (a turn
        // short of it is a swing's top, rung on without a stand).
        if wrap(level[a]).abs() + (top - level[a]).abs() <= std::f64::consts::PI {
            continue;
        }
        let mut e = a;
        while e < n && !bad[e] && t[e] - t[a] < 3.0 {
            e += 1;
        }
        let since = t.partition_point(|&x| x < t[a] - 0.3);
        // (Not a fall from a rest's end, already taken.)
        let taken = out.iter().any(|s| s.free && a < s.b && e > s.a);
        if e > a + 20 && clean(since, a) && !taken {
            out.push(Stretch { a, b: e, free: true });
        }
    }
}

/// A fall from the balance (a set's or a stand's) is fitted from this far
/// (rad) below its top: 30 deg, clear of the ringer's pull off the stay
/// and of the stand's shaking. The pull is no free pendulum's: on Data141,
/// whose two falls from a set are both handstrokes, fitting them from the
/// top put the tilt at −1.93 deg and every backstroke's bottom 4.3-6.2 ms
/// after its moment of greatest speed; from 20, 30 or 45 deg below, the
/// tilt reads −1.37 to −1.43 deg and every bottom is within 3.9 ms.
const FALL_LEFT: f64 = 30.0 * std::f64::consts::PI / 180.0;

/// The log's quiet stretches: its rests (`rests`: start, end, s), the
/// falls from rests near the balance and from turns past it outside a
/// rest (stands on the stay too short to be rests), each from [`FALL_LEFT`] below the
/// top to the first burst (at most 3 s),
/// and the half swings between `turns` (sample indices of turning points
/// of the plain angle `level`, rad) that take 0.3 to 3 s with no burst in
/// them nor in the second before, and swing steadily.
pub(crate) fn quiet_stretches(
    log: &AccelLog,
    bad: &[bool],
    rests: &[(f64, f64, f64)],
    (level, turns): (&[f64], &[usize]),
) -> Vec<Stretch> {
    let t = &log.t;
    let n = t.len();
    let mut out = vec![];
    let clean = |a: usize, b: usize| !bad[a..b].iter().any(|&x| x);
    for r in rests {
        let (a, b) = (t.partition_point(|&x| x < r.0), t.partition_point(|&x| x <= r.1));
        let good: Vec<usize> = (a..b).filter(|&k| !bad[k]).collect();
        if good.len() >= 20 && clean(a, b) {
            out.push(Stretch { a, b, free: false });
        }
        if wrap(r.2).abs() > 150f64.to_radians() {
            // From where the bell has left the top by [`FALL_LEFT`].
            let Some(a) = (b..n)
                .take_while(|&k| !bad[k])
                .find(|&k| (level[k] - r.2).abs() >= FALL_LEFT)
            else {
                continue;
            };
            let mut e = a;
            while e < n && !bad[e] && t[e] - t[a] < 3.0 {
                e += 1;
            }
            if e > a + 20 {
                out.push(Stretch { a, b: e, free: true });
            }
        }
    }
    falls_from_stands(log, bad, rests, (level, turns), &mut out);
    for (i, w) in turns.windows(2).enumerate() {
        let (a, b) = (w[0], w[1] + 1);
        let took = t[w[1]] - t[w[0]];
        // Free: the span as the one before's and the one after's, within 3 %.
        let span = |x: usize, y: usize| (level[x] - level[y]).abs();
        let steady = i >= 1
            && i + 2 < turns.len()
            && [span(turns[i - 1], turns[i]), span(turns[i + 1], turns[i + 2])]
                .iter()
                .all(|&o| (o - span(w[0], w[1])).abs() <= 0.03 * span(w[0], w[1]));
        if !steady {
            continue;
        }
        let since = t.partition_point(|&x| x < t[a] - 1.0);
        if (0.3..3.0).contains(&took) && b - a >= 20 && clean(since, b.min(n)) {
            // Not within a rest.
            if !rests.iter().any(|r| t[a] >= r.0 - 0.1 && t[w[1]] <= r.1 + 0.1) {
                out.push(Stretch {
                    a,
                    b: b.min(n),
                    free: true,
                });
            }
        }
    }
    out.sort_by_key(|s| s.a);
    out
}
