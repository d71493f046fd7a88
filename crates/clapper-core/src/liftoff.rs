//! The closed-form lift-off angles for r = 0, equations (15) and (16).
//!
//! With r = 0 the clapper resting on the bell feels a holding force
//! proportional to (L_b/L_c) sin(θ + φ_max) − sin θ (14); it lifts off where
//! that vanishes. The condition is exact for the full equations at r = 0,
//! not only for the approximate ones: the bell's acceleration cancels out.

use crate::bell::ParamError;

/// Lift-off angles (rad) for ringing right and wrong.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LiftoffAngles {
    /// θ_r from (15), in (0, π).
    pub right: f64,
    /// θ_w = π − θ_r (16).
    pub wrong: f64,
}

/// Lift-off angles for a bell at `lb_over_lc` with contact angle `phi_max`
/// (rad): tan θ_r = sin φ_max / (L_c/L_b − cos φ_max), θ_r taken in (0, π).
///
/// ```
/// let a = clapper_core::liftoff::liftoff_angles(1.68, 26f64.to_radians()).unwrap();
/// assert!((a.right.to_degrees() - 124.70).abs() < 0.005);
/// ```
pub fn liftoff_angles(lb_over_lc: f64, phi_max: f64) -> Result<LiftoffAngles, ParamError> {
    if !(lb_over_lc.is_finite() && lb_over_lc > 0.0) {
        return Err(ParamError {
            field: "lb_over_lc",
            value: lb_over_lc,
            allowed: "a finite number > 0",
        });
    }
    if !(phi_max.is_finite() && phi_max > 0.0 && phi_max < std::f64::consts::FRAC_PI_2) {
        return Err(ParamError {
            field: "phi_max_deg",
            value: phi_max.to_degrees(),
            allowed: "between 0 and 90 deg, exclusive",
        });
    }
    // atan2 with a positive first argument lands in (0, π) as (15) requires.
    let right = phi_max.sin().atan2(1.0 / lb_over_lc - phi_max.cos());
    Ok(LiftoffAngles {
        right,
        wrong: std::f64::consts::PI - right,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spec_reference_value_and_symmetry() {
        let a = liftoff_angles(1.68, 26f64.to_radians()).unwrap();
        assert!(
            (a.right.to_degrees() - 124.70).abs() < 0.005,
            "{}",
            a.right.to_degrees()
        );
        assert!((a.right + a.wrong - std::f64::consts::PI).abs() < 1e-15);
        // L_c/L_b = cos φ_max: lift-off exactly at 90 deg.
        let a = liftoff_angles(1.0 / 26f64.to_radians().cos(), 26f64.to_radians()).unwrap();
        assert!((a.right.to_degrees() - 90.0).abs() < 1e-9);
        assert!(liftoff_angles(-1.0, 0.4).is_err());
        assert!(liftoff_angles(1.0, 2.0).is_err());
    }
}
