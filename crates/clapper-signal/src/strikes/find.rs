//! The strike finder's steps put together: bands, onsets, strikes told
//! between bells, timing and double strikes.

use super::band::{band, decimate, Band, SharedBand};
use super::heard::{check_options, Heard, HeardStrike, StrikeOptions};
use super::onsets::{hear_bell, BellHearing};
use super::plan::{mean_spectrum, plan_bands};
use super::voice::BellVoice;
use crate::{Signal, SignalError};

/// Find every strike of every bell in `sig`; `voices[0]` is bell 1.
pub fn find_strikes(sig: &Signal, voices: &[BellVoice], opts: &StrikeOptions) -> Result<Heard, SignalError> {
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
    let mut heard: Vec<BellHearing> = plan
        .into_iter()
        .map(|p| {
            let bands: Vec<Band> = p.bands.into_iter().map(|(f, w, l)| band(&low, f, w, l)).collect();
            shared_bands.push(
                p.shared
                    .into_iter()
                    .map(|((f, w, l), with)| SharedBand::new(band(&low, f, w, l), with, opts))
                    .collect(),
            );
            hear_bell(bands, opts)
        })
        .collect();
    drop(low);
    Ok(strikes_of(&mut heard, &shared_bands, voices.len(), opts))
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
/// with the bands it shares), in time order.
fn strikes_of(
    heard: &mut [BellHearing],
    shared_bands: &[Vec<SharedBand>],
    bells: usize,
    opts: &StrikeOptions,
) -> Heard {
    explain_shared(heard);
    let mut warnings = vec![];
    // 3. Per bell, the strikes: candidates standing clear of the rest,
    //    timed; then each looked at for a second strike, in its own bands
    //    and in the bands it shares where no sharing bell strikes nearby.
    let firsts: Vec<Vec<(f64, f64)>> = heard
        .iter()
        .enumerate()
        .map(|(b, h)| {
            if h.bands.is_empty() {
                warnings.push(format!(
                    "bell {}: its strongest partial is not in the recording, or none of its partials can be told from other bells'",
                    b + 1
                ));
                return vec![];
            }
            let found = h.firsts(opts, bells);
            if found.is_empty() {
                warnings.push(format!("bell {}: no strikes heard", b + 1));
            }
            found
        })
        .collect();
    let times: Vec<Vec<f64>> = firsts.iter().map(|f| f.iter().map(|x| x.0).collect()).collect();
    let mut strikes = vec![];
    for (b, (h, found)) in heard.iter().zip(firsts).enumerate() {
        // Doubles are fitted about the start times, each strike free to
        // slide a little first (`second_strike`): about the half-way times
        // (moved by the bell's median lateness) doubles of 52 and 76 ms
        // were fitted 37 and 64 ms late at RT60 1.2 s, the first strike's
        // rise merged with the second's in the long bands.
        let timed = h.timed(found, &shared_bands[b], &times);
        let doubles = h.doubles(&timed, &shared_bands[b], &times, opts);
        strikes.extend(
            timed
                .into_iter()
                .zip(doubles)
                .map(|((t, strength), double)| HeardStrike {
                    bell: b + 1,
                    t,
                    strength,
                    double,
                }),
        );
    }
    strikes.sort_by(|a, b| a.t.total_cmp(&b.t).then(a.bell.cmp(&b.bell)));
    Heard { strikes, warnings }
}

/// Step 2: a strike that steps a band two bells share is heard in both; it
/// is the bell whose onset stands higher against its own typical
/// strike. Onsets within 25 ms are one strike unless both stand high:
/// the other bell's candidate is set to 0.
fn explain_shared(heard: &mut [BellHearing]) {
    let mut all: Vec<(f64, usize, usize, f64)> = vec![];
    for (b, h) in heard.iter().enumerate() {
        for (k, c) in h.candidates.iter().enumerate() {
            all.push((c.0 as f64 / h.rate, b, k, c.1));
        }
    }
    all.sort_by(|a, b| a.0.total_cmp(&b.0));
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
        if rival > x.3 && x.3 < 0.6 * rival.min(1.0) {
            explained.push((x.1, x.2));
        }
    }
    for (b, k) in explained {
        heard[b].candidates[k].1 = 0.0;
    }
}
