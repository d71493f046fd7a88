//! The strike finder's steps put together: bands, onsets, strikes told
//! between bells, timing and double strikes.

use std::cell::OnceCell;

use super::band::{bands, decimate, Band, SharedBand};
use super::heard::{check_options, Heard, HeardDouble, HeardStrike, QuietStrokes, StrikeOptions};
use super::onsets::{hear_bell, BellHearing};
use super::plan::{mean_spectrum, plan_bands};
use super::stats::median;
use super::voice::BellVoice;
use crate::{Signal, SignalError};

/// Find every strike of every bell in `sig`; `voices[0]` is bell 1.
pub fn find_strikes(sig: &Signal, voices: &[BellVoice], opts: &StrikeOptions) -> Result<Heard, SignalError> {
    Ok(hear_strikes(sig, voices, opts)?.with_doubles())
}

/// What the band finder hears in a recording: every strike of every bell,
/// timed, with its double strikes judged only when asked
/// ([`Hearing::double`]). Fitting a second strike after each strike is a
/// fifth of the finder's time, wasted where the doubles are judged
/// otherwise (against each bell's template) or not needed (a bell's
/// lateness learned from the strikes' times).
pub struct Hearing {
    heard: Vec<BellHearing>,
    shared: Vec<Vec<SharedBand>>,
    /// Per bell, per band it is heard in, the other bells (from 0) whose
    /// partials lie in that band (none but for a bell heard in shared bands).
    sharers: Vec<Vec<Vec<usize>>>,
    /// Every bell's strikes as first found (onset s), before timing.
    times: Vec<Vec<f64>>,
    /// Every bell's strikes timed: (onset s, strength).
    timed: Vec<Vec<(f64, f64)>>,
    /// The strikes in time order: (bell from 0, index in `timed`).
    order: Vec<(usize, usize)>,
    warnings: Vec<String>,
    opts: StrikeOptions,
    /// Each bell's double strikes, judged when first asked.
    doubles: Vec<OnceCell<Vec<Option<HeardDouble>>>>,
}

impl Hearing {
    /// The strikes heard, in time order, none judged double.
    pub fn singles(&self) -> Heard {
        Heard {
            strikes: self
                .order
                .iter()
                .map(|&(b, k)| HeardStrike {
                    bell: b + 1,
                    t: self.timed[b][k].0,
                    strength: self.timed[b][k].1,
                    double: None,
                })
                .collect(),
            warnings: self.warnings.clone(),
        }
    }

    /// The double strike of strike `i` of [`Self::singles`], if it is one
    /// (its bell's strikes are all judged at the first ask, each as
    /// [`find_strikes`] judges it).
    pub fn double(&self, i: usize) -> Option<HeardDouble> {
        let &(b, k) = self.order.get(i)?;
        let all = self.doubles[b].get_or_init(|| {
            self.heard[b].doubles(
                &self.timed[b],
                &self.shared[b],
                &self.sharers[b],
                &self.times,
                &self.opts,
            )
        });
        all[k]
    }

    /// The strikes with their double strikes: what [`find_strikes`] hears.
    pub fn with_doubles(&self) -> Heard {
        let mut heard = self.singles();
        for (i, s) in heard.strikes.iter_mut().enumerate() {
            s.double = self.double(i);
        }
        heard
    }
}

