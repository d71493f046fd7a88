//! Onsets: each bell's onset function from its bands, the peaks that are
//! strikes (a bell strikes once a row), and each strike timed.

use super::band::{change, Band, SharedBand, BAND_RATE};
use super::heard::{QuietStrokes, StrikeOptions};
use super::stats::{local_peaks, median, typical_peak};
use super::timing::{band_onset, on_one_footing, onset_time, ONSET_LEVEL};

/// One bell as heard: its bands, their changes, and its candidate
/// strikes (band sample, onset function over its typical strike).
pub(super) struct BellHearing {
    pub(super) bands: Vec<Band>,
    pub(super) changes: Vec<Vec<f64>>,
    pub(super) rate: f64,
    pub(super) candidates: Vec<(usize, f64)>,
    /// The onset function over its typical strike, per band sample.
    pub(super) onset: Vec<f64>,
    /// The onset function's median over its typical strike.
    pub(super) floor: f64,
}

pub(super) fn hear_bell(bands: Vec<Band>, opts: &StrikeOptions) -> BellHearing {
    let n = bands.iter().map(|b| b.z.len()).min().unwrap_or(0);
    // Each band's change across a step's rise.
    let changes: Vec<Vec<f64>> = bands.iter().map(|b| change(b)[..n].to_vec()).collect();
    heard_in(bands, changes, opts)
}

/// The bell heard in `bands` with their `changes`: each band's typical
/// step, the onset function, its candidate strikes and its floor.
fn heard_in(mut bands: Vec<Band>, changes: Vec<Vec<f64>>, opts: &StrikeOptions) -> BellHearing {
    let n = changes.iter().map(|c| c.len()).min().unwrap_or(0);
    let rate = bands.first().map_or(BAND_RATE, |b| b.rate);
    let sep = (opts.min_separation_s * rate) as usize;
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
    let onset: Vec<f64> = onset.iter().map(|v| v / typical).collect();
    let candidates = local_peaks(&onset, sep).into_iter().map(|m| (m, onset[m])).collect();
    let floor = median(onset.clone()).unwrap_or(0.0);
    BellHearing {
        bands,
        changes,
        rate,
        candidates,
        onset,
        floor,
    }
}

impl BellHearing {
    /// The bell heard again with what other bells' strikes put into the
    /// bands it shares with them taken out: `others[i]` holds the times
    /// (s) of the strikes of the bells whose partials lie in band `i`,
    /// and about each the band's change is set to none for as far as a
    /// step moves it (a rise and a half either side, and 20 ms for the
    /// other strike's timing). A bell with fewer than two bands of its
    /// own is heard in bands it shares ([`super::plan::plan_bands`]):
    /// on a major ten the 9th's nominal is the 2nd's prime and its only
    /// own band its hum, and the 2nd's strikes stood as high in its onset
    /// function as its own, so that neither was told a strike.
    pub(super) fn without_others(self, others: &[Vec<f64>], opts: &StrikeOptions) -> BellHearing {
        let BellHearing {
            bands,
            mut changes,
            rate,
            ..
        } = self;
        for ((b, c), times) in bands.iter().zip(changes.iter_mut()).zip(others) {
            let reach = (3 * b.rise).div_ceil(2) + (0.02 * rate).round() as usize;
            for &t in times {
                let m = (t * rate).round().max(0.0) as usize;
                let (lo, hi) = (m.saturating_sub(reach), (m + reach + 1).min(c.len()));
                if lo < hi {
                    c[lo..hi].iter_mut().for_each(|v| *v = 0.0);
                }
            }
        }
        heard_in(bands, changes, opts)
    }

    /// The strikes: (onset s, strength).
    pub(super) fn firsts(&self, opts: &StrikeOptions, bells: usize) -> Vec<(f64, f64)> {
        self.timed_at(self.kept(opts, bells), opts)
    }

    /// [`Self::firsts`] with the bell's quieter strokes found by the
    /// ring's rhythm ([`quiet_stroke_in_rhythm`], `period_s` the ring's
    /// typical interval between a bell's strikes, s; `others` the other
    /// bells' strikes, s, in time order), where its strikes keep two rows
    /// apart and the quieter strokes are there; else none (the bell's
    /// strikes stand as [`Self::firsts`] has them).
    pub(super) fn firsts_at_both_strokes(
        &self,
        opts: &StrikeOptions,
        bells: usize,
        period_s: f64,
        others: &[f64],
    ) -> Option<Vec<(f64, f64)>> {
        let period = period_s * self.rate;
        if !(period.is_finite() && period > 0.0) {
            return None;
        }
        let kept = self.kept(opts, bells);
        let others: Vec<usize> = others
            .iter()
            .map(|t| (t * self.rate).round().max(0.0) as usize)
            .collect();
        let quiet = quiet_stroke_in_rhythm(&self.onset, &kept, &others, bells, period);
        if quiet.is_empty() {
            return None;
        }
        // Each quieter stroke timed as far after its onset function's peak
        // as the bell's louder strokes are (the median): its own bands,
        // stepped a third as far over the louder stroke's ringing, timed
        // it 20-60 ms off either way, and the bell's lateness learned
        // from the recording's strikes moved with them.
        let lag: Vec<f64> = kept
            .iter()
            .filter_map(|&(m, _)| {
                Some(onset_time(&self.bands, &self.changes, self.first_of_double(m, opts))? - m as f64 / self.rate)
            })
            .collect();
        let lag = median(lag)?;
        let mut all = self.timed_at(kept, opts);
        all.extend(quiet.into_iter().map(|(m, h)| (m as f64 / self.rate + lag, h)));
        all.sort_by(|a, b| a.0.total_cmp(&b.0));
        Some(all)
    }

