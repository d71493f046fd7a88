//! One stroke: from the bell at its start to the bell's next turning point,
//! with any contact law (docs/model.md §3, §4), and every quantity of a
//! stroke.
//!
//! [`run_stroke`] is a short loop: build the segment (`segment.rs`) for
//! the clapper's state, let the stepper run it to its first event, hand a
//! contact event to the [`ContactLaw`], and tell the recorder
//! (`recorder.rs`) what happened.

mod recorder;
mod segment;

use std::f64::consts::PI;

use crate::bell::{Bell, ParamError};
pub use crate::contact::{ClapperState, ContactModel, Restitution, Side, DEFAULT_STIFFNESS};
use crate::contact::{ContactLaw, ForceLaw, Stops};
use crate::dynamics::{Dynamics, Load, State, PHI, PHI_DOT, THETA, THETA_DOT};
use crate::ode::{DenseOutput, Dopri5, Fallback, OdeError, Options, Stats, Stepper, Stop, Taylor};
use crate::ringer::Pull;
use crate::swing::ClosedFormSwing;
use recorder::StrokeRecorder;
use segment::{BellEvent, Ev, FrictionEvent, Segment, StrokeFrame};

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

/// A time (s) and the bell angle θ then (rad).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Moment {
    /// Time (s).
    pub t: f64,
    /// θ (rad).
    pub theta: f64,
}

/// One impact of the clapper on the bell (for the penalty model: the start
/// of one contact).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Impact {
    /// Time (s).
    pub t: f64,
    /// Bell angle θ (rad).
    pub theta: f64,
    /// φ' just before (rad/s).
    pub phi_dot_before: f64,
    /// φ' just after (impact model), or at separation (penalty model) (rad/s);
    /// zero if the clapper came to rest, `None` if it was still in contact
    /// when the stroke ended.
    pub phi_dot_after: Option<f64>,
    /// The side hit.
    pub side: Side,
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

/// What the amplitude ratio A of (33) compares between the first strike
/// and the impact after it (docs/model.md §4.1). With one coefficient of
/// restitution (R2 = R) the three are the same number; they part when the
/// later bounces lose less than the strike (R2 > R), as the paper's drops
/// show.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case"))]
pub enum StrikeAmplitude {
    /// The clapper's rate just before each impact, |φ'⁻| (the paper's
    /// reading, and the default).
    #[default]
    Rate,
    /// The impulse each impact gives the bell, ∝ |φ'⁻ − φ'⁺|: what the
    /// modal synthesis sets each mode moving with (`clapper synth`), so the
    /// amplitude ratio of the synthesised strikes.
    Impulse,
    /// The energy each impact takes from the clapper's motion,
    /// ∝ φ'⁻² − φ'⁺², as an amplitude (its square root): the paper's
    /// reading of a low R, that the strike's lost energy is what rings.
    Vibration,
}

impl StrikeAmplitude {
    /// Whether this is the default, [`StrikeAmplitude::Rate`].
    pub fn is_rate(&self) -> bool {
        *self == Self::Rate
    }

    /// The size of impact `i` by this definition, in units that cancel in
    /// the ratio (rad/s). A contact still open when the stroke ended counts
    /// as come to rest (φ'⁺ = 0).
    pub fn of(self, i: &Impact) -> f64 {
        let (before, after) = (i.phi_dot_before, i.phi_dot_after.unwrap_or(0.0));
        match self {
            Self::Rate => before.abs(),
            Self::Impulse => (before - after).abs(),
            Self::Vibration => (before * before - after * after).max(0.0).sqrt(),
        }
    }
}

/// D = max(0, A − 0.2) · max(0, dt12 − 22) / 2.25, dt12 in ms (33).
pub fn double_strike_index(amplitude_ratio: f64, delay_ms: f64) -> f64 {
    (amplitude_ratio - 0.2).max(0.0) * (delay_ms - 22.0).max(0.0) / 2.25
}

/// A state sampled during a simulation, with the contact force.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    /// Time (s).
    pub t: f64,
    /// State `[θ, φ, θ', φ']` (rad, rad/s).
    pub y: State,
    /// Generalised contact force Q_φ on the clapper (N m): the force of a
    /// resting or compressed contact; zero in flight. Impacts are impulses
    /// and do not show.
    pub contact_force: f64,
    /// Generalised forces of friction (Q_θ, Q_φ) (N m) besides the contact
    /// force; both zero for a frictionless bell. Q_φ is zero while the
    /// clapper rests or sticks: the contact force then holds it all.
    pub friction: [f64; 2],
}

