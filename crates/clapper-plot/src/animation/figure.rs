//! A bell and its clapper drawn to scale from the model's numbers
//! (docs/model.md §1, §10.1): where the clapper pivot is (r along the
//! bell's axis, d across it), how long the clapper is (b), and the angles
//! at which it touches the bell (the stops). The bell's outline is a
//! plausible English profile sized so that the clapper's ball meets its
//! soundbow exactly at the stops: the picture then shows the contact where
//! the model has it, whatever the bell.

use clapper_core::bell::Bell;
use serde::Serialize;

/// Density of the ball's iron (kg/m³).
const IRON: f64 = 7850.0;
/// Share of the clapper's mass in its ball: a wrought or cast clapper's
/// ball holds about half; the shaft and flight the rest.
const BALL_SHARE: f64 = 0.5;

/// The outer profile of an English bell from the lip up, as (radius over
/// the mouth's radius, height over the mouth's diameter D): soundbow,
/// waist, shoulder and crown, the shape of a typical tuned bell, about
/// 0.79 D tall.
const OUTER: [(f64, f64); 12] = [
    (1.0, 0.0),
    (1.0, 0.08),
    (0.965, 0.14),
    (0.89, 0.22),
    (0.80, 0.34),
    (0.74, 0.46),
    (0.70, 0.58),
    (0.67, 0.66),
    (0.62, 0.72),
    (0.50, 0.765),
    (0.25, 0.785),
    (0.0, 0.79),
];

/// The inner profile: the soundbow is D/13 thick (0.154 of the radius) at
/// the soundbow, 0.08 D above the lip; the waist about a third of that.
const INNER: [(f64, f64); 11] = [
    (0.9, 0.0),
    (0.846, 0.08),
    (0.835, 0.14),
    (0.815, 0.22),
    (0.74, 0.34),
    (0.685, 0.46),
    (0.645, 0.58),
    (0.615, 0.66),
    (0.55, 0.70),
    (0.35, 0.73),
    (0.0, 0.74),
];

/// The inner profile's radius (over the mouth's radius) at height `h`
/// above the lip (over D), between its points.
fn inner_radius_at(h: f64) -> f64 {
    for w in INNER.windows(2) {
        let ((x0, h0), (x1, h1)) = (w[0], w[1]);
        if h <= h1 {
            return x0 + (x1 - x0) * ((h - h0) / (h1 - h0)).clamp(0.0, 1.0);
        }
    }
    INNER[INNER.len() - 1].0
}

/// One shape of a drawing, in metres.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Shape {
    /// A closed polygon.
    Polygon {
        /// Corners (m).
        points: Vec<[f64; 2]>,
    },
    /// An open line through the points.
    Line {
        /// Points (m).
        points: Vec<[f64; 2]>,
    },
    /// A circle.
    Circle {
        /// Centre (m).
        centre: [f64; 2],
        /// Radius (m).
        radius: f64,
    },
}

/// A shape with its paint.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Part {
    /// What is drawn.
    #[serde(flatten)]
    pub shape: Shape,
    /// Fill colour (`#rrggbb`), if filled.
    pub fill: Option<&'static str>,
    /// Outline colour, if outlined.
    pub stroke: Option<&'static str>,
    /// Outline width (m, so that it scales with the bell).
    pub width: f64,
    /// Whether the outline is dashed.
    pub dashed: bool,
}

impl Part {
    fn filled(shape: Shape, fill: &'static str, stroke: &'static str, width: f64) -> Self {
        Part {
            shape,
            fill: Some(fill),
            stroke: Some(stroke),
            width,
            dashed: false,
        }
    }

    fn line(points: Vec<[f64; 2]>, stroke: &'static str, width: f64, dashed: bool) -> Self {
        Part {
            shape: Shape::Line { points },
            fill: None,
            stroke: Some(stroke),
            width,
            dashed,
        }
    }

    fn points(&self) -> Vec<[f64; 2]> {
        match &self.shape {
            Shape::Polygon { points } | Shape::Line { points } => points.clone(),
            Shape::Circle { centre, radius } => vec![
                [centre[0] + radius, centre[1]],
                [centre[0] - radius, centre[1]],
                [centre[0], centre[1] + radius],
                [centre[0], centre[1] - radius],
            ],
        }
    }
}

