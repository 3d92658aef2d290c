//! Small fixed-size 3D geometry: Euler parameters and the matrices built from them.

pub(crate) mod euler_angles;
pub(crate) mod euler_parameters;

pub use euler_angles::{continue_angle, EulerSequence, GIMBAL_LOCK_TOLERANCE};

pub use euler_parameters::{
    e_matrix, g_matrix, rotation_matrix, rotation_matrix_defect, EulerParameters, OrientationError, ROTATION_TOLERANCE,
};

/// 3-vector (nalgebra, fixed size).
pub type Vec3 = nalgebra::Vector3<f64>;
/// 3×3 matrix (nalgebra, fixed size).
pub type Mat3 = nalgebra::Matrix3<f64>;
/// 4-vector of Euler parameters `[e0, e1, e2, e3]`.
pub type Vec4 = nalgebra::Vector4<f64>;
/// 3×4 matrix, the shape of `E(p)` and `G(p)`.
pub type Mat3x4 = nalgebra::Matrix3x4<f64>;
/// 3×6 matrix: a marker's point or rotation Jacobian with respect to one rigid body's `[Ṙ, ω̄]`.
pub type Mat3x6 = nalgebra::Matrix3x6<f64>;
/// 6×6 matrix: one rigid body's mass matrix in `[Ṙ, ω̄]`.
pub type Mat6 = nalgebra::Matrix6<f64>;
/// 6-vector: one rigid body's velocity `[Ṙ, ω̄]` or generalized force `[F, N̄]`.
pub type Vec6 = nalgebra::Vector6<f64>;

/// The skew-symmetric matrix `x̃` with `x̃ y = x × y`.
#[inline]
pub fn skew(x: &Vec3) -> Mat3 {
    x.cross_matrix()
}
