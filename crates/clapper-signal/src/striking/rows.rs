//! Rows found as the best split of the strikes in time order into runs of
//! about one strike per bell, alternately handstroke and backstroke
//! (docs/strikes.md, "Rows in methods").
//!
//! A bell's own alternating intervals say its strokes only while it keeps
//! to its places: a bell that dodges (places p, p+1, p, p+1, as Stedman's
//! and Plain Bob's bells do for rows on end) has its hand-to-back interval
//! the longer one, and reads the wrong way round. The ring as a whole does
//! not: every backstroke row is followed by the handstroke gap. And a row
//! split at each change of stroke lost one strike or gained one, every row
//! after was numbered one more. So the rows are chosen together, by
//! dynamic programming over where each row starts, costing what a real
//! touch would not do: a row of more or fewer strikes than bells heard, a
//! bell twice in a row, a row's lead not what its stroke makes it (the
//! handstroke gap before a handstroke, a plain interval before a
//! backstroke), and the bells' own stroke votes against the row's.

/// What the split is given: strikes in time order.
pub(super) struct Sequence<'a> {
    /// Onsets (s), ascending.
    pub t: &'a [f64],
    /// Each strike's bell (from 1).
    pub bell: &'a [usize],
    /// Each strike's stroke as its own bell's intervals say (true: hand).
    pub vote: &'a [Option<bool>],
}

/// What a touch costs, in units of a badly timed row lead.
#[derive(Clone, Copy, Debug)]
pub(super) struct Costs {
    /// Strikes per row: the bells heard.
    pub bells: usize,
    /// Of those, how many a row may lack: bells heard at one stroke only.
    pub optional: usize,
    /// Places per row: the bells listened for (a bell never heard leaves
    /// its place empty in every row).
    pub places: usize,
    /// Interval between successive bells (s).
    pub interval: f64,
    /// The handstroke gap (intervals); 0 when none stands out.
    pub gap: f64,
}

/// One row: strikes `start..end` of the sequence, and its stroke.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Row {
    /// First strike (index into the sequence).
    pub start: usize,
    /// One past the last strike.
    pub end: usize,
    /// Handstroke (else backstroke).
    pub hand: bool,
}

// A row one strike short or long costs less than a lead a gap off (the
// gap is the surer sign); a bell twice more than a strike moved over a
// back row's boundary costs in size (a row of one bell too many and one
// too few, or a lead one interval long: a strike lost and a false one are
// both kept where they are); a
// bell's own vote, a little (dodging bells vote wrong for rows on end).
const SIZE: f64 = 1.5;
const TWICE: f64 = 6.0;
const VOTE: f64 = 0.6;
// The spread of a row's lead (intervals) in fair striking.
const LEAD_SD: f64 = 0.35;
// A lead costs at most this much: a strike missed before a row.
const LEAD_CAP: f64 = 9.0;

/// The best split of `seq` into rows under `c`. Every strike is in one row.
pub(super) fn split(seq: &Sequence, c: &Costs) -> Vec<Row> {
    split_priced(seq, c, 0.0)
}

// Each row priced at most this much more (units of a badly timed lead) to
// bring the split down to the rows the ringing's length holds: past it,
// rows cost more than any strike's misplacing, and the split is kept.
const ROW_PRICE_MAX: f64 = 40.0;

/// The best split of `seq` under `c` in at most `most` rows, where one
/// within [`ROW_PRICE_MAX`] a row is found; else the best split. Strikes
/// timed tens of ms off (tester18's fast ring with `--nominals`, 74-77
/// rows read for 72) cost less split half a row out at some stretch than
/// in their rows, and every row after it then took the other stroke:
/// each row priced alike (the least price that does: bisection) makes the
/// split that ringing of that length can hold.
pub(super) fn split_at_most(seq: &Sequence, c: &Costs, most: usize) -> Vec<Row> {
    let free = split(seq, c);
    if free.len() <= most || most == 0 {
        return free;
    }
    let mut hi = split_priced(seq, c, ROW_PRICE_MAX);
    if hi.len() > most {
        return free;
    }
    let (mut lo_price, mut hi_price) = (0.0, ROW_PRICE_MAX);
    // Rows fall as the price rises; 12 halvings leave it within 0.01.
    for _ in 0..12 {
        let mid = 0.5 * (lo_price + hi_price);
        let rows = split_priced(seq, c, mid);
        if rows.len() <= most {
            (hi, hi_price) = (rows, mid);
        } else {
            lo_price = mid;
        }
    }
    hi
}

