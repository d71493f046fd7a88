//! Forces applied to the bell and clapper from outside (a ringer's pull,
//! a rope, a tower's motion): the one interface through which a stroke
//! takes them, so the stroke names no model of what applies them.
//!
//! A forcing holds its torques constant over each integration segment and
//! says where they change by events of its own (level crossings of the
//! state); at such an event the stroke starts a new segment and asks again.

use std::fmt::Debug;

use crate::bell::ParamError;
use crate::dynamics::State;
use crate::ode::Event;

/// Where a segment of a stroke begins, as a forcing sees it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SegmentStart<'a> {
    /// The state `[θ, φ, θ', φ']` (rad, rad/s).
    pub y: &'a State,
    /// The side of the bottom the stroke started on (±1): the bell moves
    /// toward −`s0` throughout the stroke.
    pub s0: f64,
    /// Whether the bell has passed the bottom in this stroke.
    pub bottom_passed: bool,
}

/// Torques applied from outside, held over one segment.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Applied {
    /// On the bell (N m), positive in the sense of θ.
    pub bell: f64,
    /// On the clapper (N m), positive in the sense of φ: a generalised
    /// force Q_φ between bell and clapper, as the pivot's friction is.
    /// Against a stop the stop takes it: the clapper lifts off when the
    /// force holding it there, less this torque, pulls.
    pub clapper: f64,
}

impl Applied {
    /// No torque on either.
    pub const NONE: Applied = Applied {
        bell: 0.0,
        clapper: 0.0,
    };
}

/// An applied torque on the bell and on the clapper, with its own events.
pub trait Forcing: Debug + Sync {
    /// Checks the forcing is physical.
    fn validate(&self) -> Result<(), ParamError>;

    /// The torques over the segment beginning at `at`, and the events
    /// (handed to `push`) at which they change; the segment ends at the
    /// first of them (or at any of the stroke's own) and the next segment
    /// asks again. Keep them few: a segment holds eight events in all.
    fn over_segment(&self, at: &SegmentStart<'_>, push: &mut dyn FnMut(Event)) -> Applied;
}