/// [`find_strikes`] with the double strikes left to be judged when asked
/// ([`Hearing`]).
pub fn hear_strikes(sig: &Signal, voices: &[BellVoice], opts: &StrikeOptions) -> Result<Hearing, SignalError> {
    check_inputs(sig, voices, opts)?;
    let nyq = 0.45 * sig.rate;
    let fmax = voices
        .iter()
        .flat_map(|v| v.partials.iter().map(|p| p.freq_hz))
        .filter(|f| *f < nyq)
        .fold(0.0, f64::max);
    let low = decimate(sig, fmax);
    let spectrum = mean_spectrum(&low);
    let plan = plan_bands(voices, low.rate, &spectrum);
    // 1. Each bell's bands and onset function, and its candidate strikes.
    let mut shared_bands: Vec<Vec<SharedBand>> = vec![];
    let sharers: Vec<Vec<Vec<usize>>> = plan.iter().map(|p| p.sharers.clone()).collect();
    let heard: Vec<BellHearing> = plan
        .into_iter()
        .map(|p| {
            // The bell's own bands and its shared ones, made in one pass.
            let own = p.bands.len();
            let specs: Vec<_> = p.bands.into_iter().chain(p.shared.iter().map(|s| s.0)).collect();
            let mut made = bands(&low, &specs);
            let shared: Vec<Band> = made.split_off(own);
            shared_bands.push(
                shared
                    .into_iter()
                    .zip(p.shared)
                    .map(|(b, (_, with))| SharedBand::new(b, with, opts))
                    .collect(),
            );
            hear_bell(made, opts)
        })
        .collect();
    drop(low);
    let (heard, again) = without_sharers(heard, &sharers, voices.len(), opts);
    let loudest: Vec<f64> = voices.iter().map(loudest_partial).collect();
    Ok(strikes_of(heard, again, shared_bands, sharers, &loudest, opts))
}

/// The frequency (Hz) of `voice`'s strongest partial (the first of the
/// strongest).
fn loudest_partial(voice: &BellVoice) -> f64 {
    let top = voice.partials.iter().map(|p| p.strength).fold(0.0, f64::max);
    voice
        .partials
        .iter()
        .find(|p| p.strength == top)
        .map_or(f64::NAN, |p| p.freq_hz)
}

/// Each bell heard only in bands it shares (`sharers[b][i]`: the bells
/// whose partials lie in its band `i`) heard again with the strikes of
/// those bells, found in their own bands, taken out of those bands
/// ([`BellHearing::without_others`]), where it is heard as it is in fewer
/// than half as many strikes as its sharers. A sharer heard in shared
/// bands itself times nothing here. Also, per bell, whether it was heard
/// again.
fn without_sharers(
    heard: Vec<BellHearing>,
    sharers: &[Vec<Vec<usize>>],
    bells: usize,
    opts: &StrikeOptions,
) -> (Vec<BellHearing>, Vec<bool>) {
    let mut again = vec![false; heard.len()];
    let leaning: Vec<bool> = sharers.iter().map(|s| s.iter().any(|x| !x.is_empty())).collect();
    if !leaning.contains(&true) {
        return (heard, again);
    }
    let needed = |o: usize| !leaning[o] && sharers.iter().flatten().flatten().any(|&x| x == o);
    let times: Vec<Vec<f64>> = heard
        .iter()
        .enumerate()
        .map(|(o, h)| {
            if needed(o) && !h.bands.is_empty() {
                h.firsts(opts, bells).into_iter().map(|x| x.0).collect()
            } else {
                vec![]
            }
        })
        .collect();
    let heard = heard
        .into_iter()
        .zip(sharers)
        .zip(again.iter_mut())
        .map(|((h, s), again)| {
            if s.iter().all(|x| x.is_empty()) {
                return h;
            }
            // Heard as it is in at least half as many strikes as its
            // sharers (a treble of an eight, its nominal on the tenor's
            // octave): left so. On bench/strikes' seeds 1-4 any share
            // from 0.3 to 1, or every such bell heard again, reads the
            // same to a strike (none heard again: the ten 0.924 -> 0.891
            // within 10 ms); on the held-out 11-12, every one heard again
            // cost the fast and all-together rows 1-3 strikes in 480.
            let mut counts: Vec<usize> = s.iter().flatten().map(|&o| times[o].len()).filter(|&n| n > 0).collect();
            counts.sort_unstable();
            if counts
                .get(counts.len() / 2)
                .is_none_or(|&c| 2 * h.firsts(opts, bells).len() >= c)
            {
                return h;
            }
            let others: Vec<Vec<f64>> = s
                .iter()
                .map(|with| {
                    let mut t: Vec<f64> = with.iter().flat_map(|&o| times[o].iter().copied()).collect();
                    t.sort_by(f64::total_cmp);
                    t
                })
                .collect();
            *again = true;
            h.without_others(&others, opts)
        })
        .collect();
    (heard, again)
}

