//! Doubts about the strikes heard (issue 46): what says a recording is not
//! of these bells rung in rows. Bells whose strikes come together are one
//! sound heard as several (a bell's partials where another's are); strikes
//! of few of the bells given, never in a row with every bell, are no ring's.
//! (Each bell's own share of strikes rising ([`clapper_signal::strikes::rising`])
//! does not serve: on rings built from recorded tower bells, bells whose
//! strikes were found right rose at 3 to 10 of 24, their hum still ringing.)

use clapper_signal::striking::Timed;

/// Strikes of two bells closer than this (s) are one sound: bells rung in
/// rows strike 160 ms or more apart, and a clash as close is rare.
pub(super) const TOGETHER_S: f64 = 0.02;
/// Warned when at least this share of the strikes come together. On rings
/// built from recorded tower bells (docs/reliability.md) heard by assumed
/// nominals, where partials of bells 4, 6, 7 and 8 lie close, up to 27 %
/// of the strikes did (mostly strikes wrongly heard, but bells); one bell
/// heard as four, or a single strike, all of them.
const TOGETHER_SHARE: f64 = 0.5;

/// A warning when many strikes of different bells come together
/// (within [`TOGETHER_S`]): one sound heard as several bells.
pub(super) fn struck_together(timed: &[Timed]) -> Option<String> {
    let mut order: Vec<&Timed> = timed.iter().collect();
    order.sort_by(|a, b| a.t.total_cmp(&b.t));
    let near = |i: usize, j: usize| order[i].bell != order[j].bell && (order[j].t - order[i].t).abs() < TOGETHER_S;
    let mut bells: Vec<usize> = vec![];
    let mut count = 0;
    for i in 0..order.len() {
        if (i > 0 && near(i - 1, i)) || (i + 1 < order.len() && near(i, i + 1)) {
            count += 1;
            bells.push(order[i].bell);
        }
    }
    bells.sort_unstable();
    bells.dedup();
    (count >= 3 && count as f64 >= TOGETHER_SHARE * order.len() as f64).then(|| {
        let names: Vec<String> = bells.iter().map(usize::to_string).collect();
        format!(
            "{count} of the {} strikes come within {:.0} ms of another bell's, as bells rung in rows do not: \
             one sound is heard as several bells (bells {} together), one bell's partials lying where another's \
             are; give only the nominals of the bells that ring",
            order.len(),
            TOGETHER_S * 1e3,
            names.join(", ")
        )
    })
}

/// A warning when `strikes` strikes make `rows` rows, none with every
/// bell (`placed_rows` 0: none placed, a row lacking one bell never heard
/// is placed): of only `heard` bells, half or fewer of the `bells` given, no
/// ring rung in rows; of every bell, no bell's striking can be judged
/// (each bell's figures come from full rows: a tester's phone recording
/// of six in wind and traffic read "0 full rows" and "-" for every bell,
/// with no word why). A bell or two not heard is warned of alone.
pub(super) fn no_full_row(
    strikes: usize,
    rows: usize,
    placed_rows: usize,
    heard: usize,
    bells: usize,
) -> Option<String> {
    if bells < 2 || placed_rows > 0 || strikes < 4 * bells.max(3) {
        return None;
    }
    if 2 * heard > bells && heard < bells {
        return None;
    }
    Some(if 2 * heard <= bells {
        format!(
            "{strikes} strikes of only {heard} of the {bells} bells given, in {rows} row(s) none of which holds \
             every bell: not a ring rung in rows (not these bells, or not bells at all); the rows and places \
             below mean nothing"
        )
    } else {
        format!(
            "{strikes} strikes of {heard} of the {bells} bells given, in {rows} row(s) none of which holds every \
             bell: no bell's striking can be judged (each bell's figures come from full rows); some bell is heard \
             too seldom or at the wrong times"
        )
    })
}

/// Each warning once, where it first stands (two layers may say one
/// thing), in the order a ringer acts on them (`order::rank`): the CLI's
/// text and the web page's list alike.
pub(super) fn once_each(warnings: &mut Vec<super::Warning>) {
    let mut seen = std::collections::HashSet::new();
    warnings.retain(|w| seen.insert(w.text.clone()));
    super::order::rank(warnings);
}

