//! One strike far off its row's rhythm (tester19 fault 4): a strike heard
//! at the wrong time (a false strike, or a bell's strike heard a place
//! early or late) in a row holding every bell once puts the row's later
//! strikes a place out in time order, and a line through the row's times
//! against those places is wrong for every strike of it (ring D
//! `--templates`: errors of +262 ms in a row whose other strikes were timed
//! within 0.01 ms). Such a row is read again without each strike in turn,
//! the rest placed around one empty place; where one strike's leaving
//! leaves the rest in an even rhythm, that strike is far off: left out of
//! the row's line, and placed (in the empty place) only where it lies
//! between that place's neighbours in time.

/// A strike is far off where the row's line misses one of its strikes by
/// more than this share of the row's interval (55 ms in 220 ms intervals:
/// over three times the striking error of most bands); and the row without
/// it must miss none of the rest by as much.
pub(super) const FAR_OFF: f64 = 0.25;

/// The row read again without its far-off strike.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Reread {
    /// The far-off strike: its position in the row's members (time order).
    pub out: usize,
    /// The rest's slots (place − 1), in the members' order without `out`.
    pub slots: Vec<usize>,
    /// The empty slot: `out`'s place less one, where `out` lies between
    /// that slot's neighbours in time; `None` where it does not (heard out
    /// of the row's order: not placed).
    pub hole: Option<usize>,
}

/// What the rows around a row say of where an empty place at its ends
/// is: the time from the last strike of the row before to this row's first,
/// and from this row's last to the next row's first, each in intervals
/// beyond the one interval and the handstroke gap the rhythm puts there
/// (about 1 where the empty place is; `None` where there is no such row).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Ends {
    /// Extra time before the row (intervals).
    pub before: Option<f64>,
    /// Extra time after the row (intervals).
    pub after: Option<f64>,
}

/// The row of `t` (times, time order, s) at `slots` (one each of `bells`
/// places), read again without one far-off strike; `None` where the row's
/// line misses no strike by [`FAR_OFF`] of its interval, or no one strike's
/// leaving evens it. `prev` is each strike's bell's slot in the row before,
/// where known: of the readings that even the row, the one that moves
/// fewest bells more than a place from there is taken (a false strike of
/// the treble just before the second's leaves the same times either way).
pub(super) fn reread(t: &[f64], slots: &[usize], bells: usize, ends: Ends, prev: &[Option<usize>]) -> Option<Reread> {
    let n = t.len();
    // Four strikes left at least, so that a line through them says something.
    if n < 5 || n != bells || prev.len() != n {
        return None;
    }
    let pts: Vec<(f64, f64)> = slots.iter().zip(t).map(|(&p, &y)| (p as f64, y)).collect();
    let (worst, iv) = misfit(&pts)?;
    if worst <= FAR_OFF * iv {
        return None;
    }
    let mut best: Option<((usize, f64), usize, usize)> = None;
    for k in 0..n {
        let rest: Vec<usize> = (0..n).filter(|&j| j != k).collect();
        // Every empty place but the last: the first and last read alike.
        for hole in 0..bells - 1 {
            let pts: Vec<(f64, f64)> = (rest.iter().enumerate())
                .map(|(j, &m)| (at(j, hole) as f64, t[m]))
                .collect();
            let Some((m, iv)) = misfit(&pts) else { continue };
            if m > FAR_OFF * iv || m >= 0.5 * worst {
                continue;
            }
            let hole = match hole {
                0 => end_hole(&rest, prev, bells, ends),
                _ => hole,
            };
            let key = (moved(&rest, prev, hole), m);
            if best.is_none_or(|b| key.0 < b.0 .0 || (key.0 == b.0 .0 && key.1 < b.0 .1)) {
                best = Some((key, k, hole));
            }
        }
    }
    let (_, out, hole) = best?;
    let slots: Vec<usize> = (0..n - 1).map(|j| at(j, hole)).collect();
    // Between the empty place's neighbours in time: placed there.
    let before = (hole > 0).then(|| t[if hole <= out { hole - 1 } else { hole }]);
    let placed = before.is_none_or(|b| b <= t[out]) && {
        let next = (0..n).filter(|&j| j != out).nth(hole);
        next.is_none_or(|j| t[j] >= t[out])
    };
    Some(Reread {
        out,
        slots,
        hole: placed.then_some(hole),
    })
}

/// The slot of the `j`th strike of a row whose slot `hole` is empty.
fn at(j: usize, hole: usize) -> usize {
    if j < hole {
        j
    } else {
        j + 1
    }
}

