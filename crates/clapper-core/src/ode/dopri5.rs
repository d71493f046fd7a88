//! Dormand–Prince 5(4) with Hairer's step-size control and 4th-order dense
//! output (Hairer, Nørsett & Wanner, *Solving ODEs I*, II.5 and the DOPRI5
//! code), plus root location of events on the dense output.

use super::interface::{
    begin, check_options, crossed, sign, split_exp2, split_exponent, DenseOutput, Direction, ErrorWeights, Event,
    NextSegment, Observe, OdeError, Options, Run, Segment, Span, Stats, Stepper, Stop, System, MAX_EVENTS,
};

// Butcher tableau of Dormand & Prince (1980).
const C2: f64 = 1.0 / 5.0;
const C3: f64 = 3.0 / 10.0;
const C4: f64 = 4.0 / 5.0;
const C5: f64 = 8.0 / 9.0;
const A21: f64 = 1.0 / 5.0;
const A31: f64 = 3.0 / 40.0;
const A32: f64 = 9.0 / 40.0;
const A41: f64 = 44.0 / 45.0;
const A42: f64 = -56.0 / 15.0;
const A43: f64 = 32.0 / 9.0;
const A51: f64 = 19372.0 / 6561.0;
const A52: f64 = -25360.0 / 2187.0;
const A53: f64 = 64448.0 / 6561.0;
const A54: f64 = -212.0 / 729.0;
const A61: f64 = 9017.0 / 3168.0;
const A62: f64 = -355.0 / 33.0;
const A63: f64 = 46732.0 / 5247.0;
const A64: f64 = 49.0 / 176.0;
const A65: f64 = -5103.0 / 18656.0;
const A71: f64 = 35.0 / 384.0;
const A73: f64 = 500.0 / 1113.0;
const A74: f64 = 125.0 / 192.0;
const A75: f64 = -2187.0 / 6784.0;
const A76: f64 = 11.0 / 84.0;
// Error weights: 5th-order minus embedded 4th-order solution.
const E1: f64 = 71.0 / 57600.0;
const E3: f64 = -71.0 / 16695.0;
const E4: f64 = 71.0 / 1920.0;
const E5: f64 = -17253.0 / 339200.0;
const E6: f64 = 22.0 / 525.0;
const E7: f64 = -1.0 / 40.0;
// Dense output coefficients (Hairer's CONTD5).
const D1: f64 = -12715105075.0 / 11282082432.0;
const D3: f64 = 87487479700.0 / 32700410799.0;
const D4: f64 = -10690763975.0 / 1880347072.0;
const D5: f64 = 701980252875.0 / 199316789632.0;
const D6: f64 = -1453857185.0 / 822651844.0;
const D7: f64 = 69997945.0 / 29380423.0;

// Step-size controller (Hairer's PI controller constants).
const SAFETY: f64 = 0.9;
const BETA: f64 = 0.04;
const EXPO1: f64 = 0.2 - BETA * 0.75;
const FAC_MIN: f64 = 0.2; // largest shrink per step is 1/5 ...
const FAC_MAX: f64 = 10.0; // ... largest growth 10x
/// Bisection/Illinois iterations for one root; 1e-12 s from a 0.05 s step
/// needs about 36 halvings, so this bound is never the binding one.
const MAX_ROOT_ITERS: usize = 200;