/// One accepted integration step, for observers: evaluate the state
/// anywhere in `[t_from, t_to]`.
pub struct StepView<'a> {
    dense: &'a dyn DenseOutput<4>,
    t_to: f64,
    law: ForceLaw,
    load: Option<Load>,
    dynamics: &'a Dynamics,
}

impl StepView<'_> {
    /// Start of the step (s).
    pub fn t_from(&self) -> f64 {
        self.dense.t0()
    }

    /// End of the part of the step that was used (s).
    pub fn t_to(&self) -> f64 {
        self.t_to
    }

    /// The state and contact force at `t` (s).
    pub fn sample(&self, t: f64) -> Sample {
        let y = self.dense.eval(t);
        Sample::new(t, y, self.law, self.load.as_ref(), self.dynamics)
    }

    /// The friction acting over this step, if any: its power along the
    /// step is what friction takes from the bell and clapper.
    pub fn friction(&self) -> Option<Load> {
        self.load
    }
}

impl Sample {
    fn new(t: f64, y: State, law: ForceLaw, load: Option<&Load>, d: &Dynamics) -> Self {
        let (contact_force, friction) = match (law, load) {
            (ForceLaw::Resting, Some(l)) => (d.resting_q(&y, l.theta(&y)).1, [l.theta(&y), 0.0]),
            (_, Some(l)) => (law.force(d, &y), [l.theta(&y), l.phi(&y)]),
            (_, None) => (law.force(d, &y), [0.0; 2]),
        };
        Sample {
            t,
            y,
            contact_force,
            friction,
        }
    }
}

/// Watches a simulation as it runs (argmin-style: the core never prints).
/// Every method has an empty default, so `()` observes nothing at no cost.
pub trait Observer {
    /// After every accepted integration step.
    fn on_step(&mut self, _step: &StepView<'_>) {}
    /// At every event and at the start of every stroke: the state just
    /// before and just after (they differ at an impact or a restart).
    fn on_jump(&mut self, _before: &Sample, _after: &Sample) {}
    /// Whether it watches nothing (then a caller that tries strokes
    /// before keeping one need not run the kept one again for it).
    const SILENT: bool = false;
}

impl Observer for () {
    const SILENT: bool = true;
}

/// Samples a trace every `interval` seconds of simulated time, plus both
/// sides of every jump, and hands each sample to `sink` as it comes: a
/// trace of any length in constant memory (a file written as it goes).
#[derive(Clone, Debug)]
pub struct TraceSampler<F> {
    /// Sampling interval (s).
    pub interval: f64,
    next: u64,
    last: Option<Sample>,
    sink: F,
}

impl<F: FnMut(&Sample)> TraceSampler<F> {
    /// A sampler every `interval` seconds (> 0) into `sink`.
    pub fn new(interval: f64, sink: F) -> Self {
        Self {
            interval,
            next: 0,
            last: None,
            sink,
        }
    }

    fn push(&mut self, s: Sample) {
        (self.sink)(&s);
        self.last = Some(s);
    }
}

impl<F: FnMut(&Sample)> Observer for TraceSampler<F> {
    fn on_step(&mut self, step: &StepView<'_>) {
        // Bounded: at most (t_to - t_from) / interval + 1 samples.
        loop {
            let t = self.next as f64 * self.interval;
            if t > step.t_to() {
                break;
            }
            if t >= step.t_from() {
                self.push(step.sample(t));
            }
            self.next += 1;
        }
    }

    fn on_jump(&mut self, before: &Sample, after: &Sample) {
        for s in [before, after] {
            if self.last.as_ref() != Some(s) {
                self.push(*s);
            }
        }
    }
}

/// Records a trace in memory: samples every `interval` seconds of
/// simulated time, plus both sides of every jump ([`TraceSampler`] into
/// a vector).
#[derive(Clone, Debug, PartialEq)]
pub struct TraceRecorder {
    /// Sampling interval (s).
    pub interval: f64,
    next: u64,
    /// The samples, in time order.
    pub samples: Vec<Sample>,
}

impl TraceRecorder {
    /// A recorder sampling every `interval` seconds (> 0).
    pub fn new(interval: f64) -> Self {
        Self {
            interval,
            next: 0,
            samples: Vec::new(),
        }
    }

