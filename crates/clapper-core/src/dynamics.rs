//! Equations of motion (5), (6) in mass-matrix form (docs/model.md §2), the energy
//! (1), (4), and the impulse and contact-force laws that the contact models
//! build on.
//!
//! State `y = [θ, φ, θ', φ']`: bell angle from the downward vertical and
//! clapper angle relative to the bell's axis (rad), and their rates (rad/s).

use crate::bell::{Bell, G};
use crate::ode::taylor::{Coeffs, MAX_ORDER};

/// Index of θ in the state.
pub const THETA: usize = 0;
/// Index of φ in the state.
pub const PHI: usize = 1;
/// Index of θ' in the state.
pub const THETA_DOT: usize = 2;
/// Index of φ' in the state.
pub const PHI_DOT: usize = 3;

/// The state `[θ, φ, θ', φ']` (rad, rad, rad/s, rad/s).
pub type State = [f64; 4];

/// A bell's equations of motion with the constant coefficients computed once.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dynamics {
    /// I_b + I_c + m (r² + d²) (kg m²).
    pub(crate) j0: f64,
    /// m r b (kg m²).
    pub(crate) mrb: f64,
    /// I_c (kg m²).
    pub(crate) ic: f64,
    /// (M a + m r) g (N m).
    pub(crate) gravity_bell: f64,
    /// m b g (N m).
    pub(crate) gravity_clapper: f64,
    /// m b d (kg m²): the pivot offset's share of the coupling.
    mbd: f64,
    /// m g d (N m): the offset pivot's gravity torque on the bell.
    pub(crate) gravity_offset: f64,
    /// d ≠ 0. A bell with its pivot on the axis runs the paper's equations
    /// as written, bit for bit and with no extra work (docs/model.md §10).
    pub(crate) offset: bool,
    /// The two stops' angles φ (rad; + side, − side) and their sin and cos:
    /// a resting clapper sits at exactly one of them, so the resting
    /// equations need no trig of φ (a tenth of a chart's time).
    stops: [(f64, f64, f64); 2],
    bell: Bell,
}

/// Friction's generalised forces over one stretch of motion in which the
/// Coulomb torques keep their signs (docs/model.md §10.2):
/// Q_θ = −c_b θ' + τ_θ on the bell, Q_φ = −c_c φ' + τ_φ on the clapper.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Load {
    /// c_b (N m s/rad).
    pub bell_damping: f64,
    /// τ_θ (N m), signed: against the bell's motion.
    pub bell_torque: f64,
    /// c_c (N m s/rad).
    pub clapper_damping: f64,
    /// τ_φ (N m), signed: against the clapper's motion relative to the bell.
    pub clapper_torque: f64,
}

impl Load {
    /// Q_θ (N m) at `y`.
    #[inline]
    pub fn theta(&self, y: &State) -> f64 {
        self.bell_torque - self.bell_damping * y[THETA_DOT]
    }

    /// The friction part of Q_φ (N m) at `y`.
    #[inline]
    pub fn phi(&self, y: &State) -> f64 {
        self.clapper_torque - self.clapper_damping * y[PHI_DOT]
    }

    /// Power of these forces (W) at `y`: what friction takes from the bell.
    pub fn power(&self, y: &State) -> f64 {
        self.theta(y) * y[THETA_DOT] + self.phi(y) * y[PHI_DOT]
    }

    /// n-th Taylor coefficients of (Q_θ, Q_φ) along a motion with rates
    /// `w` (θ') and `v` (φ').
    #[inline]
    fn series_term(&self, w: &Coeffs, v: &Coeffs, n: usize) -> (f64, f64) {
        let (qt, qp) = if n == 0 {
            (self.bell_torque, self.clapper_torque)
        } else {
            (0.0, 0.0)
        };
        (qt - self.bell_damping * w[n], qp - self.clapper_damping * v[n])
    }
}

/// A linear spring on the clapper: Q_φ = −k (φ − φ_s), the penalty law's
/// contact force (12), (13). Written once, here, for the right-hand side
/// and for the Taylor series.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LinearSpring {
    /// k (N m/rad).
    pub k: f64,
    /// φ_s: where the spring is relaxed (rad).
    pub phi_s: f64,
}

impl LinearSpring {
    /// No spring at all (k = 0): free flight, in the series' terms.
    pub const NONE: LinearSpring = LinearSpring { k: 0.0, phi_s: 0.0 };

    /// A spring of stiffness `k` (N m/rad) relaxed at `phi_s` (rad).
    pub fn new(k: f64, phi_s: f64) -> Self {
        Self { k, phi_s }
    }

