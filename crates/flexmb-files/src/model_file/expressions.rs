//! Expressions written in the model file: constants (of `[parameters]` only), functions of time and
//! measures (actuators, force components), and functions of time alone (driver functions, distance
//! lengths). Names are checked here, with "did you mean" hints, before `exmex` sees the text.

use std::collections::{BTreeMap, BTreeSet};

use flexmb::function::{Expression, ExpressionError, TimeFunction, Variable};
use flexmb::model::MeasureId;

use flexmb::function::expression_text::{identifiers, rewrite, tokenize, Token, BUILTIN_NAMES, FUNCTION_NAMES};
use super::suggest::did_you_mean;

/// The names an expression may use besides `exmex`'s constants and functions.
pub(crate) struct Scope<'a> {
    /// Parameter values, substituted into the text.
    pub parameters: &'a BTreeMap<String, f64>,
    /// Measures the expression may read.
    pub measures: &'a BTreeMap<String, MeasureId>,
    /// Every measure the file declares, built or not: for messages about functions of time alone.
    pub declared_measures: &'a BTreeSet<String>,
}

/// What an expression may depend on.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Dependence {
    Constant,
    Time,
    TimeAndMeasures,
    /// `t`, measures and output columns (a user output).
    TimeMeasuresAndColumns,
}

/// What a column of an earlier output is written as in the text `exmex` reads.
const COLUMN_PLACEHOLDER: &str = "__column_";

impl Scope<'_> {
    /// The value of an expression of parameters only.
    pub(crate) fn constant(&self, text: &str) -> Result<f64, String> {
        let expression = self.parse(text, Dependence::Constant)?;
        let value = expression.eval(0.0, &[]);
        if value.is_finite() {
            Ok(value)
        } else {
            Err(format!("expression `{text}` evaluates to {value}, expected a finite number"))
        }
    }

    /// An expression of `t` and measures.
    pub(crate) fn expression(&self, text: &str) -> Result<Expression, String> {
        self.parse(text, Dependence::TimeAndMeasures)
    }

    /// A user output's expression of `t`, measures and the output columns `columns` (named in full,
    /// dots included: `bob.angular_velocity.z`).
    pub(crate) fn output_expression(&self, text: &str, columns: &[String]) -> Result<Expression, String> {
        let ready = substitute_columns(text, columns)?;
        self.parse(&ready, Dependence::TimeMeasuresAndColumns).map_err(|message| message.replace(&ready, text))
    }

    /// A function of `t` alone, differentiated twice.
    pub(crate) fn time_function(&self, text: &str) -> Result<TimeFunction, String> {
        let expression = self.parse(text, Dependence::Time)?;
        TimeFunction::new(expression).map_err(|e| describe(&e, text))
    }

    fn parse(&self, text: &str, dependence: Dependence) -> Result<Expression, String> {
        if text.trim().is_empty() {
            return Err("expression is empty".to_string());
        }
        self.check_names(text, dependence)?;
        check_parentheses(text)?;
        check_operators(text)?;
        let ready = rewrite(text, &|name| self.parameters.get(name).copied());
        let resolve = |name: &str| match name.strip_prefix(COLUMN_PLACEHOLDER) {
            Some(index) => index.parse().ok().map(Variable::OutputColumn),
            None => self.measures.get(name).copied().map(Variable::Measure),
        };
        let expression = Expression::parse_with_columns(&ready, &resolve).map_err(|e| describe(&e, text))?;
        Ok(expression)
    }

    /// Every identifier must be a builtin, a parameter, or (where allowed) `t` or a measure.
    fn check_names(&self, text: &str, dependence: Dependence) -> Result<(), String> {
        for name in identifiers(text) {
            let is_time = name == "t";
            let is_measure = self.measures.contains_key(name) || self.declared_measures.contains(name);
            if BUILTIN_NAMES.contains(&name) || self.parameters.contains_key(name) {
                continue;
            }
            match dependence {
                Dependence::TimeMeasuresAndColumns if is_time || is_measure || name.starts_with(COLUMN_PLACEHOLDER) => continue,
                Dependence::TimeAndMeasures if is_time || is_measure => continue,
                Dependence::Time if is_time => continue,
                Dependence::Time if is_measure => {
                    return Err(format!(
                        "expression `{text}` reads measure `{name}`, but this function may depend on time `t` only"
                    ))
                }
                Dependence::Constant if is_time => {
                    return Err(format!("expression `{text}` depends on time `t`, but a constant is expected"))
                }
                _ => {}
            }
            let mut candidates: Vec<&str> = self.parameters.keys().map(String::as_str).collect();
            let allowed = match dependence {
                Dependence::Constant => "a parameter",
                Dependence::Time => "`t` or a parameter",
                Dependence::TimeAndMeasures => {
                    candidates.extend(self.measures.keys().map(String::as_str));
                    "`t`, a parameter or a measure"
                }
                Dependence::TimeMeasuresAndColumns => {
                    candidates.extend(self.measures.keys().map(String::as_str));
                    "`t`, a parameter, a measure or a column of an output before this one"
                }
            };
            candidates.extend(BUILTIN_NAMES);
            let hint = did_you_mean(name, candidates);
            return Err(format!("expression `{text}` names `{name}`, which is not {allowed}{hint}"));
        }
        Ok(())
    }
}

