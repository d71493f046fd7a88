//! Energy lost into vibration at an impact, Section 3.3, equations (24) to
//! (32), with the half-sine pulse of docs/model.md §6; and the paper's aside on
//! choosing an impulse hammer.

use std::f64::consts::PI;

use crate::bell::ParamError;

/// One mode of the struck structure at the strike point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mode {
    /// Natural frequency (Hz).
    pub freq_hz: f64,
    /// Effective mass at the strike point, M_n = 1/u_n² (kg), (27).
    pub effective_mass: f64,
}

/// |F(ω)| of a half-sine force pulse of length `tau` (s), normalised to 1 at
/// ω = 0: |cos(ωτ/2)| / |1 − (ωτ/π)²|, π/4 at ωτ = π.
pub fn half_sine_spectrum(omega: f64, tau: f64) -> f64 {
    let x = omega * tau;
    let d = 1.0 - (x / PI).powi(2);
    if d.abs() < 1e-9 {
        PI / 4.0
    } else {
        ((x / 2.0).cos() / d).abs()
    }
}

/// K = Σ (m/M_n) |F(ω_n)|² (32) for mass `m` (kg) and a half-sine pulse
/// of length `tau` (s); `tau` = 0 is the ideal impulse of (32). The weight
/// is the squared spectrum because a mode's energy goes as the square of
/// the velocity the pulse gives it.
pub fn k_factor(modes: &[Mode], m: f64, tau: f64) -> f64 {
    modes
        .iter()
        .map(|md| m / md.effective_mass * half_sine_spectrum(2.0 * PI * md.freq_hz, tau).powi(2))
        .sum()
}

/// λ = v1/v0 = (1 − K)/(1 + K), (31).
pub fn lambda(k: f64) -> f64 {
    (1.0 - k) / (1.0 + k)
}

/// The energy coefficient of restitution R = λ² for a given K.
pub fn restitution(k: f64) -> f64 {
    lambda(k).powi(2)
}

/// K that gives an energy restitution `r` with a clean rebound (λ ≥ 0):
/// K = (1 − √R)/(1 + √R). The paper's lab-bell arithmetic: R = 0.1 gives 0.52.
pub fn k_for_restitution(r: f64) -> f64 {
    let l = r.sqrt();
    (1.0 - l) / (1.0 + l)
}

/// Check a modes list.
pub fn validate_modes(modes: &[Mode]) -> Result<(), ParamError> {
    if modes.is_empty() {
        return Err(ParamError {
            field: "modes",
            value: 0.0,
            allowed: "at least one mode",
        });
    }
    for md in modes {
        if !(md.freq_hz.is_finite() && md.freq_hz >= 0.0) {
            return Err(ParamError {
                field: "freq_hz",
                value: md.freq_hz,
                allowed: "a finite frequency >= 0",
            });
        }
        if !(md.effective_mass.is_finite() && md.effective_mass > 0.0) {
            return Err(ParamError {
                field: "effective_mass_kg",
                value: md.effective_mass,
                allowed: "a finite mass > 0",
            });
        }
    }
    Ok(())
}

/// The shortest half-sine pulse (s) that still gives a clean rebound: the
/// smallest τ such that K(τ') ≤ 1 for every longer τ'. The last crossing
/// of K = 1 is bracketed on a logarithmic grid from 1 µs to 1 s (400
/// points per decade), then refined by bisection to 1e-12 of τ (60 halvings
/// of a bracket 0.6 % wide), so the answer is the crossing, not a grid
/// point. `None` if K stays above 1 (the striker is too heavy for any
/// pulse: m > M_0 for a rigid-body mode), `Some(0.0)` if even an ideal
/// impulse rebounds.
pub fn shortest_clean_pulse(modes: &[Mode], m: f64) -> Option<f64> {
    let grid: Vec<f64> = (0..=2400).map(|k| 1e-6 * 10f64.powf(k as f64 / 400.0)).collect();
    if k_factor(modes, m, *grid.last()?) > 1.0 {
        return None;
    }
    let mut shortest = *grid.last()?;
    for &tau in grid.iter().rev() {
        if k_factor(modes, m, tau) > 1.0 {
            // K(tau) > 1 >= K(shortest): bisect the crossing.
            let (mut bad, mut good) = (tau, shortest);
            for _ in 0..60 {
                let mid = 0.5 * (bad + good);
                if k_factor(modes, m, mid) > 1.0 {
                    bad = mid;
                } else {
                    good = mid;
                }
                if good - bad <= 1e-12 * good {
                    break;
                }
            }
            return Some(good);
        }
        shortest = tau;
    }
    Some(0.0)
}

