//! The ring's scale as the bells heard place it (`clapper strikes --bells
//! N`, [`super::learn`]): its notes, those beyond its ends, how many bells
//! ring from the onsets' rhythm, and the notes no bell was heard at (a
//! bell too quiet to learn keeps its place there). Shared by the learner
//! and leaf to it: it imports nothing from it.

use super::stats::median;

/// A bell heard: its nominal (Hz, as noted) and the onsets that were its strikes.
pub(super) struct Heard {
    pub(super) nominal_hz: f64,
    pub(super) onsets: Vec<usize>,
}

/// A bell lies within this (semitones) of its note of the scale.
pub(super) const IN_TUNE: f64 = 0.45;
/// A major scale's steps (semitones) from its key note: a ring is N
/// consecutive notes of it, from any degree (major, minor and the rest).
pub(super) const DIATONIC: [f64; 7] = [2.0, 2.0, 1.0, 2.0, 2.0, 2.0, 1.0];

/// The bells heard placed on the ring's scale (`learn::ring_octaves`).
pub(super) struct RingFit {
    /// Each bell heard, its nominal moved by octaves onto its note, or
    /// `None` if left out.
    pub(super) moved: Vec<Option<f64>>,
    /// The notes of the scale no bell heard took (Hz).
    pub(super) empty: Vec<f64>,
    /// The scale's notes (Hz), lowest first.
    pub(super) notes: Vec<f64>,
    /// The degree of the major scale its lowest note is (0: the key note).
    pub(super) degree: usize,
    /// The scale's next notes below its lowest and above its highest (Hz,
    /// nearest first, as many as it has): where bells not heard at an end
    /// of the ring may be instead.
    pub(super) beyond: (Vec<f64>, Vec<f64>),
    /// How far this ring's fit stands above the best other ring's (a sum
    /// of bells' fits, 0 to about one a bell; infinite if no other fits):
    /// near 0, the recording fits another set of notes as well.
    pub(super) margin: f64,
}

/// The notes (semitones) of the diatonic scale beyond an end of a ring
/// of `bells` consecutive notes from its `degree`th ([`scale_notes`]),
/// the end at `from`: below it (`dir` -1) or above (+1), nearest first,
/// as many as the ring has bells.
pub(super) fn ring_beyond(degree: usize, bells: usize, from: f64, dir: i32) -> impl Iterator<Item = f64> {
    let n = DIATONIC.len();
    (1..=bells).scan(from, move |p, j| {
        let step = if dir < 0 {
            DIATONIC[(degree + n * bells - j) % n]
        } else {
            DIATONIC[(degree + bells - 2 + j) % n]
        };
        *p += f64::from(dir) * step;
        Some(*p)
    })
}

/// How many bells ring, from the rhythm of the onsets (`onsets`: their
/// frames) of the bells heard (`ring`): a bell strikes once a row, every
/// (bells + 1/2) intervals on average (the handstroke gap), and the
/// onsets come an interval apart. `None` with fewer than two bells heard
/// at four onsets or more. A bell too quiet to be heard leaves its
/// interval empty in every row, so counts.
pub(super) fn ringing(ring: &[(Heard, f64)], onsets: &[usize]) -> Option<f64> {
    // The mean of the steps within half of their median either side
    // (frames are a quarter window apart: a single step is coarse).
    let typical = |mut d: Vec<f64>| -> Option<f64> {
        d.sort_by(f64::total_cmp);
        let mid = *d.get(d.len() / 2)?;
        let near: Vec<f64> = d.into_iter().filter(|&x| x > 0.5 * mid && x < 1.5 * mid).collect();
        (!near.is_empty()).then(|| near.iter().sum::<f64>() / near.len() as f64)
    };
    let steps = |mut t: Vec<usize>| -> Vec<f64> {
        t.sort_unstable();
        t.windows(2).map(|w| (w[1] - w[0]) as f64).collect()
    };
    let interval = typical(steps(onsets.to_vec()))?;
    let rows: Vec<f64> = ring
        .iter()
        .filter(|(b, _)| b.onsets.len() >= 4)
        .filter_map(|(b, _)| typical(steps(b.onsets.iter().map(|&i| onsets[i]).collect())))
        .collect();
    if rows.len() < 2 {
        return None;
    }
    Some(median(rows)? / interval - 0.5)
}

