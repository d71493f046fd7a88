//! The bells' nominals learned from a recording of the ring alone
//! (`clapper strikes --bells N`, docs/strikes.md): what a ringer with a
//! phone has is the recording and the number of bells.
//!
//! Every strike makes its bell's partials rise together, its nominal most
//! (the strongest partial of a tuned bell as heard). So at each onset of
//! the recording (a peak of the spectral rise) the partial that rose most
//! is noted; each bell's strikes put their nominal there again and again,
//! while its hum, prime, tierce and quint, and the partials above, rise
//! less and are noted seldom. The notes are grouped by frequency; the N
//! groups noted most often are the bells, each group's frequency refined
//! on the mean rise of its own onsets.

use super::band::decimate;
use crate::{Signal, SignalError};

/// One bell learned.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LearnedBell {
    /// Its nominal (Hz).
    pub nominal_hz: f64,
    /// How sure (0 to 1): the onsets its nominal rose most at, against the
    /// typical (median) learned bell's, at most 1: every bell of a ring
    /// strikes as often as the others.
    pub confidence: f64,
    /// The onsets its nominal rose most at.
    pub onsets: usize,
}

/// The bells learned from a recording.
#[derive(Clone, Debug, PartialEq)]
pub struct Learned {
    /// The bells, treble (highest) first; fewer than asked when fewer are heard.
    pub bells: Vec<LearnedBell>,
    /// Onsets heard in the recording.
    pub onsets: usize,
    /// What made it unsure, in words.
    pub warnings: Vec<String>,
}

/// Highest frequency looked at (Hz): above a light ring's treble nominal.
const F_MAX: f64 = 6000.0;
/// Lowest frequency looked at (Hz): below the nominal of a heavy ring's tenor.
const F_MIN: f64 = 150.0;
/// Notes this close (fraction) are one partial (doublets, Doppler, the window).
const SAME: f64 = 0.008;
/// Groups of notes whose mean rises are alike past this (the cosine of
/// their spectra) are one bell's.
const SAME_BELL: f64 = 0.75;
/// A peak of a bell's mean rise this strong against its strongest may be its nominal.
const CANDIDATE: f64 = 0.25;
/// A peak an octave below the one chosen this strong (against the
/// strongest) that fits about as well is the nominal.
const OCTAVE_BELOW: f64 = 0.3;
/// What being the strongest peak counts for, in partials found.
const STRONG: f64 = 4.0;
/// A partial this strong against the strongest is present.
const PRESENT: f64 = 0.1;
/// Learned nominals closer than this (fraction, about two-thirds of a
/// semitone) are warned of: no ring is tuned so close.
const CLOSE: f64 = 0.04;

/// The short-time spectra: magnitudes from `k_lo` to `k_hi` of frames `hop` apart.
pub(super) struct Frames<'a> {
    sig: &'a [f64],
    win: Vec<f64>,
    hop: usize,
    fft: std::sync::Arc<dyn realfft::RealToComplex<f64>>,
    pub(super) k_lo: usize,
    k_hi: usize,
    /// Bin spacing (Hz).
    pub(super) df: f64,
}

impl<'a> Frames<'a> {
    /// About 90 ms windows, zero-padded twice, from [`F_MIN`] to [`F_MAX`]:
    /// long enough to part bells a semitone apart, short enough that bells
    /// 150 ms apart rise in different frames.
    fn of(low: &'a Signal) -> Self {
        Self::up_to(low, F_MAX)
    }

    /// As [`Frames::of`], up to `f_max` (Hz) rather than [`F_MAX`].
    pub(super) fn up_to(low: &'a Signal, f_max: f64) -> Self {
        let rate = low.rate;
        let n_win = ((0.09 * rate) as usize).next_power_of_two();
        let nfft = 2 * n_win;
        let df = rate / nfft as f64;
        let mut planner = realfft::RealFftPlanner::<f64>::new();
        Frames {
            sig: &low.samples,
            win: crate::spectrogram::hann(n_win),
            hop: n_win / 4,
            fft: planner.plan_fft_forward(nfft),
            k_lo: (F_MIN / df).ceil() as usize,
            k_hi: ((f_max.min(0.45 * rate)) / df).floor() as usize,
            df,
        }
    }

