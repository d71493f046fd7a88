//! Contact laws between the clapper and the bell (docs/model.md §3): what
//! force holds or pushes the clapper in each of its states, which events
//! end a state, and what happens at each event (an impact, a bounce, rest,
//! lift-off). A stroke knows nothing of contact but this interface.
//!
//! Two laws: [`RigidImpact`] (the default) and [`PenaltySpring`] (the
//! paper's). Both take their restitution as a [`Restitution`]: R for the
//! first impact on a side, R2 for the bounces that follow it (the paper's
//! Section 3.2: the first impact loses far more energy than later ones).
//!
//! Adding a law: a type that implements [`ContactLaw`], and a variant of
//! [`ContactModel`] that [`ContactModel::law`] turns into it.

use std::fmt::Debug;

use crate::dynamics::{Dynamics, LinearSpring, Load, State, PHI, PHI_DOT};
use crate::ode::{Direction, Event, NextSegment, Source};

/// One of the two places where the clapper meets the bell: φ = +φ_max
/// (`Plus`) or φ = −φ_max (`Minus`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case"))]
pub enum Side {
    /// φ = −φ_max.
    Minus,
    /// φ = +φ_max.
    Plus,
}

impl Side {
    /// −1 or +1.
    pub fn sign(self) -> f64 {
        match self {
            Side::Minus => -1.0,
            Side::Plus => 1.0,
        }
    }

    /// The other side.
    pub fn opposite(self) -> Side {
        match self {
            Side::Minus => Side::Plus,
            Side::Plus => Side::Minus,
        }
    }

    /// `Plus` for x ≥ 0, `Minus` otherwise.
    pub fn of(x: f64) -> Side {
        if x >= 0.0 {
            Side::Plus
        } else {
            Side::Minus
        }
    }
}

/// Where the two stops are and how hard the clapper's pivot can grip:
/// what a contact law needs of the bell (docs/model.md §3, §10).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stops {
    /// Contact angle of the + (back) side (rad, positive).
    pub plus: f64,
    /// Contact angle of the − (hand) side (rad, positive).
    pub minus: f64,
    /// τ_c: the Coulomb torque of the clapper's pivot (N m), which holds a
    /// resting clapper at its stop until the torque needed exceeds it.
    pub grip: f64,
}

impl Stops {
    /// Symmetric stops at ±`phi_max` (rad) with no grip: the paper's bell.
    pub fn symmetric(phi_max: f64) -> Self {
        Self {
            plus: phi_max,
            minus: phi_max,
            grip: 0.0,
        }
    }

    /// The stops of `bell`.
    pub fn of(bell: &crate::bell::Bell) -> Self {
        let (hand, back) = bell.contact_angles();
        Self {
            plus: back,
            minus: hand,
            grip: bell.hanging.friction.clapper_friction,
        }
    }

    /// The contact angle of `side` (rad, positive).
    #[inline]
    pub fn angle(&self, side: Side) -> f64 {
        match side {
            Side::Plus => self.plus,
            Side::Minus => self.minus,
        }
    }

    /// φ at the stop of `side` (rad, signed).
    #[inline]
    pub fn at(&self, side: Side) -> f64 {
        side.sign() * self.angle(side)
    }
}

/// What the clapper is doing. Every law uses some of these states.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ClapperState {
    /// In free flight between the stops; `bounced_off` is the side it just
    /// bounced off, if it did (its next impact there is a later bounce,
    /// with restitution R2), and `None` after a lift-off from rest.
    Flying {
        /// The side of the impact this flight began with.
        bounced_off: Option<Side>,
    },
    /// Impact law: at rest against a side, moving with the bell.
    Resting(Side),
    /// Penalty law: pressing into the spring on a side, stiffness k.
    Compressing {
        /// The side in contact.
        side: Side,
        /// Whether this contact is a bounce after an earlier one on the
        /// same side (then it rebounds with R2 k).
        later: bool,
    },
    /// Held still relative to the bell by the Coulomb friction of its pivot,
    /// away from the stops (docs/model.md §10.2); it breaks away when the
    /// torque needed to hold it exceeds that friction.
    Stuck,
    /// Penalty law: past maximum compression, stiffness R k (R2 k for a
    /// later bounce) until it separates. `settled` once it has turned back
    /// into the spring without separating: the penalty law's way of coming
    /// to rest.
    Rebounding {
        /// The side in contact.
        side: Side,
        /// Whether the clapper has stopped bouncing.
        settled: bool,
        /// As in [`ClapperState::Compressing`].
        later: bool,
    },
}