/// The recording, the bells and the options checked.
fn check_inputs(sig: &Signal, voices: &[BellVoice], opts: &StrikeOptions) -> Result<(), SignalError> {
    sig.validate()?;
    check_options(opts)?;
    if voices.is_empty() {
        return Err(SignalError::Option("no bells to listen for".into()));
    }
    if sig.rate < 4000.0 || sig.rate > 200_000.0 {
        return Err(SignalError::Option(format!(
            "sample rate {} Hz: 4 to 200 kHz",
            sig.rate
        )));
    }
    let nyq = 0.45 * sig.rate;
    for (i, v) in voices.iter().enumerate() {
        let ok = v
            .partials
            .iter()
            .any(|p| p.freq_hz.is_finite() && p.freq_hz > 20.0 && p.freq_hz < nyq);
        if !ok
            || v.partials
                .iter()
                .any(|p| !(p.freq_hz > 0.0 && p.strength > 0.0 && p.strength.is_finite()))
        {
            return Err(SignalError::Option(format!(
                "bell {}: no partial from 20 Hz to {:.0} Hz (0.45 of the sample rate), or a partial not positive",
                i + 1,
                nyq
            )));
        }
    }
    Ok(())
}

/// Steps 2 and 3: the strikes of every bell from its hearing (`heard`,
/// with the bands it shares), timed, in time order; their double strikes
/// judged when asked. `loudest`: each bell's strongest partial (Hz), for
/// the warning where it is not listened for.
fn strikes_of(
    mut heard: Vec<BellHearing>,
    again: Vec<bool>,
    mut shared_bands: Vec<Vec<SharedBand>>,
    sharers: Vec<Vec<Vec<usize>>>,
    loudest: &[f64],
    opts: &StrikeOptions,
) -> Hearing {
    let bells = loudest.len();
    explain_shared(&mut heard, &sharers, &again);
    let mut warnings = vec![];
    // 3. Per bell, the strikes: candidates standing clear of the rest,
    //    timed; then (when asked) each looked at for a second strike, in
    //    its own bands and in the bands it shares where no sharing bell
    //    strikes nearby.
    let firsts: Vec<Vec<(f64, f64)>> = heard
        .iter()
        .enumerate()
        .map(|(b, h)| {
            if h.bands.is_empty() {
                warnings.push(format!(
                    "bell {}: not listened for: the partial it is heard loudest at ({:.0} Hz) does not stand out in the recording as a whole (the bell not rung, far quieter than the others, not at the nominal given, or that partial learned wrong), or each of its partials lies on another bell's",
                    b + 1,
                    loudest.get(b).copied().unwrap_or(f64::NAN)
                ));
                return vec![];
            }
            h.firsts(opts, bells)
        })
        .collect();
    let firsts = in_the_rings_rhythm(&heard, firsts, bells, opts);
    for (b, (h, f)) in heard.iter().zip(&firsts).enumerate() {
        if f.is_empty() && !h.bands.is_empty() {
            warnings.push(format!("bell {}: no strikes heard", b + 1));
        }
    }
    let times: Vec<Vec<f64>> = firsts.iter().map(|f| f.iter().map(|x| x.0).collect()).collect();
    // Doubles are fitted about the start times, each strike free to
    // slide a little first (`second_strike`): about the half-way times
    // (moved by the bell's median lateness) doubles of 52 and 76 ms
    // were fitted 37 and 64 ms late at RT60 1.2 s, the first strike's
    // rise merged with the second's in the long bands.
    let timed: Vec<Vec<(f64, f64)>> = heard
        .iter()
        .zip(firsts)
        .enumerate()
        .map(|(b, (h, found))| h.timed(found, &shared_bands[b], &times))
        .collect();
    // Judging doubles later needs only the bands: the changes and onset
    // functions (a third of the hearing) are let go.
    for h in &mut heard {
        h.changes = vec![];
        h.onset = vec![];
    }
    for sb in shared_bands.iter_mut().flatten() {
        sb.change = vec![];
    }
    let mut order: Vec<(usize, usize)> = timed
        .iter()
        .enumerate()
        .flat_map(|(b, v)| (0..v.len()).map(move |k| (b, k)))
        .collect();
    order.sort_by(|&(a, i), &(b, j)| timed[a][i].0.total_cmp(&timed[b][j].0).then(a.cmp(&b)));
    Hearing {
        doubles: heard.iter().map(|_| OnceCell::new()).collect(),
        heard,
        shared: shared_bands,
        sharers,
        times,
        timed,
        order,
        warnings,
        opts: *opts,
    }
}

