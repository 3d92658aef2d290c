//! `[[beam_section]]` (explicit A, Iy, Iz, J or a shape with its dimensions) and `[[shell_section]]`,
//! and the check that a beam's orientation vector is not along the beam.

use std::ops::Range;

use nalgebra::Vector3;
use toml::Spanned;

use flexmb_fem::inp::sections::{self as shapes, SectionProperties};
use flexmb_fem::{BeamSection, ShellSection};
use flexmb_fem::input::Quantity;

use super::build::Builder;
use super::format::point;
use super::schema::{BeamSectionSection, ShellSectionSection};
use crate::model_file::key_path::KeyPath;
use crate::model_file::schema::span_of;
use crate::model_file::{ErrorKind, ModelFileError};

/// Below this sine of the angle between a beam and its section's orientation vector, the two are
/// parallel (the element's own criterion).
const PARALLEL: f64 = 1e-6;

#[derive(Clone, Copy, PartialEq)]
enum Shape {
    Rectangle,
    Circle,
    Tube,
}

pub(crate) fn add_beam_sections(b: &mut Builder, tables: &[Spanned<BeamSectionSection>]) -> Result<(), ModelFileError> {
    for (k, table) in tables.iter().enumerate() {
        let element = KeyPath::root().key("beam_section").index(k);
        let s = table.get_ref();
        b.beam_sections.check_new(&s.name, &element, b.source())?;
        let material = b.materials.resolve(&s.material, &element.key("material"), b.source())?;
        let orientation_key = element.key("orientation");
        let orientation = b.ctx.vector(&s.orientation, &orientation_key)?;
        if orientation.norm() == 0.0 {
            return Err(b.ctx.invalid(
                &s.orientation.span(),
                &orientation_key,
                "the orientation (the direction of the section's local y axis) must not be zero",
            ));
        }
        let shear_coefficient = s
            .shear_coefficient
            .as_ref()
            .map(|k| b.positive(k, &element.key("shear_coefficient"), "the shear coefficient", Quantity::Factor))
            .transpose()?;
        let properties = section_properties(b, s, &element, &table.span())?;
        let mesh = &mut b.model.mesh;
        mesh.beam_sections.push(BeamSection {
            name: s.name.get_ref().clone(),
            material,
            area: properties.area,
            iy: properties.iy,
            iz: properties.iz,
            torsion_constant: properties.torsion_constant,
            orientation,
            shear_coefficient,
            outline: properties.outline,
        });
        let index = mesh.beam_sections.len() - 1;
        b.beam_sections.define(&s.name, &element, index);
        b.orientation_lines.insert(index, b.source().line(s.orientation.span().start));
    }
    Ok(())
}

