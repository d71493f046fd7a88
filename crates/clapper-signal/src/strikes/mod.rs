//! Strikes heard in a recording of a ring (docs/strikes.md): which bell
//! struck when, to the millisecond, and whether its clapper struck twice.
//!
//! Each bell is known by its partials ([`BellVoice`]: from its nominal and
//! a tuned bell's ratios, or from a recording of it struck alone). Every
//! partial becomes a band: the signal moved down by the partial's
//! frequency and smoothed by three boxes of length L, short enough to
//! follow a strike and long enough to put a null on the nearest partial of
//! another bell. A strike adds a complex step to each of its bell's bands,
//! so a bell's onset function is the size of the change in its bands over
//! the step's rise (3L), the bands weighted by how much of each is the
//! bell's own. Peaks of it well above the rest, no closer than a row
//! allows, are strikes; the onset is where the change reaches half its
//! size (the smoothing is symmetric, so that is the start of the sound).
//! Each band's response to one strike of its bell, in this room, is then
//! learned from all the bell's strikes (their median), and a double strike
//! is a second copy of that response within the double-strike window,
//! fitted beside the first: the room's reverberation is in the response,
//! so it no longer passes for a second strike.

mod band;
mod doubles;
mod find;
mod fit;
mod heard;
mod learn;
mod learn_gaps;
mod learn_heard;
mod learn_pick;
mod learn_scale;
mod learn_sure;
mod learn_voices;
mod onsets;
mod plan;
mod plausible;
mod stats;
mod stream;
mod timing;
mod voice;

pub use find::{find_strikes, hear_strikes, Hearing};
pub use heard::{Heard, HeardDouble, HeardStrike, QuietStrokes, StrikeOptions, DEFAULT_DOUBLE_MIN_RATIO};
pub use learn::{learn_nominals, Learned, LearnedBell};
pub use learn_voices::{learn_voices, LearnedVoice, LearnedVoices};
pub use plausible::{
    below_nominal, rising, rising_at, RisePartial, HANDBELL_BELOW, PLAUSIBLE_SHARE, RING_ON_FALL, RING_ON_FROM_S,
    RING_ON_TO_S, RISE_POWER, RISE_SHARE, TOWER_BELOW,
};
pub use stream::{
    find_strikes_streamed, find_strikes_streamed_deferred, find_strikes_streamed_heard, InMemory, RecordingBlocks,
    Window, Windows,
};
pub use voice::{BellVoice, VoicePartial};
#[cfg(test)]
mod learn_real_tests;
