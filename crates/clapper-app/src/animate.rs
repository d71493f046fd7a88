//! A bell and its clapper animated in step with their sound (`clapper
//! animate`, `POST /api/animate`): one bell, bells side by side on one
//! clock, or a ring ringing rounds.
//!
//! Each bell is simulated twice, identically: once to learn where its
//! strokes fall (and to record when the clapper rests, for the sound), once
//! to take each frame from the integrator's dense output at that frame's
//! exact simulated time. Animation time is simulated time shifted stroke by
//! stroke, exactly as the synthesised sound shifts it, so a strike is seen
//! and heard at the same moment; between strokes the bell waits at the
//! balance, as a ringer holds it.

use clapper_core::prelude::*;
use clapper_core::stroke::{Observer, Sample, StepView};
use clapper_io::LoadedBell;
use clapper_plot::animation::{Animation, BellMotion, Figure, Frame, StrikeMark};
use clapper_signal::synth::{synthesize, typical_partials, SynthSpec};
use clapper_signal::Signal;
use serde::Deserialize;

use crate::simulate::SimulateRequest;
use crate::sound::{heard_rests, heard_strikes, Partials, SynthOptions, LEAD_S};
use crate::AppError;

/// Most frames one animation may hold, over all its bells: 2 million
/// (about 60 MB of frames); a longer one asks for fewer strokes or frames.
pub const MAX_FRAMES: usize = 2_000_000;
/// Most strokes a bell may ring in an animation: 200 (a quarter of an
/// hour of ringing, longer than anyone watches).
pub const MAX_STROKES: usize = 200;

/// How the bells are set out in time.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Arrangement {
    /// Every bell starts at once and rings its own strokes (one bell, or
    /// two compared side by side), with the sound's handstroke gap (`AnimateOptions::sound`) before each
    /// handstroke.
    #[default]
    SideBySide,
    /// A ring ringing rounds: each bell's swing placed so that its blows
    /// would fall evenly if every bell struck at the ring's mean time after
    /// bottom dead centre; what each clapper does then shows as its blow
    /// landing early, late or twice.
    Rounds,
}

/// What to animate besides the bells.
#[derive(Clone, Debug, PartialEq)]
pub struct AnimateOptions {
    /// Frames per second of animation time.
    pub fps: f64,
    /// Add a frame at every impact (the clapper drawn on the bell exactly
    /// at the strike): for SVG and HTML, not for a GIF (one rate).
    pub impact_frames: bool,
    /// The sound's options (rate, partials, handstroke gap, tail after the
    /// last stroke).
    pub sound: SynthOptions,
}

impl Default for AnimateOptions {
    /// 60 frames a second; impacts as frames; the sound as `clapper synth`
    /// makes it at 22.05 kHz (half the CD rate: ample for partials under
    /// 5 kHz, half the size to embed) with 1 s after the last stroke.
    fn default() -> Self {
        Self {
            fps: 60.0,
            impact_frames: true,
            sound: SynthOptions {
                rate: 22050.0,
                tail: 1.0,
                ..SynthOptions::default()
            },
        }
    }
}

/// An animation and its sound.
pub struct Animated {
    /// The frames and strikes to draw.
    pub animation: Animation,
    /// The sound, on the same clock (0 at the animation's start).
    pub sound: Signal,
}

