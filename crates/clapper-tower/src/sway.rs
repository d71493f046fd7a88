//! The tower's sway in one direction: a linear oscillator of modal mass m,
//! frequency f and damping ratio ζ, driven by the frame's horizontal force
//! at the bell chamber (docs/tower.md §4). Stepped exactly for a force held
//! constant over each step (the mean of its two ends), so the only error
//! is the force's own sampling.

use serde::{Deserialize, Serialize};

use crate::TowerError;

/// One direction of the tower's sway (its first mode).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Sway {
    /// Natural frequency (Hz).
    pub frequency_hz: f64,
    /// Damping ratio ζ (fraction of critical), in [0, 1).
    pub damping_ratio: f64,
    /// Modal mass referred to the bell chamber (kg): the mass that, moving
    /// with the chamber, has the mode's kinetic energy.
    pub modal_mass_kg: f64,
}

impl Sway {
    /// Checks the numbers.
    pub fn validate(&self, which: &str) -> Result<(), TowerError> {
        let bad = |what: String| Err(TowerError::Tower(format!("{which} sway: {what}")));
        if !(self.frequency_hz.is_finite() && self.frequency_hz > 0.0) {
            return bad(format!(
                "frequency_hz {} is out of range: a frequency above 0 Hz",
                self.frequency_hz
            ));
        }
        if !(0.0..1.0).contains(&self.damping_ratio) {
            return bad(format!(
                "damping_ratio {} is out of range: a fraction of critical from 0 up to, not including, 1",
                self.damping_ratio
            ));
        }
        if !(self.modal_mass_kg.is_finite() && self.modal_mass_kg > 0.0) {
            return bad(format!(
                "modal_mass_kg {} is out of range: a mass above 0 kg",
                self.modal_mass_kg
            ));
        }
        Ok(())
    }

    /// ω = 2πf (rad/s).
    pub fn omega(&self) -> f64 {
        std::f64::consts::TAU * self.frequency_hz
    }

    /// Stiffness k = m ω² (N/m).
    pub fn stiffness(&self) -> f64 {
        self.modal_mass_kg * self.omega().powi(2)
    }

    /// Damping coefficient c = 2 ζ m ω (N s/m).
    pub fn damping(&self) -> f64 {
        2.0 * self.damping_ratio * self.modal_mass_kg * self.omega()
    }
}

/// The sway over a force history.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SwayHistory {
    /// Displacement at the bell chamber (m), one per force sample.
    pub displacement: Vec<f64>,
    /// Velocity (m/s).
    pub velocity: Vec<f64>,
    /// Acceleration (m/s²).
    pub acceleration: Vec<f64>,
}

/// The response to `force` (N) sampled every `dt` (s), from rest.
pub fn respond(s: &Sway, force: &[f64], dt: f64) -> SwayHistory {
    let (w, z, m) = (s.omega(), s.damping_ratio, s.modal_mass_kg);
    let (k, c) = (s.stiffness(), s.damping());
    let wd = w * (1.0 - z * z).sqrt();
    let e = (-z * w * dt).exp();
    let (sn, cs) = (wd * dt).sin_cos();
    // The transition over one step, and the response to a unit force held.
    let p11 = e * (cs + z * w / wd * sn);
    let p12 = e * sn / wd;
    let p21 = -e * w * w / wd * sn;
    let p22 = e * (cs - z * w / wd * sn);
    let g1 = (1.0 - p11) / k;
    let g2 = -p21 / k;
    let n = force.len();
    let mut out = SwayHistory {
        displacement: Vec::with_capacity(n),
        velocity: Vec::with_capacity(n),
        acceleration: Vec::with_capacity(n),
    };
    let (mut x, mut v) = (0.0, 0.0);
    for i in 0..n {
        out.displacement.push(x);
        out.velocity.push(v);
        out.acceleration.push((force[i] - c * v - k * x) / m);
        if i + 1 < n {
            let f = 0.5 * (force[i] + force[i + 1]);
            let (x1, v1) = (p11 * x + p12 * v + g1 * f, p21 * x + p22 * v + g2 * f);
            x = x1;
            v = v1;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A steady force: the static deflection F/k. A harmonic force at
    /// resonance: amplitude F/(2ζk).
    #[test]
    fn static_and_resonant() {
        let s = Sway {
            frequency_hz: 1.5,
            damping_ratio: 0.02,
            modal_mass_kg: 1e5,
        };
        let dt = 0.005;
        let f = vec![1000.0; 20_000];
        let r = respond(&s, &f, dt);
        assert!((r.displacement.last().unwrap() - 1000.0 / s.stiffness()).abs() < 1e-4 * 1000.0 / s.stiffness());
        let f: Vec<f64> = (0..40_000)
            .map(|i| 1000.0 * (s.omega() * i as f64 * dt).sin())
            .collect();
        let r = respond(&s, &f, dt);
        let peak = r.displacement[30_000..].iter().fold(0.0f64, |a, &x| a.max(x.abs()));
        let want = 1000.0 / (2.0 * 0.02 * s.stiffness());
        assert!((peak / want - 1.0).abs() < 0.01, "{peak} vs {want}");
    }
}
