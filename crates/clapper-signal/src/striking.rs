//! The rhythm of strikes heard (docs/strikes.md): handstroke and
//! backstroke, rows, each strike's place and its error against the even
//! rhythm of the rest of the ring, and each bell's odd-struckness.
//!
//! Strokes come from the handstroke gap: a bell's back-to-hand interval is
//! longer than its hand-to-back interval by the gap, whatever the method
//! moves it by, so over a run of its strikes the alternating sum of its
//! intervals says which strikes are handstrokes. Rows are then the runs of
//! strikes of one stroke in time order. In a row holding every bell once,
//! the ideal time of a bell's place is the row's even rhythm fitted to the
//! others (a straight line through their times against their places, each
//! less that bell's own steady error: `even`), so a bell's own error never
//! moves its ideal, nor lends itself to the others'.

mod even;
mod far_off;
mod figures;
mod one_stroke;
mod rows;

pub use figures::{odd_struck, OddDoubt, OddStruck, ODD_DISAGREE, ODD_FEW};
pub use one_stroke::{heard_at_one_stroke, heard_mostly_at_one_stroke, typical_strikes, TWO_ROWS};
pub use rows::{rows_the_time_holds, ROWS_OVER};

/// A strike to place: bell (from 1) and onset (s).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Timed {
    /// Bell, counting from 1.
    pub bell: usize,
    /// Onset (s).
    pub t: f64,
}

/// A strike placed in the rhythm.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placed {
    /// Handstroke (else backstroke); `None` when the rhythm does not say.
    pub hand: Option<bool>,
    /// Row, counting from 0, when the strike is in one.
    pub row: Option<usize>,
    /// Place in the row (from 1), when the row holds every bell once.
    pub place: Option<usize>,
    /// Onset less its ideal time (s), when placed.
    pub error: Option<f64>,
    /// Far off its row's rhythm (a false strike, or one heard far from
    /// its time): left out of the line its row's ideal times are read
    /// from, so that it spoils no other strike's error; placed, with its
    /// error, only where it lies between its place's neighbours in time.
    pub far_off: bool,
}

/// The rhythm of a recording.
#[derive(Clone, Debug, PartialEq)]
pub struct Rhythm {
    /// One per strike given, in the same order.
    pub placed: Vec<Placed>,
    /// Rows found.
    pub rows: usize,
    /// Rows holding every bell of the ring once: a row lacking a bell (a
    /// stroke not heard, a bell never heard) is not full, though placed.
    pub full_rows: usize,
    /// Rows placed: holding every bell heard once, but for one bell never
    /// heard or heard at one stroke only, whose place is left empty.
    pub placed_rows: usize,
    /// The mean interval between successive bells in full rows (s).
    pub interval: Option<f64>,
    /// The handstroke gap: the extra time before handstroke rows, in
    /// intervals (1 in good striking), from each bell's own strikes: where
    /// a handstroke lies between two backstrokes, its back-to-hand interval
    /// less its hand-to-back one, so that the places it hunts cancel.
    pub handstroke_gap: Option<f64>,
    /// The same gap in seconds.
    pub handstroke_gap_s: Option<f64>,
    /// The strokes are known from the rhythm: the handstroke gap stood out
    /// from the striking errors.
    pub strokes_known: bool,
    /// Bells (from 1) heard at one stroke only ([`heard_at_one_stroke`]):
    /// placed where heard, not asked for in the rows of their other stroke.
    pub one_stroke: Vec<usize>,
}

