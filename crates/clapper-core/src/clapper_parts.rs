//! A clapper as a bell-hanger specifies it (docs/model.md §12): a shaft
//! hanging from the crown staple, a ball, and a flight below the ball, each
//! of a material from a table. Its mass m, centre of mass b, inertia I_c
//! about the clapper pivot, and so L_c and T_c, follow from the parts; the
//! inverse finds the flight length (hence mass) or the ball position that
//! gives a wanted T_c.
//!
//! ```
//! use clapper_core::clapper_parts::{ClapperParts, Material};
//! // A uniform wrought-iron bar 1 m long, 40 mm across, and nothing else.
//! let bar = ClapperParts { shaft_length: 1.0, shaft_diameter: 0.04, ..ClapperParts::none() };
//! let c = bar.mass_properties().unwrap();
//! let m = Material::WroughtIron.density() * std::f64::consts::PI * 0.02 * 0.02 * 1.0;
//! assert!((c.mass - m).abs() < 1e-12 * m);
//! assert!((c.b - 0.5).abs() < 1e-15);
//! ```

use std::f64::consts::PI;

use crate::bell::{period_of_length, ParamError};

/// What a clapper part is made of.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case"))]
pub enum Material {
    /// Wrought iron, 7750 kg/m³ (handbook range 7600 to 7900): the
    /// traditional forged clapper, and the default.
    #[default]
    WroughtIron,
    /// Spheroidal-graphite (ductile) cast iron, 7100 kg/m³: the usual cast
    /// clapper since wrought iron became scarce.
    SgIron,
    /// Steel (forged or machined, e.g. EN16), 7850 kg/m³.
    Steel,
    /// Ash, seasoned, 710 kg/m³: the wooden shaft a hanger fits to move a
    /// clapper's mass toward its ball and flight.
    Ash,
}

impl Material {
    /// Density (kg/m³).
    pub fn density(self) -> f64 {
        match self {
            Material::WroughtIron => 7750.0,
            Material::SgIron => 7100.0,
            Material::Steel => 7850.0,
            Material::Ash => 710.0,
        }
    }

    /// The diameter (m) of a ball of this material weighing `mass` (kg).
    pub fn ball_diameter_for_mass(self, mass: f64) -> f64 {
        (6.0 * mass / (PI * self.density())).cbrt()
    }

    /// The diameter (m) of a round bar of this material, `length` (m) long,
    /// weighing `mass` (kg).
    pub fn bar_diameter_for_mass(self, mass: f64, length: f64) -> f64 {
        (4.0 * mass / (PI * self.density() * length)).sqrt()
    }
}

/// A clapper by its parts. Distances are along the clapper from its pivot
/// (the crown staple's pin), downward, in metres; a zero size leaves a part
/// out. The parts do not overlap: the shaft runs from the pivot to the
/// ball's top, the flight from the ball's bottom down.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ClapperParts {
    /// Length of the shaft from the pivot down (m), a round bar.
    pub shaft_length: f64,
    /// Diameter of the shaft (m).
    pub shaft_diameter: f64,
    /// Material of the shaft.
    pub shaft_material: Material,
    /// Diameter of the ball (m), a sphere.
    pub ball_diameter: f64,
    /// Depth of the ball's centre below the pivot (m).
    pub ball_position: f64,
    /// Material of the ball.
    pub ball_material: Material,
    /// Length of the flight below the ball (m), a round bar.
    pub flight_length: f64,
    /// Diameter of the flight (m).
    pub flight_diameter: f64,
    /// Material of the flight.
    pub flight_material: Material,
}

/// One part's contribution.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PartMass {
    /// "shaft", "ball" or "flight".
    pub name: &'static str,
    /// Mass (kg).
    pub mass: f64,
    /// Depth of its centre of mass below the pivot (m).
    pub centre: f64,
    /// Moment of inertia about the pivot (kg m²).
    pub inertia: f64,
}

/// The clapper's mass properties, as the model uses them (docs/model.md §1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClapperMass {
    /// m (kg).
    pub mass: f64,
    /// b, the centre of mass below the pivot (m).
    pub b: f64,
    /// I_c about the pivot (kg m²).
    pub inertia: f64,
}

impl ClapperMass {
    /// L_c = I_c / (m b) (m), the equivalent simple pendulum: where a ball
    /// strikes without jarring the pivot (the centre of percussion).
    pub fn lc(&self) -> f64 {
        self.inertia / (self.mass * self.b)
    }