/// The RMS striking error over the interval above which the strikes are
/// not rows of the bells given: rows of the right bells read 0.05-0.11 on
/// an independent tester's method rings and our synthetic ones (striking
/// errors sd 3-20 ms), six bells given of eight 0.45 and seven 0.30;
/// and on the tester's rings where a bell was heard 155 ms late at every
/// strike, 0.27, or a twelve heard at half its strikes, 0.39.
const MISFIT_OF_INTERVAL: f64 = 0.25;

/// A warning that the strikes do not keep the rhythm of rows of `given`
/// bells: the RMS striking error `rms_ms` is over [`MISFIT_OF_INTERVAL`]
/// of the interval `interval_ms` (what the strikes' spacing cannot tell:
/// two bells of eight left out leave no room the spacing shows).
pub(super) fn misfit_warning(rms_ms: Option<f64>, interval_ms: Option<f64>, given: usize) -> Option<String> {
    let (rms, interval) = (rms_ms?, interval_ms?);
    (interval > 0.0 && rms > MISFIT_OF_INTERVAL * interval).then(|| {
        format!(
            "the strikes do not keep the rhythm of rows of {given} bells: the RMS striking error is {rms:.0} ms in \
             {interval:.0} ms intervals (a band's is nearer a tenth of its interval): some bell is heard at the wrong \
             time (all its strikes timed early or late, or given to another bell), or more or other bells ring than \
             were given (then give every bell that rings); the rows, places and odd-struckness below mean nothing"
        )
    })
}

/// The RMS striking error over the interval above which the strikes are
/// looser than rows of the right bells read (0.05-0.11, above: striking
/// errors sd 3-20 ms) but under [`MISFIT_OF_INTERVAL`]. Real bells heard
/// as heard through a tuned bell's partials read 0.24-0.38 on an
/// independent tester's rings of recorded strikes (each bell 20-100 ms
/// late by its own amount), some just under the misfit warning.
const LOOSE_OF_INTERVAL: f64 = 0.15;

/// How the strikes were timed, for [`loose_warning`]'s advice.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum TimedBy {
    /// As heard through the partials of the voices given.
    AsHeard,
    /// From each bell's own recorded strike.
    Templates,
    /// From the recording's own clean strikes.
    Recording,
}

/// How the strikes of a report were timed: from `templates`, else as its
/// `timing` report's source says (the recording's own strikes, or as heard).
pub(super) fn timed_by(templates: bool, timing: Option<&super::TimingReport>) -> TimedBy {
    match timing.map(|t| t.source) {
        _ if templates => TimedBy::Templates,
        Some("recording") => TimedBy::Recording,
        _ => TimedBy::AsHeard,
    }
}

/// A warning that the strikes are looser than a band rings (RMS striking
/// error `rms_ms` over [`LOOSE_OF_INTERVAL`] of the interval, under the
/// misfit warning's), with what to try given how they were `timed`.
pub(super) fn loose_warning(rms_ms: Option<f64>, interval_ms: Option<f64>, timed: TimedBy) -> Option<String> {
    let (rms, interval) = (rms_ms?, interval_ms?);
    let loose = interval > 0.0 && rms > LOOSE_OF_INTERVAL * interval && rms <= MISFIT_OF_INTERVAL * interval;
    loose.then(|| {
        let advice = match timed {
            TimedBy::AsHeard => {
                "they were timed as heard through a tuned bell's partials: bells whose partials are not a tuned \
                 bell's (most old bells) are heard late, each by its own amount; --self-calibrate learns each bell's \
                 partials and timing from the recording, and --templates times each from its own recorded strike"
            }
            TimedBy::Recording => {
                "some bell's timing learned from the recording may be wrong, or its strikes given to another: \
                 --templates (each bell's own recorded strike) times them best"
            }
            TimedBy::Templates => "some strikes may be matched to their templates at a wrong time",
        };
        format!(
            "the RMS striking error is {rms:.0} ms in {interval:.0} ms intervals, looser than most bands ring (under \
             a sixth of the interval): if this band rings better than that, the strikes are mistimed: {advice}"
        )
    })
}

/// What the bells listened for were given as: their nominals or their
/// templates (the ring-size warning names it, and what to give).
pub(super) fn given_as(templates: bool) -> &'static str {
    if templates {
        "template"
    } else {
        "nominal"
    }
}

/// The widest [`clapper_signal::striking::RingRoom::spread`] a ring's
/// size is read from: 0.05-0.20 where bells were left out of rings of
/// recorded bells (four to six of eight given), 0.33-0.61 where strikes
/// were timed astray (tester20's six and eights in dark rooms).
pub(super) const ROOM_GATHERED: f64 = 0.3;

