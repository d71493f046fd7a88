//! What an accelerometer fixed to the bell reads (docs/model.md §13): the
//! specific force (acceleration less gravity's, in m/s²) at a point of the
//! headstock, in the bell's own frame. At rest with the bell down it reads
//! +g along the bell's axis toward the crown; swinging, gravity turns with
//! the bell and the swing adds its own tangential (θ'') and centripetal
//! (θ'²) accelerations, more the further the sensor is from the pivot.

use crate::bell::G;

/// Where a sensor sits, in the bell's frame (docs/model.md §13): `along`
/// the bell's axis from the pivot toward the crown (m; a sensor on the
/// crown-staple nut, on top of the headstock, is a little above the pivot,
/// > 0) and `across` it toward the back side (m).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct SensorPlace {
    /// Distance along the bell's axis from the pivot, toward the crown (m).
    pub along: f64,
    /// Distance across the axis, toward the back side (m).
    pub across: f64,
}

/// The specific force at `place` (m/s²) with the bell at θ (rad), θ'
/// (rad/s), θ'' (rad/s²), in the bell's frame: `[tangential, radial]`,
/// tangential across the bell's axis toward the back side (at rest it reads
/// g sin θ), radial along the axis toward the crown (at rest g cos θ).
///
/// With p = (across, along): f = θ'' (−p_y, p_x) − θ'² p + g (sin θ, cos θ).
pub fn specific_force(place: SensorPlace, theta: f64, theta_dot: f64, theta_ddot: f64) -> [f64; 2] {
    let (px, py) = (place.across, place.along);
    let (s, c) = theta.sin_cos();
    let w2 = theta_dot * theta_dot;
    [-theta_ddot * py - w2 * px + G * s, theta_ddot * px - w2 * py + G * c]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The sensor's position in the tower (x across, y up) at bell angle θ.
    fn position(place: SensorPlace, theta: f64) -> [f64; 2] {
        let (s, c) = theta.sin_cos();
        [c * place.across - s * place.along, s * place.across + c * place.along]
    }

    #[test]
    fn the_reading_is_the_positions_second_derivative_less_gravity() {
        // Independent of the formula: differentiate the position twice
        // numerically along a made-up motion θ(t), add g upward, turn into
        // the bell's frame.
        let place = SensorPlace {
            along: 0.23,
            across: -0.04,
        };
        let theta = |t: f64| 2.7 * (1.3 * t).cos() + 0.2 * t;
        let h = 1e-4;
        for k in 0..40 {
            let t = 0.1 * k as f64;
            let (a, b, c) = (
                position(place, theta(t - h)),
                position(place, theta(t)),
                position(place, theta(t + h)),
            );
            let acc = [
                (a[0] - 2.0 * b[0] + c[0]) / (h * h),
                (a[1] - 2.0 * b[1] + c[1]) / (h * h),
            ];
            let f_tower = [acc[0], acc[1] + G];
            let th = theta(t);
            let (s, co) = th.sin_cos();
            // Into the bell's frame: turn back by θ.
            let f_bell = [co * f_tower[0] + s * f_tower[1], -s * f_tower[0] + co * f_tower[1]];
            let td = (theta(t + h) - theta(t - h)) / (2.0 * h);
            let tdd = (theta(t + h) - 2.0 * th + theta(t - h)) / (h * h);
            let want = specific_force(place, th, td, tdd);
            for i in 0..2 {
                assert!((f_bell[i] - want[i]).abs() < 1e-4, "t {t}: {f_bell:?} against {want:?}");
            }
        }
    }

    #[test]
    fn at_rest_it_reads_g_toward_the_crown() {
        let f = specific_force(
            SensorPlace {
                along: 0.2,
                across: 0.0,
            },
            0.0,
            0.0,
            0.0,
        );
        assert_eq!(f, [0.0, G]);
        // Mouth up at the balance: g away from the crown.
        let f = specific_force(
            SensorPlace {
                along: 0.2,
                across: 0.0,
            },
            std::f64::consts::PI,
            0.0,
            0.0,
        );
        assert!((f[1] + G).abs() < 1e-12 && f[0].abs() < 1e-12);
    }
}
