//! The interface every method shares: systems and their event functions,
//! error weights, dense output, steppers and their stops, options,
//! statistics and errors; and the small helpers of event location and
//! step control the methods use alike.

/// The largest number of event functions one [`System`] may declare.
pub const MAX_EVENTS: usize = 8;

/// How many series a system may compute besides its state, for event
/// functions that are not a state component (the bell needs one: the force
/// that holds a resting clapper).
pub const MAX_EXTRA: usize = 2;

/// Which sign change of an event function counts as the event.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Direction {
    /// The function passes from negative to zero or positive.
    Rising,
    /// The function passes from positive to zero or negative.
    Falling,
    /// Either sign change.
    Either,
}

impl Direction {
    /// The direction of the same crossing seen on the function negated.
    pub fn reversed(self) -> Direction {
        match self {
            Direction::Rising => Direction::Falling,
            Direction::Falling => Direction::Rising,
            Direction::Either => Direction::Either,
        }
    }

    /// This direction for `sign` ≥ 0, reversed for `sign` < 0: the
    /// crossing of `sign * x` seen on `x`.
    pub fn signed(self, sign: f64) -> Direction {
        if sign < 0.0 {
            self.reversed()
        } else {
            self
        }
    }
}

/// The series an event function reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Source {
    /// State component `i` (< `N`).
    State(usize),
    /// Extra function `j` (< [`MAX_EXTRA`]): [`System::extra`], and for a
    /// [`SeriesSystem`](crate::ode::SeriesSystem) its series filled by [`SeriesSystem::expand`](crate::ode::SeriesSystem::expand).
    Extra(usize),
}

/// An event function: the event is where `source` crosses `level` in
/// `direction`. Every method reads events this way: a level on a series
/// lets the Taylor integrator use the solution's own coefficients, and the
/// closed-form swing solve for the crossing.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Event {
    /// What the function reads.
    pub source: Source,
    /// The level it crosses (units of the source).
    pub level: f64,
    /// Which crossing counts: rising means from below the level to above.
    pub direction: Direction,
}

impl Event {
    /// Whether the event reads something a system of `N` states has.
    pub fn valid_for(&self, n: usize) -> bool {
        match self.source {
            Source::State(i) => i < n,
            Source::Extra(j) => j < MAX_EXTRA,
        }
    }
}

/// A system of `N` first-order ODEs with up to [`MAX_EVENTS`] event functions.
///
/// An event function that is exactly zero where integration starts takes
/// the sign it has a moment later, or if that is still zero, the side its
/// [`Direction`] comes from. So a caller can restart at the point where an
/// event fired, after changing the state, without the event firing again
/// there, and an event that leaves zero and comes back within the first
/// step is still caught.
pub trait System<const N: usize> {
    /// The derivative dy/dt at time `t` (s) and state `y`.
    fn rhs(&self, t: f64, y: &[f64; N]) -> [f64; N];
    /// The active event functions (at most [`MAX_EVENTS`]); none by default.
    fn events(&self) -> &[Event] {
        &[]
    }
    /// How each component's error is weighed on this system, given the
    /// options' tolerances: by default `atol` and `rtol` for every
    /// component, relative tolerances measured from zero.
    #[inline]
    fn error_weights(&self, atol: f64, rtol: f64) -> ErrorWeights<N> {
        ErrorWeights::uniform(atol, rtol)
    }
    /// The value of extra function `j` at `(t, y)`, for events that read
    /// [`Source::Extra`]; NaN for a system that has none.
    fn extra(&self, _j: usize, _t: f64, _y: &[f64; N]) -> f64 {
        f64::NAN
    }
    /// Event `e` at `(t, y)`: the source minus the level; the event is a
    /// root.
    #[inline]
    fn event_value(&self, e: &Event, t: f64, y: &[f64; N]) -> f64 {
        match e.source {
            Source::State(i) => y[i] - e.level,
            Source::Extra(j) => self.extra(j, t, y) - e.level,
        }
    }
}