/// Modes "strongly excited" by a pulse of length `tau`: those with
/// |F(ω_n)|² ≥ 1/2, inside the pulse's half-power band.
pub fn strongly_excited(modes: &[Mode], tau: f64) -> usize {
    modes
        .iter()
        .filter(|md| half_sine_spectrum(2.0 * PI * md.freq_hz, tau).powi(2) >= 0.5)
        .count()
}

/// The impulse-hammer aside: to excite up to `f_max` (Hz) the half-sine
/// pulse may be at most this long (s): |F|² = 1/2 at f_max.
pub fn longest_pulse_for(f_max: f64) -> f64 {
    // |F(x)|² = 1/2 by bisection on x = ωτ in (0, 3π): |F| falls monotonically
    // from 1 to its first zero at 3π (it is still (π/4)² ≈ 0.62 at π).
    let (mut lo, mut hi) = (0.0, 3.0 * PI);
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if half_sine_spectrum(mid, 1.0).powi(2) > 0.5 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi) / (2.0 * PI * f_max)
}

/// The heaviest hammer (kg) that still bounces cleanly (K ≤ 1) with a pulse
/// of length `tau`: m = 1 / Σ |F(ω_n)|²/M_n.
pub fn heaviest_clean_hammer(modes: &[Mode], tau: f64) -> f64 {
    1.0 / k_factor(modes, 1.0, tau)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spectrum_values() {
        assert!((half_sine_spectrum(0.0, 1e-3) - 1.0).abs() < 1e-12);
        assert!((half_sine_spectrum(PI, 1.0) - PI / 4.0).abs() < 1e-9);
        assert!((half_sine_spectrum(PI + 1e-6, 1.0) - PI / 4.0).abs() < 1e-5);
        assert!(half_sine_spectrum(3.0 * PI, 1.0) < 1e-12);
    }

    #[test]
    fn lab_bell_arithmetic_of_section_3_3() {
        // R = 0.1 means λ = 0.32 and K ≈ 0.5.
        let k = k_for_restitution(0.1);
        assert!((k - 0.52).abs() < 0.01, "{k}");
        assert!((lambda(k) - 0.1f64.sqrt()).abs() < 1e-12);
        assert!((restitution(k) - 0.1).abs() < 1e-12);
        // "m/M_n of the order of 0.1 ... not many more than about 5 modes": five such
        // modes give K = 0.5, as an ideal impulse.
        let modes = vec![
            Mode {
                freq_hz: 600.0,
                effective_mass: 10.0
            };
            5
        ];
        assert!((k_factor(&modes, 1.0, 0.0) - 0.5).abs() < 1e-12);
    }

    #[test]
    fn the_shortest_clean_pulse_is_the_crossing_not_a_grid_point() {
        // One mode with m/M = 2: K = 2 |F|², so K = 1 where |F|² = 1/2,
        // which is the half-power pulse of the hammer aside, found there
        // by its own root finder.
        let f = 1234.5;
        let modes = [Mode {
            freq_hz: f,
            effective_mass: 0.5,
        }];
        let tau = shortest_clean_pulse(&modes, 1.0).unwrap();
        let exact = longest_pulse_for(f);
        assert!(((tau - exact) / exact).abs() < 1e-9, "{tau} against {exact}");
    }

    #[test]
    fn clean_pulse_and_hammer() {
        // Ten modes, each m/M_n = 0.2: an ideal impulse gives K = 2 (no clean bounce).
        let modes: Vec<Mode> = (1..=10)
            .map(|n| Mode {
                freq_hz: 500.0 * n as f64,
                effective_mass: 5.0,
            })
            .collect();
        assert!(k_factor(&modes, 1.0, 0.0) > 1.0);
        let tau = shortest_clean_pulse(&modes, 1.0).unwrap();
        assert!(tau > 0.0);
        assert!(k_factor(&modes, 1.0, tau) <= 1.0 + 1e-9);
        assert!(k_factor(&modes, 1.0, tau * 0.95) > 1.0);
        // Hammer: a pulse short enough for 2 kHz, and the mass limit it implies.
        let t = longest_pulse_for(2000.0);
        assert!((half_sine_spectrum(2.0 * PI * 2000.0, t).powi(2) - 0.5).abs() < 1e-9);
        let mh = heaviest_clean_hammer(&modes, t);
        assert!((k_factor(&modes, mh, t) - 1.0).abs() < 1e-9);
        assert!(validate_modes(&[]).is_err());
        assert!(validate_modes(&[Mode {
            freq_hz: 1.0,
            effective_mass: 0.0
        }])
        .is_err());
    }
}
