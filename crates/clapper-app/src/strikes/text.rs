//! The report as a ringer reads it (tester17, session 17): what qualifies
//! the table (every warning, and the bells whose timing is in doubt) is
//! said before it; the timing in a ringer's words, the developer's detail
//! in [`StrikesReport::text_verbose`] (and the JSON).

use std::fmt::Write as _;

use super::{BellTiming, StrikesReport, StrokeStats, TimingChoice, Warning, AUTO_MARGIN, FEW_IN_COLUMN};

/// The table's "mean D" in words, printed under it where a bell has
/// doubles (tester16 fault 6: no unit, no meaning; tester20 fault 8: its
/// formula is the developer's, said with `--verbose`).
pub const MEAN_D_WORDS: &str =
    "mean D: how plainly a bell's double strikes are heard: 0 where the second blow is too weak or too soon after \
     the first to be heard apart, the larger the plainer";

/// How "mean D" is reckoned, with `--verbose`.
const MEAN_D_FORMULA: &str = "detail: mean D from the second blow's loudness against the first (A) and how long \
     after it it comes (dt, ms): max(0, A - 0.2) x max(0, dt - 22) / 2.25, no unit";

/// The line for rows in which no method was found (tester21 fault 6: no
/// `rows:` line at all did not say that it could not be told).
pub const NO_METHOD: &str = "rows: the method could not be told (too few rows heard whole, or not rounds or the plain \
                             course of plain hunt, Plain Bob, Grandsire or Stedman)";

/// The mark after a bell's number in the table whose timing is in doubt.
pub(super) const DOUBT_MARK: &str = "?";

/// `v` to `digits` places, or "-" where there is none.
fn opt(v: Option<f64>, digits: usize) -> String {
    v.map_or("-".to_string(), |x| format!("{x:.digits$}"))
}

/// The bell the warning `w` is about alone, said with it after the table
/// ([`super::order::Weight::Bell`]).
fn bell_of(w: &Warning) -> Option<usize> {
    match super::order::weight(w) {
        super::order::Weight::Bell(b) => Some(b),
        _ => None,
    }
}

/// Bells as a ringer lists them: "bell 3" or "bells 2, 4, 5".
fn named(bells: &[usize]) -> String {
    let list: Vec<String> = bells.iter().map(|b| b.to_string()).collect();
    match bells.len() {
        1 => format!("bell {}", list[0]),
        _ => format!("bells {}", list.join(", ")),
    }
}

impl StrikesReport {
    /// The readable report, for the recording `name`: the figures for the
    /// whole ring, then everything that qualifies the table (warnings, and
    /// the bells whose timing is in doubt), the table, and how the strikes
    /// were timed.
    pub fn text(&self, name: &str) -> String {
        self.text_as(name, false)
    }

    /// [`Self::text`] with the developer's detail of how the strikes were
    /// timed (the timings tried and how each bell's lateness was learned).
    pub fn text_verbose(&self, name: &str) -> String {
        self.text_as(name, true)
    }

