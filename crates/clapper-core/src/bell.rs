//! A bell and its clapper: mass properties, validation, derived lengths and
//! periods, the two bells of the paper's Table 1, and the two other ways of
//! getting a bell: from a point of the clapping chart (docs/model.md §5) and from
//! tower measurements (docs/model.md §1).

use std::f64::consts::PI;

use crate::hanging::{Hanging, SwingDecay};
pub use crate::param::{readable, ParamError, G};

/// The paper's (and King et al.'s) range of r/L_c: -0.3 to 0.7.
pub const DEFAULT_R_RANGE: [f64; 2] = [-0.3, 0.7];
/// The paper's range of L_b/L_c: 0.5 to 2.5.
pub const DEFAULT_LB_RANGE: [f64; 2] = [0.5, 2.5];

/// The shortest and longest equivalent pendulum, L_b or L_c (m): a bell
/// or clapper outside is not one (a tower bell's are 0.1 to 3 m); inside,
/// every derived length and period is finite.
pub const PENDULUM_LENGTH_RANGE_M: (f64, f64) = (1e-3, 1e3);

/// Something odd about a bell that does not stop it being simulated.
#[derive(Clone, Debug, PartialEq)]
pub enum BellWarning {
    /// `I_c < m b²`: the clapper's radius of gyration about its pivot is
    /// smaller than the distance to its centre of mass, which no real body
    /// has. The paper's chart construction produces such clappers at large
    /// L_b/L_c (and the lab bell's Table 1 values are just inside it), so it
    /// is a warning.
    ClapperInertiaBelowPointMass {
        /// I_c (kg m²).
        inertia: f64,
        /// m b² (kg m²).
        point_mass_inertia: f64,
    },
    /// The same for the bell: `I_b < M a²`.
    BellInertiaBelowPointMass {
        /// I_b (kg m²).
        inertia: f64,
        /// M a² (kg m²).
        point_mass_inertia: f64,
    },
    /// L_b/L_c outside the paper's chart ([`DEFAULT_LB_RANGE`],
    /// 0.5 to 2.5), where no tower bell we know of lies (Table 1's are 1.65
    /// and 1.75): usually a clapper period or length typed wrong (a clapper
    /// period of 5 s beside a bell's 2.3 s gives 0.22).
    OffTheChartLengths {
        /// L_b/L_c (dimensionless).
        lb_over_lc: f64,
        /// T_b, the bell's small-swing period (s).
        tb: f64,
        /// T_c, the clapper's small-swing period (s).
        tc: f64,
    },
    /// r/L_c outside the paper's chart ([`DEFAULT_R_RANGE`],
    /// -0.3 to 0.7): a clapper pivot further from the bell's axis than any
    /// hanging the chart was drawn for (Table 1's are 0.44 and 0.23).
    OffTheChartPivot {
        /// r/L_c (dimensionless).
        r_over_lc: f64,
        /// r (m).
        r: f64,
    },
    /// φ_max outside [`PHI_MAX_PLAUSIBLE_DEG`]: no bell's clapper swings so
    /// little or so far before it meets the bell; below π/2 "degrees" it
    /// reads as an angle given in radians.
    ImplausiblePhiMax {
        /// φ_max (degrees).
        phi_max_deg: f64,
    },
}

/// The clapper pivot's friction taken, over the clapper's gravity torque
/// m g b: a friction far smaller already holds the clapper still.
pub const CLAPPER_FRICTION_OVER_TORQUE: f64 = 1e6;

/// The range of φ_max (degrees) a real bell's clapper has, outside which a
/// bell is warned about: the paper's bells have 26 and 32 deg and the
/// shapes of tower bells give roughly 20 to 40; the band is wider so only
/// a mistake (radians typed as degrees, a wrong angle) meets it.
pub const PHI_MAX_PLAUSIBLE_DEG: (f64, f64) = (10.0, 50.0);