/// How an integrator weighs each component's error: component `i` may err
/// by `atol[i] + rtol[i] · |y_i − origin[i]|` per step.
///
/// A stiff contact spring is why it is per component: a clapper resting in
/// the penalty spring sits a deflection of `q / k` (about 1e-8 rad at
/// k = 1e9 N m/rad) past its stop, and its lift-off is where that
/// deflection returns to zero. Measured from zero and with the absolute
/// tolerance of an order-one state, the deflection was below the tolerance
/// and the lift-off moved by up to 0.006 deg; measured from the stop, it is
/// resolved in proportion (docs/model.md §3.2).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ErrorWeights<const N: usize> {
    /// Absolute tolerance of each component (its own units).
    pub atol: [f64; N],
    /// Relative tolerance of each component.
    pub rtol: [f64; N],
    /// What each component's relative tolerance is measured from (its own
    /// units): zero unless a system says otherwise.
    pub origin: [f64; N],
}

impl<const N: usize> ErrorWeights<N> {
    /// `atol` and `rtol` for every component, relative tolerances from
    /// zero: the usual mixed error control.
    pub fn uniform(atol: f64, rtol: f64) -> Self {
        Self {
            atol: [atol; N],
            rtol: [rtol; N],
            origin: [0.0; N],
        }
    }

    /// The error allowed in component `i` at value `y`.
    #[inline]
    pub fn scale(&self, i: usize, y: f64) -> f64 {
        self.atol[i] + self.rtol[i] * (y - self.origin[i]).abs()
    }
}

/// Where one step's dense output is valid: `[t0, t0 + h]` (s).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Span {
    /// Start (s).
    pub t0: f64,
    /// Length (s).
    pub h: f64,
}

/// The dense output of one step of any method: the state anywhere in the
/// step.
pub trait DenseOutput<const N: usize> {
    /// Where the output is valid.
    fn span(&self) -> Span;
    /// The state at time `t` (s), which should lie in the step.
    fn eval(&self, t: f64) -> [f64; N];
    /// Start time of the step (s).
    fn t0(&self) -> f64 {
        self.span().t0
    }
    /// End time of the step (s).
    fn t1(&self) -> f64 {
        let s = self.span();
        s.t0 + s.h
    }
}

/// What a [`Stepper`] hands every step to: a closure of the step's dense
/// output and the time it is used up to (s). Generic, so that an observer
/// that does nothing costs nothing.
pub trait Observe<const N: usize>: FnMut(&dyn DenseOutput<N>, f64) {}

impl<const N: usize, F: FnMut(&dyn DenseOutput<N>, f64)> Observe<N> for F {}

/// What [`Stepper::integrate`] answers: where it stopped, or a numerical
/// failure.
pub type Run<const N: usize> = Result<Segment<N>, OdeError>;

/// Why a [`Stepper`] stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stop {
    /// Event function `i` (an index into [`System::events`]) fired.
    Event(usize),
    /// The end time was reached with no event.
    EndTime,
    /// The method cannot solve this system from this state (the closed-form
    /// swing outside its case); nothing was advanced. [`Fallback`] hands
    /// the same call to another method.
    Declined,
}

/// Where a [`Stepper`] stopped.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Segment<const N: usize> {
    /// Time (s) of the stop.
    pub t: f64,
    /// State at the stop.
    pub y: [f64; N],
    /// Why it stopped.
    pub stop: Stop,
}

/// What a caller knows of the segment it is about to integrate, after a
/// jump: each method uses what helps it and ignores the rest.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum NextSegment {
    /// A short free flight of about `span` seconds (a small bounce): the
    /// Taylor method expands to a low order and seeks events over the span.
    ShortFlight {
        /// Expected length (s), with a margin.
        span: f64,
    },
    /// The right-hand side has just become much stiffer (a spring contact
    /// began): Dormand–Prince forgets its step size.
    Stiffer,
}