    /// T_c (s), the small-swing period.
    pub fn tc(&self) -> f64 {
        period_of_length(self.lc())
    }
}

fn nonnegative(field: &'static str, v: f64) -> Result<(), ParamError> {
    if v.is_finite() && v >= 0.0 {
        Ok(())
    } else {
        Err(ParamError {
            field,
            value: v,
            allowed: "a finite number >= 0 (0 leaves the part out)",
        })
    }
}

/// A round bar of length `l` and diameter `d` from depth `top` down.
fn bar(name: &'static str, material: Material, l: f64, d: f64, top: f64) -> PartMass {
    let mass = material.density() * PI * d * d / 4.0 * l;
    let centre = top + l / 2.0;
    // Solid cylinder about a transverse axis through its centre: m (3R² + L²)/12.
    let own = mass * (d * d / 16.0 + l * l / 12.0);
    PartMass {
        name,
        mass,
        centre,
        inertia: own + mass * centre * centre,
    }
}

impl ClapperParts {
    /// No parts at all: a start for `..ClapperParts::none()`.
    pub fn none() -> Self {
        Self {
            shaft_length: 0.0,
            shaft_diameter: 0.0,
            shaft_material: Material::WroughtIron,
            ball_diameter: 0.0,
            ball_position: 0.0,
            ball_material: Material::WroughtIron,
            flight_length: 0.0,
            flight_diameter: 0.0,
            flight_material: Material::WroughtIron,
        }
    }

    /// Plausible parts for the GSM tenor's clapper, all wrought iron: a
    /// 50 mm shaft 0.69 m long, a 140 mm ball with its centre 0.76 m down, a
    /// 200 mm flight of 50 mm. They give m 24.68 kg, b 0.604 m, I_c 10.76
    /// kg m² (Table 1: 24.2 kg, 0.589 m, 11.0 kg m²; within 2.6 %).
    pub fn gsm_tenor() -> Self {
        Self {
            shaft_length: 0.69,
            shaft_diameter: 0.05,
            ball_diameter: 0.14,
            ball_position: 0.76,
            flight_length: 0.2,
            flight_diameter: 0.05,
            ..Self::none()
        }
    }

    /// Whether the ball is there.
    fn has_ball(&self) -> bool {
        self.ball_diameter > 0.0
    }

    /// The ball's top and bottom below the pivot (m); the ball's centre
    /// twice when there is no ball (the flight then starts at `ball_position`).
    fn ball_ends(&self) -> (f64, f64) {
        let r = self.ball_diameter / 2.0;
        (self.ball_position - r, self.ball_position + r)
    }

    /// Each size at most its bound (5 m along the clapper, 1 m across).
    fn within_size_bounds(&self) -> Result<(), ParamError> {
        for (field, v, max, allowed) in [
            (
                "shaft_length_m",
                self.shaft_length,
                MAX_CLAPPER_LENGTH,
                "a clapper's shaft at most 5 m long",
            ),
            (
                "shaft_diameter_m",
                self.shaft_diameter,
                MAX_PART_DIAMETER,
                "a clapper's shaft at most 1 m across",
            ),
            (
                "ball_diameter_m",
                self.ball_diameter,
                MAX_PART_DIAMETER,
                "a clapper's ball at most 1 m across",
            ),
            (
                "ball_position_m",
                self.ball_position,
                MAX_CLAPPER_LENGTH,
                "a clapper's ball within 5 m of its pivot",
            ),
            (
                "flight_length_m",
                self.flight_length,
                MAX_CLAPPER_LENGTH,
                "a clapper's flight at most 5 m long",
            ),
            (
                "flight_diameter_m",
                self.flight_diameter,
                MAX_PART_DIAMETER,
                "a clapper's flight at most 1 m across",
            ),
        ] {
            if v > max {
                return Err(ParamError {
                    field,
                    value: v,
                    allowed,
                });
            }
        }
        Ok(())
    }