    /// Each of `kept` (band sample, height) timed: (onset s, strength).
    fn timed_at(&self, kept: Vec<(usize, f64)>, opts: &StrikeOptions) -> Vec<(f64, f64)> {
        kept.into_iter()
            .filter_map(|(m, h)| {
                let m = self.first_of_double(m, opts);
                Some((onset_time(&self.bands, &self.changes, m)?, h))
            })
            .collect()
    }

    /// The candidates taken as strikes, before timing (band sample,
    /// height; in time order).
    fn kept(&self, opts: &StrikeOptions, bells: usize) -> Vec<(usize, f64)> {
        let heights: Vec<f64> = self.candidates.iter().map(|c| c.1).collect();
        let Some(threshold) = strike_threshold(&heights, self.floor) else {
            return vec![];
        };
        let mut kept = once_a_row(
            self.candidates.iter().copied().filter(|c| c.1 >= threshold).collect(),
            bells,
        );
        if self.echo_of_the_last(&kept) {
            kept.pop();
        }
        let quiet = if opts.quiet_strokes == QuietStrokes::Between {
            other_stroke(&self.candidates, &kept, bells)
        } else {
            vec![]
        };
        if !quiet.is_empty() {
            kept.extend(quiet);
            kept.sort_by_key(|k| k.0);
        }
        kept
    }

    /// The strikes of a bell whose candidates do not stand clear of the
    /// rest ([`strike_threshold`] finds no split: every peak alike and the
    /// onset function high between them), chosen by the ring's rhythm:
    /// the chain of candidates ([`in_rhythm`]) a row apart (`period_s`,
    /// the ring's typical interval between a bell's strikes), if it keeps
    /// to it ([`keeps_time`]); else none. A 10 dB swing with a Doppler
    /// shift of 0.8 % turns a long band's phase 0.6 s after each strike
    /// as far as a strike steps it, and a bell heard only in its hum and
    /// tierce (50 ms boxes) had a false peak there as high as each of its
    /// strikes: no strike at all was taken.
    /// Where no bell stood clear (`unclear`: the period from the
    /// candidates), the chain may keep time more loosely ([`keeps_time`]).
    pub(super) fn firsts_in_rhythm(
        &self,
        opts: &StrikeOptions,
        bells: usize,
        period_s: f64,
        unclear: bool,
    ) -> Vec<(f64, f64)> {
        let period = period_s * self.rate;
        if !(period.is_finite() && period > 0.0) {
            return vec![];
        }
        let cands: Vec<(usize, f64)> = self.candidates.iter().copied().filter(|c| c.1 >= 0.3).collect();
        let kept = in_rhythm(&cands, bells, period);
        if !keeps_time(&kept, bells, period, unclear.then_some(self.rate)) {
            return vec![];
        }
        kept.into_iter()
            .filter_map(|(m, h)| {
                let m = self.first_of_double(m, opts);
                Some((onset_time(&self.bands, &self.changes, m)?, h))
            })
            .collect()
    }

    /// Whether the last of `kept` (band sample, height), weak, is what
    /// every strike of the bell leaves in its onset function at that lag
    /// after it: the last strike before it is followed by a bump at the
    /// same lag as the rest are (a doublet's beat null turning the band's
    /// phase over, on `clapper synth-ring`'s bells 1.2-1.5 s after each
    /// strike). Inside the ring the bell's next strike outweighs it
    /// ([`once_a_row`]); after the ring has stopped nothing does (the
    /// tenor heard 1.35 s after the last strike at RT60 1.5 s). It is
    /// an echo where it stands less than twice as high as the median
    /// bump at that lag (±10 ms) after the bell's other strikes, each
    /// looked at only where its next strike comes later.
    fn echo_of_the_last(&self, kept: &[(usize, f64)]) -> bool {
        let [.., prev, last] = kept else {
            return false;
        };
        // Weak beside the typical strike, with the rhythm known.
        if last.1 >= 0.5 || kept.len() < 7 {
            return false;
        }
        let lag = last.0 - prev.0;
        let tol = (0.01 * self.rate).round() as usize;
        let mut bumps: Vec<f64> = vec![];
        for w in kept[..kept.len() - 1].windows(2) {
            let (at, next) = (w[0].0 + lag, w[1].0);
            if at + tol + 1 >= next.saturating_sub(tol) || at + tol + 1 > self.onset.len() {
                continue;
            }
            bumps.push(
                self.onset[at.saturating_sub(tol)..at + tol + 1]
                    .iter()
                    .fold(0.0, |a: f64, &v| a.max(v)),
            );
        }
        bumps.len() >= 5 && median(bumps).is_some_and(|m| last.1 < 2.0 * m)
    }

