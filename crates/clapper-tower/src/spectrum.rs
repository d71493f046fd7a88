//! Amplitude spectra of force histories (realfft), and the strongest
//! lines in a band.

use realfft::RealFftPlanner;

/// A one-sided amplitude spectrum.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Spectrum {
    /// Bin spacing (Hz).
    pub df: f64,
    /// Amplitude of each bin (the input's units): a sinusoid of amplitude A
    /// on a bin reads A (Hann window, corrected for its gain).
    pub amplitude: Vec<f64>,
}

impl Spectrum {
    /// Frequency of bin `i` (Hz).
    pub fn frequency(&self, i: usize) -> f64 {
        i as f64 * self.df
    }

    /// Largest amplitude between `lo` and `hi` Hz, with its frequency.
    pub fn peak_in(&self, lo: f64, hi: f64) -> Option<(f64, f64)> {
        let a = (lo / self.df).ceil().max(0.0) as usize;
        let b = ((hi / self.df).floor() as usize).min(self.amplitude.len().saturating_sub(1));
        (a..=b)
            .filter(|&i| i < self.amplitude.len())
            .map(|i| (self.frequency(i), self.amplitude[i]))
            .max_by(|x, y| x.1.total_cmp(&y.1))
    }

    /// The `count` strongest local maxima between `lo` and `hi` Hz,
    /// strongest first: (frequency, amplitude).
    pub fn lines(&self, lo: f64, hi: f64, count: usize) -> Vec<(f64, f64)> {
        let a = ((lo / self.df).ceil() as usize).max(1);
        let b = ((hi / self.df).floor() as usize).min(self.amplitude.len().saturating_sub(2));
        let mut out: Vec<(f64, f64)> = (a..=b)
            .filter(|&i| self.amplitude[i] > self.amplitude[i - 1] && self.amplitude[i] >= self.amplitude[i + 1])
            .map(|i| (self.frequency(i), self.amplitude[i]))
            .collect();
        out.sort_by(|x, y| y.1.total_cmp(&x.1));
        out.truncate(count);
        out
    }
}

/// The spectrum of `x` sampled every `dt` s, its mean taken out first.
pub fn spectrum(x: &[f64], dt: f64) -> Spectrum {
    let n = x.len();
    if n < 4 {
        return Spectrum::default();
    }
    let mean = x.iter().sum::<f64>() / n as f64;
    let w: Vec<f64> = (0..n)
        .map(|i| 0.5 - 0.5 * (std::f64::consts::TAU * i as f64 / n as f64).cos())
        .collect();
    let gain: f64 = w.iter().sum();
    let mut input: Vec<f64> = x.iter().zip(&w).map(|(v, w)| (v - mean) * w).collect();
    let fft = RealFftPlanner::<f64>::new().plan_fft_forward(n);
    let mut out = fft.make_output_vec();
    fft.process(&mut input, &mut out).expect("lengths from the plan");
    Spectrum {
        df: 1.0 / (n as f64 * dt),
        amplitude: out.iter().map(|c| 2.0 * c.norm() / gain).collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_sinusoid_reads_its_amplitude_at_its_frequency() {
        let dt = 0.01;
        let x: Vec<f64> = (0..10_000)
            .map(|i| 5.0 + 3.0 * (std::f64::consts::TAU * 1.25 * i as f64 * dt).sin())
            .collect();
        let s = spectrum(&x, dt);
        let (f, a) = s.peak_in(0.5, 3.0).unwrap();
        assert!((f - 1.25).abs() < 1e-9 && (a - 3.0).abs() < 1e-6, "{f} {a}");
        assert_eq!(s.lines(0.5, 3.0, 1)[0].0, f);
    }
}