    /// Q_φ (N m) at clapper angle `phi` (rad).
    #[inline]
    pub fn force(&self, phi: f64) -> f64 {
        -self.k * (phi - self.phi_s)
    }

    /// The n-th Taylor coefficient of Q_φ along a motion whose φ has
    /// coefficients `phi` (the spring is linear: only φ_s makes the 0th
    /// term differ).
    #[inline]
    fn series_term(&self, phi: &Coeffs, n: usize) -> f64 {
        -self.k * (phi[n] - if n == 0 { self.phi_s } else { 0.0 })
    }
}

/// sin and cos of a state's clapper and bell angles, φ and θ: worked out
/// once where several of the equations' terms are wanted at one state.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Trig {
    /// sin φ, cos φ.
    pub(crate) sp: f64,
    pub(crate) cp: f64,
    /// sin θ, cos θ.
    pub(crate) st: f64,
    pub(crate) ct: f64,
}

impl Trig {
    /// Those of `y`, as [`crate::trig::sin_cos`] gives them.
    #[inline(always)]
    pub(crate) fn of(y: &State) -> Self {
        let (sp, cp) = crate::trig::sin_cos(y[PHI]);
        let (st, ct) = crate::trig::sin_cos(y[THETA]);
        Self { sp, cp, st, ct }
    }
}

/// Accelerations and the mass matrix at one state.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Accel {
    /// θ'' (rad/s²).
    pub theta: f64,
    /// φ'' (rad/s²).
    pub phi: f64,
    /// W₁₁ (kg m²).
    pub w11: f64,
    /// W₁₂ (kg m²).
    pub w12: f64,
    /// det W (kg² m⁴).
    pub det: f64,
}

/// The series a free motion's expansion builds besides the state's own
/// (`series_free`): sin and cos of θ, φ and θ + φ, u = θ + φ, e = 2θ' + φ',
/// the products a = φ' e and c = θ'², and the accelerations θ'', φ''.
/// Held by reference: twelve separate arrays on the caller's stack are
/// zeroed in line, where one struct of them is a call to `memset`.
struct FreeSeries<'a> {
    st: &'a mut Coeffs,
    ct: &'a mut Coeffs,
    sp: &'a mut Coeffs,
    cp: &'a mut Coeffs,
    sa: &'a mut Coeffs,
    ca: &'a mut Coeffs,
    u: &'a mut Coeffs,
    e: &'a mut Coeffs,
    a: &'a mut Coeffs,
    c: &'a mut Coeffs,
    tdd: &'a mut Coeffs,
    pdd: &'a mut Coeffs,
}

/// One order's sums over the earlier terms (k = 1 .. n − 1) of every
/// product in the free motion's recurrences: of the trig series (s_, c_),
/// of a and c, of the coupling's products (sb, sd, s1, s2) and of the
/// offset's, the same with sin and cos of φ swapped (ob, od, o1, o2).
#[derive(Default)]
struct OrderSums {
    s_t: f64,
    c_t: f64,
    s_p: f64,
    c_p: f64,
    s_a: f64,
    c_a: f64,
    aa: f64,
    cc: f64,
    sb: f64,
    sd: f64,
    s1: f64,
    s2: f64,
    ob: f64,
    od: f64,
    o1: f64,
    o2: f64,
}

