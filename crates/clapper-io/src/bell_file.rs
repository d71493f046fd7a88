//! Bell files in TOML. Two forms, told apart by their keys:
//!
//! By mass properties (all eight keys):
//! ```toml
//! name = "Lab bell"
//! bell_mass_kg = 45.8
//! clapper_mass_kg = 1.65
//! a_m = 0.24
//! b_m = 0.25
//! bell_inertia_kg_m2 = 4.1
//! clapper_inertia_kg_m2 = 0.093
//! r_m = 0.10
//! phi_max_deg = 26
//! ```
//!
//! By tower measurements (periods, r and φ_max; masses and a, b optional):
//! ```toml
//! name = "Tenor"
//! bell_period_s = 2.33
//! clapper_period_s = 1.76
//! r_m = 0.179
//! phi_max_deg = 32
//! ```
//! Either form may add how the bell departs from the ideal (docs/model.md
//! §10): `pivot_offset_m`, `phi_max_hand_deg` and `phi_max_back_deg` (or the
//! tape's `gap_hand_mm`, `gap_back_mm` with `ball_below_pivot_m`), and
//! friction: `bell_damping_n_m_s`, `bell_friction_n_m`,
//! `clapper_damping_n_m_s`, `clapper_friction_n_m`, or King's timings of a
//! small swing: `bell_swings_to_halve` (clapper tied) and
//! `clapper_swings_to_halve` (bell still), taken as viscous unless
//! `swing_loss = "coulomb"`, which needs `swing_amplitude_deg`.
//!
//! The clapper may be given by its parts instead of its mass properties or
//! period: a `[clapper]` table (see [`crate::clapper_input`]) supplies
//! `clapper_mass_kg`, `b_m` and `clapper_inertia_kg_m2` (mass form) or
//! `clapper_period_s` (tower form), which are then not given.
//!
//! Unknown keys are refused, so a misspelt key cannot silently fall back to
//! a default.

use std::path::Path;

use clapper_core::bell::{Assumed, Bell, ParamError, TowerMeasurements};
use serde::Deserialize;

use crate::clapper_input::ClapperInput;
use crate::hanging_input::HangingInput;
use clapper_core::clapper_parts::ClapperParts;

/// The keys of a bell file, all optional at this stage.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct BellFile {
    name: Option<String>,
    bell_mass_kg: Option<f64>,
    clapper_mass_kg: Option<f64>,
    a_m: Option<f64>,
    b_m: Option<f64>,
    bell_inertia_kg_m2: Option<f64>,
    clapper_inertia_kg_m2: Option<f64>,
    r_m: Option<f64>,
    phi_max_deg: Option<f64>,
    bell_period_s: Option<f64>,
    clapper_period_s: Option<f64>,
    /// Complete oscillations (there and back) of the bell counted ...
    bell_oscillations: Option<f64>,
    /// ... in this many seconds.
    bell_oscillations_time_s: Option<f64>,
    clapper_oscillations: Option<f64>,
    clapper_oscillations_time_s: Option<f64>,
    /// The clapper's measured restitution R (first impact on a side) and
    /// R2 (the bounces after it), e.g. from `clapper restitution`.
    restitution: Option<f64>,
    restitution_later: Option<f64>,
    pivot_offset_m: Option<f64>,
    phi_max_hand_deg: Option<f64>,
    phi_max_back_deg: Option<f64>,
    gap_hand_mm: Option<f64>,
    gap_back_mm: Option<f64>,
    ball_below_pivot_m: Option<f64>,
    bell_damping_n_m_s: Option<f64>,
    bell_friction_n_m: Option<f64>,
    clapper_damping_n_m_s: Option<f64>,
    clapper_friction_n_m: Option<f64>,
    bell_swings_to_halve: Option<f64>,
    clapper_swings_to_halve: Option<f64>,
    swing_loss: Option<clapper_core::hanging::SwingLoss>,
    swing_amplitude_deg: Option<f64>,
    /// The clapper by its parts.
    clapper: Option<ClapperInput>,
    /// The bell's place in its frame (`clapper tower`): its swing by name
    /// ("N-S", "E-W", "NE-SW", "NW-SE") or as an azimuth (deg, clockwise
    /// from north), its pivot's position east and north of the tower's
    /// centre line (m) and its height above the tower's base (m).
    swing: Option<String>,
    swing_deg: Option<f64>,
    frame_x_m: Option<f64>,
    frame_y_m: Option<f64>,
    pivot_height_m: Option<f64>,
}

/// Reads a bell file's keys from `d` and drops them. It lets a caller
/// learn the keys a bell file takes, and the kind of value of each, from
/// serde itself (the Python package names a misspelt key's near ones with
/// it) while the file's struct stays private.
pub fn deserialize_bell_file<'de, D: serde::Deserializer<'de>>(d: D) -> Result<(), D::Error> {
    BellFile::deserialize(d).map(drop)
}

