//! Lining up one bell's strikes on one another and on their average.

use super::{CORE_S, RELINE_S, RELINE_SPREAD_S, SHIFT_S};
use crate::Signal;

/// The strikes from `starts` (each `before` + [`SHIFT_S`] before its time
/// heard) lined up: their average and each one's lag (samples, from 0 to
/// twice the shift; the shift is no move). First on the clearest strike,
/// then on the average, within [`SHIFT_S`]. Where that moves the strikes
/// about far more than the band finder ever hears one bell's strikes
/// apart (a bell whose partials are near a harmonic series matches itself
/// a few periods off: d4 of the recorded rings, strikes moved ±16 ms),
/// they are lined up again from their average as heard, within
/// [`RELINE_S`], and that is kept if its average holds more of them.
pub(super) fn line_up(sig: &Signal, starts: &[usize], before: usize, after: usize) -> Option<(Vec<f64>, Vec<usize>)> {
    let rate = sig.rate;
    let shift = (SHIFT_S * rate).round() as usize;
    let len = before + after;
    let seg = |s: usize, lag: usize| &sig.samples[s + lag..s + lag + len];
    // Line up on the strike with the most sound after its time against before.
    let clarity = |s: usize| {
        let e = |a: usize, b: usize| sig.samples[s + a..s + b].iter().map(|v| v * v).sum::<f64>();
        e(shift + before, shift + before + after / 2) / e(shift, shift + before / 2).max(1e-300)
    };
    let first = (0..starts.len()).max_by(|&a, &b| clarity(starts[a]).total_cmp(&clarity(starts[b])))?;
    let pass = |reference: &[f64], lags: &mut [usize], reach: usize| {
        for (l, &s) in lags.iter_mut().zip(starts) {
            *l = best_lag(
                &sig.samples[s..s + len + 2 * shift],
                reference,
                shift,
                before,
                rate,
                reach,
            );
        }
        average(starts, lags, seg)
    };
    let mut lags = vec![shift; starts.len()];
    let mut reference = seg(starts[first], shift).to_vec();
    for _ in 0..2 {
        reference = pass(&reference, &mut lags, shift);
    }
    if mad(&lags) <= RELINE_SPREAD_S * rate {
        return Some((reference, lags));
    }
    let (r, again) = reline(sig, starts, before, after);
    let holds = |avg: &[f64], lags: &[usize]| coherence(avg, starts, lags, seg, heard_in(lags, before, shift), rate);
    if holds(&r, &again) > holds(&reference, &lags) {
        Some((r, again))
    } else {
        Some((reference, lags))
    }
}

/// The strikes from `starts` lined up from their average as heard, within
/// [`RELINE_S`] (three passes): their average and each one's lag, as
/// [`line_up`] gives them.
pub(super) fn reline(sig: &Signal, starts: &[usize], before: usize, after: usize) -> (Vec<f64>, Vec<usize>) {
    let rate = sig.rate;
    let shift = (SHIFT_S * rate).round() as usize;
    let len = before + after;
    let seg = |s: usize, lag: usize| &sig.samples[s + lag..s + lag + len];
    let reach = ((RELINE_S * rate) as usize).min(shift);
    let mut lags = vec![shift; starts.len()];
    let mut r = average(starts, &lags, seg);
    for _ in 0..3 {
        for (l, &s) in lags.iter_mut().zip(starts) {
            *l = best_lag(&sig.samples[s..s + len + 2 * shift], &r, shift, before, rate, reach);
        }
        r = average(starts, &lags, seg);
    }
    (r, lags)
}

/// The strikes from `starts` moved by `lags` (`seg`), averaged.
fn average<'a>(starts: &[usize], lags: &[usize], seg: impl Fn(usize, usize) -> &'a [f64]) -> Vec<f64> {
    let mut r: Vec<f64> = vec![];
    for (&s, &lag) in starts.iter().zip(lags) {
        let x = seg(s, lag);
        if r.is_empty() {
            r = vec![0.0; x.len()];
        }
        r.iter_mut().zip(x).for_each(|(r, v)| *r += v);
    }
    let n = starts.len().max(1) as f64;
    r.iter_mut().for_each(|r| *r /= n);
    r
}