/// Place `strikes` (any order) of a ring of `bells` bells.
pub fn rhythm(strikes: &[Timed], bells: usize) -> Rhythm {
    let mut order: Vec<usize> = (0..strikes.len()).collect();
    order.sort_by(|&a, &b| strikes[a].t.total_cmp(&strikes[b].t));
    let one_stroke = heard_at_one_stroke(strikes, bells);
    // A bell heard mostly at one stroke neither votes on strokes nor is
    // asked for in every row; only one heard at one stroke alone has its
    // strikes all given that stroke (its others are that bell's own).
    let mostly = heard_mostly_at_one_stroke(strikes, bells);
    let (mut hand, votes_strength, votes_total) = strokes_by_bell(strikes, bells, &order, &mostly);
    fill_strokes(strikes, bells, &order, &mut hand);
    // Known when the alternating sums stood out: the gap is more than a
    // tenth of the interval on the strikes' average.
    let strokes_known = votes_total > 0.0 && votes_strength / votes_total > 0.02;
    let heard = Heard::new(strikes, bells, &mostly);
    let votes = hand.clone();
    let (mut row_of, mut rows) = split_rows(strikes, &order, &mut hand, bells, &heard, strokes_known);
    if !one_stroke.is_empty() {
        // A bell heard at one stroke only strikes at the stroke most of its
        // strikes' rows have: each of its strikes votes so, and the rows are
        // split again (its strike at the end of one row, a row short of it
        // after, could as well lead that row: tester15 A6_quiet60).
        hand = votes_at_one_stroke(strikes, &one_stroke, &hand, votes);
        (row_of, rows) = split_rows(strikes, &order, &mut hand, bells, &heard, strokes_known);
    }
    let rp = place_rows(strikes, &rows, bells, &heard, &hand, true);
    let t: Vec<f64> = strikes.iter().map(|s| s.t).collect();
    let bell: Vec<usize> = strikes.iter().map(|s| s.bell).collect();
    let error = even::errors(&t, &bell, &rp.full_rows, bells);
    let interval = (!rp.intervals.is_empty()).then(|| rp.intervals.iter().sum::<f64>() / rp.intervals.len() as f64);
    // Read from each bell's own strikes, not the rows' ends: rows lacking
    // a bell, or with strikes out of order, read 2.3-3.3 intervals on
    // tester20's fast eights (true 1) and 0.94-1.02 this way.
    let gap = interval.and_then(|_| gap_by_bells(strikes, &order, &hand, bells));
    let placed = (0..strikes.len())
        .map(|i| Placed {
            hand: hand[i],
            row: row_of[i],
            place: rp.place[i],
            error: error[i],
            far_off: rp.far_off[i],
        })
        .collect();
    Rhythm {
        placed,
        rows: rows.len(),
        full_rows: rp.whole,
        placed_rows: rp.full.iter().filter(|f| **f).count(),
        interval,
        handstroke_gap: gap.map(|g| g.intervals),
        handstroke_gap_s: gap.map(|g| g.seconds),
        strokes_known,
        one_stroke,
    }
}

/// The stroke votes `votes` with each strike of a bell of `one_stroke`
/// given the stroke most of that bell's strikes have in `hand` (ties:
/// handstroke).
fn votes_at_one_stroke(
    strikes: &[Timed],
    one_stroke: &[usize],
    hand: &[Option<bool>],
    mut votes: Vec<Option<bool>>,
) -> Vec<Option<bool>> {
    for &b in one_stroke {
        let mine = || (0..strikes.len()).filter(move |&i| strikes[i].bell == b);
        let at_hand = mine().filter(|&i| hand[i] == Some(true)).count();
        let at_back = mine().filter(|&i| hand[i] == Some(false)).count();
        for i in mine() {
            votes[i] = Some(at_hand >= at_back);
        }
    }
    votes
}

/// Which bells (index from 1) hold a place in the rows.
struct Heard {
    /// Heard enough to hold a place in the rows (`bells_heard`).
    any: Vec<bool>,
    /// Of those, heard at one stroke only: a row may lack them.
    optional: Vec<bool>,
}

impl Heard {
    fn new(strikes: &[Timed], bells: usize, one_stroke: &[usize]) -> Heard {
        let any = bells_heard(strikes, bells);
        let optional = (0..any.len()).map(|b| any[b] && one_stroke.contains(&b)).collect();
        Heard { any, optional }
    }

    /// The bells heard.
    fn count(&self) -> usize {
        self.any.iter().filter(|h| **h).count()
    }

    /// The bells every row holds (heard at both strokes).
    fn required(&self) -> usize {
        self.count() - self.optional.iter().filter(|h| **h).count()
    }
}

/// Which bells (index from 1) were heard enough to hold a place in every
/// row: at least a quarter as often as the bells' median, and three times.
fn bells_heard(strikes: &[Timed], bells: usize) -> Vec<bool> {
    let mut count = vec![0usize; bells + 1];
    for s in strikes {
        if let Some(c) = count.get_mut(s.bell) {
            *c += 1;
        }
    }
    let mut some: Vec<usize> = count[1..].iter().copied().filter(|&c| c > 0).collect();
    some.sort_unstable();
    let median = some.get(some.len() / 2).copied().unwrap_or(0);
    count
        .iter()
        .enumerate()
        .map(|(b, &c)| b > 0 && c >= 3 && 4 * c >= median)
        .collect()
}

