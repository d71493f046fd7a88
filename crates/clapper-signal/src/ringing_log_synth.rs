//! A synthetic accelerometer log with known truth (docs/model.md §13), for
//! testing [`crate::ringing_log`]: a bell at rest, raised by a ringer
//! ([`clapper_core::ringer::ring_up`]), set at the balance, rung full
//! circle, lowered, and at rest again, all simulated; the sensor on the
//! headstock reads gravity and the swing's own accelerations
//! ([`clapper_core::sensor::specific_force`]), plus a burst at each of the
//! clapper's impacts scaled by its impulse, noise, the sensor's resolution
//! and its ±2 g range, at a jittered rate with gaps.

use clapper_core::bell::{Bell, G};
use clapper_core::ringer::{ring_down, ring_up, RingerConfig};
use clapper_core::ringing::{ring, Protocol};
use clapper_core::sensor::{specific_force, SensorPlace};
use clapper_core::stroke::{Observer, SimConfig, StepView, Stroke, Style};
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;

use crate::ringing_log::{AccelLog, Phase, PhaseKind};
use crate::SignalError;

/// What to synthesise.
#[derive(Clone, Debug, PartialEq)]
pub struct LogSpec {
    /// The bell.
    pub bell: Bell,
    /// Simulation settings (θ0 is set from the ring-up's set angle).
    pub cfg: SimConfig,
    /// The ringer who raises and lowers it.
    pub ringer: RingerConfig,
    /// Sample rate (Hz). belfry-sleuth logs at 100 Hz.
    pub rate: f64,
    /// Sample times jitter by up to ± this fraction of the interval.
    pub jitter: f64,
    /// Runs of lost samples (each 0.1-0.4 s), placed at random.
    pub gaps: usize,
    /// Noise, standard deviation (m/s²).
    pub noise: f64,
    /// Resolution (m/s²): an ADXL345 at ±2 g, 10 bits, reads in 0.038 m/s² steps.
    pub resolution: f64,
    /// The range: readings clip at ± this (m/s²).
    pub clip: f64,
    /// Where the sensor is.
    pub sensor: SensorPlace,
    /// Rest before raising and after lowering (s).
    pub rest_s: f64,
    /// Time set at the balance before ringing (s).
    pub set_s: f64,
    /// Strokes rung full circle (an even number: it ends at handstroke).
    pub strokes: usize,
    /// A ringing stroke's first strike's burst (m/s²); others scale with
    /// their impulse.
    pub burst: f64,
    /// Seed of the noise, jitter and gaps.
    pub seed: u64,
    /// Each axis's zero offset (radial, tangential, axle; m/s²): an
    /// ADXL345's may be up to about 1 m/s² (its data sheet's ±150 mg at
    /// ±2 g on x and y, more on z).
    pub offset: [f64; 3],
    /// Each axis's gain (radial, tangential, axle): its reading of g over g
    /// (a few per cent from 1).
    pub gain: [f64; 3],
    /// The headstock's ringing after a ringing stroke's strike (m/s²; others
    /// scale with their impulse, up to this): a slower mode than the
    /// burst's, dying over [`LogSpec::ring_s`]. At Data141's level (some 50
    /// m/s², 0.4 s) it clips the readings at ±2 g for a second.
    pub ring: f64,
    /// The ringing's time constant (s): it lasts some four of these.
    pub ring_s: f64,
    /// Every this many ringing strokes (0: none) the bell stands on the
    /// stay for [`LogSpec::stand_s`] before the next is pulled off.
    pub stand_every: usize,
    /// How long each stand lasts (s).
    pub stand_s: f64,
    /// How far past the balance the stay holds the bell on a stand (rad; 0:
    /// the stand is at the angle the next stroke falls from, short of the
    /// balance). Past it, the bell rises onto the stay and is pulled back
    /// over the balance, each over [`STAY_RAMP_S`], and the stroke after
    /// falls from the stay's angle (Data141's stands read 176-188 deg).
    pub stay: f64,
    /// After lowering, the bell let go to swing freely for this long (s; 0:
    /// stopped at once), then stopped: these swings are "down".
    pub free_s: f64,
    /// With stands ([`LogSpec::stand_every`] over 0), the last ringing
    /// stroke also rises onto the stay and stands there, and the lowering's
    /// first stroke falls from the stand: lowered straight off the last
    /// stand, with no set (as an independent tester's logs are). Else the
    /// lowering follows on from a ringing stroke that turned short of the
    /// balance.
    pub lower_from_stand: bool,
    /// Swings the lowering takes, from the balance down (0: the ringer's
    /// [`RingerConfig::swings`]). More is gentler: at 60 the first swing
    /// off the balance loses some 10 deg, as an independent tester's logs
    /// lowered off a stand do (at the ringer's 30, some 20).
    pub lower_swings: usize,
    /// How high the ringing's strokes rise (rad; 0: to the set angle, 179
    /// deg at most). An independent tester's logs rose to 172-177 deg,
    /// short of the stands past the balance. Below the set angle, the
    /// ringer eases the bell down to it over the set's last
    /// [`EASE_S`] before the first stroke.
    pub ring_top: f64,
}

