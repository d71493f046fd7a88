//! The double-strike listening test of Section 4.3 (Fig 13): the 10 x 10
//! grid of amplitude ratio and delay, a fresh random order per listener,
//! averaging answers, excluding listeners who stand apart, and fitting the
//! hyperbola of (33), (A − a)(Δt − b) = c, with standard errors.

use crate::bell::ParamError;

/// Amplitude ratios of the grid: 0.1 to 1.
pub fn ratios() -> [f64; 10] {
    std::array::from_fn(|i| 0.1 * (i + 1) as f64)
}

/// Delays of the grid (ms): 10 to 100.
pub fn delays_ms() -> [f64; 10] {
    std::array::from_fn(|i| 10.0 * (i + 1) as f64)
}

/// SplitMix64: a small, well-mixed generator for reproducible orders.
#[derive(Clone, Debug)]
pub struct SplitMix64(u64);

impl SplitMix64 {
    /// A generator from a seed.
    pub fn new(seed: u64) -> Self {
        Self(seed)
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E3779B97F4A7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58476D1CE4E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D049BB133111EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    pub fn next_f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// The order in which listener `listener` hears the 100 stimuli (indices
/// `ratio_index * 10 + delay_index`): a Fisher–Yates shuffle seeded by
/// `seed` and the listener, so every listener gets a fresh order and the
/// same seed gives the same sheets.
pub fn order(seed: u64, listener: u64) -> Vec<usize> {
    let mut rng = SplitMix64::new(seed ^ listener.wrapping_mul(0xD1B54A32D192ED03));
    let mut v: Vec<usize> = (0..100).collect();
    for i in (1..v.len()).rev() {
        let j = (rng.next_u64() % (i as u64 + 1)) as usize;
        v.swap(i, j);
    }
    v
}

/// One answer: +1 "single strike", −1 "double strike".
#[derive(Clone, Debug, PartialEq)]
pub struct Answer {
    /// Who answered.
    pub listener: String,
    /// Amplitude ratio of the stimulus.
    pub ratio: f64,
    /// Delay of the stimulus (ms).
    pub delay_ms: f64,
    /// +1 or −1.
    pub answer: i8,
}

/// The hyperbola (A − a)(Δt − b) = c with standard errors.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hyperbola {
    /// a (amplitude ratio).
    pub a: f64,
    /// b (ms).
    pub b: f64,
    /// c (ms).
    pub c: f64,
    /// Width of the transition in the fitted score (ms), a nuisance parameter.
    pub width: f64,
    /// Standard errors of a, b, c.
    pub sigma: [f64; 3],
}

impl Hyperbola {
    /// Δt (ms) on the curve of index D (D = 1 is the fitted threshold) at ratio `ratio`.
    pub fn delay_at(&self, ratio: f64, d: f64) -> Option<f64> {
        (ratio > self.a).then(|| self.b + d * self.c / (ratio - self.a))
    }
}

/// The analysed test.
#[derive(Clone, Debug, PartialEq)]
pub struct Analysis {
    /// Mean score per cell, `[ratio_index][delay_index]`; NaN where nobody answered.
    pub scores: [[f64; 10]; 10],
    /// Listeners whose answers were used.
    pub used: Vec<String>,
    /// Listeners left out, with the correlation that left them out.
    pub excluded: Vec<(String, f64)>,
    /// The fit, if it converged.
    pub fit: Option<Hyperbola>,
}

/// A listener is left out when the correlation of their answers with the
/// mean of everyone else's is below this (with at least four listeners).
/// The paper left out two listeners whose pattern was "very different".
pub const EXCLUDE_BELOW: f64 = 0.5;

fn cell_of(v: f64, grid: &[f64; 10]) -> Option<usize> {
    grid.iter().position(|g| (g - v).abs() < 1e-6 * g.abs().max(1.0))
}

fn mean_grid(rows: &[&[[f64; 2]; 100]]) -> [f64; 100] {
    std::array::from_fn(|k| {
        let (s, n) = rows.iter().fold((0.0, 0.0), |(s, n), r| (s + r[k][0], n + r[k][1]));
        if n > 0.0 {
            s / n
        } else {
            f64::NAN
        }
    })
}

fn correlation(x: &[f64; 100], y: &[f64; 100]) -> f64 {
    let pairs: Vec<(f64, f64)> = x
        .iter()
        .zip(y)
        .filter(|(a, b)| a.is_finite() && b.is_finite())
        .map(|(a, b)| (*a, *b))
        .collect();
    let n = pairs.len() as f64;
    if n < 3.0 {
        return f64::NAN;
    }
    let mx = pairs.iter().map(|p| p.0).sum::<f64>() / n;
    let my = pairs.iter().map(|p| p.1).sum::<f64>() / n;
    let sxy: f64 = pairs.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let sxx: f64 = pairs.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let syy: f64 = pairs.iter().map(|p| (p.1 - my).powi(2)).sum();
    sxy / (sxx * syy).sqrt()
}

/// Average the answers, leave out listeners who stand apart, fit (33).
pub fn analyse(answers: &[Answer]) -> Result<Analysis, ParamError> {
    let (rg, dg) = (ratios(), delays_ms());
    let mut names: Vec<String> = vec![];
    let mut sums: Vec<[[f64; 2]; 100]> = vec![];
    for a in answers {
        let (Some(i), Some(j)) = (cell_of(a.ratio, &rg), cell_of(a.delay_ms, &dg)) else {
            return Err(ParamError {
                field: "amplitude_ratio/delay_ms",
                value: a.ratio,
                allowed: "a point of the grid: ratio 0.1 to 1 by 0.1, delay 10 to 100 ms by 10",
            });
        };
        if a.answer != 1 && a.answer != -1 {
            return Err(ParamError {
                field: "answer",
                value: f64::from(a.answer),
                allowed: "+1 (single strike) or -1 (double strike)",
            });
        }
        let l = match names.iter().position(|n| *n == a.listener) {
            Some(l) => l,
            None => {
                names.push(a.listener.clone());
                sums.push([[0.0; 2]; 100]);
                names.len() - 1
            }
        };
        sums[l][i * 10 + j][0] += f64::from(a.answer);
        sums[l][i * 10 + j][1] += 1.0;
    }
    if names.is_empty() {
        return Err(ParamError {
            field: "answers",
            value: 0.0,
            allowed: "at least one answer",
        });
    }
    let mut keep = vec![true; names.len()];
    let mut excluded = vec![];
    if names.len() >= 4 {
        for l in 0..names.len() {
            let others: Vec<&[[f64; 2]; 100]> = (0..names.len()).filter(|&k| k != l).map(|k| &sums[k]).collect();
            let own = mean_grid(&[&sums[l]]);
            let r = correlation(&own, &mean_grid(&others));
            // A NaN correlation (a listener with no overlap) is left out too.
            if r.is_nan() || r < EXCLUDE_BELOW {
                keep[l] = false;
                excluded.push((names[l].clone(), r));
            }
        }
    }
    let used_rows: Vec<&[[f64; 2]; 100]> = (0..names.len()).filter(|&l| keep[l]).map(|l| &sums[l]).collect();
    let m = mean_grid(&used_rows);
    let scores: [[f64; 10]; 10] = std::array::from_fn(|i| std::array::from_fn(|j| m[i * 10 + j]));
    let counts: [[f64; 10]; 10] =
        std::array::from_fn(|i| std::array::from_fn(|j| used_rows.iter().map(|r| r[i * 10 + j][1]).sum()));
    Ok(Analysis {
        fit: fit_hyperbola(&scores, &counts),
        scores,
        used: names
            .iter()
            .zip(&keep)
            .filter(|(_, k)| **k)
            .map(|(n, _)| n.clone())
            .collect(),
        excluded,
    })
}

/// The mean score of a cell under the model: answers are −1 (double) with
/// probability 1/(1 + exp(−x/w)), x = (A − a)(Δt − b) − c, so the mean is
/// −tanh(x / 2w); its zero contour is the hyperbola.
fn model(p: &[f64; 4], a: f64, dt: f64) -> f64 {
    -(((a - p[0]) * (dt - p[1]) - p[2]) / (2.0 * p[3].abs().max(1e-9))).tanh()
}

/// The cells of a score map that have answers: (A, Δt (ms), mean score)
/// and the number of answers.
struct ScoreMap {
    cells: Vec<(f64, f64, f64)>,
    ns: Vec<f64>,
}

impl ScoreMap {
    fn new(scores: &[[f64; 10]; 10], counts: &[[f64; 10]; 10]) -> Self {
        let (rg, dg) = (ratios(), delays_ms());
        let answered: Vec<(usize, usize)> = (0..10)
            .flat_map(|i| (0..10).map(move |j| (i, j)))
            .filter(|&(i, j)| scores[i][j].is_finite() && counts[i][j] > 0.0)
            .collect();
        Self {
            cells: answered.iter().map(|&(i, j)| (rg[i], dg[j], scores[i][j])).collect(),
            ns: answered.iter().map(|&(i, j)| counts[i][j]).collect(),
        }
    }