/// How many of the strikes `rest` (positions in the row) at their slots
/// around the empty `hole` stand more than a place from their bells' slots
/// in the row before (`prev`, where known).
fn moved(rest: &[usize], prev: &[Option<usize>], hole: usize) -> usize {
    (rest.iter().enumerate())
        .filter(|(j, &m)| prev[m].is_some_and(|q| q.abs_diff(at(*j, hole)) > 1))
        .count()
}

/// The empty place of a row evened with its strikes `rest` at either end:
/// the end that moves fewer bells more than a place from the row before,
/// else the one the rows around say (`back_empty`).
fn end_hole(rest: &[usize], prev: &[Option<usize>], bells: usize, ends: Ends) -> usize {
    let (front, back) = (moved(rest, prev, 0), moved(rest, prev, bells - 1));
    match front.cmp(&back) {
        std::cmp::Ordering::Less => 0,
        std::cmp::Ordering::Greater => bells - 1,
        std::cmp::Ordering::Equal if back_empty(ends) => bells - 1,
        std::cmp::Ordering::Equal => 0,
    }
}

/// An empty place at the row's ends is at its back where the time after
/// the row is the longer (beyond what the rhythm puts there), or where
/// only the time on one side is known, where it is long after or short
/// before; at its front otherwise.
fn back_empty(ends: Ends) -> bool {
    match (ends.before, ends.after) {
        (Some(b), Some(a)) => a > b,
        (None, Some(a)) => a > 0.5,
        (Some(b), None) => b < 0.5,
        (None, None) => false,
    }
}

/// The largest miss (s) of the least-squares line through `pts` (place,
/// time) and the line's interval (s per place); `None` without a line.
fn misfit(pts: &[(f64, f64)]) -> Option<(f64, f64)> {
    let (a, b) = super::line(pts)?;
    let worst = pts.iter().map(|&(x, y)| (y - a - b * x).abs()).fold(0.0, f64::max);
    (b > 0.0).then_some((worst, b))
}

#[cfg(test)]
mod tests {
    use super::*;

    const NONE: Ends = Ends {
        before: None,
        after: None,
    };

    #[test]
    fn an_even_row_is_left_as_it_is() {
        let t: Vec<f64> = (0..8)
            .map(|p| 1.0 + 0.2 * p as f64 + 0.01 * ((p * 7) % 3) as f64)
            .collect();
        assert_eq!(reread(&t, &(0..8).collect::<Vec<_>>(), 8, NONE, &[None; 8]), None);
    }

    #[test]
    fn a_false_strike_before_a_row_with_one_strike_missed_is_taken_out() {
        // Tester19's ring D row: a false strike of bell 7 37 ms before the
        // row's first (bell 3's), bell 7's strike in fifth place not heard.
        // By their times alone bell 3's strike could as well be the false
        // one; bell 7 was sixth in the row before, bell 3 second.
        let t = [21.195, 21.232, 21.4, 21.611, 21.802, 22.201, 22.396, 22.602];
        let mut prev = [None; 8];
        (prev[0], prev[1]) = (Some(5), Some(1));
        let r = reread(&t, &(0..8).collect::<Vec<_>>(), 8, NONE, &prev).expect("reread");
        assert_eq!(r.out, 0);
        assert_eq!(r.slots, vec![0, 1, 2, 3, 5, 6, 7]);
        assert_eq!(r.hole, None, "the false strike is out of the row's order: not placed");
    }

    #[test]
    fn a_strike_far_late_keeps_its_place() {
        let mut t: Vec<f64> = (0..6).map(|p| 2.0 + 0.22 * p as f64).collect();
        t[3] += 0.15;
        let r = reread(&t, &(0..6).collect::<Vec<_>>(), 6, NONE, &[None; 6]).expect("reread");
        assert_eq!((r.out, r.hole), (3, Some(3)));
        assert_eq!(r.slots, vec![0, 1, 2, 4, 5]);
    }

    #[test]
    fn a_place_empty_at_the_front_is_told_from_the_back_by_the_rows_around() {
        // A false strike among the back bells, the first place's not heard.
        let mut t: Vec<f64> = (1..6).map(|p| 4.0 + 0.22 * p as f64).collect();
        t.insert(4, t[3] + 0.014);
        let front = Ends {
            before: Some(1.0),
            after: Some(0.0),
        };
        let r = reread(&t, &(0..6).collect::<Vec<_>>(), 6, front, &[None; 6]).expect("reread");
        assert_eq!(r.out, 4);
        assert_eq!(r.slots, vec![1, 2, 3, 4, 5]);
        let back = Ends {
            before: Some(0.0),
            after: Some(1.0),
        };
        let r = reread(&t, &(0..6).collect::<Vec<_>>(), 6, back, &[None; 6]).expect("reread");
        assert_eq!(r.slots, vec![0, 1, 2, 3, 4]);
        assert_eq!(r.hole, None);
    }
}
