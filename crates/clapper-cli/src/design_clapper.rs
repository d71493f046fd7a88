//! `clapper design-clapper`: a clapper from its shaft, ball and flight.

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;
use clapper_app::clapper_design::{design, summary, DesignRequest};
use clapper_core::clapper_parts::{Adjust, Material};
use clapper_io::clapper_input::ClapperInput;

use crate::simulate::choice;

/// The parts, each size in metres along the clapper from its pivot (the
/// crown staple's pin) downward; a part left out (or 0) is not there.
#[derive(Args, Debug)]
pub struct DesignArgs {
    /// Shaft length, from the pivot to the ball's top (m).
    #[arg(long, value_name = "M")]
    pub shaft_length: Option<f64>,
    /// Shaft diameter (m).
    #[arg(long, value_name = "M")]
    pub shaft_diameter: Option<f64>,
    /// Shaft material (ash for a wooden shaft) [default: wrought-iron].
    #[arg(long, value_name = "NAME", value_parser = choice::<Material>())]
    pub shaft_material: Option<Material>,
    /// Ball diameter (m).
    #[arg(long, value_name = "M", conflicts_with = "ball_mass")]
    pub ball_diameter: Option<f64>,
    /// Ball mass (kg), instead of its diameter.
    #[arg(long, value_name = "KG")]
    pub ball_mass: Option<f64>,
    /// Depth of the ball's centre below the pivot (m).
    #[arg(long, value_name = "M")]
    pub ball_position: Option<f64>,
    /// Ball material [default: wrought-iron].
    #[arg(long, value_name = "NAME", value_parser = choice::<Material>())]
    pub ball_material: Option<Material>,
    /// Flight length below the ball (m).
    #[arg(long, value_name = "M")]
    pub flight_length: Option<f64>,
    /// Flight diameter (m).
    #[arg(long, value_name = "M", conflicts_with = "flight_mass")]
    pub flight_diameter: Option<f64>,
    /// Flight mass (kg), instead of its diameter (needs --flight-length).
    #[arg(long, value_name = "KG")]
    pub flight_mass: Option<f64>,
    /// Flight material [default: wrought-iron].
    #[arg(long, value_name = "NAME", value_parser = choice::<Material>())]
    pub flight_material: Option<Material>,
    /// r (m): the clapper pivot (the crown staple's pin) below the bell's
    /// pivot, along the bell's axis (negative above it).
    #[arg(long, value_name = "M", allow_hyphen_values = true)]
    pub pivot: Option<f64>,
    /// The bell's small-swing period T_b (s): places the clapper on the
    /// clapping chart and checks the rule T_c >= 0.9 T_b.
    #[arg(long, value_name = "S")]
    pub bell_period: Option<f64>,
    /// Change the clapper so that its period T_c is this (s).
    #[arg(long, value_name = "S")]
    pub target_period: Option<f64>,
    /// What to change for --target-period.
    #[arg(long, value_name = "PART", value_parser = choice::<Adjust>(), default_value = "flight-length", requires = "target_period")]
    pub adjust: Adjust,
    /// Print the result as one JSON object.
    #[arg(long)]
    pub json: bool,
    /// Write the clapper part of a bell file (the designed clapper when a
    /// target is met) to this TOML file; `-` is standard output.
    #[arg(long, value_name = "FILE.toml")]
    pub out: Option<PathBuf>,
}

impl DesignArgs {
    fn request(&self) -> DesignRequest {
        DesignRequest {
            clapper: ClapperInput {
                shaft_length_m: self.shaft_length,
                shaft_diameter_m: self.shaft_diameter,
                shaft_material: self.shaft_material,
                ball_diameter_m: self.ball_diameter,
                ball_mass_kg: self.ball_mass,
                ball_position_m: self.ball_position,
                ball_material: self.ball_material,
                flight_length_m: self.flight_length,
                flight_diameter_m: self.flight_diameter,
                flight_mass_kg: self.flight_mass,
                flight_material: self.flight_material,
            },
            bell_period_s: self.bell_period,
            pivot_m: self.pivot,
            target_period_s: self.target_period,
            adjust: Some(self.adjust),
        }
    }
}

/// The request's keys, as messages name them, and this command's options
/// for them.
const OPTIONS: [(&str, &str); 14] = [
    ("shaft_length_m", "--shaft-length"),
    ("shaft_diameter_m", "--shaft-diameter"),
    ("shaft_material", "--shaft-material"),
    ("ball_diameter_m", "--ball-diameter"),
    ("ball_mass_kg", "--ball-mass"),
    ("ball_position_m", "--ball-position"),
    ("ball_material", "--ball-material"),
    ("flight_length_m", "--flight-length"),
    ("flight_diameter_m", "--flight-diameter"),
    ("flight_mass_kg", "--flight-mass"),
    ("flight_material", "--flight-material"),
    ("pivot_m", "--pivot"),
    ("bell_period_s", "--bell-period"),
    ("target_period_s", "--target-period"),
];

/// A message about the request put in the words of the command line: each
/// key (`shaft_diameter_m`) as its option (`--shaft-diameter`), `key = v`
/// as `--option v`.
fn in_option_names(message: &str) -> String {
    let mut out = message.to_string();
    for (key, option) in OPTIONS {
        out = out
            .replace(&format!("{key} = "), &format!("{option} "))
            .replace(key, option);
    }
    out
}

/// `clapper design-clapper`.
pub fn run(args: DesignArgs) -> Result<()> {
    crate::files::claim_stdout(&[("--out", args.out.as_deref())], args.json)?;
    let report = design(&args.request()).map_err(|e| anyhow::anyhow!(in_option_names(&e.to_string())))?;
    if let Some(path) = &args.out {
        // The figures of the clapper written: the designed one if found.
        let (m, b, ic, tc) = match report.design.as_ref().and_then(|d| d.clapper.as_ref()) {
            Some(c) => (c.m_kg, c.b_m, c.ic_kg_m2, c.tc_s),
            None => {
                let c = &report.clapper;
                (c.m_kg, c.b_m, c.ic_kg_m2, c.tc_s)
            }
        };
        let text = format!(
            "# A clapper by its parts, from clapper design-clapper; paste into a bell file.\n\
             # It gives m {m:.3} kg, b {b:.4} m, I_c {ic:.4} kg m^2, T_c {tc:.4} s.\n{}",
            report.bell_file_toml
        );
        crate::files::write_bytes(path, text)?;
    }
    if args.json {
        crate::say!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        crate::say_text!("{}", summary(&report));
        if let Some(path) = args.out.as_deref().filter(|p| !crate::files::is_stdout(p)) {
            crate::say!("wrote {}", path.display());
        }
    }
    Ok(())
}
