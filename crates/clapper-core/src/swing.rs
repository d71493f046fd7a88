//! The bell released from rest with its clapper resting on it, in closed
//! form.
//!
//! While the clapper rests against a stop (φ = ±φ_max, φ' = 0), bell and
//! clapper move as one rigid pendulum, from (5) with φ'' = 0:
//! J θ'' = −G_b sin θ − G_c sin(θ + φ) = −A sin(θ + β), J = W₁₁ at that φ.
//! Released from rest, its half swing is an elliptic function of time, and
//! the force holding the clapper, Q_φ from (6) with θ'² from the energy, is
//! a sinusoid in θ plus a constant. So the lift-off angle is an arcsine for
//! any r (for r = 0 it is (15), (16)), and the time to reach any angle is
//! one elliptic integral. A stroke uses this for its first phase instead of
//! integration steps: exact, and a sixth of a stroke's steps saved.
//!
//! Angles along the swing: α = θ + β, released at α₀ (|α₀| < π), and the
//! path coordinate σ = sign(α₀) α, which falls from |α₀| to −|α₀| over the
//! half swing.

use std::f64::consts::PI;

use crate::dynamics::{Dynamics, State, THETA, THETA_DOT};
use crate::elliptic::{carlson_rf, complete_k, jacobi};
use crate::ode::{DenseOutput, Direction, Event, Observe, Run, Segment, Source, Span, Stats, Stepper, Stop, System};

/// The half swing of the rigid bell (clapper resting) released from rest.
#[derive(Clone, Debug, PartialEq)]
pub struct RestingSwing {
    /// Release time (s).
    t0: f64,
    /// The clapper's angle φ = ±φ_max (rad).
    phi: f64,
    /// β (rad): α = θ + β.
    beta: f64,
    /// sign(α₀): σ = dir α.
    dir: f64,
    /// |α₀| (rad), in (0, π).
    alpha0: f64,
    /// √(A / J) (1/s).
    omega: f64,
    /// 4 A / J (1/s²): θ'² = (4A/J) sin((α₀ − σ)/2) sin((α₀ + σ)/2).
    four_a_over_j: f64,
    /// Modulus k = sin(α₀/2), its complement cos(α₀/2), and K(k).
    k: f64,
    kc: f64,
    kk: f64,
    /// Q_φ(θ) = q_sin sin θ + q_cos cos θ + q_const (N m) along the swing.
    q_sin: f64,
    q_cos: f64,
    q_const: f64,
    /// ±1: the swing is worked out for the bell angle m θ (a bell off the
    /// ideal released from θ₀ < 0 as its mirror image from −θ₀), so that
    /// a bell and its mirror image get the same numbers, bit for bit; the
    /// fields above are the mirrored swing's. +1 for an ideal bell.
    m: f64,
}

impl RestingSwing {
    /// The swing released at time `t0` (s) from rest at `theta0` (rad) with
    /// the clapper resting at `phi` (rad, ±φ_max). `None` where there is
    /// no swing to describe in this form: at the balance point (|α₀| within
    /// 1e-6 rad of 0 or π) or for a bell with no weight.
    pub fn from_rest(d: &Dynamics, t0: f64, theta0: f64, phi: f64) -> Option<Self> {
        // A bell off the ideal is worked out as released from θ₀ > 0 (its
        // mirror image if θ₀ < 0: θ, φ, d and the skew change sign), so
        // that the closed form is exactly odd; an ideal bell as it is.
        let m = if d.bell().hanging.is_ideal() || theta0 >= 0.0 {
            1.0
        } else {
            -1.0
        };
        let theta0 = m * theta0;
        let gc = d.gravity_clapper;
        let (sp, cp) = d.sin_cos_phi(phi);
        // The coupling m b c(φ) and m b s(φ) (docs/model.md §10.1; m r b cos φ
        // and m r b sin φ without a pivot offset, bit for bit).
        let (mbc, mbs) = d.coupling(sp, cp);
        // G_b sin θ + G_c sin(θ + φ) (+ m g d cos θ with an offset)
        // = ca sin θ + sa cos θ = A sin(θ + β).
        let sa = if d.offset { gc * sp + d.gravity_offset } else { gc * sp };
        // Mirrored: the odd ones change sign.
        let (sp, mbs, sa) = (m * sp, m * mbs, m * sa);
        let ca = d.gravity_bell + gc * cp;
        let j = d.j0 + 2.0 * mbc;
        let w12 = d.ic + mbc;
        let amp = ca.hypot(sa);
        let beta = sa.atan2(ca);
        let alpha = theta0 + beta;
        let usable = amp > 0.0 && j > 0.0 && alpha.abs() > 1e-6 && alpha.abs() < PI - 1e-6;
        if !(usable && t0.is_finite()) {
            return None;
        }
        let alpha0 = alpha.abs();
        let (k, kc) = (0.5 * alpha0).sin_cos();
        // Q_φ = W₁₂ θ'' + m b s(φ) θ'² + G_c sin(θ + φ), with
        // θ'' = −(ca sin θ + sa cos θ)/J and θ'² = 2 (V(θ₀) − V(θ))/J,
        // V(θ) = −ca cos θ + sa sin θ.
        let (s0, c0) = theta0.sin_cos();
        let c2 = 2.0 * mbs / j;
        Some(Self {
            t0,
            phi,
            beta,
            dir: alpha.signum(),
            alpha0,
            omega: (amp / j).sqrt(),
            four_a_over_j: 4.0 * amp / j,
            k,
            kc,
            kk: complete_k(kc),
            q_sin: -w12 / j * ca - c2 * sa + gc * cp,
            q_cos: -w12 / j * sa + c2 * ca + gc * sp,
            q_const: c2 * (-ca * c0 + sa * s0),
            m,
        })
    }