impl FreeSeries<'_> {
    /// Order 0 from the state `y`, written into `x` as well.
    #[inline(always)]
    fn start(&mut self, y: &State, trig: Option<&Trig>, x: &mut [Coeffs; 4]) {
        x[THETA][0] = y[THETA];
        x[PHI][0] = y[PHI];
        x[THETA_DOT][0] = y[THETA_DOT];
        x[PHI_DOT][0] = y[PHI_DOT];
        let Trig { sp, cp, st, ct } = trig.copied().unwrap_or_else(|| Trig::of(y));
        (self.sp[0], self.cp[0], self.st[0], self.ct[0]) = (sp, cp, st, ct);
        // As in accel: sin and cos of θ + φ from the two pairs.
        self.sa[0] = self.st[0] * self.cp[0] + self.ct[0] * self.sp[0];
        self.ca[0] = self.ct[0] * self.cp[0] - self.st[0] * self.sp[0];
    }

    /// u and e of order `n`, and every sum of order n at once; the terms
    /// at k = 0 and k = n need this order's trig coefficients and come
    /// after.
    #[inline(always)]
    fn order_sums<const OFFSET: bool>(&mut self, x: &[Coeffs; 4], n: usize) -> OrderSums {
        let [th, ph, w, v] = x;
        self.u[n] = th[n] + ph[n];
        self.e[n] = 2.0 * w[n] + v[n];
        let s = &*self;
        let mut o = OrderSums::default();
        for j in 1..n {
            let m = n - j;
            let kf = j as f64;
            let (kt, kp, ku) = (kf * th[j], kf * ph[j], kf * s.u[j]);
            o.s_t += kt * s.ct[m];
            o.c_t += kt * s.st[m];
            o.s_p += kp * s.cp[m];
            o.c_p += kp * s.sp[m];
            o.s_a += ku * s.ca[m];
            o.c_a += ku * s.sa[m];
            o.aa += v[j] * s.e[m];
            o.cc += w[j] * w[m];
            o.sb += s.a[j] * s.sp[m];
            o.sd += s.c[j] * s.sp[m];
            o.s1 += s.cp[j] * s.tdd[m];
            o.s2 += s.cp[j] * s.pdd[m];
            if OFFSET {
                o.ob += s.a[j] * s.cp[m];
                o.od += s.c[j] * s.cp[m];
                o.o1 += s.sp[j] * s.tdd[m];
                o.o2 += s.sp[j] * s.pdd[m];
            }
        }
        o
    }

    /// The trig series' coefficients of order `n` ≥ 1 from the sums.
    #[inline(always)]
    fn trig_order(&mut self, x: &[Coeffs; 4], n: usize, o: &OrderSums) {
        let [th, ph, ..] = x;
        let nf = n as f64;
        let inv = 1.0 / nf;
        self.st[n] = (o.s_t + nf * th[n] * self.ct[0]) * inv;
        self.ct[n] = -(o.c_t + nf * th[n] * self.st[0]) * inv;
        self.sp[n] = (o.s_p + nf * ph[n] * self.cp[0]) * inv;
        self.cp[n] = -(o.c_p + nf * ph[n] * self.sp[0]) * inv;
        self.sa[n] = (o.s_a + nf * self.u[n] * self.ca[0]) * inv;
        self.ca[n] = -(o.c_a + nf * self.u[n] * self.sa[0]) * inv;
    }
}

impl Dynamics {
    /// The equations of motion of `bell` (assumed valid).
    pub fn new(bell: &Bell) -> Self {
        let m = bell.clapper_mass;
        let d = bell.hanging.pivot_offset;
        let offset = d != 0.0;
        let (hand, back) = bell.contact_angles();
        let stop = |phi: f64| {
            let (s, c) = crate::trig::sin_cos(phi);
            (phi, s, c)
        };
        let mut j0 = bell.bell_inertia + bell.clapper_inertia + m * bell.r * bell.r;
        if offset {
            j0 += m * d * d;
        }
        Self {
            j0,
            mrb: m * bell.r * bell.b,
            ic: bell.clapper_inertia,
            gravity_bell: (bell.bell_mass * bell.a + m * bell.r) * G,
            gravity_clapper: m * bell.b * G,
            mbd: m * bell.b * d,
            gravity_offset: m * G * d,
            offset,
            stops: [stop(back), stop(-hand)],
            bell: *bell,
        }
    }

    /// The bell these equations describe.
    pub fn bell(&self) -> &Bell {
        &self.bell
    }

    /// The coupling m b (r cos φ + d sin φ) and its derivative's negative
    /// m b (r sin φ − d cos φ) (kg m²), from sin φ and cos φ.
    #[inline]
    pub(crate) fn coupling(&self, sp: f64, cp: f64) -> (f64, f64) {
        if self.offset {
            (self.mrb * cp + self.mbd * sp, self.mrb * sp - self.mbd * cp)
        } else {
            (self.mrb * cp, self.mrb * sp)
        }
    }

    /// Accelerations with generalised force `q_phi` (N m) on φ, Q_θ = 0.
    #[inline]
    pub fn accel(&self, y: &State, q_phi: f64) -> Accel {
        self.accel_q(y, 0.0, q_phi)
    }

    /// Accelerations with generalised forces `q_theta` on θ and `q_phi` on
    /// φ (N m).
    #[inline]
    pub fn accel_q(&self, y: &State, q_theta: f64, q_phi: f64) -> Accel {
        self.accel_at(y, &Trig::of(y), q_theta, q_phi)
    }