/// `x^p` for the step-size factor, `x ≥ 0`, within 1e-4 relative: a
/// heuristic factor needs no more, and the library `pow` took a twelfth of
/// a chart's time. log2 from the exponent bits and an atanh series for the
/// mantissa; 2^y from the integer part's bits and a Taylor series.
#[inline]
fn pow_approx(x: f64, p: f64) -> f64 {
    if x.is_nan() {
        return f64::NAN;
    }
    if x <= 1e-300 {
        return 0.0;
    }
    if x.is_infinite() {
        return if p > 0.0 { f64::INFINITY } else { 0.0 };
    }
    let (e, m) = split_exponent(x);
    let s = (m - 1.0) / (m + 1.0);
    let s2 = s * s;
    let ln_m = 2.0 * s * (1.0 + s2 * (1.0 / 3.0 + s2 * (1.0 / 5.0 + s2 * (1.0 / 7.0 + s2 / 9.0))));
    let y = (p * (e as f64 + ln_m * std::f64::consts::LOG2_E)).clamp(-1000.0, 1000.0);
    let (f, two_n) = split_exp2(y);
    let two_f = 1.0 + f * (1.0 + f * (0.5 + f * (1.0 / 6.0 + f * (1.0 / 24.0 + f * (1.0 / 120.0 + f / 720.0)))));
    two_f * two_n
}

/// The dense output of one step: a quartic in the step fraction that
/// interpolates the solution to 4th order anywhere in `[t0, t0 + h]`.
#[derive(Clone, Copy, Debug)]
pub struct Dense<const N: usize> {
    span: Span,
    r: [[f64; N]; 5],
}

impl<const N: usize> DenseOutput<N> for Dense<N> {
    fn span(&self) -> Span {
        self.span
    }

    #[inline]
    fn eval(&self, t: f64) -> [f64; N] {
        let s = (t - self.span.t0) / self.span.h;
        let s1 = 1.0 - s;
        let r = &self.r;
        std::array::from_fn(|i| r[0][i] + s * (r[1][i] + s1 * (r[2][i] + s * (r[3][i] + s1 * r[4][i]))))
    }
}

/// An adaptive Dormand–Prince 5(4) integrator.
///
/// One integrator carries a step-size suggestion and a step budget from one
/// [`integrate`](Self::integrate) call to the next, so a caller that stops at
/// an event, changes the state and calls again continues efficiently.
#[derive(Clone, Debug)]
pub struct Dopri5<const N: usize> {
    opts: Options,
    h_next: Option<f64>,
    stats: Stats,
}

impl<const N: usize> Dopri5<N> {
    /// An integrator with the given options.
    pub fn new(opts: Options) -> Self {
        Self {
            opts,
            h_next: None,
            stats: Stats::default(),
        }
    }

    /// The options in force.
    pub fn options(&self) -> &Options {
        &self.opts
    }

    /// Work done so far.
    pub fn stats(&self) -> Stats {
        self.stats
    }

    /// Forget the step-size suggestion (after a discontinuity in the
    /// right-hand side, the old step size may not fit).
    pub fn reset_step(&mut self) {
        self.h_next = None;
    }

    #[inline]
    fn err_norm(&self, w: &ErrorWeights<N>, y0: &[f64; N], y1: &[f64; N], e: &[f64; N]) -> f64 {
        let mut s = 0.0;
        for i in 0..N {
            let sk = w.scale(i, y0[i]).max(w.scale(i, y1[i]));
            let q = e[i] / sk;
            s += q * q;
        }
        (s / N as f64).sqrt()
    }

    fn initial_step<S: System<N> + ?Sized>(
        &mut self,
        sys: &S,
        w: &ErrorWeights<N>,
        t0: f64,
        y0: &[f64; N],
        f0: &[f64; N],
    ) -> f64 {
        let mut d0 = 0.0;
        let mut d1 = 0.0;
        for i in 0..N {
            let sk = w.scale(i, y0[i]);
            d0 += ((y0[i] - w.origin[i]) / sk).powi(2);
            d1 += (f0[i] / sk).powi(2);
        }
        d0 = (d0 / N as f64).sqrt();
        d1 = (d1 / N as f64).sqrt();
        let h0 = if d0 < 1e-10 || d1 < 1e-10 { 1e-6 } else { 0.01 * d0 / d1 };
        let h0 = h0.min(self.opts.h_max);
        let y1: [f64; N] = std::array::from_fn(|i| y0[i] + h0 * f0[i]);
        let f1 = sys.rhs(t0 + h0, &y1);
        self.stats.rhs_evals += 1;
        let mut d2 = 0.0;
        for i in 0..N {
            let sk = w.scale(i, y0[i]);
            d2 += ((f1[i] - f0[i]) / sk).powi(2);
        }
        d2 = (d2 / N as f64).sqrt() / h0;
        let dm = d1.max(d2);
        let h1 = if dm <= 1e-15 {
            (h0 * 1e-3).max(1e-6)
        } else {
            (0.01 / dm).powf(0.2)
        };
        (100.0 * h0).min(h1).min(self.opts.h_max)
    }
}

