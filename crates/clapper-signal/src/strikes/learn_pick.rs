//! Each bell's nominal picked from the mean rise of its strikes
//! (`clapper strikes --bells N`, [`super::learn`]), and two bells found at
//! one nominal kept apart. Leaf to the learner: it imports nothing from it.
//!
//! Recorded tower bells (docs/strikes.md, "`--bells N` on the tester's
//! real-bell rings") rise most as struck at their superquint (1.48 times
//! the nominal, twice as strong in the first 90 ms), and in a room a
//! bell's long nominal rises again at the next bell's strike: the peak a
//! bell's strikes rise most at is often not its nominal, and may be
//! another bell's.

use super::learn_gaps::Heard;

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
/// A peak of a bell's mean rise this strong against its strongest may be
/// its nominal (0.25 missed recorded bells' nominals in a room, rising at
/// 0.15-0.2 of their superquint, and took the superquint).
const CANDIDATE: f64 = 0.12;
/// What being the strongest peak counts for, in partials found.
const STRONG: f64 = 4.0;
/// A partial this strong against the strongest is present.
const PRESENT: f64 = 0.1;

/// A nominal picked: its frequency (Hz) and how many of a tuned bell's
/// other partials lie at their ratios to it ([`PARTIAL_RANGES`]).
#[derive(Clone, Copy, Debug)]
pub(super) struct Pick {
    /// The nominal (Hz).
    pub(super) hz: f64,
    /// Partials found at their ratios to it.
    pub(super) partials: usize,
}

/// The mean rise over `onsets` (summed: only its shape is used).
pub(super) fn mean_rise(rises: &[Vec<f64>], onsets: &[usize]) -> Vec<f64> {
    let mut mean = vec![0.0; rises.first().map_or(0, Vec::len)];
    for &i in onsets {
        mean.iter_mut().zip(&rises[i]).for_each(|(m, r)| *m += r);
    }
    mean
}

