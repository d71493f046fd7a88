//! Which bells are matched weighted toward their upper partials
//! ([`super::matcher::heard`]). In a room whose tail is darker than the
//! direct sound (a real room's high frequencies die first) a bell's low
//! partials can be louder in the tail than in the direct sound, and its
//! match as recorded is ruled by them: the tail's partials come into step
//! with the dry template 16-52 ms after the strike, at every strike of
//! the bell. Weighted, the match is ruled by the upper partials, which the
//! tail carries less, and times the direct sound; but where the room does
//! not darken, the weighted match is the worse (it rests on fewer, fainter
//! partials and the blow's click: synthetic bells at 16 kHz turned half a
//! period or near-harmonic matched a few tens of ms off; a bell muffled
//! in the ring has no upper partials to match). So a bell is matched
//! weighted only where, at most of its strikes, its two matches part by
//! the same amount and the weighted match rejects the plain one's time,
//! or where at a fair share the weighted match lies well before the plain
//! one (a tail comes after the direct sound) and rejects its time at
//! nearly all of those ([`is_weighted`]).

use super::lag::{best_match, voters, TURNED};
use super::matcher::{Matcher, Scratch, PRE_S};
use crate::SignalError;

/// How far from the match as recorded (s) the weighted match must lie at
/// a strike to vote for it: the dark tail put the match as recorded
/// 16-52 ms late (or, by the rule for a double's first blow, as early),
/// while where both match the same sound they agree to a few ms.
const APART_S: f64 = 0.008;
/// How near the plain match's time (s) the weighted match is read there.
const NEAR_S: f64 = 0.001;
/// The weighted match at the plain match's time, as a share of its best,
/// under which the plain match's time is not the weighted's strike.
const KEEP: f64 = 0.85;
/// How near the median of the strikes' moves (s) a strike's move must be
/// to vote: the room moves the match as recorded the same at each.
const SAME_S: f64 = 0.005;
/// The share of a bell's votes that must fall so.
const SHARE: f64 = 0.5;
/// The share of a bell's votes whose weighted match lies over [`APART_S`]
/// before the plain one, over which it is matched weighted where its
/// weighted match can tell its strike (tmpl-11, from tmpl-10's rule): in
/// the tune set's rooms whose tail was low-passed at 3 kHz and as loud as
/// the direct sound the plain match lay 8-73 ms late at most strikes of a
/// bell, by amounts that differ strike to strike, and the weighted match
/// found the plain one's time 0.80-0.98 of its best, so tmpl-7's rule
/// left them plain (A8_dark's treble 57 ms late at every strike).
const EARLY: f64 = 0.25;
/// The share of a bell's votes, weighted early, at which the weighted
/// match finds the plain one's time at least [`KEEP`] of its best, over
/// which it cannot tell its strike (a bell muffled in the ring, its upper
/// partials gone: the tune set's A6_all bell 2).
const AGAINST: f64 = 0.2;

/// Each bell's choice (treble first): whether its strikes `sought` (bell
/// from 1, and where its template is sought, s, s) in the recording `x`
/// are matched weighted, as [`is_weighted`] reads up to
/// [`VOTES`](super::lag::VOTES) of them. Matched by magnitude (before the polarities are known);
/// leaves every template matched as recorded. With it, the sign each bell
/// matches with as chosen, from the same matches: what
/// [`super::lag::polarities`] gives once the choice is made (its
/// matches are these), without matching the voters a fourth time.
pub(super) fn choose(
    m: &mut Matcher,
    x: &[f64],
    sought: &[(usize, (f64, f64))],
    sc: &mut Scratch,
) -> Result<(Vec<bool>, Vec<f64>), SignalError> {
    // The plain and weighted matches from one sample share the
    // recording's transform.
    sc.keeping(x, |sc| {
        let (mut chosen, mut signs) = (vec![], vec![]);
        for b in 0..m.bells.len() {
            let (w, turned, n) = choose_one(m, x, b, sought, sc)?;
            chosen.push(w);
            let turned = turned[usize::from(w)];
            let has = m.bells.get(b).is_some_and(Option::is_some);
            signs.push(if has && n > 0 && turned as f64 >= TURNED * n as f64 {
                -1.0
            } else {
                1.0
            });
        }
        Ok((chosen, signs))
    })
}

