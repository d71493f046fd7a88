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

    #[test]
    fn bad_jumps_are_refused() {
        assert!(estimate(&[]).is_err());
        assert!(estimate(&[vec![1.0]]).is_err());
        assert!(estimate(&[vec![1.0, -0.3]]).is_err());
        assert!(estimate(&[vec![1.0, f64::NAN]]).is_err());
    }
}
