//! An expression of time `t` and of named measures, parsed once by `exmex` and evaluated without
//! allocation inside a time step.

use exmex::prelude::*;

use super::UserFunction;
use crate::model::MeasureId;

/// Most variables one expression may name; their values are passed on the stack.
pub const MAX_VARIABLES: usize = 16;

/// What a variable of an expression stands for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Variable {
    /// Simulation time `t` (s).
    Time,
    /// The current value of a named measure.
    Measure(MeasureId),
    /// The value of an output column at the same output time, by its index among the model's output
    /// columns (time not counted); only a user output reads it
    /// ([`eval_with_columns`](Expression::eval_with_columns)).
    OutputColumn(usize),
}

/// Why an expression could not be used.
#[derive(Clone, Debug, thiserror::Error, PartialEq)]
pub enum ExpressionError {
    /// The text is not an expression `exmex` can read.
    #[error("cannot parse expression `{source_text}`: {message}")]
    Parse {
        /// The expression's text.
        source_text: String,
        /// The parser's message.
        message: String,
    },
    /// A name is neither `t` nor a measure.
    #[error("expression `{source_text}` names `{name}`, which is neither `t` nor a defined measure{hint}")]
    UnknownVariable {
        /// The expression's text.
        source_text: String,
        /// The unknown name.
        name: String,
        /// A hint on what may be meant, or empty.
        hint: String,
    },
    /// More names than an expression may have (16, `MAX_VARIABLES`).
    #[error("expression `{source_text}` names {count} variables; at most {MAX_VARIABLES} are allowed")]
    TooManyVariables {
        /// The expression's text.
        source_text: String,
        /// How many variables it names.
        count: usize,
    },
    /// A function of time (a driver's) names something other than `t`.
    #[error("expression `{source_text}` must depend on time only, but names `{name}`")]
    NotTimeOnly {
        /// The expression's text.
        source_text: String,
        /// The name other than `t`.
        name: String,
    },
    /// `exmex` cannot differentiate the expression symbolically.
    #[error("cannot differentiate `{source_text}` with respect to t: {message}")]
    NotDifferentiable {
        /// The expression's text.
        source_text: String,
        /// Why.
        message: String,
    },
}

/// A parsed expression with its variables bound to time and measures, or a law given as code
/// ([`Expression::user`]).
#[derive(Clone, Debug)]
pub struct Expression {
    source: String,
    /// `None` for a constant made by [`Expression::constant`] or a user law.
    flat: Option<FlatEx<f64>>,
    constant: f64,
    variables: Vec<Variable>,
    /// The law of [`Expression::user`], evaluated in place of `flat`.
    user: Option<UserFunction>,
}

impl Expression {
    /// Parses `source`; `resolve` maps every name other than `t` to a measure.
    pub fn parse(
        source: &str,
        resolve: &dyn Fn(&str) -> Option<MeasureId>,
    ) -> Result<Self, ExpressionError> {
        Self::parse_with_columns(source, &|name| resolve(name).map(Variable::Measure))
    }

    /// Parses `source` as [`parse`](Self::parse) does, with `resolve` mapping every name other than
    /// `t` to a measure or an output column.
    pub fn parse_with_columns(source: &str, resolve: &dyn Fn(&str) -> Option<Variable>) -> Result<Self, ExpressionError> {
        // `exmex` cannot read exponent literals such as `1e-6`: they are written out in decimals first.
        let text = super::expression_text::rewrite(source, &|_| None);
        let flat = exmex::parse::<f64>(&text).map_err(|e| ExpressionError::Parse {
            source_text: source.to_string(),
            message: e.to_string(),
        })?;
        Self::bind(source, flat, resolve)
    }

    /// A constant expression.
    pub fn constant(value: f64) -> Self {
        Self { source: format!("{value:?}"), flat: None, constant: value, variables: Vec::new(), user: None }
    }

    /// A constant that `source` names in messages.
    pub(crate) fn named_constant(source: String, value: f64) -> Self {
        Self { source, ..Self::constant(value) }
    }

    /// A law given as code, read wherever an expression is (a force element's actuator or
    /// components); its [`source`](Self::source) is ``user law `name` ``.
    pub fn user(law: UserFunction) -> Self {
        Self {
            source: format!("user law `{}`", law.name()),
            flat: None,
            constant: f64::NAN,
            variables: law.measures().iter().map(|m| Variable::Measure(*m)).collect(),
            user: Some(law),
        }
    }

    /// The law given as code, for an expression made by [`Expression::user`].
    pub fn user_function(&self) -> Option<&UserFunction> {
        self.user.as_ref()
    }