impl BellFile {
    fn hanging(&self) -> HangingInput {
        HangingInput {
            pivot_offset_m: self.pivot_offset_m,
            phi_max_hand_deg: self.phi_max_hand_deg,
            phi_max_back_deg: self.phi_max_back_deg,
            gap_hand_mm: self.gap_hand_mm,
            gap_back_mm: self.gap_back_mm,
            ball_below_pivot_m: self.ball_below_pivot_m,
            bell_damping: self.bell_damping_n_m_s,
            bell_friction: self.bell_friction_n_m,
            clapper_damping: self.clapper_damping_n_m_s,
            clapper_friction: self.clapper_friction_n_m,
            bell_swings_to_halve: self.bell_swings_to_halve,
            clapper_swings_to_halve: self.clapper_swings_to_halve,
            swing_loss: self.swing_loss,
            swing_amplitude_deg: self.swing_amplitude_deg,
        }
    }
}

/// A period from either `period` or `count` oscillations in `time` seconds.
fn period_of(
    which: &'static str,
    period: Option<f64>,
    count: Option<f64>,
    time: Option<f64>,
) -> Result<Option<f64>, BellFileError> {
    match (period, count, time) {
        (Some(p), None, None) => Ok(Some(p)),
        (None, None, None) => Ok(None),
        (None, Some(n), Some(t)) => {
            if !(n.is_finite() && n > 0.0) {
                return Err(ParamError {
                    field: if which == "bell" {
                        "bell_oscillations"
                    } else {
                        "clapper_oscillations"
                    },
                    value: n,
                    allowed: "a count > 0",
                }
                .into());
            }
            Ok(Some(t / n))
        }
        (Some(_), _, _) => Err(BellFileError::Mixed(format!(
            "{which}_period_s and {which}_oscillations: give one"
        ))),
        _ => Err(BellFileError::Missing(format!(
            "{which}_oscillations and {which}_oscillations_time_s go together"
        ))),
    }
}

/// How a bell file described its bell.
#[derive(Clone, Debug, PartialEq)]
pub enum BellSource {
    /// All mass properties given.
    MassProperties,
    /// Tower measurements; the listed properties were assumed.
    Tower(Assumed),
}

/// A bell read from a file.
#[derive(Clone, Debug, PartialEq)]
pub struct LoadedBell {
    /// The file's `name`, or the file stem.
    pub name: String,
    /// The bell (validated).
    pub bell: Bell,
    /// Which form the file used.
    pub source: BellSource,
    /// R of this bell's clapper, if the file gives it (0 < R ≤ 1): used
    /// unless a request sets its own.
    pub restitution: Option<f64>,
    /// R2 likewise.
    pub restitution_later: Option<f64>,
    /// The ball's centre below the clapper pivot (m), if the file gives it
    /// (with the tape's gaps): where a diagnosis proposes moving the ball.
    pub ball_below_pivot_m: Option<f64>,
    /// The clapper's parts, if the file gave them: where a diagnosis
    /// proposes changes to the flight, the ball or the shaft.
    pub clapper_parts: Option<ClapperParts>,
    /// Its place in the frame, where the file gives it.
    pub frame: FrameInput,
}

/// A bell's place in its frame as a ring file gives it (`clapper tower`);
/// every key optional (the command says what it assumes).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FrameInput {
    /// Azimuth of the swing (deg, clockwise from north, towards positive θ).
    pub swing_deg: Option<f64>,
    /// Pivot east of the tower's centre line (m).
    pub x_m: Option<f64>,
    /// Pivot north of the tower's centre line (m).
    pub y_m: Option<f64>,
    /// Pivot's height above the tower's base (m).
    pub pivot_height_m: Option<f64>,
}

/// A swing direction by name: N-S 0 deg, NE-SW 45, E-W 90, NW-SE 135.
fn swing_by_name(name: &str) -> Result<f64, BellFileError> {
    let key: String = name
        .chars()
        .filter(|c| c.is_ascii_alphabetic())
        .collect::<String>()
        .to_ascii_uppercase();
    match key.as_str() {
        "NS" | "SN" => Ok(0.0),
        "NESW" | "SWNE" => Ok(45.0),
        "EW" | "WE" => Ok(90.0),
        "NWSE" | "SENW" => Ok(135.0),
        _ => Err(BellFileError::Syntax(format!(
            "swing = '{name}': N-S, E-W, NE-SW or NW-SE (or swing_deg, an azimuth in degrees)"
        ))),
    }
}

impl BellFile {
    fn frame(&self) -> Result<FrameInput, BellFileError> {
        let swing_deg = match (&self.swing, self.swing_deg) {
            (Some(_), Some(_)) => return Err(BellFileError::Mixed("swing and swing_deg: give one".into())),
            (Some(name), None) => Some(swing_by_name(name)?),
            (None, d) => d,
        };
        for (field, v) in [
            ("swing_deg", swing_deg),
            ("frame_x_m", self.frame_x_m),
            ("frame_y_m", self.frame_y_m),
            ("pivot_height_m", self.pivot_height_m),
        ] {
            if let Some(v) = v.filter(|v| !v.is_finite()) {
                return Err(ParamError {
                    field,
                    value: v,
                    allowed: "a finite number",
                }
                .into());
            }
        }
        Ok(FrameInput {
            swing_deg,
            x_m: self.frame_x_m,
            y_m: self.frame_y_m,
            pivot_height_m: self.pivot_height_m,
        })
    }
}

