//! A Taylor-series integrator for small autonomous systems whose solution
//! series the system computes itself (automatic differentiation by the
//! classical recurrences; Jorba & Zou, *Experimental Mathematics* 14, 2005).
//!
//! Why: for a smooth 4-state system at tolerances near 1e-8, one expansion
//! to order ~10 costs about as much as a few right-hand-side calls of a
//! Runge–Kutta method, but its steps are several times longer, it needs no
//! trig calls beyond the expansion point, never rejects a step, and its
//! dense output is the series itself. Event functions are expanded along
//! the solution too, so every root is located on a polynomial.
//!
//! The step size comes from the last two coefficients (Jorba & Zou's rule):
//! the largest `h` with `|x_j| h^j <= atol + rtol |y|` for `j = p - 1, p` in
//! every component, capped at `h_max`.

use super::interface::{
    begin, check_options, crossed, sign, split_exp2, split_exponent, DenseOutput, Direction, ErrorWeights, Event,
    NextSegment, Observe, OdeError, Options, Run, Segment, Source, Span, Stats, Stepper, Stop, System, MAX_EXTRA,
};

/// The highest order an expansion may have.
pub const MAX_ORDER: usize = 24;

/// Taylor coefficients `c_0 .. c_MAX_ORDER` of one function of time, in
/// powers of the time since the expansion point (units of the function per
/// s^k).
pub type Coeffs = [f64; MAX_ORDER + 1];

/// How many points a step is sampled at when an event function's bound
/// cannot rule out a root: a root pair closer than 1/16 of a step (a graze)
/// can hide between samples, as it could inside a Runge–Kutta step.
const EVENT_SAMPLES: usize = 16;

/// An autonomous system of `N` first-order ODEs that computes the Taylor
/// series of its own solution and of its extra functions (those its
/// events read).
pub trait SeriesSystem<const N: usize>: System<N> {
    /// Fill `x[i][0..=p]` with the Taylor coefficients of the solution
    /// through `y` (so `x[i][0] = y[i]`) and `extra[j][0..=p]` with those
    /// of every extra function an event reads.
    fn expand(&self, y: &[f64; N], p: usize, x: &mut [Coeffs; N], extra: &mut [Coeffs; MAX_EXTRA]);

    /// Event `i`, reached at state `y`, as one the system passes through
    /// by changing its own equations (a Coulomb torque turned at the apex
    /// of a flight) rather than one that ends the run: if it is, the
    /// system turns them, sets `y` to the state after it and answers with
    /// what a caller would have said of the run that follows
    /// ([`Taylor::hint_next`]'s first step, if any). The run then goes on
    /// as a new one from there would, bit for bit, without returning.
    /// `None` (the default): the run stops at the event.
    fn pass_through(&self, _i: usize, _y: &mut [f64; N]) -> Option<Option<f64>> {
        None
    }

    /// The events (bit `i` for event `i`) whose crossing, where it is
    /// certain by a step's end and the step's polynomial is proven
    /// monotone over it, may be located on the whole step without
    /// sampling it first. None by default: the sampled search keeps every
    /// other event's roots, and so the ideal bell's results, to the bit.
    fn whole_step_events(&self) -> u32 {
        0
    }
}

/// `c_0 + c_1 s + ... + c_p s^p`, as two interleaved Horner chains in s²
/// (even and odd terms): half the latency of one chain.
#[inline]
fn horner(c: &[f64], p: usize, s: f64) -> f64 {
    if p == 0 {
        return c[0];
    }
    let s2 = s * s;
    // Highest even and odd indices.
    let (mut ke, mut ko) = if p % 2 == 0 { (p, p - 1) } else { (p - 1, p) };
    let mut even = c[ke];
    let mut odd = c[ko];
    while ke >= 2 {
        ke -= 2;
        even = even * s2 + c[ke];
    }
    while ko >= 3 {
        ko -= 2;
        odd = odd * s2 + c[ko];
    }
    even + s * odd
}

/// [`horner`] of every component at once: the same operations on each, in
/// the same order (so the same bits), side by side.
#[inline(always)]
fn horner_all<const N: usize>(x: &[Coeffs; N], p: usize, s: f64) -> [f64; N] {
    if p == 0 {
        return std::array::from_fn(|i| x[i][0]);
    }
    let s2 = s * s;
    let (mut ke, mut ko) = if p % 2 == 0 { (p, p - 1) } else { (p - 1, p) };
    let (mut even, mut odd) = ([0.0; N], [0.0; N]);
    for i in 0..N {
        (even[i], odd[i]) = (x[i][ke], x[i][ko]);
    }
    while ke >= 2 {
        ke -= 2;
        for i in 0..N {
            even[i] = even[i] * s2 + x[i][ke];
        }
    }
    while ko >= 3 {
        ko -= 2;
        for i in 0..N {
            odd[i] = odd[i] * s2 + x[i][ko];
        }
    }
    let mut y = [0.0; N];
    for i in 0..N {
        y[i] = even[i] + s * odd[i];
    }
    y
}