impl<const N: usize> Dopri5<N> {
    /// f at the start (t, y) and the first step's size: the last segment's
    /// next step, or Hairer's initial guess.
    fn first_step<S: System<N> + ?Sized>(
        &mut self,
        sys: &S,
        weights: &ErrorWeights<N>,
        t: f64,
        y: &[f64; N],
    ) -> Result<([f64; N], f64), OdeError> {
        let k1 = sys.rhs(t, y);
        self.stats.rhs_evals += 1;
        if k1.iter().chain(y.iter()).any(|v| !v.is_finite()) {
            return Err(OdeError::NonFinite { t });
        }
        let h = match self.h_next {
            Some(h) => h.min(self.opts.h_max),
            None => self.initial_step(sys, weights, t, y, &k1),
        };
        Ok((k1, h))
    }

    /// The size of the next attempt from `t`: `h`, or what is left to
    /// `t_end` (then it is the last); an error past the step budget or
    /// below the smallest step.
    #[inline]
    fn attempt(&self, t: f64, t_end: f64, h: f64) -> Result<(f64, bool), OdeError> {
        // Rejected attempts count too, so that no input can loop forever.
        if self.stats.steps + self.stats.rejected >= self.opts.max_steps {
            return Err(OdeError::StepLimit {
                limit: self.opts.max_steps,
                t,
            });
        }
        let remaining = t_end - t;
        let last = h >= remaining;
        let h = if last { remaining } else { h };
        if (h.is_nan() || h <= 1e-14 * t.abs().max(1.0)) && !last {
            return Err(OdeError::StepSizeUnderflow { h, t });
        }
        Ok((h, last))
    }
}

impl<const N: usize, S: System<N> + ?Sized> Stepper<N, S> for Dopri5<N> {
    fn stats(&self) -> Stats {
        Dopri5::stats(self)
    }

    fn expect(&mut self, next: NextSegment) {
        if next == NextSegment::Stiffer {
            self.reset_step();
        }
    }