/// Colours of the drawing; the GIF's palette is built from these.
pub mod colours {
    /// Bell metal.
    pub const BRONZE: &str = "#b5893f";
    /// Outlines of the bell.
    pub const BRONZE_DARK: &str = "#5c4213";
    /// The stay.
    pub const WOOD: &str = "#8a5a2b";
    /// The wheel, pale: it is beside the bell, not in front of it.
    pub const WHEEL: &str = "#d8bf9f";
    /// The headstock.
    pub const WOOD_DARK: &str = "#5a3a1a";
    /// The clapper.
    pub const IRON: &str = "#3a3f47";
    /// Marks: the contact angles, the vertical.
    pub const MARK: &str = "#8c8c8c";
    /// A strike's flash.
    pub const FLASH: &str = "#ffcc00";
    /// A strike's flash, its rim.
    pub const FLASH_RIM: &str = "#d9480f";
    /// Text and axes.
    pub const INK: &str = "#222222";
    /// Background.
    pub const PAPER: &str = "#ffffff";
    /// The hand side's marks.
    pub const HAND: &str = "#1f6fb4";
    /// The back side's marks.
    pub const BACK: &str = "#c2410c";
}

/// A bell and clapper to draw, in the bell's own frame: metres, the bell's
/// pivot (gudgeons) at the origin, y up (away from the mouth), x across
/// toward the back side (φ > 0). The clapper's parts are in its own frame:
/// its pivot at the origin, hanging down −y. At bell angle θ the bell's
/// frame is turned by θ (anticlockwise, y up) in the tower, and the
/// clapper's by φ more about [`Figure::clapper_pivot`].
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Figure {
    /// The bell, headstock, stay, wheel and contact marks, in the bell's frame.
    pub bell: Vec<Part>,
    /// The clapper (shaft, ball, flight), in its own frame.
    pub clapper: Vec<Part>,
    /// The clapper pivot in the bell's frame: (d, −r) (m).
    pub clapper_pivot: [f64; 2],
    /// The clapper angles φ at the hand side's and the back side's stops
    /// (rad): negative, positive.
    #[serde(rename = "stops_rad")]
    pub stops: [f64; 2],
    /// Where the ball touches the bell at the hand and back stops, in the
    /// bell's frame (m).
    pub strike_points: [[f64; 2]; 2],
    /// Mouth diameter D of the drawn bell (m).
    pub diameter: f64,
    /// Height of the lip in the bell's frame (m, negative: below the pivot).
    pub lip: f64,
    /// Height of the drawn bell, lip to crown (m).
    pub height: f64,
    /// Distance from the bell's pivot that holds every part at any angle (m).
    pub reach: f64,
}

/// Where the drawn bell's profile sits, in the bell's frame (m).
struct Profile {
    /// Height of the lip (m, negative: below the pivot).
    lip: f64,
    /// Metres per unit of the profile's height (D for a typical bell).
    u: f64,
    /// Mouth diameter D (m).
    d: f64,
}

impl Profile {
    /// The profile fitted to a clapper hung at `pivot`, its ball of radius
    /// `ball` (m) touching the inner wall at `strike_points`.
    ///
    /// Heights from where the clapper hangs: the crown's inside just above
    /// its pivot, the lip just below its ball hanging straight down (its
    /// flight may hang below). The profile is stretched to fit between
    /// them (`u`, D for a typical bell), and the mouth is as wide as makes
    /// the inner wall meet the ball at the strike's height.
    fn fitted(bell: &Bell, ball: f64, strike_points: &[[f64; 2]; 2]) -> Profile {
        let inner = 0.5 * (strike_points[0][0].abs() + strike_points[1][0].abs());
        let strike_y = 0.5 * (strike_points[0][1] + strike_points[1][1]);
        let crown_inside = -bell.r + 0.6 * ball;
        let lip = (-bell.r - bell.b - 1.1 * ball).min(strike_y - 0.3 * ball);
        let u = (crown_inside - lip) / INNER[INNER.len() - 1].1;
        let h = ((strike_y - lip) / u).clamp(0.0, 0.7);
        let d = (2.0 * inner / inner_radius_at(h)).max(2e-3);
        Profile { lip, u, d }
    }

    /// The bell's cross-section: outer wall up one side and down the
    /// other, then the inner wall back (m).
    fn outline(&self) -> Vec<[f64; 2]> {
        let radius = self.d / 2.0;
        let at = |(x, h): (f64, f64), side: f64| [side * x * radius, self.lip + h * self.u];
        let mut outline: Vec<[f64; 2]> = OUTER.iter().map(|&p| at(p, 1.0)).collect();
        outline.extend(OUTER.iter().rev().skip(1).map(|&p| at(p, -1.0)));
        outline.extend(INNER.iter().map(|&p| at(p, -1.0)));
        outline.extend(INNER.iter().rev().skip(1).map(|&p| at(p, 1.0)));
        outline
    }