/// `m^(-1/j)` for `m > 0`, within about 2e-4 relative: a step size needs
/// no more. log2 from the exponent bits and a series for the mantissa's
/// logarithm about 1.5; 2^y from its integer part's bits and a series.
#[inline]
fn inv_root(m: f64, j: usize) -> f64 {
    if !(m.is_finite() && m >= 1e-300) {
        return if m.is_nan() {
            f64::NAN
        } else if m > 1.0 {
            0.0
        } else {
            f64::INFINITY
        };
    }
    let (e, mant) = split_exponent(m);
    // ln(mant) = ln 1.5 + ln(1 + u), |u| <= 1/3. Both series by Estrin's
    // scheme: a step size waits on this, and Horner's chain is twice as long.
    let u = (mant - 1.5) * (2.0 / 3.0);
    let u2 = u * u;
    let ln1p = u * ((1.0 - 0.5 * u) + u2 * (1.0 / 3.0 - 0.25 * u) + u2 * u2 * ((0.2 - u / 6.0) + u2 * (1.0 / 7.0)));
    let log2m = e as f64 + (0.405_465_108_108_164_4 + ln1p) * std::f64::consts::LOG2_E;
    let y = (-log2m / j as f64).clamp(-1000.0, 1000.0);
    let (f, two_n) = split_exp2(y);
    let f2 = f * f;
    let two_f = (1.0 + f) + f2 * (0.5 + f / 6.0) + f2 * f2 * ((1.0 / 24.0 + f / 120.0) + f2 * (1.0 / 720.0));
    two_f * two_n
}

/// Σ |a_k| w_k in four running sums (a bound, so the order of the sum does
/// not matter, and four chains are four times shorter).
#[inline]
fn abs_dot(a: &[f64], w: &[f64]) -> f64 {
    let mut acc = [0.0f64; 4];
    let mut ca = a.chunks_exact(4);
    let mut cw = w.chunks_exact(4);
    for (x, y) in (&mut ca).zip(&mut cw) {
        for j in 0..4 {
            acc[j] += x[j].abs() * y[j];
        }
    }
    let tail: f64 = ca
        .remainder()
        .iter()
        .zip(cw.remainder())
        .map(|(x, y)| x.abs() * y)
        .sum();
    (acc[0] + acc[1]) + (acc[2] + acc[3]) + tail
}

/// Value and derivative of the polynomial at `s`: with p(s) = E(s²) + s O(s²),
/// p'(s) = O(s²) + 2 s (E'(s²) + s O'(s²)); four short chains.
#[inline]
fn horner_d(c: &Coeffs, p: usize, s: f64) -> (f64, f64) {
    let s2 = s * s;
    let (mut e, mut de, mut o, mut d_o) = (0.0, 0.0, 0.0, 0.0);
    let mut k = p;
    loop {
        if k % 2 == 0 {
            de = de * s2 + e;
            e = e * s2 + c[k];
        } else {
            d_o = d_o * s2 + o;
            o = o * s2 + c[k];
        }
        if k == 0 {
            break;
        }
        k -= 1;
    }
    (e + s * o, o + 2.0 * s * (de + s * d_o))
}

/// The first root of the polynomial `c` in `(a, b]`, where it passes from
/// the side `sa` (its value at `a` is `ga`, possibly zero) to the other
/// (`gb` at `b`). Newton's method kept inside the bracket, bisection when
/// it leaves it. Returns a point within `tol` of the root on the far side
/// (or at zero), like the Runge–Kutta event locator.
#[allow(clippy::too_many_arguments)]
fn poly_root(c: &Coeffs, p: usize, mut a: f64, ga: f64, sa: i8, mut b: f64, gb: f64, tol: f64) -> f64 {
    let orient = -f64::from(sa);
    let (fa, fb) = (ga * orient, gb * orient);
    // Start from the secant point when both ends are informative.
    let mut x = if fa < 0.0 && fb > 0.0 {
        (a * fb - b * fa) / (fb - fa)
    } else {
        0.5 * (a + b)
    };
    for _ in 0..100 {
        if b - a <= tol {
            break;
        }
        let (v, d) = horner_d(c, p, x);
        let (v, d) = (v * orient, d * orient);
        if v < 0.0 {
            a = x;
        } else {
            b = x;
        }
        let newton = x - v / d;
        let step_ok = d != 0.0 && newton > a && newton < b;
        if step_ok && (newton - x).abs() < 0.25 * tol {
            // Converged: the far side just past the Newton point.
            let hi = (newton + 0.5 * tol).min(b);
            if horner(c, p, hi) * orient >= 0.0 {
                b = hi;
            }
            break;
        }
        x = if step_ok { newton } else { 0.5 * (a + b) };
    }
    b
}

/// One step's dense output: the truncated series, valid on `[t0, t0 + h]`.
#[derive(Clone, Debug)]
pub struct Series<const N: usize> {
    span: Span,
    p: usize,
    x: [Coeffs; N],
}

impl<const N: usize> Series<N> {
    /// The state at `s` (s) from the expansion point.
    #[inline(always)]
    fn at_offset(&self, s: f64) -> [f64; N] {
        horner_all(&self.x, self.p, s)
    }
}

impl<const N: usize> DenseOutput<N> for Series<N> {
    fn span(&self) -> Span {
        self.span
    }

    #[inline]
    fn eval(&self, t: f64) -> [f64; N] {
        horner_all(&self.x, self.p, t - self.span.t0)
    }
}

/// A Taylor-series integrator of fixed order with events.
#[derive(Clone, Debug)]
pub struct Taylor<const N: usize> {
    opts: Options,
    order: usize,
    next_order: Option<usize>,
    next_cap: Option<f64>,
    h_max: f64,
    /// ln rtol, for the order of a short flight ([`bounce_order`]).
    ln_rtol: f64,
    stats: Stats,
    // Kept so that a step allocates and copies nothing: the current step's
    // series (handed to the observer as it is) and the extra series.
    series: Series<N>,
    extra: [Coeffs; MAX_EXTRA],
}