impl std::fmt::Display for BellWarning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::ClapperInertiaBelowPointMass {
                inertia,
                point_mass_inertia,
            } => write!(
                f,
                "clapper inertia I_c = {inertia:.4} kg m^2 is below m b^2 = {point_mass_inertia:.4} kg m^2: \
                 physically impossible, simulated anyway"
            ),
            Self::BellInertiaBelowPointMass {
                inertia,
                point_mass_inertia,
            } => write!(
                f,
                "bell inertia I_b = {inertia:.4} kg m^2 is below M a^2 = {point_mass_inertia:.4} kg m^2: \
                 physically impossible, simulated anyway"
            ),
            Self::OffTheChartLengths { lb_over_lc, tb, tc } => write!(
                f,
                "L_b/L_c = {lb_over_lc:.3} (T_b = {tb:.3} s, T_c = {tc:.3} s) is outside the chart's {:.1} to {:.1}, \
                 where no tower bell lies{}; simulated anyway, but the verdict is not a real bell's",
                DEFAULT_LB_RANGE[0],
                DEFAULT_LB_RANGE[1],
                if tc > tb {
                    " (a clapper slower than its bell): check the clapper's period or length"
                } else if *lb_over_lc > 1.0 {
                    " (a bell far slower than its clapper): check the bell's period or length, then the clapper's"
                } else {
                    ": check the bell's and the clapper's periods or lengths"
                }
            ),
            Self::OffTheChartPivot { r_over_lc, r } => write!(
                f,
                "r/L_c = {r_over_lc:.3} (r = {r:.3} m) is outside the chart's {:.1} to {:.1}, \
                 further than any hanging the chart was drawn for: check r (in metres); \
                 simulated anyway, but the verdict is not a real bell's",
                DEFAULT_R_RANGE[0], DEFAULT_R_RANGE[1],
            ),
            Self::ImplausiblePhiMax { phi_max_deg } => {
                write!(
                    f,
                    "phi_max = {phi_max_deg:.2} deg is outside the {:.0} to {:.0} deg of real clappers",
                    PHI_MAX_PLAUSIBLE_DEG.0, PHI_MAX_PLAUSIBLE_DEG.1
                )?;
                if *phi_max_deg < 90f64.to_radians() {
                    write!(
                        f,
                        "; given in radians? {phi_max_deg} rad is {:.1} deg",
                        phi_max_deg.to_degrees()
                    )?;
                }
                write!(f, "; simulated anyway")
            }
        }
    }
}

/// A bell and clapper by mass properties (SI units, angle in radians).
///
/// Build one with [`Bell::new`], which validates; the fields are public for
/// reading and for struct-update syntax, and every simulation entry point
/// validates again, so a hand-edited bell cannot reach the integrator.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bell {
    /// M: mass of the bell and its fittings (kg).
    pub bell_mass: f64,
    /// m: mass of the clapper (kg).
    pub clapper_mass: f64,
    /// a: bell pivot to bell centre of mass (m).
    pub a: f64,
    /// b: clapper pivot to clapper centre of mass (m).
    pub b: f64,
    /// I_b: bell moment of inertia about its pivot (kg m²).
    pub bell_inertia: f64,
    /// I_c: clapper moment of inertia about its pivot (kg m²).
    pub clapper_inertia: f64,
    /// r: how far the clapper pivot lies below the bell pivot (m); may be
    /// negative (clapper pivot above the bell's axis).
    pub r: f64,
    /// φ_max: clapper angle relative to the bell at contact (rad), in (0, π/2);
    /// the mean of the two sides' when they differ ([`Hanging::phi_max_skew`]).
    pub phi_max: f64,
    /// How the bell departs from the paper's ideal one: pivot offset,
    /// unequal contact angles, friction (docs/model.md §10). Default: ideal.
    pub hanging: Hanging,
}

fn positive(field: &'static str, value: f64) -> Result<(), ParamError> {
    ParamError::positive(field, value).map(|_| ())
}

impl Bell {
    /// A validated bell. `phi_max` is in radians.
    #[allow(clippy::too_many_arguments)] // the eight numbers of Table 1, in its order
    pub fn new(
        bell_mass: f64,
        clapper_mass: f64,
        a: f64,
        b: f64,
        bell_inertia: f64,
        clapper_inertia: f64,
        r: f64,
        phi_max: f64,
    ) -> Result<Self, ParamError> {
        let bell = Self {
            bell_mass,
            clapper_mass,
            a,
            b,
            bell_inertia,
            clapper_inertia,
            r,
            phi_max,
            hanging: Hanging::default(),
        };
        bell.validate()?;
        Ok(bell)
    }

