//! Closed-form lift-off angles: equations (15) and (16) for r = 0, and the
//! exact lift-off of any bell released from rest.
//!
//! With r = 0 the clapper resting on the bell feels a holding force
//! proportional to (L_b/L_c) sin(θ + φ_max) − sin θ (14); it lifts off where
//! that vanishes. The condition is exact for the full equations at r = 0,
//! not only for the approximate ones: the bell's acceleration cancels out.
//! For r ≠ 0 it does not, and the lift-off depends on how far the bell has
//! fallen; released from rest, bell and resting clapper are one rigid
//! pendulum, and [`liftoff_from_rest`] solves that swing in closed form
//! ([`RestingSwing`]), as every simulated stroke does.

use std::f64::consts::PI;

use crate::bell::{Bell, ParamError};
use crate::dynamics::Dynamics;
use crate::stroke::Side;
use crate::swing::RestingSwing;

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

/// Where a clapper resting on its stop leaves a bell released from rest.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LiftoffFromRest {
    /// The bell's angle θ at lift-off (rad).
    pub theta: f64,
    /// Time from the release to the lift-off (s).
    pub time: f64,
}

/// The lift-off of the clapper of `bell` resting on `side` (at ±φ_max)
/// when the bell is released from rest at `theta0` (rad, 0 < |θ0| < π):
/// exact for any r, from the closed-form swing. `Ok(None)` if the clapper
/// stays on through the half swing (or the bell stands at a balance point
/// and does not swing); lift-off at the release itself (time 0) if the
/// clapper is not pressed against that stop to begin with.
///
/// ```
/// use clapper_core::{bell::Bell, liftoff::liftoff_from_rest, stroke::Side};
///
/// let l = liftoff_from_rest(&Bell::lab(), 171f64.to_radians(), Side::Plus).unwrap().unwrap();
/// assert!(l.theta.to_degrees() > 90.0 && l.theta.to_degrees() < 171.0);
/// assert!(l.time > 0.0);
/// ```
pub fn liftoff_from_rest(bell: &Bell, theta0: f64, side: Side) -> Result<Option<LiftoffFromRest>, ParamError> {
    bell.validate()?;
    if !(theta0.is_finite() && theta0 != 0.0 && theta0.abs() < PI) {
        return Err(ParamError {
            field: "theta0_deg",
            value: theta0.to_degrees(),
            allowed: "between -180 and 180 deg, not 0",
        });
    }
    let d = Dynamics::new(bell);
    let phi = side.sign() * bell.phi_max;
    let (_, q) = d.resting(&[theta0, phi, 0.0, 0.0]);
    // Q_φ pushes the clapper off its stop unless it presses towards it.
    if side.sign() * q >= 0.0 {
        return Ok(Some(LiftoffFromRest {
            theta: theta0,
            time: 0.0,
        }));
    }
    let Some(swing) = RestingSwing::from_rest(&d, 0.0, theta0, phi) else {
        return Ok(None);
    };
    Ok(swing
        .force_zero_after(swing.sigma(theta0))
        .map(|sigma| LiftoffFromRest {
            theta: swing.theta(sigma),
            time: swing.time_at_sigma(sigma),
        }))
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

    /// The closed form against whole strokes integrated by Dormand–Prince
    /// (which integrates the resting phase rather than solving it), over
    /// chart bells of every r and both styles.
    #[test]
    fn liftoff_from_rest_agrees_with_integrated_strokes() {
        use crate::bell::ChartConstruction;
        use crate::ringing::first_stroke;
        use crate::stroke::{Integrator, SimConfig, Style};
        let mut cfg = SimConfig {
            integrator: Integrator::Dopri5,
            ..SimConfig::default()
        };
        cfg.ode.rtol = 1e-12;
        cfg.ode.atol = 1e-12;
        let c = ChartConstruction::default();
        let (mut compared, mut stays) = (0, 0);
        for x in [-0.3, -0.1, 0.0, 0.2, 0.45, 0.7] {
            for y in [0.6, 1.2, 1.68, 2.4] {
                let bell = c.bell(x, y).unwrap();
                for style in [Style::Right, Style::Wrong] {
                    let side = style.side(cfg.theta0);
                    let closed = liftoff_from_rest(&bell, cfg.theta0, side).unwrap();
                    let stroke = first_stroke(&bell, &cfg, style).unwrap();
                    // The stroke's lift-off is the last before its first
                    // strike: the first one only if no impact came before.
                    let first = stroke
                        .liftoff
                        .filter(|m| stroke.impacts.first().is_none_or(|i| i.t > m.t));
                    match (closed, first) {
                        (Some(l), Some(m)) => {
                            assert!(
                                (l.theta - m.theta).abs().to_degrees() < 1e-6,
                                "r/Lc {x} Lb/Lc {y} {style:?}: {} vs {} deg",
                                l.theta.to_degrees(),
                                m.theta.to_degrees()
                            );
                            assert!((l.time - m.t).abs() < 1e-7, "{} vs {} s", l.time, m.t);
                            compared += 1;
                        }
                        (None, None) => stays += 1,
                        (None, Some(m)) => panic!("r/Lc {x} Lb/Lc {y} {style:?}: stroke lifts off at {m:?}"),
                        // The stroke ended (or struck) before a lift-off it
                        // would have reached: only if it ended first.
                        (Some(l), None) => assert!(stroke.end.t < l.time || stroke.liftoff.is_some()),
                    }
                }
            }
        }
        assert!(compared >= 30, "only {compared} lift-offs compared ({stays} stayed on)");
    }

    #[test]
    fn liftoff_from_rest_at_r_zero_is_15_and_mirrors() {
        use crate::bell::ChartConstruction;
        let phi_max = 26f64.to_radians();
        for y in [0.8, 1.68, 2.4] {
            let bell = ChartConstruction::default().bell(0.0, y).unwrap();
            let a = liftoff_angles(y, phi_max).unwrap();
            let theta0 = 171f64.to_radians();
            let l = liftoff_from_rest(&bell, theta0, Side::Plus).unwrap().unwrap();
            assert!((l.theta - a.right).abs() < 1e-12, "{} vs {}", l.theta, a.right);
            // Released on the other side against the other stop: the mirror.
            let m = liftoff_from_rest(&bell, -theta0, Side::Minus).unwrap().unwrap();
            assert!((m.theta + l.theta).abs() < 1e-12 && (m.time - l.time).abs() < 1e-12);
        }
    }

    #[test]
    fn liftoff_from_rest_bad_input_and_no_press() {
        let bell = Bell::lab();
        for t in [0.0, PI, -4.0, f64::NAN] {
            assert_eq!(liftoff_from_rest(&bell, t, Side::Plus).unwrap_err().field, "theta0_deg");
        }
        let mut bad = bell;
        bad.clapper_mass = -1.0;
        assert!(liftoff_from_rest(&bad, 1.0, Side::Plus).is_err());
        // Released at 30 deg on the + side the clapper hangs towards the
        // − stop: against the + stop it is not pressed and leaves at once.
        let l = liftoff_from_rest(&bell, 30f64.to_radians(), Side::Plus)
            .unwrap()
            .unwrap();
        assert_eq!((l.theta, l.time), (30f64.to_radians(), 0.0));
    }
}
