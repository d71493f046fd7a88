//! The animation as one self-contained SVG file: SMIL animations, no
//! script, so it plays in a browser and in a README. The bell's group
//! turns through θ and the clapper's, inside it, through φ; their key
//! frames are the frames, at their own times.

use std::fmt::Write as _;

use super::figure::{colours, Part, Shape};
use super::layout::{caption, check_size, esc, Layout};
use super::model::{Animation, BellMotion, FLASH_S};
use crate::PlotError;

fn part_svg(o: &mut String, p: &Part) {
    let paint = format!(
        r#" fill="{}" stroke="{}" stroke-width="{}"{}"#,
        p.fill.unwrap_or("none"),
        p.stroke.unwrap_or("none"),
        p.width,
        if p.dashed {
            format!(r#" stroke-dasharray="{} {}""#, 4.0 * p.width, 3.0 * p.width)
        } else {
            String::new()
        }
    );
    let pts = |points: &[[f64; 2]]| {
        points
            .iter()
            .map(|q| format!("{:.5},{:.5}", q[0], q[1]))
            .collect::<Vec<_>>()
            .join(" ")
    };
    let _ = match &p.shape {
        Shape::Polygon { points } => writeln!(o, r#"<polygon points="{}"{paint}/>"#, pts(points)),
        Shape::Line { points } => writeln!(
            o,
            r#"<polyline points="{}"{paint} stroke-linecap="round"/>"#,
            pts(points)
        ),
        Shape::Circle { centre, radius } => writeln!(
            o,
            r#"<circle cx="{:.5}" cy="{:.5}" r="{:.5}"{paint}/>"#,
            centre[0], centre[1], radius
        ),
    };
}

/// `animateTransform` turning a group through `angles` (rad) at `times`
/// (s), looping over `duration`. Angles are written in full (shortest
/// round-trip decimals of the degrees), so the drawn angle at a key time
/// is the frame's to the last bit.
fn rotation(o: &mut String, times: &[f64], angles: impl Iterator<Item = f64>, duration: f64) {
    let key_times: Vec<String> = times.iter().map(|t| format!("{}", t / duration)).collect();
    let values: Vec<String> = angles.map(|a| format!("{}", a.to_degrees())).collect();
    let _ = writeln!(
        o,
        r#"<animateTransform attributeName="transform" type="rotate" calcMode="linear" dur="{duration}s" repeatCount="indefinite" keyTimes="{}" values="{}"/>"#,
        key_times.join(";"),
        values.join(";")
    );
}

/// Bell `i` of the animation, `b`, its pivot at `c` and its caption at
/// `cap` (px): the vertical, the bell turning through θ, the clapper
/// inside it through φ, each strike's flash, and the caption.
fn bell_svg(o: &mut String, anim: &Animation, l: &Layout, i: usize, b: &BellMotion, c: [f64; 2], cap: [f64; 2]) {
    let dur = anim.duration;
    let f = &b.figure;
    let times: Vec<f64> = b.frames.iter().map(|fr| fr.t).collect();
    let _ = writeln!(
        o,
        r#"<g id="bell-{i}" transform="translate({:.3} {:.3}) scale({} {})">"#,
        c[0], c[1], l.scale, -l.scale
    );
    let _ = writeln!(
        o,
        r#"<line x1="0" y1="0" x2="0" y2="{}" stroke="{}" stroke-width="{}" stroke-dasharray="{} {}"/>"#,
        -f.reach,
        colours::MARK,
        0.004 * f.diameter,
        0.03 * f.diameter,
        0.02 * f.diameter
    );
    let _ = writeln!(o, r#"<g class="bell">"#);
    rotation(o, &times, b.frames.iter().map(|fr| fr.theta), dur);
    for p in &f.bell {
        part_svg(o, p);
    }
    let _ = writeln!(
        o,
        r#"<g transform="translate({} {})"><g class="clapper">"#,
        f.clapper_pivot[0], f.clapper_pivot[1]
    );
    rotation(o, &times, b.frames.iter().map(|fr| fr.phi), dur);
    for p in &f.clapper {
        part_svg(o, p);
    }
    let _ = writeln!(o, "</g></g>");
    for s in &b.strikes {
        let at = f.strike_points[usize::from(s.side > 0)];
        let on = s.t / dur;
        let off = ((s.t + FLASH_S) / dur).min(1.0);
        let r = if s.first { 0.07 } else { 0.045 } * f.diameter;
        let _ = writeln!(
            o,
            r#"<circle class="strike" data-t="{}" cx="{:.5}" cy="{:.5}" r="{:.5}" fill="{}" stroke="{}" stroke-width="{:.5}" opacity="0"><animate attributeName="opacity" calcMode="discrete" dur="{dur}s" repeatCount="indefinite" keyTimes="0;{on};{off}" values="0;1;0"/></circle>"#,
            s.t,
            at[0],
            at[1],
            r,
            colours::FLASH,
            colours::FLASH_RIM,
            0.01 * f.diameter
        );
    }
    let _ = writeln!(o, "</g></g>");
    let _ = writeln!(
        o,
        r#"<text x="{:.1}" y="{:.1}" font-size="{:.1}" text-anchor="middle" fill="{}">{}</text>"#,
        cap[0],
        cap[1],
        0.85 * l.font,
        colours::INK,
        esc(&caption(anim, b))
    );
}

/// The animation as SVG text, `width` × `height` px.
pub fn animation_svg(anim: &Animation, width: u32, height: u32) -> Result<String, PlotError> {
    anim.check()?;
    check_size(width, height)?;
    let l = Layout::new(anim, width, height);
    let dur = anim.duration;
    let mut o = String::new();
    let _ = writeln!(
        o,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" viewBox="0 0 {width} {height}" font-family="DejaVu Sans, Verdana, sans-serif">"#
    );
    let _ = writeln!(o, "<title>{}</title>", esc(&anim.title));
    let _ = writeln!(
        o,
        r#"<rect width="{width}" height="{height}" fill="{}"/>"#,
        colours::PAPER
    );
    let _ = writeln!(
        o,
        r#"<text x="{}" y="{}" font-size="{}" text-anchor="middle" fill="{}">{}</text>"#,
        l.width / 2.0,
        1.3 * l.font,
        l.font,
        colours::INK,
        esc(&anim.title)
    );
    for (i, ((b, c), cap)) in anim.bells.iter().zip(&l.centres).zip(&l.captions).enumerate() {
        bell_svg(&mut o, anim, &l, i, b, *c, *cap);
    }
    // A bar that fills over the animation: where in it you are.
    let _ = writeln!(
        o,
        r#"<rect x="0" y="{}" height="4" width="0" fill="{}"><animate attributeName="width" from="0" to="{width}" dur="{dur}s" repeatCount="indefinite"/></rect>"#,
        l.height - 4.0,
        colours::MARK
    );
    o.push_str("</svg>\n");
    Ok(o)
}

#[cfg(test)]
mod tests {
    use super::super::model::tests::swinging;
    use super::*;

    /// The `values` of the `n`th animateTransform.
    fn values(svg: &str, n: usize, key: &str) -> Vec<f64> {
        let at = svg.match_indices("<animateTransform").nth(n).expect("present").0;
        let rest = &svg[at..];
        let start = rest.find(&format!("{key}=\"")).expect("key") + key.len() + 2;
        let end = start + rest[start..].find('"').expect("closed");
        rest[start..end]
            .split(';')
            .map(|v| v.parse().expect("number"))
            .collect()
    }

    #[test]
    fn the_key_frames_are_the_frames_to_the_bit() {
        let a = swinging(100, 25.0);
        let svg = animation_svg(&a, 400, 400).expect("drawn");
        let theta = values(&svg, 0, "values");
        let phi = values(&svg, 1, "values");
        let times = values(&svg, 1, "keyTimes");
        assert_eq!(theta.len(), 100);
        for (k, f) in a.bells[0].frames.iter().enumerate() {
            assert_eq!(theta[k], f.theta.to_degrees());
            assert_eq!(phi[k], f.phi.to_degrees());
            assert_eq!(times[k] * a.duration, f.t, "frame {k}");
        }
        assert_eq!(*times.last().expect("frames"), 1.0);
    }

    #[test]
    fn text_is_escaped_and_strikes_flash() {
        let a = swinging(100, 25.0);
        let svg = animation_svg(&a, 400, 400).expect("drawn");
        assert!(svg.contains("test &lt;bell&gt; &amp; co"));
        assert_eq!(svg.matches(r#"class="strike""#).count(), a.bells[0].strikes.len());
    }

    #[test]
    fn bad_sizes_are_refused() {
        let a = swinging(10, 25.0);
        assert!(animation_svg(&a, 10, 400).is_err());
        assert!(animation_svg(&a, 400, 100_000).is_err());
    }
}