impl Animated {
    /// What the command line prints: bells, length, frames, strikes.
    pub fn text(&self, out: &str) -> String {
        let a = &self.animation;
        let frames: usize = a.bells.iter().map(|b| b.frames.len()).sum();
        let mut o = format!(
            "{}: {} bell(s), {:.2} s, {frames} frames, written to {out}\n",
            a.title,
            a.bells.len(),
            a.duration
        );
        if let Some(i) = a.rounds_interval {
            o.push_str(&format!("  rounds at {:.0} ms between blows\n", i * 1e3));
        }
        for b in &a.bells {
            let firsts: Vec<String> = b
                .strikes
                .iter()
                .filter(|s| s.first)
                .map(|s| match s.ideal {
                    Some(i) => format!("{:.3} s ({:+.0} ms)", s.t, (s.t - i) * 1e3),
                    None => format!("{:.3} s", s.t),
                })
                .collect();
            o.push_str(&format!(
                "  {}: {}; blows at {}; {} impact(s) in all\n",
                b.name,
                b.caption,
                if firsts.is_empty() {
                    "none".into()
                } else {
                    firsts.join(", ")
                },
                b.strikes.len()
            ));
        }
        o
    }
}

/// Samples the simulation at given times (sorted), from each step's
/// dense output; a time on a step boundary is taken from the step ending
/// there.
struct AtTimes<'a> {
    times: &'a [f64],
    next: usize,
    out: Vec<Sample>,
}

impl Observer for AtTimes<'_> {
    fn on_step(&mut self, step: &StepView<'_>) {
        // Bounded by the number of times.
        while self.next < self.times.len() && self.times[self.next] <= step.t_to() {
            self.out.push(step.sample(self.times[self.next].max(step.t_from())));
            self.next += 1;
        }
    }
}

/// One bell simulated once, and where its strokes go on the animation's clock.
struct Rung {
    name: String,
    bell: Bell,
    cfg: SimConfig,
    req: SimulateRequest,
    ringing: Ringing,
    trace: Vec<Sample>,
    offsets: Vec<f64>,
    ideal: Vec<Option<f64>>,
}

impl Rung {
    fn end(&self) -> f64 {
        let k = self.ringing.strokes.len() - 1;
        self.ringing.strokes[k].end.t + self.offsets[k]
    }

    /// The simulated time shown at animation time `tau`, for `tau`
    /// increasing (`stroke` carries the stroke reached).
    fn sim_time(&self, tau: f64, stroke: &mut usize) -> f64 {
        let s = &self.ringing.strokes;
        while *stroke < s.len() && tau > s[*stroke].end.t + self.offsets[*stroke] {
            *stroke += 1;
        }
        match s.get(*stroke) {
            None => s[s.len() - 1].end.t,
            Some(st) if tau < st.start.t + self.offsets[*stroke] => {
                // Waiting at the balance before this stroke.
                if *stroke == 0 {
                    st.start.t
                } else {
                    s[*stroke - 1].end.t
                }
            }
            Some(st) => (tau - self.offsets[*stroke]).clamp(st.start.t, st.end.t),
        }
    }
}

fn bdc(s: &Stroke) -> f64 {
    s.bottom.map_or(0.5 * (s.start.t + s.end.t), |m| m.t)
}

/// Place every bell's strokes in rounds (module docs): the interval
/// between blows, and each bell's offsets and ideal blow times.
fn place_rounds(rungs: &mut [Rung]) -> f64 {
    let n = rungs.len() as f64;
    let leads: Vec<f64> = rungs
        .iter()
        .flat_map(|r| r.ringing.strokes.iter())
        .filter_map(|s| Some(s.first_strike()?.t - s.bottom?.t))
        .collect();
    let lead = if leads.is_empty() {
        0.0
    } else {
        leads.iter().sum::<f64>() / leads.len() as f64
    };
    // The longest stroke, bottom to bottom, sets the pace: every bell must
    // be back at the balance before its next blow is due.
    let longest = rungs
        .iter()
        .flat_map(|r| r.ringing.strokes.windows(2).map(|w| bdc(&w[1]) - bdc(&w[0])))
        .fold(0.0, f64::max);
    let first_half = rungs
        .iter()
        .map(|r| r.ringing.strokes[0].end.t - r.ringing.strokes[0].start.t)
        .fold(0.0, f64::max);
    let interval = (1.05 * longest.max(first_half) / n).max(0.05);
    let t0 = rungs
        .iter()
        .enumerate()
        .map(|(i, r)| LEAD_S + lead + bdc(&r.ringing.strokes[0]) - i as f64 * interval)
        .fold(f64::NEG_INFINITY, f64::max);
    for (i, r) in rungs.iter_mut().enumerate() {
        let (offsets, ideal) = r
            .ringing
            .strokes
            .iter()
            .enumerate()
            .map(|(k, s)| {
                // Row k, with a handstroke gap of one interval before each
                // handstroke row after the first.
                let ideal = t0 + (k as f64 * n + (k / 2) as f64 + i as f64) * interval;
                (ideal - lead - bdc(s), Some(ideal))
            })
            .unzip();
        r.offsets = offsets;
        r.ideal = ideal;
    }
    interval
}

