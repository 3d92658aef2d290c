//! The text of an expression before `exmex` parses it: a tokenizer that
//! finds identifiers (at identifier boundaries only) and number literals, and the rewriting that
//! substitutes parameters, writes exponent literals (`1e-6`, which `exmex` cannot read) in plain
//! decimals and turns tabs and newlines into spaces.

/// Names `exmex` gives a meaning: constants and functions. They cannot name a parameter or measure.
pub const BUILTIN_NAMES: &[&str] = &[
    "PI", "π", "E", "e", "TAU", "τ", "abs", "signum", "sin", "cos", "tan", "asin", "acos", "atan", "sinh", "cosh",
    "tanh", "asinh", "acosh", "atanh", "floor", "round", "ceil", "trunc", "fract", "exp", "sqrt", "cbrt", "ln", "log2",
    "log10", "log", "atan2", "min", "max",
];

/// The functions among [`BUILTIN_NAMES`]: names that may stand right before `(`.
pub const FUNCTION_NAMES: &[&str] = &[
    "abs", "signum", "sin", "cos", "tan", "asin", "acos", "atan", "sinh", "cosh", "tanh", "asinh", "acosh", "atanh",
    "floor", "round", "ceil", "trunc", "fract", "exp", "sqrt", "cbrt", "ln", "log2", "log10", "log", "atan2", "min",
    "max",
];

/// Two-argument functions `exmex` recognises at the start of any name, so no measure name may begin
/// with them (`max_torque` would read as `max` followed by `_torque`).
pub const BINARY_FUNCTION_NAMES: &[&str] = &["atan2", "min", "max"];

/// A piece of expression text.
#[derive(Clone, Debug, PartialEq)]
pub enum Token<'a> {
    /// A name: a variable, parameter, constant or function.
    Identifier(&'a str),
    /// A number literal.
    Number {
        /// As written.
        text: &'a str,
        /// Its value.
        value: f64,
    },
    /// Anything else: operators, parentheses, commas, spaces.
    Other(char),
}

/// Splits `text` into identifiers, numbers and single other characters.
pub fn tokenize(text: &str) -> Vec<Token<'_>> {
    let mut tokens = Vec::new();
    let mut rest = text;
    while let Some(c) = rest.chars().next() {
        let length = if is_identifier_start(c) {
            let length = rest.find(|c: char| !is_identifier_continue(c)).unwrap_or(rest.len());
            tokens.push(Token::Identifier(&rest[..length]));
            length
        } else if let Some(length) = number_length(rest) {
            let literal = &rest[..length];
            match literal.parse::<f64>() {
                Ok(value) => tokens.push(Token::Number { text: literal, value }),
                Err(_) => tokens.extend(literal.chars().map(Token::Other)),
            }
            length
        } else {
            tokens.push(Token::Other(c));
            c.len_utf8()
        };
        rest = &rest[length..];
    }
    tokens
}

/// The identifiers in `text`, in order of appearance.
pub fn identifiers(text: &str) -> Vec<&str> {
    tokenize(text)
        .into_iter()
        .filter_map(|t| match t {
            Token::Identifier(name) => Some(name),
            _ => None,
        })
        .collect()
}

/// `text` ready for `exmex`: identifiers for which `value_of` gives a value are replaced by it in
/// parentheses, numbers with an exponent are written out in decimals, white space becomes spaces.
pub fn rewrite(text: &str, value_of: &dyn Fn(&str) -> Option<f64>) -> String {
    let mut out = String::with_capacity(text.len());
    for token in tokenize(text) {
        match token {
            Token::Identifier(name) => match value_of(name) {
                Some(value) => out.push_str(&format!("({})", decimal(value))),
                None => out.push_str(name),
            },
            Token::Number { text, value } => {
                if text.contains(['e', 'E']) {
                    out.push_str(&decimal(value));
                } else {
                    out.push_str(text);
                }
            }
            Token::Other(c) if c.is_whitespace() => out.push(' '),
            Token::Other(c) => out.push(c),
        }
    }
    out
}

/// A finite number in plain decimal notation, as `exmex` reads it (Rust's `Display` for `f64` never
/// uses an exponent and round-trips exactly).
pub fn decimal(value: f64) -> String {
    format!("{value}")
}

/// Whether `name` is a plain ASCII identifier: a letter or `_`, then letters, digits and `_`.
pub fn is_plain_identifier(name: &str) -> bool {
    let mut chars = name.chars();
    chars.next().is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
        && chars.all(|c| c.is_ascii_alphanumeric() || c == '_')
}

fn is_identifier_start(c: char) -> bool {
    c.is_alphabetic() || c == '_'
}

fn is_identifier_continue(c: char) -> bool {
    c.is_alphanumeric() || c == '_'
}

/// Length of the number literal at the start of `text`: `12`, `1.5`, `.5`, `2.`, `1e-6`, `3.0E+2`.
fn number_length(text: &str) -> Option<usize> {
    let bytes = text.as_bytes();
    let digits = |from: usize| bytes[from..].iter().take_while(|b| b.is_ascii_digit()).count();
    let mut end = digits(0);
    let mut mantissa_digits = end;
    if bytes.get(end) == Some(&b'.') {
        let fraction = digits(end + 1);
        mantissa_digits += fraction;
        end += 1 + fraction;
    }
    if mantissa_digits == 0 {
        return None;
    }
    if matches!(bytes.get(end), Some(b'e' | b'E')) {
        let sign = usize::from(matches!(bytes.get(end + 1), Some(b'+' | b'-')));
        let exponent = digits(end + 1 + sign);
        let after = end + 1 + sign + exponent;
        let ends_cleanly = !text[after..].starts_with(is_identifier_continue);
        if exponent > 0 && ends_cleanly {
            end = after;
        }
    }
    Some(end)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn substitutes_at_identifier_boundaries_only() {
        let value_of = |n: &str| (n == "k").then_some(2.5);
        assert_eq!(rewrite("k*t + k_2 - kk + sin(k)", &value_of), "(2.5)*t + k_2 - kk + sin((2.5))");
    }

    #[test]
    fn writes_exponents_in_decimals() {
        let none = |_: &str| None;
        assert_eq!(rewrite("1e-3*t + 2.5E2 + x1e5", &none), "0.001*t + 250 + x1e5");
        assert_eq!(rewrite("3 *\n\tt", &none), "3 *  t");
    }

    #[test]
    fn e_after_a_number_without_digits_is_not_an_exponent() {
        assert_eq!(tokenize("2e"), vec![Token::Number { text: "2", value: 2.0 }, Token::Identifier("e")]);
        assert_eq!(identifiers("T_stall*(1 - w/w0) + sin(PI*t)"), ["T_stall", "w", "w0", "sin", "PI", "t"]);
    }

    #[test]
    fn negative_values_are_parenthesized() {
        let value_of = |n: &str| (n == "a").then_some(-3.0);
        assert_eq!(rewrite("2^a", &value_of), "2^(-3)");
    }
}