    fn integrate<F: Observe<N>>(&mut self, sys: &S, t0: f64, y0: [f64; N], t_end: f64, observe: &mut F) -> Run<N> {
        check_options(&self.opts, self.opts.h_max)?;
        if let Some(done) = begin(sys, t0, y0, t_end)? {
            return Ok(done);
        }
        let events = sys.events();
        let weights = sys.error_weights(self.opts.atol, self.opts.rtol);
        let mut watch = EventWatch::new(sys, events, t0, &y0);

        let mut t = t0;
        let mut y = y0;
        let (mut k1, mut h) = self.first_step(sys, &weights, t, &y)?;
        let mut control = Control {
            fac_old: 1e-4,
            last_rejected: false,
        };

        loop {
            let last;
            (h, last) = self.attempt(t, t_end, h)?;

            let t_new = if last { t_end } else { t + h };
            let st = Stages::of(sys, t, &y, k1, h, t_new);
            self.stats.rhs_evals += 6;
            let err = self.err_norm(&weights, &y, &st.y_new, &st.e);

            let h_new = match control.judge(err, h, &self.opts, &mut self.stats) {
                Judged::Retry(h_retry) => {
                    h = h_retry;
                    if !err.is_finite() && (h.is_nan() || h <= 1e-14 * t.abs().max(1.0)) {
                        return Err(OdeError::NonFinite { t });
                    }
                    continue;
                }
                Judged::Accept(h_new) => h_new,
            };

            let dense = st.dense(t, h, &y);
            let t_left = watch.left_ends(sys, events, t, t_new, h, &dense);
            let (best, g_new) =
                watch.earliest(sys, events, &t_left, t_new, &st.y_new, &dense, self.opts.event_time_tol);

            if let Some((t_ev, i)) = best {
                observe(&dense, t_ev);
                let y_ev = if t_ev >= t_new { st.y_new } else { dense.eval(t_ev) };
                self.h_next = Some(h_new.max(h));
                return Ok(Segment {
                    t: t_ev,
                    y: y_ev,
                    stop: Stop::Event(i),
                });
            }

            observe(&dense, t_new);
            watch.advance(events.len(), &g_new);
            t = t_new;
            y = st.y_new;
            k1 = st.k[6];
            if y.iter().chain(k1.iter()).any(|v| !v.is_finite()) {
                return Err(OdeError::NonFinite { t });
            }
            if last {
                self.h_next = Some(h_new);
                return Ok(Segment {
                    t,
                    y,
                    stop: Stop::EndTime,
                });
            }
            h = h_new;
        }
    }
}

/// Hairer's step-size control (DOPRI5's, with its PI factor): what the
/// last accepted step's error was and whether the last attempt failed.
struct Control {
    fac_old: f64,
    last_rejected: bool,
}

/// A step judged: tried again with a smaller size, or accepted with the
/// size for the next step.
enum Judged {
    Retry(f64),
    Accept(f64),
}

impl Control {
    /// Judge a step of size `h` whose error norm is `err`, counting it.
    #[inline]
    fn judge(&mut self, err: f64, h: f64, opts: &Options, stats: &mut Stats) -> Judged {
        if !err.is_finite() {
            // Treat like a failed step: shrink hard and try again.
            stats.rejected += 1;
            self.last_rejected = true;
            return Judged::Retry(h * 0.1);
        }
        let fac11 = pow_approx(err, EXPO1);
        if err > 1.0 {
            stats.rejected += 1;
            self.last_rejected = true;
            return Judged::Retry(h / (fac11 / SAFETY).min(1.0 / FAC_MIN));
        }
        stats.steps += 1;
        let fac = (fac11 / pow_approx(self.fac_old, BETA) / SAFETY).clamp(1.0 / FAC_MAX, 1.0 / FAC_MIN);
        let mut h_new = (h / fac).min(opts.h_max);
        if self.last_rejected {
            h_new = h_new.min(h);
        }
        self.fac_old = err.max(1e-4);
        self.last_rejected = false;
        Judged::Accept(h_new)
    }
}

/// One step's stages from (t, y), k1 = f(t, y): k1 to k7 (k7 is f at the
/// new point, reused as the next step's k1), the fifth-order solution and
/// its error estimate.
struct Stages<const N: usize> {
    k: [[f64; N]; 7],
    y_new: [f64; N],
    e: [f64; N],
}

