//! The closed form the simulation is checked against (docs/tower.md §2):
//! bell and clapper as one rigid pendulum (the clapper tied) let go from
//! rest at θ0.
//!
//! With M the whole mass, h its centre of mass below the pivot and I its
//! moment of inertia about the pivot, energy gives θ'² = 2 (M g h / I)
//! (cos θ − cos θ0) and the motion θ'' = −(M g h / I) sin θ. The frame's
//! load is the weight plus minus the mass times the centre's acceleration;
//! with κ = M h² / I (the centre's distance over the radius of gyration,
//! squared) and c = cos θ, c0 = cos θ0:
//!
//! horizontal / weight = κ sin θ (3 c − 2 c0),
//! vertical / weight   = 1 + κ (3 c² − 2 c c0 − 1).

use clapper_core::bell::Bell;

/// Bell and clapper as one rigid body (clapper tied at its rest on the
/// bell's axis): its whole mass M (kg), the centre of mass below the pivot h
/// (m) and the moment of inertia about the pivot I (kg m²).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rigid {
    /// M (kg).
    pub mass: f64,
    /// h (m).
    pub h: f64,
    /// I (kg m²).
    pub inertia: f64,
}

impl Rigid {
    /// The bell with its clapper tied along its axis: the clapper's centre
    /// at r + b below the bell's pivot; its inertia about the bell's pivot by
    /// the parallel-axis theorem, I_c + m((r + b)² − b²).
    pub fn of(bell: &Bell) -> Self {
        let m = bell.clapper_mass;
        let lc = bell.r + bell.b;
        let mass = bell.bell_mass + m;
        Self {
            mass,
            h: (bell.bell_mass * bell.a + m * lc) / mass,
            inertia: bell.bell_inertia + bell.clapper_inertia + m * (lc * lc - bell.b * bell.b),
        }
    }

    /// κ = M h² / I.
    pub fn kappa(&self) -> f64 {
        self.mass * self.h * self.h / self.inertia
    }

    /// The peak horizontal load over the weight, let go from rest at
    /// `theta0` (rad, in (0, π]): the largest |κ sin θ (3c − 2c0)| over
    /// |θ| ≤ θ0, at 6c² − 2c c0 − 3 = 0 or at θ0 itself.
    pub fn peak_horizontal(&self, theta0: f64) -> f64 {
        let c0 = theta0.cos();
        let f = |c: f64| {
            let s = (1.0 - c * c).max(0.0).sqrt();
            (self.kappa() * s * (3.0 * c - 2.0 * c0)).abs()
        };
        // Roots of 6c² − 2 c0 c − 3 = 0 inside [c0, 1].
        let disc = (4.0 * c0 * c0 + 72.0).sqrt();
        [(2.0 * c0 + disc) / 12.0, (2.0 * c0 - disc) / 12.0, c0]
            .into_iter()
            .filter(|c| (c0..=1.0).contains(c))
            .map(f)
            .fold(0.0, f64::max)
    }

    /// The peak downward load over the weight: at the bottom, 1 + κ (2 − 2 c0).
    pub fn peak_vertical(&self, theta0: f64) -> f64 {
        1.0 + self.kappa() * (2.0 - 2.0 * theta0.cos())
    }

    /// The same body as a bell whose clapper is vanishingly light and
    /// rests where it was tied: what the stroke simulation runs for the
    /// check (the clapper's share is in the bell's mass and inertia).
    pub fn as_bell(&self, like: &Bell) -> Bell {
        Bell {
            bell_mass: self.mass,
            a: self.h,
            bell_inertia: self.inertia,
            clapper_mass: 1e-9 * self.mass,
            clapper_inertia: 1e-9 * self.inertia,
            ..*like
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// From the balance (θ0 = π): vertical 1 + 4κ; horizontal at cos θ =
    /// (√76 − 2)/12 ≈ 0.5598, 3.049 κ (docs/tower.md §2).
    #[test]
    fn from_the_balance() {
        let r = Rigid {
            mass: 1.0,
            h: 1.0,
            inertia: 2.0,
        };
        let c: f64 = (76f64.sqrt() - 2.0) / 12.0;
        let s = (1.0 - c * c).sqrt();
        assert!((r.peak_horizontal(std::f64::consts::PI) - 0.5 * s * (3.0 * c + 2.0)).abs() < 1e-12);
        assert!((r.peak_horizontal(std::f64::consts::PI) / 0.5 - 3.0490).abs() < 1e-3);
        assert!((r.peak_vertical(std::f64::consts::PI) - 3.0).abs() < 1e-12);
    }

    /// The lab bell's κ with the clapper tied: 0.657, so 1 + 4κ = 3.63
    /// beside the 3.62 `diagnose` prints for the free clapper.
    #[test]
    fn lab_bell_kappa() {
        let k = Rigid::of(&Bell::lab()).kappa();
        assert!((k - 0.657).abs() < 1e-3, "{k}");
    }
}
