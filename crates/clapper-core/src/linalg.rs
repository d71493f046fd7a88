//! A small dense linear solve, for the normal equations of the few-parameter
//! least-squares fits here and in the outer crates (the listening test's
//! hyperbola, an accelerometer log's local fits).

/// Solve `m x = v` for an N × N system by Gauss-Jordan elimination with
/// partial pivoting; `None` when a pivot vanishes (a singular system).
pub fn solve<const N: usize>(m: [[f64; N]; N], v: [f64; N]) -> Option<[f64; N]> {
    let mut a = m;
    let mut b = v;
    for c in 0..N {
        let p = (c..N).max_by(|&x, &y| a[x][c].abs().total_cmp(&a[y][c].abs()))?;
        a.swap(c, p);
        b.swap(c, p);
        if a[c][c].abs() < 1e-300 || !a[c][c].is_finite() {
            return None;
        }
        let (pivot, bc) = (a[c], b[c]);
        for (r, (row, br)) in a.iter_mut().zip(b.iter_mut()).enumerate() {
            if r != c {
                let f = row[c] / pivot[c];
                for (x, p) in row.iter_mut().zip(pivot.iter()).skip(c) {
                    *x -= f * p;
                }
                *br -= f * bc;
            }
        }
    }
    Some(std::array::from_fn(|i| b[i] / a[i][i]))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_known_system_is_solved_and_a_singular_one_refused() {
        // x = (1, -2, 3): m x computed by hand.
        let m = [[2.0, 1.0, -1.0], [-3.0, -1.0, 2.0], [-2.0, 1.0, 2.0]];
        let v = [2.0 - 2.0 - 3.0, -3.0 + 2.0 + 6.0, -2.0 - 2.0 + 6.0];
        let x = solve(m, v).expect("regular");
        for (got, want) in x.iter().zip([1.0, -2.0, 3.0]) {
            assert!((got - want).abs() < 1e-12, "{x:?}");
        }
        assert!(solve([[1.0, 2.0], [2.0, 4.0]], [1.0, 2.0]).is_none());
    }
}
