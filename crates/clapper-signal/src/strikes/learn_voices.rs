//! Each bell's partials learned from the recording, its nominal given
//! (issue 43, docs/strikes.md "`--nominals` timed from the recording's own
//! strikes"): real bells do not follow a tuned bell's partial ratios (the
//! recorded tower bells' partials lie at 1.18, 1.56, 2.0, 2.7 and 3.0 times
//! the nominal), so bands placed at those ratios hear some bells at no
//! partial of theirs.
//!
//! At every onset of the recording the spectrum's rise is noted. An onset
//! is first given to the bell whose nominal rose most there (against the
//! onset's greatest rise); each bell's pattern is the mean rise of its
//! onsets, and each onset is then given again to the bell whose pattern
//! its rise is most like, among the bells whose nominal rose there (a
//! treble's prime lies on its octave's nominal: the rest of the pattern
//! tells them apart). The bell's partials are the peaks of its pattern.

use super::band::decimate;
use super::learn::{pick_onsets, Frames};
use super::voice::{BellVoice, VoicePartial};
use crate::{Signal, SignalError};

/// A bell's voice learned from the recording.
#[derive(Clone, Debug, PartialEq)]
pub struct LearnedVoice {
    /// Its partials: learned from the recording where `onsets` is enough,
    /// else assumed from its nominal ([`BellVoice::from_nominal`]).
    pub voice: BellVoice,
    /// The onsets of the recording taken for its strikes.
    pub onsets: usize,
    /// Whether its partials were learned from the recording.
    pub learned: bool,
}

/// Every bell's voice learned, and what could not be.
#[derive(Clone, Debug, PartialEq)]
pub struct LearnedVoices {
    /// Treble first, as the nominals were given.
    pub bells: Vec<LearnedVoice>,
    /// Onsets heard in the recording.
    pub onsets: usize,
    /// Bells whose partials could not be learned, or could not be told
    /// from another bell's, in words.
    pub warnings: Vec<String>,
}

/// A nominal rose at an onset if its rise is this share of the onset's greatest.
const NOMINAL_ROSE: f64 = 0.1;
/// An onset is first given to the bell whose nominal rose at least this share.
const FIRST_GUESS: f64 = 0.3;
/// An onset whose rise is less like any bell's pattern than this (cosine) is no bell's.
const LIKE: f64 = 0.5;
/// A peak of a bell's pattern this strong against its strongest is a partial.
const PARTIAL: f64 = 0.08;
/// Two bells whose patterns are this alike (cosine) cannot be told apart.
const ALIKE: f64 = 0.85;
/// Partials kept a bell.
const MOST_PARTIALS: usize = 8;

/// Each bell's partials learned from the recording `sig`, its nominal
/// given (`nominals_hz[0]` the treble's).
pub fn learn_voices(sig: &Signal, nominals_hz: &[f64]) -> Result<LearnedVoices, SignalError> {
    sig.validate()?;
    if nominals_hz.is_empty() || nominals_hz.iter().any(|f| !(f.is_finite() && *f > 20.0)) {
        return Err(SignalError::Option("nominals: one a bell, each above 20 Hz".into()));
    }
    let assumed = |onsets: usize| -> Vec<LearnedVoice> {
        nominals_hz
            .iter()
            .map(|&f| LearnedVoice {
                voice: BellVoice::from_nominal(f),
                onsets,
                learned: false,
            })
            .collect()
    };
    // Up to past the treble's octave nominal and twelfth.
    let top = nominals_hz.iter().copied().fold(0.0, f64::max);
    let f_max = (3.2 * top).clamp(2000.0, 0.45 * sig.rate);
    let low = decimate(sig, f_max);
    let frames = Frames::up_to(&low, f_max);
    let lag = 4;
    if frames.count() < lag + 3 {
        return Ok(LearnedVoices {
            bells: assumed(0),
            onsets: 0,
            warnings: vec![],
        });
    }
    let onsets = pick_onsets(&frames.flux(lag));
    let rises: Vec<Vec<f64>> = onsets
        .iter()
        .map(|&t| {
            let (a, b) = (frames.magnitudes(t), frames.magnitudes(t - lag));
            let r: Vec<f64> = a.iter().zip(&b).map(|(x, y)| (x - y).max(0.0)).collect();
            let norm = r.iter().map(|v| v * v).sum::<f64>().sqrt();
            if norm > 0.0 {
                r.into_iter().map(|v| v / norm).collect()
            } else {
                r
            }
        })
        .collect();
    let (k_lo, df) = (frames.k_lo, frames.df);
    let bin = |f: f64| (f / df).round() as isize - k_lo as isize;
    // How much each bell's nominal rose at each onset, against the onset's greatest rise.
    let rose: Vec<Vec<f64>> = rises
        .iter()
        .map(|r| {
            let top = r.iter().copied().fold(0.0, f64::max);
            nominals_hz
                .iter()
                .map(|&f| {
                    let (a, b) = (bin(0.994 * f).min(bin(f) - 1), bin(1.006 * f).max(bin(f) + 1));
                    let (a, b) = (a.max(0) as usize, (b.max(0) as usize).min(r.len().saturating_sub(1)));
                    let m = r.get(a..=b).map_or(0.0, |s| s.iter().copied().fold(0.0, f64::max));
                    if top > 0.0 {
                        m / top
                    } else {
                        0.0
                    }
                })
                .collect()
        })
        .collect();
    let n = nominals_hz.len();
    let mut owner: Vec<Option<usize>> = rose
        .iter()
        .map(|a| {
            let (k, v) = a.iter().enumerate().max_by(|x, y| x.1.total_cmp(y.1))?;
            (*v >= FIRST_GUESS).then_some(k)
        })
        .collect();
    let mut patterns = vec![vec![]; n];
    for _ in 0..4 {
        patterns = (0..n).map(|k| mean_of(&rises, &owner, k)).collect();
        owner = rises
            .iter()
            .zip(&rose)
            .map(|(r, a)| {
                (0..n)
                    .filter(|&k| a[k] >= NOMINAL_ROSE && !patterns[k].is_empty())
                    .map(|k| (k, cosine(r, &patterns[k])))
                    .filter(|x| x.1 >= LIKE)
                    .max_by(|x, y| x.1.total_cmp(&y.1))
                    .map(|x| x.0)
            })
            .collect();
    }
    patterns = (0..n).map(|k| mean_of(&rises, &owner, k)).collect();
    let counts: Vec<usize> = (0..n)
        .map(|k| owner.iter().filter(|o| **o == Some(k)).count())
        .collect();
    let typical = crate::median(&counts.iter().map(|&c| c as f64).collect::<Vec<_>>());
    let mut warnings = vec![];
    let mut bells = assumed(0);
    for k in 0..n {
        bells[k].onsets = counts[k];
        if (counts[k] as f64) < (0.3 * typical).max(3.0) {
            warnings.push(format!(
                "bell {} ({:.1} Hz): its nominal rose at only {} onsets of the recording: its partials are assumed from a tuned bell's",
                k + 1,
                nominals_hz[k],
                counts[k]
            ));
            continue;
        }
        if let Some(v) = voice_of(&patterns[k], nominals_hz[k], k_lo, df) {
            bells[k].voice = v;
            bells[k].learned = true;
        }
    }
    for i in 0..n {
        for j in i + 1..n {
            if bells[i].learned && bells[j].learned {
                let c = cosine(&patterns[i], &patterns[j]);
                if c > ALIKE {
                    warnings.push(format!(
                        "bells {} and {}: their partials rise alike at their strikes (likeness {c:.2}): their partials cannot be told apart, and one's strikes may be taken for the other's",
                        i + 1,
                        j + 1
                    ));
                }
            }
        }
    }
    Ok(LearnedVoices {
        bells,
        onsets: onsets.len(),
        warnings,
    })
}