impl ClapperState {
    /// In flight after a lift-off (not a bounce).
    pub const FLYING: ClapperState = ClapperState::Flying { bounced_off: None };

    /// The side the clapper touches, if any.
    pub fn contact_side(self) -> Option<Side> {
        match self {
            ClapperState::Flying { .. } | ClapperState::Stuck => None,
            ClapperState::Resting(s) | ClapperState::Compressing { side: s, .. } => Some(s),
            ClapperState::Rebounding { side, .. } => Some(side),
        }
    }

    /// Whether the clapper is at rest against the bell.
    pub fn is_at_rest(self) -> bool {
        matches!(
            self,
            ClapperState::Resting(_) | ClapperState::Rebounding { settled: true, .. }
        )
    }

    /// Whether the clapper is in free flight.
    pub fn is_flying(self) -> bool {
        matches!(self, ClapperState::Flying { .. })
    }
}

/// The events a contact law may declare.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ContactEvent {
    /// The flying clapper reaches a stop.
    Hit(Side),
    /// The force holding a resting clapper stops pressing it into the stop.
    LiftOff(Side),
    /// A compressing spring contact stops compressing.
    MaxCompression(Side),
    /// A rebounding clapper turns back into the spring without separating.
    TurnBack(Side),
    /// A spring contact opens: the clapper leaves the stop.
    Separation(Side),
}

/// The generalised contact force Q_φ on the clapper in one state.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ForceLaw {
    /// No contact.
    Zero,
    /// A resting clapper: whatever force keeps φ fixed (from (6) with
    /// φ'' = 0), so the state moves by the resting equations.
    Resting,
    /// A linear spring beyond a stop.
    Spring(LinearSpring),
}

impl ForceLaw {
    /// Q_φ (N m) at state `y`.
    #[inline]
    pub fn force(self, d: &Dynamics, y: &State) -> f64 {
        match self {
            ForceLaw::Zero => 0.0,
            ForceLaw::Resting => d.resting(y).1,
            ForceLaw::Spring(spring) => spring.force(y[PHI]),
        }
    }
}

/// Stronge's energy coefficients of restitution, in (0, 1]: `first` for
/// the first impact on a side (the strike), `later` for every bounce that
/// follows an impact on the same side.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Restitution {
    /// R: the first impact's.
    pub first: f64,
    /// R2: the later bounces'.
    pub later: f64,
}

/// How the clapper came to rest (for the stroke's record).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Rest {
    /// At this event.
    Now,
    /// Since the start of the contact it never left (penalty law: it turned
    /// back into the spring without separating).
    SinceContactStart,
}

/// What a contact event did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Transition {
    /// The state just after (an impact changes the rates).
    pub y: State,
    /// The clapper's new state.
    pub clapper: ClapperState,
    /// An impact (for the penalty law: a contact) began here on this side.
    pub impact: Option<Side>,
    /// φ' (rad/s) with which the clapper left the contact that ended here
    /// (zero if it came to rest); the stroke records it on that impact.
    pub rebound: Option<f64>,
    /// The clapper left this side (a lift-off or a bounce).
    pub departed: Option<Side>,
    /// The clapper came to rest.
    pub rest: Option<Rest>,
    /// What the integrator may expect next.
    pub next: Option<NextSegment>,
}

impl Transition {
    /// The clapper in state `clapper` at `y`, nothing else happening.
    fn to(y: State, clapper: ClapperState) -> Self {
        Self {
            y,
            clapper,
            impact: None,
            rebound: None,
            departed: None,
            rest: None,
            next: None,
        }
    }
}

/// An event function `scale * x + offset` (scale ±1) as a level on the
/// series `x`: it crosses zero where `x` crosses `-offset * scale`, in the
/// same direction for scale +1 and the other for −1.
pub(crate) fn linear_event(source: Source, scale: f64, offset: f64, direction: Direction) -> Event {
    Event {
        source,
        level: -offset * scale,
        direction: direction.signed(scale),
    }
}

