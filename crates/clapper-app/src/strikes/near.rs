//! The nominals given, listened for where the recording's bells are heard
//! (nom-14, tester21's fault 2). A nominal given right can still be a poor
//! place to listen: another bell's partial may ring in its band (on a ring
//! of d6-d11, d10's partials at 1091 and 1110 Hz straddle d7's nominal at
//! 1103 Hz, so d7 was heard at d10's strikes and timed 42-86 ms off). The
//! learner ([`clapper_signal::strikes::learn_nominals`]) places each bell
//! where its nominal rises at the onsets; where the timing chosen for the
//! nominals given is not even, the same nominals moved to the learner's
//! nearby ones are tried on the opening window too, and kept only where
//! their strikes come far evener.

use clapper_signal::self_calibrate::{calibrate_heard, SelfCalibration};
use clapper_signal::strikes::StrikeOptions;
use clapper_signal::Signal;

use super::choose::{evenness, AUTO_LEAST_FOUND, AUTO_MARGIN, EVEN_SHARE};
use super::{voices_from_nominals, StrikesReport, Timing, Voice};
use crate::AppError;

/// How far (fraction) a nominal the recording's bells are heard at may
/// lie from the one given and be listened for instead: under a third of a
/// semitone (6 %), so never another bell's note. On tester21's M6 the
/// learner heard d7 1.5 % and d9 1.4 % from their nominals.
pub const NEAR_HEARD: f64 = 0.02;

/// Nominals nearer than this (fraction) to the one given are the same
/// note: within a tower bell's nominal band (0.4 %), about half of it.
const SAME_NOTE: f64 = 0.0015;

/// The nominals given, each moved to the nearest of `heard` (Hz) within
/// [`NEAR_HEARD`] of it; `None` where none moves past `SAME_NOTE` or two
/// would then lie within half a percent (one bell heard for two).
pub fn moved_near(given: &[f64], heard: &[f64]) -> Option<Vec<f64>> {
    let off = |h: f64, g: f64| (h / g - 1.0).abs();
    let near: Vec<f64> = given
        .iter()
        .map(|&g| {
            let best = heard.iter().copied().min_by(|a, b| off(*a, g).total_cmp(&off(*b, g)));
            best.filter(|&h| off(h, g) <= NEAR_HEARD && off(h, g) > SAME_NOTE)
                .unwrap_or(g)
        })
        .collect();
    let moved = near.iter().zip(given).any(|(n, g)| n != g);
    (moved && voices_from_nominals(&near, Voice::Tower).is_ok()).then_some(near)
}

/// The trial of the nominals moved near where they are heard: those
/// nominals, their calibration and its strikes' figures in the window.
pub struct NearTrial {
    /// The nominals listened for (Hz), treble first.
    pub nominals: Vec<f64>,
    /// The calibration learned for them.
    pub calibration: SelfCalibration,
    /// Strikes found in the opening window.
    pub strikes: usize,
    /// Their unevenness (ms; `evenness`), under [`EVEN_SHARE`] of
    /// their median interval.
    pub unevenness_ms: f64,
    /// Their RMS striking error in the window's rows (ms).
    pub rms_ms: Option<f64>,
}

/// On the opening window `head`, the `nominals` given moved to where the
/// learner hears its bells ([`moved_near`]) and timed from the recording:
/// kept (`Some`) only where it finds [`AUTO_LEAST_FOUND`] of the `found`
/// strikes, its unevenness is under [`AUTO_MARGIN`] of `unevenness_ms`
/// (the timing chosen's) and its strikes are even ([`EVEN_SHARE`]). Nothing learned or heard is no trial (`None`).
pub fn near_trial(
    head: &Signal,
    nominals: &[f64],
    opts: &StrikeOptions,
    found: usize,
    unevenness_ms: f64,
) -> Result<Option<NearTrial>, AppError> {
    let Ok(learned) = clapper_signal::strikes::learn_nominals(head, nominals.len()) else {
        return Ok(None);
    };
    // A note the learner guessed from the scale is tried too (M6's d7,
    // whose own band another bell's partials fill): the evenness judges.
    let heard: Vec<f64> = learned.bells.iter().map(|b| b.nominal_hz).collect();
    let Some(near) = moved_near(nominals, &heard) else {
        return Ok(None);
    };
    let Ok((c, hearing)) = calibrate_heard(head, &near, opts) else {
        return Ok(None);
    };
    let r = StrikesReport::timed_singles(head, &c.voices, opts, Timing::Recording(&c), Some(hearing))?;
    let Some((u, g)) = evenness(&r) else {
        return Ok(None);
    };
    Ok(
        kept((found, unevenness_ms), (r.strikes.len(), u, g)).then_some(NearTrial {
            nominals: near,
            calibration: c,
            strikes: r.strikes.len(),
            unevenness_ms: u,
            rms_ms: r.summary.rms_error_ms,
        }),
    )
}

