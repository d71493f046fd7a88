//! The clapper's impacts on the bell and how their sizes compare
//! (docs/model.md §4.1): the double strike's amplitude ratio and index.

use crate::contact::Side;

/// A time (s) and the bell angle θ then (rad).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Moment {
    /// Time (s).
    pub t: f64,
    /// θ (rad).
    pub theta: f64,
}

/// One impact of the clapper on the bell (for the penalty model: the start
/// of one contact).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Impact {
    /// Time (s).
    pub t: f64,
    /// Bell angle θ (rad).
    pub theta: f64,
    /// φ' just before (rad/s).
    pub phi_dot_before: f64,
    /// φ' just after (impact model), or at separation (penalty model) (rad/s);
    /// zero if the clapper came to rest, `None` if it was still in contact
    /// when the stroke ended.
    pub phi_dot_after: Option<f64>,
    /// The side hit.
    pub side: Side,
}

/// What the amplitude ratio A of (33) compares between the first strike
/// and the impact after it (docs/model.md §4.1). With one coefficient of
/// restitution (R2 = R) the three are the same number; they part when the
/// later bounces lose less than the strike (R2 > R), as the paper's drops
/// show.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case"))]
pub enum StrikeAmplitude {
    /// The clapper's rate just before each impact, |φ'⁻| (the paper's
    /// reading, and the default).
    #[default]
    Rate,
    /// The impulse each impact gives the bell, ∝ |φ'⁻ − φ'⁺|: what the
    /// modal synthesis sets each mode moving with (`clapper synth`), so the
    /// amplitude ratio of the synthesised strikes.
    Impulse,
    /// The energy each impact takes from the clapper's motion,
    /// ∝ φ'⁻² − φ'⁺², as an amplitude (its square root): the paper's
    /// reading of a low R, that the strike's lost energy is what rings.
    Vibration,
}

impl StrikeAmplitude {
    /// Whether this is the default, [`StrikeAmplitude::Rate`].
    pub fn is_rate(&self) -> bool {
        *self == Self::Rate
    }

    /// The size of impact `i` by this definition, in units that cancel in
    /// the ratio (rad/s). A contact still open when the stroke ended counts
    /// as come to rest (φ'⁺ = 0).
    pub fn of(self, i: &Impact) -> f64 {
        let (before, after) = (i.phi_dot_before, i.phi_dot_after.unwrap_or(0.0));
        match self {
            Self::Rate => before.abs(),
            Self::Impulse => (before - after).abs(),
            Self::Vibration => (before * before - after * after).max(0.0).sqrt(),
        }
    }
}

/// D = max(0, A − 0.2) · max(0, dt12 − 22) / 2.25, dt12 in ms (33).
pub fn double_strike_index(amplitude_ratio: f64, delay_ms: f64) -> f64 {
    (amplitude_ratio - 0.2).max(0.0) * (delay_ms - 22.0).max(0.0) / 2.25
}
