//! The modal geometric-stiffness terms of a body (formulation.md §11): the stress states of unit
//! inertia loads, each solved once on the supported FE model, and the geometric stiffness of each
//! projected onto the mode set, `G_k = Φᵀ K_geo(σ_k) Φ`. At run time the engine adds
//! `K_G a = Σ_k f_k G_k a` to the modal equations with the factors `f_k` of the current motion
//! (Wallrapp and Schwertassek, "Representation of geometric stiffening in multibody system
//! simulation", Int. J. Numer. Meth. Eng. 32, 1991; the geometric-stiffness terms of Wallrapp's
//! standard input data, Mech. Struct. Mach. 22, 1994).
//!
//! **Unit cases** (body frame, mass point `i` at `s̄ᵢ` with mass `mᵢ` and rotary inertia `Jᵢ`): the
//! d'Alembert load of a unit rigid-body acceleration of the frame,
//!
//! - `ā_j` (translational acceleration minus gravity, `j = x, y, z`): `−mᵢ e_j`;
//! - `ω̄̇_j` (angular acceleration): `−mᵢ e_j × s̄ᵢ` and the torque `−Jᵢ e_j`;
//! - `ω̄_j²` and `ω̄_j ω̄_k` (centrifugal, in the order `xx yy zz xy yz zx`): `−mᵢ (e_j e_jᵀ − I) s̄ᵢ`
//!   and `−mᵢ (e_j e_kᵀ + e_k e_jᵀ) s̄ᵢ`.
//!
//! **Interface cases.** At each interface node of the FE model (the `[[interface]]` tables: where
//! joints and force elements act on the body), six unit loads in body axes, the forces `F_x F_y F_z`
//! and the moments `M_x M_y M_z`, each with its own `G`. At run time their factors are the force and
//! moment the mechanism applies at the node. A unit load on a held dof (a support or a completing
//! dof) is reacted where it acts and stresses nothing: its `G` is zero; a moment at a node without
//! rotational dofs (solids only) likewise.
//!
//! **Support.** Every case is solved with the supports of the mode analysis, completed, when they
//! leave rigid motions (the door's hinge line, a free body), by as many held dofs as there are
//! motions, chosen by pivoting on them (the static correction modes' extra supports): a statically
//! determinate set, on which any load, balanced or not, has one static solution and is reacted at the
//! body's frame-defining nodes. This is the stress state of a body carried at those nodes, which is
//! what a body attached to the mechanism there is (a blade at its root, a beam on a hub). Inertia
//! relief was not chosen: it makes the stress of the inertia cases vanish (each balances itself) and
//! then needs the loads at the frame-defining nodes as interface cases of their own. A hyperstatic support set (more than the six rigid motions held) is used as it is.
//!
//! **Elements.** Beams give their geometric stiffness under their axial force
//! ([`beam_geometric_stiffness`](crate::element::beam::beam_geometric_stiffness)), shells under their
//! membrane stress ([`shell_geometric_stiffness`](crate::element::shell::shell_geometric_stiffness)),
//! solids under their stress ([`solid_geometric_stiffness`](crate::element::solid::solid_geometric_stiffness)).

use faer::Mat;
use nalgebra::{DMatrix, Matrix3, Vector3, Vector6};
use serde::{Deserialize, Serialize};

use super::serde_matrix;
use crate::assembly::AssembledModel;
use crate::element::beam::{axial_force, beam_geometric_stiffness};
use crate::element::shell::shell_geometric_stiffness;
use crate::element::solid::solid_geometric_stiffness;
use crate::error::FemError;
use crate::mesh::{Element, ElementKind, FeModel, Mesh};
use crate::modes::rigid::pivot_dofs;
use crate::static_correction::solve_with_extra_supports;

/// The names of the six centrifugal cases, in order.
pub const CENTRIFUGAL_CASES: [&str; 6] = ["xx", "yy", "zz", "xy", "yz", "zx"];

/// The number of unit load cases at an interface node: three forces, three moments.
pub const INTERFACE_CASES: usize = 6;

/// The index pairs `(j, k)` of the six centrifugal cases.
const CENTRIFUGAL_PAIRS: [(usize, usize); 6] = [(0, 0), (1, 1), (2, 2), (0, 1), (1, 2), (2, 0)];