impl<const N: usize> Taylor<N> {
    /// An integrator of the given `order` (2 ..= [`MAX_ORDER`]) and largest
    /// step `h_max` (s), with the tolerances, step budget and event time
    /// resolution of `opts` (its `h_max` is not used).
    pub fn new(opts: Options, order: usize, h_max: f64) -> Self {
        Self {
            opts,
            order,
            next_order: None,
            next_cap: None,
            h_max,
            ln_rtol: opts.rtol.ln(),
            stats: Stats::default(),
            series: Series {
                span: Span::default(),
                p: 0,
                x: [[0.0; MAX_ORDER + 1]; N],
            },
            extra: [[0.0; MAX_ORDER + 1]; MAX_EXTRA],
        }
    }

    /// For the next [`integrate`](Self::integrate) call only: expand to
    /// `order` (clamped to 2 ..= the integrator's order) and make the first
    /// step at most `first_step` (s). A caller that knows the next segment
    /// is short (a small bounce) saves work: a low order, and events sought
    /// over the short span only. The step-size control keeps the accuracy
    /// whatever the hint, and a wrong guess only costs another step.
    pub fn hint_next(&mut self, order: usize, first_step: f64) {
        self.next_order = Some(order.clamp(2, self.order.max(2)));
        self.next_cap = (first_step > 0.0).then_some(first_step);
    }

    /// The order and first step (s) of a run after [`hint_next`](Self::hint_next)
    /// with a short flight of `span` (s), if any; else the integrator's own.
    fn hinted(&self, span: Option<f64>) -> (usize, f64) {
        match span {
            Some(span) => (
                bounce_order(span, self.ln_rtol, self.opts.rtol).clamp(2, self.order.max(2)),
                if span > 0.0 { span } else { f64::INFINITY },
            ),
            None => (self.order, f64::INFINITY),
        }
    }

    /// Work done so far: every step is one expansion (`steps`); no step is
    /// rejected and `rhs_evals` stays zero.
    pub fn stats(&self) -> Stats {
        self.stats
    }

    /// Whether `order` is one this integrator can expand to: 2 ..=
    /// [`MAX_ORDER`]. The one statement of the bound; `SimConfig::validate`
    /// asks it too.
    pub fn check_order(order: usize) -> Result<(), OdeError> {
        if (2..=MAX_ORDER).contains(&order) {
            Ok(())
        } else {
            Err(OdeError::InvalidOptions("Taylor order must be 2 ..= 24 (MAX_ORDER)"))
        }
    }

    fn check_options(&self) -> Result<(), OdeError> {
        check_options(&self.opts, self.h_max)?;
        Self::check_order(self.order)
    }

    /// The step the last two coefficients allow (s), before capping.
    fn step_size(&self, y: &[f64; N], p: usize, w: &ErrorWeights<N>) -> f64 {
        let (mut m1, mut m2) = (0.0f64, 0.0f64);
        for (i, (yi, xi)) in y.iter().zip(&self.series.x).enumerate() {
            let inv = 1.0 / w.scale(i, *yi);
            m1 = m1.max(xi[p - 1].abs() * inv);
            m2 = m2.max(xi[p].abs() * inv);
        }
        let root = |m: f64, j: usize| {
            if m > 0.0 {
                inv_root(m, j)
            } else {
                f64::INFINITY
            }
        };
        // The (p-1)-th term usually allows more: take its root only if not.
        // With h^p = 1 / m2, m1 h^(p-1) <= 1 reads m1 <= m2 h.
        let h = root(m2, p);
        if h.is_finite() && m1 <= m2 * h {
            h
        } else {
            h.min(root(m1, p - 1))
        }
    }

    /// The step (s) before the end time cuts it: the step-size rule's,
    /// capped at `h_max` and at a hint's `cap`. A first step capped by a
    /// hint (a short flight) usually keeps the cap: where the cap's powers
    /// prove it, the rule's roots need not be taken (the step is the same).
    fn step_for(&self, y: &[f64; N], p: usize, w: &ErrorWeights<N>, cap: f64, remaining: f64) -> f64 {
        if cap < remaining && cap <= self.h_max && self.cap_holds(y, p, w, cap) {
            return cap;
        }
        self.step_size(y, p, w).min(self.h_max).min(cap)
    }

    /// Whether the step-size rule allows more than the step `cap` (s): the
    /// last two terms within 0.97 of each component's error there.
    /// [`step_size`](Self::step_size)'s roots err by under 5e-5
    /// (`inv_root`), and 0.97 puts its exact roots at least 1.2e-3 beyond
    /// the cap for every order up to [`MAX_ORDER`] (the powers here err by
    /// under 1e-14): so where this holds, the rule's step is longer than
    /// the cap, and the cap is the step, bit for bit as with the roots taken.
    fn cap_holds(&self, y: &[f64; N], p: usize, w: &ErrorWeights<N>, cap: f64) -> bool {
        let mut before_last = 1.0;
        for _ in 1..p {
            before_last *= cap;
        }
        let last = before_last * cap;
        let mut holds = true;
        for (i, (yi, xi)) in y.iter().zip(&self.series.x).enumerate() {
            let allowed = 0.97 * w.scale(i, *yi);
            holds &= xi[p].abs() * last <= allowed && xi[p - 1].abs() * before_last <= allowed;
        }
        holds
    }