    /// Check every field against docs/model.md §1.
    pub fn validate(&self) -> Result<(), ParamError> {
        positive("bell_mass_kg", self.bell_mass)?;
        positive("clapper_mass_kg", self.clapper_mass)?;
        positive("a_m", self.a)?;
        positive("b_m", self.b)?;
        positive("bell_inertia_kg_m2", self.bell_inertia)?;
        positive("clapper_inertia_kg_m2", self.clapper_inertia)?;
        if !self.r.is_finite() {
            return Err(ParamError {
                field: "r_m",
                value: self.r,
                allowed: "a finite number (may be negative)",
            });
        }
        // Positive masses and lengths can still make no pendulum: b = 1e-320 m
        // gives L_c = inf.
        let (lo, hi) = PENDULUM_LENGTH_RANGE_M;
        for (field, value) in [
            ("L_b = I_b / (M a) (m)", self.lb()),
            ("L_c = I_c / (m b) (m)", self.lc()),
        ] {
            if !(lo..=hi).contains(&value) {
                return Err(ParamError {
                    field,
                    value,
                    allowed: "an equivalent pendulum length from 1e-3 to 1e3 m (check the masses, inertias, a and b)",
                });
            }
        }
        check_phi_max(self.phi_max)?;
        self.hanging.validate()?;
        self.check_hanging_against_the_bell()?;
        let (hand, back) = self.contact_angles();
        for (field, value) in [("phi_max_hand_deg", hand), ("phi_max_back_deg", back)] {
            if !(value > 0.0 && value < PI / 2.0) {
                return Err(ParamError {
                    field,
                    value: value.to_degrees(),
                    allowed: "between 0 and 90 deg, exclusive",
                });
            }
        }
        Ok(())
    }

    /// The hanging's sizes against the bell's own, where a value past them
    /// means no bell that swings (docs/model.md §10): a pivot offset past
    /// a quarter of L_c (a real one is millimetres), a Coulomb torque at
    /// the bell's bearings at least its largest gravity torque M g a (it
    /// would hold the bell at every angle; at the clapper's pivot such a
    /// torque is allowed: it is how a clapper is tied), viscous
    /// damping at least critical (2 sqrt(I M g a): the joint would creep
    /// back without swinging, and the integrator's steps shrink to nothing).
    fn check_hanging_against_the_bell(&self) -> Result<(), ParamError> {
        let h = &self.hanging;
        if h.pivot_offset.abs() > 0.25 * self.lc() {
            return Err(ParamError {
                field: "pivot_offset_m",
                value: h.pivot_offset,
                allowed: "within a quarter of L_c either way (a real bell's is a few millimetres)",
            });
        }
        let f = &h.friction;
        let (bell_torque, clapper_torque) = (self.bell_mass * G * self.a, self.clapper_mass * G * self.b);
        let over = [
            (
                "bell_friction_n_m",
                f.bell_friction,
                bell_torque,
                "below the bell's largest gravity torque M g a (one as large holds the bell at every angle)",
            ),
            (
                "bell_damping_n_m_s",
                f.bell_damping,
                2.0 * (self.bell_inertia * bell_torque).sqrt(),
                "below critical damping 2 sqrt(I_b M g a) (a bell damped more does not swing)",
            ),
            (
                "clapper_damping_n_m_s",
                f.clapper_damping,
                2.0 * (self.clapper_inertia * clapper_torque).sqrt(),
                "below critical damping 2 sqrt(I_c m g b) (a clapper damped more does not swing)",
            ),
            (
                "clapper_friction_n_m",
                f.clapper_friction,
                CLAPPER_FRICTION_OVER_TORQUE * clapper_torque,
                "below a million times the clapper's gravity torque m g b (far less already ties it)",
            ),
        ];
        for (field, value, limit, allowed) in over {
            if value >= limit {
                return Err(ParamError { field, value, allowed });
            }
        }
        Ok(())
    }

    /// The contact angles of the hand side (φ < 0) and the back side
    /// (φ > 0) (rad, both positive); both φ_max for a symmetric bell.
    pub fn contact_angles(&self) -> (f64, f64) {
        crate::hanging::contact_angles(self.phi_max, self.hanging.phi_max_skew)
    }

    /// The same bell hung as `hanging` says.
    pub fn with_hanging(self, hanging: Hanging) -> Self {
        Self { hanging, ..self }
    }

    /// The same bell with another contact angle φ_max (rad), validated.
    pub fn with_phi_max(self, phi_max: f64) -> Result<Self, ParamError> {
        check_phi_max(phi_max)?;
        let bell = Self { phi_max, ..self };
        bell.validate()?;
        Ok(bell)
    }

    /// The laboratory bell of Table 1.
    pub fn lab() -> Self {
        Self {
            bell_mass: 45.8,
            clapper_mass: 1.65,
            a: 0.24,
            b: 0.25,
            bell_inertia: 4.1,
            clapper_inertia: 0.093,
            r: 0.10,
            phi_max: 26f64.to_radians(),
            hanging: Hanging::default(),
        }
    }

