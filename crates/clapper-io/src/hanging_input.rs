//! A bell's departures from the ideal (pivot offset, unequal contact
//! angles, friction) as a user gives them, in a bell file or a request:
//! the contact angles directly or as a tape measure's ball-to-rim gaps
//! (docs/model.md §10). Every field is optional; given ones override the
//! bell's own.

use clapper_core::bell::{Bell, ParamError};
use clapper_core::hanging::{from_contact_angles, skew_from_gaps, SwingDecay, SwingLoss};

/// The hanging fields, in the units users give them.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct HangingInput {
    /// d: sideways offset of the clapper pivot (m), + toward the back side
    /// (where the clapper rests before a handstroke).
    pub pivot_offset_m: Option<f64>,
    /// Contact angle of the hand side, the side struck at handstroke ringing right (deg).
    pub phi_max_hand_deg: Option<f64>,
    /// Contact angle of the back side (deg).
    pub phi_max_back_deg: Option<f64>,
    /// Ball-to-rim gap on the hand side, bell down, clapper hanging (mm).
    pub gap_hand_mm: Option<f64>,
    /// The same on the back side (mm).
    pub gap_back_mm: Option<f64>,
    /// Distance of the ball's centre below the clapper pivot (m).
    pub ball_below_pivot_m: Option<f64>,
    /// c_b (N m s/rad).
    pub bell_damping: Option<f64>,
    /// τ_b (N m).
    pub bell_friction: Option<f64>,
    /// c_c (N m s/rad).
    pub clapper_damping: Option<f64>,
    /// τ_c (N m).
    pub clapper_friction: Option<f64>,
    /// King's first timing: swings (strokes) for a small swing of the bell,
    /// clapper tied, to halve; sets c_b or τ_b as `swing_loss` says.
    pub bell_swings_to_halve: Option<f64>,
    /// King's second: swings for the clapper's small swing in a still bell
    /// to halve; sets c_c or τ_c.
    pub clapper_swings_to_halve: Option<f64>,
    /// What the timings measure (default viscous).
    pub swing_loss: Option<SwingLoss>,
    /// The swing's amplitude when the count began (deg); Coulomb needs it.
    pub swing_amplitude_deg: Option<f64>,
}

/// A timing's error named by the joint's key (the core names it
/// `swings_to_halve` for either joint).
fn named(e: ParamError, key: &'static str) -> ParamError {
    if e.field == "swings_to_halve" {
        ParamError { field: key, ..e }
    } else {
        e
    }
}

impl HangingInput {
    /// Whether nothing is given.
    pub fn is_empty(&self) -> bool {
        *self == HangingInput::default()
    }

    /// `bell` with the given fields applied, validated.
    pub fn apply(&self, mut bell: Bell) -> Result<Bell, ParamError> {
        let mut h = bell.hanging;
        if let Some(d) = self.pivot_offset_m {
            h.pivot_offset = d;
        }
        let angles = self.phi_max_hand_deg.is_some() || self.phi_max_back_deg.is_some();
        let gaps = [self.gap_hand_mm, self.gap_back_mm, self.ball_below_pivot_m];
        if gaps.iter().any(Option::is_some) {
            if angles {
                return Err(ParamError {
                    field: "gap_hand_mm",
                    value: self.gap_hand_mm.unwrap_or(f64::NAN),
                    allowed: "either the tape gaps or the contact angles of the two sides, not both",
                });
            }
            let [Some(hand), Some(back), Some(ball)] = gaps else {
                return Err(ParamError {
                    field: "gap_hand_mm",
                    value: self.gap_hand_mm.unwrap_or(f64::NAN),
                    allowed: "the two gaps and the ball's depth below the clapper pivot go together: all three or none",
                });
            };
            h.phi_max_skew = skew_from_gaps(hand * 1e-3, back * 1e-3, ball, bell.phi_max)?;
        } else if angles {
            let (hand0, back0) = bell.contact_angles();
            let hand = self.phi_max_hand_deg.map_or(hand0, f64::to_radians);
            let back = self.phi_max_back_deg.map_or(back0, f64::to_radians);
            for (field, v) in [("phi_max_hand_deg", hand), ("phi_max_back_deg", back)] {
                if !(v.is_finite() && v > 0.0 && v < std::f64::consts::FRAC_PI_2) {
                    return Err(ParamError {
                        field,
                        value: v.to_degrees(),
                        allowed: "between 0 and 90 deg, exclusive",
                    });
                }
            }
            (bell.phi_max, h.phi_max_skew) = from_contact_angles(hand, back);
            // Equal angles are exactly the symmetric bell.
            if hand == back {
                (bell.phi_max, h.phi_max_skew) = (hand, 0.0);
            }
        }
        let f = &mut h.friction;
        for (given, field) in [
            (self.bell_damping, &mut f.bell_damping),
            (self.bell_friction, &mut f.bell_friction),
            (self.clapper_damping, &mut f.clapper_damping),
            (self.clapper_friction, &mut f.clapper_friction),
        ] {
            if let Some(v) = given {
                *field = v;
            }
        }
        bell.hanging = h;
        self.apply_swing_timings(&mut bell)?;
        bell.validate().map_err(|e| self.timed_cause(e))?;
        Ok(bell)
    }

