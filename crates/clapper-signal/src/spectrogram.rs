//! Short FFTs of overlapping Hann-windowed segments (the paper's Fig 3), and
//! the level of one frequency against time (Fig 4).

use std::f64::consts::PI;

use realfft::RealFftPlanner;

use crate::{Signal, SignalError};

/// A spectrogram: level in dB relative to its maximum.
#[derive(Clone, Debug, PartialEq)]
pub struct Spectrogram {
    /// Frame centre times (s).
    pub times: Vec<f64>,
    /// Bin frequencies (Hz).
    pub freqs: Vec<f64>,
    /// Level (dB re the maximum, ≤ 0), frame-major: `db[frame * freqs.len() + bin]`.
    pub db: Vec<f64>,
}

impl Spectrogram {
    /// Level (dB) of frame `f`, bin `b`.
    pub fn at(&self, f: usize, b: usize) -> f64 {
        self.db[f * self.freqs.len() + b]
    }

    /// The bin nearest `freq` (Hz).
    pub fn bin_of(&self, freq: f64) -> usize {
        let df = self.freqs.get(1).copied().unwrap_or(1.0);
        ((freq / df).round().max(0.0) as usize).min(self.freqs.len().saturating_sub(1))
    }

    /// The level (dB) of the bin nearest `freq` against time (Fig 4).
    pub fn decay(&self, freq: f64) -> Vec<(f64, f64)> {
        let b = self.bin_of(freq);
        self.times
            .iter()
            .enumerate()
            .map(|(f, &t)| (t, self.at(f, b)))
            .collect()
    }
}

/// The widest range of levels below the loudest that is drawn or
/// reported (dB): a 24-bit recording's whole span is 144 dB.
pub const MAX_RANGE_DB: f64 = 200.0;

/// The periodic Hann window of length n.
pub fn hann(n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| 0.5 - 0.5 * (2.0 * PI * i as f64 / n as f64).cos())
        .collect()
}

/// Compute a spectrogram with windows of `window` samples overlapping by
/// the fraction `overlap` (0 ≤ overlap ≤ 0.99); levels below `-range_db` are
/// clipped to it.
pub fn spectrogram(sig: &Signal, window: usize, overlap: f64, range_db: f64) -> Result<Spectrogram, SignalError> {
    spectrogram_columns(sig, window, overlap, range_db, usize::MAX)
}

