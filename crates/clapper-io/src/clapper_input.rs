//! A clapper by its parts as files and requests write it (docs/model.md
//! §12): the `[clapper]` table of a bell file, the JSON API's `clapper`
//! object, and what `clapper design-clapper --out` writes.
//!
//! ```toml
//! [clapper]
//! shaft_length_m = 0.69
//! shaft_diameter_m = 0.05
//! ball_diameter_m = 0.14      # or ball_mass_kg
//! ball_position_m = 0.76
//! flight_length_m = 0.2
//! flight_diameter_m = 0.05    # or flight_mass_kg
//! shaft_material = "ash"      # wrought-iron (default), sg-iron, steel, ash
//! ```

use clapper_core::bell::ParamError;
use clapper_core::clapper_parts::{ClapperParts, Material};
use serde::{Deserialize, Serialize};

/// The keys of a `[clapper]` table; sizes in metres, masses in kg. A part
/// whose size is left out (or 0) is not there.
#[derive(Clone, Debug, Default, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ClapperInput {
    /// Shaft length from the pivot to the ball's top (m).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shaft_length_m: Option<f64>,
    /// Shaft diameter (m).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shaft_diameter_m: Option<f64>,
    /// Shaft material [default: wrought-iron].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shaft_material: Option<Material>,
    /// Ball diameter (m).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ball_diameter_m: Option<f64>,
    /// Ball mass (kg), instead of its diameter.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ball_mass_kg: Option<f64>,
    /// Depth of the ball's centre below the pivot (m).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ball_position_m: Option<f64>,
    /// Ball material [default: wrought-iron].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ball_material: Option<Material>,
    /// Flight length below the ball (m).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub flight_length_m: Option<f64>,
    /// Flight diameter (m).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub flight_diameter_m: Option<f64>,
    /// Flight mass (kg), instead of its diameter.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub flight_mass_kg: Option<f64>,
    /// Flight material [default: wrought-iron].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub flight_material: Option<Material>,
}

/// Why a clapper's parts could not be used.
#[derive(Debug, thiserror::Error)]
pub enum ClapperInputError {
    /// Two ways of giving one size.
    #[error("clapper: give {0} or {1}, not both")]
    Both(&'static str, &'static str),
    /// A mass given for a part with no length or position.
    #[error("clapper: {0} needs {1}")]
    Needs(&'static str, &'static str),
    /// No part with any mass: nothing given, or parts given in half (a
    /// shaft's length without its diameter). Says which, and what each
    /// part needs.
    #[error(
        "clapper: no part has any mass{0}: a shaft needs shaft_length_m and shaft_diameter_m, \
         a ball ball_diameter_m (or ball_mass_kg) and ball_position_m, \
         a flight flight_length_m and flight_diameter_m (or flight_mass_kg)"
    )]
    NoMass(String),
    /// A value out of range.
    #[error("clapper: {0}")]
    Param(#[from] ParamError),
}

impl ClapperInput {
    /// The parts, validated; masses turned into diameters by the density.
    pub fn parts(&self) -> Result<ClapperParts, ClapperInputError> {
        let shaft_material = self.shaft_material.unwrap_or_default();
        let ball_material = self.ball_material.unwrap_or_default();
        let flight_material = self.flight_material.unwrap_or_default();
        let ball_diameter = match (self.ball_diameter_m, self.ball_mass_kg) {
            (Some(_), Some(_)) => return Err(ClapperInputError::Both("ball_diameter_m", "ball_mass_kg")),
            (Some(d), None) => d,
            (None, Some(m)) => ball_material.ball_diameter_for_mass(ParamError::positive("ball_mass_kg", m)?),
            (None, None) => 0.0,
        };
        let flight_length = self.flight_length_m.unwrap_or(0.0);
        let flight_diameter = match (self.flight_diameter_m, self.flight_mass_kg) {
            (Some(_), Some(_)) => return Err(ClapperInputError::Both("flight_diameter_m", "flight_mass_kg")),
            (Some(d), None) => d,
            (None, Some(m)) => {
                if flight_length <= 0.0 {
                    return Err(ClapperInputError::Needs("flight_mass_kg", "flight_length_m"));
                }
                flight_material.bar_diameter_for_mass(ParamError::positive("flight_mass_kg", m)?, flight_length)
            }
            (None, None) => 0.0,
        };
        if ball_diameter > 0.0 && self.ball_position_m.is_none() {
            return Err(ClapperInputError::Needs("a ball", "ball_position_m"));
        }
        let parts = ClapperParts {
            shaft_length: self.shaft_length_m.unwrap_or(0.0),
            shaft_diameter: self.shaft_diameter_m.unwrap_or(0.0),
            shaft_material,
            ball_diameter,
            ball_position: self.ball_position_m.unwrap_or(0.0),
            ball_material,
            flight_length,
            flight_diameter,
            flight_material,
        };
        let sizes = [
            parts.shaft_length,
            parts.shaft_diameter,
            parts.ball_diameter,
            parts.ball_position,
            parts.flight_length,
            parts.flight_diameter,
        ];
        // Sizes out of range are validate's to name; a clapper of no mass
        // is named here, where what was given is known.
        if sizes.iter().all(|v| v.is_finite() && *v >= 0.0) && parts.parts().iter().map(|p| p.mass).sum::<f64>() <= 0.0
        {
            return Err(ClapperInputError::NoMass(self.half_given()));
        }
        parts.validate()?;
        Ok(parts)
    }

