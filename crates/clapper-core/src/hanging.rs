//! How a real bell departs from the paper's ideal, symmetric, frictionless
//! one (docs/model.md §10): a clapper pivot off the bell's axis, unequal
//! contact angles on the two sides, and friction at the bell's bearings and
//! the clapper's pivot. Also the tower's own readings of these: the tape
//! measure's ball-to-rim gaps, and the number of swings for a small swing
//! to halve.
//!
//! The default [`Hanging`] is the ideal bell, and with it every result is
//! the same, bit for bit, as the paper's model.
//!
//! Sides are named by the stroke at which a bell ringing right strikes them:
//! from +θ0 (a handstroke) the clapper rests on the + side and strikes the
//! − side, so the **hand side** is φ < 0 and the **back side** φ > 0.

use std::f64::consts::{FRAC_PI_2, LN_2, PI};

use crate::param::ParamError;

/// Friction at the bell's bearings and at the clapper's pivot: a viscous
/// part (torque proportional to the rate) and a Coulomb part (a constant
/// torque against the motion, which holds the joint when the torque needed
/// to keep it still is smaller). All zero by default: the paper's bell.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Friction {
    /// c_b: viscous damping at the bell's bearings (N m s/rad): torque −c_b θ'.
    pub bell_damping: f64,
    /// τ_b: Coulomb friction torque at the bell's bearings (N m).
    pub bell_friction: f64,
    /// c_c: viscous damping at the clapper's pivot (N m s/rad): torque −c_c φ'
    /// on the clapper relative to the bell.
    pub clapper_damping: f64,
    /// τ_c: Coulomb friction torque at the clapper's pivot (N m). It can
    /// hold the clapper still relative to the bell mid-flight (it sticks)
    /// and against a stop until the torque needed exceeds it.
    pub clapper_friction: f64,
}

impl Friction {
    /// Whether there is any friction at all.
    pub fn is_none(&self) -> bool {
        *self == Friction::default()
    }

    /// Check every part is finite and not negative.
    pub fn validate(&self) -> Result<(), ParamError> {
        for (field, value) in [
            ("bell_damping_n_m_s", self.bell_damping),
            ("bell_friction_n_m", self.bell_friction),
            ("clapper_damping_n_m_s", self.clapper_damping),
            ("clapper_friction_n_m", self.clapper_friction),
        ] {
            if !(value.is_finite() && value >= 0.0) {
                return Err(ParamError {
                    field,
                    value,
                    allowed: "a finite number >= 0",
                });
            }
        }
        Ok(())
    }
}

/// A bell's departures from the ideal: pivot offset, contact-angle skew and
/// friction. The default is the ideal bell.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Hanging {
    /// d: sideways offset of the clapper pivot from the bell's axis (m),
    /// positive toward the + (back) side, the side the clapper rests on
    /// before a handstroke. r stays along the axis. A few millimetres at
    /// most in a real bell.
    pub pivot_offset: f64,
    /// Half the difference of the contact angles, hand side minus back
    /// side (rad): the hand side's stop is at φ = −(φ_max + skew), the back
    /// side's at φ = φ_max − skew. Zero for a symmetric bell.
    pub phi_max_skew: f64,
    /// Friction at the two joints.
    pub friction: Friction,
}

impl Hanging {
    /// Whether this is the paper's ideal bell.
    pub fn is_ideal(&self) -> bool {
        *self == Hanging::default()
    }

    /// Whether a bell hung so is its own mirror image: no pivot offset and
    /// equal contact angles. Friction and damping, of any size, are odd in
    /// the rates and keep the mirror: such a bell's backstroke is its
    /// handstroke mirrored, bit for bit (`tests/chart.rs`), as an ideal
    /// bell's is.
    pub fn is_mirror_symmetric(&self) -> bool {
        self.pivot_offset == 0.0 && self.phi_max_skew == 0.0
    }

    /// Check the offset and friction (the skew is checked with φ_max by
    /// [`Bell::validate`](crate::bell::Bell::validate)).
    pub fn validate(&self) -> Result<(), ParamError> {
        if !self.pivot_offset.is_finite() {
            return Err(ParamError {
                field: "pivot_offset_m",
                value: self.pivot_offset,
                allowed: "a finite number (may be negative)",
            });
        }
        if !self.phi_max_skew.is_finite() {
            return Err(ParamError {
                field: "phi_max_hand_deg",
                value: self.phi_max_skew.to_degrees(),
                allowed: "a finite angle",
            });
        }
        self.friction.validate()
    }
}

