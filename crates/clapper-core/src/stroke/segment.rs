//! One integration segment of a stroke: the bell's equations with the
//! contact force of the clapper's current state, and the events that end
//! it (the bell's, then the contact law's), as one system every stepper
//! can run.

use std::cell::Cell;
use std::f64::consts::PI;

use crate::contact::{linear_event, ClapperState, ContactEvent, ContactLaw, ForceLaw, Stops};
use crate::dynamics::{Dynamics, LinearSpring, Load, State, Trig, PHI, PHI_DOT, THETA, THETA_DOT};
use crate::ode::taylor::Coeffs;
use crate::ode::{Direction, ErrorWeights, Event, SeriesSystem, Source, System, MAX_EVENTS, MAX_EXTRA};
use crate::swing::SwingSystem;

use super::forcing::{Applied, Forcing, SegmentStart};

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

/// The events of Coulomb friction at the clapper's pivot (docs/model.md §10.2).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum FrictionEvent {
    /// A flying clapper's rate relative to the bell passes zero: it sticks
    /// or turns back.
    SlipStops,
    /// The torque needed to hold a stuck clapper exceeds the friction.
    Breakaway,
}

/// What an event of a segment is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Ev {
    /// The bell's.
    Bell(BellEvent),
    /// The contact law's.
    Contact(ContactEvent),
    /// The applied forcing's: its torques change.
    Forcing,
    /// Friction's.
    Friction(FrictionEvent),
}

/// What stays fixed over a stroke: the stops, and the friction with the
/// sign of the bearing's Coulomb torque (against the bell's motion, which
/// keeps its sign from one turning point to the next).
#[derive(Clone, Copy, Debug)]
pub(super) struct StrokeFrame<'f> {
    /// The stops and the pivot's grip.
    pub(super) stops: Stops,
    /// Friction with τ_θ signed and the clapper's part unsigned
    /// (`clapper_torque` = τ_c), or `None` without friction.
    pub(super) friction: Option<Load>,
    /// Torques applied from outside (a ringer's pull), if any.
    pub(super) forcing: Option<&'f dyn Forcing>,
}

impl StrokeFrame<'_> {
    /// The load in a segment with the clapper in `clapper` from state `y`.
    pub(super) fn load(&self, d: &Dynamics, clapper: ClapperState, y: &State) -> Option<Load> {
        self.load_held(d, clapper, y, None)
    }

    /// [`load`](Self::load), given the torque `hold` (N m) that would hold
    /// the clapper still relative to the bell at `y` with this frame's
    /// friction, where it is known (at a slip's stop it was just computed).
    pub(super) fn load_held(&self, d: &Dynamics, clapper: ClapperState, y: &State, hold: Option<f64>) -> Option<Load> {
        let f = self.friction?;
        let tau = f.clapper_torque;
        // The clapper's direction of slip relative to the bell.
        let dir = match clapper {
            ClapperState::Flying { .. } if tau > 0.0 => {
                if y[PHI_DOT] != 0.0 {
                    y[PHI_DOT].signum()
                } else {
                    // From rest relative to the bell: against the torque
                    // that would hold it.
                    let hold =
                        hold.unwrap_or_else(|| d.resting_q(&[y[THETA], y[PHI], y[THETA_DOT], 0.0], f.theta(y)).1);
                    -hold.signum()
                }
            }
            ClapperState::Compressing { side, .. } => side.sign(),
            ClapperState::Rebounding { side, .. } => -side.sign(),
            _ => 0.0,
        };
        Some(Load {
            clapper_torque: -dir * tau,
            ..f
        })
    }
}

/// The equations and event functions of one integration segment.
pub(super) struct Segment<'a> {
    d: &'a Dynamics,
    law: ForceLaw,
    /// Friction and what is applied from outside; the clapper's Coulomb
    /// torque turns where the segment passes through the apex of a flight
    /// ([`Apexes`]).
    load: Cell<Option<Load>>,
    /// The torques applied from outside, included in `load`.
    applied: Applied,
    /// Whether the closed-form swing can serve this segment.
    closed_form: bool,
    kinds: [Ev; MAX_EVENTS],
    /// The events, and the same with the slip's stop turned (the other
    /// direction of slip), in use as `turned` says.
    events: [[Event; MAX_EVENTS]; 2],
    turned: Cell<usize>,
    n: usize,
    apexes: Option<Apexes<'a>>,
}