/// Whether the nominals moved are kept: `near` (strikes found,
/// unevenness and median interval, ms) against `given` (strikes plain
/// found, the timing chosen's unevenness, ms).
fn kept(given: (usize, f64), near: (usize, f64, f64)) -> bool {
    let ((found, given_ms), (n, u, g)) = (given, near);
    // Even themselves, not merely evener: the nominals given are left only
    // on plain evidence (tester21's E8: 88 -> 59 ms in 190 ms intervals,
    // still uneven, put a bell 38 ms off that had been right).
    n as f64 >= AUTO_LEAST_FOUND * found as f64 && u < AUTO_MARGIN * given_ms && u < EVEN_SHARE * g
}

impl NearTrial {
    /// Why these nominals were listened for, in words: each bell moved
    /// (Hz, given and heard), and the unevenness either way (`given_ms`).
    pub fn reason(&self, given: &[f64], given_ms: f64) -> String {
        format!(
            "recording, each bell listened for where the recording's bells are placed nearest the nominals given ({}): with the nominals as given, the strikes came unevenly ({given_ms:.1} ms), with these {:.1} ms",
            self.moved(given),
            self.unevenness_ms
        )
    }

    /// The bells moved from the nominals `given`, in words.
    pub fn moved(&self, given: &[f64]) -> String {
        let moved: Vec<String> = (self.nominals.iter().zip(given).enumerate())
            .filter(|(_, (n, g))| n != g)
            .map(|(i, (n, g))| format!("bell {} at {n:.1} Hz (given {g:.1})", i + 1))
            .collect();
        moved.join(", ")
    }

    /// What the report warns of: the bells listened for off the nominals
    /// `given`, and why.
    pub fn warning(&self, given: &[f64]) -> String {
        format!(
            "listened for {}: with the nominals as given the strikes came unevenly timed (a bell heard at another's strikes, or not heard), with these evenly; the bells are those given, each heard a little off its nominal",
            self.moved(given)
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_nominal_heard_near_the_one_given_is_listened_for_there() {
        // tester21's M6: d7 heard 1.5 % low, d9 1.4 % high, the rest near.
        let given = [1237.2, 1103.1, 982.4, 871.5, 817.7, 727.8];
        let heard = [1238.5, 1086.2, 979.1, 883.4, 820.6, 725.9];
        let near = moved_near(&given, &heard).expect("moved");
        assert_eq!(near[1], 1086.2);
        assert_eq!(near[3], 883.4);
        // Within the band (0.1 %): the note given kept.
        assert_eq!(near[0], 1237.2);
        // Over 2 % off (another bell's note, or a partial): not moved.
        assert_eq!(moved_near(&[1103.1, 982.4], &[1070.0, 1010.0]), None);
        // All within the band: nothing to try.
        assert_eq!(moved_near(&[1103.1, 982.4], &[1103.5, 982.0]), None);
    }

    /// tester21's window figures (strikes, unevenness, interval; ms).
    #[test]
    fn only_even_strikes_far_evener_than_the_given_nominals_are_kept() {
        // M6: 97.9 ms as given, 17.7 ms moved, in 160 ms intervals.
        assert!(kept((375, 97.9), (369, 17.7, 160.0)));
        // E8: evener (88.4 -> 59.3 ms) but still uneven in 190 ms.
        assert!(!kept((220, 88.4), (381, 59.3, 190.0)));
        // Even, but not far evener than the timing chosen.
        assert!(!kept((349, 34.9), (352, 24.6, 160.0)));
        // Even, far evener, but strikes lost.
        assert!(!kept((375, 97.9), (250, 17.7, 160.0)));
    }

    #[test]
    fn one_note_heard_for_two_bells_is_not_tried() {
        // Both given bells would move onto 1000 Hz.
        assert_eq!(moved_near(&[1010.0, 990.0], &[1000.0]), None);
    }
}