    /// The earliest time in `(0, h]` (as an offset from the expansion
    /// point) where `series - level` crosses zero in direction `dir`, if
    /// any; `None` too where it is proven to come after `limit` (the first
    /// event found so far: a later crossing cannot be the step's first).
    #[allow(clippy::too_many_arguments)]
    fn first_root(
        &self,
        series: &Coeffs,
        level: f64,
        dir: Direction,
        h: f64,
        hk: &Coeffs,
        p: usize,
        limit: f64,
        whole: bool,
    ) -> Option<f64> {
        let c0 = series[0] - level;
        let lead = not_ruled_out(series, c0, hk, p, h, limit)?;
        // Rarely reached: the shifted polynomial, copied.
        let mut shifted = *series;
        shifted[0] = c0;
        let c = &shifted;
        // A function that starts at zero (a restart at its own root) has
        // the roots of c / t in (0, h]: shift out the leading zeros.
        let s0 = sign(c[lead]);
        let r: &[f64] = &c[lead..=p];
        // The walks' bound on the slope over the step.
        let deg = r.len() - 1;
        let mut kh = [0.0; MAX_ORDER + 1];
        for k in 1..=deg {
            kh[k] = k as f64 * hk[k - 1];
        }
        let slope = abs_dot(&r[1..], &kh[1..=deg]);
        // A crossing by the step's end is certain: no walk, find the first;
        // but first a walk to the limit, which may prove it later than an
        // event already found (then the search is over; if not, it goes on
        // from the step's start as before).
        let gh = horner(r, deg, h);
        let certain = crossed(dir, s0, sign(gh));
        // Where the slope's first term outweighs the rest, the polynomial
        // is monotone over the step: a certain crossing is its only one,
        // located between the step's ends (for the events that allow it).
        if whole && certain && lead == 0 && limit >= h && 2.0 * r[1].abs() > slope {
            return Some(poly_root(c, p, 0.0, c[0], s0, h, gh, self.opts.event_time_tol));
        }
        if certain && limit < h {
            exclusion_walk(r, s0, slope, |next| next > limit)?;
        }
        let a = if certain {
            0.0
        } else {
            // Also when the slope is zero (next is infinite) or NaN. A
            // root past the limit is no step's first.
            exclusion_walk(r, s0, slope, |next| next.is_nan() || next >= h || next > limit)?.0
        };
        // A root may be near: sample the rest of the step for the first
        // crossing, then locate it on the polynomial.
        let ga = if lead > 0 && a == 0.0 { 0.0 } else { horner(c, p, a) };
        self.sampled_root(c, p, (a, ga, s0), h, dir, limit)
    }

    /// The first crossing in direction `dir` of the polynomial `c` over
    /// `(a, h]`, from `a` (its value `ga` there, on side `sa`): the rest
    /// of the step sampled, the crossing located on the polynomial;
    /// `None` if none, or if it comes after `limit`.
    fn sampled_root(
        &self,
        c: &Coeffs,
        p: usize,
        (a, ga, sa): (f64, f64, i8),
        h: f64,
        dir: Direction,
        limit: f64,
    ) -> Option<f64> {
        let (mut pa, mut ga, mut sa) = (a, ga, sa);
        // All samples at once: independent Horner chains run side by side.
        let span = h - a;
        let at: [f64; EVENT_SAMPLES] = std::array::from_fn(|m| a + span * (m + 1) as f64 / EVENT_SAMPLES as f64);
        let mut val = [c[p]; EVENT_SAMPLES];
        for k in (0..p).rev() {
            for (v, s) in val.iter_mut().zip(&at) {
                *v = *v * s + c[k];
            }
        }
        for (&b, &gb) in at.iter().zip(&val) {
            if crossed(dir, sa, sign(gb)) {
                // A crossing after pa, past the limit, need not be located.
                if pa > limit {
                    return None;
                }
                return Some(poly_root(c, p, pa, ga, sa, b, gb, self.opts.event_time_tol));
            }
            // A crossing the other way, or a touch of zero that keeps the side.
            if gb != 0.0 {
                pa = b;
                ga = gb;
                sa = sign(gb);
            }
        }
        None
    }

    /// The step's first event over `(0, h]` (`hk`: the powers of `h`): its
    /// offset and index, the one listed first on a tie. Taken from the last
    /// listed (friction's, whose crossing comes first in a bounce's
    /// flight): a crossing found bounds the search for the others, which
    /// are dropped once proven later (strictly: equal times still go to
    /// the event listed first).
    fn first_event(&self, events: &[Event], whole: u32, h: f64, hk: &Coeffs, p: usize) -> Option<(f64, usize)> {
        let mut best: Option<(f64, usize)> = None;
        let mut limit = f64::INFINITY;
        for i in (0..events.len()).rev() {
            let e = &events[i];
            let series = match e.source {
                Source::State(k) => &self.series.x[k],
                Source::Extra(k) => &self.extra[k],
            };
            let whole = whole >> i & 1 == 1;
            if let Some(s) = self.first_root(series, e.level, e.direction, h, hk, p, limit, whole) {
                if s <= limit {
                    (best, limit) = (Some((s, i)), s);
                }
            }
        }
        best
    }
}

/// `hk[k] = h^k` for `k` in `0..=p`, by halves: a shorter chain of
/// dependent products.
#[inline(always)]
fn powers(hk: &mut Coeffs, h: f64, p: usize) {
    hk[0] = 1.0;
    for k in 1..=p {
        hk[k] = if k == 1 { h } else { hk[k / 2] * hk[k - k / 2] };
    }
}

