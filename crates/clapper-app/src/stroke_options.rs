//! The options every request that runs strokes takes (`clapper simulate`,
//! `clapper chart`, their JSON), defined once: θ0, R and R2, the contact
//! law and its stiffness, the integrator and its tolerance, and their
//! defaults.
//!
//! A request is one flat JSON object that refuses unknown keys, which
//! serde's `flatten` cannot give; so the shared fields are spliced into
//! each request by the crate's `with_stroke_options!` macro, and read back as a
//! [`SimConfig`] by [`StrokeOptions::config`].

use clapper_core::prelude::*;
use clapper_core::stroke::DEFAULT_STIFFNESS;

use crate::AppError;
pub use clapper_io::hanging_input::HangingInput;

pub use clapper_core::stroke::{DEFAULT_RESTITUTION, DEFAULT_THETA0_DEG};

pub(crate) fn default_theta0() -> f64 {
    DEFAULT_THETA0_DEG
}

/// The shared options of a request, borrowed out of it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StrokeOptions {
    /// θ0 (deg).
    pub theta0: f64,
    /// R; unset: [`DEFAULT_RESTITUTION`].
    pub restitution: Option<f64>,
    /// R2, if given apart from R.
    pub restitution_later: Option<f64>,
    /// What the double strike's amplitude ratio compares, if named.
    pub strike_amplitude: Option<StrikeAmplitude>,
    /// The contact law, if named.
    pub contact: Option<ContactModel>,
    /// The penalty law's stiffness k (N m/rad), if given.
    pub stiffness: Option<f64>,
    /// Integrator tolerance, relative and absolute.
    pub rtol: Option<f64>,
    /// The integrator, if named.
    pub integrator: Option<Integrator>,
    /// How the bell departs from the ideal, where given.
    pub hanging: HangingInput,
}

impl StrokeOptions {
    /// The simulation settings these options give (not yet validated: the
    /// caller validates with whatever else it sets). A stiffness alone
    /// means the penalty law.
    pub fn config(&self) -> Result<SimConfig, AppError> {
        let (contact, stiffness) = match (self.contact, self.stiffness) {
            (Some(ContactModel::Impact), Some(_)) => {
                return Err(AppError::Request(
                    "stiffness applies to the penalty model; drop it or choose contact penalty".into(),
                ))
            }
            (Some(ContactModel::Impact), None) | (None, None) => (ContactModel::Impact, DEFAULT_STIFFNESS),
            (_, k) => (ContactModel::Penalty, k.unwrap_or(DEFAULT_STIFFNESS)),
        };
        let mut cfg = SimConfig {
            theta0: self.theta0.to_radians(),
            restitution: self.restitution.unwrap_or(DEFAULT_RESTITUTION),
            restitution_later: self.restitution_later,
            strike_amplitude: self.strike_amplitude.unwrap_or_default(),
            contact,
            stiffness,
            integrator: self.integrator.unwrap_or_default(),
            ..SimConfig::default()
        };
        if let Some(r) = self.rtol {
            if !(r.is_finite() && (1e-14..=1e-2).contains(&r)) {
                return Err(AppError::Request(format!(
                    "rtol {} is out of range: 1e-14 to 1e-2",
                    clapper_core::bell::readable(r)
                )));
            }
            cfg.ode.rtol = r;
            cfg.ode.atol = r;
        }
        Ok(cfg)
    }
}

/// Words for a configuration's contact law, for titles.
pub fn contact_words(cfg: &SimConfig) -> String {
    match cfg.contact {
        ContactModel::Impact => "impact".into(),
        ContactModel::Penalty => format!("penalty (k = {:e} N m/rad)", cfg.stiffness),
    }
}