/// Everything about contact between clapper and bell.
pub trait ContactLaw: Debug + Send + Sync {
    /// The force on the clapper while in `clapper`, for a bell with these
    /// `stops`. A [`ClapperState::Stuck`] clapper is the stroke's business,
    /// not the law's.
    fn force_law(&self, clapper: ClapperState, stops: &Stops) -> ForceLaw;
    /// The events that end `clapper` (at most 4), handed to `push` with
    /// their functions, for a bell with these `stops`.
    fn events(&self, clapper: ClapperState, stops: &Stops, push: &mut dyn FnMut(ContactEvent, Event));
    /// The clapper at rest against `side` at the start of a stroke, pressed
    /// into it with holding force `q` (N m, `side.sign() * q < 0`): its
    /// state and `y` adjusted (a spring law starts at its static
    /// compression, so that it does not ring from the first instant).
    fn at_rest(&self, y: State, q: f64, side: Side) -> (State, ClapperState);
    /// What event `event` does to the clapper in `clapper` at `y`, with the
    /// stroke's `friction` (its clapper torque the Coulomb magnitude τ_c ≥ 0,
    /// its bell torque signed for the stroke), if any.
    fn transition(
        &self,
        d: &Dynamics,
        event: ContactEvent,
        y: State,
        clapper: ClapperState,
        friction: Option<&Load>,
    ) -> Transition;
}

/// Rigid stops with instantaneous impacts, φ'⁺ = −√R φ'⁻ (docs/model.md
/// §3.1); bounces accumulate until the next flight would be shorter than
/// `rest_flight_time`, when the clapper comes to rest.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RigidImpact {
    /// √R and √R2: velocity restitution of the first and later impacts.
    e: [f64; 2],
    /// Shortest flight before the clapper rests (s).
    rest_flight_time: f64,
}

impl RigidImpact {
    /// The law with restitution `r` and the rest threshold `rest_flight_time` (s).
    pub fn new(r: Restitution, rest_flight_time: f64) -> Self {
        Self {
            e: [r.first.sqrt(), r.later.sqrt()],
            rest_flight_time,
        }
    }

    fn hit(&self, d: &Dynamics, side: Side, mut y: State, later: bool, friction: Option<&Load>) -> Transition {
        let s = side.sign();
        let stops = Stops::of(d.bell());
        y[PHI] = stops.at(side);
        let bounced = d.impact(&y, self.e[usize::from(later)]);
        let stuck = d.impact(&y, 0.0);
        // Would the next flight be shorter than rest_flight_time? With
        // friction in it (Coulomb slip away from the stop is resisted by
        // +s τ_c): the rest must be judged by the forces the clapper will
        // feel, or a damped bell's bounces never settle.
        let (accel, hold) = match friction {
            None => (d.accel(&bounced, 0.0), d.resting(&stuck).1),
            Some(f) => {
                let flight = Load {
                    clapper_torque: s * f.clapper_torque,
                    ..*f
                };
                (
                    d.accel_q(&bounced, flight.theta(&bounced), flight.phi(&bounced)),
                    d.resting_q(&stuck, f.theta(&stuck)).1,
                )
            }
        };
        let toward = s * accel.phi;
        let away = -s * bounced[PHI_DOT];
        let comes_to_rest = toward > 0.0 && 2.0 * away < self.rest_flight_time * toward;
        let mut tr = if comes_to_rest && s * hold < stops.grip {
            Transition {
                rest: Some(Rest::Now),
                ..Transition::to(stuck, ClapperState::Resting(side))
            }
        } else {
            Transition {
                departed: Some(side),
                // The flight ends near 2 v / a: seek it over a little more.
                // With Coulomb friction at the pivot the slip stops at the
                // apex, near v / a, where the stepper turns the torque
                // (measured: 1.2 v / a takes the fewest instructions).
                next: (toward > 0.0).then(|| NextSegment::ShortFlight {
                    span: if stops.grip > 0.0 { 1.2 } else { 3.0 } * away / toward,
                }),
                ..Transition::to(
                    bounced,
                    ClapperState::Flying {
                        bounced_off: Some(side),
                    },
                )
            }
        };
        tr.impact = Some(side);
        tr.rebound = Some(tr.y[PHI_DOT]);
        tr
    }
}

impl ContactLaw for RigidImpact {
    fn force_law(&self, clapper: ClapperState, _stops: &Stops) -> ForceLaw {
        match clapper {
            ClapperState::Resting(_) | ClapperState::Stuck => ForceLaw::Resting,
            _ => ForceLaw::Zero,
        }
    }

    fn events(&self, clapper: ClapperState, stops: &Stops, push: &mut dyn FnMut(ContactEvent, Event)) {
        match clapper {
            ClapperState::Resting(s) => {
                // Positive once the holding force pulls instead of pushes,
                // by more than the pivot's friction can hold.
                let offset = if stops.grip > 0.0 { -stops.grip } else { 0.0 };
                push(
                    ContactEvent::LiftOff(s),
                    linear_event(Source::Extra(0), s.sign(), offset, Direction::Rising),
                )
            }
            ClapperState::Stuck => {}
            _ => push_hits(stops, push),
        }
    }