/// The ease from the set angle down to [`LogSpec::ring_top`] takes this
/// long (s).
pub const EASE_S: f64 = 0.5;

impl LogSpec {
    /// A log of `bell` as belfry-sleuth takes one: 100 Hz with 2 %
    /// jitter, no gaps, 0.04 m/s² noise, 10-bit ±2 g, the sensor on the
    /// crown-staple nut 0.15 m above the pivot, 10 s at rest each end, 8 s
    /// set, 40 strokes, 40 m/s² bursts (past the range).
    pub fn new(bell: Bell, seed: u64) -> Self {
        Self {
            bell,
            cfg: SimConfig::default(),
            ringer: RingerConfig::default(),
            rate: 100.0,
            jitter: 0.02,
            gaps: 0,
            noise: 0.04,
            resolution: 4.0 * G / 1024.0,
            clip: 2.0 * G,
            sensor: SensorPlace {
                along: 0.15,
                across: 0.0,
            },
            rest_s: 10.0,
            set_s: 8.0,
            strokes: 40,
            burst: 40.0,
            seed,
            offset: [0.0; 3],
            gain: [1.0; 3],
            ring: 0.0,
            ring_s: 0.25,
            stand_every: 0,
            stand_s: 2.0,
            stay: 0.0,
            free_s: 0.0,
            lower_from_stand: false,
            lower_swings: 0,
            ring_top: 0.0,
        }
    }
}

/// One swing as it truly was.
#[derive(Clone, Debug, PartialEq)]
pub struct TrueLogStroke {
    /// Bottom dead centre (s).
    pub bdc: f64,
    /// Handstroke (it falls from the side the bell was set on).
    pub hand: bool,
    /// The first impact a sensor sees (its burst at least 3 m/s² one
    /// sample after), if any (s).
    pub strike: Option<f64>,
    /// The angle it fell from (rad).
    pub amplitude: f64,
    /// When it turned there (s).
    pub turned: f64,
    /// Every impact after its bottom and before the next, with its burst
    /// (s, m/s²): the strike is the first of these big enough to see.
    pub impacts: Vec<(f64, f64)>,
    /// The phase it is in.
    pub phase: PhaseKind,
    /// Whether a gap in the log hides its bottom, its strike or the turning
    /// point it fell from, or lies between its bottom and its strike.
    pub hidden: bool,
}

/// The truth behind a synthetic log.
#[derive(Clone, Debug, PartialEq)]
pub struct LogTruth {
    /// The phases.
    pub phases: Vec<Phase>,
    /// The swings.
    pub strokes: Vec<TrueLogStroke>,
    /// Mean handstroke minus mean backstroke BDC-to-strike while ringing (s).
    pub odd_struck: Option<f64>,
}

/// A piece of the session: its phase, start (s), length (s) and motion.
struct Piece {
    kind: PhaseKind,
    start: f64,
    len: f64,
    motion: Motion,
    /// Stands within a simulation's strokes: (its time when the bell
    /// reaches the stay (s), how long it stands there (s), the angle (rad)).
    holds: Vec<(f64, f64, f64)>,
}

impl Piece {
    /// A simulation's time as the piece's (the stands before it added).
    fn local(&self, sim: f64) -> f64 {
        sim + self
            .holds
            .iter()
            .filter(|h| h.0 < sim - 1e-12)
            .map(|h| h.1)
            .sum::<f64>()
    }
}

enum Motion {
    /// Still at an angle (rad).
    Hold(f64),
    /// Smoothly (smoothstep) from one angle to another (rad).
    Ramp(f64, f64),
    /// A simulation's strokes, θ mirrored by the sign, its time from 0.
    Sim(Run, f64, Vec<Stroke>),
    /// Swinging freely: θ, θ', θ'' every millisecond from 0.
    Free(Vec<[f64; 3]>),
}

/// A free swing (θ'' = −(g/L) sin θ − c θ', the bell's own L and a light
/// damping c = 0.005/s) from rest at `theta0` (rad), every millisecond,
/// ending at the first turning point after `at_least` s.
fn free_swing(theta0: f64, length: f64, at_least: f64) -> Vec<[f64; 3]> {
    let acc = |th: f64, w: f64| -G / length * th.sin() - 0.005 * w;
    let dt = 1e-3;
    let (mut th, mut w) = (theta0, 0.0);
    let mut out = vec![[th, w, acc(th, w)]];
    loop {
        let k1 = (w, acc(th, w));
        let k2 = (w + 0.5 * dt * k1.1, acc(th + 0.5 * dt * k1.0, w + 0.5 * dt * k1.1));
        let k3 = (w + 0.5 * dt * k2.1, acc(th + 0.5 * dt * k2.0, w + 0.5 * dt * k2.1));
        let k4 = (w + dt * k3.1, acc(th + dt * k3.0, w + dt * k3.1));
        let w1 = w + dt / 6.0 * (k1.1 + 2.0 * k2.1 + 2.0 * k3.1 + k4.1);
        th += dt / 6.0 * (k1.0 + 2.0 * k2.0 + 2.0 * k3.0 + k4.0);
        let turned = w1.signum() != w.signum() && w != 0.0;
        w = w1;
        out.push([th, w, acc(th, w)]);
        if turned && out.len() as f64 * dt >= at_least {
            return out;
        }
    }
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Run {
    Up,
    Ring,
    Down,
}

/// Samples θ, θ', θ'' at given (sorted) simulated times, θ'' by a central
/// difference of θ' inside the step (so across no impact).
struct Kinematics<'a> {
    times: &'a [f64],
    next: usize,
    out: Vec<[f64; 3]>,
}

