//! The PNG and GIF backend: plotters' bitmap backend with its text drawn
//! glyph by glyph where the font places it. plotters 0.3.7 draws each
//! glyph's ink box at the pen, without the glyph's left side bearing, so
//! a glyph after a wide-bearing one stands apart ("tim e (s)", "ring. wav");
//! here every glyph is drawn at pen + kerning + its own bearing, as the
//! font's advance widths (which plotters' layout already uses) intend.

use ab_glyph::{Font, FontRef, ScaleFont};
use plotters::prelude::BitMapBackend;
use plotters_backend::{
    text_anchor::{HPos, VPos},
    BackendColor, BackendCoord, BackendStyle, BackendTextStyle, DrawingBackend, DrawingErrorKind,
};

/// A [`BitMapBackend`] whose text is laid out by [`draw_glyphs`].
pub struct Bitmap<'a>(pub BitMapBackend<'a>);

impl<'a> Bitmap<'a> {
    /// Draw into a PNG (or other image) file at `path`, `size` pixels.
    pub fn new<P: AsRef<std::path::Path> + ?Sized>(path: &'a P, size: (u32, u32)) -> Self {
        Self(BitMapBackend::new(path, size))
    }

    /// Draw into an RGB buffer of `size` pixels (3 bytes a pixel).
    pub fn with_buffer(buf: &'a mut [u8], size: (u32, u32)) -> Self {
        Self(BitMapBackend::with_buffer(buf, size))
    }
}

/// The embedded face, parsed once.
fn face() -> &'static FontRef<'static> {
    static FACE: std::sync::OnceLock<FontRef<'static>> = std::sync::OnceLock::new();
    FACE.get_or_init(|| match FontRef::try_from_slice(crate::fonts::DEJAVU_SANS) {
        Ok(f) => f,
        // Built into the binary: a failure is a broken build, caught by
        // every plot test.
        Err(_) => unreachable!("the embedded DejaVu Sans does not parse"),
    })
}

/// Call `ink(x, y, coverage)` for every pixel of `text` at `size` px, with
/// the pen starting at x = 0 and the glyphs' tops near y = 0 (as plotters
/// places them: y = size/2 + the glyph's top above the baseline).
pub(crate) fn draw_glyphs(size: f32, text: &str, mut ink: impl FnMut(i32, i32, f32)) {
    let font = face().as_scaled(size);
    let mut pen = 0f32;
    let mut prev = None;
    for c in text.chars() {
        let id = font.glyph_id(c);
        if let Some(p) = prev {
            pen += font.kern(p, id);
        }
        prev = Some(id);
        let glyph = id.with_scale_and_position(size, ab_glyph::point(pen, 0.0));
        if let Some(outline) = font.outline_glyph(glyph) {
            let bounds = outline.px_bounds();
            let (x0, y0) = (bounds.min.x as i32, (size / 2.0 + bounds.min.y) as i32);
            outline.draw(|x, y, c| ink(x0 + x as i32, y0 + y as i32, c));
        }
        pen += font.h_advance(id);
    }
}

impl DrawingBackend for Bitmap<'_> {
    type ErrorType = <BitMapBackend<'static> as DrawingBackend>::ErrorType;

    fn get_size(&self) -> (u32, u32) {
        self.0.get_size()
    }

    fn ensure_prepared(&mut self) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.ensure_prepared()
    }

    fn present(&mut self) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.present()
    }

    fn draw_pixel(
        &mut self,
        point: BackendCoord,
        color: BackendColor,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.draw_pixel(point, color)
    }

    fn draw_line<S: BackendStyle>(
        &mut self,
        from: BackendCoord,
        to: BackendCoord,
        style: &S,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.draw_line(from, to, style)
    }

    fn draw_rect<S: BackendStyle>(
        &mut self,
        upper_left: BackendCoord,
        bottom_right: BackendCoord,
        style: &S,
        fill: bool,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.draw_rect(upper_left, bottom_right, style, fill)
    }

    fn blit_bitmap(
        &mut self,
        pos: BackendCoord,
        (iw, ih): (u32, u32),
        src: &[u8],
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.blit_bitmap(pos, (iw, ih), src)
    }

    /// plotters' own text drawing (anchor, rotation, clipping to the
    /// picture), with the glyphs placed by [`draw_glyphs`].
    fn draw_text<T: BackendTextStyle>(
        &mut self,
        text: &str,
        style: &T,
        pos: BackendCoord,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        let color = style.color();
        if color.alpha == 0.0 {
            return Ok(());
        }
        let ((min_x, min_y), (max_x, max_y)) = style
            .layout_box(text)
            .map_err(|e| DrawingErrorKind::FontError(Box::new(e)))?;
        let (width, height) = (max_x - min_x, max_y - min_y);
        let dx = match style.anchor().h_pos {
            HPos::Left => 0,
            HPos::Right => -width,
            HPos::Center => -width / 2,
        };
        let dy = match style.anchor().v_pos {
            VPos::Top => 0,
            VPos::Center => -height / 2,
            VPos::Bottom => -height,
        };
        let trans = style.transform();
        let (w, h) = self.get_size();
        let mut result = Ok(());
        draw_glyphs(style.size() as f32, text, |x, y, coverage| {
            if result.is_err() {
                return;
            }
            let (x, y) = trans.transform(x + dx - min_x, y + dy - min_y);
            let (x, y) = (pos.0 + x, pos.1 + y);
            if x >= 0 && x < w as i32 && y >= 0 && y < h as i32 {
                let c = BackendColor {
                    alpha: color.alpha * f64::from(coverage),
                    rgb: color.rgb,
                };
                result = self.draw_pixel((x, y), c);
            }
        });
        result
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The ink columns of `text` drawn at `size` px.
    fn ink_columns(size: f32, text: &str) -> Vec<i32> {
        let mut cols = std::collections::BTreeSet::new();
        draw_glyphs(size, text, |x, _, c| {
            if c > 0.3 {
                cols.insert(x);
            }
        });
        cols.into_iter().collect()
    }

    /// The second glyph of a pair starts where the pen puts it (the first
    /// glyph's advance and the pair's kerning) plus its own left bearing:
    /// plotters' drawing, which left out the bearings, put "e" 2 px too far
    /// after "m" ("tim e (s)") and "w" after "." ("ring. wav").
    #[test]
    fn glyphs_keep_their_bearings() {
        // At 30 px "i", "m" and "l" have left bearings of 2.7-2.8 px, so
        // drawing without them misses by 2 px or more.
        for size in [13.0, 15.0, 20.0, 30.0] {
            for pair in ["me", ".w", "im", "ti", "ml"] {
                let mut chars = pair.chars();
                let (a, b) = (chars.next().unwrap(), chars.next().unwrap());
                let first = ink_columns(size, &a.to_string());
                let second_alone = ink_columns(size, &b.to_string())[0];
                let both = ink_columns(size, pair);
                let font = face().as_scaled(size);
                let pen = font.h_advance(font.glyph_id(a)) + font.kern(font.glyph_id(a), font.glyph_id(b));
                let got = both.iter().copied().find(|x| *x > *first.last().unwrap()).unwrap();
                let want = (pen + second_alone as f32).floor() as i32;
                assert!(
                    (got - want).abs() <= 1,
                    "{size} px, {pair:?}: second glyph at {got} px, the font puts it at {want}"
                );
            }
        }
    }
}
