//! The flexible-body file: everything the multibody engine needs of a reduced FE model, and what a
//! viewer needs to draw it. Written as JSON; the format is documented in `docs/flexible-body-file.md`.

use std::path::Path;

use nalgebra::{DMatrix, Matrix3, Vector3};
use serde::{Deserialize, Serialize};

use super::geometric_stiffness::GeometricStiffness;
use super::invariants::InertiaInvariants;
use super::modal_stress::ModalStresses;
use crate::mesh::{FeModel, MassModel};
use super::serde_matrix;

/// The value of [`FlexibleBody::format`].
pub const FORMAT: &str = "flexmb-flexible-body";
/// The current [`FlexibleBody::version`].
pub const VERSION: u32 = 1;

/// The mass model of a reduced body's elements ([`MassModel`], per kind of element by
/// [`ModelOptions::mass_of`](crate::mesh::ModelOptions::mass_of)).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum BodyMass {
    /// Every element's mass lumped at its nodes; also files written before the key existed.
    #[default]
    Lumped,
    /// Every element's consistent mass.
    Consistent,
    /// Consistent for some elements, lumped for others: the default on a mesh of beams or solids
    /// with shells.
    Mixed,
}

impl BodyMass {
    /// The mass model of `model`'s elements; a model without elements (imported matrices) has the
    /// mass model it names, else lumped.
    pub fn of(model: &FeModel) -> BodyMass {
        let mut kinds = model.mesh.elements.iter().map(|e| model.options.mass_of(e.kind));
        let Some(first) = kinds.next() else {
            return model.options.mass.map_or(BodyMass::Lumped, BodyMass::from);
        };
        if kinds.all(|m| m == first) {
            BodyMass::from(first)
        } else {
            BodyMass::Mixed
        }
    }

    /// The name used in the flexible-body file and in reports.
    pub fn name(self) -> &'static str {
        match self {
            BodyMass::Lumped => "lumped",
            BodyMass::Consistent => "consistent",
            BodyMass::Mixed => "mixed",
        }
    }
}

impl From<MassModel> for BodyMass {
    fn from(mass: MassModel) -> Self {
        match mass {
            MassModel::Lumped => BodyMass::Lumped,
            MassModel::Consistent => BodyMass::Consistent,
        }
    }
}

/// How the mode basis is given.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Basis {
    /// The vibration modes (mass-normalized) and the static correction modes (unit-load responses)
    /// as computed, in the order of the mode set: the seed's basis.
    Raw,
    /// The span of the raw basis, mass-orthonormalized by the reduced eigenproblem: `C9 = I` and the
    /// modal stiffness diagonal (Adams' orthonormalized Craig–Bampton modes).
    #[default]
    Orthonormal,
}

/// What a mode of the basis is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ModeKind {
    /// A vibration mode of the supported FE model (`N`).
    Vibration,
    /// A static correction mode (`S`).
    Static,
    /// A mode of the orthonormalized basis: an eigenvector of the reduced model.
    Orthonormal,
}

/// One mode of the basis.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ModeInfo {
    /// `N1`, `S2`, `O3`, …
    pub label: String,
    /// Vibration, static correction or orthonormalized.
    pub kind: ModeKind,
    /// FE natural frequency of a vibration mode, reduced-model frequency of an orthonormal mode (Hz).
    pub frequency_hz: Option<f64>,
    /// The name of a static mode's unit load.
    pub load: Option<String>,
}

/// A node of the body: label, undeformed position in the body frame, lumped mass and rotary
/// inertia (with a consistent mass, the node's share of the element masses).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BodyNode {
    /// The node's label in the FE model.
    pub label: u64,
    /// Undeformed position in the body frame (m).
    #[serde(with = "serde_matrix::vector3")]
    pub position: Vector3<f64>,
    /// Lumped mass (kg).
    pub mass: f64,
    /// Rotary inertia about the node, body axes (kg m²).
    #[serde(with = "serde_matrix::matrix3")]
    pub rotary_inertia: Matrix3<f64>,
}

/// An element, for drawing: `beam` (2 nodes) or `shell` (3 or 4 nodes, in order around it); node
/// indices into [`FlexibleBody::nodes`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BodyElement {
    /// The element's label in the FE model.
    pub label: u64,
    /// `beam` or `shell`.
    pub kind: String,
    /// Indices into [`FlexibleBody::nodes`].
    pub nodes: Vec<usize>,
}