/// The notes of the ring's scale (`fit`) that no bell of `ring` (each
/// heard and its nominal as moved) took: a bell too quiet to be learned
/// (issue 43: one quiet bell made `--bells 8` learn seven and renumber
/// them all, so every strike was given to the wrong bell). It keeps its
/// place at its note, guessed from the scale. Empty notes at the ends of
/// the ring might as well be notes beyond the other end (the bells heard
/// fit both): the scale is slid by whole notes, still holding every bell
/// heard, to where its empty notes' frequencies rise most at the onsets
/// no bell took (summed over `rises`, each against its highest). (On ten
/// handbells 150 ms apart, five heard, the five guessed were the two
/// notes above the treble until slid.)
pub(super) fn unheard_notes(
    fit: &RingFit,
    ring: &[(Heard, f64)],
    ringing: Option<f64>,
    rises: &[Vec<f64>],
    k_lo: usize,
    df: f64,
) -> Vec<f64> {
    let semitone = 2f64.powf(IN_TUNE / 12.0);
    let near = |a: f64, b: f64| a / b < semitone && b / a < semitone;
    let mut empty: Vec<f64> = fit
        .empty
        .iter()
        .copied()
        .filter(|&n| !ring.iter().any(|(_, f)| near(*f, n)))
        .collect();
    let mut taken = vec![false; rises.len()];
    ring.iter().flat_map(|b| &b.0.onsets).for_each(|&i| taken[i] = true);
    let evidence = |note: f64| rise_at(note, &taken, rises, k_lo, df);
    // The ring: as many notes as ring (the onsets' rhythm says, else as
    // asked), holding every bell heard, slid by whole notes so that its
    // tenor is a major or minor key note (a ring's tenor is), then to
    // where its empty notes rise most at the onsets no bell took, a major
    // key before a minor.
    let n = fit.notes.len();
    let ext: Vec<f64> = fit
        .beyond
        .0
        .iter()
        .rev()
        .chain(&fit.notes)
        .chain(&fit.beyond.1)
        .copied()
        .collect();
    let base = fit.beyond.0.len();
    let held: Vec<usize> = (0..n)
        .filter(|&k| !empty.contains(&fit.notes[k]))
        .map(|k| k + base)
        .collect();
    let (Some(&lo), Some(&hi)) = (held.first(), held.last()) else {
        return empty;
    };
    // Fewer ringing than the bells heard and the notes between them span:
    // the onsets missed many strikes (ten handbells 150 ms apart: 40
    // onsets for 240 strikes), and the rhythm says nothing.
    let span = hi - lo + 1;
    let m = match ringing {
        Some(r) if r >= span as f64 - 0.5 => (r.round() as usize).clamp(span, n),
        _ => n,
    };
    let degree = |k: usize| (fit.degree as i64 + k as i64 - base as i64).rem_euclid(DIATONIC.len() as i64);
    let score = |w: usize| -> (bool, f64, bool) {
        let key = degree(w);
        let e = (w..w + m).filter(|k| !held.contains(k)).map(|k| evidence(ext[k])).sum();
        (key == 0 || key == 5, e, key == 0)
    };
    let better = |a: (bool, f64, bool), b: (bool, f64, bool)| {
        if a.0 != b.0 {
            a.0
        } else if (a.1 - b.1).abs() > 1e-9 {
            a.1 > b.1
        } else {
            a.2 && !b.2
        }
    };
    let first = (hi + 1).saturating_sub(m);
    let mut best = (first, score(first));
    for w in first + 1..=lo.min(ext.len() - m) {
        let sc = score(w);
        if better(sc, best.1) {
            best = (w, sc);
        }
    }
    empty = (best.0..best.0 + m)
        .filter(|k| !held.contains(k))
        .map(|k| ext[k])
        .collect();
    empty
}

/// How much `note` (Hz, within [`IN_TUNE`]) rises at the onsets not
/// `taken`: each onset's rise there against its highest (`rises`: bins
/// from `k_lo`, `df` Hz apart), summed.
pub(super) fn rise_at(note: f64, taken: &[bool], rises: &[Vec<f64>], k_lo: usize, df: f64) -> f64 {
    let semitone = 2f64.powf(IN_TUNE / 12.0);
    let (lo, hi) = ((note / semitone / df) as usize, (note * semitone / df).ceil() as usize);
    if lo < k_lo || rises.is_empty() || hi >= k_lo + rises[0].len() {
        return 0.0;
    }
    (0..rises.len())
        .filter(|&i| !taken[i])
        .map(|i| {
            let r = &rises[i];
            let top = r.iter().copied().fold(0.0, f64::max);
            let here = r[lo - k_lo..=hi - k_lo].iter().copied().fold(0.0, f64::max);
            if top > 0.0 {
                here / top
            } else {
                0.0
            }
        })
        .sum()
}

/// Semitones of `bells` consecutive notes of the diatonic scale from its
/// `degree`th (0: the major's key note), the lowest at 0.
pub(super) fn scale_notes(degree: usize, bells: usize) -> Vec<f64> {
    let mut notes = vec![0.0];
    for k in 0..bells.saturating_sub(1) {
        notes.push(notes[k] + DIATONIC[(degree + k) % DIATONIC.len()]);
    }
    notes
}