impl Observer for Kinematics<'_> {
    fn on_step(&mut self, step: &StepView<'_>) {
        while self.next < self.times.len() && self.times[self.next] <= step.t_to() {
            let t = self.times[self.next].max(step.t_from());
            let h = (0.25 * (step.t_to() - step.t_from())).min(1e-5);
            let (a, b) = ((t - h).max(step.t_from()), (t + h).min(step.t_to()));
            let y = step.sample(t).y;
            let acc = if b > a {
                (step.sample(b).y[2] - step.sample(a).y[2]) / (b - a)
            } else {
                0.0
            };
            self.out.push([y[0], y[2], acc]);
            self.next += 1;
        }
    }
}

fn err(e: impl std::fmt::Display) -> SignalError {
    SignalError::Option(format!("the synthetic log's simulation failed: {e}"))
}

/// Run one simulation of the session with `obs` watching.
fn run<O: Observer>(
    spec: &LogSpec,
    cfg: &SimConfig,
    ringer: &RingerConfig,
    which: Run,
    obs: &mut O,
) -> Result<Vec<Stroke>, SignalError> {
    Ok(match which {
        Run::Up => ring_up(&spec.bell, cfg, ringer, obs).map_err(err)?.strokes,
        Run::Ring => {
            ring(&spec.bell, cfg, Style::Right, Protocol::Restart, spec.strokes, obs)
                .map_err(err)?
                .strokes
        }
        Run::Down => ring_down(&spec.bell, cfg, ringer, obs).map_err(err)?.strokes,
    })
}

fn smoothstep(u: f64) -> (f64, f64, f64) {
    let u = u.clamp(0.0, 1.0);
    (u * u * (3.0 - 2.0 * u), 6.0 * u * (1.0 - u), 6.0 - 12.0 * u)
}

/// A standard normal number (Box-Muller).
fn gauss(rng: &mut Pcg64) -> f64 {
    let u: f64 = rng.random_range(f64::MIN_POSITIVE..1.0);
    let v: f64 = rng.random();
    (-2.0 * u.ln()).sqrt() * (2.0 * std::f64::consts::PI * v).cos()
}

/// The restart protocol puts each ringing stroke back at ±θ0 from where
/// the one before turned, a degree or two lower (what its strikes took),
/// and the lowering starts at θ0 too: the bell would jump at the top, which
/// no real bell does and no reader should be asked to follow. Here the
/// ringer's pull restores it instead over the rise after each bottom: θ
/// gains δ smoothstep(u) from the bottom (u = 0) to the turn (u = 1), δ
/// the jump. The bottoms, the strikes' times and the amplitudes (each
/// stroke's start) are as simulated; the rope's pull is a step in θ'' at
/// the bottom, as [`clapper_core::ringer`]'s is.
fn restore_between_restarts(pieces: &[Piece], times: &[f64], kin: &mut [[f64; 3]]) {
    for (p, piece) in pieces.iter().enumerate() {
        let Motion::Sim(Run::Ring, sign, strokes) = &piece.motion else {
            continue;
        };
        let after = pieces.get(p + 1).map(|q| match &q.motion {
            Motion::Hold(a) | Motion::Ramp(a, _) => *a,
            Motion::Free(table) => table[0][0],
            Motion::Sim(_, s, st) => st.first().map_or(0.0, |x| s * x.start.y[0]),
        });
        for (i, st) in strokes.iter().enumerate() {
            let target = match strokes.get(i + 1) {
                Some(next) => sign * next.start.y[0],
                None => match after {
                    Some(a) => a,
                    None => continue,
                },
            };
            let Some(bottom) = st.bottom else { continue };
            let (t0, t1) = (piece.start + piece.local(bottom.t), piece.start + piece.local(st.end.t));
            let delta = target - sign * st.end.y[0];
            // Only a restart at the top: not a stroke that ends elsewhere.
            if t1 <= t0 || delta.abs() > 0.2 {
                continue;
            }
            let span = t1 - t0;
            let (a, b) = (times.partition_point(|&x| x < t0), times.partition_point(|&x| x < t1));
            for (x, v) in times[a..b].iter().zip(&mut kin[a..b]) {
                let (s0, s1, s2) = smoothstep((x - t0) / span);
                v[0] += delta * s0;
                v[1] += delta * s1 / span;
                v[2] += delta * s2 / (span * span);
            }
        }
    }
}

/// Synthesise a log and its truth.
pub fn synth_log(spec: &LogSpec) -> Result<(AccelLog, LogTruth), SignalError> {
    render_log(spec, &plan_log(spec)?)
}

/// A log's session planned: its bell's swings simulated, no sample drawn
/// yet, so that its length can be bounded before its samples are
/// allocated (a 10 kHz log of a peal is tens of millions of them).
pub struct LogPlan {
    session: Session,
}

