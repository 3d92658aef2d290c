//! FE model files: the finite-element model of a flexible body described in TOML (see
//! `docs/fe-model-file.md`) — materials, sections, nodes, elements, generated beam lines and plates,
//! masses, supports and the static loads of the static correction modes, optionally on top of an
//! Abaqus/CalculiX `.inp` mesh — built into a [`flexmb_fem::FeModel`].
//!
//! Errors are those of mechanism model files ([`ModelFileError`]): file, 1-based line, TOML key path
//! and what was expected; the TOML parsing, `[parameters]`, numbers and expressions, names and
//! suggestions are the model-file layer's own.

mod build;
mod elements;
pub(crate) mod format;
mod generators;
mod interfaces;
mod masses;
mod matrices;
mod materials;
mod mesh_file;
mod names;
pub(crate) mod node_ref;
mod nodes;
mod options;
mod reduce_file;
mod schema;
mod sections;
mod static_loads;
mod supports;
mod value;

use std::path::{Path, PathBuf};


use flexmb_fem::reduction::{Basis, ModeSet};

use crate::model_file::source::{read_text_file, Source};
use crate::model_file::toml_errors;
use crate::model_file::ErrorKind;
pub use crate::model_file::ModelFileError;
pub use reduce_file::{reduce_fe_model_file, ReduceFileError, ReducedFeModel, ReductionRequest};

use schema::FeModelFile;

/// An FE model read from a file, with the file's defaults for `flexmb modes`.
#[derive(Clone, Debug)]
pub struct LoadedFeModel {
    /// `[fe_model] name`, or the file name without extension.
    pub name: String,
    /// The finite-element model: mesh, materials, sections, supports, static loads, options.
    pub model: flexmb_fem::FeModel,
    /// The `[modes]` defaults.
    pub defaults: ModesDefaults,
    /// Things worth knowing that do not stop the model from being built (a definition nothing uses,
    /// a skipped keyword of the mesh file), each `file:line: …`.
    pub warnings: Vec<String>,
    /// The files the model was read from: for [`load_fe_model`], the FE model file first; then the
    /// mesh file (`[fe_model] mesh`) and the files it `*INCLUDE`s. What a cache of the reduced body
    /// depends on.
    pub sources: Vec<PathBuf>,
}

/// `[modes]`: what `flexmb modes` uses unless told otherwise; `None` where the file says nothing.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ModesDefaults {
    /// `set`: the mode set, e.g. `4N2S`.
    pub mode_set: Option<ModeSet>,
    /// `basis`: raw or mass-orthonormalized modes.
    pub basis: Option<Basis>,
    /// `stresses`: whether the reduction stores each mode's stresses (`FlexibleBody::stresses`).
    pub stresses: Option<bool>,
}