impl LoadedBell {
    /// A bell with no restitution of its own.
    pub fn new(name: String, bell: Bell, source: BellSource) -> Self {
        Self {
            name,
            bell,
            source,
            restitution: None,
            restitution_later: None,
            ball_below_pivot_m: None,
            clapper_parts: None,
            frame: FrameInput::default(),
        }
    }
}

/// Why a bell file could not be used. Every message is one line.
#[derive(Debug, thiserror::Error)]
pub enum BellFileError {
    /// The file could not be read.
    #[error("cannot read bell file {path}: {reason}")]
    Read {
        /// The path.
        path: String,
        /// The I/O error (in the message, so not also a source: the
        /// command line would say it twice).
        reason: std::io::Error,
    },
    /// Not text at all: a recording or an image given as a bell file.
    #[error("{0}")]
    NotText(crate::text_file::NotText),
    /// Not valid TOML, an unknown key, or a value of the wrong type.
    #[error("{0}")]
    Syntax(String),
    /// Keys of the mass form are missing.
    #[error("bell file is missing {0} (give all mass properties, or bell_period_s and clapper_period_s)")]
    Missing(String),
    /// Keys of the two forms are mixed.
    #[error("bell file mixes forms: {0} cannot be combined with bell_period_s / clapper_period_s")]
    Mixed(String),
    /// A value is out of range (its message in this one's, not a source).
    #[error("bell file: {0}")]
    Param(ParamError),
    /// The clapper given both by its parts and by these keys.
    #[error("bell file gives the clapper twice: the [clapper] table stands for {0}; leave those out")]
    ClapperTwice(String),
    /// The `[clapper]` table cannot be used.
    #[error("bell file: {0}")]
    Clapper(crate::clapper_input::ClapperInputError),
}

// By hand, not `#[from]`: that would make the inner error a source too,
// and error chains (anyhow's `{:#}`) would print its message twice.
impl From<ParamError> for BellFileError {
    fn from(e: ParamError) -> Self {
        Self::Param(e)
    }
}

impl From<crate::clapper_input::ClapperInputError> for BellFileError {
    fn from(e: crate::clapper_input::ClapperInputError) -> Self {
        Self::Clapper(e)
    }
}

/// The file's text and stem (the default name of an unnamed bell).
/// `wanted` is what the file should be ("a bell file"), for the message
/// when it is not text.
fn read_text(path: &Path, wanted: &'static str) -> Result<(String, String), BellFileError> {
    use crate::text_file::{read_text, ReadTextError};
    let text = read_text(path, wanted).map_err(|e| match e {
        ReadTextError::Io(reason) => BellFileError::Read {
            path: path.display().to_string(),
            reason,
        },
        ReadTextError::NotText(e) => BellFileError::NotText(e),
    })?;
    let stem = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    Ok((text, stem))
}

/// Put the path in front of a syntax error, so the one line says which file.
fn in_file<T>(path: &Path, r: Result<T, BellFileError>) -> Result<T, BellFileError> {
    r.map_err(|e| match e {
        BellFileError::Syntax(m) => BellFileError::Syntax(format!("{}: {m}", path.display())),
        other => other,
    })
}

/// Read and validate a bell file.
pub fn load_bell(path: &Path) -> Result<LoadedBell, BellFileError> {
    let (text, stem) = read_text(path, "a bell file")?;
    in_file(path, parse_bell(&text, &stem))
}

/// Read a file of one bell, or of several as `[[bell]]` tables (each with
/// the keys of a one-bell file), or a ring as CSV (by the `.csv` extension).
pub fn load_bells(path: &Path) -> Result<Vec<LoadedBell>, BellFileError> {
    let (text, stem) = read_text(path, "a bell or ring file")?;
    let is_csv = path.extension().is_some_and(|e| e.eq_ignore_ascii_case("csv"));
    in_file(
        path,
        if is_csv {
            parse_ring_csv(&text)
        } else {
            parse_bells(&text, &stem)
        },
    )
}

/// Parse a ring from CSV: a header row of bell-file keys (`name` first is
/// usual; any form, empty cells for keys a row does not use), one bell a row.
/// A cell that cannot be read is named by its row, line, column and value.
pub fn parse_ring_csv(text: &str) -> Result<Vec<LoadedBell>, BellFileError> {
    let mut rdr = csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .from_reader(text.as_bytes());
    let header = rdr
        .headers()
        .map_err(|e| BellFileError::Syntax(csv_error(&e, None)))?
        .clone();
    let mut out = vec![];
    for (k, row) in rdr.records().enumerate() {
        let row = row.map_err(|e| BellFileError::Syntax(csv_error(&e, Some(k + 1))))?;
        // The header is line 1; a quoted cell may span lines, so ask.
        let line = row.position().map_or(k as u64 + 2, csv::Position::line);
        let at = format!("row {} (line {line})", k + 1);
        let f: BellFile = row
            .deserialize(Some(&header))
            .map_err(|e| BellFileError::Syntax(csv_cell_error(&e, &header, &row, &at)))?;
        out.push(bell_from_fields(f, &format!("bell {}", k + 1)).map_err(|e| match e {
            BellFileError::Syntax(m) => BellFileError::Syntax(format!("{at}: {m}")),
            BellFileError::Param(p) => BellFileError::Syntax(format!("{at}: {p}")),
            // Said of the row, in a CSV's words: an empty cell, most often.
            BellFileError::Missing(m) => {
                BellFileError::Syntax(format!("{at}: no {m} (an empty cell? every row needs a value for it)"))
            }
            BellFileError::Mixed(m) => BellFileError::Syntax(format!(
                "{at}: {m} cannot be combined with bell_period_s / clapper_period_s in one row"
            )),
            other => other,
        })?);
    }
    if out.is_empty() {
        return Err(BellFileError::Missing("every bell: the ring file has no rows".into()));
    }
    Ok(out)
}

