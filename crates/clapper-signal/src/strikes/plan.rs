//! Which bands each bell is heard in: its partials placed on the
//! recording's mean spectrum, shared ones told from its own.

use super::voice::{BellVoice, VoicePartial};
use crate::Signal;

/// The mean magnitude spectrum over 1 s Hann windows (frequency step
/// under 0.5 Hz, zero-padded), for finding each partial where it really
/// lies. Returns (frequency step Hz, magnitudes).
pub(super) fn mean_spectrum(sig: &Signal) -> (f64, Vec<f64>) {
    let len = (sig.rate as usize).min(sig.samples.len());
    let n = (2 * len)
        .next_power_of_two()
        .max(2 * (sig.rate as usize).next_power_of_two());
    let mut planner = realfft::RealFftPlanner::<f64>::new();
    let fft = planner.plan_fft_forward(n);
    let w = crate::spectrogram::hann(len);
    let mut buf = fft.make_input_vec();
    let mut spec = fft.make_output_vec();
    let mut acc = vec![0.0; spec.len()];
    // At most 120 windows, spread over the recording: enough to find a
    // partial, quick for any length.
    let windows = (sig.samples.len() / len).max(1);
    let step = windows.div_ceil(120);
    for k in (0..windows).step_by(step) {
        buf.iter_mut().for_each(|v| *v = 0.0);
        for i in 0..len {
            buf[i] = sig.samples[k * len + i] * w[i];
        }
        if fft.process(&mut buf, &mut spec).is_ok() {
            for (a, c) in acc.iter_mut().zip(&spec) {
                *a += super::stats::hypot(c.re, c.im);
            }
        }
    }
    (sig.rate / n as f64, acc)
}

/// One band to listen in: centre (Hz), weight, box length (samples).
pub(super) type BandSpec = (f64, f64, usize);

/// What a bell is heard in: its bands, and the strong partials it shares
/// with other bells (with those bells, from 0) that are left out of them,
/// to be fitted for a double strike where no sharing bell strikes.
pub(super) struct BandPlan {
    pub(super) bands: Vec<BandSpec>,
    pub(super) shared: Vec<(BandSpec, Vec<usize>)>,
    /// Per band of `bands`, the other bells (from 0) whose partials lie
    /// in it, where the bell has fewer than two bands of its own (else
    /// none): their strikes step its bands too.
    pub(super) sharers: Vec<Vec<usize>>,
}

pub(super) fn plan_bands(voices: &[BellVoice], rate: f64, spectrum: &(f64, Vec<f64>)) -> Vec<BandPlan> {
    let nyq = 0.45 * rate;
    let (df, mag) = spectrum;
    // Each partial where the recording has it: a peak within 2 % (a
    // tuned bell's partials stray a few tens of cents), then known to
    // half a percent; else left where assumed, uncertain as it was.
    let placed: Vec<Vec<VoicePartial>> = voices
        .iter()
        .map(|v| {
            v.partials
                .iter()
                .filter(|p| p.freq_hz > 20.0 && p.freq_hz < nyq)
                .map(|p| match find_peak(p.freq_hz, p.uncertainty.min(0.02), *df, mag) {
                    Some(f) => VoicePartial {
                        freq_hz: f,
                        uncertainty: p.uncertainty.min(0.005),
                        ..*p
                    },
                    None => *p,
                })
                .collect()
        })
        .collect();
    placed
        .iter()
        .enumerate()
        .map(|(b, v)| {
            let smax = v.iter().map(|p| p.strength).fold(0.0, f64::max);
            // The bell's strongest partial must be in the recording, or
            // the bell is not: nothing of it is listened for.
            let strongest = v.iter().find(|p| p.strength == smax);
            if strongest.is_some_and(|p| find_peak(p.freq_hz, 0.01, *df, mag).is_none()) {
                return BandPlan {
                    bands: vec![],
                    shared: vec![],
                    sharers: vec![],
                };
            }
            let bands: Vec<(f64, f64, f64, usize, Vec<usize>)> =
                v.iter().map(|p| partial_band(p, b, smax, &placed, rate)).collect();
            // A band another bell shares beats with it while both ring and
            // steps when the other strikes: with two bands or more of its
            // own (90 %), a bell is heard in those alone; else in its best
            // shared ones, weighted by how much of each is its own.
            let clean: Vec<_> = bands.iter().filter(|b| b.2 >= 0.9 && b.1 >= 0.1).collect();
            // Its strong partials left out for being shared (a nominal on
            // another bell's tierce): a double strike is often told
            // soonest there, between the sharing bells' strikes.
            let mut shared: Vec<(BandSpec, Vec<usize>)> = vec![];
            let mut chosen: Vec<(BandSpec, Vec<usize>)> = if clean.len() >= 2 {
                shared = bands
                    .iter()
                    .filter(|b| b.2 < 0.9 && b.1 >= 0.3 && !b.4.is_empty())
                    .map(|b| ((b.0, b.1, b.3), b.4.clone()))
                    .collect();
                clean.iter().map(|b| ((b.0, b.1, b.3), vec![])).collect()
            } else {
                bands
                    .iter()
                    .map(|b| ((b.0, b.1 * b.2 * b.2, b.3), b.4.clone()))
                    .filter(|b| b.0 .1 >= 0.02)
                    .collect()
            };
            chosen.sort_by(|a, b| b.0 .1.total_cmp(&a.0 .1));
            chosen.truncate(6);
            let (bands, sharers) = chosen.into_iter().unzip();
            BandPlan { bands, shared, sharers }
        })
        .collect()
}

