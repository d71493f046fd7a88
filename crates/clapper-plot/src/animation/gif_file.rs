//! The animation as a GIF: each frame drawn with plotters into a pixel
//! buffer, mapped onto a fixed palette (the drawing's own colours and
//! greys for anti-aliased text; no quantiser, so it is fast and the same
//! bytes every time), and only the part that changed stored after the
//! first frame.

use plotters::coord::Shift;
use plotters::prelude::*;

use super::figure::{colours, rotate, Part, Shape};
use super::layout::{caption, check_size, Layout};
use super::model::{Animation, BellMotion, Frame, FLASH_S};
use crate::PlotError;

fn rgb(hex: &str) -> RGBColor {
    let v = u32::from_str_radix(hex.trim_start_matches('#'), 16).unwrap_or(0);
    RGBColor((v >> 16) as u8, (v >> 8) as u8, v as u8)
}

/// The palette: the drawing's colours, then greys between ink and paper.
fn palette() -> Vec<[u8; 3]> {
    let mut p: Vec<[u8; 3]> = [
        colours::PAPER,
        colours::INK,
        colours::BRONZE,
        colours::BRONZE_DARK,
        colours::WOOD,
        colours::WHEEL,
        colours::WOOD_DARK,
        colours::IRON,
        colours::MARK,
        colours::FLASH,
        colours::FLASH_RIM,
        colours::HAND,
        colours::BACK,
    ]
    .iter()
    .map(|h| {
        let c = rgb(h);
        [c.0, c.1, c.2]
    })
    .collect();
    for k in 1..12u8 {
        let g = 0x22 + k * 18;
        p.push([g, g, g]);
    }
    p
}

/// Nearest palette entry of every 15-bit colour.
fn lookup(pal: &[[u8; 3]]) -> Vec<u8> {
    (0..1u32 << 15)
        .map(|c| {
            let q = [(c >> 10) & 31, (c >> 5) & 31, c & 31].map(|v| (v * 255 / 31) as i32);
            let dist = |p: &[u8; 3]| (0..3).map(|i| (q[i] - i32::from(p[i])).pow(2)).sum::<i32>();
            (0..pal.len()).min_by_key(|&i| dist(&pal[i])).unwrap_or(0) as u8
        })
        .collect()
}

struct Pen<'a, 'b> {
    area: &'a DrawingArea<crate::bitmap_text::Bitmap<'b>, Shift>,
    scale: f64,
    centre: [f64; 2],
}

impl Pen<'_, '_> {
    fn px(&self, p: [f64; 2]) -> (i32, i32) {
        (
            (self.centre[0] + self.scale * p[0]).round() as i32,
            (self.centre[1] - self.scale * p[1]).round() as i32,
        )
    }

    /// Draw `part`, its points mapped by `to_tower` (m, y up).
    fn part(&self, part: &Part, to_tower: impl Fn([f64; 2]) -> [f64; 2]) -> Result<(), String> {
        let width = ((part.width * self.scale).round() as u32).max(1);
        let stroke = part.stroke.map(|c| ShapeStyle::from(rgb(c)).stroke_width(width));
        let fill = part.fill.map(|c| ShapeStyle::from(rgb(c)).filled());
        let e = |e: DrawingAreaErrorKind<_>| e.to_string();
        match &part.shape {
            Shape::Polygon { points } => {
                let pts: Vec<(i32, i32)> = points.iter().map(|&p| self.px(to_tower(p))).collect();
                if let Some(f) = fill {
                    self.area.draw(&Polygon::new(pts.clone(), f)).map_err(e)?;
                }
                if let Some(s) = stroke {
                    let mut closed = pts;
                    closed.push(closed[0]);
                    self.area.draw(&PathElement::new(closed, s)).map_err(e)?;
                }
            }
            Shape::Line { points } => {
                let pts: Vec<(i32, i32)> = points.iter().map(|&p| self.px(to_tower(p))).collect();
                if let Some(s) = stroke {
                    if part.dashed {
                        for seg in dashes(&pts, 6.0, 4.0) {
                            self.area.draw(&PathElement::new(seg, s)).map_err(e)?;
                        }
                    } else {
                        self.area.draw(&PathElement::new(pts, s)).map_err(e)?;
                    }
                }
            }
            Shape::Circle { centre, radius } => {
                let c = self.px(to_tower(*centre));
                let r = ((radius * self.scale).round() as i32).max(1);
                if let Some(f) = fill {
                    self.area.draw(&Circle::new(c, r, f)).map_err(e)?;
                }
                if let Some(s) = stroke {
                    self.area.draw(&Circle::new(c, r, s)).map_err(e)?;
                }
            }
        }
        Ok(())
    }
}

