//! # clapper-core
//!
//! The physics of a church bell rung full circle: the bell and its clapper as
//! two coupled pendulums (equations (5), (6) of Woodhouse et al. 2012), the
//! clapper striking and bouncing (rigid impacts or the paper's penalty
//! spring), strokes and their quantities, and the paper's closed forms.
//!
//! This crate does no file, terminal or network I/O; formats, plots and the
//! command line live in outer crates. The model it implements is written
//! up in `docs/model.md`, which the code cites by section; units are SI
//! inside, radians for angles.
//!
//! ```
//! use clapper_core::prelude::*;
//!
//! let bell = Bell::lab();
//! let cfg = SimConfig::default(); // theta0 171 deg, R 0.2, impact model
//! let right = first_stroke(&bell, &cfg, Style::Right).unwrap();
//! let wrong = first_stroke(&bell, &cfg, Style::Wrong).unwrap();
//! // The lab bell rings both right and wrong when fully up (docs/model.md §7).
//! assert!(right.sustained() && wrong.sustained());
//! println!("first strike at {:.1} deg", right.strike_angle().unwrap().to_degrees());
//! ```

#![warn(missing_docs)]

pub mod bell;
pub mod chart;
pub mod clapper_changes;
pub mod clapper_parts;
pub mod contact;
pub mod diagnose;
pub mod dynamics;
pub mod elliptic;
pub mod frame;
pub mod hanging;
pub mod liftoff;
pub mod linalg;
pub mod listening;
pub mod ode;
pub mod param;
pub mod restitution;
pub mod ringer;
pub mod ringing;
pub mod sensor;
pub mod stroke;
pub mod swing;
pub mod trig;
mod verdicts;
pub mod vibration;

/// The names most programs need.
pub mod prelude {
    pub use crate::bell::{Bell, BellWarning, ChartConstruction, ParamError, TowerMeasurements};
    pub use crate::liftoff::{liftoff_angles, liftoff_from_rest, LiftoffAngles, LiftoffFromRest};
    pub use crate::ringing::{first_stroke, ring, Protocol, Ringing};
    pub use crate::stroke::{
        run_stroke, ClapperState, ContactModel, EndReason, Impact, Integrator, Observer, Side, SimConfig, SimError,
        StrikeAmplitude, Stroke, StrokeStart, Style, TraceRecorder,
    };
    pub use crate::Choice;
}

/// A choice among a few named options (a style, a protocol, a contact
/// law, an integrator): every layer spells it by these names, which are
/// also its serde form (kebab case).
pub trait Choice: Copy + Sized + 'static {
    /// Every option, in order.
    const ALL: &'static [Self];
    /// The name of this option, as in files, JSON and command-line options.
    fn name(self) -> &'static str;
}

/// [`Choice`] and `Display` for an enum of unit variants.
macro_rules! named_choice {
    ($ty:ty { $($variant:ident => $name:literal),+ $(,)? }) => {
        impl Choice for $ty {
            const ALL: &'static [$ty] = &[$(<$ty>::$variant),+];

            fn name(self) -> &'static str {
                match self {
                    $(<$ty>::$variant => $name,)+
                }
            }
        }

        impl std::fmt::Display for $ty {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str(self.name())
            }
        }
    };
}

named_choice!(stroke::Style { Right => "right", Wrong => "wrong" });
named_choice!(ringing::Protocol { Restart => "restart", Free => "free" });
named_choice!(contact::ContactModel { Impact => "impact", Penalty => "penalty" });
named_choice!(stroke::Integrator { Taylor => "taylor", Dopri5 => "dopri5" });
named_choice!(stroke::StrikeAmplitude { Rate => "rate", Impulse => "impulse", Vibration => "vibration" });
named_choice!(chart::Styles { Right => "right", Wrong => "wrong", Both => "both" });
named_choice!(hanging::SwingLoss { Viscous => "viscous", Coulomb => "coulomb" });
named_choice!(clapper_parts::Material { WroughtIron => "wrought-iron", SgIron => "sg-iron", Steel => "steel", Ash => "ash" });
named_choice!(clapper_parts::Adjust { FlightLength => "flight-length", BallPosition => "ball-position" });