    fn at_rest(&self, y: State, _q: f64, side: Side) -> (State, ClapperState) {
        (y, ClapperState::Resting(side))
    }

    fn transition(
        &self,
        d: &Dynamics,
        event: ContactEvent,
        y: State,
        clapper: ClapperState,
        friction: Option<&Load>,
    ) -> Transition {
        match event {
            ContactEvent::Hit(side) => {
                let later = clapper
                    == ClapperState::Flying {
                        bounced_off: Some(side),
                    };
                self.hit(d, side, y, later, friction)
            }
            ContactEvent::LiftOff(side) => Transition {
                departed: Some(side),
                ..Transition::to(y, ClapperState::FLYING)
            },
            // Not this law's events: nothing changes.
            _ => Transition::to(y, clapper),
        }
    }
}

/// Hits on either stop: positive once the clapper is past it.
fn push_hits(stops: &Stops, push: &mut dyn FnMut(ContactEvent, Event)) {
    for side in [Side::Plus, Side::Minus] {
        push(
            ContactEvent::Hit(side),
            linear_event(Source::State(PHI), side.sign(), -stops.angle(side), Direction::Rising),
        );
    }
}

/// The paper's linear spring beyond the stops, (12), (13), with Stronge's
/// reduced stiffness R k (R2 k for a later bounce) from maximum
/// compression until separation (docs/model.md §3.2).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PenaltySpring {
    /// k (N m/rad).
    k: f64,
    /// R k and R2 k (N m/rad).
    rk: [f64; 2],
}

impl PenaltySpring {
    /// The law with stiffness `k` (N m/rad) and restitution `r`.
    pub fn new(k: f64, r: Restitution) -> Self {
        Self {
            k,
            rk: [r.first * k, r.later * k],
        }
    }
}

impl ContactLaw for PenaltySpring {
    fn force_law(&self, clapper: ClapperState, stops: &Stops) -> ForceLaw {
        let spring = |side: Side, k| ForceLaw::Spring(LinearSpring::new(k, stops.at(side)));
        match clapper {
            ClapperState::Compressing { side, .. } => spring(side, self.k),
            ClapperState::Rebounding { side, later, .. } => spring(side, self.rk[usize::from(later)]),
            ClapperState::Stuck => ForceLaw::Resting,
            _ => ForceLaw::Zero,
        }
    }

    fn events(&self, clapper: ClapperState, stops: &Stops, push: &mut dyn FnMut(ContactEvent, Event)) {
        match clapper {
            ClapperState::Compressing { side: s, .. } => {
                // Positive once the clapper moves back out of the spring.
                push(
                    ContactEvent::MaxCompression(s),
                    linear_event(Source::State(PHI_DOT), -s.sign(), 0.0, Direction::Rising),
                )
            }
            ClapperState::Rebounding { side, settled, .. } => {
                push(
                    ContactEvent::Separation(side),
                    linear_event(Source::State(PHI), side.sign(), -stops.angle(side), Direction::Falling),
                );
                if !settled {
                    // Positive once it moves into the spring again.
                    push(
                        ContactEvent::TurnBack(side),
                        linear_event(Source::State(PHI_DOT), side.sign(), 0.0, Direction::Rising),
                    );
                }
            }
            ClapperState::Stuck => {}
            _ => push_hits(stops, push),
        }
    }

    fn at_rest(&self, mut y: State, q: f64, side: Side) -> (State, ClapperState) {
        y[PHI] -= q / self.rk[0];
        let resting = ClapperState::Rebounding {
            side,
            settled: true,
            later: false,
        };
        (y, resting)
    }

    fn transition(
        &self,
        _d: &Dynamics,
        event: ContactEvent,
        y: State,
        clapper: ClapperState,
        _friction: Option<&Load>,
    ) -> Transition {
        let later = |side| match clapper {
            ClapperState::Flying { bounced_off } => bounced_off == Some(side),
            ClapperState::Compressing { later, .. } | ClapperState::Rebounding { later, .. } => later,
            ClapperState::Resting(_) | ClapperState::Stuck => false,
        };
        match event {
            ContactEvent::Hit(side) => Transition {
                impact: Some(side),
                // A spring contact is much shorter than a free-flight step.
                next: Some(NextSegment::Stiffer),
                ..Transition::to(
                    y,
                    ClapperState::Compressing {
                        side,
                        later: later(side),
                    },
                )
            },
            ContactEvent::MaxCompression(side) => Transition::to(
                y,
                ClapperState::Rebounding {
                    side,
                    settled: false,
                    later: later(side),
                },
            ),
            ContactEvent::TurnBack(side) => Transition {
                rest: Some(Rest::SinceContactStart),
                ..Transition::to(
                    y,
                    ClapperState::Rebounding {
                        side,
                        settled: true,
                        later: later(side),
                    },
                )
            },
            ContactEvent::Separation(side) => {
                // Leaving a settled contact is a lift-off, not a bounce.
                let settled = matches!(clapper, ClapperState::Rebounding { settled: true, .. });
                Transition {
                    departed: Some(side),
                    rebound: Some(y[PHI_DOT]),
                    ..Transition::to(
                        y,
                        ClapperState::Flying {
                            bounced_off: (!settled).then_some(side),
                        },
                    )
                }
            }
            ContactEvent::LiftOff(_) => Transition::to(y, clapper),
        }
    }
}

