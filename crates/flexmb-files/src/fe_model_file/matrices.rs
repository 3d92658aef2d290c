//! `[matrices]`: a body from the stiffness and mass matrices another FE program exported, with the
//! coordinates of their nodes and the map of their rows to the nodes' degrees of freedom (the formats
//! in [`crate::exported_matrices`]). The nodes (and, from a deck, its node sets) become the model's;
//! supports, static loads, point masses and mode sets then work as for any FE model.

use std::collections::{BTreeSet, HashMap};
use std::path::Path;

use nalgebra::Vector3;
use toml::Spanned;

use flexmb_fem::inp::read_inp_nodes;
use flexmb_fem::mesh::ImportedMatrices;

use super::build::Builder;
use super::mesh_file::{inp_error, mesh_path};
use super::schema::MatricesSection;
use crate::exported_matrices::{
    parse_abaqus, parse_ansys_mapping, parse_coordinate, parse_dof_file, parse_node_list, read_text, upper_triangle,
    CoordinateLayout, MatrixEntries, MatrixFileError, MatrixFormat, RowDof,
};
use crate::model_file::key_path::KeyPath;
use crate::model_file::schema::Name;
use crate::model_file::{ErrorKind, ModelFileError};

fn file_error(e: MatrixFileError) -> ModelFileError {
    ModelFileError { kind: ErrorKind::Invalid, file: e.file, line: e.line, key_path: String::new(), message: e.message }
}

/// Reads the matrices `table` names (paths relative to `base_dir`) into the builder's empty model.
pub(crate) fn add_matrices(
    b: &mut Builder,
    table: &Spanned<MatricesSection>,
    mesh: Option<&Name>,
    base_dir: &Path,
) -> Result<(), ModelFileError> {
    let key = KeyPath::root().key("matrices");
    let t = table.get_ref();
    if let Some(mesh) = mesh {
        return Err(b.ctx.invalid(
            &mesh.span(),
            &KeyPath::root().key("fe_model").key("mesh"),
            "a mesh file and [matrices] do not go together: the matrices hold the deck's elements; give the deck they \
             came from as [matrices] nodes, which reads its nodes and node sets only",
        ));
    }
    let format = MatrixFormat::parse(t.format.get_ref()).ok_or_else(|| {
        b.ctx.invalid(
            &t.format.span(),
            &key.key("format"),
            format!("`{}` is not a supported matrix format; supported: {}", t.format.get_ref(), MatrixFormat::supported()),
        )
    })?;
    let path_of = |name: &Name, what: &str| -> Result<std::path::PathBuf, ModelFileError> {
        if name.get_ref().trim().is_empty() {
            return Err(b.ctx.invalid(&name.span(), &key.key(what), format!("expected the path of the {what} file, got an empty string")));
        }
        Ok(mesh_path(base_dir, name.get_ref()))
    };
    let read = |name: &Name, what: &str| -> Result<(String, String), ModelFileError> {
        let path = path_of(name, what)?;
        let shown = path.display().to_string();
        let text = read_text(&path, &format!("{what} file")).map_err(|e| {
            b.ctx.invalid(&name.span(), &key.key(what), format!("cannot read the {what} file `{shown}`: {}", e.message))
        })?;
        Ok((shown, text))
    };
    // The map of the rows to nodes and dofs.
    let dof_rows: Option<(String, Vec<RowDof>)> = match (&t.dofs, format.needs_dof_file()) {
        (Some(dofs), true) => {
            let (shown, text) = read(dofs, "dofs")?;
            let rows = match format {
                MatrixFormat::Ansys => parse_ansys_mapping(&text, &shown),
                _ => parse_dof_file(&text, &shown),
            }
            .map_err(file_error)?;
            Some((shown, rows))
        }
        (None, true) => {
            return Err(b.ctx.invalid(
                &table.span(),
                &key,
                format!("format `{}` needs `dofs`, the file that maps the matrices' rows to nodes and dofs", format.name()),
            ))
        }
        (Some(dofs), false) => {
            return Err(b.ctx.invalid(
                &dofs.span(),
                &key.key("dofs"),
                "the abaqus format names each row's node and dof in the matrix files: remove `dofs`",
            ))
        }
        (None, false) => None,
    };
    let matrix = |name: &Name, what: &str| -> Result<MatrixEntries, ModelFileError> {
        let (shown, text) = read(name, what)?;
        match format {
            MatrixFormat::Calculix => parse_coordinate(&text, &shown, CoordinateLayout::Entries),
            MatrixFormat::MatrixMarket => parse_coordinate(&text, &shown, CoordinateLayout::MatrixMarket),
            MatrixFormat::Ansys => parse_coordinate(&text, &shown, CoordinateLayout::SizeLine),
            MatrixFormat::Abaqus => parse_abaqus(&text, &shown),
        }
        .map_err(file_error)
    };
    let stiffness = matrix(&t.stiffness, "stiffness")?;
    let mass = matrix(&t.mass, "mass")?;
    let rows_of = |m: &MatrixEntries| -> (String, Vec<RowDof>) {
        match &dof_rows {
            Some((file, rows)) => (file.clone(), rows.clone()),
            None => (m.file.clone(), m.rows.clone()),
        }
    };
    let (stiffness_rows_file, stiffness_rows) = rows_of(&stiffness);
    let (mass_rows_file, mass_rows) = rows_of(&mass);
    let used: BTreeSet<u64> = stiffness_rows.iter().chain(&mass_rows).map(|(label, _)| *label).collect();
    add_nodes(b, &t.nodes, &key, base_dir, &used)?;
    let node_index: HashMap<u64, usize> = b.model.mesh.nodes.iter().enumerate().map(|(i, n)| (n.label, i)).collect();
    let k = upper_triangle(&stiffness, &stiffness_rows, &node_index, &stiffness_rows_file).map_err(file_error)?;
    let m = upper_triangle(&mass, &mass_rows, &node_index, &mass_rows_file).map_err(file_error)?;
    b.model.mesh.imported = Some(ImportedMatrices { origin: stiffness.file.clone(), stiffness: k, mass: m });
    for name in [Some(&t.stiffness), Some(&t.mass), t.dofs.as_ref(), Some(&t.nodes)].into_iter().flatten() {
        b.sources.push(mesh_path(base_dir, name.get_ref()));
    }
    Ok(())
}

