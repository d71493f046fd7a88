//! One integration segment of a stroke: the bell's equations with the
//! contact force of the clapper's current state, and the events that end
//! it (the bell's, then the contact law's), as one system every stepper
//! can run.

use std::f64::consts::PI;

use crate::contact::{linear_event, ClapperState, ContactEvent, ContactLaw, ForceLaw};
use crate::dynamics::{Dynamics, LinearSpring, State, THETA, THETA_DOT};
use crate::ode::taylor::Coeffs;
use crate::ode::{Direction, Event, SeriesSystem, Source, System, MAX_EVENTS, MAX_EXTRA};
use crate::swing::SwingSystem;

/// The bell's own events.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum BellEvent {
    /// θ passes zero: the bottom of the swing.
    Bottom,
    /// θ' reaches zero after the bottom: the turning point, the stroke's end.
    Turning,
    /// |θ| reaches 180 deg on the far side: over the balance.
    OverTop,
}

/// What an event of a segment is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Ev {
    /// The bell's.
    Bell(BellEvent),
    /// The contact law's.
    Contact(ContactEvent),
}

/// The equations and event functions of one integration segment.
pub(super) struct Segment<'a> {
    d: &'a Dynamics,
    law: ForceLaw,
    kinds: [Ev; MAX_EVENTS],
    events: [Event; MAX_EVENTS],
    n: usize,
}

impl<'a> Segment<'a> {
    /// The segment of a stroke that started at θ of sign `s0` (±1), with
    /// the clapper in `clapper` under `law`.
    pub(super) fn new(
        d: &'a Dynamics,
        law: &dyn ContactLaw,
        clapper: ClapperState,
        s0: f64,
        bottom_passed: bool,
    ) -> Self {
        let placeholder = Event {
            source: Source::State(0),
            level: 0.0,
            direction: Direction::Either,
        };
        let mut seg = Self {
            d,
            law: law.force_law(clapper, d.bell().phi_max),
            kinds: [Ev::Bell(BellEvent::OverTop); MAX_EVENTS],
            events: [placeholder; MAX_EVENTS],
            n: 0,
        };
        // The bell's events first: on a tie the first listed wins.
        seg.push(
            Ev::Bell(BellEvent::OverTop),
            linear_event(Source::State(THETA), -s0, -PI, Direction::Rising),
        );
        if bottom_passed {
            seg.push(
                Ev::Bell(BellEvent::Turning),
                linear_event(Source::State(THETA_DOT), s0, 0.0, Direction::Rising),
            );
        } else {
            seg.push(
                Ev::Bell(BellEvent::Bottom),
                linear_event(Source::State(THETA), s0, 0.0, Direction::Falling),
            );
        }
        law.events(clapper, d.bell().phi_max, &mut |kind, e| seg.push(Ev::Contact(kind), e));
        seg
    }

    fn push(&mut self, kind: Ev, e: Event) {
        // A law declares at most four events and the bell two.
        if self.n < MAX_EVENTS {
            self.kinds[self.n] = kind;
            self.events[self.n] = e;
            self.n += 1;
        }
    }

    /// What event `i` is.
    pub(super) fn kind(&self, i: usize) -> Ev {
        self.kinds[i]
    }

    /// The contact force in this segment.
    pub(super) fn force_law(&self) -> ForceLaw {
        self.law
    }
}

impl System<4> for Segment<'_> {
    #[inline]
    fn rhs(&self, _t: f64, y: &State) -> State {
        match self.law {
            ForceLaw::Zero => self.d.rhs_free(y),
            ForceLaw::Resting => self.d.rhs_resting(y),
            ForceLaw::Spring(spring) => self.d.rhs_forced(y, spring.force(y[1])),
        }
    }

    fn events(&self) -> &[Event] {
        &self.events[..self.n]
    }

    /// Extra function 0: the force holding a resting clapper.
    #[inline]
    fn extra(&self, _j: usize, _t: f64, y: &State) -> f64 {
        self.d.resting(y).1
    }
}

impl SeriesSystem<4> for Segment<'_> {
    fn expand(&self, y: &State, p: usize, x: &mut [Coeffs; 4], extra: &mut [Coeffs; MAX_EXTRA]) {
        match self.law {
            ForceLaw::Zero => self.d.series_free(y, &LinearSpring::NONE, p, x),
            // The holding force is extra series 0.
            ForceLaw::Resting => self.d.series_resting(y, p, x, &mut extra[0]),
            ForceLaw::Spring(spring) => self.d.series_free(y, &spring, p, x),
        }
    }
}

impl SwingSystem for Segment<'_> {
    fn resting_dynamics(&self) -> Option<&Dynamics> {
        (self.law == ForceLaw::Resting).then_some(self.d)
    }
}