    fn bind(
        source: &str,
        flat: FlatEx<f64>,
        resolve: &dyn Fn(&str) -> Option<Variable>,
    ) -> Result<Self, ExpressionError> {
        let names = flat.var_names();
        if names.len() > MAX_VARIABLES {
            return Err(ExpressionError::TooManyVariables {
                source_text: source.to_string(),
                count: names.len(),
            });
        }
        let mut variables = Vec::with_capacity(names.len());
        for name in names {
            let v = if name == "t" {
                Variable::Time
            } else if let Some(variable) = resolve(name) {
                variable
            } else {
                let hint = if name == "e" {
                    " (`e` is Euler's number here; name the measure differently)".to_string()
                } else {
                    String::new()
                };
                return Err(ExpressionError::UnknownVariable {
                    source_text: source.to_string(),
                    name: name.clone(),
                    hint,
                });
            };
            variables.push(v);
        }
        Ok(Self { source: source.to_string(), flat: Some(flat), constant: 0.0, variables, user: None })
    }

    /// The text the expression was parsed from.
    pub fn source(&self) -> &str {
        &self.source
    }

    /// The variables in the order `exmex` expects their values.
    pub fn variables(&self) -> &[Variable] {
        &self.variables
    }

    /// The measures this expression reads.
    pub fn measures(&self) -> impl Iterator<Item = MeasureId> + '_ {
        self.variables.iter().filter_map(|v| match v {
            Variable::Measure(m) => Some(*m),
            Variable::Time | Variable::OutputColumn(_) => None,
        })
    }

    /// Evaluates at time `t` with the current measure values; NaN if evaluation fails.
    #[inline]
    pub fn eval(&self, t: f64, measures: &[f64]) -> f64 {
        self.eval_with_columns(t, measures, &[])
    }

    /// The output columns this expression reads, by index.
    pub fn output_columns(&self) -> impl Iterator<Item = usize> + '_ {
        self.variables.iter().filter_map(|v| match v {
            Variable::OutputColumn(c) => Some(*c),
            _ => None,
        })
    }

    /// Evaluates at time `t` with the current measure values and the output columns computed so far;
    /// NaN if evaluation fails or a column is missing.
    #[inline]
    pub fn eval_with_columns(&self, t: f64, measures: &[f64], columns: &[f64]) -> f64 {
        if let Some(user) = &self.user {
            return user.eval(t, measures);
        }
        let Some(flat) = &self.flat else {
            return self.constant;
        };
        let mut values = [0.0; MAX_VARIABLES];
        for (slot, v) in values.iter_mut().zip(&self.variables) {
            *slot = match v {
                Variable::Time => t,
                Variable::Measure(m) => measures.get(m.0).copied().unwrap_or(f64::NAN),
                Variable::OutputColumn(c) => columns.get(*c).copied().unwrap_or(f64::NAN),
            };
        }
        flat.eval(&values[..self.variables.len()]).unwrap_or(f64::NAN)
    }

    /// `d/dt` of an expression of time only (symbolic, by `exmex`).
    pub(crate) fn time_derivative(&self) -> Result<Self, ExpressionError> {
        if self.user.is_some() {
            return Err(ExpressionError::NotDifferentiable {
                source_text: self.source.clone(),
                message: "a law given as code is not differentiated: give a motion with its derivatives".into(),
            });
        }
        let Some(flat) = &self.flat else {
            return Ok(Self::constant(0.0));
        };
        match self.variables.as_slice() {
            [] => Ok(Self::constant(0.0)),
            [Variable::Time] => {
                let d = flat.clone().partial(0).map_err(|e| ExpressionError::NotDifferentiable {
                    source_text: self.source.clone(),
                    message: e.to_string(),
                })?;
                let text = d.to_string();
                Ok(Self { source: text, flat: Some(d), constant: 0.0, variables: self.variables.clone(), user: None })
            }
            _ => Err(ExpressionError::NotTimeOnly {
                source_text: self.source.clone(),
                name: flat.var_names().iter().find(|n| *n != "t").cloned().unwrap_or_default(),
            }),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn evaluates_time_and_measures_in_name_order() {
        let resolve = |n: &str| match n {
            "omega" => Some(MeasureId(1)),
            "alpha" => Some(MeasureId(0)),
            _ => None,
        };
        let e = Expression::parse("2*alpha + omega*t", &resolve).unwrap();
        assert_eq!(e.eval(3.0, &[5.0, 7.0]), 2.0 * 5.0 + 7.0 * 3.0);
    }

    #[test]
    fn exponent_literals_are_read() {
        let e = Expression::parse("1e-3*t + 2.5E2", &|_| None).unwrap();
        assert_eq!(e.eval(2.0, &[]), 0.002 + 250.0);
        assert_eq!(e.source(), "1e-3*t + 2.5E2");
    }

    #[test]
    fn unknown_name_is_reported() {
        let err = Expression::parse("k*t", &|_| None).unwrap_err();
        assert!(matches!(err, ExpressionError::UnknownVariable { ref name, .. } if name == "k"));
    }
}