    /// The (old) tenor of Great St Mary's, Cambridge, Table 1.
    pub fn gsm_tenor() -> Self {
        Self {
            bell_mass: 1378.0,
            clapper_mass: 24.2,
            a: 0.705,
            b: 0.589,
            bell_inertia: 1311.0,
            clapper_inertia: 11.0,
            r: 0.179,
            phi_max: 32f64.to_radians(),
            hanging: Hanging::default(),
        }
    }

    /// L_b = I_b / (M a), the bell's equivalent simple pendulum length (m), (8).
    pub fn lb(&self) -> f64 {
        self.bell_inertia / (self.bell_mass * self.a)
    }

    /// L_c = I_c / (m b), the clapper's equivalent simple pendulum length (m), (8).
    pub fn lc(&self) -> f64 {
        self.clapper_inertia / (self.clapper_mass * self.b)
    }

    /// T_b = 2π √(L_b/g), the bell's small-swing period (s), (9).
    pub fn tb(&self) -> f64 {
        period_of_length(self.lb())
    }

    /// T_c = 2π √(L_c/g), the clapper's small-swing period (s), (9).
    pub fn tc(&self) -> f64 {
        period_of_length(self.lc())
    }

    /// r / L_c, the chart's horizontal coordinate (dimensionless).
    pub fn r_over_lc(&self) -> f64 {
        self.r / self.lc()
    }

    /// L_b / L_c, the chart's vertical coordinate (dimensionless).
    pub fn lb_over_lc(&self) -> f64 {
        self.lb() / self.lc()
    }

    /// Physically odd but simulable properties (docs/model.md §1).
    pub fn warnings(&self) -> Vec<BellWarning> {
        let mut w = Vec::new();
        let mb2 = self.clapper_mass * self.b * self.b;
        if self.clapper_inertia < mb2 {
            w.push(BellWarning::ClapperInertiaBelowPointMass {
                inertia: self.clapper_inertia,
                point_mass_inertia: mb2,
            });
        }
        let ma2 = self.bell_mass * self.a * self.a;
        if self.bell_inertia < ma2 {
            w.push(BellWarning::BellInertiaBelowPointMass {
                inertia: self.bell_inertia,
                point_mass_inertia: ma2,
            });
        }
        let outside = |v: f64, [lo, hi]: [f64; 2]| !(lo..=hi).contains(&v);
        // A hair beyond the edges: chart points on the edge itself are
        // the chart's own bells.
        let (lb_range, r_range) = (widen(DEFAULT_LB_RANGE), widen(DEFAULT_R_RANGE));
        if outside(self.lb_over_lc(), lb_range) {
            w.push(BellWarning::OffTheChartLengths {
                lb_over_lc: self.lb_over_lc(),
                tb: self.tb(),
                tc: self.tc(),
            });
        }
        if outside(self.r_over_lc(), r_range) {
            w.push(BellWarning::OffTheChartPivot {
                r_over_lc: self.r_over_lc(),
                r: self.r,
            });
        }
        let phi_max_deg = self.phi_max.to_degrees();
        if !(PHI_MAX_PLAUSIBLE_DEG.0..=PHI_MAX_PLAUSIBLE_DEG.1).contains(&phi_max_deg) {
            w.push(BellWarning::ImplausiblePhiMax { phi_max_deg });
        }
        w
    }
}

/// A chart range widened by 1e-9 of its span at each end.
fn widen([lo, hi]: [f64; 2]) -> [f64; 2] {
    let pad = 1e-9 * (hi - lo);
    [lo - pad, hi + pad]
}

fn check_phi_max(phi_max: f64) -> Result<(), ParamError> {
    if phi_max.is_finite() && phi_max > 0.0 && phi_max < PI / 2.0 {
        Ok(())
    } else {
        Err(ParamError {
            field: "phi_max_deg",
            value: phi_max.to_degrees(),
            allowed: "between 0 and 90 deg, exclusive",
        })
    }
}

/// T = 2π √(L/g) (s) for a pendulum length L (m).
pub fn period_of_length(l: f64) -> f64 {
    2.0 * PI * (l / G).sqrt()
}

/// L = g T² / (4π²) (m) for a small-swing period T (s).
pub fn length_of_period(t: f64) -> f64 {
    G * t * t / (4.0 * PI * PI)
}

