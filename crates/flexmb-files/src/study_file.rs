//! Study files: one model run in several variants (cases: mode sets of flexible bodies, parameter
//! values) with several integrators. Read with the model file's located errors (file, key path, line).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde::Deserialize;
use toml::Spanned;

use crate::model_file::key_path::KeyPath;
use crate::model_file::source::{read_text_file, Source};
use crate::model_file::value::NumberOrExpression;
use crate::model_file::{toml_errors, ModelFileError, ModelOverrides};

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct StudyFile {
    study: Spanned<StudySection>,
    #[serde(default)]
    case: Vec<Spanned<CaseSection>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct StudySection {
    name: Option<Spanned<String>>,
    model: Spanned<String>,
    integrators: Option<Spanned<Vec<Spanned<String>>>>,
    t_end: Option<Spanned<f64>>,
    rtol: Option<Spanned<f64>>,
    atol: Option<Spanned<f64>>,
    plot: Option<Spanned<Vec<Spanned<String>>>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct CaseSection {
    name: Spanned<String>,
    #[serde(default)]
    modes: BTreeMap<String, Spanned<String>>,
    #[serde(default)]
    parameters: BTreeMap<String, Spanned<NumberOrExpression>>,
    published: Option<Spanned<PublishedSection>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PublishedSection {
    t_end: Option<f64>,
    cpu: Option<f64>,
    rms_step: Option<f64>,
}

/// A study, ready to run.
#[derive(Clone, Debug)]
pub struct Study {
    /// `name`: names the output directory and the table.
    pub name: String,
    /// The model file, relative to the working directory.
    pub model: PathBuf,
    /// Integrators by name (`bdf`, `adams`, `gen-alpha`, or `bdf:K` for the BDF with orders up to `K`),
    /// in table order; the first one's runs are plotted.
    pub integrators: Vec<String>,
    /// End time of every run (s); `None`: the model file's.
    pub t_end: Option<f64>,
    /// Relative tolerance of every run; `None`: the model file's.
    pub rtol: Option<f64>,
    /// Absolute tolerance of every run; `None`: the model file's.
    pub atol: Option<f64>,
    /// Output columns to plot, one plot each with a curve per case.
    pub plot: Vec<String>,
    /// The variants, in table order.
    pub cases: Vec<Case>,
}

/// One variant of the model.
#[derive(Clone, Debug)]
pub struct Case {
    /// The case's name, in tables, legends and file names.
    pub name: String,
    /// Where the case is written, `FILE:LINE: case[k]`, for messages about it.
    pub location: String,
    /// Its mode sets and parameter values.
    pub overrides: ModelOverrides,
    /// Figures published for this case (e.g. the seed's table), shown beside the run's.
    pub published: Option<Published>,
}

/// A published run's end time, CPU time and RMS step size, for comparison.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Published {
    /// End time (s).
    pub t_end: Option<f64>,
    /// CPU time (s).
    pub cpu: Option<f64>,
    /// RMS step size (s).
    pub rms_step: Option<f64>,
}

/// Reads the study file at `path`.
pub fn load_study(path: &Path) -> Result<Study, ModelFileError> {
    let file = path.display().to_string();
    let text = read_text_file(path, "study")?;
    parse_study(&text, &file, path.parent().unwrap_or(Path::new("")))
}

/// Reads a study from its text; the model path is relative to `base_dir`.
pub fn parse_study(text: &str, file_name: &str, base_dir: &Path) -> Result<Study, ModelFileError> {
    let source = Source::new(file_name, text);
    let parsed: StudyFile = toml_errors::deserialize_located(&source)?;
    build_study(&source, parsed, base_dir)
}

fn build_study(source: &Source, parsed: StudyFile, base_dir: &Path) -> Result<Study, ModelFileError> {
    let table = KeyPath::root().key("study");
    let s = parsed.study.into_inner();
    let default_name = Path::new(source.file()).file_stem().and_then(|n| n.to_str()).unwrap_or("study");
    let integrators = match s.integrators {
        Some(list) => {
            let span = list.span();
            let names: Vec<Spanned<String>> = list.into_inner();
            if names.is_empty() {
                return Err(source.invalid(&span, &table.key("integrators"), "list at least one integrator"));
            }
            for (k, name) in names.iter().enumerate() {
                crate::integrator_choice::parse_study_integrator(name.get_ref())
                    .map_err(|e| source.invalid(&name.span(), &table.key("integrators").index(k), e))?;
            }
            distinct(source, names, &table.key("integrators"), "integrator")?
        }
        None => vec!["bdf".to_string()],
    };
    let positive = |value: &Option<Spanned<f64>>, key: &str| -> Result<Option<f64>, ModelFileError> {
        match value {
            Some(v) if !(*v.get_ref() > 0.0 && v.get_ref().is_finite()) => Err(source.invalid(
                &v.span(),
                &table.key(key),
                format!("{key} must be a positive number, got {}", v.get_ref()),
            )),
            Some(v) => Ok(Some(*v.get_ref())),
            None => Ok(None),
        }
    };
    let plot = match s.plot {
        Some(list) => distinct(source, list.into_inner(), &table.key("plot"), "column")?,
        None => Vec::new(),
    };
    let cases = cases(source, parsed.case)?;
    Ok(Study {
        name: s.name.map(|n| n.into_inner()).unwrap_or_else(|| default_name.to_string()),
        model: base_dir.join(s.model.get_ref()),
        integrators,
        t_end: positive(&s.t_end, "t_end")?,
        rtol: positive(&s.rtol, "rtol")?,
        atol: positive(&s.atol, "atol")?,
        plot,
        cases,
    })
}

/// The integrators or the columns to plot, each once (1392 copies of an integrator ran each case 1392
/// times, 1281 copies of a column drew its plot 1281 times; found by the fuzz test).
fn distinct(source: &Source, items: Vec<Spanned<String>>, key: &KeyPath, what: &str) -> Result<Vec<String>, ModelFileError> {
    for (k, item) in items.iter().enumerate() {
        if items[..k].iter().any(|c| c.get_ref() == item.get_ref()) {
            return Err(source.invalid(&item.span(), &key.index(k), format!("{what} '{}' is listed twice", item.get_ref())));
        }
    }
    Ok(items.into_iter().map(|c| c.into_inner()).collect())
}

/// A case's published figures, each a positive number (an infinite CPU time was printed in the table as
/// `inf`, found by the fuzz test).
fn published(source: &Source, table: Spanned<PublishedSection>, key: &KeyPath) -> Result<Published, ModelFileError> {
    let span = table.span();
    let p = table.into_inner();
    for (name, value) in [("t_end", p.t_end), ("cpu", p.cpu), ("rms_step", p.rms_step)] {
        if let Some(x) = value.filter(|x| !(*x > 0.0 && x.is_finite())) {
            return Err(source.invalid(&span, &key.key(name), format!("{name} must be a positive number, got {x}")));
        }
    }
    Ok(Published { t_end: p.t_end, cpu: p.cpu, rms_step: p.rms_step })
}

fn cases(source: &Source, sections: Vec<Spanned<CaseSection>>) -> Result<Vec<Case>, ModelFileError> {
    if sections.is_empty() {
        let end = source.text().len();
        return Err(source.invalid(&(end..end), &KeyPath::root().key("case"), "a study needs at least one [[case]]"));
    }
    let mut cases: Vec<Case> = Vec::new();
    for (k, section) in sections.into_iter().enumerate() {
        let key = KeyPath::root().key("case").index(k);
        let location = format!("{}:{}: {key}", source.file(), source.line(section.span().start));
        let c = section.into_inner();
        let name = c.name.get_ref().trim().to_string();
        if name.is_empty() || name.contains(['/', '\\']) {
            return Err(source.invalid(&c.name.span(), &key.key("name"), "a case name must be non-empty and hold no '/' or '\\' (it names files)"));
        }
        if cases.iter().any(|other| other.name == name) {
            return Err(source.invalid(&c.name.span(), &key.key("name"), format!("case '{name}' is named twice")));
        }
        let published = match c.published {
            Some(p) => Some(published(source, p, &key.key("published"))?),
            None => None,
        };
        let mut overrides = ModelOverrides {
            modes: c.modes.into_iter().map(|(body, set)| (body, set.into_inner())).collect(),
            ..Default::default()
        };
        for (parameter, value) in c.parameters {
            match value.into_inner() {
                NumberOrExpression::Number(x) => overrides.parameters.push((parameter, x)),
                NumberOrExpression::Expression(text) => overrides.parameter_expressions.push((parameter, text)),
            }
        }
        cases.push(Case { name, location, overrides, published });
    }
    Ok(cases)
}
