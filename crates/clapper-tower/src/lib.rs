//! # clapper-tower
//!
//! A ring of bells in its tower (issue 47, docs/tower.md): the rows of a
//! touch (rounds, a method through `bellframe`, or rows given), every bell
//! rung through it at the band's speed with its own strokes simulated by
//! clapper-core (each stroke's frame load, hand and back, placed at the
//! bell's strike times), the horizontal forces of all bells added in the
//! tower's two directions, the moments about the tower's base, their
//! spectra, the sway of the bell chamber as two linear oscillators, and
//! which bells' swing directions to turn to reduce it.
//!
//! No file, terminal or network I/O. Units are SI; angles in radians
//! except where a field's name says degrees. Tower axes: x east, y north,
//! z up; a swing direction is the azimuth (clockwise from north) towards
//! which a bell's positive θ points.

#![warn(missing_docs)]

pub mod pendulum;
pub mod rows;
pub mod spectrum;
pub mod stroke_loads;
pub mod sway;
pub mod touch;

use clapper_core::stroke::SimError;

pub use rows::{touch_rows, TouchSpec};
pub use sway::Sway;
pub use touch::{ring_touch, RingBell, Timing, TouchResult};

/// What can go wrong.
#[derive(Debug, thiserror::Error)]
pub enum TowerError {
    /// The rows asked for cannot be made.
    #[error("rows: {0}")]
    Rows(String),
    /// A bell cannot be rung as asked.
    #[error("ring: {0}")]
    Ring(String),
    /// The tower's numbers are out of range.
    #[error("tower: {0}")]
    Tower(String),
    /// A stroke's simulation failed.
    #[error("simulation: {0}")]
    Sim(#[from] SimError),
}

/// A bell's place in the frame.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct FramePlace {
    /// Azimuth of the bell's swing (deg, clockwise from north, towards
    /// positive θ): 0 swings north-south, 90 east-west.
    pub swing_deg: f64,
    /// Pivot's position east of the tower's centre line (m).
    pub x_m: f64,
    /// Pivot's position north of the tower's centre line (m).
    pub y_m: f64,
    /// Height of the pivot above the tower's base (m), for the moments.
    pub pivot_height_m: f64,
}

impl FramePlace {
    /// The unit vector (east, north) of the swing direction.
    pub fn direction(&self) -> (f64, f64) {
        let a = self.swing_deg.to_radians();
        (a.sin(), a.cos())
    }

    /// The same place with the bell turned 90 deg in the frame.
    pub fn turned(&self) -> Self {
        Self {
            swing_deg: (self.swing_deg + 90.0).rem_euclid(360.0),
            ..*self
        }
    }
}

/// The tower: its sway in two directions.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Tower {
    /// East-west sway (the x direction).
    pub east_west: Sway,
    /// North-south sway (the y direction).
    pub north_south: Sway,
}

impl Tower {
    /// Checks both directions.
    pub fn validate(&self) -> Result<(), TowerError> {
        self.east_west.validate("east-west")?;
        self.north_south.validate("north-south")
    }
}