    /// [`accel_q`](Self::accel_q) with the sines and cosines of `y`'s
    /// angles given (bit for bit the same).
    #[inline(always)]
    pub(crate) fn accel_at(&self, y: &State, trig: &Trig, q_theta: f64, q_phi: f64) -> Accel {
        let [_, _, thd, phd] = *y;
        let Trig { sp, cp, st, ct } = *trig;
        // sin(θ + φ) from the two sin_cos calls: one trig call fewer per step
        // stage, and still exactly odd under (θ, φ) → (−θ, −φ).
        let s_abs = st * cp + ct * sp;
        let (w11, w12, f1, f2) = if self.offset {
            let (kc, ks) = self.coupling(sp, cp);
            let f1 = ks * phd * (2.0 * thd + phd)
                - self.gravity_bell * st
                - self.gravity_offset * ct
                - self.gravity_clapper * s_abs;
            let f2 = q_phi - ks * thd * thd - self.gravity_clapper * s_abs;
            (self.j0 + 2.0 * kc, self.ic + kc, f1 + q_theta, f2)
        } else {
            // The paper's (5), (6) as written, term for term.
            let w12 = self.ic + self.mrb * cp;
            let w11 = self.j0 + 2.0 * self.mrb * cp;
            let f1 = self.mrb * phd * (2.0 * thd + phd) * sp - self.gravity_bell * st - self.gravity_clapper * s_abs;
            let f2 = q_phi - self.mrb * thd * thd * sp - self.gravity_clapper * s_abs;
            (w11, w12, f1 + q_theta, f2)
        };
        let det = w11 * self.ic - w12 * w12;
        Accel {
            theta: (self.ic * f1 - w12 * f2) / det,
            phi: (w11 * f2 - w12 * f1) / det,
            w11,
            w12,
            det,
        }
    }

    /// dy/dt in free flight (no contact force).
    #[inline]
    pub fn rhs_free(&self, y: &State) -> State {
        let a = self.accel(y, 0.0);
        [y[2], y[3], a.theta, a.phi]
    }

    /// dy/dt with a generalised contact force `q_phi` (N m) on φ.
    #[inline]
    pub fn rhs_forced(&self, y: &State, q_phi: f64) -> State {
        let a = self.accel(y, q_phi);
        [y[2], y[3], a.theta, a.phi]
    }

    /// dy/dt with forces `q_theta`, `q_phi` (N m).
    #[inline]
    pub fn rhs_q(&self, y: &State, q_theta: f64, q_phi: f64) -> State {
        let a = self.accel_q(y, q_theta, q_phi);
        [y[2], y[3], a.theta, a.phi]
    }

    /// With the clapper held against the bell (φ fixed, φ' = 0): θ'' (rad/s²)
    /// and the generalised contact force Q_φ (N m) that holds it, from (5)
    /// and (6) with φ'' = 0. `y[PHI_DOT]` is taken as zero.
    #[inline]
    pub fn resting(&self, y: &State) -> (f64, f64) {
        self.resting_q(y, 0.0)
    }

    /// [`resting`](Self::resting) with a force `q_theta` (N m) on the bell.
    #[inline]
    pub fn resting_q(&self, y: &State, q_theta: f64) -> (f64, f64) {
        let (sp, cp) = self.sin_cos_phi(y[PHI]);
        let (st, ct) = crate::trig::sin_cos(y[THETA]);
        self.resting_at(y, &Trig { sp, cp, st, ct }, q_theta)
    }

    /// [`resting_q`](Self::resting_q) with the sines and cosines of `y`'s
    /// angles given (bit for bit the same).
    #[inline(always)]
    pub(crate) fn resting_at(&self, y: &State, trig: &Trig, q_theta: f64) -> (f64, f64) {
        let thd = y[THETA_DOT];
        let Trig { sp, cp, st, ct } = *trig;
        let s_abs = st * cp + ct * sp;
        if self.offset {
            let (kc, ks) = self.coupling(sp, cp);
            let f1 = -self.gravity_bell * st - self.gravity_offset * ct - self.gravity_clapper * s_abs + q_theta;
            let theta_dd = f1 / (self.j0 + 2.0 * kc);
            let q = (self.ic + kc) * theta_dd + ks * thd * thd + self.gravity_clapper * s_abs;
            return (theta_dd, q);
        }
        let w11 = self.j0 + 2.0 * self.mrb * cp;
        let w12 = self.ic + self.mrb * cp;
        let f1 = -self.gravity_bell * st - self.gravity_clapper * s_abs + q_theta;
        let theta_dd = f1 / w11;
        let q = w12 * theta_dd + self.mrb * thd * thd * sp + self.gravity_clapper * s_abs;
        (theta_dd, q)
    }

