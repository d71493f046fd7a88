//! Where a template matches best near a strike: the lag of the best
//! normalised match, unless an earlier one nearly as good is a double
//! strike's first blow.

use super::matcher::{Matcher, Scratch, Template};
use crate::SignalError;

/// A match this share of the best, 30 ms or more before it, is the strike:
/// a double strike's second blow (at most as loud) matches later. At 0.6
/// the synthetic near-harmonic bells (six, rounds, seeds 1-2) had 38-74 ms
/// early matches taken so, and a second copy at the true time called a
/// double: recall within 10 ms 0.62 dry / 0.39 at RT60 0.6 s, 22 / 56
/// false doubles in 240; at 0.85 0.99 / 0.60, 1 / 35 (0.75: 0.80 / 0.48,
/// 32 / 60). The recorded rings (bench/strikes, seeds 11-12) the same
/// within 10 ms, false doubles 15 -> 11 and 14 -> 9 on two eights in rooms.
const FIRST_SHARE: f64 = 0.85;
/// How far (s) before the best match such a match must lie: nearer ones
/// are the template's own partials coming back into step (on the recorded
/// tower bells, 12 ms before the true lag).
const GAP_S: f64 = 0.03;
/// The dip (a share of the earlier match) that parts two blows.
const DIP: f64 = 0.7;

/// How many of each bell's strikes, spread over the recording, vote on
/// the sign it matches with (and on its weighting, `weight.rs`).
pub(super) const VOTES: usize = 16;
/// The share of a bell's votes that turn its sign.
pub(super) const TURNED: f64 = 0.75;

/// Up to [`VOTES`] of bell `bell`'s (from 1) strikes `sought` (where its
/// template is sought, s, s), spread over the recording: those that vote
/// on how its template matches.
pub(super) fn voters(sought: &[(usize, (f64, f64))], bell: usize) -> Vec<(f64, f64)> {
    let mine: Vec<(f64, f64)> = sought.iter().filter(|s| s.0 == bell).map(|s| s.1).collect();
    let step = mine.len().div_ceil(VOTES).max(1);
    mine.into_iter().step_by(step).collect()
}

/// The sign each bell's strikes match the recording `x` with (treble
/// first, +1 or -1): the sign of the best match by magnitude where each of
/// up to [`VOTES`] of its strikes `sought` (bell from 1, and where its
/// template is sought, s, s) is sought; -1 where [`TURNED`] of them or
/// more are turned, else +1. A bell of nearly one or two partials matches
/// half a period off, turned, nearly as well as at its strike, and the
/// magnitude then takes one lag or the other strike by strike; a room
/// shifts a bell's phase the same at every strike, and where it turns the
/// match at the strike it does so at nearly all. Needs `m`'s polarities
/// not yet known (the match by magnitude). (`weight::choose` gives the
/// same signs from its own matches.)
#[cfg(test)]
pub(super) fn polarities(
    m: &Matcher,
    x: &[f64],
    sought: &[(usize, (f64, f64))],
    sc: &mut Scratch,
) -> Result<Vec<f64>, SignalError> {
    let mut signs = vec![];
    for (b, t) in m.bells.iter().enumerate() {
        let Some(t) = t else {
            signs.push(1.0);
            continue;
        };
        let (mut turned, mut n) = (0usize, 0usize);
        for (from, to) in voters(sought, b + 1) {
            let start = (from * m.rate).round() as i64;
            let lags = (((to - from) * m.rate).round() as usize).min(m.span());
            m.normalised(x, t, start, lags, sc)?;
            let out = &sc.out[..=lags];
            let k = (0..=lags)
                .max_by(|&a, &b| out[a].abs().total_cmp(&out[b].abs()))
                .unwrap_or(0);
            n += 1;
            turned += usize::from(out[k] < 0.0);
        }
        signs.push(if n > 0 && turned as f64 >= TURNED * n as f64 {
            -1.0
        } else {
            1.0
        });
    }
    Ok(signs)
}

