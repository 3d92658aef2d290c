//! The lines of a deck: `*INCLUDE` expansion, comments, keyword lines with their parameters, and
//! the data lines that follow each keyword ("cards"); the number formats of data fields.

use std::path::{Path, PathBuf};
use std::rc::Rc;

use super::InpError;

/// How deep `*INCLUDE` may nest (a file that includes itself stops here).
const MAX_INCLUDE_DEPTH: usize = 16;

/// Where a line comes from: file (as shown in messages) and 1-based line number.
#[derive(Clone, Debug)]
pub(super) struct Loc {
    pub file: Rc<str>,
    pub line: usize,
}

impl Loc {
    pub fn error(&self, message: impl Into<String>) -> InpError {
        InpError::Input {
            file: self.file.to_string(),
            line: self.line,
            message: message.into(),
        }
    }

    pub fn message(&self, message: &str) -> String {
        format!("{}:{}: {}", self.file, self.line, message)
    }
}

/// One line of input after `*INCLUDE` expansion, without its line terminator.
struct RawLine {
    loc: Loc,
    text: String,
}

/// A keyword parameter: `KEY=value` or a bare `KEY`. Keys are upper case with single spaces; values
/// keep their case, without surrounding quotes.
#[derive(Clone, Debug)]
pub(super) struct Param {
    pub key: String,
    pub value: Option<String>,
}

/// A data line split at commas, fields trimmed; a trailing comma gives an empty last field and a
/// blank line no fields.
#[derive(Clone, Debug)]
pub(super) struct DataLine {
    pub loc: Loc,
    pub fields: Vec<String>,
}

impl DataLine {
    /// The fields without the empty ones at the end (a trailing comma, blank padding).
    pub fn trimmed_fields(&self) -> &[String] {
        let n = self
            .fields
            .iter()
            .rposition(|f| !f.is_empty())
            .map_or(0, |i| i + 1);
        &self.fields[..n]
    }

    pub fn is_blank(&self) -> bool {
        self.trimmed_fields().is_empty()
    }
}

/// A keyword line and its data lines.
#[derive(Clone, Debug)]
pub(super) struct Card {
    /// Upper case, single spaces, without the star: `BEAM SECTION`.
    pub keyword: String,
    pub params: Vec<Param>,
    pub loc: Loc,
    pub data: Vec<DataLine>,
}

impl Card {
    /// The value of parameter `key` (upper case); `Some("")` for a bare parameter.
    pub fn param(&self, key: &str) -> Option<&str> {
        self.params
            .iter()
            .find(|p| p.key == key)
            .map(|p| p.value.as_deref().unwrap_or(""))
    }

    pub fn has_param(&self, key: &str) -> bool {
        self.params.iter().any(|p| p.key == key)
    }

    /// The value of a required `KEY=value` parameter.
    pub fn required(&self, key: &str) -> Result<&str, InpError> {
        match self.params.iter().find(|p| p.key == key) {
            Some(Param { value: Some(v), .. }) if !v.is_empty() => Ok(v),
            _ => Err(self
                .loc
                .error(format!("*{}: missing parameter {key}=…", self.keyword))),
        }
    }

    /// The data lines that are not blank.
    pub fn lines(&self) -> impl Iterator<Item = &DataLine> {
        self.data.iter().filter(|d| !d.is_blank())
    }

    /// An error at the keyword line.
    pub fn error(&self, message: impl AsRef<str>) -> InpError {
        self.loc
            .error(format!("*{}: {}", self.keyword, message.as_ref()))
    }
}

/// Splits a deck into cards, reading `*INCLUDE, INPUT=…` files relative to `dir` (the including
/// file's folder).
pub(super) fn cards(text: &str, file: &str, dir: Option<&Path>) -> Result<Vec<Card>, InpError> {
    let mut lines = Vec::new();
    load(text, Rc::from(file), dir, 0, &mut lines)?;
    group(lines)
}

fn is_comment(text: &str) -> bool {
    text.trim_start().starts_with("**")
}

fn is_keyword(text: &str) -> bool {
    let t = text.trim_start();
    t.starts_with('*') && !t.starts_with("**")
}

/// The normalized keyword of a keyword line (`*Beam  Section, …` → `BEAM SECTION`).
fn keyword_name(text: &str) -> String {
    let body = text.trim_start().trim_start_matches('*');
    let name = body.split(',').next().unwrap_or("");
    normalize(name)
}

fn normalize(s: &str) -> String {
    s.split_whitespace()
        .collect::<Vec<_>>()
        .join(" ")
        .to_uppercase()
}

fn load(
    text: &str,
    file: Rc<str>,
    dir: Option<&Path>,
    depth: usize,
    out: &mut Vec<RawLine>,
) -> Result<(), InpError> {
    for (i, line) in text.lines().enumerate() {
        let loc = Loc {
            file: file.clone(),
            line: i + 1,
        };
        let line = line.trim_end_matches(['\r', '\n']);
        if is_keyword(line) && keyword_name(line) == "INCLUDE" {
            let params = parse_params(line);
            let Some(input) = params
                .iter()
                .find(|p| p.key == "INPUT")
                .and_then(|p| p.value.clone())
            else {
                return Err(loc.error("*INCLUDE: missing parameter INPUT=file"));
            };
            if depth >= MAX_INCLUDE_DEPTH {
                return Err(loc.error(format!(
                    "*INCLUDE: more than {MAX_INCLUDE_DEPTH} nested includes (does a file include itself?)"
                )));
            }
            let path = match dir {
                Some(d) if Path::new(&input).is_relative() => d.join(&input),
                _ => PathBuf::from(&input),
            };
            let bytes = crate::input::read_file(&path)
                .map_err(|e| loc.error(format!("*INCLUDE: cannot read {}: {e}", path.display())))?;
            let included = String::from_utf8_lossy(&bytes);
            let name: Rc<str> = Rc::from(path.display().to_string());
            load(&included, name, path.parent(), depth + 1, out)?;
            continue;
        }
        out.push(RawLine {
            loc,
            text: line.to_string(),
        });
    }
    Ok(())
}

