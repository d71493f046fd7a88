//! The one typeface every plot uses, carried inside the binary: DejaVu
//! Sans (Bitstream Vera licence, `fonts/DejaVuSans-LICENSE.txt`), so that
//! PNG text needs no fontconfig and no system font, and SVG text is laid
//! out with the same metrics on every machine.

use std::sync::Once;

use plotters::style::{register_font, FontStyle};

/// DejaVu Sans 2.37 (760 kB): Latin, Greek (θ, φ) and the maths signs the
/// plots use.
pub(crate) static DEJAVU_SANS: &[u8] = include_bytes!("../fonts/DejaVuSans.ttf");

/// The family name the plots ask for; registered as DejaVu Sans.
pub(crate) const FAMILY: &str = "sans-serif";

/// Register the embedded font under [`FAMILY`], once per process, before
/// anything is drawn. Other styles (bold, italic) fall back to it.
pub(crate) fn ensure() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        // The bytes are a font file built into the binary; a failure here
        // is a broken build, caught by every plot test.
        if register_font(FAMILY, FontStyle::Normal, DEJAVU_SANS).is_err() {
            unreachable!("the embedded DejaVu Sans does not parse");
        }
    });
}

#[cfg(test)]
mod tests {
    use super::*;
    use plotters::style::{FontDesc, FontFamily};

    #[test]
    fn the_embedded_font_lays_out_text() {
        ensure();
        let font = FontDesc::new(FontFamily::SansSerif, 20.0, FontStyle::Normal);
        let (w, _) = font.box_size("θ = 170°").expect("font found");
        // DejaVu Sans at 20 px: eight glyphs, each a few px wide.
        assert!(w > 40 && w < 160, "width {w} px");
        let italic = FontDesc::new(FontFamily::SansSerif, 20.0, FontStyle::Italic);
        assert!(
            italic.box_size("x").is_ok(),
            "other styles fall back to the regular face"
        );
    }
}