/// The strike's time (s) where template `t` matches the recording `x`
/// best from `from` to `to` (s), and how well (the normalised match, 0 to
/// 1), or None where the recording is silent there.
pub(super) fn best_match(
    m: &Matcher,
    x: &[f64],
    t: &Template,
    from: f64,
    to: f64,
    sc: &mut Scratch,
) -> Result<Option<(f64, f64)>, SignalError> {
    let rate = m.rate;
    let start = (from * rate).round() as i64;
    let lags = (((to - from) * rate).round() as usize).min(MOST_SPANS * m.span());
    // Within one span (most searches) the match is read where the
    // transform leaves it, not copied out (speed-8).
    let whole;
    let out: &[f64] = if lags <= m.span() {
        m.normalised(x, t, start, lags, sc)?;
        &sc.out[..=lags]
    } else {
        whole = curve(m, x, t, start, lags, sc)?;
        &whole
    };
    let (top, top_k) = top_of(out);
    if top == 0.0 {
        return Ok(None);
    }
    let best = first_blow_from(out, lags, top, top_k, rate);
    // The peak between samples, from the parabola through its neighbours.
    let off = if best > 0 && best < lags {
        let (a, b, c) = (out[best - 1].abs(), out[best].abs(), out[best + 1].abs());
        let den = a - 2.0 * b + c;
        if den < 0.0 {
            (0.5 * (a - c) / den).clamp(-0.5, 0.5)
        } else {
            0.0
        }
    } else {
        0.0
    };
    Ok(Some((
        (start as f64 + (best + m.pre) as f64 + off) / rate,
        out[best].abs(),
    )))
}

/// The most transforms' spans one search covers.
const MOST_SPANS: usize = 4;

/// The normalised match of template `t` against `x` from sample `start`
/// at lags 0 to `lags` ([`Matcher::normalised`]), a transform's span at a
/// time: at 16 kHz one span is 0.32 s, shorter than a search from 280 ms
/// before a strike's time less its lateness to 40 ms after the time heard
/// (cut there, the recorded bell d11's strikes heard 12 ms late with a
/// lateness of 104 ms were matched at a side peak 8 ms early, and a second
/// copy after it called double). `sc.out` keeps the first span's match.
fn curve(
    m: &Matcher,
    x: &[f64],
    t: &Template,
    start: i64,
    lags: usize,
    sc: &mut Scratch,
) -> Result<Vec<f64>, SignalError> {
    let mut out = Vec::with_capacity(lags + 1);
    let mut at = start;
    // Bounded: each pass adds at least one lag.
    while out.len() <= lags {
        let n = (lags - out.len()).min(m.span());
        m.normalised(x, t, at, n, sc)?;
        out.extend_from_slice(&sc.out[..=n]);
        at += n as i64 + 1;
    }
    // `sc.out` left as one transform leaves it (its first span), as
    // callers that read it after the match (`weight`) expect.
    let first = lags.min(m.span());
    if lags > first {
        sc.out[..=first].copy_from_slice(&out[..=first]);
    }
    Ok(out)
}

/// The best match in `out[..=lags]` (its largest `top`), unless a match at
/// least 0.6 as good lies 30 ms or more before it with a dip between (a
/// double strike's first blow): then the best within 10 ms of the earliest
/// such. Without the dip it is the same strike matching broadly (partials
/// near whole ratios keep in step with themselves for tens of ms).
#[cfg(test)]
fn first_blow(out: &[f64], lags: usize, top: f64, rate: f64) -> usize {
    let top_k = (0..=lags)
        .max_by(|&a, &b| out[a].abs().total_cmp(&out[b].abs()))
        .unwrap_or(0);
    first_blow_from(out, lags, top, top_k, rate)
}

/// The largest |v| of `out` (0 if none is above 0), and the last lag
/// where |v| is largest: what a fold of `f64::max` and a `max_by` of
/// `total_cmp` give, in one pass (speed-8: the two passes, one a chain
/// of `max`, the other of comparisons through the bits, were most of
/// [`best_match`]'s own time). Where a NaN lies in `out` (it never does:
/// the recording's samples are finite, the template's energy above 0),
/// the two passes themselves, which rank it otherwise.
fn top_of(out: &[f64]) -> (f64, usize) {
    let (mut top, mut top_k, mut nan) = (0.0f64, 0usize, false);
    for (k, v) in out.iter().enumerate() {
        let a = v.abs();
        nan |= a.is_nan();
        if a >= top {
            (top, top_k) = (a, k);
        }
    }
    if !nan {
        return (top, top_k);
    }
    let top = out.iter().map(|v| v.abs()).fold(0.0, f64::max);
    let top_k = (0..out.len())
        .max_by(|&a, &b| out[a].abs().total_cmp(&out[b].abs()))
        .unwrap_or(0);
    (top, top_k)
}