/// [`choose`] for bell `b` (from 0): whether it is matched weighted, and
/// of its voters (how many: the third), how many match turned as recorded
/// and weighted (by magnitude, the sign at the best).
fn choose_one(
    m: &mut Matcher,
    x: &[f64],
    b: usize,
    sought: &[(usize, (f64, f64))],
    sc: &mut Scratch,
) -> Result<(bool, [usize; 2], usize), SignalError> {
    // Each voting strike's move (weighted less plain, s) and whether
    // the weighted match rejects the plain one's time.
    let mut parts = vec![];
    let (mut turned, mut voted) = ([0usize; 2], 0usize);
    for (from, to) in voters(sought, b + 1) {
        voted += 1;
        set(m, b, false);
        let plain = best(m, x, b, from, to, sc)?;
        turned[0] += usize::from(is_turned(m, from, to, sc));
        set(m, b, true);
        let weighted = best(m, x, b, from, to, sc)?;
        turned[1] += usize::from(is_turned(m, from, to, sc));
        let (Some(p), Some(w)) = (plain, weighted) else {
            continue;
        };
        // The weighted match at the plain match's time: read from the
        // weighted match just made where it lies inside it.
        let near = (p.0 - PRE_S - NEAR_S, p.0 - PRE_S + NEAR_S);
        let at_p = match read_within(m, (from, to), near, &sc.out) {
            Some(v) => v,
            None => best(m, x, b, near.0, near.1, sc)?.map_or(0.0, |f| f.1),
        };
        parts.push((w.0 - p.0, at_p < KEEP * w.1));
    }
    set(m, b, false);
    Ok((is_weighted(&parts), turned, voted))
}

/// Whether a bell whose voting strikes' two matches part as `parts` say
/// (the weighted match's time less the plain one's, s, and whether the
/// weighted match there rejects the plain one's time) is matched
/// weighted: where over [`SHARE`] of them move over [`APART_S`], rejected,
/// within [`SAME_S`] of their median move (tmpl-7: a room moves a bell
/// alike), or where over [`EARLY`] of them are weighted over [`APART_S`]
/// before the plain match and at no more than [`AGAINST`] of them is the
/// plain one's time not rejected (a room's tail comes after the direct
/// sound, so it pulls the plain match late, not always by the same).
fn is_weighted(parts: &[(f64, bool)]) -> bool {
    let n = parts.len() as f64;
    let apart: Vec<f64> = parts
        .iter()
        .filter(|(d, rejected)| d.abs() > APART_S && *rejected)
        .map(|p| p.0)
        .collect();
    let mid = if apart.is_empty() { 0.0 } else { crate::median(&apart) };
    let votes = apart.iter().filter(|d| (*d - mid).abs() <= SAME_S).count();
    let early: Vec<bool> = parts.iter().filter(|p| p.0 < -APART_S).map(|p| p.1).collect();
    let against = early.iter().filter(|rejected| !**rejected).count();
    n > 0.0 && (votes as f64 > SHARE * n || (early.len() as f64 > EARLY * n && against as f64 <= AGAINST * n))
}

/// The best match (by magnitude) from `near.0` to `near.1` (s), read from
/// the normalised match `out` just made from `made.0` to `made.1` (s),
/// where its lags lie inside that: what [`best`] there gives (from
/// another transform, so to a rounding: speed-4), without it. None
/// outside.
fn read_within(m: &Matcher, made: (f64, f64), near: (f64, f64), out: &[f64]) -> Option<f64> {
    let rate = m.rate;
    let lags = |(from, to): (f64, f64)| (((to - from) * rate).round() as usize).min(m.span());
    let (start, start_near) = ((made.0 * rate).round() as i64, (near.0 * rate).round() as i64);
    let j = usize::try_from(start_near - start).ok()?;
    (j + lags(near) <= lags(made)).then(|| out[j..=j + lags(near)].iter().fold(0.0f64, |a, v| a.max(v.abs())))
}

