//! The rhythm's tests: strikes of synthetic towers (`crate::tower`) with
//! known truth placed again.

use super::*;
use crate::tower::{tower_strikes, Method, PlainCourse, RingBell, TowerSpec, Variation};

fn spec(method: Method) -> TowerSpec {
    TowerSpec {
        rate: 8000.0,
        bells: (0..6)
            .map(|i| RingBell {
                nominal_hz: 1000.0 - 50.0 * i as f64,
                mass_kg: 200.0,
                odd_struck_ms: if i == 2 { 20.0 } else { 0.0 },
            })
            .collect(),
        rows: 60,
        interval: 0.2,
        handstroke_gap: 1.0,
        jitter: 0.01,
        seed: 4,
        doubles: vec![],
        lead_in: 0.5,
        tail: 1.0,
        method,
        variation: Variation::NONE,
        room: None,
        snr_db: None,
        doublets: None,
        swing: None,
        voice: crate::tower::Voice::Tower,
        noise: crate::tower::Noise::White,
        attack: None,
    }
}

#[test]
fn strokes_rows_places_and_odd_struckness_come_back_from_the_times() {
    for method in [Method::Rounds, Method::PlainHunt] {
        let truth = tower_strikes(&spec(method)).unwrap();
        let timed: Vec<Timed> = truth.iter().map(|s| Timed { bell: s.bell, t: s.t }).collect();
        let r = rhythm(&timed, 6);
        assert!(r.strokes_known);
        assert_eq!((r.rows, r.full_rows), (60, 60), "{method:?}");
        for (s, p) in truth.iter().zip(&r.placed) {
            assert_eq!(p.hand, Some(s.hand));
            assert_eq!(p.row, Some(s.row));
            assert_eq!(p.place, Some(s.place));
        }
        assert!((r.interval.unwrap() - 0.2).abs() < 0.002);
        assert!((r.handstroke_gap.unwrap() - 1.0).abs() < 0.05, "{:?}", r.handstroke_gap);
        // Bell 3 planted 20 ms odd-struck.
        let odd = r.odd_struck(&timed, 3).unwrap() * 1e3;
        assert!((odd - 20.0).abs() < 3.0, "{method:?}: odd-struck {odd} ms");
    }
}

/// An independent tester's case (issue 43): rounds of six struck with
/// errors of sd 3 ms, bell 3 25 ms odd-struck, read from the true
/// times themselves. With the row's line through the others' times as
/// they were, bell 3 lent the treble -12.9 ms of odd-struckness; the
/// acceptance asks bell 3 within 6 ms of 25 and the others within 8 ms
/// of none.
#[test]
fn one_bells_odd_struckness_is_not_lent_to_the_others() {
    for (method, seed) in [
        (Method::Rounds, 1),
        (Method::Rounds, 2),
        (Method::PlainHunt, 3),
        (Method::PlainHunt, 4),
    ] {
        let mut s = spec(method);
        s.rows = 24;
        s.jitter = 0.003 * 3f64.sqrt();
        s.seed = seed;
        s.bells[2].odd_struck_ms = 25.0;
        let truth = tower_strikes(&s).unwrap();
        let timed: Vec<Timed> = truth.iter().map(|s| Timed { bell: s.bell, t: s.t }).collect();
        let r = rhythm(&timed, 6);
        assert_eq!(r.full_rows, 24, "{method:?}");
        for bell in 1..=6 {
            let odd = r.odd_struck(&timed, bell).unwrap() * 1e3;
            let (want, within) = if bell == 3 { (25.0, 6.0) } else { (0.0, 4.0) };
            assert!(
                (odd - want).abs() < within,
                "{method:?} seed {seed}: bell {bell} odd-struck {odd:.1} ms"
            );
        }
    }
}