/// One mode shape at every node: translation and rotation (body frame).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ModeShape {
    /// The translation of every node (body frame), one per node.
    pub translation: Vec<[f64; 3]>,
    /// The rotation of every node (body frame), one per node.
    pub rotation: Vec<[f64; 3]>,
}

/// Rigid-body mass properties of the undeformed FE model.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BodyMassProperties {
    /// Total mass (kg).
    pub mass: f64,
    /// Centre of mass in the body frame (m).
    #[serde(with = "serde_matrix::vector3")]
    pub center_of_mass: Vector3<f64>,
    /// About the centre of mass, body axes (kg m²).
    #[serde(with = "serde_matrix::matrix3")]
    pub inertia: Matrix3<f64>,
}

/// A reduced flexible body.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FlexibleBody {
    /// Always [`FORMAT`].
    pub format: String,
    /// [`VERSION`] of the writer.
    pub version: u32,
    /// The body's name.
    pub name: String,
    /// The mode set, e.g. `4N5S`.
    pub mode_set: String,
    /// Raw or mass-orthonormalized modes.
    pub basis: Basis,
    /// The FE model's mass: `lumped` (the invariants are sums over the nodes' masses),
    /// `consistent` (integrals over the elements; the nodes' masses are then their shares, for
    /// drawing and checking) or `mixed` (integrals over the consistent elements, sums over the nodes
    /// of the lumped ones). Files without it are lumped.
    #[serde(default)]
    pub mass: BodyMass,
    /// Every node of the FE model.
    pub nodes: Vec<BodyNode>,
    /// Every element, for drawing.
    pub elements: Vec<BodyElement>,
    /// The modes, in basis order.
    pub modes: Vec<ModeInfo>,
    /// The mode shapes, in basis order.
    pub shapes: Vec<ModeShape>,
    /// `K_aa = Φᵀ K Φ` (m×m).
    #[serde(with = "serde_matrix::dmatrix")]
    pub modal_stiffness: DMatrix<f64>,
    /// `Φᵀ M Φ` (m×m): `C9` plus the rotary part.
    #[serde(with = "serde_matrix::dmatrix")]
    pub modal_mass: DMatrix<f64>,
    /// The inertia invariants of the equations of motion.
    pub invariants: InertiaInvariants,
    /// Natural frequencies of the reduced model (Hz), ascending.
    pub reduced_frequencies_hz: Vec<f64>,
    /// The lowest natural frequencies of the supported FE model (Hz), ascending.
    pub fe_frequencies_hz: Vec<f64>,
    /// Number of rigid motions the supports left (excluded from the modes).
    pub rigid_modes: usize,
    /// Mass, centre of mass and inertia of the undeformed body.
    pub mass_properties: BodyMassProperties,
    /// The modal geometric stiffness of the unit inertia loads (formulation.md §11), for the
    /// engine's geometric stiffening; absent in files written before it and for bodies with
    /// elements other than beams.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub geometric_stiffness: Option<GeometricStiffness>,
    /// Each mode's stress at the body's stress points ([`ModalStresses`]), when the reduction was
    /// asked for them; absent otherwise and in files written before them.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stresses: Option<ModalStresses>,
}

/// A problem reading or writing a flexible-body file.
#[derive(Debug, thiserror::Error)]
pub enum BodyFileError {
    /// The file cannot be written.
    #[error("{file}: {source}")]
    Io {
        /// The file's path.
        file: String,
        /// The operating system's error.
        source: std::io::Error,
    },
    /// The file cannot be read.
    #[error("{file}: cannot read: {source}")]
    Read {
        /// The file's path.
        file: String,
        /// Why.
        source: crate::input::InputFileError,
    },
    /// The file is not a flexible-body file.
    #[error("{file}:{line}:{column}: {message}")]
    Parse {
        /// The file's path.
        file: String,
        /// The line (from 1).
        line: usize,
        /// The column (from 1).
        column: usize,
        /// The parser's message.
        message: String,
    },
    /// The file reads but its contents disagree (sizes, format, version).
    #[error("{file}: {message}")]
    Invalid {
        /// The file's path.
        file: String,
        /// What is wrong.
        message: String,
    },
}

