//! The sensor's place read from the bell's falls from the balance
//! (docs/model.md §13 step 3), and L from a free swing's timing.

use super::fits::wrap;
use super::types::AccelLog;
use crate::median;
use clapper_core::bell::G;
use clapper_core::linalg::solve;

/// The sensor's place read from the bell's falls from rest at the balance
/// (method step 2, first): from a set bell's release to its first strike
/// the bell swings free, θ'' = −(g/L) sin θ and θ'² = (2g/L)(cos θ − c₀),
/// so the readings over g are
/// f_t = (1 + κ) sin θ − 2δ (cos θ − c₀) and
/// f_r = cos θ − 2κ (cos θ − c₀) − δ sin θ, κ = h/L and δ = d/L, functions
/// of θ alone: κ, δ, c₀ and each sample's θ are fitted to both readings
/// (c₀ free: the ringer's pull off the balance adds a little energy), then
/// L from the time the fall took, ∫ dθ / √((2g/L)(cos θ − c₀)). Unlike the
/// fit over the whole log (which takes θ'' from the angle it corrects, and
/// reads h short where the strikes shake the headstock), nothing here is
/// differentiated. The median over the falls; `None` without one.
pub(super) struct Falls {
    /// κ = h/L (h above the pivot, along the axis).
    pub(super) kappa: f64,
    /// δ = d/L (d across the axis).
    pub(super) delta: f64,
    /// The bell's equivalent pendulum length L (m).
    pub(super) length: f64,
    /// How many falls were read.
    pub(super) count: usize,
}

/// One fall's fit: (κ, δ, c₀), θ at each sample, and the rms misfit (in g).
pub(super) fn fit_fall(ft: &[f64], fr: &[f64], rest: f64, kappa0: f64) -> Option<([f64; 3], Vec<f64>, f64)> {
    let n = ft.len();
    let mut p = [kappa0, 0.0, rest.cos()];
    // The first guess: the free pendulum's readings solved for θ, with δ = 0.
    let mut th: Vec<f64> = (0..n)
        .map(|k| free_fall_angle(ft[k], fr[k], kappa0, p[2], 1.0))
        .collect();
    let mut last = rest;
    for v in &mut th {
        *v = last + wrap(*v - last);
        last = *v;
    }
    let resid = |p: &[f64; 3], th: &[f64]| -> f64 {
        (0..n)
            .map(|k| {
                let (s, c) = th[k].sin_cos();
                let rt = (1.0 + p[0]) * s - 2.0 * p[1] * (c - p[2]) - ft[k];
                let rr = c - 2.0 * p[0] * (c - p[2]) - p[1] * s - fr[k];
                rt * rt + rr * rr
            })
            .sum()
    };
    let mut cost = resid(&p, &th);
    // Gauss-Newton, each θ_k eliminated (it touches only its own sample's
    // two residuals): a 3 × 3 system a step.
    for _ in 0..40 {
        let mut s = [[0.0f64; 3]; 3];
        let mut rhs = [0.0f64; 3];
        let mut local = Vec::with_capacity(n);
        for k in 0..n {
            let (sn, cs) = th[k].sin_cos();
            let ct = cs - p[2];
            let r = [
                (1.0 + p[0]) * sn - 2.0 * p[1] * ct - ft[k],
                cs - 2.0 * p[0] * ct - p[1] * sn - fr[k],
            ];
            let jt = [(1.0 + p[0]) * cs + 2.0 * p[1] * sn, -sn + 2.0 * p[0] * sn - p[1] * cs];
            let jp = [[sn, -2.0 * ct, 2.0 * p[1]], [-2.0 * ct, -sn, 2.0 * p[0]]];
            let a = jt[0] * jt[0] + jt[1] * jt[1];
            if a < 1e-12 {
                return None;
            }
            let b: [f64; 3] = std::array::from_fn(|i| jt[0] * jp[0][i] + jt[1] * jp[1][i]);
            let g = jt[0] * r[0] + jt[1] * r[1];
            for i in 0..3 {
                rhs[i] -= jp[0][i] * r[0] + jp[1][i] * r[1] - b[i] * g / a;
                for l in 0..3 {
                    s[i][l] += jp[0][i] * jp[0][l] + jp[1][i] * jp[1][l] - b[i] * b[l] / a;
                }
            }
            local.push((a, b, g));
        }
        let dp = solve(s, rhs)?;
        let dth: Vec<f64> = local
            .iter()
            .map(|(a, b, g)| -(g + b[0] * dp[0] + b[1] * dp[1] + b[2] * dp[2]) / a)
            .collect();
        // Halve the step until the misfit falls (a few times at most).
        let mut scale = 1.0;
        let mut accepted = false;
        for _ in 0..6 {
            let q: [f64; 3] = std::array::from_fn(|i| p[i] + scale * dp[i]);
            let t2: Vec<f64> = th.iter().zip(&dth).map(|(t, d)| t + scale * d).collect();
            let c2 = resid(&q, &t2);
            if c2 <= cost {
                p = q;
                th = t2;
                cost = c2;
                accepted = true;
                break;
            }
            scale *= 0.5;
        }
        if !accepted || dp.iter().all(|v| v.abs() < 1e-8) {
            break;
        }
    }
    (p.iter().all(|v| v.is_finite())).then(|| (p, th, (cost / (2 * n) as f64).sqrt()))
}