/// The tester's Stedman case in small: one of the tenor's backstrokes
/// heard 99 ms late reads as a tenor odd-struck by -8 ms with plain
/// means; its steady errors leave that strike out.
#[test]
fn one_strike_heard_far_off_does_not_make_a_bell_odd_struck() {
    let mut s = spec(Method::PlainHunt);
    s.rows = 24;
    s.jitter = 0.003 * 3f64.sqrt();
    s.bells[2].odd_struck_ms = 0.0;
    let truth = tower_strikes(&s).unwrap();
    let mut timed: Vec<Timed> = truth.iter().map(|s| Timed { bell: s.bell, t: s.t }).collect();
    let before = rhythm(&timed, 6).odd_struck(&timed, 6).unwrap();
    let k = truth
        .iter()
        .position(|x| x.bell == 6 && !x.hand && x.row == 11)
        .unwrap();
    timed[k].t += 0.099;
    let r = rhythm(&timed, 6);
    let after = r.odd_struck(&timed, 6).unwrap();
    assert!(
        (after - before).abs() < 0.002,
        "tenor {:.1} ms, {:.1} before",
        after * 1e3,
        before * 1e3
    );
    for bell in 1..=5 {
        assert!(r.odd_struck(&timed, bell).unwrap().abs() < 0.004, "bell {bell}");
    }
}

#[test]
fn a_strike_heard_far_off_does_not_move_the_steady_error() {
    let mut e: Vec<f64> = (0..12).map(|i| 0.003 * ((i * 7 % 5) as f64 - 2.0)).collect();
    let plain = mean_sd(&e).unwrap().0;
    e[4] = 0.099;
    let s = steady(&e).unwrap();
    assert_eq!((s.kept, s.left_out), (11, 1));
    assert!((s.mean - plain).abs() < 0.001, "{} against {plain}", s.mean);
    // Striking uniform within ±20 ms keeps every strike.
    let wide: Vec<f64> = (0..12).map(|i| -0.02 + 0.04 * i as f64 / 11.0).collect();
    assert_eq!(steady(&wide).unwrap().left_out, 0);
}

#[test]
fn a_missing_strike_costs_its_row_not_the_labels() {
    let truth = tower_strikes(&spec(Method::PlainHunt)).unwrap();
    let mut timed: Vec<Timed> = truth.iter().map(|s| Timed { bell: s.bell, t: s.t }).collect();
    let gone = timed.remove(100);
    let r = rhythm(&timed, 6);
    let kept: Vec<_> = truth
        .iter()
        .filter(|s| !(s.bell == gone.bell && s.t == gone.t))
        .collect();
    let right = kept
        .iter()
        .zip(&r.placed)
        .filter(|(s, p)| p.hand == Some(s.hand))
        .count();
    assert!(right >= kept.len() - 1, "{right} of {}", kept.len());
    assert_eq!(r.full_rows, 59);
}

/// Every strike's stroke, row and place as the truth's.
fn assert_placed_as(truth: &[crate::tower::TrueStrike], r: &Rhythm, what: &str) {
    let wrong: Vec<_> = truth
        .iter()
        .zip(&r.placed)
        .filter(|(s, p)| p.hand != Some(s.hand) || p.row != Some(s.row) || p.place != Some(s.place))
        .map(|(s, p)| (s.bell, s.row, s.place, s.hand, *p))
        .collect();
    assert!(
        wrong.is_empty(),
        "{what}: {} wrong, first {:?}",
        wrong.len(),
        wrong.first()
    );
}

/// Bells that dodge (Plain Bob's lead ends, Stedman's sixes) have their
/// hand-to-back interval the longer for rows on end and read the wrong
/// way round on their own; the rows are read from the ring's handstroke
/// gap.
#[test]
fn methods_rows_come_back_though_their_bells_dodge() {
    use crate::methods::PlainCourse;
    for course in [PlainCourse::PlainBob, PlainCourse::Grandsire, PlainCourse::Stedman] {
        let truth = tower_strikes(&spec(Method::Course(course))).unwrap();
        let timed: Vec<Timed> = truth.iter().map(|s| Timed { bell: s.bell, t: s.t }).collect();
        let r = rhythm(&timed, 6);
        assert_eq!((r.rows, r.full_rows), (60, 60), "{course:?}");
        assert_placed_as(&truth, &r, course.name());
        let odd = r.odd_struck(&timed, 3).unwrap() * 1e3;
        assert!((odd - 20.0).abs() < 3.0, "{course:?}: odd-struck {odd} ms");
    }
}

