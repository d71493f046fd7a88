//! One stroke: from the bell at its start to the bell's next turning point,
//! with either contact model (SPEC §3, §4), and every quantity of a stroke.

use std::f64::consts::PI;

use crate::bell::{Bell, ParamError};
use crate::dynamics::{Dynamics, State, PHI, PHI_DOT, THETA, THETA_DOT};
use crate::ode::taylor::{Coeffs, Series, SeriesEvent, Source, MAX_EXTRA};
use crate::ode::{Dense, Direction, Dopri5, EventSystem, OdeError, Options, SeriesSystem, Stats, Taylor, MAX_EVENTS};
use crate::swing::RestingSwing;

/// One of the two places where the clapper meets the bell: φ = +φ_max
/// (`Plus`) or φ = −φ_max (`Minus`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
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

/// How the clapper rests against the bell relative to the bell's swing.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Style {
    /// The clapper rests on the side with the sign of θ (the trailing side)
    /// and strikes the other, leading, side.
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

/// The contact law between clapper and bell (SPEC §3).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ContactModel {
    /// Rigid stops with instantaneous impacts, φ'⁺ = −√R φ'⁻; bounces
    /// accumulate until the clapper comes to rest. The default.
    Impact,
    /// The paper's linear spring beyond the stops, (12), (13), with
    /// Stronge's reduced stiffness R k from maximum compression until
    /// separation.
    Penalty {
        /// k (N m/rad); the paper's is 1e6.
        stiffness: f64,
    },
}

impl ContactModel {
    /// The spring stiffness k (N m/rad); zero for rigid impacts, which
    /// have no spring.
    pub fn stiffness(self) -> f64 {
        match self {
            ContactModel::Penalty { stiffness } => stiffness,
            ContactModel::Impact => 0.0,
        }
    }
}

/// Which integrator a stroke uses.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Integrator {
    /// Taylor series of the bell's own equations, expanded to `order` (2 ..=
    /// 24) at every step, with steps of at most `h_max` (s). The default:
    /// order 12 and 0.25 s, chosen by measurement
    /// (`cargo run --release -p clapper-core --example tolerance`): on the
    /// paper's chart 2.4 times as fast as Dormand–Prince at the same
    /// tolerance, with a first strike angle eight times closer to the
    /// reference; orders 10 to 16 cost about the same. Every event function
    /// is a polynomial in each step, ruled out by a bound or checked at 16
    /// points, so `h_max` stays a fraction of a swing. With the impact
    /// model, a resting phase that starts from rest (the stroke's first) is
    /// not integrated but solved in closed form ([`crate::swing`]): the
    /// bell is then a rigid pendulum.
    Taylor {
        /// Order of the expansion.
        order: usize,
        /// Largest step (s).
        h_max: f64,
    },
    /// Dormand–Prince 5(4) with the step limit of [`Options::h_max`]: the
    /// general-purpose method, kept as the check on the Taylor one.
    Dopri5,
}

impl Default for Integrator {
    fn default() -> Self {
        Integrator::Taylor { order: 12, h_max: 0.25 }
    }
}

/// What a stroke simulation needs besides the bell.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SimConfig {
    /// θ0: the angle the bell starts from, at rest (rad). Default 171 deg,
    /// the paper's: close to the balance, far enough that the bell falls.
    pub theta0: f64,
    /// R: Stronge's energy coefficient of restitution, in (0, 1]. Default
    /// 0.2, the paper's value for its first charts.
    pub restitution: f64,
    /// The contact law. Default [`ContactModel::Impact`].
    pub contact: ContactModel,
    /// Impact model: when the next flight of a bouncing clapper would be
    /// shorter than this (s), it comes to rest. Default 1e-7 s: far below
    /// anything audible or visible in a trace, and reached after a few tens
    /// of bounces, so the Zeno sequence costs little.
    pub rest_flight_time: f64,
    /// Integrator tolerances and step budget.
    pub ode: Options,
    /// Which integrator. Default [`Integrator::Taylor`].
    pub integrator: Integrator,
    /// Most events (impacts, lift-offs, contact switches) in one stroke.
    /// Default 100,000: R = 0.99 needs a few thousand bounces to come to rest.
    pub max_events: u32,
    /// Longest stroke, in small-swing periods T_b of the bell. Default 20; a
    /// full-circle swing from 179.9 deg lasts under 3 T_b.
    pub max_stroke_periods: f64,
}

