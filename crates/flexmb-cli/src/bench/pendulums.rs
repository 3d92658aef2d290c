//! The flexible-pendulum cases: the shipped `models/flexible_pendulum.toml` (a steel strip on a hinge,
//! four vibration modes), the same with ten modes, and the same strip made rigid (its FE mass
//! properties, no modes): the cost per step of flexibility.

use std::path::{Path, PathBuf};

use flexmb::body::{Marker, RigidBody};
use flexmb::joint::{Joint, JointKind};
use flexmb::math::{Mat3, Vec3};
use flexmb::model::{BodyId, BodyRef, ModelBuilder};
use flexmb::Model;

use flexmb_files::model_file::parse_model_with;

/// The shipped model file (its FE model is read relative to it, so the case runs from a checkout).
fn model_path() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../models/flexible_pendulum.toml")
}

/// The shipped flexible pendulum, with its own mode set or with `modes`.
pub fn flexible_pendulum(modes: Option<&str>) -> Result<Model, String> {
    let path = model_path();
    let text = std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    let text = match modes {
        Some(set) => text.replacen("fe_model = ", &format!("modes = \"{set}\"\nfe_model = "), 1),
        None => text,
    };
    let base = path.parent().unwrap_or(Path::new("."));
    parse_model_with(&text, &path.display().to_string(), base, &crate::limits::load_options()).map(|l| std::sync::Arc::unwrap_or_clone(l.model)).map_err(|e| e.to_string())
}

/// The same strip made rigid: one rigid body with the FE model's mass properties on the same hinge.
pub fn rigid_pendulum() -> Result<Model, String> {
    let flexible = flexible_pendulum(None)?;
    let strip = flexible.body(BodyId(0)).ok_or("the flexible pendulum has no body")?;
    let mut b = ModelBuilder::new("rigid pendulum").gravity(flexible.gravity());
    let body = b.add_body(RigidBody {
        name: "beam".into(),
        mass: strip.mass,
        center_of_mass: strip.center_of_mass,
        inertia: strip.inertia,
        initial: strip.initial.clone(),
    }).map_err(|e| e.to_string())?;
    let on_body = b.add_marker(Marker { name: "hinge_beam".into(), body: BodyRef::Body(body), origin: Vec3::zeros(), axes: Mat3::identity() }).map_err(|e| e.to_string())?;
    let on_ground = b.add_marker(Marker { name: "hinge_ground".into(), body: BodyRef::Ground, origin: Vec3::zeros(), axes: Mat3::identity() }).map_err(|e| e.to_string())?;
    b.add_joint(Joint { name: "hinge".into(), kind: JointKind::Revolute, marker_i: on_ground, marker_j: on_body }).map_err(|e| e.to_string())?;
    b.build().map_err(|e| e.to_string())
}