/// The contact angles of the two sides (rad, both positive), from φ_max and
/// the skew: (hand side, back side).
pub fn contact_angles(phi_max: f64, skew: f64) -> (f64, f64) {
    (phi_max + skew, phi_max - skew)
}

/// φ_max and the skew (rad) from the two contact angles (rad).
pub fn from_contact_angles(phi_max_hand: f64, phi_max_back: f64) -> (f64, f64) {
    (0.5 * (phi_max_hand + phi_max_back), 0.5 * (phi_max_hand - phi_max_back))
}

/// The skew (rad) that a tape measure's ball-to-rim gaps give, for a ball
/// whose centre hangs `ball_below_pivot` (m) below the clapper pivot and a
/// bell whose mean contact angle is `phi_max` (rad). `gap_hand` and
/// `gap_back` are in metres, measured with the bell down and the clapper
/// hanging still.
///
/// The ball meets the bell where its centre has moved sideways by the gap:
/// ℓ sin φ = g. A gap difference Δg = g_hand − g_back therefore tilts the
/// two contact angles apart by Δg / (ℓ cos φ_max) (to first order: a few
/// millimetres in a gap of a hundred); the mean contact angle is the
/// bell's φ_max, which the tape reads less well than the difference (the
/// bell's flare and the ball's shape enter the absolute reading, not the
/// difference).
pub fn skew_from_gaps(gap_hand: f64, gap_back: f64, ball_below_pivot: f64, phi_max: f64) -> Result<f64, ParamError> {
    for (field, value) in [("gap_hand_mm", gap_hand * 1e3), ("gap_back_mm", gap_back * 1e3)] {
        if !(value.is_finite() && value >= 0.0) {
            return Err(ParamError {
                field,
                value,
                allowed: "a finite length >= 0",
            });
        }
    }
    if !(ball_below_pivot.is_finite() && ball_below_pivot > 0.0) {
        return Err(ParamError {
            field: "ball_below_pivot_m",
            value: ball_below_pivot,
            allowed: "a finite length > 0",
        });
    }
    let skew = 0.5 * (gap_hand - gap_back) / (ball_below_pivot * phi_max.cos());
    // Gaps that would tip a contact angle past 0 or 90 deg are named as
    // the gaps given, not as an angle the user never typed.
    let (hand, back) = contact_angles(phi_max, skew);
    let right = |a: f64| a > 0.0 && a < std::f64::consts::FRAC_PI_2;
    if !(right(hand) && right(back)) {
        // In mm as given (to a nanometre: the m -> mm product is not exact).
        let mm = |g: f64| (g * 1e9).round() / 1e6;
        let (field, value) = if gap_hand > gap_back {
            ("gap_hand_mm", mm(gap_hand))
        } else {
            ("gap_back_mm", mm(gap_back))
        };
        return Err(ParamError {
            field,
            value,
            allowed: "a gap that, beside the other and the ball's depth below the pivot, keeps both contact \
                      angles between 0 and 90 deg (the two gaps differ by a few mm on a real bell)",
        });
    }
    Ok(skew)
}

/// The ball's sideways movement (m, toward the back side) that changes the
/// skew by `d_skew` (rad): the inverse of [`skew_from_gaps`]. Moving the ball
/// x toward the back side closes the back gap and opens the hand gap by x.
pub fn ball_shift_for_skew(d_skew: f64, ball_below_pivot: f64, phi_max: f64) -> f64 {
    d_skew * ball_below_pivot * phi_max.cos()
}

/// Which kind of friction a swing-decay timing is taken to measure: the
/// count alone cannot tell them apart (a viscous loss shrinks the swing by
/// a constant ratio, a Coulomb loss by a constant angle), so the user says.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case"))]
pub enum SwingLoss {
    /// Viscous damping (oil, grease): the default, as it needs no amplitude.
    #[default]
    Viscous,
    /// Coulomb friction (dry or plain bearings).
    Coulomb,
}