    /// Every strike timed again from all the bands where it is heard, its
    /// own and those it shares (where no sharing bell strikes nearby), on
    /// one footing: in a room each band hears a bell's strikes late (or
    /// early) by the same amount every time (the room's sound at that
    /// partial), so each band's lateness is learned over the strikes and
    /// taken off ([`on_one_footing`]), and the lateness the bell is heard
    /// with is the weighted median of the bands'. A band
    /// heard in some strikes and not others (a shared band, quiet only
    /// between the sharers' strikes) then moves none of them against the
    /// rest: a handstroke and a backstroke have different neighbours.
    pub(super) fn timed(&self, found: Vec<(f64, f64)>, shared: &[SharedBand], times: &[Vec<f64>]) -> Vec<(f64, f64)> {
        let n = found.len();
        // Per strike, per band: the onset heard there and its weight.
        let mut est: Vec<Vec<Option<(f64, f64)>>> = Vec::with_capacity(n);
        for &(t, _) in &found {
            let m = (t * self.rate).round() as usize;
            let mut row: Vec<Option<(f64, f64)>> = self
                .bands
                .iter()
                .zip(&self.changes)
                .map(|(b, c)| band_onset(b, c, m, false, ONSET_LEVEL))
                .collect();
            row.extend(shared.iter().map(|sb| {
                let reach = 2.0 * sb.band.rise as f64 / sb.band.rate + 0.02;
                let quiet = sb
                    .with
                    .iter()
                    .all(|&o| times.get(o).is_none_or(|v| v.iter().all(|&u| (u - t).abs() > reach)));
                if quiet {
                    band_onset(&sb.band, &sb.change, m, true, ONSET_LEVEL)
                } else {
                    None
                }
            }));
            est.push(row);
        }
        let at = on_one_footing(&est);
        found
            .into_iter()
            .zip(at)
            .map(|((t, h), a)| (a.unwrap_or(t), h))
            .collect()
    }

    /// A peak of the onset function may be the second strike of a double
    /// (as loud as the first, or louder): the first is an earlier peak
    /// within the double-strike window at least half as high, with a dip
    /// to 0.8 of it between. Judged on each set of the bell's shortest
    /// bands (those of rise up to each band's), where the second is the
    /// set's peak nearest the onset function's and the two stand at least
    /// the set's longest rise apart, so that its bands can part them: a
    /// long band (a hum's 50 ms boxes) holds one broad change across both
    /// and fills the dip (in a room, 13 of the 20 doubles missed over the
    /// benchmark's first 20 recordings at RT60 1.2 s were timed at their
    /// second strike, judged on all the bands at a dip to 0.7). The first
    /// must also stand half as high as the second in the onset function
    /// itself (a short band alone is noisy). Of several, the highest there.
    pub(super) fn first_of_double(&self, m: usize, opts: &StrikeOptions) -> usize {
        let (dmin, dmax) = opts.double_window_ms;
        let (dmin, dmax) = (
            (dmin * 1e-3 * self.rate).round() as usize,
            (dmax * 1e-3 * self.rate).round() as usize,
        );
        // The onset function's peak is off a short band's by up to half the longest rise.
        let lag = self.bands.iter().map(|b| b.rise / 2).max().unwrap_or(0);
        let end = (m + lag + 2).min(self.onset.len());
        let lo = m.saturating_sub(dmax + lag).max(1);
        if lo + 2 >= end {
            return m;
        }
        let mut rises: Vec<usize> = self.bands.iter().map(|b| b.rise).collect();
        rises.sort_unstable();
        rises.dedup();
        let mut best: Option<usize> = None;
        for &x in &rises {
            let used: Vec<usize> = (0..self.bands.len()).filter(|&i| self.bands[i].rise <= x).collect();
            // Over lo−1..end.
            let v: Vec<f64> = if used.len() == self.bands.len() {
                self.onset[lo - 1..end].to_vec()
            } else {
                (lo - 1..end)
                    .map(|j| {
                        used.iter()
                            .map(|&i| self.bands[i].weight * self.changes[i][j] / self.bands[i].scale)
                            .sum::<f64>()
                    })
                    .collect()
            };
            let at = |j: usize| v[j + 1 - lo];
            // The second strike in these bands: their peak nearest m.
            let Some(p) = (m.saturating_sub(lag).max(lo)..(m + lag + 1).min(end - 1))
                .filter(|&j| at(j) >= at(j - 1) && at(j) > at(j + 1))
                .min_by_key(|&j| j.abs_diff(m))
            else {
                continue;
            };
            let vp = at(p);
            let first = p.saturating_sub(dmax).max(lo);
            let last = p.saturating_sub(dmin.max(x));
            for k in first..last.min(end - 1) {
                let vk = at(k);
                let dip = (k..p).map(at).fold(f64::INFINITY, f64::min);
                if vk > 0.0
                    && vk >= at(k - 1)
                    && vk > at(k + 1)
                    && vk >= 0.5 * vp
                    && dip <= 0.8 * vk
                    && self.onset[k] >= 0.5 * self.onset[m]
                    && best.is_none_or(|b| self.onset[k] > self.onset[b])
                {
                    best = Some(k);
                }
            }
        }
        best.unwrap_or(m)
    }
}

