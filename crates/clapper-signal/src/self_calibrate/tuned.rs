//! Whether a bell sounds as a tuned bell is assumed to (docs/strikes.md,
//! "Self-calibration keeps the tuned bells' times heard"): its partials
//! learned a tuned bell's, and heard where a tuned bell's partials hear it.

use crate::strikes::{BellVoice, Heard};

/// A learned partial this near (a fraction of its frequency) one of a
/// tuned bell's is that partial: `clapper synth-ring`'s bells stray up
/// to 15 cents (0.87 %); the recorded bells' lower partials 0.6-6 % (at
/// 1 % d4, heard 62 ms late in a room, was taken for a tuned bell).
pub const AS_ASSUMED: f64 = 0.009;
/// A bell whose partials learned (but the prime, nominal and octave) are
/// this share (by strength) or more a tuned bell's, their strongest among
/// them, is tuned as assumed (recorded d2 had all but its strongest, at
/// 1.483 times its nominal for a tuned bell's 1.5, near a tuned bell's).
pub const TUNED_SHARE: f64 = 0.6;
/// And its partials learned hear its strikes this near where the tuned
/// bell's partials hear them (s, the median).
pub const SAME_S: f64 = 0.003;
/// A strike heard through a tuned bell's partials is paired with one heard
/// through the partials learned this near it (s).
const PAIR_S: f64 = 0.05;

/// The share (by strength) of `voice`'s partials, those near the prime,
/// nominal and octave left out (any bell has them: the unit tests' untuned
/// bells too), that lie within [`AS_ASSUMED`] of a partial of a tuned bell
/// of nominal `nominal_hz`; 0 where the strongest of them does not.
pub(super) fn as_assumed(voice: &BellVoice, nominal_hz: f64) -> f64 {
    let tuned = BellVoice::from_nominal(nominal_hz);
    let near = |f: f64| tuned.partials.iter().any(|p| (f / p.freq_hz - 1.0).abs() <= AS_ASSUMED);
    let any_bells = |f: f64| {
        [0.5, 1.0, 2.0]
            .iter()
            .any(|r| (f / (r * nominal_hz) - 1.0).abs() <= AS_ASSUMED)
    };
    let own: Vec<_> = voice.partials.iter().filter(|p| !any_bells(p.freq_hz)).collect();
    let strongest = own.iter().max_by(|a, b| a.strength.total_cmp(&b.strength));
    if !strongest.is_some_and(|p| near(p.freq_hz)) {
        return 0.0;
    }
    let all: f64 = own.iter().map(|p| p.strength).sum();
    let kept: f64 = own.iter().filter(|p| near(p.freq_hz)).map(|p| p.strength).sum();
    if all > 0.0 {
        kept / all
    } else {
        0.0
    }
}

/// Whether `plain` (the strikes heard through a tuned bell's partials)
/// hears bell `bell`'s clean strikes, heard at `clean` (s) through its
/// partials learned, within [`SAME_S`] of those times (the median over the
/// strikes paired within [`PAIR_S`], of which [`FEWEST`](super::FEWEST) or more).
pub(super) fn heard_alike(plain: &Heard, bell: usize, clean: &[f64]) -> bool {
    let mut after_heard: Vec<f64> = clean
        .iter()
        .filter_map(|&t| {
            plain
                .strikes
                .iter()
                .filter(|s| s.bell == bell && (s.t - t).abs() <= PAIR_S)
                .map(|s| s.t - t)
                .min_by(|a, b| a.abs().total_cmp(&b.abs()))
        })
        .collect();
    if after_heard.len() < super::FEWEST {
        return false;
    }
    after_heard.sort_by(f64::total_cmp);
    after_heard[after_heard.len() / 2].abs() <= SAME_S
}