/// One partial `p` of bell `b` (its strongest partial `smax` strong),
/// among every bell's partials `placed`, as a band: (frequency Hz,
/// strength over the strongest, the share of the band that is its own,
/// box length in samples, the bells whose partials may lie in it).
fn partial_band(
    p: &VoicePartial,
    b: usize,
    smax: f64,
    placed: &[Vec<VoicePartial>],
    rate: f64,
) -> (f64, f64, f64, usize, Vec<usize>) {
    let f = p.freq_hz;
    // Other bells' partials that may lie in this band, and the nearest that cannot.
    let mut shared = 0.0;
    let mut sharers = vec![];
    let mut nearest = f64::INFINITY;
    for (ob, ov) in placed.iter().enumerate() {
        if ob == b {
            continue;
        }
        let omax = ov.iter().map(|p| p.strength).fold(0.0, f64::max);
        for op in ov {
            let d = (op.freq_hz - f).abs();
            let tol = (p.uncertainty + op.uncertainty).max(0.01) * f;
            if d < tol {
                shared += (op.strength / omax).powi(2);
                sharers.push(ob);
            } else {
                nearest = nearest.min(d);
            }
        }
    }
    let s = p.strength / smax;
    let own = s * s / (s * s + shared);
    // A null of the smoothing on the nearest other partial; 3 to 50 ms.
    let secs = (1.0 / nearest.max(0.03 * f)).clamp(0.003, 0.05);
    let len = ((secs * rate).round() as usize) | 1;
    sharers.dedup();
    (f, s, own, len, sharers)
}

/// The peak of the mean spectrum within `f` ± uncertainty, if it stands
/// 10 dB above the median around it (else the partial is too weak to place).
pub(super) fn find_peak(f: f64, uncertainty: f64, df: f64, mag: &[f64]) -> Option<f64> {
    let lo = ((f * (1.0 - uncertainty)) / df).floor() as usize;
    let hi = (((f * (1.0 + uncertainty)) / df).ceil() as usize).min(mag.len().saturating_sub(2));
    if lo < 1 || hi <= lo + 2 {
        return None;
    }
    // The highest peak inside the window (a stronger partial of another
    // bell just beyond its edge must not hide this one).
    let k = (lo + 1..hi)
        .filter(|&k| mag[k] >= mag[k - 1] && mag[k] >= mag[k + 1])
        .max_by(|&a, &b| mag[a].total_cmp(&mag[b]))?;
    // The level around it over ±5 % (at least ±20 Hz): a narrower window
    // is mostly the peak's own main lobe and a neighbour's.
    let wide = (0.05 * f).max(20.0);
    let wlo = (((f - wide) / df).floor().max(1.0)) as usize;
    let whi = (((f + wide) / df).ceil() as usize).min(mag.len() - 1);
    let mut sorted: Vec<f64> = mag[wlo..=whi].to_vec();
    sorted.sort_by(f64::total_cmp);
    let median = sorted[sorted.len() / 2];
    if mag[k] < 3.16 * median {
        return None;
    }
    let (a, b, c) = (mag[k - 1], mag[k], mag[k + 1]);
    let den = a - 2.0 * b + c;
    let off = if den != 0.0 { 0.5 * (a - c) / den } else { 0.0 };
    Some((k as f64 + off.clamp(-0.5, 0.5)) * df)
}
