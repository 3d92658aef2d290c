//! `[fe_model]` (name and modelling options) and `[modes]` (defaults of `flexmb modes`).

use std::str::FromStr;

use toml::Spanned;

use flexmb_fem::reduction::{Basis, ModeSet};
use flexmb_fem::{MassModel, ModelOptions};
use flexmb_fem::input::Quantity;

use super::build::Builder;
use super::schema::{FeModelSection, ModesSection};
use super::ModesDefaults;
use crate::model_file::key_path::KeyPath;
use crate::model_file::ModelFileError;

fn section_key() -> KeyPath {
    KeyPath::root().key("fe_model")
}

/// The model's name: `[fe_model] name`, or the file's stem.
pub(crate) fn model_name(
    b: &Builder,
    section: Option<&FeModelSection>,
    default_name: &str,
) -> Result<String, ModelFileError> {
    match section.and_then(|s| s.name.as_ref()) {
        Some(name) if name.get_ref().trim().is_empty() => {
            Err(b.ctx.invalid(&name.span(), &section_key().key("name"), "the model name must not be empty"))
        }
        Some(name) => Ok(name.get_ref().clone()),
        None => Ok(default_name.to_string()),
    }
}

/// The modelling options: those of `[fe_model]` over `base` (the mesh file's, or the defaults).
pub(crate) fn model_options(
    b: &Builder,
    section: Option<&FeModelSection>,
    base: ModelOptions,
) -> Result<ModelOptions, ModelFileError> {
    let mut options = base;
    let Some(section) = section else { return Ok(options) };
    if let Some(mass) = &section.mass {
        options.mass = Some(b.ctx.keyword(
            mass,
            &section_key().key("mass"),
            "mass model",
            &[MassModel::Lumped, MassModel::Consistent].map(|m| (m.name(), m)),
        )?);
    }
    if let Some(rotary) = &section.rotary_inertia {
        options.rotary_inertia = *rotary.get_ref();
    }
    if let Some(drilling) = &section.drilling_stiffness {
        options.drilling_stiffness =
            b.non_negative(drilling, &section_key().key("drilling_stiffness"), "the drilling stiffness factor", Quantity::Factor)?;
    }
    Ok(options)
}

/// `[modes]`: the mode set, basis and modal stresses `flexmb modes` uses unless told otherwise.
pub(crate) fn modes_defaults(
    b: &Builder,
    section: Option<&Spanned<ModesSection>>,
) -> Result<ModesDefaults, ModelFileError> {
    let Some(section) = section else { return Ok(ModesDefaults::default()) };
    let table = KeyPath::root().key("modes");
    let section = section.get_ref();
    let mode_set = match &section.set {
        Some(text) => {
            let key = table.key("set");
            let set =
                ModeSet::from_str(text.get_ref()).map_err(|e| b.ctx.invalid(&text.span(), &key, e.to_string()))?;
            let loads = b.model.static_loads.len();
            if set.statics() > loads {
                return Err(b.ctx.invalid(
                    &text.span(),
                    &key,
                    format!(
                        "mode set `{set}` asks for {} static correction mode(s) but the model has {loads} static \
                         load(s) ([[static_load]] tables)",
                        set.statics()
                    ),
                ));
            }
            Some(set)
        }
        None => None,
    };
    let basis = match &section.basis {
        Some(word) => Some(b.ctx.keyword(
            word,
            &table.key("basis"),
            "basis",
            &[("orthonormal", Basis::Orthonormal), ("raw", Basis::Raw)],
        )?),
        None => None,
    };
    Ok(ModesDefaults { mode_set, basis, stresses: section.stresses.as_ref().map(|s| *s.get_ref()) })
}
