//! The coefficient of restitution from measured velocity jumps, Section
//! 3.2, equations (17) to (23).

use crate::bell::ParamError;

/// R from a ratio Δv2/Δv1 if every impact loses the same fraction (21).
pub fn r_equal_loss(ratio: f64) -> f64 {
    ratio * ratio
}

/// R from a ratio Δv2/Δv1 if the impacts after the first are lossless (23).
pub fn r_lossless_later(ratio: f64) -> f64 {
    (ratio / (2.0 - ratio)).powi(2)
}

/// R (the first impact's) and R2 (the later bounces') from the mean
/// ratios of adjacent velocity jumps, the two-coefficient reading of
/// Section 3.2 that `--restitution` and `--restitution-later` take.
///
/// With v0 the speed at the first impact, v1 = √R v0 and v_k = √R2 v_{k−1}
/// after: Δv1 = v0 (1 + √R), Δv2 = v1 (1 + √R2), Δv3 = √R2 Δv2, ... So
/// √R2 is the mean ratio of the later jumps (Δv3/Δv2 and on), and
/// Δv2/Δv1 = √R (1 + √R2) / (1 + √R) gives √R = ρ / (1 + √R2 − ρ). The two
/// limits are (21) (R2 = R) and (23) (R2 = 1). `None` without a ratio
/// after the first (every drop has two jumps only), or if no R fits.
///
/// The paper found the later ratios scattered and often above one (the
/// bell's own vibration lends or takes energy at each later impact); a
/// mean above one is clamped to R2 = 1, lossless, and said so.
pub fn two_coefficients(mean_ratios: &[f64]) -> Option<TwoCoefficients> {
    let (&rho, later) = mean_ratios.split_first()?;
    if later.is_empty() {
        return None;
    }
    let mean_later = later.iter().sum::<f64>() / later.len() as f64;
    let e2 = mean_later.min(1.0);
    let e1 = rho / (1.0 + e2 - rho);
    (e1.is_finite() && e1 > 0.0 && e1 <= 1.0 && e2 > 0.0).then_some(TwoCoefficients {
        first: e1 * e1,
        later: e2 * e2,
        later_clamped: mean_later > 1.0,
    })
}

/// R and R2 from a set of drops (see [`two_coefficients`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TwoCoefficients {
    /// R: the first impact's.
    pub first: f64,
    /// R2: every later bounce's.
    pub later: f64,
    /// Whether the later ratios averaged above one and R2 was set to 1.
    pub later_clamped: bool,
}

/// What a set of drops says about R.
#[derive(Clone, Debug, PartialEq)]
pub struct RestitutionEstimate {
    /// Ratios of adjacent jumps per drop: `ratios[d][k]` = Δv_{k+2}/Δv_{k+1}.
    pub ratios: Vec<Vec<f64>>,
    /// Mean over drops of each pair's ratio (the circles of Fig 8).
    pub mean_ratios: Vec<f64>,
    /// R by (21) from the mean Δv2/Δv1.
    pub r_equal_loss: f64,
    /// R by (23) from the mean Δv2/Δv1.
    pub r_lossless_later: f64,
    /// R and R2 together, where a drop has a third jump.
    pub two: Option<TwoCoefficients>,
}