/// A flying clapper's apexes that a segment passes through (the Coulomb
/// torque turned, the clapper slipping back), where the clapper does not
/// stick there: what the stroke would do at the event, done without
/// ending the segment (docs/model.md §10.2). Only for an observer that
/// watches nothing (a jump at the apex is not shown) and nothing applied
/// from outside.
pub(super) struct Apexes<'a> {
    frame: StrokeFrame<'a>,
    clapper: ClapperState,
    /// How many it may pass through: the stroke's events left.
    budget: u32,
    passed: Cell<u32>,
    /// The state of the last apex passed through (its bits) and its sines
    /// and cosines, for the expansion from it.
    trig: Cell<Option<([u64; 4], Trig)>>,
}

impl<'a> Segment<'a> {
    /// The segment of a stroke that started at θ of sign `s0` (±1), with
    /// the clapper in `clapper` under `law`, from state `y`; `hold`: the
    /// torque holding the clapper still relative to the bell there, if
    /// known ([`StrokeFrame::load_held`]); `apexes`: how many apexes of a
    /// flight it may pass through ([`Apexes`]), if any.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn new(
        d: &'a Dynamics,
        law: &dyn ContactLaw,
        frame: &StrokeFrame<'a>,
        clapper: ClapperState,
        y: &State,
        s0: f64,
        bottom_passed: bool,
        hold: Option<f64>,
        apexes: Option<u32>,
    ) -> Self {
        let placeholder = Event {
            source: Source::State(0),
            level: 0.0,
            direction: Direction::Either,
        };
        let stops = &frame.stops;
        let friction = frame.load_held(d, clapper, y, hold);
        let mut seg = Self {
            d,
            law: law.force_law(clapper, stops),
            load: Cell::new(friction),
            applied: Applied::NONE,
            closed_form: false,
            kinds: [Ev::Bell(BellEvent::OverTop); MAX_EVENTS],
            events: [[placeholder; MAX_EVENTS]; 2],
            turned: Cell::new(0),
            n: 0,
            apexes: None,
        };
        // The bell's events first: on a tie the first listed wins.
        seg.push_bell_events(frame, s0, bottom_passed);
        if let Some(f) = frame.forcing {
            let at = SegmentStart { y, s0, bottom_passed };
            let applied = f.over_segment(&at, &mut |e| seg.push(Ev::Forcing, e));
            seg.apply(applied);
        }
        law.events(clapper, stops, &mut |kind, e| seg.push(Ev::Contact(kind), e));
        // Friction's direction of slip is its own torque's, without what
        // is applied from outside.
        seg.push_friction_events(clapper, stops.grip, friction);
        seg.closed_form = seg.law == ForceLaw::Resting && seg.is_rigid_pendulum(clapper);
        if let Some(budget) = apexes {
            seg.pass_apexes(frame, clapper, budget);
        }
        seg
    }

    /// Whether the bell with its clapper resting (`clapper`) is a rigid
    /// pendulum in this segment, as the closed-form swing takes it: no
    /// load, or only friction at the clapper's pivot, which does no work
    /// while the clapper rests against a stop (not stuck by that friction
    /// elsewhere) and sets only the level of its lift-off; nothing applied
    /// from outside.
    fn is_rigid_pendulum(&self, clapper: ClapperState) -> bool {
        match self.load.get() {
            None => true,
            Some(l) => {
                matches!(clapper, ClapperState::Resting(_))
                    && l.bell_torque == 0.0
                    && l.bell_damping == 0.0
                    && self.applied == Applied::NONE
            }
        }
    }

    /// Over the balance, the turning point and the bottom, as far as the
    /// stroke has come.
    fn push_bell_events(&mut self, frame: &StrokeFrame, s0: f64, bottom_passed: bool) {
        self.push(
            Ev::Bell(BellEvent::OverTop),
            linear_event(Source::State(THETA), -s0, -PI, Direction::Rising),
        );
        // Coulomb friction at the bearings may turn the bell back before
        // the bottom.
        let early_turn = frame.friction.is_some_and(|f| f.bell_torque != 0.0);
        if bottom_passed || early_turn {
            self.push(
                Ev::Bell(BellEvent::Turning),
                linear_event(Source::State(THETA_DOT), s0, 0.0, Direction::Rising),
            );
        }
        if !bottom_passed {
            self.push(
                Ev::Bell(BellEvent::Bottom),
                linear_event(Source::State(THETA), s0, 0.0, Direction::Falling),
            );
        }
    }

    /// Adds the torques applied from outside to this segment's load.
    fn apply(&mut self, applied: Applied) {
        self.applied = applied;
        // A zero torque leaves the load as it was: no load at all keeps
        // the unloaded equations (and the closed-form swing).
        if applied.bell != 0.0 || applied.clapper != 0.0 {
            let mut l = self.load.get().unwrap_or_default();
            if applied.bell != 0.0 {
                l.bell_torque += applied.bell;
            }
            if applied.clapper != 0.0 {
                l.clapper_torque += applied.clapper;
            }
            self.load.set(Some(l));
        }
    }

    /// Coulomb friction at the clapper's pivot (grip τ_c > 0): a flying
    /// clapper's slip stopping, a stuck one breaking away. `friction`: the
    /// segment's friction load, which sets the direction of slip.
    fn push_friction_events(&mut self, clapper: ClapperState, grip: f64, friction: Option<Load>) {
        if grip <= 0.0 {
            return;
        }
        match clapper {
            ClapperState::Flying { .. } => {
                let dir = -friction.map_or(0.0, |l| l.clapper_torque).signum();
                self.push(Ev::Friction(FrictionEvent::SlipStops), slip_stops(dir));
            }
            ClapperState::Stuck => {
                // The holding torque (extra 0) leaving [−τ_c, τ_c].
                for scale in [1.0, -1.0] {
                    self.push(
                        Ev::Friction(FrictionEvent::Breakaway),
                        linear_event(Source::Extra(0), scale, -grip, Direction::Rising),
                    );
                }
            }
            _ => {}
        }
    }

    fn push(&mut self, kind: Ev, e: Event) {
        // A law declares at most four events and the bell two.
        if self.n < MAX_EVENTS {
            self.kinds[self.n] = kind;
            self.events[0][self.n] = e;
            self.n += 1;
        }
    }

    /// Pass through the apexes of the clapper's flight where it does not
    /// stick, up to `budget` of them ([`Apexes`]).
    fn pass_apexes(&mut self, frame: &StrokeFrame<'a>, clapper: ClapperState, budget: u32) {
        let flying = matches!(clapper, ClapperState::Flying { .. });
        let n = self.n;
        if !(flying && frame.stops.grip > 0.0 && frame.forcing.is_none() && self.applied == Applied::NONE && n > 0) {
            return;
        }
        if self.kinds[n - 1] != Ev::Friction(FrictionEvent::SlipStops) {
            return;
        }
        // The events with the slip's stop in the other direction, for an
        // apex passed through.
        self.events[1] = self.events[0];
        let dir = -self.load.get().map_or(0.0, |l| l.clapper_torque).signum();
        self.events[1][n - 1] = slip_stops(-dir);
        self.apexes = Some(Apexes {
            frame: *frame,
            clapper,
            budget,
            passed: Cell::new(0),
            trig: Cell::new(None),
        });
    }

    /// How many apexes the run passed through (each an event handled).
    pub(super) fn apexes_passed(&self) -> u32 {
        self.apexes.as_ref().map_or(0, |a| a.passed.get())
    }

    /// What event `i` is.
    pub(super) fn kind(&self, i: usize) -> Ev {
        self.kinds[i]
    }

    /// The contact force in this segment.
    pub(super) fn force_law(&self) -> ForceLaw {
        self.law
    }

    /// Friction in this segment, with the torques applied from outside
    /// (at its end, after any apex passed through).
    pub(super) fn load(&self) -> Option<Load> {
        self.load.get()
    }

    /// The load a contact's outcome is judged with, the forces of the
    /// flight to come: this segment's, with the clapper's Coulomb torque
    /// the pivot's grip τ_c (unsigned) plus what is applied to the clapper.
    pub(super) fn judging_load(&self, frame: &StrokeFrame) -> Option<Load> {
        self.load.get().map(|l| {
            let mut clapper_torque = frame.friction.map_or(0.0, |f| f.clapper_torque);
            if self.applied.clapper != 0.0 {
                clapper_torque += self.applied.clapper;
            }
            Load { clapper_torque, ..l }
        })
    }
}