/// Which contact law (docs/model.md §3). Its parameters are fields of
/// [`SimConfig`](crate::stroke::SimConfig): the restitution for both, the
/// stiffness for the penalty law.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case"))]
pub enum ContactModel {
    /// Rigid stops with instantaneous impacts ([`RigidImpact`]). The default.
    #[default]
    Impact,
    /// The paper's linear spring beyond the stops ([`PenaltySpring`]).
    Penalty,
}

/// The paper's contact stiffness (N m/rad), used by the penalty model unless
/// another is given.
pub const DEFAULT_STIFFNESS: f64 = 1e6;

impl ContactModel {
    /// The law with restitution `r`, stiffness `k` (N m/rad; the penalty
    /// law's) and rest threshold `rest_flight_time` (s; the rigid law's).
    /// The one place a new law is registered.
    pub fn law(self, r: Restitution, k: f64, rest_flight_time: f64) -> Box<dyn ContactLaw> {
        match self {
            ContactModel::Impact => Box::new(RigidImpact::new(r, rest_flight_time)),
            ContactModel::Penalty => Box::new(PenaltySpring::new(k, r)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bell::Bell;

    /// A bounce after an impact on the same side takes R2; the first
    /// impact on a side, or one after a lift-off, takes R.
    #[test]
    fn later_bounces_take_the_second_coefficient() {
        let d = Dynamics::new(&Bell::lab());
        let r = Restitution { first: 0.2, later: 0.6 };
        let law = RigidImpact::new(r, 1e-7);
        let phi_max = d.bell().phi_max;
        let y = [-1.2, phi_max + 1e-12, -2.0, 3.0];
        let ratio = |from: ClapperState| {
            let tr = law.transition(&d, ContactEvent::Hit(Side::Plus), y, from, None);
            assert_eq!(tr.impact, Some(Side::Plus));
            -tr.y[PHI_DOT] / y[PHI_DOT]
        };
        assert!((ratio(ClapperState::FLYING) - 0.2f64.sqrt()).abs() < 1e-15);
        let bounced_minus = ClapperState::Flying {
            bounced_off: Some(Side::Minus),
        };
        assert!((ratio(bounced_minus) - 0.2f64.sqrt()).abs() < 1e-15);
        let bounced_plus = ClapperState::Flying {
            bounced_off: Some(Side::Plus),
        };
        assert!((ratio(bounced_plus) - 0.6f64.sqrt()).abs() < 1e-15);
        // The penalty law rebounds with R2 k after a bounce on the same side.
        let spring = PenaltySpring::new(1e6, r);
        let comp = spring
            .transition(&d, ContactEvent::Hit(Side::Plus), y, bounced_plus, None)
            .clapper;
        let reb = spring
            .transition(&d, ContactEvent::MaxCompression(Side::Plus), y, comp, None)
            .clapper;
        let at = |k| ForceLaw::Spring(LinearSpring::new(k, phi_max));
        let stops = Stops::symmetric(phi_max);
        assert_eq!(spring.force_law(reb, &stops), at(0.6e6));
        let comp = spring
            .transition(&d, ContactEvent::Hit(Side::Plus), y, ClapperState::FLYING, None)
            .clapper;
        let reb = spring
            .transition(&d, ContactEvent::MaxCompression(Side::Plus), y, comp, None)
            .clapper;
        assert_eq!(spring.force_law(reb, &stops), at(0.2e6));
        // Separating from a settled contact is a lift-off.
        let settled = ClapperState::Rebounding {
            side: Side::Plus,
            settled: true,
            later: true,
        };
        let flying = spring
            .transition(&d, ContactEvent::Separation(Side::Plus), y, settled, None)
            .clapper;
        assert_eq!(flying, ClapperState::FLYING);
    }
}
