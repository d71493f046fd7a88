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

/// Least squares of data `z` on complex shapes with complex coefficients,
/// from the normal equations: the Gram matrix `g` (g[i][j] = Σ conj(b_i)
/// b_j), `r` (r[i] = Σ conj(b_i) z) and Σ|z|². Returns (squared error,
/// coefficients).
pub(super) fn fit_gram(g: &[Vec<C>], r: &[C], zz: f64) -> (f64, Vec<C>) {
    let k = r.len();
    // As a real system of twice the size: [Re G, −Im G; Im G, Re G].
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
    let sz: C = z.iter().fold((0.0, 0.0), |a, v| (a.0 + v.0, a.1 + v.1));
    let rz = dot(r, z);
    let zz: f64 = z.iter().map(|v| v.0 * v.0 + v.1 * v.1).sum();
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

/// Solve G c = r (G symmetric, small) by Gaussian elimination with
/// pivoting; a singular direction gets 0.
pub(super) fn solve(mut g: Vec<Vec<f64>>, mut r: Vec<(f64, f64)>) -> Vec<(f64, f64)> {
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

#[cfg(test)]
mod tests {
    use super::*;

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
        let (e, c) = fit_gram(&g, &r, zz);
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
