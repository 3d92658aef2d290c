//! What every element builder needs: the source for locating errors, the parameter values, the measures
//! defined so far, and conversions of numbers, vectors and expressions with their key paths.

use std::collections::{BTreeMap, BTreeSet};
use std::ops::Range;

use flexmb::function::{Expression, TimeFunction};
use flexmb::math::Vec3;
use flexmb::model::MeasureId;
use flexmb_fem::input::Quantity;
use toml::Spanned;

use crate::model_file::error::{ErrorKind, ModelFileError};
use flexmb::function::expression_text::decimal;
use crate::model_file::expressions::Scope;
use crate::model_file::key_path::KeyPath;
use crate::model_file::schema::{Number, Vector};
use crate::model_file::source::Source;
use crate::model_file::suggest::did_you_mean;
use crate::model_file::value::NumberOrExpression;

pub(crate) struct Context<'a> {
    pub source: &'a Source<'a>,
    pub parameters: BTreeMap<String, f64>,
    /// Measures by name, filled before any expression that may read them is parsed.
    pub measures: BTreeMap<String, MeasureId>,
    /// The names of all measures in the file, known from the start.
    pub declared_measures: BTreeSet<String>,
}

impl<'a> Context<'a> {
    pub(crate) fn new(
        source: &'a Source<'a>,
        parameters: BTreeMap<String, f64>,
        declared_measures: BTreeSet<String>,
    ) -> Self {
        Self { source, parameters, measures: BTreeMap::new(), declared_measures }
    }

    pub(crate) fn invalid(&self, span: &Range<usize>, key: &KeyPath, message: impl Into<String>) -> ModelFileError {
        self.source.invalid(span, key, message)
    }

