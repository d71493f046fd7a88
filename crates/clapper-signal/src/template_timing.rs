//! Strikes timed against each bell's own recorded strike (issue 43): where
//! a template of the bell struck alone is known, each strike heard is
//! timed again by sliding the template over the recording near it. The
//! template's sound starts at a known point ([`crate::sampled_ring::sample_onset`]), so the lag
//! where it matches best is the start of the strike's sound, however slowly
//! the bell's partials build up: the band finder's timing, a fifth of the
//! way up each band's step, heard the recorded tower bells measured 15 to
//! 85 ms late, by an amount that changes with the room.
//!
//! The match is the cross-correlation of the recording with the first
//! 150 ms of the template's sound, and 40 ms of silence before it, both
//! for a bell whose room moves its match (`weight`) taken as their second
//! or third difference (the third where the template carries its
//! partials above 3 kHz: `matcher::Matcher::order_for`; weighted toward
//! the upper partials,
//! where a room's tail is weaker than the direct sound: `matcher::heard`), over
//! the recording's level there (its
//! magnitude: a bell struck on the other side sounds with some partials'
//! signs turned), searched from 280 ms before to 80 ms after the strike's
//! time as the band finder heard it less the bell's lateness learned on a
//! ring of its templates ([`crate::lateness::from_templates`]), or from
//! 200 ms before to 100 ms after it where that lateness is not sure; the
//! strike is the best match unless one at least 0.85 as good lies 30 ms
//! or more before it (a double strike's second blow, no louder, matches
//! later: `lag`). It is also sought in the stretch before that search, to
//! 600 ms before the time heard (`late`: in a room the band finder can
//! hear a bell far later than its lateness says), the better match kept. Strikes the band finder missed are found by their
//! templates (`fill`), and double strikes judged by the match
//! (`doubles`).

mod doubles;
mod fill;
mod lag;
mod late;
mod matcher;
mod weight;

use matcher::{Matcher, Scratch, PRE_S};

use crate::strikes::{Heard, HeardStrike, Hearing, StrikeOptions};
use crate::{Signal, SignalError};

/// How far before the strike's time as first heard, less its bell's
/// lateness, the match is searched (s): in a room the band finder hears a
/// bell later than on the ring of the templates its lateness was learned
/// on (on the recorded bells in rooms of RT60 0.6 s, true times lay 20 to
/// 90 ms before a search from 100 ms), and a double strike may be timed
/// at its second blow (up to 150 ms after the first). Chosen on seeds 1-2
/// of the recorded rings (0.1 s: recall within 10 ms 0.77-0.79 in rooms of
/// six bells; 0.16 s: 0.93-0.98; 0.22 s: 0.93-0.99; 0.28 s: 0.95-1.00).
const EARLY_S: f64 = 0.28;
/// How far after (s). At 40 ms the recorded bell d11 (r6 of session 14's
/// tester, 44.1 kHz, no phone processing), heard 5-17 ms late against a
/// lateness learned 64 ms, had the search end 11 ms before its sound: 13 of
/// 86 strikes matched at side peaks 8-11 ms early, and a second copy after
/// each called double (false doubles 3.0 %); at 80 ms none.
const LATE_S: f64 = 0.08;
/// Without a sure lateness, how far before the time heard (s): the band
/// finder heard the recorded bells measured up to 85 ms late.
const WIDE_EARLY_S: f64 = 0.2;
/// And after it (s).
const WIDE_LATE_S: f64 = 0.1;

/// Time every strike of `heard` (as the band finder heard it) again
/// against its bell's template (`templates[0]` the treble's), near its
/// time less the bell's `lateness` (s, as learned on a ring of the
/// templates: [`crate::lateness::from_templates`]) where it is known, else
/// from 200 ms before to 100 ms after its time. Returns how far each bell's strikes moved (the median, s),
/// treble first; a bell whose template is too short keeps its times.
pub fn retime(
    sig: &Signal,
    heard: &mut Heard,
    templates: &[Signal],
    lateness: &[Option<f64>],
) -> Result<Vec<Option<f64>>, SignalError> {
    let moves = retime_each(sig, heard, templates, lateness)?;
    let mut moved: Vec<Vec<f64>> = vec![vec![]; templates.len()];
    for (s, m) in heard.strikes.iter().zip(moves) {
        if let Some(m) = m {
            moved[s.bell - 1].push(m);
        }
    }
    heard
        .strikes
        .sort_by(|a, b| a.t.total_cmp(&b.t).then(a.bell.cmp(&b.bell)));
    Ok(moved.into_iter().map(median_of).collect())
}

/// Whether each template (treble first) is long enough to be matched in a
/// recording at `rate` (Hz): a bell whose template is not keeps its times
/// as heard (less its lateness), and every strike of one that is, those
/// the band finder missed and its templates found included, is timed at
/// the start of its sound.
pub fn matchable(rate: f64, templates: &[Signal]) -> Result<Vec<bool>, SignalError> {
    Ok(Matcher::new(rate, templates)?
        .bells
        .iter()
        .map(Option::is_some)
        .collect())
}

/// The median of `v` (the upper of the middle two), if any.
pub fn median_of(mut v: Vec<f64>) -> Option<f64> {
    v.sort_by(f64::total_cmp);
    v.get(v.len() / 2).copied()
}

