//! Strikes heard in a recording of a ring (docs/strikes.md): which bell
//! struck when, to the millisecond, and whether its clapper struck twice.
//!
//! Each bell is known by its partials ([`BellVoice`]: from its nominal and
//! a tuned bell's ratios, or from a recording of it struck alone). Every
//! partial becomes a band: the signal moved down by the partial's
//! frequency and smoothed by three boxes of length L, short enough to
//! follow a strike and long enough to put a null on the nearest partial of
//! another bell. A strike adds a complex step to each of its bell's bands,
//! so a bell's onset function is the size of the change in its bands over
//! the step's rise (3L), the bands weighted by how much of each is the
//! bell's own. Peaks of it well above the rest are strikes; the onset is
//! where the change reaches half its size (the smoothing is symmetric, so
//! that is the start of the sound); a double strike is a second step in
//! the bands within the double-strike window, fitted beside the first.

use std::f64::consts::PI;

use crate::{Signal, SignalError};

/// One partial of a bell.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VoicePartial {
    /// Frequency (Hz).
    pub freq_hz: f64,
    /// Strength relative to the bell's strongest partial (amplitude).
    pub strength: f64,
    /// How far the true partial may lie from `freq_hz` (fraction): small
    /// for a measured partial, about a quarter-tone for one assumed from
    /// the nominal.
    pub uncertainty: f64,
}

/// A bell as heard: its partials.
#[derive(Clone, Debug, PartialEq)]
pub struct BellVoice {
    /// The partials.
    pub partials: Vec<VoicePartial>,
}

/// A tuned bell's partials as (ratio to the nominal, strength): hum,
/// prime, tierce, quint, nominal, superquint, octave nominal and the next
/// upper partial. Listed so that a band another bell's partial falls in is
/// known to be shared, whether or not it is listened to.
const ASSUMED: [(f64, f64); 8] = [
    (0.25, 0.35),
    (0.5, 0.45),
    (0.5946, 0.5),
    (0.75, 0.2),
    (1.0, 1.0),
    (1.5, 0.45),
    (2.0, 0.35),
    (2.52, 0.25),
];

impl BellVoice {
    /// A bell known by its nominal (Hz): the others assumed from a tuned
    /// bell's ratios, each within a quarter-tone (3 %).
    pub fn from_nominal(nominal_hz: f64) -> Self {
        BellVoice {
            partials: ASSUMED
                .iter()
                .map(|&(r, s)| VoicePartial {
                    freq_hz: r * nominal_hz,
                    strength: s,
                    uncertainty: if r == 1.0 { 0.004 } else { 0.03 },
                })
                .collect(),
        }
    }

    /// A bell known from a recording of it struck alone: its strongest
    /// spectral peaks from 50 Hz up (at most eight, each at least 30 dB
    /// below the strongest), over the first two seconds after its loudest
    /// moment.
    pub fn from_template(sig: &Signal) -> Result<Self, SignalError> {
        sig.validate()?;
        let start = sig
            .samples
            .iter()
            .enumerate()
            .fold((0, 0.0f64), |b, (i, v)| if v.abs() > b.1 { (i, v.abs()) } else { b })
            .0;
        let len = ((2.0 * sig.rate) as usize).min(sig.samples.len() - start);
        if len < (0.2 * sig.rate) as usize {
            return Err(SignalError::TooShort(
                "a template needs 0.2 s of sound after its strike".into(),
            ));
        }
        let n = len.next_power_of_two() * 2;
        let mut planner = realfft::RealFftPlanner::<f64>::new();
        let fft = planner.plan_fft_forward(n);
        let mut buf = fft.make_input_vec();
        let w = crate::spectrogram::hann(len);
        for (i, b) in buf.iter_mut().take(len).enumerate() {
            *b = sig.samples[start + i] * w[i];
        }
        let mut spec = fft.make_output_vec();
        fft.process(&mut buf, &mut spec)
            .map_err(|e| SignalError::Invalid(e.to_string()))?;
        let mag: Vec<f64> = spec.iter().map(|c| c.norm()).collect();
        let df = sig.rate / n as f64;
        let lo = (50.0 / df) as usize;
        let mut peaks: Vec<(f64, f64)> = (lo.max(2)..mag.len() - 2)
            .filter(|&k| (1..=3).all(|j| mag[k] >= mag[k - j.min(k)] && mag[k] >= mag[(k + j).min(mag.len() - 1)]))
            .map(|k| {
                let (a, b, c) = (mag[k - 1].ln(), mag[k].ln(), mag[k + 1].ln());
                let den = a - 2.0 * b + c;
                let off = if den != 0.0 { 0.5 * (a - c) / den } else { 0.0 };
                ((k as f64 + off.clamp(-0.5, 0.5)) * df, mag[k])
            })
            .collect();
        peaks.sort_by(|a, b| b.1.total_cmp(&a.1));
        let top = peaks.first().map_or(0.0, |p| p.1);
        if top <= 0.0 {
            return Err(SignalError::Invalid("the template is silent".into()));
        }
        // Keep peaks apart by 2 %: a doublet or a window's shoulder is one partial.
        let mut kept: Vec<(f64, f64)> = vec![];
        for p in peaks.into_iter().filter(|p| p.1 >= top * 10f64.powf(-30.0 / 20.0)) {
            if kept.iter().all(|k| (k.0 - p.0).abs() > 0.02 * p.0) {
                kept.push(p);
            }
            if kept.len() == 8 {
                break;
            }
        }
        Ok(BellVoice {
            partials: kept
                .into_iter()
                .map(|(f, m)| VoicePartial {
                    freq_hz: f,
                    strength: m / top,
                    uncertainty: 0.004,
                })
                .collect(),
        })
    }
}