    /// Sizes that are numbers ≥ 0, parts that do not overlap, and some mass.
    pub fn validate(&self) -> Result<(), ParamError> {
        for (field, v) in [
            ("shaft_length_m", self.shaft_length),
            ("shaft_diameter_m", self.shaft_diameter),
            ("ball_diameter_m", self.ball_diameter),
            ("ball_position_m", self.ball_position),
            ("flight_length_m", self.flight_length),
            ("flight_diameter_m", self.flight_diameter),
        ] {
            nonnegative(field, v)?;
        }
        self.within_size_bounds()?;
        let (top, bottom) = self.ball_ends();
        let lowest = if self.has_ball() { bottom } else { self.ball_position } + self.flight_length;
        if lowest > MAX_CLAPPER_LENGTH {
            return Err(ParamError {
                field: "flight_length_m",
                value: self.flight_length,
                allowed: "a clapper whose flight ends within 5 m of its pivot",
            });
        }
        if self.has_ball() && top < 0.0 {
            return Err(ParamError {
                field: "ball_position_m",
                value: self.ball_position,
                allowed: "at least the ball's radius (the ball hangs below the pivot)",
            });
        }
        // A little slack so that a shaft given to the ball's top in rounded
        // millimetres is not refused.
        if self.has_ball() && self.shaft_length * self.shaft_diameter > 0.0 && self.shaft_length > top + 1e-9 {
            return Err(ParamError {
                field: "shaft_length_m",
                value: self.shaft_length,
                allowed: "at most the ball's top, ball_position_m - ball_diameter_m / 2 (the shaft ends where the ball begins)",
            });
        }
        if self.parts().iter().map(|p| p.mass).sum::<f64>() <= 0.0 {
            return Err(ParamError {
                field: "shaft_length_m",
                value: self.shaft_length,
                allowed: "a clapper with some mass: give a shaft, a ball or a flight",
            });
        }
        Ok(())
    }

    /// The parts present, each with its mass, centre and inertia about the
    /// pivot (unvalidated).
    pub fn parts(&self) -> Vec<PartMass> {
        let mut out = vec![];
        if self.shaft_length > 0.0 && self.shaft_diameter > 0.0 {
            out.push(bar(
                "shaft",
                self.shaft_material,
                self.shaft_length,
                self.shaft_diameter,
                0.0,
            ));
        }
        if self.has_ball() {
            let d = self.ball_diameter;
            let mass = self.ball_material.density() * PI * d * d * d / 6.0;
            let z = self.ball_position;
            // Solid sphere about a diameter: 2/5 m R² = m d²/10.
            out.push(PartMass {
                name: "ball",
                mass,
                centre: z,
                inertia: mass * (d * d / 10.0 + z * z),
            });
        }
        if self.flight_length > 0.0 && self.flight_diameter > 0.0 {
            let top = if self.has_ball() {
                self.ball_ends().1
            } else {
                self.ball_position
            };
            out.push(bar(
                "flight",
                self.flight_material,
                self.flight_length,
                self.flight_diameter,
                top,
            ));
        }
        out
    }

    /// m, b and I_c of the whole clapper, validated.
    pub fn mass_properties(&self) -> Result<ClapperMass, ParamError> {
        self.validate()?;
        let parts = self.parts();
        let mass: f64 = parts.iter().map(|p| p.mass).sum();
        let moment: f64 = parts.iter().map(|p| p.mass * p.centre).sum();
        let inertia: f64 = parts.iter().map(|p| p.inertia).sum();
        Ok(ClapperMass {
            mass,
            b: moment / mass,
            inertia,
        })
    }

    /// The same clapper with its ball (and the flight hanging from it) moved
    /// `dz` (m) down the clapper, the shaft lengthened to keep meeting it.
    pub fn with_ball_moved(&self, dz: f64) -> Self {
        Self {
            ball_position: self.ball_position + dz,
            shaft_length: if self.shaft_length > 0.0 {
                (self.shaft_length + dz).max(0.0)
            } else {
                0.0
            },
            ..*self
        }
    }

    /// The same clapper with a flight `length` (m) long.
    pub fn with_flight_length(&self, length: f64) -> Self {
        Self {
            flight_length: length,
            ..*self
        }
    }

    /// The same clapper with its shaft made of `material`.
    pub fn with_shaft_material(&self, material: Material) -> Self {
        Self {
            shaft_material: material,
            ..*self
        }
    }
}

/// Which dimension the inverse design changes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case"))]
pub enum Adjust {
    /// The flight's length (and so its mass), its diameter kept.
    FlightLength,
    /// The ball's position (the flight moves with it, the shaft meets it).
    BallPosition,
}

/// The outcome of [`design_for_period`]: a value, never an error, when the
/// wanted period is out of the dimension's reach.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Designed {
    /// The clapper that gives the period, and its mass properties.
    Found(ClapperParts, ClapperMass),
    /// No size within the search range gives it: the shortest and longest
    /// periods the range reaches (s).
    OutOfReach {
        /// Shortest T_c found over the range (s).
        shortest: f64,
        /// Longest T_c found over the range (s).
        longest: f64,
    },
}