    /// The sampler this recorder is, for one call.
    fn sampler(&mut self) -> TraceSampler<impl FnMut(&Sample) + '_> {
        let samples = &mut self.samples;
        TraceSampler {
            interval: self.interval,
            next: self.next,
            last: samples.last().copied(),
            sink: move |s: &Sample| samples.push(*s),
        }
    }
}

impl Observer for TraceRecorder {
    fn on_step(&mut self, step: &StepView<'_>) {
        let next = {
            let mut s = self.sampler();
            s.on_step(step);
            s.next
        };
        self.next = next;
    }

    fn on_jump(&mut self, before: &Sample, after: &Sample) {
        self.sampler().on_jump(before, after);
    }
}

/// Simulate one stroke from `start` until the bell's next turning point.
///
/// ```
/// use clapper_core::{bell::Bell, stroke::{run_stroke, SimConfig, Side, StrokeStart}};
///
/// let bell = Bell::lab();
/// let cfg = SimConfig::default();
/// // Ringing right from +171 deg: the clapper rests on the + side.
/// let start = StrokeStart::at_rest(&bell, &cfg, 0.0, cfg.theta0, Side::Plus);
/// let stroke = run_stroke(&bell, &cfg, start, &mut ()).unwrap();
/// assert!(stroke.sustained());
/// assert!(stroke.strike_velocity().unwrap() < 0.0);
/// ```
pub fn run_stroke<O: Observer>(
    bell: &Bell,
    cfg: &SimConfig,
    start: StrokeStart,
    observer: &mut O,
) -> Result<Stroke, SimError> {
    run_stroke_pulled(bell, cfg, start, None, observer)
}

/// [`run_stroke`] with a ringer's `pull` on the rope, if any (ringing up
/// and down, [`crate::ringer`]).
pub fn run_stroke_pulled<O: Observer>(
    bell: &Bell,
    cfg: &SimConfig,
    start: StrokeStart,
    pull: Option<Pull>,
    observer: &mut O,
) -> Result<Stroke, SimError> {
    bell.validate()?;
    cfg.validate()?;
    if let Some(p) = pull {
        p.validate()?;
    }
    let TaylorOptions { order, h_max } = cfg.taylor;
    match cfg.integrator {
        // A resting phase from rest is a closed-form swing with the rigid
        // law (the Dormand–Prince path integrates it, as a check).
        Integrator::Taylor if cfg.contact == ContactModel::Impact => {
            let taylor = Taylor::new(cfg.ode, order, h_max);
            let stepper = Fallback {
                first: ClosedFormSwing::default(),
                then: taylor,
            };
            drive(stepper, bell, cfg, start, pull, observer)
        }
        Integrator::Taylor => drive(Taylor::new(cfg.ode, order, h_max), bell, cfg, start, pull, observer),
        Integrator::Dopri5 => drive(Dopri5::new(cfg.ode), bell, cfg, start, pull, observer),
    }
}