/// The parameters of a keyword line (everything after the first comma).
fn parse_params(text: &str) -> Vec<Param> {
    let mut parts = text.split(',');
    parts.next();
    parts
        .map(str::trim)
        .filter(|p| !p.is_empty())
        .map(|p| match p.split_once('=') {
            Some((k, v)) => Param {
                key: normalize(k),
                value: Some(v.trim().trim_matches('"').trim().to_string()),
            },
            None => Param {
                key: normalize(p),
                value: None,
            },
        })
        .collect()
}

fn group(lines: Vec<RawLine>) -> Result<Vec<Card>, InpError> {
    let mut cards: Vec<Card> = Vec::new();
    let mut iter = lines
        .into_iter()
        .filter(|l| !is_comment(&l.text))
        .peekable();
    while let Some(line) = iter.next() {
        if is_keyword(&line.text) {
            let mut text = line.text.trim().to_string();
            // A keyword line ending in a comma continues on the next line when that line holds
            // parameters (`KEY=value`), not data.
            while text.ends_with(',') {
                match iter.peek() {
                    Some(next)
                        if !is_keyword(&next.text)
                            && next.text.split(',').next().is_some_and(|f| f.contains('=')) =>
                    {
                        text.push_str(next.text.trim());
                        iter.next();
                    }
                    _ => break,
                }
            }
            cards.push(Card {
                keyword: keyword_name(&text),
                params: parse_params(&text),
                loc: line.loc,
                data: Vec::new(),
            });
        } else {
            let fields: Vec<String> = if line.text.trim().is_empty() {
                Vec::new()
            } else {
                line.text.split(',').map(|f| f.trim().to_string()).collect()
            };
            match cards.last_mut() {
                Some(card) => card.data.push(DataLine {
                    loc: line.loc,
                    fields,
                }),
                None if fields.is_empty() => {}
                None => {
                    return Err(line.loc.error(
                        "a data line before the first keyword (keyword lines start with *)",
                    ))
                }
            }
        }
    }
    for card in &mut cards {
        while card.data.last().is_some_and(DataLine::is_blank) {
            card.data.pop();
        }
    }
    Ok(cards)
}

/// A real number: Fortran-style input is accepted (`1.`, `.5`, `2.1E+11`, `1.5D3`); infinities and
/// NaN are not.
pub(super) fn parse_real(field: &str) -> Option<f64> {
    let t = field.trim();
    if t.is_empty()
        || t.chars()
            .any(|c| c.is_alphabetic() && !matches!(c, 'e' | 'E' | 'd' | 'D'))
    {
        return None;
    }
    let t = t.replace(['d', 'D'], "e");
    t.parse::<f64>().ok().filter(|x| x.is_finite())
}

/// A node or element label: a positive integer.
pub(super) fn parse_label(field: &str) -> Option<u64> {
    field.trim().parse::<u64>().ok().filter(|&l| l > 0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers() {
        assert_eq!(parse_real("1."), Some(1.0));
        assert_eq!(parse_real(" .5 "), Some(0.5));
        assert_eq!(parse_real("2.1E+11"), Some(2.1e11));
        assert_eq!(parse_real("1.5d3"), Some(1500.0));
        assert_eq!(parse_real("-3"), Some(-3.0));
        assert_eq!(parse_real("nan"), None);
        assert_eq!(parse_real("inf"), None);
        assert_eq!(parse_real("1e999"), None);
        assert_eq!(parse_real("abc"), None);
        assert_eq!(parse_real(""), None);
        assert_eq!(parse_label("12"), Some(12));
        assert_eq!(parse_label("0"), None);
        assert_eq!(parse_label("-1"), None);
        assert_eq!(parse_label("1.0"), None);
    }

    #[test]
    fn cards_keywords_parameters_and_comments() {
        let text = "** a comment\n*Heading\n title\n*Beam  Section, elset=\"Beams\", MATERIAL=steel,\nsection=rect\n\
                    0.1, 0.2\n\n0, 1, 0\n\n*NODE\n1, 0, 0, 0,\n";
        let cards = cards(text, "t.inp", None).unwrap();
        assert_eq!(cards.len(), 3);
        assert_eq!(cards[1].keyword, "BEAM SECTION");
        assert_eq!(cards[1].param("ELSET"), Some("Beams"));
        assert_eq!(cards[1].param("SECTION"), Some("rect"));
        assert_eq!(cards[1].loc.line, 4);
        assert_eq!(cards[1].data.len(), 3); // the blank line between the two data lines is kept
        assert_eq!(cards[1].data[2].loc.line, 8);
        assert_eq!(cards[2].data[0].fields, vec!["1", "0", "0", "0", ""]);
        assert_eq!(cards[2].data[0].trimmed_fields().len(), 4);
        let err = super::cards("1, 2\n*NODE\n", "t.inp", None).unwrap_err();
        assert_eq!(
            err.to_string(),
            "t.inp:1: a data line before the first keyword (keyword lines start with *)"
        );
    }
}