/// The median absolute deviation of `lags` (samples).
pub(super) fn mad(lags: &[usize]) -> f64 {
    let mut l: Vec<f64> = lags.iter().map(|&v| v as f64).collect();
    l.sort_by(f64::total_cmp);
    let m = l[l.len() / 2];
    let mut d: Vec<f64> = l.iter().map(|v| (v - m).abs()).collect();
    d.sort_by(f64::total_cmp);
    d[d.len() / 2]
}

/// Where the strikes were heard, in the reckoning of their average lined
/// up by `lags` (samples): the median.
pub(super) fn heard_in(lags: &[usize], before: usize, shift: usize) -> usize {
    let mut l = lags.to_vec();
    l.sort_unstable();
    (before + shift).saturating_sub(l[l.len() / 2])
}

/// How much of the strikes their average `avg` holds about `heard`
/// (from [`CORE_S`] before to 200 ms after): its energy against the
/// strikes' mean energy there.
fn coherence<'a>(
    avg: &[f64],
    starts: &[usize],
    lags: &[usize],
    seg: impl Fn(usize, usize) -> &'a [f64],
    heard: usize,
    rate: f64,
) -> f64 {
    let (lo, hi) = (
        heard.saturating_sub((CORE_S * rate) as usize),
        (heard + (0.2 * rate) as usize).min(avg.len()),
    );
    let e = |x: &[f64]| x[lo..hi].iter().map(|v| v * v).sum::<f64>();
    let each: f64 = starts.iter().zip(lags).map(|(&s, &l)| e(seg(s, l))).sum::<f64>() / starts.len().max(1) as f64;
    e(avg) / each.max(1e-300)
}

/// The lag (`shift` ± `reach` samples) at which `x` matches `reference`
/// best, over the reference from [`CORE_S`] before its time heard (`at`)
/// to its end.
pub(super) fn best_lag(x: &[f64], reference: &[f64], shift: usize, at: usize, rate: f64, reach: usize) -> usize {
    let (lo, scores) = lag_scores(x, reference, shift, at, rate, (reach, reach));
    widest(lo, &scores).unwrap_or(shift)
}

/// How well `x` matches `reference` (its core, as [`best_lag`] takes it)
/// at each lag from `shift` less `reach.0` to `shift` and `reach.1`
/// samples: the first lag, and the correlation at it and each after.
pub(super) fn lag_scores(
    x: &[f64],
    reference: &[f64],
    shift: usize,
    at: usize,
    rate: f64,
    reach: (usize, usize),
) -> (usize, Vec<f64>) {
    let from = at.saturating_sub((CORE_S * rate) as usize);
    let core = &reference[from..];
    // Only the lags sought are transformed: x from the first of them (the
    // core starts `from` into the reference) to as far as the core reaches
    // from the last; the transform need hold no more than the core and the
    // lags without wrapping (half the length of the whole x and core).
    let (below, above) = (reach.0.min(shift), reach.1);
    let lo = shift - below;
    let first = (lo + from).min(x.len());
    let y = &x[first..(first + below + above + core.len()).min(x.len())];
    let n = (core.len() + below + above + 1).next_power_of_two();
    // out[j]: the core against x from lag lo + j.
    let scores = crate::fft::correlate(y, core, n, |out| out[..=below + above].to_vec());
    (lo, scores)
}

/// The best of `scores` (lags from `lo`), the last of equals: None if empty.
pub(super) fn widest(lo: usize, scores: &[f64]) -> Option<usize> {
    (0..scores.len())
        .max_by(|&p, &q| scores[p].total_cmp(&scores[q]))
        .map(|j| lo + j)
}

#[cfg(test)]
mod tests {
    use super::super::{sharp, AFTER_S, BEFORE_S};
    use super::*;