impl FlexibleBody {
    /// Number of modes.
    pub fn mode_count(&self) -> usize {
        self.modes.len()
    }

    /// `Ψᵢ`, the translational mode matrix of node `i` (3×m); `None` for `node` not below the number of
    /// nodes.
    pub fn psi(&self, node: usize) -> Option<DMatrix<f64>> {
        let has_node = node < self.nodes.len() && self.shapes.iter().all(|shape| node < shape.translation.len());
        has_node.then(|| DMatrix::from_fn(3, self.shapes.len(), |r, j| self.shapes[j].translation[node][r]))
    }

    /// `Θᵢ`, the rotational mode matrix of node `i` (3×m); `None` for `node` not below the number of
    /// nodes.
    pub fn theta(&self, node: usize) -> Option<DMatrix<f64>> {
        let has_node = node < self.nodes.len() && self.shapes.iter().all(|shape| node < shape.rotation.len());
        has_node.then(|| DMatrix::from_fn(3, self.shapes.len(), |r, j| self.shapes[j].rotation[node][r]))
    }

    /// The body as JSON text.
    pub fn to_json(&self) -> String {
        serde_json::to_string(self).expect("a flexible body serializes")
    }

    /// Writes the body to `path` as JSON.
    pub fn write(&self, path: &Path) -> Result<(), BodyFileError> {
        std::fs::write(path, self.to_json())
            .map_err(|source| BodyFileError::Io { file: path.display().to_string(), source })
    }

    /// Reads a body from JSON text; `file` names it in errors.
    pub fn from_json(text: &str, file: &str) -> Result<FlexibleBody, BodyFileError> {
        let body: FlexibleBody = serde_json::from_str(text).map_err(|e| BodyFileError::Parse {
            file: file.to_string(),
            line: e.line(),
            column: e.column(),
            message: e.to_string(),
        })?;
        body.validate().map_err(|message| BodyFileError::Invalid { file: file.to_string(), message })?;
        Ok(body)
    }

    /// Reads a body from the JSON file at `path`.
    pub fn read(path: &Path) -> Result<FlexibleBody, BodyFileError> {
        let file = path.display().to_string();
        let text = crate::input::read_text(path).map_err(|source| BodyFileError::Read { file: file.clone(), source })?;
        FlexibleBody::from_json(&text, &file)
    }

    /// Checks that the sizes agree with each other.
    fn validate(&self) -> Result<(), String> {
        if self.format != FORMAT {
            return Err(format!("not a flexible-body file: format is `{}`, expected `{FORMAT}`", self.format));
        }
        if self.version > VERSION {
            return Err(format!("file version {} is newer than this program's {VERSION}", self.version));
        }
        let (m, n) = (self.modes.len(), self.nodes.len());
        if self.shapes.len() != m {
            return Err(format!("{} mode shapes for {m} modes", self.shapes.len()));
        }
        if let Some(j) = self.shapes.iter().position(|s| s.translation.len() != n || s.rotation.len() != n) {
            return Err(format!("mode shape {} does not have one entry per node ({n})", j + 1));
        }
        let square = |name: &str, a: &DMatrix<f64>| {
            if a.nrows() == m && a.ncols() == m { Ok(()) } else { Err(format!("{name} is {}×{}, expected {m}×{m}", a.nrows(), a.ncols())) }
        };
        square("modal_stiffness", &self.modal_stiffness)?;
        square("modal_mass", &self.modal_mass)?;
        square("invariants.c9", &self.invariants.c9)?;
        if self.invariants.c4.len() != m || self.invariants.c5.len() != m || self.invariants.c7.len() != m {
            return Err(format!("invariants C4, C5, C7 must have {m} entries"));
        }
        if let Some(terms) = &self.geometric_stiffness {
            terms.validate(m)?;
        }
        if let Some(stresses) = &self.stresses {
            stresses.validate(m, n)?;
        }
        if let Some(e) = self.elements.iter().find(|e| e.nodes.iter().any(|&i| i >= n)) {
            return Err(format!("element {} refers to a node index beyond the {n} nodes", e.label));
        }
        Ok(())
    }
}