impl LogPlan {
    /// The session's length (s).
    pub fn seconds(&self) -> f64 {
        self.session.total
    }
}

/// Plan the log `spec` asks for ([`render_log`] draws its samples).
pub fn plan_log(spec: &LogSpec) -> Result<LogPlan, SignalError> {
    check(spec)?;
    Ok(LogPlan {
        session: session(spec)?,
    })
}

/// Draw the samples of the log `plan` (planned from `spec`) and its truth.
pub fn render_log(spec: &LogSpec, plan: &LogPlan) -> Result<(AccelLog, LogTruth), SignalError> {
    let session = &plan.session;
    let mut rng = Pcg64::seed_from_u64(spec.seed);
    let (times, gaps) = sample_times(spec, session.total, &mut rng);
    let Motions {
        kin,
        impacts,
        mut strokes,
    } = motions(spec, session, &times)?;
    let bursts = burst_list(spec, &impacts, &mut rng);
    truth_strikes(&mut strokes, &bursts, &gaps, 1.0 / spec.rate);
    let [radial, tangential, axle] = readings(spec, &times, &kin, &bursts, &mut rng);
    let odd_struck = truth_odd_struck(&strokes);
    Ok((
        AccelLog {
            name: Some("synthetic".into()),
            t: times,
            radial,
            tangential,
            axle,
        },
        LogTruth {
            phases: session_phases(&session.pieces),
            strokes,
            odd_struck,
        },
    ))
}

/// The rate and the strokes asked for, checked.
fn check(spec: &LogSpec) -> Result<(), SignalError> {
    if !(spec.rate.is_finite() && (5.0..=10_000.0).contains(&spec.rate)) {
        return Err(SignalError::Option(format!(
            "sample rate {} Hz: 5 to 10,000",
            spec.rate
        )));
    }
    if spec.strokes % 2 != 0 || spec.strokes == 0 {
        return Err(SignalError::Option(format!(
            "{} strokes: an even number, at least 2",
            spec.strokes
        )));
    }
    Ok(())
}

/// The session, piece by piece, and the settings its ringing and lowering
/// were simulated with.
struct Session {
    pieces: Vec<Piece>,
    /// Its length (s).
    total: f64,
    /// The ringing's and lowering's settings (θ0 the set angle).
    cfg: SimConfig,
    /// The lowering's ringer (its stay at the set angle).
    ringer: RingerConfig,
}

/// Pieces laid end to end.
struct Pieces {
    pieces: Vec<Piece>,
    t: f64,
}

impl Pieces {
    fn add(&mut self, kind: PhaseKind, len: f64, motion: Motion) {
        self.pieces.push(Piece {
            kind,
            start: self.t,
            len,
            motion,
            holds: vec![],
        });
        self.t += len;
    }
}

/// The session, piece by piece (each simulation run once to learn its
/// length): rest, raising, set, ringing (with its stands), lowering, free
/// swings if asked, rest.
fn session(spec: &LogSpec) -> Result<Session, SignalError> {
    let mut p = Pieces { pieces: vec![], t: 0.0 };
    p.add(PhaseKind::Down, spec.rest_s, Motion::Hold(0.0));
    let tug = spec.ringer.start;
    p.add(PhaseKind::Raising, 0.5, Motion::Ramp(0.0, tug));
    let up = run(spec, &spec.cfg, &spec.ringer, Run::Up, &mut ())?;
    let last = up.last().ok_or_else(|| err("no swings ringing up"))?;
    // Ringing up may end on either side; mirrored, it ends on the + side,
    // which is then the handstroke side (the bell is set at handstroke).
    let sign = last.end.y[0].signum();
    // Set where the last swing of the raising reached (short of the very
    // balance, from which a restart would never fall).
    let set = last.end.y[0].abs().min(179f64.to_radians());
    let up_len = last.end.t;
    p.add(PhaseKind::Raising, up_len, Motion::Sim(Run::Up, sign, up));
    let top = if spec.ring_top > 0.0 { spec.ring_top } else { set };
    if top == set {
        p.add(PhaseKind::Up, spec.set_s, Motion::Hold(set));
    } else {
        let ease = EASE_S.min(0.5 * spec.set_s);
        p.add(PhaseKind::Up, spec.set_s - ease, Motion::Hold(set));
        p.add(PhaseKind::Up, ease, Motion::Ramp(set, top));
    }
    let cfg = SimConfig {
        theta0: top,
        ..spec.cfg
    };
    ringing_piece(spec, &cfg, &mut p)?;
    let ringer = RingerConfig {
        stay: set,
        swings: match spec.lower_swings {
            0 => spec.ringer.swings,
            n => n,
        },
        ..spec.ringer
    };
    let down = run(spec, &cfg, &ringer, Run::Down, &mut ())?;
    let (down_len, down_end) = down.last().map_or((0.0, 0.0), |s| (s.end.t, s.end.y[0]));
    p.add(PhaseKind::Lowering, down_len, Motion::Sim(Run::Down, 1.0, down));
    if spec.free_s > 0.0 {
        // Let go: the bell swings freely, then is checked and stopped.
        let table = free_swing(down_end, spec.bell.lb(), spec.free_s);
        let (len, end) = ((table.len() - 1) as f64 * 1e-3, table[table.len() - 1][0]);
        p.add(PhaseKind::Down, len, Motion::Free(table));
        p.add(PhaseKind::Down, 1.5, Motion::Ramp(end, 0.0));
    } else {
        p.add(PhaseKind::Lowering, 1.5, Motion::Ramp(down_end, 0.0));
    }
    p.add(PhaseKind::Down, spec.rest_s, Motion::Hold(0.0));
    Ok(Session {
        total: p.t,
        pieces: p.pieces,
        cfg,
        ringer,
    })
}