/// Options for finding strikes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StrikeOptions {
    /// No bell strikes twice in less than this (s), double strikes apart.
    /// Default 0.5 s: a bell's handstroke and backstroke are a row apart,
    /// at least 0.9 s in any ring.
    pub min_separation_s: f64,
    /// The double-strike window (ms): a second strike this long after the
    /// first. Default 10 to 150 ms (issue 19; the paper's double strikes
    /// fall from 20 to 120 ms).
    pub double_window_ms: (f64, f64),
    /// A second strike this loud or louder, against the first (amplitude
    /// ratio), is a double strike. Default 0.3: below it the paper's
    /// listeners heard no double strike at any delay (eq. 33's A − 0.2 is
    /// small).
    pub double_min_ratio: f64,
}

impl Default for StrikeOptions {
    fn default() -> Self {
        StrikeOptions {
            min_separation_s: 0.5,
            double_window_ms: (10.0, 150.0),
            double_min_ratio: 0.3,
        }
    }
}

/// A second strike heard after a first.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HeardDouble {
    /// Delay after the first strike (s).
    pub delay_s: f64,
    /// Its amplitude over the first's.
    pub amplitude_ratio: f64,
}

/// A strike heard.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HeardStrike {
    /// Bell, counting from 1 (the treble).
    pub bell: usize,
    /// Onset (s from the start of the recording): the start of its sound.
    pub t: f64,
    /// Its onset function's peak over the bell's typical strike (1 is typical).
    pub strength: f64,
    /// The clapper's second strike, if it struck twice.
    pub double: Option<HeardDouble>,
}

/// What was heard.
#[derive(Clone, Debug, PartialEq)]
pub struct Heard {
    /// Every strike, in time order.
    pub strikes: Vec<HeardStrike>,
    /// What the listener could not do (a bell never heard, say), in words.
    pub warnings: Vec<String>,
}

/// The rate the bands are kept at (Hz): onsets are interpolated within it.
const BAND_RATE: f64 = 1000.0;

/// A band: one partial of one bell, moved to 0 Hz and smoothed.
struct Band {
    /// Sample rate of `z` (Hz): about [`BAND_RATE`], a whole fraction of the signal's.
    rate: f64,
    /// Weight in the bell's onset function.
    weight: f64,
    /// Box length (s).
    box_s: f64,
    /// The complex band signal at the band rate.
    z: Vec<(f64, f64)>,
    /// Rise of a step (band samples, 3L rounded up).
    rise: usize,
    /// Typical size of a strike's change in this band.
    scale: f64,
}

/// Find every strike of every bell in `sig`; `voices[0]` is bell 1.
pub fn find_strikes(sig: &Signal, voices: &[BellVoice], opts: &StrikeOptions) -> Result<Heard, SignalError> {
    sig.validate()?;
    check_options(opts)?;
    if voices.is_empty() {
        return Err(SignalError::Option("no bells to listen for".into()));
    }
    if sig.rate < 4000.0 || sig.rate > 200_000.0 {
        return Err(SignalError::Option(format!(
            "sample rate {} Hz: 4 to 200 kHz",
            sig.rate
        )));
    }
    let nyq = 0.45 * sig.rate;
    for (i, v) in voices.iter().enumerate() {
        let ok = v
            .partials
            .iter()
            .any(|p| p.freq_hz.is_finite() && p.freq_hz > 20.0 && p.freq_hz < nyq);
        if !ok
            || v.partials
                .iter()
                .any(|p| !(p.freq_hz > 0.0 && p.strength > 0.0 && p.strength.is_finite()))
        {
            return Err(SignalError::Option(format!(
                "bell {}: no partial from 20 Hz to {:.0} Hz (0.45 of the sample rate), or a partial not positive",
                i + 1,
                nyq
            )));
        }
    }
    let mut warnings = vec![];
    let fmax = voices
        .iter()
        .flat_map(|v| v.partials.iter().map(|p| p.freq_hz))
        .filter(|f| *f < nyq)
        .fold(0.0, f64::max);
    let low = decimate(sig, fmax);
    let spectrum = mean_spectrum(&low);
    let plan = plan_bands(voices, low.rate, &spectrum);
    // 1. Each bell's bands and onset function, and its candidate strikes.
    let mut heard: Vec<BellHearing> = plan
        .into_iter()
        .map(|bands| {
            let bands: Vec<Band> = bands.into_iter().map(|(f, w, l)| band(&low, f, w, l)).collect();
            hear_bell(bands, opts)
        })
        .collect();
    // 2. A strike that steps a band two bells share is heard in both; it
    //    is the bell whose onset stands higher against its own typical
    //    strike. Onsets within 25 ms are one strike unless both stand high.
    let mut all: Vec<(f64, usize, usize, f64)> = vec![];
    for (b, h) in heard.iter().enumerate() {
        for (k, c) in h.candidates.iter().enumerate() {
            all.push((c.0 as f64 / h.rate, b, k, c.1));
        }
    }
    all.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut explained: Vec<(usize, usize)> = vec![];
    for (i, x) in all.iter().enumerate() {
        let rival = all[..i]
            .iter()
            .rev()
            .take_while(|y| x.0 - y.0 < 0.025)
            .chain(all[i + 1..].iter().take_while(|y| y.0 - x.0 < 0.025))
            .filter(|y| y.1 != x.1)
            .map(|y| y.3)
            .fold(0.0, f64::max);
        if rival > x.3 && x.3 < 0.6 * rival.min(1.0) {
            explained.push((x.1, x.2));
        }
    }
    for (b, k) in explained {
        heard[b].candidates[k].1 = 0.0;
    }
    // 3. Per bell, the strikes: candidates standing clear of the rest,
    //    timed, and looked at for a second strike.
    let mut strikes = vec![];
    for (b, h) in heard.iter().enumerate() {
        if h.bands.is_empty() {
            warnings.push(format!(
                "bell {}: its strongest partial is not in the recording, or none of its partials can be told from other bells'",
                b + 1
            ));
            continue;
        }
        let found = h.strikes(opts);
        if found.is_empty() {
            warnings.push(format!("bell {}: no strikes heard", b + 1));
        }
        strikes.extend(found.into_iter().map(|(t, strength, double)| HeardStrike {
            bell: b + 1,
            t,
            strength,
            double,
        }));
    }
    strikes.sort_by(|a, b| a.t.total_cmp(&b.t).then(a.bell.cmp(&b.bell)));
    Ok(Heard { strikes, warnings })
}