    /// [`best_lag`] as it was, correlating the whole of x against the core
    /// at twice the length (every lag, most of them never sought).
    fn best_lag_whole(x: &[f64], reference: &[f64], shift: usize, at: usize, rate: f64, reach: usize) -> usize {
        let from = at.saturating_sub((CORE_S * rate) as usize);
        let core = &reference[from..];
        let n = (x.len() + core.len()).next_power_of_two();
        crate::fft::correlate(x, core, n, |out| {
            (shift - reach..=shift + reach)
                .max_by(|&p, &q| out[p + from].total_cmp(&out[q + from]))
                .unwrap_or(shift)
        })
    }

    /// Correlating only the lags sought (a transform a quarter to a half
    /// as long) finds the lag the whole correlation finds: strikes of a
    /// bell-like sound in noise, lined up on their average as
    /// `retime_each` and `line_up` line them up, within the full reach,
    /// a sharp blow's and a few samples', at two rates.
    #[test]
    fn the_lags_sought_alone_are_matched_as_in_the_whole_correlation() {
        let mut seed = 12345u64;
        let mut noise = move || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            ((seed >> 11) as f64 / (1u64 << 53) as f64) - 0.5
        };
        let mut checked = 0;
        for rate in [44100.0, 16000.0] {
            let (before, after) = ((BEFORE_S * rate).round() as usize, (AFTER_S * rate).round() as usize);
            let shift = (SHIFT_S * rate).round() as usize;
            let strike = |t: f64| {
                let partials: [(f64, f64, f64); 4] = [
                    (440.0, 1.0, 1.5),
                    (880.0, 0.6, 3.0),
                    (1050.0, 0.5, 4.0),
                    (1760.0, 0.3, 6.0),
                ];
                partials
                    .iter()
                    .map(|&(f, a, d)| a * (-d * t).exp() * (2.0 * std::f64::consts::PI * f * t).sin())
                    .sum::<f64>()
            };
            let reference: Vec<f64> = (0..before + after)
                .map(|i| {
                    let t = (i as f64 - before as f64) / rate;
                    if t < 0.0 {
                        0.0
                    } else {
                        strike(t)
                    }
                })
                .collect();
            for (k, offset) in [0usize, 17, 333, shift, 2 * shift - 5, 2 * shift]
                .into_iter()
                .enumerate()
            {
                let x: Vec<f64> = (0..before + after + 2 * shift)
                    .map(|i| {
                        let t = (i as f64 - (before + offset) as f64) / rate;
                        let s = if t < 0.0 { 0.0 } else { strike(t) };
                        s + 0.3 * (k as f64 + 1.0) * noise()
                    })
                    .collect();
                for reach in [shift, sharp::reach(rate), 3] {
                    let alone = best_lag(&x, &reference, shift, before, rate, reach);
                    let whole = best_lag_whole(&x, &reference, shift, before, rate, reach);
                    assert_eq!(alone, whole, "rate {rate}, offset {offset}, reach {reach}");
                    checked += 1;
                }
            }
        }
        assert_eq!(checked, 36);
    }

    /// The lags sought may reach further after than before: a sound 90 ms
    /// after where the reference puts it is found with a reach of 60 ms
    /// before and 100 ms after (a strike heard at its blow, 90 ms before
    /// its bell is heard on the rest), not with 60 ms either way.
    #[test]
    fn lags_reach_further_after_where_asked() {
        let rate = 8000.0;
        let (shift, at) = ((SHIFT_S * rate) as usize, 400);
        let sound = |i: usize| {
            if i < at {
                0.0
            } else {
                (0.3 * i as f64).sin() * (-((i - at) as f64) / 400.0).exp()
            }
        };
        let reference: Vec<f64> = (0..1600).map(sound).collect();
        let late = (0.09 * rate) as usize;
        let x: Vec<f64> = (0..1600 + shift + late + 100)
            .map(|i| if i < shift + late { 0.0 } else { sound(i - shift - late) })
            .collect();
        let (lo, scores) = lag_scores(&x, &reference, shift, at, rate, (shift, (0.1 * rate) as usize));
        assert_eq!(widest(lo, &scores), Some(shift + late));
        let (lo, scores) = lag_scores(&x, &reference, shift, at, rate, (shift, shift));
        assert_ne!(widest(lo, &scores), Some(shift + late));
    }
}