/// Whether the match just made from `from` to `to` (s; by magnitude, its
/// normalised match left in `sc.out`) is of the turned sign at its best,
/// as [`super::lag::polarities`] reads it.
fn is_turned(m: &Matcher, from: f64, to: f64, sc: &Scratch) -> bool {
    let lags = (((to - from) * m.rate).round() as usize).min(m.span());
    let out = &sc.out[..=lags];
    let k = (0..=lags)
        .max_by(|&a, &b| out[a].abs().total_cmp(&out[b].abs()))
        .unwrap_or(0);
    out[k] < 0.0
}

/// Bell `b` (from 0) matched `weighted` or not.
fn set(m: &mut Matcher, b: usize, weighted: bool) {
    if let Some(Some(t)) = m.bells.get_mut(b) {
        t.weighted = weighted;
    }
}

/// The strike's time (s) and match where bell `b`'s template matches `x`
/// best from `from` to `to` (s, [`best_match`]: its rule for a double
/// strike's first blow); none where silent.
fn best(
    m: &Matcher,
    x: &[f64],
    b: usize,
    from: f64,
    to: f64,
    sc: &mut Scratch,
) -> Result<Option<(f64, f64)>, SignalError> {
    let Some(Some(t)) = m.bells.get(b) else {
        return Ok(None);
    };
    best_match(m, x, t, from, to, sc)
}

#[cfg(test)]
mod tests {
    use super::super::lag::polarities;
    use super::super::matcher::Matcher;
    use super::{best, choose, is_weighted, read_within, set, NEAR_S, PRE_S};
    use crate::template_timing::tests::slow_bell;

    /// The signs read from the choice's own matches are those
    /// `lag::polarities` gives once the choice is made (speed-4): three
    /// bells, one turned at every strike, one at half, in a room whose
    /// tail is darker than the direct sound (so some are matched weighted).
    #[test]
    fn the_signs_read_in_the_choice_are_the_polarities_voted_after_it() {
        use crate::tower::{convolve, room_response, Room};
        use rand::SeedableRng;
        let rate = 16_000.0;
        let bells: Vec<_> = [700.0, 1000.0, 1400.0]
            .iter()
            .map(|&f| slow_bell(rate, f, 0.03))
            .collect();
        let mut x = vec![0.0; (40.0 * rate) as usize];
        let mut sought = vec![];
        for k in 0..36 {
            let b = k % 3;
            let t = 0.5 + k as f64;
            let turned = b == 0 || (b == 1 && k % 2 == 0);
            let g = if turned { -1.0 } else { 1.0 };
            let o = (crate::sampled_ring::sample_onset(&bells[b]).unwrap() * rate).round() as usize;
            let i0 = (t * rate).round() as usize;
            for (j, v) in bells[b].samples[o..].iter().enumerate() {
                x[i0 + j] += g * v;
            }
            sought.push((b + 1, (t - 0.15, t + 0.1)));
        }
        let room = Room::chamber(1.0).with_dark_tail(0.6, 0.0);
        let ir = room_response(room, rate, &mut rand_pcg::Pcg64::seed_from_u64(2));
        let y = convolve(&x, &ir);
        let mut seen = vec![];
        for sig in [&x, &y] {
            let mut m = Matcher::new(rate, &bells).unwrap();
            let mut sc = m.scratch();
            let (chosen, signs) = choose(&mut m, sig, &sought, &mut sc).unwrap();
            for (t, w) in m.bells.iter_mut().zip(&chosen) {
                t.as_mut().unwrap().weighted = *w;
            }
            assert_eq!(
                signs,
                polarities(&m, sig, &sought, &mut sc).unwrap(),
                "chosen {chosen:?}"
            );
            seen.extend(signs);
        }
        assert!(seen.contains(&-1.0) && seen.contains(&1.0), "{seen:?}");
    }

