//! # clapper-signal
//!
//! The analyses of the paper's experimental half, on sampled signals held in
//! memory (reading files is `clapper-io`'s job): time-frequency analysis
//! (Fig 3, 4), modal frequencies and Q factors of a single strike, the
//! contact detector (Figs 2, 5), and velocity jumps from an accelerometer
//! (Section 3.2). Every analysis is tested against synthetic signals of
//! known truth, since no recordings come with the project.

#![warn(missing_docs)]

pub mod accel;
pub mod contacts;
mod fft;
pub mod lateness;
pub mod methods;
pub mod modes;
pub mod ringing_log;
pub mod ringing_log_synth;
pub mod sampled_ring;
pub mod self_calibrate;
pub mod spectrogram;
pub mod strikes;
pub mod striking;
pub mod synth;
pub mod template_timing;
pub mod tower;
pub mod tower_effects;

/// The median of `v` (the upper of the middle two), 0 for none: the
/// element the sorted order puts at the middle, found by selection (in
/// linear time: the double judge takes hundreds of thousands of medians
/// on ten minutes; the same value as sorting, `total_cmp` being a total
/// order).
pub(crate) fn median(v: &[f64]) -> f64 {
    let mut s = v.to_vec();
    if s.is_empty() {
        return 0.0;
    }
    let k = s.len() / 2;
    *s.select_nth_unstable_by(k, f64::total_cmp).1
}

/// A signal: samples at a fixed rate.
#[derive(Clone, Debug, PartialEq)]
pub struct Signal {
    /// Sample rate (Hz).
    pub rate: f64,
    /// Samples (any unit).
    pub samples: Vec<f64>,
}

/// A signal that cannot be analysed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SignalError {
    /// Too short for the analysis asked.
    #[error("signal too short: {0}")]
    TooShort(String),
    /// NaN or infinite samples, or a bad rate.
    #[error("signal not usable: {0}")]
    Invalid(String),
    /// An option out of range.
    #[error("{0}")]
    Option(String),
}

impl Signal {
    /// Check rate and samples.
    pub fn validate(&self) -> Result<(), SignalError> {
        if !(self.rate.is_finite() && self.rate > 0.0) {
            return Err(SignalError::Invalid(format!("sample rate {} Hz", self.rate)));
        }
        if let Some(i) = self.samples.iter().position(|v| !v.is_finite()) {
            return Err(SignalError::Invalid(format!("sample {i} is not a finite number")));
        }
        if self.samples.is_empty() {
            return Err(SignalError::TooShort("no samples".into()));
        }
        Ok(())
    }

    /// Duration (s).
    pub fn duration(&self) -> f64 {
        self.samples.len() as f64 / self.rate
    }
}
