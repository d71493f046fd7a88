//! A long recording heard in windows (issue 46): read in blocks, never
//! held whole. A recording up to [`Windows::whole_s`] long is one window
//! and heard exactly as [`find_strikes`](super::find_strikes) hears it; a longer one is cut into
//! equal cores of at most [`Windows::core_s`], each heard with
//! [`Windows::overlap_s`] of the recording either side (so its strikes lie
//! far from where its bands, its strikes' responses and its rhythm are
//! cut off), and each window reports the strikes of its core. A strike
//! timed across the cut by two windows (a few ms apart) is reported once,
//! by the window it lies deeper in. What a window learns over its strikes
//! (each band's typical step and lateness, each bell's response) it
//! learns from the strikes of its own minutes, which in a long peal is
//! nearer the truth than a mean over hours (the ringers tire, the
//! microphone is moved).
//!
//! Memory is the window's audio and its bands: independent of the
//! recording's length, and time is linear in it.

use super::find::{hear_strikes, Hearing};
use super::heard::{Heard, HeardStrike, StrikeOptions};
use super::voice::BellVoice;
use crate::{Signal, SignalError};

/// A recording read in blocks: a file, say, or [`InMemory`].
pub trait RecordingBlocks {
    /// Sample rate (Hz).
    fn rate(&self) -> f64;
    /// Samples in the whole recording.
    fn total(&self) -> usize;
    /// Append up to `max` more samples to `out`, from where the last read
    /// stopped; returns how many (0 at the end).
    fn read(&mut self, out: &mut Vec<f64>, max: usize) -> Result<usize, SignalError>;
}

/// A recording already in memory, read in blocks.
pub struct InMemory<'a> {
    sig: &'a Signal,
    at: usize,
}

impl<'a> InMemory<'a> {
    /// Read `sig` from its start.
    pub fn new(sig: &'a Signal) -> Self {
        InMemory { sig, at: 0 }
    }
}

impl RecordingBlocks for InMemory<'_> {
    fn rate(&self) -> f64 {
        self.sig.rate
    }

    fn total(&self) -> usize {
        self.sig.samples.len()
    }

    fn read(&mut self, out: &mut Vec<f64>, max: usize) -> Result<usize, SignalError> {
        let end = (self.at + max).min(self.sig.samples.len());
        out.extend_from_slice(&self.sig.samples[self.at..end]);
        let n = end - self.at;
        self.at = end;
        Ok(n)
    }
}

/// How a long recording is cut into windows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Windows {
    /// A recording up to this long (s) is heard whole, as one window.
    pub whole_s: f64,
    /// The longest core of a window of a longer recording (s): the
    /// recording is cut into equal cores no longer than this.
    pub core_s: f64,
    /// The recording a window hears either side of its core (s).
    pub overlap_s: f64,
    /// Samples read at a time.
    pub block: usize,
}

impl Default for Windows {
    /// 80 s heard whole; longer, cores of up to 60 s with 10 s either
    /// side (at 44.1 kHz and eight bells a window holds about 140 MB: its
    /// audio, 0.35 MB a second, and 50 bands at 1 kHz, 1.2 MB a second).
    /// A minute holds 25 strikes of each of eight bells, enough to learn
    /// each band's step and lateness and each bell's response from.
    fn default() -> Self {
        Windows {
            whole_s: 80.0,
            core_s: 60.0,
            overlap_s: 10.0,
            block: 1 << 16,
        }
    }
}

impl Windows {
    /// Windows as (first sample, end sample, core from, core to): the
    /// whole recording as one when it is short.
    fn plan(&self, total: usize, rate: f64) -> Result<Vec<(usize, usize, usize, usize)>, SignalError> {
        let ok = self.whole_s.is_finite()
            && self.core_s.is_finite()
            && self.overlap_s.is_finite()
            && self.core_s >= 1.0
            && self.overlap_s >= 1.0
            && self.whole_s >= self.core_s
            && self.block > 0;
        if !ok {
            return Err(SignalError::Option(format!(
                "windows {self:?}: cores and overlaps of 1 s or more"
            )));
        }
        if total as f64 <= self.whole_s * rate {
            return Ok(vec![(0, total, 0, total)]);
        }
        let n = (total as f64 / (self.core_s * rate)).ceil() as usize;
        let over = (self.overlap_s * rate).round() as usize;
        Ok((0..n)
            .map(|k| {
                let (from, to) = (k * total / n, (k + 1) * total / n);
                (from.saturating_sub(over), (to + over).min(total), from, to)
            })
            .collect())
    }
}

