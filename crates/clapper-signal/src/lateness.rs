//! Each bell's lateness: how far after the start of its sound the strike
//! finder ([`find_strikes`](crate::strikes::find_strikes)) times its strikes, learned per bell and taken
//! off (issue 43, docs/strikes.md).
//!
//! The finder times a strike where its bands have risen a fifth of the way
//! through their step: the start of the sound for a partial that starts at
//! full strength, as the project's synthetic bells' do. A real bell's
//! partials build up over tens of milliseconds after the clapper's blow
//! (the recorded strikes measured rise 10-20 dB over the first 20-60 ms),
//! so each bell was heard late by its own constant amount (15 to 85 ms on
//! the recorded tower bells measured): place errors between bells as
//! large as the striking being judged. The lateness depends on the bell's
//! timbre, not on when it strikes, so it is learned once per bell:
//!
//! from recordings of each bell struck alone ([`from_templates`]): a ring
//! is built from them ([`crate::sampled_ring`]) with known strike times,
//! listened to, and each bell's median lateness taken. (Learning it from
//! the recording itself, by averaging each bell's clean strikes lined up
//! on their waveforms, was tried and found no clear start in the average
//! on the recorded bells: docs/strikes.md.)

use crate::sampled_ring::sampled_ring;
use crate::strikes::{hear_strikes, BellVoice, Heard, HeardStrike, StrikeOptions};
use crate::tower::{Method, RingBell, TowerSpec, TrueStrike};
use crate::{Signal, SignalError};

/// One bell's lateness, learned.
#[derive(Clone, Debug, PartialEq)]
pub struct BellLateness {
    /// Bell, counting from 1.
    pub bell: usize,
    /// How late its strikes are heard (s): taken off each of them. 0 where
    /// it could not be learned.
    pub lateness_s: f64,
    /// The spread of the lateness over the strikes it was learned from (s;
    /// the median absolute deviation).
    pub spread_s: f64,
    /// Strikes it was learned from.
    pub strikes: usize,
    /// Its strikes in the ring of the templates: the lateness is sure when
    /// it was heard in at least 90 % of them ([`BellLateness::sure`]).
    pub of: usize,
}

impl BellLateness {
    /// Heard in at least 90 % of its strikes on the ring of the templates.
    pub fn sure(&self) -> bool {
        self.of > 0 && self.strikes as f64 >= HEARD_ENOUGH * self.of as f64
    }
}

/// Every bell's lateness, and what could not be learned.
#[derive(Clone, Debug, PartialEq)]
pub struct Lateness {
    /// Where it was learned: "templates".
    pub source: &'static str,
    /// Treble first.
    pub bells: Vec<BellLateness>,
    /// Bells whose lateness could not be learned, or whose partials cannot
    /// be told from another bell's, in words.
    pub warnings: Vec<String>,
}

impl Lateness {
    /// Take each bell's lateness off its strikes (and keep them in time
    /// order).
    pub fn correct(&self, heard: &mut Heard) {
        for s in &mut heard.strikes {
            if let Some(b) = self.bells.get(s.bell - 1) {
                s.t -= b.lateness_s;
            }
        }
        heard
            .strikes
            .sort_by(|a, b| a.t.total_cmp(&b.t).then(a.bell.cmp(&b.bell)));
    }

    /// The warnings that still hold once the strikes were timed on their
    /// bells' templates: `matched[b - 1]` whether bell b's template could
    /// match, `found[b - 1]` how many strikes of bell b the recording has
    /// after the search. A bell whose template matched was sought by it,
    /// not by the band finder the ring of the templates judged: its
    /// warnings from that ring are dropped (on the recorded eight, bells 2,
    /// 5 and 6 were "heard at 0-3 of 16" and then every strike was found
    /// within 0.2 ms), and it is warned of only where its count of strikes
    /// stands off the bells' median by over a tenth (fewer: strikes missed;
    /// more: another bell's taken), saying what the ring of the templates
    /// showed. Other bells keep their warnings.
    pub fn warnings_after_matching(&self, matched: &[bool], found: &[usize]) -> Vec<String> {
        let typical = median(found.iter().map(|&n| n as f64).collect()).unwrap_or(0.0);
        let mut out = vec![];
        let mut doubted: Vec<usize> = vec![];
        for w in &self.warnings {
            match bell_of(w).filter(|b| matched.get(b - 1).copied().unwrap_or(false)) {
                Some(b) => doubted.push(b),
                None => out.push(w.clone()),
            }
        }
        doubted.dedup();
        for b in doubted {
            let n = found.get(b - 1).copied().unwrap_or(0);
            if (n as f64 - typical).abs() <= FOUND_SPREAD * typical {
                continue;
            }
            let (heard, of) = self.bells.get(b - 1).map_or((0, 0), |l| (l.strikes, l.of));
            out.push(format!(
                "bell {b}: {n} strikes found by its template, the bells' median {typical}: {} (the band finder heard it at {heard} of its {of} strikes in a ring of the templates: its partials are hard to tell from the other bells')",
                if (n as f64) < typical { "some of its strikes may be missed" } else { "some of another bell's strikes may be taken for its" }
            ));
        }
        out
    }
}