/// A warning that more bells ring than `given` were, each by its `noun`
/// ([`given_as`]), from the strikes' spacing
/// ([`clapper_signal::striking::ring_room`]).
pub(super) fn ring_size_warning(timed: &[Timed], given: usize, noun: &str) -> Option<String> {
    ring_size_warning_as(timed, given, None, noun)
}

/// [`ring_size_warning`], worded for `given` nominals learned from the
/// recording when `asked` (`--bells N`, N asked): none were given, and the
/// spacing of strikes heard about nominals learned wrong says so too.
/// Fewer learned than asked for, it says so with the number the ringer
/// typed (tester21 fault 7b: "--bells 4" to one who typed `--bells 8`).
pub(super) fn ring_size_warning_as(timed: &[Timed], given: usize, asked: Option<usize>, noun: &str) -> Option<String> {
    let k = given as f64;
    // With every bell given it read n - 1.1 to n + 2.6 on 120 synthetic
    // rings (4 to 16 bells, striking errors to ±40 ms, handstroke gaps 0.5
    // to 2; the most with sixteen bells at ±40 ms in 160 ms intervals):
    // warned from k + 2 + k/10, none of them was, and two or more bells
    // left out were in 159 of 240 (118 of 167 with three or more given).
    let room = clapper_signal::striking::ring_room(timed)?;
    if room.interval_s < TOGETHER_S {
        // Bells "0 ms apart" leave room for thousands: no estimate at all.
        return Some(format!(
            "no ring's size can be read from the strikes: those of different bells come {:.0} ms apart, \
             together, not one after another",
            room.interval_s * 1e3
        ));
    }
    // Strikes timed astray scatter their spacings, and the room read from
    // them is no ring's (tester20's fast dark eights, 0.16 s: "room for
    // about 17-23 bells"): not said. The rhythm warnings say what is wrong.
    let gathered = room.spread <= ROOM_GATHERED;
    (gathered && room.bells >= k + 2.0 + 0.1 * k).then(|| {
        let (bells, row_ms, apart_ms) = (room.bells.round(), room.row_s * 1e3, room.interval_s * 1e3);
        if let Some(asked) = asked.filter(|a| *a > given) {
            format!(
                "--bells {asked}, but only {given} nominal(s) learned, and the strikes heard about them leave room \
                 for about {bells:.0} bells (a bell strikes every {row_ms:.0} ms, bells {apart_ms:.0} ms apart): \
                 the bells not learned ring too, their strikes are missing, and the rows, places and odd-struckness \
                 are wrong"
            )
        } else if let Some(asked) = asked {
            format!(
                "--bells {asked}, but the strikes heard about the nominals learned leave room for about {bells:.0} \
                 bells (a bell strikes every {row_ms:.0} ms, bells {apart_ms:.0} ms apart): if more bells ring, ask \
                 for them all; else some nominals learned are wrong, and so are the rows, places and odd-struckness"
            )
        } else {
            format!(
                "{given} {noun}(s) given, but the strikes leave room for about {bells:.0} bells (a bell strikes every \
                 {row_ms:.0} ms, bells {apart_ms:.0} ms apart): if more bells ring, give every bell's {noun}, treble \
                 first; the rows, places and odd-struckness are wrong without them"
            )
        }
    })
}

/// Warned when more than this share of the full rows (each bell given
/// once) hold one gap of about two intervals, the rest even: a bell not
/// given rings there (tester22's r6c with five nominals of its six: 51 of
/// 72 rows, 0.71; with every bell given, at most 0.07 of any ring of
/// tester22's in any mode; 0.24 with three of six learned).
pub(super) const GAP_ROWS: f64 = 0.4;

/// The fewest full rows the gap is looked for in.
const GAP_FEWEST_ROWS: usize = 8;

