//! What every part of the model shares and depends on nothing: gravity,
//! and the error of a parameter out of range, with its value written as a
//! person reads it.

/// Acceleration due to gravity (m/s²), the value the paper uses.
pub const G: f64 = 9.81;

/// A bad bell parameter: which field, its value, and what is allowed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{field} = {} is out of range: {allowed}", readable(*value))]
pub struct ParamError {
    /// The field's name as the user writes it (e.g. `clapper_mass_kg`).
    pub field: &'static str,
    /// The rejected value.
    pub value: f64,
    /// The allowed range, in words.
    pub allowed: &'static str,
}

/// `v` as a person reads it: plain for ordinary sizes, in exponent form
/// (`1e-300`, not three hundred digits) for very small or large ones.
pub fn readable(v: f64) -> String {
    if v != 0.0 && v.is_finite() && !(1e-4..1e7).contains(&v.abs()) {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}

impl ParamError {
    /// `value` if it is a finite number > 0, else the error naming `field`.
    pub fn positive(field: &'static str, value: f64) -> Result<f64, ParamError> {
        if value.is_finite() && value > 0.0 {
            Ok(value)
        } else {
            Err(ParamError {
                field,
                value,
                allowed: "a finite number > 0",
            })
        }
    }
}