    /// Height of the crown's top in the bell's frame (m).
    fn crown(&self) -> f64 {
        self.lip + OUTER[OUTER.len() - 1].1 * self.u
    }
}

/// A rectangle from corner (x0, y0) to corner (x1, y1).
fn rect(x0: f64, y0: f64, x1: f64, y1: f64) -> Shape {
    Shape::Polygon {
        points: vec![[x0, y0], [x1, y0], [x1, y1], [x0, y1]],
    }
}

/// The wheel with its spokes (so that it is seen to turn), the stay, the
/// headstock, the bell and the contact marks from `pivot` to each strike
/// point, and the gudgeon, in the bell's frame.
fn bell_parts(profile: &Profile, pivot: [f64; 2], strike_points: &[[f64; 2]; 2]) -> Vec<Part> {
    let d = profile.d;
    let crown = profile.crown();
    let top = crown.max(0.0) + 0.1 * d;
    let wheel = 0.7 * d;
    let thin = 0.006 * d;
    let mut parts = vec![Part {
        shape: Shape::Circle {
            centre: [0.0, 0.0],
            radius: wheel,
        },
        fill: None,
        stroke: Some(colours::WHEEL),
        width: 0.02 * d,
        dashed: false,
    }];
    for k in 0..6 {
        let a = std::f64::consts::PI * (k as f64 / 3.0 + 1.0 / 6.0);
        parts.push(Part::line(
            vec![[0.0, 0.0], [wheel * a.cos(), wheel * a.sin()]],
            colours::WHEEL,
            0.008 * d,
            false,
        ));
    }
    parts.push(Part::filled(
        rect(-0.02 * d, top, 0.02 * d, top + 0.45 * d),
        colours::WOOD,
        colours::WOOD_DARK,
        thin,
    ));
    parts.push(Part::filled(
        rect(-0.28 * d, crown.min(0.0) - 0.02 * d, 0.28 * d, top),
        colours::WOOD_DARK,
        colours::WOOD_DARK,
        thin,
    ));
    parts.push(Part::filled(
        Shape::Polygon {
            points: profile.outline(),
        },
        colours::BRONZE,
        colours::BRONZE_DARK,
        thin,
    ));
    for (p, colour) in strike_points.iter().zip([colours::HAND, colours::BACK]) {
        parts.push(Part::line(vec![pivot, *p], colour, 0.5 * thin, true));
    }
    parts.push(Part::filled(
        Shape::Circle {
            centre: [0.0, 0.0],
            radius: 0.03 * d,
        },
        colours::IRON,
        colours::IRON,
        thin,
    ));
    parts
}

/// The clapper in its own frame: shaft, flight, a ball of radius `ball`
/// centred `b` below its pivot (m), and the pivot's mark; outlines `thin`
/// wide (m).
fn clapper_parts(b: f64, ball: f64, thin: f64) -> Vec<Part> {
    let shaft = (b - ball).max(0.0);
    vec![
        Part::line(vec![[0.0, 0.0], [0.0, -shaft]], colours::IRON, 0.45 * ball, false),
        Part::filled(
            rect(-0.22 * ball, -b, 0.22 * ball, -b - 2.2 * ball),
            colours::IRON,
            colours::IRON,
            thin,
        ),
        Part::filled(
            Shape::Circle {
                centre: [0.0, -b],
                radius: ball,
            },
            colours::IRON,
            colours::INK,
            thin,
        ),
        Part::filled(
            Shape::Circle {
                centre: [0.0, 0.0],
                radius: 0.3 * ball,
            },
            colours::MARK,
            colours::IRON,
            thin,
        ),
    ]
}

/// The farthest any point of `parts` lies from the origin (m).
fn farthest(parts: &[Part]) -> f64 {
    parts
        .iter()
        .flat_map(Part::points)
        .map(|p| p[0].hypot(p[1]))
        .fold(0.0, f64::max)
}