    pub(super) fn count(&self) -> usize {
        if self.sig.len() < self.win.len() {
            0
        } else {
            (self.sig.len() - self.win.len()) / self.hop + 1
        }
    }

    /// Pass 1: the spectral rise of every frame over `lag` frames before
    /// it (summed over frequency).
    pub(super) fn flux(&self, lag: usize) -> Vec<f64> {
        let mut flux = vec![0.0; self.count()];
        let mut past: std::collections::VecDeque<Vec<f64>> = std::collections::VecDeque::new();
        for (t, f) in flux.iter_mut().enumerate() {
            let m = self.magnitudes(t);
            if past.len() == lag {
                let old = past.pop_front().unwrap_or_default();
                *f = m.iter().zip(&old).map(|(a, b)| (a - b).max(0.0)).sum();
            }
            past.push_back(m);
        }
        flux
    }

    pub(super) fn magnitudes(&self, t: usize) -> Vec<f64> {
        let mut buf = self.fft.make_input_vec();
        let start = t * self.hop;
        for (i, w) in self.win.iter().enumerate() {
            buf[i] = self.sig[start + i] * w;
        }
        let mut out = self.fft.make_output_vec();
        // The lengths are the plan's own: process cannot fail.
        let _ = self.fft.process(&mut buf, &mut out);
        out[self.k_lo..self.k_hi].iter().map(|c| c.norm()).collect()
    }
}

/// Learn the nominals of the `bells` bells ringing in `sig`.
pub fn learn_nominals(sig: &Signal, bells: usize) -> Result<Learned, SignalError> {
    sig.validate()?;
    if bells == 0 {
        return Err(SignalError::Option("no bells to listen for".into()));
    }
    if sig.rate < 4000.0 || sig.rate > 200_000.0 {
        return Err(SignalError::Option(format!(
            "sample rate {} Hz: 4 to 200 kHz",
            sig.rate
        )));
    }
    let low = decimate(sig, F_MAX);
    let frames = Frames::of(&low);
    let (k_lo, df) = (frames.k_lo, frames.df);
    // The rise is taken over one window (four hops): a strike is wholly in
    // the later frame and not in the earlier.
    let lag = 4;
    let n = frames.count();
    if n < lag + 3 {
        return Err(SignalError::TooShort(
            "learning the bells needs a second of ringing".into(),
        ));
    }
    let onsets = pick_onsets(&frames.flux(lag));
    if onsets.is_empty() {
        return Err(SignalError::Invalid(
            "no strikes heard: the recording is silent or steady".into(),
        ));
    }
    // Pass 2: at each onset, the partial that rose most.
    let rises: Vec<Vec<f64>> = onsets
        .iter()
        .map(|&t| {
            let (a, b) = (frames.magnitudes(t), frames.magnitudes(t - lag));
            a.iter().zip(&b).map(|(x, y)| (x - y).max(0.0)).collect()
        })
        .collect();
    let freq = |k: f64| (k + k_lo as f64) * df;
    let notes: Vec<(f64, usize)> = rises
        .iter()
        .enumerate()
        .filter_map(|(i, d)| peak_of(d).map(|k| (freq(k), i)))
        .collect();
    let groups = group_notes(notes, df);
    let expected = onsets.len() as f64 / bells as f64;
    let bells_heard = same_bells(&groups, &rises, k_lo, df, (0.3 * expected).max(3.0));
    // A bell heard at fewer onsets than this is no bell of the ring.
    let least = (0.3 * expected).max(3.0);
    let mut chosen: Vec<&Heard> = bells_heard.iter().filter(|b| b.onsets.len() as f64 >= least).collect();
    chosen.sort_by_key(|b| std::cmp::Reverse(b.onsets.len()));
    chosen.truncate(bells);
    // A bell's share against the typical learned bell's: every bell of a
    // ring strikes as often as the others (onsets of the room, the noise
    // and strikes heard at another partial are no bell's).
    let typical = median(chosen.iter().map(|b| b.onsets.len() as f64).collect()).max(1.0);
    let in_ring = octaves_into_ring(&chosen.iter().map(|b| b.nominal_hz).collect::<Vec<_>>(), bells);
    let mut learned: Vec<LearnedBell> = chosen
        .iter()
        .zip(in_ring)
        .map(|(b, f)| LearnedBell {
            nominal_hz: refine(&rises, &b.onsets, f, k_lo, df),
            confidence: (b.onsets.len() as f64 / typical).min(1.0),
            onsets: b.onsets.len(),
        })
        .collect();
    learned.sort_by(|a, b| b.nominal_hz.total_cmp(&a.nominal_hz));
    let warnings = warnings_of(&learned, bells);
    Ok(Learned {
        bells: learned,
        onsets: onsets.len(),
        warnings,
    })
}