/// Step 3: rows, the strikes in time order split as a touch is
/// (`rows::split`), each strike given its row's stroke: each strike's
/// row, and each row's strikes.
fn split_rows(
    strikes: &[Timed],
    order: &[usize],
    hand: &mut [Option<bool>],
    bells: usize,
    heard: &Heard,
    strokes_known: bool,
) -> (Vec<Option<usize>>, Vec<Vec<usize>>) {
    let t: Vec<f64> = order.iter().map(|&i| strikes[i].t).collect();
    let bell: Vec<usize> = order.iter().map(|&i| strikes[i].bell).collect();
    let vote: Vec<Option<bool>> = order.iter().map(|&i| hand[i]).collect();
    let n = heard.count().max(1);
    let interval = ring_room(strikes).map_or(0.0, |r| r.interval_s);
    // The gap the bells' own votes found, where they found one.
    let (_, runs) = rows_of(order, hand, bells);
    // Rows not read again for far-off strikes (`far_off`): the gap the
    // rows are split by is the one read before (tester19 D `--nominals`:
    // read again, 38 strikes changed row).
    let first = place_rows(strikes, &runs, bells, heard, hand, false);
    let gap = match first.intervals.is_empty() {
        false if strokes_known => {
            let iv = first.intervals.iter().sum::<f64>() / first.intervals.len() as f64;
            handstroke_gap(strikes, &runs, hand, &first, bells, iv).unwrap_or(1.0)
        }
        true if strokes_known => 1.0,
        _ => 0.0,
    };
    let seq = rows::Sequence {
        t: &t,
        bell: &bell,
        vote: &vote,
    };
    let costs = rows::Costs {
        bells: n,
        optional: n - heard.required().min(n),
        places: bells,
        interval,
        gap: gap.clamp(0.0, 2.0),
    };
    // No more rows than the bells' own strikes span.
    let times: Vec<Vec<f64>> = (1..=bells).map(|b| times_of(strikes, order, b)).collect();
    let most = rows::rows_the_bells_span(&times).unwrap_or(usize::MAX);
    let mut row_of = vec![None; strikes.len()];
    let mut rows = vec![];
    for (r, row) in rows::split_at_most(&seq, &costs, most).iter().enumerate() {
        let members: Vec<usize> = order[row.start..row.end].to_vec();
        for &i in &members {
            row_of[i] = Some(r);
            hand[i] = Some(row.hand);
        }
        rows.push(members);
    }
    (row_of, rows)
}

/// Step 1: each bell's strokes, in runs of its strikes without a missing
/// or extra one, from the alternating sum of its intervals. Returns the
/// strokes (per strike, as given) and the votes' strength and total.
fn strokes_by_bell(
    strikes: &[Timed],
    bells: usize,
    order: &[usize],
    one_stroke: &[usize],
) -> (Vec<Option<bool>>, f64, f64) {
    let mut hand: Vec<Option<bool>> = vec![None; strikes.len()];
    let mut votes_strength = 0.0;
    let mut votes_total = 0.0;
    // A bell heard at one stroke only has no alternate intervals to read:
    // its strikes take their neighbours' stroke (`fill_strokes`).
    for bell in (1..=bells).filter(|b| !one_stroke.contains(b)) {
        let mine: Vec<usize> = order.iter().copied().filter(|&i| strikes[i].bell == bell).collect();
        if mine.len() < 3 {
            continue;
        }
        let gaps: Vec<f64> = mine.windows(2).map(|w| strikes[w[1]].t - strikes[w[0]].t).collect();
        let mut sorted = gaps.clone();
        sorted.sort_by(f64::total_cmp);
        let typical = sorted[sorted.len() / 2];
        // A bell moves at most a place a row: its interval runs from
        // (bells − 1) to (bells + 2) places (one more place and the
        // handstroke gap), its typical one about bells + ½; a little
        // beyond that is a missing or extra strike.
        let n = bells as f64;
        let lo = (0.9 * (n - 1.0) / (n + 0.5)).max(0.5) * typical;
        let hi = (1.1 * (n + 2.0) / (n + 0.5)).min(2.0) * typical;
        let mut start = 0;
        for k in 0..=gaps.len() {
            let broken = k == gaps.len() || !(lo..=hi).contains(&gaps[k]);
            if !broken {
                continue;
            }
            // Strikes mine[start..=k] are a run; its intervals gaps[start..k].
            let run = &gaps[start..k];
            if run.len() >= 2 {
                let mean = run.iter().sum::<f64>() / run.len() as f64;
                let s: f64 = run
                    .iter()
                    .enumerate()
                    .map(|(j, d)| if j % 2 == 0 { d - mean } else { mean - d })
                    .sum();
                // s < 0: the run's first interval is short, hand to back.
                let first_hand = s < 0.0;
                for (j, &i) in mine[start..=k].iter().enumerate() {
                    hand[i] = Some(first_hand == (j % 2 == 0));
                }
                votes_strength += s.abs();
                votes_total += run.len() as f64 * 0.5 * typical;
            }
            start = k + 1;
        }
    }
    (hand, votes_strength, votes_total)
}

/// Step 2: strikes left unlabelled take the stroke most of their
/// neighbours in time have (a row's strikes are neighbours).
fn fill_strokes(strikes: &[Timed], bells: usize, order: &[usize], hand: &mut [Option<bool>]) {
    let labelled: Vec<(f64, bool)> = order
        .iter()
        .filter_map(|&i| hand[i].map(|h| (strikes[i].t, h)))
        .collect();
    let span = typical_row(strikes, bells, order);
    for &i in order {
        if hand[i].is_none() {
            let t = strikes[i].t;
            let (h, b) = labelled
                .iter()
                .filter(|x| (x.0 - t).abs() < 0.3 * span)
                .fold(
                    (0, 0),
                    |acc, x| if x.1 { (acc.0 + 1, acc.1) } else { (acc.0, acc.1 + 1) },
                );
            if h != b {
                hand[i] = Some(h > b);
            }
        }
    }
}