/// One interface over every method: integrate a system from `(t0, y0)`
/// towards `t_end`, stopping at the earliest event, handing every step's
/// dense output to `observe(dense, t_used_to)`.
pub trait Stepper<const N: usize, S: ?Sized> {
    /// Integrate `sys` from `(t0, y0)` towards `t_end` (> `t0`). `observe`
    /// is called after every step with its dense output and the time it is
    /// used up to (earlier than the step's end when an event cut it short).
    fn integrate<F: Observe<N>>(&mut self, sys: &S, t0: f64, y0: [f64; N], t_end: f64, observe: &mut F) -> Run<N>;
    /// Work done so far.
    fn stats(&self) -> Stats;
    /// A hint for the next call only (see [`NextSegment`]); none by default.
    fn expect(&mut self, _next: NextSegment) {}
}

/// `first` where it applies, `then` where `first` declines: the closed-form
/// swing with an integrator behind it. Its work is `then`'s (the closed
/// form takes no steps).
#[derive(Clone, Debug)]
pub struct Fallback<A, B> {
    /// Tried first.
    pub first: A,
    /// Used where `first` declines.
    pub then: B,
}

impl<const N: usize, S: ?Sized, A: Stepper<N, S>, B: Stepper<N, S>> Stepper<N, S> for Fallback<A, B> {
    fn integrate<F: Observe<N>>(&mut self, sys: &S, t0: f64, y0: [f64; N], t_end: f64, observe: &mut F) -> Run<N> {
        let seg = self.first.integrate(sys, t0, y0, t_end, observe)?;
        if seg.stop == Stop::Declined {
            self.then.integrate(sys, t0, y0, t_end, observe)
        } else {
            Ok(seg)
        }
    }

    fn stats(&self) -> Stats {
        self.then.stats()
    }

    fn expect(&mut self, next: NextSegment) {
        self.first.expect(next);
        self.then.expect(next);
    }
}

/// `x > 0` (finite, normal) split as `2^e * m` with `m` in [1, 2): the
/// first half of both integrators' fast powers (`dopri5::pow_approx`,
/// `taylor::inv_root`). Each keeps its own series for ln m and 2^f, so that
/// results stay what they were to the last bit.
#[inline]
pub(crate) fn split_exponent(x: f64) -> (i64, f64) {
    let bits = x.to_bits();
    let e = ((bits >> 52) & 0x7ff) as i64 - 1023;
    (
        e,
        f64::from_bits((bits & 0x000f_ffff_ffff_ffff) | 0x3ff0_0000_0000_0000),
    )
}

/// `y` (|y| ≤ 1000) split as `n + f / ln 2` with integer `n` = floor(y)
/// and `f` in [0, ln 2), without the library floor; and `2^n` as two
/// factors, each a normal f64. The second half of the fast powers.
#[inline]
pub(crate) fn split_exp2(y: f64) -> (f64, f64) {
    let t = y as i64 as f64;
    let n = if t > y { t - 1.0 } else { t };
    let f = (y - n) * std::f64::consts::LN_2;
    let half = (n as i64) / 2;
    let scale = |k: i64| f64::from_bits(((k + 1023) as u64) << 52);
    (f, scale(half) * scale(n as i64 - half))
}

/// Error tolerances and limits of the integrator.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Options {
    /// Relative tolerance per step. Default 3e-8, chosen by measurement
    /// (`cargo run --release -p clapper-core --example tolerance`): over the
    /// paper's 20 x 20 chart of both styles, against a 1e-12 reference, the
    /// first strike angle is then within about 4e-5 deg with the default
    /// Taylor integrator (and within 3e-4 deg with Dormand–Prince, whose 1e-7
    /// would already err by 1e-3 deg), with no verdict changed. For
    /// [`Dopri5`](crate::ode::Dopri5) it bounds the local error estimate of each step; for
    /// [`Taylor`](crate::ode::Taylor) the last two terms of each step's series.
    pub rtol: f64,
    /// Absolute tolerance per step, in the state's units (rad, rad/s).
    /// Default 3e-8, matching `rtol` for states of order one.
    pub atol: f64,
    /// Largest step of [`Dopri5`](crate::ode::Dopri5) (s). Default 0.05 s, a few percent of the
    /// fastest swing period of a real bell, so that no event hides inside
    /// one step. ([`Taylor`](crate::ode::Taylor) has its own, and samples its event polynomials
    /// inside each step.)
    pub h_max: f64,
    /// The most step attempts (accepted and rejected) one integrator may make
    /// over its life (a stroke uses one integrator). Default 2,000,000: enough for the penalty model at
    /// k = 1e9 N m/rad over a long stroke, small enough to stop in seconds.
    pub max_steps: u64,
    /// Time resolution of event location (s). Default 1e-12 s.
    pub event_time_tol: f64,
}