/// The paper's recipe for a bell at a point of the clapping chart
/// (Section 4.2 and docs/model.md §5). Defaults are the paper's values.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ChartConstruction {
    /// M (kg); default 45.8, the lab bell's.
    pub bell_mass: f64,
    /// m (kg); default 1.65, the lab clapper's.
    pub clapper_mass: f64,
    /// a (m); default 0.24, the lab bell's.
    pub a: f64,
    /// T_b (s); default 1.8 s, between the lab bell and the GSM tenor. Fixes
    /// L_b = g T_b²/(4π²) = 0.805 m (the paper prints 0.85 m, which does not
    /// follow from 1.8 s; docs/model.md §5 takes the period as the input).
    pub tb: f64,
    /// I_c (kg m²); default 0.20.
    pub clapper_inertia: f64,
    /// φ_max (rad); default 26 deg, the lab bell's.
    pub phi_max: f64,
}

/// The contact angle φ_max of every chart bell (deg): the paper's 26 deg,
/// the lab bell's.
pub const CHART_PHI_MAX_DEG: f64 = 26.0;

impl Default for ChartConstruction {
    fn default() -> Self {
        Self {
            bell_mass: 45.8,
            clapper_mass: 1.65,
            a: 0.24,
            tb: 1.8,
            clapper_inertia: 0.20,
            phi_max: CHART_PHI_MAX_DEG.to_radians(),
        }
    }
}

impl ChartConstruction {
    /// The bell at chart point (`r_over_lc`, `lb_over_lc`).
    pub fn bell(&self, r_over_lc: f64, lb_over_lc: f64) -> Result<Bell, ParamError> {
        if !r_over_lc.is_finite() {
            return Err(ParamError {
                field: "r_over_lc",
                value: r_over_lc,
                allowed: "a finite number",
            });
        }
        positive("lb_over_lc", lb_over_lc)?;
        positive("tb_s", self.tb)?;
        let lb = length_of_period(self.tb);
        let lc = lb / lb_over_lc;
        Bell::new(
            self.bell_mass,
            self.clapper_mass,
            self.a,
            self.clapper_inertia / (self.clapper_mass * lc),
            self.bell_mass * self.a * lb,
            self.clapper_inertia,
            r_over_lc * lc,
            self.phi_max,
        )
    }
}

/// A bell as a tower measures it: two small-swing periods, the pivot offset,
/// the contact angle, and optionally what else is known (docs/model.md §1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TowerMeasurements {
    /// Small-swing period of the bell (s).
    pub bell_period: f64,
    /// Small-swing period of the clapper, swinging alone in the hung bell (s).
    pub clapper_period: f64,
    /// r (m).
    pub r: f64,
    /// φ_max (rad).
    pub phi_max: f64,
    /// M (kg), if weighed.
    pub bell_mass: Option<f64>,
    /// m (kg), if weighed.
    pub clapper_mass: Option<f64>,
    /// a (m), if known.
    pub a: Option<f64>,
    /// b (m), if known.
    pub b: Option<f64>,
}

/// Which mass properties a tower-measured bell had to assume.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Assumed {
    /// Field names (as in bell files) with the value assumed, in SI units.
    pub fields: Vec<(&'static str, f64)>,
}

impl TowerMeasurements {
    /// Assumed a/L_b when neither a nor M is given: 0.6, so that
    /// I_b = 0.6 M L_b² is above M a² (a real body). Table 1's bells have
    /// 0.64 (lab) and 0.52 (GSM tenor). It does not move the chart position.
    pub const A_OVER_LB: f64 = 0.6;
    /// Assumed b/L_c when b is not given: 0.9, so that I_c = 0.9 m L_c² is
    /// above m b². It does not move the chart position.
    pub const B_OVER_LC: f64 = 0.9;
    /// κ in a ≈ κ M^(1/3) (m kg^(-1/3)), used for a when M is weighed and a
    /// is not: bells of one family are close to scaled copies, so their
    /// centre of mass sits at a fixed multiple of the cube root of the mass.
    /// Table 1 gives 0.0671 (lab bell) and 0.0633 (GSM tenor); 0.065 is
    /// between them. With no M, M is taken as (0.6 L_b / κ)³, which gives
    /// 41.8 kg for the lab bell (45.8 weighed) and 1935 kg for the GSM
    /// tenor (1378).
    pub const A_PER_CUBE_ROOT_KG: f64 = 0.065;
    /// The range a/L_b is held to when a comes from κ M^(1/3): around the
    /// two bells of Table 1 (0.52, 0.64), and below 1 so that I_b > M a².
    pub const A_OVER_LB_RANGE: (f64, f64) = (0.45, 0.75);
    /// Assumed m/M when the clapper is not weighed: 0.025. Table 1 gives
    /// 3.6 % (lab) and 1.76 % (GSM tenor); bell-hangers' rule of thumb is
    /// 2 to 3 % of the bell.
    pub const CLAPPER_MASS_RATIO: f64 = 0.025;

