//! The tower under a ring (`clapper tower`): its sway in two directions,
//! as a file of its own or as the `[tower]` table of a TOML ring file.
//!
//! ```toml
//! [east_west]
//! frequency_hz = 1.9       # first sway mode, east-west
//! damping_ratio = 0.02     # fraction of critical
//! modal_mass_kg = 150000   # referred to the bell chamber
//! [north_south]
//! frequency_hz = 1.65
//! damping_ratio = 0.02
//! modal_mass_kg = 150000
//! ```

use clapper_tower::Tower;

use crate::bell_file::BellFileError;

/// A tower file's text: its two directions.
pub fn parse_tower(text: &str) -> Result<Tower, BellFileError> {
    let tower: Tower = toml::from_str(text).map_err(|e| BellFileError::Syntax(e.message().replace('\n', " ")))?;
    tower.validate().map_err(|e| BellFileError::Syntax(e.to_string()))?;
    Ok(tower)
}

/// The `[tower]` table of a TOML ring file, if it has one.
pub fn ring_tower(text: &str) -> Result<Option<Tower>, BellFileError> {
    let table: toml::Table = toml::from_str(text).map_err(|e| BellFileError::Syntax(e.message().replace('\n', " ")))?;
    match table.get("tower") {
        None => Ok(None),
        Some(t) => {
            let text = toml::to_string(t).map_err(|e| BellFileError::Syntax(e.to_string()))?;
            parse_tower(&text)
                .map(Some)
                .map_err(|e| BellFileError::Syntax(format!("[tower]: {e}")))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_tower_and_a_ring_with_one() {
        let t = parse_tower(
            "[east_west]\nfrequency_hz = 1.9\ndamping_ratio = 0.02\nmodal_mass_kg = 1.5e5\n\
             [north_south]\nfrequency_hz = 1.65\ndamping_ratio = 0.03\nmodal_mass_kg = 1.2e5\n",
        )
        .unwrap();
        assert_eq!(t.north_south.modal_mass_kg, 1.2e5);
        assert!(parse_tower("[east_west]\nfrequency_hz = 1.9\n").is_err());
        assert!(parse_tower(
            "[east_west]\nfrequency_hz = -1\ndamping_ratio = 0.02\nmodal_mass_kg = 1\n\
             [north_south]\nfrequency_hz = 1\ndamping_ratio = 0.02\nmodal_mass_kg = 1\n"
        )
        .is_err());
        let ring = "[[bell]]\nname = \"a\"\nbell_period_s = 1.3\nclapper_period_s = 1.03\nr_m = 0.1\n\
                    phi_max_deg = 28\nbell_mass_kg = 180\nclapper_mass_kg = 5\nswing = \"E-W\"\n\
                    [tower.east_west]\nfrequency_hz = 1.9\ndamping_ratio = 0.02\nmodal_mass_kg = 1.5e5\n\
                    [tower.north_south]\nfrequency_hz = 1.65\ndamping_ratio = 0.02\nmodal_mass_kg = 1.5e5\n";
        assert_eq!(ring_tower(ring).unwrap().unwrap().east_west.frequency_hz, 1.9);
        let bells = crate::parse_bells(ring, "r").unwrap();
        assert_eq!(bells[0].frame.swing_deg, Some(90.0));
        assert!(crate::parse_bells(&ring.replace("\"E-W\"", "\"up-down\""), "r").is_err());
    }
}