/// The nominal in one bell's mean rise (bins from `k_lo`, `df` Hz apart):
/// the peak with the most partials at a tuned bell's ratios to it, its
/// strength counting for up to [`STRONG`] more, none within `near`
/// (fraction) of a frequency of `away` (Hz). Its octave is chosen later
/// with the ring's (`learn::ring_octaves`): taking a strong peak an octave
/// below here (as once for recorded bells) put an eight's treble, heard
/// at its prime, on its tenor's nominal, and the two were one bell.
pub(super) fn nominal_of(mean: &[f64], k_lo: usize, df: f64, away: &[f64], near: f64) -> Option<Pick> {
    let top = mean.iter().copied().fold(0.0, f64::max);
    if top <= 0.0 || mean.len() < 3 {
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
        .map(|k| ((k + k_lo) as f64 * df, k))
        .filter(|(f, _)| away.iter().all(|a| (f - a).abs() >= near * a))
        .map(|(f, k)| (f, score(f), mean[k]))
        .collect();
    // Another bell's partials rising nearby fill a range now and then: a
    // strong peak is taken over a weak one with one partial more.
    let value = |p: &(f64, usize, f64)| p.1 as f64 + STRONG * p.2 / top;
    let best = peaks.iter().max_by(|a, b| value(a).total_cmp(&value(b)))?;
    Some(Pick {
        hz: best.0,
        partials: best.1,
    })
}

/// The bells of `sets` (each the onsets of one bell's strikes), each at
/// its nominal ([`nominal_of`] over its mean rise in `rises`). Two found
/// within twice `same` (fraction) of one nominal are one bell heard two
/// ways, unless `crowded` (by their onsets) says they struck too often
/// for one: then the nominal is the one's it fits more partials of, and
/// the other is heard at its next best peak away from it (in a room a
/// tenor's strikes rose most at the long nominal of the bell before it,
/// and the tenor was lost; 2026-11-27), or, with none, at both.
pub(super) fn apart(
    sets: Vec<Vec<usize>>,
    rises: &[Vec<f64>],
    k_lo: usize,
    df: f64,
    same: f64,
    crowded: impl Fn(usize, usize) -> bool,
) -> Vec<Heard> {
    let mut out: Vec<(Heard, usize)> = vec![];
    for onsets in sets {
        let Some(pick) = nominal_of(&mean_rise(rises, &onsets), k_lo, df, &[], 0.0) else {
            continue;
        };
        let near = 2.0 * same;
        let Some(i) = out
            .iter()
            .position(|(h, _)| (h.nominal_hz - pick.hz).abs() < near * pick.hz)
        else {
            out.push((
                Heard {
                    nominal_hz: pick.hz,
                    onsets,
                },
                pick.partials,
            ));
            continue;
        };
        if !crowded(out[i].0.onsets.len(), onsets.len()) {
            out[i].0.onsets.extend(onsets);
            continue;
        }
        let (hz, partials) = (out[i].0.nominal_hz, out[i].1);
        if pick.partials > partials {
            // The bell found before moves to its next best.
            if let Some(p) = nominal_of(&mean_rise(rises, &out[i].0.onsets), k_lo, df, &[pick.hz], near) {
                out[i] = (
                    Heard {
                        nominal_hz: p.hz,
                        onsets: std::mem::take(&mut out[i].0.onsets),
                    },
                    p.partials,
                );
            }
            out.push((
                Heard {
                    nominal_hz: pick.hz,
                    onsets,
                },
                pick.partials,
            ));
        } else {
            let p = nominal_of(&mean_rise(rises, &onsets), k_lo, df, &[hz], near).unwrap_or(pick);
            out.push((
                Heard {
                    nominal_hz: p.hz,
                    onsets,
                },
                p.partials,
            ));
        }
    }
    out.into_iter().map(|(h, _)| h).collect()
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;

    /// Bins (5 Hz apart, from 150 Hz) of a rise with peaks (Hz, height), each three bins wide.
    pub(in crate::strikes) fn spectrum(peaks: &[(f64, f64)]) -> Vec<f64> {
        let mut s = vec![0.0; 1200];
        for &(f, a) in peaks {
            let k = (f / 5.0).round() as usize - 30;
            s[k] += a;
            s[k - 1] += 0.5 * a;
            s[k + 1] += 0.5 * a;
        }
        s
    }

    /// A recorded treble's rise in a room (d1-d3 of the recorded ring):
    /// its superquint five times its nominal's. Main took the
    /// superquint, which lies 1.4 % below the nominal of the bell a fifth
    /// above: that bell was left out and this one's note guessed.
    #[test]
    fn a_nominal_weaker_than_its_superquint_is_picked() {
        let mean = spectrum(&[
            (325.0, 0.2),
            (650.0, 0.2),
            (775.0, 0.45),
            (1300.0, 0.17),
            (1925.0, 1.0),
            (2620.0, 0.2),
            (3380.0, 0.22),
        ]);
        let pick = nominal_of(&mean, 30, 5.0, &[], 0.0).unwrap();
        assert!((pick.hz - 1300.0).abs() < 6.0, "{pick:?}");
    }

    /// A tenor's strikes in a room, rising most at the long nominal of the
    /// bell struck before it (1310 Hz, with that bell's partials), and that
    /// bell's own: struck too often for one bell, they are two, the tenor
    /// at its own nominal (1237 Hz). Main gave both 1310 Hz, left the
    /// tenor out, and slid the ring's scale to invent a treble above.
    #[test]
    fn a_bell_heard_at_anothers_nominal_moves_to_its_own() {
        let other = [(655.0, 0.3), (775.0, 0.3), (1310.0, 1.0), (1940.0, 0.3), (2620.0, 0.3)];
        let own = [
            (309.0, 0.2),
            (618.0, 0.4),
            (731.0, 0.3),
            (1237.0, 0.3),
            (1861.0, 0.5),
            (2500.0, 0.3),
        ];
        let tenor = spectrum(&[&other[..], &own[..]].concat());
        let bell = spectrum(&[
            (327.0, 0.2),
            (655.0, 0.5),
            (775.0, 0.5),
            (1310.0, 1.0),
            (1940.0, 0.8),
            (2620.0, 0.4),
            (3400.0, 0.3),
        ]);
        let rises: Vec<Vec<f64>> = (0..20)
            .map(|i| if i < 12 { tenor.clone() } else { bell.clone() })
            .collect();
        let sets = vec![(0..12).collect(), (12..20).collect()];
        let heard = apart(sets, &rises, 30, 5.0, 0.008, |_, _| true);
        let mut hz: Vec<f64> = heard.iter().map(|h| h.nominal_hz).collect();
        hz.sort_by(f64::total_cmp);
        assert!(
            hz.len() == 2 && (hz[0] - 1237.0).abs() < 6.0 && (hz[1] - 1310.0).abs() < 6.0,
            "{hz:?}"
        );
        // Not crowded: one bell heard two ways.
        let sets = vec![(0..12).collect(), (12..20).collect()];
        assert_eq!(apart(sets, &rises, 30, 5.0, 0.008, |_, _| false).len(), 1);
    }
}
