//! Turns the TOML parser's and deserializer's errors into located [`ModelFileError`]s: the key path is
//! found by walking the parsed document to the error's byte offset, and serde's wording ("field",
//! "sequence", "f64") is put in the file's terms ("key", "array", "number").

use std::ops::Range;

use toml::de::{DeTable, DeValue};

use super::error::{ErrorKind, ModelFileError};
use super::key_path::KeyPath;
use super::source::Source;
use super::suggest::did_you_mean;

/// Parses `source`'s text into `T`, with the syntax and schema errors located in the file.
pub(crate) fn deserialize_located<'de, T: serde::Deserialize<'de>>(source: &Source<'de>) -> Result<T, ModelFileError> {
    let (document, syntax_errors) = DeTable::parse_recoverable(source.text());
    if let Some(error) = syntax_errors.first() {
        return Err(syntax_error(source, document.get_ref(), error));
    }
    T::deserialize(toml::de::Deserializer::from(document.clone())).map_err(|e| schema_error(source, document.get_ref(), &e))
}

/// A syntax error; `document` is what the parser recovered, used to name the key near the error.
pub(crate) fn syntax_error(source: &Source, document: &DeTable, error: &toml::de::Error) -> ModelFileError {
    let span = error.span().unwrap_or(source.text().len()..source.text().len());
    let key = key_path_at(document, span.start);
    let mut message = format!("TOML syntax error: {}", error.message());
    if error.message() == "duplicate key" {
        if let Some(duplicate) = source.text().get(span.clone()) {
            message = format!("TOML syntax error: duplicate key `{duplicate}`: each key may appear once per table");
        }
    }
    source.error(ErrorKind::Syntax, &span, &key, message)
}

/// An unknown or missing key, or a value of the wrong type.
pub(crate) fn schema_error(source: &Source, document: &DeTable, error: &toml::de::Error) -> ModelFileError {
    let span = error.span().unwrap_or(0..0);
    let key = key_path_at(document, span.start);
    let message = error.message();
    if let Some(rest) = message.strip_prefix("unknown field ") {
        let mut names = backticked(rest).into_iter();
        let unknown = names.next().unwrap_or_default();
        let allowed: Vec<&str> = names.collect();
        let allowed_text = if allowed.is_empty() {
            "this table takes no keys".to_string()
        } else {
            let list: Vec<String> = allowed.iter().map(|a| format!("`{a}`")).collect();
            format!("allowed keys: {}", list.join(", "))
        };
        let hint = did_you_mean(unknown, allowed.iter().copied());
        let key = without_trailing_indices(key);
        return source.error(ErrorKind::Schema, &span, &key, format!("unknown key `{unknown}`{hint}; {allowed_text}"));
    }
    if let Some(rest) = message.strip_prefix("missing field ") {
        let missing = backticked(rest).into_iter().next().unwrap_or_default();
        return source.error(ErrorKind::Schema, &span, &key.key(missing), format!("missing required key `{missing}`"));
    }
    source.error(ErrorKind::Schema, &span, &key, in_file_terms(message))
}

/// `bodies[0]` → `bodies`: an unknown array-of-tables key is named without the element index.
fn without_trailing_indices(key: KeyPath) -> KeyPath {
    let text = key.as_str();
    // Strip whole `[n]` groups only: a key may itself end in a digit (`rh0`).
    let mut trimmed = text;
    while let Some(open) = trimmed.strip_suffix(']').and_then(|t| t.rfind('[')) {
        if trimmed[open + 1..trimmed.len() - 1].chars().all(|c| c.is_ascii_digit()) {
            trimmed = &trimmed[..open];
        } else {
            break;
        }
    }
    if trimmed.len() == text.len() {
        key
    } else {
        KeyPath::from_rendered(trimmed)
    }
}

/// The texts between pairs of backticks.
fn backticked(text: &str) -> Vec<&str> {
    text.split('`').skip(1).step_by(2).collect()
}