    /// Release time (s).
    pub fn t0(&self) -> f64 {
        self.t0
    }

    /// Duration of the half swing, release to the other turning point (s).
    pub fn half_period(&self) -> f64 {
        2.0 * self.kk / self.omega
    }

    /// The path coordinate σ of bell angle `theta` (rad).
    pub fn sigma(&self, theta: f64) -> f64 {
        self.dir * (self.m * theta + self.beta)
    }

    /// The bell angle θ (rad) at path coordinate `sigma`.
    pub fn theta(&self, sigma: f64) -> f64 {
        self.m * (self.dir * sigma - self.beta)
    }

    /// |α₀| (rad): σ runs from this down to its negative.
    pub fn amplitude(&self) -> f64 {
        self.alpha0
    }

    /// The direction θ moves in over the half swing: +1 or −1.
    pub fn theta_direction(&self) -> f64 {
        -self.dir * self.m
    }

    /// The state at path coordinate `sigma` (clamped to the half swing).
    pub fn state_at_sigma(&self, sigma: f64) -> State {
        let s = sigma.clamp(-self.alpha0, self.alpha0);
        let (a, b) = ((0.5 * (self.alpha0 - s)).sin(), (0.5 * (self.alpha0 + s)).sin());
        let speed = (self.four_a_over_j * a * b).max(0.0).sqrt();
        [self.theta(s), self.phi, self.m * (-self.dir * speed), 0.0]
    }

    /// Time from release to path coordinate `sigma` (s), in
    /// [0, half period]: (1/ω) F(ϕ, k) on the first quarter, with sin ϕ, cos ϕ
    /// and 1 − k² sin² ϕ written as products that lose no digits near the
    /// release or the bottom; the second quarter by symmetry.
    pub fn time_at_sigma(&self, sigma: f64) -> f64 {
        let s = sigma.clamp(-self.alpha0, self.alpha0);
        let quarter = |s: f64| {
            let (sh, ch) = (0.5 * s).sin_cos();
            let ab = (0.5 * (self.alpha0 - s)).sin() * (0.5 * (self.alpha0 + s)).sin();
            let sin_phi = ab.max(0.0).sqrt() / (self.k * ch);
            let cos2 = (self.kc * sh / (self.k * ch)).powi(2);
            let dn2 = (self.kc / ch).powi(2);
            sin_phi * carlson_rf(cos2, dn2, 1.0)
        };
        let u = if s >= 0.0 {
            quarter(s)
        } else {
            2.0 * self.kk - quarter(-s)
        };
        u / self.omega
    }

    /// The state at time `t` (s), clamped to the half swing: sin(σ/2) =
    /// k cd(u, k) with u = ω (t − t0), and σ' = −2 k kc ω sn(u)/dn(u)
    /// (which stays accurate at the turning points, where the energy's
    /// square root would not).
    pub fn state_at(&self, t: f64) -> State {
        let u = (self.omega * (t - self.t0)).clamp(0.0, 2.0 * self.kk);
        let (sn, cn, dn) = jacobi(u, self.k, self.kc);
        let sigma = 2.0 * (self.k * cn / dn).clamp(-1.0, 1.0).asin();
        let sigma_dot = -2.0 * self.k * self.kc * self.omega * sn / dn;
        [self.theta(sigma), self.phi, self.m * (self.dir * sigma_dot), 0.0]
    }

    /// The holding force Q_φ (N m) when the bell is at `theta` (rad) on
    /// this swing.
    pub fn holding_force(&self, theta: f64) -> f64 {
        let (s, c) = (self.m * theta).sin_cos();
        self.m * (self.q_sin * s + self.q_cos * c + self.q_const)
    }

