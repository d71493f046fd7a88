//! What a stroke simulation needs besides the bell: the integrator and
//! its options, the contact law's coefficients and the limits of a
//! stroke; and the errors a simulation can end in.

use std::f64::consts::PI;

use crate::bell::ParamError;
use crate::contact::{ContactLaw, ContactModel, Restitution, DEFAULT_STIFFNESS};
use crate::ode::{OdeError, Options, Taylor};

use super::impact::StrikeAmplitude;

/// Which integrator a stroke uses; each has its options in [`SimConfig`]
/// (`taylor`, and `ode` for both).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case"))]
pub enum Integrator {
    /// Taylor series of the bell's own equations ([`TaylorOptions`]). The
    /// default: on the paper's chart 2.4 times as fast as Dormand–Prince at
    /// the same tolerance, with a first strike angle eight times closer to
    /// the reference. With the impact law, a resting phase that starts from
    /// rest (the stroke's first) is not integrated but solved in closed
    /// form ([`crate::swing`]): the bell is then a rigid pendulum.
    #[default]
    Taylor,
    /// Dormand–Prince 5(4) with the step limit of [`Options::h_max`]: the
    /// general-purpose method, kept as the check on the Taylor one.
    Dopri5,
}

/// Options of the Taylor integrator.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct TaylorOptions {
    /// Order of the expansion, 2 ..= 24 ([`crate::ode::taylor::MAX_ORDER`]).
    /// Default 12, chosen by measurement (`cargo run --release -p
    /// clapper-core --example tolerance`): orders 10 to 16 cost about the
    /// same; lower orders take many more steps.
    pub order: usize,
    /// Largest step (s). Default 0.25 s: every event function is a
    /// polynomial in each step, ruled out by a bound or checked at 16
    /// points, so a step stays a fraction of a swing.
    pub h_max: f64,
}

impl Default for TaylorOptions {
    fn default() -> Self {
        Self { order: 12, h_max: 0.25 }
    }
}

/// What a stroke simulation needs besides the bell.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct SimConfig {
    /// θ0: the angle the bell starts from, at rest (rad). Default 171 deg,
    /// the paper's: close to the balance, far enough that the bell falls.
    pub theta0: f64,
    /// R: Stronge's energy coefficient of restitution, in (0, 1], of the
    /// first impact on a side (the strike). Default 0.2, the paper's value
    /// for its first charts.
    pub restitution: f64,
    /// R2: the restitution of every bounce that follows an impact on the
    /// same side, in (0, 1]; `None` (the default) means R2 = R. The
    /// paper's drops (Section 3.2, Fig 8) show the first impact losing far
    /// more than the later ones.
    #[cfg_attr(feature = "serde", serde(default, skip_serializing_if = "Option::is_none"))]
    pub restitution_later: Option<f64>,
    /// What the double strike's amplitude ratio A compares. Default
    /// [`StrikeAmplitude::Rate`], the paper's (docs/model.md §4.1).
    #[cfg_attr(feature = "serde", serde(default, skip_serializing_if = "StrikeAmplitude::is_rate"))]
    pub strike_amplitude: StrikeAmplitude,
    /// The contact law. Default [`ContactModel::Impact`].
    pub contact: ContactModel,
    /// Penalty law: the contact stiffness k (N m/rad). Default
    /// [`DEFAULT_STIFFNESS`], the paper's 1e6.
    pub stiffness: f64,
    /// Impact model: when the next flight of a bouncing clapper would be
    /// shorter than this (s), it comes to rest. Default 1e-7 s: far below
    /// anything audible or visible in a trace, and reached after a few tens
    /// of bounces, so the Zeno sequence costs little.
    pub rest_flight_time: f64,
    /// Integrator tolerances and step budget.
    pub ode: Options,
    /// Which integrator. Default [`Integrator::Taylor`].
    pub integrator: Integrator,
    /// The Taylor integrator's options.
    pub taylor: TaylorOptions,
    /// Most events (impacts, lift-offs, contact switches) in one stroke.
    /// Default 100,000: R = 0.99 needs a few thousand bounces to come to rest.
    pub max_events: u32,
    /// Longest stroke, in small-swing periods T_b of the bell. Default 20; a
    /// full-circle swing from 179.9 deg lasts under 3 T_b.
    pub max_stroke_periods: f64,
}