    /// A loss at a joint out of range, said as the swings-to-halve timing
    /// it came from when it came from one (the user gave the timing, not
    /// the damping it stands for).
    fn timed_cause(&self, e: ParamError) -> ParamError {
        const TOO_QUICK: &str =
            "more swings: a decay as quick as this needs a loss at the joint that stops it swinging";
        let bell = matches!(e.field, "bell_damping_n_m_s" | "bell_friction_n_m");
        let clapper = matches!(e.field, "clapper_damping_n_m_s" | "clapper_friction_n_m");
        match (self.bell_swings_to_halve, self.clapper_swings_to_halve) {
            (Some(n), _) if bell && self.bell_damping.is_none() && self.bell_friction.is_none() => ParamError {
                field: "bell_swings_to_halve",
                value: n,
                allowed: TOO_QUICK,
            },
            (_, Some(n)) if clapper && self.clapper_damping.is_none() && self.clapper_friction.is_none() => {
                ParamError {
                    field: "clapper_swings_to_halve",
                    value: n,
                    allowed: TOO_QUICK,
                }
            }
            _ => e,
        }
    }
}

impl HangingInput {
    /// Friction from the swings-to-halve timings, computed on the bell as
    /// otherwise given (its inertia and offset); each timing replaces the
    /// one friction parameter it measures, and may not be given with it.
    fn apply_swing_timings(&self, bell: &mut Bell) -> Result<(), ParamError> {
        let loss = self.swing_loss.unwrap_or_default();
        let timed = self.bell_swings_to_halve.is_some() || self.clapper_swings_to_halve.is_some();
        if !timed {
            if self.swing_loss.is_some() || self.swing_amplitude_deg.is_some() {
                // Named by what was given: the loss (a word, no value) or
                // the amplitude.
                let (field, value) = match (self.swing_loss, self.swing_amplitude_deg) {
                    (None, Some(a)) => ("swing_amplitude_deg", a),
                    _ => ("swing_loss", f64::NAN),
                };
                return Err(ParamError {
                    field,
                    value,
                    allowed: "only with a swings-to-halve timing of the bell or of the clapper",
                });
            }
            return Ok(());
        }
        let amplitude = self.swing_amplitude_deg.map(f64::to_radians);
        if loss == SwingLoss::Viscous && amplitude.is_some() {
            return Err(ParamError {
                field: "swing_amplitude_deg",
                value: self.swing_amplitude_deg.unwrap_or(f64::NAN),
                allowed: "only with a Coulomb swing loss (a viscous decay needs no amplitude)",
            });
        }
        let clash = |field, damping: Option<f64>, friction: Option<f64>| {
            if damping.is_some() || friction.is_some() {
                Err(ParamError {
                    field,
                    value: damping.or(friction).unwrap_or(f64::NAN),
                    allowed: "not with the swings-to-halve timing of the same joint: give one",
                })
            } else {
                Ok(())
            }
        };
        if let Some(n) = self.bell_swings_to_halve {
            clash("bell_swings_to_halve", self.bell_damping, self.bell_friction)?;
            let v = SwingDecay::bell_tied(bell, n)
                .friction(loss, amplitude)
                .map_err(|e| named(e, "bell_swings_to_halve"))?;
            let f = &mut bell.hanging.friction;
            match loss {
                SwingLoss::Viscous => f.bell_damping = v,
                SwingLoss::Coulomb => f.bell_friction = v,
            }
        }
        if let Some(n) = self.clapper_swings_to_halve {
            clash("clapper_swings_to_halve", self.clapper_damping, self.clapper_friction)?;
            let v = SwingDecay::clapper_in_still_bell(bell, n)
                .friction(loss, amplitude)
                .map_err(|e| named(e, "clapper_swings_to_halve"))?;
            let f = &mut bell.hanging.friction;
            match loss {
                SwingLoss::Viscous => f.clapper_damping = v,
                SwingLoss::Coulomb => f.clapper_friction = v,
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nothing_given_is_the_bell_itself_and_angles_or_gaps_set_the_skew() {
        let lab = Bell::lab();
        assert_eq!(HangingInput::default().apply(lab).unwrap(), lab);
        let b = HangingInput {
            phi_max_hand_deg: Some(27.0),
            phi_max_back_deg: Some(25.0),
            ..Default::default()
        }
        .apply(lab)
        .unwrap();
        let (h, k) = b.contact_angles();
        assert!((h.to_degrees() - 27.0).abs() < 1e-12 && (k.to_degrees() - 25.0).abs() < 1e-12);
        let g = HangingInput {
            gap_hand_mm: Some(103.0),
            gap_back_mm: Some(97.0),
            ball_below_pivot_m: Some(0.3),
            ..Default::default()
        }
        .apply(lab)
        .unwrap();
        assert!(g.hanging.phi_max_skew > 0.0 && g.phi_max == lab.phi_max);
        let half = HangingInput {
            gap_hand_mm: Some(103.0),
            ..Default::default()
        };
        assert_eq!(half.apply(lab).unwrap_err().field, "gap_hand_mm");
        let neg = HangingInput {
            clapper_friction: Some(-1.0),
            ..Default::default()
        };
        assert_eq!(neg.apply(lab).unwrap_err().field, "clapper_friction_n_m");
    }

    #[test]
    fn swing_timings_set_the_friction_they_measure_and_refuse_clashes() {
        let lab = Bell::lab();
        let timed = |loss, amplitude| HangingInput {
            bell_swings_to_halve: Some(30.0),
            clapper_swings_to_halve: Some(10.0),
            swing_loss: loss,
            swing_amplitude_deg: amplitude,
            ..Default::default()
        };
        let v = timed(None, None).apply(lab).unwrap().hanging.friction;
        assert_eq!(v.bell_damping, SwingDecay::bell_tied(&lab, 30.0).viscous().unwrap());
        assert_eq!(
            v.clapper_damping,
            SwingDecay::clapper_in_still_bell(&lab, 10.0).viscous().unwrap()
        );
        assert_eq!((v.bell_friction, v.clapper_friction), (0.0, 0.0));
        let c = timed(Some(SwingLoss::Coulomb), Some(8.0))
            .apply(lab)
            .unwrap()
            .hanging
            .friction;
        let want = SwingDecay::bell_tied(&lab, 30.0).coulomb(8f64.to_radians()).unwrap();
        assert_eq!((c.bell_friction, c.bell_damping), (want, 0.0));
        let err = |h: HangingInput| h.apply(lab).unwrap_err().field;
        assert_eq!(err(timed(Some(SwingLoss::Coulomb), None)), "swing_amplitude_deg");
        assert_eq!(err(timed(None, Some(8.0))), "swing_amplitude_deg");
        assert_eq!(
            err(HangingInput {
                bell_damping: Some(1.0),
                ..timed(None, None)
            }),
            "bell_swings_to_halve"
        );
        assert_eq!(
            err(HangingInput {
                swing_loss: Some(SwingLoss::Coulomb),
                ..Default::default()
            }),
            "swing_loss"
        );
    }
}
