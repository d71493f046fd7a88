//! Each bell's lateness in the recording itself: how long after the start
//! of its sound the band finder hears it here, from a wide search of its
//! template about a few of its strikes. The lateness learned on a dry ring
//! of the templates ([`crate::lateness::from_templates`]) can be far from
//! it in a room: on the recorded eight the tenor (d8) was learned 35 ms
//! late there and heard 340-390 ms late at RT60 0.6-1.2 s, so the search
//! about its strikes (280 ms before the time less that lateness) never
//! reached the true time and every strike was matched 110-130 ms late.

use super::lag::best_match;
use super::matcher::{Matcher, Scratch, Template};
use crate::strikes::Heard;
use crate::SignalError;

/// How far before a strike's time heard its template is sought (s): the
/// recorded bells were heard up to 390 ms late in rooms.
const REACH_S: f64 = 0.6;
/// Nor further than this share of the bell's typical interval between
/// strikes (its previous strike would match as well).
const REACH_SHARE: f64 = 0.6;
/// How far after (s).
const AFTER_S: f64 = 0.05;
/// At most this many of a bell's strikes are searched (evenly spread).
const SAMPLE: usize = 9;
/// A bell's lateness needs this many strikes heard.
const MIN_STRIKES: usize = 3;

/// How a bell's strikes are sought where the search about its time heard
/// less its lateness finds no good match.
#[derive(Clone, Copy, Debug)]
pub(super) struct Wide {
    /// How far before the time heard (s).
    pub reach: f64,
    /// The bell's typical match (the median over up to [`SAMPLE`] of its
    /// strikes searched so, in the recording as it is).
    pub typical: f64,
}

/// Each bell's [`Wide`] search in the recording `x`, treble first; none
/// for a bell with no template or too few strikes heard.
pub(super) fn wide(m: &Matcher, x: &[f64], heard: &Heard, sc: &mut Scratch) -> Result<Vec<Option<Wide>>, SignalError> {
    let mut out = vec![];
    for (b, tm) in m.bells.iter().enumerate() {
        let Some(tm) = tm else {
            out.push(None);
            continue;
        };
        let mut times: Vec<f64> = heard.strikes.iter().filter(|s| s.bell == b + 1).map(|s| s.t).collect();
        times.sort_by(f64::total_cmp);
        if times.len() < MIN_STRIKES {
            out.push(None);
            continue;
        }
        let gaps: Vec<f64> = times.windows(2).map(|w| w[1] - w[0]).collect();
        let reach = REACH_S.min(REACH_SHARE * crate::median(&gaps));
        let step = times.len().div_ceil(SAMPLE);
        let mut q = vec![];
        for &t in times.iter().step_by(step) {
            if let Some((_, v)) = widest(m, x, tm, t - reach, t + AFTER_S, sc)? {
                q.push(v);
            }
        }
        out.push((q.len() >= MIN_STRIKES).then(|| Wide {
            reach,
            typical: crate::median(&q),
        }));
    }
    Ok(out)
}

/// The strike's time (s) and match where template `t` matches `x` best
/// from `reach` (s) before `heard` (s) to [`AFTER_S`] after it: the best
/// match over the whole stretch, then [`best_match`] about it (its rule
/// for a double strike's first blow).
pub(super) fn search(
    m: &Matcher,
    x: &[f64],
    t: &Template,
    heard: f64,
    reach: f64,
    sc: &mut Scratch,
) -> Result<Option<(f64, f64)>, SignalError> {
    let Some((at, _)) = widest(m, x, t, heard - reach, heard + AFTER_S, sc)? else {
        return Ok(None);
    };
    best_match(m, x, t, at - NEAR_S.0, at + NEAR_S.1, sc)
}

/// [`search`] times its best match again from this long before it to this
/// long after (s): as a search about the time heard less the lateness
/// reaches.
const NEAR_S: (f64, f64) = (0.28, 0.04);

/// The time (s) where template `t` matches `x` best from `from` to `to`
/// (s), and how well (the normalised match), searched a transform's span
/// at a time; none where the recording is silent.
fn widest(
    m: &Matcher,
    x: &[f64],
    t: &Template,
    from: f64,
    to: f64,
    sc: &mut Scratch,
) -> Result<Option<(f64, f64)>, SignalError> {
    let rate = m.rate;
    let (first, last) = ((from * rate).round() as i64, (to * rate).round() as i64);
    let mut best: Option<(i64, f64)> = None;
    let mut start = first;
    while start <= last {
        let lags = ((last - start) as usize).min(m.span());
        m.normalised(x, t, start, lags, sc)?;
        for k in 0..=lags {
            let v = sc.out[k].abs();
            if v > 0.0 && best.is_none_or(|b| v > b.1) {
                best = Some((start + k as i64, v));
            }
        }
        start += lags as i64 + 1;
    }
    Ok(best.map(|(k, q)| ((k + m.pre as i64) as f64 / rate, q)))
}
