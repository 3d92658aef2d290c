//! Changes a study makes to a model file before it is built: the mode set of a flexible body, the
//! value of a parameter. They replace what the file says, keeping the file's positions for messages.

use toml::Spanned;

use super::schema::ModelFile;
use super::suggest::did_you_mean;
use super::value::NumberOrExpression;

/// Values that replace those of a model file.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ModelOverrides {
    /// `(flexible body, mode set)`: the `modes` of that `[[flexible_body]]`.
    pub modes: Vec<(String, String)>,
    /// `(name, value)`: the value of that `[parameters]` entry.
    pub parameters: Vec<(String, f64)>,
    /// `(name, expression)`: that `[parameters]` entry replaced by a constant expression of the file's
    /// parameters (a study's `[[case]] parameters = { w = "2*PI*f" }`), applied after `parameters`.
    pub parameter_expressions: Vec<(String, String)>,
}

impl ModelOverrides {
    /// Applies the overrides; an override of a body or parameter the file does not have is an error
    /// that lists those it has.
    pub(crate) fn apply(&self, file: &mut ModelFile) -> Result<(), String> {
        for (body, set) in &self.modes {
            let section = file.flexible_body.iter_mut().find(|s| s.get_ref().name.get_ref() == body);
            let Some(section) = section else {
                let names: Vec<&str> = file.flexible_body.iter().map(|s| s.get_ref().name.get_ref().as_str()).collect();
                let hint = did_you_mean(body, names.iter().copied());
                return Err(format!("the model has no flexible body '{body}' (it has: {}){hint}", list(&names)));
            };
            let span = section.span();
            let f = section.get_mut();
            let at = f.modes.as_ref().map_or(span, |m| m.span());
            f.modes = Some(Spanned::new(at, set.clone()));
        }
        let numbers = self.parameters.iter().map(|(name, value)| (name, NumberOrExpression::Number(*value)));
        let expressions =
            self.parameter_expressions.iter().map(|(name, text)| (name, NumberOrExpression::Expression(text.clone())));
        for (name, value) in numbers.chain(expressions) {
            let Some(entry) = file.parameters.iter_mut().find(|(k, _)| k.get_ref() == name) else {
                let names: Vec<&str> = file.parameters.keys().map(|k| k.get_ref().as_str()).collect();
                let hint = did_you_mean(name, names.iter().copied());
                return Err(format!("the model has no parameter '{name}' (it has: {}){hint}", list(&names)));
            };
            *entry.1 = Spanned::new(entry.1.span(), value);
        }
        Ok(())
    }
}

fn list(names: &[&str]) -> String {
    if names.is_empty() {
        "none".to_string()
    } else {
        names.join(", ")
    }
}
