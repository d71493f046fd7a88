//! Small complex least squares: the normal equations and their solution.

use super::band::C;

/// Σ conj(a)·b.
pub(super) fn dot(a: &[C], b: &[C]) -> C {
    a.iter().zip(b).fold((0.0, 0.0), |s, (x, y)| {
        (s.0 + x.0 * y.0 + x.1 * y.1, s.1 + x.0 * y.1 - x.1 * y.0)
    })
}

pub(super) fn conj(a: C) -> C {
    (a.0, -a.1)
}

/// Least squares of data `z` on a constant and two complex shapes with
/// complex coefficients, from the normal equations: the Gram matrix `g`
/// (g[i][j] = Σ conj(b_i) b_j), `r` (r[i] = Σ conj(b_i) z) and Σ|z|².
/// Returns (squared error, coefficients). On arrays, allocating nothing:
/// the double-strike fit solves one per band, delay and strike.
pub(super) fn fit_gram3(g: &[[C; 3]; 3], r: &[C; 3], zz: f64) -> (f64, [C; 3]) {
    const K: usize = 3;
    // As a real system of twice the size: [Re G, −Im G; Im G, Re G].
    let mut m = [[0.0; 2 * K]; 2 * K];
    let mut rhs = [0.0; 2 * K];
    for i in 0..K {
        for j in 0..K {
            m[i][j] = g[i][j].0;
            m[i][K + j] = -g[i][j].1;
            m[K + i][j] = g[i][j].1;
            m[K + i][K + j] = g[i][j].0;
        }
        rhs[i] = r[i].0;
        rhs[K + i] = r[i].1;
    }
    let sol = solve_real(m, rhs);
    let c: [C; K] = std::array::from_fn(|i| (sol[i], sol[K + i]));
    // |z − Bc|² = Σ|z|² − Re Σ conj(c_i) r_i at the solution.
    let explained: f64 = c.iter().zip(r).map(|(c, r)| c.0 * r.0 + c.1 * r.1).sum();
    ((zz - explained).max(0.0), c)
}

/// Window `z` fitted by a constant and the response `r` (with Σ r = `s`,
/// Σ|r|² = `rr`), by the 2×2 complex normal equations in closed form:
/// (squared error, the response's coefficient), or None if the two cannot
/// be told apart.
pub(super) fn fit_alone(z: &[C], r: &[C], s: C, rr: f64) -> Option<(f64, C)> {
    let n = z.len() as f64;
    let det = n * rr - (s.0 * s.0 + s.1 * s.1);
    if det <= 1e-12 * n * rr {
        return None;
    }
    let (sz, rz, zz) = window_sums(z, r);
    // c0 = (rr sz − s rz)/det, c1 = (n rz − conj(s) sz)/det.
    let c0 = (
        (rr * sz.0 - (s.0 * rz.0 - s.1 * rz.1)) / det,
        (rr * sz.1 - (s.0 * rz.1 + s.1 * rz.0)) / det,
    );
    let c1 = (
        (n * rz.0 - (s.0 * sz.0 + s.1 * sz.1)) / det,
        (n * rz.1 - (s.0 * sz.1 - s.1 * sz.0)) / det,
    );
    let explained = c0.0 * sz.0 + c0.1 * sz.1 + c1.0 * rz.0 + c1.1 * rz.1;
    Some(((zz - explained).max(0.0), c1))
}

/// (Σ z, Σ conj(r)·z, Σ|z|²) in one pass, each sum in the order summed
/// alone: five chains of additions side by side, where three passes left
/// the processor waiting on each addition in turn.
pub(super) fn window_sums(z: &[C], r: &[C]) -> (C, C, f64) {
    let (mut sz, mut rz, mut zz) = ((0.0, 0.0), (0.0, 0.0), 0.0);
    let both = z.len().min(r.len());
    for (v, x) in z[..both].iter().zip(&r[..both]) {
        sz = (sz.0 + v.0, sz.1 + v.1);
        rz = (rz.0 + x.0 * v.0 + x.1 * v.1, rz.1 + x.0 * v.1 - x.1 * v.0);
        zz += v.0 * v.0 + v.1 * v.1;
    }
    for v in &z[both..] {
        sz = (sz.0 + v.0, sz.1 + v.1);
        zz += v.0 * v.0 + v.1 * v.1;
    }
    (sz, rz, zz)
}