/// One window as heard: its audio (from sample `start` of the recording),
/// its strikes (times from the window's start), and the part of them it
/// reports (from `core.0` to `core.1`, samples of the recording).
pub struct Window<'a> {
    /// The window's audio.
    pub sig: &'a Signal,
    /// Its first sample in the recording.
    pub start: usize,
    /// The samples of the recording whose strikes it reports.
    pub core: (usize, usize),
}

/// Every strike of every bell in the recording `src` (`voices[0]` is bell
/// 1), heard window by window ([`Windows`]). `each` sees every window with
/// its strikes (times from the window's start) before they are kept, to
/// time them again against the window's audio (templates), say, or to
/// read its level. Warnings said by several windows are said once, and
/// a bell's warning (not heard) not at all if another window heard it.
pub fn find_strikes_streamed(
    src: &mut dyn RecordingBlocks,
    voices: &[BellVoice],
    opts: &StrikeOptions,
    windows: &Windows,
    each: &mut dyn FnMut(&Window, &mut Heard) -> Result<(), SignalError>,
) -> Result<Heard, SignalError> {
    find_strikes_streamed_deferred(src, voices, opts, windows, &mut |w, heard, hearing| {
        for (i, s) in heard.strikes.iter_mut().enumerate() {
            s.double = hearing.double(i);
        }
        drop(hearing);
        each(w, heard)
    })
}

/// [`find_strikes_streamed`], each window's strikes handed to `each` not
/// yet judged double: `each` asks the window's [`Hearing`] for the band
/// finder's judgement of those it wants (by the strike's index as handed,
/// [`Hearing::double`]) and judges the rest otherwise (against the bells'
/// templates, say), and the finder spends no time fitting those. The
/// hearing is `each`'s to let go of (its bands are the window's largest
/// part) once it has asked.
pub fn find_strikes_streamed_deferred(
    src: &mut dyn RecordingBlocks,
    voices: &[BellVoice],
    opts: &StrikeOptions,
    windows: &Windows,
    each: &mut dyn FnMut(&Window, &mut Heard, Hearing) -> Result<(), SignalError>,
) -> Result<Heard, SignalError> {
    find_strikes_streamed_heard(src, voices, opts, windows, None, each)
}

/// [`find_strikes_streamed_deferred`], a recording heard as one window
/// ([`Windows::whole_s`] or shorter) heard as `ready` says if given: the
/// caller's [`hear_strikes`] of the same recording, voices and options
/// (the recording timing's trial hears the opening window the
/// calibration has just heard). A longer recording ignores it.
pub fn find_strikes_streamed_heard(
    src: &mut dyn RecordingBlocks,
    voices: &[BellVoice],
    opts: &StrikeOptions,
    windows: &Windows,
    mut ready: Option<Hearing>,
    each: &mut dyn FnMut(&Window, &mut Heard, Hearing) -> Result<(), SignalError>,
) -> Result<Heard, SignalError> {
    let rate = src.rate();
    let plan = windows.plan(src.total(), rate)?;
    let mut audio: Vec<f64> = vec![];
    let mut first = 0usize;
    // (strike, samples from its window's nearer cut, window).
    let mut kept: Vec<(HeardStrike, f64, usize)> = vec![];
    let mut warnings: Vec<String> = vec![];
    for (w, &(from, to, core_from, core_to)) in plan.iter().enumerate() {
        // Drop what no later window hears, then read to the window's end.
        audio.drain(..from - first);
        first = from;
        while first + audio.len() < to {
            let want = (to - first - audio.len()).min(windows.block);
            if src.read(&mut audio, want)? == 0 {
                return Err(SignalError::Invalid(format!(
                    "the recording ended at sample {} of {}",
                    first + audio.len(),
                    src.total()
                )));
            }
        }
        // The window's audio is the buffer itself, lent and taken back.
        let sig = Signal {
            rate,
            samples: std::mem::take(&mut audio),
        };
        let hearing = match ready.take().filter(|_| plan.len() == 1) {
            Some(h) => h,
            None => hear_strikes(&sig, voices, opts)?,
        };
        let mut heard = hearing.singles();
        let window = Window {
            sig: &sig,
            start: from,
            core: (core_from, core_to),
        };
        each(&window, &mut heard, hearing)?;
        audio = sig.samples;
        for m in heard.warnings {
            if !warnings.contains(&m) {
                warnings.push(m);
            }
        }
        if plan.len() == 1 {
            kept.extend(heard.strikes.into_iter().map(|s| (s, 0.0, 0)));
            continue;
        }
        // A strike a little past the cut is kept too: the next window may
        // time it a little before it; the deeper one stays ([`once`]).
        let reach = opts.min_separation_s * rate;
        for mut s in heard.strikes {
            let at = s.t * rate + from as f64;
            if at >= core_from as f64 - reach && at < core_to as f64 + reach {
                let depth = (at - core_from as f64).min(core_to as f64 - at);
                s.t = at / rate;
                kept.push((s, depth, w));
            }
        }
    }
    let strikes = once(kept, opts.min_separation_s);
    if plan.len() > 1 {
        // A bell not heard in one window but heard in others was heard:
        // the finder's warnings of a bell start "bell N: ".
        warnings.retain(|m| !strikes.iter().any(|s| m.starts_with(&format!("bell {}: ", s.bell))));
    }
    Ok(Heard { strikes, warnings })
}

