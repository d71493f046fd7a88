//! A ring timed from the recording's own strikes, the nominals given
//! (issue 43, `clapper strikes --nominals`; docs/strikes.md, "`--nominals`
//! timed from the recording's own strikes").
//!
//! 1. Each bell's partials are learned from the recording
//!    ([`learn_voices`]), and the strikes heard with them; a bell they
//!    never hear is heard at its nominal alone (`heard_bells`).
//! 2. Each bell's template is learned from its clean strikes (no other
//!    bell's strike heard within [`CLEAR_S`], no double strike): the
//!    recording about each, lined up on the first by cross-correlation,
//!    averaged, and lined up again on the average. What the strikes share
//!    is the bell; the rest of the ring and the noise differ from strike to
//!    strike and average away; but in rounds a bell always follows the same
//!    bell at nearly the same interval, whose ringing would stay in its
//!    average, under its start. So every bell's strike is first fitted
//!    jointly (`Joint`: the recording as the sum of each bell's strike
//!    placed at its strikes, by least squares), and each bell's template
//!    learned from the recording with the other bells' fitted strikes
//!    taken out. The start of the bell's sound is where the
//!    strikes start to agree: the first of the millisecond blocks before
//!    the average's loudest whose energy stands `START` times or more
//!    above what the strikes' spread leaves in an average of so many
//!    (from there on to the loudest, with at most `GAPS` blocks under).
//!    Where that finds none, or one further back than a bell is ever heard
//!    late (in a room the blow's jump is under the reverberant tail of the
//!    bells before), the start is the average's greatest step up in
//!    broadband energy once whitened against what rings through all the
//!    strikes (every bell's partials pressed down, the blow left).
//! 3. Every strike is lined up on its bell's average as the clean ones
//!    were (on the part from `CORE_S` before its time heard: in rounds
//!    the part before belongs to the bell struck just before), the other
//!    bells' fitted strikes taken out of it first, and its
//!    start is the average's ([`SelfCalibration::retime_each`]); the
//!    bell's lateness is how long after that start the band finder heard
//!    the clean strikes (their median).

mod heard_bells;
mod sharp;

use crate::strikes::{learn_voices, BellVoice, Heard, HeardStrike, Hearing, StrikeOptions};
use crate::{Signal, SignalError};

/// A strike is clean if no other bell's strike is heard this near it (s).
pub const CLEAR_S: f64 = 0.1;
/// The recording taken before a strike's time heard, to learn from (s):
/// the band finder heard the recorded tower bells up to 85 ms late.
const BEFORE_S: f64 = 0.25;
/// And after it (s).
const AFTER_S: f64 = 0.3;
/// The reference matched in lining strikes up: from this long before the
/// time heard to its end (s).
const CORE_S: f64 = 0.02;
/// How far a strike may be moved to line it up (s).
const SHIFT_S: f64 = 0.06;
/// The block the start is looked for in (s).
const BLOCK_S: f64 = 0.0005;
/// A block's energy in the average this many times what the strikes'
/// spread leaves there is the bell's.
const START: f64 = 4.0;
/// From a block over `START`, the start is moved back over blocks above
/// this (the strikes' spread alone gives 1).
const ABOVE: f64 = 1.3;
/// Blocks under `START` allowed between the start and the loudest.
const GAPS: usize = 6;
/// The band finder heard the recorded tower bells up to 85 ms late (more
/// in a room: in tester 14's r8b, RT60 1.2 s, its treble 153 ms, bells 2
/// and 6 127 and 143 ms): a start where the strikes agree found further
/// back than this before the time heard is another sound's (s). At 0.15
/// the treble's agreement was refused and it was started 118 ms late.
const LATEST_S: f64 = 0.2;
/// The same for a start found by the whitened average's step, a weaker
/// sign (s).
const LATEST_STEP_S: f64 = 0.1;
/// Where lining up moves one bell's strikes about more than this (s, the
/// median absolute deviation; the band finder hears them within 0.3-2 ms
/// of one another), they are lined up again...
const RELINE_SPREAD_S: f64 = 0.003;
/// ...within this of their times heard (s).
const RELINE_S: f64 = 0.0025;
/// Where the strikes were lined up in scattered steps, an agreement this
/// near their time heard (s) is their lining up's, not the bell's (d4 of the
/// recorded rings, its strikes heard 45-60 ms late, started 0-4 ms before;
/// at 10 ms the tests' untuned bell 4 in rounds, rightly agreeing 9 ms
/// before, was started 69 ms early).
const AGREE_NEAR_S: f64 = 0.005;
/// The whitened average's step is moved back over blocks standing this
/// much above its level before (dB, summed: a change point)...
const ABOVE_DB: f64 = 1.5;
/// ...that level the median over 20 ms ending this long before the step (s)...
const LEVEL_BEFORE_S: f64 = 0.03;
/// ...by at most this (s).
const WALK_S: f64 = 0.03;
/// Where neither the whitened average's step of [`STEP`] nor the strikes'
/// agreement shows a start, a step of this many times is taken (in a room
/// at 15 dB the blow raised the whitened average by 2-3 dB).
const WEAK_STEP: f64 = 1.6;
/// The strikes' agreement may start late under the other bells' ringing:
/// a whitened step up to this much before it is the start (s).
const EARLIER_S: f64 = 0.015;
/// Where the whitened average's step lies further than this after the
/// strikes' agreement, and is [`CLEAR_STEP`] times or more, the step is
/// the start (s).
const DISAGREE_S: f64 = 0.0085;
/// A step that clear.
const CLEAR_STEP: f64 = 3.0;
/// The whitening's spectrum is smoothed over this much either side (Hz).
const SMOOTH_HZ: f64 = 11.0;
/// The whitening raises no band by more than this under the strikes'
/// strongest (a power ratio, 70 dB): a band the recording holds next to
/// nothing of (above 16 kHz after MP3 at 64 kbit/s, 80 dB under) would
/// otherwise be raised to the level of the rest, and the codec's frames
/// in it stood out of the average as a step (tester 14's r6 bell 3 was
/// started 35 ms early; at 1e-12, 1e-9 still so).
const WHITEN_RANGE: f64 = 1e-7;
/// The whitened average's energy must step up this many times at the start.
const STEP: f64 = 2.2;
/// The start's step is measured over this long after it (s)...
const LOUD_S: f64 = 0.0015;
/// ...against this long before (s).
const QUIET_S: f64 = 0.004;
/// Silence put before a template's sound (s): its start is then where
/// [`crate::sampled_ring::sample_onset`] finds it.
const LEAD_S: f64 = 0.04;
/// Fewest clean strikes a template is learned from.
const FEWEST: usize = 4;

/// One bell's calibration.
#[derive(Clone, Debug, PartialEq)]
pub struct BellCalibration {
    /// Bell, counting from 1.
    pub bell: usize,
    /// Whether its partials were learned from the recording (else assumed
    /// from a tuned bell's ratios).
    pub partials_learned: bool,
    /// How long after the start of its sound the band finder heard its
    /// clean strikes (s, their median); none without a template.
    pub lateness_s: Option<f64>,
    /// The spread of that lateness (s, median absolute deviation).
    pub spread_s: f64,
    /// Clean strikes its template was learned from (0: none learned).
    pub strikes: usize,
}

/// The ring's calibration from the recording itself.
#[derive(Clone, Debug, PartialEq)]
pub struct SelfCalibration {
    /// Each bell's voice (partials), treble first.
    pub voices: Vec<BellVoice>,
    /// Each bell's template: its sound from `LEAD_S` of silence on, at the
    /// recording's rate; a bell without one has a template too short to
    /// match (its strikes keep their times heard).
    pub templates: Vec<Signal>,
    /// Treble first.
    pub bells: Vec<BellCalibration>,
    /// What could not be learned, in words.
    pub warnings: Vec<String>,
    /// Each bell's average strike as lined up (from [`BEFORE_S`] before
    /// its time heard to [`AFTER_S`] after) and the sample its sound
    /// starts at, where learned.
    averages: Vec<Option<Average>>,
    /// Each bell's jointly fitted strike (kernel) and where it lies
    /// against a strike's time heard, where fitted: every strike is lined
    /// up with the other bells' fitted strikes taken out.
    kernels: Vec<Option<Kernel>>,
}

/// One bell's jointly fitted strike ([`Joint`]): its samples, the first
/// `offset` samples before a strike's time heard.
#[derive(Clone, Debug, PartialEq)]
struct Kernel {
    samples: Vec<f64>,
    offset: usize,
}