impl System<4> for Segment<'_> {
    #[inline]
    fn rhs(&self, _t: f64, y: &State) -> State {
        match (self.law, &self.load.get()) {
            (ForceLaw::Zero, None) => self.d.rhs_free(y),
            (ForceLaw::Resting, None) => self.d.rhs_resting(y),
            (ForceLaw::Spring(spring), None) => self.d.rhs_forced(y, spring.force(y[PHI])),
            (ForceLaw::Zero, Some(l)) => self.d.rhs_q(y, l.theta(y), l.phi(y)),
            (ForceLaw::Resting, Some(l)) => self.d.rhs_resting_q(y, l.theta(y)),
            (ForceLaw::Spring(spring), Some(l)) => self.d.rhs_q(y, l.theta(y), spring.force(y[PHI]) + l.phi(y)),
        }
    }

    fn events(&self) -> &[Event] {
        &self.events[self.turned.get()][..self.n]
    }

    /// In a spring contact the clapper angle's error is measured from the
    /// spring's rest angle, with tolerances in proportion to the spring's
    /// own scales: its deflection under the clapper's weight moment,
    /// m b g / k (rad), for φ, and the rate of an oscillation of that size,
    /// m b g / √(k I_c) (rad/s), for φ', each times the options'
    /// tolerance. A resting clapper's deflection is then resolved as
    /// finely as an order-one angle is in flight, and its lift-off, where
    /// the deflection returns to zero, converges to the rigid law's as 1/k
    /// (docs/model.md §3.2). The spring never damps an oscillation the
    /// steps' errors start, so φ' is held 100 times tighter again: measured
    /// on the lab bell, at 1 the lift-off stalls about 5e-7 s from the rigid
    /// law's for every k from 1e7 N m/rad up. The floor, a few units in the
    /// last place of the stop angle, is what f64 resolves of φ there.
    fn error_weights(&self, atol: f64, rtol: f64) -> ErrorWeights<4> {
        let mut w = ErrorWeights::uniform(atol, rtol);
        if let ForceLaw::Spring(spring) = self.law {
            let deflection = self.d.gravity_clapper / spring.k;
            let rate = self.d.gravity_clapper / (spring.k * self.d.ic).sqrt();
            let resolvable = 4.0 * f64::EPSILON * spring.phi_s.abs();
            w.atol[PHI] = (atol * deflection.min(1.0)).max(resolvable);
            w.origin[PHI] = spring.phi_s;
            w.atol[PHI_DOT] = 0.01 * atol * rate.min(1.0);
        }
        w
    }

    /// Extra function 0: the force holding a resting clapper, less what is
    /// applied to the clapper from outside (the stop takes the rest).
    #[inline]
    fn extra(&self, _j: usize, _t: f64, y: &State) -> f64 {
        match &self.load.get() {
            None => self.d.resting(y).1,
            Some(l) if self.applied.clapper != 0.0 => self.d.resting_q(y, l.theta(y)).1 - self.applied.clapper,
            Some(l) => self.d.resting_q(y, l.theta(y)).1,
        }
    }
}