/// Serde's type names in the words of the file format.
fn in_file_terms(message: &str) -> String {
    let mut text = message
        .replace("expected f64", "expected a number")
        .replace("a sequence", "an array")
        .replace("expected a map", "expected a table");
    if let Some(at) = text.find("expected struct ") {
        let name_end = text[at + 16..].find(|c: char| !c.is_alphanumeric()).map_or(text.len(), |e| at + 16 + e);
        text.replace_range(at..name_end, "expected a table");
    }
    text
}

/// The key path of the innermost key or value whose span holds `offset`; failing that (the offset is
/// in text the parser could not read), the path of the last key that starts before it.
pub(crate) fn key_path_at(document: &DeTable, offset: usize) -> KeyPath {
    let mut entries = Vec::new();
    collect_table(document, &KeyPath::root(), 0, &mut entries);
    let containing = entries
        .iter()
        .filter(|e| contains(&e.key_span, offset) || contains(&e.value_span, offset))
        .max_by_key(|e| e.depth);
    let preceding =
        || entries.iter().filter(|e| e.key_span.start <= offset).max_by_key(|e| (e.key_span.start, e.depth));
    containing.or_else(preceding).map(|e| e.path.clone()).unwrap_or_default()
}

/// One key (or array element) of the parsed document.
struct Entry {
    path: KeyPath,
    depth: usize,
    key_span: Range<usize>,
    value_span: Range<usize>,
}

fn contains(span: &Range<usize>, offset: usize) -> bool {
    span.contains(&offset) || (span.is_empty() && span.start == offset)
}

fn collect_table(table: &DeTable, path: &KeyPath, depth: usize, entries: &mut Vec<Entry>) {
    for (key, value) in table.iter() {
        let key_path = path.key(key.get_ref());
        entries.push(Entry {
            path: key_path.clone(),
            depth: depth + 1,
            key_span: key.span(),
            value_span: value.span(),
        });
        collect_value(value.get_ref(), &key_path, depth + 1, entries);
    }
}

fn collect_value(value: &DeValue, path: &KeyPath, depth: usize, entries: &mut Vec<Entry>) {
    match value {
        DeValue::Table(table) => collect_table(table, path, depth, entries),
        DeValue::Array(array) => {
            for (index, element) in array.iter().enumerate() {
                let element_path = path.index(index);
                entries.push(Entry {
                    path: element_path.clone(),
                    depth: depth + 1,
                    key_span: element.span(),
                    value_span: element.span(),
                });
                collect_value(element.get_ref(), &element_path, depth + 1, entries);
            }
        }
        _ => {}
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn path_at(text: &str, needle: &str) -> String {
        let (document, _) = DeTable::parse_recoverable(text);
        let offset = text.find(needle).expect("needle in text");
        key_path_at(document.get_ref(), offset).to_string()
    }

    #[test]
    fn finds_keys_in_arrays_of_tables_and_inline_tables() {
        let text = "[[body]]\nname = 'a'\n[[body]]\nname = 'b'\norientation = { axis = [0, 0, 1], angle = 2 }\n";
        assert_eq!(path_at(text, "'b'"), "body[1].name");
        assert_eq!(path_at(text, "angle ="), "body[1].orientation.angle");
        assert_eq!(path_at(text, "1]"), "body[1].orientation.axis[2]");
        assert_eq!(path_at(text, "[[body]]\nname = 'b'"), "body[1]");
    }

    #[test]
    fn rewords_serde_types() {
        assert_eq!(
            in_file_terms("invalid type: string \"x\", expected f64"),
            "invalid type: string \"x\", expected a number"
        );
        assert_eq!(
            in_file_terms("invalid type: integer `3`, expected struct BodySection"),
            "invalid type: integer `3`, expected a table"
        );
        assert_eq!(
            in_file_terms("invalid type: integer `3`, expected a sequence"),
            "invalid type: integer `3`, expected an array"
        );
    }
}