    /// Each cell's weight n/(1 − m²) at the model mean m (floored).
    fn weights(&self, p: &[f64; 4]) -> Vec<f64> {
        self.cells
            .iter()
            .zip(&self.ns)
            .map(|(&(a, dt, _), n)| n / (1.0 - model(p, a, dt).powi(2)).max(0.02))
            .collect()
    }

    /// The weighted sum of squared residuals.
    fn wsse(&self, p: &[f64; 4], w: &[f64]) -> f64 {
        self.cells
            .iter()
            .zip(w)
            .map(|(&(a, dt, s), wi)| wi * (s - model(p, a, dt)).powi(2))
            .sum()
    }

    /// The model's derivatives in the parameters at each cell (central
    /// differences).
    fn jac(&self, p: &[f64; 4]) -> Vec<[f64; 4]> {
        self.cells
            .iter()
            .map(|&(a, dt, _)| {
                std::array::from_fn(|k| {
                    let h = 1e-6 * p[k].abs().max(1.0);
                    let (mut up, mut dn) = (*p, *p);
                    up[k] += h;
                    dn[k] -= h;
                    (model(&up, a, dt) - model(&dn, a, dt)) / (2.0 * h)
                })
            })
            .collect()
    }
}

/// Where the score map's rows and columns cross zero (from above), as
/// (A, Δt (ms)).
fn zero_crossings(scores: &[[f64; 10]; 10]) -> Vec<(f64, f64)> {
    let (rg, dg) = (ratios(), delays_ms());
    let mut pts = vec![];
    for i in 0..10 {
        for j in 0..9 {
            let (s0, s1) = (scores[i][j], scores[i][j + 1]);
            if s0.is_finite() && s1.is_finite() && s0 > 0.0 && s1 <= 0.0 {
                pts.push((rg[i], dg[j] + 10.0 * s0 / (s0 - s1)));
            }
        }
    }
    for j in 0..10 {
        for i in 0..9 {
            let (s0, s1) = (scores[i][j], scores[i + 1][j]);
            if s0.is_finite() && s1.is_finite() && s0 > 0.0 && s1 <= 0.0 {
                pts.push((rg[i] + 0.1 * s0 / (s0 - s1), dg[j]));
            }
        }
    }
    pts
}

/// The fit's start: (A − a)(Δt − b) − c = 0 through the zero crossings
/// `pts`, which is linear in (b, a, ab − c); a fixed guess with fewer
/// than three or no hyperbola through them.
fn algebraic_start(pts: &[(f64, f64)]) -> [f64; 4] {
    let mut p = [0.2, 20.0, 3.0, 1.0];
    if pts.len() >= 3 {
        let mut m = [[0.0; 4]; 4];
        let mut v = [0.0; 4];
        for &(a, dt) in pts {
            let x = [a, dt, -1.0];
            for r in 0..3 {
                for c in 0..3 {
                    m[r][c] += x[r] * x[c];
                }
                v[r] += x[r] * a * dt;
            }
        }
        m[3][3] = 1.0;
        if let Some(q) = crate::linalg::solve(m, v) {
            // A Δt = b A + a Δt + (c − a b)... residual form: AΔt − bA − aΔt + (ab − c).
            let (b, a, k) = (q[0], q[1], q[2]);
            let c = a * b - k;
            if a.is_finite() && b.is_finite() && c.is_finite() && c > 0.0 {
                p = [a, b, c, 1.0];
            }
        }
    }
    p
}

/// Levenberg–Marquardt from `p` (at most 500 iterations), reweighting at
/// each accepted step.
fn levenberg_marquardt(map: &ScoreMap, mut p: [f64; 4]) -> [f64; 4] {
    let mut lambda = 1e-3;
    let mut w = map.weights(&p);
    let mut cur = map.wsse(&p, &w);
    for _ in 0..500 {
        let j = map.jac(&p);
        let mut jtj = [[0.0; 4]; 4];
        let mut jtr = [0.0; 4];
        for ((row, &(a, dt, s)), wi) in j.iter().zip(&map.cells).zip(&w) {
            let r = s - model(&p, a, dt);
            for x in 0..4 {
                jtr[x] += wi * row[x] * r;
                for y in 0..4 {
                    jtj[x][y] += wi * row[x] * row[y];
                }
            }
        }
        let mut m = jtj;
        for d in 0..4 {
            m[d][d] += lambda * jtj[d][d].max(1e-12);
        }
        let Some(step) = crate::linalg::solve(m, jtr) else {
            break;
        };
        let trial: [f64; 4] = std::array::from_fn(|k| p[k] + step[k]);
        let next = map.wsse(&trial, &w);
        if next < cur {
            let done = (cur - next) < 1e-12 * cur.max(1e-300);
            p = trial;
            // Reweight at the new model (iteratively reweighted least squares).
            w = map.weights(&p);
            cur = map.wsse(&p, &w);
            lambda = (lambda / 3.0).max(1e-12);
            if done {
                break;
            }
        } else {
            lambda *= 4.0;
            if lambda > 1e12 {
                break;
            }
        }
    }
    p
}

/// Standard errors of (a, b, c) at `p` from the weighted normal matrix,
/// scaled up by χ²/dof when that exceeds one.
fn standard_errors(map: &ScoreMap, p: &[f64; 4]) -> [f64; 3] {
    let j = map.jac(p);
    let w = map.weights(p);
    let mut jtj = [[0.0; 4]; 4];
    for (row, wi) in j.iter().zip(&w) {
        for x in 0..4 {
            for y in 0..4 {
                jtj[x][y] += wi * row[x] * row[y];
            }
        }
    }
    let dof = (map.cells.len() as f64 - 4.0).max(1.0);
    let var = (map.wsse(p, &w) / dof).max(1.0);
    std::array::from_fn(|k| {
        let mut e = [0.0; 4];
        e[k] = 1.0;
        crate::linalg::solve(jtj, e).map_or(f64::NAN, |col| (var * col[k]).max(0.0).sqrt())
    })
}

/// Fit (A − a)(Δt − b) = c (with a transition width) to the score map by
/// Levenberg–Marquardt (at most 500 iterations), started from the algebraic
/// least-squares fit of the map's zero crossings. A cell's mean of n answers
/// of ±1 has variance (1 − m²)/n, so cells are weighted by n/(1 − m²) at the
/// current model mean m (floored at 1 − m² = 0.02); standard errors from the
/// weighted normal matrix, scaled up by χ²/dof when that exceeds one.
pub fn fit_hyperbola(scores: &[[f64; 10]; 10], counts: &[[f64; 10]; 10]) -> Option<Hyperbola> {
    let map = ScoreMap::new(scores, counts);
    if map.cells.len() < 8 {
        return None;
    }
    let p = levenberg_marquardt(&map, algebraic_start(&zero_crossings(scores)));
    let sigma = standard_errors(&map, &p);
    let ok = p.iter().all(|v| v.is_finite()) && sigma.iter().all(|s| s.is_finite());
    ok.then_some(Hyperbola {
        a: p[0],
        b: p[1],
        c: p[2],
        width: p[3].abs(),
        sigma,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn simulate(truth: (f64, f64, f64, f64), listeners: usize, seed: u64) -> Vec<Answer> {
        let (a, b, c, w) = truth;
        let mut rng = SplitMix64::new(seed);
        let mut out = vec![];
        for l in 0..listeners {
            for &r in &ratios() {
                for &d in &delays_ms() {
                    let x = (r - a) * (d - b) - c;
                    let p_double = 1.0 / (1.0 + (-x / w).exp());
                    let answer = if rng.next_f64() < p_double { -1 } else { 1 };
                    out.push(Answer {
                        listener: format!("L{l}"),
                        ratio: r,
                        delay_ms: d,
                        answer,
                    });
                }
            }
        }
        out
    }

    #[test]
    fn known_hyperbola_comes_back_within_its_uncertainty() {
        for (truth, seed) in [((0.2, 22.0, 2.25, 1.0), 1u64), ((0.3, 15.0, 4.0, 1.5), 2)] {
            let mut answers = simulate(truth, 30, seed);
            // Two listeners who hear everything the other way round.
            for mut a in simulate(truth, 2, seed + 100) {
                a.listener = format!("odd {}", a.listener);
                a.answer = -a.answer;
                answers.push(a);
            }
            let an = analyse(&answers).unwrap();
            assert_eq!(an.excluded.len(), 2, "{:?}", an.excluded);
            assert!(an.excluded.iter().all(|(n, _)| n.starts_with("odd")));
            let f = an.fit.unwrap();
            for (k, (est, want)) in [(f.a, truth.0), (f.b, truth.1), (f.c, truth.2)].iter().enumerate() {
                let s = f.sigma[k];
                assert!(s > 0.0 && s < 0.5 * want.abs().max(0.1), "sigma {s}");
                assert!((est - want).abs() <= 2.5 * s, "param {k}: {est} vs {want} (sigma {s})");
            }
        }
    }

    #[test]
    fn orders_are_fresh_per_listener_and_reproducible() {
        let a = order(7, 0);
        let b = order(7, 1);
        assert_ne!(a, b);
        assert_eq!(a, order(7, 0));
        let mut s = a.clone();
        s.sort();
        assert_eq!(s, (0..100).collect::<Vec<_>>());
    }

    #[test]
    fn off_grid_answers_are_refused() {
        let bad = vec![Answer {
            listener: "x".into(),
            ratio: 0.15,
            delay_ms: 10.0,
            answer: 1,
        }];
        assert!(analyse(&bad).is_err());
        let bad = vec![Answer {
            listener: "x".into(),
            ratio: 0.1,
            delay_ms: 10.0,
            answer: 0,
        }];
        assert!(analyse(&bad).is_err());
    }
}