impl SeriesSystem<4> for Segment<'_> {
    fn expand(&self, y: &State, p: usize, x: &mut [Coeffs; 4], extra: &mut [Coeffs; MAX_EXTRA]) {
        let load = self.load.get();
        let load = load.as_ref();
        match self.law {
            ForceLaw::Zero => {
                // From an apex just passed through: its sines and cosines.
                let trig = self.apexes.as_ref().and_then(|a| a.trig.take());
                let trig = trig.filter(|(bits, _)| *bits == y.map(f64::to_bits));
                self.d
                    .series_free_at(y, trig.as_ref().map(|(_, t)| t), &LinearSpring::NONE, load, p, x)
            }
            // The holding force is extra series 0, less what is applied to
            // the clapper from outside (a constant).
            ForceLaw::Resting => {
                self.d.series_resting(y, load, p, x, &mut extra[0]);
                if self.applied.clapper != 0.0 {
                    extra[0][0] -= self.applied.clapper;
                }
            }
            ForceLaw::Spring(spring) => self.d.series_free(y, &spring, load, p, x),
        }
    }

    /// Friction's slip stop, the apex of a flight: its root located on the
    /// whole step where φ' is monotone over it (its crossing is then the
    /// only one).
    fn whole_step_events(&self) -> u32 {
        match self.n.checked_sub(1) {
            Some(i) if self.kinds[i] == Ev::Friction(FrictionEvent::SlipStops) => 1 << i,
            _ => 0,
        }
    }

    /// A flying clapper's slip stopping, where it does not stick: what
    /// `run::frictional` and the next segment would make of it (the same
    /// holding torque, the same torque turned, the same flight hint), done
    /// in place. Declined (the stroke handles the event) where it sticks,
    /// where the budget is spent, or where a forcing is applied.
    fn pass_through(&self, i: usize, y: &mut State) -> Option<Option<f64>> {
        let a = self.apexes.as_ref()?;
        if self.kinds[i] != Ev::Friction(FrictionEvent::SlipStops) || a.passed.get() >= a.budget {
            return None;
        }
        let frame = &a.frame;
        let mut ya = *y;
        ya[PHI_DOT] = 0.0;
        // The sines and cosines at the apex, once: for the check for
        // sticking, the flight's hint and the next expansion.
        let trig = Trig::of(&ya);
        let (stuck, hold) = slip_stop_hold_at(self.d, frame, &ya, &trig, self.load.get());
        let hold = hold.filter(|_| !stuck)?;
        let turned = frame.load_held(self.d, a.clapper, &ya, Some(hold));
        // The slip's stop of the turned torque is the other array's.
        let dir = -turned.map_or(0.0, |l| l.clapper_torque).signum();
        let other = 1 - self.turned.get();
        if self.events[other][i] != slip_stops(dir) {
            return None;
        }
        let hint = flight_from_apex_at(self.d, frame, &ya, &trig, a.clapper, turned);
        self.load.set(turned);
        self.turned.set(other);
        a.passed.set(a.passed.get() + 1);
        a.trig.set(Some((ya.map(f64::to_bits), trig)));
        *y = ya;
        Some(hint)
    }
}

