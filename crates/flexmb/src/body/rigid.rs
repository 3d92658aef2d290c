//! A rigid body: mass, centre of mass and inertia in its body frame; reference coordinates `R, p`.

use crate::math::{skew, EulerParameters, Mat3, Vec3};

/// Initial pose and velocity of a body's reference frame.
#[derive(Clone, Debug)]
pub struct InitialState {
    /// Origin of the body frame in global coordinates (m).
    pub position: Vec3,
    /// Orientation of the body frame.
    pub orientation: EulerParameters,
    /// Velocity of the body-frame origin, global (m/s). `None`: free for the velocity analysis to choose.
    pub velocity: Option<Vec3>,
    /// Angular velocity, global components (rad/s). `None`: free for the velocity analysis to choose.
    pub angular_velocity: Option<Vec3>,
}

impl Default for InitialState {
    fn default() -> Self {
        Self {
            position: Vec3::zeros(),
            orientation: EulerParameters::identity(),
            velocity: None,
            angular_velocity: None,
        }
    }
}

/// A rigid body. The body frame need not be at the centre of mass nor along principal axes.
#[derive(Clone, Debug)]
pub struct RigidBody {
    /// The body's name.
    pub name: String,
    /// Mass (kg), positive.
    pub mass: f64,
    /// Centre of mass in the body frame (m).
    pub center_of_mass: Vec3,
    /// Inertia tensor about the centre of mass, body-frame axes (kg m²), symmetric positive definite.
    pub inertia: Mat3,
    /// Initial pose and velocity of the body frame.
    pub initial: InitialState,
}

impl RigidBody {
    /// First moment of mass about the frame origin, `S̄ = m c̄` (the flexible body's `C1` for a rigid one).
    pub fn first_moment(&self) -> Vec3 {
        self.mass * self.center_of_mass
    }

    /// Inertia about the frame origin, `J̄ = J̄_c − m c̄̃ c̄̃` (parallel-axis theorem).
    pub fn inertia_about_origin(&self) -> Mat3 {
        let c = skew(&self.center_of_mass);
        self.inertia - self.mass * c * c
    }
}
