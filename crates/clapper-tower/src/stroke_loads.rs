//! One bell's frame loads over its handstroke and its backstroke, sampled
//! on a fine uniform clock, and placed at any strike time on a touch's
//! clock (linear interpolation).

use clapper_core::bell::{Bell, G};
use clapper_core::dynamics::Dynamics;
use clapper_core::frame::frame_load;
use clapper_core::stroke::{run_stroke, Side, SimConfig, StrokeStart, Style, TraceRecorder};

use crate::TowerError;

/// Sampling interval of a stroke's own load history (s): far finer than
/// the touch's clock, so that placing a stroke at any instant loses
/// nothing the touch's clock can carry.
pub const STROKE_DT: f64 = 1e-3;

/// One stroke's load on the frame, from rest at the balance to the
/// turning point at the other.
#[derive(Clone, Debug, PartialEq)]
pub struct StrokeLoad {
    /// Time from the start of the stroke to the strike (the clapper's
    /// first impact) (s); NaN for a stroke without one.
    pub to_strike: f64,
    /// Duration of the stroke (s).
    pub duration: f64,
    /// Horizontal load along the bell's swing direction (N), positive
    /// towards positive θ, every [`STROKE_DT`] from the start.
    pub horizontal: Vec<f64>,
    /// Vertical load minus the weight (N), positive downwards, likewise.
    pub vertical: Vec<f64>,
}

impl StrokeLoad {
    /// The loads `tau` seconds after the stroke's start (zero outside it:
    /// the ringer holds the bell at the balance, where its load is its weight).
    #[inline]
    pub fn at(&self, tau: f64) -> (f64, f64) {
        let x = tau / STROKE_DT;
        if x.is_nan() || x < 0.0 {
            return (0.0, 0.0);
        }
        let i = x as usize;
        if i + 1 >= self.horizontal.len() {
            return (0.0, 0.0);
        }
        let w = x - i as f64;
        (
            self.horizontal[i] + w * (self.horizontal[i + 1] - self.horizontal[i]),
            self.vertical[i] + w * (self.vertical[i + 1] - self.vertical[i]),
        )
    }

    /// Largest |horizontal| (N).
    pub fn peak_horizontal(&self) -> f64 {
        self.horizontal.iter().fold(0.0, |a, &h| a.max(h.abs()))
    }

    /// Largest vertical load minus the weight (N).
    pub fn peak_vertical(&self) -> f64 {
        self.vertical.iter().fold(f64::MIN, |a, &v| a.max(v))
    }
}

/// A bell's two strokes as rung in a touch.
#[derive(Clone, Debug, PartialEq)]
pub struct BellStrokes {
    /// The balance angle the strokes start from (rad).
    pub theta0: f64,
    /// Weight of bell and clapper (N).
    pub weight: f64,
    /// Handstroke: from +θ0, ringing right.
    pub hand: StrokeLoad,
    /// Backstroke: from −θ0, the clapper where the handstroke left it.
    pub back: StrokeLoad,
}

/// The load history of one stroke from `start`.
fn stroke_load(bell: &Bell, cfg: &SimConfig, start: StrokeStart) -> Result<(StrokeLoad, Side), TowerError> {
    let mut rec = TraceRecorder::new(STROKE_DT / 2.0);
    let stroke = run_stroke(bell, cfg, start, &mut rec)?;
    // A stroke with no strike (a tied clapper's) has none to be placed by.
    let hit = stroke.first_strike().map_or(f64::NAN, |i| i.t);
    let d = Dynamics::new(bell);
    let weight = (bell.bell_mass + bell.clapper_mass) * G;
    let t0 = start.t;
    let duration = stroke.end.t - t0;
    let n = (duration / STROKE_DT).floor() as usize + 1;
    let (mut h, mut v) = (Vec::with_capacity(n), Vec::with_capacity(n));
    let loads: Vec<_> = rec.samples.iter().map(|s| frame_load(&d, s)).collect();
    let mut j = 0;
    for k in 0..n {
        let t = t0 + k as f64 * STROKE_DT;
        while j + 2 < loads.len() && loads[j + 1].t <= t {
            j += 1;
        }
        let (a, b) = (&loads[j], &loads[(j + 1).min(loads.len() - 1)]);
        let w = if b.t > a.t {
            ((t - a.t) / (b.t - a.t)).clamp(0.0, 1.0)
        } else {
            0.0
        };
        h.push(a.horizontal + w * (b.horizontal - a.horizontal));
        v.push(a.vertical + w * (b.vertical - a.vertical) - weight);
    }
    Ok((
        StrokeLoad {
            to_strike: hit - t0,
            duration,
            horizontal: h,
            vertical: v,
        },
        stroke.end.side(),
    ))
}

