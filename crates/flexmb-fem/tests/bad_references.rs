//! A model that refers to a node, material or section it does not have, or a generator asked for
//! nothing, is refused with an error that names the part; nothing panics.

mod support;

use flexmb_fem::assembly::assemble;
use flexmb_fem::element::{element_matrices, ElementError};
use flexmb_fem::mesh::ShellShape;
use flexmb_fem::modes::{vibration_modes, EigenSettings};
use flexmb_fem::reduction::{reduce, Basis, ModeSet, ReductionSettings};
use flexmb_fem::{DofSet, Element, ElementKind, FemError, Support};
use nalgebra::Vector3;
use support::{beam, square_section};

#[test]
fn an_element_on_a_node_the_mesh_lacks_is_refused() {
    let mut model = beam(1.0, 4, square_section(0.01));
    model.mesh.elements.push(Element { label: 99, kind: ElementKind::Beam { section: 0 }, nodes: vec![4, 7] });
    let error = assemble(&model).unwrap_err();
    assert_eq!(error, FemError::UnknownIndex { part: "element 99".into(), kind: "node", index: 7, count: 5 });
    assert_eq!(error.to_string(), "element 99: node index 7 is beyond the model's 5");
    let alone = element_matrices(&model.mesh, model.mesh.elements.last().unwrap(), &model.options).unwrap_err();
    assert_eq!(alone, ElementError::UnknownIndex { kind: "node", index: 7, count: 5 });
}

#[test]
fn a_section_or_material_the_mesh_lacks_is_refused() {
    let mut model = beam(1.0, 4, square_section(0.01));
    model.mesh.elements[2].kind = ElementKind::Shell { section: 0 };
    assert_eq!(
        assemble(&model).unwrap_err().to_string(),
        "element 3: shell section index 0 is beyond the model's 0"
    );
    let mut model = beam(1.0, 4, square_section(0.01));
    model.mesh.beam_sections[0].material = 2;
    let error = vibration_modes(&model, 2, &EigenSettings::default()).unwrap_err();
    assert_eq!(error.to_string(), "beam section 'square': material index 2 is beyond the model's 1");
}

#[test]
fn supports_and_static_loads_off_the_mesh_are_refused() {
    let mut model = beam(1.0, 4, square_section(0.01));
    model.supports.push(Support { node: 5, dofs: DofSet::ALL });
    assert_eq!(assemble(&model).unwrap_err().to_string(), "a support: node index 5 is beyond the model's 5");
    let mut model = beam(1.0, 4, square_section(0.01));
    model.static_loads.push(support::force("pull", 12, [1.0, 0.0, 0.0]));
    let settings = ReductionSettings {
        mode_set: "2N1S".parse::<ModeSet>().unwrap(),
        basis: Basis::Orthonormal,
        eigen: EigenSettings::default(),
    };
    assert_eq!(
        reduce(&model, "rod", &settings).unwrap_err().to_string(),
        "static load 'pull': node index 12 is beyond the model's 5"
    );
}

#[test]
fn generators_asked_for_nothing_are_refused_and_leave_the_mesh_alone() {
    let mut model = beam(1.0, 4, square_section(0.01));
    let before = model.mesh.clone();
    let error = model.mesh.add_beam_line(Vector3::zeros(), Vector3::new(0.0, 1.0, 0.0), 0, 0).unwrap_err();
    assert_eq!(error.to_string(), "beam line: a line needs at least one element");
    let edge = Vector3::new(0.0, 1.0, 0.0);
    let error = model
        .mesh
        .add_rectangular_plate(Vector3::zeros(), edge, Vector3::new(0.0, 0.0, 1.0), 3, 0, 0, ShellShape::Triangle)
        .unwrap_err();
    assert_eq!(error, FemError::Generator { generator: "plate", problem: "a plate needs at least one cell each way" });
    assert_eq!(model.mesh, before);
}

#[test]
fn inertia_invariants_of_inputs_that_disagree_in_size_are_refused() {
    use flexmb_fem::reduction::InertiaInvariants;
    use nalgebra::{DMatrix, Matrix3};
    let positions = [Vector3::zeros(), Vector3::x()];
    let rotary = [Matrix3::zeros(); 2];
    let shapes = [DMatrix::zeros(3, 2), DMatrix::zeros(3, 2)];
    let error = InertiaInvariants::new(&positions, &[1.0], &rotary, &shapes, &shapes, 2).unwrap_err();
    assert_eq!(error.to_string(), "inertia invariants: 1 masses for 2 points");
    let error = InertiaInvariants::new(&positions, &[1.0, 1.0], &rotary, &shapes, &shapes, 3).unwrap_err();
    assert_eq!(error.to_string(), "inertia invariants: point 0: mode matrices (3, 2) and (3, 2), expected (3, 3)");
    let invariants = InertiaInvariants::new(&positions, &[1.0, 2.0], &rotary, &shapes, &shapes, 2).unwrap();
    assert_eq!(invariants.mass, 3.0);
}
