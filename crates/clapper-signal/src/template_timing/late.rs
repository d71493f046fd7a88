//! Strikes sought further back than the search about their time heard
//! less their bell's lateness reaches. That lateness, learned on a dry
//! ring of the templates ([`crate::lateness::from_templates`]), can be
//! far from how late the band finder hears a bell in a room: on the
//! recorded eight the tenor (d8) was learned 35 ms late there and heard
//! 25 ms late at some strikes and 340-390 ms at others at RT60 0.6-1.2 s,
//! so the search (from 280 ms before the time less the lateness) never
//! reached the true time at those, and each was matched 110-130 ms late.

use super::lag::best_match;
use super::matcher::{Matcher, Scratch, Template};
use crate::strikes::Heard;
use crate::SignalError;

/// How far before a strike's time heard its template is sought (s): the
/// recorded bells were heard up to 390 ms late in rooms.
pub(super) const REACH_S: f64 = 0.6;
/// Nor further than this share of the bell's typical interval between
/// strikes (its previous strike would match as well).
const REACH_SHARE: f64 = 0.6;
/// [`before`] times its best match again from this long before it to this
/// long after (s), as the search about the time heard less the lateness
/// reaches.
const NEAR_S: (f64, f64) = (0.28, 0.04);

/// How far before its time heard each bell's strike is sought (s, treble
/// first; `bells` of them): [`REACH_S`], or [`REACH_SHARE`] of the bell's
/// median interval between its strikes in `heard` where that is less.
pub(super) fn reach(bells: usize, heard: &Heard) -> Vec<f64> {
    (1..=bells)
        .map(|b| {
            let mut times: Vec<f64> = heard.strikes.iter().filter(|s| s.bell == b).map(|s| s.t).collect();
            times.sort_by(f64::total_cmp);
            let gaps: Vec<f64> = times.windows(2).map(|w| w[1] - w[0]).collect();
            if gaps.is_empty() {
                REACH_S
            } else {
                REACH_S.min(REACH_SHARE * crate::median(&gaps))
            }
        })
        .collect()
}

/// The strike's time (s) and match where template `t` matches `x` best
/// in the search `(from, to)` (s, [`best_match`]) or in the stretch
/// before it from `earliest` (s, [`before`]): the band finder can hear a
/// strike later than the search reaches (in a room, the recorded tenor d8
/// at 25 ms at some strikes and 340-390 ms at others, its lateness learned
/// on the dry ring of the templates 35 ms). The better match is kept.
pub(super) fn best_of(
    m: &Matcher,
    x: &[f64],
    t: &Template,
    (from, to): (f64, f64),
    earliest: f64,
    sc: &mut Scratch,
) -> Result<Option<(f64, f64)>, SignalError> {
    let found = best_match(m, x, t, from, to, sc)?;
    let beat = found.map_or(0.0, |g| g.1);
    Ok(before(m, x, t, earliest, from, beat, sc)?.or(found))
}

/// The strike's time (s) and match where template `t` matches `x` best
/// from `from` to `to` (s), if better than `beat` (a match elsewhere;
/// nothing where `from` is not before `to`): the best match over the
/// stretch, then [`best_match`] about it (its rule for a double strike's
/// first blow; its match is at most the stretch's best, so that is
/// timed only where it beats `beat`: the ten-minute ring's time).
#[allow(clippy::too_many_arguments)]
fn before(
    m: &Matcher,
    x: &[f64],
    t: &Template,
    from: f64,
    to: f64,
    beat: f64,
    sc: &mut Scratch,
) -> Result<Option<(f64, f64)>, SignalError> {
    if from >= to {
        return Ok(None);
    }
    let Some((at, q)) = widest(m, x, t, from, to, sc)? else {
        return Ok(None);
    };
    if q <= beat {
        return Ok(None);
    }
    Ok(best_match(m, x, t, at - NEAR_S.0, at + NEAR_S.1, sc)?.filter(|f| f.1 > beat))
}

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

#[cfg(test)]
mod tests {
    use crate::sampled_ring::{octave_heavy_strike, sampled_ring};
    use crate::strikes::{find_strikes, BellVoice, StrikeOptions};
    use crate::template_timing::retime_each_with;
    use crate::tower::{major_scale, Room, TowerSpec};
    use crate::Signal;

    /// Eight bells with a recorded bell's partials (`octave_heavy_strike`) in rounds in a room (RT60 0.6 s), the
    /// tenor's strikes handed 400 ms late, as the band finder heard the
    /// recorded tenor d8 in rooms (340-390 ms, its lateness learned on the
    /// dry ring of the templates 35 ms): every strike of it is timed within
    /// 10 ms of the truth. Searched only from 280 ms before its time less
    /// that lateness, none was (each matched 80-130 ms late).
    #[test]
    fn a_bell_heard_far_later_than_its_lateness_is_timed_at_its_sound() {
        let rate = 16_000.0;
        let bells = major_scale(8, 1000.0).unwrap();
        let templates: Vec<Signal> = bells
            .iter()
            .enumerate()
            .map(|(i, b)| octave_heavy_strike(b.nominal_hz, 1.0, rate, 3 + i as u64))
            .collect();
        let spec = TowerSpec {
            rate,
            rows: 12,
            snr_db: Some(25.0),
            room: Some(Room::chamber(0.6)),
            ..TowerSpec::new(bells)
        };
        let (sig, truth) = sampled_ring(&spec, &templates).unwrap();
        let voices: Vec<BellVoice> = templates.iter().map(|t| BellVoice::from_template(t).unwrap()).collect();
        let opts = StrikeOptions::default();
        let mut heard = find_strikes(&sig, &voices, &opts).unwrap();
        let late = crate::lateness::from_templates(&templates, &voices, &opts).unwrap();
        let l: Vec<Option<f64>> = late.bells.iter().map(|b| b.sure().then_some(b.lateness_s)).collect();
        let tenor = truth.iter().filter(|s| s.bell == 8).count();
        // The tenor's strikes as heard, each 400 ms late (the true times
        // less nothing: well past any lateness learned).
        heard.strikes.retain(|s| s.bell != 8);
        for x in truth.iter().filter(|s| s.bell == 8) {
            heard.strikes.push(crate::strikes::HeardStrike {
                bell: 8,
                t: x.t + 0.4,
                strength: 1.0,
                double: None,
            });
        }
        heard.strikes.sort_by(|a, b| a.t.total_cmp(&b.t));
        retime_each_with(&sig, &mut heard, &templates, &l, &opts).unwrap();
        let off: Vec<f64> = truth
            .iter()
            .filter(|x| x.bell == 8)
            .map(|x| {
                heard
                    .strikes
                    .iter()
                    .filter(|s| s.bell == 8)
                    .map(|s| (s.t - x.t) * 1e3)
                    .min_by(|a, b| a.abs().total_cmp(&b.abs()))
                    .unwrap_or(f64::INFINITY)
            })
            .collect();
        let within = off.iter().filter(|e| e.abs() <= 10.0).count();
        assert_eq!(within, tenor, "the tenor's strikes off by (ms): {off:.1?}");
    }
}