/// The nodes of the matrices (labels in `used`) from `nodes`: an `.inp` deck's `*NODE` and `*NSET`
/// lines, or a node list (`NODE X Y Z`). Nodes the matrices do not mention are left out.
fn add_nodes(b: &mut Builder, nodes: &Name, key: &KeyPath, base_dir: &Path, used: &BTreeSet<u64>) -> Result<(), ModelFileError> {
    let path = mesh_path(base_dir, nodes.get_ref());
    let shown = path.display().to_string();
    let unreadable = |message: String| b.ctx.invalid(&nodes.span(), &key.key("nodes"), format!("cannot read the nodes file `{shown}`: {message}"));
    type Sets = Vec<(String, Vec<u64>)>;
    let (listed, sets): (Vec<(u64, Vector3<f64>)>, Sets) =
        if path.extension().is_some_and(|e| e.eq_ignore_ascii_case("inp")) {
            let inp = read_inp_nodes(&path).map_err(|e| match e {
                flexmb_fem::inp::InpError::Read { message, .. } => unreadable(message),
                other => inp_error(&other),
            })?;
            let mesh = inp.model.mesh;
            let sets = mesh.node_sets.iter().map(|(name, members)| (name.clone(), members.iter().map(|&i| mesh.nodes[i].label).collect())).collect();
            (mesh.nodes.into_iter().map(|n| (n.label, n.position)).collect(), sets)
        } else {
            let text = read_text(&path, "nodes file").map_err(|e| unreadable(e.message))?;
            let list = parse_node_list(&text, &shown).map_err(file_error)?;
            (list.into_iter().map(|(label, x)| (label, Vector3::from(x))).collect(), Vec::new())
        };
    let mesh = &mut b.model.mesh;
    let mut index: HashMap<u64, usize> = HashMap::new();
    for (label, position) in listed {
        if used.contains(&label) {
            index.insert(label, mesh.add_node(label, position));
        }
    }
    if let Some(missing) = used.iter().find(|l| !index.contains_key(l)) {
        return Err(b.ctx.invalid(
            &nodes.span(),
            &key.key("nodes"),
            format!("node {missing} has rows in the matrices but no coordinates in `{shown}`"),
        ));
    }
    for (name, labels) in sets {
        let members: Vec<usize> = labels.iter().filter_map(|l| index.get(l).copied()).collect();
        mesh.node_sets.insert(name, members);
    }
    b.parts.add_from_mesh(&shown, b.model.mesh.node_sets.keys().map(|name| (name.as_str(), 0)));
    Ok(())
}
