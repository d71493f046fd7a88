//! Where things go in a picture, shared by the SVG, the GIF and the
//! HTML page: each bell's cell and scale, its caption, escaping and the
//! size check.

use super::model::{Animation, BellMotion};
use crate::PlotError;

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
