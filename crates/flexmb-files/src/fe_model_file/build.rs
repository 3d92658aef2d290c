//! From the parsed file to an [`FeModel`]: parameters and options first, then, in this order, the mesh
//! file, materials and sections, nodes, the generators (`[[beam_line]]` and `[[plate]]` in file
//! order), explicit elements, masses, supports and static loads, each checked with the key and line it
//! came from; last the checks of the whole model (elements present, every node connected).

use std::collections::{BTreeMap, BTreeSet};
use std::ops::Range;
use std::path::{Path, PathBuf};

use flexmb_fem::{ElementKind, FeModel};
use flexmb_fem::input::Quantity;

use super::names::Registry;
use super::schema::FeModelFile;
use super::{elements, generators, interfaces, masses, materials, matrices, mesh_file, nodes, options, sections, static_loads, supports};
use super::{LoadedFeModel, ModesDefaults};
use crate::model_file::build::context::Context;
use crate::model_file::build::names::NameTable;
use crate::model_file::key_path::KeyPath;
use crate::model_file::parameters;
use crate::model_file::schema::Number;
use crate::model_file::source::Source;
use crate::model_file::ModelFileError;

/// The most elements a generator may be asked for along one direction.
pub(crate) const MAX_COUNT: f64 = 1e6;

/// The model being built and the names defined so far.
pub(crate) struct Builder<'a> {
    pub ctx: Context<'a>,
    /// The file's name as shown in messages.
    pub file: &'a str,
    pub model: FeModel,
    pub materials: Registry,
    pub beam_sections: Registry,
    pub shell_sections: Registry,
    /// Named beam lines and plates (their node sets), and the mesh file's node sets.
    pub parts: Registry,
    pub static_loads: NameTable<usize>,
    /// The `[[node]]` tables, by label: the node's index, the table's key path and the label's span.
    pub explicit_nodes: BTreeMap<u64, (usize, KeyPath, Range<usize>)>,
    /// For each of `model.supports`, the `[[support]]` table that made it (`None` for the mesh
    /// file's), for messages about loads on supported degrees of freedom.
    pub support_origins: Vec<Option<(KeyPath, Range<usize>)>>,
    /// The line of each `[[beam_section]]`'s orientation, by section index.
    pub orientation_lines: BTreeMap<usize, usize>,
    /// The mesh file's name as shown in messages, if there is one.
    pub mesh_file: Option<String>,
    /// The mesh file and the files it includes.
    pub sources: Vec<PathBuf>,
    pub warnings: Vec<String>,
}

impl<'a> Builder<'a> {
    fn new(ctx: Context<'a>, file: &'a str) -> Self {
        Self {
            ctx,
            file,
            model: FeModel::default(),
            materials: Registry::new("material"),
            beam_sections: Registry::new("beam section"),
            shell_sections: Registry::new("shell section"),
            parts: Registry::new("node set"),
            static_loads: NameTable::new("static load"),
            explicit_nodes: BTreeMap::new(),
            support_origins: Vec::new(),
            orientation_lines: BTreeMap::new(),
            mesh_file: None,
            sources: Vec::new(),
            warnings: Vec::new(),
        }
    }

    pub(crate) fn source(&self) -> &'a Source<'a> {
        self.ctx.source
    }

    /// A positive, finite constant of `quantity`, within its window; `what` names it in the message.
    pub(crate) fn positive(&self, value: &Number, key: &KeyPath, what: &str, q: Quantity) -> Result<f64, ModelFileError> {
        self.signed(value, key, q, |x| x > 0.0, &format!("{what} must be positive"))
    }

    /// A finite constant of `quantity`, within its window, that is zero or positive.
    pub(crate) fn non_negative(&self, value: &Number, key: &KeyPath, what: &str, q: Quantity) -> Result<f64, ModelFileError> {
        self.signed(value, key, q, |x| x >= 0.0, &format!("{what} must not be negative"))
    }

    /// A constant of `quantity` that `accepts`; `rule` says what it must be.
    fn signed(
        &self,
        value: &Number,
        key: &KeyPath,
        quantity: Quantity,
        accepts: fn(f64) -> bool,
        rule: &str,
    ) -> Result<f64, ModelFileError> {
        let x = self.ctx.quantity(value, key, quantity)?;
        if accepts(x) {
            Ok(x)
        } else {
            Err(self.ctx.invalid(&value.span(), key, format!("{rule}, got {x}")))
        }
    }

    /// A number of elements: a whole number from 1 to a million.
    pub(crate) fn count(&self, value: &Number, key: &KeyPath) -> Result<usize, ModelFileError> {
        let x = self.ctx.number(value, key)?;
        if (1.0..=MAX_COUNT).contains(&x) && x.fract() == 0.0 {
            Ok(x as usize)
        } else {
            Err(self.ctx.invalid(
                &value.span(),
                key,
                format!("expected a number of elements: a whole number from 1 to {MAX_COUNT:e}, got {x}"),
            ))
        }
    }
}