fn check_options(o: &StrikeOptions) -> Result<(), SignalError> {
    let (a, b) = o.double_window_ms;
    let ok = o.min_separation_s.is_finite()
        && o.min_separation_s >= 0.2
        && o.min_separation_s <= 5.0
        && a.is_finite()
        && b.is_finite()
        && a >= 5.0
        && a < b
        && b * 1e-3 < o.min_separation_s
        && o.double_min_ratio.is_finite()
        && o.double_min_ratio > 0.0
        && o.double_min_ratio <= 2.0;
    if ok {
        Ok(())
    } else {
        Err(SignalError::Option(format!(
            "strike options {o:?}: separation 0.2 to 5 s, a double-strike window from 5 ms up and shorter than the separation, a ratio in (0, 2]"
        )))
    }
}

/// Low-pass and keep every q-th sample, q as large as keeps `fmax` 20 %
/// below the new Nyquist frequency (a windowed-sinc filter).
fn decimate(sig: &Signal, fmax: f64) -> Signal {
    let q = ((sig.rate / (2.4 * fmax)).floor() as usize).max(1);
    if q == 1 {
        return sig.clone();
    }
    let rate = sig.rate / q as f64;
    let cutoff = (1.1 * fmax).min(0.45 * rate) / sig.rate;
    let transition = (0.5 * rate / sig.rate - cutoff).max(0.02 / q as f64);
    let half = ((2.0 / transition).ceil() as usize).clamp(8, 2000);
    // Blackman-windowed sinc, unit gain at 0 Hz.
    let mut h: Vec<f64> = (0..=2 * half)
        .map(|i| {
            let x = i as f64 - half as f64;
            let s = if x == 0.0 {
                2.0 * cutoff
            } else {
                (2.0 * PI * cutoff * x).sin() / (PI * x)
            };
            let w = 0.42 - 0.5 * (PI * i as f64 / half as f64).cos() + 0.08 * (2.0 * PI * i as f64 / half as f64).cos();
            s * w
        })
        .collect();
    let sum: f64 = h.iter().sum();
    h.iter_mut().for_each(|v| *v /= sum);
    let x = &sig.samples;
    let n_out = x.len().div_ceil(q);
    let samples = (0..n_out)
        .map(|m| {
            let c = m * q;
            let (lo, hi) = (c.saturating_sub(half), (c + half).min(x.len() - 1));
            (lo..=hi).map(|i| x[i] * h[i + half - c]).sum()
        })
        .collect();
    Signal { rate, samples }
}

/// The mean magnitude spectrum over 1 s Hann windows (frequency step
/// under 0.5 Hz, zero-padded), for finding each partial where it really
/// lies. Returns (frequency step Hz, magnitudes).
fn mean_spectrum(sig: &Signal) -> (f64, Vec<f64>) {
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
                *a += c.norm();
            }
        }
    }
    (sig.rate / n as f64, acc)
}