/// Each bell listened for and not heard (its bands there, no strike
/// standing clear of the rest) heard again by the ring's rhythm
/// ([`BellHearing::firsts_in_rhythm`]): the typical interval between a
/// bell's strikes, the median over the bells heard in six strikes or
/// more. A chain found so that lies on the other bells' strikes is not
/// taken. On bench/strikes' seeds 1-4 (where this was chosen), within
/// 10 ms: the swing row 0.814 -> 0.908, doublets 0.898 -> 0.992, fast
/// 0.966 -> 0.997, heavy 0.748 -> 0.780 (its precision 0.823 -> 0.777),
/// twelve bells 0.835 -> 0.852; without that test all together's
/// precision fell 0.497 -> 0.486 (bell 7 of seed 1 heard 0.65 s after
/// each strike, a false peak's chain).
fn in_the_rings_rhythm(
    heard: &[BellHearing],
    mut firsts: Vec<Vec<(f64, f64)>>,
    bells: usize,
    opts: &StrikeOptions,
) -> Vec<Vec<(f64, f64)>> {
    let mut gaps: Vec<f64> = firsts
        .iter()
        .filter(|f| f.len() >= 6)
        .filter_map(|f| median(f.windows(2).map(|w| w[1].0 - w[0].0).collect()))
        .collect();
    gaps.sort_by(f64::total_cmp);
    // No bell stood clear: the period from the candidates, and each
    // chain let keep time more loosely (the fast eight's middle minute).
    let unclear = gaps.is_empty();
    let Some(period) = ring_period(heard, &gaps) else {
        return firsts;
    };
    if opts.quiet_strokes == QuietStrokes::ByRhythm {
        at_both_strokes(heard, &mut firsts, bells, period, opts);
    }
    let mut others: Vec<f64> = firsts.iter().flatten().map(|x| x.0).collect();
    others.sort_by(f64::total_cmp);
    let place = period / (bells as f64 + 0.5);
    for (h, f) in heard.iter().zip(firsts.iter_mut()) {
        if f.is_empty() && !h.bands.is_empty() {
            let found = h.firsts_in_rhythm(opts, bells, period, unclear);
            // A chain on other bells' strikes (within a quarter of a
            // place, in most of its strikes) is theirs heard in this
            // bell's bands, or a false peak a whole number of places
            // after each of its own strikes: not taken.
            let near = |t: f64| {
                let k = others.partition_point(|&u| u < t);
                let d = |j: usize| others.get(j).map_or(f64::INFINITY, |&u| (u - t).abs());
                d(k).min(if k > 0 { d(k - 1) } else { f64::INFINITY })
            };
            let on_others = median(found.iter().map(|x| near(x.0)).collect()).is_some_and(|d| d < 0.25 * place);
            if !on_others {
                *f = found;
            }
        }
    }
    firsts
}

