//! Every bell heard through the voices the calibration listens with
//! (issue 43, docs/strikes.md, "`--nominals` on methods and big rings
//! (selfcal-4)"). The band finder can hear no strike at all of a bell
//! whose partials, learned or assumed, lie on other bells' (its onset
//! function then stands as high between its strikes as at them): on an
//! independent tester's rings of recorded bells in methods, through the
//! learned voices one to three bells of six to twelve were never heard in
//! the opening minute (Plain Bob Major bell 6, Plain Bob Minor bells
//! 1-3), and a bell never heard learns no template and is timed as the
//! ring's rhythm fills it, tens of ms off. Through a tuned bell's assumed
//! partials other bells are lost instead (the assumed prime of one bell
//! on another's nominal). So a bell heard through its learned voice at
//! under half the strikes of the typical bell is heard at its nominal
//! alone ([`nominal_alone`]; and the reverse), and that set is kept where
//! it hears more bells.

use super::Hearing;
use crate::strikes::{hear_strikes, BellVoice, LearnedVoices, StrikeOptions};
use crate::{Signal, SignalError};

/// A bell heard at under this share of the typical bell's strikes is
/// unheard: its voice is swapped.
const HEARD_SHARE: f64 = 0.5;
/// Rounds of swapping (each hears the window once more).
const ROUNDS: usize = 2;

/// What the calibration heard its recording through ([`hear_through`]).
pub(super) struct HeardThrough {
    /// Each bell's voice, treble first.
    pub(super) voices: Vec<BellVoice>,
    /// The recording heard through them.
    pub(super) hearing: Hearing,
    /// Per bell, whether its learned voice is kept.
    pub(super) kept: Vec<bool>,
    /// A warning for each learned voice left, in words.
    pub(super) warnings: Vec<String>,
}

/// `sig` heard through the voices `learned` from it (the nominals
/// `nominals_hz`, treble first), a bell they never hear at its nominal
/// alone ([`hear_every_bell`]).
pub(super) fn hear_through(
    sig: &Signal,
    nominals_hz: &[f64],
    learned: &LearnedVoices,
    opts: &StrikeOptions,
) -> Result<HeardThrough, SignalError> {
    let voices: Vec<BellVoice> = learned.bells.iter().map(|b| b.voice.clone()).collect();
    let hearing = hear_strikes(sig, &voices, opts)?;
    let assumed: Vec<BellVoice> = nominals_hz.iter().map(|&f| nominal_alone(f)).collect();
    let (voices, hearing, kept) = hear_every_bell(sig, &voices, &assumed, hearing, opts)?;
    let warnings = (0..kept.len())
        .filter(|&k| !kept[k] && learned.bells.get(k).is_some_and(|b| b.learned))
        .map(|k| {
            format!(
                "bell {}: never heard through the partials learned for it: heard at its nominal alone",
                k + 1
            )
        })
        .collect();
    Ok(HeardThrough {
        voices,
        hearing,
        kept,
        warnings,
    })
}

/// The voices heard through, and the hearing, after swapping the voices
/// of bells unheard through `learned` (treble first) for `assumed` (each
/// bell's [`nominal_alone`]; and back), where a set hears more bells; `hearing` is `sig` heard through
/// `learned`. Also, per bell, whether its learned voice is kept.
pub(super) fn hear_every_bell(
    sig: &Signal,
    learned: &[BellVoice],
    assumed: &[BellVoice],
    hearing: Hearing,
    opts: &StrikeOptions,
) -> Result<(Vec<BellVoice>, Hearing, Vec<bool>), SignalError> {
    let mut uses_learned = vec![true; learned.len()];
    let mut best = (heard_bells(&hearing, learned.len()), hearing, uses_learned.clone());
    for _ in 0..ROUNDS {
        let unheard: Vec<usize> = (0..learned.len()).filter(|&k| !best.0[k]).collect();
        if unheard.is_empty() {
            break;
        }
        for &k in &unheard {
            uses_learned[k] = !best.2[k];
        }
        let voices = chosen(learned, assumed, &uses_learned);
        let h = hear_strikes(sig, &voices, opts)?;
        let heard = heard_bells(&h, learned.len());
        let count = |v: &[bool]| v.iter().filter(|&&x| x).count();
        if count(&heard) <= count(&best.0) {
            break;
        }
        best = (heard, h, uses_learned.clone());
    }
    let (_, hearing, uses) = best;
    Ok((chosen(learned, assumed, &uses), hearing, uses))
}