/// `text` with every name of a column in `columns` replaced by its placeholder: a name with dots
/// (`bob.position.x`) must be one of them; a plain name (`power`) is one if a column has it.
fn substitute_columns(text: &str, columns: &[String]) -> Result<String, String> {
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(c) = rest.chars().next() {
        if !(c.is_alphabetic() || c == '_') {
            out.push(c);
            rest = &rest[c.len_utf8()..];
            continue;
        }
        let length = rest.find(|c: char| !(c.is_alphanumeric() || c == '_' || c == '.')).unwrap_or(rest.len());
        let name = rest[..length].trim_end_matches('.');
        match columns.iter().position(|column| column == name) {
            Some(index) => out.push_str(&format!("{COLUMN_PLACEHOLDER}{index}")),
            None if name.contains('.') => {
                let hint = did_you_mean(name, columns.iter().map(String::as_str));
                return Err(format!(
                    "expression `{text}` names `{name}`, which is not a column of an output before this one{hint}"
                ));
            }
            None => out.push_str(name),
        }
        rest = &rest[name.len()..];
    }
    Ok(out)
}

/// Deepest nesting of parentheses accepted (the parser recurses on each level).
const MAX_NESTING: i64 = 100;

/// Unbalanced parentheses get a clearer message than `exmex` gives.
fn check_parentheses(text: &str) -> Result<(), String> {
    let mut depth = 0i64;
    for c in text.chars() {
        match c {
            '(' => depth += 1,
            ')' => depth -= 1,
            '{' | '}' => return Err(format!("expression `{text}` contains a brace; use parentheses")),
            _ => {}
        }
        if depth < 0 {
            return Err(format!("expression `{text}` has a `)` without a matching `(`"));
        }
        if depth > MAX_NESTING {
            return Err(format!("expression `{text}` nests parentheses more than {MAX_NESTING} deep"));
        }
    }
    if depth > 0 {
        return Err(format!("expression `{text}` has a `(` that is never closed"));
    }
    Ok(())
}

/// Two operands side by side (`2 PI`, `L t`, `(a)(b)`) get a clearer message than `exmex` gives.
fn check_operators(text: &str) -> Result<(), String> {
    let tokens: Vec<Token> =
        tokenize(text).into_iter().filter(|t| !matches!(t, Token::Other(c) if c.is_whitespace())).collect();
    for pair in tokens.windows(2) {
        let ends_operand = match &pair[0] {
            Token::Identifier(name) => !FUNCTION_NAMES.contains(name),
            Token::Number { .. } => true,
            Token::Other(c) => *c == ')',
        };
        let starts_operand = matches!(pair[1], Token::Identifier(_) | Token::Number { .. } | Token::Other('('));
        if ends_operand && starts_operand {
            return Err(format!(
                "expression `{text}` has no operator between `{}` and `{}`",
                token_text(&pair[0]),
                token_text(&pair[1])
            ));
        }
    }
    Ok(())
}

fn token_text(token: &Token) -> String {
    match token {
        Token::Identifier(name) => name.to_string(),
        Token::Number { text, .. } => text.to_string(),
        Token::Other(c) => c.to_string(),
    }
}

/// An engine expression error, worded with the text the user wrote (not the rewritten one).
fn describe(error: &ExpressionError, text: &str) -> String {
    match error {
        ExpressionError::Parse { message, .. } => format!("cannot parse expression `{text}`: {message}"),
        ExpressionError::UnknownVariable { name, hint, .. } => {
            format!("expression `{text}` names `{name}`, which is neither `t`, a parameter nor a measure{hint}")
        }
        ExpressionError::TooManyVariables { count, .. } => {
            format!("expression `{text}` reads {count} different variables, more than the engine allows")
        }
        ExpressionError::NotTimeOnly { name, .. } => {
            format!("expression `{text}` must depend on time `t` only, but names `{name}`")
        }
        ExpressionError::NotDifferentiable { message, .. } => {
            format!("cannot differentiate `{text}` with respect to t: {message}")
        }
    }
}