/// A flying clapper's slip in direction `dir` (±1) stopping.
fn slip_stops(dir: f64) -> Event {
    linear_event(Source::State(PHI_DOT), dir, 0.0, Direction::Falling)
}

impl SwingSystem for Segment<'_> {
    fn resting_dynamics(&self) -> Option<&Dynamics> {
        // The closed form is a rigid pendulum: the bell with its clapper at
        // a stop (either contact angle, any pivot offset), without friction
        // on the bell or a torque applied from outside.
        self.closed_form.then_some(self.d)
    }
}

/// Where a flying clapper's slip stops (`y`, with φ' = 0) in a segment
/// with `load`, given the sines and cosines of `y`'s angles: whether the
/// pivot's friction holds it (it sticks), and the torque that would hold
/// it with the frame's friction ([`StrokeFrame::load_held`]), where that
/// is the segment's.
pub(super) fn slip_stop_hold_at(
    d: &Dynamics,
    frame: &StrokeFrame,
    y: &State,
    trig: &Trig,
    load: Option<Load>,
) -> (bool, Option<f64>) {
    let bell_load = load.map_or(0.0, |l| l.theta(y));
    // As resting_q: its sines and cosines of φ at a stop are trig's.
    let hold = d.resting_at(y, trig, bell_load).1;
    // The same torque as the frame's unless a forcing adds to the
    // bell's (then the frame's is worked out afresh).
    let same = frame.friction.is_some_and(|f| f.theta(y) == bell_load);
    (hold.abs() <= frame.stops.grip, same.then_some(hold))
}

/// The rest of a bounce's flight after its apex, where the clapper turns
/// back toward the stop it bounced off, still flying: about √(2Δ/a) for a
/// distance Δ (rad) to the stop under the relative acceleration a toward
/// it (rad/s²), with a margin of 1.5 times (s); given the sines and cosines
/// of `y`'s angles and the load of the flight after the apex.
pub(super) fn flight_from_apex_at(
    d: &Dynamics,
    frame: &StrokeFrame,
    y: &State,
    trig: &Trig,
    clapper: ClapperState,
    load: Option<Load>,
) -> Option<f64> {
    let ClapperState::Flying {
        bounced_off: Some(side),
    } = clapper
    else {
        return None;
    };
    let s = side.sign();
    let distance = s * (frame.stops.at(side) - y[PHI]);
    let load = load?;
    let toward = s * d.accel_at(y, trig, load.theta(y), load.phi(y)).phi;
    (distance > 0.0 && toward > 0.0).then(|| 1.5 * (2.0 * distance / toward).sqrt())
}