/// A run passed through an event at `(t, y)` stops there as a new run
/// from there would at once: at a state not finite, or at `t_end`.
#[inline(always)]
fn ended<const N: usize>(t: f64, y: [f64; N], t_end: f64) -> Option<Run<N>> {
    if y.iter().any(|v| !v.is_finite()) {
        return Some(Err(OdeError::NonFinite { t }));
    }
    (t_end <= t).then_some(Ok(Segment {
        t,
        y,
        stop: Stop::EndTime,
    }))
}

/// The first nonzero term of the series less its level (`c0` at 0), unless
/// a bound rules out a root over the step (`hk`: the powers of `h`), or up
/// to `limit` (an event found) where that is sooner. Cheapest test first:
/// the constant term outweighs all the others.
#[inline(always)]
fn not_ruled_out(series: &Coeffs, c0: f64, hk: &Coeffs, p: usize, h: f64, limit: f64) -> Option<usize> {
    let (lead, first) = if c0 != 0.0 {
        if c0.abs() > abs_dot(&series[1..=p], &hk[1..=p]) {
            return None;
        }
        (0, c0)
    } else {
        // Restarted at its own root (a clapper's slip after the apex of
        // its flight, or a flight off a stop): c = t^lead r(t) has the
        // sign of r on (0, h], and r none of its roots where its first
        // term outweighs the others there.
        let lead = series[1..=p].iter().position(|&v| v != 0.0)? + 1;
        if (series[lead] * hk[lead]).abs() > abs_dot(&series[lead + 1..=p], &hk[lead + 1..=p]) {
            return None;
        }
        (lead, series[lead])
    };
    // The same test up to the limit: no crossing before an event already
    // found (a flight off a stop, whose return comes after the apex that
    // friction stops it at).
    if limit < h {
        let mut lk = [0.0; MAX_ORDER + 1];
        lk[0] = 1.0;
        for k in 1..=p {
            lk[k] = lk[k - 1] * limit;
        }
        if (first * lk[lead]).abs() > abs_dot(&series[lead + 1..=p], &lk[lead + 1..=p]) {
            return None;
        }
    }
    Some(lead)
}

/// The exclusion walk over a polynomial `r` on side `s0` from 0: |r'| <=
/// `slope` on the step, so r keeps its sign on [s, s + |r(s)| / slope). At
/// most four moves, each stopped where `beyond` says the rest need not be
/// searched (then `None`); else where it stopped (a root may be near) and
/// the value there. Usually proves there is no root in one or two
/// evaluations.
#[inline]
fn exclusion_walk(r: &[f64], s0: i8, slope: f64, beyond: impl Fn(f64) -> bool) -> Option<(f64, f64)> {
    let deg = r.len() - 1;
    let (mut a, mut ga) = (0.0, r[0]);
    for _ in 0..4 {
        let next = a + ga.abs() / slope;
        if beyond(next) {
            return None;
        }
        // A NaN (no slope bound) has no sign: the walk stops.
        let gn = horner(r, deg, next);
        if sign(gn) != s0 {
            break;
        }
        (a, ga) = (next, gn);
    }
    Some((a, ga))
}

/// A Taylor order for a first step of `flight` (s) after a bounce: the terms
/// of a series fall off about as (t / 0.25 s)^n over the bell's motion, so
/// a short flight needs few of them to reach rtol (`ln_rtol`: its
/// logarithm, worked out once). Only a work estimate:
/// the step-size control keeps the accuracy whatever the order.
///
/// ceil(ln rtol / ln ratio) is the least k with ratio^k ≤ rtol: found by
/// powers where both k and k − 1 are clear of the boundary by 1e-9
/// relative (the quotient of logarithms errs by under 1e-13, the powers by
/// under 1e-14, so both give the same k), by logarithms elsewhere.
fn bounce_order(flight: f64, ln_rtol: f64, rtol: f64) -> usize {
    let ratio = flight / 0.25;
    if !(ratio > 0.0 && ratio < 0.5) {
        return usize::MAX;
    }
    let (mut k, mut power, mut before) = (1usize, ratio, f64::INFINITY);
    while power > rtol && k < 48 {
        (k, before, power) = (k + 1, power, power * ratio);
    }
    let clear = power <= rtol * (1.0 - 1e-9) && before > rtol * (1.0 + 1e-9) && power > 1e-280;
    let k = if clear { k as f64 } else { (ln_rtol / ratio.ln()).ceil() };
    k.max(2.0) as usize + 1
}

/// An event function that is exactly zero at `t0` takes the sign of its
/// first nonzero Taylor coefficient: the sign it has just after `t0`.
impl<const N: usize, S: SeriesSystem<N> + ?Sized> Stepper<N, S> for Taylor<N> {
    fn stats(&self) -> Stats {
        Taylor::stats(self)
    }

    fn expect(&mut self, next: NextSegment) {
        if let NextSegment::ShortFlight { span } = next {
            self.hint_next(bounce_order(span, self.ln_rtol, self.opts.rtol), span);
        }
    }

