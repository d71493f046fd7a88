//! Equations of motion (5), (6) in mass-matrix form (SPEC §2), the energy
//! (1), (4), and the impulse and contact-force laws that the contact models
//! build on.
//!
//! State `y = [θ, φ, θ', φ']`: bell angle from the downward vertical and
//! clapper angle relative to the bell's axis (rad), and their rates (rad/s).

use crate::bell::{Bell, G};

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
    /// I_b + I_c + m r² (kg m²).
    j0: f64,
    /// m r b (kg m²).
    mrb: f64,
    /// I_c (kg m²).
    ic: f64,
    /// (M a + m r) g (N m).
    gravity_bell: f64,
    /// m b g (N m).
    gravity_clapper: f64,
    /// sin and cos of φ_max: a resting clapper sits at exactly ±φ_max, so
    /// the resting equations need no trig of φ (a tenth of a chart's time).
    sin_phi_max: f64,
    cos_phi_max: f64,
    bell: Bell,
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

impl Dynamics {
    /// The equations of motion of `bell` (assumed valid).
    pub fn new(bell: &Bell) -> Self {
        let m = bell.clapper_mass;
        let (sin_phi_max, cos_phi_max) = crate::trig::sin_cos(bell.phi_max);
        Self {
            j0: bell.bell_inertia + bell.clapper_inertia + m * bell.r * bell.r,
            mrb: m * bell.r * bell.b,
            ic: bell.clapper_inertia,
            gravity_bell: (bell.bell_mass * bell.a + m * bell.r) * G,
            gravity_clapper: m * bell.b * G,
            sin_phi_max,
            cos_phi_max,
            bell: *bell,
        }
    }

    /// The bell these equations describe.
    pub fn bell(&self) -> &Bell {
        &self.bell
    }

    /// Accelerations with generalised force `q_phi` (N m) on φ, Q_θ = 0.
    #[inline]
    pub fn accel(&self, y: &State, q_phi: f64) -> Accel {
        let [th, ph, thd, phd] = *y;
        let (sp, cp) = crate::trig::sin_cos(ph);
        let (st, ct) = crate::trig::sin_cos(th);
        let w12 = self.ic + self.mrb * cp;
        let w11 = self.j0 + 2.0 * self.mrb * cp;
        // sin(θ + φ) from the two sin_cos calls: one trig call fewer per step
        // stage, and still exactly odd under (θ, φ) → (−θ, −φ).
        let s_abs = st * cp + ct * sp;
        let f1 = self.mrb * phd * (2.0 * thd + phd) * sp - self.gravity_bell * st - self.gravity_clapper * s_abs;
        let f2 = q_phi - self.mrb * thd * thd * sp - self.gravity_clapper * s_abs;
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

    /// With the clapper held against the bell (φ fixed, φ' = 0): θ'' (rad/s²)
    /// and the generalised contact force Q_φ (N m) that holds it, from (5)
    /// and (6) with φ'' = 0. `y[PHI_DOT]` is taken as zero.
    #[inline]
    pub fn resting(&self, y: &State) -> (f64, f64) {
        let [th, ph, thd, _] = *y;
        // Bit for bit what sin_cos(ph) gives, as sin_cos is exactly odd.
        let (sp, cp) = if ph == self.bell.phi_max {
            (self.sin_phi_max, self.cos_phi_max)
        } else if ph == -self.bell.phi_max {
            (-self.sin_phi_max, self.cos_phi_max)
        } else {
            crate::trig::sin_cos(ph)
        };
        let (st, ct) = crate::trig::sin_cos(th);
        let w11 = self.j0 + 2.0 * self.mrb * cp;
        let w12 = self.ic + self.mrb * cp;
        let s_abs = st * cp + ct * sp;
        let f1 = -self.gravity_bell * st - self.gravity_clapper * s_abs;
        let theta_dd = f1 / w11;
        let q = w12 * theta_dd + self.mrb * thd * thd * sp + self.gravity_clapper * s_abs;
        (theta_dd, q)
    }

    /// dy/dt with the clapper resting against the bell.
    #[inline]
    pub fn rhs_resting(&self, y: &State) -> State {
        let (tdd, _) = self.resting(y);
        [y[2], 0.0, tdd, 0.0]
    }

    /// The state just after an impact at `y` with velocity restitution
    /// `e` = √R: the generalised impulse acts on φ only, φ'⁺ = −e φ'⁻ and θ'
    /// jumps by (W⁻¹)₁₂ P (SPEC §3). `e = 0` is a perfectly plastic impact.
    pub fn impact(&self, y: &State, e: f64) -> State {
        let a = self.accel(y, 0.0);
        // W^-1 = [[W22, -W12], [-W12, W11]] / det, W22 = I_c.
        let winv12 = -a.w12 / a.det;
        let winv22 = a.w11 / a.det;
        let p = -(1.0 + e) * y[PHI_DOT] / winv22;
        [y[0], y[1], y[2] + winv12 * p, -e * y[PHI_DOT]]
    }

    /// Kinetic energy (4) (J).
    pub fn kinetic_energy(&self, y: &State) -> f64 {
        let [_, ph, thd, phd] = *y;
        let b = &self.bell;
        0.5 * b.bell_inertia * thd * thd
            + 0.5 * b.clapper_inertia * (thd + phd) * (thd + phd)
            + 0.5 * b.clapper_mass * b.r * b.r * thd * thd
            + self.mrb * (thd * thd + thd * phd) * ph.cos()
    }

    /// Potential energy (1) (J), zero with both hanging straight down.
    pub fn potential_energy(&self, y: &State) -> f64 {
        let [th, ph, _, _] = *y;
        self.gravity_bell * (1.0 - th.cos()) + self.gravity_clapper * (1.0 - (th + ph).cos())
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
}
