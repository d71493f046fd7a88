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

/// A bell's nominal rose at an onset if it rose by this share of what sounded there before.
const NOMINAL_ROSE: f64 = 0.5;
/// An onset is first given to the bell whose nominal jumped most, if by this much (twice: 6 dB).
const FIRST_GUESS: f64 = 1.0;
/// What sounded before is taken as at least this share of the onset's
/// loudest (so a bin silent before does not jump without end).
const JUMP_FLOOR: f64 = 0.02;
/// An onset whose rise is less like any bell's pattern than this (cosine) is no bell's.
const LIKE: f64 = 0.5;
/// A peak of a bell's pattern this strong against its strongest is a partial.
const PARTIAL: f64 = 0.08;
/// Two bells whose patterns are this alike (cosine) cannot be told apart.
const ALIKE: f64 = 0.85;
/// Peaks this strong against a pattern's strongest count in its fit to a bell.
const FIT_PEAK: f64 = 0.15;
/// Two bells' patterns are swapped if they fit the other's nominal better by this much in all.
const SWAP: f64 = 0.2;
/// Groups of alike onsets looked for beyond one a bell (the noise, double
/// strikes, a bell heard two ways).
const EXTRA_GROUPS: usize = 4;
/// Partials kept a bell.
const MOST_PARTIALS: usize = 8;

/// Each bell's partials learned from the recording `sig`, its nominal
/// given (`nominals_hz[0]` the treble's).
pub fn learn_voices(sig: &Signal, nominals_hz: &[f64]) -> Result<LearnedVoices, SignalError> {
    sig.validate()?;
    if nominals_hz.is_empty() || nominals_hz.iter().any(|f| !(f.is_finite() && *f > 20.0)) {
        return Err(SignalError::Option("nominals: one a bell, each above 20 Hz".into()));
    }
    // Up to past the treble's octave nominal and twelfth.
    let top = nominals_hz.iter().copied().fold(0.0, f64::max);
    let f_max = (3.2 * top).clamp(2000.0, 0.45 * sig.rate);
    let low = decimate(sig, f_max);
    let frames = Frames::up_to(&low, f_max);
    let lag = 4;
    if frames.count() < lag + 3 {
        return Ok(LearnedVoices {
            bells: assumed(nominals_hz),
            onsets: 0,
            warnings: vec![],
        });
    }
    let onsets = pick_onsets(&frames.flux(lag), 2.0);
    let o = OnsetRises::of(&frames, &onsets, lag, nominals_hz);
    let n = nominals_hz.len();
    let mut owner = o.first_owners();
    let mut patterns = vec![vec![]; n];
    for _ in 0..4 {
        patterns = (0..n).map(|k| mean_of(&o.rises, &owner, k)).collect();
        owner = o.closest(&patterns);
    }
    patterns = (0..n).map(|k| mean_of(&o.rises, &owner, k)).collect();
    let mut counts: Vec<usize> = (0..n)
        .map(|k| owner.iter().filter(|x| **x == Some(k)).count())
        .collect();
    o.swap_octaves(&mut patterns, &mut counts);
    o.swap_octave_pairs(&mut patterns, &mut counts);
    let (bells, warnings) = o.voices(&patterns, &counts);
    Ok(LearnedVoices {
        bells,
        onsets: onsets.len(),
        warnings,
    })
}

/// Every bell assumed from its nominal.
fn assumed(nominals_hz: &[f64]) -> Vec<LearnedVoice> {
    nominals_hz
        .iter()
        .map(|&f| LearnedVoice {
            voice: BellVoice::from_nominal(f),
            onsets: 0,
            learned: false,
        })
        .collect()
}

/// Each onset's rise (normalised) and how far each bell's nominal jumped
/// there, with the nominals and the spectra's bins.
struct OnsetRises<'a> {
    rises: Vec<Vec<f64>>,
    /// Per onset, per bell: its nominal's rise over what sounded there
    /// before (a struck bell's nominal comes back far above its last
    /// strike's decay; the other bells' do not move, whatever their strength).
    jumped: Vec<Vec<f64>>,
    nominals_hz: &'a [f64],
    k_lo: usize,
    df: f64,
}