    /// The torque on the bell (N m) that would hold it still at `y` (θ' = 0)
    /// for an instant: with the clapper `resting` (moving with the bell) or
    /// free. What Coulomb friction at the bearings must exceed to hold it.
    pub fn bell_holding_torque(&self, y: &State, resting: bool) -> f64 {
        let y0 = [y[THETA], y[PHI], 0.0, if resting { 0.0 } else { y[PHI_DOT] }];
        if resting {
            // J θ'' = f1 + Q with J = W₁₁ at this φ.
            let (sp, cp) = self.sin_cos_phi(y0[PHI]);
            let (tdd, _) = self.resting(&y0);
            -tdd * (self.j0 + 2.0 * self.coupling(sp, cp).0)
        } else {
            // θ'' = 0 in W a = F + (Q, 0): I_c φ'' = f2, W12 φ'' = f1 + Q.
            let a = self.accel(&y0, 0.0);
            // Q moves θ'' by I_c Q / det: the Q that brings it to zero.
            -a.theta * a.det / self.ic
        }
    }

    /// sin and cos of a clapper angle `ph` (rad): cached at the two stops,
    /// where a resting clapper sits, and bit for bit what `trig::sin_cos`
    /// gives there.
    #[inline]
    pub(crate) fn sin_cos_phi(&self, ph: f64) -> (f64, f64) {
        let [(plus, sp, cp), (minus, sm, cm)] = self.stops;
        if ph == plus {
            (sp, cp)
        } else if ph == minus {
            (sm, cm)
        } else {
            crate::trig::sin_cos(ph)
        }
    }

    /// dy/dt with the clapper resting against the bell.
    #[inline]
    pub fn rhs_resting(&self, y: &State) -> State {
        let (tdd, _) = self.resting(y);
        [y[2], 0.0, tdd, 0.0]
    }

    /// dy/dt with the clapper held against the bell and a force `q_theta`
    /// (N m) on the bell.
    #[inline]
    pub fn rhs_resting_q(&self, y: &State, q_theta: f64) -> State {
        let (tdd, _) = self.resting_q(y, q_theta);
        [y[2], 0.0, tdd, 0.0]
    }

    /// The state just after an impact at `y` with velocity restitution
    /// `e` = √R: the generalised impulse acts on φ only, φ'⁺ = −e φ'⁻ and θ'
    /// jumps by (W⁻¹)₁₂ P (docs/model.md §3). `e = 0` is a perfectly plastic impact.
    pub fn impact(&self, y: &State, e: f64) -> State {
        let a = self.accel(y, 0.0);
        // W^-1 = [[W22, -W12], [-W12, W11]] / det, W22 = I_c.
        let winv12 = -a.w12 / a.det;
        let winv22 = a.w11 / a.det;
        let p = -(1.0 + e) * y[PHI_DOT] / winv22;
        [y[0], y[1], y[2] + winv12 * p, -e * y[PHI_DOT]]
    }

    /// Taylor coefficients to order `p` (≤ [`MAX_ORDER`]) of the solution
    /// through `y` in flight or against a linear spring `spring`
    /// ([`LinearSpring::NONE`] in free flight), with friction `load` if
    /// any. Fills `x[i][0..=p]` in powers of time (rad/s^k, rad/s^(k+1)).
    /// The recurrences are those of [`accel_q`](Self::accel_q), term by
    /// term, and keep its exact symmetry under (θ, φ, d) → (−θ, −φ, −d).
    pub fn series_free(&self, y: &State, spring: &LinearSpring, load: Option<&Load>, p: usize, x: &mut [Coeffs; 4]) {
        self.series_free_at(y, None, spring, load, p, x)
    }

    /// [`series_free`](Self::series_free) with the sines and cosines of
    /// `y`'s angles given, where they are known (bit for bit the same).
    pub(crate) fn series_free_at(
        &self,
        y: &State,
        trig: Option<&Trig>,
        spring: &LinearSpring,
        load: Option<&Load>,
        p: usize,
        x: &mut [Coeffs; 4],
    ) {
        // The offset's extra sums only where there is an offset: the paper's
        // bell pays nothing for it.
        if self.offset {
            self.series_free_impl::<true>(y, trig, spring, load, p, x)
        } else {
            self.series_free_impl::<false>(y, trig, spring, load, p, x)
        }
    }

