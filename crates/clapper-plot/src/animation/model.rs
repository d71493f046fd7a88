//! What an animation is made of: frames the caller computed, the strikes
//! to flash, each bell's motion, and the whole with its check.

use super::figure::Figure;
use crate::PlotError;

/// How long a strike's flash shows in an SVG or GIF (s): two or three
/// pictures at 25 a second, so that it is seen; the first picture after
/// the impact shows it.
pub const FLASH_S: f64 = 0.1;

/// One picture of a bell: what it shows, at which time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    /// Animation time (s): when the picture is shown (and the sound heard).
    pub t: f64,
    /// The simulated time (s) whose state it shows.
    pub t_sim: f64,
    /// Bell angle θ (rad).
    pub theta: f64,
    /// Clapper angle φ relative to the bell (rad).
    pub phi: f64,
}

/// One impact of the clapper, where and when it is drawn.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StrikeMark {
    /// Animation time (s).
    pub t: f64,
    /// Simulated time (s).
    pub t_sim: f64,
    /// The side hit: −1 the hand side, +1 the back side.
    pub side: i8,
    /// The stroke it belongs to (0 the first).
    pub stroke: usize,
    /// Whether it is its stroke's first strike (the blow a listener hears).
    pub first: bool,
    /// When a perfectly struck blow would land (s, animation time): set
    /// for first strikes in rounds, for the striking diagram.
    pub ideal: Option<f64>,
    /// |φ'| just before the impact (rad/s).
    pub speed: f64,
}

/// One bell's part in an animation.
#[derive(Clone, Debug, PartialEq)]
pub struct BellMotion {
    /// The bell's name.
    pub name: String,
    /// A short line under it (style, settings).
    pub caption: String,
    /// What is drawn.
    pub figure: Figure,
    /// Its frames, in time order.
    pub frames: Vec<Frame>,
    /// Its impacts, in time order.
    pub strikes: Vec<StrikeMark>,
}

/// An animation: one bell, bells side by side, or a ring in rounds.
#[derive(Clone, Debug, PartialEq)]
pub struct Animation {
    /// Title line.
    pub title: String,
    /// Length (s); the last frame's time.
    pub duration: f64,
    /// The bells, left to right.
    pub bells: Vec<BellMotion>,
    /// The interval between blows in rounds (s), when the bells ring
    /// rounds (the HTML page then shows a striking diagram).
    pub rounds_interval: Option<f64>,
}

impl Animation {
    /// Refuse what cannot be drawn: no bells, frames out of order or not
    /// spanning `[0, duration]`, numbers that are not finite.
    pub fn check(&self) -> Result<(), PlotError> {
        if self.bells.is_empty() {
            return Err(PlotError::Empty("no bells to animate"));
        }
        if !(self.duration.is_finite() && self.duration > 0.0) {
            return Err(PlotError::Empty("an animation of no length"));
        }
        for b in &self.bells {
            let (Some(first), Some(last)) = (b.frames.first(), b.frames.last()) else {
                return Err(PlotError::Empty("a bell with no frames"));
            };
            let ordered = b.frames.windows(2).all(|w| w[0].t <= w[1].t);
            let finite = b.frames.iter().all(|f| f.theta.is_finite() && f.phi.is_finite());
            if first.t != 0.0 || last.t != self.duration || !ordered || !finite {
                return Err(PlotError::Empty(
                    "frames must be finite, in time order, from 0 to the animation's end",
                ));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::animation::layout::Layout;
    use clapper_core::bell::Bell;

    /// A made-up motion: the bell swinging as cos, the clapper lagging,
    /// one strike per second.
    pub fn swinging(n: usize, fps: f64) -> Animation {
        let frames: Vec<Frame> = (0..n)
            .map(|j| {
                let t = j as f64 / fps;
                Frame {
                    t,
                    t_sim: t,
                    theta: 2.9 * (t * 1.5).cos(),
                    phi: 0.4 * (t * 3.0).sin(),
                }
            })
            .collect();
        let duration = frames[n - 1].t;
        let strikes = (1..duration as usize + 1)
            .map(|k| StrikeMark {
                t: k as f64 - 0.5,
                t_sim: k as f64 - 0.5,
                side: if k % 2 == 0 { -1 } else { 1 },
                stroke: k,
                first: true,
                ideal: None,
                speed: 2.0,
            })
            .collect();
        Animation {
            title: "test <bell> & co".into(),
            duration,
            bells: vec![BellMotion {
                name: "lab".into(),
                caption: "ringing right".into(),
                figure: Figure::of(&Bell::lab()),
                frames,
                strikes,
            }],
            rounds_interval: None,
        }
    }

    #[test]
    fn frames_out_of_order_or_short_are_refused() {
        let mut a = swinging(50, 25.0);
        assert!(a.check().is_ok());
        a.bells[0].frames.swap(3, 4);
        assert!(a.check().is_err());
        let mut a = swinging(50, 25.0);
        a.duration += 1.0;
        assert!(a.check().is_err());
        let mut a = swinging(50, 25.0);
        a.bells.clear();
        assert!(a.check().is_err());
    }

    #[test]
    fn every_bell_fits_its_cell_at_one_scale() {
        let mut a = swinging(10, 25.0);
        let mut tenor = a.bells[0].clone();
        tenor.figure = Figure::of(&Bell::gsm_tenor());
        a.bells.push(tenor);
        for n in [2, 5, 8] {
            while a.bells.len() < n {
                a.bells.push(a.bells[a.bells.len() % 2].clone());
            }
            let l = Layout::new(&a, 600, 400);
            for ((b, c), cap) in a.bells.iter().zip(&l.centres).zip(&l.captions) {
                let r = b.figure.reach * l.scale;
                assert!(
                    c[0] - r >= 0.0 && c[0] + r <= 600.0 && c[1] + r <= cap[1] - 0.5 * l.font,
                    "{n} bells"
                );
            }
            // Two rows above four bells, each bell's caption under it.
            let rows = l
                .centres
                .iter()
                .map(|c| c[1].to_bits())
                .collect::<std::collections::BTreeSet<_>>();
            assert_eq!(rows.len(), if n > 4 { 2 } else { 1 });
        }
    }
}