    /// [`Self::text`], with the developer's timing detail if `verbose`.
    fn text_as(&self, name: &str, verbose: bool) -> String {
        let s = &self.summary;
        // A row lacking a bell is not full, though its other bells are
        // judged in it (tester18: "72 rows (71 full)", bell 5 in 36).
        let lacking = match s.placed_rows.saturating_sub(s.full_rows) {
            0 => String::new(),
            n => format!(", {n} lacking one bell"),
        };
        // Fewer bells learned than asked for: both said (tester21's G8
        // `--bells 8` read "4 bell(s)" and nothing of the 8).
        let asked = match &self.learned_set {
            Some(l) if l.asked > self.bells => format!(" (of {} asked for)", l.asked),
            _ => String::new(),
        };
        let mut o = format!(
            "{name}: {:.1} s, {} bell(s){asked}, {} strike(s) heard in {} row(s) ({} full{lacking})\n",
            s.duration_s, self.bells, s.strikes, s.rows, s.full_rows
        );
        let doubted: Vec<usize> = (self.per_bell.iter())
            .filter(|b| b.timing_doubt.is_some())
            .map(|b| b.bell)
            .collect();
        let sure = match s.rms_error_sure_ms {
            Some(v) if !doubted.is_empty() => {
                format!(" ({v:.1} ms leaving out {}, whose timing is in doubt)", named(&doubted))
            }
            _ => String::new(),
        };
        let _ = writeln!(
            o,
            "interval {} ms, handstroke gap {} interval(s) ({} ms extra), RMS striking error {} ms{sure}, double strikes {}",
            opt(s.interval_ms, 1),
            opt(s.handstroke_gap_intervals, 2),
            opt(s.handstroke_gap_ms, 0),
            opt(s.rms_error_ms, 1),
            s.double_strikes
        );
        o.push_str(&match &s.method {
            Some(m) => m.line() + "\n",
            // Said plainly, not left out (tester21 fault 6).
            None if s.strikes > 0 && self.bells >= 3 => format!("{NO_METHOD}\n"),
            None => String::new(),
        });
        // The warnings about the whole ring, most serious first; a bell's
        // own are said with it after the table (tester20 fault 8).
        let mut ranked = s.warnings.0.clone();
        super::order::rank(&mut ranked);
        // A bell heard at no strike stays before it (tester17: such a bell
        // was named nowhere); its line in the table is empty.
        let heard = |b: usize| self.per_bell.iter().any(|x| x.bell == b && x.strikes > 0);
        let (own, ring): (Vec<Warning>, Vec<Warning>) =
            (ranked.into_iter()).partition(|w| bell_of(w).is_some_and(heard));
        for w in &ring {
            let _ = writeln!(o, "warning: {w}");
        }
        self.table_text(&mut o);
        let unsaid = self.bells_text(&mut o, &own);
        self.learned_text(&mut o);
        self.timing_text(&mut o);
        if verbose {
            self.lateness_text(&mut o);
            self.timing_detail(&mut o);
            for w in &unsaid {
                let _ = writeln!(o, "detail: {w}");
            }
            if self.per_bell.iter().any(|b| b.mean_d.is_some()) {
                let _ = writeln!(o, "{MEAN_D_FORMULA}");
            }
        }
        o
    }

    /// After the table, a line for each bell whose timing is in doubt
    /// (marked in the table) or with warnings of its own (`own`, each about
    /// one bell): why its timing is in doubt, else its first warning, and
    /// how many more there are; one bell per line, so that the ring's
    /// warnings before the table are not buried (tester20 fault 8). Returns
    /// the warnings not said, which `--verbose` lists.
    fn bells_text(&self, o: &mut String, own: &[Warning]) -> Vec<String> {
        let mut unsaid = vec![];
        let mut lines = vec![];
        for b in &self.per_bell {
            let mut said: Vec<String> = b.timing_doubt.iter().map(|d| format!("bell {}: {d}", b.bell)).collect();
            said.extend(
                own.iter()
                    .filter(|w| bell_of(w) == Some(b.bell))
                    .map(|w| w.text.clone()),
            );
            let Some(first) = said.first() else {
                continue;
            };
            let more = match said.len() - 1 {
                0 => String::new(),
                n => format!(" (and {n} more)"),
            };
            lines.push(format!("  {first}{more}"));
            unsaid.extend(said.into_iter().skip(1));
        }
        if lines.is_empty() {
            return unsaid;
        }
        let _ = writeln!(
            o,
            "about each bell (one marked {DOUBT_MARK} in the table the listener may have timed, or placed in rows, \
             wrongly, so that its figures may show that error rather than the ringer's striking):"
        );
        for l in lines {
            let _ = writeln!(o, "{l}");
        }
        if !unsaid.is_empty() {
            let _ = writeln!(
                o,
                "{} more about these bells: --verbose lists them at the end",
                unsaid.len()
            );
        }
        unsaid
    }