/// A CSV reader's error as one line that says where (`row`, counting
/// from 1 after the header, and the line): a row with more cells than the
/// header is most often a decimal comma that split a number.
fn csv_error(e: &csv::Error, row: Option<usize>) -> String {
    let line = e.position().map(csv::Position::line);
    let at = match (row, line) {
        (Some(r), Some(l)) => format!("row {r} (line {l}): "),
        (Some(r), None) => format!("row {r}: "),
        (None, Some(l)) => format!("line {l}: "),
        (None, None) => String::new(),
    };
    match e.kind() {
        csv::ErrorKind::UnequalLengths { expected_len, len, .. } => {
            let hint = if len > expected_len {
                " (a decimal comma splits a number in two: write 0.05, not 0,05)"
            } else {
                ""
            };
            format!("{at}{len} cells where the header has {expected_len}{hint}")
        }
        _ => format!("{at}{}", cut(&e.to_string().replace('\n', " "))),
    }
}

/// A cell of a ring CSV that does not read as its column's key wants:
/// where (`at`: its row and line), the column's header and the value.
fn csv_cell_error(e: &csv::Error, header: &csv::StringRecord, row: &csv::StringRecord, at: &str) -> String {
    let csv::ErrorKind::Deserialize { err, .. } = e.kind() else {
        return format!("{at}: {}", cut(&e.to_string().replace('\n', " ")));
    };
    let Some(i) = err.field().and_then(|i| usize::try_from(i).ok()) else {
        // Not one cell's fault: an unknown column is the header's (line 1).
        let words = cut(&err.kind().to_string().replace('\n', " "));
        if words.starts_with("unknown field") {
            return format!(
                "line 1 (the header): {}",
                words.replacen("unknown field", "unknown column", 1)
            );
        }
        return format!("{at}: {words}");
    };
    // Escaped: a quoted cell may hold a line break, and the message is one line.
    let column = cut(&header.get(i).unwrap_or("?").escape_debug().to_string());
    let value = cut(&row.get(i).unwrap_or("").escape_debug().to_string());
    match err.kind() {
        csv::DeserializeErrorKind::ParseFloat(_) => {
            let hint = decimal_comma(&value).map_or(String::new(), |w| format!(" ({w})"));
            format!("{at}, column {column}: '{value}' is not a number{hint}")
        }
        other => format!("{at}, column {column}: '{value}': {}", cut(&other.to_string())),
    }
}

/// Advice for a number written with a decimal comma (`0,05`): write it
/// with a point. `None` when `value` is not such a number.
fn decimal_comma(value: &str) -> Option<String> {
    let v = value.trim();
    let (int, frac) = v.split_once(',')?;
    let digits = |s: &str| !s.is_empty() && s.bytes().all(|c| c.is_ascii_digit());
    if !(digits(int.trim_start_matches(['+', '-'])) && digits(frac)) {
        return None;
    }
    let point = format!("{int}.{frac}");
    // 1,000 is as likely a thousand as a decimal comma.
    Some(
        if frac.len() == 3 && !int.trim_start_matches(['+', '-', '0']).is_empty() {
            format!("a thousands separator or a decimal comma? write {int}{frac} or {point}")
        } else {
            format!("decimal comma? write {point}")
        },
    )
}

/// Parse one bell, or several as `[[bell]]` tables.
pub fn parse_bells(text: &str, default_name: &str) -> Result<Vec<LoadedBell>, BellFileError> {
    let table: toml::Table = toml::from_str(text).map_err(|e| BellFileError::Syntax(one_line(text, &e)))?;
    match table.get("bell") {
        Some(toml::Value::Array(list)) => {
            // A ring may carry its tower's sway (`clapper tower`).
            if table.keys().any(|k| k != "bell" && k != "tower") {
                return Err(BellFileError::Syntax(
                    "a file of several bells holds only [[bell]] tables (and a [tower] table)".into(),
                ));
            }
            list.iter()
                .enumerate()
                .map(|(k, v)| {
                    let one = toml::to_string(v).map_err(|e| BellFileError::Syntax(e.to_string()))?;
                    parse_bell(&one, &format!("{default_name} {}", k + 1)).map_err(|e| match e {
                        BellFileError::Syntax(m) => BellFileError::Syntax(format!("bell {}: {m}", k + 1)),
                        other => other,
                    })
                })
                .collect()
        }
        _ => Ok(vec![parse_bell(text, default_name)?]),
    }
}