impl Default for Options {
    fn default() -> Self {
        Self {
            rtol: 3e-8,
            atol: 3e-8,
            h_max: 0.05,
            max_steps: 2_000_000,
            event_time_tol: 1e-12,
        }
    }
}

/// The sign of `x`: 1, −1, or 0 for zero (and NaN).
pub(crate) fn sign(x: f64) -> i8 {
    if x > 0.0 {
        1
    } else if x < 0.0 {
        -1
    } else {
        0
    }
}

/// Whether an event function known to be on side `s0` and now on side `s1`
/// has crossed in direction `dir` (reaching zero counts).
pub(crate) fn crossed(dir: Direction, s0: i8, s1: i8) -> bool {
    match dir {
        Direction::Rising => s0 < 0 && s1 >= 0,
        Direction::Falling => s0 > 0 && s1 <= 0,
        Direction::Either => s0 != 0 && s1 != s0,
    }
}

/// What both integrators check of a call before they start: the events
/// read series that exist, the start is finite; and an end time not after
/// the start is reached at once (`Some` segment: nothing to integrate).
pub(crate) fn begin<const N: usize, S: System<N> + ?Sized>(
    sys: &S,
    t0: f64,
    y0: [f64; N],
    t_end: f64,
) -> Result<Option<Segment<N>>, OdeError> {
    let events = sys.events();
    if events.len() > MAX_EVENTS || !events.iter().all(|e| e.valid_for(N)) {
        return Err(OdeError::InvalidOptions("an event reads a series that does not exist"));
    }
    if !t0.is_finite() || y0.iter().any(|v| !v.is_finite()) {
        return Err(OdeError::NonFinite { t: t0 });
    }
    Ok((t_end <= t0 || t_end.is_nan()).then_some(Segment {
        t: t0,
        y: y0,
        stop: Stop::EndTime,
    }))
}

/// The checks both integrators make of their options, with their own
/// largest step `h_max` (s).
pub(crate) fn check_options(o: &Options, h_max: f64) -> Result<(), OdeError> {
    let positive = |x: f64| x.is_finite() && x > 0.0;
    if !(positive(o.rtol) && positive(o.atol)) {
        return Err(OdeError::InvalidOptions("tolerances must be positive and finite"));
    }
    if !(positive(h_max) && positive(o.event_time_tol)) {
        return Err(OdeError::InvalidOptions("h_max and event_time_tol must be positive"));
    }
    Ok(())
}

/// Work done by an integrator.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Stats {
    /// Accepted steps.
    pub steps: u64,
    /// Rejected steps.
    pub rejected: u64,
    /// Right-hand-side evaluations.
    pub rhs_evals: u64,
}

/// A numerical failure of the integrator.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
pub enum OdeError {
    /// The step budget of [`Options::max_steps`] ran out.
    #[error("integrator step limit of {limit} reached at t = {t} s")]
    StepLimit {
        /// The limit that was hit.
        limit: u64,
        /// Time (s) when it was hit.
        t: f64,
    },
    /// The step size fell below what f64 can resolve at this time.
    #[error("integrator step size underflow ({h:e} s) at t = {t} s")]
    StepSizeUnderflow {
        /// The step size (s).
        h: f64,
        /// Time (s).
        t: f64,
    },
    /// The state or its derivative became NaN or infinite.
    #[error("non-finite state or derivative at t = {t} s")]
    NonFinite {
        /// Time (s).
        t: f64,
    },
    /// Invalid options (non-positive tolerance, step or limit).
    #[error("invalid integrator options: {0}")]
    InvalidOptions(&'static str),
}