/// Σ conj(a_i)·z for four shapes `a` at once, each summed in [`dot`]'s
/// order: four chains of additions side by side.
pub(super) fn dots4(a: [&[C]; 4], z: &[C]) -> [C; 4] {
    let n = a.iter().map(|x| x.len()).min().unwrap_or(0).min(z.len());
    if a.iter().any(|x| x.len().min(z.len()) != n) {
        return a.map(|x| dot(x, z));
    }
    // Slices of one length: the loop reads them without bounds checks.
    let (a0, a1, a2, a3, z) = (&a[0][..n], &a[1][..n], &a[2][..n], &a[3][..n], &z[..n]);
    let mut s = [(0.0, 0.0); 4];
    for k in 0..n {
        let y = z[k];
        for (s, x) in s.iter_mut().zip([a0[k], a1[k], a2[k], a3[k]]) {
            *s = (s.0 + x.0 * y.0 + x.1 * y.1, s.1 + x.0 * y.1 - x.1 * y.0);
        }
    }
    s
}

/// Σ conj(a_i)·z for each shape of `a`, four at a time ([`dots4`]).
pub(super) fn dots(a: &[&[C]], z: &[C]) -> Vec<C> {
    let mut out = Vec::with_capacity(a.len());
    let mut four = a.chunks_exact(4);
    for q in four.by_ref() {
        out.extend(dots4([q[0], q[1], q[2], q[3]], z));
    }
    out.extend(four.remainder().iter().map(|x| dot(x, z)));
    out
}