/// Each bell heard at one stroke only (its kept strikes two rows apart)
/// with its quieter strokes listened for where the ring's rhythm
/// (`period`, s: a bell's typical interval) says they must be
/// ([`BellHearing::firsts_at_both_strokes`]), none on another bell's
/// strike (`firsts`, each bell's strikes: onset s, strength). Only where
/// asked ([`QuietStrokes::ByRhythm`]: not in the calibration from the
/// recording's own strikes; with templates they are looked for otherwise,
/// [`QuietStrokes::Between`]).
fn at_both_strokes(
    heard: &[BellHearing],
    firsts: &mut [Vec<(f64, f64)>],
    bells: usize,
    period: f64,
    opts: &StrikeOptions,
) {
    let all: Vec<Vec<f64>> = firsts.iter().map(|f| f.iter().map(|x| x.0).collect()).collect();
    for (b, (h, f)) in heard.iter().zip(firsts.iter_mut()).enumerate() {
        if f.len() < 6 {
            continue;
        }
        let mut others: Vec<f64> = all
            .iter()
            .enumerate()
            .filter(|(o, _)| *o != b)
            .flat_map(|x| x.1.iter().copied())
            .collect();
        others.sort_by(f64::total_cmp);
        if let Some(both) = h.firsts_at_both_strokes(opts, bells, period, &others) {
            *f = both;
        }
    }
}

/// How many times the ring's period a bell heard at one stroke only
/// keeps between its strikes (two rows, a handstroke gap in one of them:
/// 2 `bells` + 1 places over `bells` or `bells` + 1), at most and at
/// least, for rings of three to sixteen.
const ONE_STROKE_RATIO: (f64, f64) = (1.7, 2.4);

/// The ring's typical interval between a bell's strikes (s): the median
/// of `gaps` (each clear bell's median interval, sorted), else
/// [`candidates_period`]. Where the clear bells are fewer than half of
/// those heard and their period is about twice the candidates' (within
/// [`ONE_STROKE_RATIO`]), the candidates': a bell heard at one stroke
/// only (issue 43: the other far quieter, or absent) strikes every two
/// rows, and where it alone stood clear, every other bell was heard by
/// its rhythm once every two rows (the tester's six with bell 5 silent at
/// backstroke: in each 55 s window only bell 5 stood clear, and the
/// others lost half their strikes, recall 0.62).
fn ring_period(heard: &[BellHearing], gaps: &[f64]) -> Option<f64> {
    let Some(&p) = gaps.get(gaps.len() / 2) else {
        return candidates_period(heard);
    };
    let listened = heard.iter().filter(|h| !h.bands.is_empty()).count();
    if 2 * gaps.len() >= listened {
        return Some(p);
    }
    let half = candidates_period(heard).filter(|&c| {
        let r = p / c;
        r >= ONE_STROKE_RATIO.0 && r <= ONE_STROKE_RATIO.1
    });
    Some(half.unwrap_or(p))
}

/// The ring's typical interval between a bell's strikes (s) where no
/// bell's strikes stood clear of the rest to give it: the median over the
/// bells of the median interval between a bell's candidates (those
/// [`BellHearing::firsts_in_rhythm`] weighs), from bells with six or more.
/// In fast rings (six bells 150 ms apart, rows under a second) every
/// bell's onset function stands high between its strikes (the others'
/// strikes heard in its bands), so no bell's strikes stand clear: a
/// minute of Plain Bob Minor gave no strike at all. Only where there is
/// no other period: each chain found by it must still keep time
/// ([`BellHearing::firsts_in_rhythm`]).
fn candidates_period(heard: &[BellHearing]) -> Option<f64> {
    let mut gaps: Vec<f64> = heard
        .iter()
        .filter(|h| !h.bands.is_empty())
        .filter_map(|h| {
            let c: Vec<usize> = h.candidates.iter().filter(|c| c.1 >= 0.3).map(|c| c.0).collect();
            if c.len() < 6 {
                return None;
            }
            median(c.windows(2).map(|w| (w[1] - w[0]) as f64 / h.rate).collect())
        })
        .collect();
    gaps.sort_by(f64::total_cmp);
    gaps.get(gaps.len() / 2).copied()
}