/// Onset frames: peaks of the rise standing above its neighbours within
/// three frames and above twice its lower quartile.
pub(super) fn pick_onsets(flux: &[f64]) -> Vec<usize> {
    let mut sorted: Vec<f64> = flux.iter().copied().filter(|f| *f > 0.0).collect();
    if sorted.is_empty() {
        return vec![];
    }
    sorted.sort_by(f64::total_cmp);
    let low = sorted[sorted.len() / 4];
    let top = sorted[sorted.len() - 1];
    // A recording of noise alone rises by chance a little everywhere; a
    // strike rises far above the lower quartile (not the median: in fast
    // ringing half the frames or more are rising).
    let floor = (2.0 * low).max(1e-3 * top);
    (4..flux.len())
        .filter(|&t| {
            let lo = t.saturating_sub(3);
            let hi = (t + 4).min(flux.len());
            flux[t] > floor && (lo..hi).all(|u| u == t || flux[u] < flux[t] || (flux[u] == flux[t] && u > t))
        })
        .collect()
}

/// The bin (fractional) of the greatest rise, by a parabola through it and
/// its neighbours.
fn peak_of(d: &[f64]) -> Option<f64> {
    let (k, &m) = d.iter().enumerate().max_by(|a, b| a.1.total_cmp(b.1))?;
    if m <= 0.0 {
        return None;
    }
    if k == 0 || k + 1 >= d.len() {
        return Some(k as f64);
    }
    let (a, b, c) = (d[k - 1], d[k], d[k + 1]);
    let den = a - 2.0 * b + c;
    let off = if den != 0.0 { 0.5 * (a - c) / den } else { 0.0 };
    Some(k as f64 + off.clamp(-0.5, 0.5))
}

/// Notes (Hz, onset) grouped where they lie within [`SAME`] (or one and a
/// half bins of `df` Hz, low down) of the next.
fn group_notes(mut notes: Vec<(f64, usize)>, df: f64) -> Vec<Vec<(f64, usize)>> {
    notes.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut groups: Vec<Vec<(f64, usize)>> = vec![];
    for n in notes {
        match groups.last_mut() {
            Some(g) if g.last().is_some_and(|l| n.0 - l.0 <= (SAME * n.0).max(1.5 * df)) => g.push(n),
            _ => groups.push(vec![n]),
        }
    }
    groups
}