/// Builds the model a parsed file describes. `base_dir` is where a relative mesh path starts;
/// `default_name` names the model when `[fe_model]` does not.
pub(crate) fn build<'a>(
    file: &FeModelFile,
    source: &'a Source<'a>,
    file_name: &'a str,
    base_dir: &Path,
    default_name: &str,
) -> Result<LoadedFeModel, ModelFileError> {
    let parameters = parameters::evaluate(&file.parameters, source)?;
    let mut b = Builder::new(Context::new(source, parameters, BTreeSet::new()), file_name);
    let section = file.fe_model.as_ref().map(|s| s.get_ref());
    let name = options::model_name(&b, section, default_name)?;
    if let Some(mesh) = section.and_then(|s| s.mesh.as_ref()) {
        mesh_file::add_mesh(&mut b, mesh, base_dir)?;
    }
    if let Some(table) = &file.matrices {
        matrices::add_matrices(&mut b, table, section.and_then(|s| s.mesh.as_ref()), base_dir)?;
    }
    b.model.options = options::model_options(&b, section, b.model.options)?;
    materials::add_materials(&mut b, &file.material)?;
    sections::add_beam_sections(&mut b, &file.beam_section)?;
    sections::add_shell_sections(&mut b, &file.shell_section)?;
    nodes::add_nodes(&mut b, &file.node)?;
    generators::add_generated(&mut b, &file.beam_line, &file.plate)?;
    elements::add_beams(&mut b, &file.beam)?;
    elements::add_shells(&mut b, &file.shell)?;
    check_elements_present(&b, file)?;
    nodes::check_connected(&b)?;
    masses::add_masses(&mut b, &file.mass)?;
    supports::add_supports(&mut b, &file.support)?;
    static_loads::add_static_loads(&mut b, &file.static_load)?;
    interfaces::add_interfaces(&mut b, &file.interface)?;
    let defaults: ModesDefaults = options::modes_defaults(&b, file.modes.as_ref())?;
    warn_unused(&mut b);
    Ok(LoadedFeModel { name, model: b.model, defaults, warnings: b.warnings, sources: b.sources })
}

/// A model without elements has nothing to analyse.
fn check_elements_present(b: &Builder, file: &FeModelFile) -> Result<(), ModelFileError> {
    if !b.model.mesh.elements.is_empty() || b.model.mesh.imported.is_some() {
        return Ok(());
    }
    let (span, key) = match &file.fe_model {
        Some(section) => (section.span(), KeyPath::root().key("fe_model")),
        None => (0..0, KeyPath::root()),
    };
    let from_mesh = match &b.mesh_file {
        Some(mesh) => format!(" (the mesh file `{mesh}` has none)"),
        None => String::new(),
    };
    Err(b.ctx.invalid(
        &span,
        &key,
        format!(
            "the model has no elements{from_mesh}: add [[beam_line]], [[plate]], [[beam]] or [[shell]] tables, a \
             mesh file ([fe_model] mesh = \"….inp\"), or exported matrices ([matrices])"
        ),
    ))
}

/// Materials and sections this file defines that nothing uses are probably mistakes.
fn warn_unused(b: &mut Builder) {
    let mesh = &b.model.mesh;
    let mut used_beam = BTreeSet::new();
    let mut used_shell = BTreeSet::new();
    for element in &mesh.elements {
        match element.kind {
            ElementKind::Beam { section } => used_beam.insert(section),
            ElementKind::Shell { section } => used_shell.insert(section),
            ElementKind::Solid { .. } => false,
        };
    }
    let used_materials: BTreeSet<usize> = mesh
        .beam_sections
        .iter()
        .enumerate()
        .filter(|(k, _)| used_beam.contains(k))
        .map(|(_, s)| s.material)
        .chain(mesh.shell_sections.iter().enumerate().filter(|(k, _)| used_shell.contains(k)).map(|(_, s)| s.material))
        .collect();
    let source = b.ctx.source;
    let mut warnings = Vec::new();
    for (registry, used, what) in [
        (&b.materials, &used_materials, "material"),
        (&b.beam_sections, &used_beam, "beam section"),
        (&b.shell_sections, &used_shell, "shell section"),
    ] {
        for (name, definition) in registry.defined_here() {
            if !used.contains(&definition.id) {
                warnings.push(format!(
                    "{}:{}: {}: {what} `{name}` is used by no element",
                    b.file,
                    source.line(definition.span.start),
                    definition.element
                ));
            }
        }
    }
    b.warnings.extend(warnings);
}