/// Falls longer than this (s) are cut: from the balance to the first strike
/// takes a second or two.
pub(super) const FALL_MAX_S: f64 = 3.0;

/// A fall's misfit above this (m/s²) is not a free fall (a ringer checking
/// it, the clapper moving in the bell): left out.
pub(super) const FALL_MAX_MISFIT: f64 = 0.5;

pub(super) fn place_from_falls(
    log: &AccelLog,
    bad: &[bool],
    rests: &[(f64, f64, f64)],
    interval: f64,
) -> Option<Falls> {
    let (t, n) = (&log.t, log.t.len());
    // (κ, δ, L) of each fall read.
    let mut found: Vec<[f64; 3]> = vec![];
    // (The rests' angles may be unwrapped by turns.)
    for (_, r1, rest) in rests
        .iter()
        .map(|r| (r.0, r.1, wrap(r.2)))
        .filter(|r| r.2.abs() > 150f64.to_radians())
    {
        let j = t.partition_point(|&x| x <= r1);
        let mut e = j;
        // To the first strike, or a gap.
        while e < n && !bad[e] && t[e] - t[j] < FALL_MAX_S && (e == j || t[e] - t[e - 1] < 3.0 * interval) {
            e += 1;
        }
        if e - j < 20 {
            continue;
        }
        let ft: Vec<f64> = log.tangential[j..e].iter().map(|v| v / G).collect();
        let fr: Vec<f64> = log.radial[j..e].iter().map(|v| v / G).collect();
        let Some((p, th, rms)) = [0.0, 0.15, 0.3, 0.45]
            .iter()
            .filter_map(|&k0| fit_fall(&ft, &fr, rest, k0))
            .min_by(|a, b| a.2.total_cmp(&b.2))
        else {
            continue;
        };
        // A fall passes the bottom; and the energy is that of a bell near
        // the balance.
        let passes = th.iter().any(|v| wrap(*v).abs() < 0.2);
        if rms * G > FALL_MAX_MISFIT || !passes || !(-1.3..-0.8).contains(&p[2]) {
            continue;
        }
        let Some(length) = length_of_fall(&t[j..e], &th, p[2]) else {
            continue;
        };
        if (0.05..10.0).contains(&length) {
            found.push([p[0], p[1], length]);
        }
    }
    if found.is_empty() {
        return None;
    }
    let pick = |i: usize| median(&found.iter().map(|x| x[i]).collect::<Vec<_>>());
    let (kappa, delta, length) = (pick(0), pick(1), pick(2));
    Some(Falls {
        kappa,
        delta,
        length,
        count: found.len(),
    })
}

/// The equivalent pendulum length L (m) from a free swing's timing: `th`
/// (rad) at times `t` (s), swinging with cos θ − c₀ ∝ θ'².
pub(super) fn length_of_fall(t: &[f64], th: &[f64], c0: f64) -> Option<f64> {
    // √(L/2g) from the time taken: t against ∫ dθ / √(cos θ − c₀), a
    // straight line's slope, where the bell moves well (cos θ − c₀ >
    // 0.2: away from the balance, where the fall's start is slow and
    // its timing uncertain; for a small swing, the half of it nearest
    // the bottom). Signed steps, so the angle's noise cancels rather than
    // adds.
    let fast_above = 0.2f64.min(0.5 * (1.0 - c0));
    let fast: Vec<usize> = (0..th.len()).filter(|&k| th[k].cos() - c0 > fast_above).collect();
    let (Some(&k0), Some(&k1)) = (fast.first(), fast.last()) else {
        return None;
    };
    if k1 < k0 + 10 {
        return None;
    }
    let sense = (0..th.len() - 1).map(|k| wrap(th[k + 1] - th[k])).sum::<f64>().signum();
    let mut integral = vec![0.0; k1 - k0 + 1];
    for k in k0..k1 {
        let cb = ((0.5 * (th[k] + th[k + 1])).cos() - c0).max(0.05f64.min(0.25 * (1.0 - c0)));
        integral[k + 1 - k0] = integral[k - k0] + sense * wrap(th[k + 1] - th[k]) / cb.sqrt();
    }
    let m = integral.len() as f64;
    let (mi, mt) = (
        integral.iter().sum::<f64>() / m,
        (k0..=k1).map(|k| t[k]).sum::<f64>() / m,
    );
    let (mut num, mut den) = (0.0, 0.0);
    for (i, k) in (k0..=k1).enumerate() {
        num += (integral[i] - mi) * (t[k] - mt);
        den += (integral[i] - mi).powi(2);
    }
    if den <= 0.0 || num <= 0.0 {
        return None;
    }
    // The slope is √(L/2g).
    Some(2.0 * G * (num / den).powi(2))
}

