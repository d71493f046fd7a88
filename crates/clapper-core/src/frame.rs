//! Forces on the frame (beyond the paper; tower engineers ask for it): the
//! bearing reaction of bell and clapper over a stroke, from the motion.
//!
//! Axes: x horizontal (positive towards positive θ), y vertical up, origin
//! at the bell's pivot; θ from the downward vertical. The load on the frame
//! is the weight of bell and clapper plus the inertial force of their
//! centres of mass: F = −(M a_B + m a_C) + (M + m) g, with g pointing down.
//! Impacts are impulses and are not part of this smooth load.

use crate::bell::G;
use crate::dynamics::{Dynamics, State};
use crate::stroke::Sample;

/// The load bell and clapper put on the frame at one instant.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameLoad {
    /// Time (s).
    pub t: f64,
    /// Horizontal load (N), positive towards positive θ.
    pub horizontal: f64,
    /// Vertical load (N), positive downwards (the weight at rest).
    pub vertical: f64,
}

/// The load at one sample (its contact force gives the accelerations).
pub fn frame_load(d: &Dynamics, s: &Sample) -> FrameLoad {
    let bell = d.bell();
    let y: &State = &s.y;
    let acc = d.accel(y, s.contact_force);
    let [th, ph, thd, phd] = *y;
    let (st, ct) = th.sin_cos();
    let (sa, ca) = (th + ph).sin_cos();
    let (tdd, pdd) = (acc.theta, acc.phi);
    // Position of a point at distance l along angle α from the pivot:
    // (l sin α, −l cos α); its acceleration: l(α'' cos α − α'² sin α, α'' sin α + α'² cos α).
    let bell_acc = (
        bell.a * (tdd * ct - thd * thd * st),
        bell.a * (tdd * st + thd * thd * ct),
    );
    let w = thd + phd;
    let wd = tdd + pdd;
    let clapper_acc = (
        bell.r * (tdd * ct - thd * thd * st) + bell.b * (wd * ca - w * w * sa),
        bell.r * (tdd * st + thd * thd * ct) + bell.b * (wd * sa + w * w * ca),
    );
    let (big_m, m) = (bell.bell_mass, bell.clapper_mass);
    FrameLoad {
        t: s.t,
        horizontal: -(big_m * bell_acc.0 + m * clapper_acc.0),
        // Up-positive reaction would be M a_y + m a_y + (M+m) g; the load is its opposite, down-positive.
        vertical: big_m * bell_acc.1 + m * clapper_acc.1 + (big_m + m) * G,
    }
}

/// Peaks of the frame load over a trace, as forces and as multiples of the
/// weight of bell and clapper.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FramePeaks {
    /// Weight of bell and clapper (N).
    pub weight: f64,
    /// Largest |horizontal| load (N).
    pub horizontal: f64,
    /// Largest downward load (N).
    pub vertical_down: f64,
    /// Most upward (least downward) load (N); negative means the bell lifts
    /// on its bearings.
    pub vertical_min: f64,
}

impl FramePeaks {
    /// Peak horizontal load over weight.
    pub fn horizontal_ratio(&self) -> f64 {
        self.horizontal / self.weight
    }
    /// Peak downward load over weight.
    pub fn vertical_ratio(&self) -> f64 {
        self.vertical_down / self.weight
    }
}

/// The peaks of [`frame_load`] over `samples` (none for an empty trace).
pub fn frame_peaks(d: &Dynamics, samples: &[Sample]) -> Option<FramePeaks> {
    let bell = d.bell();
    let mut it = samples.iter().map(|s| frame_load(d, s));
    let first = it.next()?;
    let mut p = FramePeaks {
        weight: (bell.bell_mass + bell.clapper_mass) * G,
        horizontal: first.horizontal.abs(),
        vertical_down: first.vertical,
        vertical_min: first.vertical,
    };
    for l in it {
        p.horizontal = p.horizontal.max(l.horizontal.abs());
        p.vertical_down = p.vertical_down.max(l.vertical);
        p.vertical_min = p.vertical_min.min(l.vertical);
    }
    Some(p)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bell::Bell;
    use crate::stroke::{run_stroke, Side, SimConfig, StrokeStart, TraceRecorder};

    /// A compound pendulum (the clapper vanishingly light): the load from
    /// the simulation equals the closed form at every sample.
    #[test]
    fn compound_pendulum_closed_form() {
        let lab = Bell::lab();
        let bell = Bell {
            clapper_mass: 1e-9,
            clapper_inertia: 1e-10,
            ..lab
        };
        let cfg = SimConfig::default();
        let mut rec = TraceRecorder::new(1e-3);
        let start = StrokeStart::at_rest(&bell, &cfg, 0.0, cfg.theta0, Side::Plus);
        run_stroke(&bell, &cfg, start, &mut rec).unwrap();
        let d = Dynamics::new(&bell);
        let (m, a, lb, th0) = (bell.bell_mass, bell.a, bell.lb(), cfg.theta0);
        let mut checked = 0;
        for s in &rec.samples {
            let th = s.y[0];
            // Energy: θ'² = 2 (g/L_b)(cos θ − cos θ0); motion: θ'' = −(g/L_b) sin θ.
            let w2 = 2.0 * G / lb * (th.cos() - th0.cos());
            let tdd = -G / lb * th.sin();
            let h = -m * a * (tdd * th.cos() - w2 * th.sin());
            let v = m * a * (tdd * th.sin() + w2 * th.cos()) + m * G;
            let l = frame_load(&d, s);
            assert!(
                (l.horizontal - h).abs() < 1e-5 * m * G,
                "t {}: {} vs {h}",
                s.t,
                l.horizontal
            );
            assert!(
                (l.vertical - v).abs() < 1e-5 * m * G,
                "t {}: {} vs {v}",
                s.t,
                l.vertical
            );
            checked += 1;
        }
        assert!(checked > 500);
        // At the bottom: 1 + 2 (a/L_b)(1 − cos θ0) times the weight.
        let p = frame_peaks(&d, &rec.samples).unwrap();
        let bottom = 1.0 + 2.0 * (a / lb) * (1.0 - th0.cos());
        assert!(
            (p.vertical_ratio() - bottom).abs() < 1e-3,
            "{} vs {bottom}",
            p.vertical_ratio()
        );
    }

    #[test]
    fn at_rest_the_load_is_the_weight() {
        let bell = Bell::gsm_tenor();
        let d = Dynamics::new(&bell);
        let s = Sample {
            t: 0.0,
            y: [0.0, 0.0, 0.0, 0.0],
            contact_force: 0.0,
        };
        let l = frame_load(&d, &s);
        assert!(l.horizontal.abs() < 1e-9);
        assert!((l.vertical - (bell.bell_mass + bell.clapper_mass) * G).abs() < 1e-9);
    }
}