impl<const N: usize> Stages<N> {
    #[inline]
    fn of<S: System<N> + ?Sized>(sys: &S, t: f64, y: &[f64; N], k1: [f64; N], h: f64, t_new: f64) -> Self {
        let yt: [f64; N] = std::array::from_fn(|i| y[i] + h * A21 * k1[i]);
        let k2 = sys.rhs(t + C2 * h, &yt);
        let yt: [f64; N] = std::array::from_fn(|i| y[i] + h * (A31 * k1[i] + A32 * k2[i]));
        let k3 = sys.rhs(t + C3 * h, &yt);
        let yt: [f64; N] = std::array::from_fn(|i| y[i] + h * (A41 * k1[i] + A42 * k2[i] + A43 * k3[i]));
        let k4 = sys.rhs(t + C4 * h, &yt);
        let yt: [f64; N] = std::array::from_fn(|i| y[i] + h * (A51 * k1[i] + A52 * k2[i] + A53 * k3[i] + A54 * k4[i]));
        let k5 = sys.rhs(t + C5 * h, &yt);
        let yt: [f64; N] =
            std::array::from_fn(|i| y[i] + h * (A61 * k1[i] + A62 * k2[i] + A63 * k3[i] + A64 * k4[i] + A65 * k5[i]));
        let k6 = sys.rhs(t_new, &yt);
        let y_new: [f64; N] =
            std::array::from_fn(|i| y[i] + h * (A71 * k1[i] + A73 * k3[i] + A74 * k4[i] + A75 * k5[i] + A76 * k6[i]));
        let k7 = sys.rhs(t_new, &y_new);
        let e: [f64; N] =
            std::array::from_fn(|i| h * (E1 * k1[i] + E3 * k3[i] + E4 * k4[i] + E5 * k5[i] + E6 * k6[i] + E7 * k7[i]));
        Self {
            k: [k1, k2, k3, k4, k5, k6, k7],
            y_new,
            e,
        }
    }

    /// The step's 4th-order dense output over [t, t + h].
    #[inline]
    fn dense(&self, t: f64, h: f64, y: &[f64; N]) -> Dense<N> {
        let [k1, _, k3, k4, k5, k6, k7] = &self.k;
        let y_new = &self.y_new;
        let mut r = [[0.0; N]; 5];
        for i in 0..N {
            let ydiff = y_new[i] - y[i];
            let bspl = h * k1[i] - ydiff;
            r[0][i] = y[i];
            r[1][i] = ydiff;
            r[2][i] = bspl;
            r[3][i] = ydiff - h * k7[i] - bspl;
            r[4][i] = h * (D1 * k1[i] + D3 * k3[i] + D4 * k4[i] + D5 * k5[i] + D6 * k6[i] + D7 * k7[i]);
        }
        Dense {
            span: Span { t0: t, h },
            r,
        }
    }
}

/// Event bookkeeping across steps: each event's last value, the sign it
/// is known to have, and whether it started exactly at zero (a restart at
/// its own root).
struct EventWatch {
    g_prev: [f64; MAX_EVENTS],
    s_prev: [i8; MAX_EVENTS],
    at_zero: [bool; MAX_EVENTS],
    first_step: bool,
}

impl EventWatch {
    fn new<const N: usize, S: System<N> + ?Sized>(sys: &S, events: &[Event], t0: f64, y0: &[f64; N]) -> Self {
        let mut w = Self {
            g_prev: [0.0f64; MAX_EVENTS],
            s_prev: [0i8; MAX_EVENTS],
            at_zero: [false; MAX_EVENTS],
            first_step: true,
        };
        for (i, e) in events.iter().enumerate() {
            let g = sys.event_value(e, t0, y0);
            w.g_prev[i] = g;
            w.s_prev[i] = sign(g);
            w.at_zero[i] = g == 0.0;
        }
        w
    }

    /// Where each event's search starts in the step from `t`. An event
    /// that starts exactly at zero takes the sign it has just after the
    /// start (probed on the dense output, well inside any real flight);
    /// only if that is still zero, the side its direction comes from. So
    /// it neither fires again at the restart point nor misses a return to
    /// zero within the first step.
    fn left_ends<const N: usize, S: System<N> + ?Sized>(
        &mut self,
        sys: &S,
        events: &[Event],
        t: f64,
        t_new: f64,
        h: f64,
        dense: &Dense<N>,
    ) -> [f64; MAX_EVENTS] {
        let mut t_left = [t; MAX_EVENTS];
        if self.first_step {
            self.first_step = false;
            let tp = t + (1e-9 * h).max(4.0 * f64::EPSILON * t.abs());
            for (i, e) in events.iter().enumerate() {
                if self.at_zero[i] && tp < t_new {
                    let gp = sys.event_value(e, tp, &dense.eval(tp));
                    self.s_prev[i] = match (sign(gp), e.direction) {
                        (0, Direction::Rising) => -1,
                        (0, Direction::Falling) => 1,
                        (s, _) => s,
                    };
                    self.g_prev[i] = gp;
                    t_left[i] = tp;
                }
            }
        }
        t_left
    }

