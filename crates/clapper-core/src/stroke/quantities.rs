//! A stroke and its quantities (docs/model.md §4): how it starts and
//! ends, its lift-off, bottom, strikes and rest, and the style the
//! clapper rings in.

use crate::bell::Bell;
use crate::contact::{ClapperState, Side, Stops};
use crate::dynamics::{Dynamics, State, PHI, THETA};
use crate::ode::Stats;

use super::config::SimConfig;
use super::impact::{double_strike_index, Impact, Moment, StrikeAmplitude};

/// How the clapper rests against the bell relative to the bell's swing.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case"))]
pub enum Style {
    /// The clapper rests on the side with the sign of θ (the trailing side)
    /// and strikes the other, leading, side.
    #[default]
    Right,
    /// The opposite.
    Wrong,
}

impl Style {
    /// The style of a clapper on `side` with the bell at angle `theta`.
    pub fn of(side: Side, theta: f64) -> Style {
        if side == Side::of(theta) {
            Style::Right
        } else {
            Style::Wrong
        }
    }

    /// The side the clapper rests on for this style with the bell at `theta`.
    pub fn side(self, theta: f64) -> Side {
        match self {
            Style::Right => Side::of(theta),
            Style::Wrong => Side::of(theta).opposite(),
        }
    }

    /// The other style.
    pub fn opposite(self) -> Style {
        match self {
            Style::Right => Style::Wrong,
            Style::Wrong => Style::Right,
        }
    }
}

/// Why a stroke ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EndReason {
    /// The bell reached its turning point: θ' = 0 after the bottom, or θ'
    /// reversed in a jump by an impact (at R = 1 near the turning point).
    TurningPoint,
    /// The bell went over the balance (|θ| reached 180 deg on the far side).
    OverTheBalance,
    /// [`SimConfig::max_stroke_periods`] ran out first.
    TimeLimit,
    /// The bell never moved: Coulomb friction at its bearings holds it
    /// where it started (docs/model.md §10.2).
    Held,
}

/// How a stroke ended.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StrokeEnd {
    /// Time (s).
    pub t: f64,
    /// State.
    pub y: State,
    /// What the clapper was doing.
    pub clapper: ClapperState,
    /// Why the stroke ended.
    pub reason: EndReason,
}

impl StrokeEnd {
    /// The side the clapper was left on: the side it touches, or in flight
    /// the side it is nearer to.
    pub fn side(&self) -> Side {
        self.clapper.contact_side().unwrap_or_else(|| Side::of(self.y[PHI]))
    }
}

/// Where and how a stroke begins.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StrokeStart {
    /// Time (s).
    pub t: f64,
    /// State.
    pub y: State,
    /// What the clapper is doing.
    pub clapper: ClapperState,
}

impl StrokeStart {
    /// The bell at rest at `theta` (rad) and the clapper at rest against
    /// `side`: pressed into it if the contact force presses, otherwise in
    /// flight from it (it will leave at once). For the penalty model the
    /// clapper starts at the static compression of the R k spring, so that
    /// it does not ring in the spring from the first instant.
    pub fn at_rest(bell: &Bell, cfg: &SimConfig, t: f64, theta: f64, side: Side) -> Self {
        let d = Dynamics::new(bell);
        let stops = Stops::of(bell);
        let y = [theta, stops.at(side), 0.0, 0.0];
        let (_, q) = d.resting(&y);
        // Not pressed, and more than the pivot's friction can hold.
        if side.sign() * q >= stops.grip {
            return Self {
                t,
                y,
                clapper: ClapperState::FLYING,
            };
        }
        let (y, clapper) = cfg.contact_law().at_rest(y, q, side);
        Self { t, y, clapper }
    }

    /// The side the clapper starts on (in flight: the nearer side).
    pub fn side(&self) -> Side {
        self.clapper.contact_side().unwrap_or_else(|| Side::of(self.y[PHI]))
    }
}

/// How the clapper left its starting side at a stroke's lift-off.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LiftoffKind {
    /// From rest against its side (pressed, held, or at a standstill there
    /// at the start): the lift-off of the paper's Section 3.
    FromRest,
    /// Off a bounce: the clapper, still flying from the stroke before,
    /// struck its starting side and left it again without resting; the
    /// lift-off reported is that last bounce (docs/model.md §4).
    Bounce,
}

impl LiftoffKind {
    /// "from rest" or "bounce", as reports spell it.
    pub fn name(self) -> &'static str {
        match self {
            LiftoffKind::FromRest => "from rest",
            LiftoffKind::Bounce => "bounce",
        }
    }
}

/// What the clapper did after a stroke that reached its turning point
/// between its first strike and a second impact: the double strike's
/// second impact may come after the bell has turned (docs/model.md §4).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AfterEnd {
    /// Its next impact (the second strike), after the stroke's end.
    Impact(Impact),
    /// It came to rest on the bell without another impact.
    Rested(Moment),
    /// The bell went over the balance first.
    OverTheBalance,
    /// No impact within one bell period T_b after the stroke's end.
    NoneWithin,
}