impl Figure {
    /// The drawing of `bell`: the ball (half the clapper's mass, iron)
    /// centred at b, the clapper's centre of mass; the bell's lip just below
    /// the hanging ball, and its mouth sized so that the ball touches its
    /// inner wall at both stops (their mean, for an offset or skewed bell);
    /// headstock, stay and a wheel 1.4 D across.
    pub fn of(bell: &Bell) -> Figure {
        let (hand, back) = bell.contact_angles();
        let stops = [-hand, back];
        let pivot = [bell.hanging.pivot_offset, -bell.r];
        let ball = (BALL_SHARE * bell.clapper_mass / (IRON * 4.0 / 3.0 * std::f64::consts::PI)).cbrt();
        // A ball larger than the clapper is long would hide the shaft.
        let ball = ball.min(0.35 * bell.b);
        let centre = |phi: f64| [pivot[0] + bell.b * phi.sin(), pivot[1] - bell.b * phi.cos()];
        // The ball meets the bell on the side it swings toward.
        let touch = |phi: f64| {
            let c = centre(phi);
            let s = phi.signum();
            [c[0] + s * ball * phi.cos(), c[1] + s * ball * phi.sin()]
        };
        let strike_points = [touch(stops[0]), touch(stops[1])];
        let profile = Profile::fitted(bell, ball, &strike_points);
        let parts = bell_parts(&profile, pivot, &strike_points);
        let clapper = clapper_parts(bell.b, ball, 0.006 * profile.d);
        let clapper_reach = pivot[0].hypot(pivot[1]) + farthest(&clapper);
        Figure {
            reach: farthest(&parts).max(clapper_reach),
            bell: parts,
            clapper,
            clapper_pivot: pivot,
            stops,
            strike_points,
            diameter: profile.d,
            lip: profile.lip,
            height: OUTER[OUTER.len() - 1].1 * profile.u,
        }
    }

    /// Where a point of the clapper's own frame is in the bell's frame,
    /// the clapper at angle `phi` (rad).
    pub fn clapper_to_bell(&self, p: [f64; 2], phi: f64) -> [f64; 2] {
        let [x, y] = rotate(p, phi);
        [x + self.clapper_pivot[0], y + self.clapper_pivot[1]]
    }
}

/// `p` turned anticlockwise (y up) by `angle` (rad).
pub fn rotate(p: [f64; 2], angle: f64) -> [f64; 2] {
    let (s, c) = angle.sin_cos();
    [c * p[0] - s * p[1], s * p[0] + c * p[1]]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ball_centre(f: &Figure, bell: &Bell, phi: f64) -> [f64; 2] {
        f.clapper_to_bell([0.0, -bell.b], phi)
    }

    #[test]
    fn the_ball_touches_the_soundbow_at_the_stops_and_not_before() {
        for bell in [Bell::lab(), Bell::gsm_tenor()] {
            let f = Figure::of(&bell);
            let ball = match f.clapper[2].shape {
                Shape::Circle { radius, .. } => radius,
                _ => unreachable!("the ball is the third part"),
            };
            for (k, &stop) in f.stops.iter().enumerate() {
                let c = ball_centre(&f, &bell, stop);
                let p = f.strike_points[k];
                // The touching point is one ball radius from the ball's centre
                // and lies on the bell's inner wall at its height.
                assert!(((p[0] - c[0]).hypot(p[1] - c[1]) - ball).abs() < 1e-12);
                let u = f.height / OUTER[OUTER.len() - 1].1;
                let wall = inner_radius_at((p[1] - f.lip) / u) * f.diameter / 2.0;
                assert!((p[0].abs() - wall).abs() < 1e-6 * f.diameter, "{} against {wall}", p[0]);
                // The ball hanging straight down is inside the mouth.
                assert!(ball_centre(&f, &bell, 0.0)[1] - ball > f.lip);
                // Halfway to the stop, the ball is clear of the wall.
                let half = ball_centre(&f, &bell, 0.5 * stop);
                assert!(half[0].abs() + ball < p[0].abs());
            }
            // The drawn bell is of a plausible size: 0.3-2.5 m across.
            assert!((0.3..2.5).contains(&f.diameter), "D = {}", f.diameter);
        }
    }

    #[test]
    fn the_tenor_is_drawn_larger_than_the_lab_bell() {
        let (lab, tenor) = (Figure::of(&Bell::lab()), Figure::of(&Bell::gsm_tenor()));
        assert!(tenor.diameter > 2.0 * lab.diameter);
        assert!(tenor.reach > lab.reach);
    }

    #[test]
    fn a_pivot_offset_moves_the_clapper_pivot_across() {
        let mut bell = Bell::lab();
        bell.hanging.pivot_offset = 0.01;
        let f = Figure::of(&bell);
        assert_eq!(f.clapper_pivot, [0.01, -bell.r]);
    }
}
