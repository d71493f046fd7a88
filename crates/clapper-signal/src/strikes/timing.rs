//! Where a strike's rise is timed in each band, and the bands' onsets
//! put on one footing.

use super::band::{Band, SHARED_BAND_QUIET};
use super::stats::{median, weighted_median};

/// Where a strike's rise is timed in each band: where the band has moved
/// this fraction of the way from its level before the rise to its level
/// after, moved back by where a bare step through the three boxes reaches
/// it. Not half-way: in a room the level after holds the reverberation
/// built up behind the direct sound, later the longer the box, and a
/// partial where the room's sound outweighs the direct sound read 40 ms
/// late half-way (the benchmark at RT60 0.6 s: p95 12.2 ms at 0.5,
/// 7.4 ms at 0.2, 7.2 at 0.15, 7.9 at 0.1, where noise starts to tell;
/// without a room 1.9 ms at 0.5 and 1.8 at 0.2).
pub(super) const ONSET_LEVEL: f64 = 0.2;

/// The three boxes' step response: the fraction of a step through them
/// at `u` boxes from the start of the rise (0 to 3; the cumulative
/// Irwin-Hall distribution of three).
pub(super) fn box3_step(u: f64) -> f64 {
    let u = u.clamp(0.0, 3.0);
    if u <= 1.0 {
        u * u * u / 6.0
    } else if u <= 2.0 {
        (-2.0 * u * u * u + 9.0 * u * u - 9.0 * u + 3.0) / 6.0
    } else {
        1.0 - (3.0 - u).powi(3) / 6.0
    }
}