/// A two-point line cut into dashes `on` px long with `off` px gaps.
fn dashes(pts: &[(i32, i32)], on: f64, off: f64) -> Vec<Vec<(i32, i32)>> {
    let (Some(a), Some(b)) = (pts.first(), pts.last()) else {
        return vec![];
    };
    let (dx, dy) = (f64::from(b.0 - a.0), f64::from(b.1 - a.1));
    let len = dx.hypot(dy);
    let mut out = vec![];
    let mut s = 0.0;
    while s < len {
        let e = (s + on).min(len);
        let at = |u: f64| (a.0 + (dx * u / len).round() as i32, a.1 + (dy * u / len).round() as i32);
        out.push(vec![at(s), at(e)]);
        s += on + off;
    }
    out
}

/// A drawing failure in the GIF, as the crate's error.
fn draw_err(m: String) -> PlotError {
    PlotError::Draw {
        path: "(gif)".into(),
        message: m,
    }
}

/// An encoder's failure, as the crate's error.
fn gif_err(e: gif::EncodingError) -> PlotError {
    PlotError::Draw {
        path: "(gif)".into(),
        message: e.to_string(),
    }
}

/// What every picture of one GIF shares: the animation, its layout and
/// its fonts.
struct Painter<'a> {
    anim: &'a Animation,
    l: Layout,
    title_font: TextStyle<'a>,
    caption_font: TextStyle<'a>,
}

impl Painter<'_> {
    /// Draw picture `j` (showing frame `now`) into `area`: the title, each
    /// bell, and the time bar along the bottom.
    fn picture(
        &self,
        area: &DrawingArea<crate::bitmap_text::Bitmap<'_>, Shift>,
        j: usize,
        now: &Frame,
    ) -> Result<(), PlotError> {
        let (anim, l) = (self.anim, &self.l);
        area.fill(&rgb(colours::PAPER)).map_err(|e| draw_err(e.to_string()))?;
        let (tw, _) = area
            .estimate_text_size(&anim.title, &self.title_font)
            .map_err(|e| draw_err(e.to_string()))?;
        area.draw_text(
            &anim.title,
            &self.title_font,
            (((l.width - f64::from(tw)) / 2.0) as i32, (0.4 * l.font) as i32),
        )
        .map_err(|e| draw_err(e.to_string()))?;
        for ((b, c), cap) in anim.bells.iter().zip(&l.centres).zip(&l.captions) {
            self.bell(area, b, &b.frames[j], *c, *cap)?;
        }
        let bar = (l.width * now.t / anim.duration).round() as i32;
        let height = l.height as i32;
        area.draw(&Rectangle::new(
            [(0, height - 4), (bar, height)],
            rgb(colours::MARK).filled(),
        ))
        .map_err(|e| draw_err(e.to_string()))?;
        area.present().map_err(|e| draw_err(e.to_string()))
    }

    /// Draw bell `b` at frame `fr`, its pivot at `c` and its caption at
    /// `cap` (px): the vertical, the bell, the clapper, any strike's flash.
    fn bell(
        &self,
        area: &DrawingArea<crate::bitmap_text::Bitmap<'_>, Shift>,
        b: &BellMotion,
        fr: &Frame,
        c: [f64; 2],
        cap: [f64; 2],
    ) -> Result<(), PlotError> {
        let l = &self.l;
        let f = &b.figure;
        let pen = Pen {
            area,
            scale: l.scale,
            centre: c,
        };
        let (mark, d) = (rgb(colours::MARK), f.diameter);
        for seg in dashes(&[pen.px([0.0, 0.0]), pen.px([0.0, -f.reach])], 6.0, 4.0) {
            area.draw(&PathElement::new(seg, mark.stroke_width(1)))
                .map_err(|e| draw_err(e.to_string()))?;
        }
        for p in &f.bell {
            pen.part(p, |q| rotate(q, fr.theta)).map_err(draw_err)?;
        }
        for p in &f.clapper {
            pen.part(p, |q| rotate(f.clapper_to_bell(q, fr.phi), fr.theta))
                .map_err(draw_err)?;
        }
        for s in b.strikes.iter().filter(|s| (0.0..FLASH_S).contains(&(fr.t - s.t))) {
            let at = rotate(f.strike_points[usize::from(s.side > 0)], fr.theta);
            let r = ((if s.first { 0.07 } else { 0.045 }) * d * l.scale).max(3.0) as i32;
            area.draw(&Circle::new(pen.px(at), r, rgb(colours::FLASH).filled()))
                .map_err(|e| draw_err(e.to_string()))?;
            area.draw(&Circle::new(pen.px(at), r, rgb(colours::FLASH_RIM).stroke_width(2)))
                .map_err(|e| draw_err(e.to_string()))?;
        }
        let text = caption(self.anim, b);
        let (cw, _) = area
            .estimate_text_size(&text, &self.caption_font)
            .map_err(|e| draw_err(e.to_string()))?;
        area.draw_text(
            &text,
            &self.caption_font,
            ((cap[0] - f64::from(cw) / 2.0) as i32, (cap[1] - 0.8 * l.font) as i32),
        )
        .map_err(|e| draw_err(e.to_string()))
    }
}