/// The strikes of all windows in time order, a strike two windows both
/// report (the same bell within `sep` s, from different windows) kept from
/// the window it lies deeper in.
fn once(mut kept: Vec<(HeardStrike, f64, usize)>, sep: f64) -> Vec<HeardStrike> {
    kept.sort_by(|a, b| a.0.t.total_cmp(&b.0.t).then(a.0.bell.cmp(&b.0.bell)));
    let mut drop = vec![false; kept.len()];
    for i in 0..kept.len() {
        for j in i + 1..kept.len() {
            if kept[j].0.t - kept[i].0.t >= sep {
                break;
            }
            if kept[j].0.bell == kept[i].0.bell && kept[j].2 != kept[i].2 && !drop[i] && !drop[j] {
                if kept[j].1 > kept[i].1 {
                    drop[i] = true;
                } else {
                    drop[j] = true;
                }
            }
        }
    }
    kept.into_iter()
        .zip(drop)
        .filter(|(_, d)| !d)
        .map(|(k, _)| k.0)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::strikes::find_strikes;

    /// A short recording is one window; a longer one is cut into equal
    /// cores with the overlap either side.
    #[test]
    fn windows_are_planned_whole_or_in_equal_cores() {
        let plan = Windows::default().plan(80 * 8000, 8000.0).unwrap();
        assert_eq!(plan, vec![(0, 640_000, 0, 640_000)]);
        // Longer: equal cores of at most 60 s, 10 s either side.
        let plan = Windows::default().plan(130 * 8000, 8000.0).unwrap();
        assert_eq!(plan.len(), 3);
        assert_eq!(plan[0], (0, plan[0].3 + 80_000, 0, plan[0].3));
        assert_eq!(plan[2].1, 130 * 8000);
        assert!(plan.windows(2).all(|w| w[0].3 == w[1].2));
    }

    #[test]
    fn a_strike_two_windows_report_is_kept_once_from_the_deeper() {
        let s = |bell: usize, t: f64| HeardStrike {
            bell,
            t,
            strength: 1.0,
            double: None,
        };
        let kept = vec![
            (s(1, 59.998), 0.2, 0),
            (s(2, 59.9), 100.0, 0),
            (s(1, 60.001), 9.0, 1),
            (s(1, 61.0), 8000.0, 1),
        ];
        let once = once(kept, 0.5);
        let got: Vec<(usize, f64)> = once.iter().map(|s| (s.bell, s.t)).collect();
        assert_eq!(got, vec![(2, 59.9), (1, 60.001), (1, 61.0)]);
    }

    /// A ring of 90 s heard in windows of 20 s cores: read in blocks of
    /// 1000 samples or of a million, bit for bit the same strikes; and the
    /// strikes heard whole, each once (the same bell within 5 ms, the
    /// median under 0.5 ms, the same double strikes).
    #[test]
    fn a_ring_heard_in_windows_is_heard_as_whole_in_blocks_of_any_size() {
        use crate::tower::{major_scale, tower_recording, DoubleStrikeSpec, TowerSpec};
        let bells = major_scale(6, 1000.0).unwrap();
        let spec = TowerSpec {
            rate: 8000.0,
            rows: 60,
            snr_db: Some(30.0),
            doubles: vec![DoubleStrikeSpec {
                bell: 3,
                row: 30,
                delay_ms: 60.0,
                amplitude_ratio: 0.8,
            }],
            ..TowerSpec::new(bells.clone())
        };
        let (sig, _) = tower_recording(&spec).unwrap();
        let voices: Vec<BellVoice> = bells.iter().map(|b| BellVoice::from_nominal(b.nominal_hz)).collect();
        let opts = StrikeOptions::default();
        let heard = |block: usize| {
            let w = Windows {
                whole_s: 20.0,
                core_s: 20.0,
                overlap_s: 6.0,
                block,
            };
            assert!(w.plan(sig.samples.len(), sig.rate).unwrap().len() >= 4);
            find_strikes_streamed(&mut InMemory::new(&sig), &voices, &opts, &w, &mut |_, _| Ok(())).unwrap()
        };
        let (small, large) = (heard(1000), heard(1 << 20));
        assert_eq!(small, large);
        let whole = find_strikes(&sig, &voices, &opts).unwrap();
        assert_eq!(small.strikes.len(), whole.strikes.len());
        let mut d: Vec<f64> = small
            .strikes
            .iter()
            .zip(&whole.strikes)
            .map(|(a, b)| (a.t - b.t).abs() * 1e3)
            .collect();
        d.sort_by(f64::total_cmp);
        println!(
            "windowed against whole (ms): median {:.4}, p90 {:.4}, max {:.4}, {} strikes; {} the same to the bit",
            d[d.len() / 2],
            d[d.len() * 9 / 10],
            d[d.len() - 1],
            d.len(),
            d.iter().filter(|v| **v == 0.0).count()
        );
        for (a, b) in small.strikes.iter().zip(&whole.strikes) {
            assert_eq!(a.bell, b.bell, "at {} s", b.t);
            assert!(
                (a.t - b.t).abs() < 0.005,
                "bell {} at {} s heard at {} s",
                b.bell,
                b.t,
                a.t
            );
            assert_eq!(a.double.is_some(), b.double.is_some(), "bell {} at {} s", b.bell, b.t);
        }
        // Each window learns its bands' steps and lateness from its own
        // 32 s (13 strikes a bell): most strikes move well under a millisecond.
        assert!(d[d.len() / 2] < 0.5, "median {} ms", d[d.len() / 2]);
        assert!(whole.strikes.iter().any(|s| s.double.is_some()));
    }

    /// A recording heard as one window with the caller's hearing of it
    /// handed in is heard as without (the same strikes, doubles and
    /// warnings), and the hearing handed in is the one used (another
    /// recording's gives that one's strikes); a recording of several
    /// windows ignores it.
    #[test]
    fn a_hearing_handed_in_is_used_for_one_window_only() {
        use crate::tower::{major_scale, tower_recording, TowerSpec};
        let bells = major_scale(5, 1000.0).unwrap();
        let ring = |rows: usize, seed: u64| {
            let spec = TowerSpec {
                rate: 8000.0,
                rows,
                snr_db: Some(30.0),
                seed,
                ..TowerSpec::new(bells.clone())
            };
            tower_recording(&spec).unwrap().0
        };
        let voices: Vec<BellVoice> = bells.iter().map(|b| BellVoice::from_nominal(b.nominal_hz)).collect();
        let opts = StrikeOptions::default();
        let judged = |_: &Window, heard: &mut Heard, hearing: Hearing| {
            for (i, s) in heard.strikes.iter_mut().enumerate() {
                s.double = hearing.double(i);
            }
            Ok(())
        };
        let heard = |sig: &Signal, ready: Option<Hearing>, windows: &Windows| {
            let mut each = judged;
            find_strikes_streamed_heard(&mut InMemory::new(sig), &voices, &opts, windows, ready, &mut each).unwrap()
        };
        let (a, b) = (ring(12, 1), ring(16, 2));
        let whole = Windows::default();
        let alone = heard(&a, None, &whole);
        assert!(alone.strikes.len() >= 50);
        assert_eq!(
            heard(&a, Some(hear_strikes(&a, &voices, &opts).unwrap()), &whole),
            alone
        );
        let other = heard(&b, None, &whole);
        assert_ne!(other.strikes.len(), alone.strikes.len());
        assert_eq!(
            heard(&a, Some(hear_strikes(&b, &voices, &opts).unwrap()), &whole),
            other
        );
        let short = Windows {
            whole_s: 8.0,
            core_s: 8.0,
            overlap_s: 3.0,
            block: 1000,
        };
        let cut = heard(&a, None, &short);
        assert_eq!(heard(&a, Some(hear_strikes(&b, &voices, &opts).unwrap()), &short), cut);
    }
}