/// A bell's nominal (Hz) from its mass, for a ring's sound: nominal ∝
/// M^(-1/3) (bells of a ring are near scaled copies), 580 Hz at a tonne,
/// a rule of thumb for English bells.
pub fn nominal_from_mass(mass_kg: f64) -> f64 {
    580.0 * (mass_kg / 1000.0).cbrt().recip()
}

/// Animate `bells` (each a request and the bell file its caller read, if
/// any), set out as `arrangement` says.
pub fn animate(
    bells: Vec<(SimulateRequest, Option<LoadedBell>)>,
    arrangement: Arrangement,
    opts: &AnimateOptions,
) -> Result<Animated, AppError> {
    if bells.is_empty() {
        return Err(AppError::Request("nothing to animate: no bells".into()));
    }
    if !(opts.fps.is_finite() && (1.0..=2000.0).contains(&opts.fps)) {
        return Err(AppError::Request(format!(
            "--fps {} is out of range: 1 to 2000 frames a second",
            opts.fps
        )));
    }
    opts.sound.check()?;
    let mut rungs = Vec::with_capacity(bells.len());
    for (req, file) in bells {
        rungs.push(rung_of(req, file, opts)?);
    }
    let rounds_interval = (arrangement == Arrangement::Rounds).then(|| place_rounds(&mut rungs));
    let end = rungs.iter().map(Rung::end).fold(0.0, f64::max) + opts.sound.tail;
    let n_frames = (end * opts.fps).ceil() as usize + 1;
    if n_frames.saturating_mul(rungs.len()) > MAX_FRAMES {
        return Err(AppError::Request(format!(
            "{n_frames} frames for each of {} bell(s) is too many (at most {MAX_FRAMES} in all): ask for fewer strokes or a lower --fps",
            rungs.len()
        )));
    }
    let duration = (n_frames - 1) as f64 / opts.fps;
    let mut motions = Vec::with_capacity(rungs.len());
    let mut sound: Vec<f64> = vec![];
    for r in &rungs {
        motions.push(motion(r, opts, n_frames, duration)?);
        let signal = bell_sound(r, opts, arrangement, duration)?;
        if sound.len() < signal.samples.len() {
            sound.resize(signal.samples.len(), 0.0);
        }
        for (a, b) in sound.iter_mut().zip(&signal.samples) {
            *a += b;
        }
    }
    let title = title_of(arrangement, &rungs, rounds_interval);
    Ok(Animated {
        animation: Animation {
            title,
            duration,
            bells: motions,
            rounds_interval,
        },
        sound: Signal {
            rate: opts.sound.rate,
            samples: sound,
        },
    })
}