/// The modal geometric stiffness of the unit inertia cases (each `m × m`, symmetric); the factors
/// are body-frame components.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GeometricStiffness {
    /// `G` of a unit `ā_x`, `ā_y`, `ā_z` (per m/s²): the frame's acceleration minus gravity.
    #[serde(with = "serde_matrix::dmatrix_list")]
    pub acceleration: Vec<DMatrix<f64>>,
    /// `G` of a unit `ω̄̇_x`, `ω̄̇_y`, `ω̄̇_z` (per rad/s²).
    #[serde(with = "serde_matrix::dmatrix_list")]
    pub angular_acceleration: Vec<DMatrix<f64>>,
    /// `G` of the centrifugal products `ω̄ₓ²`, `ω̄ᵧ²`, `ω̄𝓏²`, `ω̄ₓω̄ᵧ`, `ω̄ᵧω̄𝓏`, `ω̄𝓏ω̄ₓ` (per rad²/s²).
    #[serde(with = "serde_matrix::dmatrix_list")]
    pub centrifugal: Vec<DMatrix<f64>>,
    /// The interface cases, one entry per interface node (none without `[[interface]]` tables).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub interface: Vec<InterfaceStiffness>,
}

/// The modal geometric stiffness of the six unit loads at one interface node.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct InterfaceStiffness {
    /// The node's label in the FE model.
    pub node: u64,
    /// `G` of a unit force `F_x`, `F_y`, `F_z` (per N) and a unit moment `M_x`, `M_y`, `M_z` (per N m)
    /// at the node, body axes.
    #[serde(with = "serde_matrix::dmatrix_list")]
    pub loads: Vec<DMatrix<f64>>,
}

impl GeometricStiffness {
    /// Checks the counts (3, 3, 6) and that every matrix is `m × m`.
    pub fn validate(&self, m: usize) -> Result<(), String> {
        let groups = [("acceleration", &self.acceleration, 3), ("angular_acceleration", &self.angular_acceleration, 3), ("centrifugal", &self.centrifugal, 6)];
        for (name, list, count) in groups {
            if list.len() != count {
                return Err(format!("geometric_stiffness.{name} has {} matrices, expected {count}", list.len()));
            }
            if let Some(g) = list.iter().find(|g| g.shape() != (m, m)) {
                return Err(format!("geometric_stiffness.{name} holds a {}×{} matrix, expected {m}×{m}", g.nrows(), g.ncols()));
            }
        }
        for case in &self.interface {
            if case.loads.len() != INTERFACE_CASES {
                return Err(format!(
                    "geometric_stiffness.interface of node {} has {} matrices, expected {INTERFACE_CASES}",
                    case.node,
                    case.loads.len()
                ));
            }
            if let Some(g) = case.loads.iter().find(|g| g.shape() != (m, m)) {
                return Err(format!(
                    "geometric_stiffness.interface of node {} holds a {}×{} matrix, expected {m}×{m}",
                    case.node,
                    g.nrows(),
                    g.ncols()
                ));
            }
        }
        Ok(())
    }
}

/// The geometric-stiffness terms of `model` (prepared: supports complete but for the free rigid
/// motions `rigid`) for the mode shapes `nodal_modes` (one vector of all `6 n_nodes` nodal dofs per
/// mode).
pub(crate) fn geometric_stiffness(
    model: &FeModel,
    assembled: &AssembledModel,
    rigid: &Mat<f64>,
    nodal_modes: &[Vec<f64>],
) -> Result<GeometricStiffness, FemError> {
    let mesh = &model.mesh;
    let inertia = unit_inertia_loads(assembled);
    let interface = unit_interface_loads(model, assembled);
    let loads = Mat::from_fn(inertia.nrows(), 12 + interface.ncols(), |i, j| if j < 12 { inertia[(i, j)] } else { interface[(i, j - 12)] });
    let held = pivot_dofs(rigid);
    let displacements = solve_with_extra_supports(assembled, &held, &loads, rigid.ncols())?;
    let m = nodal_modes.len();
    let mut terms: Vec<DMatrix<f64>> = Vec::with_capacity(loads.ncols());
    for case in 0..loads.ncols() {
        let free: Vec<f64> = (0..displacements.nrows()).map(|i| displacements[(i, case)]).collect();
        let u = assembled.dofs.expand(&free);
        let mut g = DMatrix::zeros(m, m);
        for element in &mesh.elements {
            let Some(k_geo) = element_geometric_stiffness(mesh, element, &u)? else { continue };
            let phi = DMatrix::from_fn(6 * element.nodes.len(), m, |r, j| nodal_modes[j][6 * element.nodes[r / 6] + r % 6]);
            g += phi.transpose() * k_geo * phi;
        }
        terms.push((&g + g.transpose()) * 0.5);
    }
    let interface_terms = terms.split_off(12);
    let interface = model
        .interface_nodes
        .iter()
        .zip(interface_terms.chunks(INTERFACE_CASES))
        .map(|(&node, loads)| InterfaceStiffness { node: mesh.nodes[node].label, loads: loads.to_vec() })
        .collect();
    let centrifugal = terms.split_off(6);
    let angular_acceleration = terms.split_off(3);
    Ok(GeometricStiffness { acceleration: terms, angular_acceleration, centrifugal, interface })
}

