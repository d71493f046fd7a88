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
//! period or near-harmonic matched a few tens of ms off). So a bell is
//! matched weighted only where, at most of its strikes, its two matches
//! part by the same amount and the weighted match rejects the plain one's
//! time.

use super::lag::{best_match, voters};
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

/// Each bell's choice (treble first): whether its strikes `sought` (bell
/// from 1, and where its template is sought, s, s) in the recording `x`
/// match weighted over [`APART_S`] from as recorded, the weighted match
/// at the plain one's time under [`KEEP`] of its best, and moved within
/// [`SAME_S`] of their median move, at over [`SHARE`] of up to [`VOTES`](super::lag::VOTES)
/// of them. Matched by magnitude (before the polarities are known);
/// leaves every template matched as recorded.
pub(super) fn choose(
    m: &mut Matcher,
    x: &[f64],
    sought: &[(usize, (f64, f64))],
    sc: &mut Scratch,
) -> Result<Vec<bool>, SignalError> {
    let mut chosen = vec![];
    for b in 0..m.bells.len() {
        let (mut apart, mut n) = (vec![], 0usize);
        for (from, to) in voters(sought, b + 1) {
            set(m, b, false);
            let plain = best(m, x, b, from, to, sc)?;
            set(m, b, true);
            let weighted = best(m, x, b, from, to, sc)?;
            let (Some(p), Some(w)) = (plain, weighted) else {
                continue;
            };
            // The weighted match at the plain match's time.
            let at_p = best(m, x, b, p.0 - PRE_S - NEAR_S, p.0 - PRE_S + NEAR_S, sc)?.map_or(0.0, |f| f.1);
            n += 1;
            // The plain match's time, not the weighted's strike, and far
            // from it.
            if (w.0 - p.0).abs() > APART_S && at_p < KEEP * w.1 {
                apart.push(w.0 - p.0);
            }
        }
        set(m, b, false);
        // A room moves a bell's match the same at every strike.
        let mid = if apart.is_empty() { 0.0 } else { crate::median(&apart) };
        let votes = apart.iter().filter(|d| (*d - mid).abs() <= SAME_S).count();
        chosen.push(n > 0 && votes as f64 > SHARE * n as f64);
    }
    Ok(chosen)
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
