//! A bell's motion read from a 3-axis accelerometer on its headstock
//! (`clapper ringing-log`, docs/model.md §13): the bell's angle swing by
//! swing, bottom dead centre, the clapper's strikes, the swing's amplitude,
//! odd-struckness, and the phases of a session (down, raising, up,
//! ringing, lowering).
//!
//! The method, in order:
//! 1. **Strikes** are bursts: the clapper's impact shakes the headstock
//!    far harder and faster than the swing, often past the sensor's range.
//!    A sample is a burst when it departs from the straight line through
//!    the two samples before it (a causal prediction, so that the sample
//!    before an impact is never blamed for it) by more than 6 robust
//!    standard deviations of that departure over the log (at least 1.5
//!    m/s²), or is clipped. A strike is the first burst sample.
//! 2. **The angle**: θ = atan2(tangential, radial) on the samples that
//!    are not bursts (interpolated across those that are), then corrected
//!    for the swing's own accelerations at the sensor,
//!    g sin θ = f_t + h θ'' + d θ'² and g cos θ = f_r + h θ'² − d θ'' (h the sensor's distance
//!    above the pivot, d across the axis: read from the bell's free falls
//!    from the balance, else given or fitted so that the corrected force
//!    is g throughout), θ' and θ'' from local fits; twice.
//! 3. **Strokes**: each crossing of θ = 0 while the bell moves is a bottom
//!    dead centre, timed by the zero of the tangential reading corrected
//!    by h θ'' + d θ'² (a line over ±12 deg of the bottom); the stroke's
//!    amplitude is the turning point it fell from; its strike the first
//!    burst after it.
//! 4. **Phases**: rests (no motion for 1.5 s or more) are down (near
//!    θ = 0) or up (near the balance); what moves between two rests is
//!    raising (from down to up), ringing (from up; the full swings), and
//!    lowering (the swings after the last full one, down to rest).
//! 0. **Tilt**: a sensor not square on its nut reads the resting bell
//!    (which hangs plumb) a few degrees off; that angle, from the rests
//!    near the bottom, is turned out of the readings first.
//! 5. **Hand and back**: the bell is set at handstroke, so a stroke that
//!    starts from the side the bell was set on is a handstroke (with no
//!    set, the side with θ > 0 on the sensor's axes).
//!
//! The files, leaf first: [`types`](AccelLog) (the data), `fits` (local
//! fits, unwrapping), `bursts` (step 1), `rests`, `falls` and `calibrate`
//! (the sensor's place and calibration), `orient` (which way is down),
//! `reading` (step 2), `bottoms` (step 3), `phases` (step 4), `checks`,
//! `tops` (what each stroke rose to: a stand on the stay, or a turning
//! point hidden by the headstock's ringing, timed), `dying` and `unring`
//! (the headstock's ring taken out of the readings: one dying oscillation
//! from each strike to the next, and local fits), `plausible` (whether
//! it is a bell's log at all) and `analyse` (the steps in order).

mod analyse;
mod bottoms;
mod bursts;
mod calibrate;
pub mod checks;
mod dying;
mod falls;
mod fits;
mod orient;
mod phases;
mod plausible;
mod reading;
mod rests;
mod tops;
mod types;
mod unring;

pub use analyse::{analyse_log, LogAnalysis, MAX_ODD_SE};
pub use bottoms::GAP;
pub use bursts::{RINGING_S, STRIKE_S};
pub use calibrate::{Calibration, CalibrationSe};
pub use orient::{orientation, Orientation};
pub use phases::STAND_MAX_S;
pub use plausible::{plausibility, Plausibility, GRAVITY_BAND, MAX_JUMPS};
pub use tops::{STAND_PAST, TIMED_MAX};
pub use types::{AccelLog, ClapperingStart, LogOptions, LogStroke, Phase, PhaseKind, Stand};