/// Stedman on ten bells with one strike in 23 lost: each bell's own
/// votes, in short runs between its lost strikes, read dodges as the
/// other stroke, and each lost strike had cut its row in two; the
/// rows' strokes and numbers now come from the ring.
#[test]
fn stedman_on_ten_with_strikes_lost_keeps_its_strokes_and_rows() {
    use crate::methods::PlainCourse;
    let mut sp = spec(Method::Course(PlainCourse::Stedman));
    sp.bells = (0..10)
        .map(|i| RingBell {
            nominal_hz: 1000.0 - 40.0 * i as f64,
            mass_kg: 200.0,
            odd_struck_ms: if i == 2 { 20.0 } else { 0.0 },
        })
        .collect();
    sp.rows = 120;
    let truth = tower_strikes(&sp).unwrap();
    let kept: Vec<_> = truth
        .iter()
        .enumerate()
        .filter(|(k, _)| k % 23 != 5)
        .map(|(_, s)| *s)
        .collect();
    let timed: Vec<Timed> = kept.iter().map(|s| Timed { bell: s.bell, t: s.t }).collect();
    let r = rhythm(&timed, 10);
    let wrong = kept
        .iter()
        .zip(&r.placed)
        .filter(|(s, p)| p.hand != Some(s.hand) || p.row != Some(s.row))
        .count();
    // A strike lost at a handstroke row's lead leaves the next row's
    // first strike as likely its own (bell 6 at 27.71 s here): that
    // strike only.
    assert!(wrong <= 2, "{wrong} of {} strikes in the wrong row", kept.len());
    assert_eq!(r.rows, 120);
}

/// A strike lost in one row and a false one in the next cost those
/// rows, not the numbers of every row after.
#[test]
fn a_lost_strike_and_a_false_one_do_not_renumber_the_rows_after() {
    let truth = tower_strikes(&spec(Method::PlainHunt)).unwrap();
    let mut timed: Vec<Timed> = truth.iter().map(|s| Timed { bell: s.bell, t: s.t }).collect();
    // Row 20's last strike lost; a false strike of that bell at row
    // 21's third.
    let last = truth.iter().position(|s| s.row == 20 && s.place == 6).unwrap();
    let third = truth.iter().position(|s| s.row == 21 && s.place == 3).unwrap();
    timed[last].t = timed[third].t + 0.002;
    let r = rhythm(&timed, 6);
    assert_eq!(r.rows, 60);
    for (s, p) in truth.iter().zip(&r.placed).filter(|(s, _)| s.row >= 22) {
        assert_eq!(p.row, Some(s.row), "{s:?}");
        assert_eq!(p.place, Some(s.place), "{s:?}");
    }
    assert_eq!(r.full_rows, 59, "row 21 placed without its false strike");
}

/// One bell of six never heard: the rows of the other five are placed
/// around its place, and their odd-struckness read.
#[test]
fn a_bell_never_heard_is_placed_around() {
    for method in [Method::Rounds, Method::PlainHunt] {
        let truth: Vec<_> = tower_strikes(&spec(method))
            .unwrap()
            .into_iter()
            .filter(|s| s.bell != 5)
            .collect();
        let timed: Vec<Timed> = truth.iter().map(|s| Timed { bell: s.bell, t: s.t }).collect();
        let r = rhythm(&timed, 6);
        // Placed around bell 5's empty place, but none is full.
        assert_eq!((r.placed_rows, r.full_rows), (60, 0), "{method:?}");
        let placed = truth
            .iter()
            .zip(&r.placed)
            .filter(|(s, p)| p.place == Some(s.place) && p.row == Some(s.row))
            .count();
        // Where bell 5 leads or lies, which end it is at is a guess.
        assert!(
            placed * 10 >= truth.len() * 9,
            "{method:?}: {placed} of {}",
            truth.len()
        );
        let odd = r.odd_struck(&timed, 3).unwrap() * 1e3;
        assert!((odd - 20.0).abs() < 3.0, "{method:?}: odd-struck {odd} ms");
    }
}

/// Tester20 fault 8: the handstroke gap read 2.3-3.3 intervals on fast
/// eights (true 1), from the ends of rows lacking a bell or with strikes
/// out of order. Read from each bell's own strikes, it is the gap rung,
/// with the tenor never heard (each row's last place empty), in rounds,
/// plain hunt and Plain Bob, and at gaps of half an interval to two.
#[test]
fn the_handstroke_gap_is_each_bells_own() {
    for method in [Method::Rounds, Method::PlainHunt, Method::Course(PlainCourse::PlainBob)] {
        for gap in [0.5, 1.0, 2.0] {
            let mut s = spec(method);
            s.handstroke_gap = gap;
            s.bells[2].odd_struck_ms = 0.0;
            let timed: Vec<Timed> = (tower_strikes(&s).unwrap().iter())
                .filter(|x| x.bell != 6)
                .map(|x| Timed { bell: x.bell, t: x.t })
                .collect();
            let r = rhythm(&timed, 6);
            let read = r.handstroke_gap.unwrap_or(f64::NAN);
            assert!((read - gap).abs() < 0.1, "{method:?} gap {gap}: read {read}");
            let ms = r.handstroke_gap_s.unwrap_or(f64::NAN) * 1e3;
            assert!((ms - gap * 200.0).abs() < 20.0, "{method:?} gap {gap}: {ms} ms");
        }
    }
}