impl<'a> OnsetRises<'a> {
    fn of(frames: &Frames, onsets: &[usize], lag: usize, nominals_hz: &'a [f64]) -> Self {
        let (k_lo, df) = (frames.k_lo, frames.df);
        let bin = |f: f64| (f / df).round() as isize - k_lo as isize;
        let mut rises: Vec<Vec<f64>> = vec![];
        let mut jumped: Vec<Vec<f64>> = vec![];
        for &t in onsets {
            let (a, b) = (frames.magnitudes(t), frames.magnitudes(t - lag));
            let r: Vec<f64> = a.iter().zip(&b).map(|(x, y)| (x - y).max(0.0)).collect();
            let top = a.iter().copied().fold(0.0, f64::max);
            let floor = (JUMP_FLOOR * top).max(1e-300);
            jumped.push(
                nominals_hz
                    .iter()
                    .map(|&f| {
                        let (lo, hi) = (bin(0.994 * f).min(bin(f) - 1), bin(1.006 * f).max(bin(f) + 1));
                        let (lo, hi) = (lo.max(0) as usize, (hi.max(0) as usize).min(r.len().saturating_sub(1)));
                        (lo..=hi).map(|k| r[k] / (b[k] + floor)).fold(0.0, f64::max)
                    })
                    .collect(),
            );
            let norm = r.iter().map(|v| v * v).sum::<f64>().sqrt();
            rises.push(if norm > 0.0 {
                r.into_iter().map(|v| v / norm).collect()
            } else {
                r
            });
        }
        OnsetRises {
            rises,
            jumped,
            nominals_hz,
            k_lo,
            df,
        }
    }

    fn fit(&self, pattern: &[f64], k: usize) -> f64 {
        bell_fit(pattern, self.nominals_hz[k], self.k_lo, self.df)
    }

    /// The first guess of each onset's bell: the bell whose nominal jumped
    /// most there; or, where that leaves more bells without onsets, the
    /// onsets' own groups (alike rises) given to the bells whose nominal
    /// they fit (in rounds a bell always follows the same one, whose
    /// partials rise at its onsets too).
    fn first_owners(&self) -> Vec<Option<usize>> {
        let n = self.nominals_hz.len();
        let owner: Vec<Option<usize>> = self
            .jumped
            .iter()
            .map(|j| {
                let (k, v) = j.iter().enumerate().max_by(|x, y| x.1.total_cmp(y.1))?;
                (*v >= FIRST_GUESS).then_some(k)
            })
            .collect();
        let groups = alike_groups(&self.rises, n + EXTRA_GROUPS);
        let expected = self.rises.len() as f64 / n as f64;
        let mut scored: Vec<(usize, usize, f64)> = vec![];
        for (g, members) in groups.iter().enumerate() {
            if (members.len() as f64) < 0.3 * expected {
                continue;
            }
            let pattern = mean_of_onsets(&self.rises, members);
            for k in 0..n {
                let rose = members.iter().filter(|&&i| self.jumped[i][k] >= NOMINAL_ROSE).count();
                if 2 * rose >= members.len() {
                    scored.push((g, k, self.fit(&pattern, k)));
                }
            }
        }
        scored.sort_by(|a, b| b.2.total_cmp(&a.2));
        let (mut group_done, mut bell_done) = (vec![false; groups.len()], vec![false; n]);
        let mut from_groups: Vec<Option<usize>> = vec![None; self.rises.len()];
        for (g, k, _) in scored {
            if group_done[g] || bell_done[k] {
                continue;
            }
            group_done[g] = true;
            bell_done[k] = true;
            for &i in &groups[g] {
                from_groups[i] = Some(k);
            }
        }
        let guessed = (0..n).filter(|&k| owner.contains(&Some(k))).count();
        if bell_done.iter().filter(|d| **d).count() > guessed {
            from_groups
        } else {
            owner
        }
    }

    /// Each onset given to the bell whose pattern its rise is most like,
    /// among those whose nominal rose there.
    fn closest(&self, patterns: &[Vec<f64>]) -> Vec<Option<usize>> {
        self.rises
            .iter()
            .zip(&self.jumped)
            .map(|(r, j)| {
                (0..patterns.len())
                    .filter(|&k| j[k] >= NOMINAL_ROSE && !patterns[k].is_empty())
                    .map(|k| (k, cosine(r, &patterns[k])))
                    .filter(|x| x.1 >= LIKE)
                    .max_by(|x, y| x.1.total_cmp(&y.1))
                    .map(|x| x.0)
            })
            .collect()
    }