/// Each bell of a ring as a bell file of its own (TOML text), in the
/// ring's order: the `[[bell]]` tables of a TOML ring or the rows of a CSV
/// one (`csv`), or the one bell of a bell file. A bell without a `name`
/// gets the one [`parse_bells`] / [`parse_ring_csv`] would give it, so
/// that [`parse_bell`] of the k-th text is the k-th bell of the ring. A
/// page uses these to simulate one bell of a ring it diagnosed.
pub fn bell_texts(text: &str, csv: bool, default_name: &str) -> Result<Vec<String>, BellFileError> {
    let named = |mut t: toml::Table, name: String| {
        t.entry("name").or_insert(toml::Value::String(name));
        toml::to_string(&t).map_err(|e| BellFileError::Syntax(e.to_string()))
    };
    if csv {
        let mut rdr = csv::ReaderBuilder::new()
            .trim(csv::Trim::All)
            .from_reader(text.as_bytes());
        let header = rdr.headers().map_err(|e| BellFileError::Syntax(e.to_string()))?.clone();
        let mut out = vec![];
        for (k, row) in rdr.records().enumerate() {
            let row = row.map_err(|e| BellFileError::Syntax(format!("row {}: {e}", k + 1)))?;
            let mut t = toml::Table::new();
            for (key, cell) in header.iter().zip(row.iter()).filter(|(_, c)| !c.is_empty()) {
                // A number where it reads as one, except the name.
                let v = match cell.parse::<f64>() {
                    Ok(x) if key != "name" => toml::Value::Float(x),
                    _ => toml::Value::String(cell.to_string()),
                };
                t.insert(key.to_string(), v);
            }
            out.push(named(t, format!("bell {}", k + 1))?);
        }
        return Ok(out);
    }
    let table: toml::Table = toml::from_str(text).map_err(|e| BellFileError::Syntax(one_line(text, &e)))?;
    match table.get("bell") {
        Some(toml::Value::Array(list)) => list
            .iter()
            .enumerate()
            .map(|(k, v)| match v {
                toml::Value::Table(t) => named(t.clone(), format!("{default_name} {}", k + 1)),
                _ => Err(BellFileError::Syntax(format!("bell {}: not a table", k + 1))),
            })
            .collect(),
        _ => Ok(vec![named(table, default_name.to_string())?]),
    }
}

/// One line from a TOML error: where, which key, and what is wrong; a
/// number written with a decimal comma (`r_m = 0,05`, which TOML reads as
/// 0 followed by junk) is named as such.
fn one_line(text: &str, err: &toml::de::Error) -> String {
    let msg = err.message().replace('\n', " ");
    match err.span() {
        Some(span) => {
            let line = text[..span.start.min(text.len())].matches('\n').count() + 1;
            let src = text.lines().nth(line - 1).unwrap_or("");
            // The value: after the key's `=`, before any comment.
            let value = src.split_once('=').map(|(_, v)| v.split('#').next().unwrap_or(v));
            let src = cut(src.trim());
            match value.and_then(decimal_comma) {
                Some(advice) => format!("line {line} (`{src}`): {advice}"),
                None => format!("line {line} (`{src}`): {}", cut(&msg)),
            }
        }
        None => cut(&msg),
    }
}

/// Longest piece of the user's text quoted in a message (characters).
const QUOTE_MAX: usize = 120;

/// `s` cut to [`QUOTE_MAX`] characters with "...": a 200 KB line is not
/// echoed back whole.
fn cut(s: &str) -> String {
    if s.chars().count() <= QUOTE_MAX {
        s.to_string()
    } else {
        s.chars().take(QUOTE_MAX - 3).collect::<String>() + "..."
    }
}

/// Parse a bell file's text; `default_name` names a bell without `name`.
pub fn parse_bell(text: &str, default_name: &str) -> Result<LoadedBell, BellFileError> {
    // A ring ([[bell]] tables) where one bell is wanted: say so, rather
    // than "unknown field `bell`".
    if let Ok(toml::Value::Table(t)) = toml::from_str::<toml::Value>(text) {
        if let Some(toml::Value::Array(bells)) = t.get("bell") {
            return Err(BellFileError::Syntax(format!(
                "this file holds a ring of {} bell(s) ([[bell]] tables), where one bell is wanted: \
                 give one bell's file, or diagnose the ring (clapper diagnose FILE)",
                bells.len()
            )));
        }
    }
    let f: BellFile = toml::from_str(text).map_err(|e| BellFileError::Syntax(one_line(text, &e)))?;
    bell_from_fields(f, default_name)
}

fn bell_from_fields(f: BellFile, default_name: &str) -> Result<LoadedBell, BellFileError> {
    for (field, value) in [
        ("restitution", f.restitution),
        ("restitution_later", f.restitution_later),
    ] {
        if let Some(v) = value.filter(|v| !(v.is_finite() && *v > 0.0 && *v <= 1.0)) {
            return Err(ParamError {
                field,
                value: v,
                allowed: "greater than 0 and at most 1",
            }
            .into());
        }
    }
    let (restitution, restitution_later) = (f.restitution, f.restitution_later);
    let frame = f.frame()?;
    let hanging = f.hanging();
    let (f, clapper_parts) = with_clapper_parts(f)?;
    let mut loaded = bell_from_measures(f, default_name)?;
    loaded.bell = hanging.apply(loaded.bell)?;
    Ok(LoadedBell {
        restitution,
        restitution_later,
        ball_below_pivot_m: hanging.ball_below_pivot_m,
        clapper_parts,
        frame,
        ..loaded
    })
}

