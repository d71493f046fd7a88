//! A bell and its clapper animated (`clapper animate`): the drawing
//! ([`Figure`], to scale from the bell's numbers), the motion as frames
//! taken from the simulation at exact times, and three ways to show it: an
//! animated SVG (SMIL, no script), a GIF, and an HTML page whose canvas
//! player (`player.js`, also served by the web app) plays the synthesised
//! sound in step, with slow motion and a time cursor on θ and φ.
//!
//! The frames are data the caller computed ([`Frame`]: an animation time,
//! the simulated time it shows, θ and φ); nothing here simulates or
//! interpolates the model. An SVG's key frames are the frames themselves;
//! the GIF draws one frame per picture; the HTML player draws, at each
//! moment, the last frame at or before it.

mod figure;
mod gif_file;
mod html;
mod svg;

pub use figure::{colours, rotate, Figure, Part, Shape};
pub use gif_file::animation_gif;
pub use html::{animation_html, player_json, PLAYER_JS};
pub use svg::animation_svg;

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

/// Where each bell is drawn in a picture `width` × `height` px: a title
/// band on top, the bells in a row (more than four: two rows), each with a
/// caption under it, all at one scale (a tenor beside a treble looks its
/// size). The HTML player lays bells out by the same rule.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Layout {
    pub width: f64,
    pub height: f64,
    /// px per metre.
    pub scale: f64,
    /// Each bell's pivot (px, y down).
    pub centres: Vec<[f64; 2]>,
    /// Each bell's caption: its centre and baseline (px).
    pub captions: Vec<[f64; 2]>,
    /// Title font size (px).
    pub font: f64,
}

/// Columns for `n` bells: one row up to four, else two rows.
pub fn columns(n: usize) -> usize {
    if n > 4 {
        n.div_ceil(2)
    } else {
        n.max(1)
    }
}

impl Layout {
    pub fn new(anim: &Animation, width: u32, height: u32) -> Layout {
        let (w, h) = (f64::from(width), f64::from(height));
        let font = (h / 28.0).clamp(9.0, 18.0);
        let top = 1.8 * font;
        let n = anim.bells.len().max(1);
        let cols = columns(n);
        let rows = n.div_ceil(cols);
        let cell = w / cols as f64;
        let row_h = ((h - top - 4.0) / rows as f64).max(10.0);
        let area = (row_h - 1.6 * font).max(10.0);
        let scale = anim
            .bells
            .iter()
            .map(|b| 0.48 * cell.min(area) / b.figure.reach.max(1e-6))
            .fold(f64::INFINITY, f64::min);
        let at = |i: usize| ((i % cols) as f64, (i / cols) as f64);
        let centres = (0..anim.bells.len())
            .map(|i| {
                let (c, r) = at(i);
                [cell * (c + 0.5), top + r * row_h + area / 2.0]
            })
            .collect();
        let captions = (0..anim.bells.len())
            .map(|i| {
                let (c, r) = at(i);
                [cell * (c + 0.5), top + (r + 1.0) * row_h - 0.5 * font]
            })
            .collect();
        Layout {
            width: w,
            height: h,
            scale,
            centres,
            captions,
            font,
        }
    }
}

/// A bell's caption: its name and how it rings, or for more than two
/// bells (narrow cells) its name alone.
pub(crate) fn caption(anim: &Animation, b: &BellMotion) -> String {
    if anim.bells.len() > 2 {
        b.name.clone()
    } else {
        format!("{}: {}", b.name, b.caption)
    }
}

/// Text made safe inside SVG or HTML, in text or in an attribute.
pub(crate) fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// Check a picture size (px): 64 to 4096 a side.
pub(crate) fn check_size(width: u32, height: u32) -> Result<(), PlotError> {
    if (64..=4096).contains(&width) && (64..=4096).contains(&height) {
        Ok(())
    } else {
        Err(PlotError::Empty("a picture size outside 64-4096 px a side"))
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
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