/// Declares a request struct with the stroke options appended to its own
/// fields (with their JSON names, defaults and docs), `stroke_options()` to
/// read them, and `Default` (every field's serde default: the request `{}`).
#[macro_export]
macro_rules! with_stroke_options {
    ($(#[$meta:meta])* pub struct $name:ident { $($(#[$fmeta:meta])* pub $field:ident : $ty:ty,)* }) => {
        $(#[$meta])*
        pub struct $name {
            $($(#[$fmeta])* pub $field: $ty,)*
            /// Starting angle of the bell at rest (deg, 0 < θ0 < 180).
            #[serde(default = "crate::stroke_options::default_theta0")]
            pub theta0: f64,
            /// Stronge's energy coefficient of restitution R (0 < R ≤ 1)
            /// of the first impact on a side (the strike); unset: the bell
            /// file's, else 0.2.
            #[serde(default)]
            pub restitution: Option<f64>,
            /// R2: the restitution of the bounces after the first impact
            /// on a side (0 < R2 ≤ 1); unset means R2 = R.
            #[serde(default, skip_serializing_if = "Option::is_none", alias = "restitution-later")]
            pub restitution_later: Option<f64>,
            /// What the double strike's amplitude ratio A compares: rate
            /// (the clapper's, the default), impulse or vibration
            /// (docs/model.md §4.1).
            #[serde(default, skip_serializing_if = "Option::is_none", alias = "strike-amplitude")]
            pub strike_amplitude: Option<clapper_core::stroke::StrikeAmplitude>,
            /// Contact model (default impact; a stiffness implies penalty).
            #[serde(default)]
            pub contact: Option<clapper_core::stroke::ContactModel>,
            /// Contact stiffness k of the penalty model (N m/rad).
            #[serde(default)]
            pub stiffness: Option<f64>,
            /// Integrator tolerance, relative and absolute (default 3e-8).
            #[serde(default)]
            pub rtol: Option<f64>,
            /// Integrator (default Taylor).
            #[serde(default)]
            pub integrator: Option<clapper_core::stroke::Integrator>,
            /// Sideways offset d of the clapper pivot (m), + toward the side
            /// the clapper rests on before a handstroke; unset: the bell's (0).
            #[serde(default, skip_serializing_if = "Option::is_none", alias = "pivot-offset")]
            pub pivot_offset: Option<f64>,
            /// Contact angle of the side struck at handstroke (deg).
            #[serde(default, skip_serializing_if = "Option::is_none", alias = "phi-max-hand")]
            pub phi_max_hand: Option<f64>,
            /// Contact angle of the side struck at backstroke (deg).
            #[serde(default, skip_serializing_if = "Option::is_none", alias = "phi-max-back")]
            pub phi_max_back: Option<f64>,
            /// Tape reading: ball-to-rim gap on the hand side, bell down (mm).
            #[serde(default, skip_serializing_if = "Option::is_none", alias = "gap-hand")]
            pub gap_hand: Option<f64>,
            /// Tape reading: ball-to-rim gap on the back side (mm).
            #[serde(default, skip_serializing_if = "Option::is_none", alias = "gap-back")]
            pub gap_back: Option<f64>,
            /// The ball's centre below the clapper pivot (m), with the gaps.
            #[serde(default, skip_serializing_if = "Option::is_none", alias = "ball-below-pivot")]
            pub ball_below_pivot: Option<f64>,
            /// Viscous damping at the bell's bearings (N m s/rad).
            #[serde(default, skip_serializing_if = "Option::is_none", alias = "bell-damping")]
            pub bell_damping: Option<f64>,
            /// Coulomb friction torque at the bell's bearings (N m).
            #[serde(default, skip_serializing_if = "Option::is_none", alias = "bell-friction")]
            pub bell_friction: Option<f64>,
            /// Viscous damping at the clapper's pivot (N m s/rad).
            #[serde(default, skip_serializing_if = "Option::is_none", alias = "clapper-damping")]
            pub clapper_damping: Option<f64>,
            /// Coulomb friction torque at the clapper's pivot (N m).
            #[serde(default, skip_serializing_if = "Option::is_none", alias = "clapper-friction")]
            pub clapper_friction: Option<f64>,
            /// Swings (strokes) for the bell's small swing, clapper tied,
            /// to halve: sets the bell's damping or friction.
            #[serde(default, skip_serializing_if = "Option::is_none", alias = "bell-swings-to-halve")]
            pub bell_swings_to_halve: Option<f64>,
            /// Swings for the clapper's small swing in a still bell to halve.
            #[serde(default, skip_serializing_if = "Option::is_none", alias = "clapper-swings-to-halve")]
            pub clapper_swings_to_halve: Option<f64>,
            /// What those timings measure: viscous (default) or coulomb.
            #[serde(default, skip_serializing_if = "Option::is_none", alias = "swing-loss")]
            pub swing_loss: Option<clapper_core::hanging::SwingLoss>,
            /// The timed swing's starting amplitude (deg), for coulomb.
            #[serde(default, skip_serializing_if = "Option::is_none", alias = "swing-amplitude")]
            pub swing_amplitude: Option<f64>,
        }

        impl Default for $name {
            fn default() -> Self {
                serde_json::from_str("{}").expect("every field has a default")
            }
        }

        impl $name {
            /// The options shared by every request that runs strokes.
            pub fn stroke_options(&self) -> $crate::stroke_options::StrokeOptions {
                $crate::stroke_options::StrokeOptions {
                    theta0: self.theta0,
                    restitution: self.restitution,
                    restitution_later: self.restitution_later,
                    strike_amplitude: self.strike_amplitude,
                    contact: self.contact,
                    stiffness: self.stiffness,
                    rtol: self.rtol,
                    integrator: self.integrator,
                    hanging: $crate::stroke_options::HangingInput {
                        pivot_offset_m: self.pivot_offset,
                        phi_max_hand_deg: self.phi_max_hand,
                        phi_max_back_deg: self.phi_max_back,
                        gap_hand_mm: self.gap_hand,
                        gap_back_mm: self.gap_back,
                        ball_below_pivot_m: self.ball_below_pivot,
                        bell_damping: self.bell_damping,
                        bell_friction: self.bell_friction,
                        clapper_damping: self.clapper_damping,
                        clapper_friction: self.clapper_friction,
                        bell_swings_to_halve: self.bell_swings_to_halve,
                        clapper_swings_to_halve: self.clapper_swings_to_halve,
                        swing_loss: self.swing_loss,
                        swing_amplitude_deg: self.swing_amplitude,
                    },
                }
            }
        }
    };
}

pub(crate) use with_stroke_options;

#[cfg(test)]
mod tests {
    use super::*;
    use clapper_core::chart::Styles;

    fn names_are_serde_forms<T>()
    where
        T: Choice + serde::Serialize + serde::de::DeserializeOwned + PartialEq + std::fmt::Debug + std::fmt::Display,
    {
        for &v in T::ALL {
            let json = serde_json::to_string(&v).unwrap();
            assert_eq!(json, format!("\"{}\"", v.name()));
            assert_eq!(serde_json::from_str::<T>(&json).unwrap(), v);
            assert_eq!(v.to_string(), v.name());
        }
    }

    /// The command line lists a choice by `name()`, JSON and files spell
    /// it by serde: they must agree.
    #[test]
    fn every_choice_is_spelt_alike_everywhere() {
        names_are_serde_forms::<Style>();
        names_are_serde_forms::<Protocol>();
        names_are_serde_forms::<ContactModel>();
        names_are_serde_forms::<Integrator>();
        names_are_serde_forms::<StrikeAmplitude>();
        names_are_serde_forms::<Styles>();
    }

    #[test]
    fn a_stiffness_alone_means_the_penalty_law_and_impact_refuses_one() {
        let opts = |contact, stiffness| StrokeOptions {
            theta0: 171.0,
            restitution: None,
            restitution_later: None,
            strike_amplitude: None,
            contact,
            stiffness,
            rtol: None,
            integrator: None,
            hanging: HangingInput::default(),
        };
        let cfg = opts(None, Some(3e6)).config().unwrap();
        assert_eq!((cfg.contact, cfg.stiffness), (ContactModel::Penalty, 3e6));
        assert_eq!(opts(None, None).config().unwrap(), SimConfig::default());
        assert!(opts(Some(ContactModel::Impact), Some(1e6)).config().is_err());
    }
}