/// Step 2: a strike that steps a band two bells share is heard in both; it
/// is the bell whose onset stands higher against its own typical
/// strike. Onsets within 25 ms are one strike unless both stand high:
/// the other bell's candidate is set to 0. A bell heard in bands it
/// shares (`sharers[b][i]`: the bells whose partials lie in its band
/// `i`) hears a sharer's strike there for as long as the band's step
/// rises (its rise, up to 150 ms with 50 ms boxes), its onset
/// function's peak late by up to that much: after a sharer's strike its
/// candidates are weighed against the sharer's over that rise. On the
/// default eight (treble 1400 Hz, the tenor's octave) the tenor's last
/// strike, with no treble strike after it to outweigh it, was heard as a
/// treble strike 50-75 ms after it. A bell heard again without its
/// sharers' strikes (`again`) has had them taken out already.
fn explain_shared(heard: &mut [BellHearing], sharers: &[Vec<Vec<usize>>], again: &[bool]) {
    let mut all: Vec<(f64, usize, usize, f64)> = vec![];
    for (b, h) in heard.iter().enumerate() {
        for (k, c) in h.candidates.iter().enumerate() {
            all.push((c.0 as f64 / h.rate, b, k, c.1));
        }
    }
    all.sort_by(|a, b| a.0.total_cmp(&b.0));
    // Per bell, per other bell: the longest rise (s) of the bands they share.
    let reach: Vec<Vec<f64>> = heard
        .iter()
        .enumerate()
        .map(|(b, h)| {
            let mut r = vec![0.0; heard.len()];
            if again.get(b).copied().unwrap_or(false) {
                return r;
            }
            let with = sharers.get(b).map_or(&[][..], |s| s.as_slice());
            for (band, w) in h.bands.iter().zip(with) {
                for &o in w {
                    if let Some(x) = r.get_mut(o) {
                        *x = f64::max(*x, band.rise as f64 / band.rate);
                    }
                }
            }
            r
        })
        .collect();
    let longest = reach.iter().flatten().fold(0.025, |a: f64, &x| a.max(x));
    let mut explained: Vec<(usize, usize)> = vec![];
    for (i, x) in all.iter().enumerate() {
        let rival = all[..i]
            .iter()
            .rev()
            .take_while(|y| x.0 - y.0 < 0.025)
            .chain(all[i + 1..].iter().take_while(|y| y.0 - x.0 < 0.025))
            .filter(|y| y.1 != x.1)
            .map(|y| y.3)
            .fold(0.0, f64::max);
        // A sharer's strike earlier within the band's rise: weighed
        // harder (a third of it, not 0.6), the bell's own strike may
        // follow a sharer's closely (ten bells, seeds 1-4: at 0.6,
        // 0.973 -> 0.948 of the strikes within 50 ms).
        let sharer = all[..i]
            .iter()
            .rev()
            .take_while(|y| x.0 - y.0 < longest)
            .filter(|y| y.1 != x.1 && x.0 - y.0 < reach[x.1][y.1])
            .map(|y| y.3)
            .fold(0.0, f64::max);
        if (rival > x.3 && x.3 < 0.6 * rival.min(1.0)) || x.3 < 0.3 * sharer.min(1.0) {
            explained.push((x.1, x.2));
        }
    }
    for (b, k) in explained {
        heard[b].candidates[k].1 = 0.0;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A bell whose strongest partial sounds nowhere in the recording is
    /// not listened for, and the warning says so in a ringer's words, at
    /// that partial's frequency, with the bell not rung or its partial
    /// learned wrong among the causes (tester 16's fault 4: it read "its
    /// strongest partial is not in the recording", blaming the recording
    /// for a bell rung at every handstroke).
    #[test]
    fn a_bell_not_listened_for_is_told_why_at_its_loudest_partial() {
        let rate = 8000.0;
        let samples: Vec<f64> = (0..(4.0 * rate) as usize)
            .map(|i| {
                (2.0 * std::f64::consts::PI * 1000.0 * i as f64 / rate).sin() * (-((i % 8000) as f64) / 2000.0).exp()
            })
            .collect();
        let sig = Signal { rate, samples };
        let voice = |f: f64| BellVoice {
            partials: vec![crate::strikes::VoicePartial {
                freq_hz: f,
                strength: 1.0,
                uncertainty: 0.004,
            }],
        };
        let heard = hear_strikes(&sig, &[voice(1000.0), voice(2750.0)], &StrikeOptions::default()).unwrap();
        let told: Vec<&String> = heard.warnings.iter().filter(|w| w.starts_with("bell 2:")).collect();
        assert_eq!(told.len(), 1, "{:?}", heard.warnings);
        for words in ["not listened for", "(2750 Hz)", "the bell not rung", "learned wrong"] {
            assert!(told[0].contains(words), "{words:?} not in {:?}", told[0]);
        }
    }

    /// A bell heard at `candidates` (band sample at 1 kHz, height), with
    /// one band or none.
    fn hearing(candidates: Vec<(usize, f64)>, with_band: bool) -> BellHearing {
        let band = Band {
            rate: 1000.0,
            weight: 1.0,
            box_s: 0.05,
            z: vec![],
            rise: 150,
            scale: 1.0,
        };
        BellHearing {
            bands: if with_band { vec![band] } else { vec![] },
            changes: vec![],
            rate: 1000.0,
            candidates,
            onset: vec![],
            floor: 0.4,
        }
    }

    /// Where no bell's strikes stood clear to give the ring's period, it is
    /// the median over the bells of their candidates' median interval:
    /// weak candidates (under 0.3), bells with fewer than six and bells
    /// with no band left out.
    #[test]
    fn a_fast_rings_period_comes_from_its_bells_candidates() {
        let every =
            |period: usize, from: usize| -> Vec<(usize, f64)> { (0..20).map(|k| (from + k * period, 0.8)).collect() };
        let mut with_weak = every(975, 30);
        with_weak.extend((0..19).map(|k| (500 + k * 975, 0.2)));
        with_weak.sort_by_key(|c| c.0);
        let heard = vec![
            hearing(with_weak.clone(), true),
            hearing(with_weak, true),
            hearing(every(1000, 10), true),
            hearing(every(300, 0)[..5].to_vec(), true),
            hearing(every(100, 0), false),
        ];
        let p = candidates_period(&heard).unwrap();
        assert!((p - 0.975).abs() < 1e-9, "{p}");
        assert_eq!(candidates_period(&heard[3..]), None);
    }

    /// A bell heard at one stroke only (the other absent) strikes every
    /// two rows; where it alone stood clear, the ring's period is the
    /// candidates' (a row), not its two rows: the others, heard by the
    /// ring's rhythm, lost every other strike (the tester's A6_quiet60,
    /// recall within 10 ms 0.62). Where most bells stood clear, or the
    /// candidates do not say half, their period stands.
    #[test]
    fn a_bell_heard_at_one_stroke_alone_does_not_set_the_rings_period_to_two_rows() {
        // Rows of six at 240 ms with a handstroke gap: 1.44 and 1.68 s.
        let rows: Vec<(usize, f64)> = (0..20)
            .map(|k| (30 + 1560 * k - if k % 2 == 1 { 120 } else { 0 }, 0.8))
            .collect();
        let heard: Vec<BellHearing> = (0..5).map(|_| hearing(rows.clone(), true)).collect();
        let p = ring_period(&heard, &[3.12]).unwrap();
        assert!((p - 1.44).abs() < 1e-9, "{p}");
        // Three clear bells of five: the clear bells' period.
        assert_eq!(ring_period(&heard, &[1.56, 3.12, 3.12]), Some(3.12));
        // One clear bell, its period not twice the candidates': its own.
        assert_eq!(ring_period(&heard, &[1.5]), Some(1.5));
        // No clear bell: the candidates'.
        assert_eq!(ring_period(&heard, &[]), candidates_period(&heard));
    }
}