impl Falls {
    /// The sensor's place (h along, d across; m).
    pub(super) fn place(&self) -> (f64, f64) {
        (self.kappa * self.length, self.delta * self.length)
    }
}

/// The angle of a free pendulum that fell from rest at cos θ = `c0` (a
/// sensor on its axis at κ = h/L) from its readings `ft`, `fr` in units of
/// `g` (m/s², or 1 for readings over g): ft = g (1 + κ) sin θ and
/// fr = g (cos θ − 2κ (cos θ − c₀)) solved for θ.
pub(super) fn free_fall_angle(ft: f64, fr: f64, kappa: f64, c0: f64, g: f64) -> f64 {
    (ft / (1.0 + kappa)).atan2((fr - 2.0 * g * kappa * c0) / (1.0 - 2.0 * kappa))
}

#[cfg(test)]
mod tests {
    use super::*;
    use clapper_core::sensor::{specific_force, SensorPlace};

    /// A free pendulum (L = 0.66 m) released at 179 deg, integrated here by
    /// RK4 and read through clapper_core::sensor's forward formula at a
    /// place off the axis: the falls give the place and L back, though
    /// their fit never differentiates and the formula is not theirs.
    #[test]
    fn a_free_fall_from_the_balance_gives_the_sensor_place_and_the_length() {
        let (length, place) = (
            0.66,
            SensorPlace {
                along: 0.2,
                across: 0.07,
            },
        );
        let acc = |th: f64| -G / length * th.sin();
        let (mut th, mut w, mut now) = (179f64.to_radians(), 0.0, 0.0);
        let (dt, every) = (1e-4, 50); // 200 Hz samples
        let mut log = AccelLog::default();
        for k in 0..(4.2 / dt) as usize {
            if k % every == 0 {
                // At rest for the first 2 s, then released.
                let (a, b, c) = if now < 2.0 {
                    (179f64.to_radians(), 0.0, 0.0)
                } else {
                    (th, w, acc(th))
                };
                let f = specific_force(place, a, b, c);
                log.t.push(now);
                log.tangential.push(f[0]);
                log.radial.push(f[1]);
                log.axle.push(0.0);
            }
            if now >= 2.0 {
                let k1 = (w, acc(th));
                let k2 = (w + 0.5 * dt * k1.1, acc(th + 0.5 * dt * k1.0));
                let k3 = (w + 0.5 * dt * k2.1, acc(th + 0.5 * dt * k2.0));
                let k4 = (w + dt * k3.1, acc(th + dt * k3.0));
                th += dt / 6.0 * (k1.0 + 2.0 * k2.0 + 2.0 * k3.0 + k4.0);
                w += dt / 6.0 * (k1.1 + 2.0 * k2.1 + 2.0 * k3.1 + k4.1);
            }
            now += dt;
        }
        // A strike ends the fall 2 s after the release.
        let bad: Vec<bool> = log.t.iter().map(|&x| x > 4.0).collect();
        let falls = place_from_falls(&log, &bad, &[(0.0, 2.0, 179f64.to_radians())], 1.0 / 200.0).expect("a fall read");
        assert_eq!(falls.count, 1);
        let (along, across) = falls.place();
        assert!((along - 0.2).abs() < 1e-3, "along {along}");
        assert!((across - 0.07).abs() < 1e-3, "across {across}");
        assert!((falls.length - length).abs() < 0.01 * length, "L {}", falls.length);
        assert!((falls.kappa - 0.2 / length).abs() < 1e-3, "κ {}", falls.kappa);
        // No rest at the balance, no fall.
        assert!(place_from_falls(&log, &bad, &[(0.0, 2.0, 0.1)], 1.0 / 200.0).is_none());
    }
}