    /// The first point after path coordinate `from` (and before the end of
    /// the half swing) where the holding force is zero, as a path
    /// coordinate: the lift-off, if the force pressed before it.
    pub fn force_zero_after(&self, from: f64) -> Option<f64> {
        self.force_level_after(from, 0.0)
    }

    /// [`force_zero_after`](Self::force_zero_after) for the holding force
    /// reaching `level` (N m): the lift-off of a clapper whose pivot's
    /// friction holds it until the force pulls by that much.
    pub fn force_level_after(&self, from: f64, level: f64) -> Option<f64> {
        // R sin(θ + ψ) = level − q_const (level mirrored as Q_φ is; exact
        // for m = ±1, and −q_const itself at level 0).
        let r = self.q_sin.hypot(self.q_cos);
        let ratio = (self.m * level - self.q_const) / r;
        if !(r > 0.0 && ratio.abs() <= 1.0) {
            return None;
        }
        let (a, psi) = (ratio.asin(), self.q_cos.atan2(self.q_sin));
        let mut best: Option<f64> = None;
        for base in [a - psi, PI - a - psi] {
            for m in -2..=2 {
                // σ of the mirrored swing's angle (θ itself when m = 1).
                let sigma = self.dir * (base + 2.0 * PI * m as f64 + self.beta);
                if sigma < from && sigma > -self.alpha0 && best.is_none_or(|b| sigma > b) {
                    best = Some(sigma);
                }
            }
        }
        best
    }
}

/// A system the closed-form swing can serve: while the clapper rests in
/// it, the system says so and gives the bell's equations. Its extra
/// function 0 must be the holding force Q_φ (N m), so that an event on it
/// is the lift-off.
pub trait SwingSystem: System<4> {
    /// The equations, when the clapper rests against the bell in this
    /// system (φ fixed at ±φ_max); `None` otherwise.
    fn resting_dynamics(&self) -> Option<&Dynamics>;
}

/// Part of a swing as a step's dense output, from `t_from` to `t_to` (s).
struct SwingPiece<'a> {
    swing: &'a RestingSwing,
    span: Span,
}

impl DenseOutput<4> for SwingPiece<'_> {
    fn span(&self) -> Span {
        self.span
    }

    fn eval(&self, t: f64) -> State {
        self.swing.state_at(t)
    }
}

/// The closed-form swing as a [`Stepper`]: it serves a resting phase that
/// starts from rest (θ' = 0) and goes on serving the same swing, segment
/// after segment, while the clapper rests; it declines anything else, and
/// gives up on a swing (for the rest of that resting phase) as soon as an
/// event is one it cannot place. Events it places: θ crossing a level, θ'
/// reaching zero (the end of the half swing) and the holding force
/// reaching zero or a level (lift-off).
#[derive(Clone, Debug, Default)]
pub struct ClosedFormSwing {
    swing: Option<RestingSwing>,
    given_up: bool,
}

