//! `[[static_load]]`: the unit loads of the static correction modes, a force along a direction or a
//! torque about an axis at one node, which must act on free degrees of freedom.

use toml::Spanned;

use flexmb_fem::{Dof, StaticLoad, StaticLoadKind};

use super::build::Builder;
use super::node_ref::resolve_node;
use super::schema::StaticLoadSection;
use crate::model_file::key_path::KeyPath;
use crate::model_file::{ErrorKind, ModelFileError};

/// Components of a unit load below this are zero (the static correction modes' own rule).
const ZERO_COMPONENT: f64 = 1e-14;

pub(crate) fn add_static_loads(b: &mut Builder, tables: &[Spanned<StaticLoadSection>]) -> Result<(), ModelFileError> {
    for (k, table) in tables.iter().enumerate() {
        let element = KeyPath::root().key("static_load").index(k);
        let s = table.get_ref();
        b.static_loads.check_new(&s.name, &element, b.source())?;
        let node = resolve_node(&b.ctx, &b.model.mesh, &s.at, &element.key("at"), "a static load")?;
        let (vector, name, first) = match (&s.force, &s.torque) {
            (Some(force), None) => (force, "force", 0),
            (None, Some(torque)) => (torque, "torque", 3),
            (Some(_), Some(torque)) => {
                return Err(b.ctx.invalid(
                    &torque.span(),
                    &element.key("torque"),
                    "a static load is either a `force` or a `torque`, not both: write two [[static_load]] tables",
                ))
            }
            (None, None) => {
                return Err(b.source().error(
                    ErrorKind::Schema,
                    &table.span(),
                    &element,
                    "a static load needs `force` (a direction) or `torque` (an axis)",
                ))
            }
        };
        let key = element.key(name);
        let direction = b.ctx.vector(vector, &key)?;
        if direction.norm() == 0.0 {
            return Err(b.ctx.invalid(&vector.span(), &key, format!("the {name} direction must not be zero")));
        }
        let unit = direction.normalize();
        for c in (0..3).filter(|&c| unit[c].abs() >= ZERO_COMPONENT) {
            let dof = Dof::ALL[first + c];
            let held = b.model.supports.iter().enumerate().find(|(_, s)| s.node == node && s.dofs.contains(dof));
            if let Some((index, _)) = held {
                let by = match b.support_origins.get(index).cloned().flatten() {
                    Some((table, span)) => format!("{table} (line {})", b.source().line(span.start)),
                    None => format!("a *BOUNDARY of the mesh file `{}`", b.mesh_file.as_deref().unwrap_or("")),
                };
                let label = b.model.mesh.nodes[node].label;
                return Err(b.ctx.invalid(
                    &vector.span(),
                    &key,
                    format!(
                        "the {name} acts on dof {} of node {label}, which {by} supports: a static correction load must \
                         act on free degrees of freedom",
                        dof.name()
                    ),
                ));
            }
        }
        let kind = if first == 0 { StaticLoadKind::Force(unit) } else { StaticLoadKind::Torque(unit) };
        b.model.static_loads.push(StaticLoad { name: s.name.get_ref().clone(), node, kind });
        b.static_loads.define(&s.name, &element, b.model.static_loads.len() - 1);
    }
    Ok(())
}
