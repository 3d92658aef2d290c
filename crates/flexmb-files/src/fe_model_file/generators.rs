//! `[[beam_line]]` and `[[plate]]`: regular meshes generated in file order (interleaved as written),
//! connected to what is already in the mesh through coincident nodes, with node sets named after them.

use toml::Spanned;

use flexmb_fem::mesh::ShellShape;
use flexmb_fem::input::Quantity;

use super::build::{Builder, MAX_COUNT};
use super::format::point;
use super::schema::{BeamLineSection, PlateSection};
use super::sections::check_orientation;
use crate::model_file::key_path::KeyPath;
use crate::model_file::schema::Name;
use crate::model_file::ModelFileError;

/// Below this sine of the angle between its edges, a plate is degenerate.
const PARALLEL_EDGES: f64 = 1e-9;

/// Adds every beam line and plate in the order the tables appear in the file.
pub(crate) fn add_generated(
    b: &mut Builder,
    lines: &[Spanned<BeamLineSection>],
    plates: &[Spanned<PlateSection>],
) -> Result<(), ModelFileError> {
    enum Part<'t> {
        Line(usize, &'t BeamLineSection),
        Plate(usize, &'t PlateSection),
    }
    let mut parts: Vec<(usize, Part)> = lines
        .iter()
        .enumerate()
        .map(|(k, t)| (t.span().start, Part::Line(k, t.get_ref())))
        .chain(plates.iter().enumerate().map(|(k, t)| (t.span().start, Part::Plate(k, t.get_ref()))))
        .collect();
    parts.sort_by_key(|(start, _)| *start);
    for (_, part) in parts {
        match part {
            Part::Line(k, line) => add_beam_line(b, k, line)?,
            Part::Plate(k, plate) => add_plate(b, k, plate)?,
        }
    }
    Ok(())
}

fn add_beam_line(b: &mut Builder, k: usize, line: &BeamLineSection) -> Result<(), ModelFileError> {
    let element = KeyPath::root().key("beam_line").index(k);
    let derived = ["start", "end"];
    if let Some(name) = &line.name {
        check_part_name(b, name, &element, &derived)?;
    }
    let section_key = element.key("section");
    let section = b.beam_sections.resolve(&line.section, &section_key, b.source())?;
    let from = b.ctx.vector_of(&line.from, &element.key("from"), Quantity::Length)?;
    let to = b.ctx.vector_of(&line.to, &element.key("to"), Quantity::Length)?;
    let count = b.count(&line.elements, &element.key("elements"))?;
    let axis = to - from;
    if axis.norm() <= f64::EPSILON * from.norm().max(to.norm()) {
        return Err(b.ctx.invalid(
            &line.to.span(),
            &element.key("to"),
            format!("the line has no length: `from` and `to` are both {}", point(&from)),
        ));
    }
    check_orientation(b, section, &axis, &line.section.span(), &section_key, "this line")?;
    let nodes = b.model.mesh.add_beam_line(from, to, count, section).map_err(|e| {
        b.ctx.invalid(&line.elements.span(), &element.key("elements"), e.to_string())
    })?;
    if let Some(name) = &line.name {
        let sets = &mut b.model.mesh.node_sets;
        let text = name.get_ref();
        sets.insert(format!("{text}.start"), vec![nodes[0]]);
        sets.insert(format!("{text}.end"), vec![nodes[count]]);
        sets.insert(text.clone(), nodes);
        b.parts.define(name, &element, k);
    }
    Ok(())
}

fn add_plate(b: &mut Builder, k: usize, plate: &PlateSection) -> Result<(), ModelFileError> {
    let element = KeyPath::root().key("plate").index(k);
    let derived = ["boundary"];
    if let Some(name) = &plate.name {
        check_part_name(b, name, &element, &derived)?;
    }
    let section = b.shell_sections.resolve(&plate.section, &element.key("section"), b.source())?;
    let corner = b.ctx.vector_of(&plate.corner, &element.key("corner"), Quantity::Length)?;
    let edge_a = b.ctx.vector_of(&plate.edge_a, &element.key("edge_a"), Quantity::Length)?;
    let edge_b_key = element.key("edge_b");
    let edge_b = b.ctx.vector_of(&plate.edge_b, &edge_b_key, Quantity::Length)?;
    let counts_key = element.key("elements");
    let counts = plate.elements.get_ref();
    if counts.len() != 2 {
        return Err(b.ctx.invalid(
            &plate.elements.span(),
            &counts_key,
            format!(
                "expected the numbers of elements along edge_a and edge_b, [na, nb], got {} number(s)",
                counts.len()
            ),
        ));
    }
    let na = b.count(&counts[0], &counts_key.index(0))?;
    let nb = b.count(&counts[1], &counts_key.index(1))?;
    if (na * nb) as f64 > MAX_COUNT {
        return Err(b.ctx.invalid(
            &plate.elements.span(),
            &counts_key,
            format!("a plate of {na} × {nb} = {} elements is more than {MAX_COUNT:e}", na * nb),
        ));
    }
    if edge_a.cross(&edge_b).norm() <= PARALLEL_EDGES * edge_a.norm() * edge_b.norm()
        || edge_a.norm() == 0.0
        || edge_b.norm() == 0.0
    {
        return Err(b.ctx.invalid(
            &plate.edge_b.span(),
            &edge_b_key,
            format!(
                "the plate has no area: edge_a {} and edge_b {} must be non-zero and not parallel",
                point(&edge_a),
                point(&edge_b)
            ),
        ));
    }
    let shape = match &plate.shape {
        Some(word) => b.ctx.keyword(
            word,
            &element.key("shape"),
            "plate element shape",
            &[("quadrilateral", ShellShape::Quadrilateral), ("triangle", ShellShape::Triangle)],
        )?,
        None => ShellShape::Quadrilateral,
    };
    let grid = b
        .model
        .mesh
        .add_rectangular_plate(corner, edge_a, edge_b, na, nb, section, shape)
        .map_err(|e| b.ctx.invalid(&plate.elements.span(), &counts_key, e.to_string()))?;
    if let Some(name) = &plate.name {
        let boundary: Vec<usize> = grid
            .iter()
            .enumerate()
            .flat_map(|(i, row)| {
                row.iter().enumerate().filter(move |(j, _)| i == 0 || i == na || *j == 0 || *j == nb).map(|(_, &n)| n)
            })
            .collect();
        let all: Vec<usize> = grid.into_iter().flatten().collect();
        let sets = &mut b.model.mesh.node_sets;
        sets.insert(format!("{}.boundary", name.get_ref()), boundary);
        sets.insert(name.get_ref().clone(), all);
        b.parts.define(name, &element, k);
    }
    Ok(())
}

/// A part's name names node sets: it must be new, and neither it nor its derived set names
/// (`name.start`, …) may be taken.
fn check_part_name(b: &Builder, name: &Name, element: &KeyPath, derived: &[&str]) -> Result<(), ModelFileError> {
    b.parts.check_new(name, element, b.source())?;
    let text = name.get_ref();
    let key = element.key("name");
    if text.contains('.') {
        return Err(b.ctx.invalid(
            &name.span(),
            &key,
            format!("a part name must not contain `.`, which separates the node sets derived from it (`{text}`)"),
        ));
    }
    for suffix in derived {
        let set = format!("{text}.{suffix}");
        if b.model.mesh.node_sets.contains_key(&set) {
            return Err(b.ctx.invalid(
                &name.span(),
                &key,
                format!("the node set `{set}` this name defines already exists in the mesh file"),
            ));
        }
    }
    Ok(())
}