/// [`run_stroke`] with one stepper: segments from event to event, each
/// event handed to the bell (bottom, turning point, over the balance) or
/// the contact law, and what happened to the recorder.
fn drive<M, O>(
    mut stepper: M,
    bell: &Bell,
    cfg: &SimConfig,
    start: StrokeStart,
    pull: Option<Pull>,
    observer: &mut O,
) -> Result<Stroke, SimError>
where
    M: for<'a> Stepper<4, Segment<'a>>,
    O: Observer,
{
    let d = Dynamics::new(bell);
    let law = cfg.contact_law();
    let stops = Stops::of(bell);
    // The side of the bottom the bell starts on (±1): it swings toward the
    // bottom, unless bearing friction says otherwise (below).
    let mut s0 = if start.y[THETA] >= 0.0 { 1.0 } else { -1.0 };
    let t_limit = start.t + cfg.max_stroke_periods * bell.tb();
    let mut rec = StrokeRecorder::new(start, &stops);
    let (mut t, mut y, mut clapper) = (start.t, start.y, start.clapper);
    let friction = &bell.hanging.friction;
    // The bearing's Coulomb torque opposes the bell's motion, which keeps
    // its sign until the stroke's turning point; a bell at rest that the
    // friction can hold does not move at all.
    let mut held = false;
    let frame = StrokeFrame {
        stops,
        friction: (!friction.is_none()).then(|| {
            let tau = friction.bell_friction;
            let mut dir = y[THETA_DOT].signum();
            if tau > 0.0 && y[THETA_DOT].abs() < 1e-9 {
                let hold = d.bell_holding_torque(&y, !clapper.is_flying());
                held = hold.abs() <= tau;
                dir = -hold.signum();
            }
            if tau > 0.0 {
                // Events are set by the direction the bell actually moves:
                // from a turning point between the equilibrium and the
                // bottom it swings away from the bottom.
                s0 = -dir;
            }
            Load {
                bell_damping: friction.bell_damping,
                bell_torque: if tau > 0.0 { -dir * tau } else { 0.0 },
                clapper_damping: friction.clapper_damping,
                clapper_torque: friction.clapper_friction,
            }
        }),
        pull,
    };
    let sample = |t, y: State, clapper| {
        let load = frame.load(&d, clapper, &y);
        Sample::new(t, y, law.force_law(clapper, &frame.stops), load.as_ref(), &d)
    };
    let mut bottom_passed = false;
    let mut events = 0u32;
    let initial = sample(t, y, clapper);
    observer.on_jump(&initial, &initial);
    let reason = loop {
        if held {
            break EndReason::Held;
        }
        let seg = Segment::new(&d, law.as_ref(), &frame, clapper, &y, s0, bottom_passed);
        let (law_now, load_now) = (seg.force_law(), seg.load());
        let stop = stepper.integrate(&seg, t, y, t_limit, &mut |dense, t_to| {
            observer.on_step(&StepView {
                dense,
                t_to,
                law: law_now,
                load: load_now,
                dynamics: &d,
            })
        })?;
        (t, y) = (stop.t, stop.y);
        let Stop::Event(i) = stop.stop else {
            break EndReason::TimeLimit;
        };
        events += 1;
        if events > cfg.max_events {
            return Err(SimError::EventLimit {
                limit: cfg.max_events,
                t,
            });
        }
        let before = Sample::new(t, y, law_now, load_now.as_ref(), &d);
        match seg.kind(i) {
            Ev::Bell(BellEvent::OverTop) => break EndReason::OverTheBalance,
            Ev::Bell(BellEvent::Turning) => break EndReason::TurningPoint,
            Ev::Bell(BellEvent::Bottom) => {
                bottom_passed = true;
                rec.bottom(t, y[THETA]);
            }
            // The next segment takes the pull on or off.
            Ev::Bell(BellEvent::Pull) => {}
            Ev::Contact(e) => {
                // The rest after a bounce is judged with the forces of the
                // flight to come: friction, and the ringer's pull.
                let judge = load_now.map(|l| Load {
                    clapper_torque: frame.friction.map_or(0.0, |f| f.clapper_torque),
                    ..l
                });
                let tr = law.transition(&d, e, y, clapper, judge.as_ref());
                rec.contact(t, &y, &tr);
                // An impact may reverse the bell's rate in a jump (at R = 1
                // near a turning point): the bell turns there, though θ'
                // never passes through zero (docs/model.md §4).
                let reversed = y[THETA_DOT] * s0 < 0.0 && tr.y[THETA_DOT] * s0 > 0.0;
                (y, clapper) = (tr.y, tr.clapper);
                if reversed {
                    observer.on_jump(&before, &sample(t, y, clapper));
                    break EndReason::TurningPoint;
                }
                if let Some(next) = tr.next {
                    stepper.expect(next);
                }
            }
            Ev::Friction(e) => (y, clapper) = frictional(&d, &frame, e, y, clapper, load_now),
        }
        observer.on_jump(&before, &sample(t, y, clapper));
    };
    let last = sample(t, y, clapper);
    observer.on_jump(&last, &last);
    // The second impact of a double strike may come after the bell has
    // turned: follow the clapper (unobserved: the stroke is over) until it.
    let after_end = if reason == EndReason::TurningPoint && rec.awaits_second_impact() {
        let back = StrokeFrame {
            stops: frame.stops,
            // The bearing's Coulomb torque turns with the bell; the ringer's
            // pull is left out of this look past the stroke.
            friction: frame.friction.map(|l| Load {
                bell_torque: -l.bell_torque,
                ..l
            }),
            pull: None,
        };
        let budget = cfg.max_events.saturating_sub(events);
        Some(follow_to_next_impact(
            &mut stepper,
            &d,
            law.as_ref(),
            &back,
            (t, y, clapper),
            -s0,
            t + bell.tb(),
            budget,
        )?)
    } else {
        None
    };
    let mut stroke = rec.finish(
        StrokeEnd { t, y, clapper, reason },
        stepper.stats(),
        events,
        cfg.strike_amplitude,
    );
    stroke.after_end = after_end;
    Ok(stroke)
}