    /// Bells an octave apart share two partials (the treble's prime is the
    /// tenor's nominal, the tenor's octave nominal the treble's): each
    /// pattern goes to the nominal its other partials fit best.
    fn swap_octaves(&self, patterns: &mut [Vec<f64>], counts: &mut [usize]) {
        let n = patterns.len();
        loop {
            let best = (0..n)
                .flat_map(|i| (i + 1..n).map(move |j| (i, j)))
                .map(|(i, j)| {
                    let gain = self.fit(&patterns[i], j) + self.fit(&patterns[j], i)
                        - self.fit(&patterns[i], i)
                        - self.fit(&patterns[j], j);
                    (i, j, gain)
                })
                .max_by(|a, b| a.2.total_cmp(&b.2));
            match best {
                Some((i, j, gain)) if gain >= SWAP => {
                    patterns.swap(i, j);
                    counts.swap(i, j);
                }
                _ => break,
            }
        }
    }

    /// Two bells an exact octave apart (within [`OCTAVE_WITHIN`]): the
    /// upper bell's hum, prime and nominal lie on the lower's prime,
    /// nominal and octave nominal, and the upper partials of each fit the
    /// other's [`FAMILY`] (a Taylor treble's tierce and quint at 1.19 and
    /// 1.53 of the tenor's nominal), so [`Self::swap_octaves`] cannot tell
    /// them apart. The upper bell's strikes raise its nominal most; only
    /// the lower bell's raise anything below the upper's hum or between
    /// its hum and prime (the lower's hum, tierce and quint): the pattern
    /// more like the upper bell's by these ([`upper_likeness`]) is its.
    /// On the tester's
    /// Sather eights (issue 43) the tenor's pattern was the treble's, and
    /// every treble strike was reported as the tenor's.
    fn swap_octave_pairs(&self, patterns: &mut [Vec<f64>], counts: &mut [usize]) {
        let n = patterns.len();
        for lo in 0..n {
            for hi in 0..n {
                let (f_lo, f_hi) = (self.nominals_hz[lo], self.nominals_hz[hi]);
                if (f_hi / (2.0 * f_lo) - 1.0).abs() > OCTAVE_WITHIN {
                    continue;
                }
                let upper = |p: &[f64]| upper_likeness(p, f_lo, f_hi, self.k_lo, self.df);
                if upper(&patterns[lo]) > upper(&patterns[hi]) + OCTAVE_MARGIN {
                    patterns.swap(lo, hi);
                    counts.swap(lo, hi);
                }
            }
        }
    }

    /// Each bell's voice from its pattern (of `counts` onsets), and the
    /// warnings: a bell heard at too few onsets (assumed from its
    /// nominal), two bells whose patterns are alike.
    fn voices(&self, patterns: &[Vec<f64>], counts: &[usize]) -> (Vec<LearnedVoice>, Vec<String>) {
        let n = patterns.len();
        let typical = crate::median(&counts.iter().map(|&c| c as f64).collect::<Vec<_>>());
        let mut warnings = vec![];
        let mut bells = assumed(self.nominals_hz);
        for k in 0..n {
            bells[k].onsets = counts[k];
            if (counts[k] as f64) < (0.3 * typical).max(3.0) {
                warnings.push(format!(
                    "bell {} ({:.1} Hz): its nominal rose at only {} strikes heard in the recording: its partials are assumed from a tuned bell's",
                    k + 1,
                    self.nominals_hz[k],
                    counts[k]
                ));
                continue;
            }
            let others: Vec<&[f64]> = (0..n)
                .filter(|&j| j != k && counts[j] > 0)
                .map(|j| patterns[j].as_slice())
                .collect();
            if let Some(v) = voice_of(&patterns[k], &others, self.nominals_hz[k], self.k_lo, self.df) {
                bells[k].voice = v;
                bells[k].learned = true;
            }
        }
        for i in 0..n {
            for j in i + 1..n {
                let c = cosine(&patterns[i], &patterns[j]);
                if bells[i].learned && bells[j].learned && c > ALIKE {
                    warnings.push(format!(
                        "bells {} and {}: their partials rise alike at their strikes (likeness {c:.2}): their partials cannot be told apart, and one's strikes may be taken for the other's",
                        i + 1,
                        j + 1
                    ));
                }
            }
        }
        (bells, warnings)
    }
}

/// A bell's partials as heard in recordings, as ranges of the ratio to
/// its nominal: hum, prime, tierce, quint, nominal, and the upper partials
/// of tuned bells (superquint, octave nominal, 2.5-2.7, twelfth, double
/// octave) and of the recorded tower bells (1.18, 1.56, 2.7, 3.0, 4.1:
/// docs/strikes.md).
const FAMILY: [(f64, f64); 11] = [
    (0.24, 0.26),
    (0.485, 0.515),
    (0.58, 0.61),
    (0.73, 0.78),
    (0.99, 1.01),
    (1.15, 1.21),
    (1.45, 1.58),
    (1.97, 2.08),
    (2.4, 2.75),
    (2.9, 3.1),
    (3.95, 4.2),
];