/// Rows as runs of one stroke in time order, none longer than the ring
/// (the bells' own votes' rows, from which the handstroke gap is first
/// read): each strike's row, and each row's strikes.
fn rows_of(order: &[usize], hand: &[Option<bool>], bells: usize) -> (Vec<Option<usize>>, Vec<Vec<usize>>) {
    let mut row_of: Vec<Option<usize>> = vec![None; hand.len()];
    let mut rows: Vec<Vec<usize>> = vec![];
    let mut last: Option<bool> = None;
    for &i in order {
        let Some(h) = hand[i] else {
            last = None;
            continue;
        };
        let new = last != Some(h) || rows.last().is_none_or(|r| r.len() >= bells);
        if new {
            rows.push(vec![]);
        }
        if let Some(r) = rows.last_mut() {
            r.push(i);
        }
        row_of[i] = Some(rows.len() - 1);
        last = Some(h);
    }
    (row_of, rows)
}

/// Places and errors in full rows (step 4).
struct RowPlaces {
    place: Vec<Option<usize>>,
    /// Each strike left out of its row's line (`far_off`).
    far_off: Vec<bool>,
    /// The rows holding every bell heard once, for their errors (`even`).
    full_rows: Vec<even::FullRow>,
    /// Each full row's interval (s).
    intervals: Vec<f64>,
    /// Whether each row is placed (holds every bell heard once).
    full: Vec<bool>,
    /// Rows holding every one of the ring's bells once.
    whole: usize,
    /// Some bell heard at one stroke only stands out of the rows of its
    /// other stroke.
    one_stroke_rows: bool,
}

/// Step 4: each strike's place in the rows holding every bell heard once
/// (their errors are found together after, `even`). A row with a bell twice (a false strike) is placed without
/// the one of the two its rhythm fits worse; one bell never heard is
/// placed around (`slots`); with `reread`, a row with a strike far off its
/// rhythm is read again without it (`reread_far_off`).
fn place_rows(
    strikes: &[Timed],
    rows: &[Vec<usize>],
    bells: usize,
    heard: &Heard,
    hand: &[Option<bool>],
    reread: bool,
) -> RowPlaces {
    let n = heard.count();
    let mut out = RowPlaces {
        place: vec![None; strikes.len()],
        far_off: vec![false; strikes.len()],
        full_rows: vec![],
        intervals: vec![],
        full: vec![false; rows.len()],
        whole: 0,
        one_stroke_rows: heard.required() < n,
    };
    if n < 3 || n + 1 < bells {
        return out;
    }
    let mut missing_at = None;
    for (r, members) in rows.iter().enumerate() {
        let Some(members) = one_each(strikes, members, heard) else {
            continue;
        };
        // A row lacking a bell heard at one stroke only and a bell never
        // heard has two places empty: `slots` places around one.
        if members.len() + 1 < bells {
            continue;
        }
        let slots = slots(strikes, &members, bells, &mut missing_at);
        out.full[r] = true;
        out.whole += usize::from(members.len() == bells);
        // A row lacking a bell has its one empty place already; `reread`
        // false, each row as it stands.
        let row = match reread && members.len() == bells {
            true => reread_far_off(strikes, rows, r, hand, members, slots, &mut out),
            false => even::FullRow {
                hand: hand[members[0]],
                far: vec![false; members.len()],
                members,
                slots,
            },
        };
        let pts: Vec<(f64, f64)> = (row.members.iter().zip(&row.slots).zip(&row.far))
            .filter(|(_, far)| !**far)
            .map(|((&i, &p), _)| (p as f64, strikes[i].t))
            .collect();
        if let Some((_, slope)) = line(&pts) {
            out.intervals.push(slope);
        }
        for (&i, &p) in row.members.iter().zip(&row.slots) {
            out.place[i] = Some(p + 1);
        }
        out.full_rows.push(row);
    }
    out
}