/// Follow the clapper from a stroke's end (time, state, clapper) with the
/// bell swinging back (`s0`: the side of the bottom it now starts from)
/// until its next impact, its rest, the bell over the balance, `t_limit`
/// (s) or `budget` events, whichever is first.
#[allow(clippy::too_many_arguments)]
fn follow_to_next_impact<M>(
    stepper: &mut M,
    d: &Dynamics,
    law: &dyn ContactLaw,
    frame: &StrokeFrame,
    (mut t, mut y, mut clapper): (f64, State, ClapperState),
    mut s0: f64,
    t_limit: f64,
    budget: u32,
) -> Result<AfterEnd, SimError>
where
    M: for<'a> Stepper<4, Segment<'a>>,
{
    let mut bottom_passed = false;
    for _ in 0..budget {
        let seg = Segment::new(d, law, frame, clapper, &y, s0, bottom_passed);
        let load_now = seg.load();
        let stop = stepper.integrate(&seg, t, y, t_limit, &mut |_: &dyn DenseOutput<4>, _| {})?;
        (t, y) = (stop.t, stop.y);
        let Stop::Event(i) = stop.stop else {
            return Ok(AfterEnd::NoneWithin);
        };
        match seg.kind(i) {
            Ev::Bell(BellEvent::OverTop) => return Ok(AfterEnd::OverTheBalance),
            // Another swing: watch its bottom and turning point afresh.
            Ev::Bell(BellEvent::Turning) => (s0, bottom_passed) = (-s0, false),
            Ev::Bell(BellEvent::Bottom) => bottom_passed = true,
            Ev::Bell(BellEvent::Pull) => {}
            Ev::Contact(e) => {
                let judge = load_now.map(|l| Load {
                    clapper_torque: frame.friction.map_or(0.0, |f| f.clapper_torque),
                    ..l
                });
                let tr = law.transition(d, e, y, clapper, judge.as_ref());
                if let Some(side) = tr.impact {
                    return Ok(AfterEnd::Impact(Impact {
                        t,
                        theta: y[THETA],
                        phi_dot_before: y[PHI_DOT],
                        phi_dot_after: tr.rebound,
                        side,
                    }));
                }
                if tr.rest.is_some() {
                    return Ok(AfterEnd::Rested(Moment { t, theta: y[THETA] }));
                }
                (y, clapper) = (tr.y, tr.clapper);
                if let Some(next) = tr.next {
                    stepper.expect(next);
                }
            }
            Ev::Friction(e) => (y, clapper) = frictional(d, frame, e, y, clapper, load_now),
        }
    }
    Ok(AfterEnd::NoneWithin)
}

/// The clapper at a friction event: still relative to the bell, for an
/// instant (slip stops, unless the pivot's friction can hold it: stuck) or
/// from now on; or free again (breakaway).
fn frictional(
    d: &Dynamics,
    frame: &StrokeFrame,
    e: FrictionEvent,
    mut y: State,
    clapper: ClapperState,
    load: Option<Load>,
) -> (State, ClapperState) {
    y[PHI_DOT] = 0.0;
    let clapper = match e {
        FrictionEvent::SlipStops => {
            let bell_load = load.map_or(0.0, |l| l.theta(&y));
            let hold = d.resting_q(&y, bell_load).1;
            if hold.abs() <= frame.stops.grip {
                ClapperState::Stuck
            } else {
                clapper
            }
        }
        FrictionEvent::Breakaway => ClapperState::FLYING,
    };
    (y, clapper)
}