/// Of the full rows among `strikes` (each of `bells` bells once), how
/// many hold one gap between successive strikes of 1.7 to 2.4 times the
/// median gap within rows and every other 0.6 to 1.4 times it (a bell
/// not given, striking in the gap), and of how many; none under
/// [`GAP_FEWEST_ROWS`] full rows.
pub(super) fn gapped_rows(strikes: &[super::StrikeReport], bells: usize) -> Option<(usize, usize)> {
    let mut rows: std::collections::BTreeMap<usize, Vec<(f64, usize)>> = Default::default();
    for s in strikes {
        if let Some(r) = s.row {
            rows.entry(r).or_default().push((s.t_s, s.bell));
        }
    }
    let gaps: Vec<Vec<f64>> = (rows.into_values())
        .filter(|r| {
            let mut b: Vec<usize> = r.iter().map(|x| x.1).collect();
            b.sort_unstable();
            b.dedup();
            r.len() == bells && b.len() == bells && bells >= 3
        })
        .map(|mut r| {
            r.sort_by(|a, b| a.0.total_cmp(&b.0));
            r.windows(2).map(|w| w[1].0 - w[0].0).collect()
        })
        .collect();
    if gaps.len() < GAP_FEWEST_ROWS {
        return None;
    }
    let mut all: Vec<f64> = gaps.iter().flatten().copied().collect();
    all.sort_by(f64::total_cmp);
    let m = all[all.len() / 2];
    let gapped = gaps
        .iter()
        .filter(|g| {
            let wide = g.iter().filter(|&&x| x > 1.7 * m && x < 2.4 * m).count();
            let even = g.iter().filter(|&&x| x > 0.6 * m && x < 1.4 * m).count();
            wide == 1 && even + 1 == g.len()
        })
        .count();
    Some((gapped, gaps.len()))
}

/// A warning that a bell not given rings: more than [`GAP_ROWS`] of the
/// full rows among `strikes` hold a gap of two intervals (tester22 fault
/// 10: five nominals given for a six read "360 strikes in 72 rows (72
/// full)" with no word of a sixth bell). `given` bells, each by its `noun`
/// ([`given_as`]); worded for nominals learned where `asked` (`--bells N`).
pub(super) fn gap_warning(
    strikes: &[super::StrikeReport],
    given: usize,
    asked: Option<usize>,
    noun: &str,
) -> Option<String> {
    let (gapped, full) = gapped_rows(strikes, given)?;
    let rows = format!(
        "{gapped} of the {full} full rows hold a gap of two intervals between successive strikes, the rest even: \
         another bell seems to ring in it"
    );
    (gapped as f64 > GAP_ROWS * full as f64).then(|| match asked {
        Some(asked) => format!(
            "--bells {asked}: {given} nominal(s) learned, but {rows}, not learned; the rows, places and \
             odd-struckness are wrong without it"
        ),
        None => format!(
            "{given} {noun}(s) given, but {rows}; if more bells ring, give every bell's {noun}, treble first; the \
             rows, places and odd-struckness are wrong without them"
        ),
    })
}