    /// The table of each bell's striking and what is said under it,
    /// appended to `o`.
    fn table_text(&self, o: &mut String) {
        let s = &self.summary;
        let _ = writeln!(
            o,
            "  {:>4} {:>7} {:>18} {:>18} {:>18} {:>9} {:>6}",
            "bell", "strikes", "hand mean±sd (ms)", "back mean±sd (ms)", "odd-struck±se (ms)", "doubles", "mean D"
        );
        for b in &self.per_bell {
            let ms = |st: &StrokeStats| match (st.mean_error_ms, st.spread_ms) {
                (Some(m), Some(sd)) if st.n >= FEW_IN_COLUMN => format!("{m:+.1} ± {sd:.1}"),
                (Some(m), _) => format!("{m:+.1} (n = {})", st.n),
                _ => "-".into(),
            };
            let odd = match (b.odd_struck_ms, b.odd_struck_se_ms, &b.odd_struck_doubt) {
                (Some(o), Some(se), None) => format!("{o:+.1} ± {se:.1}"),
                (Some(o), Some(se), Some(_)) => format!("{o:+.1} ± {se:.1} {DOUBT_MARK}"),
                (Some(o), None, Some(_)) => format!("{o:+.1} {DOUBT_MARK}"),
                (Some(o), None, None) => format!("{o:+.1} (no se)"),
                (None, _, Some(_)) => format!("- {DOUBT_MARK}"),
                _ if s.rows_doubted && b.strikes > 0 => "- (rows doubted)".into(),
                _ => "-".into(),
            };
            let mark = if b.timing_doubt.is_some() { DOUBT_MARK } else { "" };
            let doubled = if s.doubles_doubted.contains(&b.bell) {
                DOUBT_MARK
            } else {
                ""
            };
            let _ = writeln!(
                o,
                "  {:>4} {:>7} {:>18} {:>18} {:>18} {:>9} {:>6}",
                format!("{}{mark}", b.bell),
                b.strikes,
                ms(&b.hand),
                ms(&b.back),
                odd,
                format!("{} ({:.0} %){doubled}", b.double_strikes, 100.0 * b.double_rate),
                opt(b.mean_d, 1)
            );
        }
        if let Some(why) = &s.columns_why {
            let _ = writeln!(o, "{why}");
        }
        self.odd_legend(o);
        if self.per_bell.iter().any(|b| b.mean_d.is_some()) {
            o.push_str(MEAN_D_WORDS);
            o.push('\n');
        }
    }

    /// What the hand, back and odd-struck columns leave out, and each
    /// odd-struckness in doubt with why (tester19 fault 3, 4), appended to
    /// `o`; nothing where none is left out or in doubt.
    fn odd_legend(&self, o: &mut String) {
        let left: usize = self.per_bell.iter().map(|b| b.hand.left_out + b.back.left_out).sum();
        let doubts: Vec<(usize, &String)> = (self.per_bell.iter())
            .filter_map(|b| b.odd_struck_doubt.as_ref().map(|w| (b.bell, w)))
            .collect();
        if left > 0 {
            let _ = writeln!(
                o,
                "hand, back: each stroke's mean place error and its spread, leaving out {left} strike(s) whose \
                 errors lie far from the rest of their bell's at that stroke; odd-struck: the hand mean less the \
                 back mean, from the same errors"
            );
        }
        if !doubts.is_empty() {
            let _ = writeln!(o, "odd-struckness in doubt (marked {DOUBT_MARK} in its column):");
            // Bells doubted for one reason share a line (tester22's r6a:
            // three bells' doubles doubted, one line each, word for word).
            let mut said: Vec<(Vec<usize>, &String)> = vec![];
            for (b, w) in doubts {
                match said.iter_mut().find(|(_, x)| *x == w) {
                    Some((bells, _)) => bells.push(b),
                    None => said.push((vec![b], w)),
                }
            }
            for (bells, w) in said {
                let _ = writeln!(o, "  {}: {w}", bells_named(&bells));
            }
        }
    }