/// Whether the lowering starts from a stand ([`LogSpec::lower_from_stand`]).
fn lowered_off_a_stand(spec: &LogSpec) -> bool {
    spec.lower_from_stand && spec.stand_every > 0
}

/// The ringing, from the set at `cfg.theta0`, with its stands: every
/// `stand_every`th stroke rests on the stay at the angle the next falls
/// from.
fn ringing_piece(spec: &LogSpec, cfg: &SimConfig, p: &mut Pieces) -> Result<(), SignalError> {
    let rung = run(spec, cfg, &spec.ringer, Run::Ring, &mut ())?;
    let mut holds: Vec<(f64, f64, f64)> = match spec.stand_every {
        0 => vec![],
        every => (0..rung.len().saturating_sub(1))
            .filter(|i| (i + 1) % every == 0)
            .map(|i| (rung[i].end.t, spec.stand_s, rung[i + 1].start.y[0]))
            .collect(),
    };
    // Lowered off the last stand: the lowering starts from the set angle on
    // the side the last stroke turned on.
    if let Some(last) = rung.last().filter(|_| lowered_off_a_stand(spec)) {
        holds.push((last.end.t, spec.stand_s, last.end.y[0].signum() * cfg.theta0));
    }
    let ring_len = rung.last().map_or(0.0, |s| s.end.t) + holds.iter().map(|h| h.1).sum::<f64>();
    p.add(PhaseKind::Ringing, ring_len, Motion::Sim(Run::Ring, 1.0, rung));
    if let Some(last) = p.pieces.last_mut() {
        last.holds = holds;
    }
    Ok(())
}

/// Sample times over `total` s: jittered, with gaps (each 0.1-0.4 s; the
/// gaps returned as (start, end), s).
#[allow(clippy::type_complexity)]
fn sample_times(spec: &LogSpec, total: f64, rng: &mut Pcg64) -> (Vec<f64>, Vec<(f64, f64)>) {
    let dt = 1.0 / spec.rate;
    let mut gaps: Vec<(f64, f64)> = (0..spec.gaps)
        .map(|_| {
            let a = rng.random_range(0.0..total - 0.5);
            (a, a + rng.random_range(0.1..0.4))
        })
        .collect();
    gaps.sort_by(|x, y| x.0.total_cmp(&y.0));
    let n = (total * spec.rate) as usize;
    let times: Vec<f64> = (0..n)
        .map(|k| k as f64 * dt + spec.jitter * dt * rng.random_range(-0.5..0.5))
        .filter(|&x| x >= 0.0 && x < total && !gaps.iter().any(|g| x >= g.0 && x < g.1))
        .collect();
    (times, gaps)
}

/// The bell's motion at every sample, its impacts and its true swings.
struct Motions {
    /// θ, θ', θ'' at every sample (rad, rad/s, rad/s²).
    kin: Vec<[f64; 3]>,
    /// (time (s), impulse, a first strike while ringing).
    impacts: Vec<(f64, f64, bool)>,
    /// The true swings (strikes not yet set).
    strokes: Vec<TrueLogStroke>,
}

/// θ, θ', θ'' at every sample time, piece by piece.
fn motions(spec: &LogSpec, session: &Session, times: &[f64]) -> Result<Motions, SignalError> {
    let mut m = Motions {
        kin: Vec::with_capacity(times.len()),
        impacts: vec![],
        strokes: vec![],
    };
    let mut i = 0;
    for p in &session.pieces {
        let j = times.partition_point(|&x| x < p.start + p.len);
        let local: Vec<f64> = times[i..j].iter().map(|x| x - p.start).collect();
        match &p.motion {
            Motion::Hold(a) => m.kin.extend(local.iter().map(|_| [*a, 0.0, 0.0])),
            Motion::Free(table) => free_motion(p, table, &local, &mut m),
            Motion::Ramp(a, b) => m.kin.extend(local.iter().map(|&u| {
                let (s, ds, dds) = smoothstep(u / p.len);
                [a + (b - a) * s, (b - a) * ds / p.len, (b - a) * dds / (p.len * p.len)]
            })),
            Motion::Sim(which, sign, strokes) => {
                let (c, r) = match which {
                    Run::Up => (&spec.cfg, &spec.ringer),
                    _ => (&session.cfg, &session.ringer),
                };
                sim_motion(spec, p, (c, r, *which), &local, &mut m)?;
                sim_truth(spec, p, (*which, *sign, strokes), &mut m);
            }
        }
        i = j;
    }
    restore_between_restarts(&session.pieces, times, &mut m.kin);
    Ok(m)
}