/// Estimate R from the velocity jumps of one or more drops (each at least
/// two positive jumps, in any consistent unit).
pub fn estimate(drops: &[Vec<f64>]) -> Result<RestitutionEstimate, ParamError> {
    if drops.is_empty() {
        return Err(ParamError {
            field: "jumps",
            value: 0.0,
            allowed: "at least one drop of at least two jumps",
        });
    }
    let mut ratios = vec![];
    for d in drops {
        if d.len() < 2 {
            return Err(ParamError {
                field: "jumps",
                value: d.len() as f64,
                allowed: "at least two jumps per drop",
            });
        }
        if let Some(&bad) = d.iter().find(|v| !(v.is_finite() && **v > 0.0)) {
            return Err(ParamError {
                field: "jumps",
                value: bad,
                allowed: "finite jumps > 0",
            });
        }
        ratios.push(d.windows(2).map(|w| w[1] / w[0]).collect::<Vec<f64>>());
    }
    let longest = ratios.iter().map(Vec::len).max().unwrap_or(0);
    let mean_ratios: Vec<f64> = (0..longest)
        .map(|k| {
            let v: Vec<f64> = ratios.iter().filter_map(|r| r.get(k).copied()).collect();
            v.iter().sum::<f64>() / v.len() as f64
        })
        .collect();
    let first = mean_ratios[0];
    Ok(RestitutionEstimate {
        r_equal_loss: r_equal_loss(first),
        r_lossless_later: r_lossless_later(first),
        two: two_coefficients(&mean_ratios),
        ratios,
        mean_ratios,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn papers_mean_ratio() {
        // "The mean value of Δv2/Δv1 ... was 0.35. Using (21) gives R ≈ 0.12, (23) gives R ≈ 0.045."
        assert!((r_equal_loss(0.35) - 0.12).abs() < 0.005);
        assert!((r_lossless_later(0.35) - 0.045).abs() < 0.0005);
    }

    #[test]
    fn exact_jumps_give_r_to_1e9() {
        for r in [0.01, 0.05, 0.12, 0.5, 0.9] {
            let e = f64::sqrt(r);
            // Equal loss: v_k = e^k v0, Δv_k = v_{k-1} + v_k.
            let v: Vec<f64> = (0..6).map(|k| e.powi(k)).collect();
            let jumps: Vec<f64> = v.windows(2).map(|w| w[0] + w[1]).collect();
            let est = estimate(&[jumps]).unwrap();
            assert!((est.r_equal_loss - r).abs() < 1e-9, "{r}");
            // Lossless later: v1 = e v0, then v_k = v1.
            let jumps = vec![1.0 + e, 2.0 * e, 2.0 * e];
            let est = estimate(&[jumps]).unwrap();
            assert!((est.r_lossless_later - r).abs() < 1e-9, "{r}");
        }
    }

    /// Drops synthesised with a known R and R2 give both back; the two
    /// limits are (21) and (23).
    #[test]
    fn two_coefficients_come_back_from_exact_jumps() {
        for (r, r2) in [(0.05, 0.3), (0.12, 0.12), (0.2, 0.6), (0.045, 1.0), (0.5, 0.9)] {
            let (e, e2) = (f64::sqrt(r), f64::sqrt(r2));
            // v0 = 1, v1 = e, v_k = e2 v_{k-1}; Δv_k = v_{k-1} + v_k.
            let mut v = vec![1.0, e];
            for _ in 0..4 {
                v.push(e2 * v[v.len() - 1]);
            }
            let jumps: Vec<f64> = v.windows(2).map(|w| w[0] + w[1]).collect();
            let two = estimate(&[jumps]).unwrap().two.unwrap();
            assert!((two.first - r).abs() < 1e-12, "R {r}: {two:?}");
            assert!((two.later - r2).abs() < 1e-12, "R2 {r2}: {two:?}");
            assert!(!two.later_clamped);
        }
        // R2 = R is (21); R2 = 1 is (23).
        for rho in [0.2, 0.35, 0.6] {
            let a = two_coefficients(&[rho, rho]).unwrap();
            assert!((a.first - r_equal_loss(rho)).abs() < 1e-12);
            let b = two_coefficients(&[rho, 1.0]).unwrap();
            assert!((b.first - r_lossless_later(rho)).abs() < 1e-12);
        }
        // Later ratios above one: lossless, said so. Two jumps only: unknown.
        assert!(two_coefficients(&[0.35, 1.3, 1.1]).unwrap().later_clamped);
        assert_eq!(two_coefficients(&[0.35]), None);
    }

    #[test]
    fn bad_jumps_are_refused() {
        assert!(estimate(&[]).is_err());
        assert!(estimate(&[vec![1.0]]).is_err());
        assert!(estimate(&[vec![1.0, -0.3]]).is_err());
        assert!(estimate(&[vec![1.0, f64::NAN]]).is_err());
    }
}