/// How well a pattern (bins from `k_lo`, `df` Hz apart) fits a bell of
/// nominal `f`: the share of its peaks' strength (those at least
/// [`FIT_PEAK`] of its strongest) that lies in the ranges of [`FAMILY`].
fn bell_fit(pattern: &[f64], f: f64, k_lo: usize, df: f64) -> f64 {
    let top = pattern.iter().copied().fold(0.0, f64::max);
    if top <= 0.0 || pattern.len() < 5 {
        return 0.0;
    }
    let (mut all, mut fit) = (0.0, 0.0);
    for k in 2..pattern.len() - 2 {
        let v = pattern[k];
        if v >= FIT_PEAK * top && (1..=2).all(|j| v >= pattern[k - j] && v >= pattern[k + j]) {
            let r = (k + k_lo) as f64 * df / f;
            all += v;
            if FAMILY.iter().any(|(lo, hi)| r >= *lo && r <= *hi) {
                fit += v;
            }
        }
    }
    if all > 0.0 {
        fit / all
    } else {
        0.0
    }
}

/// Two nominals are an exact octave apart within this fraction (the
/// tester's Sather and Westerkerk eights: 0.0 % and 0.7 %; the recorded
/// Ringing Room eight 1.1 %, left as it was).
const OCTAVE_WITHIN: f64 = 0.01;
/// A pattern is taken for the upper bell's of an octave pair if it is
/// more like it ([`upper_likeness`], from -2 to 1) by this much. The
/// tester's Sather and Westerkerk eights (sa8a-d, wk8a-d, recorded) part
/// by 0.9 or more: the upper bell's pattern about 0.7 to 1, the lower's
/// below 0.
const OCTAVE_MARGIN: f64 = 0.2;

/// How much a pattern (bins from `k_lo`, `df` Hz apart) is like the upper
/// bell's of two an octave apart (nominals `f_lo`, `f_hi` Hz): its rise at
/// `f_hi` (within 0.6 %) against its strongest, less twice its strongest
/// rise where only the lower bell has partials (its hum, 0.2-0.46 of
/// `f_lo`; its tierce and quint, 0.55-0.9).
fn upper_likeness(pattern: &[f64], f_lo: f64, f_hi: f64, k_lo: usize, df: f64) -> f64 {
    let top = pattern.iter().copied().fold(0.0, f64::max);
    if top <= 0.0 {
        return 0.0;
    }
    let (mut at_hi, mut low) = (0.0f64, 0.0f64);
    let near = (0.006 * f_hi).max(1.5 * df);
    for (k, &v) in pattern.iter().enumerate() {
        let f = (k + k_lo) as f64 * df;
        let r = f / f_lo;
        if (f - f_hi).abs() <= near {
            at_hi = at_hi.max(v);
        }
        if (0.2..=0.46).contains(&r) || (0.55..=0.9).contains(&r) {
            low = low.max(v);
        }
    }
    (at_hi - 2.0 * low) / top
}

/// Groups of alike rises (`rises` normalised): `k` groups by the cosine,
/// started from the rise most like the rest and then each time the rise
/// least like any group's start, refined eight times. Each group's onsets.
fn alike_groups(rises: &[Vec<f64>], k: usize) -> Vec<Vec<usize>> {
    let m = rises.len();
    if m == 0 {
        return vec![];
    }
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    let mean: Vec<f64> = mean_of_onsets(rises, &(0..m).collect::<Vec<_>>());
    let first = (0..m).max_by(|&a, &b| dot(&rises[a], &mean).total_cmp(&dot(&rises[b], &mean)));
    let mut centres: Vec<Vec<f64>> = first.map(|f| rises[f].clone()).into_iter().collect();
    while centres.len() < k.min(m) {
        let far = (0..m).min_by(|&a, &b| {
            let near = |i: usize| centres.iter().map(|c| cosine(&rises[i], c)).fold(f64::MIN, f64::max);
            near(a).total_cmp(&near(b))
        });
        match far {
            Some(f) => centres.push(rises[f].clone()),
            None => break,
        }
    }
    let mut groups: Vec<Vec<usize>> = vec![];
    for _ in 0..8 {
        groups = vec![vec![]; centres.len()];
        for (i, r) in rises.iter().enumerate() {
            let c = (0..centres.len()).max_by(|&a, &b| cosine(r, &centres[a]).total_cmp(&cosine(r, &centres[b])));
            if let Some(c) = c {
                groups[c].push(i);
            }
        }
        for (c, g) in centres.iter_mut().zip(&groups) {
            if !g.is_empty() {
                *c = mean_of_onsets(rises, g);
            }
        }
    }
    groups
}

