//! Shared helpers of the crate's unit tests: a deterministic random generator and body-frame turns.

use crate::math::{EulerParameters, Vec3, Vec4};

/// A tiny deterministic generator (Knuth's MMIX linear congruential constants).
pub(crate) struct Lcg(pub u64);

impl Lcg {
    pub fn uniform(&mut self) -> f64 {
        self.0 = self.0.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
    pub fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.uniform()
    }
    pub fn vec3(&mut self, scale: f64) -> Vec3 {
        Vec3::new(self.range(-scale, scale), self.range(-scale, scale), self.range(-scale, scale))
    }
    pub fn unit(&mut self) -> Vec3 {
        loop {
            let v = self.vec3(1.0);
            let n = v.norm();
            if n > 0.2 && n < 1.0 {
                return v / n;
            }
        }
    }
    pub fn rotation(&mut self) -> EulerParameters {
        let axis = self.unit();
        EulerParameters::from_axis_angle(&axis, self.range(-3.0, 3.0)).unwrap()
    }
}

/// Hamilton product `p ⊗ r`, so that `A(p ⊗ r) = A(p) A(r)`.
pub(crate) fn quat_mul(p: &Vec4, r: &Vec4) -> Vec4 {
    let (p0, pv) = (p[0], Vec3::new(p[1], p[2], p[3]));
    let (r0, rv) = (r[0], Vec3::new(r[1], r[2], r[3]));
    let v = p0 * rv + r0 * pv + pv.cross(&rv);
    Vec4::new(p0 * r0 - pv.dot(&rv), v.x, v.y, v.z)
}

/// `p ⊗ exp(½ π̄)`: the body frame turned by the body-frame rotation vector `π̄`, `A ← A exp(π̄~)`.
pub(crate) fn turn_body_frame(p: &Vec4, pi_bar: &Vec3) -> Vec4 {
    let angle = pi_bar.norm();
    let r = if angle == 0.0 {
        Vec4::new(1.0, 0.0, 0.0, 0.0)
    } else {
        let (s, c) = (0.5 * angle).sin_cos();
        Vec4::new(c, s * pi_bar.x / angle, s * pi_bar.y / angle, s * pi_bar.z / angle)
    };
    quat_mul(p, &r)
}

