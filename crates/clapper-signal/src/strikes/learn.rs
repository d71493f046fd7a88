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
use super::learn_gaps::{ringing, unheard_notes, Heard, IN_TUNE};
use super::learn_pick::{apart, mean_rise};
use super::learn_scale::{octave_fits, octaves_into_ring, ring_octaves, OCTAVES};
use super::learn_sure::{
    bell_sure, bells_as_sure_as_their_set, doubt_first, doubt_of_set, learned_set_sure, octave_share, ring_size,
    rival_doubt, rival_sure, sounds, warnings_of, DOUBTFUL,
};
use crate::{Signal, SignalError};

/// One bell learned.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LearnedBell {
    /// Its nominal (Hz).
    pub nominal_hz: f64,
    /// How sure (0 to 1): its `support` (`learn_sure`), less where a step
    /// to a neighbour is no whole number of semitones, no surer than the
    /// set where that is doubtful; 0 for a note of the ring guessed, no
    /// bell heard there.
    pub confidence: f64,
    /// The onsets its nominal rose most at.
    pub onsets: usize,
    /// Its onsets against the typical (median) learned bell's, at most 1:
    /// every bell of a ring strikes as often as the others.
    pub support: f64,
    /// How well its strikes' partials fit a tuned bell's with this
    /// nominal, against the best octave of it (0 to 1; 1: it fits best here).
    pub partials_fit: f64,
}