/// One bell's average strike as lined up (from [`BEFORE_S`] before its
/// time heard to [`AFTER_S`] after), the sample its sound starts at, and
/// how far a strike may be moved to line it up on it (samples).
#[derive(Clone, Debug, PartialEq)]
struct Average {
    samples: Vec<f64>,
    start: usize,
    reach: usize,
    /// Whether its start is a sharp blow ([`sharp::sharp_start`]): its
    /// strikes are then lined up within [`sharp::SHARP_REACH_S`].
    sharp: bool,
}

impl SelfCalibration {
    /// Each bell's lateness where its template was learned, for
    /// [`crate::template_timing::retime_each`].
    pub fn lateness(&self) -> Vec<Option<f64>> {
        self.bells.iter().map(|b| b.lateness_s).collect()
    }

    /// Time each strike of `heard` (times from the start of `sig`, as the
    /// band finder heard them through [`SelfCalibration::voices`]) again:
    /// lined up on its bell's average strike as the clean strikes were,
    /// within `SHIFT_S` of its time heard, its start is the average's.
    /// In place (the strikes then out of time order); how far each moved
    /// (s; none where its bell has no average or the recording ends).
    pub fn retime_each(&self, sig: &Signal, heard: &mut Heard) -> Vec<Option<f64>> {
        let rate = sig.rate;
        let (before, after) = ((BEFORE_S * rate).round() as usize, (AFTER_S * rate).round() as usize);
        let shift = (SHIFT_S * rate).round() as usize;
        let n = sig.samples.len();
        // Every strike's fitted sound placed at its time heard: what the
        // other bells leave under a strike, taken out before lining it up.
        let origin = |s: &HeardStrike| {
            let k = self.kernels.get(s.bell - 1)?.as_ref()?;
            let o = ((s.t * rate).round() as usize).checked_sub(k.offset)?;
            (o + k.samples.len() <= n).then_some((o, &k.samples))
        };
        let mut model = vec![];
        if self.kernels.iter().any(Option::is_some) {
            model = vec![0.0; n];
            for (o, h) in heard.strikes.iter().filter_map(origin) {
                model[o..o + h.len()].iter_mut().zip(h).for_each(|(m, v)| *m += v);
            }
        }
        heard
            .strikes
            .iter_mut()
            .map(|s| {
                let a = self.averages.get(s.bell - 1)?.as_ref()?;
                let (avg, start) = (&a.samples, a.start);
                let at = (s.t * rate).round() as usize;
                let from = at.checked_sub(before + shift)?;
                let end = from + before + after + 2 * shift;
                if end > n || avg.len() != before + after {
                    return None;
                }
                let mut x = sig.samples[from..end].to_vec();
                if let Some((o, h)) = origin(s) {
                    // The recording less every fitted strike but this one.
                    for (j, v) in x.iter_mut().enumerate() {
                        let i = from + j;
                        let own = if i >= o && i < o + h.len() { h[i - o] } else { 0.0 };
                        *v -= model[i] - own;
                    }
                }
                let reach = if a.sharp {
                    a.reach.min(sharp::reach(rate))
                } else {
                    a.reach
                };
                let lag = best_lag(&x, avg, shift, before, rate, reach);
                let t = (from + lag + start) as f64 / rate;
                let moved = t - s.t;
                s.t = t;
                Some(moved)
            })
            .collect()
    }
}

/// Learn each bell's partials and template from the recording `sig`, the
/// nominals given (`nominals_hz[0]` the treble's).
pub fn calibrate(sig: &Signal, nominals_hz: &[f64], opts: &StrikeOptions) -> Result<SelfCalibration, SignalError> {
    calibrate_heard(sig, nominals_hz, opts).map(|(c, _)| c)
}

/// [`calibrate`], with what the band finder heard in `sig` through the
/// calibration's voices (its doubles judged): what
/// [`hear_strikes`](crate::strikes::hear_strikes)`(sig, &calibration.voices, opts)` hears, handed on so
/// that a caller hearing `sig` so again need not.
pub fn calibrate_heard(
    sig: &Signal,
    nominals_hz: &[f64],
    opts: &StrikeOptions,
) -> Result<(SelfCalibration, Hearing), SignalError> {
    let learned = learn_voices(sig, nominals_hz)?;
    // A bell its learned voice never hears is heard at its nominal alone.
    let through = heard_bells::hear_through(sig, nominals_hz, &learned, opts)?;
    let (voices, hearing, kept) = (through.voices, through.hearing, through.kept);
    let heard = hearing.with_doubles();
    let mut warnings = [learned.warnings, through.warnings].concat();
    let mut templates = vec![];
    let mut bells = vec![];
    let mut averages = vec![];
    let cleans: Vec<Vec<f64>> = (1..=learned.bells.len())
        .map(|bell| clean_strikes(&heard, bell, sig))
        .collect();
    let joint = Joint::estimate(sig, &heard, &cleans);
    for (k, lv) in learned.bells.iter().enumerate() {
        let bell = k + 1;
        let clean = &cleans[k];
        let t = if clean.len() >= FEWEST {
            match joint.as_ref().and_then(|j| j.others_out(sig, bell)) {
                Some(own) => template_of(&own, clean),
                None => template_of(sig, clean),
            }
        } else {
            None
        };
        match t {
            Some(t) => {
                bells.push(BellCalibration {
                    bell,
                    partials_learned: lv.learned && kept[k],
                    lateness_s: Some(t.lateness_s),
                    spread_s: t.spread_s,
                    strikes: clean.len(),
                });
                templates.push(t.template);
                averages.push(Some(t.average));
            }
            None => {
                warnings.push(format!(
                    "bell {bell}: no template learned from the recording ({} clean strike(s) heard, no start of its sound found): its strikes are timed as heard",
                    clean.len()
                ));
                bells.push(BellCalibration {
                    bell,
                    partials_learned: lv.learned && kept[k],
                    lateness_s: None,
                    spread_s: 0.0,
                    strikes: 0,
                });
                templates.push(no_template(sig.rate));
                averages.push(None);
            }
        }
    }
    let kernels = match &joint {
        Some(j) => (0..bells.len())
            .map(|k| {
                averages[k].as_ref()?;
                Some(Kernel {
                    samples: j.kernels[k].clone()?,
                    offset: j.offset[k],
                })
            })
            .collect(),
        None => vec![None; bells.len()],
    };
    let calibration = SelfCalibration {
        voices,
        templates,
        bells,
        warnings,
        averages,
        kernels,
    };
    Ok((calibration, hearing))
}

/// Each bell's strike estimated jointly: the recording taken as the sum of
/// every bell's strike (a kernel from [`BEFORE_S`] before its time heard
/// to [`JOINT_AFTER_S`] after) placed at each of its strikes, fitted by
/// least squares (block coordinate descent over the bells). In rounds a
/// bell always follows the same bell at nearly the same interval, so in
/// its plain average that bell's ringing does not average away: it lies
/// under the bell's own start as a fixed feature. Fitted jointly, each
/// bell's kernel holds its own sound only, and the recording with the
/// other bells' fitted strikes taken out is what its start is sought in.
struct Joint {
    /// Each bell's kernel (none where it has too few clean strikes).
    kernels: Vec<Option<Vec<f64>>>,
    /// Where each bell's kernels are placed (samples, the kernel's first).
    at: Vec<Vec<usize>>,
    /// The sum of every placed kernel.
    model: Vec<f64>,
    /// How far before a strike's time heard its bell's kernel starts, a
    /// strike not clean placed so (samples, by the median lag).
    offset: Vec<usize>,
}

/// The joint fit's kernels run this long after a strike's time heard (s):
/// in rounds of eight the bell two places before rings on under a bell's
/// start from some 450 ms after its own.
const JOINT_AFTER_S: f64 = 1.0;
/// Sweeps over the bells in the joint fit.
const SWEEPS: usize = 4;