/// [`first_blow`] with the last lag of the largest |v|, `top_k`, known.
fn first_blow_from(out: &[f64], lags: usize, top: f64, top_k: usize, rate: f64) -> usize {
    let gap = (GAP_S * rate).round() as usize;
    let half = (0.0015 * rate).round() as usize;
    // A first blow's envelope reaches FIRST_SHARE of the top somewhere
    // before `top_k - gap`: where no lag that near does, there is none
    // (most strikes), and the envelope is not made.
    let near = (top_k.saturating_sub(gap) + half).min(lags + 1);
    if top_k <= gap || !out[..near].iter().any(|v| v.abs() >= FIRST_SHARE * top) {
        return top_k;
    }
    // The largest |out| within `half` of each lag before the top, found
    // once (the dip is sought only before it).
    let env = envelope(&out[..=(top_k + half).min(lags)], half);
    let first = (0..top_k.saturating_sub(gap)).find(|&k| {
        let e = env[k];
        e >= FIRST_SHARE * top && (k..top_k).step_by(half.max(1)).any(|j| env[j] < DIP * e)
    });
    match first {
        Some(first) => {
            let reach = (first + (0.01 * rate).round() as usize).min(lags);
            (first..=reach)
                .max_by(|&a, &b| out[a].abs().total_cmp(&out[b].abs()))
                .unwrap_or(first)
        }
        None => top_k,
    }
}

/// The largest |v| within `half` samples of each sample of `v` (0 for an
/// empty window), in one pass: the indices of a falling run of |v| kept,
/// each dropped once a larger one comes or it leaves the window.
fn envelope(v: &[f64], half: usize) -> Vec<f64> {
    let mut env = Vec::with_capacity(v.len());
    let mut run: std::collections::VecDeque<usize> = std::collections::VecDeque::new();
    let mut next = 0;
    for k in 0..v.len() {
        let hi = (k + half).min(v.len() - 1);
        while next <= hi {
            let a = v[next].abs();
            while run.back().is_some_and(|&b| v[b].abs() <= a) {
                run.pop_back();
            }
            run.push_back(next);
            next += 1;
        }
        while run.front().is_some_and(|&f| f + half < k) {
            run.pop_front();
        }
        env.push(run.front().map_or(0.0, |&f| v[f].abs().max(0.0)));
    }
    env
}

#[cfg(test)]
mod tests {
    use super::super::matcher::{Matcher, PRE_S};
    use super::{best_match, envelope, first_blow, DIP, FIRST_SHARE, GAP_S};
    use crate::template_timing::tests::slow_bell;

    /// A search longer than one transform's span (at 16 kHz 0.32 s) is
    /// searched to its end: a strike 20 ms before the search's end is
    /// found there. Before, the search was cut to the span and ended 40 ms
    /// before the strike (a recorded bell at 16 kHz matched at side peaks
    /// 8-11 ms early, and called double).
    #[test]
    fn a_search_longer_than_a_transform_reaches_its_end() {
        let rate = 16_000.0;
        let bell = slow_bell(rate, 900.0, 0.03);
        let o = (crate::sampled_ring::sample_onset(&bell).unwrap() * rate).round() as usize;
        let m = Matcher::new(rate, std::slice::from_ref(&bell)).unwrap();
        let span_s = m.span() as f64 / rate;
        assert!(span_s < 0.36, "span {span_s} s");
        let at = (1.0 * rate) as usize;
        let mut x = vec![0.0; (3.0 * rate) as usize];
        for (k, v) in bell.samples.iter().enumerate() {
            x[at + k] += v;
        }
        let onset = (at + o) as f64 / rate;
        let t = m.bells[0].as_ref().unwrap();
        let mut sc = m.scratch();
        let from = onset - PRE_S - span_s - 0.04;
        let found = best_match(&m, &x, t, from, onset - PRE_S + 0.02, &mut sc).unwrap();
        assert!(
            found.is_some_and(|f| (f.0 - onset).abs() < 0.001),
            "{found:?} for {onset}"
        );
    }

