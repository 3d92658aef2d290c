//! Euler angles: a rotation written as three successive rotations about body-fixed axes,
//! `A = A_i(φ) A_j(θ) A_k(ψ)`, for any of the 12 sequences — the six proper Euler sequences (`i = k`,
//! e.g. 3-1-3, Haug 1989 §6.1.3) and the six Tait–Bryan sequences (`i, j, k` distinct, e.g. 1-2-3 or
//! the 3-2-1 yaw–pitch–roll). Axis 1 is x, 2 is y, 3 is z.
//!
//! Each sequence has a singular orientation (gimbal lock) where the first and third axes line up and
//! only `φ ± ψ` is defined: a proper sequence at `θ = 0` or `π`, a Tait–Bryan sequence at
//! `θ = ±π/2`. There [`EulerSequence::angles`] keeps the third angle at the value it is given and puts
//! the whole rotation about the aligned axes into the first.

use super::Mat3;

/// Within this distance of a sequence's singularity (the sine of `θ` for a proper sequence, its
/// cosine for a Tait–Bryan one) the third angle is held.
pub const GIMBAL_LOCK_TOLERANCE: f64 = 1e-9;

/// One of the 12 sequences of body-fixed rotation axes, `[i, j, k]` with axes 0, 1, 2 for x, y, z.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct EulerSequence([usize; 3]);

impl EulerSequence {
    /// The sequence written as three digits 1–3, e.g. `"313"` or `"123"`; `None` for anything that is not
    /// one of the 12 (two equal neighbours, such as `"113"`, do not describe every rotation).
    pub fn parse(text: &str) -> Option<Self> {
        let digits: Vec<usize> = text.chars().map(|c| c.to_digit(10).map_or(usize::MAX, |d| d as usize)).collect();
        match digits[..] {
            [i, j, k] if (1..=3).contains(&i) && (1..=3).contains(&j) && (1..=3).contains(&k) && i != j && j != k => {
                Some(Self([i - 1, j - 1, k - 1]))
            }
            _ => None,
        }
    }

    /// The three digits, e.g. `"313"`.
    pub fn digits(&self) -> String {
        self.0.iter().map(|a| char::from(b'1' + *a as u8)).collect()
    }

    /// Whether it is a proper Euler sequence (first axis = third axis).
    pub fn is_proper(&self) -> bool {
        self.0[0] == self.0[2]
    }

    /// `A_i(φ) A_j(θ) A_k(ψ)`.
    pub fn rotation_matrix(&self, [phi, theta, psi]: [f64; 3]) -> Mat3 {
        let [i, j, k] = self.0;
        axis_rotation(i, phi) * axis_rotation(j, theta) * axis_rotation(k, psi)
    }

    /// The angles `[φ, θ, ψ]` of rotation matrix `a`: `θ` in `[0, π]` (proper) or `[−π/2, π/2]`
    /// (Tait–Bryan), `φ` and `ψ` in `(−π, π]`. At the singularity (within
    /// [`GIMBAL_LOCK_TOLERANCE`]) `ψ` is `psi_at_lock` and `φ` takes the rest of the rotation.
    pub fn angles(&self, a: &Mat3, psi_at_lock: f64) -> [f64; 3] {
        let [i, j, k0] = self.0;
        // The axis that is neither i nor j, and the sign of the permutation (i, j, k).
        let k = 3 - i - j;
        let s = if (i + 1) % 3 == j { 1.0 } else { -1.0 };
        let (theta, locked) = if self.is_proper() {
            let sin = a[(j, i)].hypot(a[(k, i)]);
            (sin.atan2(a[(i, i)]), sin < GIMBAL_LOCK_TOLERANCE)
        } else {
            let cos = a[(i, i)].hypot(a[(i, j)]);
            ((s * a[(i, k)]).atan2(cos), cos < GIMBAL_LOCK_TOLERANCE)
        };
        if locked {
            // A A_k(ψ)ᵀ = A_i(φ) A_j(θ), whose column j is A_i(φ) e_j = cos φ e_j + s sin φ e_k.
            let m = a * axis_rotation(k0, psi_at_lock).transpose();
            let phi = (s * m[(k, j)]).atan2(m[(j, j)]);
            return [phi, theta, psi_at_lock];
        }
        if self.is_proper() {
            [a[(j, i)].atan2(-s * a[(k, i)]), theta, a[(i, j)].atan2(s * a[(i, k)])]
        } else {
            [(-s * a[(j, k)]).atan2(a[(k, k)]), theta, (-s * a[(i, j)]).atan2(a[(i, i)])]
        }
    }
}

/// The rotation by `angle` about axis `axis` (0, 1, 2).
fn axis_rotation(axis: usize, angle: f64) -> Mat3 {
    let (s, c) = angle.sin_cos();
    let mut r = Mat3::identity();
    let (p, q) = ((axis + 1) % 3, (axis + 2) % 3);
    r[(p, p)] = c;
    r[(q, q)] = c;
    r[(p, q)] = -s;
    r[(q, p)] = s;
    r
}

/// `angle` plus the multiple of 2π that brings it nearest `previous`: continues an angle past ±π.
pub fn continue_angle(angle: f64, previous: f64) -> f64 {
    let turns = ((previous - angle) / std::f64::consts::TAU).round();
    if turns.is_finite() {
        angle + turns * std::f64::consts::TAU
    } else {
        angle
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const ALL: [&str; 12] = ["121", "131", "212", "232", "313", "323", "123", "132", "213", "231", "312", "321"];

    #[test]
    fn angles_give_back_the_rotation_for_every_sequence() {
        for text in ALL {
            let seq = EulerSequence::parse(text).unwrap();
            assert_eq!(seq.digits(), text);
            let theta = if seq.is_proper() { 1.1 } else { -0.7 };
            let given = [2.5, theta, -1.9];
            let a = seq.rotation_matrix(given);
            let got = seq.angles(&a, 0.0);
            for (g, w) in got.iter().zip(given) {
                assert!((g - w).abs() < 1e-13, "{text}: {got:?} vs {given:?}");
            }
        }
    }

    #[test]
    fn at_gimbal_lock_the_third_angle_is_held_and_the_rotation_kept() {
        for text in ALL {
            let seq = EulerSequence::parse(text).unwrap();
            let theta = if seq.is_proper() { 0.0 } else { std::f64::consts::FRAC_PI_2 };
            let a = seq.rotation_matrix([0.4, theta, 0.3]);
            let got = seq.angles(&a, 0.25);
            assert_eq!(got[2], 0.25);
            assert!((seq.rotation_matrix(got) - a).amax() < 1e-14, "{text}: {got:?}");
        }
    }

    #[test]
    fn sequences_with_equal_neighbours_are_refused() {
        for text in ["113", "331", "12", "1234", "404", "abc"] {
            assert!(EulerSequence::parse(text).is_none(), "{text}");
        }
    }

    #[test]
    fn continued_angles_follow_the_previous_value() {
        let tau = std::f64::consts::TAU;
        assert!((continue_angle(-3.1, 3.1) - (tau - 3.1)).abs() < 1e-15);
        assert_eq!(continue_angle(0.5, 0.4), 0.5);
        assert!((continue_angle(0.1, 4.0 * tau) - (4.0 * tau + 0.1)).abs() < 1e-12);
    }
}