/// The bells learned from a recording.
#[derive(Clone, Debug, PartialEq)]
pub struct Learned {
    /// The bells, treble (highest) first; fewer than asked when fewer are heard.
    pub bells: Vec<LearnedBell>,
    /// Onsets heard in the recording.
    pub onsets: usize,
    /// How sure the set is (0 to 1): its bells heard's mean confidence
    /// times their share, doubtful with a note guessed or fewer bells
    /// learned than asked, less where the onsets' rhythm says another
    /// number of bells ring or two neighbours step oddly (`learn_sure`).
    pub confidence: f64,
    /// How many bells ring, from the onsets' rhythm (`None` if it says nothing).
    pub ringing: Option<f64>,
    /// What made it unsure, in words.
    pub warnings: Vec<String>,
    /// The bells asked for.
    pub asked: usize,
    /// Far fewer bells heard than asked: each sound heard is a bell, no
    /// note guessed for the rest (one bell struck again and again).
    pub few: bool,
    /// How far the ring learned fits its bells' partials better than the
    /// best other ring of the scale (a sum of bells' fits, 0 to about one
    /// a bell; infinite where no other ring fits or no scale was chosen):
    /// near 0 the recording fits another set of nominals as well, and the
    /// set is no surer than `rival_sure` of it (the margin over 0.2).
    pub margin: f64,
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
/// A bell is heard at this share of the onsets one bell of the ring has, at least.
const LEAST: f64 = 0.3;
/// Onsets at one nominal this many times one bell's are two bells'.
const ONE_BELL: f64 = 1.5;
/// The segments after and before a strike its nominal is measured late in (s).
const LATE_S: f64 = 0.3;
/// A nominal measured late lies within this (fraction) of the one heard as its strikes rose.
const LATE_WIDTH: f64 = 0.015;
/// At most about this many of a bell's strikes are measured late (spread evenly).
const LATE_MOST: usize = 40;
/// A bell on an empty note rises there at least this share of its onset's highest rise.
const EMPTY_RISE: f64 = 0.3;
/// Bells heard (before they are gathered into sounds) this many times
/// or fewer than asked for are all that ring: no note is guessed.
const FEW: usize = 3;
/// Bells heard beyond those asked for that the ring's scale may choose among.
const SPARE: usize = 3;
/// Onsets a second (1/s) under which the rise's floor is lowered to
/// [`FAST_FLOOR`]: the slowest ring (a twelve's tenor at 0.3 s an
/// interval) strikes about three times a second, so under 2.5 at least
/// one strike in six is unheard. 1.5 left an eight 0.21 s apart in a room
/// (RT60 0.8 s, recorded bells: 1.55 onsets a second of its 4.4 strikes)
/// at its first floor, and `--bells 8` learned four bells' upper partials
/// for their nominals (recall within 10 ms 0.09; 0.88 at 2.5).
const FEW_ONSETS: f64 = 2.5;
/// The rise's floor (times its lower quartile) in fast ringing
/// ([`onsets_of`]): white noise's rise peaks at 1.29 of its lower
/// quartile; strikes in an eight 0.2 s apart in a room at 1.5-1.9.
const FAST_FLOOR: f64 = 1.5;
/// Onsets whose median rise is under this many times the rise's lower
/// quartile stand barely over the floor ([`onsets_of`]): about 2.3 in an
/// eight 0.2 s apart in a room (RT60 0.8 s); a bell struck alone, or a
/// ring slow enough that its rise falls between strikes, far more.
const CROWDED: f64 = 3.0;
/// Learned nominals closer than this (fraction, a twelfth of a semitone)
/// are one bell's.
const ONE_NOMINAL: f64 = 0.005;

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

/// A frame of about 90 ms at `rate` (Hz): the next power of two of
/// samples, halved where that would last over 150 ms (bells 150 ms apart
/// must rise in different frames), so 64-150 ms at any rate. Unhalved it
/// lasted 171 ms at 48 kHz in the recording timing (decimated to 12 kHz,
/// 1080 samples -> 2048), where bells 200 ms apart rose in one frame and
/// their partials were learned mixed: a ring's recall within 10 ms fell
/// from 0.84 at 44.1 kHz to 0.10 at 48 kHz. Every other rate the tests and
/// the recorded rings are heard at keeps its frames (`--bells` at 44.1 kHz
/// 139 ms, 16 kHz 128 ms: shorter frames there lost a quiet handbell's
/// warning and a superquint bell's nominal to 1.01 %).
pub(super) fn frame_len(rate: f64) -> usize {
    let up = ((0.09 * rate) as usize).max(1).next_power_of_two();
    if up as f64 > 0.15 * rate && up > 1 {
        up / 2
    } else {
        up
    }
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
        let n_win = frame_len(rate);
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
    let onsets = onsets_of(&frames.flux(lag), low.samples.len() as f64 / low.rate);
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
    let heard = bells_of(&groups, &rises, k_lo, df, bells);
    let (ring, few, margin) = ring_of(heard, &onsets, &rises, k_lo, df, bells);
    let rhythm = ring_size(&ring, &onsets);
    // A bell's share against the typical learned bell's: every bell of a
    // ring strikes as often as the others (onsets of the room, the noise
    // and strikes heard at another partial are no bell's).
    let heard: Vec<f64> = ring
        .iter()
        .filter(|(b, _)| !b.onsets.is_empty())
        .map(|(b, _)| b.onsets.len() as f64)
        .collect();
    let typical = median(heard).max(1.0);
    let mut learned: Vec<LearnedBell> = ring
        .iter()
        .map(|(b, f)| learned_bell(b, *f, typical, &rises, &onsets, &frames, &low))
        .collect();
    learned.sort_by(|a, b| b.nominal_hz.total_cmp(&a.nominal_hz));
    let mut learned = one_per_nominal(learned);
    let confidence = learned_set_sure(&learned, rhythm, bells, few).min(rival_sure(margin));
    let mut warnings = warnings_of(&learned, bells, few);
    if confidence < DOUBTFUL && !learned.is_empty() {
        let doubt = rival_doubt(margin, confidence).unwrap_or_else(|| doubt_of_set(&learned, confidence, rhythm));
        doubt_first(&mut warnings, doubt);
    }
    bells_as_sure_as_their_set(&mut learned, confidence);
    Ok(Learned {
        bells: learned,
        onsets: onsets.len(),
        confidence,
        ringing: rhythm,
        warnings,
        asked: bells,
        few,
        margin,
    })
}

/// The ring's bells among those `heard`, each with its nominal (Hz) as
/// placed, and whether far fewer were heard than the `bells` asked for
/// (then each sound heard is a bell and no note is guessed; else
/// [`on_the_scale`]), and the ring's margin over the next best
/// ([`Learned::margin`]).
fn ring_of(
    heard: Vec<Heard>,
    onsets: &[usize],
    rises: &[Vec<f64>],
    k_lo: usize,
    df: f64,
    bells: usize,
) -> (Vec<(Heard, f64)>, bool, f64) {
    // A recording of far fewer bells than asked (one bell struck again and
    // again): each sound heard is a bell, and no note is guessed for the
    // rest. A third or fewer heard, not a half: ten handbells 150 ms apart
    // are heard as five, and their notes' guesses are right.
    let few = FEW * heard.len() <= bells;
    let heard_sounds = if few { sounds(&heard, rises, k_lo, df) } else { vec![] };
    let (ring, margin) = if few {
        // Each at [`LEAST`] of the most heard one's onsets at least (as a
        // ring's bells against one bell's share): a partial of it noted
        // at a few onsets is no bell.
        let most = heard_sounds.iter().map(|b| b.onsets.len()).max().unwrap_or(0) as f64;
        let ring = heard_sounds
            .into_iter()
            .filter(|b| b.onsets.len() as f64 >= LEAST * most)
            .map(|b| {
                let f = b.nominal_hz;
                (b, f)
            })
            .collect();
        (ring, f64::INFINITY)
    } else {
        on_the_scale(heard, onsets, rises, k_lo, df, bells)
    };
    (ring, few, margin)
}

/// The bell `b` heard, its nominal moved to `f` (Hz), learned: its
/// nominal refined where it rose (`rises` at `onsets`, frames of
/// `frames` over `low`) and then as it lasts ([`refine_late`]), its
/// confidence its onsets against `typical`'s. A note of the ring no bell
/// was heard at (no onsets) keeps its nominal guessed from the scale.
fn learned_bell(
    b: &Heard,
    f: f64,
    typical: f64,
    rises: &[Vec<f64>],
    onsets: &[usize],
    frames: &Frames,
    low: &Signal,
) -> LearnedBell {
    if b.onsets.is_empty() {
        return LearnedBell {
            nominal_hz: f,
            confidence: 0.0,
            onsets: 0,
            support: 0.0,
            partials_fit: 0.0,
        };
    }
    let heard = refine_moved(rises, &b.onsets, b.nominal_hz, f, frames.k_lo, frames.df);
    let starts: Vec<usize> = b.onsets.iter().map(|&i| onsets[i] * frames.hop).collect();
    let support = (b.onsets.len() as f64 / typical).min(1.0);
    let fits = octave_fits(&mean_rise(rises, &b.onsets), f, frames.k_lo, frames.df);
    let partials_fit = octave_share(&fits, OCTAVES as usize);
    LearnedBell {
        nominal_hz: refine_late(low, &starts, frames.win.len(), heard).unwrap_or(heard),
        confidence: bell_sure(support),
        onsets: b.onsets.len(),
        support,
        partials_fit,
    }
}

/// The ring's bells among those `heard`, each with its nominal moved by
/// octaves: each bell's octave chosen with the others' (a ring is a
/// scale, [`ring_octaves`]), the bells heard that fit no note left out
/// and the empty notes filled ([`fill_empty_notes`]); failing that, the
/// `bells` heard most, each moved into the ring's span alone. With the
/// ring's margin over the next best ([`Learned::margin`]; infinite
/// with no scale).
fn on_the_scale(
    heard: Vec<Heard>,
    onsets: &[usize],
    rises: &[Vec<f64>],
    k_lo: usize,
    df: f64,
    bells: usize,
) -> (Vec<(Heard, f64)>, f64) {
    let pool: Vec<&Heard> = heard.iter().collect();
    match ring_octaves(&pool, rises, k_lo, df, bells) {
        Some(fit) => {
            let mut ring: Vec<(Heard, f64)> = heard
                .into_iter()
                .zip(fit.moved.iter().copied())
                .filter_map(|(b, f)| Some((b, f?)))
                .collect();
            let chosen: Vec<&Heard> = ring.iter().map(|b| &b.0).collect();
            let filled = fill_empty_notes(&fit.empty, &chosen, rises, k_lo, df, bells);
            ring.extend(filled.into_iter().map(|b| {
                let f = b.nominal_hz;
                (b, f)
            }));
            let unheard = unheard_notes(&fit, &ring, ringing(&ring, onsets), rises, k_lo, df);
            ring.extend(unheard.into_iter().map(|f| {
                let b = Heard {
                    nominal_hz: f,
                    onsets: vec![],
                };
                (b, f)
            }));
            (ring, fit.margin)
        }
        None => {
            let mut heard = heard;
            heard.truncate(bells);
            let hz: Vec<f64> = heard.iter().map(|b| b.nominal_hz).collect();
            let moved = octaves_into_ring(&hz, bells);
            (heard.into_iter().zip(moved).collect(), f64::INFINITY)
        }
    }
}

/// The bells heard at most onsets, a few more than `bells` (at least [`LEAST`] of one
/// bell's share each), from the groups of notes ([`same_bells`]).
fn bells_of(groups: &[Vec<(f64, usize)>], rises: &[Vec<f64>], k_lo: usize, df: f64, bells: usize) -> Vec<Heard> {
    let expected = rises.len() as f64 / bells as f64;
    // A bell heard at fewer onsets than this is no bell of the ring.
    let least = (LEAST * expected).max(3.0);
    let enough = |h: &Vec<Heard>| h.iter().filter(|b| b.onsets.len() as f64 >= least).count();
    let mut heard = same_bells(groups, rises, k_lo, df, least, false);
    if enough(&heard) < bells {
        // Too few: a nominal heard far more often than one bell strikes
        // may be two bells' (the tenor's octave on the treble's nominal).
        heard = same_bells(groups, rises, k_lo, df, least, true);
    }
    heard.retain(|b| b.onsets.len() as f64 >= least);
    heard.sort_by_key(|b| std::cmp::Reverse(b.onsets.len()));
    // A few more than asked: the ring's scale chooses among them.
    heard.truncate(bells + SPARE);
    heard
}

/// The onset frames of a recording `secs` (s) long, from its rise
/// `flux`: [`pick_onsets`] above twice the rise's lower quartile; where
/// that leaves fewer than [`FEW_ONSETS`] a second and those found stand
/// barely over the floor (their median rise under [`CROWDED`] times the
/// lower quartile), above [`FAST_FLOOR`] times it. In fast ringing in a
/// room (eight bells 0.2 s apart, RT60 0.8 s) every frame rises with
/// some bell, the lower quartile stands at 0.5-0.6 of a strike's rise,
/// and twice it kept 230 onsets of 1129 strikes: the tenor was never
/// heard and `--bells 8` learned another bell twice. One bell struck
/// every 1.5 s also gives few onsets, but they stand far over the
/// floor (the noise of its decays): there the floor stays.
fn onsets_of(flux: &[f64], secs: f64) -> Vec<usize> {
    let onsets = pick_onsets(flux, 2.0);
    let mut rising: Vec<f64> = flux.iter().copied().filter(|f| *f > 0.0).collect();
    rising.sort_by(f64::total_cmp);
    let low = rising.get(rising.len() / 4).copied().unwrap_or(0.0);
    let found = median(onsets.iter().map(|&t| flux[t]).collect());
    let crowded = found < CROWDED * low;
    if crowded && (onsets.len() as f64) < FEW_ONSETS * secs {
        pick_onsets(flux, FAST_FLOOR)
    } else {
        onsets
    }
}

/// Onset frames: peaks of the rise standing above its neighbours within
/// three frames and above `floor` times its lower quartile.
pub(super) fn pick_onsets(flux: &[f64], floor: f64) -> Vec<usize> {
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
    let floor = (floor * low).max(1e-3 * top);
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

/// A bell's nominal measured late: over [`LATE_S`] after each of its
/// strikes (`starts`: the samples of `low` where the frames its strikes
/// rose in begin, `win` long) less what sounded as long before, summed,
/// the peak within [`LATE_WIDTH`] of `f` (Hz); `None` if at the edge. The
/// rise of one 90 ms frame cannot part a nominal's doublet: a recorded
/// tenor's (d6) sounds at 1228 Hz as struck and 1237 Hz after, and a
/// tuner's nominal is the one that lasts.
fn refine_late(low: &Signal, starts: &[usize], win: usize, f: f64) -> Option<f64> {
    let n = (LATE_S * low.rate) as usize;
    let nfft = (4 * n).next_power_of_two();
    let df = low.rate / nfft as f64;
    let lo = ((1.0 - LATE_WIDTH) * f / df).floor() as usize;
    let hi = ((1.0 + LATE_WIDTH) * f / df).ceil() as usize;
    if lo < 2 || hi + 2 >= nfft / 2 {
        return None;
    }
    let hann = crate::spectrogram::hann(n);
    let fft = realfft::RealFftPlanner::<f64>::new().plan_fft_forward(nfft);
    let spectrum = |a: usize| -> Vec<f64> {
        let mut buf = fft.make_input_vec();
        for (i, w) in hann.iter().enumerate() {
            buf[i] = low.samples[a + i] * w;
        }
        let mut out = fft.make_output_vec();
        // The lengths are the plan's own: process cannot fail.
        let _ = fft.process(&mut buf, &mut out);
        out[lo - 1..=hi + 1].iter().map(|c| c.norm()).collect()
    };
    let mut sum = vec![0.0; hi - lo + 3];
    let mut used = 0;
    for &s in starts.iter().step_by((starts.len() / LATE_MOST).max(1)) {
        if s < n || s + win + n > low.samples.len() {
            continue;
        }
        let (after, before) = (spectrum(s + win), spectrum(s - n));
        for ((m, a), b) in sum.iter_mut().zip(&after).zip(&before) {
            *m += (a - b).max(0.0);
        }
        used += 1;
    }
    if used == 0 {
        return None;
    }
    let k = (1..sum.len() - 1).max_by(|&a, &b| sum[a].total_cmp(&sum[b]))?;
    if k == 1 || k == sum.len() - 2 || sum[k - 1] <= 0.0 || sum[k + 1] <= 0.0 {
        return None;
    }
    let (a, b, c) = (sum[k - 1].ln(), sum[k].ln(), sum[k + 1].ln());
    let den = a - 2.0 * b + c;
    let off = if den != 0.0 { 0.5 * (a - c) / den } else { 0.0 };
    Some((k as f64 + (lo - 1) as f64 + off.clamp(-0.5, 0.5)) * df)
}

/// A bell's nominal from the mean rise over its onsets, heard at `heard`
/// (Hz) and moved by octaves to `moved`. Not moved: the peak about it.
/// Moved: the centre of the rise within 2 % of `moved`, then within
/// 1.2 % of that, three times (the nominal's own peak may be split in two
/// by a partial of the bell struck before, its centre kept; twice the
/// nominal is not its octave partial to better than about 1 %).
fn refine_moved(rises: &[Vec<f64>], onsets: &[usize], heard: f64, moved: f64, k_lo: usize, df: f64) -> f64 {
    if (moved / heard - 1.0).abs() < 0.1 {
        return refine(rises, onsets, heard, 0.02, k_lo, df).unwrap_or(heard);
    }
    let mean = mean_rise(rises, onsets);
    let mut centre = moved;
    for width in [0.02, 0.012, 0.012, 0.012] {
        let (lo, hi) = ((1.0 - width) * centre / df, (1.0 + width) * centre / df);
        let (mut w, mut wf) = (0.0, 0.0);
        for (i, m) in mean.iter().enumerate() {
            let k = (i + k_lo) as f64;
            if k >= lo && k <= hi {
                w += m;
                wf += m * k * df;
            }
        }
        if w <= 0.0 {
            break;
        }
        centre = wf / w;
    }
    centre
}

/// A group's frequency from the mean rise over its onsets: the peak within
/// `width` (fraction) of `centre`, by a parabola through the log
/// magnitudes; `None` if the greatest rise there is at its edge.
fn refine(rises: &[Vec<f64>], onsets: &[usize], centre: f64, width: f64, k_lo: usize, df: f64) -> Option<f64> {
    let mean = mean_rise(rises, onsets);
    let len = mean.len();
    let bin = |f: f64| ((f / df).round() as usize).saturating_sub(k_lo).min(len - 1);
    let (lo, hi) = (
        bin((1.0 - width) * centre).max(1),
        bin((1.0 + width) * centre).min(len - 2),
    );
    let k = (lo..=hi).max_by(|&a, &b| mean[a].total_cmp(&mean[b]))?;
    if !(mean[k - 1] > 0.0 && mean[k] > 0.0 && mean[k + 1] > 0.0) || mean[k - 1] > mean[k] || mean[k + 1] > mean[k] {
        return None;
    }
    let (a, b, c) = (mean[k - 1].ln(), mean[k].ln(), mean[k + 1].ln());
    let den = a - 2.0 * b + c;
    let off = if den != 0.0 { 0.5 * (a - c) / den } else { 0.0 };
    Some((k as f64 + k_lo as f64 + off.clamp(-0.5, 0.5)) * df)
}

/// The groups of notes that are one bell's: its strikes' rise is the same
/// across the spectrum whichever of its partials rose most. Largest
/// first, a group whose mean rise is like a bell's first group's joins it;
/// else one noted at `big` onsets or more is a new bell (and, with
/// `split_crowded`, two found at one nominal are kept apart when they
/// hold far more onsets than one bell). Each bell's
/// nominal is then the peak of its mean rise with the most of a tuned
/// bell's other partials at their ratios to it (`learn_pick::nominal_of`), the
/// strongest among equals (handbells have only a twelfth).
fn same_bells(
    groups: &[Vec<(f64, usize)>],
    rises: &[Vec<f64>],
    k_lo: usize,
    df: f64,
    big: f64,
    split_crowded: bool,
) -> Vec<Heard> {
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
    let mut left: Vec<usize> = vec![];
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
            _ => left.push(i),
        }
    }
    // A bell whose strikes rose most at several partials in turn (in a
    // room, at 15 dB) is noted as several small groups: alike, together
    // they are a bell.
    let mut used = vec![false; left.len()];
    for a in 0..left.len() {
        if used[a] {
            continue;
        }
        let like: Vec<usize> = (a..left.len())
            .filter(|&b| !used[b] && (b == a || cos(left[a], left[b]) > SAME_BELL))
            .collect();
        like.iter().for_each(|&b| used[b] = true);
        let set: Vec<usize> = like.iter().map(|&b| left[b]).collect();
        if set.iter().map(|&g| groups[g].len()).sum::<usize>() as f64 >= big {
            members.push(set);
        }
    }
    let sets: Vec<Vec<usize>> = members
        .iter()
        .map(|m| m.iter().flat_map(|&i| groups[i].iter().map(|x| x.1)).collect())
        .collect();
    // Two bells found at one nominal are one bell heard two ways, unless
    // (`split_crowded`) together they struck far more often than a bell
    // does (a tenor's octave nominal on the treble's nominal: two bells).
    let crowded = |a: usize, b: usize| split_crowded && ((a + b) as f64) >= ONE_BELL * big / LEAST;
    apart(sets, rises, k_lo, df, SAME, crowded)
}

