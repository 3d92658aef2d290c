//! `[[support]]`: degrees of freedom held at zero in the mode analysis, at one node or at every node
//! of a set.

use toml::Spanned;

use flexmb_fem::{Dof, DofSet, Support};

use super::build::Builder;
use super::node_ref::resolve_nodes;
use super::schema::SupportSection;
use super::value::DofsInput;
use crate::model_file::key_path::KeyPath;
use crate::model_file::suggest::did_you_mean;
use crate::model_file::ModelFileError;

pub(crate) fn add_supports(b: &mut Builder, tables: &[Spanned<SupportSection>]) -> Result<(), ModelFileError> {
    b.support_origins.resize(b.model.supports.len(), None);
    for (k, table) in tables.iter().enumerate() {
        let element = KeyPath::root().key("support").index(k);
        let s = table.get_ref();
        let at_key = element.key("at");
        let nodes = resolve_nodes(&b.ctx, &b.model.mesh, &s.at, &at_key)?;
        if nodes.is_empty() {
            return Err(b.ctx.invalid(&s.at.span(), &at_key, "this node set holds no nodes"));
        }
        let dofs = dof_set(b, &s.dofs, &element.key("dofs"))?;
        for node in nodes {
            b.model.supports.push(Support { node, dofs });
            b.support_origins.push(Some((element.clone(), table.span())));
        }
    }
    Ok(())
}

/// `"all"`, `"translations"`, `"rotations"` or a list of `x y z rx ry rz`.
fn dof_set(b: &Builder, dofs: &Spanned<DofsInput>, key: &KeyPath) -> Result<DofSet, ModelFileError> {
    match dofs.get_ref() {
        DofsInput::Keyword(word) => b.ctx.keyword(
            &Spanned::new(dofs.span(), word.clone()),
            key,
            "set of degrees of freedom",
            &[("all", DofSet::ALL), ("translations", DofSet::TRANSLATIONS), ("rotations", DofSet::ROTATIONS)],
        ),
        DofsInput::List(names) => {
            if names.is_empty() {
                return Err(b.ctx.invalid(
                    &dofs.span(),
                    key,
                    r#"expected at least one degree of freedom ("x", "y", "z", "rx", "ry", "rz")"#,
                ));
            }
            let mut set = DofSet::EMPTY;
            for (k, name) in names.iter().enumerate() {
                let Some(dof) = Dof::parse(name.get_ref()) else {
                    let hint = did_you_mean(name.get_ref(), Dof::ALL.iter().map(|d| d.name()));
                    return Err(b.ctx.invalid(
                        &name.span(),
                        &key.index(k),
                        format!(
                            "unknown degree of freedom `{}`{hint}; expected one of `x`, `y`, `z` (translations), \
                             `rx`, `ry`, `rz` (rotations)",
                            name.get_ref()
                        ),
                    ));
                };
                set = set.with(dof);
            }
            Ok(set)
        }
    }
}