/// How far a bell's count of strikes may stand off the bells' median (a
/// share of it) before it is warned of, once timed on the templates: a
/// tenth (three of 30 rows).
const FOUND_SPREAD: f64 = 0.1;

/// The bell a warning of this module is about ("bell B: ..."), if any.
fn bell_of(w: &str) -> Option<usize> {
    w.strip_prefix("bell ")?
        .split(':')
        .next()?
        .parse()
        .ok()
        .filter(|b| *b > 0)
}

fn median(mut v: Vec<f64>) -> Option<f64> {
    v.sort_by(f64::total_cmp);
    (!v.is_empty()).then(|| {
        let m = v.len() / 2;
        if v.len() % 2 == 1 {
            v[m]
        } else {
            0.5 * (v[m - 1] + v[m])
        }
    })
}

fn mad(v: &[f64], m: f64) -> f64 {
    median(v.iter().map(|x| (x - m).abs()).collect()).unwrap_or(0.0)
}

/// A bell is heard in fewer than this share of its own strikes (on the
/// ring of its templates) and its partials cannot be told from others'.
const HEARD_ENOUGH: f64 = 0.9;

/// Each bell's lateness from a recording of it struck alone
/// (`templates[0]` the treble's, all at one sample rate), listened to
/// through `voices` as the recording will be: a ring of the templates in
/// plain hunt (16 rows, a 2 s row, no room, 40 dB SNR) is built with known
/// strike times and listened to; a bell's lateness is its median heard
/// minus true time. Warns of a bell heard in under 90 % of its strikes
/// there, or heard where another bell struck (their partials cannot be
/// told apart).
pub fn from_templates(
    templates: &[Signal],
    voices: &[BellVoice],
    opts: &StrikeOptions,
) -> Result<Lateness, SignalError> {
    check_templates(templates, voices)?;
    let n = templates.len();
    let interval = (2.0 / (n as f64 + 1.0)).max(0.15);
    let (sig, truth) = ring_of_templates(templates, interval)?;
    // Only the strikes' times are wanted: no double strikes judged.
    let heard = hear_strikes(&sig, voices, opts)?.singles();
    let mut out = Lateness {
        source: "templates",
        bells: vec![],
        warnings: vec![],
    };
    // A heard strike belongs to the nearest true strike of its bell within
    // 0.4 of an interval (a bell is never heard that late: 90 ms at most
    // on the recorded bells measured, at 0.22 s intervals).
    let reach = 0.4 * interval;
    for b in 1..=n {
        let (bell, warnings) = bell_lateness(b, &truth, &heard.strikes, reach);
        out.bells.push(bell);
        out.warnings.extend(warnings);
    }
    Ok(out)
}

/// One template a bell, all at one sample rate.
fn check_templates(templates: &[Signal], voices: &[BellVoice]) -> Result<(), SignalError> {
    let n = templates.len();
    if n == 0 || n != voices.len() {
        return Err(SignalError::Option(format!(
            "{n} templates for {} bells: one each",
            voices.len()
        )));
    }
    let rate = templates[0].rate;
    if let Some(i) = templates.iter().position(|t| (t.rate - rate).abs() > 1e-6) {
        return Err(SignalError::Option(format!(
            "bell {}'s template at {} Hz, bell 1's at {rate} Hz: give them at one rate",
            i + 1,
            templates[i].rate
        )));
    }
    Ok(())
}