/// A free swing's samples (interpolated in its millisecond table) and its
/// bottoms, each falling from the turning point before.
fn free_motion(p: &Piece, table: &[[f64; 3]], local: &[f64], m: &mut Motions) {
    let at = |u: f64| {
        let x = (u / 1e-3).clamp(0.0, (table.len() - 1) as f64);
        let (k, f) = ((x.floor() as usize).min(table.len() - 2), x - x.floor());
        let v: [f64; 3] = std::array::from_fn(|i| table[k][i] + f * (table[k + 1][i] - table[k][i]));
        v
    };
    m.kin.extend(local.iter().map(|&u| at(u)));
    let mut turn = (0usize, table[0][0]);
    for k in 1..table.len() {
        if table[k][1].signum() != table[k - 1][1].signum() {
            turn = (k, table[k][0]);
        }
        if table[k][0].signum() != table[k - 1][0].signum() && turn.1.abs() > 0.0 {
            let f = table[k - 1][0] / (table[k - 1][0] - table[k][0]);
            m.strokes.push(TrueLogStroke {
                bdc: p.start + (k as f64 - 1.0 + f) * 1e-3,
                hand: turn.1 > 0.0,
                strike: None,
                amplitude: turn.1.abs(),
                turned: p.start + turn.0 as f64 * 1e-3,
                impacts: vec![],
                phase: p.kind,
                hidden: false,
            });
        }
    }
}

/// A simulation's samples at the piece's times `local` (s from its
/// start), run again with an observer: samples in a stand hold still; the
/// others are the simulation's, at its own times, mirrored by the piece's sign.
fn sim_motion(
    spec: &LogSpec,
    p: &Piece,
    (c, r, which): (&SimConfig, &RingerConfig, Run),
    local: &[f64],
    m: &mut Motions,
) -> Result<(), SignalError> {
    let Motion::Sim(_, sign, _) = &p.motion else {
        return Ok(());
    };
    let held = |u: f64| {
        let mut before = 0.0;
        for h in &p.holds {
            let at = h.0 + before;
            if u >= at && u < at + h.1 {
                return Err(on_the_stay(spec.stay, h, u - at));
            }
            if u >= at + h.1 {
                before += h.1;
            }
        }
        Ok(u - before)
    };
    let sim: Vec<f64> = local.iter().filter_map(|&u| held(u).ok()).collect();
    let mut k = Kinematics {
        times: &sim,
        next: 0,
        out: Vec::with_capacity(sim.len()),
    };
    run(spec, c, r, which, &mut k)?;
    if k.out.len() != sim.len() {
        return Err(err("the second run did not repeat the first"));
    }
    let mut from_sim = k.out.iter();
    for &u in local {
        match held(u) {
            Err(v) => m.kin.push([sign * v[0], sign * v[1], sign * v[2]]),
            Ok(_) => {
                let v = from_sim.next().ok_or_else(|| err("samples out of step"))?;
                m.kin.push([sign * v[0], sign * v[1], sign * v[2]]);
            }
        }
    }
    Ok(())
}

/// A stand's rise onto the stay and the pull back over the balance each
/// take this long (s).
pub const STAY_RAMP_S: f64 = 0.3;

/// θ, θ', θ'' (rad, rad/s, rad/s²) `u` s into the stand `h` (when, how
/// long, the angle the next stroke falls from): with the stay `stay` rad
/// past the balance, up onto it from that angle and back (smoothstep);
/// else still at that angle.
fn on_the_stay(stay: f64, h: &(f64, f64, f64), u: f64) -> [f64; 3] {
    let base = h.2;
    if stay <= 0.0 {
        return [base, 0.0, 0.0];
    }
    let ramp = STAY_RAMP_S.min(0.5 * h.1);
    let top = base.signum() * (std::f64::consts::PI + stay);
    let (from, to, x) = if u < ramp {
        (base, top, u)
    } else if u > h.1 - ramp {
        (top, base, u - (h.1 - ramp))
    } else {
        return [top, 0.0, 0.0];
    };
    let (s0, s1, s2) = smoothstep(x / ramp);
    [
        from + (to - from) * s0,
        (to - from) * s1 / ramp,
        (to - from) * s2 / (ramp * ramp),
    ]
}

/// A simulation's impacts (with their impulses) and its true swings.
fn sim_truth(spec: &LogSpec, p: &Piece, (which, sign, strokes): (Run, f64, &[Stroke]), m: &mut Motions) {
    for st in strokes {
        let first = st.first_strike_index();
        for (k, im) in st.impacts.iter().enumerate() {
            let impulse =
                spec.bell.clapper_mass * spec.bell.b * (im.phi_dot_before - im.phi_dot_after.unwrap_or(0.0)).abs();
            m.impacts
                .push((p.start + p.local(im.t), impulse, which == Run::Ring && first == Some(k)));
        }
        if let Some(b) = st.bottom {
            m.strokes.push(TrueLogStroke {
                bdc: p.start + p.local(b.t),
                // Falling from the + side (mirrored): a handstroke.
                hand: sign * st.start.y[0] > 0.0,
                strike: None,
                // After a stand past the balance, it fell from the stay (the
                // lowering's first, lowered off the last stand, too).
                amplitude: if spec.stay > 0.0
                    && (p.holds.iter().any(|h| (h.0 - st.start.t).abs() < 1e-9)
                        || (which == Run::Down && lowered_off_a_stand(spec) && std::ptr::eq(st, &strokes[0])))
                {
                    std::f64::consts::PI + spec.stay
                } else {
                    st.start.y[0].abs()
                },
                turned: p.start + p.local(st.start.t),
                impacts: vec![],
                phase: p.kind,
                hidden: false,
            });
        }
    }
}

