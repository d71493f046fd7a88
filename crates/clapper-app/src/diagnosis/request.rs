//! Which bells to diagnose, as the server's request gives them.

use clapper_io::bell_file::LoadedBell;

use crate::AppError;

/// Most bells diagnosed at once: a ring of 64 is beyond any tower.
pub const MAX_BELLS: usize = 64;

/// Which bells to diagnose, given as data (the server's request): a
/// preset, or the text of a bell or ring file.
///
/// ```json
/// {"preset": "lab"}
/// {"toml": "name = \"Tenor\"\nbell_period_s = 2.33\nclapper_period_s = 1.76\nr_m = 0.179\nphi_max_deg = 32\n"}
/// {"csv": "name,bell_period_s,clapper_period_s,r_m,phi_max_deg\nTreble,1.6,1.3,0.08,26\n"}
/// ```
#[derive(Clone, Debug, Default, PartialEq, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DiagnoseRequest {
    /// A bell of Table 1.
    #[serde(default)]
    pub preset: Option<crate::simulate::Preset>,
    /// A bell file, or several bells as `[[bell]]` tables (TOML text).
    #[serde(default)]
    pub toml: Option<String>,
    /// A ring as CSV text: a header of bell-file keys, one bell a row.
    #[serde(default)]
    pub csv: Option<String>,
}

impl DiagnoseRequest {
    /// The bells, and words saying where they came from.
    pub fn bells(&self) -> Result<(Vec<LoadedBell>, String), AppError> {
        match (&self.toml, &self.csv, self.preset) {
            (Some(t), None, None) => Ok((clapper_io::parse_bells(t, "bell")?, "bells entered".into())),
            (None, Some(c), None) => Ok((clapper_io::parse_ring_csv(c)?, "ring file (CSV)".into())),
            (None, None, p) => {
                let p = p.unwrap_or(crate::simulate::Preset::Lab);
                Ok((vec![p.loaded()], format!("preset {}", p.name())))
            }
            _ => Err(AppError::Request("give one of preset, toml or csv".into())),
        }
    }

    /// Each bell of the request as the bell source of a
    /// [`crate::simulate::SimulateRequest`], in the order of [`Self::bells`]:
    /// `{"bell": "...its own bell file..."}` or `{"preset": "lab"}`. A page
    /// that diagnosed a ring simulates one of its bells with these.
    pub fn one_bell_sources(&self) -> Result<Vec<serde_json::Value>, AppError> {
        Ok(match (&self.toml, &self.csv) {
            (Some(t), None) => clapper_io::bell_texts(t, false, "bell")?,
            (None, Some(c)) => clapper_io::bell_texts(c, true, "bell")?,
            _ => {
                let p = self.preset.unwrap_or(crate::simulate::Preset::Lab);
                return Ok(vec![serde_json::json!({ "preset": p.name() })]);
            }
        }
        .into_iter()
        .map(|text| serde_json::json!({ "bell": text }))
        .collect())
    }
}