    /// The nominals learned from the recording and how sure the set is
    /// (`--bells N`), appended to `o`.
    fn learned_text(&self, o: &mut String) {
        let set = self.learned_set.as_ref();
        if let Some(l) = &self.learned_nominals_hz {
            let _ = writeln!(o, "{}", learned_line(l, set.map(|s| s.confidence)));
        }
        if let Some(set) = set {
            let rhythm = set
                .ringing
                .map_or(String::new(), |r| format!(", the rhythm says about {r:.0} ring"));
            let _ = writeln!(
                o,
                "the set learned: {:.0} % sure ({} bell(s) heard{rhythm})",
                100.0 * set.confidence,
                set.heard
            );
        }
    }

    /// How the strikes were timed, in a ringer's words (tester17: "band
    /// finder" and "docs/model.md" are the developers' words), appended to
    /// `o`; the numbers are the JSON's `timing`, and with `--verbose`
    /// [`Self::lateness_text`]'s.
    fn timing_text(&self, o: &mut String) {
        let Some(t) = &self.timing else {
            return;
        };
        if let Some(c) = &t.choice {
            let _ = writeln!(o, "{}", choice_words(c));
        }
        let how = match t.source {
            "recording" => "learned from its own clean strikes in this recording",
            "templates" => "against its own recorded strike",
            _ => return,
        };
        let _ = writeln!(
            o,
            "each bell's strikes timed at the start of its sound, {how} (--verbose gives each bell's figures)"
        );
    }

    /// Each bell's lateness and how far its strikes were moved, appended
    /// to `o` with `--verbose` only: a ringer cannot use them, and they
    /// read as bells struck 100 ms late on rings timed to 0.3 ms, or as
    /// a bell heard before its blow (tester21 fault 7c, 7f).
    fn lateness_text(&self, o: &mut String) {
        let Some(t) = &self.timing else {
            return;
        };
        let list = |f: &dyn Fn(&BellTiming) -> Option<f64>, dash: &str| {
            let l: Vec<String> = (t.per_bell.iter())
                .map(|b| f(b).map_or(format!("{} -", b.bell), |v| format!("{} {v:+.1}", b.bell)))
                .collect();
            let none = t.per_bell.iter().any(|b| f(b).is_none());
            format!(
                "{}{}",
                l.join(", "),
                if none { format!(" (-: {dash})") } else { String::new() }
            )
        };
        let mut late = list(
            &|b| (b.learned_from > 0).then_some(b.lateness_ms),
            "not learned, nothing taken off",
        );
        // A bell is heard after its blow, never before: a lateness under 0
        // (tester20: "-34.0") is a start of its sound found wrong.
        let before: Vec<usize> = (t.per_bell.iter())
            .filter(|b| b.learned_from > 0 && b.lateness_ms < 0.0)
            .map(|b| b.bell)
            .collect();
        if !before.is_empty() {
            let _ = write!(
                late,
                " (under 0: {} heard before where its sound was found to start, which cannot be: that start is \
                 another sound's, and its strikes are timed late by at least as much)",
                named(&before)
            );
        }
        let _ = match t.source {
            "recording" => writeln!(
                o,
                "each bell's strikes timed at the start of its sound, learned from its own clean strikes in this \
                 recording: a bell is heard some time after its clapper strikes, by (ms) {late}; each bell's strikes \
                 were moved by (ms, the median) {}{}",
                list(&|b| b.matched_ms, "not moved: timed as first heard"),
                parted_words(&t.per_bell)
            ),
            "templates" => writeln!(
                o,
                "each bell's strikes timed at the start of its sound, against its own recorded strike: a bell is \
                 heard some time after its clapper strikes, by (ms) {late}; each bell's strikes were moved by (ms, \
                 the median) {}",
                list(
                    &|b| b.matched_ms,
                    "none of its strikes (if any was found) matched its recorded strike well enough to be moved: \
                     timed as first heard, less the first figure if there is one"
                )
            ),
            _ => Ok(()),
        };
    }

