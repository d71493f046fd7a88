//! Elliptic integrals and functions: what the swing of a rigid pendulum is
//! made of, for the bell swinging with its clapper at rest
//! ([`crate::swing`]).
//!
//! Modulus convention: `k` (not the parameter m = k²), and the
//! complementary modulus `kc` = √(1 − k²) is passed in as well where the
//! caller knows it more accurately than `1 − k²` would give it (a bell
//! released near the top has k within 1e-3 of 1).

/// Carlson's symmetric integral R_F(x, y, z) = ½ ∫₀^∞ dt / √((t+x)(t+y)(t+z))
/// for x, y, z ≥ 0, at most one of them zero (DLMF 19.16.1), by the
/// duplication theorem (DLMF 19.26.18) and the fifth-order series at the
/// end (DLMF 19.36.1): about 1e-16 relative. `NaN` outside the domain.
pub fn carlson_rf(x: f64, y: f64, z: f64) -> f64 {
    let zeros = [x, y, z].iter().filter(|&&v| v == 0.0).count();
    if !(x >= 0.0 && y >= 0.0 && z >= 0.0) || zeros > 1 || !(x + y + z).is_finite() {
        return f64::NAN;
    }
    let (mut x, mut y, mut z) = (x, y, z);
    // Each duplication divides the spread by 4: from any start, 40 rounds
    // reach 1e-24 of it. Stop once the series below is exact to rounding.
    let mut mu = (x + y + z) / 3.0;
    for _ in 0..40 {
        let spread = (mu - x).abs().max((mu - y).abs()).max((mu - z).abs()) / mu;
        if spread < 1e-3 {
            break;
        }
        let (sx, sy, sz) = (x.sqrt(), y.sqrt(), z.sqrt());
        let lambda = sx * (sy + sz) + sy * sz;
        x = 0.25 * (x + lambda);
        y = 0.25 * (y + lambda);
        z = 0.25 * (z + lambda);
        mu = (x + y + z) / 3.0;
    }
    let (dx, dy) = ((mu - x) / mu, (mu - y) / mu);
    let dz = -(dx + dy);
    let e2 = dx * dy - dz * dz;
    let e3 = dx * dy * dz;
    (1.0 - e2 / 10.0 + e3 / 14.0 + e2 * e2 / 24.0 - 3.0 * e2 * e3 / 44.0) / mu.sqrt()
}

/// The complete integral of the first kind K(k) = R_F(0, kc², 1), with
/// `kc` = √(1 − k²) the complementary modulus (0 < kc ≤ 1).
pub fn complete_k(kc: f64) -> f64 {
    carlson_rf(0.0, kc * kc, 1.0)
}