/// Put the `[clapper]` table's mass properties in the keys it stands for,
/// refusing those keys given as well.
fn with_clapper_parts(f: BellFile) -> Result<(BellFile, Option<ClapperParts>), BellFileError> {
    let Some(input) = &f.clapper else {
        return Ok((f, None));
    };
    let given: Vec<&str> = [
        ("clapper_mass_kg", f.clapper_mass_kg.is_some()),
        ("b_m", f.b_m.is_some()),
        ("clapper_inertia_kg_m2", f.clapper_inertia_kg_m2.is_some()),
        ("clapper_period_s", f.clapper_period_s.is_some()),
        ("clapper_oscillations", f.clapper_oscillations.is_some()),
    ]
    .iter()
    .filter(|(_, present)| *present)
    .map(|(k, _)| *k)
    .collect();
    if !given.is_empty() {
        return Err(BellFileError::ClapperTwice(given.join(", ")));
    }
    let parts = input.parts()?;
    let c = parts.mass_properties()?;
    let tower = f.bell_period_s.is_some() || f.bell_oscillations.is_some();
    let f = BellFile {
        clapper_mass_kg: Some(c.mass),
        b_m: Some(c.b),
        clapper_inertia_kg_m2: (!tower).then_some(c.inertia),
        clapper_period_s: tower.then(|| c.tc()),
        ..f
    };
    Ok((f, Some(parts)))
}

fn bell_from_measures(f: BellFile, default_name: &str) -> Result<LoadedBell, BellFileError> {
    let name = f.name.clone().unwrap_or_else(|| default_name.to_string());
    let phi_max = f.phi_max_deg.map(f64::to_radians);
    let f = BellFile {
        bell_period_s: period_of("bell", f.bell_period_s, f.bell_oscillations, f.bell_oscillations_time_s)?,
        clapper_period_s: period_of(
            "clapper",
            f.clapper_period_s,
            f.clapper_oscillations,
            f.clapper_oscillations_time_s,
        )?,
        ..f
    };
    let tower = f.bell_period_s.is_some() || f.clapper_period_s.is_some();
    if tower {
        let mixed: Vec<&str> = [
            ("bell_inertia_kg_m2", f.bell_inertia_kg_m2.is_some()),
            ("clapper_inertia_kg_m2", f.clapper_inertia_kg_m2.is_some()),
        ]
        .iter()
        .filter(|(_, present)| *present)
        .map(|(k, _)| *k)
        .collect();
        if !mixed.is_empty() {
            return Err(BellFileError::Mixed(mixed.join(", ")));
        }
        let missing = missing_of(&[
            ("bell_period_s", f.bell_period_s.is_some()),
            ("clapper_period_s", f.clapper_period_s.is_some()),
            ("r_m", f.r_m.is_some()),
            ("phi_max_deg", f.phi_max_deg.is_some()),
        ]);
        if !missing.is_empty() {
            return Err(BellFileError::Missing(missing));
        }
        let t = TowerMeasurements {
            bell_period: f.bell_period_s.unwrap_or_default(),
            clapper_period: f.clapper_period_s.unwrap_or_default(),
            r: f.r_m.unwrap_or_default(),
            phi_max: phi_max.unwrap_or_default(),
            bell_mass: f.bell_mass_kg,
            clapper_mass: f.clapper_mass_kg,
            a: f.a_m,
            b: f.b_m,
        };
        let (bell, assumed) = t.bell()?;
        return Ok(LoadedBell::new(name, bell, BellSource::Tower(assumed)));
    }
    let missing = missing_of(&[
        ("bell_mass_kg", f.bell_mass_kg.is_some()),
        ("clapper_mass_kg", f.clapper_mass_kg.is_some()),
        ("a_m", f.a_m.is_some()),
        ("b_m", f.b_m.is_some()),
        ("bell_inertia_kg_m2", f.bell_inertia_kg_m2.is_some()),
        ("clapper_inertia_kg_m2", f.clapper_inertia_kg_m2.is_some()),
        ("r_m", f.r_m.is_some()),
        ("phi_max_deg", f.phi_max_deg.is_some()),
    ]);
    if !missing.is_empty() {
        return Err(BellFileError::Missing(missing));
    }
    let bell = Bell::new(
        f.bell_mass_kg.unwrap_or_default(),
        f.clapper_mass_kg.unwrap_or_default(),
        f.a_m.unwrap_or_default(),
        f.b_m.unwrap_or_default(),
        f.bell_inertia_kg_m2.unwrap_or_default(),
        f.clapper_inertia_kg_m2.unwrap_or_default(),
        f.r_m.unwrap_or_default(),
        phi_max.unwrap_or_default(),
    )?;
    Ok(LoadedBell::new(name, bell, BellSource::MassProperties))
}