/// Reads and builds the FE model file at `path`: a TOML FE model file, or an `.inp` deck directly
/// (then the model is the deck's, named after the file, without `[modes]` defaults).
///
/// Reduced to its `[modes]` set, written as a flexible-body file and made the engine's modal body:
///
/// ```
/// use flexmb_fem::reduction::{reduce, ReductionSettings};
///
/// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../models/fe/cantilever.toml");
/// let loaded = flexmb_files::fe_model_file::load_fe_model(std::path::Path::new(path))?;
/// let mode_set = loaded.defaults.mode_set.clone().ok_or("no [modes] set")?;
/// let basis = loaded.defaults.basis.unwrap_or_default();
/// let settings = ReductionSettings { mode_set, basis, eigen: Default::default() };
/// let reduction = reduce(&loaded.model, &loaded.name, &settings)?;
/// assert_eq!(reduction.body.mode_count(), 6); // 4N2S
/// let file = std::env::temp_dir().join(format!("flexmb-files-doctest-{}.json", std::process::id()));
/// reduction.body.write(&file)?;
/// let modal = flexmb_files::flexible_body::modal_body(&reduction.body, &flexmb::body::ModalDamping::None)?;
/// assert_eq!(modal.mode_labels.len(), 6);
/// std::fs::remove_file(&file)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn load_fe_model(path: &Path) -> Result<LoadedFeModel, ModelFileError> {
    let file = path.display().to_string();
    let stem = file_stem(&file);
    if path.extension().is_some_and(|e| e.eq_ignore_ascii_case("inp")) {
        let inp = flexmb_fem::inp::read_inp(path).map_err(|e| mesh_file::inp_error(&e))?;
        check_has_elements(&inp.model, &file)?;
        return Ok(LoadedFeModel {
            name: stem,
            model: inp.model,
            defaults: ModesDefaults::default(),
            warnings: inp.warnings,
            sources: mesh_file::deck_files(path),
        });
    }
    let text = read_text_file(path, "FE model")?;
    if is_matrix_file(path, &text) {
        return Err(unsupported_input(&file, "is a matrix file, not an FE model"));
    }
    let base_dir = path.parent().unwrap_or(Path::new(""));
    let is_toml = path.extension().is_some_and(|e| e.eq_ignore_ascii_case("toml"));
    let mut loaded = parse_fe_model(&text, &file, base_dir).map_err(|e| match e.kind {
        ErrorKind::Syntax if !is_toml => unsupported_input(&file, &format!("is not TOML ({})", e.message)),
        _ => e,
    })?;
    loaded.sources.insert(0, path.to_path_buf());
    Ok(loaded)
}

/// Builds an FE model from the text of an FE model file. `file_name` is used in error messages and its
/// stem is the model's default name; a relative `[fe_model] mesh` path starts at `base_dir`. The
/// model's `sources` are the mesh file and its includes (the text itself has no file).
pub fn parse_fe_model(text: &str, file_name: &str, base_dir: &Path) -> Result<LoadedFeModel, ModelFileError> {
    let source = Source::new(file_name, text);
    let file: FeModelFile = toml_errors::deserialize_located(&source)?;
    build::build(&file, &source, file_name, base_dir, &file_stem(file_name))
}

fn file_stem(file_name: &str) -> String {
    Path::new(file_name).file_stem().and_then(|s| s.to_str()).unwrap_or("fe_model").to_string()
}

/// Extensions of matrix files other programs write (Matrix Market, CalculiX's matrix storage, Ansys'
/// exports, Harwell–Boeing).
const MATRIX_EXTENSIONS: [&str; 8] = ["mtx", "mm", "sti", "mas", "dof", "full", "hb", "rb"];

/// Whether `path` is a matrix file rather than an FE model: by its extension, or a Matrix Market header.
fn is_matrix_file(path: &Path, text: &str) -> bool {
    let extension = path.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
    MATRIX_EXTENSIONS.contains(&extension.as_str()) || text.trim_start().to_ascii_lowercase().starts_with("%%matrixmarket")
}

/// The error for an input `flexmb modes` does not read, listing what it reads.
fn unsupported_input(file: &str, what: &str) -> ModelFileError {
    ModelFileError {
        kind: ErrorKind::Invalid,
        file: file.to_string(),
        line: None,
        key_path: String::new(),
        message: format!(
            "{what}: an unsupported format. flexmb reads an FE model file (TOML, .toml) or an Abaqus/CalculiX deck (.inp); \
             a body from exported stiffness and mass matrices is an FE model file with a [matrices] table naming the \
             matrix, row-map and node files, in one of the supported matrix formats: {}",
            crate::exported_matrices::MatrixFormat::supported()
        ),
    }
}

/// An `.inp` deck read directly must have elements, as a TOML model must.
fn check_has_elements(model: &flexmb_fem::FeModel, file: &str) -> Result<(), ModelFileError> {
    if model.mesh.elements.is_empty() {
        return Err(ModelFileError {
            kind: ErrorKind::Invalid,
            file: file.to_string(),
            line: None,
            key_path: String::new(),
            message: "the mesh file has no elements (*ELEMENT with a beam or shell type)".to_string(),
        });
    }
    Ok(())
}