/// A, Iy, Iz, J: given, or computed from the shape.
fn section_properties(
    b: &Builder,
    s: &BeamSectionSection,
    element: &KeyPath,
    span: &Range<usize>,
) -> Result<SectionProperties, ModelFileError> {
    let present = [
        ("A", span_of(&s.area)),
        ("Iy", span_of(&s.iy)),
        ("Iz", span_of(&s.iz)),
        ("J", span_of(&s.torsion_constant)),
        ("width", span_of(&s.width)),
        ("height", span_of(&s.height)),
        ("radius", span_of(&s.radius)),
        ("thickness", span_of(&s.thickness)),
    ];
    let Some(shape_name) = &s.shape else {
        if present.iter().all(|(_, span)| span.is_none()) {
            return Err(b.source().error(
                ErrorKind::Schema,
                span,
                element,
                "a beam section needs either its properties `A`, `Iy`, `Iz` and `J`, or a `shape` (\"rectangle\", \
                 \"circle\" or \"tube\") with its dimensions",
            ));
        }
        let description = "a beam section without `shape`";
        b.ctx.reject_unused_keys(element, description, &present, &["A", "Iy", "Iz", "J"])?;
        let value = |number, name: &str, what: &str, quantity| {
            let given = b.ctx.required(number, element, span, name, description)?;
            b.positive(given, &element.key(name), what, quantity)
        };
        return Ok(SectionProperties {
            area: value(&s.area, "A", "the area A", Quantity::Area)?,
            iy: value(&s.iy, "Iy", "the second moment of area Iy", Quantity::SecondMoment)?,
            iz: value(&s.iz, "Iz", "the second moment of area Iz", Quantity::SecondMoment)?,
            torsion_constant: value(&s.torsion_constant, "J", "the torsion constant J", Quantity::SecondMoment)?,
            outline: flexmb_fem::SectionOutline::Equivalent,
        });
    };
    let shape_key = element.key("shape");
    let shape = b.ctx.keyword(
        shape_name,
        &shape_key,
        "section shape",
        &[("rectangle", Shape::Rectangle), ("circle", Shape::Circle), ("tube", Shape::Tube)],
    )?;
    let (description, keys): (&str, &[&str]) = match shape {
        Shape::Rectangle => ("a rectangle section", &["width", "height"]),
        Shape::Circle => ("a circle section", &["radius"]),
        Shape::Tube => ("a tube section", &["radius", "thickness"]),
    };
    b.ctx.reject_unused_keys(element, description, &present, keys)?;
    let dimension = |number, name: &str| {
        let given = b.ctx.required(number, element, span, name, description)?;
        b.positive(given, &element.key(name), &format!("the {name}"), Quantity::Length)
    };
    let properties = match shape {
        Shape::Rectangle => shapes::rect(dimension(&s.width, "width")?, dimension(&s.height, "height")?),
        Shape::Circle => shapes::circ(dimension(&s.radius, "radius")?),
        Shape::Tube => {
            let radius = dimension(&s.radius, "radius")?;
            let thickness = dimension(&s.thickness, "thickness")?;
            if thickness > radius {
                let given = s.thickness.as_ref().map_or(span.clone(), Spanned::span);
                return Err(b.ctx.invalid(
                    &given,
                    &element.key("thickness"),
                    format!("the wall thickness {thickness} exceeds the outer radius {radius}"),
                ));
            }
            shapes::pipe(radius, thickness)
        }
    };
    // The dimensions are checked positive above, so the formulas accept them.
    properties.map_err(|message| b.ctx.invalid(&shape_name.span(), &shape_key, message.to_string()))
}

pub(crate) fn add_shell_sections(
    b: &mut Builder,
    tables: &[Spanned<ShellSectionSection>],
) -> Result<(), ModelFileError> {
    for (k, table) in tables.iter().enumerate() {
        let element = KeyPath::root().key("shell_section").index(k);
        let s = table.get_ref();
        b.shell_sections.check_new(&s.name, &element, b.source())?;
        let material = b.materials.resolve(&s.material, &element.key("material"), b.source())?;
        let thickness = b.positive(&s.thickness, &element.key("thickness"), "the thickness", Quantity::Length)?;
        let mesh = &mut b.model.mesh;
        mesh.shell_sections.push(ShellSection { name: s.name.get_ref().clone(), material, thickness });
        let index = mesh.shell_sections.len() - 1;
        b.shell_sections.define(&s.name, &element, index);
    }
    Ok(())
}

/// An error at `span` if beam section `section`'s orientation vector is parallel to `axis`, the axis
/// of `what` (e.g. "this line", "the beam from node 1 to node 2").
pub(crate) fn check_orientation(
    b: &Builder,
    section: usize,
    axis: &Vector3<f64>,
    span: &Range<usize>,
    key: &KeyPath,
    what: &str,
) -> Result<(), ModelFileError> {
    let s = &b.model.mesh.beam_sections[section];
    let o = s.orientation;
    let across = o - axis * (axis.dot(&o) / axis.norm_squared());
    if across.norm() > PARALLEL * o.norm() {
        return Ok(());
    }
    let defined = match (b.beam_sections.definition(&s.name), b.orientation_lines.get(&section)) {
        (Some(d), Some(line)) => format!(" ({}, line {line})", d.element.key("orientation")),
        _ => String::new(),
    };
    Err(b.ctx.invalid(
        span,
        key,
        format!(
            "the orientation {} of beam section `{}`{defined} is parallel to {what}, along {}: the orientation \
             gives the section's local y axis and must not lie along the beam",
            point(&o),
            s.name,
            point(axis)
        ),
    ))
}