/// Bells on the notes of the ring's scale that no bell heard took
/// (`empty`, Hz): a bell whose strikes rose most at another sound (wind,
/// another bell's prime on its nominal) is heard there at the onsets no
/// bell took, its rise peaking within [`IN_TUNE`] of the note and
/// [`EMPTY_RISE`] as high as the onset's highest; at [`LEAST`] of a
/// bell's share of them or more, a bell.
fn fill_empty_notes(
    empty: &[f64],
    chosen: &[&Heard],
    rises: &[Vec<f64>],
    k_lo: usize,
    df: f64,
    bells: usize,
) -> Vec<Heard> {
    let least = (LEAST * rises.len() as f64 / bells as f64).max(3.0);
    let mut taken = vec![false; rises.len()];
    chosen.iter().flat_map(|b| &b.onsets).for_each(|&i| taken[i] = true);
    let semitone = 2f64.powf(IN_TUNE / 12.0);
    let mut out = vec![];
    for &note in empty {
        let (lo, hi) = ((note / semitone / df) as usize, (note * semitone / df).ceil() as usize);
        if lo <= k_lo + 1 || hi + 1 >= k_lo + rises[0].len() {
            continue;
        }
        let (lo, hi) = (lo - k_lo, hi - k_lo);
        let onsets: Vec<usize> = (0..rises.len())
            .filter(|&i| {
                let r = &rises[i];
                let top = r.iter().copied().fold(0.0, f64::max);
                let k = (lo..=hi).max_by(|&a, &b| r[a].total_cmp(&r[b])).unwrap_or(lo);
                !taken[i] && top > 0.0 && r[k] >= EMPTY_RISE * top && r[k] > r[k - 1] && r[k] > r[k + 1]
            })
            .collect();
        if (onsets.len() as f64) < least {
            continue;
        }
        let nominal_hz = refine(rises, &onsets, note, 1.0 - 1.0 / semitone, k_lo, df).unwrap_or(note);
        onsets.iter().for_each(|&i| taken[i] = true);
        out.push(Heard { nominal_hz, onsets });
    }
    out
}

/// Bells learned (highest first) within [`ONE_NOMINAL`] of the one
/// before are that bell heard twice (two partials moved by octaves onto
/// one note, in a room): one bell, the one heard at more onsets, with
/// both's onsets. No ring is tuned so close, and two voices there could
/// not be told apart (`--nominals` refuses them).
fn one_per_nominal(learned: Vec<LearnedBell>) -> Vec<LearnedBell> {
    let mut out: Vec<LearnedBell> = vec![];
    for b in learned {
        match out.last_mut() {
            Some(a) if a.nominal_hz - b.nominal_hz < ONE_NOMINAL * a.nominal_hz => {
                if b.onsets > a.onsets {
                    a.nominal_hz = b.nominal_hz;
                }
                a.onsets += b.onsets;
                a.support = (a.support + b.support).min(1.0);
                a.partials_fit = a.partials_fit.max(b.partials_fit);
                a.confidence = bell_sure(a.support);
            }
            _ => out.push(b),
        }
    }
    out
}

#[cfg(test)]
#[path = "learn_tests.rs"]
mod tests;