/// A pendulum's small swing as the tower times it: `swings_to_halve` swings
/// (one swing is one stroke, half a period) for the amplitude to halve.
/// `inertia` (kg m²) and `stiffness` (N m/rad, the gravity torque per radian
/// of a small swing) describe the pendulum: the bell with its clapper tied
/// (I = W₁₁, K = (M a + m r + m b) g), or the clapper in a still bell
/// (I = I_c, K = m b g).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SwingDecay {
    /// Swings (strokes, half periods) for the amplitude to halve.
    pub swings_to_halve: f64,
    /// Moment of inertia about the pivot (kg m²).
    pub inertia: f64,
    /// Gravity stiffness of a small swing (N m/rad).
    pub stiffness: f64,
}

impl SwingDecay {
    fn check(&self) -> Result<(), ParamError> {
        if !(self.swings_to_halve.is_finite() && self.swings_to_halve > 0.0) {
            return Err(ParamError {
                field: "swings_to_halve",
                value: self.swings_to_halve,
                allowed: "a finite number of swings > 0",
            });
        }
        Ok(())
    }

    /// The friction that halves the swing in that many swings, all the loss
    /// taken as `loss`: c (N m s/rad) for viscous, τ (N m) for Coulomb, which
    /// needs the swing's starting `amplitude` (rad).
    pub fn friction(&self, loss: SwingLoss, amplitude: Option<f64>) -> Result<f64, ParamError> {
        match loss {
            SwingLoss::Viscous => self.viscous(),
            SwingLoss::Coulomb => self.coulomb(amplitude.ok_or(ParamError {
                field: "swing_amplitude_deg",
                value: f64::NAN,
                allowed: "given with swing_loss = coulomb: the amplitude the count started at",
            })?),
        }
    }

    /// The viscous damping (N m s/rad) that halves the swing in that many
    /// swings, all the loss taken as viscous: the amplitude decays as
    /// exp(−c t / 2I), and a swing lasts π √(I/K) (light damping).
    pub fn viscous(&self) -> Result<f64, ParamError> {
        self.check()?;
        let swing = PI * (self.inertia / self.stiffness).sqrt();
        Ok(2.0 * self.inertia * LN_2 / (self.swings_to_halve * swing))
    }

    /// The Coulomb torque (N m) that halves a swing of starting amplitude
    /// `amplitude` (rad) in that many swings, all the loss taken as Coulomb:
    /// each swing loses 2τ/K of amplitude (4τ/K per period), linearly.
    pub fn coulomb(&self, amplitude: f64) -> Result<f64, ParamError> {
        self.check()?;
        // A small swing's count: the decay is taken as linear in the angle.
        if !(amplitude.is_finite() && amplitude > 0.0 && amplitude <= FRAC_PI_2) {
            return Err(ParamError {
                field: "swing_amplitude_deg",
                value: amplitude.to_degrees(),
                allowed: "a swing's amplitude above 0 and at most 90 deg (the swing the count started at)",
            });
        }
        Ok(self.stiffness * 0.5 * amplitude / (2.0 * self.swings_to_halve))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn angles_round_trip_and_gaps_give_the_skew() {
        let (h, b) = contact_angles(0.5, 0.01);
        let (m, k) = from_contact_angles(h, b);
        assert!((m - 0.5).abs() < 1e-15 && (k - 0.01).abs() < 1e-15);
        // 6 mm more gap on the hand side, ball 0.8 m below the pivot.
        let skew = skew_from_gaps(0.103, 0.097, 0.8, 0.5).unwrap();
        assert!((skew - 0.003 / (0.8 * 0.5f64.cos())).abs() < 1e-15);
        assert!((ball_shift_for_skew(skew, 0.8, 0.5) - 0.003).abs() < 1e-15);
        assert!(skew_from_gaps(0.1, 0.1, 0.0, 0.5).is_err());
        assert!(skew_from_gaps(-0.1, 0.1, 0.8, 0.5).is_err());
    }

    #[test]
    fn decay_inversions_halve_the_swing() {
        let s = SwingDecay {
            swings_to_halve: 40.0,
            inertia: 2.0,
            stiffness: 50.0,
        };
        let c = s.viscous().unwrap();
        let t = 40.0 * PI * (2.0f64 / 50.0).sqrt();
        assert!(((-c * t / 4.0).exp() - 0.5).abs() < 1e-12);
        let tau = s.coulomb(0.1).unwrap();
        assert!((0.1 - 40.0 * 2.0 * tau / 50.0 - 0.05).abs() < 1e-15);
        assert!(SwingDecay {
            swings_to_halve: 0.0,
            ..s
        }
        .viscous()
        .is_err());
    }
}