    /// The earliest root among the events that crossed in their direction
    /// in the step to `t_new`, and every event's value at `t_new`.
    #[allow(clippy::too_many_arguments)] // one step's ends and its dense output
    fn earliest<const N: usize, S: System<N> + ?Sized>(
        &self,
        sys: &S,
        events: &[Event],
        t_left: &[f64; MAX_EVENTS],
        t_new: f64,
        y_new: &[f64; N],
        dense: &Dense<N>,
        tol: f64,
    ) -> (Option<(f64, usize)>, [f64; MAX_EVENTS]) {
        let mut best: Option<(f64, usize)> = None;
        let mut g_new = [0.0f64; MAX_EVENTS];
        for (i, e) in events.iter().enumerate() {
            let g1 = sys.event_value(e, t_new, y_new);
            g_new[i] = g1;
            let s0 = self.s_prev[i];
            let s1 = sign(g1);
            if crossed(e.direction, s0, s1) {
                let root = locate_root(
                    |tt| sys.event_value(e, tt, &dense.eval(tt)),
                    t_left[i],
                    self.g_prev[i],
                    s0,
                    t_new,
                    g1,
                    tol,
                );
                if best.is_none_or(|(tb, _)| root < tb) {
                    best = Some((root, i));
                }
            }
        }
        (best, g_new)
    }

    /// Past an accepted step with no event: its end values become the last.
    fn advance(&mut self, n_ev: usize, g_new: &[f64; MAX_EVENTS]) {
        for (i, &g) in g_new.iter().enumerate().take(n_ev) {
            self.g_prev[i] = g;
            let s1 = sign(g);
            if s1 != 0 {
                self.s_prev[i] = s1;
            }
        }
    }
}

