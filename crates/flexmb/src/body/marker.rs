//! Markers: the seed's ξ–η–ζ joint definition frames, fixed on a body or on ground.

use crate::math::{Mat3, Vec3};
use crate::model::BodyRef;

/// A frame fixed on a body (or ground). Joints, forces and outputs attach to markers.
#[derive(Clone, Debug)]
pub struct Marker {
    /// The marker's name.
    pub name: String,
    /// The body it is fixed on, or ground.
    pub body: BodyRef,
    /// Origin in the body frame (global coordinates for a ground marker), m.
    pub origin: Vec3,
    /// Axes in the body frame: columns are the marker's x, y, z unit vectors (proper rotation).
    pub axes: Mat3,
}