fn median(mut v: Vec<f64>) -> f64 {
    if v.is_empty() {
        return 0.0;
    }
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// A group's frequency from the mean rise over its onsets: the peak within
/// 2 % of `centre`, by a parabola through the log magnitudes.
fn refine(rises: &[Vec<f64>], onsets: &[usize], centre: f64, k_lo: usize, df: f64) -> f64 {
    let mean = mean_rise(rises, onsets);
    let len = mean.len();
    let bin = |f: f64| ((f / df).round() as usize).saturating_sub(k_lo).min(len - 1);
    let (lo, hi) = (bin(0.98 * centre).max(1), bin(1.02 * centre).min(len - 2));
    let Some(k) = (lo..=hi).max_by(|&a, &b| mean[a].total_cmp(&mean[b])) else {
        return centre;
    };
    if !(mean[k - 1] > 0.0 && mean[k] > 0.0 && mean[k + 1] > 0.0) {
        return centre;
    }
    let (a, b, c) = (mean[k - 1].ln(), mean[k].ln(), mean[k + 1].ln());
    let den = a - 2.0 * b + c;
    let off = if den != 0.0 { 0.5 * (a - c) / den } else { 0.0 };
    (k as f64 + k_lo as f64 + off.clamp(-0.5, 0.5)) * df
}

/// The mean rise over `onsets`.
fn mean_rise(rises: &[Vec<f64>], onsets: &[usize]) -> Vec<f64> {
    let mut mean = vec![0.0; rises[0].len()];
    for &i in onsets {
        mean.iter_mut().zip(&rises[i]).for_each(|(m, r)| *m += r);
    }
    mean
}

/// A bell heard: its nominal (Hz, as noted) and the onsets that were its strikes.
struct Heard {
    nominal_hz: f64,
    onsets: Vec<usize>,
}

/// A tuned bell's partials as heard in recordings, as ranges of the
/// ratio to the nominal: hum, prime, tierce, quint, superquint, octave
/// nominal, the partial at 2.5-2.7, the twelfth and the double octave
/// (docs/strikes.md, "What real bells sound like": the recorded tower
/// bells' upper partials at 2.0, 2.4-2.7, 3.0 and 4.05-4.15 times their
/// nominal, often stronger than it).
const PARTIAL_RANGES: [(f64, f64); 9] = [
    (0.24, 0.26),
    (0.485, 0.515),
    (0.58, 0.61),
    (0.73, 0.77),
    (1.45, 1.58),
    (1.97, 2.03),
    (2.4, 2.75),
    (2.9, 3.1),
    (3.95, 4.2),
];

/// The groups of notes that are one bell's: its strikes' rise is the same
/// across the spectrum whichever of its partials rose most. Largest
/// first, a group whose mean rise is like a bell's first group's joins it;
/// else one noted at `big` onsets or more is a new bell. Each bell's
/// nominal is then the peak of its mean rise with the most of a tuned
/// bell's other partials at their ratios to it ([`PARTIAL_RANGES`]), the
/// strongest among equals (handbells have only a twelfth).
fn same_bells(groups: &[Vec<(f64, usize)>], rises: &[Vec<f64>], k_lo: usize, df: f64, big: f64) -> Vec<Heard> {
    let means: Vec<Vec<f64>> = groups
        .iter()
        .map(|g| {
            let m = mean_rise(rises, &g.iter().map(|x| x.1).collect::<Vec<_>>());
            let norm = m.iter().map(|v| v * v).sum::<f64>().sqrt().max(1e-300);
            m.into_iter().map(|v| v / norm).collect()
        })
        .collect();
    let cos = |i: usize, j: usize| -> f64 { means[i].iter().zip(&means[j]).map(|(a, b)| a * b).sum() };
    // Largest first, each group joins the bell whose first group it is
    // most like (no chains of likeness: a partial two bells share is like
    // both), or, if large enough, is a bell of its own.
    let mut order: Vec<usize> = (0..groups.len()).collect();
    order.sort_by_key(|&a| std::cmp::Reverse(groups[a].len()));
    let mut members: Vec<Vec<usize>> = vec![];
    for i in order {
        let like = members
            .iter()
            .enumerate()
            .map(|(m, g)| (m, cos(i, g[0])))
            .max_by(|a, b| a.1.total_cmp(&b.1));
        match like {
            // A group noted at most of a bell's strikes is a bell's nominal,
            // even if like another's (an octave's prime is its nominal).
            Some((m, c)) if c > SAME_BELL && (groups[i].len() as f64) < 2.0 * big => members[m].push(i),
            _ if groups[i].len() as f64 >= big => members.push(vec![i]),
            _ => {}
        }
    }
    let mut out: Vec<Heard> = vec![];
    for m in members {
        let onsets: Vec<usize> = m.iter().flat_map(|&i| groups[i].iter().map(|x| x.1)).collect();
        let Some(nominal_hz) = nominal_of(&mean_rise(rises, &onsets), k_lo, df) else {
            continue;
        };
        // Two bells found at one nominal are one bell heard two ways.
        match out
            .iter_mut()
            .find(|h| (h.nominal_hz - nominal_hz).abs() < 2.0 * SAME * nominal_hz)
        {
            Some(h) => h.onsets.extend(onsets),
            None => out.push(Heard { nominal_hz, onsets }),
        }
    }
    out
}

/// The nominal in one bell's mean rise (bins from `k_lo`, `df` Hz apart):
/// the peak with the most partials at a tuned bell's ratios to it, its
/// strength counting for up to [`STRONG`] more.
fn nominal_of(mean: &[f64], k_lo: usize, df: f64) -> Option<f64> {
    let top = mean.iter().copied().fold(0.0, f64::max);
    if top <= 0.0 {
        return None;
    }
    let bin = |f: f64| (f / df).round() as isize - k_lo as isize;
    let present = |lo: f64, hi: f64| {
        let (a, b) = (bin(lo).max(0), bin(hi).min(mean.len() as isize - 1));
        a <= b && (a..=b).any(|k| mean[k as usize] >= PRESENT * top)
    };
    let score = |f: f64| PARTIAL_RANGES.iter().filter(|(lo, hi)| present(lo * f, hi * f)).count();
    let peaks: Vec<(f64, usize, f64)> = (1..mean.len() - 1)
        .filter(|&k| mean[k] >= CANDIDATE * top && mean[k] >= mean[k - 1] && mean[k] > mean[k + 1])
        .map(|k| {
            let f = (k + k_lo) as f64 * df;
            (f, score(f), mean[k])
        })
        .collect();
    // Another bell's partials rising nearby fill a range now and then: a
    // strong peak is taken over a weak one with one partial more.
    let value = |p: &(f64, usize, f64)| p.1 as f64 + STRONG * p.2 / top;
    let best = peaks.iter().max_by(|a, b| value(a).total_cmp(&value(b)))?;
    // Recorded tower bells' upper partials (at 1.18, 1.56, 2.7, 3 and 4
    // times the nominal) fit an octave nominal as well as the nominal: a
    // strong peak an octave below that fits about as well is the nominal
    // (a synthetic bell's prime, an octave below, fits far worse).
    let below = peaks
        .iter()
        .find(|p| (p.0 / best.0 - 0.5).abs() < 0.01 && p.2 >= OCTAVE_BELOW * top && p.1 + 1 >= best.1);
    Some(below.unwrap_or(best).0)
}

/// Semitones from the tenor to the treble of a ring of `bells` tuned to
/// a major scale (the widest diatonic ring), a tone more for the sharp
/// trebles of real rings.
fn ring_span(bells: usize) -> f64 {
    const MAJOR: [f64; 16] = [0., 2., 4., 5., 7., 9., 11., 12., 14., 16., 17., 19., 21., 23., 24., 26.];
    MAJOR[bells.clamp(1, 16) - 1] + 2.0
}

/// The nominals `f` moved by octaves into the ring: the bells of a ring
/// span at most [`ring_span`] semitones, so a nominal an octave or two
/// outside the span that holds the most of the others was a prime or hum
/// (or an octave nominal) taken for it, and is moved by whole octaves
/// into the span where that lands on no other.
fn octaves_into_ring(f: &[f64], bells: usize) -> Vec<f64> {
    let ratio = 2f64.powf(ring_span(bells) / 12.0);
    let Some(low) = f
        .iter()
        .copied()
        .max_by_key(|&lo| f.iter().filter(|&&g| g >= lo * 0.99 && g <= lo * ratio * 1.01).count())
    else {
        return vec![];
    };
    let inside = |g: f64| g >= low * 0.99 && g <= low * ratio * 1.01;
    let kept: Vec<f64> = f.iter().copied().filter(|&g| inside(g)).collect();
    let (lo, hi) = kept.iter().fold((f64::MAX, 0.0f64), |(a, b), &g| (a.min(g), b.max(g)));
    f.iter()
        .map(|&g| {
            if inside(g) {
                return g;
            }
            // The fewest octaves that bring it within the span of the others.
            [2.0, 0.5, 4.0, 0.25]
                .iter()
                .map(|m| g * m)
                .find(|&h| h.max(hi) <= h.min(lo) * ratio * 1.01 && f.iter().all(|&o| (o - h).abs() > CLOSE * h))
                .unwrap_or(g)
        })
        .collect()
}

/// Warnings: fewer bells heard than asked, a bell heard seldom, two close.
fn warnings_of(learned: &[LearnedBell], bells: usize) -> Vec<String> {
    let mut w = vec![];
    if learned.len() < bells {
        w.push(format!(
            "{bells} bells asked for, but only {} nominal(s) heard again and again: fewer bells ring, or some are too faint",
            learned.len()
        ));
    }
    for (i, b) in learned.iter().enumerate() {
        if b.confidence < 0.5 {
            w.push(format!(
                "bell {} ({:.1} Hz): its nominal rose most at only {} onsets, {:.0} % of a typical bell's: unsure",
                i + 1,
                b.nominal_hz,
                b.onsets,
                100.0 * b.confidence
            ));
        }
    }
    for p in learned.windows(2) {
        if p[0].nominal_hz - p[1].nominal_hz < CLOSE * p[0].nominal_hz {
            w.push(format!(
                "two nominals learned close together ({:.1} and {:.1} Hz): one may be another bell's partial",
                p[0].nominal_hz, p[1].nominal_hz
            ));
        }
    }
    w
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tower::{major_scale, tower_recording, tuned_ring, Doublets, Room, Scale, TowerSpec, Voice};

    /// The worst error (%) of the nominals learned from `spec`'s ring
    /// against its true ones, and the warnings.
    fn worst_error(spec: &TowerSpec) -> (f64, Vec<String>) {
        let (sig, _) = tower_recording(spec).unwrap();
        let n = spec.bells.len();
        let l = learn_nominals(&sig, n).unwrap();
        let got: Vec<String> = l
            .bells
            .iter()
            .map(|b| format!("{:.1} ({:.2})", b.nominal_hz, b.confidence))
            .collect();
        eprintln!("{n} bells seed {}: learned {}", spec.seed, got.join(", "));
        if l.bells.len() < n {
            return (f64::INFINITY, l.warnings);
        }
        let worst = spec
            .bells
            .iter()
            .zip(&l.bells)
            .map(|(t, b)| 100.0 * (b.nominal_hz / t.nominal_hz - 1.0).abs())
            .fold(0.0, f64::max);
        (worst, l.warnings)
    }

    // Seeds 1-2 (tenor 500 Hz) were used while choosing the parameters;
    // 11-12 (tenor 600 Hz) are reported. Ten and twelve bells are printed,
    // not asserted: a tierce or prime is still taken for a low bell's
    // nominal at times (docs/strikes.md, "--bells N").
    #[test]
    fn learns_tuned_rings_within_one_percent() {
        let mut failed = vec![];
        for seed in [11, 12] {
            for (n, scale) in [
                (6, Scale::Major),
                (8, Scale::Minor),
                (10, Scale::Major),
                (12, Scale::Minor),
            ] {
                let spec = TowerSpec {
                    seed,
                    rows: 16,
                    interval: 2.0 / (n as f64 + 1.0),
                    doublets: Some(Doublets::REAL),
                    room: Some(Room::chamber(0.8)),
                    snr_db: Some(20.0),
                    ..TowerSpec::new(tuned_ring(n, 600.0, scale).unwrap())
                };
                let (worst, warnings) = worst_error(&spec);
                eprintln!("{n} bells seed {seed}: worst {worst:.2} %; {warnings:?}");
                if n <= 8 && !(worst < 1.0 && warnings.is_empty()) {
                    failed.push((n, seed, worst, warnings));
                }
            }
        }
        assert!(failed.is_empty(), "{failed:?}");
    }

    #[test]
    fn learns_handbells_within_one_percent() {
        let spec = TowerSpec {
            seed: 11,
            rows: 16,
            voice: Voice::Handbell,
            ..TowerSpec::new(major_scale(8, 1400.0).unwrap())
        };
        let (worst, warnings) = worst_error(&spec);
        assert!(worst < 1.0, "worst {worst:.2} %; {warnings:?}");
    }

    #[test]
    fn too_many_bells_asked_is_warned_of() {
        let spec = TowerSpec {
            rows: 16,
            ..TowerSpec::new(major_scale(6, 1400.0).unwrap())
        };
        let (sig, _) = tower_recording(&spec).unwrap();
        let l = learn_nominals(&sig, 10).unwrap();
        assert!(l.bells.len() < 10, "{:?}", l.bells);
        assert!(
            l.warnings.iter().any(|w| w.contains("10 bells asked for")),
            "{:?}",
            l.warnings
        );
    }

    #[test]
    fn silence_is_refused_in_words() {
        let sig = Signal {
            rate: 22050.0,
            samples: vec![0.0; 22050 * 5],
        };
        let e = learn_nominals(&sig, 6).unwrap_err().to_string();
        assert!(e.contains("no strikes heard"), "{e}");
    }
}