/// One stroke from rest at `theta0` (rad), the clapper resting as when
/// ringing right: its load history, struck or not.
pub fn swing_from_rest(bell: &Bell, cfg: &SimConfig, theta0: f64) -> Result<StrokeLoad, TowerError> {
    let cfg = SimConfig { theta0, ..*cfg };
    let start = StrokeStart::at_rest(bell, &cfg, 0.0, theta0, Style::Right.side(theta0));
    Ok(stroke_load(bell, &cfg, start)?.0)
}

/// Handstroke and backstroke from ±`theta0` (rad).
pub fn bell_strokes(bell: &Bell, cfg: &SimConfig, theta0: f64) -> Result<BellStrokes, TowerError> {
    let cfg = SimConfig { theta0, ..*cfg };
    let start = StrokeStart::at_rest(bell, &cfg, 0.0, theta0, Style::Right.side(theta0));
    let (hand, side) = stroke_load(bell, &cfg, start)?;
    let start = StrokeStart::at_rest(bell, &cfg, 0.0, -theta0, side);
    let (back, _) = stroke_load(bell, &cfg, start)?;
    if !(hand.to_strike.is_finite() && back.to_strike.is_finite()) {
        return Err(TowerError::Ring(format!(
            "no strike in a stroke from {:.1} deg",
            theta0.to_degrees()
        )));
    }
    Ok(BellStrokes {
        theta0,
        weight: (bell.bell_mass + bell.clapper_mass) * G,
        hand,
        back,
    })
}

/// Lowest and highest balance angle tried when fitting a stroke's time
/// (deg): a bell set much lower than 150 deg is not rung full circle; one
/// higher than 179.9 deg is held at the balance by the ringer, whose hold
/// is not part of the stroke.
pub const THETA0_RANGE_DEG: (f64, f64) = (150.0, 179.9);

/// The balance angle at which the handstroke lasts `duration` (s), by
/// bisection: a bell rung at the band's speed swings from balance to
/// balance in half a whole pull. A bell too slow even from the lowest
/// angle is an error; one too quick even from the highest waits at the
/// balance (the highest angle is returned).
pub fn theta0_for(bell: &Bell, cfg: &SimConfig, duration: f64) -> Result<f64, TowerError> {
    let (lo_deg, hi_deg) = THETA0_RANGE_DEG;
    let time = |th: f64| -> Result<f64, TowerError> {
        let c = SimConfig { theta0: th, ..*cfg };
        let start = StrokeStart::at_rest(bell, &c, 0.0, th, Style::Right.side(th));
        Ok(run_stroke(bell, &c, start, &mut ())?.end.t)
    };
    let (mut lo, mut hi) = (lo_deg.to_radians(), hi_deg.to_radians());
    if time(lo)? > duration {
        return Err(TowerError::Ring(format!(
            "the bell's stroke from {lo_deg} deg takes {:.2} s, longer than the {duration:.2} s the band's speed allows",
            time(lo)?
        )));
    }
    if time(hi)? <= duration {
        return Ok(hi);
    }
    for _ in 0..40 {
        let mid = 0.5 * (lo + hi);
        if time(mid)? > duration {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    Ok(0.5 * (lo + hi))
}