/// Tester16 fault 3: one bell silent at every backstroke (a bell
/// heard at one stroke only). Its strikes two rows apart are not a
/// handstroke gap of two intervals; the other bells' rows, strokes and
/// odd-struckness come from the bells heard at both strokes.
#[test]
fn a_bell_silent_at_backstroke_does_not_make_the_gap() {
    for method in [Method::Rounds, Method::PlainHunt] {
        let truth: Vec<_> = tower_strikes(&spec(method))
            .unwrap()
            .into_iter()
            .filter(|s| s.bell != 5 || s.hand)
            .collect();
        let timed: Vec<Timed> = truth.iter().map(|s| Timed { bell: s.bell, t: s.t }).collect();
        let r = rhythm(&timed, 6);
        // Tester18 fault 6: "60 rows (60 full)" where bell 5 is
        // missing from 30: its backstroke rows are placed, not full.
        assert_eq!((r.rows, r.placed_rows, r.full_rows), (60, 60, 30), "{method:?}");
        let gap = r.handstroke_gap.unwrap_or(f64::NAN);
        assert!((gap - 1.0).abs() < 0.1, "{method:?}: gap {gap}");
        let right = truth
            .iter()
            .zip(&r.placed)
            .filter(|(s, p)| p.hand == Some(s.hand))
            .count();
        assert_eq!(right, truth.len(), "{method:?}");
        let odd = r.odd_struck(&timed, 3).unwrap() * 1e3;
        assert!((odd - 20.0).abs() < 3.0, "{method:?}: odd-struck {odd} ms");
        for bell in [1, 2, 4, 6] {
            let odd = r.odd_struck(&timed, bell).unwrap() * 1e3;
            assert!(odd.abs() < 4.0, "{method:?}: bell {bell} odd-struck {odd} ms");
        }
    }
}

/// Tester21's G8 `--templates`: a bell quieter at backstroke heard at some
/// of its backstrokes (16 of 61) was neither heard at one stroke only nor
/// at both: the rows lacking it were left unplaced (places right 1.00 ->
/// 0.60). Heard mostly at one stroke, its rows may lack it.
#[test]
fn a_bell_heard_at_a_few_of_its_backstrokes_leaves_their_rows_placed() {
    for method in [Method::Rounds, Method::PlainHunt] {
        let mut back = 0;
        let truth: Vec<_> = tower_strikes(&spec(method))
            .unwrap()
            .into_iter()
            .filter(|s| {
                if s.bell != 5 || s.hand {
                    return true;
                }
                back += 1;
                back % 4 == 0
            })
            .collect();
        let timed: Vec<Timed> = truth.iter().map(|s| Timed { bell: s.bell, t: s.t }).collect();
        let r = rhythm(&timed, 6);
        assert_eq!((r.rows, r.placed_rows), (60, 60), "{method:?}");
        let right = truth
            .iter()
            .zip(&r.placed)
            .filter(|(s, p)| p.place == Some(s.place) && p.hand == Some(s.hand))
            .count();
        // Where the bell lacking stood at the row's end, its place is
        // guessed from where it last stood (`slots`)
        // (plain hunt: 316 of 337, the three rows it leads guessed at the
        // back, and one handstroke at the back taken to lead the row after.)
        assert!(10 * right >= 9 * truth.len(), "{method:?}: {right} of {}", truth.len());
    }
}

#[test]
fn no_gap_means_strokes_unknown() {
    let mut s = spec(Method::Rounds);
    s.handstroke_gap = 0.0;
    s.jitter = 0.0;
    s.bells[2].odd_struck_ms = 0.0;
    let truth = tower_strikes(&s).unwrap();
    let timed: Vec<Timed> = truth.iter().map(|s| Timed { bell: s.bell, t: s.t }).collect();
    assert!(!rhythm(&timed, 6).strokes_known);
    assert!(rhythm(&[], 6).placed.is_empty());
}