/// One bell rung as `req` asks (its bell file `file`, if any), its sound
/// laid out one stroke after another.
fn rung_of(req: SimulateRequest, file: Option<LoadedBell>, opts: &AnimateOptions) -> Result<Rung, AppError> {
    let loaded = req.bell(file)?;
    let cfg = req.config_for(&loaded)?;
    if req.strokes > MAX_STROKES {
        return Err(AppError::Request(format!(
            "strokes {} is too many to animate: at most {MAX_STROKES}",
            req.strokes
        )));
    }
    let mut rec = TraceRecorder::new(1e-3);
    let ringing = ring(&loaded.bell, &cfg, req.style, req.protocol, req.strokes, &mut rec)?;
    let n = ringing.strokes.len();
    Ok(Rung {
        name: loaded.name,
        bell: loaded.bell,
        cfg,
        req,
        ringing,
        trace: rec.samples,
        offsets: (0..n).map(|k| LEAD_S + opts.sound.gap * (k / 2) as f64).collect(),
        ideal: vec![None; n],
    })
}

/// One bell's sound over the animation's `duration` (s): at its own
/// pitch in a ring rung in rounds.
fn bell_sound(r: &Rung, opts: &AnimateOptions, arrangement: Arrangement, duration: f64) -> Result<Signal, AppError> {
    let mut sopts = opts.sound.clone();
    if arrangement == Arrangement::Rounds && sopts.partials == Partials::Typical {
        sopts.nominal = nominal_from_mass(r.bell.bell_mass);
    }
    let modes = match arrangement {
        // A ring's bells sound at their own pitches.
        Arrangement::Rounds if sopts.partials == Partials::Lab => {
            typical_partials(nominal_from_mass(r.bell.bell_mass), r.bell.bell_mass)
        }
        _ => sopts.modes(&r.bell),
    };
    let spec = SynthSpec {
        rate: sopts.rate,
        duration,
        modes,
        strikes: heard_strikes(&r.bell, &r.ringing, &r.offsets, sopts.pulse_ms * 1e-3),
        rests: heard_rests(&r.trace, &r.ringing, &r.offsets, duration),
        rest_damping: sopts.rest_damping,
        acceleration: false,
    };
    synthesize(&spec).map_err(|e| AppError::Sound(e.to_string()))
}

/// The animation's title: the ring in rounds, the one bell, or the bells
/// side by side.
fn title_of(arrangement: Arrangement, rungs: &[Rung], rounds_interval: Option<f64>) -> String {
    match (arrangement, rungs) {
        (Arrangement::Rounds, _) => format!(
            "{} bells ringing rounds, {:.0} ms between blows",
            rungs.len(),
            rounds_interval.unwrap_or(0.0) * 1e3
        ),
        (_, [one]) => format!(
            "{}: ringing {} from {} deg, R = {}",
            one.name,
            one.req.style.name(),
            one.req.theta0,
            one.cfg.restitution
        ),
        // The same bell two ways: name it once.
        _ if rungs.iter().all(|r| r.name == rungs[0].name) => format!(
            "{}: {}",
            rungs[0].name,
            rungs
                .iter()
                .map(|r| r.req.style.name())
                .collect::<Vec<_>>()
                .join(" beside ")
        ),
        _ => rungs
            .iter()
            .map(|r| r.name.as_str())
            .collect::<Vec<_>>()
            .join(" beside "),
    }
}

/// A rung bell's impacts, each at its time in the animation.
fn strike_marks(r: &Rung) -> Vec<StrikeMark> {
    let mut strikes = vec![];
    for (k, s) in r.ringing.strokes.iter().enumerate() {
        let first = s.first_strike_index();
        for (j, i) in s.impacts.iter().enumerate() {
            strikes.push(StrikeMark {
                t: i.t + r.offsets[k],
                t_sim: i.t,
                side: if i.side == Side::Plus { 1 } else { -1 },
                stroke: k,
                first: first == Some(j),
                ideal: if first == Some(j) { r.ideal[k] } else { None },
                speed: i.phi_dot_before.abs(),
            });
        }
    }
    strikes
}