/// Row `r` of `rows`, holding each of the ring's bells once as `members`
/// (time order) at `slots`, read again without a strike far off its rhythm
/// where there is one (`far_off`): that strike marked in `out`, and kept
/// in the row (at the place left empty, out of its line) only where it
/// lies between that place's neighbours in time.
fn reread_far_off(
    strikes: &[Timed],
    rows: &[Vec<usize>],
    r: usize,
    hand: &[Option<bool>],
    members: Vec<usize>,
    slots: Vec<usize>,
    out: &mut RowPlaces,
) -> even::FullRow {
    let t: Vec<f64> = members.iter().map(|&i| strikes[i].t).collect();
    // The row's median interval: its far-off strike moves it little.
    let mut d: Vec<f64> = t.windows(2).map(|w| w[1] - w[0]).collect();
    d.sort_by(f64::total_cmp);
    let iv = d.get(d.len() / 2).copied().unwrap_or(0.0);
    // Beyond one interval, and the handstroke gap (taken as one interval)
    // before a handstroke row.
    let extra = |a: f64, b: f64, next: Option<&usize>| {
        let gap = f64::from(u8::from(next.and_then(|&i| hand[i]) == Some(true)));
        (iv > 0.0).then(|| (b - a) / iv - 1.0 - gap)
    };
    let (first, last) = (t[0], t[t.len() - 1]);
    let ends = far_off::Ends {
        before: (r > 0)
            .then(|| rows[r - 1].last())
            .flatten()
            .and_then(|&i| extra(strikes[i].t, first, members.first())),
        after: rows
            .get(r + 1)
            .and_then(|n| n.first())
            .and_then(|i| extra(last, strikes[*i].t, Some(i))),
    };
    let row = |members: Vec<usize>, slots: Vec<usize>, far: Vec<bool>| even::FullRow {
        hand: hand[members[0]],
        members,
        slots,
        far,
    };
    // Each bell's slot in the row before, where that row was placed.
    let before = |i: usize| {
        let b = strikes[i].bell;
        let prev = rows.get(r.wrapping_sub(1))?;
        prev.iter()
            .find(|&&j| strikes[j].bell == b)
            .and_then(|&j| out.place[j])
            .map(|p| p - 1)
    };
    let prev: Vec<Option<usize>> = members.iter().map(|&i| before(i)).collect();
    let Some(rr) = far_off::reread(&t, &slots, slots.len(), ends, &prev) else {
        let n = members.len();
        return row(members, slots, vec![false; n]);
    };
    out.far_off[members[rr.out]] = true;
    let mut kept: Vec<(usize, usize, bool)> = (members.iter().enumerate())
        .filter(|(k, _)| *k != rr.out)
        .map(|(_, &i)| i)
        .zip(rr.slots)
        .map(|(i, p)| (i, p, false))
        .collect();
    if let Some(h) = rr.hole {
        kept.push((members[rr.out], h, true));
        kept.sort_by_key(|x| x.1);
    }
    row(
        kept.iter().map(|x| x.0).collect(),
        kept.iter().map(|x| x.1).collect(),
        kept.iter().map(|x| x.2).collect(),
    )
}

/// The row's strikes (time order) holding each bell heard once (a bell
/// heard at one stroke only, at most once): as they are, or with one
/// strike left out (a bell's second, or a bell's not heard) where that
/// leaves such a row, the one whose rhythm the rest fit best; `None`
/// otherwise.
fn one_each(strikes: &[Timed], members: &[usize], heard: &Heard) -> Option<Vec<usize>> {
    let required = heard.required();
    let ok = |m: &[usize]| {
        let mut seen = vec![false; heard.any.len()];
        let distinct = m.iter().all(|&i| {
            let b = strikes[i].bell;
            heard.any.get(b) == Some(&true) && !std::mem::replace(&mut seen[b], true)
        });
        let optional = m.iter().filter(|&&i| heard.optional[strikes[i].bell]).count();
        distinct && m.len() == required + optional
    };
    if ok(members) {
        return Some(members.to_vec());
    }
    if !(required + 1..=heard.count() + 1).contains(&members.len()) {
        return None;
    }
    let mut best: Option<(f64, Vec<usize>)> = None;
    for k in 0..members.len() {
        let rest: Vec<usize> = members
            .iter()
            .enumerate()
            .filter(|(j, _)| *j != k)
            .map(|(_, &i)| i)
            .collect();
        if !ok(&rest) {
            continue;
        }
        let pts: Vec<(f64, f64)> = rest
            .iter()
            .enumerate()
            .map(|(p, &i)| (p as f64, strikes[i].t))
            .collect();
        let misfit = line(&pts).map_or(f64::INFINITY, |(a, b)| {
            pts.iter().map(|&(x, y)| (y - a - b * x).powi(2)).sum::<f64>()
        });
        if best.as_ref().is_none_or(|(m, _)| misfit < *m) {
            best = Some((misfit, rest));
        }
    }
    best.map(|x| x.1)
}