/// The longest clapper (m): its lowest point at most this far below its
/// pivot (the largest bells' clappers are about 3 m).
pub const MAX_CLAPPER_LENGTH: f64 = 5.0;
/// The widest part of a clapper (m).
pub const MAX_PART_DIAMETER: f64 = 1.0;

/// The largest flight considered (m): longer than any bell's clapper.
pub const MAX_FLIGHT_LENGTH: f64 = 2.0;
/// The largest ball move considered either way (m).
pub const MAX_BALL_MOVE: f64 = 1.0;

/// Change one dimension of `parts` so that T_c is `target` (s), to 1e-9 s.
/// The range is scanned in 200 steps and the first crossing bisected (60
/// halvings), so the answer nearest the range's start is found and the
/// search always ends. Flight length runs from 0 to [`MAX_FLIGHT_LENGTH`]
/// (the flight's diameter must be set); the ball moves up to
/// [`MAX_BALL_MOVE`] either way, nearest the present position first.
pub fn design_for_period(parts: &ClapperParts, target: f64, adjust: Adjust) -> Result<Designed, ParamError> {
    if !(target.is_finite() && target > 0.0) {
        return Err(ParamError {
            field: "target_period_s",
            value: target,
            allowed: "a finite number > 0",
        });
    }
    if adjust == Adjust::FlightLength && parts.flight_diameter <= 0.0 {
        return Err(ParamError {
            field: "flight_diameter_m",
            value: parts.flight_diameter,
            allowed: "greater than 0 to find the flight's length",
        });
    }
    parts.mass_properties()?;
    let at = |u: f64| -> ClapperParts {
        match adjust {
            Adjust::FlightLength => parts.with_flight_length(u),
            Adjust::BallPosition => parts.with_ball_moved(u),
        }
    };
    // T_c - target at u, or None where the clapper is not a valid one.
    let f = |u: f64| at(u).mass_properties().ok().map(|c| c.tc() - target);
    // The scan: outward from the start (both ways for the ball).
    let steps = 200;
    let paths: Vec<(f64, f64)> = match adjust {
        Adjust::FlightLength => vec![(0.0, MAX_FLIGHT_LENGTH)],
        Adjust::BallPosition => vec![(0.0, MAX_BALL_MOVE), (0.0, -MAX_BALL_MOVE)],
    };
    let (mut shortest, mut longest) = (f64::INFINITY, f64::NEG_INFINITY);
    let mut best: Option<(f64, f64)> = None; // (|u|, u) of the nearest root
    for (from, to) in paths {
        let mut prev: Option<(f64, f64)> = None;
        for k in 0..=steps {
            let u = from + (to - from) * k as f64 / steps as f64;
            let Some(v) = f(u) else {
                prev = None;
                continue;
            };
            shortest = shortest.min(v + target);
            longest = longest.max(v + target);
            if let Some((pu, pv)) = prev {
                if pv == 0.0 || pv.signum() != v.signum() {
                    let root = bisect(&f, pu, pv, u);
                    if best.is_none_or(|(d, _)| root.abs() < d) {
                        best = Some((root.abs(), root));
                    }
                    break;
                }
            }
            prev = Some((u, v));
        }
    }
    Ok(match best {
        Some((_, u)) => {
            let p = at(u);
            Designed::Found(p, p.mass_properties()?)
        }
        None => Designed::OutOfReach { shortest, longest },
    })
}