/// Each bell's bands as (frequency Hz, weight, box length in samples).
fn plan_bands(voices: &[BellVoice], rate: f64, spectrum: &(f64, Vec<f64>)) -> Vec<Vec<(f64, f64, usize)>> {
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
                return vec![];
            }
            let bands: Vec<(f64, f64, f64, usize)> = v
                .iter()
                .map(|p| {
                    let f = p.freq_hz;
                    // Other bells' partials that may lie in this band, and the nearest that cannot.
                    let mut shared = 0.0;
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
                    (f, s, own, len)
                })
                .collect();
            // A band another bell shares beats with it while both ring and
            // steps when the other strikes: with two bands or more of its
            // own (90 %), a bell is heard in those alone; else in its best
            // shared ones, weighted by how much of each is its own.
            let clean: Vec<_> = bands.iter().copied().filter(|b| b.2 >= 0.9 && b.1 >= 0.1).collect();
            let mut chosen: Vec<(f64, f64, usize)> = if clean.len() >= 2 {
                clean.iter().map(|b| (b.0, b.1, b.3)).collect()
            } else {
                bands
                    .iter()
                    .map(|b| (b.0, b.1 * b.2 * b.2, b.3))
                    .filter(|b| b.1 >= 0.02)
                    .collect()
            };
            chosen.sort_by(|a, b| b.1.total_cmp(&a.1));
            chosen.truncate(6);
            chosen
        })
        .collect()
}

/// The peak of the mean spectrum within `f` ± uncertainty, if it stands
/// 10 dB above the median there (else the partial is too weak to place).
fn find_peak(f: f64, uncertainty: f64, df: f64, mag: &[f64]) -> Option<f64> {
    let lo = ((f * (1.0 - uncertainty)) / df).floor() as usize;
    let hi = (((f * (1.0 + uncertainty)) / df).ceil() as usize).min(mag.len().saturating_sub(2));
    if lo < 1 || hi <= lo + 2 {
        return None;
    }
    let k = (lo..=hi).max_by(|&a, &b| mag[a].total_cmp(&mag[b]))?;
    let mut sorted: Vec<f64> = mag[lo..=hi].to_vec();
    sorted.sort_by(f64::total_cmp);
    let median = sorted[sorted.len() / 2];
    if mag[k] < 3.16 * median || k <= lo || k >= hi {
        return None;
    }
    let (a, b, c) = (mag[k - 1], mag[k], mag[k + 1]);
    let den = a - 2.0 * b + c;
    let off = if den != 0.0 { 0.5 * (a - c) / den } else { 0.0 };
    Some((k as f64 + off.clamp(-0.5, 0.5)) * df)
}

/// The band of partial `f` (Hz): x e^{−iωt} through three boxes of
/// `len` samples, centred (no delay), kept at about [`BAND_RATE`].
fn band(sig: &Signal, f: f64, weight: f64, len: usize) -> Band {
    let hop = ((sig.rate / BAND_RATE).round() as usize).max(1);
    let x = &sig.samples;
    let n = x.len();
    let w = 2.0 * PI * f / sig.rate;
    let delay = 3 * (len - 1) / 2;
    let mut z = Vec::with_capacity(n / hop + 1);
    // Three running sums, each with its own history of what entered it.
    let mut hist = [vec![(0.0, 0.0); len], vec![(0.0, 0.0); len], vec![(0.0, 0.0); len]];
    let mut sum = [(0.0f64, 0.0f64); 3];
    let norm = 2.0 / (len as f64).powi(3);
    let (cr, ci) = (w.cos(), -w.sin());
    let mut p = (1.0f64, 0.0f64);
    #[allow(clippy::needless_range_loop)] // i runs past the signal's end, to flush the boxes
    for i in 0..n + delay {
        if i % 4096 == 0 {
            // The exact phasor, now and then, so rounding never builds up.
            let a = -w * i as f64;
            p = (a.cos(), a.sin());
        }
        let v = if i < n { x[i] } else { 0.0 };
        let mut input = (v * p.0, v * p.1);
        p = (p.0 * cr - p.1 * ci, p.0 * ci + p.1 * cr);
        let slot = i % len;
        for s in 0..3 {
            let old = hist[s][slot];
            hist[s][slot] = input;
            sum[s] = (sum[s].0 + input.0 - old.0, sum[s].1 + input.1 - old.1);
            input = sum[s];
        }
        // Output i is centred on input i − delay.
        if i >= delay && (i - delay) % hop == 0 {
            z.push((input.0 * norm, input.1 * norm));
        }
    }
    let rise = (3 * len).div_ceil(hop).max(2);
    Band {
        rate: sig.rate / hop as f64,
        weight,
        box_s: len as f64 / sig.rate,
        z,
        rise,
        scale: 1.0,
    }
}

fn diff(a: (f64, f64), b: (f64, f64)) -> f64 {
    (a.0 - b.0).hypot(a.1 - b.1)
}

/// One bell as heard: its bands, their changes, and its candidate
/// strikes (band sample, onset function over its typical strike).
struct BellHearing {
    bands: Vec<Band>,
    changes: Vec<Vec<f64>>,
    rate: f64,
    candidates: Vec<(usize, f64)>,
    /// The onset function's median over its typical strike.
    floor: f64,
}