impl Joint {
    /// The joint fit of the strikes `heard` in `sig`, each bell's kernel
    /// learned from its clean strikes `cleans[bell - 1]` (times heard, s)
    /// lined up as [`line_up`] lines them; a strike not clean is placed at
    /// its time heard moved by its bell's median lag. None if no bell has
    /// [`FEWEST`] clean strikes.
    fn estimate(sig: &Signal, heard: &Heard, cleans: &[Vec<f64>]) -> Option<Joint> {
        let rate = sig.rate;
        let (before, after) = ((BEFORE_S * rate).round() as usize, (AFTER_S * rate).round() as usize);
        let shift = (SHIFT_S * rate).round() as usize;
        let len = before + (JOINT_AFTER_S * rate).round() as usize;
        let n = sig.samples.len();
        let mut at = vec![vec![]; cleans.len()];
        let mut offset = vec![0; cleans.len()];
        let mut clean_at = vec![vec![]; cleans.len()];
        for (k, times) in cleans.iter().enumerate() {
            if times.len() < FEWEST {
                continue;
            }
            let starts: Vec<usize> = times
                .iter()
                .map(|t| (t * rate).round() as usize - before - shift)
                .collect();
            let (_, lags) = line_up(sig, &starts, before, after)?;
            let mut sorted = lags.clone();
            sorted.sort_unstable();
            let median = sorted[sorted.len() / 2];
            offset[k] = (before + shift).saturating_sub(median);
            clean_at[k] = starts
                .iter()
                .zip(&lags)
                .map(|(&s, &l)| s + l)
                .filter(|&o| o + len <= n)
                .collect();
            at[k] = heard
                .strikes
                .iter()
                .filter(|s| s.bell == k + 1)
                .filter_map(|s| {
                    // A clean strike where it was lined up, another by the median lag.
                    let o = match times.iter().position(|&t| t == s.t) {
                        Some(i) => starts[i] + lags[i],
                        None => ((s.t * rate).round() as usize).checked_sub(before + shift)? + median,
                    };
                    (o + len <= n).then_some(o)
                })
                .collect();
        }
        if clean_at.iter().all(|c| c.len() < FEWEST) {
            return None;
        }
        let mut model = vec![0.0; n];
        let mut kernels: Vec<Option<Vec<f64>>> = vec![None; cleans.len()];
        for _ in 0..SWEEPS {
            for k in 0..cleans.len() {
                if clean_at[k].len() < FEWEST {
                    continue;
                }
                if let Some(h) = &kernels[k] {
                    for &o in &at[k] {
                        model[o..o + len].iter_mut().zip(h).for_each(|(m, v)| *m -= v);
                    }
                }
                let mut h = vec![0.0; len];
                for &o in &clean_at[k] {
                    for ((hv, x), m) in h.iter_mut().zip(&sig.samples[o..o + len]).zip(&model[o..o + len]) {
                        *hv += x - m;
                    }
                }
                let c = clean_at[k].len() as f64;
                h.iter_mut().for_each(|v| *v /= c);
                for &o in &at[k] {
                    model[o..o + len].iter_mut().zip(&h).for_each(|(m, v)| *m += v);
                }
                kernels[k] = Some(h);
            }
        }
        Some(Joint {
            kernels,
            at,
            model,
            offset,
        })
    }

    /// The recording `sig` with every bell's fitted strikes but `bell`'s
    /// taken out; none if that bell has no kernel.
    fn others_out(&self, sig: &Signal, bell: usize) -> Option<Signal> {
        let h = self.kernels.get(bell - 1)?.as_ref()?;
        let mut samples: Vec<f64> = sig.samples.iter().zip(&self.model).map(|(x, m)| x - m).collect();
        for &o in &self.at[bell - 1] {
            samples[o..o + h.len()].iter_mut().zip(h).for_each(|(s, v)| *s += v);
        }
        Some(Signal {
            rate: sig.rate,
            samples,
        })
    }
}

/// A template too short to match: [`crate::template_timing::retime_each`]
/// leaves the bell's strikes where they were heard.
fn no_template(rate: f64) -> Signal {
    Signal {
        rate,
        samples: vec![1.0],
    }
}

/// The times heard of bell `bell`'s clean strikes: single, no other bell's
/// strike within [`CLEAR_S`], the recording about it whole.
fn clean_strikes(heard: &Heard, bell: usize, sig: &Signal) -> Vec<f64> {
    let end = sig.samples.len() as f64 / sig.rate;
    let others: Vec<&HeardStrike> = heard.strikes.iter().filter(|s| s.bell != bell).collect();
    heard
        .strikes
        .iter()
        .filter(|s| s.bell == bell && s.double.is_none())
        .filter(|s| s.t - BEFORE_S - SHIFT_S >= 0.0 && s.t + AFTER_S + SHIFT_S <= end)
        .filter(|s| others.iter().all(|o| (o.t - s.t).abs() >= CLEAR_S))
        .map(|s| s.t)
        .collect()
}

/// A template learned from strikes heard at `times`.
struct Learned {
    template: Signal,
    average: Average,
    lateness_s: f64,
    spread_s: f64,
}

/// The template of one bell from its clean strikes heard at `times` (s).
fn template_of(sig: &Signal, times: &[f64]) -> Option<Learned> {
    let rate = sig.rate;
    let (before, after) = ((BEFORE_S * rate).round() as usize, (AFTER_S * rate).round() as usize);
    let shift = (SHIFT_S * rate).round() as usize;
    let len = before + after;
    // Each strike's recording from `before` + `shift` before its time heard.
    let starts: Vec<usize> = times
        .iter()
        .map(|t| (t * rate).round() as usize - before - shift)
        .collect();
    let seg = |s: usize, lag: usize| &sig.samples[s + lag..s + lag + len];
    let (mut reference, mut lags) = line_up(sig, &starts, before, after)?;
    // The time heard in the average's own reckoning (samples): the strikes
    // are lined up on one of them, which may have been heard off the rest.
    let start_in = |reference: &[f64], lags: &[usize]| {
        let segs: Vec<&[f64]> = starts.iter().zip(lags).map(|(&s, &lag)| seg(s, lag)).collect();
        let in_step = mad(lags) <= RELINE_SPREAD_S * rate;
        start_of(reference, &segs, heard_in(lags, before, shift), rate, in_step)
    };
    let mut reach = shift;
    // A sharp blow is the start, whatever else the average shows.
    let sharp = sharp::sharp_start(sig, &starts, &reference, &lags, before, after);
    let is_sharp = sharp.is_some();
    let mut start = match sharp {
        Some(sharp::Sharp { start, relined: None }) => Some(start),
        Some(sharp::Sharp {
            start,
            relined: Some((r, l)),
        }) => {
            (reference, lags, reach) = (r, l, ((RELINE_S * rate) as usize).min(shift));
            Some(start)
        }
        None => start_in(&reference, &lags),
    };
    // Lined up in scattered steps (in rounds, on the bell before's sound),
    // with no start shown: lined up again near their times heard, where
    // the band finder heard them (within 0.3-2 ms of one another).
    if start.is_none() && mad(&lags) > RELINE_SPREAD_S * rate {
        let (r, l) = reline(sig, &starts, before, after);
        start = start_in(&r, &l);
        (reference, lags, reach) = (r, l, ((RELINE_S * rate) as usize).min(shift));
    }
    let start = start?;
    // Each clean strike's start of sound, and how late it was heard.
    let mut late: Vec<f64> = starts
        .iter()
        .zip(&lags)
        .zip(times)
        .map(|((&s, &lag), &t)| t - (s + lag + start) as f64 / rate)
        .collect();
    late.sort_by(f64::total_cmp);
    let lateness_s = late[late.len() / 2];
    let mut dev: Vec<f64> = late.iter().map(|l| (l - lateness_s).abs()).collect();
    dev.sort_by(f64::total_cmp);
    let lead = (LEAD_S * rate).round() as usize;
    let mut samples = vec![0.0; lead];
    samples.extend_from_slice(&reference[start..]);
    Some(Learned {
        template: Signal { rate, samples },
        average: Average {
            samples: reference,
            start,
            reach,
            sharp: is_sharp,
        },
        lateness_s,
        spread_s: dev[dev.len() / 2],
    })
}

/// The strikes from `starts` (each `before` + [`SHIFT_S`] before its time
/// heard) lined up: their average and each one's lag (samples, from 0 to
/// twice the shift; the shift is no move). First on the clearest strike,
/// then on the average, within [`SHIFT_S`]. Where that moves the strikes
/// about far more than the band finder ever hears one bell's strikes
/// apart (a bell whose partials are near a harmonic series matches itself
/// a few periods off: d4 of the recorded rings, strikes moved ±16 ms),
/// they are lined up again from their average as heard, within
/// [`RELINE_S`], and that is kept if its average holds more of them.
fn line_up(sig: &Signal, starts: &[usize], before: usize, after: usize) -> Option<(Vec<f64>, Vec<usize>)> {
    let rate = sig.rate;
    let shift = (SHIFT_S * rate).round() as usize;
    let len = before + after;
    let seg = |s: usize, lag: usize| &sig.samples[s + lag..s + lag + len];
    // Line up on the strike with the most sound after its time against before.
    let clarity = |s: usize| {
        let e = |a: usize, b: usize| sig.samples[s + a..s + b].iter().map(|v| v * v).sum::<f64>();
        e(shift + before, shift + before + after / 2) / e(shift, shift + before / 2).max(1e-300)
    };
    let first = (0..starts.len()).max_by(|&a, &b| clarity(starts[a]).total_cmp(&clarity(starts[b])))?;
    let pass = |reference: &[f64], lags: &mut [usize], reach: usize| {
        for (l, &s) in lags.iter_mut().zip(starts) {
            *l = best_lag(
                &sig.samples[s..s + len + 2 * shift],
                reference,
                shift,
                before,
                rate,
                reach,
            );
        }
        average(starts, lags, seg)
    };
    let mut lags = vec![shift; starts.len()];
    let mut reference = seg(starts[first], shift).to_vec();
    for _ in 0..2 {
        reference = pass(&reference, &mut lags, shift);
    }
    if mad(&lags) <= RELINE_SPREAD_S * rate {
        return Some((reference, lags));
    }
    let (r, again) = reline(sig, starts, before, after);
    let holds = |avg: &[f64], lags: &[usize]| coherence(avg, starts, lags, seg, heard_in(lags, before, shift), rate);
    if holds(&r, &again) > holds(&reference, &lags) {
        Some((r, again))
    } else {
        Some((reference, lags))
    }
}

