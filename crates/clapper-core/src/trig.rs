//! sin and cos together, for the right-hand side: about a third of a
//! chart's time went to the C library's `sincos`. Reduction by π/2 in three
//! parts (Cody & Waite) and Taylor polynomials on |r| ≤ π/4, truncated where
//! the next term is below 1e-16 of the result. Within a few ulp of `std`
//! (tested), exactly odd (sin) and even (cos) in x, which the hand/backstroke
//! mirror symmetry relies on, and deterministic (plain f64 arithmetic).

/// π/2 in three parts: the first two with 33 significant bits, so that
/// `k * PIO2_1` and `k * PIO2_2` are exact for |k| < 2^20.
const PIO2_1: f64 = 1.570_796_326_734_125_6;
const PIO2_2: f64 = 6.077_100_506_303_966e-11;
const PIO2_3: f64 = 2.022_266_248_795_950_6e-21;
const TWO_OVER_PI: f64 = std::f64::consts::FRAC_2_PI;
/// Beyond this |x| the three-part reduction loses accuracy; the library
/// function takes over (no bell angle comes near it).
const REDUCE_LIMIT: f64 = 1e5;
/// 1.5 * 2^52: adding it leaves no fraction bits.
const ROUNDER: f64 = 6_755_399_441_055_744.0;

// Taylor coefficients (-1)^k / (2k+1)! and (-1)^k / (2k)!.
const S1: f64 = -1.0 / 6.0;
const S2: f64 = 1.0 / 120.0;
const S3: f64 = -1.0 / 5040.0;
const S4: f64 = 1.0 / 362_880.0;
const S5: f64 = -1.0 / 39_916_800.0;
const S6: f64 = 1.0 / 6_227_020_800.0;
const S7: f64 = -1.0 / 1_307_674_368_000.0;
const C1: f64 = -1.0 / 2.0;
const C2: f64 = 1.0 / 24.0;
const C3: f64 = -1.0 / 720.0;
const C4: f64 = 1.0 / 40_320.0;
const C5: f64 = -1.0 / 3_628_800.0;
const C6: f64 = 1.0 / 479_001_600.0;
const C7: f64 = -1.0 / 87_178_291_200.0;
const C8: f64 = 1.0 / 20_922_789_888_000.0;

/// `(sin x, cos x)`.
#[inline]
pub fn sin_cos(x: f64) -> (f64, f64) {
    if x.is_nan() || x.abs() >= REDUCE_LIMIT {
        return x.sin_cos();
    }
    // Round to nearest (ties to even) by adding and subtracting 1.5 * 2^52:
    // inline, unlike f64::round, and symmetric, so k(-x) = -k(x) and
    // r(-x) = -r(x).
    let k = (x * TWO_OVER_PI + ROUNDER) - ROUNDER;
    let r = ((x - k * PIO2_1) - k * PIO2_2) - k * PIO2_3;
    let z = r * r;
    let s = r + r * z * (S1 + z * (S2 + z * (S3 + z * (S4 + z * (S5 + z * (S6 + z * S7))))));
    let c = 1.0 + z * (C1 + z * (C2 + z * (C3 + z * (C4 + z * (C5 + z * (C6 + z * (C7 + z * C8)))))));
    match (k as i64) & 3 {
        0 => (s, c),
        1 => (c, -s),
        2 => (-s, -c),
        _ => (-c, s),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ulps(a: f64, b: f64) -> f64 {
        // Relative to the larger of |b| and a floor, so values near zero are
        // judged by absolute error on the scale of 1.
        (a - b).abs() / (f64::EPSILON * b.abs().max(1e-3))
    }

    #[test]
    fn agrees_with_std_and_is_symmetric() {
        let mut worst = 0.0f64;
        let mut x = -40.0;
        while x < 40.0 {
            let (s, c) = sin_cos(x);
            worst = worst.max(ulps(s, x.sin())).max(ulps(c, x.cos()));
            let (sm, cm) = sin_cos(-x);
            assert_eq!(sm, -s, "sin not odd at {x}");
            assert_eq!(cm, c, "cos not even at {x}");
            x += 0.000_713_3;
        }
        assert!(worst < 4.0, "worst error {worst} ulp");
        for x in [
            0.0,
            -0.0,
            1e-300,
            std::f64::consts::FRAC_PI_4,
            std::f64::consts::PI,
            3.0e5,
            f64::NAN,
        ] {
            let (s, c) = sin_cos(x);
            let (ss, cc) = x.sin_cos();
            assert!(
                (s - ss).abs() <= 1e-15 && (c - cc).abs() <= 1e-15 || (s.is_nan() && ss.is_nan()),
                "{x}"
            );
        }
    }
}
