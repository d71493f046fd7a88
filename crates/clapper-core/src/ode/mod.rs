//! Our own ODE layer: one stepper interface ([`Stepper`]) over three
//! methods, one way to declare event functions ([`Event`]: a level on a
//! series), and one dense output ([`DenseOutput`]).
//!
//! - [`Dopri5`]: adaptive Dormand–Prince 5(4) with dense output, for any
//!   [`System`]; the general method and the cross-check.
//! - [`Taylor`]: a Taylor-series integrator for systems that expand their
//!   own solution ([`SeriesSystem`]; the bell does, in `stroke`): longer
//!   steps and exact dense output for smooth motion.
//! - `swing::ClosedFormSwing` (in [`crate::swing`]): the bell released from
//!   rest with its clapper resting, solved in closed form; it declines
//!   ([`Stop::Declined`]) whatever it cannot solve, and [`Fallback`] hands
//!   that on to an integrator.
//!
//! It is small on purpose. The state is a fixed-size array (`[f64; N]`), so a
//! step allocates nothing; the system is a generic parameter, so the
//! right-hand side inlines. It is checked against the `ode_solvers` crate and
//! against analytic cases in the tests.
//!
//! ```
//! use clapper_core::ode::{Direction, Dopri5, Event, Options, Source, Stepper, Stop, System};
//!
//! /// y'' = -y, stopped when y falls through zero.
//! struct Oscillator([Event; 1]);
//! impl System<2> for Oscillator {
//!     fn rhs(&self, _t: f64, y: &[f64; 2]) -> [f64; 2] { [y[1], -y[0]] }
//!     fn events(&self) -> &[Event] { &self.0 }
//! }
//!
//! let falls = Oscillator([Event { source: Source::State(0), level: 0.0, direction: Direction::Falling }]);
//! let mut solver = Dopri5::new(Options::default());
//! let end = solver.integrate(&falls, 0.0, [1.0, 0.0], 10.0, &mut |_, _| {}).unwrap();
//! assert_eq!(end.stop, Stop::Event(0));
//! assert!((end.t - std::f64::consts::FRAC_PI_2).abs() < 1e-9);
//! ```

mod dopri5;
mod interface;
pub mod taylor;

pub use dopri5::{Dense, Dopri5};
pub use interface::{
    DenseOutput, Direction, ErrorWeights, Event, Fallback, NextSegment, Observe, OdeError, Options, Run, Segment,
    Source, Span, Stats, Stepper, Stop, System, MAX_EVENTS, MAX_EXTRA,
};
pub use taylor::{SeriesSystem, Taylor};
