//! `[[mass]]`: concentrated masses, with optional rotary inertia, at single nodes.

use nalgebra::Vector3;
use toml::Spanned;

use flexmb_fem::PointMass;
use flexmb_fem::input::Quantity;

use super::build::Builder;
use super::node_ref::resolve_node;
use super::schema::MassSection;
use crate::model_file::key_path::KeyPath;
use crate::model_file::ModelFileError;

pub(crate) fn add_masses(b: &mut Builder, tables: &[Spanned<MassSection>]) -> Result<(), ModelFileError> {
    for (k, table) in tables.iter().enumerate() {
        let element = KeyPath::root().key("mass").index(k);
        let m = table.get_ref();
        let node = resolve_node(&b.ctx, &b.model.mesh, &m.at, &element.key("at"), "a mass")?;
        let mass = b.non_negative(&m.mass, &element.key("mass"), "the mass", Quantity::Mass)?;
        let rotary_inertia = match &m.rotary_inertia {
            Some(vector) => {
                let key = element.key("rotary_inertia");
                let j = b.ctx.vector_of(vector, &key, Quantity::Inertia)?;
                if let Some(c) = (0..3).find(|&c| j[c] < 0.0) {
                    return Err(b.ctx.invalid(
                        &vector.get_ref()[c].span(),
                        &key.index(c),
                        format!("a moment of inertia must not be negative, got {}", j[c]),
                    ));
                }
                j
            }
            None => Vector3::zeros(),
        };
        b.model.mesh.point_masses.push(PointMass { node, mass, rotary_inertia });
    }
    Ok(())
}
