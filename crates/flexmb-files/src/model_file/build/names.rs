//! Element names: each kind has its own name space; a name is defined once and referred to by later
//! elements, with a "did you mean" hint for names that are not defined.

use std::collections::BTreeMap;
use std::ops::Range;

use crate::model_file::error::ModelFileError;
use crate::model_file::key_path::KeyPath;
use crate::model_file::schema::Name;
use crate::model_file::source::Source;
use crate::model_file::suggest::did_you_mean;

/// Where an element was defined.
#[derive(Clone, Debug)]
pub(crate) struct Definition<Id> {
    pub id: Id,
    /// Key path of the element, such as `joint[2]`.
    pub element: KeyPath,
    /// Span of its name.
    pub span: Range<usize>,
}

/// The names of one kind of element.
pub(crate) struct NameTable<Id> {
    /// `body`, `marker`, …: used in messages.
    what: &'static str,
    entries: BTreeMap<String, Definition<Id>>,
}

impl<Id: Copy> NameTable<Id> {
    pub(crate) fn new(what: &'static str) -> Self {
        Self { what, entries: BTreeMap::new() }
    }

    /// Checks that `name` is a usable, new name (without defining it yet).
    pub(crate) fn check_new(&self, name: &Name, element: &KeyPath, source: &Source) -> Result<(), ModelFileError> {
        let text = name.get_ref();
        let key = element.key("name");
        if text.trim().is_empty() || text.trim() != text {
            return Err(source.invalid(
                &name.span(),
                &key,
                format!("a {} name must be non-empty, without leading or trailing spaces", self.what),
            ));
        }
        if let Some(previous) = self.entries.get(text) {
            return Err(source.invalid(
                &name.span(),
                &key,
                format!(
                    "{} name `{text}` is already used by {} on line {}",
                    self.what,
                    previous.element,
                    source.line(previous.span.start)
                ),
            ));
        }
        Ok(())
    }

    /// Records a new name (checked with [`check_new`](Self::check_new)).
    pub(crate) fn define(&mut self, name: &Name, element: &KeyPath, id: Id) {
        self.entries.insert(name.get_ref().clone(), Definition { id, element: element.clone(), span: name.span() });
    }

    /// The element a reference names.
    pub(crate) fn resolve(&self, name: &Name, key: &KeyPath, source: &Source) -> Result<Id, ModelFileError> {
        self.get(name.get_ref()).ok_or_else(|| self.unknown(name, key, source, &[]))
    }

    /// The error for a name that is not defined; `extra` names are offered as hints too.
    pub(crate) fn unknown(&self, name: &Name, key: &KeyPath, source: &Source, extra: &[&str]) -> ModelFileError {
        let text = name.get_ref();
        let candidates = self.names().chain(extra.iter().copied());
        let hint = did_you_mean(text, candidates);
        let defined = if self.entries.is_empty() && extra.is_empty() {
            format!(" (the file defines no {})", self.what)
        } else {
            String::new()
        };
        source.invalid(&name.span(), key, format!("no {} named `{text}`{hint}{defined}", self.what))
    }

    pub(crate) fn get(&self, name: &str) -> Option<Id> {
        self.entries.get(name).map(|d| d.id)
    }

    pub(crate) fn definition(&self, name: &str) -> Option<&Definition<Id>> {
        self.entries.get(name)
    }

    /// The name of the element with this id.
    pub(crate) fn name_of(&self, id: Id) -> Option<&str>
    where
        Id: PartialEq,
    {
        self.entries.iter().find(|(_, d)| d.id == id).map(|(name, _)| name.as_str())
    }

    pub(crate) fn names(&self) -> impl Iterator<Item = &str> {
        self.entries.keys().map(String::as_str)
    }
}