/// Each strike's slot (place − 1) in a row of `bells` whose `members`
/// (time order) are every bell but at most one: the bell never heard
/// stands where the row's longest interval is half as long again as its
/// median (in the row), else at the end of the row nearer where it last
/// stood (`missing_at`; the back at first: the two ends are alike in time).
fn slots(strikes: &[Timed], members: &[usize], bells: usize, missing_at: &mut Option<usize>) -> Vec<usize> {
    let n = members.len();
    if n >= bells {
        return (0..n).collect();
    }
    let d: Vec<f64> = members.windows(2).map(|w| strikes[w[1]].t - strikes[w[0]].t).collect();
    let mut sorted = d.clone();
    sorted.sort_by(f64::total_cmp);
    let median = sorted.get(sorted.len() / 2).copied().unwrap_or(0.0);
    let longest = d.iter().enumerate().max_by(|a, b| a.1.total_cmp(b.1));
    let at = match longest {
        Some((k, &x)) if x > 1.5 * median => k + 1,
        _ if missing_at.is_some_and(|m| 2 * m < bells) => 0,
        _ => bells - 1,
    };
    *missing_at = Some(at);
    (0..n).map(|j| if j < at { j } else { j + 1 }).collect()
}

/// The handstroke gap (intervals of `iv` s): the mean over hand rows after
/// full back rows, both full, from the back row's last strike placed to the
/// hand row's first, less the places between them (a row of `bells` may
/// lack a bell never heard, or one heard at the other stroke only: its
/// empty place is no gap).
fn handstroke_gap(
    strikes: &[Timed],
    rows: &[Vec<usize>],
    hand: &[Option<bool>],
    rp: &RowPlaces,
    bells: usize,
    iv: f64,
) -> Option<f64> {
    let mut gaps = vec![];
    let placed = |i: &usize| rp.place[*i].map(|p| (p, *i));
    for r in 1..rows.len() {
        let (prev, this) = (&rows[r - 1], &rows[r]);
        let is_hand = this.first().and_then(|&i| hand[i]) == Some(true);
        if is_hand && rp.full[r] && rp.full[r - 1] {
            let (Some((pa, a)), Some((pb, b))) = (
                prev.iter().filter_map(placed).max(),
                this.iter().filter_map(placed).min(),
            ) else {
                continue;
            };
            // Without a bell heard at one stroke only, from the rows' ends
            // as before: a bell never heard leaves its place a guess at the
            // row's ends (`slots`), and its guessed places read worse
            // (tester15 A8_quietback `--nominals`: strokes right 0.96
            // against 0.99).
            let (pa, pb, a, b) = match rp.one_stroke_rows {
                true => (pa, pb, a, b),
                false => match (prev.last(), this.first()) {
                    (Some(&a), Some(&b)) => (bells, 1, a, b),
                    _ => continue,
                },
            };
            let places = (bells + pb).saturating_sub(pa) as f64;
            gaps.push((strikes[b].t - strikes[a].t) / iv - places);
        }
    }
    (!gaps.is_empty()).then(|| gaps.iter().sum::<f64>() / gaps.len() as f64)
}

/// The handstroke gap read from each bell's own strikes.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Gap {
    /// In intervals between successive bells.
    intervals: f64,
    /// In seconds.
    seconds: f64,
}

/// The handstroke gap from each bell's own strikes (strokes `hand`, time
/// `order`) on `bells` bells. Where a bell's handstroke stands between two
/// backstrokes, its back-to-hand interval less its hand-to-back one is
/// the gap and the places it moved by at each change less each other:
/// nothing in rounds and while it hunts (one place a change), so their
/// median is the gap (backstrokes between handstrokes alike). Each whole
/// pull (hand to hand, over a strike: their mean within 30 % of the
/// median, the places hunted cancelling up and down) is 2 × `bells`
/// intervals and the gap; so the gap and the interval come from the
/// bells' own rhythm, whatever rows were heard whole or their ends (a
/// bell never heard, strikes out of order). Intervals over 1.4 rows (a
/// strike missed) or under half a row are left out. `None` with fewer
/// than [`FEWEST_GAPS`] such differences.
fn gap_by_bells(strikes: &[Timed], order: &[usize], hand: &[Option<bool>], bells: usize) -> Option<Gap> {
    let mine: Vec<Vec<usize>> = (1..=bells)
        .map(|bell| order.iter().copied().filter(|&i| strikes[i].bell == bell).collect())
        .collect();
    let t = |i: usize| strikes[i].t;
    let mut pulls: Vec<f64> = mine
        .iter()
        .flat_map(|m| m.windows(3).map(|w| t(w[2]) - t(w[0])))
        .collect();
    if pulls.is_empty() {
        return None;
    }
    pulls.sort_by(f64::total_cmp);
    let median_pull = pulls[pulls.len() / 2];
    let row = 0.5 * median_pull;
    let mut diffs = vec![];
    for w in mine.iter().flat_map(|m| m.windows(3)) {
        let (before, after) = (t(w[1]) - t(w[0]), t(w[2]) - t(w[1]));
        if [before, after].iter().any(|d| *d < 0.5 * row || *d > MISSED_PULL * row) {
            continue;
        }
        match (hand[w[0]], hand[w[1]], hand[w[2]]) {
            (Some(false), Some(true), Some(false)) => diffs.push(before - after),
            (Some(true), Some(false), Some(true)) => diffs.push(after - before),
            _ => {}
        }
    }
    if diffs.len() < FEWEST_GAPS {
        return None;
    }
    let seconds = crate::median(&diffs);
    let whole: Vec<f64> = pulls
        .iter()
        .copied()
        .filter(|p| (0.7 * median_pull..=1.3 * median_pull).contains(p))
        .collect();
    let pull = whole.iter().sum::<f64>() / whole.len().max(1) as f64;
    let interval = (pull - seconds) / (2 * bells.max(1)) as f64;
    (interval > 0.0).then_some(Gap {
        intervals: seconds / interval,
        seconds,
    })
}

