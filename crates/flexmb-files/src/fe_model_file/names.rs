//! Names of materials, sections, parts and static loads: those the file defines (with their tables,
//! for messages) and those the mesh file brought in, in one name space per kind.

use std::collections::BTreeMap;

use crate::model_file::build::names::{Definition, NameTable};
use crate::model_file::key_path::KeyPath;
use crate::model_file::schema::Name;
use crate::model_file::source::Source;
use crate::model_file::ModelFileError;

/// The names of one kind of thing, each with its index in the model.
pub(crate) struct Registry {
    what: &'static str,
    /// Defined by tables of this file.
    table: NameTable<usize>,
    /// Defined by the mesh file.
    from_mesh: BTreeMap<String, usize>,
    /// The mesh file's name, for messages.
    mesh_file: String,
}

impl Registry {
    pub(crate) fn new(what: &'static str) -> Self {
        Self { what, table: NameTable::new(what), from_mesh: BTreeMap::new(), mesh_file: String::new() }
    }

    /// Adds the names the mesh file `file` defines.
    pub(crate) fn add_from_mesh<'n>(&mut self, file: &str, names: impl IntoIterator<Item = (&'n str, usize)>) {
        self.mesh_file = file.to_string();
        self.from_mesh.extend(names.into_iter().map(|(name, index)| (name.to_string(), index)));
    }

    /// Checks that `name` is a usable name that neither this file nor the mesh file defines yet.
    pub(crate) fn check_new(&self, name: &Name, element: &KeyPath, source: &Source) -> Result<(), ModelFileError> {
        self.table.check_new(name, element, source)?;
        if let Some(used) = self.from_mesh.keys().find(|n| n.eq_ignore_ascii_case(name.get_ref())) {
            return Err(source.invalid(
                &name.span(),
                &element.key("name"),
                format!(
                    "{} name `{}` is already used in the mesh file `{}`{}",
                    self.what,
                    name.get_ref(),
                    self.mesh_file,
                    if used == name.get_ref() {
                        String::new()
                    } else {
                        format!(" as `{used}` (its names ignore case)")
                    }
                ),
            ));
        }
        Ok(())
    }

    /// Records a name checked with [`check_new`](Self::check_new).
    pub(crate) fn define(&mut self, name: &Name, element: &KeyPath, index: usize) {
        self.table.define(name, element, index);
    }

    /// The index a reference names, with a "did you mean" hint when nothing has that name. Names of
    /// the mesh file are case-insensitive, as in Abaqus.
    pub(crate) fn resolve(&self, name: &Name, key: &KeyPath, source: &Source) -> Result<usize, ModelFileError> {
        let text = name.get_ref();
        let found = self.table.get(text).or_else(|| self.from_mesh.get(text).copied()).or_else(|| {
            let mut same = self.from_mesh.iter().filter(|(n, _)| n.eq_ignore_ascii_case(text));
            match (same.next(), same.next()) {
                (Some((_, index)), None) => Some(*index),
                _ => None,
            }
        });
        if let Some(index) = found {
            return Ok(index);
        }
        let extra: Vec<&str> = self.from_mesh.keys().map(String::as_str).collect();
        Err(self.table.unknown(name, key, source, &extra))
    }

    /// Where this file defines `name` (`None` for names of the mesh file).
    pub(crate) fn definition(&self, name: &str) -> Option<&Definition<usize>> {
        self.table.definition(name)
    }

    /// The names this file defines, with their definitions.
    pub(crate) fn defined_here(&self) -> impl Iterator<Item = (&str, &Definition<usize>)> {
        self.table.names().filter_map(|name| self.table.definition(name).map(|d| (name, d)))
    }
}