/// Eight bells of 200 kg, none odd-struck, the treble at 1000 Hz and
/// each bell `step_hz` (Hz) under the one before.
fn eight_bells(step_hz: f64) -> Vec<RingBell> {
    (0..8)
        .map(|i| RingBell {
            nominal_hz: 1000.0 - step_hz * i as f64,
            mass_kg: 200.0,
            odd_struck_ms: 0.0,
        })
        .collect()
}

#[test]
fn the_strikes_of_three_bells_of_eight_leave_room_for_eight() {
    let mut s = spec(Method::PlainHunt);
    s.bells = eight_bells(50.0);
    s.rows = 12;
    s.jitter = 0.02;
    let truth = tower_strikes(&s).unwrap();
    let timed: Vec<Timed> = truth.iter().map(|s| Timed { bell: s.bell, t: s.t }).collect();
    let all = ring_room(&timed).unwrap();
    assert!((all.bells - 8.0).abs() < 1.0, "{all:?}");
    for bells in [[1, 2, 3], [6, 7, 8], [1, 4, 8]] {
        let some: Vec<Timed> = timed.iter().copied().filter(|t| bells.contains(&t.bell)).collect();
        let room = ring_room(&some).unwrap();
        assert!(room.bells > 6.0, "{bells:?}: {room:?}");
    }
    let one: Vec<Timed> = timed.iter().copied().filter(|t| t.bell == 1).collect();
    assert_eq!(ring_room(&one), None);
}

#[test]
fn a_stretch_of_strikes_lost_leaves_room_for_the_bells_that_ring() {
    // Every other strike of every bell lost for the first 12 of 20
    // rows (tester15: "room for about 11 bells" for 6 with half their
    // strikes lost): a pull across a strike lost is not a row.
    let mut s = spec(Method::PlainHunt);
    s.rows = 20;
    s.jitter = 0.01;
    let truth = tower_strikes(&s).unwrap();
    let bells = s.bells.len();
    let mut seen = vec![0usize; bells + 1];
    let mut timed = vec![];
    for x in &truth {
        seen[x.bell] += 1;
        if seen[x.bell] > 12 || seen[x.bell] % 2 == 0 {
            timed.push(Timed { bell: x.bell, t: x.t });
        }
    }
    let room = ring_room(&timed).unwrap();
    assert!((room.bells - bells as f64).abs() < 1.0, "{bells} bells: {room:?}");
}

/// Tester19 fault 4 (ring D `--templates`): in one row of plain hunt on
/// eight, a bell's strike is not heard and a false strike of it is heard
/// just before the row's first. Read through it in time order, the row's
/// later strikes stood a place out and every error of the row was off by
/// up to 262 ms; the false strike is now far off, and the row's other
/// strikes keep errors true to their times.
#[test]
fn a_false_strike_and_a_lost_one_spoil_no_other_strike_of_their_row() {
    let mut s = spec(Method::PlainHunt);
    s.bells = eight_bells(40.0);
    s.rows = 24;
    s.jitter = 0.003 * 3f64.sqrt();
    let truth = tower_strikes(&s).unwrap();
    let row = 12;
    let lost = truth.iter().position(|x| x.row == row && x.place == 5).unwrap();
    let first = truth.iter().position(|x| x.row == row && x.place == 1).unwrap();
    let mut timed: Vec<Timed> = truth.iter().map(|x| Timed { bell: x.bell, t: x.t }).collect();
    timed[lost].t = truth[first].t - 0.037;
    let r = rhythm(&timed, 8);
    assert!(r.placed[lost].far_off, "{:?}", r.placed[lost]);
    assert_eq!(r.placed[lost].error, None);
    for (k, x) in truth.iter().enumerate().filter(|(k, x)| x.row == row && *k != lost) {
        let p = &r.placed[k];
        assert!(!p.far_off, "{p:?}");
        assert_eq!(p.place, Some(x.place), "{p:?}");
        // The true error, less the row's own timing: a few ms.
        let e = p.error.unwrap();
        assert!(
            (e - (x.t - x.ideal_t)).abs() < 0.012,
            "bell {}: {:.1} ms",
            x.bell,
            e * 1e3
        );
    }
}