fn hear_bell(mut bands: Vec<Band>, opts: &StrikeOptions) -> BellHearing {
    let n = bands.iter().map(|b| b.z.len()).min().unwrap_or(0);
    let rate = bands.first().map_or(BAND_RATE, |b| b.rate);
    let sep = (opts.min_separation_s * rate) as usize;
    // Each band's change across a step's rise, and its typical size.
    let changes: Vec<Vec<f64>> = bands.iter().map(|b| change(b)[..n].to_vec()).collect();
    for (b, c) in bands.iter_mut().zip(&changes) {
        b.scale = typical_peak(c, sep);
    }
    let wsum: f64 = bands.iter().map(|b| b.weight).sum::<f64>().max(1e-300);
    let onset: Vec<f64> = (0..n)
        .map(|m| {
            bands
                .iter()
                .zip(&changes)
                .map(|(b, c)| b.weight * c[m] / b.scale)
                .sum::<f64>()
                / wsum
        })
        .collect();
    let typical = typical_peak(&onset, sep);
    let candidates = local_peaks(&onset, sep)
        .into_iter()
        .map(|m| (m, onset[m] / typical))
        .collect();
    let mut sorted = onset.clone();
    sorted.sort_by(f64::total_cmp);
    let floor = sorted.get(sorted.len() / 2).copied().unwrap_or(0.0) / typical;
    BellHearing {
        bands,
        changes,
        rate,
        candidates,
        floor,
    }
}

/// A strike's typical height in `v`: the 90th percentile of its peaks
/// (a bell strikes about once in every four of them).
fn typical_peak(v: &[f64], sep: usize) -> f64 {
    let mut h: Vec<f64> = local_peaks(v, sep).iter().map(|&m| v[m]).collect();
    h.sort_by(f64::total_cmp);
    h.get(h.len() * 9 / 10).copied().filter(|v| *v > 0.0).unwrap_or(1.0)
}

impl BellHearing {
    /// The strikes: (onset s, strength, double strike).
    fn strikes(&self, opts: &StrikeOptions) -> Vec<(f64, f64, Option<HeardDouble>)> {
        let heights: Vec<f64> = self.candidates.iter().map(|c| c.1).collect();
        let Some(threshold) = strike_threshold(&heights, self.floor) else {
            return vec![];
        };
        self.candidates
            .iter()
            .filter(|c| c.1 >= threshold)
            .filter_map(|&(m, h)| {
                let t0 = onset_time(&self.bands, &self.changes, m)?;
                let double = second_strike(&self.bands, t0, opts);
                Some((t0, h, double))
            })
            .collect()
    }
}

/// The band's change across a rise at each sample: the mean of `z` over
/// a rise's length just after the rise centred there, less its mean over
/// as long just before. A strike of this bell is a lasting step and gives
/// its full size, at its onset; another bell's strike only passes through
/// the band for the length of the smoothing (its partials switching on),
/// and averages away.
fn change(b: &Band) -> Vec<f64> {
    let n = b.z.len();
    let g = b.rise.div_ceil(2);
    let w = b.rise;
    let mut cum = vec![(0.0, 0.0); n + 1];
    for (k, z) in b.z.iter().enumerate() {
        cum[k + 1] = (cum[k].0 + z.0, cum[k].1 + z.1);
    }
    // Mean of z[a..b].
    let mean = |a: usize, e: usize| {
        let d = (e - a) as f64;
        ((cum[e].0 - cum[a].0) / d, (cum[e].1 - cum[a].1) / d)
    };
    let valid = |m: usize| m + 1 >= g + w && m + g + w <= n;
    let pairs: Vec<((f64, f64), (f64, f64))> = (0..n)
        .map(|m| {
            if valid(m) {
                (mean(m + g, m + g + w), mean(m + 1 - g - w, m + 1 - g))
            } else {
                ((0.0, 0.0), (0.0, 0.0))
            }
        })
        .collect();
    let rho = decay_ratio(&pairs);
    pairs
        .iter()
        .map(|&(after, before)| {
            let pred = (rho.0 * before.0 - rho.1 * before.1, rho.0 * before.1 + rho.1 * before.0);
            diff(after, pred)
        })
        .collect()
}

/// What a freely ringing partial's mean after becomes of its mean before:
/// the complex ratio (its decay and its small turning, the band being a
/// little off its frequency), as the median over the loudest half of the
/// recording, where the bell is ringing and not struck.
/// A complex number as (re, im).
type C = (f64, f64);

fn decay_ratio(pairs: &[(C, C)]) -> C {
    let mut level: Vec<f64> = pairs.iter().map(|p| p.1 .0.hypot(p.1 .1)).collect();
    level.sort_by(f64::total_cmp);
    let floor = level.get(level.len() / 2).copied().unwrap_or(0.0);
    let (mut re, mut im): (Vec<f64>, Vec<f64>) = pairs
        .iter()
        .filter(|p| p.1 .0.hypot(p.1 .1) > floor && floor > 0.0)
        .map(|&(a, b)| {
            let d = b.0 * b.0 + b.1 * b.1;
            ((a.0 * b.0 + a.1 * b.1) / d, (a.1 * b.0 - a.0 * b.1) / d)
        })
        .unzip();
    if re.is_empty() {
        return (1.0, 0.0);
    }
    re.sort_by(f64::total_cmp);
    im.sort_by(f64::total_cmp);
    (re[re.len() / 2], im[im.len() / 2])
}

