//! The stroke recorder: turns the stream of events of one stroke (impacts,
//! rebounds, lift-offs, rest, the bottom) into a [`Stroke`] and its
//! quantities (docs/model.md §4).

use crate::contact::{Rest, Side, Stops, Transition};
use crate::dynamics::{State, PHI_DOT, THETA};
use crate::ode::Stats;

use super::impact::{Impact, Moment, StrikeAmplitude};
use super::quantities::{LiftoffKind, Stroke, StrokeEnd, StrokeStart, Style};

/// What a stroke has done so far.
pub(super) struct StrokeRecorder {
    start: StrokeStart,
    start_side: Side,
    impacts: Vec<Impact>,
    liftoff: Option<Moment>,
    liftoff_kind: Option<LiftoffKind>,
    /// Whether the clapper has been at rest on its starting side since it
    /// last left it (or since the start): its next departure is a lift-off
    /// from rest, not a bounce.
    rested: bool,
    rest_after_strike: Option<Moment>,
    bottom: Option<Moment>,
    /// Whether the first strike (an impact on the far side) has happened.
    struck: bool,
}

impl StrokeRecorder {
    /// A stroke from `start`, for a bell with these `stops`.
    pub(super) fn new(start: StrokeStart, stops: &Stops) -> Self {
        let start_side = start.side();
        let y = start.y;
        // Against its side but not pressed: it leaves at once.
        let leaves_at_once = start.clapper.is_flying()
            && start_side == Side::of(y[1])
            && (y[1].abs() - stops.angle(start_side)).abs() < 1e-12;
        Self {
            start,
            start_side,
            impacts: Vec::with_capacity(32),
            liftoff: leaves_at_once.then_some(Moment {
                t: start.t,
                theta: y[THETA],
            }),
            liftoff_kind: leaves_at_once.then_some(LiftoffKind::FromRest),
            // Against its side at the start (pressed, held, or leaving at
            // once from a standstill there); in flight from the last stroke otherwise.
            rested: !start.clapper.is_flying() || leaves_at_once,
            rest_after_strike: None,
            bottom: None,
            struck: false,
        }
    }

    /// The bell passed the bottom at time `t` (s), angle `theta` (rad).
    pub(super) fn bottom(&mut self, t: f64, theta: f64) {
        self.bottom = Some(Moment { t, theta });
    }

    /// A contact event at time `t` (s) with the state `y` just before it,
    /// and what the contact law made of it.
    pub(super) fn contact(&mut self, t: f64, y: &State, tr: &Transition) {
        let now = Moment { t, theta: y[THETA] };
        if let Some(side) = tr.impact {
            self.struck |= side != self.start_side;
            self.impacts.push(Impact {
                t,
                theta: y[THETA],
                phi_dot_before: y[PHI_DOT],
                phi_dot_after: None,
                side,
            });
        }
        if let (Some(v), Some(side)) = (tr.rebound, tr.impact.or(tr.departed)) {
            if let Some(last) = self
                .impacts
                .last_mut()
                .filter(|l| l.side == side && l.phi_dot_after.is_none())
            {
                last.phi_dot_after = Some(v);
            }
        }
        if let (Some(rest), true, None) = (tr.rest, self.struck, self.rest_after_strike) {
            self.rest_after_strike = match rest {
                Rest::Now => Some(now),
                // At rest since the contact it never left.
                Rest::SinceContactStart => self.impacts.last().map(|l| Moment { t: l.t, theta: l.theta }),
            };
        }
        if tr.rest.is_some() && !self.struck {
            self.rested = true;
        }
        if tr.departed == Some(self.start_side) && !self.struck {
            self.liftoff = Some(now);
            self.liftoff_kind = Some(if self.rested {
                LiftoffKind::FromRest
            } else {
                LiftoffKind::Bounce
            });
            self.rested = false;
        }
    }

    /// Whether the stroke has struck and awaits the impact after its first
    /// strike, the clapper not at rest.
    pub(super) fn awaits_second_impact(&self) -> bool {
        let first = self.impacts.iter().position(|i| i.side != self.start_side);
        first.is_some_and(|k| k + 1 == self.impacts.len()) && self.rest_after_strike.is_none()
    }

    /// The stroke, ended as `end`, with the stepper's work, the number of
    /// events handled, and what its amplitude ratio compares.
    pub(super) fn finish(self, end: StrokeEnd, stats: Stats, events: u32, strike_amplitude: StrikeAmplitude) -> Stroke {
        Stroke {
            start: self.start,
            start_side: self.start_side,
            style: Style::of(self.start_side, self.start.y[THETA]),
            impacts: self.impacts,
            liftoff: self.liftoff,
            liftoff_kind: self.liftoff_kind,
            rest_after_strike: self.rest_after_strike,
            bottom: self.bottom,
            end,
            after_end: None,
            stats,
            events,
            strike_amplitude,
        }
    }
}