    fn scope(&self) -> Scope<'_> {
        Scope { parameters: &self.parameters, measures: &self.measures, declared_measures: &self.declared_measures }
    }

    /// A finite constant: a number, or an expression of parameters.
    pub(crate) fn number(&self, value: &Number, key: &KeyPath) -> Result<f64, ModelFileError> {
        match value.get_ref() {
            NumberOrExpression::Number(x) if x.is_finite() => Ok(*x),
            NumberOrExpression::Number(x) => {
                Err(self.invalid(&value.span(), key, format!("expected a finite number, got {x}")))
            }
            NumberOrExpression::Expression(text) => {
                self.scope().constant(text).map_err(|message| self.invalid(&value.span(), key, message))
            }
        }
    }

    /// A finite constant of a physical `quantity`, within its window (`flexmb_fem::input::magnitude`).
    pub(crate) fn quantity(&self, value: &Number, key: &KeyPath, quantity: Quantity) -> Result<f64, ModelFileError> {
        let x = self.number(value, key)?;
        quantity.check(x).map_err(|message| self.invalid(&value.span(), key, message))
    }

    /// An optional constant with its default.
    pub(crate) fn number_or(&self, value: &Option<Number>, key: &KeyPath, default: f64) -> Result<f64, ModelFileError> {
        value.as_ref().map_or(Ok(default), |v| self.number(v, key))
    }

    /// An optional constant of a physical `quantity` that must not be negative.
    pub(crate) fn non_negative_or(
        &self,
        value: &Option<Number>,
        key: &KeyPath,
        default: f64,
        quantity: Quantity,
    ) -> Result<f64, ModelFileError> {
        let Some(v) = value else { return Ok(default) };
        let x = self.quantity(v, key, quantity)?;
        if x < 0.0 {
            return Err(self.invalid(&v.span(), key, format!("expected a value >= 0, got {x}")));
        }
        Ok(x)
    }

    /// An array of exactly `N` constants.
    pub(crate) fn numbers<const N: usize>(
        &self,
        value: &Vector,
        key: &KeyPath,
        what: &str,
    ) -> Result<[f64; N], ModelFileError> {
        let items = value.get_ref();
        if items.len() != N {
            return Err(self.invalid(
                &value.span(),
                key,
                format!("expected {what} with {N} components, got {} component(s)", items.len()),
            ));
        }
        let mut out = [0.0; N];
        for (k, (slot, item)) in out.iter_mut().zip(items).enumerate() {
            *slot = self.number(item, &key.index(k))?;
        }
        Ok(out)
    }

    /// A 3-vector `[x, y, z]`.
    pub(crate) fn vector(&self, value: &Vector, key: &KeyPath) -> Result<Vec3, ModelFileError> {
        let [x, y, z] = self.numbers::<3>(value, key, "a vector [x, y, z]")?;
        Ok(Vec3::new(x, y, z))
    }

    /// A 3-vector of a physical `quantity`, each component within its window.
    pub(crate) fn vector_of(&self, value: &Vector, key: &KeyPath, quantity: Quantity) -> Result<Vec3, ModelFileError> {
        let v = self.vector(value, key)?;
        for (k, item) in value.get_ref().iter().enumerate() {
            quantity.check(v[k]).map_err(|message| self.invalid(&item.span(), &key.index(k), message))?;
        }
        Ok(v)
    }

    /// An optional 3-vector of a physical `quantity`, zero if absent.
    pub(crate) fn vector_or_zero(
        &self,
        value: &Option<Vector>,
        key: &KeyPath,
        quantity: Quantity,
    ) -> Result<Vec3, ModelFileError> {
        value.as_ref().map_or(Ok(Vec3::zeros()), |v| self.vector_of(v, key, quantity))
    }

    /// An optional 3-vector of a physical `quantity`, `None` if absent.
    pub(crate) fn optional_vector(
        &self,
        value: &Option<Vector>,
        key: &KeyPath,
        quantity: Quantity,
    ) -> Result<Option<Vec3>, ModelFileError> {
        value.as_ref().map(|v| self.vector_of(v, key, quantity)).transpose()
    }

    /// An expression of `t` and measures (a number is a constant expression).
    pub(crate) fn expression(&self, value: &Number, key: &KeyPath) -> Result<Expression, ModelFileError> {
        let text = self.expression_text(value, key)?;
        self.scope().expression(&text).map_err(|message| self.invalid(&value.span(), key, message))
    }

    /// A user output's expression of `t`, measures and the output columns `columns` before it.
    pub(crate) fn output_expression(&self, text: &Spanned<String>, key: &KeyPath, columns: &[String]) -> Result<Expression, ModelFileError> {
        self.scope().output_expression(text.get_ref(), columns).map_err(|message| self.invalid(&text.span(), key, message))
    }

    /// A function of `t` alone.
    pub(crate) fn time_function(&self, value: &Number, key: &KeyPath) -> Result<TimeFunction, ModelFileError> {
        let text = self.expression_text(value, key)?;
        self.scope().time_function(&text).map_err(|message| self.invalid(&value.span(), key, message))
    }

    /// A constant function of time.
    pub(crate) fn constant_time_function(
        &self,
        value: f64,
        span: &Range<usize>,
        key: &KeyPath,
    ) -> Result<TimeFunction, ModelFileError> {
        self.scope().time_function(&format!("({})", decimal(value))).map_err(|message| self.invalid(span, key, message))
    }

    fn expression_text(&self, value: &Number, key: &KeyPath) -> Result<String, ModelFileError> {
        match value.get_ref() {
            NumberOrExpression::Number(x) if x.is_finite() => Ok(format!("({})", decimal(*x))),
            NumberOrExpression::Number(x) => {
                Err(self.invalid(&value.span(), key, format!("expected a finite number, got {x}")))
            }
            NumberOrExpression::Expression(text) => Ok(text.clone()),
        }
    }

    /// A keyword from a fixed list, with a "did you mean" hint when it is not one of them.
    pub(crate) fn keyword<T: Copy>(
        &self,
        value: &Spanned<String>,
        key: &KeyPath,
        what: &str,
        choices: &[(&str, T)],
    ) -> Result<T, ModelFileError> {
        let text = value.get_ref();
        if let Some((_, choice)) = choices.iter().find(|(word, _)| word == text) {
            return Ok(*choice);
        }
        let words: Vec<&str> = choices.iter().map(|(word, _)| *word).collect();
        let hint = did_you_mean(text, words.iter().copied());
        let list: Vec<String> = words.iter().map(|w| format!("`{w}`")).collect();
        Err(self.invalid(
            &value.span(),
            key,
            format!("unknown {what} `{text}`{hint}; expected one of {}", list.join(", ")),
        ))
    }

    /// Rejects keys present in an element that its type does not use.
    pub(crate) fn reject_unused_keys(
        &self,
        element: &KeyPath,
        description: &str,
        present: &[(&'static str, Option<Range<usize>>)],
        used: &[&str],
    ) -> Result<(), ModelFileError> {
        for (name, span) in present {
            if let Some(span) = span {
                if !used.contains(name) {
                    let takes = if used.is_empty() {
                        "none of these keys".to_string()
                    } else {
                        used.iter().map(|u| format!("`{u}`")).collect::<Vec<_>>().join(", ")
                    };
                    return Err(self.invalid(
                        span,
                        &element.key(name),
                        format!("key `{name}` does not apply to {description}, which takes {takes}"),
                    ));
                }
            }
        }
        Ok(())
    }

    /// A key that this element's type requires.
    pub(crate) fn required<'v, T>(
        &self,
        value: &'v Option<T>,
        element: &KeyPath,
        element_span: &Range<usize>,
        name: &str,
        description: &str,
    ) -> Result<&'v T, ModelFileError> {
        value.as_ref().ok_or_else(|| {
            self.source.error(
                ErrorKind::Schema,
                element_span,
                &element.key(name),
                format!("missing required key `{name}` for {description}"),
            )
        })
    }
}
