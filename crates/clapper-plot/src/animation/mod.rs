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
mod layout;
mod model;
mod svg;

pub use figure::{colours, rotate, Figure, Part, Shape};
pub use gif_file::animation_gif;
pub use html::{animation_html, player_json, PLAYER_JS};
pub use layout::columns;
pub use model::{Animation, BellMotion, Frame, StrikeMark, FLASH_S};
pub use svg::animation_svg;