/// Bisection between `a` (value `fa`) and `b` of opposite sign; 60 halvings.
fn bisect(f: &dyn Fn(f64) -> Option<f64>, mut a: f64, fa: f64, mut b: f64) -> f64 {
    if fa == 0.0 {
        return a;
    }
    let sa = fa.signum();
    for _ in 0..60 {
        let mid = 0.5 * (a + b);
        match f(mid) {
            Some(0.0) => return mid,
            Some(v) if v.signum() == sa => a = mid,
            _ => b = mid,
        }
    }
    0.5 * (a + b)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bell::{Bell, G};
    use approx::assert_relative_eq;

    #[test]
    fn a_uniform_bar_hung_from_its_end_is_the_textbook_pendulum() {
        let (l, d) = (0.9, 0.05);
        let bar = ClapperParts {
            shaft_length: l,
            shaft_diameter: d,
            shaft_material: Material::Steel,
            ..ClapperParts::none()
        };
        let c = bar.mass_properties().unwrap();
        let m = 7850.0 * PI * (d / 2.0).powi(2) * l;
        assert_relative_eq!(c.mass, m, max_relative = 1e-12);
        assert_relative_eq!(c.b, l / 2.0, max_relative = 1e-12);
        // Solid cylinder about an axis through one end, across it: m (L²/3 + R²/4).
        let i = m * (l * l / 3.0 + (d / 2.0).powi(2) / 4.0);
        assert!((c.inertia - i).abs() <= 1e-9 * i);
        let tc = 2.0 * PI * (i / (m * G * l / 2.0)).sqrt();
        assert!((c.tc() - tc).abs() <= 1e-9 * tc);
        // The thin-rod limit: T = 2π √(2L / 3g).
        let thin = ClapperParts {
            shaft_diameter: 1e-6,
            ..bar
        };
        let t_thin = 2.0 * PI * (2.0 * l / (3.0 * G)).sqrt();
        assert!((thin.mass_properties().unwrap().tc() - t_thin).abs() <= 1e-9 * t_thin);
    }

    #[test]
    fn a_ball_alone_is_a_point_mass_plus_its_own_inertia() {
        let (d, h) = (0.12, 0.7);
        let ball = ClapperParts {
            ball_diameter: d,
            ball_position: h,
            ball_material: Material::SgIron,
            ..ClapperParts::none()
        };
        let c = ball.mass_properties().unwrap();
        let m = 7100.0 * 4.0 / 3.0 * PI * (d / 2.0).powi(3);
        assert_relative_eq!(c.mass, m, max_relative = 1e-12);
        assert_relative_eq!(c.b, h, max_relative = 1e-12);
        let i = m * h * h + 0.4 * m * (d / 2.0).powi(2);
        assert!((c.inertia - i).abs() <= 1e-9 * i);
        // A small ball is the simple pendulum: T -> 2π √(h/g).
        let point = ClapperParts {
            ball_diameter: 1e-5,
            ..ball
        };
        let t = 2.0 * PI * (h / G).sqrt();
        assert!((point.mass_properties().unwrap().tc() - t).abs() <= 1e-9 * t);
    }

    #[test]
    fn the_gsm_tenor_clapper_from_plausible_parts() {
        let c = ClapperParts::gsm_tenor().mass_properties().unwrap();
        let t = Bell::gsm_tenor();
        for (got, want) in [(c.mass, t.clapper_mass), (c.inertia, t.clapper_inertia), (c.b, t.b)] {
            assert!((got / want - 1.0).abs() < 0.05, "{got} against {want}");
        }
    }

    #[test]
    fn the_inverse_finds_the_flight_and_the_ball_that_give_a_period() {
        let p = ClapperParts::gsm_tenor();
        for adjust in [Adjust::FlightLength, Adjust::BallPosition] {
            for target in [1.65, 1.762, 1.85] {
                match design_for_period(&p, target, adjust).unwrap() {
                    Designed::Found(q, c) => {
                        assert!((c.tc() - target).abs() < 1e-9, "{adjust:?} {target}: {}", c.tc());
                        assert_relative_eq!(q.mass_properties().unwrap().tc(), c.tc());
                    }
                    other => panic!("{adjust:?} {target}: {other:?}"),
                }
            }
        }
        // Far out of reach: a value saying how far it can go.
        match design_for_period(&p, 0.5, Adjust::FlightLength).unwrap() {
            Designed::OutOfReach { shortest, longest } => assert!(shortest > 0.5 && longest > shortest),
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn bad_parts_are_refused_by_name() {
        let p = ClapperParts::gsm_tenor();
        let e = ClapperParts {
            shaft_length: 0.75,
            ..p
        }
        .validate()
        .unwrap_err();
        assert_eq!(e.field, "shaft_length_m");
        let e = ClapperParts {
            ball_diameter: -0.1,
            ..p
        }
        .validate()
        .unwrap_err();
        assert_eq!(e.field, "ball_diameter_m");
        assert!(ClapperParts::none().validate().is_err());
        assert!(design_for_period(&p, f64::NAN, Adjust::BallPosition).is_err());
    }

    #[test]
    fn an_ash_shaft_lengthens_the_period() {
        // Lighter at the top, the clapper's mass sits lower: L_c grows.
        let iron = ClapperParts::gsm_tenor().mass_properties().unwrap();
        let ash = ClapperParts::gsm_tenor()
            .with_shaft_material(Material::Ash)
            .mass_properties()
            .unwrap();
        assert!(ash.mass < iron.mass && ash.tc() > iron.tc());
    }
}