    /// A bell whose plain match a dark tail pulls late by amounts that
    /// differ strike to strike (the weighted match 8-73 ms earlier,
    /// rejecting the plain time) is matched weighted, as tmpl-7's rule
    /// (the same move at over half) did not; one whose matches part late,
    /// or early where the weighted match cannot tell its strike (a muffled
    /// bell), or at a few strikes, is not.
    #[test]
    fn a_bell_whose_plain_match_the_tail_pulls_late_is_matched_weighted() {
        let dark: Vec<(f64, bool)> = [
            -0.058,
            -0.037,
            -0.014,
            -0.073,
            -0.008 - 1e-3,
            -0.02,
            -0.045,
            0.0,
            -0.03,
            0.001,
        ]
        .iter()
        .map(|&d| (d, true))
        .collect();
        assert!(is_weighted(&dark));
        let late: Vec<(f64, bool)> = dark.iter().map(|&(d, r)| (-d, r)).collect();
        assert!(!is_weighted(&late));
        let unsure: Vec<(f64, bool)> = dark.iter().enumerate().map(|(k, &(d, _))| (d, k % 3 != 0)).collect();
        assert!(!is_weighted(&unsure));
        let few: Vec<(f64, bool)> = dark
            .iter()
            .enumerate()
            .map(|(k, &(d, r))| if k < 2 { (d, r) } else { (0.0, r) })
            .collect();
        assert!(!is_weighted(&few));
        // tmpl-7's rule still holds: the same move at over half, late too.
        let same: Vec<(f64, bool)> = (0..10).map(|k| (if k < 6 { 0.02 } else { 0.0 }, true)).collect();
        assert!(is_weighted(&same));
        assert!(!is_weighted(&[]));
    }

    /// The weighted match at the plain match's time read from the
    /// weighted match over the strike's search (speed-4) is the one
    /// matched there alone, to 1e-12, at every strike of three bells in a
    /// dark room.
    #[test]
    fn the_weighted_match_read_at_the_plain_time_is_the_one_matched_there() {
        use crate::tower::{convolve, room_response, Room};
        use rand::SeedableRng;
        let rate = 16_000.0;
        let bells: Vec<_> = [700.0, 1000.0, 1400.0]
            .iter()
            .map(|&f| slow_bell(rate, f, 0.03))
            .collect();
        let mut x = vec![0.0; (20.0 * rate) as usize];
        let mut sought = vec![];
        for k in 0..18 {
            let (b, t) = (k % 3, 0.5 + k as f64);
            let o = (crate::sampled_ring::sample_onset(&bells[b]).unwrap() * rate).round() as usize;
            let i0 = (t * rate).round() as usize;
            for (j, v) in bells[b].samples[o..].iter().enumerate() {
                x[i0 + j] += v;
            }
            sought.push((b, (t - 0.15, t + 0.1)));
        }
        let room = Room::chamber(1.0).with_dark_tail(0.6, 0.0);
        let y = convolve(&x, &room_response(room, rate, &mut rand_pcg::Pcg64::seed_from_u64(1)));
        let mut m = Matcher::new(rate, &bells).unwrap();
        let mut sc = m.scratch();
        let mut read = 0;
        for (b, (from, to)) in sought {
            set(&mut m, b, false);
            let p = best(&m, &y, b, from, to, &mut sc).unwrap().unwrap();
            set(&mut m, b, true);
            best(&m, &y, b, from, to, &mut sc).unwrap().unwrap();
            let near = (p.0 - PRE_S - NEAR_S, p.0 - PRE_S + NEAR_S);
            let Some(v) = read_within(&m, (from, to), near, &sc.out) else {
                continue;
            };
            let alone = best(&m, &y, b, near.0, near.1, &mut sc).unwrap().unwrap().1;
            assert!((v - alone).abs() <= 1e-12 * alone, "{v} against {alone}");
            read += 1;
        }
        assert!(read >= 15, "{read} of 18 read");
    }
}