/// [`split`], each row costing `per_row` more.
fn split_priced(seq: &Sequence, c: &Costs, per_row: f64) -> Vec<Row> {
    let n = seq.t.len();
    if n == 0 || c.bells == 0 {
        return vec![];
    }
    let longest = c.bells + 2;
    let pace = paces(seq, c);
    // best[i][s]: the least cost of rows covering strikes ..i, the next row
    // of stroke s (0 back, 1 hand); from[i][s]: where the last row began.
    let mut best = vec![[f64::INFINITY; 2]; n + 1];
    let mut from = vec![[usize::MAX; 2]; n + 1];
    best[0] = [0.0, 0.0];
    for i in 0..n {
        for s in 0..2 {
            if !best[i][s].is_finite() {
                continue;
            }
            for end in i + 1..=(i + longest).min(n) {
                let cost = best[i][s] + row_cost(seq, c, pace[i], i, end, s == 1) + per_row;
                let next = 1 - s;
                if cost < best[end][next] {
                    best[end][next] = cost;
                    from[end][next] = i;
                }
            }
        }
    }
    let mut s = if best[n][0] <= best[n][1] { 0 } else { 1 };
    let mut end = n;
    let mut rows = vec![];
    // Each step moves back at least one strike: bounded by n.
    while end > 0 {
        let start = from[end][s];
        rows.push(Row {
            start,
            end,
            hand: s == 0,
        });
        end = start;
        s = 1 - s;
    }
    rows.reverse();
    rows
}

// The interval about a strike may stand off the whole recording's by this
// share (of it) before the local one is used: a band's pace wanders less,
// ringing up and down strikes 1.6 times slower (where every interval read
// as a strike lost, and the first two rows were split in three).
const PACE_OFF: f64 = 0.15;

/// The interval between successive bells (s) about each strike of `seq`:
/// the whole recording's (`c.interval`) unless the strikes within a row
/// and a half either side keep an interval over [`PACE_OFF`] off it, read
/// as `ring_room` reads one (the median of the spacings of different bells
/// near their lower quartile: strikes lost leave it as it is).
fn paces(seq: &Sequence, c: &Costs) -> Vec<f64> {
    let n = seq.t.len();
    let span = (3 * c.bells / 2).max(4);
    (0..n)
        .map(|i| {
            let (lo, hi) = (i.saturating_sub(span), (i + span).min(n - 1));
            let mut apart: Vec<f64> = (lo..hi)
                .filter(|&k| seq.bell[k] != seq.bell[k + 1])
                .map(|k| seq.t[k + 1] - seq.t[k])
                .collect();
            if apart.len() < 8 || c.interval <= 0.0 {
                return c.interval;
            }
            apart.sort_by(f64::total_cmp);
            let q = apart[apart.len() / 4];
            let near: Vec<f64> = apart.into_iter().filter(|d| (0.5 * q..=1.5 * q).contains(d)).collect();
            let local = near.get(near.len() / 2).copied().unwrap_or(c.interval);
            if (local / c.interval - 1.0).abs() > PACE_OFF && local > 0.0 {
                local
            } else {
                c.interval
            }
        })
        .collect()
}

/// What the row of strikes `i..end` of stroke `hand` costs, bells
/// `interval` (s) apart about it.
fn row_cost(seq: &Sequence, c: &Costs, interval: f64, i: usize, end: usize, hand: bool) -> f64 {
    // The places the row spans: its strikes, and a place for each of its
    // intervals about twice the plain one (a strike lost inside it). A
    // row of strikes spanning one place too many is a row with a strike of
    // the next (which the count alone cannot tell from the truth where
    // the lost strike was that bell's).
    let holes: usize = if interval > 0.0 {
        seq.t[i..end]
            .windows(2)
            .map(|w| (w[1] - w[0]) / interval)
            .filter(|&x| x > 1.6)
            .map(|x| (x.round() as usize).saturating_sub(1).min(c.bells))
            .sum()
    } else {
        0
    };
    let spans = end - i + holes;
    // A row cut by the recording's start or end costs as a row short of
    // strikes does: it is one whatever the split, and a discount there let
    // a false strike before the first row stand as a row of its own.
    let (lo, hi) = (c.bells - c.optional.min(c.bells), c.places.max(c.bells));
    let size = SIZE * (lo.saturating_sub(spans) + spans.saturating_sub(hi) + holes.saturating_sub(hi - lo)) as f64;
    let mut seen = [0u64; 4];
    let mut twice = 0;
    for &b in &seq.bell[i..end] {
        let (w, m) = (b / 64 % 4, 1u64 << (b % 64));
        if seen[w] & m != 0 {
            twice += 1;
        }
        seen[w] |= m;
    }
    let lead = if i > 0 && interval > 0.0 {
        let x = (seq.t[i] - seq.t[i - 1]) / interval;
        let expect = 1.0 + if hand { c.gap } else { 0.0 };
        // One interval longer: a strike lost at the row's end or start.
        let plain = ((x - expect) / LEAD_SD).powi(2);
        let one_lost = ((x - expect - 1.0) / LEAD_SD).powi(2) + SIZE;
        plain.min(one_lost).min(LEAD_CAP)
    } else {
        0.0
    };
    let against = seq.vote[i..end].iter().filter(|v| **v == Some(!hand)).count();
    size + TWICE * twice as f64 + lead + VOTE * against as f64
}