/// Jacobi's elliptic functions (sn, cn, dn)(u, k) for 0 ≤ k < 1, given k
/// and kc = √(1 − k²), by the arithmetic-geometric mean and the descending
/// Landen transformation (DLMF 22.20.1-22.20.2): about 1e-15.
pub fn jacobi(u: f64, k: f64, kc: f64) -> (f64, f64, f64) {
    // The AGM converges quadratically: 8 rounds are exact for kc >= 1e-100.
    const ROUNDS: usize = 8;
    let mut a = [0.0f64; ROUNDS + 1];
    let mut c = [0.0f64; ROUNDS + 1];
    let (mut an, mut bn) = (1.0f64, kc);
    a[0] = 1.0;
    c[0] = k;
    let mut n = 0;
    while n < ROUNDS && c[n].abs() > 1e-17 * an {
        let (a1, b1) = (0.5 * (an + bn), (an * bn).sqrt());
        c[n + 1] = 0.5 * (an - bn);
        (an, bn) = (a1, b1);
        n += 1;
        a[n] = an;
    }
    // φ_n = 2^n a_n u, then φ_{j-1} = (φ_j + asin(c_j sin φ_j / a_j)) / 2.
    let mut phi = (1u64 << n) as f64 * a[n] * u;
    for j in (1..=n).rev() {
        phi = 0.5 * (phi + (c[j] * phi.sin() / a[j]).asin());
    }
    let (s, co) = phi.sin_cos();
    // dn² = 1 − k² sn² = kc² + k² cn²: no cancellation as k → 1.
    (s, co, (kc * kc + k * k * co * co).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// K by the arithmetic-geometric mean, K = π / (2 AGM(1, kc)).
    fn k_agm(kc: f64) -> f64 {
        let (mut a, mut b) = (1.0f64, kc);
        for _ in 0..30 {
            (a, b) = (0.5 * (a + b), (a * b).sqrt());
        }
        PI / (2.0 * a)
    }

    /// F(φ, k) by Simpson's rule on the integrand 1/√(1 − k² sin² t).
    fn f_simpson(phi: f64, k: f64) -> f64 {
        let n = 20_000;
        let h = phi / n as f64;
        let f = |t: f64| 1.0 / (1.0 - k * k * t.sin().powi(2)).sqrt();
        let mut s = f(0.0) + f(phi);
        for i in 1..n {
            s += if i % 2 == 1 { 4.0 } else { 2.0 } * f(i as f64 * h);
        }
        s * h / 3.0
    }

    #[test]
    fn carlson_rf_known_values_and_homogeneity() {
        // R_F(x, x, x) = 1/√x; R_F(0, 1, 1) = π/2; R_F(0, y, y) = π/(2√y).
        assert!((carlson_rf(2.0, 2.0, 2.0) - 0.5f64.sqrt()).abs() < 1e-15);
        assert!((carlson_rf(0.0, 1.0, 1.0) - PI / 2.0).abs() < 1e-15);
        assert!((carlson_rf(0.0, 4.0, 4.0) - PI / 4.0).abs() < 1e-15);
        // R_F(λx, λy, λz) = R_F(x, y, z) / √λ.
        let (a, b) = (carlson_rf(0.3, 1.7, 4.1), carlson_rf(3.0, 17.0, 41.0));
        assert!((a - b * 10f64.sqrt()).abs() < 1e-15 * a);
        assert!(carlson_rf(-1.0, 1.0, 1.0).is_nan());
        assert!(carlson_rf(0.0, 0.0, 1.0).is_nan());
    }

    #[test]
    fn complete_and_incomplete_integrals_match_independent_ones() {
        for kc in [1.0, 0.9, 0.5, 0.1, 0.0785, 1e-3, 1e-8] {
            let want = k_agm(kc);
            assert!((complete_k(kc) - want).abs() < 2e-15 * want, "kc {kc}");
        }
        // F(φ, k) = sin φ R_F(cos² φ, 1 − k² sin² φ, 1).
        for k in [0.3, 0.9, 0.99] {
            for phi in [0.2, 1.0, 1.5] {
                let (s, c) = f64::sin_cos(phi);
                let f = s * carlson_rf(c * c, 1.0 - k * k * s * s, 1.0);
                assert!((f - f_simpson(phi, k)).abs() < 1e-12, "k {k} phi {phi}");
            }
        }
    }

    #[test]
    fn jacobi_functions_invert_the_integral() {
        for k in [0.0f64, 0.3, 0.9, 0.996_917] {
            let kc = (1.0 - k * k).sqrt();
            let kk = complete_k(kc);
            for frac in [0.0, 0.1, 0.5, 0.99, 1.0, 1.7, -0.4] {
                let u = frac * kk;
                let (sn, cn, dn) = jacobi(u, k, kc);
                assert!((sn * sn + cn * cn - 1.0).abs() < 1e-14);
                assert!((dn * dn + k * k * sn * sn - 1.0).abs() < 1e-14);
                // u = F(am u, k) on the first quarter period.
                if (0.0..=1.0).contains(&frac) {
                    let back = sn * carlson_rf(cn * cn, dn * dn, 1.0);
                    assert!((back - u).abs() < 1e-13 * kk.max(1.0), "k {k} u {u}: {back}");
                }
            }
            // sn(K) = 1, cn(K) = 0, dn(K) = kc.
            let (sn, cn, dn) = jacobi(kk, k, kc);
            assert!((sn - 1.0).abs() < 1e-14 && cn.abs() < 1e-7 && (dn - kc).abs() < 1e-7);
        }
    }
}