/// A bell rung full circle strikes once a row, and moves at most one place
/// a row: in a ring of `bells`, its interval is at least (bells − 1) places
/// where its typical one (the median between its strong strikes, those at
/// least 0.7 of typical) is about bells + ½ (a row and half the handstroke
/// gap). Of two strikes closer than 0.9 of that shortest interval (0.5 of
/// typical at least, for the smallest rings), the weaker is not a strike.
/// Strikes are (band sample, height) in time order; fewer than six strong
/// ones say too little of the rhythm and are kept as they are.
pub(super) fn once_a_row(strikes: Vec<(usize, f64)>, bells: usize) -> Vec<(usize, f64)> {
    let strong: Vec<usize> = strikes.iter().filter(|s| s.1 >= 0.7).map(|s| s.0).collect();
    if strong.len() < 6 {
        return strikes;
    }
    let mut gaps: Vec<usize> = strong.windows(2).map(|w| w[1] - w[0]).collect();
    gaps.sort_unstable();
    let n = bells as f64;
    let factor = (0.9 * (n - 1.0) / (n + 0.5)).max(0.5);
    let sep = (factor * gaps[gaps.len() / 2] as f64) as usize;
    let mut order: Vec<usize> = (0..strikes.len()).collect();
    order.sort_by(|&a, &b| strikes[b].1.total_cmp(&strikes[a].1).then(a.cmp(&b)));
    let mut keep = vec![false; strikes.len()];
    for i in order {
        let near = |j: usize| keep[j] && strikes[i].0.abs_diff(strikes[j].0) < sep;
        if !(0..strikes.len()).any(near) {
            keep[i] = true;
        }
    }
    strikes
        .into_iter()
        .zip(keep)
        .filter(|(_, k)| *k)
        .map(|(s, _)| s)
        .collect()
}

/// The least height (over the typical strike) of a bell's strike at its
/// quieter stroke ([`other_stroke`]): 12 dB down is 0.25.
const QUIET_STROKE_MIN: f64 = 0.15;

/// A bell quieter at one stroke than the other (issue 43: a tower bell's
/// level is not the same at hand and back): the split between strikes and
/// the rest ([`strike_threshold`]) falls between its two strokes, or its
/// louder strokes alone set its rhythm to two rows ([`once_a_row`]), and
/// `kept` (band sample, height; in time order) holds only its louder
/// stroke. Its quieter strokes are then the `cands` (at least
/// [`QUIET_STROKE_MIN`]) one in the middle of each interval between two
/// kept strikes, within the bell's moving a place a row and the
/// handstroke gap (1.5 places of the pair of rows, 2 `bells` + 1 places);
/// taken where half the intervals or more (five at least) have one, else
/// none. On the tester's six with bell 5 9.2 dB quieter at backstroke,
/// 11-12 of its 16-19 intervals had one (some kept pairs are four rows
/// apart), a bell heard at both strokes 0-2 of 15-31.
fn other_stroke(cands: &[(usize, f64)], kept: &[(usize, f64)], bells: usize) -> Vec<(usize, f64)> {
    if kept.len() < 6 {
        return vec![];
    }
    let places = 2.0 * bells as f64 + 1.0;
    let found: Vec<(usize, f64)> = kept
        .windows(2)
        .filter_map(|w| {
            let (a, b) = (w[0].0 as f64, w[1].0 as f64);
            let (mid, tol) = (0.5 * (a + b), 1.5 / places * (b - a));
            cands
                .iter()
                .filter(|c| c.1 >= QUIET_STROKE_MIN && (c.0 as f64 - mid).abs() <= tol)
                .max_by(|x, y| x.1.total_cmp(&y.1))
                .copied()
        })
        .collect();
    if found.len() >= 5 && 2 * found.len() >= kept.len() - 1 {
        found
    } else {
        vec![]
    }
}

/// How far either side of where a bell heard at one stroke only must
/// strike at its other stroke its quieter strike is listened for
/// ([`quiet_stroke_in_rhythm`]), in places: a bell moves at most a place
/// a row, so its other stroke is at most a place from the middle of its
/// two rows (half a place more or less for the handstroke gap).
const IN_RHYTHM_PLACES: f64 = 1.25;

/// The least height (over the typical strike) of a quieter stroke found
/// by the ring's rhythm ([`quiet_stroke_in_rhythm`]): lower than
/// [`QUIET_STROKE_MIN`], the window being narrower.
const IN_RHYTHM_MIN: f64 = 0.1;

/// How many times the ring's typical interval between a bell's strikes
/// (its period: a bell's median interval, between `bells` and `bells` + 1
/// places, hand to back a row and back to hand a row and the handstroke
/// gap) two rows of a bell heard at one stroke only span, at least and at
/// most: two rows are 2 `bells` + 1 places, two more or less for a bell
/// moving a place each row (hunting), so from (2 `bells` − 1) over
/// `bells` + 1 to (2 `bells` + 3) over `bells`: 1.57-2.5 on six, 1.67-2.38
/// on eight.
/// A bell heard at both strokes keeps at most (`bells` + 2) / `bells`
/// between strikes (1.4 on five). At 1.7-2.4 a hunting six's intervals
/// down (1.6-1.7) failed: tester20's R1 (Plain Bob Minor, bell 5 9 dB
/// quieter at hand, the period read as 6.1 places) had 12 of 15 of its
/// intervals there and no quiet stroke was looked for; at 1.5-2.6, 14.
const ONE_STROKE_ROWS: (f64, f64) = (1.5, 2.6);