/// The fewest differences of single bells' successive intervals the
/// handstroke gap is read from ([`gap_by_bells`]).
const FEWEST_GAPS: usize = 4;

/// `bell`'s strike times (s), in `order`.
fn times_of(strikes: &[Timed], order: &[usize], bell: usize) -> Vec<f64> {
    order
        .iter()
        .filter(|&&i| strikes[i].bell == bell)
        .map(|&i| strikes[i].t)
        .collect()
}

/// The median time between a bell's successive strikes (s): a row's length.
fn typical_row(strikes: &[Timed], bells: usize, order: &[usize]) -> f64 {
    let mut gaps = vec![];
    for bell in 1..=bells {
        let mine = times_of(strikes, order, bell);
        gaps.extend(mine.windows(2).map(|w| w[1] - w[0]));
    }
    gaps.sort_by(f64::total_cmp);
    gaps.get(gaps.len() / 2).copied().unwrap_or(2.0)
}

/// How many bells the strikes' spacing leaves room for: heard with fewer
/// bells' nominals than ring, each bell still strikes once a row, but the
/// strikes of the bells listened for are as close as the interval between
/// successive bells of the whole ring.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RingRoom {
    /// About how many bells ring: `row_s / interval_s - ½` (a bell strikes
    /// every n + ½ intervals, half the handstroke gap on average).
    pub bells: f64,
    /// The median over bells' strikes of half the time from a strike to
    /// the strike after next (s): a row and half the handstroke gap, which
    /// the median of single intervals, alternately short and long, is not;
    /// those that span a strike missed left out (over 1.4 times the tenth
    /// shortest).
    pub row_s: f64,
    /// The interval between successive bells (s), which bells not listened
    /// for leave as it is: the median of the times between successive
    /// strikes of two different bells that lie within half and one and a
    /// half times their lower quartile (the quartile alone is shortened by
    /// striking errors: a bell's strike early, its neighbour's late).
    pub interval_s: f64,
    /// How loosely those spacings gather about `interval_s`: their
    /// interquartile range over it. Strikes of bells rung in rows, some
    /// left out, gather (0.05-0.20 on rings of recorded bells, four to
    /// six of eight given); strikes timed tens of ms astray scatter over
    /// the window (0.33-0.61 on tester20's fast dark eights, whose
    /// interval then read 57-81 ms for 160), and the room read from them
    /// means nothing.
    pub spread: f64,
}

/// A bell's pull (half the time from a strike to the strike after next)
/// over the bells' tenth-shortest above which it spans a strike missed
/// (such a pull is 1.5 rows or more; a pace that speeds up by a quarter
/// stays under it).
const MISSED_PULL: f64 = 1.4;

/// The room the strikes (any order) leave for bells: `None` with strikes
/// of fewer than two bells, or fewer than three strikes of a bell or eight
/// spacings between different bells.
pub fn ring_room(strikes: &[Timed]) -> Option<RingRoom> {
    let mut order: Vec<usize> = (0..strikes.len()).collect();
    order.sort_by(|&a, &b| strikes[a].t.total_cmp(&strikes[b].t));
    let bells = strikes.iter().map(|s| s.bell).max().unwrap_or(0);
    let with_three = (1..=bells)
        .filter(|&b| strikes.iter().filter(|s| s.bell == b).count() >= 3)
        .count();
    let mut apart: Vec<f64> = order
        .windows(2)
        .filter(|w| strikes[w[0]].bell != strikes[w[1]].bell)
        .map(|w| strikes[w[1]].t - strikes[w[0]].t)
        .collect();
    if with_three < 2 || apart.len() < 8 {
        return None;
    }
    apart.sort_by(f64::total_cmp);
    let quartile = apart[apart.len() / 4];
    let near: Vec<f64> = apart
        .iter()
        .copied()
        .filter(|d| (0.5 * quartile..=1.5 * quartile).contains(d))
        .collect();
    let interval_s = near[near.len() / 2];
    let spread = (near[3 * near.len() / 4] - near[near.len() / 4]) / interval_s.max(f64::MIN_POSITIVE);
    let mut pulls = vec![];
    for bell in 1..=bells {
        let mine = times_of(strikes, &order, bell);
        pulls.extend(mine.windows(3).map(|w| 0.5 * (w[2] - w[0])));
    }
    pulls.sort_by(f64::total_cmp);
    // A pull across a strike missed spans 1.5 rows or more: left out (on
    // 6 bells with one heard at handstroke only the median read 11 bells).
    let least = pulls[pulls.len() / 10];
    let whole: Vec<f64> = pulls.iter().copied().filter(|p| *p <= MISSED_PULL * least).collect();
    let row_s = whole[whole.len() / 2];
    (interval_s > 0.0).then(|| RingRoom {
        bells: row_s / interval_s - 0.5,
        row_s,
        interval_s,
        spread,
    })
}