/// Indices of the local maxima of `v` that are the largest within `sep`
/// either side (ties to the earliest).
fn local_peaks(v: &[f64], sep: usize) -> Vec<usize> {
    let mut out = vec![];
    let mut m = 0;
    while m < v.len() {
        let lo = m.saturating_sub(sep);
        let hi = (m + sep + 1).min(v.len());
        // The maximum of the window: if it is m, m is a peak; else jump to it.
        let best = (lo..hi).fold(lo, |b, k| if v[k] > v[b] { k } else { b });
        if best == m && v[m] > 0.0 {
            out.push(m);
            m += sep + 1;
        } else if best > m {
            m = best;
        } else {
            m += 1;
        }
    }
    out
}

/// The height that parts strikes from the rest (heights over the typical
/// strike): Otsu's split of the peaks' logarithms, if the two groups stand
/// a factor 2 apart. If they do not, the peaks are all alike: all strikes
/// when the typical one stands five times above the onset function's
/// median `floor` (nothing else came between them), else nothing (the
/// bell was not heard).
fn strike_threshold(heights: &[f64], floor: f64) -> Option<f64> {
    let mut l: Vec<f64> = heights.iter().filter(|h| **h > 0.0).map(|h| h.log10()).collect();
    if l.len() < 2 {
        return (floor < 0.2 && !l.is_empty()).then_some(0.3);
    }
    l.sort_by(f64::total_cmp);
    let n = l.len() as f64;
    let total: f64 = l.iter().sum();
    let mut best = (f64::NEG_INFINITY, 0usize);
    let mut left = 0.0;
    for k in 1..l.len() {
        left += l[k - 1];
        let (n1, n2) = (k as f64, n - k as f64);
        let (m1, m2) = (left / n1, (total - left) / n2);
        let between = n1 * n2 * (m1 - m2).powi(2);
        if between > best.0 {
            best = (between, k);
        }
    }
    let k = best.1;
    let m1 = l[..k].iter().sum::<f64>() / k as f64;
    let m2 = l[k..].iter().sum::<f64>() / (l.len() - k) as f64;
    if m2 - m1 < 0.3 {
        return (floor < 0.2).then_some(0.3);
    }
    let high_median = l[k + (l.len() - k) / 2];
    Some(10f64.powf(0.5 * (l[k - 1] + l[k])).max(0.2 * 10f64.powf(high_median)))
}

/// The onset near band sample `m` (s): in each band where the strike is
/// heard, where `z` has moved half-way from its mean before the rise to
/// its mean after; the weighted median over bands, shorter boxes
/// weighing more.
fn onset_time(bands: &[Band], changes: &[Vec<f64>], m: usize) -> Option<f64> {
    let mut est: Vec<(f64, f64)> = vec![];
    for (b, c) in bands.iter().zip(changes) {
        let g = b.rise.div_ceil(2);
        let w = b.rise;
        let lo = m.saturating_sub(g);
        let hi = (m + g).min(c.len() - 1);
        let top = (lo..=hi).fold(lo, |best, k| if c[k] > c[best] { k } else { best });
        if top + 1 < g + w || top + g + w > b.z.len() || c[top] < 0.3 * b.scale {
            continue;
        }
        let avg = |a: usize, e: usize| {
            let s = b.z[a..e].iter().fold((0.0, 0.0), |s, z| (s.0 + z.0, s.1 + z.1));
            (s.0 / (e - a) as f64, s.1 / (e - a) as f64)
        };
        let before = avg(top + 1 - g - w, top + 1 - g);
        let after = avg(top + g, top + g + w);
        // Along the line from before to after: where is z half-way?
        let (dx, dy) = (after.0 - before.0, after.1 - before.1);
        let len2 = dx * dx + dy * dy;
        if len2 <= 0.0 {
            continue;
        }
        let progress = |k: usize| ((b.z[k].0 - before.0) * dx + (b.z[k].1 - before.1) * dy) / len2;
        let mut prev = progress(top - g);
        for k in top + 1 - g..=top + g {
            let p = progress(k);
            if p >= 0.5 {
                let frac = if p > prev { (0.5 - prev) / (p - prev) } else { 0.0 };
                let t = (k as f64 - 1.0 + frac.clamp(0.0, 1.0)) / b.rate;
                let weight = b.weight * (c[top] / b.scale).min(2.0) / b.box_s;
                est.push((t, weight));
                break;
            }
            prev = p;
        }
    }
    weighted_median(&mut est)
}

fn weighted_median(v: &mut [(f64, f64)]) -> Option<f64> {
    if v.is_empty() {
        return None;
    }
    v.sort_by(|a, b| a.0.total_cmp(&b.0));
    let total: f64 = v.iter().map(|p| p.1).sum();
    let mut acc = 0.0;
    for p in v.iter() {
        acc += p.1;
        if acc >= 0.5 * total {
            return Some(p.0);
        }
    }
    v.last().map(|p| p.0)
}