/// Where [`box3_step`] reaches `level` (boxes from the rise's start).
pub(super) fn box3_reaches(level: f64) -> f64 {
    let (mut lo, mut hi) = (0.0, 3.0);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if box3_step(mid) < level {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// The onset heard in band `b` (with its change `c`) near band sample `m`
/// (s), timed `level` of the way up its rise ([`ONSET_LEVEL`] for the
/// times reported), and its weight (shorter boxes and clearer steps weigh
/// more), if the strike is heard there. A shared band (`faint`)
/// is used only where what rings there before the strike is small beside
/// the strike's step.
pub(super) fn band_onset(b: &Band, c: &[f64], m: usize, faint: bool, level: f64) -> Option<(f64, f64)> {
    let g = b.rise.div_ceil(2);
    let w = b.rise;
    let lo = m.saturating_sub(g);
    let hi = (m + g).min(c.len().checked_sub(1)?);
    let top = (lo..=hi).fold(lo, |best, k| if c[k] > c[best] { k } else { best });
    if top + 1 < g + w || top + g + w > b.z.len() || c[top] < 0.3 * b.scale {
        return None;
    }
    let avg = |a: usize, e: usize| {
        let s = b.z[a..e].iter().fold((0.0, 0.0), |s, z| (s.0 + z.0, s.1 + z.1));
        (s.0 / (e - a) as f64, s.1 / (e - a) as f64)
    };
    let before = avg(top + 1 - g - w, top + 1 - g);
    let after = avg(top + g, top + g + w);
    let (dx, dy) = (after.0 - before.0, after.1 - before.1);
    let len2 = dx * dx + dy * dy;
    if len2 <= 0.0 || (faint && before.0.hypot(before.1) > SHARED_BAND_QUIET * len2.sqrt()) {
        return None;
    }
    // Along the line from before to after: where is z that far?
    let progress = |k: usize| ((b.z[k].0 - before.0) * dx + (b.z[k].1 - before.1) * dy) / len2;
    let shift = (1.5 - box3_reaches(level)) * b.box_s;
    let first = top.saturating_sub(2 * g).max(1);
    let mut prev = progress(first - 1);
    for k in first..=top + g {
        let p = progress(k);
        if p >= level {
            let frac = if p > prev { (level - prev) / (p - prev) } else { 0.0 };
            let at = k as f64 - 1.0 + frac.clamp(0.0, 1.0);
            // In a shared band, the climb from `level` to half-way must be
            // a strike's: another bell's partial ringing there, turning
            // against this one's, can carry the band to `level` before the
            // rise.
            if faint && level < 0.5 {
                let half = (k..b.z.len().min(top + g + w)).find(|&j| progress(j) >= 0.5);
                if half.is_none_or(|j| (j as f64 - at) / b.rate > MAX_CLIMB_BOXES * b.box_s) {
                    return None;
                }
            }
            return Some((at / b.rate + shift, b.weight * (c[top] / b.scale).min(2.0) / b.box_s));
        }
        prev = p;
    }
    None
}

/// The longest climb (in boxes) from the level a shared band's onset is
/// timed at ([`ONSET_LEVEL`]) to half-way that is a strike's: a bare step
/// through the three boxes takes 0.44 of a box. A partial of another
/// bell ringing in the band (`faint` in [`band_onset`]: under
/// [`SHARED_BAND_QUIET`] of the step, as its mean) turns against this
/// bell's a few Hz off it and moves the band along the step by up to
/// twice its level before the strike; at a fifth of the step that alone
/// could reach the level timed at, up to 60 ms before the sound (bell 8's
/// nominal on the treble's prime and bell 5's quint in README's
/// recordings: 46 and 62 ms early, the strike then fitted as a double
/// at the real one). Climbing that slowly, the band does not time the
/// strike. Over the benchmark's first 10 recordings per condition, at 1
/// box against none: recall 99.84 -> 100 % without a room and 99.62 ->
/// 99.69 % at RT60 1.2 s, onset p95 3.00 -> 2.81 ms and 5.66 -> 5.06 ms;
/// at 0.7 box false doubles at RT60 0.6 s rose from 25 to 38, at 1.5
/// boxes the onset p95 there was 6.33 ms against 4.79 at 1. Judging
/// "faint" by the band's RMS level before the strike, under a tenth of
/// the step, instead lost
/// the shared bands where they time a bell best (bell 6 heard 30-58 ms
/// late in a room).
pub(super) const MAX_CLIMB_BOXES: f64 = 1.0;

/// The half-way onset near band sample `m` (s): the weighted median over
/// the bands where the strike is heard ([`band_onset`] at 0.5, where the
/// rise is steepest). Double strikes are fitted about it; the time
/// reported is [`BellHearing::timed`]'s.
pub(super) fn onset_time(bands: &[Band], changes: &[Vec<f64>], m: usize) -> Option<f64> {
    let mut est: Vec<(f64, f64)> = bands
        .iter()
        .zip(changes)
        .filter_map(|(b, c)| band_onset(b, c, m, false, 0.5))
        .collect();
    weighted_median(&mut est)
}

/// Strike times from per-strike, per-band onsets (`est[strike][band]`:
/// time s and weight, or none where the band did not hear it), each band's
/// constant lateness taken off ([`BellHearing::timed`]). The lateness is
/// measured against the band heard in most strikes (the median difference
/// over the strikes both heard, five at least; a band seldom heard with it
/// against the times the others give); a strike's time is then the
/// weighted median of its bands' onsets less their lateness, plus the
/// weighted median lateness of all the bands (so a strike every band hears
/// is timed as before). None where no band heard the strike.
pub(super) fn on_one_footing(est: &[Vec<Option<(f64, f64)>>]) -> Vec<Option<f64>> {
    let bands = est.iter().map(Vec::len).max().unwrap_or(0);
    let heard = |j: usize| est.iter().filter_map(|row| *row.get(j)?).collect::<Vec<_>>();
    let Some(reference) = (0..bands).max_by(|&a, &b| {
        let (ha, hb) = (heard(a), heard(b));
        let w = |h: &[(f64, f64)]| h.iter().map(|x| x.1).sum::<f64>();
        ha.len().cmp(&hb.len()).then(w(&ha).total_cmp(&w(&hb))).then(b.cmp(&a))
    }) else {
        return vec![None; est.len()];
    };
    let lateness_against = |j: usize, against: &dyn Fn(usize) -> Option<f64>| -> Option<f64> {
        let d: Vec<f64> = est
            .iter()
            .enumerate()
            .filter_map(|(s, row)| Some((*row.get(j)?)?.0 - against(s)?))
            .collect();
        (d.len() >= 5).then(|| median(d)).flatten()
    };
    let mut late: Vec<Option<f64>> = (0..bands)
        .map(|j| lateness_against(j, &|s| est[s].get(reference).copied().flatten().map(|x| x.0)))
        .collect();
    let times = |late: &[Option<f64>]| -> Vec<Option<f64>> {
        est.iter()
            .map(|row| {
                let mut v: Vec<(f64, f64)> = row
                    .iter()
                    .zip(late)
                    .filter_map(|(e, l)| {
                        let ((t, w), d) = ((*e)?, (*l)?);
                        Some((t - d, w))
                    })
                    .collect();
                weighted_median(&mut v)
            })
            .collect()
    };
    let first = times(&late);
    for (j, l) in late.iter_mut().enumerate() {
        if l.is_none() {
            *l = lateness_against(j, &|s| first[s]);
        }
    }
    let common = weighted_median(
        &mut (0..bands)
            .filter_map(|j| Some((late[j]?, heard(j).iter().map(|x| x.1).sum::<f64>())))
            .collect::<Vec<_>>(),
    )
    .unwrap_or(0.0);
    times(&late)
        .into_iter()
        .zip(est)
        .map(|(t, row)| {
            t.map(|t| t + common)
                .or_else(|| weighted_median(&mut row.iter().flatten().copied().collect::<Vec<_>>()))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    use crate::strikes::band::{band, change};
    use crate::strikes::stats::typical_peak;
    use crate::Signal;

    /// A tone switched on (over an earlier, fainter tone ringing on) is
    /// timed at the switch at any level of the rise: the three boxes' step
    /// response is what `box3_step` says. With a slow build-up after the
    /// switch (a room's), a low level is timed nearer the switch than
    /// half-way.
    #[test]
    fn a_rise_is_timed_at_its_start_at_any_level() {
        let rate = 8000.0;
        let on = 4003;
        let tone = |i: usize, grow: f64| {
            let t = i as f64 / rate;
            let before = 0.05 * (2.0 * PI * 1000.0 * t + 1.0).sin();
            let after = if i >= on {
                let since = (i - on) as f64 / rate;
                0.3 * (1.0 + grow * since.min(0.1)) * (2.0 * PI * 1000.0 * t).sin()
            } else {
                0.0
            };
            before + after
        };
        let truth = on as f64 / rate;
        let mut late = vec![];
        for grow in [0.0, 30.0] {
            let samples: Vec<f64> = (0..16_000).map(|i| tone(i, grow)).collect();
            let mut b = band(&Signal { rate, samples }, 1000.0, 1.0, 161);
            let c = change(&b);
            b.scale = typical_peak(&c, 500);
            let m = (truth * b.rate).round() as usize;
            let at = |level: f64| band_onset(&b, &c, m, false, level).expect("heard").0 - truth;
            if grow == 0.0 {
                for level in [0.1, 0.2, 0.5, 0.8] {
                    assert!(at(level).abs() < 2e-4, "level {level}: {} s", at(level));
                }
            } else {
                late = vec![at(0.2), at(0.5)];
            }
        }
        // Growing to four times its first step over 0.1 s: half-way is
        // late by several ms, a fifth of the way by much less.
        assert!(late[1] > 0.004 && late[0] < 0.5 * late[1], "{late:?}");
    }

    /// A band that hears a bell's strikes 30 ms late hears only every other
    /// one (as a shared band, quiet only between the sharers' strikes):
    /// taken at face value it would move those strikes against the rest
    /// (a handstroke-backstroke difference the bell does not have); with
    /// its lateness learned and taken off, the times keep their spacing.
    #[test]
    fn a_band_heard_in_some_strikes_moves_none_against_the_rest() {
        let truth: Vec<f64> = (0..20).map(|k| 1.0 + 2.2 * k as f64).collect();
        let est: Vec<Vec<Option<(f64, f64)>>> = truth
            .iter()
            .enumerate()
            .map(|(k, &t)| {
                vec![
                    Some((t + 0.004, 1.0)),
                    Some((t - 0.002, 1.0)),
                    (k % 2 == 0).then_some((t + 0.030, 5.0)),
                ]
            })
            .collect();
        let at: Vec<f64> = on_one_footing(&est).into_iter().map(|a| a.expect("heard")).collect();
        let offsets: Vec<f64> = at.iter().zip(&truth).map(|(a, t)| a - t).collect();
        let spread = offsets.iter().fold(f64::NEG_INFINITY, |a, &b| a.max(b))
            - offsets.iter().fold(f64::INFINITY, |a, &b| a.min(b));
        assert!(spread < 1e-9, "{offsets:?}");
        // The plain weighted median per strike moves the even ones 30 ms.
        let plain: Vec<f64> = est
            .iter()
            .zip(&truth)
            .map(|(row, t)| weighted_median(&mut row.iter().flatten().copied().collect::<Vec<_>>()).unwrap() - t)
            .collect();
        assert!((plain[0] - plain[1]).abs() > 0.02, "{plain:?}");
    }

    /// A shared band: this bell's partial switched on at 0.5 s over
    /// another bell's ringing there 6 Hz off, at a sixth of the step (so
    /// "faint" by its mean), in every phase. Turning against the step, the
    /// other partial carries the band a fifth of the way up before the
    /// strike in some phases (up to 40 ms early, timed there); the climb
    /// to half-way is then slow and the band does not time the strike.
    /// Wherever it does, it is off by less than a box (by up to 14 ms:
    /// the other partial still tilts the rise, which the other bands and
    /// the band's lateness learned over the strikes outweigh).
    #[test]
    fn a_shared_band_is_not_timed_by_another_bells_partial_turning_in_it() {
        let rate = 8000.0;
        let on = 4003;
        let truth = on as f64 / rate;
        let (mut timed, mut refused) = (0, 0);
        for k in 0..16 {
            let phase = 2.0 * PI * k as f64 / 16.0;
            let samples: Vec<f64> = (0..16_000)
                .map(|i| {
                    let t = i as f64 / rate;
                    let other = 0.05 * (2.0 * PI * 1006.0 * t + phase).sin();
                    let own = if i >= on {
                        0.3 * (2.0 * PI * 1000.0 * t).sin()
                    } else {
                        0.0
                    };
                    other + own
                })
                .collect();
            let mut b = band(&Signal { rate, samples }, 1000.0, 1.0, 161);
            let c = change(&b);
            b.scale = typical_peak(&c, 500);
            let m = (truth * b.rate).round() as usize;
            match band_onset(&b, &c, m, true, ONSET_LEVEL) {
                Some((t, _)) => {
                    timed += 1;
                    // Within a box (20 ms); without the rule, up to 40 ms early.
                    assert!(
                        (t - truth).abs() < b.box_s,
                        "phase {k}/16: timed {:.1} ms off",
                        (t - truth) * 1e3
                    );
                }
                None => refused += 1,
            }
        }
        // Most phases still time it.
        assert!(timed >= 8 && refused >= 1, "timed {timed}, refused {refused}");
    }
}