/// [`spectrogram`] in at most `columns` frames, for a picture: when there
/// are more, each column is the loudest of as many successive frames as it
/// takes (its time the middle of theirs). Memory is `columns` frames
/// whatever the recording's length (3 million samples at 0.98 overlap are
/// 36,000 frames: 1.2 GB whole); with no more frames than columns it is
/// [`spectrogram`] exactly.
pub fn spectrogram_columns(
    sig: &Signal,
    window: usize,
    overlap: f64,
    range_db: f64,
    columns: usize,
) -> Result<Spectrogram, SignalError> {
    sig.validate()?;
    if window < 16 {
        return Err(SignalError::Option(format!("window of {window} samples: at least 16")));
    }
    if !(0.0..=0.99).contains(&overlap) {
        return Err(SignalError::Option(format!("overlap {overlap}: from 0 to 0.99")));
    }
    if !(range_db.is_finite() && range_db > 0.0 && range_db <= MAX_RANGE_DB) {
        return Err(SignalError::Option(format!(
            "dB range {range_db}: more than 0, at most {MAX_RANGE_DB} dB (a 24-bit recording spans 144)"
        )));
    }
    if columns == 0 {
        return Err(SignalError::Option("a spectrogram of no columns".into()));
    }
    if sig.samples.len() < window {
        return Err(SignalError::TooShort(format!(
            "{} samples, less than one window of {window}",
            sig.samples.len()
        )));
    }
    let hop = ((window as f64 * (1.0 - overlap)).round() as usize).max(1);
    let w = hann(window);
    let mut planner = RealFftPlanner::<f64>::new();
    let fft = planner.plan_fft_forward(window);
    let mut input = fft.make_input_vec();
    let mut output = fft.make_output_vec();
    let nbins = output.len();
    let frames = (sig.samples.len() - window) / hop + 1;
    let group = frames.div_ceil(columns);
    let cols = frames.div_ceil(group);
    let mut mag = vec![0.0f64; cols * nbins];
    for f in 0..frames {
        let s = &sig.samples[f * hop..f * hop + window];
        for i in 0..window {
            input[i] = s[i] * w[i];
        }
        fft.process(&mut input, &mut output)
            .map_err(|e| SignalError::Invalid(e.to_string()))?;
        let col = &mut mag[(f / group) * nbins..(f / group + 1) * nbins];
        for (m, c) in col.iter_mut().zip(&output) {
            *m = m.max(c.norm());
        }
    }
    let max = mag.iter().cloned().fold(0.0f64, f64::max);
    let floor = 10f64.powf(-range_db / 20.0);
    // In place: the levels are the magnitudes' only copy.
    for m in mag.iter_mut() {
        let rel = if max > 0.0 { *m / max } else { 0.0 };
        *m = 20.0 * rel.max(floor).log10();
    }
    let centre = |f: usize| (f * hop) as f64 / sig.rate + 0.5 * window as f64 / sig.rate;
    Ok(Spectrogram {
        times: (0..cols)
            .map(|c| {
                let (first, last) = (c * group, ((c + 1) * group).min(frames) - 1);
                if first == last {
                    centre(first)
                } else {
                    0.5 * (centre(first) + centre(last))
                }
            })
            .collect(),
        freqs: (0..nbins).map(|b| b as f64 * sig.rate / window as f64).collect(),
        db: mag,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Columns are the loudest of their frames, and with enough columns
    /// the spectrogram is the plain one exactly.
    #[test]
    fn columns_take_the_loudest_frame_and_change_nothing_when_enough() {
        let sig = Signal {
            rate: 8000.0,
            samples: (0..20000)
                .map(|k| (k as f64 * 0.3).sin() * (-(k as f64) / 5000.0).exp())
                .collect(),
        };
        let full = spectrogram(&sig, 256, 0.75, 80.0).unwrap();
        assert_eq!(
            spectrogram_columns(&sig, 256, 0.75, 80.0, full.times.len()).unwrap(),
            full
        );
        let few = spectrogram_columns(&sig, 256, 0.75, 80.0, 10).unwrap();
        assert!(few.times.len() <= 10 && few.db.len() == few.times.len() * few.freqs.len());
        let group = full.times.len().div_ceil(10);
        for c in 0..few.times.len() {
            for b in [0, 25, 100] {
                let loudest = (c * group..((c + 1) * group).min(full.times.len()))
                    .map(|f| full.at(f, b))
                    .fold(f64::NEG_INFINITY, f64::max);
                assert!((few.at(c, b) - loudest).abs() < 1e-9, "column {c}, bin {b}");
            }
        }
    }

    /// The overlap's range includes its end, as its message says.
    #[test]
    fn an_overlap_of_0_99_is_taken_and_1_refused() {
        let sig = Signal {
            rate: 8000.0,
            samples: (0..4000).map(|k| (k as f64 * 0.3).sin()).collect(),
        };
        assert!(spectrogram(&sig, 256, 0.99, 80.0).is_ok());
        let e = spectrogram(&sig, 256, 1.0, 80.0).unwrap_err().to_string();
        assert!(e.contains("0.99"), "{e}");
    }

    #[test]
    fn a_tone_lands_in_its_bin_and_decays_at_its_rate() {
        let rate = 8000.0;
        let (f0, q) = (1000.0, 500.0);
        let alpha = PI * f0 / q;
        let samples: Vec<f64> = (0..16000)
            .map(|i| {
                let t = i as f64 / rate;
                (-alpha * t).exp() * (2.0 * PI * f0 * t).sin()
            })
            .collect();
        let s = spectrogram(&Signal { rate, samples }, 512, 0.75, 80.0).unwrap();
        let b = s.bin_of(f0);
        assert!((s.freqs[b] - f0).abs() < 8.0);
        // Slope of the decay in dB/s: −20 α / ln 10.
        let d = s.decay(f0);
        let (t1, l1) = d[5];
        let (t2, l2) = d[40];
        let slope = (l2 - l1) / (t2 - t1);
        let want = -20.0 * alpha / std::f64::consts::LN_10;
        assert!((slope - want).abs() / want.abs() < 0.02, "{slope} vs {want}");
        assert!(s.db.iter().all(|v| *v <= 0.0 && *v >= -80.0));
    }

    #[test]
    fn bad_options_are_refused() {
        let sig = Signal {
            rate: 100.0,
            samples: vec![0.0; 100],
        };
        assert!(spectrogram(&sig, 8, 0.5, 40.0).is_err());
        assert!(spectrogram(&sig, 64, 1.0, 40.0).is_err());
        assert!(spectrogram(&sig, 200, 0.5, 40.0).is_err());
        let nan = Signal {
            rate: 100.0,
            samples: vec![f64::NAN; 100],
        };
        assert!(spectrogram(&nan, 64, 0.5, 40.0).is_err());
    }
}