/// The summed rise of `onsets`.
fn mean_of_onsets(rises: &[Vec<f64>], onsets: &[usize]) -> Vec<f64> {
    let mut m = vec![0.0; rises.first().map_or(0, |r| r.len())];
    for &i in onsets {
        m.iter_mut().zip(&rises[i]).for_each(|(a, b)| *a += b);
    }
    m
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
fn voice_of(pattern: &[f64], others: &[&[f64]], nominal: f64, k_lo: usize, df: f64) -> Option<BellVoice> {
    let top = pattern.iter().copied().fold(0.0, f64::max);
    if top <= 0.0 || pattern.len() < 5 {
        return None;
    }
    // A peak another bell's pattern holds more strongly (against its own
    // strongest) is that bell's, rising at this bell's onsets because it
    // was struck just before (in rounds, always the same bell).
    let theirs = |k: usize| {
        others.iter().any(|o| {
            let otop = o.iter().copied().fold(0.0, f64::max);
            otop > 0.0
                && o[k.saturating_sub(1)..(k + 2).min(o.len())]
                    .iter()
                    .any(|v| v / otop > pattern[k] / top)
        })
    };
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
            v >= PARTIAL * top && (1..=2).all(|j| v >= pattern[k - j] && v >= pattern[k + j]) && !theirs(k)
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

#[cfg(test)]
mod tests {
    use super::*;

    /// A rise pattern (bins 5 Hz apart from 150 Hz) with peaks (Hz, strength).
    fn pattern(peaks: &[(f64, f64)]) -> Vec<f64> {
        let mut p = vec![0.0; 800];
        for &(f, s) in peaks {
            p[(f / 5.0).round() as usize - 30] = s;
        }
        p
    }

    /// A treble an exact octave over the tenor (1600 and 800 Hz), their
    /// patterns as a Taylor eight's were learned (issue 43's tester, Sather
    /// Tower: the tenor's rise strongest at 1.3 times its nominal, its
    /// tierce faint, its octave nominal not rising; the treble's tierce and
    /// superquint at 1.17 and 1.49 of the tenor's nominal), each given to
    /// the other bell. The family's fit leaves them so (they fit the wrong
    /// nominals better); the rise at the treble's nominal and at the
    /// tenor's own low partials gives each its own.
    #[test]
    fn a_treble_an_octave_over_the_tenor_keeps_its_own_pattern() {
        let nominals = [1600.0, 1200.0, 800.0];
        let tenor = pattern(&[
            (470.0, 0.11),
            (800.0, 0.28),
            (1044.0, 1.0),
            (1615.0, 0.3),
            (1877.0, 0.4),
        ]);
        let treble = pattern(&[
            (800.0, 0.08),
            (934.0, 0.11),
            (1600.0, 1.0),
            (2110.0, 0.17),
            (2380.0, 0.36),
        ]);
        let middle = pattern(&[(600.0, 0.5), (1200.0, 1.0), (1800.0, 0.4)]);
        let o = OnsetRises {
            rises: vec![],
            jumped: vec![],
            nominals_hz: &nominals,
            k_lo: 30,
            df: 5.0,
        };
        // Each pattern named by its strongest rise (Hz).
        let strongest = |ps: &[Vec<f64>]| -> Vec<f64> {
            ps.iter()
                .map(|p| {
                    let k = (0..p.len()).max_by(|&a, &b| p[a].total_cmp(&p[b])).unwrap_or(0);
                    (k + 30) as f64 * 5.0
                })
                .collect()
        };
        let mut patterns = vec![tenor, middle, treble];
        let mut counts = vec![20, 32, 32];
        o.swap_octaves(&mut patterns, &mut counts);
        assert_eq!(
            strongest(&patterns),
            vec![1045.0, 1200.0, 1600.0],
            "the family's fit alone"
        );
        o.swap_octave_pairs(&mut patterns, &mut counts);
        assert_eq!(strongest(&patterns), vec![1600.0, 1200.0, 1045.0]);
        assert_eq!(counts, vec![32, 32, 20]);
    }
}