/// An RGB picture's pixels as palette indices, through the 15-bit `lut`.
fn indexed(rgb_buf: &[u8], lut: &[u8]) -> Vec<u8> {
    rgb_buf
        .chunks_exact(3)
        .map(|p| {
            let c = (usize::from(p[0] >> 3) << 10) | (usize::from(p[1] >> 3) << 5) | usize::from(p[2] >> 3);
            lut[c]
        })
        .collect()
}

/// The GIF frame of picture `idx` (`w` × `h` palette indices): only the
/// rectangle that changed since `prev`, over the picture before.
fn frame_of<'a>(prev: Option<&[u8]>, idx: &[u8], w: usize, h: usize, delay: u16) -> gif::Frame<'a> {
    let (x0, y0, x1, y1) = match prev {
        None => (0, 0, w, h),
        Some(p) => changed(p, idx, w, h).unwrap_or((0, 0, 1, 1)),
    };
    let mut sub = Vec::with_capacity((x1 - x0) * (y1 - y0));
    for y in y0..y1 {
        sub.extend_from_slice(&idx[y * w + x0..y * w + x1]);
    }
    gif::Frame {
        delay,
        dispose: gif::DisposalMethod::Keep,
        left: x0 as u16,
        top: y0 as u16,
        width: (x1 - x0) as u16,
        height: (y1 - y0) as u16,
        buffer: std::borrow::Cow::Owned(sub),
        ..gif::Frame::default()
    }
}

/// The animation as a GIF, `width` × `height` px, one picture per frame
/// (the frames must be at one rate: the delay is the first interval,
/// in hundredths of a second as GIF counts). Every bell must have the same
/// frame times.
pub fn animation_gif(anim: &Animation, width: u32, height: u32) -> Result<Vec<u8>, PlotError> {
    anim.check()?;
    check_size(width, height)?;
    let frames = &anim.bells[0].frames;
    if anim.bells.iter().any(|b| b.frames.len() != frames.len()) || frames.len() < 2 {
        return Err(PlotError::Empty("a GIF needs every bell's frames at the same times"));
    }
    let delay = ((frames[1].t - frames[0].t) * 100.0).round().clamp(2.0, 65535.0) as u16;
    crate::fonts::ensure();
    let l = Layout::new(anim, width, height);
    let pal = palette();
    let lut = lookup(&pal);
    let flat: Vec<u8> = pal.iter().flatten().copied().collect();
    let (w, h) = (width as usize, height as usize);
    let painter = Painter {
        anim,
        title_font: ("sans-serif", l.font).into_font().color(&rgb(colours::INK)),
        caption_font: ("sans-serif", 0.85 * l.font).into_font().color(&rgb(colours::INK)),
        l,
    };
    let mut out = Vec::new();
    {
        let mut enc = gif::Encoder::new(&mut out, width as u16, height as u16, &flat).map_err(gif_err)?;
        enc.set_repeat(gif::Repeat::Infinite).map_err(gif_err)?;
        let mut rgb_buf = vec![0u8; w * h * 3];
        let mut prev: Option<Vec<u8>> = None;
        for (j, now) in frames.iter().enumerate() {
            {
                let area = crate::bitmap_text::Bitmap::with_buffer(&mut rgb_buf, (width, height)).into_drawing_area();
                painter.picture(&area, j, now)?;
            }
            let idx = indexed(&rgb_buf, &lut);
            enc.write_frame(&frame_of(prev.as_deref(), &idx, w, h, delay))
                .map_err(gif_err)?;
            prev = Some(idx);
        }
    }
    Ok(out)
}