/// The rows (two or four) an interval `d` (band samples) between the
/// strikes of a bell heard at one stroke only spans, the ring's typical
/// interval between a bell's strikes being `period` (band samples):
/// [`ONE_STROKE_ROWS`] periods, or twice that (a louder stroke lost
/// between); else none.
fn rows_between(d: usize, period: f64) -> Option<usize> {
    let x = d as f64 / period;
    [2, 4].into_iter().find(|&k| {
        let r = x / (k / 2) as f64;
        (ONE_STROKE_ROWS.0..=ONE_STROKE_ROWS.1).contains(&r)
    })
}

/// How far after another bell's strike (its time heard) a peak of a
/// quiet bell's onset function is taken for that strike heard in its
/// bands ([`quiet_stroke_in_rhythm`]), in places (a quarter of a place
/// before it): in a room whose tail is as loud as the direct sound a
/// strike's step in a neighbour's bands goes on rising after it is heard,
/// and the next bell's strike stood 70-90 ms (a third of a place) after
/// its time heard, higher than the quiet stroke a place before it
/// (tester20's R1, bell 5: 3 of its 12 quiet strokes taken there, a
/// place late).
const AFTER_OTHER_PLACES: f64 = 0.5;

/// A bell heard at one stroke only with the band finder's split between
/// strikes and the rest (`kept`, band sample, height; in time order):
/// the other stroke 6-15 dB quieter below it (issue 43, `--nominals`).
/// Its kept strikes keep two rows apart (seven in eight of its intervals
/// two or four rows, [`rows_between`]; a bell heard at both strokes
/// that loses a strike here and there has intervals of one and three
/// rows; at three in four, a bell whose strikes' spectra vary, heard at
/// one stroke for a while, had its other strokes taken and was timed
/// worse, tune ring A8_tilt 0.725 -> 0.572 within 10 ms), and its
/// quieter strokes are then the highest peaks of its onset function
/// `onset` (at least [`IN_RHYTHM_MIN`]) within [`IN_RHYTHM_PLACES`] of
/// the middle of each pair of rows (a place being
/// `period` over `bells` + ½), none from a quarter of a place before
/// another bell's strike to [`AFTER_OTHER_PLACES`] after it (`others`,
/// band samples, in time order: heard in this bell's bands), taken where three in four of those places or more
/// (five at least) have one; else none. The onset function itself, not the
/// candidates: a candidate is the highest peak within half a second, and
/// a quiet stroke often stands beside another bell's strike or its own
/// sound swelling again. Listened for only there, and only at such a
/// bell: with the nominals' assumed partials a recorded bell's sound
/// swells again about a second after each strike, and a search at every
/// bell took that (docs/strikes.md, nom-8).
fn quiet_stroke_in_rhythm(
    onset: &[f64],
    kept: &[(usize, f64)],
    others: &[usize],
    bells: usize,
    period: f64,
) -> Vec<(usize, f64)> {
    if kept.len() < 6 {
        return vec![];
    }
    let rows: Vec<Option<usize>> = kept.windows(2).map(|w| rows_between(w[1].0 - w[0].0, period)).collect();
    if 8 * rows.iter().flatten().count() < 7 * rows.len() {
        return vec![];
    }
    let place = period / (bells as f64 + 0.5);
    let tol = IN_RHYTHM_PLACES * place;
    let (before, after) = ((0.25 * place) as usize, (AFTER_OTHER_PLACES * place) as usize);
    let near_other = |m: usize| {
        let k = others.partition_point(|&u| u < m);
        others.get(k).is_some_and(|&u| u - m <= before) || (k > 0 && m - others[k - 1] <= after)
    };
    let (mut places, mut found) = (0, vec![]);
    for (w, k) in kept.windows(2).zip(rows) {
        let Some(k) = k else { continue };
        let (a, b) = (w[0].0 as f64, w[1].0 as f64);
        for j in 0..k / 2 {
            let at = a + (2 * j + 1) as f64 / k as f64 * (b - a);
            places += 1;
            let lo = ((at - tol).max(1.0)) as usize;
            let hi = ((at + tol) as usize).min(onset.len().saturating_sub(1));
            let best = (lo..hi)
                .filter(|&m| onset[m] >= onset[m - 1] && onset[m] > onset[m + 1] && !near_other(m))
                .max_by(|&x, &y| onset[x].total_cmp(&onset[y]).then(y.cmp(&x)))
                .filter(|&m| onset[m] >= IN_RHYTHM_MIN);
            found.extend(best.map(|m| (m, onset[m])));
        }
    }
    if found.len() >= 5 && 4 * found.len() >= 3 * places {
        found
    } else {
        vec![]
    }
}

/// How far an interval `d` (band samples) is from a whole number of
/// rows (`period`, 1 to 3: a strike or two lost between) beyond what a
/// bell's moving a place a row and the handstroke gap allow (1.5 places
/// of a row of `bells` + ½), in rows; 1 past three rows.
fn off_rhythm(d: usize, bells: usize, period: f64) -> f64 {
    let x = d as f64 / period;
    let k = x.round();
    if !(1.0..=3.0).contains(&k) {
        return 1.0;
    }
    let tol = 1.5 / (bells as f64 + 0.5);
    ((x - k).abs() - tol).max(0.0)
}