/// A simulated stroke and its quantities (docs/model.md §4).
#[derive(Clone, Debug, PartialEq)]
pub struct Stroke {
    /// How it began.
    pub start: StrokeStart,
    /// The clapper's starting side.
    pub start_side: Side,
    /// The style it began in.
    pub style: Style,
    /// Every impact, in time order.
    pub impacts: Vec<Impact>,
    /// When the clapper last left its starting side before the first strike.
    pub liftoff: Option<Moment>,
    /// How it left then: from rest, or off a bounce (a clapper still flying
    /// from the stroke before that struck its starting side and left it
    /// again without resting). `Some` exactly when `liftoff` is.
    pub liftoff_kind: Option<LiftoffKind>,
    /// When the clapper first came to rest after the first strike.
    pub rest_after_strike: Option<Moment>,
    /// When the bell passed the bottom (θ = 0).
    pub bottom: Option<Moment>,
    /// How it ended.
    pub end: StrokeEnd,
    /// The clapper followed past the end, when the stroke ended at its
    /// turning point with a first strike, no impact after it and the
    /// clapper not at rest: where its second impact came, or why none did.
    pub after_end: Option<AfterEnd>,
    /// Integrator work (the following past the end included).
    pub stats: Stats,
    /// Events handled.
    pub events: u32,
    /// What the amplitude ratio A compares ([`SimConfig::strike_amplitude`]).
    pub strike_amplitude: StrikeAmplitude,
}

impl Stroke {
    /// Index in [`impacts`](Self::impacts) of the first strike: the first
    /// impact on the side opposite the starting side.
    pub fn first_strike_index(&self) -> Option<usize> {
        self.impacts.iter().position(|i| i.side != self.start_side)
    }

    /// The first strike.
    pub fn first_strike(&self) -> Option<&Impact> {
        self.first_strike_index().map(|i| &self.impacts[i])
    }

    /// The impact after the first strike (the second strike): in the
    /// stroke, or after its end when the bell turned first.
    pub fn second_strike(&self) -> Option<&Impact> {
        let i = self.first_strike_index()?;
        self.impacts.get(i + 1).or(match &self.after_end {
            Some(AfterEnd::Impact(imp)) => Some(imp),
            _ => None,
        })
    }

    /// Why a stroke that struck has no second impact, in words; `None` if
    /// it has one or did not strike.
    pub fn no_second_impact(&self) -> Option<&'static str> {
        self.first_strike()?;
        if self.second_strike().is_some() {
            return None;
        }
        Some(match (self.after_end, self.end.reason) {
            (Some(AfterEnd::OverTheBalance), _) | (_, EndReason::OverTheBalance) => {
                "the bell went over the balance first"
            }
            (Some(AfterEnd::NoneWithin), _) => "none within a bell period after the turning point",
            (_, EndReason::TimeLimit) => "the stroke reached its time limit first",
            (_, EndReason::Held) => "the bell was held first",
            // At rest after the strike, in the stroke or after it.
            _ => "the clapper came to rest on the bell after the strike",
        })
    }

    /// Every strike: the first strike and every impact after it.
    pub fn strikes(&self) -> &[Impact] {
        match self.first_strike_index() {
            Some(i) => &self.impacts[i..],
            None => &[],
        }
    }

    /// θ at the first strike (rad).
    pub fn strike_angle(&self) -> Option<f64> {
        self.first_strike().map(|i| i.theta)
    }

    /// φ' just before the first strike (rad/s): negative ringing right from
    /// positive θ0.
    pub fn strike_velocity(&self) -> Option<f64> {
        self.first_strike().map(|i| i.phi_dot_before)
    }

    /// θ when the clapper last left its starting side before the first
    /// strike (rad).
    pub fn liftoff_angle(&self) -> Option<f64> {
        self.liftoff.map(|m| m.theta)
    }

    /// dt12: time from the first strike to the impact after it (s).
    pub fn second_strike_delay(&self) -> Option<f64> {
        Some(self.second_strike()?.t - self.first_strike()?.t)
    }

    /// A: the impact after the first strike against the first strike, by
    /// [`Self::strike_amplitude`]; by default |φ' at the second impact| /
    /// |φ' at the first strike|.
    pub fn amplitude_ratio(&self) -> Option<f64> {
        self.amplitude_ratio_by(self.strike_amplitude)
    }

    /// A by definition `how` (docs/model.md §4.1).
    pub fn amplitude_ratio_by(&self, how: StrikeAmplitude) -> Option<f64> {
        Some(how.of(self.second_strike()?) / how.of(self.first_strike()?))
    }

    /// The double strike index D of (33), clamped (docs/model.md §4), of
    /// the first strike and the impact after it (after the stroke's end if
    /// the bell turned first). `None` without a first strike, or without a
    /// second impact ([`Self::no_second_impact`] says why).
    pub fn double_strike_index(&self) -> Option<f64> {
        Some(double_strike_index(
            self.amplitude_ratio()?,
            self.second_strike_delay()? * 1e3,
        ))
    }

    /// Time from bottom dead centre (θ = 0) to the first strike (s), what a
    /// tower's striking meter reads; negative if the strike came first.
    /// `None` without a strike or without a bottom (docs/model.md §10.3).
    pub fn bdc_to_strike(&self) -> Option<f64> {
        Some(self.first_strike()?.t - self.bottom?.t)
    }

    /// Time from the first strike until the clapper came to rest (s).
    pub fn bounce_time(&self) -> Option<f64> {
        Some(self.rest_after_strike?.t - self.first_strike()?.t)
    }

    /// The style the next stroke starts in: how the clapper was left
    /// relative to the bell's final angle.
    pub fn continues_as(&self) -> Style {
        Style::of(self.end.side(), self.end.y[THETA])
    }

    /// Whether the stroke sustains its style: it strikes, reaches its
    /// turning point, and leaves the clapper where the same style goes on.
    pub fn sustained(&self) -> bool {
        self.first_strike().is_some() && self.end.reason == EndReason::TurningPoint && self.continues_as() == self.style
    }
}