/// Find the first time in `(a, b]` where `g` reaches the side opposite to
/// `sa`, the sign `g` is known to have at `a` (its value `ga` there may be
/// exactly zero after a restart). Returns a time at which `g` is already on
/// the far side (or zero), within `tol` of the root.
pub(super) fn locate_root<G: Fn(f64) -> f64>(g: G, mut a: f64, ga: f64, sa: i8, mut b: f64, gb: f64, tol: f64) -> f64 {
    // Oriented so that the start side is negative.
    let orient = -f64::from(sa);
    let mut fa = ga * orient;
    let mut fb = gb * orient;
    if fb == 0.0 && fa < 0.0 && (b - a) <= tol {
        return b;
    }
    let mut side = 0i8;
    for iter in 0..MAX_ROOT_ITERS {
        if b - a <= tol {
            break;
        }
        // Regula falsi (Illinois) when both ends are informative, bisection
        // otherwise and every fourth iteration, so the bracket always shrinks.
        let c = if fa < 0.0 && fb > 0.0 && iter % 4 != 3 {
            let c = (a * fb - b * fa) / (fb - fa);
            let margin = 0.01 * (b - a);
            c.clamp(a + margin.min(tol * 0.5), b - margin.min(tol * 0.5))
        } else {
            0.5 * (a + b)
        };
        let fc = g(c) * orient;
        if fc < 0.0 {
            a = c;
            fa = fc;
            if side == -1 {
                fb *= 0.5;
            }
            side = -1;
        } else {
            b = c;
            fb = fc.max(f64::MIN_POSITIVE);
            if side == 1 {
                fa *= 0.5;
            }
            side = 1;
        }
    }
    b
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::ode::{Event, Source};

    struct Exp;
    impl System<1> for Exp {
        fn rhs(&self, _t: f64, y: &[f64; 1]) -> [f64; 1] {
            [y[0]]
        }
    }

    /// y0 rising through zero, and y1 crossing zero either way.
    struct Osc([Event; 2]);
    const OSC: Osc = Osc([
        Event {
            source: Source::State(0),
            level: 0.0,
            direction: Direction::Rising,
        },
        Event {
            source: Source::State(1),
            level: 0.0,
            direction: Direction::Either,
        },
    ]);
    impl System<2> for Osc {
        fn rhs(&self, _t: f64, y: &[f64; 2]) -> [f64; 2] {
            [y[1], -y[0]]
        }
        fn events(&self) -> &[Event] {
            &self.0
        }
    }

    #[test]
    fn exponential_growth_to_tolerance() {
        let mut s = Dopri5::new(Options {
            rtol: 1e-10,
            atol: 1e-12,
            ..Options::default()
        });
        let end = s.integrate(&Exp, 0.0, [1.0], 2.0, &mut |_, _| {}).unwrap();
        assert_eq!(end.stop, Stop::EndTime);
        assert!((end.y[0] - 2f64.exp()).abs() / 2f64.exp() < 1e-9, "{}", end.y[0]);
    }

    #[test]
    fn dense_output_is_accurate_inside_steps() {
        let mut s = Dopri5::new(Options {
            rtol: 1e-10,
            atol: 1e-12,
            h_max: 0.5,
            ..Options::default()
        });
        let mut worst = 0.0f64;
        let mut steps = 0;
        s.integrate(&Exp, 0.0, [1.0], 3.0, &mut |d, t_stop| {
            steps += 1;
            for k in 0..=10 {
                let tt = d.t0() + (t_stop - d.t0()) * k as f64 / 10.0;
                worst = worst.max((d.eval(tt)[0] - tt.exp()).abs() / tt.exp());
            }
        })
        .unwrap();
        assert!(steps > 3);
        // 4th-order interpolant: a little looser than the 5th-order step ends.
        assert!(worst < 1e-8, "dense error {worst}");
    }

    #[test]
    fn events_fire_in_direction_and_do_not_retrigger_on_restart() {
        let mut s = Dopri5::new(Options::default());
        // y0 = sin t. Rising zero of y0 at 2 pi; the Either event on y1 = cos t at pi/2 comes first.
        let end = s.integrate(&OSC, 0.0, [0.0, 1.0], 20.0, &mut |_, _| {}).unwrap();
        assert_eq!(end.stop, Stop::Event(1));
        assert!((end.t - std::f64::consts::FRAC_PI_2).abs() < 1e-10);
        // Restart exactly at a rising zero of y0: it must not fire at the start.
        let end = s.integrate(&OSC, 0.0, [0.0, 1.0], 20.0, &mut |_, _| {}).unwrap();
        assert!(end.t > 1.0);
        let mut t = 0.0;
        let mut y = [0.0, 1.0];
        let mut rising = vec![];
        for _ in 0..10 {
            let seg = s.integrate(&OSC, t, y, 20.0, &mut |_, _| {}).unwrap();
            if seg.stop == Stop::EndTime {
                break;
            }
            if seg.stop == Stop::Event(0) {
                rising.push(seg.t);
            }
            t = seg.t;
            y = seg.y;
        }
        let two_pi = 2.0 * std::f64::consts::PI;
        assert_eq!(rising.len(), 3, "{rising:?}");
        for (k, r) in rising.iter().enumerate() {
            assert!((r - two_pi * (k + 1) as f64).abs() < 1e-8, "{r}");
        }
    }

    #[test]
    fn step_limit_is_a_typed_error() {
        let mut s = Dopri5::new(Options {
            max_steps: 5,
            h_max: 1e-3,
            ..Options::default()
        });
        let err = s.integrate(&Exp, 0.0, [1.0], 1.0, &mut |_, _| {}).unwrap_err();
        assert!(matches!(err, OdeError::StepLimit { limit: 5, .. }));
    }

    #[test]
    fn blow_up_is_a_typed_error_not_a_hang() {
        struct Blow;
        impl System<1> for Blow {
            fn rhs(&self, _t: f64, y: &[f64; 1]) -> [f64; 1] {
                [y[0] * y[0]]
            }
        }
        let mut s = Dopri5::new(Options::default());
        // y' = y^2 from 1 blows up at t = 1.
        let err = s.integrate(&Blow, 0.0, [1.0], 2.0, &mut |_, _| {}).unwrap_err();
        assert!(matches!(
            err,
            OdeError::StepSizeUnderflow { .. } | OdeError::NonFinite { .. } | OdeError::StepLimit { .. }
        ));
    }

    #[test]
    fn pow_approx_is_close_enough_for_step_control() {
        let mut x = 1e-12;
        while x < 1e12 {
            for p in [EXPO1, BETA, 0.2, -0.2] {
                let (a, b) = (pow_approx(x, p), x.powf(p));
                assert!((a - b).abs() <= 1e-4 * b, "{x}^{p}: {a} vs {b}");
            }
            x *= 1.37;
        }
        assert_eq!(pow_approx(0.0, EXPO1), 0.0);
        assert!(pow_approx(f64::NAN, EXPO1).is_nan());
    }

    #[test]
    fn root_locator_finds_first_root_after_zero_start() {
        // g = t (t - 1): zero at 0 (the restart point) and at 1; known negative just after 0.
        let r = locate_root(|t| t * (t - 1.0), 0.0, 0.0, -1, 1.5, 0.75, 1e-13);
        assert!((r - 1.0).abs() < 1e-12, "{r}");
        assert!(r >= 1.0);
    }

    /// A tiny oscillation about a far origin, y = c + A cos(ω t) with
    /// A = 1e-9 and c = 1: the penalty spring's resting clapper in
    /// miniature. Weighed from zero with an order-one absolute tolerance,
    /// the oscillation is lost in the tolerance; weighed from c with the
    /// tolerance scaled to A (as `ErrorWeights` lets a system say), it is
    /// followed to the tolerance's share of A. Checked against the exact
    /// solution.
    struct Ring {
        origin: bool,
    }
    const RING_A: f64 = 1e-9;
    impl System<2> for Ring {
        fn rhs(&self, _t: f64, y: &[f64; 2]) -> [f64; 2] {
            [y[1], -100.0 * (y[0] - 1.0)]
        }
        fn error_weights(&self, atol: f64, rtol: f64) -> ErrorWeights<2> {
            let mut w = ErrorWeights::uniform(atol, rtol);
            if self.origin {
                w.origin[0] = 1.0;
                w.atol = [atol * RING_A, atol * RING_A * 10.0];
            }
            w
        }
    }

    #[test]
    fn error_weights_from_an_origin_resolve_a_small_deflection() {
        // A largest step well beyond the ring's period, so that the
        // tolerance alone sets the steps.
        let error = |origin| {
            let mut s = Dopri5::new(Options {
                h_max: 10.0,
                ..Options::default()
            });
            let mut noop = |_: &dyn DenseOutput<2>, _: f64| {};
            let seg = s
                .integrate(&Ring { origin }, 0.0, [1.0 + RING_A, 0.0], 3.0, &mut noop)
                .unwrap();
            let exact = 1.0 + RING_A * (10.0f64 * 3.0).cos();
            ((seg.y[0] - exact) / RING_A).abs()
        };
        let (plain, weighed) = (error(false), error(true));
        assert!(plain > 0.1, "weighed from zero: error {plain} of the amplitude");
        assert!(
            weighed < 1e-5,
            "weighed from the origin: error {weighed} of the amplitude"
        );
    }
}