impl ClosedFormSwing {
    /// The first event of `events` after the bell's angle `theta` (rad) on
    /// `sw`: its time (s), state and index. `None` if the swing's form
    /// does not apply (it moves away from the events' side) or no event
    /// comes before the end of the half swing or `t_limit` (s).
    fn first_event(sw: &RestingSwing, events: &[Event], theta: f64, t_limit: f64) -> Option<(f64, State, usize)> {
        let moving = if sw.theta_direction() > 0.0 {
            Direction::Rising
        } else {
            Direction::Falling
        };
        let from = sw.sigma(theta);
        let end = -sw.amplitude();
        let mut best: Option<(f64, usize)> = None;
        for (i, e) in events.iter().enumerate() {
            let sigma = match e.source {
                Source::State(THETA) | Source::State(THETA_DOT) if e.direction != Direction::Either => {
                    // θ' ends the half swing rising from below zero when θ
                    // falls: the opposite of θ's own direction.
                    let along = if e.source == Source::State(THETA) {
                        e.direction
                    } else {
                        e.direction.reversed()
                    };
                    if along != moving {
                        // Every bell event is a crossing towards the far
                        // side: a swing the other way is not this form's.
                        return None;
                    }
                    match e.source {
                        Source::State(THETA) => Some(sw.sigma(e.level)),
                        _ => (e.level == 0.0).then_some(end),
                    }
                }
                Source::Extra(0) => sw.force_level_after(from, e.level),
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
}

impl<S: SwingSystem + ?Sized> Stepper<4, S> for ClosedFormSwing {
    fn integrate<F: Observe<4>>(&mut self, sys: &S, t0: f64, y0: State, t_end: f64, observe: &mut F) -> Run<4> {
        let declined = Ok(Segment {
            t: t0,
            y: y0,
            stop: Stop::Declined,
        });
        let Some(d) = sys.resting_dynamics() else {
            (self.swing, self.given_up) = (None, false);
            return declined;
        };
        if self.swing.is_none() && !self.given_up && y0[THETA_DOT] == 0.0 {
            self.swing = RestingSwing::from_rest(d, t0, y0[THETA], y0[1]);
        }
        let Some(sw) = self.swing.as_ref() else {
            return declined;
        };
        match Self::first_event(sw, sys.events(), y0[THETA], t_end) {
            Some((t, y, i)) => {
                observe(
                    &SwingPiece {
                        swing: sw,
                        span: Span { t0, h: t - t0 },
                    },
                    t,
                );
                Ok(Segment {
                    t,
                    y,
                    stop: Stop::Event(i),
                })
            }
            None => {
                // Not an event this form finds: integrate the rest of the phase.
                (self.swing, self.given_up) = (None, true);
                declined
            }
        }
    }

    /// The closed form takes no steps.
    fn stats(&self) -> Stats {
        Stats::default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bell::Bell;
    use crate::ode::{Dopri5, Options};

    struct Rigid<'a>(&'a Dynamics);
    impl System<4> for Rigid<'_> {
        fn rhs(&self, _t: f64, y: &State) -> State {
            self.0.rhs_resting(y)
        }
    }

    fn tight() -> Options {
        Options {
            rtol: 1e-12,
            atol: 1e-12,
            ..Options::default()
        }
    }

    /// Time, state and holding force along the swing against the resting
    /// equations integrated by Dormand–Prince, for a bell released near the
    /// top and one released low, with the clapper on either side.
    #[test]
    fn swing_matches_the_integrated_resting_equations() {
        for bell in [Bell::lab(), Bell::gsm_tenor()] {
            let d = Dynamics::new(&bell);
            for (theta0, side) in [(171f64, 1.0), (171.0, -1.0), (40.0, 1.0), (-120.0, 1.0)] {
                let (theta0, phi) = (theta0.to_radians(), side * bell.phi_max);
                let sw = RestingSwing::from_rest(&d, 0.5, theta0, phi).unwrap();
                let mut rk = Dopri5::<4>::new(tight());
                let (mut t, mut y) = (0.5, [theta0, phi, 0.0, 0.0]);
                for step in 1..=10 {
                    let t1 = 0.5 + sw.half_period() * step as f64 / 10.0;
                    y = rk.integrate(&Rigid(&d), t, y, t1, &mut |_, _| {}).unwrap().y;
                    t = t1;
                    let ours = sw.state_at(t);
                    assert!((ours[0] - y[0]).abs() < 1e-9, "{step}: {} vs {}", ours[0], y[0]);
                    assert!((ours[2] - y[2]).abs() < 1e-8, "{step}: {} vs {}", ours[2], y[2]);
                    // The time to that angle, back from the angle.
                    let back = sw.t0() + sw.time_at_sigma(sw.sigma(y[0]));
                    if step < 10 {
                        assert!((back - t).abs() < 1e-9, "{step}: {back} vs {t}");
                    }
                    let (_, q) = d.resting(&y);
                    assert!((sw.holding_force(y[0]) - q).abs() < 1e-9 * q.abs().max(1.0));
                }
                // The half swing ends at rest at the mirror angle about −β.
                assert!(y[2].abs() < 1e-8, "{}", y[2]);
            }
        }
    }

    /// For r = 0 the lift-off angle is (15): tan θ_r = sin φ_max /
    /// (L_c/L_b − cos φ_max).
    #[test]
    fn liftoff_at_r_zero_is_equation_15() {
        let mut bell = Bell::lab();
        bell.r = 0.0;
        let d = Dynamics::new(&bell);
        let want = crate::liftoff::liftoff_angles(bell.lb() / bell.lc(), bell.phi_max).unwrap();
        let sw = RestingSwing::from_rest(&d, 0.0, 171f64.to_radians(), bell.phi_max).unwrap();
        let sigma = sw.force_zero_after(sw.amplitude()).unwrap();
        let theta = sw.theta(sigma);
        assert!((theta - want.right).abs() < 1e-12, "{} vs {}", theta, want.right);
        assert!(sw.holding_force(theta).abs() < 1e-9);
    }

    #[test]
    fn no_swing_at_the_balance_points() {
        let d = Dynamics::new(&Bell::lab());
        let phi = d.bell().phi_max;
        let sw = RestingSwing::from_rest(&d, 0.0, 1.0, phi).unwrap();
        let beta = sw.sigma(0.0);
        assert!(RestingSwing::from_rest(&d, 0.0, -beta, phi).is_none());
        assert!(RestingSwing::from_rest(&d, 0.0, PI - beta, phi).is_none());
        assert!(RestingSwing::from_rest(&d, f64::NAN, 1.0, phi).is_none());
    }
}