    #[inline(never)]
    fn series_free_impl<const OFFSET: bool>(
        &self,
        y: &State,
        trig: Option<&Trig>,
        spring: &LinearSpring,
        load: Option<&Load>,
        p: usize,
        x: &mut [Coeffs; 4],
    ) {
        // Order p writes terms up to x[..][p]; the integrator checks its
        // order against MAX_ORDER before it expands.
        debug_assert!(p <= MAX_ORDER);
        const Z: Coeffs = [0.0; MAX_ORDER + 1];
        let (mut st, mut ct, mut sp, mut cp, mut sa, mut ca) = (Z, Z, Z, Z, Z, Z);
        let (mut u, mut e, mut a, mut c, mut tdd, mut pdd) = (Z, Z, Z, Z, Z, Z);
        let mut s = FreeSeries {
            st: &mut st,
            ct: &mut ct,
            sp: &mut sp,
            cp: &mut cp,
            sa: &mut sa,
            ca: &mut ca,
            u: &mut u,
            e: &mut e,
            a: &mut a,
            c: &mut c,
            tdd: &mut tdd,
            pdd: &mut pdd,
        };
        s.start(y, trig, x);
        // W(t) a(t) = F(t) order by order: W_0 a_n = F_n − Σ_{k≥1} W_k a_{n−k},
        // where W_k = m b (r cos φ + d sin φ)_k [[2, 1], [1, 0]] for k ≥ 1.
        let (w11, w12) = if OFFSET {
            let (kc, _) = self.coupling(s.sp[0], s.cp[0]);
            (self.j0 + 2.0 * kc, self.ic + kc)
        } else {
            (self.j0 + 2.0 * self.mrb * s.cp[0], self.ic + self.mrb * s.cp[0])
        };
        let inv_det = 1.0 / (w11 * self.ic - w12 * w12);
        for n in 0..p {
            let sums = s.order_sums::<OFFSET>(x, n);
            if n > 0 {
                s.trig_order(x, n, &sums);
            }
            let (mut f1, mut f2) = self.free_forces::<OFFSET>(&mut s, x, n, &sums, spring);
            if let Some(load) = load {
                let (qt, qp) = load.series_term(&x[THETA_DOT], &x[PHI_DOT], n);
                f1 += qt;
                f2 += qp;
            }
            s.tdd[n] = (self.ic * f1 - w12 * f2) * inv_det;
            s.pdd[n] = (w11 * f2 - w12 * f1) * inv_det;
            let inv = 1.0 / (n + 1) as f64;
            x[THETA][n + 1] = x[THETA_DOT][n] * inv;
            x[PHI][n + 1] = x[PHI_DOT][n] * inv;
            x[THETA_DOT][n + 1] = s.tdd[n] * inv;
            x[PHI_DOT][n + 1] = s.pdd[n] * inv;
        }
    }

    /// The generalised forces (F_1, F_2) of order `n` of the free motion
    /// (N m), without friction: gravity, the coupling's products and the
    /// spring; fills the order's products a and c of `s`.
    #[inline(always)]
    fn free_forces<const OFFSET: bool>(
        &self,
        s: &mut FreeSeries,
        x: &[Coeffs; 4],
        n: usize,
        sums: &OrderSums,
        spring: &LinearSpring,
    ) -> (f64, f64) {
        let [_, ph, w, v] = x;
        let (sp, cp) = (&*s.sp, &*s.cp);
        s.a[n] = if n == 0 {
            v[0] * s.e[0]
        } else {
            sums.aa + v[0] * s.e[n] + v[n] * s.e[0]
        };
        s.c[n] = if n == 0 {
            w[0] * w[0]
        } else {
            sums.cc + 2.0 * w[0] * w[n]
        };
        let (a, c) = (&*s.a, &*s.c);
        let (sb, sd) = if n == 0 {
            (a[0] * sp[0], c[0] * sp[0])
        } else {
            (
                sums.sb + a[0] * sp[n] + a[n] * sp[0],
                sums.sd + c[0] * sp[n] + c[n] * sp[0],
            )
        };
        let q = spring.series_term(ph, n);
        let mut f1 = self.mrb * sb - self.gravity_bell * s.st[n] - self.gravity_clapper * s.sa[n];
        let mut f2 = q - self.mrb * sd - self.gravity_clapper * s.sa[n];
        if n > 0 {
            let s1 = sums.s1 + cp[n] * s.tdd[0];
            let s2 = sums.s2 + cp[n] * s.pdd[0];
            f1 -= self.mrb * (2.0 * s1 + s2);
            f2 -= self.mrb * s1;
        }
        if OFFSET {
            let (ob, od) = if n == 0 {
                (a[0] * cp[0], c[0] * cp[0])
            } else {
                (
                    sums.ob + a[0] * cp[n] + a[n] * cp[0],
                    sums.od + c[0] * cp[n] + c[n] * cp[0],
                )
            };
            f1 -= self.mbd * ob + self.gravity_offset * s.ct[n];
            f2 += self.mbd * od;
            if n > 0 {
                let o1 = sums.o1 + sp[n] * s.tdd[0];
                let o2 = sums.o2 + sp[n] * s.pdd[0];
                f1 -= self.mbd * (2.0 * o1 + o2);
                f2 -= self.mbd * o1;
            }
        }
        (f1, f2)
    }