/// The default starting angle θ0 (deg): a bell "fully up", as the
/// paper's charts: close to the balance, far enough that the bell falls.
pub const DEFAULT_THETA0_DEG: f64 = 171.0;
/// The default energy coefficient of restitution R: the paper's value for
/// its first charts (Section 3.2 measured 0.05 to 0.12 by (21) and (23)).
pub const DEFAULT_RESTITUTION: f64 = 0.2;

impl Default for SimConfig {
    fn default() -> Self {
        Self {
            theta0: DEFAULT_THETA0_DEG.to_radians(),
            restitution: DEFAULT_RESTITUTION,
            restitution_later: None,
            strike_amplitude: StrikeAmplitude::Rate,
            contact: ContactModel::Impact,
            stiffness: DEFAULT_STIFFNESS,
            rest_flight_time: 1e-7,
            ode: Options::default(),
            integrator: Integrator::default(),
            taylor: TaylorOptions::default(),
            max_events: 100_000,
            max_stroke_periods: 20.0,
        }
    }
}

impl SimConfig {
    /// R and R2 as the contact law takes them.
    pub fn restitution_pair(&self) -> Restitution {
        Restitution {
            first: self.restitution,
            later: self.restitution_later.unwrap_or(self.restitution),
        }
    }

    /// The configured contact law.
    pub fn contact_law(&self) -> Box<dyn ContactLaw> {
        self.contact
            .law(self.restitution_pair(), self.stiffness, self.rest_flight_time)
    }

    /// Check the user-settable fields against docs/model.md §1 and §3.
    pub fn validate(&self) -> Result<(), ParamError> {
        if !(self.theta0.is_finite() && self.theta0 > 0.0 && self.theta0 < PI) {
            return Err(ParamError {
                field: "theta0_deg",
                value: self.theta0.to_degrees(),
                allowed: "between 0 and 180 deg, exclusive",
            });
        }
        let r = self.restitution_pair();
        for (field, value) in [("restitution", r.first), ("restitution_later", r.later)] {
            if !(value.is_finite() && value > 0.0 && value <= 1.0) {
                return Err(ParamError {
                    field,
                    value,
                    allowed: "greater than 0 and at most 1",
                });
            }
        }
        // 1e2: a spring that yields a radian under 100 N m holds no
        // clapper off the bell; 1e12: past it the resting deflection is a
        // few units in the last place of the clapper angle (docs/model.md §3.2).
        if self.contact == ContactModel::Penalty && !(1e2..=1e12).contains(&self.stiffness) {
            return Err(ParamError {
                field: "stiffness_n_m_per_rad",
                value: self.stiffness,
                allowed: "from 1e2 to 1e12 N m/rad",
            });
        }
        if self.integrator == Integrator::Taylor {
            if Taylor::<4>::check_order(self.taylor.order).is_err() {
                return Err(ParamError {
                    field: "taylor_order",
                    value: self.taylor.order as f64,
                    allowed: "2 to 24 (ode::taylor::MAX_ORDER)",
                });
            }
            if !(self.taylor.h_max.is_finite() && self.taylor.h_max > 0.0) {
                return Err(ParamError {
                    field: "taylor_h_max_s",
                    value: self.taylor.h_max,
                    allowed: "a finite number > 0",
                });
            }
        }
        if !(self.rest_flight_time.is_finite() && self.rest_flight_time > 0.0) {
            return Err(ParamError {
                field: "rest_flight_time_s",
                value: self.rest_flight_time,
                allowed: "a finite number > 0",
            });
        }
        if !(self.max_stroke_periods.is_finite() && self.max_stroke_periods > 0.0) {
            return Err(ParamError {
                field: "max_stroke_periods",
                value: self.max_stroke_periods,
                allowed: "a finite number > 0",
            });
        }
        Ok(())
    }
}

/// A simulation that could not produce a result.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SimError {
    /// A parameter of the bell or the configuration is out of range.
    #[error(transparent)]
    Param(#[from] ParamError),
    /// The integrator failed.
    #[error(transparent)]
    Ode(#[from] OdeError),
    /// More events in one stroke than [`SimConfig::max_events`].
    #[error("event limit of {limit} reached in one stroke at t = {t} s")]
    EventLimit {
        /// The limit.
        limit: u32,
        /// Time (s).
        t: f64,
    },
}
