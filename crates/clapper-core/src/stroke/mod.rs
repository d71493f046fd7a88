//! One stroke: from the bell at its start to the bell's next turning point,
//! with any contact law (docs/model.md §3, §4), and every quantity of a
//! stroke.
//!
//! [`run_stroke`] is a short loop (`run.rs`): build the segment
//! (`segment.rs`) for the clapper's state, let the stepper run it to its
//! first event, hand a contact event to the [`ContactLaw`](crate::contact::ContactLaw),
//! and tell the recorder (`recorder.rs`) what happened. What a stroke
//! needs besides the bell is in `config.rs`, a stroke and its quantities
//! in `quantities.rs` and `impact.rs`, its observers in `observe.rs`, and
//! the torques applied from outside (a ringer's pull) come through the one
//! interface of `forcing.rs`.
//!
//! This file only declares the parts and names what they export.

mod config;
mod forcing;
mod impact;
mod observe;
mod quantities;
mod recorder;
mod run;
mod segment;

pub use crate::contact::{ClapperState, ContactModel, Restitution, Side, DEFAULT_STIFFNESS};
pub use config::{Integrator, SimConfig, SimError, TaylorOptions, DEFAULT_RESTITUTION, DEFAULT_THETA0_DEG};
pub use forcing::{Applied, Forcing, SegmentStart};
pub use impact::{double_strike_index, Impact, Moment, StrikeAmplitude};
pub use observe::{Observer, Sample, StepView, TraceRecorder, TraceSampler};
pub use quantities::{AfterEnd, EndReason, LiftoffKind, Stroke, StrokeEnd, StrokeStart, Style};
pub use run::{run_stroke, run_stroke_forced, run_stroke_pulled};