/// One bell's frames and strikes: the second, identical simulation,
/// sampled at each frame's simulated time.
fn motion(r: &Rung, opts: &AnimateOptions, n_frames: usize, duration: f64) -> Result<BellMotion, AppError> {
    let strikes = strike_marks(r);
    let mut taus: Vec<f64> = (0..n_frames).map(|j| j as f64 / opts.fps).collect();
    if opts.impact_frames {
        taus.extend(strikes.iter().map(|s| s.t).filter(|t| *t < duration));
        taus.sort_by(f64::total_cmp);
        taus.dedup();
    }
    let mut stroke = 0;
    let mut sim_times: Vec<f64> = taus.iter().map(|&tau| r.sim_time(tau, &mut stroke)).collect();
    // An impact's frame shows the impact's own time, not that time shifted
    // there and back (which may differ in the last bit).
    for s in &strikes {
        if let Ok(j) = taus.binary_search_by(|t| t.total_cmp(&s.t)) {
            sim_times[j] = s.t_sim;
        }
    }
    let mut sampler = AtTimes {
        times: &sim_times,
        next: 0,
        out: Vec::with_capacity(sim_times.len()),
    };
    let again = ring(
        &r.bell,
        &r.cfg,
        r.req.style,
        r.req.protocol,
        r.req.strokes,
        &mut sampler,
    )?;
    if again.strokes.len() != r.ringing.strokes.len() || sampler.out.len() != taus.len() {
        return Err(AppError::Sound(format!(
            "could not draw {}'s frames: simulated again to sample them, it gave {} of {} frames (a fault of clapper's, not of the request: please report it)",
            r.name,
            sampler.out.len(),
            taus.len()
        )));
    }
    let frames = taus
        .iter()
        .zip(&sampler.out)
        .map(|(&t, s)| Frame {
            t,
            t_sim: s.t,
            theta: s.y[0],
            phi: s.y[1],
        })
        .collect();
    let caption = format!(
        "ringing {} from {} deg, R = {}{}",
        r.req.style.name(),
        r.req.theta0,
        r.cfg.restitution,
        if r.ringing.sustained() {
            ""
        } else {
            " (cannot keep it up)"
        }
    );
    Ok(BellMotion {
        name: r.name.clone(),
        caption,
        figure: Figure::of(&r.bell),
        frames,
        strikes,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::simulate::simulate_traced;

    fn lab(style: &str, strokes: usize) -> SimulateRequest {
        serde_json::from_str(&format!(
            r#"{{"preset": "lab", "style": "{style}", "strokes": {strokes}}}"#
        ))
        .expect("request")
    }

    #[test]
    fn each_frame_is_the_simulated_state_at_its_time() {
        // At 400 frames a second every frame's simulated time lies on the
        // plot trace's grid (0.5 ms), whatever the stroke's shift (0.2 s,
        // 0.25 s): the two runs are set side by side, sample by sample.
        let req = lab("right", 4);
        let opts = AnimateOptions {
            fps: 400.0,
            impact_frames: false,
            ..AnimateOptions::default()
        };
        let a = animate(vec![(req.clone(), None)], Arrangement::SideBySide, &opts).expect("animated");
        let trace = simulate_traced(&req, None, None).expect("trace").samples;
        let mut matched = 0;
        for f in &a.animation.bells[0].frames {
            let k = (f.t_sim / 5e-4).round() as usize;
            let Some(s) = trace
                .iter()
                .find(|s| (s.t - k as f64 * 5e-4).abs() < 1e-12 && (s.t - f.t_sim).abs() < 1e-9)
            else {
                continue;
            };
            assert!((s.y[0] - f.theta).abs() < 1e-10, "theta at {}", f.t_sim);
            assert!((s.y[1] - f.phi).abs() < 1e-10, "phi at {}", f.t_sim);
            matched += 1;
        }
        assert!(matched > 1000, "{matched} frames matched");
    }

    #[test]
    fn the_clapper_is_at_the_stop_in_the_frame_of_each_impact() {
        let a = animate(
            vec![(lab("right", 2), None)],
            Arrangement::SideBySide,
            &AnimateOptions::default(),
        )
        .expect("animated");
        let b = &a.animation.bells[0];
        assert!(b.strikes.len() >= 2);
        for s in &b.strikes {
            let f = b.frames.iter().find(|f| f.t == s.t).expect("a frame at the impact");
            let stop = b.figure.stops[usize::from(s.side > 0)];
            assert!((f.phi - stop).abs() < 1e-7, "phi {} at stop {stop}", f.phi);
            assert_eq!(f.t_sim, s.t_sim);
        }
    }

    #[test]
    fn the_sound_is_the_synth_commands_sound() {
        // One bell: the animation's clock is `clapper synth`'s.
        let req = lab("right", 2);
        let opts = AnimateOptions::default();
        let a = animate(vec![(req.clone(), None)], Arrangement::SideBySide, &opts).expect("animated");
        let s = crate::sound::synth(&req, None, &opts.sound).expect("synth");
        let n = a.sound.samples.len().min(s.signal.samples.len());
        let err = (0..n)
            .map(|i| (a.sound.samples[i] - s.signal.samples[i]).abs())
            .fold(0.0, f64::max);
        let peak = s.signal.samples.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        assert!(err <= 1e-9 * peak, "{err} against {peak}");
        let firsts: Vec<f64> = a.animation.bells[0].strikes.iter().map(|s| s.t).collect();
        let heard: Vec<f64> = s.report.strikes.iter().map(|s| s.t_s).collect();
        assert_eq!(firsts, heard);
    }

    #[test]
    fn rounds_keep_each_bell_in_its_place() {
        let bells: Vec<(SimulateRequest, Option<LoadedBell>)> = (0..3).map(|_| (lab("right", 4), None)).collect();
        let a = animate(bells, Arrangement::Rounds, &AnimateOptions::default()).expect("animated");
        let i = a.animation.rounds_interval.expect("rounds");
        // Identical bells strike exactly in their places: blow j of the
        // ring falls j intervals (and the handstroke gaps) after the first.
        let mut blows: Vec<(f64, f64)> = a
            .animation
            .bells
            .iter()
            .flat_map(|b| b.strikes.iter().filter(|s| s.first))
            .map(|s| (s.t, s.ideal.expect("ideal")))
            .collect();
        blows.sort_by(|x, y| x.0.total_cmp(&y.0));
        assert_eq!(blows.len(), 12);
        for (t, ideal) in &blows {
            assert!((t - ideal).abs() < 1e-9, "blow at {t}, ideal {ideal}");
        }
        for w in blows.windows(2) {
            let gap = w[1].0 - w[0].0;
            assert!((gap - i).abs() < 1e-9 || (gap - 2.0 * i).abs() < 1e-9, "gap {gap}");
        }
        // No bell's stroke begins before the one before it has ended.
        for b in &a.animation.bells {
            assert!(b.frames.windows(2).all(|w| w[0].t_sim <= w[1].t_sim));
        }
    }

    #[test]
    fn too_many_frames_or_a_bad_rate_are_refused() {
        let o = AnimateOptions {
            fps: 0.0,
            ..AnimateOptions::default()
        };
        assert!(animate(vec![(lab("right", 2), None)], Arrangement::SideBySide, &o).is_err());
        let o = AnimateOptions {
            fps: 2000.0,
            ..AnimateOptions::default()
        };
        let three = vec![
            (lab("right", 200), None),
            (lab("right", 200), None),
            (lab("right", 200), None),
        ];
        let e = animate(three, Arrangement::SideBySide, &o);
        assert!(e.is_err_and(|e| e.to_string().contains("frames for each")));
        let e = animate(vec![(lab("right", 201), None)], Arrangement::SideBySide, &o);
        assert!(e.is_err_and(|e| e.to_string().contains("too many to animate")));
        assert!(animate(vec![], Arrangement::SideBySide, &AnimateOptions::default()).is_err());
    }
}