/// [`retime`] without the order and the medians: each strike of `heard`
/// timed again where its template matches, in place (the strikes then
/// out of time order), and how far each moved (s; none where its bell's
/// template is too short or nothing matched). For a recording heard in
/// windows ([`crate::strikes::find_strikes_streamed`]): `sig` is the
/// window's audio, the strikes' times from its start. Double strikes are
/// judged as [`retime_each_with`] does with the default options.
pub fn retime_each(
    sig: &Signal,
    heard: &mut Heard,
    templates: &[Signal],
    lateness: &[Option<f64>],
) -> Result<Vec<Option<f64>>, SignalError> {
    retime_each_with(sig, heard, templates, lateness, &StrikeOptions::default())
}

/// [`retime_each`], the strikes taken in time order, each matched in the
/// recording with the strikes before it taken out (their templates,
/// scaled to fit), with the strikes the band finder missed added where
/// their templates match and the bell's rhythm leaves room (`fill`; at
/// the end of `heard.strikes`, moved by none), and every strike's double
/// judged by the match (`doubles`: a second copy of the template within
/// `opts.double_window_ms`, at least `opts.double_min_ratio` of the first
/// beyond the room's own echo of the bell), replacing the band finder's.
pub fn retime_each_with(
    sig: &Signal,
    heard: &mut Heard,
    templates: &[Signal],
    lateness: &[Option<f64>],
    opts: &StrikeOptions,
) -> Result<Vec<Option<f64>>, SignalError> {
    retime_judging(sig, heard, templates, lateness, opts, None)
}

/// [`retime_each_with`] for a window whose strikes were handed not yet
/// judged double ([`crate::strikes::find_strikes_streamed_deferred`]):
/// a strike the templates cannot judge (its bell's template too short,
/// the recording silent about it) takes the band finder's judgement from
/// `hearing` (by its index as handed), so the finder fits no second
/// strike after the others; `hearing` (its bands) is let go once every
/// strike is matched, before the missed strikes are sought. The strikes
/// and doubles are those [`retime_each_with`] gives strikes handed with
/// the band finder's doubles.
pub fn retime_each_deferred(
    sig: &Signal,
    heard: &mut Heard,
    hearing: Hearing,
    templates: &[Signal],
    lateness: &[Option<f64>],
    opts: &StrikeOptions,
) -> Result<Vec<Option<f64>>, SignalError> {
    retime_judging(sig, heard, templates, lateness, opts, Some(hearing))
}

/// Where a strike heard at `t` (s) is sought against its template (s, s):
/// near the time less the bell's `late`ness where that is sure, else widely
/// about the time heard.
fn sought(t: f64, late: Option<f64>) -> (f64, f64) {
    match late {
        Some(late) => (t - late.max(0.0) - EARLY_S, t - late.max(0.0) + LATE_S),
        None => (t - WIDE_EARLY_S, t + WIDE_LATE_S),
    }
}

/// A strike settled: its time (s), match, the correlations from its first
/// copy ([`doubles::Pairs::aligned`]) and the first copy's gain.
type Settled = (f64, f64, Vec<f64>, f64);

/// A strike of bell `bell` matched at `found` (time s, match) in `left`,
/// settled: where a second copy after it is far louder than the first
/// ([`doubles::LOUDER`]: no double strike's second blow is), the first was
/// something faint before the strike, and it is matched again about that
/// second (twice at most). Its time (s), match, correlations from the first copy
/// and gain; none where its bell has no whole template.
#[allow(clippy::too_many_arguments)]
fn settle(
    m: &Matcher,
    pairs: &mut doubles::Pairs,
    left: &[f64],
    bell: usize,
    (mut t, mut q): (f64, f64),
    window: (f64, f64),
    sc: &mut matcher::Scratch,
) -> Result<Option<Settled>, SignalError> {
    let Some(Some(tm)) = m.bells.get(bell - 1) else {
        return Ok(None);
    };
    for round in 0..3 {
        let Some(al) = pairs.aligned(left, bell, (t * m.rate).round() as i64)? else {
            return Ok(None);
        };
        // Moved earlier where the whole template says so (a side peak of
        // the first 150 ms taken: `doubles::EARLIER_S`).
        t += al.moved;
        let (a, gain) = (al.c, al.gain);
        let later = if round < 2 {
            pairs.louder_later(bell, &a, window)
        } else {
            None
        };
        let Some(d) = later else {
            return Ok(Some((t, q, a, gain)));
        };
        // Matched again about the louder second copy.
        match lag::best_match(m, left, tm, t + d - 0.01 - PRE_S, t + d + 0.01 - PRE_S, sc)? {
            // Only where it matches better: in a dark room the tail can
            // fit a louder copy after a strike matched at its sound.
            Some(f) if f.1 > q => (t, q) = f,
            _ => return Ok(Some((t, q, a, gain))),
        }
    }
    Ok(None)
}