fn missing_of(keys: &[(&str, bool)]) -> String {
    keys.iter()
        .filter(|(_, present)| !present)
        .map(|(k, _)| *k)
        .collect::<Vec<_>>()
        .join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A very long line is cut in the message, not echoed whole.
    #[test]
    fn a_long_line_is_cut_in_the_message() {
        let text = format!("bell_mass_kg = {}", "9".repeat(200_000));
        let e = parse_bell(&text, "x").unwrap_err().to_string();
        assert!(
            e.len() < 400 && e.contains("line 1") && e.contains("..."),
            "{} bytes",
            e.len()
        );
    }

    #[test]
    fn a_ring_where_one_bell_is_wanted_says_so() {
        let ring = "[[bell]]\nbell_period_s = 2\nclapper_period_s = 1.6\nr_m = 0.1\nphi_max_deg = 26\n[[bell]]\nbell_period_s = 2.1\nclapper_period_s = 1.6\nr_m = 0.1\nphi_max_deg = 26\n";
        let e = parse_bell(ring, "x").unwrap_err().to_string();
        assert!(
            e.contains("a ring of 2 bell(s)") && e.contains("clapper diagnose"),
            "{e}"
        );
    }

    #[test]
    fn each_bell_of_a_ring_stands_alone_as_the_same_bell() {
        let toml_ring = "[[bell]]\nname = \"Treble\"\nbell_period_s = 1.6\nclapper_period_s = 1.3\nr_m = 0.08\nphi_max_deg = 26\n\
                         [[bell]]\nbell_period_s = 2.33\nr_m = 0.179\nphi_max_deg = 32\n\
                         gap_hand_mm = 253\ngap_back_mm = 247\nball_below_pivot_m = 0.8\n\
                         [bell.clapper]\nshaft_length_m = 0.69\nshaft_diameter_m = 0.05\nball_diameter_m = 0.14\nball_position_m = 0.76\n";
        let csv_ring =
            "name,bell_period_s,clapper_period_s,r_m,phi_max_deg,swing_loss,bell_swings_to_halve,swing_amplitude_deg\n\
                        1,1.6,1.3,0.08,26,,,\n,2.33,1.76,0.179,32,coulomb,40,10\n";
        for (text, csv) in [(toml_ring, false), (csv_ring, true), (LAB, false)] {
            let ring = if csv {
                parse_ring_csv(text).unwrap()
            } else {
                parse_bells(text, "bell").unwrap()
            };
            let alone = bell_texts(text, csv, "bell").unwrap();
            assert_eq!(alone.len(), ring.len());
            for (t, b) in alone.iter().zip(&ring) {
                assert_eq!(&parse_bell(t, "other").unwrap(), b, "{t}");
            }
        }
    }

    const LAB: &str = "name = \"Lab bell\"\nbell_mass_kg = 45.8\nclapper_mass_kg = 1.65\na_m = 0.24\nb_m = 0.25\n\
                       bell_inertia_kg_m2 = 4.1\nclapper_inertia_kg_m2 = 0.093\nr_m = 0.10\nphi_max_deg = 26\n";

    #[test]
    fn mass_form_reads_the_lab_bell() {
        let b = parse_bell(LAB, "x").unwrap();
        assert_eq!(b.name, "Lab bell");
        assert_eq!(b.source, BellSource::MassProperties);
        assert!((b.bell.lb_over_lc() - Bell::lab().lb_over_lc()).abs() < 1e-12);
    }

    #[test]
    fn tower_form_lists_what_it_assumed() {
        let b = parse_bell(
            "bell_period_s = 2.33\nclapper_period_s = 1.76\nr_m = 0.179\nphi_max_deg = 32\n",
            "tenor",
        )
        .unwrap();
        assert_eq!(b.name, "tenor");
        let BellSource::Tower(assumed) = &b.source else {
            panic!()
        };
        assert_eq!(assumed.fields.len(), 4);
        assert!((b.bell.lb_over_lc() - 1.752).abs() < 0.01);
        let b = parse_bell(
            "bell_period_s = 2.33\nclapper_period_s = 1.76\nr_m = 0.179\nphi_max_deg = 32\nbell_mass_kg = 1378\n",
            "t",
        )
        .unwrap();
        let BellSource::Tower(assumed) = &b.source else {
            panic!()
        };
        assert!(assumed.fields.iter().all(|(k, _)| *k != "bell_mass_kg"));
    }

    #[test]
    fn oscillation_counts_and_csv_rings() {
        let b = parse_bell(
            "bell_oscillations = 10\nbell_oscillations_time_s = 23.3\nclapper_period_s = 1.76\nr_m = 0.179\nphi_max_deg = 32\n",
            "t",
        )
        .unwrap();
        assert!((b.bell.tb() - 2.33).abs() < 1e-9);
        let e = parse_bell("bell_period_s = 2\nbell_oscillations = 3\nbell_oscillations_time_s = 6\nclapper_period_s = 1\nr_m = 0\nphi_max_deg = 30\n", "t");
        assert!(e.unwrap_err().to_string().contains("give one"));
        let csv =
            "name,bell_period_s,clapper_period_s,r_m,phi_max_deg\ntreble,1.4,1.1,0.08,28\ntenor,2.3,1.76,0.179,32\n";
        let ring = parse_ring_csv(csv).unwrap();
        assert_eq!(ring.len(), 2);
        assert_eq!(ring[1].name, "tenor");
        // An unknown column is the header's fault (line 1), not the first row's.
        let bad = parse_ring_csv("name,colour\nx,red\n").unwrap_err().to_string();
        assert!(
            bad.contains("line 1 (the header): unknown column") && bad.contains("colour"),
            "{bad}"
        );
        // An empty cell is named with its row and line, in a CSV's words.
        let bad = parse_ring_csv("name,bell_period_s,clapper_period_s,r_m,phi_max_deg\nx,2,1.5,0.1,30\ny,2,1.5,0.1,\n")
            .unwrap_err()
            .to_string();
        assert!(
            bad.starts_with("row 2 (line 3): no phi_max_deg (an empty cell?"),
            "{bad}"
        );
        let bad = parse_ring_csv("name,bell_period_s,clapper_period_s,r_m,phi_max_deg\nx,abc,1,0.1,30\n").unwrap_err();
        assert!(
            bad.to_string()
                .contains("row 1 (line 2), column bell_period_s: 'abc' is not a number"),
            "{bad}"
        );
        assert!(parse_ring_csv("name,r_m\n").is_err());
    }

    #[test]
    fn several_bells_as_tables() {
        let text = format!("[[bell]]\n{LAB}\n[[bell]]\nname = \"t\"\nbell_period_s = 2\nclapper_period_s = 1.5\nr_m = 0.1\nphi_max_deg = 30\n");
        let bells = parse_bells(&text, "ring").unwrap();
        assert_eq!(bells.len(), 2);
        assert_eq!(bells[0].name, "Lab bell");
        assert_eq!(bells[1].name, "t");
        assert_eq!(parse_bells(LAB, "one").unwrap().len(), 1);
        let bad = text.replace("phi_max_deg = 30", "phi_max_deg = \"x\"");
        assert!(parse_bells(&bad, "ring").unwrap_err().to_string().contains("bell 2"));
    }

    const PARTS: &str = "[clapper]\nshaft_length_m = 0.69\nshaft_diameter_m = 0.05\nball_diameter_m = 0.14\n\
                         ball_position_m = 0.76\nflight_length_m = 0.2\nflight_diameter_m = 0.05\n";

    #[test]
    fn a_clapper_by_its_parts_in_either_form() {
        let tower = parse_bell(
            &format!("bell_period_s = 2.33\nr_m = 0.179\nphi_max_deg = 32\nbell_mass_kg = 1378\n{PARTS}"),
            "t",
        )
        .unwrap();
        let c = tower.clapper_parts.unwrap().mass_properties().unwrap();
        assert!((tower.bell.tc() - c.tc()).abs() < 1e-12);
        assert!((tower.bell.clapper_mass - c.mass).abs() < 1e-12 && (tower.bell.b - c.b).abs() < 1e-12);
        let BellSource::Tower(assumed) = &tower.source else {
            panic!()
        };
        assert!(assumed
            .fields
            .iter()
            .all(|(k, _)| !["clapper_mass_kg", "b_m"].contains(k)));
        let mass_form = LAB
            .replace("clapper_mass_kg = 1.65\n", "")
            .replace("b_m = 0.25\n", "")
            .replace("clapper_inertia_kg_m2 = 0.093\n", "");
        let b = parse_bell(&format!("{mass_form}{PARTS}"), "x").unwrap();
        assert!((b.bell.clapper_inertia - c.inertia).abs() < 1e-12);
        let e = parse_bell(&format!("{LAB}{PARTS}"), "x").unwrap_err().to_string();
        assert!(e.contains("twice") && e.contains("clapper_mass_kg"), "{e}");
        let e = parse_bell(&format!("{mass_form}{}", PARTS.replace("0.69", "0.8")), "x")
            .unwrap_err()
            .to_string();
        assert!(e.contains("shaft_length_m") && !e.contains('\n'), "{e}");
    }

    #[test]
    fn errors_are_one_line_and_name_the_problem() {
        let cases = [
            (LAB.replace("45.8", "-45.8"), "bell_mass_kg"),
            (LAB.replace("= 26", "= 120"), "phi_max_deg"),
            (format!("{LAB}colour = \"bronze\"\n"), "colour"),
            (LAB.replace("0.25", "\"abc\""), "b_m"),
            (LAB.replace("a_m = 0.24\n", ""), "a_m"),
            (
                "bell_period_s = 2\nclapper_period_s = 1.5\nr_m = 0.1\nphi_max_deg = 30\nbell_inertia_kg_m2 = 3\n"
                    .into(),
                "bell_inertia_kg_m2",
            ),
            ("this is not toml".into(), "line 1"),
        ];
        for (text, needle) in cases {
            let e = parse_bell(&text, "x").unwrap_err().to_string();
            assert!(!e.contains('\n'), "not one line: {e}");
            assert!(e.contains(needle), "{e:?} should name {needle}");
        }
    }
}