    /// What a stopwatch, a tape and a protractor give: periods (s), r (m)
    /// and φ_max (rad); nothing weighed.
    pub fn new(bell_period: f64, clapper_period: f64, r: f64, phi_max: f64) -> Self {
        Self {
            bell_period,
            clapper_period,
            r,
            phi_max,
            bell_mass: None,
            clapper_mass: None,
            a: None,
            b: None,
        }
    }

    /// A full bell with the measured periods, r and φ_max. What is not
    /// given is assumed from what is, scaled to this bell (M from L_b, a
    /// from M, m from M; see the constants above): the motion depends on
    /// the masses only through the small mass ratio, forces scale with
    /// them. The assumed values are listed.
    pub fn bell(&self) -> Result<(Bell, Assumed), ParamError> {
        positive("bell_period_s", self.bell_period)?;
        positive("clapper_period_s", self.clapper_period)?;
        let lb = length_of_period(self.bell_period);
        let lc = length_of_period(self.clapper_period);
        let mut assumed = Assumed::default();
        let mut pick = |name: &'static str, given: Option<f64>, default: f64| match given {
            Some(v) => {
                positive(name, v)?;
                Ok(v)
            }
            None => {
                assumed.fields.push((name, default));
                Ok(default)
            }
        };
        let kappa = Self::A_PER_CUBE_ROOT_KG;
        let big_m = pick("bell_mass_kg", self.bell_mass, (Self::A_OVER_LB * lb / kappa).powi(3))?;
        let small_m = pick("clapper_mass_kg", self.clapper_mass, Self::CLAPPER_MASS_RATIO * big_m)?;
        let (lo, hi) = Self::A_OVER_LB_RANGE;
        let a_default = match self.bell_mass {
            Some(_) => (kappa * big_m.cbrt()).clamp(lo * lb, hi * lb),
            None => Self::A_OVER_LB * lb,
        };
        let a = pick("a_m", self.a, a_default)?;
        let b = pick("b_m", self.b, Self::B_OVER_LC * lc)?;
        let bell = Bell::new(
            big_m,
            small_m,
            a,
            b,
            big_m * a * lb,
            small_m * b * lc,
            self.r,
            self.phi_max,
        )?;
        Ok((bell, assumed))
    }
}

/// The bell's own swing-decay timings (here so that the hanging needs no
/// bell, docs/model.md §10.2).
impl SwingDecay {
    /// The bell with its clapper tied to it at φ = 0, the first of King's
    /// two timings.
    pub fn bell_tied(bell: &Bell, swings_to_halve: f64) -> Self {
        let m = bell.clapper_mass;
        let d = bell.hanging.pivot_offset;
        Self {
            swings_to_halve,
            inertia: bell.bell_inertia
                + bell.clapper_inertia
                + m * (bell.r * bell.r + d * d)
                + 2.0 * m * bell.r * bell.b,
            stiffness: (bell.bell_mass * bell.a + m * bell.r + m * bell.b) * G,
        }
    }