/// [`retime_each_with`]; with a `hearing`, the strikes their templates do
/// not judge take its doubles ([`retime_each_deferred`]).
fn retime_judging(
    sig: &Signal,
    heard: &mut Heard,
    templates: &[Signal],
    lateness: &[Option<f64>],
    opts: &StrikeOptions,
    hearing: Option<Hearing>,
) -> Result<Vec<Option<f64>>, SignalError> {
    sig.validate()?;
    let mut m = Matcher::new(sig.rate, templates)?;
    let mut sc = m.scratch();
    set_polarities(&mut m, sig, heard, lateness, &mut sc)?;
    let sounds: Vec<Option<&[f64]>> = m.bells.iter().map(|b| b.as_ref().map(|t| &t.sound[..])).collect();
    let weighted: Vec<bool> = m.bells.iter().map(|b| b.as_ref().is_some_and(|t| t.weighted)).collect();
    let mut pairs = doubles::Pairs::new(m.rate, &sounds, &weighted, opts.double_window_ms.1 * 1e-3)?;
    let window = (opts.double_window_ms.0 * 1e-3, opts.double_window_ms.1 * 1e-3);
    // The recording with the strikes matched so far taken out (their
    // templates, scaled to fit): a strike is matched, and the missed ones
    // sought, in what the others leave.
    let mut left = sig.samples.clone();
    let mut moves = vec![None; heard.strikes.len()];
    let mut judged = vec![];
    let mut matched = vec![];
    let mut order: Vec<usize> = (0..heard.strikes.len()).collect();
    order.sort_by(|&a, &b| heard.strikes[a].t.total_cmp(&heard.strikes[b].t));
    // How far before its time heard each bell's strikes are sought.
    let reach = late::reach(m.bells.len(), heard);
    for i in order {
        let s = &mut heard.strikes[i];
        let Some(Some(tm)) = m.bells.get(s.bell - 1) else {
            continue;
        };
        let (from, to) = sought(s.t, lateness.get(s.bell - 1).copied().flatten());
        // And before that, to the bell's reach before the time heard.
        let found = late::best_of(&m, &left, tm, (from, to), s.t - reach[s.bell - 1], &mut sc)?;
        let Some(found) = found else {
            continue;
        };
        let Some((t, q, a, gain)) = settle(&m, &mut pairs, &left, s.bell, found, window, &mut sc)? else {
            moves[i] = Some(found.0 - s.t);
            s.t = found.0;
            continue;
        };
        moves[i] = Some(t - s.t);
        s.t = t;
        m.subtract(&mut left, tm, t, gain);
        judged.push((i, (s.bell, a)));
        matched.push((s.bell, s.t, q));
    }
    // Its hearing (its bands, as large as the fill's match) let go here.
    if let Some(hearing) = hearing {
        band_doubles(heard, hearing, judged.iter().map(|j| j.0));
    }
    // Strikes the band finder missed, where the rhythm leaves room.
    for (bell, t, q) in missing(&m, &left, &matched, &mut sc)? {
        let (Some(al), Some(Some(tm))) = (
            pairs.aligned(&left, bell, (t * m.rate).round() as i64)?,
            m.bells.get(bell - 1),
        ) else {
            continue;
        };
        let (t, a, gain) = (t + al.moved, al.c, al.gain);
        m.subtract(&mut left, tm, t, gain);
        judged.push((heard.strikes.len(), (bell, a)));
        heard.strikes.push(HeardStrike {
            bell,
            t,
            strength: q,
            double: None,
        });
        moves.push(None);
    }
    let (which, fits): (Vec<usize>, Vec<(usize, Vec<f64>)>) = judged.into_iter().unzip();
    for (i, fit) in which.into_iter().zip(pairs.judge(&fits, window, opts.double_min_ratio)) {
        heard.strikes[i].double = fit;
    }
    Ok(moves)
}

/// The sign each bell of `m` matches with, voted by its strikes of
/// `heard` where they are sought (its `lateness`, s), before any is
/// matched: a match of the other sign is none (tmpl-5).
fn set_polarities(
    m: &mut Matcher,
    sig: &Signal,
    heard: &Heard,
    lateness: &[Option<f64>],
    sc: &mut Scratch,
) -> Result<(), SignalError> {
    let windows = voter_windows(m.bells.len(), heard, lateness);
    // The signs (`lag::polarities`) read from the choice's own matches.
    let (chosen, signs) = weight::choose(m, &sig.samples, &windows, sc)?;
    for (t, w) in m.bells.iter_mut().zip(chosen) {
        if let Some(t) = t {
            t.weighted = w;
        }
    }
    for (t, s) in m.bells.iter_mut().zip(signs) {
        if let Some(t) = t {
            t.polarity = s;
        }
    }
    Ok(())
}

/// Where each strike of `heard` is sought when its bell's choice and
/// sign are voted (bell, and from, to: s), its bell's `lateness` (s)
/// taken off where known ([`sought`]); `bells` in all.
///
/// Where a bell's lateness is not known, its voters are sought as far
/// back as its strikes are then matched ([`late::best_of`] from
/// [`late::reach`]): sought only 200 ms back, the voters of a bell the
/// band finder heard 290 ms late (tester22's r6a, bell 2 in a dark room)
/// never reached its sound, both matches fell on the room's tail or
/// another bell, the weighted one no earlier, and it was left plain:
/// its plain match then took the tail, 9-16 ms late at most strikes
/// (mean +12.0 ms; weighted: -0.1), and it was called double at all 48
/// (now 22, most at 35 ms: the room's copy, still judged a second blow).
fn voter_windows(bells: usize, heard: &Heard, lateness: &[Option<f64>]) -> Vec<(usize, (f64, f64))> {
    let reach = late::reach(bells, heard);
    heard
        .strikes
        .iter()
        .map(|s| {
            let late = lateness.get(s.bell.wrapping_sub(1)).copied().flatten();
            let (from, to) = sought(s.t, late);
            let back = reach.get(s.bell.wrapping_sub(1)).copied().unwrap_or(0.0);
            (s.bell, (if late.is_none() { from.min(s.t - back) } else { from }, to))
        })
        .collect()
}