/// How many rows the bells' own strikes span: each bell's strikes, `times`
/// (s, ascending; one list per bell), step a row each, two across a
/// strike lost, none for a false one half a row from its neighbour (each
/// interval over the bells' typical one, rounded), and the bell that
/// spans most says. Unlike the time over an interval read from strikes
/// of different bells ([`rows_the_time_holds`]), a bell's whole offset (a
/// lateness learned wrong: tester18's fast ring with `--nominals`, 74
/// rows read for 72) does not move it. `None` with no bell struck thrice.
pub(super) fn rows_the_bells_span(times: &[Vec<f64>]) -> Option<usize> {
    let median = |mut v: Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v.get(v.len() / 2).copied()
    };
    let each: Vec<f64> = (times.iter().filter(|t| t.len() >= 3))
        .filter_map(|t| median(t.windows(2).map(|w| w[1] - w[0]).collect()))
        .collect();
    // A bell heard at one stroke only steps two rows a strike: the
    // bells' median keeps to one.
    let row = median(each).filter(|r| *r > 0.0)?;
    (times.iter().filter(|t| t.len() >= 3))
        .map(|t| {
            1 + t
                .windows(2)
                .map(|w| ((w[1] - w[0]) / row).round() as usize)
                .sum::<usize>()
        })
        .max()
}

/// Rows found beyond those the ringing's length holds by more than this
/// are rows split half a row out somewhere (tester 17's S6, `--bells 6`:
/// 84 rows read for 82, eight of them on the wrong stroke). Strikes
/// missing at the ends make fewer rows, never more.
pub const ROWS_OVER: f64 = 1.5;