/// What an interval off the rhythm costs a chain of strikes (in typical
/// strikes' heights): a false peak a third of a row after each strike,
/// as high as the strike, puts two intervals off it.
const OFF_RHYTHM_COST: f64 = 0.5;

/// Of `cands` (band sample, height; in time order), the chain a bell of
/// a ring of `bells` could strike (no two closer than [`once_a_row`]
/// allows) with the most height less what its intervals off the rhythm
/// (`period`, band samples) cost: each costs [`OFF_RHYTHM_COST`] from
/// the tolerance on up to twice it (linearly), the whole beyond that.
fn in_rhythm(cands: &[(usize, f64)], bells: usize, period: f64) -> Vec<(usize, f64)> {
    let n = bells as f64;
    let sep = ((0.9 * (n - 1.0) / (n + 0.5)).max(0.5) * period) as usize;
    let tol = 1.5 / (n + 0.5);
    let reach = (3.5 * period) as usize;
    // Best chain ending at each candidate: (score, previous).
    let mut best: Vec<(f64, Option<usize>)> = Vec::with_capacity(cands.len());
    for (i, c) in cands.iter().enumerate() {
        let mut here = (c.1, None);
        // Every earlier candidate within 3.5 rows, and the best chain
        // ending before those (an interval off the rhythm).
        let mut far: Option<usize> = None;
        for j in (0..i).rev() {
            let d = c.0 - cands[j].0;
            if d < sep {
                continue;
            }
            if d > reach {
                far = Some(far.map_or(j, |f| if best[j].0 > best[f].0 { j } else { f }));
                continue;
            }
            let cost = OFF_RHYTHM_COST * (off_rhythm(d, bells, period) / tol).min(1.0);
            let s = best[j].0 - cost + c.1;
            if s > here.0 {
                here = (s, Some(j));
            }
        }
        if let Some(f) = far {
            let s = best[f].0 - OFF_RHYTHM_COST + c.1;
            if s > here.0 {
                here = (s, Some(f));
            }
        }
        best.push(here);
    }
    let Some(mut at) = (0..best.len()).max_by(|&a, &b| best[a].0.total_cmp(&best[b].0).then(b.cmp(&a))) else {
        return vec![];
    };
    let mut chain = vec![cands[at]];
    // Each step goes to an earlier candidate: at most one per candidate.
    while let Some(p) = best[at].1 {
        chain.push(cands[p]);
        at = p;
    }
    chain.reverse();
    chain
}

/// How late the band finder may hear one strike beside the next, beyond
/// the ring's rhythm (s): in a fast ring it hears a bell's strike where
/// its bands' steps rise through the next bells' strikes (the tester's
/// eight at 150 ms: 170-380 ms late, a place or two).
const HEARD_JITTER_S: f64 = 0.15;

/// Whether a chain of strikes `kept` (band sample, height) keeps to the
/// rhythm of a ring of `bells` (`period`, band samples): at least six,
/// three in four of its intervals within [`off_rhythm`]'s tolerance, and
/// no more than a third of its rows without one; or, where `jitter_at` is
/// given (the band samples a second: no bell of the ring stood clear), a
/// strike in nearly every row (0.85), three in four within
/// [`HEARD_JITTER_S`] more. With the tolerance alone, the tester's
/// eight at 150 ms (Plain Bob Major) kept 58-74 % of its intervals (a
/// strike in 85-95 % of its rows) and lost its middle minute; with the
/// jitter wherever a bell did not stand clear, a false chain of 30 strikes
/// on a Stedman Caters (0.18 s), where other bells did, put its
/// recording's timing off (`--nominals`, recall within 10 ms 0.42 ->
/// 0.12).
fn keeps_time(kept: &[(usize, f64)], bells: usize, period: f64, jitter_at: Option<f64>) -> bool {
    let (Some(first), Some(last)) = (kept.first(), kept.last()) else {
        return false;
    };
    let on = |slack: f64| {
        kept.windows(2)
            .filter(|w| {
                let x = (w[1].0 - w[0].0) as f64 / period;
                off_rhythm(w[1].0 - w[0].0, bells, period) <= slack && (1.0..=3.0).contains(&x.round())
            })
            .count()
    };
    let rows = (last.0 - first.0) as f64 / period + 1.0;
    let n = kept.len();
    let strict = 4 * on(0.0) >= 3 * (n - 1) && n as f64 >= rows * 2.0 / 3.0;
    let jittered =
        jitter_at.is_some_and(|rate| 4 * on(HEARD_JITTER_S * rate / period) >= 3 * (n - 1) && n as f64 >= rows * 0.85);
    n >= 6 && (strict || jittered)
}

