//! The ringing log's data: the log as read, how to read it, and the
//! phases and strokes found in it (a leaf: it imports nothing from its
//! siblings).

use clapper_core::bell::G;

/// An accelerometer log, its axes already named (m/s², s).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct AccelLog {
    /// The bell's name, when the log gives one.
    pub name: Option<String>,
    /// Sample times (s), increasing.
    pub t: Vec<f64>,
    /// Along the bell's axis, toward the crown (m/s²): +g with the bell
    /// down and still.
    pub radial: Vec<f64>,
    /// Across the bell's axis in its plane of swing (m/s²): g sin θ with
    /// the bell still at θ.
    pub tangential: Vec<f64>,
    /// Along the pivot's axis (m/s²): no swing, only strikes and noise.
    pub axle: Vec<f64>,
}

/// How to read a log.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LogOptions {
    /// The sensor's distance above the pivot along the bell's axis (m), if
    /// known; otherwise read from the bell's falls from the balance, or
    /// without one fitted from the whole log.
    pub sensor_along: Option<f64>,
    /// The sensor's range (m/s²): readings at 99 % of it or more are taken
    /// as clipped. Default 2 g, an ADXL345 at its ±2 g setting.
    pub clip: f64,
    /// A stroke rings "full" (ringing, not raising or lowering) when its
    /// amplitude is at least this (rad). Default 150 deg.
    pub full_swing: f64,
    /// Read which way is down from the log (its small swings: [`orientation`](super::orientation))
    /// and turn the radial and tangential axes over if they read it upside
    /// down. Default true; false takes the axes as given.
    pub find_down: bool,
    /// Read the angle through a strike's ringing headstock: the samples of a
    /// burst lasting over [`RINGING_S`](super::RINGING_S), after its strikes' first
    /// [`STRIKE_S`](super::STRIKE_S), that are not clipped go into the angle's fits, their
    /// vibration taken as noise (else the angle is bridged across the whole
    /// burst). Default true.
    pub through_ringing: bool,
}

impl Default for LogOptions {
    fn default() -> Self {
        Self {
            sensor_along: None,
            clip: 2.0 * G,
            full_swing: 150f64.to_radians(),
            find_down: true,
            through_ringing: true,
        }
    }
}

/// A part of a ringing session.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PhaseKind {
    /// At rest, mouth down.
    Down,
    /// Being rung up.
    Raising,
    /// Set at the balance.
    Up,
    /// Rung full circle.
    Ringing,
    /// Being rung down.
    Lowering,
}

impl PhaseKind {
    /// The name in JSON and text.
    pub fn name(self) -> &'static str {
        match self {
            PhaseKind::Down => "down",
            PhaseKind::Raising => "raising",
            PhaseKind::Up => "up",
            PhaseKind::Ringing => "ringing",
            PhaseKind::Lowering => "lowering",
        }
    }
}

/// A phase and when it held (s).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Phase {
    /// What the bell was doing.
    pub kind: PhaseKind,
    /// Start (s).
    pub start: f64,
    /// End (s).
    pub end: f64,
}

/// One swing read from the log.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LogStroke {
    /// Bottom dead centre (s).
    pub bdc: f64,
    /// Handstroke (else backstroke).
    pub hand: bool,
    /// The clapper's first strike after bottom dead centre (s), if any.
    pub strike: Option<f64>,
    /// Whether a gap in the log (samples lost: an interval over [`GAP`](super::GAP)
    /// times the usual) lies between bottom dead centre and the first burst after
    /// it: the clapper may have struck in the gap, so `strike` is `None`
    /// (not known, rather than not struck).
    pub strike_hidden: bool,
    /// The bell's angle at the strike (rad).
    pub strike_theta: Option<f64>,
    /// The turning point it fell from: |θ| (rad).
    pub amplitude: f64,
    /// The side it fell from: +1 (θ > 0) or −1.
    pub from_side: f64,
    /// The phase it belongs to.
    pub phase: PhaseKind,
    /// The moment of greatest speed near the bottom (s): the peak of |θ'|
    /// ([`checks`](super::checks)), which needs no zero of the angle; a check on `bdc`.
    pub speed_peak: Option<f64>,
    /// The standard error of `bdc` (s) that the sensor's calibration
    /// leaves (its tilt, offset and place across the axis).
    pub bdc_se: Option<f64>,
    /// The stay it rose to after its strike, if it stood there (a stand,
    /// or the bell set): where the next stroke falls from.
    pub stand: Option<Stand>,
    /// Whether `amplitude` was read from the swing's time (bottom to
    /// bottom, a free pendulum's half period) because the headstock's
    /// ringing hid the turning point.
    pub amplitude_timed: bool,
}

/// A stroke's end on the stay: the bell held at or past the balance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stand {
    /// Its angle from the bottom (rad): the amplitude the next stroke falls
    /// from.
    pub angle: f64,
    /// How long it stood (s): a rest's length, or the time the angle read
    /// stayed within 3 deg of the stand's; `None` when only its angle was
    /// read (a turning point past the balance).
    pub duration: Option<f64>,
    /// A set (a rest at the balance longer than [`STAND_MAX_S`](super::STAND_MAX_S)),
    /// not a stand within the ringing.
    pub set: bool,
}

impl LogStroke {
    /// Bottom dead centre to strike (s).
    pub fn bdc_to_strike(&self) -> Option<f64> {
        self.strike.map(|s| s - self.bdc)
    }
}

/// Where clappering starts while the bell is raised.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClapperingStart {
    /// When (s): the first strike of the raising (its bottom dead centre
    /// if a gap hides the strike).
    pub t: f64,
    /// The amplitude of the swing it is in (rad).
    pub amplitude: f64,
    /// Whether that swing is a handstroke.
    pub hand: bool,
}