    fn integrate<F: Observe<N>>(&mut self, sys: &S, t0: f64, y0: [f64; N], t_end: f64, observe: &mut F) -> Run<N> {
        self.check_options()?;
        if let Some(done) = begin(sys, t0, y0, t_end)? {
            return Ok(done);
        }
        let mut events = sys.events();
        let mut whole = sys.whole_step_events();
        let weights = sys.error_weights(self.opts.atol, self.opts.rtol);
        let mut p = self.next_order.take().unwrap_or(self.order);
        let mut cap = self.next_cap.take().unwrap_or(f64::INFINITY);
        let (mut t, mut y) = (t0, y0);
        loop {
            if self.stats.steps >= self.opts.max_steps {
                return Err(OdeError::StepLimit {
                    limit: self.opts.max_steps,
                    t,
                });
            }
            sys.expand(&y, p, &mut self.series.x, &mut self.extra);
            self.stats.steps += 1;
            // A non-finite term anywhere reaches the last ones, which the
            // step size uses: inf * 0 and NaN * 0 are NaN.
            let probe: f64 = self.series.x.iter().map(|c| (c[p - 1] + c[p]) * 0.0).sum();
            if probe.is_nan() {
                return Err(OdeError::NonFinite { t });
            }
            let remaining = t_end - t;
            let h = self.step_for(&y, p, &weights, cap, remaining);
            cap = f64::INFINITY;
            let last = h >= remaining;
            let h = if last { remaining } else { h };
            if h.is_nan() || (h <= 1e-14 * t.abs().max(1.0) && !last) {
                return Err(OdeError::StepSizeUnderflow { h, t });
            }
            let mut hk = [0.0; MAX_ORDER + 1];
            powers(&mut hk, h, p);
            let best = self.first_event(events, whole, h, &hk, p);
            (self.series.span, self.series.p) = (Span { t0: t, h }, p);
            if let Some((s, i)) = best {
                let t_ev = t + s;
                observe(&self.series, t_ev);
                let mut y_ev = self.series.eval(t_ev);
                let Some(hint) = sys.pass_through(i, &mut y_ev) else {
                    return Ok(Segment {
                        t: t_ev,
                        y: y_ev,
                        stop: Stop::Event(i),
                    });
                };
                // Passed through: on as a new run from there would go.
                if let Some(done) = ended(t_ev, y_ev, t_end) {
                    return done;
                }
                (events, whole) = (sys.events(), sys.whole_step_events());
                (p, cap) = self.hinted(hint);
                (t, y) = (t_ev, y_ev);
                continue;
            }
            let t_new = if last { t_end } else { t + h };
            observe(&self.series, t_new);
            y = self.series.at_offset(h);
            t = t_new;
            if y.iter().any(|v| !v.is_finite()) {
                return Err(OdeError::NonFinite { t });
            }
            if last {
                return Ok(Segment {
                    t,
                    y,
                    stop: Stop::EndTime,
                });
            }
        }
    }
}

/// Recurrences for the n-th Taylor coefficient of products, quotients and
/// trigonometric functions of series whose coefficients `0..=n` (for the
/// inputs) and `0..n` (for the output) are known: the building blocks of a
/// [`SeriesSystem`]. (The bell's own expansions in `dynamics` run the same
/// recurrences fused into one loop per order, for speed.)
pub mod rec {
    use crate::ode::taylor::Coeffs;

    /// n-th coefficient of `a b`.
    #[inline]
    pub fn mul(a: &Coeffs, b: &Coeffs, n: usize) -> f64 {
        a[..=n].iter().zip(b[..=n].iter().rev()).map(|(x, y)| x * y).sum()
    }

    /// n-th coefficient of `a / b`, given the quotient's earlier ones in `q`.
    #[inline]
    pub fn div(a: &Coeffs, b: &Coeffs, q: &Coeffs, n: usize) -> f64 {
        let mut s = a[n];
        for k in 1..=n {
            s -= b[k] * q[n - k];
        }
        s / b[0]
    }