/// The strike's burst: decay time (s): it dies in a few hundredths.
const TAU: f64 = 0.012;
/// The strike's burst's frequency (Hz).
const F_RING: f64 = 180.0;
/// The headstock's slower ring's frequency (Hz).
const F_HEADSTOCK: f64 = 37.0;

/// Each impact's burst: (time (s), size (m/s²), phase on each axis),
/// scaled to a ringing stroke's strike.
fn burst_list(spec: &LogSpec, impacts: &[(f64, f64, bool)], rng: &mut Pcg64) -> Vec<(f64, f64, [f64; 3])> {
    let reference = {
        let mut v: Vec<f64> = impacts.iter().filter(|x| x.2).map(|x| x.1).collect();
        v.sort_by(f64::total_cmp);
        v.get(v.len() / 2).copied().unwrap_or(1.0).max(1e-9)
    };
    impacts
        .iter()
        .map(|&(ti, j, _)| {
            let phases = [0, 1, 2].map(|_| rng.random_range(0.0..std::f64::consts::TAU));
            (ti, spec.burst * j / reference, phases)
        })
        .collect()
}

/// Each true swing's impacts and strike: the first impact after bottom
/// whose burst is at least 3 m/s² one sample (`dt`, s) later (what any
/// reader could see), before the next bottom; and whether a gap hides it.
fn truth_strikes(strokes: &mut [TrueLogStroke], bursts: &[(f64, f64, [f64; 3])], gaps: &[(f64, f64)], dt: f64) {
    let seen = 3.0 * (dt / TAU).exp();
    let bottoms: Vec<f64> = strokes.iter().map(|s| s.bdc).collect();
    for (k, s) in strokes.iter_mut().enumerate() {
        let until = bottoms.get(k + 1).copied().unwrap_or(s.bdc + 2.5).min(s.bdc + 2.5);
        s.impacts = bursts
            .iter()
            .filter(|b| b.0 > s.bdc && b.0 < until)
            .map(|b| (b.0, b.1))
            .collect();
        s.strike = s.impacts.iter().find(|b| b.1 >= seen).map(|b| b.0);
    }
    // A stroke's strike must come before the next bottom.
    for k in 0..strokes.len().saturating_sub(1) {
        let next = strokes[k + 1].bdc;
        if strokes[k].strike.is_some_and(|x| x >= next) {
            strokes[k].strike = None;
        }
    }
    let near_gap = |x: f64| gaps.iter().any(|g| x > g.0 - 2.0 * dt && x < g.1 + 2.0 * dt);
    for s in strokes {
        // A gap between the bottom and the strike leaves a reader unable to
        // tell whether it struck in the gap.
        let between = |x: f64| gaps.iter().any(|g| g.1 > s.bdc && g.0 < x);
        s.hidden = near_gap(s.bdc) || s.strike.is_some_and(|x| near_gap(x) || between(x)) || near_gap(s.turned);
    }
}

/// The sensor's readings (radial, tangential, axle; m/s²) at every
/// sample: gravity and the swing's own accelerations at the sensor, the
/// bursts and the headstock's ring, each axis's gain and offset, noise,
/// resolution and range.
fn readings(
    spec: &LogSpec,
    times: &[f64],
    kin: &[[f64; 3]],
    bursts: &[(f64, f64, [f64; 3])],
    rng: &mut Pcg64,
) -> [Vec<f64>; 3] {
    let mut out = [0, 1, 2].map(|_| Vec::with_capacity(times.len()));
    let mut b0 = 0;
    // How long a burst (and the headstock's ring) lasts.
    let reach = if spec.ring > 0.0 {
        (6.0 * spec.ring_s).max(0.2)
    } else {
        0.2
    };
    for (k, &x) in times.iter().enumerate() {
        let [th, w, a] = kin[k];
        let f = specific_force(spec.sensor, th, w, a);
        let mut v = [f[1], f[0], 0.0];
        while b0 < bursts.len() && bursts[b0].0 < x - reach {
            b0 += 1;
        }
        for b in &bursts[b0..] {
            if b.0 > x {
                break;
            }
            let d = x - b.0;
            let env = b.1 * (-d / TAU).exp();
            // The headstock's slower ring, longer lived; a harder blow (of
            // the raising or lowering, whose impulses run to three times a
            // ringing strike's here) rings it no harder: on Data141 those
            // strikes clip the readings no more than the ringing's.
            let ring = spec.ring * (b.1 / spec.burst.max(1e-9)).min(1.0) * (-d / spec.ring_s.max(1e-3)).exp();
            for (axis, val) in v.iter_mut().enumerate() {
                *val += env * (2.0 * std::f64::consts::PI * F_RING * d + b.2[axis]).cos();
                *val += ring * (2.0 * std::f64::consts::PI * F_HEADSTOCK * d + 2.0 * b.2[axis]).cos();
            }
        }
        for (axis, val) in v.iter_mut().enumerate() {
            *val = spec.gain[axis] * *val + spec.offset[axis];
        }
        for val in &mut v {
            *val += spec.noise * gauss(rng);
            if spec.resolution > 0.0 {
                *val = (*val / spec.resolution).round() * spec.resolution;
            }
            *val = val.clamp(-spec.clip, spec.clip);
        }
        for (o, val) in out.iter_mut().zip(v) {
            o.push(val);
        }
    }
    out
}