/// About how many rows the ringing of `strikes` (any order) holds, `bells`
/// a row: from the first strike to the last, less a row's own span
/// (`bells` − 1 intervals), over the time a row takes with half the
/// handstroke gap (`bells` + ½ intervals, the interval
/// [`super::ring_room`]'s), plus one. (The room's own row, read from each
/// bell's pulls, is a place long where bells hunt: 37 rows for 40.)
/// `None` where the room says nothing.
pub fn rows_the_time_holds(strikes: &[super::Timed], bells: usize) -> Option<f64> {
    let iv = super::ring_room(strikes)?.interval_s;
    let first = strikes.iter().map(|s| s.t).fold(f64::INFINITY, f64::min);
    let last = strikes.iter().map(|s| s.t).fold(f64::NEG_INFINITY, f64::max);
    let span = last - first - bells.saturating_sub(1) as f64 * iv;
    let row = (bells as f64 + 0.5) * iv;
    (row > 0.0 && span.is_finite()).then(|| span.max(0.0) / row + 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Rows of `bells` in rounds, interval 0.2 s, gap 1 before handstrokes.
    fn rounds(rows: usize, bells: usize) -> (Vec<f64>, Vec<usize>, Vec<bool>) {
        let (mut t, mut b, mut h) = (vec![], vec![], vec![]);
        let mut now = 0.0;
        for r in 0..rows {
            let hand = r % 2 == 0;
            if hand && r > 0 {
                now += 0.2;
            }
            for bell in 1..=bells {
                now += 0.2;
                t.push(now);
                b.push(bell);
                h.push(hand);
            }
        }
        (t, b, h)
    }

    /// `split` of every bell of `bells` heard, 0.2 s apart, gap 1.
    fn split_every(t: &[f64], bell: &[usize], vote: &[Option<bool>], bells: usize) -> Vec<Row> {
        let c = Costs {
            bells,
            optional: 0,
            places: bells,
            interval: 0.2,
            gap: 1.0,
        };
        split(&Sequence { t, bell, vote }, &c)
    }

    #[test]
    fn a_strike_lost_and_one_gained_cost_their_rows_not_the_numbers_after() {
        let (mut t, mut b, _) = rounds(20, 8);
        // Row 6 loses bell 8; row 7 gains a false bell 8 at bell 3's blow.
        let lost = 6 * 8 + 7;
        let at = 7 * 8 + 2;
        t.insert(at + 1, t[at] + 0.001);
        b.insert(at + 1, 8);
        t.remove(lost);
        b.remove(lost);
        // No votes: the rows come from the gap and the bells alone.
        let rows = split_every(&t, &b, &vec![None; t.len()], 8);
        assert_eq!(rows.len(), 20, "{rows:?}");
        assert!(rows.iter().enumerate().all(|(r, row)| row.hand == (r % 2 == 0)));
        assert_eq!(rows[6].end - rows[6].start, 7);
        assert_eq!(rows[7].end - rows[7].start, 9);
        assert_eq!(rows[19].end, t.len());
    }

    #[test]
    fn rows_rung_up_slower_are_not_split_for_strikes_lost() {
        // Ringing up (tester15 A8_updown): the first 6 rows 1.6 times
        // slower than the 0.2 s of the rest, which read as a strike lost
        // at every interval, and the first two rows were split in three.
        let (mut t, b, h) = rounds(30, 8);
        let slow = 6 * 8;
        let stretch = 0.6 * t[slow];
        for (k, x) in t.iter_mut().enumerate() {
            *x = if k < slow { 1.6 * *x } else { *x + stretch };
        }
        let rows = split_every(&t, &b, &vec![None; t.len()], 8);
        assert_eq!(rows.len(), 30, "{rows:?}");
        for row in &rows {
            assert_eq!(row.end - row.start, 8, "{rows:?}");
            assert!(h[row.start..row.end].iter().all(|&x| x == row.hand), "{rows:?}");
        }
    }

    #[test]
    fn a_bell_voting_the_wrong_stroke_for_rows_on_end_is_outvoted_by_the_gap() {
        let (t, b, h) = rounds(16, 10);
        let vote: Vec<Option<bool>> = b
            .iter()
            .zip(&h)
            .map(|(&bell, &hand)| Some(hand != (bell == 6)))
            .collect();
        let rows = split_every(&t, &b, &vote, 10);
        assert_eq!(rows.len(), 16);
        for row in &rows {
            assert_eq!(row.end - row.start, 10);
            assert!(h[row.start..row.end].iter().all(|&x| x == row.hand));
        }
    }

    /// Tester18's fast ring with `--nominals`: each bell timed wrong by its
    /// own offset (a lateness learned wrong, up to half an interval),
    /// strikes lost and one false strike between rows; its bells still
    /// count the 72 rows rung.
    #[test]
    fn the_rows_are_counted_by_the_bells_whatever_their_offsets() {
        let (t, b, _) = rounds(72, 6);
        let off = [0.06, 0.0, 0.09, -0.02, 0.07, 0.04];
        let mut times = vec![vec![]; 6];
        for (k, (&t, &bell)) in t.iter().zip(&b).enumerate() {
            if k % 9 != 4 {
                times[bell - 1].push(t + off[bell - 1]);
            }
        }
        times[2].push(5.0 + 0.55);
        times[2].sort_by(f64::total_cmp);
        assert_eq!(rows_the_bells_span(&times), Some(72));
        // Bell 5 heard at handstroke only: the others keep the count.
        times[4].retain(|x| ((x - 0.07) / 2.6).fract() < 0.5);
        assert_eq!(rows_the_bells_span(&times), Some(72));
    }

    /// Forty rows of eight in rounds hold forty rows by their length, to
    /// within the slack a slip of rows must pass ([`ROWS_OVER`]), with
    /// strikes lost here and there too; a split of 42 rows would be warned.
    #[test]
    fn the_rows_a_ringing_holds_are_counted_from_its_length() {
        let (t, b, _) = rounds(40, 8);
        let all: Vec<super::super::Timed> = t
            .iter()
            .zip(&b)
            .map(|(&t, &bell)| super::super::Timed { bell, t })
            .collect();
        let held = rows_the_time_holds(&all, 8).unwrap_or(0.0);
        assert!((held - 40.0).abs() < 0.5, "{held}");
        let lost: Vec<super::super::Timed> = all
            .iter()
            .copied()
            .enumerate()
            .filter(|(k, _)| k % 7 != 3)
            .map(|x| x.1)
            .collect();
        let held = rows_the_time_holds(&lost, 8).unwrap_or(0.0);
        assert!((held - 40.0).abs() < 0.5, "{held}");
        assert!(42.0 > held + ROWS_OVER);
    }
}