    /// [`first_blow`] as it was, the envelope made over every lag.
    fn first_blow_everywhere(out: &[f64], lags: usize, top: f64, rate: f64) -> usize {
        let top_k = (0..=lags)
            .max_by(|&a, &b| out[a].abs().total_cmp(&out[b].abs()))
            .unwrap_or(0);
        let gap = (GAP_S * rate).round() as usize;
        let half = (0.0015 * rate).round() as usize;
        let env = envelope(&out[..=lags], half);
        let first = (0..top_k.saturating_sub(gap)).find(|&k| {
            let e = env[k];
            e >= FIRST_SHARE * top && (k..top_k).step_by(half.max(1)).any(|j| env[j] < DIP * e)
        });
        match first {
            Some(first) => {
                let reach = (first + (0.01 * rate).round() as usize).min(lags);
                (first..=reach)
                    .max_by(|&a, &b| out[a].abs().total_cmp(&out[b].abs()))
                    .unwrap_or(first)
            }
            None => top_k,
        }
    }

    /// The first blow found with the envelope made only where it can
    /// count is the one found with it made over every lag: matches with
    /// one peak, with a first blow before it (a dip between or none),
    /// peaks at either end, at two rates and for every count of lags.
    #[test]
    fn a_first_blow_sought_only_where_it_can_be_is_the_one_sought_everywhere() {
        let mut firsts = 0;
        for rate in [16_000.0, 44_100.0] {
            for case in 0..240usize {
                let n = 200 + (case * 7919) % 3000;
                let peak = |at: f64, h: f64, w: f64, k: usize| h * (-((k as f64 - at) / w).powi(2)).exp();
                let (a, b) = ((case * 31) % n, (case * 131 + 17) % n);
                let ha = 0.5 + 0.5 * ((case % 11) as f64 / 10.0);
                let w = 5.0 + (case % 13) as f64 * 40.0;
                let out: Vec<f64> = (0..n)
                    .map(|k| {
                        let ripple = 0.05 * ((k * 7919 + case) % 101) as f64 / 101.0;
                        let s = if k % 3 == 0 { -1.0 } else { 1.0 };
                        s * (peak(a as f64, ha, w, k) + peak(b as f64, 1.0, w, k) + ripple)
                    })
                    .collect();
                for lags in [n - 1, n / 2, (case % 5) * 40] {
                    let top = (0..=lags).map(|k| out[k].abs()).fold(0.0, f64::max);
                    let got = first_blow(&out, lags, top, rate);
                    let top_k = (0..=lags)
                        .max_by(|&x, &y| out[x].abs().total_cmp(&out[y].abs()))
                        .unwrap();
                    firsts += usize::from(got != top_k);
                    assert_eq!(
                        got,
                        first_blow_everywhere(&out, lags, top, rate),
                        "case {case}, lags {lags}"
                    );
                }
            }
        }
        // Some cases are first blows, not the top.
        assert!(firsts > 10, "{firsts} first blows");
        // A first blow just past the top less the gap, reached only by the
        // envelope's half-width before it: found.
        let rate = 16_000.0;
        let (gap, half) = ((GAP_S * rate).round() as usize, (0.0015 * rate).round() as usize);
        let mut out = vec![0.01; 2000];
        out[1500] = 1.0;
        out[1500 - gap + half - 1] = 0.9;
        let got = first_blow(&out, 1999, 1.0, rate);
        assert_eq!(got, 1500 - gap + half - 1);
        assert_eq!(got, first_blow_everywhere(&out, 1999, 1.0, rate));
    }

    /// The envelope in one pass is the largest |v| over each window,
    /// found window by window.
    #[test]
    fn the_envelope_is_the_largest_magnitude_near_each_sample() {
        let v: Vec<f64> = (0..500)
            .map(|k| ((k * 7919) % 263) as f64 / 263.0 - 0.5 + if k % 97 == 0 { -2.0 } else { 0.0 })
            .collect();
        for half in [0, 1, 3, 66] {
            let env = envelope(&v, half);
            for (k, e) in env.iter().enumerate() {
                let direct = v[k.saturating_sub(half)..=(k + half).min(v.len() - 1)]
                    .iter()
                    .fold(0.0f64, |m, x| m.max(x.abs()));
                assert_eq!(*e, direct, "half {half}, sample {k}");
            }
        }
    }
}