/// A bell heard at its nominal alone (`nominal_hz`, within 0.4 %, as a
/// tuned bell's assumed nominal): a tuned bell's other assumed partials
/// lie in other bells' bands, and given them the bell moved the others'
/// hearing (on the tester's six at 0.15 s, bells 3 and 6 heard 30 ms
/// further off).
pub(super) fn nominal_alone(nominal_hz: f64) -> BellVoice {
    BellVoice {
        partials: vec![crate::strikes::VoicePartial {
            freq_hz: nominal_hz,
            strength: 1.0,
            uncertainty: 0.004,
        }],
    }
}

/// Each bell's voice: learned where `uses_learned`, else assumed.
fn chosen(learned: &[BellVoice], assumed: &[BellVoice], uses_learned: &[bool]) -> Vec<BellVoice> {
    learned
        .iter()
        .zip(assumed)
        .zip(uses_learned)
        .map(|((l, a), &u)| if u { l.clone() } else { a.clone() })
        .collect()
}

/// Per bell, whether `hearing` hears it at [`HEARD_SHARE`] or more of the
/// typical bell's strikes (the median over the bells).
fn heard_bells(hearing: &Hearing, bells: usize) -> Vec<bool> {
    let heard = hearing.singles();
    let counts: Vec<usize> = (1..=bells)
        .map(|b| heard.strikes.iter().filter(|s| s.bell == b).count())
        .collect();
    let mut sorted = counts.clone();
    sorted.sort_unstable();
    let typical = sorted.get(sorted.len() / 2).copied().unwrap_or(0) as f64;
    counts.iter().map(|&n| n as f64 >= HEARD_SHARE * typical).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampled_ring::{sampled_ring, UntunedStrike};
    use crate::strikes::VoicePartial;
    use crate::tower::{major_scale, Method, TowerSpec};

    /// Four untuned bells in plain hunt; bell 2's learned voice a lone
    /// partial where no bell sounds (as a voice learned from another
    /// bell's partials, which the band finder never hears it in): the
    /// learned voices hear no strike of bell 2; it is given its nominal
    /// alone, and heard at nearly all its strikes.
    #[test]
    fn a_bell_its_learned_voice_never_hears_is_heard_at_its_nominal() {
        let rate = 16_000.0;
        let bells = major_scale(4, 1000.0).unwrap();
        let nominals: Vec<f64> = bells.iter().map(|b| b.nominal_hz).collect();
        let strikes: Vec<Signal> = nominals
            .iter()
            .enumerate()
            .map(|(i, &f)| UntunedStrike::with_noisy_blow(f, 0.02 + 0.003 * i as f64).signal(rate))
            .collect();
        let spec = TowerSpec {
            rate,
            rows: 20,
            interval: 2.0 / 5.0,
            method: Method::PlainHunt,
            snr_db: Some(25.0),
            ..TowerSpec::new(bells)
        };
        let (sig, truth) = sampled_ring(&spec, &strikes).unwrap();
        let assumed: Vec<BellVoice> = nominals.iter().map(|&f| nominal_alone(f)).collect();
        let mut learned: Vec<BellVoice> = nominals.iter().map(|&f| BellVoice::from_nominal(f)).collect();
        learned[1] = BellVoice {
            partials: vec![VoicePartial {
                freq_hz: 3333.0,
                strength: 1.0,
                uncertainty: 0.004,
            }],
        };
        let opts = StrikeOptions::default();
        let count = |h: &Hearing| h.singles().strikes.iter().filter(|s| s.bell == 2).count();
        let through_learned = hear_strikes(&sig, &learned, &opts).unwrap();
        let before = count(&through_learned);
        let (voices, hearing, uses) = hear_every_bell(&sig, &learned, &assumed, through_learned, &opts).unwrap();
        let of = truth.iter().filter(|s| s.bell == 2).count();
        assert!(
            before * 4 < of,
            "bell 2 heard through the learned voices at {before} of {of}"
        );
        assert_eq!(uses, vec![true, false, true, true]);
        assert_eq!(voices[1], assumed[1]);
        let after = count(&hearing);
        assert!(after * 10 >= of * 9, "bell 2 heard at {after} of {of}");
    }
}