    /// The parts given in half, as " (shaft_length_m needs
    /// shaft_diameter_m)", or "" when none is.
    fn half_given(&self) -> String {
        let given = |v: Option<f64>| v.is_some_and(|x| x != 0.0);
        let mut half = vec![];
        match (given(self.shaft_length_m), given(self.shaft_diameter_m)) {
            (true, false) => half.push("shaft_length_m needs shaft_diameter_m"),
            (false, true) => half.push("shaft_diameter_m needs shaft_length_m"),
            _ => {}
        }
        if given(self.ball_position_m) && !given(self.ball_diameter_m) && !given(self.ball_mass_kg) {
            half.push("ball_position_m needs ball_diameter_m or ball_mass_kg");
        }
        let flight_thickness = given(self.flight_diameter_m) || given(self.flight_mass_kg);
        match (given(self.flight_length_m), flight_thickness) {
            (true, false) => half.push("flight_length_m needs flight_diameter_m or flight_mass_kg"),
            (false, true) => half.push("flight_diameter_m needs flight_length_m"),
            _ => {}
        }
        if half.is_empty() {
            String::new()
        } else {
            format!(" ({})", half.join("; "))
        }
    }

    /// The table that describes `parts` (diameters, every material named),
    /// sizes rounded to the micrometre so that a file does not carry
    /// arithmetic noise (0.6399999999999999 m); T_c moves by under 1e-6 s.
    pub fn of(parts: &ClapperParts) -> Self {
        let some = |v: f64| (v > 0.0).then_some((v * 1e6).round() / 1e6);
        Self {
            shaft_length_m: some(parts.shaft_length),
            shaft_diameter_m: some(parts.shaft_diameter),
            shaft_material: Some(parts.shaft_material),
            ball_diameter_m: some(parts.ball_diameter),
            ball_mass_kg: None,
            ball_position_m: some(parts.ball_position),
            ball_material: Some(parts.ball_material),
            flight_length_m: some(parts.flight_length),
            flight_diameter_m: some(parts.flight_diameter),
            flight_mass_kg: None,
            flight_material: Some(parts.flight_material),
        }
    }

    /// The `[clapper]` table as TOML text.
    pub fn to_toml(&self) -> String {
        let mut out = String::from("[clapper]\n");
        // A table of plain keys cannot fail to serialize.
        out += &toml::to_string(self).unwrap_or_default();
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn masses_become_diameters_and_the_table_reads_back() {
        let input = ClapperInput {
            shaft_length_m: Some(0.69),
            shaft_diameter_m: Some(0.05),
            ball_mass_kg: Some(11.0),
            ball_position_m: Some(0.76),
            flight_length_m: Some(0.2),
            flight_mass_kg: Some(3.0),
            shaft_material: Some(Material::Ash),
            ..Default::default()
        };
        let p = input.parts().unwrap();
        let c = p.mass_properties().unwrap();
        let parts = p.parts();
        let ball = parts.iter().find(|q| q.name == "ball").unwrap();
        assert!((ball.mass - 11.0).abs() < 1e-9);
        let flight = parts.iter().find(|q| q.name == "flight").unwrap();
        assert!((flight.mass - 3.0).abs() < 1e-9);
        let text = ClapperInput::of(&p).to_toml();
        assert!(text.contains("shaft_material = \"ash\""), "{text}");
        let table: toml::Table = toml::from_str(&text).unwrap();
        let back: ClapperInput = table["clapper"].clone().try_into().unwrap();
        let c2 = back.parts().unwrap().mass_properties().unwrap();
        assert!((c2.tc() - c.tc()).abs() < 1e-6);
    }

    #[test]
    fn two_forms_of_one_size_are_refused() {
        let e = ClapperInput {
            ball_diameter_m: Some(0.1),
            ball_mass_kg: Some(3.0),
            ball_position_m: Some(0.5),
            ..Default::default()
        }
        .parts()
        .unwrap_err();
        assert!(e.to_string().contains("not both"), "{e}");
        let e = ClapperInput {
            ball_diameter_m: Some(0.1),
            ..Default::default()
        }
        .parts()
        .unwrap_err();
        assert!(e.to_string().contains("ball_position_m"), "{e}");
    }

    #[test]
    fn a_clapper_of_no_mass_says_what_each_part_needs() {
        let e = ClapperInput {
            shaft_length_m: Some(0.69),
            ..Default::default()
        }
        .parts()
        .unwrap_err()
        .to_string();
        assert!(
            e.contains("no part has any mass (shaft_length_m needs shaft_diameter_m)"),
            "{e}"
        );
        let e = ClapperInput::default().parts().unwrap_err().to_string();
        assert!(e.contains("no part has any mass: a shaft needs"), "{e}");
    }
}
