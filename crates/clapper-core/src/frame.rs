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

/// The load at one sample (its contact force and friction give the
/// accelerations). The clapper pivot sits r along the bell's axis and d
/// (`pivot_offset`) across it (docs/model.md §10.1).
pub fn frame_load(d: &Dynamics, s: &Sample) -> FrameLoad {
    let bell = d.bell();
    let y: &State = &s.y;
    let acc = d.accel_q(y, s.friction[0], s.contact_force + s.friction[1]);
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
    // The offset d: the point (d cos θ, d sin θ), accelerating as
    // d(−θ'' sin θ − θ'² cos θ, θ'' cos θ − θ'² sin θ).
    let off = bell.hanging.pivot_offset;
    let clapper_acc = (
        bell.r * (tdd * ct - thd * thd * st) + bell.b * (wd * ca - w * w * sa) - off * (tdd * st + thd * thd * ct),
        bell.r * (tdd * st + thd * thd * ct) + bell.b * (wd * sa + w * w * ca) + off * (tdd * ct - thd * thd * st),
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
            friction: [0.0; 2],
        };
        let l = frame_load(&d, &s);
        assert!(l.horizontal.abs() < 1e-9);
        assert!((l.vertical - (bell.bell_mass + bell.clapper_mass) * G).abs() < 1e-9);
    }

    /// An offset pivot and friction: the load equals the weight less the
    /// rate of change of momentum, the momentum's rate taken by central
    /// differences of the centres of mass along the simulated trace (not
    /// from the accelerations the load uses).
    #[test]
    fn load_is_the_rate_of_change_of_momentum_with_offset_and_friction() {
        use crate::hanging::{Friction, Hanging};
        let bell = Bell::lab().with_hanging(Hanging {
            pivot_offset: 0.02,
            phi_max_skew: 0.02,
            friction: Friction {
                bell_damping: 0.5,
                clapper_damping: 0.05,
                ..Friction::default()
            },
        });
        let mut cfg = SimConfig::default();
        cfg.ode.rtol = 1e-12;
        cfg.ode.atol = 1e-12;
        let h = 1e-3;
        let mut rec = TraceRecorder::new(h);
        let start = StrokeStart::at_rest(&bell, &cfg, 0.0, cfg.theta0, Side::Plus);
        let stroke = run_stroke(&bell, &cfg, start, &mut rec).unwrap();
        let strike = stroke.first_strike().map_or(stroke.end.t, |f| f.t);
        let d = Dynamics::new(&bell);
        let (big_m, m, off) = (bell.bell_mass, bell.clapper_mass, bell.hanging.pivot_offset);
        let moment = |y: &State| {
            let [th, ph, ..] = *y;
            let xb = (bell.a * th.sin(), -bell.a * th.cos());
            let xc = (
                bell.r * th.sin() + off * th.cos() + bell.b * (th + ph).sin(),
                -bell.r * th.cos() + off * th.sin() - bell.b * (th + ph).cos(),
            );
            (big_m * xb.0 + m * xc.0, big_m * xb.1 + m * xc.1)
        };
        // Evenly spaced samples before the strike (no impact in a triple).
        let even: Vec<&Sample> = rec.samples.iter().filter(|s| s.t < strike - 2.0 * h).collect();
        let (mut checked, mut worst) = (0, 0.0f64);
        for w in even.windows(3) {
            if (w[1].t - w[0].t - h).abs() > 1e-12 || (w[2].t - w[1].t - h).abs() > 1e-12 {
                continue;
            }
            let (p0, p1, p2) = (moment(&w[0].y), moment(&w[1].y), moment(&w[2].y));
            let acc = (
                (p2.0 - 2.0 * p1.0 + p0.0) / (h * h),
                (p2.1 - 2.0 * p1.1 + p0.1) / (h * h),
            );
            let l = frame_load(&d, w[1]);
            let weight = (big_m + m) * G;
            worst = worst.max((l.horizontal + acc.0).abs() / weight);
            worst = worst.max((l.vertical - acc.1 - weight).abs() / weight);
            checked += 1;
        }
        assert!(checked > 500, "{checked}");
        println!("{checked} samples, worst {worst:.2e} of the weight");
        assert!(worst < 1e-4, "worst {worst} of the weight");
        assert!(rec.samples.iter().any(|s| s.friction[0] != 0.0 && s.friction[1] != 0.0));
    }
}