/// The smoothing's step response `dt` (s) after the step, for three
/// boxes of `box_s` (s).
fn step_response(dt: f64, box_s: f64) -> f64 {
    // Three boxes make a quadratic B-spline kernel over ±1.5 box lengths;
    // its integral in closed form.
    let u = dt / box_s + 1.5;
    if u <= 0.0 {
        0.0
    } else if u < 1.0 {
        u.powi(3) / 6.0
    } else if u < 2.0 {
        (-2.0 * u.powi(3) + 9.0 * u * u - 9.0 * u + 3.0) / 6.0
    } else if u < 3.0 {
        1.0 - (3.0 - u).powi(3) / 6.0
    } else {
        1.0
    }
}

/// A second strike within the double-strike window after `t0` (s): in
/// each band whose steps are short enough, the change fitted as a level,
/// a first step (with a slope for its decay) and a second step, scanned
/// over the window; the second step's size over the first's, its median
/// over the bands, must reach the option's ratio, with the fit's error
/// halved or better.
fn second_strike(bands: &[Band], t0: f64, opts: &StrikeOptions) -> Option<HeardDouble> {
    let (dmin, dmax) = (opts.double_window_ms.0 * 1e-3, opts.double_window_ms.1 * 1e-3);
    let rate = bands.first()?.rate;
    let m0 = t0 * rate;
    let steps = ((dmax - dmin) * rate).round() as usize + 1;
    // Per delay tried (band-sample steps), per band heard at it: (error
    // with one step, error with two, second step over first).
    let mut per_delay: Vec<Vec<(f64, f64, f64, f64)>> = vec![vec![]; steps];
    // Only bands mostly the bell's own: a shared band hears the next bell.
    let wmax = bands.iter().map(|b| b.weight).fold(0.0, f64::max);
    for b in bands.iter().filter(|b| b.weight >= 0.3 * wmax) {
        // A second step is told from the first once the first has risen (3 boxes).
        let first_delay = 3.0 * b.box_s;
        if first_delay > dmax {
            continue;
        }
        let lo = (m0 - 1.5 * b.box_s * rate).floor().max(0.0) as usize;
        let hi = ((m0 + (dmax + 1.5 * b.box_s) * rate).ceil() as usize).min(b.z.len().saturating_sub(1));
        if hi <= lo + 8 {
            continue;
        }
        let zs = &b.z[lo..=hi];
        let ones = vec![1.0; zs.len()];
        // The first step where it fits best, within a band sample of t0.
        let first = [-1.0, 0.0, 1.0]
            .iter()
            .map(|shift| {
                let ts: Vec<f64> = (lo..=hi).map(|k| (k as f64 - shift) / rate - t0).collect();
                let s1: Vec<f64> = ts.iter().map(|&t| step_response(t, b.box_s)).collect();
                let ramp: Vec<f64> = ts.iter().zip(&s1).map(|(t, v)| v * t.max(0.0)).collect();
                let (e1, c1) = fit(&[&ones, &s1, &ramp], zs);
                (e1, c1[1].0.hypot(c1[1].1), ts, s1, ramp)
            })
            .min_by(|a, b| a.0.total_cmp(&b.0));
        let Some((e1, a1, ts, s1, ramp)) = first else {
            continue;
        };
        if a1 <= 0.0 {
            continue;
        }
        for (j, slot) in per_delay.iter_mut().enumerate() {
            let d = dmin + j as f64 / rate;
            if d < first_delay {
                continue;
            }
            let s2: Vec<f64> = ts.iter().map(|&t| step_response(t - d, b.box_s)).collect();
            let (e2, c2) = fit(&[&ones, &s1, &ramp, &s2], zs);
            // The same rise spread over three times as long: a room's
            // reverberation builds up so; a clapper's second strike does not.
            let slow: Vec<f64> = ts.iter().map(|&t| step_response(t - d, 3.0 * b.box_s)).collect();
            let (e_slow, _) = fit(&[&ones, &s1, &ramp, &slow], zs);
            let a1b = c2[1].0.hypot(c2[1].1);
            let ratio = if a1b > 0.0 { c2[3].0.hypot(c2[3].1) / a1b } else { 0.0 };
            slot.push((e1 / (a1 * a1), e2 / (a1 * a1), ratio, e_slow / (a1 * a1)));
        }
    }
    // The delay where a second step explains most of what one step leaves.
    let (j, gain) = per_delay
        .iter()
        .enumerate()
        .filter(|(_, v)| !v.is_empty())
        .map(|(j, v)| {
            let e1: f64 = v.iter().map(|x| x.0).sum();
            let e2: f64 = v.iter().map(|x| x.1).sum();
            (j, if e1 > 0.0 { 1.0 - e2 / e1 } else { 0.0 })
        })
        .max_by(|a, b| a.1.total_cmp(&b.1))?;
    let e2: f64 = per_delay[j].iter().map(|x| x.1).sum();
    let e_slow: f64 = per_delay[j].iter().map(|x| x.3).sum();
    // A sharp step must explain clearly more than a slow rise.
    let sharp = e2 < e_slow;
    let mut r: Vec<f64> = per_delay[j].iter().map(|x| x.2).collect();
    r.sort_by(f64::total_cmp);
    let ratio = r[r.len() / 2];
    (ratio >= opts.double_min_ratio && gain >= 0.5 && sharp).then_some(HeardDouble {
        delay_s: dmin + j as f64 / rate,
        amplitude_ratio: ratio,
    })
}