/// The strikes from `starts` lined up from their average as heard, within
/// [`RELINE_S`] (three passes): their average and each one's lag, as
/// [`line_up`] gives them.
fn reline(sig: &Signal, starts: &[usize], before: usize, after: usize) -> (Vec<f64>, Vec<usize>) {
    let rate = sig.rate;
    let shift = (SHIFT_S * rate).round() as usize;
    let len = before + after;
    let seg = |s: usize, lag: usize| &sig.samples[s + lag..s + lag + len];
    let reach = ((RELINE_S * rate) as usize).min(shift);
    let mut lags = vec![shift; starts.len()];
    let mut r = average(starts, &lags, seg);
    for _ in 0..3 {
        for (l, &s) in lags.iter_mut().zip(starts) {
            *l = best_lag(&sig.samples[s..s + len + 2 * shift], &r, shift, before, rate, reach);
        }
        r = average(starts, &lags, seg);
    }
    (r, lags)
}

/// Where the bell's sound starts in `reference`, the average of the
/// strikes `segs` lined up, heard at sample `heard`: where the strikes'
/// second differences first agree ([`sound_start`]), or the whitened
/// average's step (below, not moved back) up to [`EARLIER_S`] before
/// that, or that step moved back ([`walk_back`]) where it lies more than
/// [`DISAGREE_S`] from the agreement either way; else, if the strikes
/// were lined up alike (`in_step`), the greatest step up in the average
/// whitened against what rings through all the strikes (its partials and
/// the other bells' pressed down, the blow left) from [`LATEST_STEP_S`]
/// before the time heard, of [`STEP`] or else [`WEAK_STEP`] times, moved
/// back to where it first stood out ([`walk_back`]).
fn start_of(reference: &[f64], segs: &[&[f64]], heard: usize, rate: f64, in_step: bool) -> Option<usize> {
    let b = block_len(rate);
    let energy = block_energy(&whiten(reference, segs, rate), rate);
    let (from, latest) = (
        heard.saturating_sub((LATEST_STEP_S * rate) as usize),
        heard + (0.005 * rate) as usize,
    );
    let walked = |least: f64| {
        step_from(&energy, rate, from, latest, least)
            .filter(|_| in_step)
            .map(|k| walk_back(&energy, k / b) * b)
    };
    // The strikes' agreement, looked for in their second differences (the
    // clapper's blow is broadband, the bells already ringing are partials
    // low down, which the difference keeps under).
    let n = segs.len() as f64;
    let mean_hi = second_difference(reference);
    // The strikes' spread about the average, per sample, over the strikes.
    let mut spread = vec![0.0; reference.len()];
    for s in segs {
        for ((v, m), x) in spread.iter_mut().zip(&mean_hi).zip(second_difference(s)) {
            *v += (x - m) * (x - m);
        }
    }
    let shift = (SHIFT_S * rate).round() as usize;
    match sound_start(&mean_hi, &spread, n, rate, heard + shift) {
        // A start further back than the band finder ever heard a bell late is another sound's.
        Some(s) if s + (LATEST_S * rate) as usize >= heard => {
            // Under the other bells' ringing the agreement can come late;
            // the blow's step just before it is the start.
            let far = (DISAGREE_S * rate) as usize;
            let step = step_of(&energy, rate, from, latest);
            // Strikes lined up in scattered steps agree where they were
            // lined up (from `CORE_S` before the time heard): an agreement
            // that near it is their lining up's, and a step before it the start.
            let near = s + (AGREE_NEAR_S * rate) as usize >= heard;
            if let Some((k, _)) = step.filter(|&(k, r)| !in_step && near && k < s && r >= WEAK_STEP) {
                return Some(walk_back(&energy, k / b) * b);
            }
            match step.filter(|&(_, r)| in_step && r >= STEP) {
                Some((k, _)) if k <= s && s - k <= (EARLIER_S * rate) as usize => Some(k),
                // A clear step well before the agreement: the agreement came
                // late (its own partials), or was another sound's after it.
                Some((k, _)) if k < s => Some(walk_back(&energy, k / b) * b),
                // Well after it, only a very clear step: the agreement may be
                // the bell before's blow, or this bell's own first sound
                // rising slowly before its step (both seen). Either way the
                // start is not before the agreement: walked back over a
                // slow rise it went 10-15 ms before it (tester 14's r6,
                // bells 4-6 after MP3, wind, 16 kHz or clean).
                Some((k, r)) if k - s > far && r >= CLEAR_STEP => Some(walk_back_to(&energy, k / b, s / b) * b),
                _ => Some(s),
            }
        }
        _ => walked(STEP).or_else(|| walked(WEAK_STEP)),
    }
}

/// The strikes from `starts` moved by `lags` (`seg`), averaged.
fn average<'a>(starts: &[usize], lags: &[usize], seg: impl Fn(usize, usize) -> &'a [f64]) -> Vec<f64> {
    let mut r: Vec<f64> = vec![];
    for (&s, &lag) in starts.iter().zip(lags) {
        let x = seg(s, lag);
        if r.is_empty() {
            r = vec![0.0; x.len()];
        }
        r.iter_mut().zip(x).for_each(|(r, v)| *r += v);
    }
    let n = starts.len().max(1) as f64;
    r.iter_mut().for_each(|r| *r /= n);
    r
}

/// The median absolute deviation of `lags` (samples).
fn mad(lags: &[usize]) -> f64 {
    let mut l: Vec<f64> = lags.iter().map(|&v| v as f64).collect();
    l.sort_by(f64::total_cmp);
    let m = l[l.len() / 2];
    let mut d: Vec<f64> = l.iter().map(|v| (v - m).abs()).collect();
    d.sort_by(f64::total_cmp);
    d[d.len() / 2]
}

/// Where the strikes were heard, in the reckoning of their average lined
/// up by `lags` (samples): the median.
fn heard_in(lags: &[usize], before: usize, shift: usize) -> usize {
    let mut l = lags.to_vec();
    l.sort_unstable();
    (before + shift).saturating_sub(l[l.len() / 2])
}

/// How much of the strikes their average `avg` holds about `heard`
/// (from [`CORE_S`] before to 200 ms after): its energy against the
/// strikes' mean energy there.
fn coherence<'a>(
    avg: &[f64],
    starts: &[usize],
    lags: &[usize],
    seg: impl Fn(usize, usize) -> &'a [f64],
    heard: usize,
    rate: f64,
) -> f64 {
    let (lo, hi) = (
        heard.saturating_sub((CORE_S * rate) as usize),
        (heard + (0.2 * rate) as usize).min(avg.len()),
    );
    let e = |x: &[f64]| x[lo..hi].iter().map(|v| v * v).sum::<f64>();
    let each: f64 = starts.iter().zip(lags).map(|(&s, &l)| e(seg(s, l))).sum::<f64>() / starts.len().max(1) as f64;
    e(avg) / each.max(1e-300)
}

/// The second difference of `x` (0 at its ends).
fn second_difference(x: &[f64]) -> Vec<f64> {
    (0..x.len())
        .map(|i| {
            if i == 0 || i + 1 == x.len() {
                0.0
            } else {
                x[i + 1] - 2.0 * x[i] + x[i - 1]
            }
        })
        .collect()
}

/// The lag (`shift` ± `reach` samples) at which `x` matches `reference`
/// best, over the reference from [`CORE_S`] before its time heard (`at`)
/// to its end.
fn best_lag(x: &[f64], reference: &[f64], shift: usize, at: usize, rate: f64, reach: usize) -> usize {
    let from = at.saturating_sub((CORE_S * rate) as usize);
    let core = &reference[from..];
    // Only the lags sought are transformed: x from the first of them (the
    // core starts `from` into the reference) to as far as the core reaches
    // from the last; the transform need hold no more than the core and the
    // lags without wrapping (half the length of the whole x and core).
    let (lo, reach) = (shift.saturating_sub(reach), reach.min(shift));
    let first = (lo + from).min(x.len());
    let y = &x[first..(first + 2 * reach + core.len()).min(x.len())];
    let n = (core.len() + 2 * reach + 1).next_power_of_two();
    // out[j]: the core against x from lag lo + j.
    crate::fft::correlate(y, core, n, |out| {
        (lo..=shift + reach)
            .max_by(|&p, &q| out[p - lo].total_cmp(&out[q - lo]))
            .unwrap_or(shift)
    })
}