/// Least-squares line y = a + b x: (a, b); `None` for fewer than two
/// distinct x.
fn line(pts: &[(f64, f64)]) -> Option<(f64, f64)> {
    let n = pts.len() as f64;
    if pts.len() < 2 {
        return None;
    }
    let mx = pts.iter().map(|p| p.0).sum::<f64>() / n;
    let my = pts.iter().map(|p| p.1).sum::<f64>() / n;
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
    if sxx <= 0.0 {
        return None;
    }
    let b = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum::<f64>() / sxx;
    Some((my - b * mx, b))
}

impl Rhythm {
    /// The place errors (s) of `bell`'s strikes at one stroke; `strikes`
    /// are the ones this rhythm was found from, in the same order.
    pub fn stroke_errors(&self, strikes: &[Timed], bell: usize, hand: bool) -> Vec<f64> {
        strikes
            .iter()
            .zip(&self.placed)
            .filter(|(s, p)| s.bell == bell && p.hand == Some(hand))
            .filter_map(|(_, p)| p.error)
            .collect()
    }

    /// `bell`'s odd-struckness (s): its steady handstroke error less its
    /// steady backstroke error (`steady`); `None` without both.
    pub fn odd_struck(&self, strikes: &[Timed], bell: usize) -> Option<f64> {
        let mean = |hand| steady(&self.stroke_errors(strikes, bell, hand)).map(|x| x.mean);
        Some(mean(true)? - mean(false)?)
    }
}

/// A bell's steady error at one stroke: the mean of its errors, leaving
/// out those a strike mistimed in hearing gives. One strike in twelve heard
/// 100 ms off moves a plain mean by 8 ms, as much as the odd-struckness
/// sought (an independent tester's finding: a tenor read -13.9 ms for
/// -1.4 from one backstroke timed 99 ms late). Left out: errors further
/// from the errors' median than four robust standard deviations (1.4826
/// times the median absolute deviation) and than `WILD_S`, so that striking
/// of any real spread (uniform within ±20 ms: a robust sd of 15 ms, a cut
/// at 59 ms) keeps every strike.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Steady {
    /// Mean of the errors kept (s).
    pub mean: f64,
    /// Their standard deviation (s; 0 for one).
    pub sd: f64,
    /// Errors kept.
    pub kept: usize,
    /// Errors left out as mistimed.
    pub left_out: usize,
}

/// No error nearer its bell's median than this (s) is left out as
/// mistimed: about a tenth of a typical interval (220 ms); wider striking
/// widens the cut (four robust standard deviations).
const WILD_S: f64 = 0.025;

/// The steady error of `errors` (s); `None` when empty.
pub fn steady(errors: &[f64]) -> Option<Steady> {
    let mut v = errors.to_vec();
    v.sort_by(f64::total_cmp);
    let mid = |v: &[f64]| match v.len() {
        0 => 0.0,
        n if n % 2 == 1 => v[n / 2],
        n => 0.5 * (v[n / 2 - 1] + v[n / 2]),
    };
    let median = mid(&v);
    let mut dev: Vec<f64> = v.iter().map(|e| (e - median).abs()).collect();
    dev.sort_by(f64::total_cmp);
    let cut = (4.0 * 1.4826 * mid(&dev)).max(WILD_S);
    let kept: Vec<f64> = errors.iter().copied().filter(|e| (e - median).abs() <= cut).collect();
    let (mean, sd) = mean_sd(&kept)?;
    Some(Steady {
        mean,
        sd,
        kept: kept.len(),
        left_out: errors.len() - kept.len(),
    })
}

/// Mean and standard deviation (s) of `v`; `None` when empty (sd 0 for one).
pub fn mean_sd(v: &[f64]) -> Option<(f64, f64)> {
    if v.is_empty() {
        return None;
    }
    let n = v.len() as f64;
    let m = v.iter().sum::<f64>() / n;
    let var = if v.len() > 1 {
        v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (n - 1.0)
    } else {
        0.0
    };
    Some((m, var.sqrt()))
}

#[cfg(test)]
mod tests;