/// The templates rung in plain hunt (16 rows, `interval` s apart, no room,
/// 40 dB SNR) with their true strike times.
fn ring_of_templates(templates: &[Signal], interval: f64) -> Result<(Signal, Vec<TrueStrike>), SignalError> {
    let bells = vec![
        RingBell {
            nominal_hz: 1000.0,
            mass_kg: 1.0,
            odd_struck_ms: 0.0,
        };
        templates.len()
    ];
    let spec = TowerSpec {
        rate: templates[0].rate,
        rows: 16,
        interval,
        jitter: (0.05 * interval).min(0.01),
        seed: 43,
        method: Method::PlainHunt,
        snr_db: Some(40.0),
        ..TowerSpec::new(bells)
    };
    sampled_ring(&spec, templates)
}

/// Bell `b`'s lateness from its strikes heard in the ring of templates,
/// with the warnings of a bell heard too seldom or where another struck.
fn bell_lateness(b: usize, truth: &[TrueStrike], heard: &[HeardStrike], reach: f64) -> (BellLateness, Vec<String>) {
    let mine: Vec<f64> = truth.iter().filter(|s| s.bell == b).map(|s| s.t).collect();
    let mut late = vec![];
    let mut elsewhere: Vec<usize> = vec![];
    for h in heard.iter().filter(|s| s.bell == b) {
        let near = mine
            .iter()
            .map(|t| h.t - t)
            .filter(|d| d.abs() <= reach)
            .min_by(|x, y| x.abs().total_cmp(&y.abs()));
        match near {
            Some(d) => late.push(d),
            None => {
                if let Some(o) = truth
                    .iter()
                    .filter(|s| s.bell != b && (h.t - s.t).abs() <= reach)
                    .min_by(|x, y| (h.t - x.t).abs().total_cmp(&(h.t - y.t).abs()))
                {
                    elsewhere.push(o.bell);
                }
            }
        }
    }
    let m = median(late.clone());
    let mut warnings = vec![];
    if (late.len() as f64) < HEARD_ENOUGH * mine.len() as f64 {
        warnings.push(format!(
            "bell {b}: heard at {} of its {} strikes in a ring of the templates: its partials are hard to tell from the other bells'{}",
            late.len(),
            mine.len(),
            if m.is_none() { "; its strikes are not corrected" } else { "" }
        ));
    }
    elsewhere.sort_unstable();
    elsewhere.dedup();
    if !elsewhere.is_empty() {
        warnings.push(format!(
            "bell {b}: heard where bell(s) {} struck, in a ring of the templates: their partials cannot be told apart",
            elsewhere.iter().map(|x| x.to_string()).collect::<Vec<_>>().join(", ")
        ));
    }
    let bell = BellLateness {
        bell: b,
        lateness_s: m.unwrap_or(0.0),
        spread_s: m.map_or(0.0, |m| mad(&late, m)),
        strikes: late.len(),
        of: mine.len(),
    };
    (bell, warnings)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lateness() -> Lateness {
        let bell = |bell: usize, strikes: usize| BellLateness {
            bell,
            lateness_s: 0.03,
            spread_s: 0.001,
            strikes,
            of: 16,
        };
        Lateness {
            source: "templates",
            bells: vec![bell(1, 16), bell(2, 1), bell(3, 3)],
            warnings: vec![
                "bell 2: heard at 1 of its 16 strikes in a ring of the templates: its partials are hard to tell from the other bells'".into(),
                "bell 3: heard at 3 of its 16 strikes in a ring of the templates: its partials are hard to tell from the other bells'".into(),
                "bell 3: heard where bell(s) 1 struck, in a ring of the templates: their partials cannot be told apart".into(),
            ],
        }
    }

    /// A bell the band finder hardly heard on the ring of its templates
    /// but whose strikes were all found by its template is not warned of
    /// (an independent tester: "heard at 1 of its 16 strikes" where every
    /// strike was then found within 0.2 ms); one with strikes missed is,
    /// and one whose template cannot match keeps the warning.
    #[test]
    fn bells_found_in_full_by_their_templates_are_not_warned_of() {
        let l = lateness();
        assert!(l.warnings_after_matching(&[true, true, true], &[30, 30, 30]).is_empty());
        let w = l.warnings_after_matching(&[true, true, true], &[30, 24, 30]);
        assert_eq!(w.len(), 1, "{w:?}");
        assert!(
            w[0].starts_with("bell 2: 24 strikes found") && w[0].contains("missed"),
            "{w:?}"
        );
        let w = l.warnings_after_matching(&[true, true, false], &[30, 30, 30]);
        assert_eq!(w, l.warnings[1..].to_vec());
        assert_eq!(bell_of("bell 12: x"), Some(12));
        assert_eq!(bell_of("no bell"), None);
    }
}