/// Where the bell's sound starts in the average `mean` of `n` strikes
/// lined up, their summed squared spread about it `spread` (per sample):
/// of the blocks up to `heard` (the time the strikes were heard, samples
/// from the start of `mean`), the first before the loudest from which the average stands
/// `START` times above what the spread leaves in it, with at most
/// `GAPS` blocks under on the way to the loudest. None if the average
/// never stands out.
fn sound_start(mean: &[f64], spread: &[f64], n: f64, rate: f64, heard: usize) -> Option<usize> {
    let b = ((BLOCK_S * rate).round() as usize).max(1);
    let blocks = mean.len() / b;
    // Over 2 ms about each block: chance keeps under START there.
    let w = 2 * b;
    let ratio: Vec<f64> = (0..blocks)
        .map(|k| {
            let (lo, hi) = ((k * b).saturating_sub(w / 2), (k * b + b + w / 2).min(mean.len()));
            let m: f64 = mean[lo..hi].iter().map(|v| v * v).sum();
            // What noise of this spread leaves in an average of n.
            let s: f64 = spread[lo..hi].iter().sum::<f64>() / (n * (n - 1.0)).max(1.0);
            if s > 0.0 {
                m / s
            } else {
                f64::INFINITY
            }
        })
        .collect();
    let energy = |k: usize| mean[k * b..(k + 1) * b].iter().map(|v| v * v).sum::<f64>();
    let loudest = (0..blocks.min(heard / b + 1)).max_by(|&p, &q| energy(p).total_cmp(&energy(q)))?;
    if ratio[loudest] < START {
        return None;
    }
    let mut start = loudest;
    let mut gaps = 0;
    for k in (0..loudest).rev() {
        if ratio[k] >= START {
            start = k;
            gaps = 0;
        } else {
            gaps += 1;
            if gaps > GAPS {
                break;
            }
        }
    }
    // Back from there to where the average sinks to the strikes' spread
    // (the blow rises out of it over a few ms).
    while start > 0 && ratio[start - 1] > ABOVE {
        start -= 1;
    }
    // Nothing before it stood out: the window may have cut the sound's start.
    (start > 0).then_some(start * b)
}

/// `x` whitened against the spectrum of the strikes `segs` (each as long
/// as `x`; their mean power, over [`SMOOTH_HZ`]): what rings through them
/// all (every bell's partials) is pressed down, and the blow, broadband,
/// stands out of what is left.
fn whiten(x: &[f64], segs: &[&[f64]], rate: f64) -> Vec<f64> {
    let n = (2 * x.len()).next_power_of_two();
    let (fwd, inv) = crate::fft::plans(n);
    let mut buf = fwd.make_input_vec();
    let mut spec = fwd.make_output_vec();
    let mut power = vec![0.0; spec.len()];
    for s in segs {
        buf.iter_mut().for_each(|v| *v = 0.0);
        buf[..s.len()].copy_from_slice(s);
        // The lengths are the plan's own: the transforms cannot fail.
        let _ = fwd.process(&mut buf, &mut spec);
        power.iter_mut().zip(&spec).for_each(|(p, c)| *p += c.norm_sqr());
    }
    let half = ((SMOOTH_HZ * n as f64 / rate).round() as usize).max(1);
    let mut run = vec![0.0; power.len() + 1];
    for (i, p) in power.iter().enumerate() {
        run[i + 1] = run[i] + p;
    }
    let smooth: Vec<f64> = (0..power.len())
        .map(|i| {
            let (lo, hi) = (i.saturating_sub(half), (i + half + 1).min(power.len()));
            (run[hi] - run[lo]) / (hi - lo) as f64
        })
        .collect();
    let floor = smooth.iter().copied().fold(0.0, f64::max) * WHITEN_RANGE;
    buf.iter_mut().for_each(|v| *v = 0.0);
    buf[..x.len()].copy_from_slice(x);
    let _ = fwd.process(&mut buf, &mut spec);
    for (c, p) in spec.iter_mut().zip(&smooth) {
        *c /= (p + floor).sqrt();
    }
    spec[0].im = 0.0;
    if let Some(l) = spec.last_mut() {
        l.im = 0.0;
    }
    let mut out = inv.make_output_vec();
    let _ = inv.process(&mut spec, &mut out);
    out.truncate(x.len());
    out
}

/// Samples in a block of [`BLOCK_S`].
fn block_len(rate: f64) -> usize {
    ((BLOCK_S * rate).round() as usize).max(1)
}

/// The greatest step up in `energy` (block energies, each [`BLOCK_S`]),
/// over [`LOUD_S`] against the [`QUIET_S`] before, from sample `from` to
/// `heard` (samples); none if it is under `least` times.
fn step_from(energy: &[f64], rate: f64, from: usize, heard: usize, least: f64) -> Option<usize> {
    step_of(energy, rate, from, heard).and_then(|(k, step)| (step >= least).then_some(k))
}

/// The greatest step up in `energy` as [`step_from`] finds it: where
/// (samples), and how many times.
fn step_of(energy: &[f64], rate: f64, from: usize, heard: usize) -> Option<(usize, f64)> {
    let b = block_len(rate);
    let quiet = ((QUIET_S / BLOCK_S).round() as usize).max(1);
    let loud = ((LOUD_S / BLOCK_S).round() as usize).max(1);
    let last = (heard / b).min(energy.len().saturating_sub(loud));
    let first = (from / b).max(quiet);
    let mean = |r: std::ops::Range<usize>| energy[r.clone()].iter().sum::<f64>() / r.len() as f64;
    let (k, step) = (first..last)
        .map(|k| (k, mean(k..k + loud) / mean(k - quiet..k).max(1e-300)))
        .max_by(|p, q| p.1.total_cmp(&q.1))?;
    Some((k * b, step))
}

/// From block `k` of `energy` (block energies, each [`BLOCK_S`]), where
/// the whitened average steps up most, back to where its rise began: the
/// block from which on to `k` the energy stands most above its level
/// before (the median over 20 ms ending [`LEVEL_BEFORE_S`] before `k`),
/// less [`ABOVE_DB`] a block, summed in dB (at most [`WALK_S`] back). In a
/// room the direct sound and the first reflections rise over 10-25 ms
/// before the greatest step (the step, or a walk back over blocks twice
/// the level 25-5 ms before, came 3-27 ms late on the recorded rings).
fn walk_back(energy: &[f64], k: usize) -> usize {
    let per_ms = (1e-3 / BLOCK_S).round() as usize;
    let hi = k.saturating_sub((LEVEL_BEFORE_S * 1e3) as usize * per_ms);
    let lo = hi.saturating_sub(20 * per_ms);
    if hi <= lo || k >= energy.len() {
        return k;
    }
    let mut before: Vec<f64> = energy[lo..hi].to_vec();
    before.sort_by(f64::total_cmp);
    let level = before[before.len() / 2].max(1e-300);
    let most = (WALK_S / BLOCK_S).round() as usize;
    let (mut sum, mut best, mut start) = (0.0, f64::MIN, k);
    for j in (k.saturating_sub(most - 1)..=k).rev() {
        sum += 10.0 * (energy[j].max(1e-300) / level).log10() - ABOVE_DB;
        if sum > best {
            (best, start) = (sum, j);
        }
    }
    start
}

/// [`walk_back`] from block `k`, but not back past block `floor`.
fn walk_back_to(energy: &[f64], k: usize, floor: usize) -> usize {
    walk_back(energy, k).max(floor.min(k))
}

/// The energy of `x` in blocks of [`BLOCK_S`].
fn block_energy(x: &[f64], rate: f64) -> Vec<f64> {
    let b = ((BLOCK_S * rate).round() as usize).max(1);
    x.chunks_exact(b).map(|c| c.iter().map(|v| v * v).sum()).collect()
}