    /// Taylor coefficients to order `p` of the solution through `y` with
    /// the clapper held against the bell (φ fixed at `y[PHI]`, φ' = 0), and
    /// in `q` those of the force Q_φ (N m) that holds it, as in
    /// [`resting_q`](Self::resting_q), with friction `load` on the bell.
    pub fn series_resting(&self, y: &State, load: Option<&Load>, p: usize, x: &mut [Coeffs; 4], q: &mut Coeffs) {
        const Z: Coeffs = [0.0; MAX_ORDER + 1];
        let (mut st, mut ct, mut sa, mut w2) = (Z, Z, Z, Z);
        let (sp, cp) = self.sin_cos_phi(y[PHI]);
        let (kc, ks) = self.coupling(sp, cp);
        let (w11, w12) = if self.offset {
            (self.j0 + 2.0 * kc, self.ic + kc)
        } else {
            (self.j0 + 2.0 * self.mrb * cp, self.ic + self.mrb * cp)
        };
        x[THETA][0] = y[THETA];
        x[PHI][0] = y[PHI];
        x[THETA_DOT][0] = y[THETA_DOT];
        x[PHI_DOT][0] = 0.0;
        (st[0], ct[0]) = crate::trig::sin_cos(y[THETA]);
        // To order p for the force (an event function), p - 1 for the state's
        // derivatives.
        for n in 0..=p {
            if n > 0 {
                // sin θ, cos θ and θ'² in one pass over the earlier terms.
                let (mut s_t, mut c_t, mut w2n) = (0.0, 0.0, 0.0);
                for j in 1..n {
                    let kt = j as f64 * x[THETA][j];
                    s_t += kt * ct[n - j];
                    c_t += kt * st[n - j];
                    w2n += x[THETA_DOT][j] * x[THETA_DOT][n - j];
                }
                let nf = n as f64;
                st[n] = (s_t + nf * x[THETA][n] * ct[0]) / nf;
                ct[n] = -(c_t + nf * x[THETA][n] * st[0]) / nf;
                w2[n] = w2n + 2.0 * x[THETA_DOT][0] * x[THETA_DOT][n];
            } else {
                w2[0] = x[THETA_DOT][0] * x[THETA_DOT][0];
            }
            sa[n] = st[n] * cp + ct[n] * sp;
            let mut f1 = -self.gravity_bell * st[n] - self.gravity_clapper * sa[n];
            if self.offset {
                f1 -= self.gravity_offset * ct[n];
            }
            if let Some(load) = load {
                f1 += load.series_term(&x[THETA_DOT], &Z, n).0;
            }
            let tdd = f1 / w11;
            q[n] = if self.offset {
                w12 * tdd + ks * w2[n] + self.gravity_clapper * sa[n]
            } else {
                w12 * tdd + self.mrb * w2[n] * sp + self.gravity_clapper * sa[n]
            };
            if n < p {
                let inv = 1.0 / (n + 1) as f64;
                x[THETA][n + 1] = x[THETA_DOT][n] * inv;
                x[PHI][n + 1] = 0.0;
                x[THETA_DOT][n + 1] = tdd * inv;
                x[PHI_DOT][n + 1] = 0.0;
            }
        }
    }

    /// Kinetic energy (4) (J), with the offset's terms.
    pub fn kinetic_energy(&self, y: &State) -> f64 {
        let [_, ph, thd, phd] = *y;
        let b = &self.bell;
        let base = 0.5 * b.bell_inertia * thd * thd
            + 0.5 * b.clapper_inertia * (thd + phd) * (thd + phd)
            + 0.5 * b.clapper_mass * b.r * b.r * thd * thd
            + self.mrb * (thd * thd + thd * phd) * ph.cos();
        if self.offset {
            let d = b.hanging.pivot_offset;
            base + 0.5 * b.clapper_mass * d * d * thd * thd + self.mbd * (thd * thd + thd * phd) * ph.sin()
        } else {
            base
        }
    }

    /// Potential energy (1) (J), zero with the bell at θ = 0 and the
    /// clapper hanging straight down.
    pub fn potential_energy(&self, y: &State) -> f64 {
        let [th, ph, _, _] = *y;
        let v = self.gravity_bell * (1.0 - th.cos()) + self.gravity_clapper * (1.0 - (th + ph).cos());
        if self.offset {
            v + self.gravity_offset * th.sin()
        } else {
            v
        }
    }