/// The phases: pieces of one kind run together.
fn session_phases(pieces: &[Piece]) -> Vec<Phase> {
    let mut phases: Vec<Phase> = vec![];
    for p in pieces {
        match phases.last_mut() {
            Some(q) if q.kind == p.kind => q.end = p.start + p.len,
            _ => phases.push(Phase {
                kind: p.kind,
                start: p.start,
                end: p.start + p.len,
            }),
        }
    }
    phases
}

/// Mean handstroke minus mean backstroke BDC-to-strike while ringing (s).
fn truth_odd_struck(strokes: &[TrueLogStroke]) -> Option<f64> {
    let mean = |hand: bool| {
        let v: Vec<f64> = strokes
            .iter()
            .filter(|s| s.phase == PhaseKind::Ringing && s.hand == hand)
            .filter_map(|s| s.strike.map(|x| x - s.bdc))
            .collect();
        (!v.is_empty()).then(|| v.iter().sum::<f64>() / v.len() as f64)
    };
    mean(true).zip(mean(false)).map(|(h, b)| h - b)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// With [`LogSpec::ring_top`] the ringing's strokes fall from it (the
    /// stands from past the balance still), and the log stays continuous
    /// through the ease from the set down to it: no step of 0.5 m/s² there,
    /// noise-free (a jump from 179 to 175 deg is one of 0.68; the ease's
    /// smoothstep steps θ'' by 6Δ/T² at its ends, 0.25 m/s² at the sensor
    /// here, as the stay's ramps do).
    #[test]
    fn the_ringing_rises_to_its_top() {
        let mut spec = LogSpec::new(Bell::gsm_tenor(), 2);
        (spec.noise, spec.resolution, spec.jitter, spec.burst) = (0.0, 0.0, 0.0, 0.0);
        spec.clip = 100.0;
        spec.strokes = 6;
        spec.stand_every = 2;
        spec.stay = 4f64.to_radians();
        spec.ring_top = 175f64.to_radians();
        let (log, truth) = synth_log(&spec).expect("synthesised");
        let tops: Vec<f64> = truth
            .strokes
            .iter()
            .filter(|t| t.phase == PhaseKind::Ringing && t.amplitude < std::f64::consts::PI)
            .map(|t| t.amplitude.to_degrees())
            .collect();
        assert!(
            tops.len() >= 3 && tops.iter().all(|a| (a - 175.0).abs() < 0.01),
            "{tops:?}"
        );
        let up = truth.phases.iter().find(|p| p.kind == PhaseKind::Up).expect("set");
        let worst = (1..log.t.len())
            .filter(|&k| log.t[k] > up.end - EASE_S - 0.1 && log.t[k] < up.end + 0.1)
            .map(|k| (log.tangential[k] - log.tangential[k - 1]).abs())
            .fold(0.0, f64::max);
        assert!(worst < 0.5, "a step of {worst} m/s² in the ease");
    }

    /// Near the tops of the ringing the bell moves slowly, so a clean log
    /// changes little sample to sample; the restart protocol's jump of a
    /// degree or two at each top (had it been left in) is a step of some
    /// 0.3 m/s² in the tangential reading there.
    #[test]
    fn the_ringing_is_continuous_through_its_tops() {
        let mut spec = LogSpec::new(Bell::gsm_tenor(), 1);
        (spec.noise, spec.resolution, spec.jitter, spec.burst) = (0.0, 0.0, 0.0, 0.0);
        spec.clip = 100.0;
        spec.strokes = 6;
        let (log, truth) = synth_log(&spec).expect("synthesised");
        let ringing = truth
            .phases
            .iter()
            .find(|p| p.kind == PhaseKind::Ringing)
            .expect("rung");
        let mut tops = 0;
        let mut worst = 0.0f64;
        for k in 1..log.t.len() {
            let near_top = log.radial[k] < -0.95 * G && log.radial[k - 1] < -0.95 * G;
            if near_top && log.t[k] > ringing.start + 0.5 && log.t[k] < ringing.end - 0.5 {
                tops += 1;
                worst = worst.max((log.tangential[k] - log.tangential[k - 1]).abs());
            }
        }
        assert!(tops > 50, "{tops} samples near the tops");
        assert!(worst < 0.15, "a step of {worst} m/s² near a top");
    }
}