/// The geometric stiffness (`6n × 6n`, body frame, the element's nodes in order) of `element` under
/// the stress of the nodal displacements `u` (all `6 n_nodes` dofs); `None` for a beam without axial
/// force.
fn element_geometric_stiffness(mesh: &Mesh, element: &Element, u: &[f64]) -> Result<Option<DMatrix<f64>>, FemError> {
    let element_error = |source| FemError::Element { label: element.label, source };
    let points: Vec<Vector3<f64>> = element.nodes.iter().map(|&n| mesh.nodes[n].position).collect();
    let translations: Vec<Vector3<f64>> = element.nodes.iter().map(|&n| Vector3::new(u[6 * n], u[6 * n + 1], u[6 * n + 2])).collect();
    let k_geo = match element.kind {
        ElementKind::Beam { section } => {
            let section = &mesh.beam_sections[section];
            let material = &mesh.materials[section.material];
            let force = axial_force(&points[0], &points[1], section, material, &translations[0], &translations[1]).map_err(element_error)?;
            if force == 0.0 {
                return Ok(None);
            }
            beam_geometric_stiffness(&points[0], &points[1], section, force)
        }
        ElementKind::Shell { section } => {
            let section = &mesh.shell_sections[section];
            shell_geometric_stiffness(&points, section, &mesh.materials[section.material], &translations)
        }
        ElementKind::Solid { section, formulation } => {
            let material = &mesh.materials[mesh.solid_sections[section].material];
            solid_geometric_stiffness(&points, formulation, material, &translations)
        }
    };
    k_geo.map(Some).map_err(element_error)
}

/// The unit loads at the interface nodes over the free dofs (`n_free × 6 n_interface`, forces then
/// moments at each node): a load on a dependent dof (a rigid coupling) goes to its reference node's
/// equations; one on a held or absent dof is left out (it stresses nothing).
fn unit_interface_loads(model: &FeModel, assembled: &AssembledModel) -> Mat<f64> {
    let dofs = &assembled.dofs;
    let mut loads = Mat::zeros(dofs.n_free(), INTERFACE_CASES * model.interface_nodes.len());
    for (k, &node) in model.interface_nodes.iter().enumerate() {
        for d in 0..INTERFACE_CASES {
            for (e, c) in dofs.terms(6 * node + d) {
                loads[(e, INTERFACE_CASES * k + d)] += c;
            }
        }
    }
    loads
}

/// The twelve unit inertia loads over the free dofs (`n_free × 12`, module documentation), summed
/// from the mass points: a point's load `[f; τ]` goes to its nodes as `Gᵀ [f; τ]`.
fn unit_inertia_loads(assembled: &AssembledModel) -> Mat<f64> {
    let dofs = &assembled.dofs;
    let mut loads = Mat::zeros(dofs.n_free(), 12);
    let e = |j: usize| Vector3::ith(j, 1.0);
    for point in &assembled.mass_points {
        let s = point.position;
        let mut cases: Vec<(Vector3<f64>, Vector3<f64>)> = Vec::with_capacity(12);
        for j in 0..3 {
            cases.push((-point.mass * e(j), Vector3::zeros()));
        }
        for j in 0..3 {
            cases.push((-point.mass * e(j).cross(&s), -point.rotary_inertia * e(j)));
        }
        for (j, k) in CENTRIFUGAL_PAIRS {
            let outer: Matrix3<f64> = if j == k { e(j) * e(j).transpose() - Matrix3::identity() } else { e(j) * e(k).transpose() + e(k) * e(j).transpose() };
            cases.push((-point.mass * outer * s, Vector3::zeros()));
        }
        for (case, (force, torque)) in cases.iter().enumerate() {
            let load = Vector6::new(force.x, force.y, force.z, torque.x, torque.y, torque.z);
            for (node, block) in &point.interpolation {
                let nodal = block.transpose() * load;
                for d in 0..6 {
                    if let Some(eq) = dofs.equation_of(6 * node + d) {
                        loads[(eq, case)] += nodal[d];
                    }
                }
            }
        }
    }
    loads
}