/// Where the bell's sound starts (samples from the start of `energy`,
/// its block energies, each [`BLOCK_S`] long) when it was heard at `heard`
/// (samples): the block before then where the energy steps up most, over
/// [`LOUD_S`] against the [`QUIET_S`] before (the clapper's blow: 20-30 dB
/// out of the noise within a block in the recorded tower strikes, where the
/// partials then build up over tens of ms). None if no step of [`STEP`]
/// or more is found.
#[cfg(test)]
fn step_start(energy: &[f64], rate: f64, heard: usize) -> Option<usize> {
    step_from(energy, rate, 0, heard, STEP)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampled_ring::{sampled_ring, UntunedStrike};
    use crate::strikes::find_strikes;
    use crate::tower::{major_scale, score, Method, Room, TowerSpec, TrueStrike};
    use rand::{Rng, SeedableRng};

    /// A bell with a recorded bell's partial ratios (docs/strikes.md), its
    /// blow broadband noise dying away over 30 ms, its partials building up
    /// over `rise_s`.
    fn recorded_like(rate: f64, nominal: f64, rise_s: f64) -> Signal {
        UntunedStrike::with_noisy_blow(nominal, rise_s).signal(rate)
    }

    /// Four bells with a recorded bell's partial ratios (none of a tuned
    /// bell's but the prime and octave), building up over 20 to 29 ms after
    /// the blow, rung in plain hunt; and their nominals.
    fn untuned_ring() -> (Signal, Vec<TrueStrike>, Vec<f64>) {
        untuned_ring_in(Method::PlainHunt, None, 25.0)
    }

    /// Such a ring rung by `method` in `room` at `snr_db`.
    fn untuned_ring_in(method: Method, room: Option<Room>, snr_db: f64) -> (Signal, Vec<TrueStrike>, Vec<f64>) {
        let rate = 16_000.0;
        let bells = major_scale(4, 1000.0).unwrap();
        let nominals: Vec<f64> = bells.iter().map(|b| b.nominal_hz).collect();
        let strikes: Vec<Signal> = nominals
            .iter()
            .enumerate()
            .map(|(i, &f)| recorded_like(rate, f, 0.02 + 0.003 * i as f64))
            .collect();
        let spec = TowerSpec {
            rate,
            rows: 20,
            interval: 2.0 / 5.0,
            method,
            room,
            snr_db: Some(snr_db),
            ..TowerSpec::new(bells)
        };
        let (sig, truth) = sampled_ring(&spec, &strikes).unwrap();
        (sig, truth, nominals)
    }

    /// Each bell's median error (ms) with the ring `(sig, truth, nominals)`
    /// calibrated from itself, where a template was learned (else none).
    fn medians_calibrated(sig: &Signal, truth: &[TrueStrike], nominals: &[f64]) -> Vec<Option<f64>> {
        let opts = StrikeOptions::default();
        let c = calibrate(sig, nominals, &opts).unwrap();
        let mut heard = find_strikes(sig, &c.voices, &opts).unwrap();
        c.retime_each(sig, &mut heard);
        c.bells
            .iter()
            .map(|b| {
                b.lateness_s?;
                let mut e: Vec<f64> = heard
                    .strikes
                    .iter()
                    .filter(|s| s.bell == b.bell)
                    .filter_map(|s| {
                        truth
                            .iter()
                            .filter(|x| x.bell == b.bell)
                            .map(|x| s.t - x.t)
                            .min_by(|p, q| p.abs().total_cmp(&q.abs()))
                    })
                    .collect();
                e.sort_by(f64::total_cmp);
                e.get(e.len() / 2).map(|v| 1e3 * v)
            })
            .collect()
    }

    /// Each bell's partials are learned where the recording has them: at
    /// 2.98 times the nominal, where a tuned bell has none, and none at a
    /// tuned bell's tierce or superquint.
    #[test]
    fn a_bells_partials_are_learned_from_the_recording_not_assumed() {
        let (sig, _, nominals) = untuned_ring();
        let l = learn_voices(&sig, &nominals).unwrap();
        for (b, &f) in l.bells.iter().zip(&nominals) {
            assert!(b.learned, "{:?}", l.warnings);
            let at = |r: f64| {
                b.voice
                    .partials
                    .iter()
                    .any(|p| (p.freq_hz / (r * f) - 1.0).abs() < 0.005)
            };
            assert!(at(2.979), "{f} Hz: no partial at 2.979 times: {:?}", b.voice.partials);
            // A tuned bell's tierce and superquint, which these bells lack.
            assert!(!at(0.5946) && !at(1.5), "{f} Hz: {:?}", b.voice.partials);
        }
    }

    /// Heard through a tuned bell's ratios, most strikes of such bells are
    /// more than 10 ms off. Calibrated from the ring's own clean strikes, a
    /// bell whose strikes agree (their lateness spread under a
    /// millisecond) is timed at the start of its sound, within 3 ms; one
    /// whose strikes do not agree is reported so (on this ring bells 2-4:
    /// docs/strikes.md, shortfalls).
    #[test]
    fn a_bell_calibrated_from_its_own_clean_strikes_is_timed_at_the_start_of_its_sound() {
        let (sig, truth, nominals) = untuned_ring();
        let opts = StrikeOptions::default();
        let tuned: Vec<BellVoice> = nominals.iter().map(|&f| BellVoice::from_nominal(f)).collect();
        let recall = score(&find_strikes(&sig, &tuned, &opts).unwrap().times(), &truth, 0.01).recall();
        // 0.575 since a bell heard in no strike is heard in the ring's
        // rhythm (band-1; 0.5 before): still most bells off.
        assert!(recall < 0.6, "as heard through a tuned bell's ratios: recall {recall}");
        let c = calibrate(&sig, &nominals, &opts).unwrap();
        let mut heard = find_strikes(&sig, &c.voices, &opts).unwrap();
        c.retime_each(&sig, &mut heard);
        let median_ms = |b: usize| {
            let mut e: Vec<f64> = heard
                .strikes
                .iter()
                .filter(|s| s.bell == b)
                .filter_map(|s| {
                    truth
                        .iter()
                        .filter(|x| x.bell == b)
                        .map(|x| s.t - x.t)
                        .min_by(|p, q| p.abs().total_cmp(&q.abs()))
                })
                .collect();
            e.sort_by(f64::total_cmp);
            1e3 * e[e.len() / 2]
        };
        let sure: Vec<&BellCalibration> = c
            .bells
            .iter()
            .filter(|b| b.lateness_s.is_some() && b.spread_s < 1e-3)
            .collect();
        assert!(!sure.is_empty(), "{:?}", c.bells);
        for b in sure {
            let m = median_ms(b.bell);
            assert!(m.abs() <= 3.0, "bell {}: median error {m:.2} ms", b.bell);
        }
    }

    /// Strikes of a bell lined up, its blow a burst of broadband noise (the
    /// same at every strike, as one bell's blow is) at sample `at` under
    /// three louder bells ringing on (their phases differing from strike to
    /// strike) and noise, its partial building up after: (the strikes, `at`).
    fn strikes_under_ringing(rate: f64) -> (Vec<Vec<f64>>, usize) {
        strikes_under_ringing_at(rate, 0.15)
    }

    /// The same, the blow's level `blow_level` against the partial's.
    fn strikes_under_ringing_at(rate: f64, blow_level: f64) -> (Vec<Vec<f64>>, usize) {
        let (len, at) = ((0.5 * rate) as usize, (0.3 * rate) as usize);
        // The tests on these strikes pass with this sequence, not with
        // most others: the start is found 1.5-4 ms early on 11 of 12 PCG
        // seeds (docs/strikes.md, "Tests that pass on one noise"); kept so
        // that the weakness stays in view rather than hidden by a new seed.
        let mut seed = 12345u64;
        let mut rnd = move || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        // Low down (a 1 ms running mean of noise): in a room the walls take
        // the blow's top off.
        let raw: Vec<f64> = (0..len + 16).map(|_| rnd()).collect();
        let blow: Vec<f64> = (0..len).map(|i| raw[i..i + 16].iter().sum::<f64>() / 4.0).collect();
        let strikes = (0..20)
            .map(|_| {
                let phases: Vec<f64> = (0..3).map(|_| 7.0 * rnd()).collect();
                (0..len)
                    .map(|i| {
                        let t = i as f64 / rate;
                        let ringing: f64 = [523.0, 697.0, 1046.0]
                            .iter()
                            .zip(&phases)
                            .map(|(f, p)| (2.0 * std::f64::consts::PI * f * t + p).sin())
                            .sum();
                        let own = if i >= at {
                            let u = (i - at) as f64 / rate;
                            blow_level * blow[i] * (-u / 0.01).exp()
                                + (1.0 - (-u / 0.04).exp()) * (2.0 * std::f64::consts::PI * 1318.0 * u).sin()
                        } else {
                            0.0
                        };
                        ringing + own + 0.02 * rnd()
                    })
                    .collect()
            })
            .collect();
        (strikes, at)
    }

    /// Under other bells ringing on louder than its blow, the strikes'
    /// agreement shows no start of a bell's sound (the band finder's time,
    /// kept as heard, was then 25-85 ms late on the recorded bells in
    /// rooms); the whitened average's step finds it within a millisecond.
    #[test]
    fn a_blow_under_other_bells_ringing_is_found_in_the_whitened_average() {
        let rate = 16_000.0;
        let (strikes, at) = strikes_under_ringing(rate);
        let n = strikes.len() as f64;
        let len = strikes[0].len();
        let mean = average(&strikes);
        let heard = at + (0.05 * rate) as usize;
        let mean_hi = second_difference(&mean);
        let mut spread = vec![0.0; len];
        for s in &strikes {
            for ((v, m), x) in spread.iter_mut().zip(&mean_hi).zip(second_difference(s)) {
                *v += (x - m) * (x - m);
            }
        }
        let agreed = sound_start(&mean_hi, &spread, n, rate, heard);
        assert!(
            agreed.is_none_or(|s| (s as f64 - at as f64).abs() > 0.003 * rate),
            "the strikes' agreement found the start {agreed:?} (true {at})"
        );
        let segs: Vec<&[f64]> = strikes.iter().map(|s| s.as_slice()).collect();
        let start = step_start(&block_energy(&whiten(&mean, &segs, rate), rate), rate, heard).unwrap();
        let off_ms = (start as f64 - at as f64) / rate * 1e3;
        assert!(off_ms.abs() <= 1.0, "start {off_ms:.2} ms off");
    }

    /// In rounds a bell always strikes just after the same one, whose
    /// sound then fills the part of its strikes before they are heard:
    /// lined up on that part (from 140 ms before), the strikes of bells 3
    /// and 4 of this ring were lined up on their neighbour's sound and
    /// timed 167 and 51 ms early (the recorded rings' worst bell 25-47 ms
    /// off). Lined up on their own sound, from just before they are heard,
    /// three bells of four learn their start and are timed within 3 ms;
    /// the fourth's start is not sure and it is timed as heard (reported).
    #[test]
    fn in_rounds_each_bell_is_lined_up_on_its_own_sound() {
        let (sig, truth, nominals) = untuned_ring_in(Method::Rounds, None, 25.0);
        let m = medians_calibrated(&sig, &truth, &nominals);
        let timed: Vec<f64> = m.iter().flatten().copied().collect();
        assert!(timed.len() >= 3, "{m:?}");
        for e in timed {
            assert!(e.abs() <= 3.0, "median error {e:.2} ms ({m:?})");
        }
    }

    /// The average of `strikes`, sample by sample.
    fn average(strikes: &[Vec<f64>]) -> Vec<f64> {
        let n = strikes.len() as f64;
        let mut mean = vec![0.0; strikes[0].len()];
        for s in strikes {
            mean.iter_mut().zip(s).for_each(|(m, v)| *m += v / n);
        }
        mean
    }

    /// How far (ms) the start found on `strikes`' average (`start_of`,
    /// `in_step` as there) lies from the blow at sample `at`, heard at
    /// sample `heard`.
    fn start_off_ms(strikes: &[Vec<f64>], at: usize, heard: usize, rate: f64, in_step: bool) -> f64 {
        let segs: Vec<&[f64]> = strikes.iter().map(|s| s.as_slice()).collect();
        let start = start_of(&average(strikes), &segs, heard, rate, in_step).unwrap();
        (start as f64 - at as f64) / rate * 1e3
    }

    /// The start found on these strikes' average, heard 50 ms after the
    /// blow at sample `at`, is the blow within a millisecond.
    fn assert_start_within_a_millisecond(strikes: &[Vec<f64>], at: usize, rate: f64) {
        let off_ms = start_off_ms(strikes, at, at + (0.05 * rate) as usize, rate, true);
        assert!(off_ms.abs() <= 1.0, "start {off_ms:.2} ms off");
    }

    /// Under other bells ringing on, the strikes' agreement comes 10 ms
    /// after the blow (it was taken as the start); the whitened average's
    /// step just before it is the start, within a millisecond.
    #[test]
    fn a_blow_found_just_before_a_late_agreement_is_the_start() {
        let rate = 16_000.0;
        let (strikes, at) = strikes_under_ringing(rate);
        assert_start_within_a_millisecond(&strikes, at, rate);
    }

    /// A sound in every strike's window that starts 60 ms before the
    /// blow and is the same at every strike (in rounds, what the bell before
    /// leaves there): the strikes agree from its start, 60 ms early (on the
    /// recorded rings in rooms such a start put a bell 20-60 ms off). The
    /// whitened average's clear step, far from it, is the start, within a
    /// millisecond.
    #[test]
    fn an_agreement_far_from_the_blows_clear_step_is_another_sounds() {
        let rate = 16_000.0;
        let (mut strikes, at) = strikes_under_ringing(rate);
        let early = at - (0.06 * rate) as usize;
        for s in strikes.iter_mut() {
            for (i, v) in s.iter_mut().enumerate().skip(early) {
                let u = (i - early) as f64 / rate;
                *v += 0.3 * (2.0 * std::f64::consts::PI * 3100.0 * u).sin();
            }
        }
        assert_start_within_a_millisecond(&strikes, at, rate);
    }

    /// The whitened average's block energies about a blow in a room as the
    /// recorded rings show them (eight bells, plain hunt, RT60 0.6 s): the
    /// other bells' ringing and the noise level (±1.5 dB), then from the
    /// blow's block `at` its direct sound 3-4 dB above that, and its
    /// greatest step 7 ms later as the room's sound comes in.
    fn blow_in_a_room_energies() -> (Vec<f64>, usize, usize) {
        let per_ms = (1e-3 / BLOCK_S).round() as usize;
        let (at, step) = (120 * per_ms, 127 * per_ms);
        let mut rng = rand_pcg::Pcg64::seed_from_u64(4242);
        let energy = (0..200 * per_ms)
            .map(|k| {
                let jitter_db = 3.0 * rng.random_range(-0.5..0.5);
                let db = match k {
                    _ if k >= step => 46.0,
                    _ if k >= at => 41.5,
                    _ => 38.0,
                };
                10f64.powf((db + jitter_db) / 10.0)
            })
            .collect();
        (energy, at, step)
    }

    /// From the greatest step, 7 ms after the blow, back to where the
    /// rise began (the blow's direct sound), within a millisecond: walked
    /// back over blocks twice the level 25-5 ms before, at most 8 ms, it
    /// stopped 3-6 ms late (the recorded bells' starts 3-6 ms late in
    /// rooms), or at the step.
    #[test]
    fn a_blows_direct_sound_before_the_rooms_step_is_its_start() {
        let (energy, at, step) = blow_in_a_room_energies();
        let rate = 16_000.0;
        let b = block_len(rate);
        assert_eq!(
            step_of(&energy, rate, 0, energy.len() * b).map(|(k, _)| k / b),
            Some(step)
        );
        let start = walk_back(&energy, step);
        let off_ms = (start as f64 - at as f64) * BLOCK_S * 1e3;
        assert!(off_ms.abs() <= 1.0, "start {off_ms:.2} ms off the direct sound");
    }

    /// A step found well after the strikes' agreement is walked back no
    /// further than the agreement: from the room's step the walk reaches
    /// the blow's direct sound, 7 ms before; with the agreement 3 ms
    /// before the step, the start is the agreement (tester 14's r6 after
    /// MP3: bell 5 was walked 11 ms past its agreement, 14 ms early).
    #[test]
    fn a_step_after_the_agreement_is_not_walked_back_past_it() {
        let (energy, at, step) = blow_in_a_room_energies();
        let agreed = step - 6;
        assert!(
            walk_back(&energy, step) < agreed,
            "the walk alone goes past the agreement"
        );
        assert_eq!(walk_back_to(&energy, step, agreed), agreed);
        // An agreement before where the walk stops leaves the walk as it was.
        assert_eq!(walk_back_to(&energy, step, at - 20), walk_back(&energy, step));
    }

    /// A faint click in a band the strikes hold nothing else of (a codec's
    /// frame above its cut-off, here 100 dB under the bells) is not raised
    /// by the whitening to the bells' level: at 1e-12 of the strongest it
    /// added 29 % to the whitened average's energy about it.
    #[test]
    fn a_click_in_an_empty_band_is_not_whitened_to_the_bells_level() {
        use std::f64::consts::{PI, TAU};
        let rate = 16_000.0;
        let (len, click) = (4000, 2000);
        let mut rng = rand_pcg::Pcg64::seed_from_u64(7);
        // Each strike: 40 partials under 3 kHz at random phases, under a
        // Hann window (nothing leaks far up); the click a 7 kHz burst of
        // 1 ms, 1e-5 of a partial's amplitude.
        let mut rings = vec![];
        for _ in 0..6 {
            let partials: Vec<(f64, f64)> = (0..40)
                .map(|_| (rng.random_range(100.0..3000.0), rng.random_range(0.0..TAU)))
                .collect();
            let ring: Vec<f64> = (0..len)
                .map(|i| {
                    let t = i as f64 / rate;
                    let w = (PI * i as f64 / len as f64).sin().powi(2);
                    w * partials.iter().map(|(f, p)| (TAU * f * t + p).sin()).sum::<f64>()
                })
                .collect();
            rings.push(ring);
        }
        let burst = |i: usize| {
            let j = i as f64 - click as f64;
            if (0.0..16.0).contains(&j) {
                1e-5 * (PI * j / 16.0).sin().powi(2) * (TAU * 7000.0 * i as f64 / rate).sin()
            } else {
                0.0
            }
        };
        let segs: Vec<Vec<f64>> = rings
            .iter()
            .map(|r| r.iter().enumerate().map(|(i, v)| v + burst(i)).collect())
            .collect();
        let mean = |with: bool| -> Vec<f64> {
            (0..len)
                .map(|i| rings.iter().map(|r| r[i]).sum::<f64>() / 6.0 + if with { burst(i) } else { 0.0 })
                .collect()
        };
        let refs: Vec<&[f64]> = segs.iter().map(|s| s.as_slice()).collect();
        let about = |x: Vec<f64>| {
            whiten(&x, &refs, rate)[click - 40..click + 56]
                .iter()
                .map(|v| v * v)
                .sum::<f64>()
        };
        let raised = about(mean(true)) / about(mean(false));
        assert!(
            raised < 1.01,
            "the click raised the whitened average {raised:.3} times about it"
        );
    }

    /// Strikes lined up in scattered steps are made to agree where they
    /// were lined up, from just before their time heard: here a sound the
    /// same at every strike from 3 ms before it, the bell's own partial
    /// differing in phase from strike to strike (d4 of the recorded rings,
    /// heard 45-60 ms late, was started 0-4 ms before its time heard, so
    /// timed as heard). The blow's step before that agreement is the
    /// start, within 2 ms.
    #[test]
    fn an_agreement_at_the_time_heard_of_strikes_lined_up_apart_is_their_lining_ups() {
        let rate = 16_000.0;
        let (len, at) = ((0.5 * rate) as usize, (0.3 * rate) as usize);
        let (heard, agreed) = (at + (0.05 * rate) as usize, at + (0.047 * rate) as usize);
        let mut rng = rand_pcg::Pcg64::seed_from_u64(99);
        let mut rnd = move || rng.random_range(-0.5..0.5);
        let blow: Vec<f64> = (0..len).map(|_| rnd()).collect();
        let tau = 2.0 * std::f64::consts::PI;
        let strikes: Vec<Vec<f64>> = (0..20)
            .map(|_| {
                let phases: Vec<f64> = (0..4).map(|_| 7.0 * rnd()).collect();
                (0..len)
                    .map(|i| {
                        let t = i as f64 / rate;
                        let ringing: f64 = [523.0, 697.0, 1046.0]
                            .iter()
                            .zip(&phases)
                            .map(|(f, p)| (tau * f * t + p).sin())
                            .sum();
                        let own = if i >= at {
                            let u = (i - at) as f64 / rate;
                            0.3 * blow[i] * (-u / 0.01).exp()
                                + (1.0 - (-u / 0.04).exp()) * (tau * 1318.0 * u + phases[3]).sin()
                        } else {
                            0.0
                        };
                        let lined_up = if i >= agreed {
                            0.3 * (tau * 3100.0 * (i - agreed) as f64 / rate).sin()
                        } else {
                            0.0
                        };
                        // Loud noise: the blow steps up the whitened average 2-5 times, as
                        // on the recorded rings.
                        ringing + own + lined_up + 0.5 * rnd()
                    })
                    .collect()
            })
            .collect();
        let off_ms = start_off_ms(&strikes, at, heard, rate, false);
        assert!(off_ms.abs() <= 2.0, "start {off_ms:.2} ms off");
    }

    /// In rounds in a room (RT60 0.6 s) each bell always follows the same
    /// bell at nearly the same interval, so in its plain average that
    /// bell's ringing does not average away but stands under its start:
    /// three of the four untuned bells were timed 36-78 ms off (medians).
    /// Each bell's strike fitted jointly with the others', and every strike
    /// lined up with the others' fitted strikes taken out, three of the
    /// four are timed within 3 ms.
    #[test]
    fn in_rounds_in_a_room_each_bells_strike_is_fitted_jointly_with_the_others() {
        let (sig, truth, nominals) = untuned_ring_in(Method::Rounds, Some(Room::chamber(0.6)), 25.0);
        let m = medians_calibrated(&sig, &truth, &nominals);
        let near = m.iter().flatten().filter(|e| e.abs() <= 3.0).count();
        assert!(near >= 3, "bells timed within 3 ms: {near} of 4 ({m:?})");
    }

    /// In rounds in a room, the second of four untuned bells lines up in
    /// scattered steps (its strikes moved about by over 3 ms, median
    /// absolute deviation, where the band finder heard them all 9-14 ms
    /// late) and its average shows no start: it was timed as heard, 12 ms
    /// late. Lined up again near its times heard
    /// it learns its start and is timed within 3 ms. (The others of this
    /// ring are still off: docs/strikes.md, "what is left".)
    #[test]
    fn strikes_lined_up_in_scattered_steps_are_lined_up_again_near_their_times_heard() {
        let (sig, truth, nominals) = untuned_ring_in(Method::Rounds, Some(Room::chamber(0.6)), 25.0);
        let m = medians_calibrated(&sig, &truth, &nominals);
        let e = m[1].unwrap_or_else(|| panic!("bell 2 not calibrated: {m:?}"));
        assert!(e.abs() <= 3.0, "bell 2: median error {e:.2} ms ({m:?})");
    }

    /// [`best_lag`] as it was, correlating the whole of x against the core
    /// at twice the length (every lag, most of them never sought).
    fn best_lag_whole(x: &[f64], reference: &[f64], shift: usize, at: usize, rate: f64, reach: usize) -> usize {
        let from = at.saturating_sub((CORE_S * rate) as usize);
        let core = &reference[from..];
        let n = (x.len() + core.len()).next_power_of_two();
        crate::fft::correlate(x, core, n, |out| {
            (shift - reach..=shift + reach)
                .max_by(|&p, &q| out[p + from].total_cmp(&out[q + from]))
                .unwrap_or(shift)
        })
    }

    /// Correlating only the lags sought (a transform a quarter to a half
    /// as long) finds the lag the whole correlation finds: strikes of a
    /// bell-like sound in noise, lined up on their average as
    /// `retime_each` and `line_up` line them up, within the full reach,
    /// a sharp blow's and a few samples', at two rates.
    #[test]
    fn the_lags_sought_alone_are_matched_as_in_the_whole_correlation() {
        let mut seed = 12345u64;
        let mut noise = move || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            ((seed >> 11) as f64 / (1u64 << 53) as f64) - 0.5
        };
        let mut checked = 0;
        for rate in [44100.0, 16000.0] {
            let (before, after) = ((BEFORE_S * rate).round() as usize, (AFTER_S * rate).round() as usize);
            let shift = (SHIFT_S * rate).round() as usize;
            let strike = |t: f64| {
                let partials: [(f64, f64, f64); 4] = [
                    (440.0, 1.0, 1.5),
                    (880.0, 0.6, 3.0),
                    (1050.0, 0.5, 4.0),
                    (1760.0, 0.3, 6.0),
                ];
                partials
                    .iter()
                    .map(|&(f, a, d)| a * (-d * t).exp() * (2.0 * std::f64::consts::PI * f * t).sin())
                    .sum::<f64>()
            };
            let reference: Vec<f64> = (0..before + after)
                .map(|i| {
                    let t = (i as f64 - before as f64) / rate;
                    if t < 0.0 {
                        0.0
                    } else {
                        strike(t)
                    }
                })
                .collect();
            for (k, offset) in [0usize, 17, 333, shift, 2 * shift - 5, 2 * shift]
                .into_iter()
                .enumerate()
            {
                let x: Vec<f64> = (0..before + after + 2 * shift)
                    .map(|i| {
                        let t = (i as f64 - (before + offset) as f64) / rate;
                        let s = if t < 0.0 { 0.0 } else { strike(t) };
                        s + 0.3 * (k as f64 + 1.0) * noise()
                    })
                    .collect();
                for reach in [shift, sharp::reach(rate), 3] {
                    let alone = best_lag(&x, &reference, shift, before, rate, reach);
                    let whole = best_lag_whole(&x, &reference, shift, before, rate, reach);
                    assert_eq!(alone, whole, "rate {rate}, offset {offset}, reach {reach}");
                    checked += 1;
                }
            }
        }
        assert_eq!(checked, 36);
    }
}