    /// The developer's detail of the timing ([`Self::text_verbose`]): the
    /// choice's figures and what the band finder heard, appended to `o`.
    fn timing_detail(&self, o: &mut String) {
        let Some(t) = &self.timing else {
            return;
        };
        if let Some(c) = &t.choice {
            let _ = writeln!(o, "detail: {}", c.line());
        }
        for b in &t.per_bell {
            let _ = writeln!(
                o,
                "detail: bell {}: the band finder's lateness {:+.1} ms (spread {:.1} ms, MAD) learned from {} strike(s) \
                 ({}); matched to its template, moved by (median) {} ms",
                b.bell,
                b.lateness_ms,
                b.spread_ms,
                b.learned_from,
                if t.source == "recording" {
                    "the recording's own clean strikes, against the start of its average strike's sound"
                } else {
                    "a ring of the templates, against the start of its template's sound"
                },
                opt(b.matched_ms, 1)
            );
        }
    }
}

/// How the strikes were timed with nominals and why, in a ringer's words
/// (the figures as [`TimingChoice::line`] gives them).
fn choice_words(c: &TimingChoice) -> String {
    let how = if c.used == "recording" {
        "from each bell's own sound, learned from its clean strikes in this recording"
    } else {
        "as each bell is first heard, its sound taken as a tuned bell's (nothing learned from this recording)"
    };
    let n = |v: Option<usize>| v.map_or("-".to_string(), |x| x.to_string());
    let why = match (c.window_s, c.plain_unevenness_ms, c.recording_unevenness_ms) {
        (Some(w), Some(p), Some(r)) => {
            let kept = if c.used == "recording" && r < AUTO_MARGIN * p {
                "the evener kept".to_string()
            } else if c.used == "recording" {
                "timed as first heard they were far from even, so each bell's own sound was kept".to_string()
            } else if r < AUTO_MARGIN * p {
                format!(
                    "learned from the recording, {} strikes were found against {}: not kept",
                    n(c.recording_strikes),
                    n(c.plain_strikes)
                )
            } else {
                "learning from the recording was not evener enough to be kept".to_string()
            };
            // Not the striking error (tester18 read "8.2 ms" beside an RMS
            // of 36 ms as one): how evenly one strike follows the last.
            format!(
                " (both ways tried on the first {w:.0} s: the gaps between successive strikes varied by {r:.1} ms \
                 timed from each bell's own sound, {p:.1} ms timed as first heard; {kept}; a measure of the timing \
                 only, not the striking error)"
            )
        }
        (Some(w), _, _) => format!(" (both ways tried on the first {w:.0} s: too few strikes to compare)"),
        _ => " (as asked)".to_string(),
    };
    format!("strikes timed {how}{why}")
}

/// Where a bell timed from the recording was moved by more or less than
/// its lateness ([`PARTED_MS`] or more apart), why, in words (tester19
/// read "heard ... by 8 +52.8" beside "moved by 8 -104.3" and could not
/// reconcile them); empty where none was. The lateness is learned where the
/// clean strikes were heard; each strike is lined up on its bell's average
/// strike from where it was heard in the report's own pass, and a bell
/// heard there at another point of its sound (a slow bell heard at its
/// blow, not as its sound built up) moves by the difference.
fn parted_words(per_bell: &[BellTiming]) -> String {
    let parted: Vec<String> = per_bell
        .iter()
        .filter(|b| b.learned_from > 0)
        .filter_map(|b| {
            let d = b.matched_ms? + b.lateness_ms;
            (d.abs() >= PARTED_MS).then(|| format!("{} by {:+.1}", b.bell, d))
        })
        .collect();
    if parted.is_empty() {
        return String::new();
    }
    format!(
        " (moved more or less than heard late: bell {}; this pass heard those strikes at another point of their \
         sound than the clean strikes the lateness was learned from, and each strike is timed where its sound \
         starts when lined up on its bell's average strike, whatever the lateness)",
        parted.join(", ")
    )
}

/// A bell moved by more or less than its lateness by this much is said so (ms).
const PARTED_MS: f64 = 5.0;