    /// Total energy (J).
    pub fn energy(&self, y: &State) -> f64 {
        self.kinetic_energy(y) + self.potential_energy(y)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    /// The mass-matrix rhs must satisfy the paper's (5) and (6) as printed.
    #[test]
    fn accelerations_satisfy_equations_5_and_6() {
        let bell = Bell::lab();
        let d = Dynamics::new(&bell);
        let y = [2.1, -0.3, -1.7, 4.2];
        let q = 12.5;
        let a = d.accel(&y, q);
        let (m, r, b) = (bell.clapper_mass, bell.r, bell.b);
        let (ib, ic, big_m, aa) = (bell.bell_inertia, bell.clapper_inertia, bell.bell_mass, bell.a);
        let [th, ph, thd, phd] = y;
        let e5 = (ib + ic + m * r * r + 2.0 * m * r * b * ph.cos()) * a.theta + (ic + m * r * b * ph.cos()) * a.phi
            - m * r * b * phd * (2.0 * thd + phd) * ph.sin()
            + big_m * G * aa * th.sin()
            + m * G * r * th.sin()
            + m * G * b * (th + ph).sin();
        let e6 = ic * (a.theta + a.phi)
            + m * r * b * a.theta * ph.cos()
            + m * r * b * thd * thd * ph.sin()
            + m * G * b * (th + ph).sin()
            - q;
        assert!(e5.abs() < 1e-10, "{e5}");
        assert!(e6.abs() < 1e-10, "{e6}");
    }

    #[test]
    fn resting_force_holds_the_clapper() {
        let d = Dynamics::new(&Bell::lab());
        let y = [2.5, 0.45, -2.0, 0.0];
        let (tdd, q) = d.resting(&y);
        let a = d.accel(&y, q);
        assert!(a.phi.abs() < 1e-9, "{}", a.phi);
        assert_relative_eq!(a.theta, tdd, max_relative = 1e-12);
    }

    #[test]
    fn elastic_impact_keeps_energy_and_plastic_stops_phi() {
        let d = Dynamics::new(&Bell::gsm_tenor());
        let y = [-0.8, -0.55, -3.0, -6.0];
        let after = d.impact(&y, 1.0);
        assert_relative_eq!(d.kinetic_energy(&after), d.kinetic_energy(&y), max_relative = 1e-12);
        assert_relative_eq!(after[3], 6.0);
        let stuck = d.impact(&y, 0.0);
        assert_eq!(stuck[3], 0.0);
        assert!(d.kinetic_energy(&stuck) < d.kinetic_energy(&y));
    }

    /// The expansions start as the equations do, and the mirror state
    /// (θ, φ) → (−θ, −φ) gives exactly the negated series (the chart's
    /// hand/backstroke symmetry holds bit for bit).
    #[test]
    fn series_start_with_the_equations_and_are_exactly_odd() {
        let d = Dynamics::new(&Bell::lab());
        let y = [2.1, -0.3, -1.7, 4.2];
        let (mut x, mut xm) = ([[0.0; MAX_ORDER + 1]; 4], [[0.0; MAX_ORDER + 1]; 4]);
        d.series_free(&y, &LinearSpring::NONE, None, 12, &mut x);
        let a = d.accel(&y, 0.0);
        assert_relative_eq!(x[THETA_DOT][1], a.theta, max_relative = 1e-12);
        assert_relative_eq!(x[PHI_DOT][1], a.phi, max_relative = 1e-12);
        assert_eq!(x[THETA][1], y[THETA_DOT]);
        // Second order: d(θ'')/dt by a central difference along the flow.
        let h = 1e-5;
        let step = |s: f64| {
            let yy: State = std::array::from_fn(|i| (0..=12).rev().fold(0.0, |v, k| v * s + x[i][k]));
            d.accel(&yy, 0.0).theta
        };
        assert_relative_eq!(
            2.0 * x[THETA_DOT][2],
            (step(h) - step(-h)) / (2.0 * h),
            max_relative = 1e-6
        );
        d.series_free(&y.map(|v| -v), &LinearSpring::NONE, None, 12, &mut xm);
        for i in 0..4 {
            for k in 0..=12 {
                assert_eq!(xm[i][k], -x[i][k], "component {i} order {k}");
            }
        }
        // Resting: the holding force's series starts at the resting force.
        let yr = [2.5, Bell::lab().phi_max, -2.0, 0.0];
        let mut q = [0.0; MAX_ORDER + 1];
        d.series_resting(&yr, None, 10, &mut x, &mut q);
        let (tdd, q0) = d.resting(&yr);
        assert_relative_eq!(q[0], q0, max_relative = 1e-12);
        assert_relative_eq!(x[THETA_DOT][1], tdd, max_relative = 1e-12);
        assert!(x[PHI][1..=10].iter().all(|&v| v == 0.0));
    }
}