/// Solve G c = r (G symmetric, small) by Gaussian elimination with
/// pivoting; a singular direction gets 0. On arrays: the same steps as
/// the general solver, which carried an unused second part of `r`.
fn solve_real<const K: usize>(mut g: [[f64; K]; K], mut r: [f64; K]) -> [f64; K] {
    let scale = (0..K).map(|i| g[i][i].abs()).fold(0.0, f64::max).max(1e-300);
    for col in 0..K {
        let p = (col..K)
            .max_by(|&a, &b| g[a][col].abs().total_cmp(&g[b][col].abs()))
            .unwrap_or(col);
        g.swap(col, p);
        r.swap(col, p);
        if g[col][col].abs() < 1e-12 * scale {
            continue;
        }
        for row in col + 1..K {
            let f = g[row][col] / g[col][col];
            let pivot = g[col];
            for (gc, pc) in g[row].iter_mut().zip(&pivot).skip(col) {
                *gc -= f * pc;
            }
            r[row] -= f * r[col];
        }
    }
    let mut c = [0.0; K];
    for i in (0..K).rev() {
        if g[i][i].abs() < 1e-12 * scale {
            continue;
        }
        let mut v = r[i];
        for j in i + 1..K {
            v -= g[i][j] * c[j];
        }
        c[i] = v / g[i][i];
    }
    c
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The general least squares the double-strike fit used before
    /// [`fit_gram3`] (vectors of vectors, a complex right-hand side): the
    /// reference its numbers are checked against, bit for bit.
    fn fit_gram(g: &[Vec<C>], r: &[C], zz: f64) -> (f64, Vec<C>) {
        let k = r.len();
        let mut m = vec![vec![0.0; 2 * k]; 2 * k];
        let mut rhs = vec![(0.0, 0.0); 2 * k];
        for i in 0..k {
            for j in 0..k {
                m[i][j] = g[i][j].0;
                m[i][k + j] = -g[i][j].1;
                m[k + i][j] = g[i][j].1;
                m[k + i][k + j] = g[i][j].0;
            }
            rhs[i] = (r[i].0, 0.0);
            rhs[k + i] = (r[i].1, 0.0);
        }
        let sol = solve(m, rhs);
        let c: Vec<C> = (0..k).map(|i| (sol[i].0, sol[k + i].0)).collect();
        let explained: f64 = c.iter().zip(r).map(|(c, r)| c.0 * r.0 + c.1 * r.1).sum();
        ((zz - explained).max(0.0), c)
    }

    /// The general solver before [`solve_real`].
    fn solve(mut g: Vec<Vec<f64>>, mut r: Vec<(f64, f64)>) -> Vec<(f64, f64)> {
        let k = r.len();
        let scale = (0..k).map(|i| g[i][i].abs()).fold(0.0, f64::max).max(1e-300);
        for col in 0..k {
            let p = (col..k)
                .max_by(|&a, &b| g[a][col].abs().total_cmp(&g[b][col].abs()))
                .unwrap_or(col);
            g.swap(col, p);
            r.swap(col, p);
            if g[col][col].abs() < 1e-12 * scale {
                continue;
            }
            for row in col + 1..k {
                let f = g[row][col] / g[col][col];
                let pivot = g[col].clone();
                for (gc, pc) in g[row].iter_mut().zip(&pivot).skip(col) {
                    *gc -= f * pc;
                }
                r[row] = (r[row].0 - f * r[col].0, r[row].1 - f * r[col].1);
            }
        }
        let mut c = vec![(0.0, 0.0); k];
        for i in (0..k).rev() {
            if g[i][i].abs() < 1e-12 * scale {
                continue;
            }
            let mut v = r[i];
            for j in i + 1..k {
                v = (v.0 - g[i][j] * c[j].0, v.1 - g[i][j] * c[j].1);
            }
            c[i] = (v.0 / g[i][i], v.1 / g[i][i]);
        }
        c
    }

    /// A reproducible pseudo-random series in [−1, 1).
    fn series(seed: u64, n: usize) -> Vec<C> {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_pcg::Pcg64::seed_from_u64(seed);
        let mut next = || rng.random_range(-1.0..1.0);
        (0..n).map(|_| (next(), next())).collect()
    }

    #[test]
    fn the_gram_fit_on_arrays_is_the_general_fit_to_the_bit() {
        for seed in 0..300u64 {
            let n = 20 + (seed as usize % 50);
            let (a, mut b, z) = (series(seed, n), series(seed + 1000, n), series(seed + 2000, n));
            // Some shapes the constant and the first cannot be told from:
            // the solver's singular directions.
            if seed % 7 == 0 {
                b = vec![(1.0, 0.0); n];
            }
            if seed % 11 == 0 {
                b = a.clone();
            }
            let one = vec![(1.0, 0.0); n];
            let basis = [&one, &a, &b];
            let g: Vec<Vec<C>> = basis
                .iter()
                .map(|x| basis.iter().map(|y| dot(x, y)).collect())
                .collect();
            let r: Vec<C> = basis.iter().map(|x| dot(x, &z)).collect();
            let zz: f64 = z.iter().map(|v| v.0 * v.0 + v.1 * v.1).sum();
            let g3: [[C; 3]; 3] = std::array::from_fn(|i| std::array::from_fn(|j| g[i][j]));
            let (e, c) = fit_gram3(&g3, &[r[0], r[1], r[2]], zz);
            let (e_ref, c_ref) = fit_gram(&g, &r, zz);
            assert_eq!(e.to_bits(), e_ref.to_bits(), "seed {seed}");
            for (x, y) in c.iter().zip(&c_ref) {
                assert_eq!(
                    (x.0.to_bits(), x.1.to_bits()),
                    (y.0.to_bits(), y.1.to_bits()),
                    "seed {seed}"
                );
            }
        }
    }

    #[test]
    fn the_sums_in_one_pass_are_each_sum_alone_to_the_bit() {
        for seed in 0..100u64 {
            let (nz, nr) = (10 + seed as usize % 40, 10 + (seed as usize * 7) % 40);
            let (z, r) = (series(seed, nz), series(seed + 500, nr));
            let (sz, rz, zz) = window_sums(&z, &r);
            let sz_ref = z.iter().fold((0.0, 0.0), |a, v| (a.0 + v.0, a.1 + v.1));
            let zz_ref: f64 = z.iter().map(|v| v.0 * v.0 + v.1 * v.1).sum();
            let bits = |c: C| (c.0.to_bits(), c.1.to_bits());
            assert_eq!(bits(sz), bits(sz_ref));
            assert_eq!(bits(rz), bits(dot(&r, &z)));
            assert_eq!(zz.to_bits(), zz_ref.to_bits());
            // Four shapes at once, and any number.
            let shapes: Vec<Vec<C>> = (0..7).map(|k| series(seed * 10 + k, nr)).collect();
            let refs: Vec<&[C]> = shapes.iter().map(|v| v.as_slice()).collect();
            let each: Vec<_> = refs.iter().map(|a| bits(dot(a, &z))).collect();
            assert_eq!(dots(&refs, &z).into_iter().map(bits).collect::<Vec<_>>(), each);
            let uneven = [refs[0], &refs[1][1..], refs[2], refs[3]];
            let four = dots4(uneven, &z).map(bits);
            assert_eq!(
                four.to_vec(),
                uneven.iter().map(|a| bits(dot(a, &z))).collect::<Vec<_>>()
            );
        }
    }

    #[test]
    fn a_strike_alone_is_fitted_in_closed_form_as_by_the_normal_equations() {
        // A decaying, turning response and a window: its scaled copy on a
        // constant, with a wobble the two cannot fit.
        let r: Vec<C> = (0..60)
            .map(|k| {
                let a = (1.0 - (-(k as f64) / 8.0).exp()) * (-(k as f64) / 200.0).exp();
                (a * (0.05 * k as f64).cos(), a * (0.05 * k as f64).sin())
            })
            .collect();
        let z: Vec<C> = r
            .iter()
            .enumerate()
            .map(|(k, v)| {
                let w = 0.1 * (0.7 * k as f64).sin();
                (0.3 + 1.5 * v.0 - 0.4 * v.1 + w, -0.2 + 1.5 * v.1 + 0.4 * v.0 - w)
            })
            .collect();
        let s = r.iter().fold((0.0, 0.0), |a, v| (a.0 + v.0, a.1 + v.1));
        let rr: f64 = r.iter().map(|v| v.0 * v.0 + v.1 * v.1).sum();
        let (e, c1) = fit_alone(&z, &r, s, rr).unwrap();
        let g = vec![vec![(z.len() as f64, 0.0), s], vec![conj(s), (rr, 0.0)]];
        let rhs = vec![z.iter().fold((0.0, 0.0), |a, v| (a.0 + v.0, a.1 + v.1)), dot(&r, &z)];
        let zz = z.iter().map(|v| v.0 * v.0 + v.1 * v.1).sum();
        let (e_ref, c) = fit_gram(&g, &rhs, zz);
        assert!((e - e_ref).abs() <= 1e-9 * zz, "{e} {e_ref}");
        assert!(
            (c1.0 - c[1].0).abs() < 1e-9 && (c1.1 - c[1].1).abs() < 1e-9,
            "{c1:?} {c:?}"
        );
        // The wobble is what is left, and the coefficient near the one put in.
        assert!(
            e > 0.0 && (c1.0 - 1.5).abs() < 0.1 && (c1.1 - 0.4).abs() < 0.1,
            "{e} {c1:?}"
        );
        // A constant response cannot be told from the constant.
        let flat = vec![(1.0, 0.0); 60];
        assert!(fit_alone(&z, &flat, (60.0, 0.0), 60.0).is_none());
    }

    #[test]
    fn the_gram_fit_matches_its_residual() {
        // Complex data on a constant and two complex shapes: the error
        // from the normal equations is the residual summed directly.
        let n = 50;
        let a: Vec<C> = (0..n)
            .map(|k| ((k as f64 * 0.3).sin(), (k as f64 * 0.1).cos()))
            .collect();
        let b: Vec<C> = (0..n)
            .map(|k| ((k as f64 * 0.05).exp() * 0.1, -(k as f64) * 0.02))
            .collect();
        let one: Vec<C> = vec![(1.0, 0.0); n];
        let z: Vec<C> = (0..n)
            .map(|k| {
                let noise = ((k * 7919 % 101) as f64 / 101.0 - 0.5) * 0.1;
                (
                    0.5 + 2.0 * a[k].0 - 0.7 * a[k].1 + 0.3 * b[k].0 + noise,
                    -1.0 + 2.0 * a[k].1 + 0.7 * a[k].0 + 0.3 * b[k].1,
                )
            })
            .collect();
        let basis = [&one, &a, &b];
        let g: Vec<Vec<C>> = basis
            .iter()
            .map(|x| basis.iter().map(|y| dot(x, y)).collect())
            .collect();
        let r: Vec<C> = basis.iter().map(|x| dot(x, &z)).collect();
        let zz: f64 = z.iter().map(|v| v.0 * v.0 + v.1 * v.1).sum();
        let g3: [[C; 3]; 3] = std::array::from_fn(|i| std::array::from_fn(|j| g[i][j]));
        let (e, c) = fit_gram3(&g3, &[r[0], r[1], r[2]], zz);
        let direct: f64 = (0..n)
            .map(|k| {
                let (mut re, mut im) = z[k];
                for (x, ci) in basis.iter().zip(&c) {
                    re -= x[k].0 * ci.0 - x[k].1 * ci.1;
                    im -= x[k].0 * ci.1 + x[k].1 * ci.0;
                }
                re * re + im * im
            })
            .sum();
        assert!((e - direct).abs() < 1e-9 * zz, "{e} against {direct}");
        // The coefficient on `a` is 2 + 0.7i, as put in.
        assert!((c[1].0 - 2.0).abs() < 0.05 && (c[1].1 - 0.7).abs() < 0.05, "{c:?}");
    }
}