/// "bell 4", or "bells 1, 4, 5": `bells` (from 1) named.
fn bells_named(bells: &[usize]) -> String {
    let list: Vec<String> = bells.iter().map(usize::to_string).collect();
    match bells.len() {
        1 => format!("bell {}", list[0]),
        _ => format!("bells {}", list.join(", ")),
    }
}

/// The line of the nominals learned `l`, each with how sure it is; where
/// every bell's sureness is the set's (`set`: a doubtful set caps each
/// bell's at its own), each with its own evidence instead, the set's
/// sureness said once on the next line (tester22 fault 12: r6e read "25 %
/// sure" for all six, the two bells guessed and the four heard alike).
fn learned_line(l: &[super::LearnedNominal], set: Option<f64>) -> String {
    let flat = l.len() > 1 && set.is_some_and(|s| l.iter().all(|b| b.confidence == s));
    let list: Vec<String> = l
        .iter()
        .map(|b| match (flat, b.onsets) {
            (false, _) => format!("{} {:.1} Hz ({:.0} % sure)", b.bell, b.nominal_hz, 100.0 * b.confidence),
            (true, 0) => format!("{} {:.1} Hz (guessed: not heard rising)", b.bell, b.nominal_hz),
            (true, _) => format!("{} {:.1} Hz ({:.0} %)", b.bell, b.nominal_hz, 100.0 * b.support),
        })
        .collect();
    // The evidence's meaning after the list: the line starts as it did.
    let why = if flat {
        " (each the onsets it rose most at against a typical bell's: no bell is surer than the set, below)"
    } else {
        ""
    };
    format!("nominals learned from the recording: {}{why}", list.join(", "))
}

#[cfg(test)]
mod parted_tests {
    use super::{learned_line, parted_words, BellTiming};

    /// Tester22 fault 12: r6e's six learned nominals each read "25 % sure",
    /// the set's, two of them guessed. Where each bell's is the set's, each
    /// bell's own evidence is printed; where not, each bell's sureness.
    #[test]
    fn each_learned_nominal_says_its_own_evidence() {
        let bell = |b: usize, onsets: usize, support: f64, confidence: f64| crate::strikes::LearnedNominal {
            bell: b,
            nominal_hz: 2000.0 - 100.0 * b as f64,
            confidence,
            onsets,
            support,
            partials_fit: 1.0,
        };
        let flat = [bell(1, 62, 1.0, 0.25), bell(2, 0, 0.0, 0.25), bell(3, 24, 0.39, 0.25)];
        let line = learned_line(&flat, Some(0.25));
        assert_eq!(
            line,
            "nominals learned from the recording: 1 1900.0 Hz (100 %), 2 1800.0 Hz (guessed: not heard rising), 3 \
             1700.0 Hz (39 %) (each the onsets it rose most at against a typical bell's: no bell is surer than the \
             set, below)"
        );
        let own = [bell(1, 62, 1.0, 1.0), bell(2, 40, 0.6, 0.6)];
        assert_eq!(
            learned_line(&own, Some(0.8)),
            "nominals learned from the recording: 1 1900.0 Hz (100 % sure), 2 1800.0 Hz (60 % sure)"
        );
    }

    fn bell(bell: usize, lateness_ms: f64, matched_ms: Option<f64>) -> BellTiming {
        BellTiming {
            bell,
            lateness_ms,
            spread_ms: 1.0,
            learned_from: 30,
            matched_ms,
            start_unclear: false,
        }
    }

    /// A bell moved by about its lateness is not named; one moved by far
    /// more (tester19's bell 8: heard 52.8 ms late, moved -104.3) is, with
    /// the difference and why the two figures part.
    #[test]
    fn a_bell_moved_by_other_than_its_lateness_is_said_why() {
        assert_eq!(parted_words(&[bell(1, 70.8, Some(-71.2)), bell(2, 20.0, None)]), "");
        let w = parted_words(&[bell(1, 70.8, Some(-71.2)), bell(8, 52.8, Some(-104.3))]);
        assert!(
            w.contains("bell 8 by -51.5") && w.contains("another point of their sound"),
            "{w}"
        );
        assert!(!w.contains("1 by"), "{w}");
    }
}