    /// The clapper swinging in a still bell, the second.
    pub fn clapper_in_still_bell(bell: &Bell, swings_to_halve: f64) -> Self {
        Self {
            swings_to_halve,
            inertia: bell.clapper_inertia,
            stiffness: bell.clapper_mass * bell.b * G,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_hanging_that_stops_the_bell_swinging_is_refused() {
        let lab = Bell::lab();
        let with = |f: &dyn Fn(&mut Hanging)| {
            let mut h = Hanging::default();
            f(&mut h);
            lab.with_hanging(h).validate()
        };
        // Real sizes pass: 10 mm offset, a little friction and damping.
        assert!(with(&|h| {
            h.pivot_offset = 0.010;
            h.friction.bell_friction = 0.5;
            h.friction.clapper_damping = 0.01;
        })
        .is_ok());
        let field = |r: Result<(), ParamError>| r.unwrap_err().field;
        assert_eq!(field(with(&|h| h.pivot_offset = -1.0)), "pivot_offset_m");
        let mga = lab.bell_mass * G * lab.a;
        assert_eq!(field(with(&|h| h.friction.bell_friction = mga)), "bell_friction_n_m");
        assert!(with(&|h| h.friction.bell_friction = 0.99 * mga).is_ok());
        // A tied clapper: held at every angle by its pivot's friction.
        assert!(with(&|h| h.friction.clapper_friction = 1e5).is_ok());
        assert_eq!(
            field(with(&|h| h.friction.clapper_friction = 1e300)),
            "clapper_friction_n_m"
        );
        assert_eq!(field(with(&|h| h.friction.bell_damping = 1e9)), "bell_damping_n_m_s");
        assert_eq!(
            field(with(&|h| h.friction.clapper_damping = 1e9)),
            "clapper_damping_n_m_s"
        );
    }

    /// Positive but meaningless inputs are refused with the derived
    /// quantity named, and tiny numbers are printed readably.
    #[test]
    fn a_bell_that_is_no_pendulum_is_refused_readably() {
        let bad = Bell {
            b: 1e-320,
            ..Bell::lab()
        };
        let e = bad.validate().unwrap_err();
        assert!(e.field.starts_with("L_c"), "{e}");
        let tiny = Bell {
            bell_mass: 1e-300,
            ..Bell::lab()
        };
        let e = tiny.validate().unwrap_err().to_string();
        assert!(e.contains("L_b") && e.len() < 200, "{e}");
        assert_eq!(readable(1e-300), "1e-300");
        assert_eq!(readable(0.25), "0.25");
        assert_eq!(readable(3e9), "3e9");
        assert!(Bell::lab().validate().is_ok() && Bell::gsm_tenor().validate().is_ok());
    }
    use approx::assert_relative_eq;

    #[test]
    fn table1_lab_derived_values() {
        let b = Bell::lab();
        // Table 1 prints rounded L values; from the inputs (docs/model.md §1):
        assert_relative_eq!(b.lb(), 4.1 / (45.8 * 0.24), max_relative = 1e-12);
        assert!((b.lb() - 0.376).abs() / 0.376 < 0.01);
        assert!((b.lc() - 0.224).abs() / 0.224 < 0.01);
        assert!((b.tb() - 1.23).abs() < 0.01);
        assert!((b.tc() - 0.95).abs() < 0.01);
        assert!((b.r_over_lc() - 0.444).abs() < 0.001, "{}", b.r_over_lc());
        assert!((b.lb_over_lc() - 1.654).abs() < 0.001, "{}", b.lb_over_lc());
        // And to Table 1's printed ratios within 1 %.
        assert!((b.r_over_lc() - 0.45).abs() / 0.45 < 0.015);
        assert!((b.lb_over_lc() - 1.68).abs() / 1.68 < 0.016);
    }

    #[test]
    fn table1_gsm_tenor_derived_values() {
        let b = Bell::gsm_tenor();
        assert!((b.lb() - 1.35).abs() / 1.35 < 0.01);
        assert!((b.lc() - 0.770).abs() / 0.770 < 0.01);
        assert!((b.tb() - 2.33).abs() < 0.01);
        assert!((b.tc() - 1.76).abs() < 0.01);
        assert!((b.r_over_lc() - 0.23).abs() < 0.005);
        assert!((b.lb_over_lc() - 1.75).abs() < 0.005);
        assert!(b.warnings().is_empty());
    }

    /// Bells no tower has are warned about, each with the reason: a
    /// clapper slower than its bell, a pivot far off the chart, radians
    /// typed as degrees; the Table 1 bells and the chart's corners are not.
    #[test]
    fn bells_outside_what_real_bells_are_are_warned_about() {
        let tenor = Bell::gsm_tenor();
        let slow = Bell {
            clapper_inertia: tenor.clapper_inertia * (5.0 / tenor.tc()).powi(2),
            ..tenor
        };
        let w = slow.warnings();
        assert!(matches!(w[..], [BellWarning::OffTheChartLengths { .. }]), "{w:?}");
        assert!(w[0].to_string().contains("a clapper slower than its bell"), "{}", w[0]);
        let far = Bell { r: 1.79, ..tenor };
        assert!(matches!(far.warnings()[..], [BellWarning::OffTheChartPivot { .. }]));
        let radians = tenor.with_phi_max(0.56f64.to_radians()).unwrap();
        let w = radians.warnings();
        assert!(matches!(w[..], [BellWarning::ImplausiblePhiMax { .. }]), "{w:?}");
        assert!(w[0].to_string().contains("0.56 rad is 32.1 deg"), "{}", w[0]);
        for (x, y) in [(-0.3, 0.5), (0.7, 2.5), (-0.3, 2.5), (0.7, 0.5)] {
            let b = ChartConstruction::default().bell(x, y).unwrap();
            assert!(
                !b.warnings().iter().any(|w| matches!(
                    w,
                    BellWarning::OffTheChartLengths { .. } | BellWarning::OffTheChartPivot { .. }
                )),
                "({x}, {y}): {:?}",
                b.warnings()
            );
        }
    }

    #[test]
    fn lab_clapper_is_flagged_as_impossible_but_accepted() {
        let b = Bell::lab();
        assert!(b.validate().is_ok());
        assert!(matches!(
            b.warnings()[..],
            [BellWarning::ClapperInertiaBelowPointMass { .. }]
        ));
    }

    #[test]
    fn validation_names_the_field() {
        let e = Bell {
            clapper_mass: -1.0,
            ..Bell::lab()
        }
        .validate()
        .unwrap_err();
        assert_eq!(e.field, "clapper_mass_kg");
        let e = Bell::lab().with_phi_max(120f64.to_radians()).unwrap_err();
        assert_eq!(e.field, "phi_max_deg");
        assert!((e.value - 120.0).abs() < 1e-9);
        let e = Bell {
            r: f64::NAN,
            ..Bell::lab()
        }
        .validate()
        .unwrap_err();
        assert_eq!(e.field, "r_m");
        assert!(Bell { r: -0.2, ..Bell::lab() }.validate().is_ok());
    }

    #[test]
    fn chart_point_bell_lands_on_its_point() {
        let c = ChartConstruction::default();
        assert!((length_of_period(1.8) - 0.805).abs() < 0.001);
        for &(x, y) in &[(0.458, 0.732), (-0.005, 1.363), (0.0, 2.4), (-0.3, 0.5), (0.7, 2.5)] {
            let b = c.bell(x, y).unwrap();
            assert_relative_eq!(b.r_over_lc(), x, epsilon = 1e-12);
            assert_relative_eq!(b.lb_over_lc(), y, max_relative = 1e-12);
            assert_relative_eq!(b.tb(), 1.8, max_relative = 1e-12);
            assert_relative_eq!(b.clapper_inertia, 0.2);
        }
        assert_eq!(c.bell(0.1, 0.0).unwrap_err().field, "lb_over_lc");
    }

    #[test]
    fn tower_measurements_reproduce_table1_positions() {
        for bell in [Bell::lab(), Bell::gsm_tenor()] {
            let t = TowerMeasurements::new(bell.tb(), bell.tc(), bell.r, bell.phi_max);
            let (tb, assumed) = t.bell().unwrap();
            assert_relative_eq!(tb.r_over_lc(), bell.r_over_lc(), max_relative = 1e-12);
            assert_relative_eq!(tb.lb_over_lc(), bell.lb_over_lc(), max_relative = 1e-12);
            assert_eq!(assumed.fields.len(), 4);
            assert!(tb.warnings().is_empty());
        }
    }

    /// What a tower does not weigh is assumed at this bell's size, not the
    /// lab bell's: the masses of Table 1's two bells, 30 times apart, come
    /// back within a factor 1.5 from their periods alone, and a from the
    /// weighed mass within 5 %.
    #[test]
    fn assumed_masses_are_scaled_to_the_bell() {
        for bell in [Bell::lab(), Bell::gsm_tenor()] {
            let t = TowerMeasurements::new(bell.tb(), bell.tc(), bell.r, bell.phi_max);
            let (guess, _) = t.bell().unwrap();
            let ratio = guess.bell_mass / bell.bell_mass;
            assert!((1.0 / 1.5..1.5).contains(&ratio), "{ratio}");
            assert_relative_eq!(
                guess.clapper_mass / guess.bell_mass,
                TowerMeasurements::CLAPPER_MASS_RATIO
            );
            let weighed = TowerMeasurements {
                bell_mass: Some(bell.bell_mass),
                ..t
            };
            let (b, assumed) = weighed.bell().unwrap();
            assert_eq!(b.bell_mass, bell.bell_mass);
            assert!((b.a / bell.a - 1.0).abs() < 0.05, "a {} for {}", b.a, bell.a);
            assert!(assumed.fields.iter().all(|(k, _)| *k != "bell_mass_kg"));
            assert_relative_eq!(b.lb_over_lc(), bell.lb_over_lc(), max_relative = 1e-12);
        }
    }
}