/// Rows found (`rows`) beyond what the ringing of `timed` holds, `bells`
/// a row ([`clapper_signal::striking::rows_the_time_holds`]), in words: some rows were split half a
/// row out, their strokes wrong.
pub(super) fn rows_slipped(timed: &[Timed], bells: usize, rows: usize) -> Option<String> {
    let held = clapper_signal::striking::rows_the_time_holds(timed, bells)?;
    (rows as f64 > held + clapper_signal::striking::ROWS_OVER).then(|| {
        format!(
            "{rows} rows read where the ringing's length holds about {held:.0}: some rows are split half a row \
             out (strikes missing there), so their strokes, rows and places are wrong and odd-struckness is not \
             given"
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Rounds on `bells` bells, `rows` rows, `iv` (s) apart with a gap of
    /// one interval before each handstroke, each strike timed astray by up
    /// to ± `astray_s` (s, uniform, a fixed seed).
    fn rounds(bells: usize, rows: usize, iv: f64, astray_s: f64) -> Vec<Timed> {
        let mut seed = 12_345_u64;
        let mut next = || {
            seed = seed
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            2.0 * ((seed >> 11) as f64 / (1_u64 << 53) as f64) - 1.0
        };
        let mut out = vec![];
        let mut t = 1.0;
        for r in 0..rows {
            t += if r % 2 == 0 { iv } else { 0.0 };
            for bell in 1..=bells {
                out.push(Timed {
                    bell,
                    t: t + astray_s * next(),
                });
                t += iv;
            }
        }
        out
    }

    /// Tester20's fast eights in dark rooms (0.16 s, strikes timed some
    /// 100 ms astray) read "room for about 17-23 bells": their spacings
    /// scatter and no size is said; four of eight given, well timed, still
    /// leave room for eight.
    #[test]
    fn strikes_timed_astray_leave_no_room_to_read() {
        let astray = rounds(8, 24, 0.16, 0.1);
        assert_eq!(ring_size_warning(&astray, 8, "nominal"), None);
        let four: Vec<Timed> = rounds(8, 24, 0.16, 0.01).into_iter().filter(|s| s.bell <= 4).collect();
        let w = ring_size_warning(&four, 4, "nominal").expect("warned");
        assert!(w.contains("room for about 8 bells"), "{w}");
    }

    #[test]
    fn strikes_looser_than_a_band_say_what_to_try() {
        // An independent tester's six recorded bells in plain hunt, heard
        // as heard: 53.5 ms in 220.8 ms intervals, under the misfit warning.
        let w = loose_warning(Some(53.5), Some(220.8), TimedBy::AsHeard).expect("warned");
        assert!(w.contains("--self-calibrate") && w.contains("54 ms"), "{w}");
        assert!(loose_warning(Some(53.5), Some(220.8), TimedBy::Recording)
            .unwrap()
            .contains("--templates"));
        // A band's own striking (a tenth of the interval) is not warned of,
        // nor what the misfit warning already says.
        assert_eq!(loose_warning(Some(22.0), Some(220.0), TimedBy::AsHeard), None);
        assert_eq!(loose_warning(Some(60.0), Some(220.0), TimedBy::AsHeard), None);
        assert!(misfit_warning(Some(60.0), Some(220.0), 6).is_some());
        assert_eq!(loose_warning(None, Some(220.0), TimedBy::AsHeard), None);
    }

    #[test]
    fn a_bell_heard_as_four_at_once_is_told() {
        let timed: Vec<Timed> = (0..5)
            .flat_map(|k| {
                [1, 3, 5, 8].map(|bell| Timed {
                    bell,
                    t: 2.0 * k as f64 + 0.001 * bell as f64,
                })
            })
            .collect();
        let w = struck_together(&timed).expect("warned");
        assert!(
            w.contains("20 of the 20 strikes") && w.contains("bells 1, 3, 5, 8"),
            "{w}"
        );
        let rows: Vec<Timed> = (0..40)
            .map(|k| Timed {
                bell: k % 8 + 1,
                t: 0.2 * k as f64,
            })
            .collect();
        assert_eq!(struck_together(&rows), None);
    }

    #[test]
    fn strikes_of_few_of_the_bells_given_in_no_full_row_are_told() {
        assert!(no_full_row(48, 16, 0, 2, 8)
            .unwrap()
            .starts_with("48 strikes of only 2 of the 8"));
        // A bell or two not heard in a ring of eight: warned of alone.
        assert_eq!(no_full_row(168, 36, 0, 7, 8), None);
        assert_eq!(no_full_row(48, 16, 3, 2, 8), None);
    }

    #[test]
    fn every_bell_heard_in_no_full_row_is_told() {
        let w = no_full_row(140, 40, 0, 6, 6).expect("warned");
        assert!(w.contains("no bell's striking can be judged"), "{w}");
        assert_eq!(no_full_row(140, 40, 2, 6, 6), None);
    }

    #[test]
    fn a_warning_said_twice_is_said_once_where_it_first_stands() {
        let note = |t: &str| super::super::Warning::new(super::super::WarningKind::Note, t);
        let mut w = ["a", "b", "a", "c", "b"].map(note).to_vec();
        once_each(&mut w);
        assert_eq!(w, ["a", "b", "c"].map(note));
    }
}

#[cfg(test)]
mod slip_tests {
    use super::*;

    /// Tester 17's S6 (`--bells 6`): 84 rows read for 82, without a word.
    /// Rows read beyond what the ringing's length holds are warned of.
    #[test]
    fn rows_read_beyond_what_the_ringing_holds_are_warned_of() {
        let mut timed = vec![];
        let mut t = 1.0;
        for r in 0..40 {
            if r % 2 == 0 && r > 0 {
                t += 0.22;
            }
            for bell in 1..=6 {
                timed.push(Timed { bell, t });
                t += 0.22;
            }
        }
        assert_eq!(rows_slipped(&timed, 6, 40), None);
        assert_eq!(rows_slipped(&timed, 6, 41), None);
        let w = rows_slipped(&timed, 6, 42).unwrap_or_default();
        assert!(
            w.starts_with("42 rows read where the ringing's length holds about 40"),
            "{w}"
        );
    }
}