impl Default for SimConfig {
    fn default() -> Self {
        Self {
            theta0: 171f64.to_radians(),
            restitution: 0.2,
            contact: ContactModel::Impact,
            rest_flight_time: 1e-7,
            ode: Options::default(),
            integrator: Integrator::default(),
            max_events: 100_000,
            max_stroke_periods: 20.0,
        }
    }
}

/// The paper's contact stiffness (N m/rad), used by the penalty model unless
/// another is given.
pub const DEFAULT_STIFFNESS: f64 = 1e6;

impl SimConfig {
    /// Check the user-settable fields against SPEC §1 and §3.
    pub fn validate(&self) -> Result<(), ParamError> {
        if !(self.theta0.is_finite() && self.theta0 > 0.0 && self.theta0 < PI) {
            return Err(ParamError {
                field: "theta0_deg",
                value: self.theta0.to_degrees(),
                allowed: "between 0 and 180 deg, exclusive",
            });
        }
        if !(self.restitution.is_finite() && self.restitution > 0.0 && self.restitution <= 1.0) {
            return Err(ParamError {
                field: "restitution",
                value: self.restitution,
                allowed: "greater than 0 and at most 1",
            });
        }
        if let ContactModel::Penalty { stiffness } = self.contact {
            if !(stiffness.is_finite() && stiffness > 0.0) {
                return Err(ParamError {
                    field: "stiffness_n_m_per_rad",
                    value: stiffness,
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

/// What the clapper is doing.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ClapperState {
    /// In free flight between the stops.
    Flying,
    /// Impact model: at rest against a side, moving with the bell.
    Resting(Side),
    /// Penalty model: pressing into the spring on a side, stiffness k.
    Compressing(Side),
    /// Penalty model: past maximum compression, stiffness R k until it
    /// separates. `settled` once it has turned back into the spring without
    /// separating: the penalty model's way of coming to rest.
    Rebounding {
        /// The side in contact.
        side: Side,
        /// Whether the clapper has stopped bouncing.
        settled: bool,
    },
}

impl ClapperState {
    /// The side the clapper touches, if any.
    pub fn contact_side(self) -> Option<Side> {
        match self {
            ClapperState::Flying => None,
            ClapperState::Resting(s) | ClapperState::Compressing(s) => Some(s),
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
    /// The bell reached its turning point (θ' = 0 after the bottom).
    TurningPoint,
    /// The bell went over the balance (|θ| reached 180 deg on the far side).
    OverTheBalance,
    /// [`SimConfig::max_stroke_periods`] ran out first.
    TimeLimit,
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
        let s = side.sign();
        let mut y = [theta, s * bell.phi_max, 0.0, 0.0];
        let (_, q) = d.resting(&y);
        if s * q >= 0.0 {
            return Self {
                t,
                y,
                clapper: ClapperState::Flying,
            };
        }
        let clapper = match cfg.contact {
            ContactModel::Impact => ClapperState::Resting(side),
            ContactModel::Penalty { stiffness } => {
                y[PHI] -= q / (cfg.restitution * stiffness);
                ClapperState::Rebounding { side, settled: true }
            }
        };
        Self { t, y, clapper }
    }

    /// The side the clapper starts on (in flight: the nearer side).
    pub fn side(&self) -> Side {
        self.clapper.contact_side().unwrap_or_else(|| Side::of(self.y[PHI]))
    }
}

/// A simulated stroke and its quantities (SPEC §4).
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
    /// When the clapper first came to rest after the first strike.
    pub rest_after_strike: Option<Moment>,
    /// When the bell passed the bottom (θ = 0).
    pub bottom: Option<Moment>,
    /// How it ended.
    pub end: StrokeEnd,
    /// Integrator work.
    pub stats: Stats,
    /// Events handled.
    pub events: u32,
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

    /// The impact after the first strike (the second strike).
    pub fn second_strike(&self) -> Option<&Impact> {
        self.first_strike_index().and_then(|i| self.impacts.get(i + 1))
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

    /// A = |φ' at the second impact| / |φ' at the first strike|.
    pub fn amplitude_ratio(&self) -> Option<f64> {
        let first = self.first_strike()?.phi_dot_before.abs();
        let second = self.second_strike()?.phi_dot_before.abs();
        Some(second / first)
    }

    /// The double strike index D of (33), clamped (SPEC §4). `None` without
    /// a first strike; 0 when the first strike has no second impact (the
    /// clapper stayed on the bell or the stroke ended first: nothing to hear
    /// as a second strike).
    pub fn double_strike_index(&self) -> Option<f64> {
        self.first_strike()?;
        match (self.amplitude_ratio(), self.second_strike_delay()) {
            (Some(a), Some(dt)) => Some(double_strike_index(a, dt * 1e3)),
            _ => Some(0.0),
        }
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
}

/// The force law in force during one integration segment.
#[derive(Clone, Copy, Debug)]
enum ForceLaw {
    Zero,
    Resting,
    Spring { side: f64, k: f64, phi_max: f64 },
}

impl ForceLaw {
    fn force(self, d: &Dynamics, y: &State) -> f64 {
        match self {
            ForceLaw::Zero => 0.0,
            ForceLaw::Resting => d.resting(y).1,
            ForceLaw::Spring { side, k, phi_max } => -k * (y[PHI] - side * phi_max),
        }
    }
}

/// One accepted integration step, for observers: evaluate the state
/// anywhere in `[t_from, t_to]`.
pub struct StepView<'a> {
    dense: DenseRef<'a>,
    t_to: f64,
    law: ForceLaw,
    dynamics: &'a Dynamics,
}

impl StepView<'_> {
    /// Start of the step (s).
    pub fn t_from(&self) -> f64 {
        match self.dense {
            DenseRef::Rk(d) => d.t0(),
            DenseRef::Series(d) => d.t0(),
            DenseRef::Swing { t_from, .. } => t_from,
        }
    }

    /// End of the part of the step that was used (s).
    pub fn t_to(&self) -> f64 {
        self.t_to
    }

    /// The state and contact force at `t` (s).
    pub fn sample(&self, t: f64) -> Sample {
        let y = match self.dense {
            DenseRef::Rk(d) => d.eval(t),
            DenseRef::Series(d) => d.eval(t),
            DenseRef::Swing { swing, .. } => swing.state_at(t),
        };
        Sample {
            t,
            y,
            contact_force: self.law.force(self.dynamics, &y),
        }
    }
}

/// A step's dense output, from either integrator.
#[derive(Clone, Copy)]
enum DenseRef<'a> {
    Rk(&'a Dense<4>),
    Series(&'a Series<4>),
    /// Part of a closed-form resting swing, from `t_from` (s).
    Swing {
        swing: &'a RestingSwing,
        t_from: f64,
    },
}

/// Watches a simulation as it runs (argmin-style: the core never prints).
/// Every method has an empty default, so `()` observes nothing at no cost.
pub trait Observer {
    /// After every accepted integration step.
    fn on_step(&mut self, _step: &StepView<'_>) {}
    /// At every event and at the start of every stroke: the state just
    /// before and just after (they differ at an impact or a restart).
    fn on_jump(&mut self, _before: &Sample, _after: &Sample) {}
}

impl Observer for () {}

/// Records a trace in memory: samples every `interval` seconds of
/// simulated time, plus both sides of every jump.
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
}

impl Observer for TraceRecorder {
    fn on_step(&mut self, step: &StepView<'_>) {
        // Bounded: at most (t_to - t_from) / interval + 1 samples.
        loop {
            let t = self.next as f64 * self.interval;
            if t > step.t_to() {
                break;
            }
            if t >= step.t_from() {
                self.samples.push(step.sample(t));
            }
            self.next += 1;
        }
    }

    fn on_jump(&mut self, before: &Sample, after: &Sample) {
        for s in [before, after] {
            if self.samples.last() != Some(s) {
                self.samples.push(*s);
            }
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Ev {
    Hit(Side),
    LiftOff(Side),
    MaxCompression(Side),
    TurnBack(Side),
    Separation(Side),
    Bottom,
    Turning,
    OverTop,
}

/// An event function of a segment (see [`Segment::event_form`]).
#[derive(Clone, Copy)]
enum EventForm {
    /// `scale * y[index] + offset`.
    Linear { index: usize, scale: f64, offset: f64 },
    /// `scale * Q_φ`, the force holding a resting clapper.
    HoldingForce { scale: f64 },
}

/// The equations and event functions of one integration segment.
struct Segment<'a> {
    d: &'a Dynamics,
    clapper: ClapperState,
    k: f64,
    rk: f64,
    phi_max: f64,
    /// +1 if the stroke starts at positive θ, −1 otherwise.
    s0: f64,
    events: [Ev; MAX_EVENTS],
    /// The same events as levels on series, for the Taylor integrator.
    series_events: [SeriesEvent; MAX_EVENTS],
    n: usize,
}

impl<'a> Segment<'a> {
    fn new(d: &'a Dynamics, cfg: &SimConfig, clapper: ClapperState, s0: f64, bottom_passed: bool) -> Self {
        let k = cfg.contact.stiffness();
        let mut events = [Ev::OverTop; MAX_EVENTS];
        let mut n = 0;
        let mut push = |e: Ev| {
            events[n] = e;
            n += 1;
        };
        push(Ev::OverTop);
        push(if bottom_passed { Ev::Turning } else { Ev::Bottom });
        match clapper {
            ClapperState::Flying => {
                push(Ev::Hit(Side::Plus));
                push(Ev::Hit(Side::Minus));
            }
            ClapperState::Resting(s) => push(Ev::LiftOff(s)),
            ClapperState::Compressing(s) => push(Ev::MaxCompression(s)),
            ClapperState::Rebounding { side, settled } => {
                push(Ev::Separation(side));
                if !settled {
                    push(Ev::TurnBack(side));
                }
            }
        }
        let mut seg = Self {
            d,
            clapper,
            k,
            rk: cfg.restitution * k,
            phi_max: d.bell().phi_max,
            s0,
            events,
            series_events: [SeriesEvent {
                source: Source::State(0),
                level: 0.0,
                direction: Direction::Either,
            }; MAX_EVENTS],
            n,
        };
        for i in 0..n {
            seg.series_events[i] = seg.series_event(i);
        }
        seg
    }

    /// Event `i` as a level on a series: `scale * x + offset` with scale
    /// ±1 crosses zero where `x` crosses `-offset * scale`, in the same
    /// direction if the scale is +1 and the other if it is −1.
    fn series_event(&self, i: usize) -> SeriesEvent {
        let (source, scale, offset) = match self.event_form(self.events[i]) {
            EventForm::Linear { index, scale, offset } => (Source::State(index), scale, offset),
            EventForm::HoldingForce { scale } => (Source::Extra(0), scale, 0.0),
        };
        let direction = EventSystem::direction(self, i);
        SeriesEvent {
            source,
            level: -offset * scale,
            direction: if scale > 0.0 { direction } else { direction.reversed() },
        }
    }

    /// What event function `e` is, in one place for both integrators: a
    /// state component scaled and shifted, or the holding force's sign.
    fn event_form(&self, e: Ev) -> EventForm {
        let linear = |index, scale, offset| EventForm::Linear { index, scale, offset };
        match e {
            // Positive once the clapper is past the stop.
            Ev::Hit(s) | Ev::Separation(s) => linear(PHI, s.sign(), -self.phi_max),
            // Positive once the holding force pulls instead of pushes.
            Ev::LiftOff(s) => EventForm::HoldingForce { scale: s.sign() },
            // Positive once the clapper moves back out of the spring.
            Ev::MaxCompression(s) => linear(PHI_DOT, -s.sign(), 0.0),
            // Positive once it moves into the spring again.
            Ev::TurnBack(s) => linear(PHI_DOT, s.sign(), 0.0),
            Ev::Bottom => linear(THETA, self.s0, 0.0),
            Ev::Turning => linear(THETA_DOT, self.s0, 0.0),
            Ev::OverTop => linear(THETA, -self.s0, -PI),
        }
    }

    fn law(&self) -> ForceLaw {
        ForceLaw::of(self.clapper, self.k, self.rk, self.phi_max)
    }
}

impl ForceLaw {
    /// The law for a clapper in `clapper` state, with spring stiffnesses
    /// `k` (compressing) and `rk` (rebounding) (N m/rad).
    fn of(clapper: ClapperState, k: f64, rk: f64, phi_max: f64) -> ForceLaw {
        match clapper {
            ClapperState::Flying => ForceLaw::Zero,
            ClapperState::Resting(_) => ForceLaw::Resting,
            ClapperState::Compressing(s) => ForceLaw::Spring {
                side: s.sign(),
                k,
                phi_max,
            },
            ClapperState::Rebounding { side, .. } => ForceLaw::Spring {
                side: side.sign(),
                k: rk,
                phi_max,
            },
        }
    }
}

impl EventSystem<4> for Segment<'_> {
    #[inline]
    fn rhs(&self, _t: f64, y: &State) -> State {
        match self.clapper {
            ClapperState::Flying => self.d.rhs_free(y),
            ClapperState::Resting(_) => self.d.rhs_resting(y),
            ClapperState::Compressing(s) => self.d.rhs_forced(y, -self.k * (y[PHI] - s.sign() * self.phi_max)),
            ClapperState::Rebounding { side, .. } => {
                self.d.rhs_forced(y, -self.rk * (y[PHI] - side.sign() * self.phi_max))
            }
        }
    }

    fn n_events(&self) -> usize {
        self.n
    }

    #[inline]
    fn event(&self, i: usize, _t: f64, y: &State) -> f64 {
        match self.event_form(self.events[i]) {
            EventForm::Linear { index, scale, offset } => scale * y[index] + offset,
            EventForm::HoldingForce { scale } => scale * self.d.resting(y).1,
        }
    }

    fn direction(&self, i: usize) -> Direction {
        match self.events[i] {
            Ev::Separation(_) | Ev::Bottom => Direction::Falling,
            _ => Direction::Rising,
        }
    }
}

impl SeriesSystem<4> for Segment<'_> {
    fn expand(&self, y: &State, p: usize, x: &mut [Coeffs; 4], extra: &mut [Coeffs; MAX_EXTRA]) {
        match self.clapper {
            ClapperState::Flying => self.d.series_free(y, 0.0, 0.0, p, x),
            // The holding force is extra series 0 (see `series_event`).
            ClapperState::Resting(_) => self.d.series_resting(y, p, x, &mut extra[0]),
            ClapperState::Compressing(s) => self.d.series_free(y, self.k, s.sign() * self.phi_max, p, x),
            ClapperState::Rebounding { side, .. } => self.d.series_free(y, self.rk, side.sign() * self.phi_max, p, x),
        }
    }

    fn events(&self) -> &[SeriesEvent] {
        &self.series_events[..self.n]
    }
}

/// A Taylor order for a first step of `flight` (s) after a bounce: the terms
/// of a series fall off about as (t / 0.25 s)^n over the bell's motion, so
/// a short flight needs few of them to reach `rtol`. Only a work estimate:
/// the step-size control keeps the accuracy whatever the order.
fn bounce_order(flight: f64, rtol: f64) -> usize {
    let ratio = flight / 0.25;
    if !(ratio > 0.0 && ratio < 0.5) {
        return usize::MAX;
    }
    (rtol.ln() / ratio.ln()).ceil().max(2.0) as usize + 1
}

/// The first event of `seg` on the closed-form swing `sw` after the bell's
/// angle `theta` (rad): its time (s), state, and index among the segment's
/// events. `None` if the swing's form does not apply (it moves away from
/// the bottom) or no event comes before the end of the half swing or
/// `t_limit` (s): the stroke then integrates.
fn swing_event(
    sw: &RestingSwing,
    seg: &Segment,
    theta: f64,
    bottom_passed: bool,
    t_limit: f64,
) -> Option<(f64, State, usize)> {
    // Each event below is a level θ crosses going from the s0 side
    // towards the other, as in the segment's event functions.
    if sw.theta_direction() != -seg.s0 {
        return None;
    }
    let from = sw.sigma(theta);
    let end = -sw.amplitude();
    let mut best: Option<(f64, usize)> = None;
    for (i, e) in seg.events[..seg.n].iter().enumerate() {
        let sigma = match *e {
            Ev::LiftOff(_) => sw.force_zero_after(from),
            Ev::Bottom => Some(sw.sigma(0.0)),
            Ev::OverTop => Some(sw.sigma(-seg.s0 * PI)),
            Ev::Turning => bottom_passed.then_some(end),
            _ => None,
        };
        let Some(sigma) = sigma.filter(|&s| s < from && s >= end) else {
            continue;
        };
        // The first along the swing; on a tie the first listed, as the
        // integrators do.
        if best.is_none_or(|(b, _)| sigma > b) {
            best = Some((sigma, i));
        }
    }
    let (sigma, i) = best?;
    let t_e = sw.t0() + sw.time_at_sigma(sigma);
    (t_e <= t_limit).then(|| (t_e, sw.state_at_sigma(sigma), i))
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
    bell.validate()?;
    cfg.validate()?;
    let d = Dynamics::new(bell);
    let mut rk = Dopri5::<4>::new(cfg.ode);
    let mut series = match cfg.integrator {
        Integrator::Taylor { order, h_max } => Some(Taylor::<4>::new(cfg.ode, order, h_max)),
        Integrator::Dopri5 => None,
    };
    let e = cfg.restitution.sqrt();
    let k = cfg.contact.stiffness();
    let law_of = |clapper| ForceLaw::of(clapper, k, cfg.restitution * k, bell.phi_max);
    let s0 = if start.y[THETA] >= 0.0 { 1.0 } else { -1.0 };
    let start_side = start.side();
    let t_limit = start.t + cfg.max_stroke_periods * bell.tb();

    let mut t = start.t;
    let mut y = start.y;
    let mut clapper = start.clapper;
    let mut bottom_passed = false;
    let mut impacts: Vec<Impact> = Vec::with_capacity(32);
    let mut liftoff = None;
    let mut rest_after_strike = None;
    let mut bottom = None;
    let mut events = 0u32;
    let mut struck = false;
    // A resting phase from rest is a closed-form swing with the Taylor
    // integrator (the Dormand–Prince path integrates it, as a check).
    let closed_form_rest = matches!(cfg.integrator, Integrator::Taylor { .. }) && cfg.contact == ContactModel::Impact;
    let mut swing: Option<RestingSwing> = None;
    let mut swing_given_up = false;

    let initial = Sample {
        t,
        y,
        contact_force: law_of(clapper).force(&d, &y),
    };
    observer.on_jump(&initial, &initial);
    if clapper == ClapperState::Flying && start_side == Side::of(y[PHI]) && (y[PHI].abs() - bell.phi_max).abs() < 1e-12
    {
        // Starts against its side but not pressed: it leaves at once.
        liftoff = Some(Moment { t, theta: y[THETA] });
    }

    let reason = loop {
        let seg = Segment::new(&d, cfg, clapper, s0, bottom_passed);
        let law = seg.law();
        if !matches!(clapper, ClapperState::Resting(_)) {
            swing = None;
            swing_given_up = false;
        } else if swing.is_none() && closed_form_rest && y[THETA_DOT] == 0.0 && !swing_given_up {
            swing = RestingSwing::from_rest(&d, t, y[THETA], y[PHI]);
        }
        let closed = swing.as_ref().and_then(|sw| {
            let (t_e, y_e, i) = swing_event(sw, &seg, y[THETA], bottom_passed, t_limit)?;
            observer.on_step(&StepView {
                dense: DenseRef::Swing { swing: sw, t_from: t },
                t_to: t_e,
                law,
                dynamics: &d,
            });
            Some(crate::ode::Segment {
                t: t_e,
                y: y_e,
                event: Some(i),
            })
        });
        if closed.is_none() && swing.is_some() {
            // Not an event this form finds: integrate the rest of the phase.
            swing = None;
            swing_given_up = true;
        }
        let stop = match (closed, series.as_mut()) {
            (Some(stop), _) => stop,
            (None, Some(ts)) => ts.integrate(&seg, t, y, t_limit, &mut |dense: &Series<4>, t_to| {
                observer.on_step(&StepView {
                    dense: DenseRef::Series(dense),
                    t_to,
                    law,
                    dynamics: &d,
                })
            })?,
            (None, None) => rk.integrate(&seg, t, y, t_limit, &mut |dense: &Dense<4>, t_to| {
                observer.on_step(&StepView {
                    dense: DenseRef::Rk(dense),
                    t_to,
                    law,
                    dynamics: &d,
                })
            })?,
        };
        t = stop.t;
        y = stop.y;
        let Some(i) = stop.event else {
            break EndReason::TimeLimit;
        };
        events += 1;
        if events > cfg.max_events {
            return Err(SimError::EventLimit {
                limit: cfg.max_events,
                t,
            });
        }
        let before = Sample {
            t,
            y,
            contact_force: law.force(&d, &y),
        };
        let mut departed: Option<Side> = None;
        match seg.events[i] {
            Ev::OverTop => break EndReason::OverTheBalance,
            Ev::Turning => break EndReason::TurningPoint,
            Ev::Bottom => {
                bottom_passed = true;
                bottom = Some(Moment { t, theta: y[THETA] });
            }
            Ev::Hit(side) => {
                let s = side.sign();
                if side != start_side && !struck {
                    struck = true;
                }
                impacts.push(Impact {
                    t,
                    theta: y[THETA],
                    phi_dot_before: y[PHI_DOT],
                    phi_dot_after: None,
                    side,
                });
                match cfg.contact {
                    ContactModel::Impact => {
                        y[PHI] = s * bell.phi_max;
                        let bounced = d.impact(&y, e);
                        // Would the next flight be shorter than rest_flight_time?
                        let toward = s * d.accel(&bounced, 0.0).phi;
                        let away = -s * bounced[PHI_DOT];
                        let comes_to_rest = toward > 0.0 && 2.0 * away < cfg.rest_flight_time * toward;
                        let stuck = d.impact(&y, 0.0);
                        if comes_to_rest && s * d.resting(&stuck).1 < 0.0 {
                            y = stuck;
                            clapper = ClapperState::Resting(side);
                            if struck && rest_after_strike.is_none() {
                                rest_after_strike = Some(Moment { t, theta: y[THETA] });
                            }
                        } else {
                            y = bounced;
                            clapper = ClapperState::Flying;
                            departed = Some(side);
                            if let (Some(ts), true) = (series.as_mut(), toward > 0.0) {
                                // The flight ends near 2 v / a: seek it over a little more.
                                let span = 3.0 * away / toward;
                                ts.hint_next(bounce_order(span, cfg.ode.rtol), span);
                            }
                        }
                        if let Some(last) = impacts.last_mut() {
                            last.phi_dot_after = Some(y[PHI_DOT]);
                        }
                    }
                    ContactModel::Penalty { .. } => {
                        clapper = ClapperState::Compressing(side);
                        // A spring contact is much shorter than a free-flight step.
                        rk.reset_step();
                    }
                }
            }
            Ev::LiftOff(side) => {
                clapper = ClapperState::Flying;
                departed = Some(side);
            }
            Ev::MaxCompression(side) => {
                clapper = ClapperState::Rebounding { side, settled: false };
            }
            Ev::TurnBack(side) => {
                clapper = ClapperState::Rebounding { side, settled: true };
                if struck && rest_after_strike.is_none() {
                    // At rest since the contact it never left.
                    if let Some(last) = impacts.last() {
                        rest_after_strike = Some(Moment {
                            t: last.t,
                            theta: last.theta,
                        });
                    }
                }
            }
            Ev::Separation(side) => {
                clapper = ClapperState::Flying;
                departed = Some(side);
                if let Some(last) = impacts
                    .last_mut()
                    .filter(|l| l.side == side && l.phi_dot_after.is_none())
                {
                    last.phi_dot_after = Some(y[PHI_DOT]);
                }
            }
        }
        if departed == Some(start_side) && !struck {
            liftoff = Some(Moment { t, theta: y[THETA] });
        }
        let after_law = law_of(clapper);
        observer.on_jump(
            &before,
            &Sample {
                t,
                y,
                contact_force: after_law.force(&d, &y),
            },
        );
    };
    let last_law = law_of(clapper);
    let last = Sample {
        t,
        y,
        contact_force: last_law.force(&d, &y),
    };
    observer.on_jump(&last, &last);

    Ok(Stroke {
        start,
        start_side,
        style: Style::of(start_side, start.y[THETA]),
        impacts,
        liftoff,
        rest_after_strike,
        bottom,
        end: StrokeEnd { t, y, clapper, reason },
        stats: series.as_ref().map_or_else(|| rk.stats(), Taylor::stats),
        events,
    })
}
