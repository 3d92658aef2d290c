//! `[parameters]`: named constants substituted into every expression and number of the file. A
//! parameter is a number or an expression of other parameters; they are evaluated in dependency order.

use std::collections::{BTreeMap, BTreeSet};

use super::error::ModelFileError;
use flexmb::function::expression_text::{identifiers, is_plain_identifier, BUILTIN_NAMES};
use super::expressions::Scope;
use super::key_path::KeyPath;
use super::schema::{Name, Number};
use super::source::Source;
use super::value::NumberOrExpression;

/// Evaluates every parameter; names must be identifiers other than `t` and `exmex`'s builtins.
pub(crate) fn evaluate(
    section: &BTreeMap<Name, Number>,
    source: &Source,
) -> Result<BTreeMap<String, f64>, ModelFileError> {
    let table = KeyPath::root().key("parameters");
    for name in section.keys() {
        check_name(name, &table, source)?;
    }
    let mut evaluation = Evaluation { section, source, table, values: BTreeMap::new(), in_progress: Vec::new() };
    for name in section.keys() {
        evaluation.value_of(name.get_ref())?;
    }
    Ok(evaluation.values)
}

fn check_name(name: &Name, table: &KeyPath, source: &Source) -> Result<(), ModelFileError> {
    let text = name.get_ref();
    let problem = if !is_plain_identifier(text) {
        "a parameter name must be an identifier: a letter or `_`, then letters, digits and `_`"
    } else if text == "t" {
        "`t` is time and cannot name a parameter"
    } else if BUILTIN_NAMES.contains(&text.as_str()) {
        "this name is a constant or function of the expression language and cannot name a parameter"
    } else {
        return Ok(());
    };
    Err(source.invalid(&name.span(), &table.key(text), problem))
}

/// Depth-first evaluation with cycle detection.
struct Evaluation<'a> {
    section: &'a BTreeMap<Name, Number>,
    source: &'a Source<'a>,
    table: KeyPath,
    values: BTreeMap<String, f64>,
    in_progress: Vec<String>,
}

impl Evaluation<'_> {
    fn value_of(&mut self, name: &str) -> Result<f64, ModelFileError> {
        if let Some(value) = self.values.get(name) {
            return Ok(*value);
        }
        let Some((key, number)) = self.section.get_key_value(name) else {
            return Err(self.source.invalid(&(0..0), &self.table, format!("parameter `{name}` is not defined")));
        };
        let path = self.table.key(key.get_ref());
        if let Some(start) = self.in_progress.iter().position(|n| n == name) {
            let cycle: Vec<&str> =
                self.in_progress[start..].iter().map(String::as_str).chain(std::iter::once(name)).collect();
            return Err(self.source.invalid(
                &number.span(),
                &path,
                format!("parameters depend on each other in a cycle: {}", cycle.join(" -> ")),
            ));
        }
        let value = match number.get_ref() {
            NumberOrExpression::Number(value) if value.is_finite() => *value,
            NumberOrExpression::Number(value) => {
                return Err(self.source.invalid(
                    &number.span(),
                    &path,
                    format!("expected a finite number, got {value}"),
                ))
            }
            NumberOrExpression::Expression(text) => {
                self.in_progress.push(name.to_string());
                for used in identifiers(text) {
                    if self.section.contains_key(used) {
                        self.value_of(used)?;
                    }
                }
                self.in_progress.pop();
                let (no_measures, no_names) = (BTreeMap::new(), BTreeSet::new());
                let scope = Scope { parameters: &self.values, measures: &no_measures, declared_measures: &no_names };
                scope.constant(text).map_err(|message| self.source.invalid(&number.span(), &path, message))?
            }
        };
        self.values.insert(name.to_string(), value);
        Ok(value)
    }
}