    /// n-th coefficients (n ≥ 1) of `sin u` and `cos u`, given their
    /// earlier ones in `s` and `c`.
    #[inline]
    pub fn sin_cos(u: &Coeffs, s: &Coeffs, c: &Coeffs, n: usize) -> (f64, f64) {
        let (mut ss, mut cc) = (0.0, 0.0);
        for (k, ((&uk, &ck), &sk)) in u[1..=n]
            .iter()
            .zip(c[..n].iter().rev())
            .zip(s[..n].iter().rev())
            .enumerate()
        {
            let ku = (k + 1) as f64 * uk;
            ss += ku * ck;
            cc -= ku * sk;
        }
        let inv = 1.0 / n as f64;
        (ss * inv, cc * inv)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ode::Event;

    /// y'' = -sin y: the pendulum, expanded with the recurrences; cos y is
    /// its extra series, and it watches the events it is given.
    struct Pendulum(Vec<Event>);

    /// The left turning point: y' rising through zero.
    fn pendulum() -> Pendulum {
        Pendulum(vec![Event {
            source: Source::State(1),
            level: 0.0,
            direction: Direction::Rising,
        }])
    }

    impl SeriesSystem<2> for Pendulum {
        fn expand(&self, y: &[f64; 2], p: usize, x: &mut [Coeffs; 2], extra: &mut [Coeffs; MAX_EXTRA]) {
            let mut s = [0.0; MAX_ORDER + 1];
            let c = &mut extra[0];
            x[0][0] = y[0];
            x[1][0] = y[1];
            (s[0], c[0]) = y[0].sin_cos();
            for n in 0..=p {
                if n > 0 {
                    (s[n], c[n]) = rec::sin_cos(&x[0], &s, c, n);
                }
                if n < p {
                    x[0][n + 1] = x[1][n] / (n + 1) as f64;
                    x[1][n + 1] = -s[n] / (n + 1) as f64;
                }
            }
        }
    }

    impl System<2> for Pendulum {
        fn rhs(&self, _t: f64, y: &[f64; 2]) -> [f64; 2] {
            [y[1], -y[0].sin()]
        }
        fn events(&self) -> &[Event] {
            &self.0
        }
        fn extra(&self, _j: usize, _t: f64, y: &[f64; 2]) -> f64 {
            y[0].cos()
        }
    }

    fn solver(rtol: f64) -> Taylor<2> {
        Taylor::new(
            Options {
                rtol,
                atol: rtol,
                ..Options::default()
            },
            16,
            1.0,
        )
    }

    /// The period of a pendulum of amplitude 170 deg is 4 K(sin 85 deg):
    /// the time from the right turning point to the left one is half of it.
    #[test]
    fn pendulum_half_period_matches_the_elliptic_integral() {
        let amp = 170f64.to_radians();
        let k = (amp / 2.0).sin();
        // K(k) by the arithmetic-geometric mean.
        let (mut a, mut b) = (1.0f64, (1.0 - k * k).sqrt());
        for _ in 0..20 {
            (a, b) = (0.5 * (a + b), (a * b).sqrt());
        }
        let half = std::f64::consts::PI / (2.0 * a) * 2.0;
        let mut s = solver(1e-12);
        let end = s.integrate(&pendulum(), 0.0, [amp, 0.0], 20.0, &mut |_, _| {}).unwrap();
        assert_eq!(end.stop, Stop::Event(0));
        assert!((end.t - half).abs() < 1e-10, "{} vs {half}", end.t);
        assert!((end.y[0] + amp).abs() < 1e-10, "{}", end.y[0]);
        // Energy along the way, at the step ends and inside steps.
        let mut worst = 0.0f64;
        let e0 = 1.0 - amp.cos();
        let mut s = solver(1e-10);
        s.integrate(&pendulum(), 0.0, [amp, 0.0], 3.0, &mut |ser, t1| {
            for k in 0..=8 {
                let tt = ser.t0() + (t1 - ser.t0()) * k as f64 / 8.0;
                let [q, v] = ser.eval(tt);
                worst = worst.max((0.5 * v * v + 1.0 - q.cos() - e0).abs());
            }
        })
        .unwrap();
        assert!(worst < 1e-9, "energy error {worst}");
        assert!(s.stats().steps < 60, "{:?}", s.stats());
    }

    /// The same crossing read on a state component and on an extra series,
    /// at a level and in either direction: from 170 deg the pendulum passes
    /// y = 85 deg (falling) exactly when cos y passes cos 85 deg (rising).
    #[test]
    fn events_read_levels_on_state_and_extra_series() {
        let (amp, half) = (170f64.to_radians(), 85f64.to_radians());
        let on = |source, level, direction| {
            Pendulum(vec![Event {
                source,
                level,
                direction,
            }])
        };
        let run = |p: Pendulum| solver(1e-12).integrate(&p, 0.0, [amp, 0.0], 20.0, &mut |_, _| {});
        let a = run(on(Source::State(0), half, Direction::Falling)).unwrap();
        let b = run(on(Source::Extra(0), half.cos(), Direction::Rising)).unwrap();
        assert_eq!((a.stop, b.stop), (Stop::Event(0), Stop::Event(0)));
        assert!((a.t - b.t).abs() < 1e-10, "{} vs {}", a.t, b.t);
        assert!((a.y[0] - half).abs() < 1e-9, "{}", a.y[0]);
        // The wrong direction is not this crossing: y next rises through
        // 85 deg on the way back, after the left turning point.
        let c = run(on(Source::State(0), half, Direction::Rising)).unwrap();
        assert!(c.t > 2.0 * a.t, "{} vs {}", c.t, a.t);
        // A source that does not exist is a typed error, not a panic.
        for source in [Source::State(2), Source::Extra(MAX_EXTRA)] {
            assert!(matches!(
                run(on(source, 0.0, Direction::Either)),
                Err(OdeError::InvalidOptions(_))
            ));
        }
    }

    #[test]
    fn restart_at_a_root_does_not_fire_again() {
        // Start exactly at the left turning point, where the event is zero
        // and rising: the next one is a whole period later.
        let amp = 1.0f64;
        let mut s = solver(1e-12);
        let first = s.integrate(&pendulum(), 0.0, [amp, 0.0], 50.0, &mut |_, _| {}).unwrap();
        let second = s
            .integrate(&pendulum(), first.t, [-amp, 0.0], 50.0, &mut |_, _| {})
            .unwrap();
        assert_eq!(second.stop, Stop::Event(0));
        assert!((second.t - 3.0 * first.t).abs() < 1e-9, "{} {}", first.t, second.t);
    }

    #[test]
    fn bad_order_and_step_limit_are_typed_errors() {
        let mut s = Taylor::<2>::new(Options::default(), 1, 1.0);
        assert!(matches!(
            s.integrate(&pendulum(), 0.0, [1.0, 0.0], 1.0, &mut |_, _| {}),
            Err(OdeError::InvalidOptions(_))
        ));
        let mut s = Taylor::<2>::new(
            Options {
                max_steps: 3,
                ..Options::default()
            },
            10,
            0.01,
        );
        assert!(matches!(
            s.integrate(&pendulum(), 0.0, [1.0, 0.0], 1.0, &mut |_, _| {}),
            Err(OdeError::StepLimit { limit: 3, .. })
        ));
    }

    #[test]
    fn polynomials_of_every_low_degree_evaluate() {
        let c: Coeffs = std::array::from_fn(|k| 1.0 + k as f64);
        for p in 0..=5 {
            let want: f64 = (0..=p).map(|k| c[k] * 0.5f64.powi(k as i32)).sum();
            assert!((horner(&c, p, 0.5) - want).abs() < 1e-14, "degree {p}");
            let dwant: f64 = (1..=p).map(|k| k as f64 * c[k] * 0.5f64.powi(k as i32 - 1)).sum();
            let (v, d) = horner_d(&c, p, 0.5);
            assert!(
                (v - want).abs() < 1e-14 && (d - dwant).abs() < 1e-13,
                "degree {p}: {v} {d}"
            );
        }
        // An event whose only nonzero term is the last: no panic, and its
        // root at 0 is the restart point, not a crossing.
        let s = Taylor::<2>::new(Options::default(), 4, 1.0);
        let mut c = [0.0; MAX_ORDER + 1];
        c[4] = 1.0;
        let hk: Coeffs = std::array::from_fn(|k| 0.5f64.powi(k as i32));
        assert_eq!(
            s.first_root(&c, 0.0, Direction::Rising, 0.5, &hk, 4, f64::INFINITY, false),
            None
        );
        // The same on a level: 3 + s^4 starts at the level 3 (a restart).
        c[0] = 3.0;
        assert_eq!(
            s.first_root(&c, 3.0, Direction::Rising, 0.5, &hk, 4, f64::INFINITY, false),
            None
        );
        c[4] = 32.0;
        // 3 + 32 s^4 crosses 5 where s^4 = 1/16: at s = 0.5.
        let root = s
            .first_root(&c, 5.0, Direction::Rising, 0.5, &hk, 4, f64::INFINITY, false)
            .unwrap();
        assert!((root - 0.5).abs() < 1e-11, "{root}");
        // A bad order is refused, and a hint does not panic on it.
        let mut bad = Taylor::<2>::new(Options::default(), 1, 1.0);
        bad.hint_next(3, 0.1);
    }

    /// The short flight's order by powers is the one by logarithms, for
    /// every flight and tolerance tried (the boundaries included: flights
    /// where ratio^k is rtol within rounding).
    #[test]
    fn bounce_order_by_powers_is_the_order_by_logarithms() {
        let by_logs = |flight: f64, rtol: f64| {
            let ratio = flight / 0.25;
            if !(ratio > 0.0 && ratio < 0.5) {
                return usize::MAX;
            }
            (rtol.ln() / ratio.ln()).ceil().max(2.0) as usize + 1
        };
        for rtol in [3e-8f64, 1e-12, 1e-6, 1e-3, 0.3, 1e-200] {
            let mut flight = 1e-12;
            while flight < 0.2 {
                assert_eq!(
                    bounce_order(flight, rtol.ln(), rtol),
                    by_logs(flight, rtol),
                    "{flight} {rtol}"
                );
                flight *= 1.0007;
            }
            // Where ratio^k = rtol: ratio = rtol^(1/k), and its neighbours.
            for k in 1..30 {
                let ratio = rtol.powf(1.0 / k as f64);
                for f in [ratio, ratio.next_up(), ratio.next_down()] {
                    let flight = f * 0.25;
                    assert_eq!(
                        bounce_order(flight, rtol.ln(), rtol),
                        by_logs(flight, rtol),
                        "{flight} {rtol}"
                    );
                }
            }
        }
        assert_eq!(bounce_order(0.2, 3e-8f64.ln(), 3e-8), usize::MAX);
        assert_eq!(bounce_order(0.0, 3e-8f64.ln(), 3e-8), usize::MAX);
    }

    #[test]
    fn inv_root_is_close_enough_for_step_control() {
        let mut m = 1e-200;
        while m < 1e200 {
            for j in [1usize, 2, 5, 11, 12, 24] {
                let (a, b) = (inv_root(m, j), m.powf(-1.0 / j as f64));
                assert!((a - b).abs() <= 2e-4 * b, "{m}^(-1/{j}): {a} vs {b}");
            }
            m *= 3.7;
        }
        assert_eq!(inv_root(f64::INFINITY, 3), 0.0);
        assert!(inv_root(f64::NAN, 3).is_nan());
    }

    #[test]
    fn recurrences_match_known_series() {
        // u = t: sin t and cos t.
        let mut u = [0.0; MAX_ORDER + 1];
        u[1] = 1.0;
        let (mut s, mut c) = ([0.0; MAX_ORDER + 1], [0.0; MAX_ORDER + 1]);
        c[0] = 1.0;
        let mut fact = 1.0;
        for n in 1..=10 {
            (s[n], c[n]) = rec::sin_cos(&u, &s, &c, n);
            fact *= n as f64;
            let (es, ec) = match n % 4 {
                0 => (0.0, 1.0),
                1 => (1.0, 0.0),
                2 => (0.0, -1.0),
                _ => (-1.0, 0.0),
            };
            assert!(
                (s[n] - es / fact).abs() < 1e-15 && (c[n] - ec / fact).abs() < 1e-15,
                "{n}"
            );
        }
        // 1 / (1 - t) = sum t^k, and (1 + t)^2.
        let mut one = [0.0; MAX_ORDER + 1];
        one[0] = 1.0;
        let mut b = one;
        b[1] = -1.0;
        let mut q = [0.0; MAX_ORDER + 1];
        for n in 0..=8 {
            q[n] = rec::div(&one, &b, &q, n);
            assert_eq!(q[n], 1.0);
        }
        let mut a = one;
        a[1] = 1.0;
        assert_eq!([0, 1, 2, 3].map(|n| rec::mul(&a, &a, n)), [1.0, 2.0, 1.0, 0.0]);
    }
}