/// The smallest rectangle `[x0, x1) × [y0, y1)` holding every pixel that
/// differs; `None` if none does.
fn changed(a: &[u8], b: &[u8], w: usize, h: usize) -> Option<(usize, usize, usize, usize)> {
    let (mut x0, mut y0, mut x1, mut y1) = (w, h, 0, 0);
    for y in 0..h {
        let (ra, rb) = (&a[y * w..(y + 1) * w], &b[y * w..(y + 1) * w]);
        if ra == rb {
            continue;
        }
        let first = ra.iter().zip(rb).position(|(p, q)| p != q).unwrap_or(0);
        let last = ra.iter().zip(rb).rposition(|(p, q)| p != q).unwrap_or(0);
        x0 = x0.min(first);
        x1 = x1.max(last + 1);
        y0 = y0.min(y);
        y1 = y1.max(y + 1);
    }
    (x1 > x0).then_some((x0, y0, x1, y1))
}

#[cfg(test)]
mod tests {
    use super::super::model::tests::swinging;
    use super::*;

    #[test]
    fn a_gif_has_one_picture_per_frame_and_loops() {
        let a = swinging(30, 25.0);
        let bytes = animation_gif(&a, 200, 200).expect("drawn");
        assert_eq!(&bytes[..6], b"GIF89a");
        let mut opts = gif::DecodeOptions::new();
        opts.set_color_output(gif::ColorOutput::Indexed);
        let mut d = opts.read_info(&bytes[..]).expect("a GIF");
        let mut n = 0;
        while let Some(f) = d.read_next_frame().expect("a frame") {
            assert_eq!(f.delay, 4, "25 frames a second");
            n += 1;
        }
        assert_eq!(n, 30);
    }

    #[test]
    fn the_bell_is_drawn_where_the_frame_puts_it() {
        // Bell down (θ = 0) or up (θ = 180 deg): bronze below the pivot
        // or above it.
        let bronze = palette().iter().position(|p| {
            let c = rgb(colours::BRONZE);
            *p == [c.0, c.1, c.2]
        });
        for (theta, below) in [(0.0, true), (std::f64::consts::PI, false)] {
            let mut a = swinging(2, 25.0);
            for f in &mut a.bells[0].frames {
                f.theta = theta;
                f.phi = 0.0;
            }
            a.bells[0].strikes.clear();
            let bytes = animation_gif(&a, 200, 200).expect("drawn");
            let mut opts = gif::DecodeOptions::new();
            opts.set_color_output(gif::ColorOutput::Indexed);
            let mut d = opts.read_info(&bytes[..]).expect("a GIF");
            let f = d.read_next_frame().expect("read").expect("a frame");
            let l = Layout::new(&a, 200, 200);
            let (cx, cy) = (l.centres[0][0] as usize, l.centres[0][1] as usize);
            let count = |rows: std::ops::Range<usize>| {
                rows.map(|y| usize::from(f.buffer[y * 200 + cx] as usize == bronze.expect("in palette")))
                    .sum::<usize>()
            };
            let (down, up) = (count(cy + 1..200), count(0..cy));
            assert_eq!(down > up, below, "theta {theta}: {down} below, {up} above");
        }
    }
}
