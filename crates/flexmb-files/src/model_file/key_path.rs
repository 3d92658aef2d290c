//! TOML key paths such as `body[2].inertia` or `force[0].components[1]`.

use std::fmt;

/// A dotted key path; arrays are indexed from 0.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub(crate) struct KeyPath(String);

impl KeyPath {
    /// The path of the whole document (renders empty).
    pub(crate) fn root() -> Self {
        Self::default()
    }

    /// The path of `key` inside this table.
    pub(crate) fn key(&self, key: &str) -> Self {
        let key = if is_bare_key(key) { key.to_string() } else { format!("{key:?}") };
        if self.0.is_empty() {
            Self(key)
        } else {
            Self(format!("{}.{key}", self.0))
        }
    }

    /// The path of element `index` of this array.
    pub(crate) fn index(&self, index: usize) -> Self {
        Self(format!("{}[{index}]", self.0))
    }

    /// A path already rendered as text.
    pub(crate) fn from_rendered(text: &str) -> Self {
        Self(text.to_string())
    }

    pub(crate) fn as_str(&self) -> &str {
        &self.0
    }
}

impl fmt::Display for KeyPath {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

/// Whether TOML accepts `key` without quotes.
fn is_bare_key(key: &str) -> bool {
    !key.is_empty() && key.chars().all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
}