/// Least squares of complex data on real basis functions: (squared
/// error, coefficients).
fn fit(basis: &[&Vec<f64>], z: &[(f64, f64)]) -> (f64, Vec<(f64, f64)>) {
    let k = basis.len();
    let mut g = vec![vec![0.0; k]; k];
    let mut r = vec![(0.0, 0.0); k];
    for i in 0..k {
        for j in 0..=i {
            let v: f64 = basis[i].iter().zip(basis[j].iter()).map(|(a, b)| a * b).sum();
            g[i][j] = v;
            g[j][i] = v;
        }
        r[i] = basis[i]
            .iter()
            .zip(z)
            .fold((0.0, 0.0), |acc, (a, zz)| (acc.0 + a * zz.0, acc.1 + a * zz.1));
    }
    let c = solve(g, r);
    let err = z
        .iter()
        .enumerate()
        .map(|(n, zz)| {
            let (mut re, mut im) = *zz;
            for (i, ci) in c.iter().enumerate() {
                re -= basis[i][n] * ci.0;
                im -= basis[i][n] * ci.1;
            }
            re * re + im * im
        })
        .sum();
    (err, c)
}

/// Solve G c = r (G symmetric, small) by Gaussian elimination with
/// pivoting; a singular direction gets 0.
fn solve(mut g: Vec<Vec<f64>>, mut r: Vec<(f64, f64)>) -> Vec<(f64, f64)> {
    let k = r.len();
    let scale = (0..k).map(|i| g[i][i].abs()).fold(0.0, f64::max).max(1e-300);
    for col in 0..k {
        let p = (col..k)
            .max_by(|&a, &b| g[a][col].abs().total_cmp(&g[b][col].abs()))
            .unwrap_or(col);
        g.swap(col, p);
        r.swap(col, p);
        if g[col][col].abs() < 1e-12 * scale {
            continue;
        }
        for row in col + 1..k {
            let f = g[row][col] / g[col][col];
            let pivot = g[col].clone();
            for (gc, pc) in g[row].iter_mut().zip(&pivot).skip(col) {
                *gc -= f * pc;
            }
            r[row] = (r[row].0 - f * r[col].0, r[row].1 - f * r[col].1);
        }
    }
    let mut c = vec![(0.0, 0.0); k];
    for i in (0..k).rev() {
        if g[i][i].abs() < 1e-12 * scale {
            continue;
        }
        let mut v = r[i];
        for j in i + 1..k {
            v = (v.0 - g[i][j] * c[j].0, v.1 - g[i][j] * c[j].1);
        }
        c[i] = (v.0 / g[i][i], v.1 / g[i][i]);
    }
    c
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_closed_form_step_is_three_boxes_summed_out() {
        // Three boxes of 41 samples convolved numerically, then summed: the
        // step response, against the closed form at the same offsets.
        let len = 41;
        let mut k = vec![1.0 / len as f64; len];
        for _ in 0..2 {
            let mut next = vec![0.0; k.len() + len - 1];
            for (i, a) in k.iter().enumerate() {
                for j in 0..len {
                    next[i + j] += a / len as f64;
                }
            }
            k = next;
        }
        let centre = (k.len() - 1) as f64 / 2.0;
        let mut sum = 0.0;
        for (i, v) in k.iter().enumerate() {
            // Half of this sample's weight lies before its centre.
            let s = sum + 0.5 * v;
            sum += v;
            let closed = step_response(i as f64 - centre, len as f64);
            assert!((s - closed).abs() < 2e-3, "at {i}: {s} against {closed}");
        }
        assert!((sum - 1.0).abs() < 1e-12);
        assert_eq!(step_response(-1.6, 1.0), 0.0);
        assert_eq!(step_response(1.6, 1.0), 1.0);
        assert!((step_response(0.0, 1.0) - 0.5).abs() < 1e-12);
    }

    #[test]
    fn a_band_is_centred_and_reads_a_tone_at_its_amplitude() {
        // A 1000 Hz tone switched on at 0.5 s: its band holds the tone's
        // amplitude, and is half-way up at the switch (no delay).
        let rate = 8000.0;
        let on = 4000;
        let samples: Vec<f64> = (0..16_000)
            .map(|i| {
                if i >= on {
                    0.3 * (2.0 * PI * 1000.0 * i as f64 / rate).sin()
                } else {
                    0.0
                }
            })
            .collect();
        let b = band(&Signal { rate, samples }, 1000.0, 1.0, 81);
        let at = |t: f64| {
            let z = b.z[(t * b.rate).round() as usize];
            z.0.hypot(z.1)
        };
        assert!((at(1.5) - 0.3).abs() < 1e-6, "{}", at(1.5));
        assert!((at(0.5) - 0.15).abs() < 0.3 * 0.02, "{}", at(0.5));
        assert!(at(0.45) < 1e-9);
    }
}