/// The height that parts strikes from the rest (heights over the typical
/// strike): Otsu's split of the peaks' logarithms, if the two groups stand
/// a factor 2 apart. If they do not, the peaks are all alike: all strikes
/// when the typical one stands five times above the onset function's
/// median `floor` (nothing else came between them), else nothing (the
/// bell was not heard).
pub(super) fn strike_threshold(heights: &[f64], floor: f64) -> Option<f64> {
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

#[cfg(test)]
mod tests {
    use super::*;

    /// A bell of eight at 150 ms (rows of 1.275 s at 1 kHz band samples)
    /// heard a place or two late at every third strike (the tester's
    /// pb8f): the chain keeps time only where no bell stood clear.
    #[test]
    fn a_chain_heard_late_keeps_time_only_where_no_bell_stood_clear() {
        let period = 1275.0;
        let kept: Vec<(usize, f64)> = (0..40)
            .map(|k| (1275 * k + if k % 3 == 1 { 330 } else { 0 }, 1.0))
            .collect();
        assert!(!keeps_time(&kept, 8, period, None));
        assert!(keeps_time(&kept, 8, period, Some(1000.0)));
        // A strike in only two rows in three: not even so.
        let sparse: Vec<(usize, f64)> = kept
            .iter()
            .enumerate()
            .filter(|(k, _)| k % 3 != 2)
            .map(|(_, c)| *c)
            .collect();
        assert!(!keeps_time(&sparse, 8, period, Some(1000.0)));
    }

    #[test]
    fn a_bell_strikes_once_a_row() {
        // Eight bells: strikes every 2 s (band samples at 1 kHz), one
        // missing (a gap of 4 s), with a weak impostor 0.7 s after one; the
        // shortest true interval is 7/8.5 of typical.
        let mut s: Vec<(usize, f64)> = (0..10).filter(|&k| k != 5).map(|k| (2000 * k, 1.0)).collect();
        s.push((4700, 0.45));
        s.sort_by_key(|x| x.0);
        let kept = once_a_row(s.clone(), 8);
        assert!(!kept.contains(&(4700, 0.45)), "{kept:?}");
        assert_eq!(kept.len(), 9);
        // Too few strong strikes to know the rhythm: all kept.
        let few = vec![(0, 1.0), (700, 0.5), (2000, 1.0)];
        assert_eq!(once_a_row(few.clone(), 8), few);
    }

    /// Six bells ringing plain hunt at `rate` (Hz), bell 5 9 dB quieter at
    /// every backstroke: the recording, its strikes and each bell's
    /// sound struck alone (partials building up over 5 ms after the
    /// clapper's click).
    fn quiet_at_backstroke(rate: f64) -> (crate::Signal, Vec<crate::tower::TrueStrike>, Vec<crate::Signal>) {
        use crate::sampled_ring::{Blow, UntunedStrike};
        use crate::tower::{in_the_room, major_scale, tower_strikes, Method, TowerSpec};
        let bells = major_scale(6, 1000.0).unwrap();
        let strike = |nominal_hz: f64| {
            let blow = Blow {
                amplitude: 0.6,
                decay_s: 0.002,
                seed: (nominal_hz * 1000.0) as u64 | 1,
            };
            let sound = UntunedStrike {
                nominal_hz,
                rise_s: 0.005,
                decay_s: 0.8,
                length_s: 1.5,
                blow: Some(blow),
            };
            sound.signal(rate)
        };
        let templates: Vec<crate::Signal> = bells.iter().map(|b| strike(b.nominal_hz)).collect();
        let spec = TowerSpec {
            rate,
            rows: 48,
            interval: 0.25,
            jitter: 0.005,
            method: Method::PlainHunt,
            snr_db: Some(30.0),
            ..TowerSpec::new(bells)
        };
        let truth = tower_strikes(&spec).unwrap();
        let end = truth.iter().map(|s| s.t).fold(0.0, f64::max) + spec.tail;
        let n = (end * rate) as usize;
        let mut mix = vec![0.0; n];
        for s in &truth {
            let gain = if s.bell == 5 && !s.hand {
                10f64.powf(-9.0 / 20.0)
            } else {
                1.0
            };
            let i0 = (s.t * rate).round() as usize;
            for (k, v) in templates[s.bell - 1].samples.iter().enumerate() {
                if let Some(m) = mix.get_mut(i0 + k) {
                    *m += gain * v;
                }
            }
        }
        let samples = in_the_room(mix, &spec, truth[0].t, n);
        (crate::Signal { rate, samples }, truth, templates)
    }

    /// An onset function (band samples at 1 kHz) of a bell of six struck
    /// at `strikes` (band sample, height), each peak 20 samples wide over
    /// a floor of 0.02.
    fn onset_of(strikes: &[(usize, f64)], len: usize) -> Vec<f64> {
        let mut v = vec![0.02; len];
        for &(m, h) in strikes {
            for (k, x) in v.iter_mut().enumerate().take(m + 20).skip(m.saturating_sub(20)) {
                *x = f64::max(*x, 0.02 + h * (1.0 - k.abs_diff(m) as f64 / 20.0));
            }
        }
        v
    }

    /// A bell heard at one stroke only (strikes 2 rows apart, rows of six
    /// at 220 ms with a handstroke gap: 1.32 and 1.54 s) has its quieter
    /// strokes (0.3 high, a place before the middle) taken; not a peak
    /// on another bell's strike, nor where there is none; and a bell
    /// heard at both strokes that lost a strike here and there (intervals
    /// of one and three rows) has none looked for.
    #[test]
    fn a_quiet_stroke_is_listened_for_where_the_rhythm_puts_it() {
        let period = 1430.0;
        let hand: Vec<(usize, f64)> = (0..12).map(|k| (500 + 2860 * k, 1.0)).collect();
        let back: Vec<(usize, f64)> = hand.iter().map(|h| (h.0 + 1320, 0.3)).collect();
        let len = 500 + 2860 * 12;
        let mut all = hand.clone();
        all.extend(back[..11].iter().copied());
        let onset = onset_of(&all, len);
        let found = quiet_stroke_in_rhythm(&onset, &hand, &[], 6, period);
        let want: Vec<usize> = back[..11].iter().map(|b| b.0).collect();
        assert_eq!(found.iter().map(|f| f.0).collect::<Vec<_>>(), want);
        // Silent at backstroke: nothing.
        assert!(quiet_stroke_in_rhythm(&onset_of(&hand, len), &hand, &[], 6, period).is_empty());
        // Each backstroke's peak on another bell's strike: not taken.
        let others: Vec<usize> = want.iter().map(|m| m + 30).collect();
        assert!(quiet_stroke_in_rhythm(&onset, &hand, &others, 6, period).is_empty());
        // Heard at both strokes, every third strike lost: nothing looked for.
        let both: Vec<(usize, f64)> = (0..24)
            .filter(|k| k % 3 != 1)
            .map(|k| (500 + 1430 * k - if k % 2 == 1 { 110 } else { 0 }, 1.0))
            .collect();
        let mut with_bumps = both.clone();
        with_bumps.extend(both.iter().map(|b| (b.0 + 700, 0.3)));
        let onset = onset_of(&with_bumps, len);
        assert!(quiet_stroke_in_rhythm(&onset, &both, &[], 6, period).is_empty());
    }

    /// A bell of six heard at one stroke only while it hunts (rows of six
    /// at 220 ms with a handstroke gap, its period 1.43 s: two rows less
    /// two places, 2.42 s, is 1.69 periods, then two rows and two places)
    /// has its quieter strokes taken (tester20's R1); and a peak a third
    /// of a place after another bell's strike is that strike heard in its
    /// bands, not taken.
    #[test]
    fn a_hunting_six_heard_at_one_stroke_has_its_quiet_strokes_listened_for() {
        let period = 1430.0;
        let mut hand: Vec<(usize, f64)> = vec![(500, 1.0)];
        for k in 1..12 {
            let d = if k % 2 == 1 { 2420 } else { 3300 };
            hand.push((hand[k - 1].0 + d, 1.0));
        }
        let back: Vec<(usize, f64)> = hand.windows(2).map(|w| ((w[0].0 + w[1].0) / 2, 0.3)).collect();
        let len = hand[11].0 + 2000;
        let mut all = hand.clone();
        all.extend(back.iter().copied());
        let onset = onset_of(&all, len);
        let found = quiet_stroke_in_rhythm(&onset, &hand, &[], 6, period);
        let want: Vec<usize> = back.iter().map(|b| b.0).collect();
        assert_eq!(found.iter().map(|f| f.0).collect::<Vec<_>>(), want);
        // Each backstroke's peak 80 ms (0.36 of a 220 ms place) after
        // another bell's strike: not taken.
        let others: Vec<usize> = want.iter().map(|m| m - 80).collect();
        assert!(quiet_stroke_in_rhythm(&onset, &hand, &others, 6, period).is_empty());
    }

    /// A bell 9 dB quieter at every backstroke (issue 43; the tester's
    /// A6_quietback, bell 5): its backstrokes were lost (0 of 24 found
    /// without [`other_stroke`]: its louder strokes alone set its rhythm
    /// to two rows); they are strikes, and the other bells keep theirs.
    #[test]
    fn a_bell_quieter_at_backstroke_is_heard_at_both_strokes() {
        use crate::strikes::{find_strikes, BellVoice};
        let (sig, truth, templates) = quiet_at_backstroke(16_000.0);
        let voices: Vec<BellVoice> = templates.iter().map(|t| BellVoice::from_template(t).unwrap()).collect();
        let opts = StrikeOptions {
            quiet_strokes: QuietStrokes::Between,
            ..StrikeOptions::default()
        };
        let heard = find_strikes(&sig, &voices, &opts).unwrap();
        // Share of the strikes (of `bell`, at `hand`) heard within 10 ms
        // before to 40 ms after.
        let found = |bell: usize, hand: bool| {
            let of: Vec<f64> = truth
                .iter()
                .filter(|s| s.bell == bell && s.hand == hand)
                .map(|s| s.t)
                .collect();
            let near = |t: f64| (heard.strikes.iter()).any(|h| h.bell == bell && h.t - t > -0.01 && h.t - t < 0.04);
            of.iter().filter(|&&t| near(t)).count() as f64 / of.len() as f64
        };
        let back = found(5, false);
        assert!(back > 0.8, "bell 5's backstrokes: {back:.2} found");
        for b in 1..=6 {
            for hand in [true, false].into_iter().filter(|&h| b != 5 || h) {
                let f = found(b, hand);
                assert!(f > 0.9, "bell {b} hand {hand}: {f:.2} found");
            }
        }
    }
}