/// The mean rise of the onsets given to bell `k`, or nothing.
fn mean_of(rises: &[Vec<f64>], owner: &[Option<usize>], k: usize) -> Vec<f64> {
    let mut m: Vec<f64> = vec![];
    for (r, _) in rises.iter().zip(owner).filter(|(_, o)| **o == Some(k)) {
        if m.is_empty() {
            m = vec![0.0; r.len()];
        }
        m.iter_mut().zip(r).for_each(|(a, b)| *a += b);
    }
    m
}

fn cosine(a: &[f64], b: &[f64]) -> f64 {
    let (ab, aa, bb) = a.iter().zip(b).fold((0.0, 0.0, 0.0), |(ab, aa, bb), (x, y)| {
        (ab + x * y, aa + x * x, bb + y * y)
    });
    if aa > 0.0 && bb > 0.0 {
        ab / (aa * bb).sqrt()
    } else {
        0.0
    }
}

/// A bell's voice from its pattern (bins from `k_lo`, `df` Hz apart): the
/// nominal where the pattern peaks within 0.6 % of the nominal given (or
/// the nominal given), and the pattern's strongest other peaks, at least
/// [`PARTIAL`] of the strongest and 2 % apart, [`MOST_PARTIALS`] in all.
fn voice_of(pattern: &[f64], nominal: f64, k_lo: usize, df: f64) -> Option<BellVoice> {
    let top = pattern.iter().copied().fold(0.0, f64::max);
    if top <= 0.0 || pattern.len() < 5 {
        return None;
    }
    let at = |k: usize| -> f64 {
        let (a, b, c) = (pattern[k - 1], pattern[k], pattern[k + 1]);
        let den = a - 2.0 * b + c;
        let off = if den < 0.0 {
            (0.5 * (a - c) / den).clamp(-0.5, 0.5)
        } else {
            0.0
        };
        (k as f64 + k_lo as f64 + off) * df
    };
    let mut peaks: Vec<(f64, f64)> = (2..pattern.len() - 2)
        .filter(|&k| {
            let v = pattern[k];
            v >= PARTIAL * top && (1..=2).all(|j| v >= pattern[k - j] && v >= pattern[k + j])
        })
        .map(|k| (at(k), pattern[k] / top))
        .collect();
    peaks.sort_by(|a, b| b.1.total_cmp(&a.1));
    // The nominal: the peak within 0.6 % (at least a bin) of the one given.
    let near = (0.006 * nominal).max(1.5 * df);
    let nom = peaks
        .iter()
        .filter(|p| (p.0 - nominal).abs() <= near)
        .copied()
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .unwrap_or((nominal, 0.3));
    let mut kept: Vec<(f64, f64)> = vec![nom];
    for p in peaks {
        if kept.len() == MOST_PARTIALS {
            break;
        }
        if kept.iter().all(|k| (k.0 - p.0).abs() > 0.02 * p.0) {
            kept.push(p);
        }
    }
    let smax = kept.iter().map(|p| p.1).fold(0.0, f64::max);
    Some(BellVoice {
        partials: kept
            .into_iter()
            .map(|(f, s)| VoicePartial {
                freq_hz: f,
                strength: s / smax,
                uncertainty: 0.005,
            })
            .collect(),
    })
}