/// The strikes of `heard` no template judged (those not in `judged`, by
/// index) take the band finder's doubles from `hearing`.
fn band_doubles(heard: &mut Heard, hearing: Hearing, judged: impl Iterator<Item = usize>) {
    let mut by_template = vec![false; heard.strikes.len()];
    judged.for_each(|i| by_template[i] = true);
    for (i, (s, by)) in heard.strikes.iter_mut().zip(by_template).enumerate() {
        if !by {
            s.double = hearing.double(i);
        }
    }
}

/// The share of the bells' typical match taken as the typical of a bell
/// with fewer than three strikes matched (the band finder heard none):
/// such a bell's partials lie among another's, and its template matches
/// less well in the mix. Tester15's A6 rings (d9 beside d10, heard at
/// none of its strikes) matched it at 0.61-0.97 of the bells' typical
/// (median about 0.75), and at 1.0 the fill missed 4, 14 and 25 of its 82
/// strikes (A6_none, A6_jitter3, A6_level); at 0.7 and 0.6 none, 0 and 11,
/// with no strike added that was not rung (0.5 added one).
const UNHEARD_SHARE: f64 = 0.7;

/// The strikes (bell, time s, match over the bell's typical) that the
/// strikes `matched` (bell, time s, match) leave out of `left` (the
/// recording with them taken out): [`fill::missed`], each bell's typical
/// match and interval its own strikes' medians (where it has too few,
/// all the bells', the match times [`UNHEARD_SHARE`]).
fn missing(
    m: &Matcher,
    left: &[f64],
    matched: &[(usize, f64, f64)],
    sc: &mut matcher::Scratch,
) -> Result<Vec<(usize, f64, f64)>, SignalError> {
    let mut found = vec![];
    if matched.len() < 2 * m.bells.len() {
        return Ok(found);
    }
    let times = |b: usize| -> Vec<f64> {
        let mut v: Vec<f64> = matched.iter().filter(|s| s.0 == b).map(|s| s.1).collect();
        v.sort_by(f64::total_cmp);
        v
    };
    let gaps = |v: &[f64]| -> Vec<f64> { v.windows(2).map(|w| w[1] - w[0]).collect() };
    let all_q: Vec<f64> = matched.iter().map(|s| s.2).collect();
    let all_gaps: Vec<f64> = (1..=m.bells.len()).flat_map(|b| gaps(&times(b))).collect();
    let (typical_q, typical_gap) = (crate::median(&all_q), crate::median(&all_gaps));
    let chunks = fill::Chunks::new(m, left, sc)?;
    for (b, tm) in m.bells.iter().enumerate() {
        let Some(tm) = tm else { continue };
        let have = times(b + 1);
        let q: Vec<f64> = matched.iter().filter(|s| s.0 == b + 1).map(|s| s.2).collect();
        // The bell's own interval, but never more than the bells' (a bell
        // heard at every other strike has twice the interval it rings at).
        let (q, gap) = if have.len() >= 3 {
            let own = crate::median(&gaps(&have));
            (crate::median(&q), own.min(typical_gap))
        } else {
            (UNHEARD_SHARE * typical_q, typical_gap)
        };
        for (t, mq) in fill::missed(m, left, &chunks, tm, &have, q, gap, sc)? {
            found.push((b + 1, t, mq / q));
        }
    }
    Ok(found)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampled_ring::{sampled_ring, Blow, UntunedStrike};
    use crate::strikes::{find_strikes, BellVoice, StrikeOptions};
    use crate::tower::{major_scale, score, Method, TowerSpec};

    /// A bell struck alone, after 20 ms of silence, whose partials start at
    /// a tenth of their peak and build up over `rise_s` (s), as recorded
    /// tower bells' do, with the clapper's blow a broadband click at its
    /// start.
    pub(crate) fn slow_bell(rate: f64, nominal: f64, rise_s: f64) -> Signal {
        let blow = Blow {
            amplitude: 0.6,
            decay_s: 0.002,
            seed: (nominal * 1000.0) as u64 | 1,
        };
        UntunedStrike {
            nominal_hz: nominal,
            rise_s,
            decay_s: 0.8,
            length_s: 1.5,
            blow: Some(blow),
        }
        .signal(rate)
    }

    /// A bell the band finder hears at none of its strikes, whose template
    /// matches the ring less well than the others' do (its template a
    /// noisy copy of its sound: a real bell's partials among a
    /// neighbour's), is found by the fill at its strikes: rounds of four
    /// slowly rising bells, bell 3's strikes taken out of what was heard.
    /// Against the bells' typical match itself (before), the fill found
    /// 0 of its 16 (it now finds 11, each within 10 ms, and nothing else).
    #[test]
    fn a_bell_heard_at_none_of_its_strikes_is_found_by_a_template_that_matches_less_well() {
        use rand::{Rng, SeedableRng};
        let rate = 16_000.0;
        let bells = major_scale(4, 1000.0).unwrap();
        let clean: Vec<Signal> = bells.iter().map(|b| slow_bell(rate, b.nominal_hz, 0.03)).collect();
        let spec = TowerSpec {
            rate,
            rows: 16,
            snr_db: Some(30.0),
            ..TowerSpec::new(bells)
        };
        let (sig, truth) = sampled_ring(&spec, &clean).unwrap();
        let voices: Vec<BellVoice> = clean.iter().map(|t| BellVoice::from_template(t).unwrap()).collect();
        let mut heard = find_strikes(&sig, &voices, &StrikeOptions::default()).unwrap();
        heard.strikes.retain(|s| s.bell != 3);
        // Bell 3's template: its sound with noise twice its level (an rms
        // ratio), from its onset: it then matches about 0.45 as well.
        let mut templates = clean.clone();
        let o = (crate::sampled_ring::sample_onset(&clean[2]).unwrap() * rate).round() as usize;
        let power = clean[2].samples[o..o + 2400].iter().map(|v| v * v).sum::<f64>() / 2400.0;
        let mut rng = rand_pcg::Pcg64::seed_from_u64(3);
        for v in &mut templates[2].samples[o..] {
            *v += 2.0 * (3.0 * power).sqrt() * rng.random_range(-1.0..1.0);
        }
        let late = crate::lateness::from_templates(&clean, &voices, &StrikeOptions::default()).unwrap();
        let l: Vec<Option<f64>> = late.bells.iter().map(|b| b.sure().then_some(b.lateness_s)).collect();
        retime_each_with(&sig, &mut heard, &templates, &l, &StrikeOptions::default()).unwrap();
        let mine: Vec<f64> = heard.strikes.iter().filter(|s| s.bell == 3).map(|s| s.t).collect();
        let found = truth
            .iter()
            .filter(|g| g.bell == 3 && mine.iter().any(|t| (t - g.t).abs() < 0.01))
            .count();
        assert!(found >= 10, "bell 3: {found} of 16 strikes found");
        assert_eq!(mine.len(), found, "bell 3: strikes reported that were not rung");
    }

    /// Each bell's sign is voted by its strikes: a bell whose sound is
    /// turned at half its strikes keeps +1 (and a turned sound then
    /// matches only half a period off), one turned at every strike (a room turning its
    /// phase, a recording turned) takes -1. By magnitude (before) the
    /// turned strikes matched as well as the others.
    #[test]
    fn a_bell_turned_at_half_its_strikes_matches_at_its_own_sign() {
        let rate = 16_000.0;
        let bell = slow_bell(rate, 900.0, 0.03);
        let o = (crate::sampled_ring::sample_onset(&bell).unwrap() * rate).round() as usize;
        let times: Vec<f64> = (0..12).map(|k| 0.5 + k as f64).collect();
        let ring = |turned: &dyn Fn(usize) -> bool| {
            let mut x = vec![0.0; (14.0 * rate) as usize];
            for (k, &t) in times.iter().enumerate() {
                let i0 = (t * rate).round() as usize;
                let g = if turned(k) { -1.0 } else { 1.0 };
                for (j, v) in bell.samples[o..].iter().enumerate() {
                    x[i0 + j] += g * v;
                }
            }
            x
        };
        let mut m = Matcher::new(rate, std::slice::from_ref(&bell)).unwrap();
        let mut sc = m.scratch();
        let windows: Vec<(usize, (f64, f64))> = times.iter().map(|&t| (1, (t - 0.1, t + 0.1))).collect();
        let half = ring(&|k| k % 2 == 1);
        let all = ring(&|_| true);
        assert_eq!(lag::polarities(&m, &half, &windows, &mut sc).unwrap(), vec![1.0]);
        assert_eq!(lag::polarities(&m, &all, &windows, &mut sc).unwrap(), vec![-1.0]);
        // A turned strike: by magnitude it matches fully, at +1 only half a
        // period off (0.72 here: the partials do not all turn back there).
        let at = |m: &Matcher, sc: &mut matcher::Scratch| {
            let t = m.bells[0].as_ref().unwrap();
            lag::best_match(m, &half, t, times[1] - 0.1 - PRE_S, times[1] + 0.1 - PRE_S, sc).unwrap()
        };
        let by_magnitude = at(&m, &mut sc).unwrap();
        assert!(
            (by_magnitude.0 - times[1]).abs() < 0.002 && by_magnitude.1 > 0.9,
            "{by_magnitude:?}"
        );
        m.bells[0].as_mut().unwrap().polarity = 1.0;
        let signed = at(&m, &mut sc).map_or(0.0, |f| f.1);
        assert!(signed < 0.8 * by_magnitude.1, "a turned strike matched at {signed:.2}");
    }

    /// The median error (ms) and the share of strikes within 2 ms.
    fn errors(heard: &Heard, truth: &[crate::tower::TrueStrike]) -> (f64, f64) {
        let sc = score(&heard.times(), truth, 0.1);
        let mut e: Vec<f64> = sc.onset_errors.iter().map(|v| v.abs() * 1e3).collect();
        e.sort_by(f64::total_cmp);
        let near = e.iter().filter(|v| **v <= 2.0).count();
        (e[e.len() / 2], near as f64 / truth.len() as f64)
    }

    /// Six slowly rising synthetic bells (partials near whole ratios, so a
    /// template matches itself well a few tens of ms off), rounds with six
    /// double strikes, timed on their templates: every strike within
    /// 10 ms and no single strike called double. With an earlier match at
    /// 0.6 of the best taken as the first blow: recall 0.62 and 22 false
    /// doubles (each after a strike matched 38-74 ms early).
    #[test]
    fn near_harmonic_bells_matched_on_their_templates_are_not_timed_early_or_called_double() {
        use crate::tower::DoubleStrikeSpec;
        let rate = 16_000.0;
        let (mut n, mut within, mut found, mut false_doubles) = (0, 0, 0, 0);
        for seed in [1, 2] {
            let bells = major_scale(6, 1000.0).unwrap();
            let templates: Vec<Signal> = bells.iter().map(|b| slow_bell(rate, b.nominal_hz, 0.03)).collect();
            let spec = TowerSpec {
                rate,
                rows: 20,
                seed,
                snr_db: Some(25.0),
                doubles: (0..6)
                    .map(|k| DoubleStrikeSpec {
                        bell: 1 + k,
                        row: 2 + 3 * k,
                        delay_ms: 50.0 + 7.0 * k as f64,
                        amplitude_ratio: 0.7,
                    })
                    .collect(),
                ..TowerSpec::new(bells)
            };
            let (sig, truth) = sampled_ring(&spec, &templates).unwrap();
            let voices: Vec<BellVoice> = templates.iter().map(|t| BellVoice::from_template(t).unwrap()).collect();
            let mut heard = find_strikes(&sig, &voices, &StrikeOptions::default()).unwrap();
            let late = crate::lateness::from_templates(&templates, &voices, &StrikeOptions::default()).unwrap();
            let l: Vec<Option<f64>> = late.bells.iter().map(|b| b.sure().then_some(b.lateness_s)).collect();
            retime(&sig, &mut heard, &templates, &l).unwrap();
            n += truth.len();
            within += score(&heard.times(), &truth, 0.01).found;
            let sc = score(&heard.times(), &truth, 0.05);
            found += sc.doubles_found;
            false_doubles += sc.false_doubles;
        }
        let recall = within as f64 / n as f64;
        assert!(recall >= 0.97, "recall within 10 ms {recall:.3}");
        assert!(found >= 9, "{found} of 12 doubles");
        assert!(false_doubles * 50 <= n, "{false_doubles} false doubles in {n}");
    }

    /// A bell struck 12 times in a room whose tail is darker than the
    /// direct sound (RT60 1 s, 0 dB direct-to-reverberant, the tail's noise
    /// filtered y[n] = x[n] + 0.6 y[n-1]: a real room's high frequencies
    /// die first), each strike sought 150 ms either side of its time: it
    /// matches at its direct sound, not where the tail's partials come
    /// into step with the template.
    #[test]
    fn a_bell_in_a_room_with_a_darker_tail_matches_at_its_direct_sound() {
        use crate::tower::{convolve, room_response, Room};
        use rand::SeedableRng;
        let rate = 16_000.0;
        let times: Vec<f64> = (0..12).map(|k| 0.5 + 2.0 * k as f64).collect();
        let mut off = vec![];
        for nominal in [700.0, 1000.0, 1400.0] {
            for seed in 1..=3u64 {
                let bell = slow_bell(rate, nominal, 0.03);
                let o = (crate::sampled_ring::sample_onset(&bell).unwrap() * rate).round() as usize;
                let mut x = vec![0.0; (26.0 * rate) as usize];
                for &t in &times {
                    let i0 = (t * rate).round() as usize;
                    for (j, v) in bell.samples[o..].iter().enumerate() {
                        x[i0 + j] += v;
                    }
                }
                let room = Room::chamber(1.0).with_dark_tail(0.6, 0.0);
                let ir = room_response(room, rate, &mut rand_pcg::Pcg64::seed_from_u64(seed));
                let y = convolve(&x, &ir);
                let mut m = Matcher::new(rate, std::slice::from_ref(&bell)).unwrap();
                let mut sc = m.scratch();
                let windows: Vec<(usize, (f64, f64))> = times
                    .iter()
                    .map(|&s| (1, (s - 0.15 - PRE_S, s + 0.15 - PRE_S)))
                    .collect();
                let w = weight::choose(&mut m, &y, &windows, &mut sc).unwrap().0;
                m.bells[0].as_mut().unwrap().weighted = w[0];
                let t = m.bells[0].as_ref().unwrap();
                let n = times
                    .iter()
                    .filter(|&&s| {
                        let f = lag::best_match(&m, &y, t, s - 0.15 - PRE_S, s + 0.15 - PRE_S, &mut sc).unwrap();
                        f.is_none_or(|f| (f.0 - s).abs() > 0.01)
                    })
                    .count();
                off.push(n);
            }
        }
        // Matched as recorded (main): 72 of 108 off, whole bells at
        // every strike ([12, 12, 0, 12, 12, 0, 0, 12, 12]); every bell
        // weighted (the WIP) 20 ([1, 12, 1, 1, 1, 1, 1, 1, 1]); weighted
        // where chosen 28 ([1, 12, 0, 1, 1, 0, 0, 12, 1]: in the 700 Hz
        // bell's second room neither match is at the sound, and in the
        // 1400 Hz bell's the weighted match at the plain one's time is
        // 0.95 of its best, so it is kept plain).
        let total: usize = off.iter().sum();
        assert!(total <= 30, "strikes matched over 10 ms off: {off:?}");
    }

    /// Strikes handed not yet judged double, their doubles judged by the
    /// templates and, where a bell's template is too short to match, by
    /// the band finder asked afterwards: the same strikes and doubles as
    /// the band finder judging every strike first and the templates
    /// judging again (the band finder's fit after each strike spared).
    #[test]
    fn doubles_judged_after_the_templates_are_those_judged_before() {
        use crate::strikes::hear_strikes;
        use crate::tower::DoubleStrikeSpec;
        let rate = 16_000.0;
        let bells = major_scale(5, 1000.0).unwrap();
        let templates: Vec<Signal> = bells.iter().map(|b| slow_bell(rate, b.nominal_hz, 0.03)).collect();
        let spec = TowerSpec {
            rate,
            rows: 16,
            snr_db: Some(30.0),
            doubles: [(2, 3), (2, 9), (4, 6), (4, 12)]
                .iter()
                .map(|&(bell, row)| DoubleStrikeSpec {
                    bell,
                    row,
                    delay_ms: 70.0,
                    amplitude_ratio: 0.9,
                })
                .collect(),
            ..TowerSpec::new(bells)
        };
        let (sig, _) = sampled_ring(&spec, &templates).unwrap();
        let voices: Vec<BellVoice> = templates.iter().map(|t| BellVoice::from_template(t).unwrap()).collect();
        let opts = StrikeOptions::default();
        // Bell 2's template cut to 0.1 s: too short to match, so its
        // strikes keep the band finder's doubles.
        let mut given = templates.clone();
        given[1].samples.truncate((0.1 * rate) as usize);
        let late = vec![None; 5];
        let mut before = find_strikes(&sig, &voices, &opts).unwrap();
        let moved_before = retime_each_with(&sig, &mut before, &given, &late, &opts).unwrap();
        let hearing = hear_strikes(&sig, &voices, &opts).unwrap();
        let mut after = hearing.singles();
        let moved_after = retime_each_deferred(&sig, &mut after, hearing, &given, &late, &opts).unwrap();
        assert_eq!(after, before);
        assert_eq!(moved_after, moved_before);
        assert!(
            before.strikes.iter().any(|s| s.bell == 2 && s.double.is_some()),
            "bell 2's doubles (the band finder's) not heard"
        );
    }

    /// Twelve rows of plain hunt on `bells` at `rate` (Hz), 30 dB over the noise.
    fn plain_hunt_at(rate: f64, bells: Vec<crate::tower::RingBell>) -> TowerSpec {
        TowerSpec {
            rate,
            rows: 12,
            method: Method::PlainHunt,
            snr_db: Some(30.0),
            ..TowerSpec::new(bells)
        }
    }

    #[test]
    fn a_slowly_rising_bell_is_timed_at_the_start_of_its_sound() {
        let rate = 16_000.0;
        let bells = major_scale(4, 1000.0).unwrap();
        let templates: Vec<Signal> = bells.iter().map(|b| slow_bell(rate, b.nominal_hz, 0.03)).collect();
        let spec = plain_hunt_at(rate, bells);
        let (sig, truth) = sampled_ring(&spec, &templates).unwrap();
        let voices: Vec<BellVoice> = templates.iter().map(|t| BellVoice::from_template(t).unwrap()).collect();
        let mut heard = find_strikes(&sig, &voices, &StrikeOptions::default()).unwrap();
        let (before, near_before) = errors(&heard, &truth);
        // The band finder hears a bell rising over 30 ms late.
        assert!(
            before > 5.0 && near_before < 0.2,
            "as heard: median {before:.2} ms, {near_before:.2} within 2 ms"
        );
        let late = crate::lateness::from_templates(&templates, &voices, &StrikeOptions::default()).unwrap();
        let l: Vec<Option<f64>> = late.bells.iter().map(|b| b.sure().then_some(b.lateness_s)).collect();
        let moved = retime(&sig, &mut heard, &templates, &l).unwrap();
        let (after, near) = errors(&heard, &truth);
        // Half the strikes now to within 2 ms, the median exact; the rest
        // matched another bell's partials or this bell's previous strike
        // still ringing (a limit: docs/strikes.md).
        assert!(
            after < 0.5 && near > 0.5,
            "timed on the templates: median {after:.2} ms, {near:.2} within 2 ms"
        );
        assert!(moved.iter().all(|m| m.is_some_and(|m| m < -0.003)), "{moved:?}");
    }

    #[test]
    fn a_room_echo_every_strike_has_is_not_a_double_strike() {
        // One bell struck every 2 s, each strike heard again 30 ms later at
        // 0.45 (a reflection, as a room gives every strike of a bell), and
        // two strikes struck twice (the second blow 61.1 ms later, at 0.7:
        // not 60 ms, 27 periods of this bell's hum, where its near-whole
        // partials are back in step and the template matches itself too
        // well for two copies to be told apart, a blind spot).
        let rate = 16_000.0;
        let bell = slow_bell(rate, 900.0, 0.03);
        let o = (crate::sampled_ring::sample_onset(&bell).unwrap() * rate) as usize;
        let sound = &bell.samples[o..];
        let times: Vec<f64> = (0..12).map(|k| 0.5 + 2.0 * k as f64).collect();
        let mut x = vec![0.0; (26.0 * rate) as usize];
        let mut put = |t: f64, g: f64| {
            let i0 = (t * rate).round() as usize;
            for (k, v) in sound.iter().enumerate() {
                x[i0 + k] += g * v;
            }
        };
        for (k, &t) in times.iter().enumerate() {
            put(t, 1.0);
            put(t + 0.03, 0.45);
            if k == 4 || k == 9 {
                put(t + 0.0611, 0.7);
                put(t + 0.0911, 0.7 * 0.45);
            }
        }
        let m = Matcher::new(rate, std::slice::from_ref(&bell)).unwrap();
        let sounds: Vec<Option<&[f64]>> = m.bells.iter().map(|b| b.as_ref().map(|t| &t.sound[..])).collect();
        let mut pairs = doubles::Pairs::new(rate, &sounds, &[], 0.15).unwrap();
        let fits: Vec<(usize, Vec<f64>)> = times
            .iter()
            .map(|&t| {
                (
                    1,
                    pairs.correlations(&x, 1, (t * rate).round() as i64).unwrap().unwrap(),
                )
            })
            .collect();
        let judged = pairs.judge(&fits, (0.01, 0.15), 0.3);
        for (k, d) in judged.iter().enumerate() {
            if k == 4 || k == 9 {
                let d = d.unwrap_or_else(|| panic!("strike {k}: its double not found"));
                // (Its delay read to within 10 ms: this bell's partials,
                // near whole ratios, fit a second copy a few periods off
                // nearly as well; the recorded bells' read to 1-2 ms.)
                assert!((d.delay_s - 0.0611).abs() < 0.01, "strike {k}: {d:?}");
            } else {
                assert!(d.is_none(), "strike {k}, single, called double: {d:?}");
            }
        }
    }

    /// Bell `strike` (its sound after 20 ms of silence) in a recording's
    /// noise floor (white, at 0.004 of its peak, seeded), with `lead_s`
    /// (s) of that noise before its sound.
    fn with_lead_in(strike: &Signal, lead_s: f64, seed: u64) -> Signal {
        let rate = strike.rate;
        let sound = &strike.samples[(0.02 * rate).round() as usize..];
        let floor = 0.004 * sound.iter().fold(0.0f64, |p, v| p.max(v.abs()));
        let mut state = seed;
        let lead = vec![0.0; (lead_s * rate).round() as usize];
        let samples = lead
            .iter()
            .chain(sound)
            .map(|v| v + 2.0 * floor * crate::sampled_ring::blow_noise(&mut state))
            .collect();
        Signal { rate, samples }
    }

    /// Four bells in plain hunt, rung from their strikes with 100 ms of
    /// their floor noise before them, timed on the same strikes with 0,
    /// 4, 20 and 100 ms of lead-in: each bell's strikes read the same to
    /// 1 ms. With the noise measured over a template's first 5 ms (main),
    /// 4 ms of lead-in took in the sound's start and read bells
    /// several ms off.
    #[test]
    fn a_template_times_its_strikes_the_same_whatever_its_lead_in() {
        use crate::sampled_ring::octave_heavy_strike;
        let rate = 16_000.0;
        let bells = major_scale(4, 1000.0).unwrap();
        let strikes: Vec<Signal> = bells
            .iter()
            .enumerate()
            .map(|(i, b)| octave_heavy_strike(b.nominal_hz, 1.0, rate, 3 + i as u64))
            .collect();
        let templates = |lead_s: f64| -> Vec<Signal> {
            strikes
                .iter()
                .enumerate()
                .map(|(i, s)| with_lead_in(s, lead_s, 11 + i as u64))
                .collect()
        };
        let long = templates(0.1);
        let spec = plain_hunt_at(rate, bells);
        let (sig, truth) = sampled_ring(&spec, &long).unwrap();
        let voices: Vec<BellVoice> = long.iter().map(|t| BellVoice::from_template(t).unwrap()).collect();
        let heard = find_strikes(&sig, &voices, &StrikeOptions::default()).unwrap();
        let late = vec![None; 4];
        let timed = |given: &[Signal]| -> Heard {
            let mut h = heard.clone();
            retime(&sig, &mut h, given, &late).unwrap();
            h
        };
        let base = timed(&long);
        let (median, _) = errors(&base, &truth);
        assert!(median < 1.0, "with 100 ms of lead-in: median error {median:.2} ms");
        for lead_s in [0.0, 0.004, 0.02] {
            let other = timed(&templates(lead_s));
            for bell in 1..=4 {
                let mine =
                    |h: &Heard| -> Vec<f64> { h.strikes.iter().filter(|s| s.bell == bell).map(|s| s.t).collect() };
                let a = mine(&base);
                let moved: Vec<f64> = mine(&other)
                    .iter()
                    .map(|t| {
                        let near = a.iter().copied().min_by(|x, y| (x - t).abs().total_cmp(&(y - t).abs()));
                        (t - near.unwrap_or(f64::INFINITY)) * 1e3
                    })
                    .collect();
                let m = median_of(moved.clone()).unwrap_or(f64::INFINITY);
                assert!(
                    m.abs() <= 1.0,
                    "bell {bell} with {:.0} ms of lead-in moved {m:.2} ms: {moved:.1?}",
                    lead_s * 1e3
                );
            }
        }
    }

    /// A bell whose lateness is not known has its voters sought as far
    /// back as its strikes are matched ([`late::reach`]: 0.6 s at 2 s a
    /// strike), so a strike the band finder heard 290 ms after its sound
    /// (tester22's r6a, bell 2) is within its voter's window; a bell whose
    /// lateness is known keeps the search about its time less that. Sought
    /// only 200 ms back, bell 2's voters never reached its sound.
    #[test]
    fn a_bell_of_unknown_lateness_votes_as_far_back_as_it_is_matched() {
        let strikes = (0..24)
            .map(|k| HeardStrike {
                bell: 1 + k % 2,
                t: 1.0 + k as f64,
                strength: 1.0,
                double: None,
            })
            .collect();
        let heard = Heard {
            strikes,
            warnings: vec![],
        };
        let windows = voter_windows(2, &heard, &[Some(0.05), None]);
        assert_eq!(windows.len(), 24);
        for ((bell, (from, to)), s) in windows.iter().zip(&heard.strikes) {
            let want = if *bell == 1 {
                sought(s.t, Some(0.05))
            } else {
                (s.t - 0.6, s.t + WIDE_LATE_S)
            };
            assert!(
                (from - want.0).abs() < 1e-9 && (to - want.1).abs() < 1e-9,
                "bell {bell}: {from}, {to}"
            );
            assert!(
                *bell == 1 || *from <= s.t - 0.29,
                "bell 2 sought from {from} at {}",
                s.t
            );
        }
    }
}
